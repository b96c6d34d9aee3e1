/* frame: one frame, shared by replay (virtual clock) and live (wall clock). Prefix frm_.
 *
 * Read top to bottom, this header is DESIGN.md's "One frame":
 *   opening a session — display and eyes, the pose source handed in, scene, the measured frequency
 *   tables (frame/assets.h), selector and cost model (frame/cost.h), renderer;
 *   then per frame — pose → eyes → cull → viewing geometry → perceptual ceiling → cost-bounded
 *   selection (frame/select.h) → stereo draw → the frame's record.
 *
 * It joins tracking, acuity, scene, lod, render and hmd; it may not touch replay/, live/ or bench/
 * (they run it), nor any file but the analysis cache and a cost profile named in its options: pose
 * sources are made by whoever runs the frame (replay's traces, live's trackers and desk). */
#ifndef HMDLOD_FRAME_H
#define HMDLOD_FRAME_H

#include <stdint.h>

#include "base/base.h"
#include "acuity/acuity.h"
#include "hmd/hmd.h"
#include "lod/lod.h"
#include "render/render.h"
#include "scene/scene.h"
#include "tracking/tracking.h"
#include "frame/assets.h"
#include "frame/cost.h"
#include "frame/select.h"

/* ---- a session's options -------------------------------------------------------------------- */
struct scn_asset_resolver;
struct frm_options {
    const char *scene;       /* built-in scene name, or a scene file (frm_scene_is_file) */
    const struct scn_asset_resolver *resolver; /* scene files' meshes; NULL = frm_cached_resolver() */
    const char *display;     /* built-in name or JSON file */
    const char *selector;    /* "none" | "reddy" | "static" | "feedback" | "fs" | "mb" */
    const char *frequency_reading; /* "narrow" (default) | "long" | "geometric" (frame/assets.h) */
    int object_count;        /* field: objects, domes: domes; 0 = the scene's default (100, 10) */
    uint64_t seed;
    double acuity_scale;     /* Reddy §6 s; 1 by default */
    /* What decides visibility (docs/visibility.md): "contrast" (default) or "acuity" (Reddy's H(v, E)
     * at full contrast, as before); the contrast sensitivity model "castle" (default) or "stela";
     * k, the CSF's safety factor (> 0, default FRM_CSF_SCALE_DEFAULT: a band is visible when c·S·k ≥ 1). */
    const char *visibility;
    const char *csf;
    double csf_scale;
    /* What fs and mb value a level by (docs/optimizer.md "Perceptual benefit"): "funkhouser"
     * (accuracy from its samples) or "perceptual" (the visible contrast it keeps; needs
     * --visibility contrast). NULL = FRM_BENEFIT_DEFAULT ("funkhouser", with or without layers:
     * docs/foveation.md "The benefit, with layers"). */
    const char *benefit;
    double render_scale;     /* per-eye resolution factor (1 = the display's pixels) */
    int quiet;               /* no note on stderr about the chains analysed (replay: no summary table either) */
    double budget_ms;        /* frame budget; 0 → the display's frame period */
    const char *cost_profile; /* JSON from hmdlod calibrate; NULL → the built-in llvmpipe profile */
    double opt_limit_us;     /* fs/mb time limit per frame (Nirenstein §5.5); 0 = none */
    double static_px_per_triangle; /* static: the average triangle covers at least this (default 64) */
    int cost_correction;     /* enum frm_correction; FRM_CORRECTION_AFFINE by default */
    double within_share;     /* the affine correction's margin aims to keep this share of frames within
                              * the budget, in (0.5, 1); 0 → LOD_COST_WITHIN_SHARE_DEFAULT */
    /* Gaze models (acuity/gaze.h; docs/gaze.md) */
    const char *gaze;        /* NULL/"auto" (default): tracked when the source has gaze, else vor;
                              * or "head" | "vor" | "tracked" */
    double vor_gain;         /* < 0 → acu_vor_params_default's; 0 … 1.2 */
    double vor_latency_ms;   /* < 0 → default */
    double fixation_m;       /* ≤ 0 → the scene's default fixation distance */
    double saccade_onset_degps; /* ≤ 0 → acu_saccade_params_default's */
    int velocity_term_off;   /* 1: acu_limits.use_velocity = 0 (bench gaze: what the velocity term saves) */
    int eccentricity_term_off; /* 1: acu_limits.use_eccentricity = 0 (Reddy's study: size + velocity) */
    int mb_simplify;         /* mb: Nirenstein et al.'s hierarchy simplification applied 0 (default) … 8 times */
    /* Foveated layers (frame/layers.h, docs/foveation.md): "off" (default: the frame as before),
     * "fixed" (inset on the lens centre) or "gaze" (on the gaze model's gaze, the measured one under
     * tracked); --periphery-scale fixes s (one of frm_layer_scales; 0 = chosen per frame), --inset-deg
     * the inset's radius (< 0 = the resolution ceiling's; 0 = no inset: global dynamic resolution),
     * --blend-deg the band (0 = FRM_LAYER_BLEND_DEG_DEFAULT). */
    const char *foveation;
    double periphery_scale, inset_deg, blend_deg;
    const char *source_name; /* the pose source in messages ("--gaze tracked: NAME has no gaze columns") */
};
void frm_options_defaults(struct frm_options *o);
/* The ranges of every option (the selector and reading parsed into *selector, *reading). 0, or −1
 * with err naming the option. */
