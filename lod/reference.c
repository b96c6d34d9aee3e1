/* Reference solvers for the multiple-choice knapsack problem of one frame (PAPERS.md §2–3), for
 * measurement only: the LP relaxation's optimum (an upper bound on every choice) and an exact
 * dynamic program over integer-scaled cost. Both accept a problem that lod_hull_reduce has not
 * touched, because the point of an exact solver is to find the optimum that may sit under the hull,
 * where the greedy cannot stop; both skip candidates with a non-finite or negative cost or benefit,
 * exactly as lod_hull_reduce drops them. */
#include "lod/lod.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* A usable candidate: what lod_hull_reduce keeps at the least. */
static int candidate_valid(const struct lod_problem *p, uint32_t c)
{
    double cost = p->cost_ms[c], benefit = p->benefit[c];
    return isfinite(cost) && isfinite(benefit) && cost >= 0.0 && benefit >= 0.0;
}

/* Per object the cheapest valid candidate's cost (+INFINITY when it has none). "Cheapest first" is
 * the problem's convention, but a caller's unreduced problem may break it, so this looks. */
static double object_min_cost(const struct lod_problem *p, size_t i)
{
    double best = INFINITY;
    for (uint32_t k = 0; k < p->count[i]; ++k) {
        uint32_t c = p->first[i] + k;
        if (candidate_valid(p, c) && p->cost_ms[c] < best)
            best = p->cost_ms[c];
    }
    return best;
}

/* Σ of the cheapest costs over objects that have a valid candidate: the cost of the choice every
 * optimizer starts from. Decides whether the frame is "fits" or "over budget". */
static double cheapest_total_ms(const struct lod_problem *p)
{
    double total = 0.0;
    for (size_t i = 0; i < p->object_count; ++i) {
        double c = object_min_cost(p, i);
        if (isfinite(c))
            total += c;
    }
    return total;
}

/* ---- LP bound ----------------------------------------------------------------------------------
 * The LP relaxation of the multiple-choice knapsack lets each object mix its candidates; its optimum
 * per object follows the upper concave envelope of the (cost, benefit) points, so the whole LP is
 * solved by taking envelope steps in falling value Δb/Δc until one does not fit, and that one
 * fractionally (Sinha & Zoltners' greedy for the MCKP relaxation). The envelope is walked here per
 * object (gift wrapping over ≤ 255 points), not read from the arrays, so an unreduced problem gets
 * its true LP optimum too. When even the cheapest candidates exceed the budget the optimizers drop
 * objects; the relaxation then gives every object a free null point (0, 0) — "draw nothing" — and
 * is solved from there, which bounds every choice that draws each object once or not at all. */

struct env_point {
    double cost_ms, benefit;
};

/* The envelope's starting point: the cheapest valid candidate with the most benefit at that cost,
 * or the null point in drop mode when it is cheaper or earns more at cost 0. Returns 0 if none. */
static int envelope_start(const struct lod_problem *p, size_t i, int drop_mode, struct env_point *start)
{
    int have = 0;
    if (drop_mode) {
        start->cost_ms = 0.0;
        start->benefit = 0.0;
        have = 1;
    }
    for (uint32_t k = 0; k < p->count[i]; ++k) {
        uint32_t c = p->first[i] + k;
        if (!candidate_valid(p, c))
            continue;
        double cost = p->cost_ms[c], benefit = p->benefit[c];
        if (!have || cost < start->cost_ms || (cost == start->cost_ms && benefit > start->benefit)) {
            start->cost_ms = cost;
            start->benefit = benefit;
            have = 1;
        }
    }
    return have;
}

/* The next envelope step from `cur`: the point of greatest slope among those costing more and
 * earning more (equal slopes: the farthest, so collinear points merge and values fall strictly).
 * Writes the step's Δcost, Δbenefit, moves cur; returns 0 when the envelope has reached its top. */
static int envelope_next(const struct lod_problem *p, size_t i, struct env_point *cur, double *dcost_ms,
                         double *dbenefit)
{
    int found = 0;
    double best_dc = 0.0, best_db = 0.0;
    for (uint32_t k = 0; k < p->count[i]; ++k) {
        uint32_t c = p->first[i] + k;
        if (!candidate_valid(p, c))
            continue;
        double dc = p->cost_ms[c] - cur->cost_ms, db = p->benefit[c] - cur->benefit;
        if (!(dc > 0.0 && db > 0.0))
            continue;
        /* Compare slopes db/dc against best_db/best_dc by cross-multiplying: no division, and exact
         * ties are recognised as ties. */
        double lhs = db * best_dc, rhs = best_db * dc;
        if (!found || lhs > rhs || (lhs == rhs && dc > best_dc)) {
            best_dc = dc;
            best_db = db;
            found = 1;
        }
    }
    if (!found)
        return 0;
    cur->cost_ms += best_dc;
    cur->benefit += best_db;
    *dcost_ms = best_dc;
    *dbenefit = best_db;
    return 1;
}

