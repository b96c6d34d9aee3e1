/* render/cost.h (measurement) and frame/cost.h (fits, profiles): NNLS against a brute-force
 * enumeration of active sets, both cost forms recovering
 * known coefficients from synthetic frames (exact and noisy), held-out accuracy arithmetic, the
 * split, the profile JSON round trip and bad
 * profiles refused with the file and field named; one tiny real measurement on headless EGL. */
#include "frame/frame.h"
#include "test_util.h"

#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A small deterministic generator (splitmix64), independent of the code under test's. */
static uint64_t rng_state = 12345;
static double uniform(void)
{
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}
static double gaussian(void) /* Box–Muller */
{
    double u = uniform(), v = uniform();
    return sqrt(-2.0 * log(u > 0 ? u : 1e-300)) * cos(2.0 * HL_PI * v);
}

/* ---- NNLS ------------------------------------------------------------------------------------ */

/* Unconstrained least squares on the columns in mask by the normal equations (Gauss–Jordan with
 * partial pivoting): a different method from the code under test's Householder QR. */
static int subset_ls(const double *a, int m, int n, const double *b, unsigned mask, double *x)
{
    int idx[8], k = 0;
    for (int j = 0; j < n; ++j)
        if (mask >> j & 1)
            idx[k++] = j;
    double g[8][9];
    for (int r = 0; r < k; ++r) {
        for (int c = 0; c < k; ++c) {
            g[r][c] = 0;
            for (int i = 0; i < m; ++i)
                g[r][c] += a[i * n + idx[r]] * a[i * n + idx[c]];
        }
        g[r][k] = 0;
        for (int i = 0; i < m; ++i)
            g[r][k] += a[i * n + idx[r]] * b[i];
    }
    for (int c = 0; c < k; ++c) {
        int p = c;
        for (int r = c + 1; r < k; ++r)
            if (fabs(g[r][c]) > fabs(g[p][c]))
                p = r;
        if (fabs(g[p][c]) < 1e-12)
            return -1;
        for (int t = 0; t <= k; ++t) {
            double tmp = g[c][t];
            g[c][t] = g[p][t];
            g[p][t] = tmp;
        }
        for (int r = 0; r < k; ++r)
            if (r != c) {
                double f = g[r][c] / g[c][c];
                for (int t = c; t <= k; ++t)
                    g[r][t] -= f * g[c][t];
            }
    }
    for (int j = 0; j < n; ++j)
        x[j] = 0;
    for (int r = 0; r < k; ++r)
        x[idx[r]] = g[r][k] / g[r][r];
    return 0;
}

static double residual(const double *a, int m, int n, const double *b, const double *x)
{
    double s = 0;
    for (int i = 0; i < m; ++i) {
        double v = b[i];
        for (int j = 0; j < n; ++j)
            v -= a[i * n + j] * x[j];
        s += v * v;
    }
    return sqrt(s);
}

/* The NNLS optimum is the best of the unconstrained least-squares solutions on every column subset
 * that come out non-negative (the KKT point's free set is one of them). */
static void test_nnls_brute_force(void)
{
    int worse = 0, x_off = 0, trials = 300;
    for (int trial = 0; trial < trials; ++trial) {
        int n = 1 + trial % 5, m = n + 1 + (trial / 5) % 6;
        double a[12 * 5], b[12], x[5], best_x[5] = {0}, s[5];
        for (int i = 0; i < m * n; ++i)
            a[i] = uniform() * 2 - 1 + (trial % 3 == 0 ? 0.0 : 0.5); /* some all-positive, some mixed */
        for (int i = 0; i < m; ++i)
            b[i] = uniform() * 2 - 1;
        double best = residual(a, m, n, b, best_x); /* the empty set: x = 0 */
        for (unsigned mask = 1; mask < 1u << n; ++mask) {
            if (subset_ls(a, m, n, b, mask, s) != 0)
                continue;
            int feasible = 1;
            for (int j = 0; j < n; ++j)
                feasible &= s[j] >= 0;
            double r = residual(a, m, n, b, s);
            if (feasible && r < best)
                best = r, memcpy(best_x, s, sizeof s);
        }
        double rnorm = -1;
        struct hl_error err = {""};
        CHECK(frm_cost_nnls(a, (size_t)m, (size_t)n, b, x, &rnorm, &err) == 0);
        int nonneg = 1;
        for (int j = 0; j < n; ++j) {
            nonneg &= x[j] >= 0;
            x_off += fabs(x[j] - best_x[j]) > 1e-7 * (1 + fabs(best_x[j]));
        }
        CHECK(nonneg);
        CHECK_NEAR(rnorm, residual(a, m, n, b, x), 1e-9);
        worse += residual(a, m, n, b, x) > best * (1 + 1e-9) + 1e-12;
    }
    printf("nnls: %d random problems (1…5 columns): %d worse than brute force, %d solutions differ\n", trials, worse,
           x_off);
    CHECK(worse == 0);
    CHECK(x_off == 0);

    /* Bad input: one message, no result. */
    struct hl_error err = {""};
    double a[2] = {1, NAN}, b[2] = {1, 1}, x[1];
    CHECK(frm_cost_nnls(a, 2, 1, b, x, NULL, &err) != 0 && strstr(err.msg, "not finite"));
    CHECK(frm_cost_nnls(a, 2, 0, b, x, NULL, &err) != 0 && strstr(err.msg, "bad sizes"));
    /* Exactly collinear columns (vertices = 2·triangles, one mesh): a solution, residual zero. */
    double a3[6 * 3], b3[6], x3[3], r3 = -1;
    for (int i = 0; i < 6; ++i) {
        double t = 100.0 * (i + 1);
        a3[3 * i] = 1, a3[3 * i + 1] = t, a3[3 * i + 2] = 2 * t;
        b3[i] = 1.0 + 3e-3 * t;
    }
    CHECK(frm_cost_nnls(a3, 6, 3, b3, x3, &r3, &err) == 0);
    CHECK_NEAR(r3, 0.0, 1e-9);
    CHECK_NEAR(x3[1] + 2 * x3[2], 3e-3, 1e-12);
    /* Columns of wildly different scale (1 and 10⁶, as frames and pixels) still fit exactly. */
    double a2[3 * 2] = {1, 2e6, 1, 5e5, 1, 1e6}, b2[3], x2[2];
    for (int i = 0; i < 3; ++i)
        b2[i] = 1.5 * a2[2 * i] + 3e-6 * a2[2 * i + 1];
    CHECK(frm_cost_nnls(a2, 3, 2, b2, x2, NULL, &err) == 0);
    CHECK_NEAR(x2[0], 1.5, 1e-9);
    CHECK_NEAR(x2[1] * 1e6, 3.0, 1e-9);
}

