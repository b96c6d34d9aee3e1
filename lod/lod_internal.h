/* Internal to lod/: what the optimizers share so that they compare the very same numbers. */
#ifndef HMDLOD_LOD_INTERNAL_H
#define HMDLOD_LOD_INTERNAL_H

#include <float.h>
#include <math.h>

#include "lod/lod.h"

/* A step's value Δbenefit / Δcost, computed in one place (lod_hull_reduce uses the same formula):
 * the greedy, fs and the LP bound order steps by these exact doubles. */
static inline double lod_step_value(double cost_lo, double benefit_lo, double cost_hi, double benefit_hi)
{
    double v = (benefit_hi - benefit_lo) / (cost_hi - cost_lo);
    return isfinite(v) ? v : DBL_MAX;
}
static inline double lod_value_of(const struct lod_problem *p, uint32_t c) /* step c−1 → c */
{
    return lod_step_value(p->cost_ms[c - 1], p->benefit[c - 1], p->cost_ms[c], p->benefit[c]);
}

/* Costs are summed in integer units of 1e−8 ms, each candidate rounded up and the budget down, so
 * "fits" is decided exactly and identically however the sum was reached (incremental or from
 * scratch), and Σ real cost ≤ Σ units ≤ budget. A candidate is clamped at 10 s (1e12 units): a
 * million of them still sum inside int64. */
#define LOD_UNITS_PER_MS 1e8
static inline int64_t lod_cost_units(double cost_ms)
{
    if (cost_ms >= 1e4)
        return (int64_t)1e12;
    double u = cost_ms * LOD_UNITS_PER_MS;
    int64_t k = (int64_t)u;
    return k + (u > (double)k); /* up, and only when there is a remainder: whole costs stay exact */
}
static inline int64_t lod_budget_units(double budget_ms)
{
    if (!(budget_ms > 0.0))
        return 0;
    return budget_ms >= 1e10 ? INT64_MAX / 2 : (int64_t)(budget_ms * LOD_UNITS_PER_MS);
}

/* A step or an object in a sorted order; ties by id, then candidate. */
struct lod_step {
    double value;
    uint32_t id, object, cand;
};
int lod_step_compare_desc(const void *a, const void *b); /* value falling, id and cand rising */
int lod_step_compare_asc(const void *a, const void *b);  /* value rising, id and cand rising */

/* Sets every object with candidates to candidate 0 when its choice is out of range (LOD_DROPPED or
 * stale), marks objects without candidates LOD_DROPPED, and returns Σ units of the choice. */
int64_t lod_choice_sanitize(const struct lod_problem *p, uint8_t *choice, uint32_t *dropped);
/* Over budget with every object at candidate 0: drops objects, lowest benefit per cost of
 * candidate 0 first (ties by object_id), until the rest fits; then re-admits the dropped ones at
 * candidate 0, highest benefit per cost first (ties by object_id), each that still fits, so no
 * dropped object's candidate 0 fits in budget − the returned total. Deterministic in the choice
 * and total given, so greedy and fs, which call it on the same state, stay equal. `order` holds
 * object_count steps. Objects p->keep marks are never dropped (the total may then stay over the
 * budget when they alone exceed it). Returns the new total; *dropped counts what stays dropped. */
int64_t lod_drop_to_fit(const struct lod_problem *p, int64_t total, int64_t budget, uint8_t *choice,
                        struct lod_step *order, uint32_t *dropped);
/* Mason & Blake 1997 §3's guard: the best single upgrade over all-candidate-0 against the choice's
 * benefit; switches the choice to it when it is worth more. Returns 1 when it switched. */
int lod_guard_single_item(const struct lod_problem *p, int64_t budget, uint8_t *choice, double *benefit_inout,
                          int64_t *total_inout);
/* The guard's cheap pre-check: no single upgrade can beat `benefit` when even the largest rise of
 * any one object over all-candidate-0 does not (with a margin for the sums' rounding). */
static inline int lod_guard_may_switch(double base_benefit, double max_gain, double benefit)
{
    return base_benefit + max_gain > benefit - 1e-9 * fabs(benefit);
}
/* Σ benefit and Σ units of a choice, in object order. */
double lod_choice_benefit(const struct lod_problem *p, const uint8_t *choice);

#endif
