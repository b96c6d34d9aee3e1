/* Per-object candidate reduction to the upper convex hull of (cost, benefit). The greedy of
 * Funkhouser & Séquin (1993 §6) and Mason & Blake (1997 §3) take steps in falling value
 * Δbenefit/Δcost; that order is only consistent within an object when its values fall as detail
 * rises (diminishing returns). The hull makes them fall; what it removes the greedy would skip. */
#include "lod/lod_internal.h"


struct cand {
    double cost, benefit;
    uint8_t level;
};

/* Cheaper first; at equal cost the more beneficial, then the coarser (LOD_DROP counts coarsest). */
static int cand_before(const struct cand *a, const struct cand *b)
{
    if (a->cost != b->cost)
        return a->cost < b->cost;
    if (a->benefit != b->benefit)
        return a->benefit > b->benefit;
    return a->level > b->level;
}

size_t lod_hull_reduce(size_t object_count, const uint32_t *first, uint8_t *count, double *cost_ms,
                       double *benefit, uint8_t *level)
{
    size_t rejected = 0;
    for (size_t i = 0; i < object_count; ++i) {
        struct cand c[LOD_MAX_LEVELS + 1];
        int n = 0;
        uint32_t base = first[i];
        for (uint32_t k = base; k < base + count[i] && n < LOD_MAX_LEVELS + 1; ++k) {
            if (!isfinite(cost_ms[k]) || !isfinite(benefit[k]) || cost_ms[k] < 0.0 || benefit[k] < 0.0) {
                ++rejected;
                continue;
            }
            struct cand x = {cost_ms[k], benefit[k], level[k]};
            int j = n++;
            while (j > 0 && cand_before(&x, &c[j - 1])) { /* insertion sort: ≤ 9 items */
                c[j] = c[j - 1];
                --j;
            }
            c[j] = x;
        }
        /* Stack of hull points: benefit and cost rise strictly, and each new step is worth less
         * per millisecond than the one before (compared with lod_step_value itself). */
        int top = 0;
        for (int k = 0; k < n; ++k) {
            if (top > 0 && (c[k].benefit <= c[top - 1].benefit || c[k].cost <= c[top - 1].cost))
                continue; /* dominated: costs as much or more, earns no more */
            while (top >= 2 && lod_step_value(c[top - 2].cost, c[top - 2].benefit, c[top - 1].cost, c[top - 1].benefit) <=
                                   lod_step_value(c[top - 1].cost, c[top - 1].benefit, c[k].cost, c[k].benefit))
                --top;
            c[top++] = c[k];
        }
        for (int k = 0; k < top; ++k) {
            cost_ms[base + k] = c[k].cost;
            benefit[base + k] = c[k].benefit;
            level[base + k] = c[k].level;
        }
        count[i] = (uint8_t)top;
    }
    return rejected;
}