/* ---- fits ------------------------------------------------------------------------------------ */

enum { FRAMES = 400, MAX_PER_FRAME = 6 };
static struct rnd_cost_frame frames[FRAMES];
static struct rnd_cost_object objects[FRAMES * MAX_PER_FRAME];

/* Frames of 1…6 objects with triangles, vertices (not proportional: the two must be separable) and
 * pixels spread over decades, so that each stage of the max form dominates in some objects; with
 * `inset`, each object's share inside an inset too (a fifth of them wholly outside, no pixels), and
 * the frames timed by the inset's model instead. */
static void synthesize_frames(const struct lod_cost_model *truth, const struct frm_inset_cost *inset, double noise)
{
    uint32_t next = 0;
    for (int f = 0; f < FRAMES; ++f) {
        frames[f].first_object = next;
        frames[f].object_count = 1 + (uint32_t)(uniform() * MAX_PER_FRAME) % MAX_PER_FRAME;
        for (uint32_t k = 0; k < frames[f].object_count; ++k) {
            struct rnd_cost_object *o = &objects[next++];
            o->triangles = pow(10, 2 + 3 * uniform());
            o->vertices = o->triangles * (0.3 + 1.2 * uniform());
            o->pixels_px = pow(10, 2 + 4 * uniform());
            o->draws = 2.0 * (1 + (int)(4 * uniform())); /* several sub-meshes: draws separable from objects */
            o->inside_share = !inset ? 0.0 : uniform() < 0.2 ? 0.0 : uniform();
            if (inset)
                o->pixels_px *= o->inside_share;
        }
        double ms = inset ? frm_cost_predict_inset_frame_ms(inset, &frames[f], objects)
                          : frm_cost_predict_frame_ms(truth, &frames[f], objects);
        frames[f].measured_ms = ms * (1 + noise * gaussian());
    }
}

static void synthesize(const struct lod_cost_model *truth, double noise)
{
    synthesize_frames(truth, NULL, noise);
}

static void check_recovered(const struct lod_cost_model *fit, const struct lod_cost_model *truth, double rel)
{
    CHECK(fit->form == truth->form);
    CHECK_NEAR(fit->c0_ms, truth->c0_ms, rel * truth->c0_ms);
    CHECK_NEAR(fit->c1_ms_per_triangle, truth->c1_ms_per_triangle, rel * truth->c1_ms_per_triangle);
    CHECK_NEAR(fit->c2_ms_per_vertex, truth->c2_ms_per_vertex, rel * truth->c2_ms_per_vertex);
    CHECK_NEAR(fit->c3_ms_per_pixel, truth->c3_ms_per_pixel, rel * truth->c3_ms_per_pixel);
    CHECK_NEAR(fit->c4_ms_per_draw, truth->c4_ms_per_draw, rel * truth->c4_ms_per_draw);
    CHECK_NEAR(fit->c5_ms_per_edge_px, truth->c5_ms_per_edge_px, rel * truth->c5_ms_per_edge_px);
}

/* The inset's model: objects with every share of their image inside the scissor; on exact data the
 * six terms come back (c0 given); with 2 % noise the triangle split within 10 %, the other terms within
 * 35 % (the edge term is the loosest), and the held-out error that of the noise. */
static void test_fit_inset(void)
{
    struct frm_inset_cost truth = {{LOD_COST_ADDITIVE, 0.3, 4e-5, 1e-5, 5e-6, 0.008, 3e-5}, 1.5e-5};
    uint32_t order[FRAMES];
    size_t train = 0;
    rnd_cost_split(FRAMES, 11, order, &train);
    struct hl_error err = {""};
    struct frm_inset_cost fit;
    struct frm_cost_fit_report rep;
    for (int noisy = 0; noisy < 2; ++noisy) {
        synthesize_frames(NULL, &truth, noisy ? 0.02 : 0.0);
        CHECK(frm_cost_fit_inset(truth.model.c0_ms, 0.5, frames, order, train, objects, &fit, &rep, &err) == 0);
        double tol = noisy ? 0.1 : 1e-6;
        check_recovered(&fit.model, &truth.model, noisy ? 0.35 : tol);
        CHECK_NEAR(fit.outside_ms_per_triangle, truth.outside_ms_per_triangle, tol * truth.outside_ms_per_triangle);
        CHECK_NEAR(fit.model.c1_ms_per_triangle, truth.model.c1_ms_per_triangle, tol * truth.model.c1_ms_per_triangle);
        struct frm_cost_accuracy acc = frm_cost_evaluate_inset(&fit, frames, order + train, FRAMES - train, objects);
        printf("fit inset, %s: inside %.4g outside %.4g per triangle, c2 %.4g c3 %.4g; held-out p95 %.3g\n",
               noisy ? "2 % noise" : "exact data", fit.model.c1_ms_per_triangle, fit.outside_ms_per_triangle,
               fit.model.c2_ms_per_vertex, fit.model.c3_ms_per_pixel, acc.p95_rel);
        CHECK(acc.p95_rel < (noisy ? 0.05 : 1e-6));
    }
    objects[0].inside_share = 1.5; /* a share outside [0, 1] is refused */
    CHECK(frm_cost_fit_inset(0.3, 0.5, frames, order, train, objects, &fit, &rep, &err) != 0 &&
          strstr(err.msg, "object"));
    objects[0].inside_share = 0.5;
    CHECK(frm_cost_fit_inset(NAN, 0.5, frames, order, train, objects, &fit, &rep, &err) != 0);
    for (size_t i = 0; i < FRAMES * MAX_PER_FRAME; ++i)
        objects[i].inside_share = 0.0;
}

