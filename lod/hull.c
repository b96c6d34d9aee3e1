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

/* The common case costs one pass: candidates already cheapest first, finite, rising in cost and
 * benefit, with falling step values — nothing to remove. */
static int already_hull(uint32_t base, uint8_t n, const double *cost, const double *benefit)
{
    if (n == 0 || n > LOD_MAX_LEVELS + 1 || !(cost[base] >= 0.0) || !(benefit[base] >= 0.0) ||
        !isfinite(cost[base]) || !isfinite(benefit[base]))
        return 0;
    double last_value = INFINITY;
    for (uint32_t k = base + 1; k < base + n; ++k) {
        if (!(cost[k] > cost[k - 1]) || !(benefit[k] > benefit[k - 1]) || !isfinite(cost[k]) || !isfinite(benefit[k]))
            return 0;
        double v = lod_step_value(cost[k - 1], benefit[k - 1], cost[k], benefit[k]);
        if (!(v < last_value))
            return 0;
        last_value = v;
    }
    return 1;
}

size_t lod_hull_reduce(size_t object_count, const uint32_t *first, uint8_t *count, double *cost_ms,
                       double *benefit, uint8_t *level)
{
    size_t rejected = 0;
    for (size_t i = 0; i < object_count; ++i) {
        uint32_t base = first[i];
        if (already_hull(base, count[i], cost_ms, benefit))
            continue;
        struct cand c[LOD_MAX_LEVELS + 1];
        int n = 0;
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
