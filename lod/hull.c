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

static int valid(double cost, double benefit)
{
    return isfinite(cost) && isfinite(benefit) && cost >= 0.0 && benefit >= 0.0;
}

/* The common case costs one pass: candidates already cheapest first, finite, rising in cost and
 * benefit, with falling step values — nothing to remove. */
static int already_hull(uint32_t base, uint8_t n, const double *cost, const double *benefit)
{
    if (n == 0 || n > LOD_MAX_LEVELS + 1 || !valid(cost[base], benefit[base]))
        return 0;
    double last_value = INFINITY;
    for (uint32_t k = base + 1; k < base + n; ++k) {
        if (!valid(cost[k], benefit[k]) || !(cost[k] > cost[k - 1]) || !(benefit[k] > benefit[k - 1]))
            return 0;
        double v = lod_step_value(cost[k - 1], benefit[k - 1], cost[k], benefit[k]);
        if (!(v < last_value))
            return 0;
        last_value = v;
    }
    return 1;
}

/* Σ over the objects of their cheapest valid candidate, in the optimizers' exact units. */
static int64_t cheapest_total(size_t object_count, const uint32_t *first, const uint8_t *count,
                              const double *cost_ms, const double *benefit, int64_t *cheapest)
{
    int64_t total = 0;
    for (size_t i = 0; i < object_count; ++i) {
        int64_t best = INT64_MAX;
        for (uint32_t k = first[i]; k < first[i] + count[i]; ++k) {
            int64_t units = valid(cost_ms[k], benefit[k]) ? lod_cost_units(cost_ms[k]) : INT64_MAX;
            best = units < best ? units : best;
        }
        cheapest[i] = best;
        total += best == INT64_MAX ? 0 : best;
    }
    return total;
}

size_t lod_hull_reduce(size_t object_count, const uint32_t *first, uint8_t *count, double *cost_ms,
                       double *benefit, uint8_t *level, double budget_ms, int64_t *scratch)
{
    size_t rejected = 0;
    int64_t budget = isfinite(budget_ms) ? lod_budget_units(budget_ms) : INT64_MAX;
    int64_t base = budget == INT64_MAX ? 0 : cheapest_total(object_count, first, count, cost_ms, benefit, scratch);
    if (base > budget)
        budget = INT64_MAX; /* over budget: dropping objects frees room, so no candidate is hopeless */
    for (size_t i = 0; i < object_count; ++i) {
        /* A candidate that cannot fit even with every other object at its cheapest can never be
         * chosen: removing it before the hull keeps the fitting candidates it would have shadowed,
         * and keeps the greedy from stopping at a step that can never fit (which would break its
         * half-optimality). The cheapest candidate always stays. */
        int64_t cap = budget == INT64_MAX || scratch[i] == INT64_MAX ? INT64_MAX : budget - (base - scratch[i]);
        uint32_t base_c = first[i];
        if (already_hull(base_c, count[i], cost_ms, benefit) &&
            (cap == INT64_MAX || lod_cost_units(cost_ms[base_c + count[i] - 1]) <= cap))
            continue;
        struct cand c[LOD_MAX_LEVELS + 1];
        int n = 0;
        for (uint32_t k = base_c; k < base_c + count[i] && n < LOD_MAX_LEVELS + 1; ++k) {
            if (!valid(cost_ms[k], benefit[k])) {
                ++rejected;
                continue;
            }
            if (cap != INT64_MAX && lod_cost_units(cost_ms[k]) > cap && lod_cost_units(cost_ms[k]) > scratch[i])
                continue; /* can never fit (not counted: it is valid) */
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
            cost_ms[base_c + k] = c[k].cost;
            benefit[base_c + k] = c[k].benefit;
            level[base_c + k] = c[k].level;
        }
        count[i] = (uint8_t)top;
    }
    return rejected;
}
