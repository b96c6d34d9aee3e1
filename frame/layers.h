/* frame/layers.h (part of frame/frame.h): resolution as a representation (issue 32). Each frame the
 * foveated layers (render/layers.h) get a setting — the periphery's scale s and the inset's radius —
 * from the same cost-bounded choice as the objects' levels:
 *   - the resolution ceiling (acuity/resolution.c): for each scale s the inset radius R_s beyond which
 *     nothing above s·ξ is visible, at the slowest retinal speed among the visible objects and at the
 *     content's contrast ring by ring — the last frame's band contrast by eccentricity
 *     (rnd_renderer_ring_contrast; full contrast before the first frame) — widened by the inset
 *     centre's angle from the gaze (under fixed foveation the eye need not look at the lens centre);
 *   - candidates: s = 1 (no layers), and for each coarser s an inset at the ceiling's radius capped
 *     at the fovea's (FRM_LAYER_FOVEA_DEG): lossless where the ceiling is within it, else losing
 *     what lies between (their benefit says how much);
 *   - fs solves its knapsack once per candidate, each object priced per layer (the inset's pixels at
 *     full resolution, the periphery's at s², its geometry in every layer it touches) with the
 *     candidate's own measured overhead (its clears against the plain frame's) taken from the budget,
 *     and keeps the best outcome (frm_layers_outcome_better); the other selectors
 *     keep their levels and take the cheapest candidate that loses nothing (the ceiling, as reddy
 *     takes the LOD ceiling).
 * The periphery draws each object no finer than its LOD ceiling at s·ξ (periphery_ceiling): detail
 * the periphery's pixels cannot show costs geometry for nothing; the inset draws the chosen level.
 * What a lossy candidate takes from an object's benefit, in the units its levels are valued in. D is
 * the visible loss of the periphery's scale on it in threshold units — Σ over the octave bands the
 * scale cannot show of max(0, c·S·k − 1), c its ring's content contrast, S at its eccentricity and
 * retinal speed (the units of the perceptual benefit's lost LOD detail, lod_visible_loss_contrast) —
 * and f the share of it in the periphery (its part in the inset keeps its detail). Under the
 * perceptual benefit the object is scaled by (1 − f) + f · a(D), a the accuracy that benefit gives a
 * level losing D (lod_benefit_perceptual_accuracy); under Funkhouser's, where D > 0,
 * each level's periphery part is worth its accuracy with Samples at most s²·pixels (§5), so a scale
 * weighs against a level as their accuracies do (frm_layers_level_share). Either way a scale coarser
 * than the ceiling costs benefit where it shows, a finer one earns nothing. docs/foveation.md. */
#ifndef HMDLOD_FRAME_LAYERS_H
#define HMDLOD_FRAME_LAYERS_H

#include "acuity/acuity.h"
#include "lod/lod.h"
#include "render/render.h"
#include "frame/cost.h"

/* adaptive: no inset — the whole eye at one scale a reactive controller sets from the measured draw
 * time, as Valve's adaptive quality does (the comparison issue 32 asks for; frm_adaptive_*). */
enum frm_foveation_mode {
    FRM_FOVEATION_OFF = 0,
    FRM_FOVEATION_FIXED = 1,
    FRM_FOVEATION_GAZE = 2,
    FRM_FOVEATION_ADAPTIVE = 3
};
/* "off" | "fixed" | "gaze" | "adaptive" (NULL = off) → the mode; −1 naming the option otherwise. */
int frm_foveation_parse(const char *name, enum frm_foveation_mode *out, struct hl_error *err);
const char *frm_foveation_name(enum frm_foveation_mode mode);

