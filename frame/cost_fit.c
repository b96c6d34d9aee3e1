/* Fitting the cost model: Lawson–Hanson NNLS, the additive and max forms (PAPERS.md §2: Funkhouser
 * & Séquin fit C1…C3 from timed renders; §5: published models reach ≈ 10 % error), held-out
 * accuracy (the seeded train/held-out split is render's, rnd_cost_split). Pure arithmetic: no GL,
 * no files. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "frame/cost.h"

enum { NNLS_MAX_COLS = 16, COST_COLS = 6, MAX_ROUNDS = 50 };

static struct acu_eye acu_eye_of(const struct rnd_cost_eye *m)
{
    return (struct acu_eye){hl_v3(m->offset_x_m, 0, 0), hl_q_identity(), m->tan_left, m->tan_right,
                            m->tan_up, m->tan_down, m->width_px, m->height_px};
}

/* The coverage is acuity's estimate from each object's sphere, for the eyes render measured with:
 * the very numbers a replay frame prices its candidates with (frame/select.c) — in a periphery of
 * scale s, s² of them, as frm_layers_level_cost_ms charges the periphery; in an inset grid within
 * the inset's rectangles (as frm_layers_inset_pixels), with the share of the whole image that is. */
int frm_cost_calibrate(const struct hmd_profile *display, struct rnd_cost_grid *grid, uint64_t seed,
                       struct rnd_calibration *out, struct hl_error *err)
{
    if (rnd_cost_measure(display, grid, seed, out, err) != 0)
        return -1;
    struct acu_eye eyes[2] = {acu_eye_of(&out->eyes[0]), acu_eye_of(&out->eyes[1])};
    struct acu_eye insets[2] = {acu_eye_of(&out->inset_eyes[0]), acu_eye_of(&out->inset_eyes[1])};
    int inset = grid->inset_radius_deg > 0.0;
    const uint32_t first = 0;
    for (size_t k = 0; k < out->object_count; ++k) {
        struct rnd_cost_object *o = &out->objects[k];
        double whole_px = 0.0, inside_px = 0.0;
        acu_compute_pixels(eyes, 2, o->center_m, &o->radius_m, &first, 1, &whole_px);
        if (inset)
            acu_compute_pixels(insets, 2, o->center_m, &o->radius_m, &first, 1, &inside_px);
        o->inside_share = !inset ? 1.0 : whole_px > 0.0 ? fmin(1.0, inside_px / whole_px) : 0.0;
        /* the fragments, as the replay charges them */
        o->pixels_px = (inset ? inside_px : whole_px) * o->fill * grid->periphery_scale * grid->periphery_scale;
    }
    return 0;
}

double frm_cost_predict_frame_ms(const struct lod_cost_model *m, const struct rnd_cost_frame *frame,
                                 const struct rnd_cost_object *objects)
{
    double sum = m->c0_ms;
    for (uint32_t k = 0; k < frame->object_count; ++k) { /* lod's own arithmetic: the replay predicts with it */
        const struct rnd_cost_object *o = &objects[frame->first_object + k];
        sum += lod_cost_object_ms(m, o->triangles, o->vertices, o->pixels_px, o->draws);
    }
    return sum;
}

/* ---- NNLS ------------------------------------------------------------------------------------ */

/* Least squares on the columns listed in set[0 … k−1] of the column-major m × n matrix a:
 * Householder QR of a copy (q: m·k doubles, rhs: m), back substitution into s (k). A column whose
 * R diagonal vanishes (collinear with earlier ones) gets 0: NNLS then treats it as inactive. */
