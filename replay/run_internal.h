/* Internal to replay/: the replay run's output files and its running summary. */
#ifndef HMDLOD_REPLAY_RUN_INTERNAL_H
#define HMDLOD_REPLAY_RUN_INTERNAL_H

#include "replay/replay.h"

/* Output files: written beside their final name and renamed when complete, so an interrupted run
 * never leaves a CSV or summary that looks finished. */
struct rpl_output {
    FILE *csv;           /* out.f: frames.csv's temporary, renamed into place by rpl_output_commit */
    struct hl_out out;
    char csv_path[4096];
};
int rpl_output_open(struct rpl_output *o, const char *dir, int max_lods, struct hl_error *err);
void rpl_output_row(struct rpl_output *o, const struct frm_frame_record *r, int max_lods);
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
    /* Minor page faults over the steady-state frames: from frame warm_frames on (a tenth of the run,
     * at least frame 1), after the driver's first-use work. */
    long warm_frames, fault_frames;
    double faults_sum;
    double frame_mean, frame_m2, frame_max;
    double frame_sum_after_first; /* frames 1… only: frame 0 pays the driver's shader compiles */
    double eye_speed_sum;
    double draw_sum, acuity_sum, select_sum, evals_sum, visible_sum;
    double cull_groups_sum, cull_instances_sum;
    double triangles_sum, finest_sum;
    long deadlines_met;
    long predicted_within, truncated_frames, over_budget_frames, underused_drop_frames;
    double dropped_sum, dropped_px_share_sum, dropped_px_share_max;
    /* foveated layers: frames per periphery scale (frm_layer_scales), lossy frames, inset radius and
     * composite time sums over the layered frames */
    long scale_frames[FRM_LAYER_SCALES], lossy_frames;
    double inset_radius_sum, composite_ms_sum, scale_sum;
    double lod_changes_sum, optimizer_us_sum, optimizer_us_max, iterations_sum;
    double benefit_share_sum, benefit_share_min; /* benefit / LP bound where the bound is known */
    long benefit_share_frames;
    long gaze_frames, saccades, suppressed_frames, refine_miss_frames, refine_missed_saccades; /* saccade */
    /* Per head-speed band (rpl_speed_band_lower_degps): what share of the finest triangles was drawn,
     * so the velocity term's effect shows in one run. */
    long band_frames[RPL_SPEED_BAND_COUNT];
    double band_triangles[RPL_SPEED_BAND_COUNT], band_finest[RPL_SPEED_BAND_COUNT];
    /* Per object: triangles drawn and finest by eccentricity and by retinal-speed band (frame record). */
    double ecc_drawn[RND_ECC_BANDS], ecc_finest[RND_ECC_BANDS];
    double retinal_drawn[FRM_RETINAL_BANDS], retinal_finest[FRM_RETINAL_BANDS];
    /* Every frame's time and draw time, for percentiles; sized once for the run (capacity). */
    double *frame_ms, *draw_ms;
    long capacity;
    double visible_error_sum, visible_error_max;
    double adapting_sum, adapting_min, adapting_max; /* the contrast criterion's adapting luminance */
    long adapting_frames;
    /* --reference frames: PSNR, SSIM and foveated SSIM of each (for percentiles), and sums */
    double *ref_psnr_db, *ref_ssim, *ref_fssim;
    long ref_n, ref_capacity, ref_identical, ref_psnr_finite;
    double ref_psnr_sum, ref_ssim_sum, ref_ssim_rgb_sum, ref_fssim_sum, ref_over32_sum, ref_visible_sum;
    double ref_band_sum[RND_ECC_BANDS];
    long ref_band_n[RND_ECC_BANDS];
    double ref_flip_sum, ref_flip_median_sum, ref_flip_mean_max, ref_flip_max, ref_flip_ppd; /* LDR-FLIP */
};
/* frames: the run's frame count; references: how many of them are --reference frames (0 for none). */
int rpl_accumulator_init(struct rpl_accumulator *a, long frames, long references, struct hl_error *err);
void rpl_accumulate(struct rpl_accumulator *a, const struct frm_frame_record *r);
/* Fills the summary; sorts the stored times in place (call once, at the end). */
void rpl_accumulator_finish(struct rpl_accumulator *a, struct rpl_summary *s);
void rpl_accumulator_free(struct rpl_accumulator *a);

#endif