/* The periphery's scales (issue 32): 1 is the plain frame. */
enum { FRM_LAYER_SCALES = 5 };
extern const double frm_layer_scales[FRM_LAYER_SCALES];
/* The largest inset a candidate gets, from the gaze (degrees; under fixed foveation plus the lens
 * centre's angle from the gaze): a scale whose ceiling lies beyond it loses what lies between. The
 * inset's edge keeps the full resolution, and the blend band (FRM_LAYER_BLEND_DEG_DEFAULT) covers the
 * rest of Reddy's flat fovea (M(E) = 1 to 5.79°, 1998 eq. 3). Measured, not derived: with the
 * ceiling's 15–40° insets and a grid down to none, fs kept 10–16° insets under Funkhouser's benefit
 * with a fifth of the triangles, or no inset under the perceptual one with the gaze's objects at
 * their coarsest; a 5° inset under Funkhouser's beat both on fSSIM, FLIP and time (docs/RESULTS.md,
 * issue 32 fifth round). --inset-deg overrides it. */
#define FRM_LAYER_FOVEA_DEG 5.0
enum { FRM_LAYER_CANDIDATES_MAX = FRM_LAYER_SCALES };
/* The blend band's width by default: wide enough that the step between a 4× coarser periphery and
 * the inset spreads over ~50 pixels of a Vive's eye (test_layers: no step across its edges). */
#define FRM_LAYER_BLEND_DEG_DEFAULT 5.0

/* The cost models of the layers (a cost profile's, frame/cost.h): per scale the periphery's (the
 * plain model where the profile has none, and at scale 1), and the inset's where the profile has
 * one; the counts say how many it had. */
struct frm_layer_costs {
    struct lod_cost_model periphery[FRM_LAYER_SCALES];
    struct frm_inset_cost inset; /* inset_measured 0: unused (the plain model prices the inset) */
    int periphery_count, inset_measured;
};

struct frm_layer_candidate {
    double scale, inset_radius_deg;
    struct rnd_layer_plan plan; /* what render will draw for it: the insets' rectangles, the sizes */
    double ceiling_radius_deg; /* R_s (+ the centre's offset): the inset that loses nothing at this s */
    double overhead_ms;        /* the layers' own cost (their clears against the plain frame's), measured
                                * at warm-up; the composite is the compositor's (docs/foveation.md) */
    int loses;                 /* 1: inset_radius_deg < ceiling_radius_deg */
};

/* Valve's adaptive quality (PAPERS.md §5, The Lab renderer), as this project reads its description:
 * quality levels L = 0 … FRM_ADAPTIVE_LEVELS − 1, each 15 % less fill than the one before (linear
 * scale √0.85^L, so level 17 is just over 0.25); after a frame whose draw took over 0.90 of the budget
 * drop two levels, then hold drops for two frames (three frames together); drop one when the draw
 * time extrapolated linearly one frame ahead exceeds 0.90; climb one level after 6 frames in a row
 * under 0.70 and two after 12 (the count restarts after a climb). */
enum { FRM_ADAPTIVE_LEVELS = 18, FRM_ADAPTIVE_HOLD_FRAMES = 2 };
#define FRM_ADAPTIVE_LOW 0.70
#define FRM_ADAPTIVE_HIGH 0.90
#define FRM_ADAPTIVE_FILL_STEP 0.85
struct frm_adaptive {
    int level, cheap_frames, hold;
    double last_draw_ms;  /* < 0 before the first measured frame */
};
void frm_adaptive_init(struct frm_adaptive *a);
double frm_adaptive_scale(const struct frm_adaptive *a); /* √(0.85^level) */
void frm_adaptive_update(struct frm_adaptive *a, double draw_ms, double budget_ms);