static void nnls_subset_ls(const double *a, size_t m, const size_t *set, size_t k, const double *b, double *q,
                           double *rhs, double *s)
{
    for (size_t j = 0; j < k; ++j)
        memcpy(q + j * m, a + set[j] * m, m * sizeof *q);
    memcpy(rhs, b, m * sizeof *rhs);
    double rmax = 0.0;
    for (size_t j = 0; j < k && j < m; ++j) {
        double *col = q + j * m, norm = 0.0;
        for (size_t i = j; i < m; ++i)
            norm = hypot(norm, col[i]);
        if (norm == 0.0)
            continue;
        double alpha = col[j] > 0 ? -norm : norm; /* sign opposite to col[j]: no cancellation */
        col[j] -= alpha;                          /* v = x − alpha·e1, kept in col[j…] */
        double vnorm2 = 0.0;
        for (size_t i = j; i < m; ++i)
            vnorm2 += col[i] * col[i];
        for (size_t l = j + 1; l < k; ++l) {
            double *c = q + l * m, dot = 0.0;
            for (size_t i = j; i < m; ++i)
                dot += col[i] * c[i];
            double f = 2.0 * dot / vnorm2;
            for (size_t i = j; i < m; ++i)
                c[i] -= f * col[i];
        }
        double dot = 0.0;
        for (size_t i = j; i < m; ++i)
            dot += col[i] * rhs[i];
        double f = 2.0 * dot / vnorm2;
        for (size_t i = j; i < m; ++i)
            rhs[i] -= f * col[i];
        col[j] = alpha; /* R's diagonal; the rest of col below j is no longer needed */
        rmax = fmax(rmax, fabs(alpha));
    }
    for (size_t jj = k; jj-- > 0;) {
        if (jj >= m || fabs(q[jj * m + jj]) <= 1e-12 * rmax) {
            s[jj] = 0.0;
            continue;
        }
        double v = rhs[jj];
        for (size_t l = jj + 1; l < k; ++l)
            v -= q[l * m + jj] * s[l];
        s[jj] = v / q[jj * m + jj];
    }
}

