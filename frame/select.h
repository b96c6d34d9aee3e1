/* frame/select.h (part of frame/frame.h): steps 5–7 of a frame (DESIGN.md "One frame") — perceptual ceiling, cost and
 * benefit, selection — for every selector: none, reddy, static, feedback, fs. The arrays are
 * sized when the scene loads; a frame allocates nothing. */
#ifndef HMDLOD_FRAME_SELECT_H
#define HMDLOD_FRAME_SELECT_H

#include "acuity/acuity.h"
#include "lod/lod.h"
#include "scene/scene.h"
#include "frame/layers.h"

/* How fs and mb correct their budget from measured draw times (lod.h): not at all, by the smoothed
 * measured/predicted ratio, or by the affine fit measured = a + b·x (the default: it learns the
 * fixed cost apart from the objects', so a fixed cost the model under-counts is not taken out of the
 * objects' share again and again — the ratio divides the whole budget, which spirals down when
 * little is drawn; docs/cost-model.md). The first FRM_CORRECTION_WARMUP_FRAMES frames of a session
 * do not teach it: they pay first-use costs (page faults, driver caches) later frames do not. */
enum frm_correction { FRM_CORRECTION_OFF = 0, FRM_CORRECTION_RATIO = 1, FRM_CORRECTION_AFFINE = 2 };
enum { FRM_CORRECTION_WARMUP_FRAMES = 5 };
/* fs drops objects only when even the coarsest levels do not fit, and never one whose estimated
 * coverage is at least this share of all eyes' pixels (about 26 000 pixels an eye on a Vive, a
 * 160-pixel square): a hole that size shows at any eccentricity, whatever it saves. A room's walls,
 * floor and ceiling fill 5–40 % of the image each, its stage about 3 %; dropping them held a
 * load-shrunk budget by showing an empty room. On the auditorium at full resolution (users 1–2,
 * docs/RESULTS.md "Honest speed") 1 % kept so many chairs that frames ran 12–16 ms; 5 % let the
 * stage go; 2 % kept the room and the nearest rows within the budget on 93–94 % of the frames.
 * mb chooses among group impostors and does not use it yet. */
#define FRM_KEEP_IMAGE_SHARE 0.02

enum frm_selector {
    FRM_SELECT_NONE = 0,
    FRM_SELECT_REDDY,
    FRM_SELECT_STATIC,
    FRM_SELECT_FEEDBACK,
    FRM_SELECT_FS,
    FRM_SELECT_MB,
};
/* "none" … "fs" → the enum; −1 with the known names in err for anything else. */
int frm_selector_parse(const char *name, enum frm_selector *out, struct hl_error *err);
/* fs and mb's benefit when --benefit is not given (docs/optimizer.md "Perceptual benefit": on equal
 * budgets Funkhouser's accuracy gave the higher foveated SSIM). */
#define FRM_BENEFIT_DEFAULT "funkhouser"
/* --benefit (NULL = FRM_BENEFIT_DEFAULT): *perceptual = 1 for "perceptual", 0 for "funkhouser";
 * −1 naming the option otherwise. Its pairing with the criterion is frm_options_check's. */
int frm_benefit_parse(const char *name, int *perceptual, struct hl_error *err);
/* 1 for the selectors whose choice follows the perceptual ceiling (reddy, fs, mb); the others
 * (none, static, feedback) see it only in the predicted visible error, after the frame's timing. */
int frm_selector_uses_ceiling(enum frm_selector selector);

/* Saccade suppression and the 28 ms refinement rule (acuity/saccade.h; docs/gaze.md). Active only
 * when the frame's pose has a measured gaze and the gaze model is tracked (head and vor stand for a
 * headset without an eye tracker, which cannot see saccades); otherwise the phase stays NONE. */
