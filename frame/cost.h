/* frame/cost.h: the machine's cost model from render/'s measurement — the non-negative fits of
 * Funkhouser & Séquin's max form and of the additive form (PAPERS.md §2, §5 "Cost models"), their
 * held-out accuracy, and the cost profile JSON (docs/cost-model.md) that hands lod/ a struct
 * lod_cost_model. Here because it joins render (the timed frames), acuity (the coverage estimate the
 * frame predicts with) and lod (the cost arithmetic). Part of the frame/frame.h umbrella. */
#ifndef HMDLOD_FRAME_COST_H
#define HMDLOD_FRAME_COST_H

#include "lod/lod.h"
#include "render/render.h"

/* render's measurement with every object's pixels_px filled with acu_compute_pixels' estimate for
 * the measured eyes: what `hmdlod calibrate` fits. Arguments and ownership as rnd_cost_measure. */
int frm_cost_calibrate(const struct hmd_profile *display, struct rnd_cost_grid *grid, uint64_t seed,
                       struct rnd_calibration *out, struct hl_error *err);

/* Frame prediction: c0 + Σ lod_cost_object_ms over the frame's objects. O(object_count). */
double frm_cost_predict_frame_ms(const struct lod_cost_model *m, const struct rnd_cost_frame *frame,
                                 const struct rnd_cost_object *objects);

/* ---- fitting (cost_fit.c) ---------------------------------------------------------------------- */
/* Non-negative least squares, Lawson & Hanson (1974, ch. 23): min |A·x − b|₂ subject to x ≥ 0.
 * a is row-major rows × cols, cols ≤ 16, rows ≥ 1; columns are scaled to unit norm internally, so
 * features of very different magnitude (1 per frame, 10⁶ pixels) fit together. Allocates O(rows ·
 * cols) scratch (calibration, never per frame). Returns 0, or −1 on bad sizes, non-finite input,
 * allocation failure or no convergence within 3·cols outer iterations (err says which).
 * *residual_norm (may be NULL) gets |A·x − b|₂. Cost O(iterations · rows · cols²). */
int frm_cost_nnls(const double *a, size_t rows, size_t cols, const double *b, double *x, double *residual_norm,
                  struct hl_error *err);

/* Fits one form on the frames listed in rows[0 … row_count−1] (indices into frames), all six
 * coefficients ≥ 0, minimising the squared RELATIVE error Σ((predicted − measured)/measured)²: the
 * budget cares about ratios, and unweighted least squares would let the heaviest frames decide.
 * LOD_COST_ADDITIVE: one NNLS. LOD_COST_MAX: alternating assignment — each object's max is replaced
 * by the stage that dominates it under the current coefficients, which makes the frame linear in
 * the coefficients; NNLS refits all six; repeat until no assignment changes (≤ 50 rounds), from
 * three starts (the additive fit's coefficients, all geometry, all pixels); the best true-max
 * objective wins. Needs measured_ms > 0 and finite counts on every listed frame. */
struct frm_cost_fit_report {
    double rms_relative; /* sqrt(mean(((pred − meas)/meas)²)) on the fitted frames */
    int rounds;          /* assignment rounds of the winning start (1 for additive) */
};
int frm_cost_fit(enum lod_cost_form form, const struct rnd_cost_frame *frames, const uint32_t *rows,
                 size_t row_count, const struct rnd_cost_object *objects, struct lod_cost_model *out,
                 struct frm_cost_fit_report *report, struct hl_error *err);

/* The same with c0 measured, not fitted (`calibrate` times empty frames, rnd_calibration.empty_ms):
 * only the objects' coefficients are fitted, on measured − c0, with the same relative weighting.
 * An intercept fitted to loaded frames absorbs whatever the per-object terms miss and is wrong at
 * both ends; the measured one is right where the budget is tightest, at frames that draw little.
 * expectile τ in (0, 1): asymmetric least squares (Newey & Powell 1987) — frames the model
 * under-predicts weigh τ, the others 1 − τ, refitted until none changes side — so τ > ½ fits a model
 * that under-predicts few frames (what breaks a budget); ½ is the ordinary fit. c0_ms finite, ≥ 0. */
int frm_cost_fit_fixed(enum lod_cost_form form, double c0_ms, double expectile, const struct rnd_cost_frame *frames,
                       const uint32_t *rows, size_t row_count, const struct rnd_cost_object *objects,
                       struct lod_cost_model *out, struct frm_cost_fit_report *report, struct hl_error *err);

/* ---- the inset's model (issue 32 item 4) ------------------------------------------------------
 * The foveal inset redraws, at full resolution under the scissor of its rectangle, every object that
 * reaches it. Of an object whose image lies a share a within the rectangle, the triangles inside are
 * set up and filled as in a plain frame; those outside are transformed, clipped and dropped at setup
 * — cheaper, not free (docs/cost-model.md) —; every vertex is shaded:
 *   lod_cost_object_ms(model, a·T, V, pixels within, D) + outside_ms_per_triangle · (1 − a)·T.
 * model is additive; its c0 the inset's empty frame (the scissored clears). a is clamped to [0, 1]. */
struct frm_inset_cost {
    struct lod_cost_model model;
    double outside_ms_per_triangle;
};
double frm_inset_object_ms(const struct frm_inset_cost *m, double triangles, double vertices, double pixels_px,
                           double draws, double inside_share);
/* c0 + Σ frm_inset_object_ms over the frame's objects (their inside_share). O(object_count). */
double frm_cost_predict_inset_frame_ms(const struct frm_inset_cost *m, const struct rnd_cost_frame *frame,
                                       const struct rnd_cost_object *objects);