int frm_cost_nnls(const double *a_rows, size_t rows, size_t cols, const double *b, double *x, double *residual_norm,
                  struct hl_error *err)
{
    if (!a_rows || !b || !x || rows < 1 || cols < 1 || cols > NNLS_MAX_COLS)
        return hl_fail(err, "nnls: bad sizes (%zu rows, %zu columns; 1…%d columns)", rows, cols, NNLS_MAX_COLS);
    for (size_t i = 0; i < rows * cols; ++i)
        if (!isfinite(a_rows[i]))
            return hl_fail(err, "nnls: matrix entry %zu (row %zu) is not finite", i, i / cols);
    for (size_t i = 0; i < rows; ++i)
        if (!isfinite(b[i]))
            return hl_fail(err, "nnls: right-hand side %zu is not finite", i);
    size_t m = rows, n = cols;
    /* a: scaled column-major copy; q: QR scratch; rhs, resid: m each. */
    double *buf = malloc((2 * m * n + 2 * m) * sizeof *buf);
    if (!buf)
        return hl_fail(err, "nnls: out of memory (%zu × %zu)", rows, cols);
    double *a = buf, *q = buf + m * n, *rhs = q + m * n, *resid = rhs + m;
    double scale[NNLS_MAX_COLS], w[NNLS_MAX_COLS], z[NNLS_MAX_COLS], s[NNLS_MAX_COLS], xs[NNLS_MAX_COLS];
    size_t set[NNLS_MAX_COLS];
    int in_p[NNLS_MAX_COLS] = {0};
    /* A column whose gradient says "enter" but whose least-squares value comes out ≤ 0 (rounding,
     * with nearly collinear columns such as triangles and vertices of one mesh) would be picked
     * again and again; it is blocked until some other column enters. */
    int blocked[NNLS_MAX_COLS] = {0};
    double anorm = 0.0;
    for (size_t j = 0; j < n; ++j) {
        double norm = 0.0;
        for (size_t i = 0; i < m; ++i)
            norm = hypot(norm, a_rows[i * n + j]);
        scale[j] = norm > 0.0 ? norm : 1.0; /* a zero column stays zero and never enters P */
        for (size_t i = 0; i < m; ++i)
            a[j * m + i] = a_rows[i * n + j] / scale[j];
        anorm = fmax(anorm, norm > 0.0 ? 1.0 : 0.0);
        xs[j] = 0.0;
    }
    double tol = 10.0 * 2.220446049250313e-16 * anorm * (double)(m > n ? m : n);
    int rc = 0;
    size_t outer = 0;
    for (;;) {
        for (size_t i = 0; i < m; ++i) {
            double v = b[i];
            for (size_t j = 0; j < n; ++j)
                v -= a[j * m + i] * xs[j];
            resid[i] = v;
        }
        size_t best = n;
        double wmax = tol;
        for (size_t j = 0; j < n; ++j) {
            w[j] = 0.0;
            for (size_t i = 0; i < m; ++i)
                w[j] += a[j * m + i] * resid[i];
            if (!in_p[j] && !blocked[j] && w[j] > wmax) /* ties: the lowest column, deterministic */
                wmax = w[j], best = j;
        }
        if (best == n)
            break; /* KKT holds: every inactive gradient ≤ tol */
        if (++outer > 3 * n) {
            rc = hl_fail(err, "nnls: no convergence after %zu outer iterations", 3 * n);
            break;
        }
        in_p[best] = 1;
        for (int inner = 0;; ++inner) {
            size_t k = 0;
            for (size_t j = 0; j < n; ++j)
                if (in_p[j])
                    set[k++] = j;
            nnls_subset_ls(a, m, set, k, b, q, rhs, s);
            for (size_t j = 0; j < n; ++j)
                z[j] = 0.0;
            for (size_t t = 0; t < k; ++t)
                z[set[t]] = s[t];
            if (inner == 0) {
                if (z[best] <= tol) {
                    in_p[best] = 0, blocked[best] = 1;
                    --outer; /* not a step: the next pick is another column or the end */
                    break;
                }
                memset(blocked, 0, sizeof blocked);
            }
            int all_positive = 1;
            for (size_t t = 0; t < k; ++t) {
                z[set[t]] = s[t];
                if (s[t] <= tol)
                    all_positive = 0;
            }
            if (all_positive || inner > (int)(3 * n)) {
                memcpy(xs, z, n * sizeof *xs);
                for (size_t j = 0; j < n; ++j)
                    if (in_p[j] && xs[j] <= tol)
                        in_p[j] = 0, xs[j] = 0.0;
                break;
            }
            /* Step from xs towards z as far as feasibility allows; the variables that hit zero leave P. */
            double alpha = 1.0;
            for (size_t j = 0; j < n; ++j)
                if (in_p[j] && z[j] <= tol) {
                    double d = xs[j] - z[j];
                    double t = d > 0.0 ? xs[j] / d : 0.0;
                    alpha = fmin(alpha, t);
                }
            for (size_t j = 0; j < n; ++j) {
                xs[j] += alpha * (z[j] - xs[j]);
                if (in_p[j] && xs[j] <= tol)
                    in_p[j] = 0, xs[j] = 0.0;
            }
        }
    }
    double rnorm = 0.0;
    for (size_t i = 0; i < m; ++i) {
        double v = b[i];
        for (size_t j = 0; j < n; ++j)
            v -= a[j * m + i] * xs[j];
        rnorm = hypot(rnorm, v);
    }
    for (size_t j = 0; j < n; ++j)
        x[j] = xs[j] / scale[j];
    if (residual_norm)
        *residual_norm = rnorm;
    free(buf);
    return rc;
}

/* ---- the two forms ------------------------------------------------------------------------- */

static void model_from(enum lod_cost_form form, const double c[COST_COLS], struct lod_cost_model *m)
{
    *m = (struct lod_cost_model){form, c[0], c[1], c[2], c[3], c[4], c[5]};
}

/* A model's prediction of one frame: a lod_cost_model (plain_predict) or a frm_inset_cost
 * (inset_predict) with the objects' counts. */