int frm_options_check(const struct frm_options *o, enum frm_selector *selector, enum frm_freq_reading *reading,
                      struct hl_error *err);
/* The layer options alone (frm_options_check calls it): mode, scale, inset, band. */
int frm_layers_options_check(const struct frm_options *o, struct hl_error *err);
/* 1 when a --scene value names a scene file (docs/scene-format.md): it ends in .json or is an
 * existing regular file; otherwise it is a built-in scene's name. */
int frm_scene_is_file(const char *scene);

/* The default k. castleCSF's sensitivity falls with eccentricity several times faster than the
 * foveated metrics' (docs/csf.md: at 10° its full-contrast cutoff is 6.5 cpd, FovVideoVDP's 14.5);
 * at k = 1 reddy on field (1000 objects, Corbillon user 1, Vive, vor) drew 0.50 of none's triangles
 * but lost foveated SSIM 0.9943 and FLIP 0.0153 in the periphery, against the goals 0.995 and 0.01;
 * at k = 2 it drew 0.69 at 0.9985 and 0.0038 (docs/visibility.md "The safety factor"). */
#define FRM_CSF_SCALE_DEFAULT 2.0


/* ---- visibility ----------------------------------------------------------------------------- */
/* The criterion a session judges lost detail by (frame/visibility.c, docs/visibility.md). */
enum frm_visibility_criterion { FRM_VISIBILITY_CONTRAST = 0, FRM_VISIBILITY_ACUITY = 1 };
/* The options --visibility, --csf and --csf-scale of o, parsed and range-checked (NULL names are
 * the defaults); 0, or −1 with err naming the option. frm_options_check and frm_visibility_open
 * both call it. */
int frm_visibility_options(const struct frm_options *o, enum frm_visibility_criterion *criterion,
                           enum acu_csf_model *csf, struct hl_error *err);
const char *frm_visibility_name(enum frm_visibility_criterion c);
/* Under contrast: the CSF table at the adapting luminance, the display's peak luminance times the
 * mean relative luminance of the previous frame (FRM_ADAPT_FIRST_FRAME on the first). The table is
 * refilled only when that luminance moves by more than FRM_ADAPT_REFILL_RATIO (a fill is ~0.2 ms;
 * 5 % of L moves log10 S by under 0.01 at 1–1000 cd/m²). */
#define FRM_ADAPT_FIRST_FRAME 0.5
#define FRM_ADAPT_REFILL_RATIO 1.05
struct frm_visibility {
    enum frm_visibility_criterion criterion;
    enum acu_csf_model csf;
    double peak_luminance_cdm2;     /* the display profile's */
    double adapting_luminance_cdm2; /* the table's */
    struct acu_csf_table *table;    /* 116 KB, heap; NULL under acuity */
    struct acu_contrast_limits limits;
    long refills;                   /* table fills after the first */
};
/* Parses the options and, under contrast, allocates and fills the table. 0, or −1 naming the option. */
int frm_visibility_open(struct frm_visibility *v, const struct frm_options *o, const struct hmd_profile *display,
                        const struct acu_limits *acuity, struct hl_error *err);
void frm_visibility_close(struct frm_visibility *v);
/* The previous frame's mean relative luminance (0…1) sets the next frame's adaptation. */
void frm_visibility_adapt(struct frm_visibility *v, double mean_relative_luminance);

