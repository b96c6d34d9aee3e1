/* What the optimizers share: sanitising a starting choice, dropping objects when even the cheapest
 * representation of everything cannot fit, and the single-item guard. */
#include <stdlib.h>

#include "lod/lod_internal.h"

static int compare(const struct lod_step *x, const struct lod_step *y)
{
    if (x->value != y->value)
        return x->value < y->value ? -1 : 1;
    if (x->id != y->id)
        return x->id < y->id ? -1 : 1;
    return (x->cand > y->cand) - (x->cand < y->cand);
}

int lod_step_compare_asc(const void *a, const void *b) { return compare(a, b); }

int lod_step_compare_desc(const void *a, const void *b)
{
    const struct lod_step *x = a, *y = b;
    if (x->value != y->value)
        return x->value > y->value ? -1 : 1;
    if (x->id != y->id)
        return x->id < y->id ? -1 : 1;
    return (x->cand > y->cand) - (x->cand < y->cand);
}

int64_t lod_choice_sanitize(const struct lod_problem *p, uint8_t *choice, uint32_t *dropped)
{
    int64_t total = 0;
    uint32_t none = 0;
    for (size_t i = 0; i < p->object_count; ++i) {
        if (p->count[i] == 0) {
            choice[i] = LOD_DROPPED;
            ++none;
            continue;
        }
        if (choice[i] >= p->count[i])
            choice[i] = 0;
        total += lod_cost_units(p->cost_ms[p->first[i] + choice[i]]);
    }
    *dropped = none;
    return total;
}

void lod_choice_start(const struct lod_problem *p, const uint8_t *previous_level, uint8_t *choice)
{
    for (size_t i = 0; i < p->object_count; ++i) {
        uint8_t pick = 0;
        uint8_t prev = previous_level[i];
        if (prev != LOD_UNSEEN) {
            /* Candidates are cheapest first, i.e. coarsest first: the last whose level is at
             * least as coarse as the previous one (LOD_DROP is the coarsest of all). */
            for (uint8_t k = 0; k < p->count[i]; ++k) {
                uint8_t lv = p->level[p->first[i] + k];
                if (lv >= prev)
                    pick = k;
            }
        }
        choice[i] = pick;
    }
}

int64_t lod_drop_to_fit(const struct lod_problem *p, int64_t total, int64_t budget, uint8_t *choice,
                        struct lod_step *order, uint32_t *dropped)
{
    size_t n = 0;
    for (size_t i = 0; i < p->object_count; ++i) {
        if (choice[i] == LOD_DROPPED || (p->keep && p->keep[i]))
            continue; /* kept objects are not candidates for dropping */
        uint32_t c = p->first[i];
        double cost = p->cost_ms[c];
        order[n].value = cost > 0.0 ? p->benefit[c] / cost : DBL_MAX; /* free objects are never dropped */
        order[n].id = p->object_id[i];
        order[n].object = (uint32_t)i;
        order[n].cand = 0;
        ++n;
    }
    qsort(order, n, sizeof *order, lod_step_compare_asc);
    size_t gone = 0;
    for (; gone < n && total > budget; ++gone) {
        uint32_t i = order[gone].object;
        total -= lod_cost_units(p->cost_ms[p->first[i] + choice[i]]);
        choice[i] = LOD_DROPPED;
        ++*dropped;
    }
    /* Drops are the last resort (issue 30): the last object dropped may be a large one that leaves
     * most of the budget unused, while smaller objects dropped before it would fit in what is left.
     * Those come back at candidate 0, highest benefit per cost first (ties by object_id), each one
     * that still fits — a first-fit pass, not a stop at the first misfit, so no dropped object's
     * candidate 0 fits in budget − total afterwards. With "no polygons" levels Funkhouser & Séquin
     * (1993 §3) render only the most valuable objects when not all fit, not fewer than the budget
     * holds; and the greedy draws every object it keeps at its cheapest before any step up, which
     * this extends to the objects the budget can still hold. Later steps only raise the total
     * (candidate 0 is each object's cheapest), so the property holds for the final choice too. */
    qsort(order, gone, sizeof *order, lod_step_compare_desc);
    for (size_t k = 0; k < gone; ++k) {
        uint32_t i = order[k].object;
        int64_t units = lod_cost_units(p->cost_ms[p->first[i]]);
        if (total + units > budget)
            continue;
        total += units;
        choice[i] = 0;
        --*dropped;
    }
    return total;
}