struct prediction {
    const void *model;
    const struct rnd_cost_object *objects;
};

static double plain_predict(const void *ctx, const struct rnd_cost_frame *frame)
{
    const struct prediction *p = ctx;
    return frm_cost_predict_frame_ms(p->model, frame, p->objects);
}

static double inset_predict(const void *ctx, const struct rnd_cost_frame *frame)
{
    const struct prediction *p = ctx;
    return frm_cost_predict_inset_frame_ms(p->model, frame, p->objects);
}

/* Relative error objective of predict() on the listed frames: Σ((pred − meas)/meas)². */
static double relative_sse(double (*predict)(const void *ctx, const struct rnd_cost_frame *f), const void *ctx,
                           const struct rnd_cost_frame *frames, const uint32_t *rows, size_t row_count)
{
    double sum = 0.0;
    for (size_t r = 0; r < row_count; ++r) {
        const struct rnd_cost_frame *f = &frames[rows[r]];
        double e = (predict(ctx, f) - f->measured_ms) / f->measured_ms;
        sum += e * e;
    }
    return sum;
}

static double fit_objective(const struct lod_cost_model *m, const struct rnd_cost_frame *frames, const uint32_t *rows,
                            size_t row_count, const struct rnd_cost_object *objects)
{
    struct prediction p = {m, objects};
    return relative_sse(plain_predict, &p, frames, rows, row_count);
}

/* One NNLS on rows [1, Σt, Σv, Σp, Σd, Σ√(t·p)] / measured against 1 (the relative-error weighting). With
 * assign == NULL every object contributes all terms (additive); else an object with assign 1 adds
 * its geometry terms only and one with 0 its pixels only: the max form with its max resolved. */
static int fit_linear(const struct rnd_cost_frame *frames, const uint32_t *rows, size_t row_count,
                      const struct rnd_cost_object *objects, const uint8_t *assign, double fixed_c0_ms,
                      const double *weight, double *a, double *b, double c[COST_COLS], struct hl_error *err)
{
    int fixed = isfinite(fixed_c0_ms); /* c0 measured: its column is zero (never enters) and moves b */
    for (size_t r = 0; r < row_count; ++r) {
        const struct rnd_cost_frame *f = &frames[rows[r]];
        double t = 0, v = 0, p = 0, d = 0, e = 0;
        for (uint32_t k = 0; k < f->object_count; ++k) {
            uint32_t o = f->first_object + k;
            const struct rnd_cost_object *ob = &objects[o];
            int geometry = !assign || assign[o], raster = !assign || !assign[o];
            if (geometry)
                t += ob->triangles, v += ob->vertices;
            if (raster)
                p += ob->pixels_px, e += sqrt(ob->triangles * ob->pixels_px);
            d += ob->draws;
        }
        double inv = (weight ? sqrt(weight[r]) : 1.0) / f->measured_ms;
        double row[COST_COLS] = {fixed ? 0.0 : inv, t * inv, v * inv, p * inv, d * inv, e * inv};
        memcpy(a + r * COST_COLS, row, sizeof row);
        b[r] = (fixed ? 1.0 - fixed_c0_ms / f->measured_ms : 1.0) * (weight ? sqrt(weight[r]) : 1.0);
    }
    int rc = frm_cost_nnls(a, row_count, COST_COLS, b, c, NULL, err);
    if (fixed)
        c[0] = fixed_c0_ms;
    return rc;
}