/* ---- the session ---------------------------------------------------------------------------- */
/* The visible-set test of a frame (DESIGN.md step 3): the union of both eyes' frusta of a display
 * as world-space planes for scn_cull (scene/cull.h). Init once per display; the planes per pose. */
struct frm_cull_frustum {
    hl_vec3d normals_head[4]; /* unit inward normals of the side planes, head frame, through its centre */
    double near_m, margin_m;  /* near plane; half the IPD, by which every plane moves out */
};
void frm_cull_frustum_init(struct frm_cull_frustum *f, const struct hmd_profile *display, double near_m);
/* Writes the five planes (left, right, top, bottom, near) for a head pose (position, body-to-world
 * orientation) and returns 5. */
int frm_cull_frustum_planes(const struct frm_cull_frustum *f, const struct trk_pose *pose, struct scn_plane *planes);

/* Per-frame working arrays, sized once when the scene loads (DESIGN.md: steps 4–7 allocate nothing). */
struct frm_frame_arrays {
    uint32_t *visible;
    double *eccentricity_deg, *velocity_degps, *diameter_deg;
    uint8_t *lod;
    uint32_t *draw_index; /* visible objects then group impostors: what the renderer gets */
    uint8_t *draw_lod;
};

struct frm_session {
    struct hmd_profile display;
    struct hmd_eye eyes[2];
    struct acu_limits limits;
    struct scn_scene scene;
    struct lod_chain *chains;
    struct frm_visibility visibility;
    struct trk_pose_source *source;
    struct rnd_renderer *renderer;
    struct frm_frame_arrays arrays;
    enum frm_selector selector;
    struct frm_select select;
    char cost_label[160];     /* where the cost model came from, for the summary */
    enum frm_freq_reading reading;
    int max_lods;
    double near_m, far_m;
    struct frm_cull_frustum cull_frustum; /* computed once per session: no square roots per frame */
    struct scn_culler culler; /* the hierarchical cull's scratch, sized when the scene loads */
    /* Gaze (acuity/gaze.h, docs/gaze.md): the model, the VOR's parameters with the fixation
     * distance, and the eyes' offset from the neck for sources without positions (zero otherwise). */
    enum acu_gaze_model gaze;
    struct acu_vor_params vor;
    hl_vec3d neck_to_eye_head_m;
    int trace_has_gaze, trace_has_position; /* what the pose source carries (set with the source) */
    /* The last frame's eyes and world gaze, for its full-detail reference (frm_frame_reference). */
    struct rnd_eye_view frame_views[2];
    hl_vec3d frame_gaze_dir;
    struct frm_layers layers; /* foveated layers (frame/layers.h); mode off: the plain frame */
    int composite_in_distortion; /* set by a runner with a distortion pass (live): the frame leaves the
                                  * layers' composite to that pass (render/window.h) */
};

/* Opening a session, in two steps so that its runner makes the pose source between them (replay
 * opens its trace after the display, as a file's errors are reported in that order):
 * open_display adopts what `made` gives (closed by frm_session_close even when opening fails) and
 * loads the display, the eyes and the acuity limits; then the runner sets s->source (and
 * trace_has_gaze, trace_has_position) unless made gave one; open_scene chooses the gaze model,
 * builds the scene, its measured tables, the selector, the cost model and the renderer (unless made
 * gave one, e.g. made in a window's context), and warms the driver up. s->selector and s->reading
 * must be set first (frm_options_check). frm_session_open does both steps for a made source. */
struct frm_session_made {
    struct trk_pose_source *source;
    struct rnd_renderer *renderer;
};
int frm_session_open_display(struct frm_session *s, const struct frm_options *o, const struct frm_session_made *made,
                             struct hl_error *err);
int frm_session_open_scene(struct frm_session *s, const struct frm_options *o, struct hl_error *err);
int frm_session_open(struct frm_session *s, const struct frm_options *o, const struct frm_session_made *made,
                     struct hl_error *err);
void frm_session_close(struct frm_session *s);

/* ---- one frame ------------------------------------------------------------------------------ */
/* What one frame did, for its CSV row. */
/* Retinal-speed bands of the frame record, deg/s (lower edges): still, slow, moderate, fast. */
enum { FRM_RETINAL_BANDS = 4 };
extern const double frm_retinal_band_lower_degps[FRM_RETINAL_BANDS];
/* The band a value falls in, given count ascending lower edges (lower[0] takes everything below
 * lower[1], NaN included; the last band is open above). */