struct frm_layers {
    enum frm_foveation_mode mode;
    struct frm_adaptive adaptive; /* the adaptive mode's controller */
    double blend_deg;          /* > 0 */
    double forced_scale;       /* > 0: --periphery-scale fixes s */
    double forced_radius_deg;  /* ≥ 0: --inset-deg fixes the radius; < 0: from the ceiling */
    double overhead_ms[FRM_LAYER_SCALES]; /* per scale, measured at warm-up (0 for s = 1) */
    /* What an object costs in each layer (frm_cost_model_load). Set by the session after
     * frm_layers_init; costed 0: the plain model everywhere. */
    struct frm_layer_costs cost;
    int costed;
    /* this frame */
    struct frm_layer_candidate cand[FRM_LAYER_CANDIDATES_MAX];
    int cand_count, chosen, evaluated; /* evaluated: candidates fs solved */
    int first_loss;                    /* cand[first_loss …] lose visible detail (those before: none) */
    hl_vec3d centre_world;      /* the inset's centre, unit world direction */
    double centre_offset_deg;   /* its angle from the gaze model's gaze */
    double slowest_degps;       /* the slowest visible object's retinal speed (0 when the fovea is held) */
    double xi_cpd;              /* the rendered image's ξ (frm_layers_plan's) */
    /* what the content needs: the last frame's band contrast by ring of eccentricity around its gaze
     * (render/layers.h; not valid before the first frame: full contrast), and per ring the coarsest
     * scale that loses nothing visible there */
    struct rnd_ring_contrast rings;
    double needed_scale[RND_CONTRAST_RINGS];
    /* per visible object (capacity: the scene's instances) */
    double *centre_angle_deg;   /* its centre's angle from the inset centre */
    double *radius_deg;         /* half its angular diameter, plus the eyes' parallax */
    double *inset_px;           /* the pixels it covers inside the current candidate's inset rectangles */
    double *resolution_loss;    /* [k·FRM_LAYER_SCALES + i]: D of scale i on it (0 for i = 0), filled
                                 * on first use in a frame (loss.ready) */
    struct frm_layers_loss_inputs {
        const struct acu_limits *acuity;
        const struct acu_contrast_limits *contrast;
        const double *eccentricity_deg, *velocity_degps; /* the frame's arrays, as frm_layers_plan got them */
        size_t count;
        int ready;
    } loss;
    int inset_px_of;            /* the candidate inset_px was computed for (−1: none yet this frame) */
    uint8_t *mask;              /* per draw entry (capacity: instances + groups + 1): RND_LAYER_* */
    uint8_t *periphery_lod;     /* per draw entry: the level the periphery draws (frm_layers_periphery_levels) */
    /* [k·FRM_LAYER_SCALES + i]: the coarsest level of visible object k whose lost detail the periphery
     * at scale i cannot show (its LOD ceiling at s·ξ; 0 for i = 0) — the periphery draws no finer */
    uint8_t *periphery_ceiling;
    uint8_t *lod_scratch;       /* per visible object: one scale's LOD ceilings (frm_layers_periphery_ceilings) */
};

/* Allocates the per-object arrays for `instances` objects and `groups` group impostors; mode and
 * the forced values from the options. 0, or −1 (out of memory). */
int frm_layers_init(struct frm_layers *l, enum frm_foveation_mode mode, double blend_deg, double forced_scale,
                    double forced_radius_deg, uint32_t instances, uint32_t groups, struct hl_error *err);
void frm_layers_free(struct frm_layers *l);

/* This frame's candidates (before selection): the inset centre (the lens centre, or under gaze
 * foveation the gaze model's gaze), each visible object's angle from it, the slowest retinal speed,
 * the ceiling radius per scale under the session's criterion (contrast: NULL → acuity's), each
 * object's resolution loss per scale, and the candidate list (the adaptive mode: its controller's
 * scale alone). view: the viewer (world), the head's orientation, the eyes' frusta and the rendered
 * eye size; xi_cpd the rendered image's ξ. */