/* Resolves each object's max under model m: 1 = geometry dominates. Returns how many changed. */
static size_t assign_stages(const struct lod_cost_model *m, const struct rnd_cost_frame *frames, const uint32_t *rows,
                            size_t row_count, const struct rnd_cost_object *objects, uint8_t *assign)
{
    size_t changed = 0;
    for (size_t r = 0; r < row_count; ++r) {
        const struct rnd_cost_frame *f = &frames[rows[r]];
        for (uint32_t k = 0; k < f->object_count; ++k) {
            uint32_t o = f->first_object + k;
            const struct rnd_cost_object *ob = &objects[o];
            uint8_t g = m->c1_ms_per_triangle * ob->triangles + m->c2_ms_per_vertex * ob->vertices >=
                        m->c3_ms_per_pixel * ob->pixels_px + m->c5_ms_per_edge_px * sqrt(ob->triangles * ob->pixels_px);
            changed += assign[o] != g;
            assign[o] = g;
        }
    }
    return changed;
}

/* Every listed frame has a positive finite time and finite non-negative counts; *object_end gets one
 * past the last object they use. */
static int check_frames(const struct rnd_cost_frame *frames, const uint32_t *rows, size_t row_count,
                        const struct rnd_cost_object *objects, size_t *object_end, struct hl_error *err)
{
    for (size_t r = 0; r < row_count; ++r) {
        const struct rnd_cost_frame *f = &frames[rows[r]];
        if (!(f->measured_ms > 0.0) || !isfinite(f->measured_ms))
            return hl_fail(err, "cost fit: frame %u: measured time %g ms is not positive and finite", rows[r],
                           f->measured_ms);
        for (uint32_t k = 0; k < f->object_count; ++k) {
            const struct rnd_cost_object *o = &objects[f->first_object + k];
            if (!isfinite(o->triangles) || !isfinite(o->vertices) || !isfinite(o->pixels_px) || !isfinite(o->draws) ||
                !isfinite(o->inside_share) || o->triangles < 0 || o->vertices < 0 || o->pixels_px < 0 || o->draws < 0 ||
                o->inside_share < 0 || o->inside_share > 1)
                return hl_fail(err, "cost fit: frame %u object %u: counts must be finite and ≥ 0", rows[r], k);
        }
        if ((size_t)f->first_object + f->object_count > *object_end)
            *object_end = (size_t)f->first_object + f->object_count;
    }
    return 0;
}

static int fit_form(enum lod_cost_form form, double fixed_c0_ms, const double *weight,
                    const struct rnd_cost_frame *frames, const uint32_t *rows, size_t row_count,
                    const struct rnd_cost_object *objects, struct lod_cost_model *out,
                    struct frm_cost_fit_report *report, struct hl_error *err)
{
    if (!frames || !rows || !objects || !out || row_count == 0)
        return hl_fail(err, "cost fit: no frames to fit");
    if (form != LOD_COST_MAX && form != LOD_COST_ADDITIVE)
        return hl_fail(err, "cost fit: unknown form %d", (int)form);
    size_t object_end = 0;
    if (check_frames(frames, rows, row_count, objects, &object_end, err) != 0)
        return -1;
    double *a = malloc(row_count * (COST_COLS + 1) * sizeof *a);
    uint8_t *assign = calloc(object_end ? object_end : 1, 1);
    if (!a || !assign) {
        free(a);
        free(assign);
        return hl_fail(err, "cost fit: out of memory (%zu frames)", row_count);
    }
    double *b = a + row_count * COST_COLS, c[COST_COLS];
    int rc = fit_linear(frames, rows, row_count, objects, NULL, fixed_c0_ms, weight, a, b, c, err);
    struct lod_cost_model additive;
    model_from(LOD_COST_ADDITIVE, c, &additive);
    struct lod_cost_model best = additive;
    int best_rounds = 1;
    if (rc == 0 && form == LOD_COST_MAX) {
        double best_obj = INFINITY;
        for (int start = 0; start < 3 && rc == 0; ++start) {
            /* Starts: the additive coefficients' own max; all geometry; all pixels. */
            struct lod_cost_model m = additive;
            m.form = LOD_COST_MAX;
            if (start == 0)
                assign_stages(&m, frames, rows, row_count, objects, assign);
            for (size_t r = 0; start > 0 && r < row_count; ++r)
                memset(assign + frames[rows[r]].first_object, start == 1, frames[rows[r]].object_count);
            /* Alternate: refit with the max resolved, re-resolve; keep the best true-max iterate (the
             * objective need not fall every round, as the refit optimises the resolved problem). */
            for (int round = 1; round <= MAX_ROUNDS; ++round) {
                if ((rc = fit_linear(frames, rows, row_count, objects, assign, fixed_c0_ms, weight, a, b, c, err)) != 0)
                    break;
                model_from(LOD_COST_MAX, c, &m);
                double obj = fit_objective(&m, frames, rows, row_count, objects);
                if (obj < best_obj)
                    best_obj = obj, best = m, best_rounds = round;
                if (assign_stages(&m, frames, rows, row_count, objects, assign) == 0)
                    break;
            }
        }
    }
    free(a);
    free(assign);
    if (rc != 0)
        return -1;
    *out = best;
    if (report) {
        report->rms_relative = sqrt(fit_objective(&best, frames, rows, row_count, objects) / (double)row_count);
        report->rounds = best_rounds;
    }
    return 0;
}