struct frm_refine_entry {
    double eccentricity_deg;
    uint32_t instance, k; /* the scene instance (ties), the visible object */
    uint8_t target;       /* the level it is owed */
};
struct frm_saccade {
    struct acu_saccade_params params;
    struct acu_saccade_state state;
    int active;           /* this frame's pose has gaze */
    int missed;           /* the current refinement has already missed its deadline */
    int started;          /* a saccade started this frame */
    uint8_t *level_before; /* per scene instance: its level on the frame before the saccade (LOD_UNSEEN) */
    struct frm_refine_entry *refine; /* per visible object: the refinement boost's order (saccade_step.c) */
    double speed_degps;   /* this frame's gaze speed in the world (0 without gaze) */
    double time_s;        /* this frame's time */
};

struct frm_select {
    enum frm_selector selector;
    struct lod_cost_model cost;
    struct lod_benefit_params benefit;
    double budget_ms;          /* the frame's whole budget (display period unless --budget-ms) */
    double opt_limit_us;       /* Nirenstein's time limit for fs and mb; 0 = none */
    double static_px;          /* static: pixels per triangle */
    int correct;               /* enum frm_correction */
    struct lod_cost_correction correction;
    struct lod_cost_rls rls;   /* the affine correction, when correct is FRM_CORRECTION_AFFINE */
    double overhead_ms;        /* smoothed frame time outside the draw (pose, cull, selection) */
    long frames_measured;      /* frames frm_select_measured has seen (the warm-up is not learnt from) */
    struct lod_feedback feedback;

    /* per visible object (capacity: the scene's instances) */
    double *pixels_px;
    uint8_t *boxed;            /* 1: pixels_px is the model box's projection, 0: the bounding sphere's */
    uint8_t *ceiling_level, *previous_level, *choice;
    uint8_t *seen_level;       /* the level hysteresis is measured from: the last one the viewer saw */
    uint8_t *keep;             /* 1: covers ≥ FRM_KEEP_IMAGE_SHARE of the image, never dropped */
    double *coarsest_ms;       /* the candidate being built: each object's coarsest level's cost */
    uint32_t *first;
    uint8_t *count;
    /* per candidate (capacity: instances × (LOD_MAX_LEVELS + 1)) */
    double *cand_cost_ms, *cand_benefit;
    uint8_t *cand_level;
    uint32_t *cand_samples;
    /* per scene instance: last frame's level (LOD_UNSEEN when not drawn), and the last visible list */
    uint8_t *level_of_instance;
    size_t level_capacity; /* entries of level_of_instance (the scene's instances) */
    uint32_t *last_visible;
    uint32_t last_visible_count;
    /* per chain, for static and feedback: triangles[c·LOD_MAX_LEVELS + l], lod_count[c] */
    uint32_t *chain_triangles;
    uint8_t *chain_lod_count;
    void *scratch;
    double fs_margin_value;    /* last frame's lod_result.margin_value (fs), 0 before the first */
    struct frm_mb *mb; /* the mb selector's tree and last solution (frame/select_mb.h); NULL otherwise */
    int mb_simplify;   /* set before frm_select_init: hierarchy simplifications for mb (select_mb.h) */
    double saccade_onset_degps; /* set before frm_select_init; ≤ 0 → acu_saccade_params_default's */
    int saccade_off;            /* 1: a gaze model without an eye tracker (head, vor): no saccades known */
    int perceptual_benefit;     /* set before frm_select_init: fs and mb value levels by visible loss */
    double *visible_loss;       /* per visible object × LOD_MAX_LEVELS (lod_visible_loss_contrast), when
                                 * perceptual_benefit and the frame has contrast limits */
    int visible_loss_valid;     /* this frame's visible_loss was computed */
    struct frm_saccade saccade;
    struct frm_layers *layers; /* the session's foveated layers (frame/layers.h); NULL or mode off: none */
};

/* Issue 30's check on fs and mb: a frame that drops objects must not end under this share of its
 * budget while a dropped object would have fit (the optimizers' rule makes it 0 every frame). */
