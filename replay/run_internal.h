/* Internal to replay/: the state of one replay run and the steps of one frame. */
#ifndef HMDLOD_REPLAY_RUN_INTERNAL_H
#define HMDLOD_REPLAY_RUN_INTERNAL_H

#include "acuity/acuity.h"
#include "lod/lod.h"
#include "hmd/hmd.h"
#include "render/render.h"
#include "replay/replay.h"
#include "replay/select.h"

/* Per-frame working arrays, sized once when the scene loads (DESIGN.md: steps 4–7 allocate nothing). */
struct rpl_frame_arrays {
    uint32_t *visible;
    double *eccentricity_deg, *velocity_degps, *diameter_deg;
    uint8_t *lod;
    uint32_t *draw_index; /* visible objects then group impostors: what the renderer gets */
    uint8_t *draw_lod;
};

/* What one frame did, for its CSV row. */
struct rpl_frame_record {
    long frame;
    double time_s;
    double head_speed_degps;
    double eye_speed_degps; /* the eye's angular speed in the world under the gaze model */
    uint32_t visible;
    uint32_t cull_groups_tested, cull_instances_tested; /* scn_cull_stats (summary only, not the CSV) */
    uint64_t acuity_evaluations;
    uint64_t triangles_per_eye, triangles_finest;
    uint32_t lod_histogram[SCN_MAX_LODS];
    double acuity_us, select_us, draw_ms, frame_ms;
    int deadline_met;
    struct rpl_select_record sel;
    double visible_error;     /* rpl_select_visible_error, outside the frame's timing */
    int has_image_error;      /* a --reference frame: image holds its comparison */
    struct rnd_image_error image;
};

struct rpl_session {
    struct hmd_profile display;
    struct hmd_eye eyes[2];
    struct acu_limits limits;
    struct scn_scene scene;
    struct lod_chain *chains;
    struct trk_pose_source *source;
    struct rnd_renderer *renderer;
    struct rpl_frame_arrays arrays;
    enum rpl_selector selector;
    struct rpl_select select;
    char cost_label[160];     /* where the cost model came from, for the summary */
    enum rpl_freq_reading reading;
    int max_lods;
    double near_m, far_m;
    struct rpl_cull_frustum cull_frustum; /* computed once per session: no square roots per frame */
    struct scn_culler culler; /* the hierarchical cull's scratch, sized when the scene loads */
    /* Gaze (acuity/gaze.h, docs/gaze.md): the model, the VOR's parameters with the fixation
     * distance, and the eyes' offset from the neck for traces without positions (zero otherwise). */
    enum acu_gaze_model gaze;
    struct acu_vor_params vor;
    hl_vec3d neck_to_eye_head_m;
    int trace_has_gaze, trace_has_position;
    /* The last frame's eyes and world gaze, for its full-detail reference (rpl_frame_reference). */
    struct rnd_eye_view frame_views[2];
    hl_vec3d frame_gaze_dir;
};

/* Opening and closing a session (replay/session.c). check_options validates the options and parses the
 * selector and the frequency reading; need_out_dir: 1 when the run writes an output folder (replay).
 * open: what is given in `made` is adopted (closed by rpl_session_close) instead of being made from
 * the options: a pose source (a live tracker, synthetic input) instead of the options' trace, a
 * renderer made in a window's context instead of a headless one. made may be NULL. */
struct rpl_session_made {
    struct trk_pose_source *source;
    struct rnd_renderer *renderer;
};
int rpl_session_check_options(const struct rpl_options *o, int need_out_dir, enum rpl_selector *selector,
                              enum rpl_freq_reading *reading, struct hl_error *err);
int rpl_session_open(struct rpl_session *s, const struct rpl_options *o, const struct rpl_session_made *made,
                     struct hl_error *err);
void rpl_session_close(struct rpl_session *s);

/* The head's state at time_s for the session's gaze model: eyes from the neck model (or the trace's
 * position), the measured gaze, and for the VOR the head latency_s earlier. Also the pose whose
 * position is the cyclopean eye, for the cull and the eye views. */
int rpl_frame_head_state(struct rpl_session *s, double time_s, struct trk_pose *eye_pose,
                         struct acu_head_state *head, struct hl_error *err);

/* Culls, computes viewing geometry, selects and draws one frame at `time_s`. */
int rpl_frame_run(struct rpl_session *s, long frame, double time_s, struct rpl_frame_record *rec,
                  struct hl_error *err);