int frm_cost_fit(enum lod_cost_form form, const struct rnd_cost_frame *frames, const uint32_t *rows,
                 size_t row_count, const struct rnd_cost_object *objects, struct lod_cost_model *out,
                 struct frm_cost_fit_report *report, struct hl_error *err)
{
    return fit_form(form, NAN, NULL, frames, rows, row_count, objects, out, report, err);
}

/* Asymmetric least squares (Newey & Powell 1987): rows the model under-predicts weigh τ, the others
 * 1 − τ, refitted until no row changes side (≤ 30 rounds). τ = ½ is the ordinary fit. */
enum { EXPECTILE_ROUNDS = 30 };
/* A fit repeated under expectile weights: fit() on the rows with weight (NULL: unweighted), then
 * predict() one frame with the model it wrote. */
struct weighted_fit {
    int (*fit)(void *ctx, const double *weight, struct hl_error *err);
    void *ctx;
    double (*predict)(const void *ctx, const struct rnd_cost_frame *f);
    struct prediction prediction;
};

static int fit_expectile(const struct weighted_fit *w, double expectile, const struct rnd_cost_frame *frames,
                         const uint32_t *rows, size_t row_count, struct hl_error *err)
{
    if (!(expectile > 0.0 && expectile < 1.0))
        return hl_fail(err, "cost fit: expectile %g is outside (0, 1)", expectile);
    if (expectile == 0.5)
        return w->fit(w->ctx, NULL, err);
    double *weight = malloc((row_count ? row_count : 1) * sizeof *weight);
    uint8_t *under = calloc(row_count ? row_count : 1, 1);
    if (!weight || !under) {
        free(weight);
        free(under);
        return hl_fail(err, "cost fit: out of memory (%zu frames)", row_count);
    }
    for (size_t r = 0; r < row_count; ++r)
        weight[r] = 0.5;
    int rc = 0;
    for (int round = 0; round < EXPECTILE_ROUNDS; ++round) {
        if ((rc = w->fit(w->ctx, weight, err)) != 0)
            break;
        size_t changed = 0;
        for (size_t r = 0; r < row_count; ++r) {
            const struct rnd_cost_frame *f = &frames[rows[r]];
            uint8_t u = w->predict(&w->prediction, f) < f->measured_ms;
            changed += round == 0 || u != under[r];
            under[r] = u;
            weight[r] = u ? expectile : 1.0 - expectile;
        }
        if (!changed)
            break;
    }
    free(weight);
    free(under);
    return rc;
}

struct form_fit {
    enum lod_cost_form form;
    double c0_ms;
    const struct rnd_cost_frame *frames;
    const uint32_t *rows;
    size_t row_count;
    const struct rnd_cost_object *objects;
    struct lod_cost_model *out;
    struct frm_cost_fit_report *report;
};

