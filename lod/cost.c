/* The cost model's arithmetic (Funkhouser & Séquin 1993 §4) and its online correction. The
 * coefficients are measured per machine by render/ (`hmdlod calibrate`). */
#include <math.h>
#include <string.h>

#include "lod/lod.h"

double lod_cost_object_ms(const struct lod_cost_model *m, double triangles, double vertices, double pixels,
                          double draws)
{
    double geometry_ms = m->c1_ms_per_triangle * triangles + m->c2_ms_per_vertex * vertices;
    double fill_ms = m->c3_ms_per_pixel * pixels;
    if (m->c5_ms_per_edge_px > 0.0) /* a square root per candidate only where the profile has the term */
        fill_ms += m->c5_ms_per_edge_px * sqrt(triangles * pixels);
    double draw_ms = m->c4_ms_per_draw * draws;
    /* §4: a pipeline runs at its slowest stage; the additive form is for renderers whose stages
     * share the same CPUs (llvmpipe bins on the calling thread, rasterises at flush). */
    if (m->form == LOD_COST_MAX)
        return fmax(geometry_ms, fill_ms) + draw_ms;
    return geometry_ms + fill_ms + draw_ms;
}

void lod_cost_correction_init(struct lod_cost_correction *c, double alpha)
{
    c->ratio = 1.0;
    c->variance = 0.0;
    c->alpha = (alpha > 0.0 && alpha <= 1.0) ? alpha : 0.1;
    c->spread = 2.0;
}

void lod_cost_correction_update(struct lod_cost_correction *c, double measured_ms, double predicted_ms)
{
    if (!isfinite(measured_ms) || !isfinite(predicted_ms) || measured_ms <= 0.0 || predicted_ms <= 0.0)
        return;
    double r = measured_ms / predicted_ms;
    double delta = r - c->ratio;
    c->ratio += c->alpha * delta;
    c->variance = (1.0 - c->alpha) * (c->variance + c->alpha * delta * delta); /* exponentially weighted */
    c->variance = fmin(c->variance, 16.0);
    /* A single pathological frame (a page fault, a preempted thread) must not starve the budget. */
    c->ratio = fmin(fmax(c->ratio, 0.25), 4.0);
}

/* Only ever tightens: a model that over-predicts keeps its own (safe) prediction as the bound, so
 * the predicted cost of a frame never exceeds the budget either. The margin of `spread` standard
 * deviations aims at a share of frames within the budget, not at the mean frame. */
double lod_cost_correction_budget_ms(const struct lod_cost_correction *c, double budget_ms)
{
    double divisor = c->ratio + c->spread * sqrt(c->variance);
    return divisor > 1.0 ? budget_ms / divisor : budget_ms;
}

/* ---- affine correction (weighted least squares with forgetting and a prior) ------------------------ */
/* The prior, as pseudo-frames: a at c0 with the weight of a tenth of a frame, b at 1 with the weight
 * of a tenth of a frame whose objects cost prior_x_ms — against ~1 / (1 − λ) = 50 frames of data it
 * biases a fit the frames determine by well under 1 %. With frames that all draw x̄ the unexplained error splits
 * x²/(x² + x̄²) onto a (rest onto b): at x̄ = 1.4 ms 98 % goes to the fixed cost, at 6 ms 74 %. */
#define RLS_PRIOR_FRAMES 0.1
#define RLS_PRIOR_X_MS 10.0
#define RLS_B_MIN 0.25
#define RLS_B_MAX 4.0
#define RLS_SIGMA_FLOOR_MS 0.3
#define RLS_SIGMA_START_MS 1.5
#define RLS_HAMPEL_FRAMES 9    /* the last frames whose median error a new frame is judged by */
#define RLS_HAMPEL_MIN 5       /* fewer errors than this: no median yet */
#define RLS_HAMPEL_K 3.0       /* robust standard deviations a frame may stray from that median */
#define RLS_QUANTILE_MIN 64    /* errors before the margin is read as a quantile (see margin_ms) */
#define RLS_BODY_SHARE 0.97    /* the quantile a tail beyond is judged against (margin_ms) */
#define RLS_TAIL_RATIO 1.5     /* how far past it a tail is followed (margin_ms) */