#define FRM_UNDERUSED_FRACTION 0.7

/* What selection did in one frame, for its CSV row. */
struct frm_select_record {
    double budget_ms, optimizer_budget_ms; /* the frame's budget; what the optimizer was given */
    double predicted_ms;                   /* c0 + Σ predicted object costs of what is drawn */
    double benefit, lp_bound;              /* Σ benefit of the choice; the LP upper bound (fs, mb) */
    uint32_t iterations, dropped, lod_changes;
    uint64_t acuity_evaluations;           /* H(v,E) evaluations, plus CSF lookups under contrast */
    int truncated, over_budget;
    int underused_drop;                    /* fs, mb: 1 when the choice costs under FRM_UNDERUSED_FRACTION of
                                            * optimizer_budget_ms while an object it dropped would have fit
                                            * in the rest (lod_choice_underused_drop); 0 otherwise */
    double dropped_px_share;               /* Σ estimated pixels of the dropped visible objects / Σ of all
                                            * visible objects': what vanished from the image, not how many */
    double optimizer_us;
    double lp_us;                          /* the LP bound's own time, left out of the frame's */
    /* saccades (frame/saccade_step.c): phase this frame; once suppression has ended and until the
     * objects are refined, the objects drawn coarser than their ceiling (pending) and those among them
     * whose refinement the budget's slack would have paid for; miss = such objects past the deadline */
    int saccade_active, saccade_phase, saccade_started;
    /* foveated layers (frame/layers.h): the chosen periphery scale (1: none) and inset radius, whether
     * it is coarser than the resolution ceiling, and how many settings were weighed (fs: solved) */
    double layer_scale, inset_radius_deg;
    int layer_loses, layer_candidates;
    double gaze_speed_degps;
    uint32_t refine_pending, refine_unbudgeted;
    int refine_miss, refine_missed_saccade; /* this frame missed; first missed frame of its saccade */
};

/* The machine cost profile: `path` (a JSON file written by hmdlod calibrate) or, for NULL, the
 * built-in profile for llvmpipe; label_out says which, for the summary. layers_out (NULL: not
 * wanted) gets the layers' models (frame/layers.h struct frm_layer_costs): per layer scale the
 * profile's periphery model at that scale, or where it has none (and at scale 1) the plain model;
 * the inset's model where it has one (inset_measured; the plain model prices the inset where not);
 * and how many periphery models it had. */
int frm_cost_model_load(const char *path, struct lod_cost_model *out, struct frm_layer_costs *layers_out,
                        char *label_out, size_t label_size, struct hl_error *err);

int frm_select_init(struct frm_select *s, const struct scn_scene *scene, struct hl_error *err);
void frm_select_free(struct frm_select *s);

/* Chooses a level for each of the n visible objects (lod_out; LOD_DROP = not drawn) and, for mb,
 * the group impostor instances to draw after them (extra_index/extra_level, *extra_count). eyes are
 * the two eyes' views for projected coverage. */
struct frm_view_inputs {
    const uint32_t *visible;
    size_t count;
    const double *eccentricity_deg, *velocity_degps, *diameter_deg;
    const struct acu_limits *limits;
    const struct lod_chain *chains;
    const struct acu_eye *eyes; /* two */
    /* The contrast criterion (frame/visibility.c): NULL → the acuity criterion, Reddy's H(v, E) with
     * unique_freq_cpdiam; else lod_select_contrast with these limits (docs/visibility.md). */
    const struct acu_contrast_limits *contrast;
};
void frm_select_frame(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                      uint8_t *lod_out, uint32_t *extra_index, uint8_t *extra_level, size_t *extra_count,
                      struct frm_select_record *rec);
/* Before frm_select_frame, once per frame: the gaze's world speed (pose's gaze angular velocity, deg/s)
 * into the saccade classifier. While suppressed (inside a saccade and its window) the selectors that
 * use the perceptual ceiling (reddy, fs, mb) see every object's ceiling at its coarsest level; static,
 * feedback and none do not use the ceiling and are left as they are (frame/saccade_step.c). */