struct frm_layers_view {
    const struct acu_viewer *viewer;
    hl_quatd head_orientation;           /* the eyes' (both look the head's way) */
    const struct hmd_eye *eyes;          /* two: the frusta */
    int eye_w_px, eye_h_px;              /* the rendered eye images */
    double half_ipd_m;
    /* 1: the eye holds what it looks at still on the fovea — a measured gaze outside a saccade and its
     * suppression (a fixation, or a pursuit, which cancels its target's motion). The resolution the
     * inset needs is then taken at retinal speed 0, not at the slowest object's: a measured gaze's
     * velocity carries the tracker's noise (EDVAM's 0.1 m rounding reads as 25–45 deg/s), which made
     * every object look fast and the inset unneeded on one frame in ten (docs/foveation.md). */
    int fovea_held;
};
void frm_layers_plan(struct frm_layers *l, const struct frm_layers_view *view, const struct acu_limits *acuity,
                     const struct acu_contrast_limits *contrast, double xi_cpd, const double *center_m,
                     const double *radius_m, const uint32_t *visible, size_t count, const double *eccentricity_deg,
                     const double *velocity_degps);
/* The pixels each visible object covers inside candidate c's inset rectangles (l->inset_px), by the
 * coverage estimate the cost model prices with (frm_coverage_compute) on each eye's rectangle as an
 * image of its own: objects wholly inside the inset disc keep pixels_px, objects wholly outside get
 * 0, only those across its edge are projected. eyes: the frame's two (acu_eye). */
struct scn_scene;
void frm_layers_inset_pixels(struct frm_layers *l, int c, const struct scn_scene *scene, const struct acu_eye *eyes,
                             const uint32_t *visible, size_t count, const double *pixels_px);

/* How fs's solution under one candidate setting did (frame/select.c solve_fs_layers), and which of
 * two is better: the less late first — late_ms is how far the kept objects' coarsest levels alone
 * exceed the setting's expected budget (the correction's, less its margin: build_problem raises the
 * budget for them, and within that the frame spends its margin rather than drop), by more than
 * FRM_LAYER_LATE_TOLERANCE_MS (issue 32's p99 goal allows a frame 10 % of the 11.1 ms period over:
 * lateness below that does not outweigh a dropped object) —, then fewer dropped pixels (by more than
 * half a pixel: dropping is the last resort), then the less of the correction's margin spent (by
 * more than FRM_LAYER_MARGIN_TIE_MS: the margin is spent to keep objects, not to draw a larger inset
 * — preferring the higher benefit there raised the budget on most frames and cut the frames within
 * it from 96 to 79 %), then the higher benefit, then the less visible loss of the periphery's scale
 * (visible_loss_px: Σ pixels · (1 − frm_layers_benefit_share), the perceptual share whatever the
 * benefit — under Funkhouser's, the default, a scale moves the benefit by 10⁻⁹ of it, so two settings
 * keeping the same levels tied and the tie went to the cheaper, s = 0.25 or 0.35 even at 4× the
 * budget: docs/RESULTS.md tenth round), then the lower cost. Without the first rule the
 * plain frame, whose large objects at full resolution cost 30 ms on the auditorium, "dropped fewer
 * pixels" than every layered setting against a budget tightened to 4.6 ms and was drawn 240 frames in
 * a row, 20–30 ms each. */
#define FRM_LAYER_LATE_TOLERANCE_MS 1.0
#define FRM_LAYER_MARGIN_TIE_MS 0.05
struct frm_layer_outcome {
    double late_ms, dropped_px;
    double margin_ms; /* how far the budget was raised past the setting's own, within the expected one */
    double benefit, cost_ms;
    double visible_loss_px; /* Σ over the visible objects of pixels · (1 − frm_layers_benefit_share) */
};
int frm_layers_outcome_better(const struct frm_layer_outcome *a, const struct frm_layer_outcome *b);

/* An object's cost under a candidate (both eyes, cost-profile units): frm_level_cost_ms for its
 * pixels in the inset rectangles (frm_layers_inset_pixels, computed for c first) at full resolution
 * with the inset's model, plus, where it reaches past the inner disc, its whole image at s² in the
 * periphery (the periphery draws the whole eye) with the periphery's model at that scale (l->cost;
 * m for both where none is set), each layer paying the geometry. */
