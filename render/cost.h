/* render/cost.h: the machine's cost model — timed stereo frames over a grid of triangle counts,
 * screen coverage and draw counts (`hmdlod calibrate`), the non-negative fits of Funkhouser &
 * Séquin's max form and of the additive form (PAPERS.md §2, §5 "Cost models"), their held-out
 * accuracy, and the cost profile JSON (docs/cost-model.md) that hands lod/ a struct lod_cost_model.
 * Included by render/render.h; not meant to be included on its own. */
#ifndef HMDLOD_RENDER_COST_H
#define HMDLOD_RENDER_COST_H

#include "base/base.h"
#include "hmd/hmd.h"
#include "lod/lod.h"

/* ---- samples ----------------------------------------------------------------------------------
 * One timed frame holds object_count objects, objects[first_object …]. Each object's counts are for
 * both eyes, as lod_cost_object_ms takes them: triangles and vertices drawn, projected pixels summed
 * over the eyes (acu_compute_pixels' estimate, not a rasterised count: the replay predicts with the
 * same estimate), draw calls. measured_ms is the median over repeats of draw + glFinish. */
struct rnd_cost_object {
    double triangles, vertices, pixels_px, draws;
};
struct rnd_cost_frame {
    double measured_ms;
    uint32_t first_object, object_count;
};

/* Frame prediction: c0 + Σ lod_cost_object_ms over the frame's objects. O(object_count). */
double rnd_cost_predict_frame_ms(const struct lod_cost_model *m, const struct rnd_cost_frame *frame,
                                 const struct rnd_cost_object *objects);

/* ---- fitting (cost_fit.c) ---------------------------------------------------------------------- */
/* Non-negative least squares, Lawson & Hanson (1974, ch. 23): min |A·x − b|₂ subject to x ≥ 0.
 * a is row-major rows × cols, cols ≤ 16, rows ≥ 1; columns are scaled to unit norm internally, so
 * features of very different magnitude (1 per frame, 10⁶ pixels) fit together. Allocates O(rows ·
 * cols) scratch (calibration, never per frame). Returns 0, or −1 on bad sizes, non-finite input,
 * allocation failure or no convergence within 3·cols outer iterations (err says which).
 * *residual_norm (may be NULL) gets |A·x − b|₂. Cost O(iterations · rows · cols²). */
int rnd_cost_nnls(const double *a, size_t rows, size_t cols, const double *b, double *x, double *residual_norm,
                  struct hl_error *err);

/* Fits one form on the frames listed in rows[0 … row_count−1] (indices into frames), all five
 * coefficients ≥ 0, minimising the squared RELATIVE error Σ((predicted − measured)/measured)²: the
 * budget cares about ratios, and unweighted least squares would let the heaviest frames decide.
 * LOD_COST_ADDITIVE: one NNLS. LOD_COST_MAX: alternating assignment — each object's max is replaced
 * by the stage that dominates it under the current coefficients, which makes the frame linear in
 * the coefficients; NNLS refits all five; repeat until no assignment changes (≤ 50 rounds), from
 * three starts (the additive fit's coefficients, all geometry, all pixels); the best true-max
 * objective wins. Needs measured_ms > 0 and finite counts on every listed frame. */
struct rnd_cost_fit_report {
    double rms_relative; /* sqrt(mean(((pred − meas)/meas)²)) on the fitted frames */
    int rounds;          /* assignment rounds of the winning start (1 for additive) */
};
int rnd_cost_fit(enum lod_cost_form form, const struct rnd_cost_frame *frames, const uint32_t *rows,
                 size_t row_count, const struct rnd_cost_object *objects, struct lod_cost_model *out,
                 struct rnd_cost_fit_report *report, struct hl_error *err);

/* Relative error (predicted − measured) / measured over the listed frames: median and 95th
 * percentile of its magnitude, and the share of frames under-predicted by more than 5 % (what
 * breaks a budget). Allocates row_count doubles; all zero when row_count is 0 or allocation fails. */
struct rnd_cost_accuracy {
    double median_rel, p95_rel, under5_share;
    uint32_t frames;
};
struct rnd_cost_accuracy rnd_cost_evaluate(const struct lod_cost_model *m, const struct rnd_cost_frame *frames,
                                           const uint32_t *rows, size_t row_count,
                                           const struct rnd_cost_object *objects);

/* Deterministic split of `count` items into a training part (the first *train_count entries of
 * order) and a held-out part (the rest): a seeded Fisher–Yates shuffle, train share 0.75 rounded,
 * at least one in each when count ≥ 2. order holds count entries. */