static void test_fit_form(enum lod_cost_form form)
{
    const char *name = frm_cost_form_name(form);
    struct lod_cost_model truth = {form, 1.5, 4e-5, 2e-5, 3e-6, 0.01, 2e-5}; /* every term, the edge one too */
    uint32_t order[FRAMES];
    size_t train = 0;
    rnd_cost_split(FRAMES, 7, order, &train);
    struct hl_error err = {""};
    struct lod_cost_model fit;
    struct frm_cost_fit_report rep;

    synthesize(&truth, 0.0); /* exact data: the coefficients themselves */
    CHECK(frm_cost_fit(form, frames, order, train, objects, &fit, &rep, &err) == 0);
    check_recovered(&fit, &truth, 1e-6);
    struct frm_cost_accuracy acc = frm_cost_evaluate(&fit, frames, order + train, FRAMES - train, objects);
    printf("fit %s, exact data: c0 %.6g c1 %.6g c2 %.6g c3 %.6g c4 %.6g; held-out p95 %.2g, %d rounds\n", name,
           fit.c0_ms, fit.c1_ms_per_triangle, fit.c2_ms_per_vertex, fit.c3_ms_per_pixel, fit.c4_ms_per_draw,
           acc.p95_rel, rep.rounds);
    CHECK(acc.p95_rel < 1e-6 && acc.under5_share == 0.0 && acc.frames == FRAMES - train);

    synthesize(&truth, 0.02); /* 2 % Gaussian timing noise */
    CHECK(frm_cost_fit(form, frames, order, train, objects, &fit, &rep, &err) == 0);
    acc = frm_cost_evaluate(&fit, frames, order + train, FRAMES - train, objects);
    printf("fit %s, 2 %% noise: c0 %.4g c1 %.4g c2 %.4g c3 %.4g c4 %.4g; held-out median %.4f p95 %.4f "
           "under-5 %% %.3f\n",
           name, fit.c0_ms, fit.c1_ms_per_triangle, fit.c2_ms_per_vertex, fit.c3_ms_per_pixel, fit.c4_ms_per_draw,
           acc.median_rel, acc.p95_rel, acc.under5_share);
    check_recovered(&fit, &truth, 0.1);
    /* With 2 % noise on the measurements, |error| has median ≈ 0.674·2 % and p95 ≈ 1.96·2 %. */
    CHECK(acc.median_rel < 0.02 && acc.p95_rel < 0.05 && acc.under5_share < 0.05);

    /* c0 measured (calibrate's empty frames): on exact data the other four come back exactly and
     * c0 is the value given, not a fit; with c0 given wrong by 20 % the objects' terms absorb less
     * than an intercept would, and the held-out error shows it. */
    synthesize(&truth, 0.0);
    CHECK(frm_cost_fit_fixed(form, truth.c0_ms, 0.5, frames, order, train, objects, &fit, &rep, &err) == 0);
    check_recovered(&fit, &truth, 1e-6);
    CHECK(fit.c0_ms == truth.c0_ms);
    CHECK(frm_cost_fit_fixed(form, 1.2 * truth.c0_ms, 0.5, frames, order, train, objects, &fit, &rep, &err) == 0);
    CHECK(fit.c0_ms == 1.2 * truth.c0_ms && rep.rms_relative > 1e-4);
    CHECK(frm_cost_fit_fixed(form, NAN, 0.5, frames, order, train, objects, &fit, &rep, &err) != 0 &&
          strstr(err.msg, "fixed cost"));
    CHECK(frm_cost_fit_fixed(form, -1.0, 0.5, frames, order, train, objects, &fit, &rep, &err) != 0);
    CHECK(frm_cost_fit_fixed(form, 1.5, 1.0, frames, order, train, objects, &fit, &rep, &err) != 0 &&
          strstr(err.msg, "expectile"));

    /* The expectile: with 5 % noise an ordinary fit under-predicts about a sixth of the frames by more
     * than 5 %; τ = 0.95 lifts the objects' terms so that few are, at the price of over-predicting. */
    synthesize(&truth, 0.05);
    struct lod_cost_model mid, high;
    CHECK(frm_cost_fit_fixed(form, truth.c0_ms, 0.5, frames, order, train, objects, &mid, NULL, &err) == 0);
    CHECK(frm_cost_fit_fixed(form, truth.c0_ms, 0.95, frames, order, train, objects, &high, NULL, &err) == 0);
    struct frm_cost_accuracy a_mid = frm_cost_evaluate(&mid, frames, order + train, FRAMES - train, objects);
    struct frm_cost_accuracy a_high = frm_cost_evaluate(&high, frames, order + train, FRAMES - train, objects);
    printf("fit %s, 5 %% noise, c0 given: under-predicted by > 5 %%: %.3f (τ ½), %.3f (τ 0.95); p95 %.3f, %.3f\n",
           name, a_mid.under5_share, a_high.under5_share, a_mid.p95_rel, a_high.p95_rel);
    CHECK(a_mid.under5_share > 0.08 && a_high.under5_share < 0.5 * a_mid.under5_share);
    CHECK(high.c3_ms_per_pixel + high.c1_ms_per_triangle > mid.c3_ms_per_pixel + mid.c1_ms_per_triangle);
}