struct lod_cost_model;
struct scn_chain;
double frm_layers_level_cost_ms(const struct frm_layers *l, const struct frm_layer_candidate *c,
                                const struct lod_cost_model *m, const struct scn_chain *ch, int level,
                                double pixels_px, int boxed, size_t k);
/* The share of object k's benefit a candidate keeps, in (0, 1]. The first call for a lossy candidate
 * in a frame computes every visible object's resolution loss (from frm_layers_plan's inputs, which
 * must still hold); frames that weigh no lossy setting never pay for it. */
double frm_layers_benefit_share(struct frm_layers *l, const struct frm_layer_candidate *c, size_t k);
/* What candidate c's periphery takes from the visible objects' image: Σ over the count objects of
 * pixels_px[k] · (1 − frm_layers_benefit_share), in pixels (frm_layer_outcome.visible_loss_px); 0 for
 * a lossless setting. O(count). */
double frm_layers_visible_loss_px(struct frm_layers *l, const struct frm_layer_candidate *c, const double *pixels_px,
                                  size_t count);
/* The same under Funkhouser's benefit, for one level of object k (samples: the level's, or its LOD
 * ceiling's where it is finer; pixels_px: the object's): where the candidate's scale loses visible
 * detail on the object (D > 0), its periphery's part is worth the level's accuracy with Samples at
 * most s²·pixels_px over its accuracy at pixels_px (lod_benefit_accuracy; §5: Samples never more
 * than the pixels covered) — resolution in the units the levels are valued in. 1 where D = 0. The
 * perceptual share above (then 1/(1 + D)), next to accuracies 10⁻⁵–10⁻³ apart, made fs take the
 * finest scale that fit and starve the geometry (docs/RESULTS.md, issue 32 sixth round). */
struct lod_benefit_params;
double frm_layers_level_share(struct frm_layers *l, const struct frm_layer_candidate *c, size_t k,
                              const struct lod_benefit_params *p, double samples, double pixels_px);

/* After selection: the chosen candidate as render's setting for these eye views (orientation per
 * eye), and each draw entry's mask (visible objects, then n_extra group impostors: both layers). */
void frm_layers_setting(const struct frm_layers *l, const struct hmd_eye eyes[2], const hl_quatd orientation[2],
                        struct rnd_layers *out);
void frm_layers_masks(struct frm_layers *l, size_t count, size_t extra);
/* The periphery's levels for the chosen setting: each visible object's level, or its periphery
 * ceiling at the chosen scale where that is coarser; group impostors as they are. */
void frm_layers_periphery_levels(struct frm_layers *l, const uint8_t *lod, size_t count, size_t extra);
/* The finest level setting c shows of visible object k: its LOD ceiling where part of it lies within
 * the inset and its blend band, else (the periphery alone shows it) its periphery ceiling at c's scale.
 * After frm_layers_periphery_ceilings. */
uint8_t frm_layers_shown_ceiling(const struct frm_layers *l, const struct frm_layer_candidate *c, size_t k);
/* The periphery ceilings (periphery_ceiling) under the frame's criterion: the LOD ceiling with ξ
 * replaced by s·ξ for each scale this frame's candidates use (ξ: frm_layers_plan's), never finer than the object's own ceiling (a saccade's lowered
 * ones included). Called by the selection (frame/select.c) after the ceilings. */
struct lod_chain;
void frm_layers_periphery_ceilings(struct frm_layers *l, const struct acu_contrast_limits *contrast,
                                   const struct acu_limits *acuity, const struct lod_chain *chains,
                                   const uint32_t *chain_of_object, const uint32_t *visible, size_t count,
                                   const double *eccentricity_deg, const double *velocity_degps,
                                   const double *diameter_deg, const uint8_t *ceiling_level);

#endif