int lod_choice_underused_drop(const struct lod_problem *p, const uint8_t *choice, double fraction)
{
    int64_t budget = lod_budget_units(p->budget_ms), total = 0, smallest = INT64_MAX;
    for (size_t i = 0; i < p->object_count; ++i) {
        if (p->count[i] == 0)
            continue; /* nothing it could draw: not a drop the budget decides */
        if (choice[i] == LOD_DROPPED) {
            int64_t units = lod_cost_units(p->cost_ms[p->first[i]]);
            smallest = units < smallest ? units : smallest;
        } else if (choice[i] < p->count[i]) {
            total += lod_cost_units(p->cost_ms[p->first[i] + choice[i]]);
        }
    }
    if (smallest == INT64_MAX || !((double)total < fraction * (double)budget))
        return 0;
    return total <= budget && smallest <= budget - total;
}

double lod_choice_benefit(const struct lod_problem *p, const uint8_t *choice)
{
    double sum = 0.0;
    for (size_t i = 0; i < p->object_count; ++i)
        if (choice[i] != LOD_DROPPED)
            sum += p->benefit[p->first[i] + choice[i]];
    return sum;
}

/* The greedy alone can be arbitrarily bad: many small high-value steps fill the budget that one
 * large step would have used far better. The better of the greedy and the best single upgrade is
 * at least half the optimum (Mason & Blake 1997 §3). */
int lod_guard_single_item(const struct lod_problem *p, int64_t budget, uint8_t *choice, double *benefit_inout,
                          int64_t *total_inout)
{
    int64_t base_total = 0;
    double base_benefit = 0.0;
    for (size_t i = 0; i < p->object_count; ++i) {
        if (choice[i] == LOD_DROPPED)
            continue;
        base_total += lod_cost_units(p->cost_ms[p->first[i]]);
        base_benefit += p->benefit[p->first[i]];
    }
    double best_gain = 0.0;
    size_t best_object = SIZE_MAX;
    uint8_t best_cand = 0;
    for (size_t i = 0; i < p->object_count; ++i) {
        if (choice[i] == LOD_DROPPED || p->count[i] < 2)
            continue;
        uint32_t c0 = p->first[i];
        int64_t rest = base_total - lod_cost_units(p->cost_ms[c0]);
        for (int k = p->count[i] - 1; k >= 1; --k) { /* benefit rises with k: the first that fits */
            if (rest + lod_cost_units(p->cost_ms[c0 + k]) <= budget) {
                double gain = p->benefit[c0 + k] - p->benefit[c0];
                if (gain > best_gain) {
                    best_gain = gain;
                    best_object = i;
                    best_cand = (uint8_t)k;
                }
                break;
            }
        }
    }
    if (best_object == SIZE_MAX || !(base_benefit + best_gain > *benefit_inout))
        return 0;
    for (size_t i = 0; i < p->object_count; ++i)
        if (choice[i] != LOD_DROPPED)
            choice[i] = 0;
    choice[best_object] = best_cand;
    *benefit_inout = lod_choice_benefit(p, choice);
    *total_inout = base_total - lod_cost_units(p->cost_ms[p->first[best_object]]) +
                   lod_cost_units(p->cost_ms[p->first[best_object] + best_cand]);
    return 1;
}

void lod_level_of_choice(const struct lod_problem *p, const uint8_t *choice, uint8_t *level_out)
{
    for (size_t i = 0; i < p->object_count; ++i)
        level_out[i] = choice[i] == LOD_DROPPED ? LOD_DROP : p->level[p->first[i] + choice[i]];
}

size_t lod_scratch_bytes(size_t max_objects, size_t max_candidates)
{
    size_t greedy = (max_candidates + max_objects) * sizeof(struct lod_step);
    size_t fs = max_objects * (2 * 16 + 2 * sizeof(uint32_t) + sizeof(struct lod_step)); /* heaps, slots, order */
    return (greedy > fs ? greedy : fs) + 128;
}