static void test_fit_misc(void)
{
    /* The wrong form fitted to max data does worse than the right one: the max is not cosmetic. */
    struct lod_cost_model truth = {LOD_COST_MAX, 1.0, 5e-5, 0, 4e-6, 0.005, 0.0}, add, mx;
    synthesize(&truth, 0.0);
    uint32_t order[FRAMES];
    size_t train = 0;
    rnd_cost_split(FRAMES, 3, order, &train);
    struct hl_error err = {""};
    CHECK(frm_cost_fit(LOD_COST_ADDITIVE, frames, order, train, objects, &add, NULL, &err) == 0);
    CHECK(frm_cost_fit(LOD_COST_MAX, frames, order, train, objects, &mx, NULL, &err) == 0);
    struct frm_cost_accuracy a = frm_cost_evaluate(&add, frames, order + train, FRAMES - train, objects);
    struct frm_cost_accuracy m = frm_cost_evaluate(&mx, frames, order + train, FRAMES - train, objects);
    CHECK(m.p95_rel < 1e-6 && a.p95_rel > 0.01);
    CHECK(add.c0_ms >= 0 && add.c1_ms_per_triangle >= 0 && add.c2_ms_per_vertex >= 0 && add.c3_ms_per_pixel >= 0 &&
          add.c4_ms_per_draw >= 0);

    /* Bad frames are refused with the frame named. */
    struct rnd_cost_frame bad = {0.0, 0, 1};
    uint32_t row = 0;
    CHECK(frm_cost_fit(LOD_COST_MAX, &bad, &row, 1, objects, &mx, NULL, &err) != 0 && strstr(err.msg, "frame 0"));
    CHECK(frm_cost_fit(LOD_COST_MAX, frames, order, 0, objects, &mx, NULL, &err) != 0);

    /* Accuracy arithmetic on hand-made frames: errors −10 %, 0, +2 %, +4 %, +20 % → median 4 %,
     * p95 (type 7: 0.8 of the way from 10 % to 20 %) 18 %, under-predicted by > 5 %: 1 of 5. */
    struct lod_cost_model one = {LOD_COST_ADDITIVE, 0, 0, 0, 0, 1.0, 0.0}; /* 1 ms per draw */
    struct rnd_cost_object ob = {.triangles = 0, .vertices = 0, .pixels_px = 0, .draws = 1};
    struct rnd_cost_frame hand[5] = {{1 / 0.9, 0, 1}, {1, 0, 1}, {1 / 1.02, 0, 1}, {1 / 1.04, 0, 1}, {1 / 1.2, 0, 1}};
    uint32_t rows[5] = {0, 1, 2, 3, 4};
    struct frm_cost_accuracy h = frm_cost_evaluate(&one, hand, rows, 5, &ob);
    CHECK_NEAR(h.median_rel, 0.04, 1e-12);
    CHECK_NEAR(h.p95_rel, 0.18, 1e-12);
    CHECK_NEAR(h.under5_share, 0.2, 1e-12);
    CHECK(h.frames == 5);

    /* Max-form arithmetic: max(geometry, raster) per object, plus draws, plus c0 once per frame. */
    struct lod_cost_model m2 = {LOD_COST_MAX, 2, 1e-3, 0, 1e-4, 0.5, 0.0};
    /* The edge term: √(triangles·pixels) pixels on triangle edges, in the raster stage. 100 triangles
     * over 400 pixels have 200 edge pixels: 0.2 ms at 1e-3; the max form takes it with the pixels. */
    struct lod_cost_model edge = {LOD_COST_ADDITIVE, 0, 0, 0, 0, 0, 1e-3};
    CHECK_NEAR(lod_cost_object_ms(&edge, 100, 0, 400, 0), 0.2, 1e-15);
    edge.form = LOD_COST_MAX, edge.c1_ms_per_triangle = 1e-3; /* geometry 0.1 ms < raster 0.2 ms */
    CHECK_NEAR(lod_cost_object_ms(&edge, 100, 0, 400, 0), 0.2, 1e-15);
    struct rnd_cost_object two[2] = {{.triangles = 1000, .vertices = 10, .pixels_px = 100, .draws = 2},
                                     {.triangles = 10, .vertices = 10, .pixels_px = 1e5, .draws = 2}};
    struct rnd_cost_frame fr = {1, 0, 2};
    CHECK_NEAR(frm_cost_predict_frame_ms(&m2, &fr, two), 2 + (1 + 1) + (10 + 1), 1e-12);
}

static void test_split(void)
{
    uint32_t a[100], b[100];
    size_t ta = 0, tb = 0;
    rnd_cost_split(100, 5, a, &ta);
    rnd_cost_split(100, 5, b, &tb);
    CHECK(ta == 75 && tb == 75 && memcmp(a, b, sizeof a) == 0);
    int seen[100] = {0};
    for (int i = 0; i < 100; ++i)
        seen[a[i]]++;
    int perm = 1;
    for (int i = 0; i < 100; ++i)
        perm &= seen[i] == 1;
    CHECK(perm);
    rnd_cost_split(100, 6, b, &tb);
    CHECK(memcmp(a, b, sizeof a) != 0);
    rnd_cost_split(2, 1, a, &ta);
    CHECK(ta == 1);
}

/* ---- profile JSON ----------------------------------------------------------------------------- */

static char dir[64];

static const char *write_text(const char *name, const char *text)
{
    static char path[128];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    return path;
}

static void expect_bad(const char *name, const char *text, const char *message)
{
    const char *path = write_text(name, text);
    struct frm_cost_profile p;
    struct hl_error err = {""};
    int rc = frm_cost_profile_read(path, &p, &err);
    CHECK(rc != 0);
    if (rc == 0 || !strstr(err.msg, path) || !strstr(err.msg, message)) {
        ++tu_failures;
        fprintf(stderr, "%s: got '%s', wanted the path and '%s'\n", name, err.msg, message);
    }
}

#define GOOD_HEAD "{\"format\": \"hmdlod-cost-profile-1\", \"form\": \"max\", \"renderer\": \"x\", "
#define GOOD_COEF "\"c0_ms\": 1, \"c1_ms_per_triangle\": 2e-5, \"c2_ms_per_vertex\": 0, \"c3_ms_per_pixel\": 3e-6"