int frm_band_of(const double *lower, int count, double value);

struct frm_frame_record {
    long frame;
    double time_s;
    double head_speed_degps;
    double eye_speed_degps; /* the eye's angular speed in the world under the gaze model */
    uint32_t visible;
    uint32_t cull_groups_tested, cull_instances_tested; /* scn_cull_stats (summary only, not the CSV) */
    uint64_t acuity_evaluations;
    uint64_t triangles_per_eye, triangles_finest;
    /* The visible objects' triangles (one eye) split by where they are: by eccentricity band
     * (rnd_ecc_band_lower_deg, the image error's bands) and by retinal-speed band
     * (frm_retinal_band_lower_degps); drawn (a dropped object draws 0) and finest (level 0). */
    uint64_t ecc_drawn[RND_ECC_BANDS], ecc_finest[RND_ECC_BANDS];
    uint64_t retinal_drawn[FRM_RETINAL_BANDS], retinal_finest[FRM_RETINAL_BANDS];
    uint32_t lod_histogram[SCN_MAX_LODS];
    double acuity_us, select_us, draw_ms, frame_ms;
    int deadline_met;
    long minor_faults;        /* pages the process faulted in during the frame (getrusage, all threads) */
    struct frm_select_record sel;
    double visible_error;     /* frm_select_visible_error, outside the frame's timing */
    int has_image_error;      /* a --reference frame: image and flip hold its comparison */
    struct rnd_image_error image;
    struct rnd_flip_result flip; /* LDR-FLIP (render/flip.h) at flip_ppd, the eye images' centre */
    double flip_ppd;
    double adapting_luminance_cdm2; /* the contrast criterion's this frame; NaN under acuity */
    double luminance_us;            /* reading the frame's mean luminance back (contrast), in frame_ms */
    struct rnd_draw_stats draw;     /* the draw's counts, with the layers' pixels (render/render.h) */
    double inset_x_deg, inset_y_deg;   /* the inset's centre in the head frame: right and up of ahead
                                        * (atan2 of x and y over −z); 0, 0 without layers */
    double composite_ms, composite_px; /* the layers' composite (0 for a plain frame): the compositor's
                                        * pass, timed apart and not in frame_ms (docs/foveation.md) */
};

/* Before the visible set: moves the scene to time t_s (scene/motion.h): instance poses, bounding-
 * sphere centres, group spheres and frames. Returns the instances' world velocities (3 per instance,
 * m/s) for acu_compute_geometry, or NULL for a static scene (s->motion == NULL), which it leaves
 * untouched. Allocates nothing. */
const double *frm_motion_step(struct scn_scene *s, double t_s);

/* The head's state at time_s for the session's gaze model: eyes from the neck model (or the source's
 * position), the measured gaze, and for the VOR the head latency_s earlier. Also the pose whose
 * position is the cyclopean eye, for the cull and the eye views. */
int frm_frame_head_state(struct frm_session *s, double time_s, struct trk_pose *eye_pose,
                         struct acu_head_state *head, struct hl_error *err);

/* Culls, computes viewing geometry, selects and draws one frame at `time_s`. */
int frm_frame_run(struct frm_session *s, long frame, double time_s, struct frm_frame_record *rec,
                  struct hl_error *err);

/* Before the first frame (frm_session_open_scene calls it, for replay and live alike): draws one
 * instance of every chain at every level from a still pose, untimed, so that the driver's first-use
 * work (shader compilation, buffer residency: tens of ms on llvmpipe) is not measured as frame 0 and
 * fed to the cost correction. */
int frm_frame_warm_up(struct frm_session *s, struct hl_error *err);

/* After frm_frame_run (and any capture of it): reads the frame back into test (unless test_read: a
 * capture has just read it there), draws the same visible objects at their finest levels from the
 * same eyes into ref, and compares them (render/image_error.h) with the foveated weights M(E) around
 * the frame's gaze, and by LDR-FLIP (render/flip.h, which allocates its scratch per call) at the
 * pixels per degree of the eye images' centre; fills rec->image, flip, flip_ppd and has_image_error.
 * Both buffers hold the renderer's whole image; w fits it. Outside the frame's timing. */
int frm_frame_reference(struct frm_session *s, struct frm_frame_record *rec, uint8_t *test, int test_read,
                        uint8_t *ref, struct rnd_image_error_work *w, struct hl_error *err);

#endif