/* Orders positive doubles (and +INFINITY) like their IEEE-754 bit patterns read as integers. */
static uint64_t value_key(double value)
{
    uint64_t key;
    memcpy(&key, &value, sizeof key);
    return key;
}

/* Radix selection over the steps' value keys instead of a sort: up to 8 passes of one byte each, from
 * the most significant, find the value λ at which the steps' cumulative cost (in falling value)
 * first exceeds the remaining budget. A pass whose chosen bucket holds a single value ends it (3
 * passes on distinct random values; values that differ only in their last bits need all 8). This needs no memory beyond 256 buckets on the stack, so the bound
 * works with any scratch (or none) and on any number of objects, in O(passes · Σ k²) for k candidates
 * per object. Ties between steps of equal value need no order: whichever is split, the LP earns λ
 * per millisecond of what is left. */
double lod_lp_bound(const struct lod_problem *p, void *scratch)
{
    (void)scratch;
    if (!(p->budget_ms >= 0.0))
        return 0.0; /* NaN or negative budget: no choice is feasible; nothing to bound */
    double cheapest_ms = cheapest_total_ms(p);
    int drop_mode = cheapest_ms > p->budget_ms;

    /* The starting choice: every object at its envelope start. */
    double base_benefit = 0.0, base_cost_ms = 0.0;
    for (size_t i = 0; i < p->object_count; ++i) {
        struct env_point s;
        if (envelope_start(p, i, drop_mode, &s)) {
            base_benefit += s.benefit;
            base_cost_ms += s.cost_ms;
        }
    }
    double remaining_ms = p->budget_ms - base_cost_ms;
    if (remaining_ms < 0.0)
        remaining_ms = 0.0; /* rounding only: drop mode starts at 0, fit mode at ≤ budget */

    uint64_t prefix = 0;           /* selected high bytes of λ's key */
    double above_cost_ms = 0.0;    /* steps with a key greater than every key under the prefix */
    double above_benefit = 0.0;
    double total_cost_ms = 0.0, total_benefit = 0.0;
    for (int pass = 0; pass < 8; ++pass) {
        int shift = 56 - 8 * pass;
        double bucket_cost[256] = {0}, bucket_benefit[256] = {0};
        double bucket_lo[256], bucket_hi[256]; /* value range: one value left ends the search */
        uint32_t bucket_steps[256] = {0};
        for (size_t i = 0; i < p->object_count; ++i) {
            struct env_point cur;
            if (!envelope_start(p, i, drop_mode, &cur))
                continue;
            double dc, db;
            while (envelope_next(p, i, &cur, &dc, &db)) {
                double value = db / dc;
                uint64_t key = value_key(value);
                if (pass > 0 && (key >> (shift + 8)) != (prefix >> (shift + 8)))
                    continue;
                unsigned b = (unsigned)((key >> shift) & 0xffu);
                bucket_cost[b] += dc;
                bucket_benefit[b] += db;
                if (bucket_steps[b]++ == 0)
                    bucket_lo[b] = bucket_hi[b] = value;
                bucket_lo[b] = fmin(bucket_lo[b], value);
                bucket_hi[b] = fmax(bucket_hi[b], value);
                if (pass == 0) {
                    total_cost_ms += dc;
                    total_benefit += db;
                }
            }
        }
        if (pass == 0 && total_cost_ms <= remaining_ms)
            return base_benefit + total_benefit; /* every step fits: the finest envelope point each */
        int lowest = -1;
        for (int b = 0; b < 256; ++b)
            if (bucket_steps[b]) {
                lowest = b;
                break;
            }
        if (lowest < 0)
            break; /* cannot happen: the previous pass chose a non-empty bucket */
        /* From the highest byte down: the first bucket that crosses the budget holds λ. A later pass
         * re-sums a bucket in another order, so rounding may make none cross; then the lowest
         * non-empty one is taken, which the previous pass said crosses. */
        int chosen = lowest;
        for (int b = 255; b >= lowest; --b) {
            if (!bucket_steps[b])
                continue;
            if (b == lowest || above_cost_ms + bucket_cost[b] > remaining_ms) {
                chosen = b;
                break;
            }
            above_cost_ms += bucket_cost[b];
            above_benefit += bucket_benefit[b];
        }
        prefix |= (uint64_t)chosen << shift;
        if (bucket_lo[chosen] == bucket_hi[chosen]) { /* one value (usually one step) left: λ */
            prefix = value_key(bucket_lo[chosen]);
            break;
        }
    }
    double lambda;
    memcpy(&lambda, &prefix, sizeof lambda);
    double split_ms = remaining_ms - above_cost_ms;
    if (split_ms < 0.0)
        split_ms = 0.0;
    return base_benefit + above_benefit + lambda * split_ms;
}