static void test_profile(void)
{
    struct frm_cost_profile p, q;
    memset(&p, 0, sizeof p);
    p.model = (struct lod_cost_model){LOD_COST_ADDITIVE, 1.25, 3.0e-5, 1.0 / 3.0 * 1e-5, 2.7e-6, 0.0071, 4.5e-5};
    p.held_out = (struct frm_cost_accuracy){0.081, 0.23, 0.12, 25};
    p.held_out_other = (struct frm_cost_accuracy){0.09, 0.31, 0.2, 25};
    snprintf(p.label, sizeof p.label, "test profile");
    snprintf(p.renderer, sizeof p.renderer, "llvmpipe (LLVM 15.0.6, 256 bits)");
    snprintf(p.display, sizeof p.display, "vive");
    p.eye_width_px = 1080, p.eye_height_px = 1200;
    snprintf(p.date, sizeof p.date, "2026-12-01 21:00 UTC");
    snprintf(p.commit, sizeof p.commit, "abc1234");
    p.load_before = 0.25, p.load_after = 1.5;
    rnd_cost_grid_default(&p.grid, 0);
    p.fixed = (struct frm_cost_fixed){1.75, 1.5, 2.25, 28};
    p.periphery_count = 2;
    p.periphery[0] = (struct frm_cost_periphery){0.5, {LOD_COST_ADDITIVE, 0.6, 4.0e-5, 0, 6.5e-6, 0.0075, 6.0e-5},
                                                 {0.1, 0.3, 0.04, 50}, {0.6, 0.5, 0.7, 182}, 0.9};
    p.periphery[1] = (struct frm_cost_periphery){0.25, {LOD_COST_MAX, 0.2, 5.5e-5, 1e-6, 4.0e-6, 0.007, 9.5e-5},
                                                 {0.2, 0.45, 0.02, 50}, {0.2, 0.15, 0.25, 182}, 0.0};
    char path[128];
    snprintf(path, sizeof path, "%s/round.json", dir);
    struct hl_error err = {""};
    CHECK(frm_cost_profile_write(path, &p, &err) == 0);
    char partial[160];
    snprintf(partial, sizeof partial, "%s.partial", path);
    CHECK(access(partial, F_OK) != 0);
    CHECK(frm_cost_profile_read(path, &q, &err) == 0);
    CHECK(q.model.form == p.model.form && q.model.c0_ms == p.model.c0_ms &&
          q.model.c1_ms_per_triangle == p.model.c1_ms_per_triangle &&
          q.model.c2_ms_per_vertex == p.model.c2_ms_per_vertex && q.model.c3_ms_per_pixel == p.model.c3_ms_per_pixel &&
          q.model.c4_ms_per_draw == p.model.c4_ms_per_draw);
    CHECK(q.held_out.p95_rel == p.held_out.p95_rel && q.held_out.frames == 25 &&
          q.held_out_other.under5_share == p.held_out_other.under5_share);
    CHECK(!strcmp(q.renderer, p.renderer) && !strcmp(q.label, p.label) && !strcmp(q.display, "vive") &&
          !strcmp(q.date, p.date) && !strcmp(q.commit, p.commit));
    CHECK(q.eye_width_px == 1080 && q.eye_height_px == 1200);
    CHECK(q.load_before == 0.25 && q.load_after == 1.5);
    CHECK(q.fixed.frames == 28 && q.fixed.median_ms == 1.75 && q.fixed.p25_ms == 1.5 && q.fixed.p75_ms == 2.25);
    CHECK(q.grid.levels == p.grid.levels && q.grid.coverages == p.grid.coverages && q.grid.counts == p.grid.counts &&
          q.grid.repeats == p.grid.repeats && q.grid.families == 2 && q.grid.objects[4] == p.grid.objects[4] &&
          q.grid.coverage[0] == p.grid.coverage[0]);
    /* The periphery's models come back whole, each with its own form, accuracy and fixed cost. */
    CHECK(q.periphery_count == 2 && q.periphery[0].scale == 0.5 && q.periphery[1].scale == 0.25);
    CHECK(q.periphery[0].model.form == LOD_COST_ADDITIVE && q.periphery[1].model.form == LOD_COST_MAX &&
          q.periphery[1].model.c5_ms_per_edge_px == 9.5e-5 && q.periphery[0].model.c0_ms == 0.6 &&
          q.periphery[1].model.c2_ms_per_vertex == 1e-6);
    CHECK(q.periphery[0].composite_ms == 0.9 && q.periphery[1].composite_ms == 0.0); /* 0: not measured, absent */
    CHECK(q.periphery[0].held_out.p95_rel == 0.3 && q.periphery[1].fixed.frames == 182 &&
          q.periphery[1].fixed.p75_ms == 0.25);
    /* The replay takes each scale's model for the periphery and the plain one where there is none. */
    struct lod_cost_model plain;
    struct frm_layer_costs lc;
    char label[300];
    CHECK(frm_cost_model_load(path, &plain, &lc, label, sizeof label, &err) == 0);
    const struct lod_cost_model *per_scale = lc.periphery;
    CHECK(lc.periphery_count == 2 && plain.c0_ms == 1.25 && per_scale[0].c0_ms == 1.25 && per_scale[1].c0_ms == 1.25 &&
          per_scale[2].c0_ms == 0.6 && per_scale[3].c0_ms == 1.25 && per_scale[4].c5_ms_per_edge_px == 9.5e-5);
    CHECK(strstr(label, "periphery models at 2 layer scales") != NULL);
    CHECK(!lc.inset_measured); /* no inset model in that profile: the plain one prices the inset */

    /* The inset's model comes back whole, and the replay prices the inset with it. */
    p.inset_measured = 1;
    p.inset = (struct frm_cost_inset){5.0, 5.0, {{LOD_COST_ADDITIVE, 0.4, 2.5e-5, 0, 5.0e-6, 0.006, 0}, 1.25e-5},
                                      {0.12, 0.35, 0.03, 50}, {0.4, 0.3, 0.5, 60}};
    CHECK(frm_cost_profile_write(path, &p, &err) == 0 && frm_cost_profile_read(path, &q, &err) == 0);
    CHECK(q.inset_measured && q.inset.radius_deg == 5.0 && q.inset.blend_deg == 5.0 &&
          q.inset.cost.model.form == LOD_COST_ADDITIVE && q.inset.cost.model.c1_ms_per_triangle == 2.5e-5 &&
          q.inset.cost.model.c3_ms_per_pixel == 5.0e-6 && q.inset.cost.outside_ms_per_triangle == 1.25e-5 &&
          q.inset.held_out.p95_rel == 0.35 && q.inset.fixed.frames == 60);
    CHECK(frm_cost_model_load(path, &plain, &lc, label, sizeof label, &err) == 0);
    CHECK(lc.inset_measured && lc.inset.model.c1_ms_per_triangle == 2.5e-5 && lc.inset.model.c0_ms == 0.4 &&
          lc.inset.outside_ms_per_triangle == 1.25e-5 && lc.periphery[2].c0_ms == 0.6 &&
          strstr(label, "an inset model (5 degrees)") != NULL);
    /* An object half inside: half its triangles at the inside rate, half at the outside one, every
     * vertex, its pixels within and its draws (additive). */
    CHECK_NEAR(frm_inset_object_ms(&lc.inset, 1000, 800, 2000, 2, 0.5),
               500 * 2.5e-5 + 500 * 1.25e-5 + 2000 * 5.0e-6 + 2 * 0.006, 1e-12);
    CHECK_NEAR(frm_inset_object_ms(&lc.inset, 1000, 800, 0, 2, NAN), 1000 * 2.5e-5 + 2 * 0.006, 1e-12);
    CHECK_NEAR(frm_inset_object_ms(&lc.inset, 1000, 800, 0, 2, -3), 1000 * 1.25e-5 + 2 * 0.006, 1e-12);
    p.inset_measured = 0;

    /* The unwritable: one message, nothing left. */
    CHECK(frm_cost_profile_write("/nonexistent-dir/x.json", &p, &err) != 0 && strstr(err.msg, "/nonexistent-dir"));
    p.model.c3_ms_per_pixel = -1;
    CHECK(frm_cost_profile_write(path, &p, &err) != 0 && strstr(err.msg, "c3_ms_per_pixel"));

    /* A minimal file reads (everything but format, form, coefficients and renderer is optional). */
    const char *minimal = write_text("minimal.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF
                                                               ", \"c4_ms_per_draw\": 0.01}}");
    CHECK(frm_cost_profile_read(minimal, &q, &err) == 0 && q.model.form == LOD_COST_MAX &&
          q.model.c4_ms_per_draw == 0.01);
    /* Formats 1 and 2 fitted the pixel terms per bounding-disc pixel: they read, and their label says so;
     * the current format's label is as written. */
    CHECK(strstr(q.label, "[hmdlod-cost-profile-1: pixel terms fitted per bounding-disc pixel, before fill factors; "
                          "recalibrate]") == q.label);
    const char *v2 = write_text("v2.json", "{\"format\": \"hmdlod-cost-profile-2\", \"form\": \"max\", "
                                           "\"renderer\": \"x\", \"label\": \"mine\", \"coefficients\": {" GOOD_COEF
                                           ", \"c4_ms_per_draw\": 0, \"c5_ms_per_edge_px\": 1e-5}}");
    CHECK(frm_cost_profile_read(v2, &q, &err) == 0 && q.model.c5_ms_per_edge_px == 1e-5 &&
          strstr(q.label, "mine [hmdlod-cost-profile-2: pixel terms fitted per bounding-disc pixel") == q.label);
    CHECK(frm_cost_profile_read(path, &q, &err) == 0 && !strcmp(q.label, p.label));

    expect_bad("missing.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF "}}", "'c4_ms_per_draw': missing");
    expect_bad("nonfinite.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 1e999}}",
               "'c4_ms_per_draw': not finite");
    expect_bad("negative.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": -0.5}}",
               "'c4_ms_per_draw': -0.5 is negative");
    expect_bad("string.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": \"1\"}}",
               "'c4_ms_per_draw': not a number");
    expect_bad("form.json",
               "{\"format\": \"hmdlod-cost-profile-1\", \"form\": \"linear\", \"renderer\": \"x\", "
               "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0}}",
               "'form': unknown form 'linear'");
    expect_bad("unknown.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0, \"c5\": 1}}",
               "'c5': unknown key");
    expect_bad("load.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0}, "
                            "\"load_average_1min\": [1]}",
               "'load_average_1min': expected two");
    expect_bad("v2five.json",
               "{\"format\": \"hmdlod-cost-profile-2\", \"form\": \"max\", \"renderer\": \"x\", "
               "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0}}",
               "'c5_ms_per_edge_px': missing");
    expect_bad("v1six.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0, "
                             "\"c5_ms_per_edge_px\": 0}}",
               "'c5_ms_per_edge_px': unknown key");
    expect_bad("nocoef.json", GOOD_HEAD "\"label\": \"x\"}", "'coefficients': missing");
    expect_bad("fixed.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0}, "
                             "\"fixed_cost\": {\"frames\": 4, \"median_ms\": 1, \"p25_ms\": 2, \"p75_ms\": 3}}",
               "'fixed_cost': expected p25_ms ≤ median_ms ≤ p75_ms");
    expect_bad("fixed0.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0}, "
                              "\"fixed_cost\": {\"frames\": 0, \"median_ms\": 1, \"p25_ms\": 1, \"p75_ms\": 1}}",
               "'fixed_cost': 'frames'");
    expect_bad("fixedkey.json", GOOD_HEAD "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0}, "
                                "\"fixed_cost\": {\"frames\": 4, \"mean_ms\": 1}}",
               "'fixed_cost': 'mean_ms': unknown key");
    expect_bad("norenderer.json",
               "{\"format\": \"hmdlod-cost-profile-1\", \"form\": \"max\", \"coefficients\": {" GOOD_COEF
               ", \"c4_ms_per_draw\": 0}}",
               "'renderer': missing");
    /* A periphery model is checked like the main one, and names its place in the list. */