void lod_cost_rls_init(struct lod_cost_rls *c, double c0_ms, double lambda)
{
    memset(c, 0, sizeof *c);
    c->c0_ms = isfinite(c0_ms) && c0_ms >= 0.0 ? c0_ms : 0.0;
    c->a_ms = c->c0_ms, c->b = 1.0;
    c->lambda = lambda > 0.5 && lambda <= 1.0 ? lambda : 0.98;
    c->spread = 2.0;
    c->within_share = LOD_COST_WITHIN_SHARE_DEFAULT;
    /* Not yet measured is not exact: the first frames keep spread · 1.5 ms in hand (a full-scale
     * auditorium frame here is under-predicted by 30–45 % at first), and the margin falls as the
     * frames show how well the fit does. */
    c->residual_var = RLS_SIGMA_START_MS * RLS_SIGMA_START_MS;
}

/* Minimises Σ w (m − a − b·x)² + r_a (a − c0)² + r_b (b − 1)² with a in [0, a_max] and b in
 * [B_MIN, B_MAX]: the 2 × 2 normal equations, and where the minimum lies outside the box, the
 * 1-D minimum on the bound it crossed (the objective is convex, so that is the constrained one). */
static void rls_solve(struct lod_cost_rls *c)
{
    const double ra = RLS_PRIOR_FRAMES, rb = RLS_PRIOR_FRAMES * RLS_PRIOR_X_MS * RLS_PRIOR_X_MS;
    const double a_max = 4.0 * c->c0_ms + 10.0;
    double p = c->s1 + ra, q = c->sx, r = c->sxx + rb;
    double u = c->sm + ra * c->c0_ms, v = c->sxm + rb * 1.0;
    double det = p * r - q * q; /* > 0: p·r ≥ ra·rb + (Σw)(Σwx²) ≥ ra·rb + (Σwx)² */
    double a = (u * r - q * v) / det, b = (p * v - q * u) / det;
    if (b < RLS_B_MIN || b > RLS_B_MAX) {
        b = fmin(fmax(b, RLS_B_MIN), RLS_B_MAX);
        a = (u - q * b) / p;
    }
    if (a < 0.0 || a > a_max) {
        a = fmin(fmax(a, 0.0), a_max);
        b = fmin(fmax((v - q * a) / r, RLS_B_MIN), RLS_B_MAX);
    }
    c->a_ms = a, c->b = b;
}

/* Median of v[0 … n−1], n ≤ RLS_HAMPEL_FRAMES (sorts v). */
static double median_small(double *v, int n)
{
    for (int i = 1; i < n; ++i)
        for (int j = i; j > 0 && v[j - 1] > v[j]; --j) {
            double t = v[j];
            v[j] = v[j - 1], v[j - 1] = t;
        }
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Hampel's identifier (Hampel 1974; Pearson 2002) on the last frames' a-priori errors, this one
 * included: their median ± K · 1.4826 · MAD, the MAD floored. A preempted frame lies outside and
 * enters the fit at the band's edge; an error the frames share (the model off by 3 ms from some
 * frame on) moves the median within five frames and passes whole. Until there are five errors,
 * ± the starting σ around none: the first frame fed decides the fit (a tenth of a frame of prior),
 * and the one here that was preempted (5 ms late) set a line through it that the next, lighter
 * frames made steeper — 68 objects dropped, 25 frames to recover. A model truly off by 2.5 ms is
 * learnt in two frames instead of one. */
static void hampel_band(const struct lod_cost_rls *c, double *lo, double *hi)
{
    int n = (int)(c->recent_count < RLS_HAMPEL_FRAMES ? c->recent_count : RLS_HAMPEL_FRAMES);
    if (n < RLS_HAMPEL_MIN) {
        *lo = -RLS_SIGMA_START_MS, *hi = RLS_SIGMA_START_MS;
        return;
    }
    double v[RLS_HAMPEL_FRAMES], d[RLS_HAMPEL_FRAMES];
    for (int j = 0; j < n; ++j)
        v[j] = c->recent_error_ms[(c->recent_next + LOD_COST_RLS_WINDOW - 1 - (uint32_t)j) % LOD_COST_RLS_WINDOW];
    double centre = median_small(v, n);
    for (int j = 0; j < n; ++j)
        d[j] = fabs(v[j] - centre);
    double scale = fmax(1.4826 * median_small(d, n), RLS_SIGMA_FLOOR_MS);
    *lo = centre - RLS_HAMPEL_K * scale, *hi = centre + RLS_HAMPEL_K * scale;
}

