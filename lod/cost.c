/* The cost model's arithmetic (Funkhouser & Séquin 1993 §4) and its online correction. The
 * coefficients are measured per machine by render/ (`hmdlod calibrate`). */
#include <math.h>

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

/* ---- affine correction (recursive least squares with forgetting) --------------------------------- */
#define RLS_P_A 4.0    /* start: a within ±2 ms of c0 (what the frame costs besides its objects
                        * varies most between machines and loads) …  */
#define RLS_P_B 0.0625 /* … b within ±0.25 of 1 (calibrate fits the per-object terms to ~13 %) */

void lod_cost_rls_init(struct lod_cost_rls *c, double c0_ms, double lambda)
{
    c->c0_ms = isfinite(c0_ms) && c0_ms >= 0.0 ? c0_ms : 0.0;
    c->a_ms = c->c0_ms, c->b = 1.0;
    c->p00 = RLS_P_A, c->p01 = 0.0, c->p11 = RLS_P_B;
    c->residual_var = 0.0;
    c->lambda = lambda > 0.5 && lambda <= 1.0 ? lambda : 0.98;
    c->spread = 2.0;
}

void lod_cost_rls_update(struct lod_cost_rls *c, double measured_ms, double x_ms)
{
    if (!isfinite(measured_ms) || !isfinite(x_ms) || measured_ms <= 0.0 || x_ms < 0.0)
        return;
    double e = measured_ms - (c->a_ms + c->b * x_ms); /* a-priori error */
    /* The residual's spread, smoothed over about 1 / (1 − λ) frames, before the update: the margin
     * must cover how wrong the prediction was, not how well the fit explains that frame after. */
    double w = 1.0 - c->lambda;
    c->residual_var = (1.0 - w) * (c->residual_var + w * e * e);
    double g0 = c->p00 + c->p01 * x_ms, g1 = c->p01 + c->p11 * x_ms; /* P·φ, φ = (1, x) */
    double denom = c->lambda + g0 + g1 * x_ms;
    double k0 = g0 / denom, k1 = g1 / denom;
    c->a_ms += k0 * e;
    c->b += k1 * e;
    c->p00 = (c->p00 - k0 * g0) / c->lambda;
    c->p01 = (c->p01 - k0 * g1) / c->lambda;
    c->p11 = (c->p11 - k1 * g1) / c->lambda;
    /* No wind-up: a direction no frame excites would grow as λ^−n; cap the covariance at its start. */
    double scale = fmax(c->p00 / RLS_P_A, c->p11 / RLS_P_B);
    if (scale > 1.0)
        c->p00 /= scale, c->p01 /= scale, c->p11 /= scale;
    /* One wild frame (a page fault, a preempted thread) must not make the model absurd. */
    c->b = fmin(fmax(c->b, 0.25), 4.0);
    c->a_ms = fmin(fmax(c->a_ms, 0.0), 4.0 * c->c0_ms + 10.0);
}

double lod_cost_rls_objects_budget_ms(const struct lod_cost_rls *c, double budget_ms)
{
    double model = budget_ms - c->c0_ms;
    double fitted = (budget_ms - c->a_ms - c->spread * sqrt(c->residual_var)) / c->b;
    double x = fitted < model ? fitted : model; /* only ever tightens */
    return x > 0.0 ? x : 0.0;
}