#define GOOD_LAYER "{\"scale\": 0.5, \"form\": \"additive\", \"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0, \"c5_ms_per_edge_px\": 0}"
#define V3_HEAD "{\"format\": \"hmdlod-cost-profile-3\", \"form\": \"max\", \"renderer\": \"x\", \"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0, \"c5_ms_per_edge_px\": 0}, "
    expect_bad("layer_scale.json", V3_HEAD "\"periphery\": [" GOOD_LAYER "}, {\"scale\": 0.6, \"form\": \"max\", "
               "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0, \"c5_ms_per_edge_px\": 0}}]}",
               "'periphery'[1]: 'scale': 0.6 is not a periphery scale");
    expect_bad("layer_twice.json", V3_HEAD "\"periphery\": [" GOOD_LAYER "}, " GOOD_LAYER "}]}",
               "'periphery'[1]: 'scale': 0.5 appears twice");
    expect_bad("layer_coef.json", V3_HEAD "\"periphery\": [{\"scale\": 0.25, \"form\": \"max\", \"coefficients\": {"
               GOOD_COEF ", \"c4_ms_per_draw\": 0}}]}",
               "'periphery'[0]: 'coefficients': 'c5_ms_per_edge_px': missing");
    expect_bad("layer_key.json", V3_HEAD "\"periphery\": [" GOOD_LAYER ", \"c6\": 1}]}", "'periphery'[0]: 'c6': unknown key");
    expect_bad("layer_fixed.json", V3_HEAD "\"periphery\": [" GOOD_LAYER ", \"fixed_cost\": {\"frames\": 2, "
               "\"median_ms\": 1, \"p25_ms\": 2, \"p75_ms\": 3}}]}",
               "'periphery'[0]: 'fixed_cost': expected p25_ms");
    expect_bad("layer_composite.json", V3_HEAD "\"periphery\": [" GOOD_LAYER ", \"composite_ms\": -2}]}",
               "'periphery'[0]: 'composite_ms': -2 is negative");
    expect_bad("layer_list.json", V3_HEAD "\"periphery\": {\"scale\": 0.5}}", "'periphery': expected an array");