void rnd_cost_split(size_t count, uint64_t seed, uint32_t *order, size_t *train_count);

/* ---- measurement (cost.c) ---------------------------------------------------------------------- */
enum { RND_COST_GRID_MAX = 8 };
struct rnd_cost_grid {
    int families;                            /* 1: the field's bumpy sphere; 2: also the auditorium's chair */
    int levels;                              /* LOD indices used (the field: 0 = 3906 … 3 = 78 triangles) */
    uint32_t level[RND_COST_GRID_MAX];
    int coverages;                           /* total projected share of each eye's image */
    double coverage[RND_COST_GRID_MAX];
    int counts;                              /* objects per frame (draws = 2 · objects) */
    uint32_t objects[RND_COST_GRID_MAX];
    int repeats;                             /* timed frames per grid point; the median is kept */
    int eye_width_px, eye_height_px;         /* per eye, after the render scale */
    double render_scale;
    char display[HMD_NAME_MAX];
};
/* The default grid (2 families × 4 levels × 5 coverages × 5 counts, 7 repeats) or --quick's
 * (2 × 2 × 2 × 3, 3 repeats). */
void rnd_cost_grid_default(struct rnd_cost_grid *g, int quick);

struct rnd_calibration {
    struct rnd_cost_frame *frames;   /* one per grid point, in grid order */
    struct rnd_cost_object *objects;
    size_t frame_count, object_count;
    char renderer[128];              /* GL_RENDERER */
    double seconds;                  /* wall time of the measurement */
};
/* Renders the field's bumpy sphere and the auditorium's chair (scene/) in stereo on `display` at
 * render_scale: for every grid point, k copies (at most the 150 chairs the auditorium has) in a grid in front of both eyes sized so their projected coverage totals the
 * requested share; `repeats` passes over the grid, each in a new seeded random order, time one
 * frame per point (hl_clock around rnd_renderer_draw_stereo, which ends with glFinish), and the
 * median over passes is kept — so a busy moment of a shared machine or a slow
 * drift hits one pass of many points, not every repeat of one. A warm-up of the heaviest point
 * comes first, as llvmpipe compiles shaders on first use. Takes seconds; allocates *out (free with
 * rnd_calibration_free). grid->eye_width_px/height_px and display are filled in. */
int rnd_cost_measure(const struct hmd_profile *display, struct rnd_cost_grid *grid, uint64_t seed,
                     struct rnd_calibration *out, struct hl_error *err);
void rnd_calibration_free(struct rnd_calibration *c);

/* ---- the cost profile (cost_profile.c, docs/cost-model.md) -------------------------------------- */
struct rnd_cost_profile {
    struct lod_cost_model model;          /* what lod/ and the replay use */
    struct rnd_cost_accuracy held_out;    /* of the kept form */
    struct rnd_cost_accuracy held_out_other; /* of the form not kept (frames 0: unknown) */
    char label[160];                      /* e.g. "built-in llvmpipe reference (2-core, measured …)" */
    char renderer[128];                   /* GL_RENDERER the coefficients were measured on */
    char display[HMD_NAME_MAX];
    int eye_width_px, eye_height_px;      /* per eye: c0 (clears) depends on it */
    char date[32], commit[64];            /* "" when unknown */
    double load_before, load_after;       /* 1-minute load average around the measurement; < 0 unknown */
    struct rnd_cost_grid grid;            /* grid.repeats 0: not recorded */
};

/* Reads a profile; every problem is one message naming the file and the field: missing,
 * not a number, non-finite, negative coefficient, unknown form, unknown key. Returns 0 or −1. */
int rnd_cost_profile_read(const char *path, struct rnd_cost_profile *out, struct hl_error *err);
/* Writes atomically (path.partial, then rename): no half-written profile is left. 0 or −1. */
int rnd_cost_profile_write(const char *path, const struct rnd_cost_profile *p, struct hl_error *err);
/* The built-in reference measured with `hmdlod calibrate` on the 2-core llvmpipe development
 * machine (Vive, render scale 1): the replay's default when no --cost-profile is given. */
void rnd_cost_profile_builtin_llvmpipe(struct rnd_cost_profile *out);
/* "max" / "additive"; NULL for an unknown form. And back: 0 and *form, or −1. */
const char *rnd_cost_form_name(enum lod_cost_form form);
int rnd_cost_form_parse(const char *name, enum lod_cost_form *form);

#endif