static int form_fit(void *ctx, const double *weight, struct hl_error *err)
{
    struct form_fit *f = ctx;
    return fit_form(f->form, f->c0_ms, weight, f->frames, f->rows, f->row_count, f->objects, f->out, f->report, err);
}

int frm_cost_fit_fixed(enum lod_cost_form form, double c0_ms, double expectile, const struct rnd_cost_frame *frames,
                       const uint32_t *rows, size_t row_count, const struct rnd_cost_object *objects,
                       struct lod_cost_model *out, struct frm_cost_fit_report *report, struct hl_error *err)
{
    if (!isfinite(c0_ms) || c0_ms < 0.0)
        return hl_fail(err, "cost fit: the measured fixed cost %g ms is not finite and ≥ 0", c0_ms);
    struct form_fit ctx = {form, c0_ms, frames, rows, row_count, objects, out, report};
    struct weighted_fit w = {form_fit, &ctx, plain_predict, {out, objects}};
    return fit_expectile(&w, expectile, frames, rows, row_count, err);
}

/* ---- the inset's model ------------------------------------------------------------------------ */

double frm_inset_object_ms(const struct frm_inset_cost *m, double triangles, double vertices, double pixels_px,
                           double draws, double inside_share)
{
    double a = fmax(0.0, fmin(1.0, inside_share)); /* NaN: fmin keeps the 1 */
    return lod_cost_object_ms(&m->model, a * triangles, vertices, pixels_px, draws) +
           m->outside_ms_per_triangle * (1.0 - a) * triangles;
}

double frm_cost_predict_inset_frame_ms(const struct frm_inset_cost *m, const struct rnd_cost_frame *frame,
                                       const struct rnd_cost_object *objects)
{
    double sum = m->model.c0_ms;
    for (uint32_t k = 0; k < frame->object_count; ++k) {
        const struct rnd_cost_object *o = &objects[frame->first_object + k];
        sum += frm_inset_object_ms(m, o->triangles, o->vertices, o->pixels_px, o->draws, o->inside_share);
    }
    return sum;
}

enum { INSET_COLS = 6 };
struct inset_fit {
    double c0_ms;
    const struct rnd_cost_frame *frames;
    const uint32_t *rows;
    size_t row_count;
    const struct rnd_cost_object *objects;
    double *a, *b; /* row_count × INSET_COLS, row_count */
    struct frm_inset_cost *out;
};

/* One NNLS on rows [Σa·t, Σv, Σp, Σd, Σ√(a·t·p), Σ(1 − a)·t] / measured against 1 − c0 / measured. */
static int inset_fit(void *ctx, const double *weight, struct hl_error *err)
{
    struct inset_fit *f = ctx;
    for (size_t r = 0; r < f->row_count; ++r) {
        const struct rnd_cost_frame *fr = &f->frames[f->rows[r]];
        double col[INSET_COLS] = {0};
        for (uint32_t k = 0; k < fr->object_count; ++k) {
            const struct rnd_cost_object *o = &f->objects[fr->first_object + k];
            double inside = o->inside_share * o->triangles;
            col[0] += inside, col[1] += o->vertices, col[2] += o->pixels_px, col[3] += o->draws;
            col[4] += sqrt(inside * o->pixels_px), col[5] += o->triangles - inside;
        }
        double w = weight ? sqrt(weight[r]) : 1.0;
        for (int j = 0; j < INSET_COLS; ++j)
            f->a[r * INSET_COLS + j] = col[j] * w / fr->measured_ms;
        f->b[r] = (1.0 - f->c0_ms / fr->measured_ms) * w;
    }
    double c[INSET_COLS];
    if (frm_cost_nnls(f->a, f->row_count, INSET_COLS, f->b, c, NULL, err) != 0)
        return -1;
    f->out->model = (struct lod_cost_model){LOD_COST_ADDITIVE, f->c0_ms, c[0], c[1], c[2], c[3], c[4]};
    f->out->outside_ms_per_triangle = c[5];
    return 0;
}