/* ---- exact dynamic program ---------------------------------------------------------------------
 * Costs become whole quanta rounded UP and the budget whole quanta rounded DOWN, so any choice the
 * program accepts fits the real budget: Σ cost ≤ Σ ⌈cost/q⌉·q ≤ ⌊budget/q⌋·q ≤ budget. The result
 * is the optimum over the choices whose rounded cost fits — the true optimum whenever its own
 * rounded cost fits, in particular when every cost is a multiple of q; in general it is at least the
 * true optimum for the budget budget − n·q (n objects each lose under one quantum). */

/* ⌈x/q⌉ with the quotient's rounding corrected in the conservative direction: units·q ≥ x holds
 * in the same double arithmetic the caller checks feasibility in, and units − 1 would not do.
 * Returns UINT64_MAX when the quotient does not fit in 2^53 (never fits any budget). */
static uint64_t quanta_up(double x, double q)
{
    double r = ceil(x / q);
    if (!(r < 9007199254740992.0))
        return UINT64_MAX;
    uint64_t u = (uint64_t)r;
    while ((double)u * q < x)
        ++u;
    while (u > 0 && (double)(u - 1) * q >= x)
        --u;
    return u;
}

/* ⌊budget/q⌋ corrected the other way: units·q ≤ budget. UINT64_MAX when it does not fit 2^53. */
static uint64_t quanta_down(double budget, double q)
{
    double r = floor(budget / q);
    if (!(r < 9007199254740992.0))
        return UINT64_MAX;
    uint64_t u = (uint64_t)r;
    while (u > 0 && (double)u * q > budget)
        --u;
    while ((double)(u + 1) * q <= budget)
        ++u;
    return u;
}

/* Budget quanta W, or UINT64_MAX when the arguments are unusable. */
static uint64_t exact_budget_units(const struct lod_problem *p, double q)
{
    if (!(q > 0.0) || !isfinite(q) || !(p->budget_ms >= 0.0) || !isfinite(p->budget_ms))
        return UINT64_MAX;
    return quanta_down(p->budget_ms, q);
}

size_t lod_solve_exact_bytes(const struct lod_problem *p, double cost_quantum_ms)
{
    uint64_t w = exact_budget_units(p, cost_quantum_ms);
    if (w == UINT64_MAX || w >= SIZE_MAX / 32)
        return 0;
    size_t columns = (size_t)w + 1;
    /* two rows of doubles, then one byte per object and budget unit for the backtrack */
    size_t per_object = columns;
    if (p->object_count > (SIZE_MAX - 2 * columns * sizeof(double)) / per_object)
        return 0;
    return 2 * columns * sizeof(double) + p->object_count * per_object;
}

/* Row update for one object: best[w] = max over its candidates of prev[w − u] + b (and prev[w] when
 * it may be dropped). "Value at most w" rows, so prev is non-decreasing in w and the answer sits at
 * W. Ties keep the first found — candidates in index order, then the null option — so the result
 * is a function of the input alone. −INFINITY marks "no choice of the objects so far fits in w". */
static void exact_row(const struct lod_problem *p, size_t i, double q, int may_drop, size_t columns,
                      const double *prev, double *best, uint8_t *pick)
{
    for (size_t w = 0; w < columns; ++w) {
        best[w] = -INFINITY;
        pick[w] = LOD_DROPPED;
    }
    for (uint32_t k = 0; k < p->count[i]; ++k) {
        uint32_t c = p->first[i] + k;
        if (!candidate_valid(p, c))
            continue;
        uint64_t u = quanta_up(p->cost_ms[c], q);
        if (u >= columns)
            continue;
        double b = p->benefit[c];
        for (size_t w = (size_t)u; w < columns; ++w) {
            double v = prev[w - (size_t)u] + b;
            if (v > best[w]) {
                best[w] = v;
                pick[w] = (uint8_t)k;
            }
        }
    }
    if (may_drop)
        for (size_t w = 0; w < columns; ++w)
            if (prev[w] > best[w]) {
                best[w] = prev[w];
                pick[w] = LOD_DROPPED;
            }
}

