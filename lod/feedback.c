/* The `feedback` selector's controller (Funkhouser & Séquin 1993 §7; shaped like the adaptive quality
 * of shipping VR runtimes, PAPERS.md §5): the static threshold steered by measured frame times. */
#include <math.h>

#include "lod/lod.h"

static const double step_factor = 1.15; /* one quality step ≈ ±15 % of the triangles */

void lod_feedback_init(struct lod_feedback *f, double start_px_per_triangle)
{
    f->min_px_per_triangle = start_px_per_triangle > 0.0 ? start_px_per_triangle : 1.0;
    f->lowest_px = 0.01;
    f->highest_px = 1e6;
    f->last_ms = 0.0;
    f->frames_high = 0;
    f->frames_cheap = 0;
}

/* A larger threshold means coarser levels: dropping quality multiplies it. */
static void shift(struct lod_feedback *f, int steps_coarser)
{
    f->min_px_per_triangle *= pow(step_factor, steps_coarser);
    f->min_px_per_triangle = fmin(fmax(f->min_px_per_triangle, f->lowest_px), f->highest_px);
}

void lod_feedback_update(struct lod_feedback *f, double measured_ms, double budget_ms)
{
    if (!isfinite(measured_ms) || !(budget_ms > 0.0))
        return;
    double load = measured_ms / budget_ms;
    /* Linear extrapolation of the last two frames: act before the budget is broken. */
    double predicted = f->last_ms > 0.0 ? (2.0 * measured_ms - f->last_ms) / budget_ms : load;
    f->last_ms = measured_ms;
    f->frames_high = load > 0.85 ? f->frames_high + 1 : 0;
    f->frames_cheap = load < 0.70 ? f->frames_cheap + 1 : 0;
    if (load > 0.90 || predicted > 1.0) {
        shift(f, 2); /* drop fast */
        f->frames_high = 0;
    } else if (f->frames_high >= 3) {
        shift(f, 1);
        f->frames_high = 0;
    } else if (f->frames_cheap >= 12) {
        shift(f, -2); /* climb slowly */
        f->frames_cheap = 0;
    } else if (f->frames_cheap == 6) {
        shift(f, -1);
    }
}