struct trk_pose;
void frm_select_saccade(struct frm_select *s, const struct trk_pose *pose, double time_s);
/* Inside frm_select_frame (frame/saccade_step.c): the level a scene instance's hysteresis is measured
 * from — last frame's, or while a saccade's refinement is owed the level before it (the suppressed
 * frames were not seen); while suppressed, lowers the ceilings of the n visible objects to their
 * coarsest levels; after the choice, the refinement accounting of rec (layer: the chosen setting, NULL
 * for the plain frame — an object only the periphery shows is owed no more than its periphery ceiling,
 * and a raise is priced as the setting prices it). */
uint8_t frm_saccade_seen_level(const struct frm_select *s, uint32_t instance);
void frm_saccade_lower_ceilings(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in);
struct frm_layer_candidate;
/* The refinement boost (issue 32 item 5), fs only, after the choice and before its prediction: while a
 * refinement is owed, each object still drawn coarser than what the saccade took from it is raised to
 * that level where the raise fits what the optimizer's budget has left under the chosen setting —
 * nearest the gaze first (the fovea sees first what the saccade landed on). Returns the raises. */
uint32_t frm_saccade_refine(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                            uint8_t *lod, const struct frm_layer_candidate *layer, double budget_ms);
void frm_saccade_account(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                         const uint8_t *lod, const struct frm_layer_candidate *layer, struct frm_select_record *rec);
/* Visible object k at a level under a layer setting (NULL or scale 1: the plain frame), ms: what
 * build_problem prices its candidates at. The setting's pixels must be prepared (its inset pixels). */
struct scn_chain;
double frm_select_level_cost_ms(const struct frm_select *s, const struct frm_layer_candidate *layer,
                                const struct scn_chain *ch, int level, size_t k);
/* After frm_select_frame, outside the frame's timing: the predicted visible error of the levels lod
 * (per visible object, LOD_DROP for not drawn): the share of the visible objects' projected pixels
 * whose object is drawn coarser than its perceptual ceiling, or dropped where the ceiling draws it.
 * Computes the ceilings for selectors that do not use them (none, static, feedback). In [0, 1]; 0 when
 * nothing is visible. */
double frm_select_visible_error(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                                const uint8_t *lod);
/* After the draw: the measured draw and frame times feed the correction and the feedback controller. */
void frm_select_measured(struct frm_select *s, const struct frm_select_record *rec, double draw_ms, double frame_ms);

/* Projected pixels of the visible objects, summed over the eyes (frame/coverage.c): bounding
 * spheres (acu_compute_pixels), and for objects that claim over 2 % of the image also their
 * oriented model box (acu_compute_pixels_box), keeping the smaller. pixels_px[k] per visible[k];
 * boxed[k] (NULL: not wanted) 1 where the box's figure was kept. */
struct acu_eye;
void frm_coverage_compute(const struct scn_scene *scene, const struct acu_eye *eyes, int eye_count,
                          const uint32_t *visible, size_t count, double *pixels_px, uint8_t *boxed);
/* An object at level `level` of its chain ch, both eyes, in the cost profile's units (lod.h): its
 * triangles, vertices and 2 draws, and the fragments it rasterises — pixels_px (frm_coverage_compute)
 * times the level's fill of the bound pixels_px measured (boxed 1: the model box; scn_lod_fill). */
double frm_level_cost_ms(const struct lod_cost_model *m, const struct scn_chain *ch, int level, double pixels_px,
                         int boxed);
/* The same in the foveal inset (frm_inset_object_ms): pixels_px within its rectangles, inside_share
 * the share of the object's image they are. */
double frm_level_inset_cost_ms(const struct frm_inset_cost *m, const struct scn_chain *ch, int level,
                               double pixels_px, double inside_share, int boxed);

#endif