/* Before the first frame (rpl_session_open calls it, for replay and live alike): draws one instance
 * of every chain at every level from a still pose, untimed, so that the driver's first-use work
 * (shader compilation, buffer residency: tens of ms on llvmpipe) is not measured as frame 0 and fed
 * to the cost correction. */
int rpl_frame_warm_up(struct rpl_session *s, struct hl_error *err);

/* After rpl_frame_run (and any capture of it): reads the frame back into test (unless test_read: a
 * capture has just read it there), draws the same visible
 * objects at their finest levels from the same eyes into ref, and compares them (render/image_error.h)
 * with the foveated weights M(E) around the frame's gaze; fills rec->image and has_image_error. Both
 * buffers hold the renderer's whole image; w fits it. Outside the frame's timing. */
int rpl_frame_reference(struct rpl_session *s, struct rpl_frame_record *rec, uint8_t *test, int test_read,
                        uint8_t *ref, struct rnd_image_error_work *w, struct hl_error *err);

/* Output files: written beside their final name and renamed when complete, so an interrupted run
 * never leaves a CSV or summary that looks finished. */
struct rpl_output {
    FILE *csv;           /* out.f: frames.csv's temporary, renamed into place by rpl_output_commit */
    struct hl_out out;
    char csv_path[4096];
};
int rpl_output_open(struct rpl_output *o, const char *dir, int max_lods, struct hl_error *err);
void rpl_output_row(struct rpl_output *o, const struct rpl_frame_record *r, int max_lods);
int rpl_output_close(struct rpl_output *o, struct hl_error *err); /* all written and synced; not renamed */
int rpl_output_commit(struct rpl_output *o, struct hl_error *err);
void rpl_output_abort(struct rpl_output *o);
int rpl_output_failed(const struct rpl_output *o); /* a write to frames.csv has failed */
/* summary.json written beside its name and closed (hl_out_close), not yet renamed: run.c renames it
 * after frames.csv, so a failed write never leaves a new frames.csv beside an old summary. */
int rpl_summary_stage_json(const char *dir, const struct rpl_summary *s, struct hl_out *out, struct hl_error *err);

/* Running mean/max/stddev of the frame records (Welford: stable over long runs). */
struct rpl_accumulator {
    long n;
    double frame_mean, frame_m2, frame_max;
    double eye_speed_sum;
    double draw_sum, acuity_sum, select_sum, evals_sum, visible_sum;
    double cull_groups_sum, cull_instances_sum;
    double triangles_sum, finest_sum;
    long deadlines_met;
    long predicted_within, truncated_frames, over_budget_frames;
    double lod_changes_sum, optimizer_us_sum, optimizer_us_max, iterations_sum;
    double benefit_share_sum, benefit_share_min; /* benefit / LP bound where the bound is known */
    long benefit_share_frames;
    long gaze_frames, saccades, suppressed_frames, refine_miss_frames, refine_missed_saccades; /* saccade */
    /* Per head-speed band (rpl_speed_band_lower_degps): what share of the finest triangles was drawn,
     * so the velocity term's effect shows in one run. */
    long band_frames[RPL_SPEED_BAND_COUNT];
    double band_triangles[RPL_SPEED_BAND_COUNT], band_finest[RPL_SPEED_BAND_COUNT];
    /* Every frame's time and draw time, for percentiles; sized once for the run (capacity). */
    double *frame_ms, *draw_ms;
    long capacity;
    double visible_error_sum, visible_error_max;
    /* --reference frames: PSNR, SSIM and foveated SSIM of each (for percentiles), and sums */
    double *ref_psnr_db, *ref_ssim, *ref_fssim;
    long ref_n, ref_capacity, ref_identical, ref_psnr_finite;
    double ref_psnr_sum, ref_ssim_sum, ref_ssim_rgb_sum, ref_fssim_sum, ref_over32_sum, ref_visible_sum;
    double ref_band_sum[RND_ECC_BANDS];
    long ref_band_n[RND_ECC_BANDS];
};
/* frames: the run's frame count; references: how many of them are --reference frames (0 for none). */
int rpl_accumulator_init(struct rpl_accumulator *a, long frames, long references, struct hl_error *err);
void rpl_accumulate(struct rpl_accumulator *a, const struct rpl_frame_record *r);
/* Fills the summary; sorts the stored times in place (call once, at the end). */
void rpl_accumulator_finish(struct rpl_accumulator *a, struct rpl_summary *s);
void rpl_accumulator_free(struct rpl_accumulator *a);

#endif