int frm_cost_fit_inset(double c0_ms, double expectile, const struct rnd_cost_frame *frames, const uint32_t *rows,
                       size_t row_count, const struct rnd_cost_object *objects, struct frm_inset_cost *out,
                       struct frm_cost_fit_report *report, struct hl_error *err)
{
    if (!frames || !rows || !objects || !out || row_count == 0)
        return hl_fail(err, "cost fit: no frames to fit");
    if (!isfinite(c0_ms) || c0_ms < 0.0)
        return hl_fail(err, "cost fit: the measured fixed cost %g ms is not finite and ≥ 0", c0_ms);
    size_t object_end = 0;
    if (check_frames(frames, rows, row_count, objects, &object_end, err) != 0)
        return -1;
    double *a = malloc(row_count * (INSET_COLS + 1) * sizeof *a);
    if (!a)
        return hl_fail(err, "cost fit: out of memory (%zu frames)", row_count);
    struct inset_fit ctx = {c0_ms, frames, rows, row_count, objects, a, a + row_count * INSET_COLS, out};
    struct weighted_fit w = {inset_fit, &ctx, inset_predict, {out, objects}};
    int rc = fit_expectile(&w, expectile, frames, rows, row_count, err);
    free(a);
    if (rc == 0 && report) {
        report->rms_relative = sqrt(relative_sse(inset_predict, &w.prediction, frames, rows, row_count) / (double)row_count);
        report->rounds = 1;
    }
    return rc;
}

/* ---- accuracy and split --------------------------------------------------------------------- */

/* Linear interpolation between order statistics (the "type 7" quantile of R and NumPy). */
static double quantile_sorted(const double *v, size_t n, double q)
{
    double pos = q * (double)(n - 1);
    size_t lo = (size_t)floor(pos);
    size_t hi = lo + 1 < n ? lo + 1 : lo;
    return v[lo] + (pos - (double)lo) * (v[hi] - v[lo]);
}

/* Median and p95 of |relative error| and the share under-predicted by > 5 % of predict() on the rows. */
static struct frm_cost_accuracy accuracy_of(double (*predict)(const void *ctx, const struct rnd_cost_frame *f),
                                            const void *ctx, const struct rnd_cost_frame *frames, const uint32_t *rows,
                                            size_t row_count)
{
    struct frm_cost_accuracy acc = {0, 0, 0, 0};
    double *e = row_count ? malloc(row_count * sizeof *e) : NULL;
    if (!e)
        return acc;
    size_t under = 0;
    for (size_t r = 0; r < row_count; ++r) {
        const struct rnd_cost_frame *f = &frames[rows[r]];
        double rel = (predict(ctx, f) - f->measured_ms) / f->measured_ms;
        under += rel < -0.05;
        e[r] = fabs(rel);
    }
    hl_sort_doubles(e, row_count);
    acc.median_rel = quantile_sorted(e, row_count, 0.5);
    acc.p95_rel = quantile_sorted(e, row_count, 0.95);
    acc.under5_share = (double)under / (double)row_count;
    acc.frames = (uint32_t)row_count;
    free(e);
    return acc;
}

struct frm_cost_accuracy frm_cost_evaluate(const struct lod_cost_model *m, const struct rnd_cost_frame *frames,
                                           const uint32_t *rows, size_t row_count,
                                           const struct rnd_cost_object *objects)
{
    struct prediction p = {m, objects};
    return accuracy_of(plain_predict, &p, frames, rows, row_count);
}

struct frm_cost_accuracy frm_cost_evaluate_inset(const struct frm_inset_cost *m, const struct rnd_cost_frame *frames,
                                                 const uint32_t *rows, size_t row_count,
                                                 const struct rnd_cost_object *objects)
{
    struct prediction p = {m, objects};
    return accuracy_of(inset_predict, &p, frames, rows, row_count);
}