void lod_cost_rls_update(struct lod_cost_rls *c, double measured_ms, double x_ms)
{
    if (!isfinite(measured_ms) || !isfinite(x_ms) || measured_ms <= 0.0 || x_ms < 0.0)
        return;
    /* The error before this frame is fitted: the margin must cover how wrong the prediction was,
     * not how well the fit explains that frame after. Clipped, so a wild frame widens it by 16 %. */
    double line = c->a_ms + c->b * x_ms, e = measured_ms - line;
    c->recent_error_ms[c->recent_next] = e; /* unclipped: the margin must see the late frames as they were */
    c->recent_next = (c->recent_next + 1) % LOD_COST_RLS_WINDOW;
    if (c->recent_count < LOD_COST_RLS_WINDOW)
        ++c->recent_count;
    double clip = fmax(3.0 * sqrt(c->residual_var), RLS_SIGMA_FLOOR_MS);
    double l = c->lambda, e_var = fmin(fmax(e, -clip), clip);
    c->residual_var = l * c->residual_var + (1.0 - l) * e_var * e_var;
    /* What the fit sees: a frame that strays from its neighbours' errors enters at the edge of
     * their band (one preempted frame had shrunk the next frames' budgets enough to drop 22 objects
     * for 6 frames), and never further out than 4σ (at least 2 ms) before there is a band. */
    double lo, hi, fit_clip = fmax(4.0 * sqrt(c->residual_var), 2.0);
    hampel_band(c, &lo, &hi);
    double e_fit = fmin(fmax(fmin(fmax(e, -fit_clip), fit_clip), lo), hi);
    double m = line + e_fit;
    c->s1 = l * c->s1 + 1.0;
    c->sx = l * c->sx + x_ms;
    c->sxx = l * c->sxx + x_ms * x_ms;
    c->sm = l * c->sm + m;
    c->sxm = l * c->sxm + x_ms * m;
    rls_solve(c);
}

/* Hoare's selection: the k-th smallest of v[0 … n−1] (reorders v). O(n) expected. */
static double select_kth(double *v, int n, int k)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        double pivot = v[(lo + hi) / 2];
        int i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot)
                ++i;
            while (v[j] > pivot)
                --j;
            if (i <= j) {
                double t = v[i];
                v[i++] = v[j], v[j--] = t;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break;
    }
    return v[k];
}

/* A share above 97 % is bought only where the tail continues the body — its quantile within
 * RLS_TAIL_RATIO times the 97 % one; else the margin is the 97 % quantile: frames preempted far
 * beyond are late whatever is kept in hand, and a 99 % quantile over a window with a 20 ms
 * preemption every 40 frames would be that preemption (test_lod's half-scale machine). Here the
 * auditorium's errors have their 99 % quantile at 1.1–1.5 times their 97 %. */
double lod_cost_rls_margin_ms(const struct lod_cost_rls *c)
{
    int n = (int)c->recent_count;
    if (n < RLS_QUANTILE_MIN) /* from fewer, a 97–99 % quantile is the largest error: one slow frame */
        return c->spread * sqrt(c->residual_var);
    double v[LOD_COST_RLS_WINDOW];
    memcpy(v, c->recent_error_ms, (size_t)n * sizeof *v);
    double share = c->within_share > 0.5 && c->within_share < 1.0 ? c->within_share : LOD_COST_WITHIN_SHARE_DEFAULT;
    int k = (int)ceil(share * (double)n) - 1;
    double q = select_kth(v, n, k < n ? k : n - 1);
    if (share > RLS_BODY_SHARE) {
        int kb = (int)ceil(RLS_BODY_SHARE * (double)n) - 1;
        double body = select_kth(v, n, kb); /* v as the first selection left it: any order serves */
        if (!(q <= RLS_TAIL_RATIO * body))
            q = body;
    }
    return q > 0.0 ? q : 0.0;
}

static double objects_budget(const struct lod_cost_rls *c, double budget_ms, double margin_ms)
{
    double model = budget_ms - c->c0_ms;
    double fitted = (budget_ms - c->a_ms - margin_ms) / c->b;
    double cap = c->recent_count >= LOD_COST_RLS_LOOSEN_AFTER ? LOD_COST_RLS_LOOSEN_MAX * model : model;
    double x = fitted < cap ? fitted : cap;
    return x > 0.0 ? x : 0.0;
}

double lod_cost_rls_objects_budget_ms(const struct lod_cost_rls *c, double budget_ms)
{
    return objects_budget(c, budget_ms, lod_cost_rls_margin_ms(c));
}

double lod_cost_rls_objects_expected_ms(const struct lod_cost_rls *c, double budget_ms)
{
    return objects_budget(c, budget_ms, 0.0);
}