int lod_solve_exact(const struct lod_problem *p, double cost_quantum_ms, void *work, size_t work_bytes,
                    uint8_t *choice, double *benefit_out)
{
    double q = cost_quantum_ms;
    uint64_t w_units = exact_budget_units(p, q);
    if (w_units == UINT64_MAX)
        return -3;
    size_t need = lod_solve_exact_bytes(p, q);
    if (need == 0 || work == NULL || work_bytes < need || ((uintptr_t)work % sizeof(double)) != 0)
        return -1;
    size_t columns = (size_t)w_units + 1;
    double *prev = (double *)work;
    double *best = prev + columns;
    uint8_t *picks = (uint8_t *)(best + columns);

    /* As the optimizers do: objects are dropped only when the cheapest candidates cannot all fit in
     * the real budget; otherwise every object with a valid candidate is drawn. */
    int drop_mode = cheapest_total_ms(p) > p->budget_ms;
    for (size_t w = 0; w < columns; ++w)
        prev[w] = 0.0;
    for (size_t i = 0; i < p->object_count; ++i) {
        uint8_t *pick = picks + i * columns;
        int has_valid = 0;
        for (uint32_t k = 0; k < p->count[i] && !has_valid; ++k)
            has_valid = candidate_valid(p, p->first[i] + k);
        if (!has_valid) {
            memset(pick, LOD_DROPPED, columns); /* nothing drawable: dropped, costs nothing */
            continue;
        }
        exact_row(p, i, q, drop_mode, columns, prev, best, pick);
        double *t = prev;
        prev = best;
        best = t;
    }
    if (!(prev[columns - 1] > -INFINITY))
        return -2; /* the cheapest candidates fit in real cost but not once rounded up to quanta */

    double benefit = 0.0;
    size_t w = columns - 1;
    for (size_t i = p->object_count; i-- > 0;) {
        uint8_t k = picks[i * columns + w];
        choice[i] = k;
        if (k != LOD_DROPPED) {
            uint32_t c = p->first[i] + k;
            w -= (size_t)quanta_up(p->cost_ms[c], q);
        }
    }
    for (size_t i = 0; i < p->object_count; ++i)
        if (choice[i] != LOD_DROPPED)
            benefit += p->benefit[p->first[i] + choice[i]];
    if (benefit_out)
        *benefit_out = benefit;
    return drop_mode ? 1 : 0;
}

/* ---- the layer choice (lod.h) ---------------------------------------------------------------------- */

size_t lod_solve_exact_settings_bytes(const struct lod_problem *problems, size_t count, double cost_quantum_ms)
{
    size_t most = 0;
    for (size_t k = 0; k < count; ++k) {
        size_t b = lod_solve_exact_bytes(&problems[k], cost_quantum_ms);
        if (b == 0)
            return 0;
        most = b > most ? b : most;
    }
    return most;
}

int lod_solve_exact_settings(const struct lod_problem *problems, size_t count, double cost_quantum_ms, void *work,
                             size_t work_bytes, uint8_t *choice, size_t *setting_out, double *benefit_out)
{
    if (!problems || count == 0)
        return -3;
    size_t best = 0;
    int best_rc = 2;
    double best_benefit = -INFINITY;
    for (size_t k = 0; k < count; ++k) {
        double benefit = 0.0;
        int rc = lod_solve_exact(&problems[k], cost_quantum_ms, work, work_bytes, choice, &benefit);
        if (rc < 0)
            return rc;
        if (rc < best_rc || (rc == best_rc && benefit > best_benefit))
            best = k, best_rc = rc, best_benefit = benefit;
    }
    /* The winner's choice again (deterministic): the loop left the last setting's in choice. */
    int rc = lod_solve_exact(&problems[best], cost_quantum_ms, work, work_bytes, choice, benefit_out);
    if (setting_out)
        *setting_out = best;
    return rc;
}

double lod_lp_bound_settings(const struct lod_problem *problems, size_t count)
{
    double bound = 0.0;
    for (size_t k = 0; k < count; ++k) {
        double b = lod_lp_bound(&problems[k], NULL);
        bound = b > bound ? b : bound;
    }
    return bound;
}