#define GOOD_INSET "{\"radius_deg\": 5, \"blend_deg\": 5, \"form\": \"additive\", \"outside_ms_per_triangle\": 1e-5, " \
                   "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0, \"c5_ms_per_edge_px\": 0}"
    expect_bad("inset_radius.json", V3_HEAD "\"inset\": {\"radius_deg\": 0, \"blend_deg\": 5, \"form\": \"max\", "
               "\"outside_ms_per_triangle\": 1e-5, \"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0, "
               "\"c5_ms_per_edge_px\": 0}}}",
               "'inset': expected radius_deg and blend_deg in (0, 45]");
    expect_bad("inset_outside.json", V3_HEAD "\"inset\": {\"radius_deg\": 5, \"blend_deg\": 5, \"form\": \"max\", "
               "\"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0, \"c5_ms_per_edge_px\": 0}}}",
               "'inset': 'outside_ms_per_triangle': missing");
    expect_bad("inset_negative.json", V3_HEAD "\"inset\": {\"radius_deg\": 5, \"blend_deg\": 5, \"form\": \"max\", "
               "\"outside_ms_per_triangle\": -1e-5, \"coefficients\": {" GOOD_COEF ", \"c4_ms_per_draw\": 0, "
               "\"c5_ms_per_edge_px\": 0}}}",
               "'inset': 'outside_ms_per_triangle'");
    expect_bad("inset_key.json", V3_HEAD "\"inset\": " GOOD_INSET ", \"scale\": 0.5}}", "'inset': 'scale': unknown key");
    expect_bad("inset_form.json", V3_HEAD "\"inset\": {\"radius_deg\": 5, \"blend_deg\": 5}}", "'inset': 'form': missing");
    expect_bad("inset_list.json", V3_HEAD "\"inset\": [" GOOD_INSET "}]}", "'inset': not an object");
    expect_bad("format.json", "{\"format\": \"hmdlod-display-1\"}", "'format'");
    expect_bad("notjson.json", "{\"format\": ", "not valid JSON");
    expect_bad("array.json", "[1, 2]", "expected a JSON object");
    struct hl_error e2 = {""};
    CHECK(frm_cost_profile_read("/nonexistent-dir/x.json", &q, &e2) != 0 && strstr(e2.msg, "/nonexistent-dir/x.json"));

    /* The built-in reference is labelled as such, on llvmpipe, with non-negative coefficients. */
    struct frm_cost_profile b;
    frm_cost_profile_builtin_llvmpipe(&b);
    CHECK(strstr(b.label, "built-in llvmpipe reference (2-core, measured") != NULL);
    CHECK(strstr(b.renderer, "llvmpipe") != NULL);
    CHECK(b.model.c0_ms > 0 && b.model.c1_ms_per_triangle >= 0 && b.model.c2_ms_per_vertex >= 0 &&
          b.model.c3_ms_per_pixel >= 0 && b.model.c4_ms_per_draw >= 0);
    CHECK(b.model.c1_ms_per_triangle + b.model.c2_ms_per_vertex > 0 && b.model.c3_ms_per_pixel > 0);
    snprintf(path, sizeof path, "%s/builtin.json", dir);
    CHECK(frm_cost_profile_write(path, &b, &err) == 0 && frm_cost_profile_read(path, &q, &err) == 0 &&
          q.model.c0_ms == b.model.c0_ms && !strcmp(q.label, b.label));
}

/* ---- one tiny real measurement --------------------------------------------------------------- */

