/* The from-scratch greedy for the multiple-choice knapsack of one frame (Funkhouser & Séquin 1993 §6,
 * guarded as Mason & Blake 1997 §3). The incremental optimizer (fs.c) must reach the same choice. */
#include <stdint.h>
#include <stdlib.h>

#include "lod/lod_internal.h"

static void *align16(void *p) { return (void *)(((uintptr_t)p + 15u) & ~(uintptr_t)15u); }

void lod_optimize_greedy(const struct lod_problem *p, void *scratch, uint8_t *choice, struct lod_result *r)
{
    int64_t t0 = hl_clock_now_ns();
    struct lod_step *steps = align16(scratch);
    int64_t budget = lod_budget_units(p->budget_ms);
    *r = (struct lod_result){0};

    for (size_t i = 0; i < p->object_count; ++i)
        choice[i] = 0;
    int64_t total = lod_choice_sanitize(p, choice, &r->dropped);
    if (total > budget) {
        r->over_budget = 1;
        total = lod_drop_to_fit(p, total, budget, choice, steps, &r->dropped);
    }

    /* Every step up of every object, by falling value; the hull made each object's steps fall, so
     * an object's steps come in its own order and each taken step is the next one up. */
    size_t n = 0;
    for (size_t i = 0; i < p->object_count; ++i) {
        if (choice[i] == LOD_DROPPED)
            continue;
        for (uint32_t k = 1; k < p->count[i]; ++k)
            steps[n++] = (struct lod_step){lod_value_of(p, p->first[i] + k), p->object_id[i], (uint32_t)i, k};
    }
    qsort(steps, n, sizeof *steps, lod_step_compare_desc);
    for (size_t k = 0; k < n; ++k) {
        uint32_t i = steps[k].object, c = p->first[i] + steps[k].cand;
        if (steps[k].cand != (uint32_t)choice[i] + 1u)
            continue; /* not reachable after a hull reduction; kept for a problem without one */
        int64_t delta = lod_cost_units(p->cost_ms[c]) - lod_cost_units(p->cost_ms[c - 1]);
        if (total + delta > budget)
            break; /* stop at the first step that does not fit (see lod.h) */
        total += delta;
        choice[i] = (uint8_t)steps[k].cand;
        ++r->iterations;
    }

    r->benefit = lod_choice_benefit(p, choice);
    r->single_item = lod_guard_single_item(p, budget, choice, &r->benefit, &total);
    r->cost_ms = (double)total / LOD_UNITS_PER_MS;
    r->elapsed_us = (double)(hl_clock_now_ns() - t0) * 1e-3;
}