/* Fits the inset's model to an inset grid (frm_cost_calibrate with grid.inset_radius_deg > 0) as
 * frm_cost_fit_fixed fits the additive form: c0 measured, one NNLS on the six columns a·T, V, pixels,
 * draws, √(a·T·pixels), (1 − a)·T with the relative weighting and the expectile τ. 0 or −1. */
int frm_cost_fit_inset(double c0_ms, double expectile, const struct rnd_cost_frame *frames, const uint32_t *rows,
                       size_t row_count, const struct rnd_cost_object *objects, struct frm_inset_cost *out,
                       struct frm_cost_fit_report *report, struct hl_error *err);

/* Relative error (predicted − measured) / measured over the listed frames: median and 95th
 * percentile of its magnitude, and the share of frames under-predicted by more than 5 % (what
 * breaks a budget). Allocates row_count doubles; all zero when row_count is 0 or allocation fails. */
struct frm_cost_accuracy {
    double median_rel, p95_rel, under5_share;
    uint32_t frames;
};
struct frm_cost_accuracy frm_cost_evaluate(const struct lod_cost_model *m, const struct rnd_cost_frame *frames,
                                           const uint32_t *rows, size_t row_count,
                                           const struct rnd_cost_object *objects);
/* The same for the inset's model. */
struct frm_cost_accuracy frm_cost_evaluate_inset(const struct frm_inset_cost *m, const struct rnd_cost_frame *frames,
                                                 const uint32_t *rows, size_t row_count,
                                                 const struct rnd_cost_object *objects);


/* ---- the cost profile (cost_profile.c, docs/cost-model.md) -------------------------------------- */
/* The fixed cost as calibrate measured it (empty frames among the grid's points); frames 0: unknown
 * (a profile from before it was measured: c0 was then an intercept). */
struct frm_cost_fixed {
    double median_ms, p25_ms, p75_ms;
    uint32_t frames;
};
/* The periphery layer's own model at one linear scale (issue 32): calibrate's grid drawn as that
 * periphery over the whole eye, pixels counted at the periphery's resolution (s² of the eye's).
 * model.c0_ms is that periphery's empty frame; a replay takes the layers' own clears from its
 * warm-up instead (frame/layers.h overhead_ms) and this model's object terms for what each object
 * costs in the periphery. */
enum { FRM_COST_PERIPHERY_MAX = 4 };
struct frm_cost_periphery {
    double scale;                     /* one of frame/layers.h's periphery scales below 1 */
    struct lod_cost_model model;
    struct frm_cost_accuracy held_out;
    struct frm_cost_fixed fixed;
    double composite_ms;              /* its composite over both whole eyes (the compositor's work,
                                       * not in a frame's time; reported); 0: not measured */
};
/* The foveal inset's own model (issue 32 item 4, frm_inset_cost above): calibrate's grid drawn as the
 * inset alone — the objects over the whole eye, drawn at full resolution under the scissor of the
 * inset's rectangle around the lens centre — pixels counted within the rectangle. */
struct frm_cost_inset {
    double radius_deg, blend_deg;     /* the inset measured (> 0) */
    struct frm_inset_cost cost;
    struct frm_cost_accuracy held_out;
    struct frm_cost_fixed fixed;      /* its empty frame: the scissored clears */
};
struct frm_cost_profile {
    struct lod_cost_model model;          /* what lod/ and the frame use */
    int periphery_count;                  /* 0: a profile without layer models (the periphery is priced
                                           * with `model`, its pixels at the periphery's resolution) */
    struct frm_cost_periphery periphery[FRM_COST_PERIPHERY_MAX];
    int inset_measured;                   /* 0: no inset model (the inset is priced with `model`) */
    struct frm_cost_inset inset;
    struct frm_cost_accuracy held_out;    /* of the kept form */
    struct frm_cost_accuracy held_out_other; /* of the form not kept (frames 0: unknown) */
    struct frm_cost_fixed fixed;          /* the measured fixed cost c0 was taken from */
    char label[256];                      /* e.g. "built-in llvmpipe reference (2-core, measured …)" */
    char renderer[128];                   /* GL_RENDERER the coefficients were measured on */
    char display[HMD_NAME_MAX];
    int eye_width_px, eye_height_px;      /* per eye: c0 (clears) depends on it */
    char date[32], commit[64];            /* "" when unknown */
    double load_before, load_after;       /* 1-minute load average around the measurement; < 0 unknown */
    struct rnd_cost_grid grid;            /* grid.repeats 0: not recorded */
};

/* Reads a profile; every problem is one message naming the file and the field: missing,
 * not a number, non-finite, negative coefficient, unknown form, unknown key. Returns 0 or −1. */
int frm_cost_profile_read(const char *path, struct frm_cost_profile *out, struct hl_error *err);
/* Writes atomically (path.partial, then rename): no half-written profile is left. 0 or −1. */
int frm_cost_profile_write(const char *path, const struct frm_cost_profile *p, struct hl_error *err);
/* The built-in reference measured with `hmdlod calibrate` on the 2-core llvmpipe development
 * machine (Vive, render scale 1): the session's default when no --cost-profile is given. */
void frm_cost_profile_builtin_llvmpipe(struct frm_cost_profile *out);
/* "max" / "additive"; NULL for an unknown form. And back: 0 and *form, or −1. */
const char *frm_cost_form_name(enum lod_cost_form form);
int frm_cost_form_parse(const char *name, enum lod_cost_form *form);

#endif