static void test_measure(void)
{
    const struct hmd_profile *vive = hmd_builtin_find("vive");
    CHECK(vive != NULL);
    if (!vive)
        return;
    struct rnd_cost_grid g;
    rnd_cost_grid_default(&g, 1);
    g.render_scale = 0.25;
    g.repeats = 1;
    struct rnd_calibration cal;
    struct hl_error err = {""};
    int rc = frm_cost_calibrate(vive, &g, 1, &cal, &err);
    if (rc != 0) {
        fprintf(stderr, "measure: %s\n", err.msg);
        CHECK(rc == 0);
        return;
    }
    CHECK(cal.frame_count == 24 && g.eye_width_px == 270 && g.eye_height_px == 300);
    CHECK(strstr(cal.renderer, "llvmpipe") != NULL || cal.renderer[0] != '\0');
    size_t objects_seen = 0;
    for (size_t f = 0; f < cal.frame_count; ++f) {
        CHECK(cal.frames[f].measured_ms > 0 && isfinite(cal.frames[f].measured_ms));
        objects_seen += cal.frames[f].object_count;
    }
    CHECK(objects_seen == cal.object_count && cal.object_count == 2 * 2 * 2 * (1 + 8 + 32));
    /* The fixed cost: one empty frame before each family's 12 points and one after every 8. */
    CHECK(cal.empty_frames == 4 && cal.empty_ms > 0.0 && cal.empty_p25_ms <= cal.empty_ms &&
          cal.empty_ms <= cal.empty_p75_ms);
    /* Grid order is level, coverage, count: frame 0 is level 0, coverage 2 %, 1 object; the estimate
     * is within 10 % of the requested coverage of both eyes (270 × 300 each). */
    const struct rnd_cost_object *o = &cal.objects[cal.frames[0].first_object];
    CHECK_NEAR(o->pixels_px / o->fill, 0.02 * 2 * 270 * 300, 0.1 * 0.02 * 2 * 270 * 300);
    /* The pixels the model charges are the fragments: the disc × the bumpy sphere's fill (scn_lod_fill). */
    CHECK(o->fill > 0.6 && o->fill < 0.8);
    CHECK(o->triangles == 2.0 * 3906 && o->draws == 2.0);
    /* The second half is the chair (600 triangles, 640 vertices at level 0). */
    const struct rnd_cost_object *chair = &cal.objects[cal.frames[12].first_object];
    CHECK(chair->triangles == 2.0 * 600 && chair->vertices == 2.0 * 640);
    /* The same grid as a periphery at s = 0.5: the same objects, a quarter of the pixels charged. */
    struct rnd_cost_grid gp = g;
    gp.periphery_scale = 0.5;
    struct rnd_calibration per;
    rc = frm_cost_calibrate(vive, &gp, 1, &per, &err);
    CHECK(rc == 0);
    if (rc == 0) {
        CHECK(per.frame_count == cal.frame_count && per.object_count == cal.object_count && per.empty_frames == 4);
        const struct rnd_cost_object *q = &per.objects[per.frames[0].first_object];
        CHECK_NEAR(q->pixels_px, 0.25 * o->pixels_px, 1e-9 * o->pixels_px);
        CHECK(q->triangles == o->triangles && per.frames[0].measured_ms > 0.0);
        /* Its composite, timed after each empty frame; the plain grid has none. */
        CHECK(per.composite_frames == per.empty_frames && per.composite_ms > 0.0 && cal.composite_frames == 0);
        rnd_calibration_free(&per);
    }
    /* The inset alone (5° + 5° around the lens centre): the same objects, their pixels counted within
     * its rectangles — none for an object wholly outside them, at most the rectangles' own. */
    struct rnd_cost_grid gi = g;
    gi.inset_radius_deg = 5.0, gi.inset_blend_deg = 5.0;
    struct rnd_calibration ins;
    rc = frm_cost_calibrate(vive, &gi, 1, &ins, &err);
    CHECK(rc == 0);
    if (rc == 0) {
        CHECK(ins.frame_count == cal.frame_count && ins.object_count == cal.object_count && ins.empty_frames == 4 &&
              ins.composite_frames == 0);
        const struct rnd_cost_eye *r0 = &ins.inset_eyes[0], *r1 = &ins.inset_eyes[1];
        double rect_px = (double)r0->width_px * r0->height_px + (double)r1->width_px * r1->height_px;
        CHECK(r0->width_px < 270 && r0->height_px < 300 && rect_px > 100.0 && ins.eyes[0].width_px == 270);
        CHECK(r0->tan_left + r0->tan_right < cal.eyes[0].tan_left + cal.eyes[0].tan_right);
        /* The rectangle's tangents per pixel are the eye's: the same image, cut. */
        CHECK_NEAR((r0->tan_left + r0->tan_right) / r0->width_px, (cal.eyes[0].tan_left + cal.eyes[0].tan_right) / 270.0,
                   1e-12);
        const struct rnd_cost_object *q = &ins.objects[ins.frames[0].first_object];
        CHECK(q->pixels_px > 0.0 && q->pixels_px <= o->pixels_px && q->pixels_px <= q->fill * rect_px * 1.001);
        CHECK_NEAR(q->inside_share, q->pixels_px / o->pixels_px, 1e-9); /* the same sphere, the same fill */
        CHECK(o->inside_share == 1.0 && q->inside_share > 0.0 && q->inside_share < 1.0);
        CHECK(q->triangles == o->triangles && ins.frames[0].measured_ms > 0.0);
        const struct rnd_cost_frame *many = &ins.frames[5]; /* 32 spheres over 30 % of each eye */
        int outside = 0;
        for (uint32_t k = 0; k < many->object_count; ++k) {
            const struct rnd_cost_object *m = &ins.objects[many->first_object + k];
            outside += m->pixels_px == 0.0 && m->inside_share == 0.0;
        }
        CHECK(many->object_count == 32 && outside > 0);
        rnd_calibration_free(&ins);
    }
    gi.periphery_scale = 0.5; /* an inset over a periphery is not a grid of one layer */
    CHECK(rnd_cost_measure(vive, &gi, 1, &ins, &err) != 0 && strstr(err.msg, "inset radius 5"));
    gp.periphery_scale = 0.1;
    struct rnd_calibration none0;
    CHECK(rnd_cost_measure(vive, &gp, 1, &none0, &err) != 0 && strstr(err.msg, "periphery scale 0.1"));
    /* Bad grids are refused before anything is drawn. */
    g.repeats = 0;
    struct rnd_calibration none;
    CHECK(rnd_cost_measure(vive, &g, 1, &none, &err) != 0 && strstr(err.msg, "grid"));
    rnd_calibration_free(&cal);
}

int main(void)
{
    /* Keep Mesa's driver loaded to the end, so LSan sees its globals as reachable (PLATFORM.md §4). */
    dlopen("/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so", RTLD_NOW | RTLD_NODELETE);
    snprintf(dir, sizeof dir, "/tmp/hmdlod-test-cost-XXXXXX");
    if (!mkdtemp(dir)) {
        fprintf(stderr, "cannot make a temporary folder\n");
        return 1;
    }
    test_nnls_brute_force();
    test_fit_form(LOD_COST_ADDITIVE);
    test_fit_form(LOD_COST_MAX);
    test_fit_misc();
    test_fit_inset();
    test_split();
    test_profile();
    test_measure();
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "note: could not remove %s\n", dir);
    return tu_finish("test_cost");
}
