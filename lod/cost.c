/* The cost model's arithmetic (Funkhouser & Séquin 1993 §4) and its online correction. The
 * coefficients are measured per machine by render/ (`hmdlod calibrate`). */
#include <math.h>

#include "lod/lod.h"

double lod_cost_object_ms(const struct lod_cost_model *m, double triangles, double vertices, double pixels,
                          double draws)
{
    double geometry_ms = m->c1_ms_per_triangle * triangles + m->c2_ms_per_vertex * vertices;
    double fill_ms = m->c3_ms_per_pixel * pixels;
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
