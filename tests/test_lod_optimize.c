/* lod/: the reference solvers (exact dynamic program, LP bound) checked against brute force and,
 * with the argument `glpsol`, against GLPK's glpsol run on written models; and the guarantees the
 * cost-bounded optimizers promise (PAPERS.md §2–4): within budget or an explicit over-budget
 * outcome, at least half of the exact optimum (Mason & Blake's guard, with the counterexample to the
 * plain greedy), identical output for identical input whatever the memory order, the incremental
 * optimizer equal to the from-scratch greedy, a time limit that leaves a feasible complete choice,
 * and the hull reduction they all rely on. Instances come from a seeded generator. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lod/lod.h"
#include "test_util.h"

/* ---- instances ---------------------------------------------------------------------------------- */

static uint64_t rng_state;
static uint64_t rng_next(void)
{ /* splitmix64: tiny, seeded, the same sequence on every machine */
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
static double rng_unit(void) { return (double)(rng_next() >> 11) * 0x1.0p-53; }
static int rng_int(int lo, int hi) { return lo + (int)(rng_next() % (uint64_t)(hi - lo + 1)); }

/* One frame's candidates in owned arrays; problem() views them as a struct lod_problem. */
struct inst {
    size_t n, cap;
    uint32_t *object_id, *first;
    uint8_t *count, *level;
    double *cost_ms, *benefit;
    double budget_ms;
};

static struct inst inst_new(size_t n, size_t max_per_object)
{
    struct inst in = {.n = n, .cap = n * max_per_object};
    in.object_id = calloc(n, sizeof *in.object_id);
    in.first = calloc(n, sizeof *in.first);
    in.count = calloc(n, 1);
    in.level = calloc(in.cap + 1, 1);
    in.cost_ms = calloc(in.cap + 1, sizeof(double));
    in.benefit = calloc(in.cap + 1, sizeof(double));
    for (size_t i = 0; i < n; ++i) {
        in.object_id[i] = (uint32_t)(1000 + 7 * i);
        in.first[i] = (uint32_t)(i * max_per_object);
    }
    return in;
}

static void inst_free(struct inst *in)
{
    free(in->object_id);
    free(in->first);
    free(in->count);
    free(in->level);
    free(in->cost_ms);
    free(in->benefit);
}

static struct inst inst_copy(const struct inst *a)
{
    struct inst b = *a;
    b.object_id = malloc(a->n * sizeof *b.object_id);
    b.first = malloc(a->n * sizeof *b.first);
    b.count = malloc(a->n);
    b.level = malloc(a->cap + 1);
    b.cost_ms = malloc((a->cap + 1) * sizeof(double));
    b.benefit = malloc((a->cap + 1) * sizeof(double));
    memcpy(b.object_id, a->object_id, a->n * sizeof *b.object_id);
    memcpy(b.first, a->first, a->n * sizeof *b.first);
    memcpy(b.count, a->count, a->n);
    memcpy(b.level, a->level, a->cap + 1);
    memcpy(b.cost_ms, a->cost_ms, (a->cap + 1) * sizeof(double));
    memcpy(b.benefit, a->benefit, (a->cap + 1) * sizeof(double));
    return b;
}

static struct lod_problem problem(const struct inst *in)
{
    struct lod_problem p = {.object_count = in->n, .object_id = in->object_id, .first = in->first,
                            .count = in->count, .cost_ms = in->cost_ms, .benefit = in->benefit,
                            .level = in->level, .budget_ms = in->budget_ms};
    return p;
}

/* The optimizers' reduction: budget-aware, as replay and an embedding engine call it. */
static size_t reduce(struct inst *in)
{
    int64_t *scratch = calloc(in->n ? in->n : 1, sizeof *scratch);
    size_t rejected = lod_hull_reduce(in->n, in->first, in->count, in->cost_ms, in->benefit, in->level,
                                      in->budget_ms, scratch);
    free(scratch);
    return rejected;
}

/* The plain hull (no budget cap), whose geometric invariants test_hull_reduce checks. */
static size_t reduce_unbounded(struct inst *in)
{
    return lod_hull_reduce(in->n, in->first, in->count, in->cost_ms, in->benefit, in->level, INFINITY, NULL);
}

static double cheapest_sum_ms(const struct inst *in)
{
    double s = 0.0;
    for (size_t i = 0; i < in->n; ++i)
        if (in->count[i])
            s += in->cost_ms[in->first[i]];
    return s;
}

static double finest_sum_ms(const struct inst *in)
{
    double s = 0.0;
    for (size_t i = 0; i < in->n; ++i)
        if (in->count[i])
            s += in->cost_ms[in->first[i] + in->count[i] - 1];
    return s;
}

/* Random unreduced instance: per object 1…kmax candidates, cheapest first, costs rising by whole
 * multiples of unit_ms (ties allowed when allow_equal), benefits anywhere in [0, 100) rounded to
 * 1/64 (exact in binary, so glpsol reads exactly what we solve) — not monotone, so candidates lie
 * under the hull. Budget: between the cheapest and the finest choice, or (over_budget) below the
 * cheapest. Levels: coarsest (highest number) first. */
static struct inst inst_random(size_t n, int kmax, double unit_ms, int allow_equal, int over_budget)
{
    struct inst in = inst_new(n, (size_t)kmax);
    for (size_t i = 0; i < n; ++i) {
        int k = rng_int(1, kmax);
        in.count[i] = (uint8_t)k;
        double c = unit_ms * rng_int(0, 4);
        for (int j = 0; j < k; ++j) {
            uint32_t at = in.first[i] + (uint32_t)j;
            if (j > 0)
                c += unit_ms * rng_int(allow_equal ? 0 : 1, 9);
            in.cost_ms[at] = c;
            in.benefit[at] = floor(rng_unit() * 100.0 * 64.0) / 64.0;
            in.level[at] = (uint8_t)(k - 1 - j);
        }
    }
    double lo = cheapest_sum_ms(&in), hi = finest_sum_ms(&in);
    if (over_budget && lo > unit_ms)
        in.budget_ms = unit_ms * floor(rng_unit() * (lo / unit_ms - 1.0));
    else
        in.budget_ms = unit_ms * floor((lo + rng_unit() * (hi - lo)) / unit_ms);
    return in;
}

/* ---- brute force (tiny instances): every combination ------------------------------------------- */

struct brute {
    const struct inst *in;
    int drop_mode;
    double budget_ms, best;
};

static void brute_rec(struct brute *b, size_t i, double cost_ms, double benefit)
{
    if (cost_ms > b->budget_ms)
        return;
    if (i == b->in->n) {
        if (benefit > b->best)
            b->best = benefit;
        return;
    }
    if (b->drop_mode || b->in->count[i] == 0)
        brute_rec(b, i + 1, cost_ms, benefit);
    for (uint32_t k = 0; k < b->in->count[i]; ++k) {
        uint32_t c = b->in->first[i] + k;
        brute_rec(b, i + 1, cost_ms + b->in->cost_ms[c], benefit + b->in->benefit[c]);
    }
}

/* Best benefit over choices with cost ≤ budget_ms; −INFINITY when none. */
static double brute_optimum(const struct inst *in, double budget_ms)
{
    struct brute b = {.in = in, .drop_mode = cheapest_sum_ms(in) > in->budget_ms, .budget_ms = budget_ms,
                      .best = -INFINITY};
    brute_rec(&b, 0, 0.0, 0.0);
    return b.best;
}

/* Σ cost and benefit of a choice; 0 when every entry is a valid candidate or LOD_DROPPED. */
static int choice_totals(const struct inst *in, const uint8_t *choice, double *cost_ms, double *benefit,
                         size_t *dropped)
{
    *cost_ms = 0.0;
    *benefit = 0.0;
    *dropped = 0;
    for (size_t i = 0; i < in->n; ++i) {
        if (choice[i] == LOD_DROPPED) {
            ++*dropped;
            continue;
        }
        if (choice[i] >= in->count[i])
            return -1;
        *cost_ms += in->cost_ms[in->first[i] + choice[i]];
        *benefit += in->benefit[in->first[i] + choice[i]];
    }
    return 0;
}

static int exact(const struct inst *in, double quantum_ms, uint8_t *choice, double *benefit)
{
    struct lod_problem p = problem(in);
    size_t bytes = lod_solve_exact_bytes(&p, quantum_ms);
    void *work = malloc(bytes ? bytes : 1);
    int rc = lod_solve_exact(&p, quantum_ms, work, bytes, choice, benefit);
    free(work);
    return rc;
}

static double rel_tol(double x) { return 1e-9 * fmax(1.0, fabs(x)); }

/* ---- the exact solver and the LP bound, without glpsol ------------------------------------------ */

static void test_exact_brute_force(void)
{
    rng_state = 13;
    int dropped_instances = 0;
    for (int t = 0; t < 120; ++t) {
        int over = t % 6 == 5;
        struct inst in = inst_random((size_t)rng_int(1, 7), 4, 1.0, t % 2, over);
        uint8_t choice[16];
        double benefit = -1, cost_ms, sum;
        size_t dropped;
        int rc = exact(&in, 1.0, choice, &benefit);
        double want = brute_optimum(&in, in.budget_ms);
        CHECK(rc == (cheapest_sum_ms(&in) > in.budget_ms ? 1 : 0));
        CHECK(choice_totals(&in, choice, &cost_ms, &sum, &dropped) == 0);
        CHECK(cost_ms <= in.budget_ms);
        CHECK(sum == benefit);
        CHECK_NEAR(benefit, want, rel_tol(want));
        if (rc == 0)
            CHECK(dropped == 0);
        dropped_instances += rc == 1;
        /* The LP relaxation bounds every choice, reduced problem or not. */
        struct lod_problem p = problem(&in);
        CHECK(lod_lp_bound(&p, NULL) >= benefit - rel_tol(benefit));
        inst_free(&in);
    }
    CHECK(dropped_instances >= 10);
}

/* The layer choice (lod_solve_exact_settings): three settings of the same objects — each its own
 * costs, benefits and budget, as a frame's layer candidates are — against brute force over every
 * setting and every combination: a setting that draws everything first, then the highest benefit;
 * the LP bound of the union bounds it. */
static void test_exact_settings_brute_force(void)
{
    rng_state = 29;
    int picked_later = 0;
    for (int t = 0; t < 60; ++t) {
        size_t n = (size_t)rng_int(1, 5);
        struct inst in[3];
        struct lod_problem p[3];
        for (int k = 0; k < 3; ++k) {
            in[k] = inst_random(n, 3, 1.0, 0, t % 5 == 4 && k != 1);
            p[k] = problem(&in[k]);
        }
        size_t bytes = lod_solve_exact_settings_bytes(p, 3, 1.0), setting = 99;
        void *work = malloc(bytes ? bytes : 1);
        uint8_t choice[16];
        double benefit = -1.0;
        int rc = lod_solve_exact_settings(p, 3, 1.0, work, bytes, choice, &setting, &benefit);
        /* Brute force: the settings that draw everything, else all; the best benefit among them. */
        int any_full = 0;
        for (int k = 0; k < 3; ++k)
            any_full |= cheapest_sum_ms(&in[k]) <= in[k].budget_ms;
        double want = -INFINITY;
        size_t want_setting = 0;
        for (int k = 0; k < 3; ++k) {
            if (any_full && cheapest_sum_ms(&in[k]) > in[k].budget_ms)
                continue;
            double b = brute_optimum(&in[k], in[k].budget_ms);
            if (b > want)
                want = b, want_setting = (size_t)k;
        }
        CHECK(rc == (any_full ? 0 : 1));
        CHECK(setting < 3);
        size_t won = setting < 3 ? setting : 0; /* a bad index is reported above, not followed */
        CHECK_NEAR(benefit, want, rel_tol(want));
        CHECK(won == want_setting || fabs(brute_optimum(&in[won], in[won].budget_ms) - want) <= rel_tol(want));
        double cost_ms = INFINITY, sum = NAN;
        size_t dropped = 0;
        CHECK(choice_totals(&in[won], choice, &cost_ms, &sum, &dropped) == 0);
        CHECK(cost_ms <= in[won].budget_ms && sum == benefit);
        CHECK(lod_lp_bound_settings(p, 3) >= benefit - rel_tol(benefit));
        picked_later += setting > 0;
        free(work);
        for (int k = 0; k < 3; ++k)
            inst_free(&in[k]);
    }
    CHECK(picked_later >= 10); /* the winner is not always the first setting */
    CHECK(lod_solve_exact_settings(NULL, 0, 1.0, NULL, 0, NULL, NULL, NULL) == -3);
}

/* Costs that are not multiples of the quantum: rounded up, so the choice still fits the real budget;
 * it is no better than the true optimum and no worse than the optimum at budget − n·q. */
static void test_exact_rounding(void)
{
    rng_state = 77;
    for (int t = 0; t < 80; ++t) {
        struct inst in = inst_random((size_t)rng_int(2, 7), 4, 0.37, 0, 0);
        for (size_t c = 0; c < in.cap; ++c)
            in.cost_ms[c] *= 1.0 + 0.2 * rng_unit(); /* off the grid, still cheapest first */
        for (size_t i = 0; i < in.n; ++i)
            for (uint32_t k = 1; k < in.count[i]; ++k)
                if (in.cost_ms[in.first[i] + k] < in.cost_ms[in.first[i] + k - 1])
                    in.cost_ms[in.first[i] + k] = in.cost_ms[in.first[i] + k - 1];
        in.budget_ms = cheapest_sum_ms(&in) + rng_unit() * (finest_sum_ms(&in) - cheapest_sum_ms(&in)) + 0.5;
        const double q = 0.1;
        uint8_t choice[16];
        double benefit, cost_ms, sum;
        size_t dropped;
        int rc = exact(&in, q, choice, &benefit);
        CHECK(rc == 0 || rc == -2);
        if (rc != 0) {
            inst_free(&in);
            continue;
        }
        CHECK(choice_totals(&in, choice, &cost_ms, &sum, &dropped) == 0 && dropped == 0);
        CHECK(cost_ms <= in.budget_ms);
        double opt = brute_optimum(&in, in.budget_ms);
        double floor_opt = brute_optimum(&in, in.budget_ms - (double)in.n * q);
        CHECK(benefit <= opt + rel_tol(opt));
        if (floor_opt > -INFINITY)
            CHECK(benefit >= floor_opt - rel_tol(floor_opt));
        inst_free(&in);
    }
}

static void test_exact_errors(void)
{
    struct inst in = inst_new(2, 2);
    in.count[0] = in.count[1] = 1;
    in.cost_ms[0] = 0.6;
    in.cost_ms[2] = 0.6;
    in.benefit[0] = in.benefit[2] = 1.0;
    in.budget_ms = 1.5;
    struct lod_problem p = problem(&in);
    uint8_t choice[2];
    double benefit;
    double work[64];
    /* 0.6 + 0.6 fits 1.5, but rounded up to whole 1.0 quanta it needs 2 of the 1 available. */
    CHECK(lod_solve_exact(&p, 1.0, work, sizeof work, choice, &benefit) == -2);
    CHECK(lod_solve_exact(&p, 0.01, work, sizeof work, choice, &benefit) == -1); /* 151 units: 2.7 kB */
    CHECK(lod_solve_exact(&p, 0.0, work, sizeof work, choice, &benefit) == -3);
    CHECK(lod_solve_exact(&p, NAN, work, sizeof work, choice, &benefit) == -3);
    CHECK(lod_solve_exact_bytes(&p, 0.0) == 0);
    CHECK(lod_solve_exact(&p, 0.3, work, sizeof work, choice, &benefit) == 0 && benefit == 2.0);
    /* An object whose only candidate is unusable is dropped and costs nothing, as after
     * lod_hull_reduce; the other is drawn. */
    in.cost_ms[2] = NAN;
    CHECK(lod_solve_exact(&p, 0.3, work, sizeof work, choice, &benefit) == 0);
    CHECK(choice[0] == 0 && choice[1] == LOD_DROPPED && benefit == 1.0);
    inst_free(&in);
}

/* Hand-worked bounds. Object A: (1, 1), (3, 5), (6, 8): steps of value 2 (Δc 2) and 1 (Δc 3);
 * object B: (0, 0), (2, 6): one step of value 3. */
static void test_lp_bound_cases(void)
{
    struct inst in = inst_new(2, 4);
    in.count[0] = 3;
    in.count[1] = 2;
    const double ca[] = {1, 3, 6}, ba[] = {1, 5, 8};
    for (int k = 0; k < 3; ++k) {
        in.cost_ms[k] = ca[k];
        in.benefit[k] = ba[k];
    }
    in.cost_ms[4] = 0;
    in.benefit[4] = 0;
    in.cost_ms[5] = 2;
    in.benefit[5] = 6;
    struct lod_problem p = problem(&in);
    /* Budget 5: base 1 (benefit 1), B's step (2 → 6), A's first (2 → 4): 11, nothing left. */
    p.budget_ms = 5.0;
    CHECK_NEAR(lod_lp_bound(&p, NULL), 11.0, 1e-12);
    /* Budget 6: one more ms goes to A's second step at value 1: 12. */
    p.budget_ms = 6.0;
    CHECK_NEAR(lod_lp_bound(&p, NULL), 12.0, 1e-12);
    /* Everything fits: the finest of each, 8 + 6. */
    p.budget_ms = 100.0;
    CHECK_NEAR(lod_lp_bound(&p, NULL), 14.0, 1e-12);
    /* A point under A's hull changes nothing; the bound walks the hull itself. */
    in.count[0] = 4;
    in.cost_ms[1] = 2;
    in.benefit[1] = 1.5;
    in.cost_ms[2] = 3;
    in.benefit[2] = 5;
    in.cost_ms[3] = 6;
    in.benefit[3] = 8;
    p = problem(&in);
    p.budget_ms = 6.0;
    CHECK_NEAR(lod_lp_bound(&p, NULL), 12.0, 1e-12);
    /* Over budget (the cheapest 1 + 0 exceed 0.5): drop mode, A starts from a free null point with
     * slope 1 to (1, 1) then 2 … : the hull from (0, 0) is (0,0) → (3, 5) (value 5/3) → (6, 8);
     * B's step of value 3 comes first: 0.5 ms of it earns 1.5. */
    p.budget_ms = 0.5;
    CHECK_NEAR(lod_lp_bound(&p, NULL), 1.5, 1e-12);
    p.budget_ms = -1.0;
    CHECK(lod_lp_bound(&p, NULL) == 0.0);
    inst_free(&in);
}

/* The LP bound as the brief of the relaxation reads, on a hull-reduced problem: every candidate 0,
 * then all steps sorted by falling value, the first that does not fit taken fractionally. */
struct lp_step {
    double value, dcost_ms, dbenefit;
};
static int lp_step_desc(const void *a, const void *b)
{
    const struct lp_step *x = a, *y = b;
    return (x->value < y->value) - (x->value > y->value);
}
static double lp_by_sort(const struct inst *in)
{
    struct lp_step *steps = malloc((in->cap + 1) * sizeof *steps);
    size_t n = 0;
    double cost_ms = 0.0, benefit = 0.0;
    for (size_t i = 0; i < in->n; ++i) {
        if (!in->count[i])
            continue;
        cost_ms += in->cost_ms[in->first[i]];
        benefit += in->benefit[in->first[i]];
        for (uint32_t k = 1; k < in->count[i]; ++k) {
            uint32_t c = in->first[i] + k;
            double dc = in->cost_ms[c] - in->cost_ms[c - 1], db = in->benefit[c] - in->benefit[c - 1];
            steps[n++] = (struct lp_step){db / dc, dc, db};
        }
    }
    qsort(steps, n, sizeof *steps, lp_step_desc);
    double left_ms = in->budget_ms - cost_ms;
    for (size_t k = 0; k < n && left_ms > 0.0; ++k) {
        double take = fmin(1.0, left_ms / steps[k].dcost_ms);
        benefit += take * steps[k].dbenefit;
        left_ms -= take * steps[k].dcost_ms;
    }
    free(steps);
    return benefit;
}

/* Large instances (where the radix passes split many buckets and values tie across objects):
 * the bound equals the sorted relaxation on the reduced problem and bounds the greedy. */
static void test_lp_bound_large(void)
{
    rng_state = 616;
    for (int t = 0; t < 20; ++t) {
        size_t n = (size_t)rng_int(500, 3000);
        struct inst in = inst_random(n, 5, t % 2 ? 1.0 : 0.013, 1, 0);
        reduce(&in);
        struct lod_problem p = problem(&in);
        double lp = lod_lp_bound(&p, NULL), want = lp_by_sort(&in);
        CHECK_NEAR(lp, want, 1e-9 * fmax(1.0, want));
        uint8_t *choice = malloc(n);
        struct lod_result r;
        void *scratch = malloc(lod_scratch_bytes(n, in.cap + 1));
        lod_optimize_greedy(&p, scratch, choice, &r);
        CHECK(r.benefit <= lp + rel_tol(lp));
        free(scratch);
        free(choice);
        inst_free(&in);
    }
}

/* ---- glpsol ------------------------------------------------------------------------------------- */

static int find_glpsol(char *path, size_t size)
{
    const char *env = getenv("PATH");
    if (!env)
        return 0;
    const char *s = env;
    while (*s) {
        const char *e = strchr(s, ':');
        size_t len = e ? (size_t)(e - s) : strlen(s);
        if (len > 0 && (size_t)snprintf(path, size, "%.*s/glpsol", (int)len, s) < size && access(path, X_OK) == 0)
            return 1;
        s += len + (e ? 1 : 0);
    }
    return 0;
}

/* The instance as a CPLEX-LP model: binary x_i_k, one (drop mode: at most one) per object, the
 * budget row; without the Binary section it is the LP relaxation. Numbers in %.17g: exact. */
static int write_model(const char *file, const struct inst *in, int binary)
{
    FILE *f = fopen(file, "w");
    if (!f)
        return -1;
    int drop = cheapest_sum_ms(in) > in->budget_ms;
    fprintf(f, "\\* hmdlod: one frame's multiple-choice knapsack *\\\nMaximize\n obj:");
    for (size_t i = 0; i < in->n; ++i)
        for (uint32_t k = 0; k < in->count[i]; ++k)
            fprintf(f, " + %.17g x_%zu_%u", in->benefit[in->first[i] + k], i, k);
    fprintf(f, "\nSubject To\n");
    for (size_t i = 0; i < in->n; ++i) {
        if (!in->count[i])
            continue;
        fprintf(f, " one_%zu:", i);
        for (uint32_t k = 0; k < in->count[i]; ++k)
            fprintf(f, " + x_%zu_%u", i, k);
        fprintf(f, " %s 1\n", drop ? "<=" : "=");
    }
    fprintf(f, " budget:");
    for (size_t i = 0; i < in->n; ++i)
        for (uint32_t k = 0; k < in->count[i]; ++k)
            fprintf(f, " + %.17g x_%zu_%u", in->cost_ms[in->first[i] + k], i, k);
    fprintf(f, " <= %.17g\n", in->budget_ms);
    if (binary) {
        fprintf(f, "Binary\n");
        for (size_t i = 0; i < in->n; ++i)
            for (uint32_t k = 0; k < in->count[i]; ++k)
                fprintf(f, " x_%zu_%u\n", i, k);
    }
    fprintf(f, "End\n");
    return fclose(f) == 0 ? 0 : -1;
}

/* Runs glpsol on the model and reads the optimum from its plain-text solution (`-w`): the line
 * "s mip ROWS COLS o OBJ" (integer optimal) or "s bas ROWS COLS f f OBJ" (LP optimal). */
static int run_glpsol(const char *glpsol, const char *dir, const struct inst *in, int binary, double *obj)
{
    char model[512], sol[512], log[512], cmd[2048];
    snprintf(model, sizeof model, "%s/model.lp", dir);
    snprintf(sol, sizeof sol, "%s/solution.txt", dir);
    snprintf(log, sizeof log, "%s/glpsol.log", dir);
    if (write_model(model, in, binary) != 0)
        return -1;
    remove(sol);
    snprintf(cmd, sizeof cmd, "'%s' --lp '%s' -w '%s' >'%s' 2>&1", glpsol, model, sol, log);
    if (system(cmd) != 0) {
        fprintf(stderr, "glpsol failed on %s (log %s)\n", model, log);
        return -1;
    }
    FILE *f = fopen(sol, "r");
    if (!f)
        return -1;
    char line[512];
    int ok = 0;
    while (fgets(line, sizeof line, f)) {
        int rows, cols;
        char s1, s2;
        if (binary && sscanf(line, "s mip %d %d %c %lf", &rows, &cols, &s1, obj) == 4)
            ok = s1 == 'o';
        else if (!binary && sscanf(line, "s bas %d %d %c %c %lf", &rows, &cols, &s1, &s2, obj) == 5)
            ok = s1 == 'f' && s2 == 'f';
    }
    fclose(f);
    remove(sol);
    remove(model);
    remove(log);
    return ok ? 0 : -1;
}

/* ≥ 50 random instances, 3–12 objects × 1–5 candidates: the exact optimum and the LP bound against
 * glpsol's MIP and LP optima within 1e-6 relative. Costs are whole units (quantum 1) or quarters
 * (quantum 0.25), exact in binary, so the quantised program solves the same problem as glpsol. */
static int test_against_glpsol(void)
{
    char glpsol[1024];
    if (!find_glpsol(glpsol, sizeof glpsol)) {
        printf("skip: glpsol (Debian package glpk-utils) is not on PATH; scripts/setup.sh installs it\n");
        return 77;
    }
    const char *tmp = getenv("TMPDIR");
    char dir[512];
    snprintf(dir, sizeof dir, "%s/hmdlod-glpsol-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(dir)) {
        fprintf(stderr, "%s: cannot make a temporary folder\n", dir);
        return 1;
    }
    rng_state = 2026;
    int compared = 0, over = 0;
    double worst_rel = 0.0;
    for (int t = 0; t < 64; ++t) {
        double unit = t % 4 == 3 ? 0.25 : 1.0;
        struct inst in = inst_random((size_t)rng_int(3, 12), 5, unit, t % 3 == 0, t % 7 == 6);
        uint8_t choice[16];
        double benefit, mip, lp, cost_ms, sum;
        size_t dropped;
        int rc = exact(&in, unit, choice, &benefit);
        CHECK(rc == 0 || rc == 1);
        over += rc == 1;
        CHECK(choice_totals(&in, choice, &cost_ms, &sum, &dropped) == 0 && cost_ms <= in.budget_ms);
        if (run_glpsol(glpsol, dir, &in, 1, &mip) == 0 && run_glpsol(glpsol, dir, &in, 0, &lp) == 0) {
            ++compared;
            struct lod_problem p = problem(&in);
            double bound = lod_lp_bound(&p, NULL);
            CHECK_NEAR(benefit, mip, 1e-6 * fmax(1.0, fabs(mip)));
            CHECK_NEAR(bound, lp, 1e-6 * fmax(1.0, fabs(lp)));
            worst_rel = fmax(worst_rel, fabs(benefit - mip) / fmax(1.0, fabs(mip)));
            worst_rel = fmax(worst_rel, fabs(bound - lp) / fmax(1.0, fabs(lp)));
        } else {
            CHECK(!"glpsol gave no optimal solution");
        }
        inst_free(&in);
    }
    rmdir(dir);
    CHECK(compared >= 50 && over >= 5);
    printf("glpsol: %d instances (%d over budget), worst relative difference %.3g (exact and LP)\n", compared,
           over, worst_rel);
    return tu_finish("test_lod_optimize glpsol");
}

/* ---- the optimizers' guarantees (lod_hull_reduce, lod_optimize_greedy, lod_optimize_fs) -------- */

/* fs's value_hint for the next optimize() (lod.h: any value must give the same result). */
static double fs_value_hint;

/* The greedy (time_limit_us < 0) or fs from `start` (NULL: all candidate 0). */
static void optimize(const struct inst *in, int use_fs, double time_limit_us, const uint8_t *start,
                     uint8_t *choice, struct lod_result *r)
{
    struct lod_problem p = problem(in);
    p.value_hint = fs_value_hint;
    void *scratch = malloc(lod_scratch_bytes(in->n, in->cap + 1));
    if (use_fs) {
        for (size_t i = 0; i < in->n; ++i)
            choice[i] = start ? start[i] : 0;
        lod_optimize_fs(&p, time_limit_us, scratch, choice, r);
    } else {
        lod_optimize_greedy(&p, scratch, choice, r);
    }
    free(scratch);
}

/* Within budget, complete, and the result's totals are the choice's: every optimizer, every time. */
static int check_outcome(const struct inst *in, const uint8_t *choice, const struct lod_result *r)
{
    double cost_ms, benefit;
    size_t dropped, empty = 0;
    int fails = tu_failures;
    CHECK(choice_totals(in, choice, &cost_ms, &benefit, &dropped) == 0);
    CHECK(cost_ms <= in->budget_ms);
    CHECK(r->cost_ms <= in->budget_ms);
    /* r->cost_ms may sit above the real sum by the optimizers' cost rounding (lod_internal.h: whole
     * 1e-8 ms units, rounded up per candidate). */
    CHECK_NEAR(r->cost_ms, cost_ms, 2e-8 * (double)in->n + 1e-12 * cost_ms);
    CHECK_NEAR(r->benefit, benefit, rel_tol(benefit));
    CHECK(r->dropped == dropped);
    for (size_t i = 0; i < in->n; ++i)
        empty += in->count[i] == 0;
    /* Objects are dropped only when the cheapest candidates cannot all fit, and then it says so. */
    CHECK(r->over_budget == (cheapest_sum_ms(in) > in->budget_ms));
    if (!r->over_budget)
        CHECK(dropped == empty);
    else
        CHECK(dropped > empty);
    /* Drops are the last resort (issue 30): no dropped object's candidate 0 fits in what is left. */
    struct lod_problem p = problem(in);
    CHECK(lod_choice_underused_drop(&p, choice, 1.0) == 0);
    return tu_failures == fails;
}

/* For a failed guarantee: the instance, unreduced and reduced, so the case can be replayed. */
static void print_instance(const char *what, const struct inst *raw, const struct inst *in, double got, double opt)
{
    fprintf(stderr, "%s: budget %.17g ms, got %.17g, exact optimum %.17g\n", what, raw->budget_ms, got, opt);
    for (size_t i = 0; i < raw->n; ++i) {
        fprintf(stderr, "  object %zu (cost ms, benefit):", i);
        for (uint32_t k = 0; k < raw->count[i]; ++k)
            fprintf(stderr, " (%g, %g)", raw->cost_ms[raw->first[i] + k], raw->benefit[raw->first[i] + k]);
        fprintf(stderr, "  hull:");
        for (uint32_t k = 0; k < in->count[i]; ++k)
            fprintf(stderr, " (%g, %g)", in->cost_ms[in->first[i] + k], in->benefit[in->first[i] + k]);
        fprintf(stderr, "\n");
    }
}

/* Random instances, exact optimum of the unreduced problem as the reference: greedy ≤ exact ≤ LP,
 * greedy ≥ ½ exact (the guard's promise holds against the optimum under the hull too, since it
 * holds against the LP bound), the budget-aware hull only tightens the LP bound, and fs from any
 * start equals greedy. */
static void test_greedy_and_fs_random(void)
{
    rng_state = 4242;
    int fs_starts = 0, guarded = 0, over = 0, below_half = 0;
    double worst_ratio = INFINITY;
    for (int t = 0; t < 400; ++t) {
        int over_budget = t % 10 == 9;
        struct inst raw = inst_random((size_t)rng_int(1, 12), 5, 1.0, t % 2, over_budget);
        raw.budget_ms += 0.5; /* never an exact fit: test_exact_fit has those */
        uint8_t ex_choice[16], choice[16], fs_choice[16], start[16];
        double opt;
        int rc = exact(&raw, 1.0, ex_choice, &opt);
        CHECK(rc == 0 || rc == 1);
        struct lod_problem praw = problem(&raw);
        double lp_raw = lod_lp_bound(&praw, NULL);
        struct inst in = inst_copy(&raw);
        CHECK(reduce(&in) == 0);
        struct lod_problem p = problem(&in);
        double lp = lod_lp_bound(&p, NULL), opt_reduced;
        CHECK(lp <= lp_raw + rel_tol(lp_raw)); /* the budget cap only removes what cannot fit: tighter, still a bound */
        CHECK(exact(&in, 1.0, ex_choice, &opt_reduced) == rc);
        CHECK(opt_reduced <= opt + rel_tol(opt));
        CHECK(opt <= lp + rel_tol(lp));

        struct lod_result r, rf;
        optimize(&in, 0, -1, NULL, choice, &r);
        check_outcome(&in, choice, &r);
        CHECK(r.benefit <= opt + rel_tol(opt));
        CHECK(r.benefit <= lp + rel_tol(lp));
        if (!r.over_budget) {
            /* ½ of the reduced problem's optimum (the header's promise) and of the unreduced one's:
             * the hull may have dropped a candidate that fits under a step that does not. */
            CHECK(r.benefit >= 0.5 * opt_reduced - rel_tol(opt_reduced));
            CHECK(r.benefit >= 0.5 * opt - rel_tol(opt));
            if (r.benefit < 0.5 * opt - rel_tol(opt) && below_half++ == 0)
                print_instance("below half of the unreduced optimum", &raw, &in, r.benefit, opt);
            if (opt > 0)
                worst_ratio = fmin(worst_ratio, r.benefit / opt);
        }
        guarded += r.single_item;
        over += r.over_budget;
        /* fs run to the end from all-coarsest, all-finest and random starts equals the greedy —
         * also with every kind of value hint: none, its own margin from a first run (the coherent
         * case), far too low, far too high, and values that must be ignored. */
        double margin = 0.0;
        for (int s = 0; s < 4; ++s) {
            for (size_t i = 0; i < in.n; ++i) {
                int top = in.count[i] ? in.count[i] - 1 : 0;
                start[i] = (uint8_t)(s == 0 ? 0 : s == 1 ? top : rng_int(0, top));
            }
            const double hints[] = {0.0, margin, margin * 1e-6, margin * 1e6 + 1.0, 1e-300, 1e300, NAN, -1.0, DBL_MAX};
            for (size_t h = 0; h < sizeof hints / sizeof hints[0]; ++h) {
                fs_value_hint = hints[h];
                optimize(&in, 1, 0.0, start, fs_choice, &rf);
                check_outcome(&in, fs_choice, &rf);
                CHECK(memcmp(fs_choice, choice, in.n) == 0);
                CHECK_NEAR(rf.benefit, r.benefit, rel_tol(r.benefit));
                CHECK(rf.truncated == 0);
                CHECK(rf.margin_value >= 0.0 && rf.margin_value < DBL_MAX);
                if (h == 0)
                    margin = rf.margin_value;
                ++fs_starts;
            }
            fs_value_hint = 0.0;
        }
        inst_free(&in);
        inst_free(&raw);
    }
    CHECK(guarded > 0 && over >= 20);
    printf("greedy: 400 instances (%d over budget, %d won by the single-item guard), worst greedy/exact %.3f, "
           "%d below half of the unreduced optimum; fs equal to greedy from %d starts\n",
           over, guarded, worst_ratio, below_half, fs_starts);
}

/* A two-candidate object per entry: candidate 0 (0, 0), candidate 1 (cost, benefit). */
static struct inst inst_steps(size_t n, const double *cost_ms, const double *benefit, double budget_ms)
{
    struct inst in = inst_new(n, 2);
    for (size_t i = 0; i < n; ++i) {
        in.count[i] = 2;
        in.cost_ms[in.first[i] + 1] = cost_ms[i];
        in.benefit[in.first[i] + 1] = benefit[i];
        in.level[in.first[i]] = 1;
    }
    in.budget_ms = budget_ms;
    return in;
}

/* Mason & Blake 1997 §3: the plain greedy takes the small step of value 2 first and then cannot fit
 * the big step of value 1 — 2 of a possible 100. The single-item guard restores ≥ ½ (here all). */
static void test_counterexample(void)
{
    const double cost2[] = {1, 100}, benefit2[] = {2, 100};
    struct inst in = inst_steps(2, cost2, benefit2, 100.5);
    uint8_t choice[64], fs_choice[64];
    struct lod_result r, rf;
    optimize(&in, 0, -1, NULL, choice, &r);
    check_outcome(&in, choice, &r);
    CHECK(r.single_item == 1 && choice[0] == 0 && choice[1] == 1);
    CHECK_NEAR(r.benefit, 100.0, 1e-12);
    optimize(&in, 1, 0.0, NULL, fs_choice, &rf);
    CHECK(memcmp(choice, fs_choice, 2) == 0);
    /* The same with the big step filling the budget exactly: a choice costing exactly the budget
     * fits ("predicted cost ≤ budget"), so the optimum is still 100 and ½ of it is owed. */
    in.budget_ms = 100.0;
    optimize(&in, 0, -1, NULL, choice, &r);
    check_outcome(&in, choice, &r);
    CHECK(r.benefit >= 50.0);
    inst_free(&in);

    /* A hull-reduced problem whose top candidate cannot fit even alone: object A (0, 0), (1, 1.5),
     * (100, 101.5) and three objects B (0, 0), (1.8, 1.8); budget 5.5. In falling value the greedy
     * takes A's first step (1.5), meets A's second (value 1.01, 99 ms) which does not fit, and stops
     * before the B steps (value 1); the guard's best single upgrade is one B (1.8). The optimum is
     * the three B (5.4): the greedy gets a third. Half is owed only if steps that can never fit do
     * not stop it (they should not count as "the first step that does not fit"). */
    {
        struct inst adv = inst_new(4, 3);
        adv.count[0] = 3;
        adv.cost_ms[1] = 1.0;
        adv.benefit[1] = 1.5;
        adv.cost_ms[2] = 100.0;
        adv.benefit[2] = 101.5;
        for (size_t i = 1; i < 4; ++i) {
            adv.count[i] = 2;
            adv.cost_ms[adv.first[i] + 1] = 1.8;
            adv.benefit[adv.first[i] + 1] = 1.8;
        }
        adv.budget_ms = 5.5;
        CHECK(reduce(&adv) == 0 && adv.count[0] == 2); /* the 100 ms level can never fit: gone */
        double opt;
        CHECK(exact(&adv, 0.1, choice, &opt) == 0);
        CHECK_NEAR(opt, 5.4, 1e-9);
        optimize(&adv, 0, -1, NULL, choice, &r);
        check_outcome(&adv, choice, &r);
        CHECK(r.benefit >= 0.5 * opt);
        if (r.benefit < 0.5 * opt)
            print_instance("unfittable top candidate", &adv, &adv, r.benefit, opt);
        inst_free(&adv);
    }

    /* A family: m small steps (1 ms, value 1.5…3) against one big step (B ms, value 1) with
     * budget B + ½; the exact optimum is the reference. */
    rng_state = 99;
    double worst = INFINITY;
    for (int t = 0; t < 200; ++t) {
        size_t m = (size_t)rng_int(1, 20);
        double cost[32], benefit[32];
        for (size_t i = 0; i < m; ++i) {
            cost[i] = 1.0;
            benefit[i] = 1.5 + floor(rng_unit() * 96.0) / 64.0;
        }
        double big = (double)rng_int((int)(m / 2) + 1, (int)(2 * m) + 2);
        cost[m] = big;
        benefit[m] = big;
        struct inst a = inst_steps(m + 1, cost, benefit, big + 0.5);
        double opt;
        CHECK(exact(&a, 0.5, choice, &opt) == 0);
        optimize(&a, 0, -1, NULL, choice, &r);
        check_outcome(&a, choice, &r);
        CHECK(r.benefit >= 0.5 * opt - rel_tol(opt));
        worst = fmin(worst, r.benefit / opt);
        inst_free(&a);
    }
    printf("counterexample family: worst greedy/exact %.3f over 200 instances\n", worst);
}

/* Even the cheapest candidates do not fit: objects are dropped, lowest benefit per cost of
 * candidate 0 first, ties by object_id; the rest fits and over_budget says so. */
static void test_over_budget(void)
{
    struct inst in = inst_new(4, 2);
    const double c0[] = {2, 2, 2, 2}, b0[] = {4, 2, 6, 2};
    for (size_t i = 0; i < 4; ++i) {
        in.count[i] = 1;
        in.cost_ms[in.first[i]] = c0[i];
        in.benefit[in.first[i]] = b0[i];
    }
    /* Objects 1 and 3 tie at 1 per ms; object 1 has the lower id and goes first. */
    in.budget_ms = 6.5;
    uint8_t choice[4];
    struct lod_result r;
    optimize(&in, 0, -1, NULL, choice, &r);
    check_outcome(&in, choice, &r);
    CHECK(r.over_budget == 1 && r.dropped == 1 && choice[1] == LOD_DROPPED && choice[3] == 0);
    /* Dropping the two at 1 per ms leaves 2 + 2 = 4 ms: an exact fit, which fits. */
    in.budget_ms = 4.0;
    optimize(&in, 0, -1, NULL, choice, &r);
    check_outcome(&in, choice, &r);
    CHECK(r.dropped == 2 && choice[1] == LOD_DROPPED && choice[3] == LOD_DROPPED && choice[0] == 0 && choice[2] == 0);
    /* Nothing fits at all: everything dropped, cost 0. */
    in.budget_ms = 1.0;
    optimize(&in, 1, 0.0, NULL, choice, &r);
    check_outcome(&in, choice, &r);
    CHECK(r.dropped == 4 && r.cost_ms == 0.0);
    inst_free(&in);
}

/* ---- drop last (issue 30 item 4) ----------------------------------------------------------------
 * When even the cheapest candidates do not fit, objects are dropped lowest benefit per cost first
 * until the rest fits; the last one dropped may be large and leave most of the budget unused while
 * smaller objects dropped before it would fit. Those come back (lod.h). */

/* The auditorium in small: a wall (6 ms, benefit 6: 1 per ms), four chairs (1 ms, 0.9 each: 0.9 per
 * ms) and a statue K (2 ms, 10; a step up to 3 ms, 15). Σ cheapest = 12 ms over a budget of 7.5:
 * the chairs go first, then the wall, leaving 2 ms of 7.5 — the chairs fit again. */
static struct inst inst_hall(void)
{
    struct inst in = inst_new(6, 2);
    in.count[0] = 1, in.cost_ms[in.first[0]] = 6.0, in.benefit[in.first[0]] = 6.0;
    for (size_t i = 1; i <= 4; ++i)
        in.count[i] = 1, in.cost_ms[in.first[i]] = 1.0, in.benefit[in.first[i]] = 0.9;
    in.count[5] = 2;
    in.cost_ms[in.first[5]] = 2.0, in.benefit[in.first[5]] = 10.0;
    in.cost_ms[in.first[5] + 1] = 3.0, in.benefit[in.first[5] + 1] = 15.0;
    in.level[in.first[5]] = 1;
    in.budget_ms = 7.5;
    return in;
}

/* A flat representation tree over a problem's objects (every object a root): lod_optimize_mb's view
 * of it, which must give the greedy's answer (lod.h). */
static void optimize_mb_flat(const struct inst *in, uint8_t *state, struct lod_result *r)
{
    uint32_t *parent = malloc(in->n * sizeof *parent), *zero = calloc(in->n + 1, sizeof *zero);
    for (size_t i = 0; i < in->n; ++i)
        parent[i] = LOD_MB_ROOT;
    struct lod_tree t = {in->n, in->object_id, parent, zero, zero, zero, in->first, in->count, in->cost_ms,
                         in->benefit, in->budget_ms};
    void *scratch = malloc(lod_mb_scratch_bytes(in->n));
    lod_mb_start_cheapest(&t, state);
    lod_optimize_mb(&t, 0.0, scratch, state, r);
    CHECK(lod_tree_underused_drop(&t, state, 1.0) == 0);
    free(scratch), free(parent), free(zero);
}

static void test_drop_last(void)
{
    struct inst in = inst_hall();
    struct lod_problem p = problem(&in);
    uint8_t choice[6], fs_choice[6], state[6];
    struct lod_result r, rf, rm;
    optimize(&in, 0, -1, NULL, choice, &r);
    check_outcome(&in, choice, &r);
    /* The wall stays dropped (6 ms never fits beside the rest); the four chairs are back; the statue
     * rises into the last 1.5 ms: 7 ms of 7.5. */
    CHECK(r.over_budget == 1 && r.dropped == 1 && choice[0] == LOD_DROPPED);
    CHECK(choice[1] == 0 && choice[2] == 0 && choice[3] == 0 && choice[4] == 0 && choice[5] == 1);
    CHECK_NEAR(r.cost_ms, 7.0, 1e-12);
    CHECK_NEAR(r.benefit, 4 * 0.9 + 15.0, 1e-12);
    CHECK(lod_choice_underused_drop(&p, choice, 0.7) == 0);
    /* fs from every start, and mb on the flat tree: the same. */
    const uint8_t starts[][6] = {{0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 1}, {LOD_DROPPED, LOD_DROPPED, 0, 0, 0, 1}};
    for (size_t s = 0; s < 3; ++s) {
        optimize(&in, 1, 0.0, starts[s], fs_choice, &rf);
        check_outcome(&in, fs_choice, &rf);
        CHECK(memcmp(fs_choice, choice, 6) == 0 && rf.dropped == 1);
    }
    optimize_mb_flat(&in, state, &rm);
    CHECK(memcmp(state, choice, 6) == 0 && rm.dropped == 1 && rm.over_budget == 1);
    CHECK_NEAR(rm.benefit, r.benefit, 1e-12);
    /* What the rule replaced: wall and chairs dropped, the statue up — 3 ms of 7.5 (40 %) with four
     * chairs that fit: an underused drop at 70 %, and at 100 %. */
    const uint8_t before[6] = {LOD_DROPPED, LOD_DROPPED, LOD_DROPPED, LOD_DROPPED, LOD_DROPPED, 1};
    CHECK(lod_choice_underused_drop(&p, before, 0.7) == 1);
    CHECK(lod_choice_underused_drop(&p, before, 1.0) == 1);
    CHECK(lod_choice_underused_drop(&p, before, 0.4) == 0); /* 3 ms is not under 3 ms */
    /* Ties among the dropped: with room for one chair only (budget 3 + ½: the statue and one chair),
     * the lowest object_id comes back. */
    in.budget_ms = 3.5;
    optimize(&in, 0, -1, NULL, choice, &r);
    check_outcome(&in, choice, &r);
    CHECK(choice[0] == LOD_DROPPED && choice[1] == 0 && choice[2] == LOD_DROPPED && choice[3] == LOD_DROPPED &&
          choice[4] == LOD_DROPPED && choice[5] == 0 && r.dropped == 4);
    optimize(&in, 1, 0.0, NULL, fs_choice, &rf);
    CHECK(memcmp(fs_choice, choice, 6) == 0);
    inst_free(&in);
}

/* lod_choice_underused_drop on its own: the fraction's edge, the fit's edge, objects without
 * candidates, an empty problem and degenerate budgets and fractions. */
static void test_underused_drop_cases(void)
{
    struct inst in = inst_new(3, 1);
    for (size_t i = 0; i < 3; ++i)
        in.count[i] = 1;
    in.cost_ms[0] = 3.0, in.cost_ms[1] = 1.0, in.cost_ms[2] = 2.0;
    in.budget_ms = 4.0;
    struct lod_problem p = problem(&in);
    uint8_t c[3] = {0, LOD_DROPPED, 0};
    CHECK(lod_choice_underused_drop(&p, c, 1.0) == 0); /* 5 ms chosen: over the budget, nothing fits */
    c[2] = LOD_DROPPED;                                /* 3 of 4 ms; object 1 (1 ms) fits exactly */
    CHECK(lod_choice_underused_drop(&p, c, 1.0) == 1);
    CHECK(lod_choice_underused_drop(&p, c, 0.76) == 1);
    CHECK(lod_choice_underused_drop(&p, c, 0.75) == 0); /* 3 ms is not under 0.75 × 4 */
    CHECK(lod_choice_underused_drop(&p, c, 0.0) == 0);
    CHECK(lod_choice_underused_drop(&p, c, -1.0) == 0);
    CHECK(lod_choice_underused_drop(&p, c, NAN) == 0);
    CHECK(lod_choice_underused_drop(&p, c, INFINITY) == 1);
    in.cost_ms[1] = 1.5, in.cost_ms[2] = 1.25; /* neither dropped object fits in 1 ms */
    CHECK(lod_choice_underused_drop(&p, c, 1.0) == 0);
    in.cost_ms[2] = 0.5; /* the smaller one does */
    CHECK(lod_choice_underused_drop(&p, c, 1.0) == 1);
    in.count[2] = 0; /* no candidate: dropped, but not by the budget */
    CHECK(lod_choice_underused_drop(&p, c, 1.0) == 0);
    const uint8_t none[3] = {LOD_DROPPED, LOD_DROPPED, LOD_DROPPED};
    in.count[2] = 1;
    CHECK(lod_choice_underused_drop(&p, none, 1.0) == 1); /* everything dropped, everything would fit */
    p.budget_ms = 0.0;
    CHECK(lod_choice_underused_drop(&p, none, 1.0) == 0);
    p.budget_ms = NAN;
    CHECK(lod_choice_underused_drop(&p, none, 1.0) == 0);
    p.object_count = 0;
    p.budget_ms = 4.0;
    CHECK(lod_choice_underused_drop(&p, none, 1.0) == 0);
    inst_free(&in);
}

/* The problem with objects `gone` (nonzero entries) taken out (count 0), otherwise the same. */
static struct inst inst_without(const struct inst *in, const uint8_t *gone)
{
    struct inst out = inst_copy(in);
    for (size_t i = 0; i < in->n; ++i)
        if (gone[i])
            out.count[i] = 0;
    return out;
}

/* Random problems over budget: no dropped object fits in what the final choice leaves; fs and mb
 * equal the greedy; the drawn set is a superset of the old rule's (drop until it fits, no return);
 * and the choice is the greedy's on the problem without the dropped objects. The old rule's benefit
 * is computed the same way (its drops taken out, the greedy run on the rest) for comparison. */
static void test_drop_last_random(void)
{
    rng_state = 3030;
    int cases = 0, readmitted = 0, old_underused = 0, lower = 0, higher = 0;
    double worst = 1.0;
    for (int t = 0; t < 600; ++t) {
        struct inst raw = inst_random((size_t)rng_int(2, 40), 5, 1.0, t % 2, 1);
        raw.budget_ms += t % 3 == 0 ? 0.0 : 0.5; /* exact fits too */
        struct inst in = inst_copy(&raw);
        CHECK(reduce(&in) == 0);
        if (!(cheapest_sum_ms(&in) > in.budget_ms)) {
            inst_free(&in), inst_free(&raw);
            continue;
        }
        ++cases;
        struct lod_problem p = problem(&in);
        uint8_t choice[40], other[40], start[40], gone_old[40], gone_new[40];
        struct lod_result r, ro;
        optimize(&in, 0, -1, NULL, choice, &r);
        CHECK(check_outcome(&in, choice, &r) && r.over_budget);
        CHECK(lod_choice_underused_drop(&p, choice, 1.0) == 0);
        for (int s = 0; s < 3; ++s) {
            for (size_t i = 0; i < in.n; ++i) {
                int top = in.count[i] ? in.count[i] - 1 : 0;
                start[i] = (uint8_t)(s == 0 ? 0 : s == 1 ? top : rng_int(0, top));
            }
            optimize(&in, 1, 0.0, start, other, &ro);
            CHECK(memcmp(other, choice, in.n) == 0 && ro.dropped == r.dropped);
        }
        optimize_mb_flat(&in, other, &ro);
        CHECK(memcmp(other, choice, in.n) == 0 && ro.dropped == r.dropped);
        /* The old rule's drops: lowest benefit per cost of candidate 0 first (ties: lower id, which
         * the ids' memory order gives here), until the rest fits. */
        double total = cheapest_sum_ms(&in);
        memset(gone_old, 0, sizeof gone_old);
        for (;;) {
            size_t pick = SIZE_MAX;
            double pick_value = 0.0;
            for (size_t i = 0; i < in.n; ++i) {
                if (in.count[i] == 0 || gone_old[i] || in.cost_ms[in.first[i]] <= 0.0)
                    continue;
                double v = in.benefit[in.first[i]] / in.cost_ms[in.first[i]];
                if (pick == SIZE_MAX || v < pick_value)
                    pick = i, pick_value = v;
            }
            if (total <= in.budget_ms || pick == SIZE_MAX)
                break;
            gone_old[pick] = 1;
            total -= in.cost_ms[in.first[pick]];
        }
        size_t old_drops = 0, new_drops = 0;
        for (size_t i = 0; i < in.n; ++i) {
            gone_new[i] = in.count[i] > 0 && choice[i] == LOD_DROPPED;
            CHECK(!gone_new[i] || gone_old[i]); /* every object the old rule drew is drawn */
            old_drops += gone_old[i], new_drops += gone_new[i];
        }
        readmitted += new_drops < old_drops;
        /* The choice is the greedy's on the objects it keeps (the drops add nothing else). */
        struct inst kept = inst_without(&in, gone_new);
        optimize(&kept, 0, -1, NULL, other, &ro);
        for (size_t i = 0; i < in.n; ++i)
            CHECK(other[i] == choice[i]);
        inst_free(&kept);
        /* The old rule's answer: its drops out, the greedy (steps and guard) on the rest. */
        struct inst old = inst_without(&in, gone_old);
        optimize(&old, 0, -1, NULL, other, &ro);
        struct lod_problem po = p; /* the old choice judged on the whole problem */
        old_underused += lod_choice_underused_drop(&po, other, 0.7);
        if (ro.benefit > r.benefit + rel_tol(r.benefit)) {
            ++lower;
            worst = fmin(worst, r.benefit / ro.benefit);
        }
        higher += r.benefit > ro.benefit + rel_tol(ro.benefit);
        inst_free(&old);
        inst_free(&in);
        inst_free(&raw);
    }
    CHECK(cases >= 300 && readmitted > 0 && old_underused > 0);
    printf("drop last: %d problems over budget, dropped objects re-admitted in %d; the old rule ended under 70 %% "
           "with one that fit in %d; benefit above the old rule's in %d, below in %d (worst %.3f of it)\n",
           cases, readmitted, old_underused, higher, lower, worst);
}

/* Objects moved in memory (ids kept) must get the same choice: ties are broken by object_id. The
 * instances repeat objects under other ids so that ties are everywhere. */
static void test_determinism(void)
{
    rng_state = 555;
    for (int t = 0; t < 100; ++t) {
        size_t n = (size_t)rng_int(2, 40);
        struct inst in = inst_random(n, 5, 1.0, 1, t % 8 == 7);
        for (size_t i = 1; i < n; ++i)
            if (rng_unit() < 0.5) { /* a twin of the previous object */
                in.count[i] = in.count[i - 1];
                for (uint32_t k = 0; k < in.count[i]; ++k) {
                    in.cost_ms[in.first[i] + k] = in.cost_ms[in.first[i - 1] + k];
                    in.benefit[in.first[i] + k] = in.benefit[in.first[i - 1] + k];
                    in.level[in.first[i] + k] = in.level[in.first[i - 1] + k];
                }
            }
        double lo = cheapest_sum_ms(&in), hi = finest_sum_ms(&in);
        if (lo <= in.budget_ms)
            in.budget_ms = floor(lo + rng_unit() * (hi - lo)) + 0.5;
        reduce(&in);
        /* The permutation: a shuffled copy, candidates moving with their object. */
        size_t perm[64];
        for (size_t i = 0; i < n; ++i)
            perm[i] = i;
        for (size_t i = n; i-- > 1;) {
            size_t j = (size_t)rng_int(0, (int)i), x = perm[i];
            perm[i] = perm[j];
            perm[j] = x;
        }
        struct inst sh = inst_copy(&in);
        for (size_t i = 0; i < n; ++i) { /* position i of sh holds object perm[i] of in */
            size_t o = perm[i];
            sh.object_id[i] = in.object_id[o];
            sh.count[i] = in.count[o];
            for (uint32_t k = 0; k < in.count[o]; ++k) {
                sh.cost_ms[sh.first[i] + k] = in.cost_ms[in.first[o] + k];
                sh.benefit[sh.first[i] + k] = in.benefit[in.first[o] + k];
                sh.level[sh.first[i] + k] = in.level[in.first[o] + k];
            }
        }
        for (int use_fs = 0; use_fs < 2; ++use_fs) {
            uint8_t a[64], b[64], c[64];
            struct lod_result ra, rb, rc;
            optimize(&in, use_fs, 0.0, NULL, a, &ra);
            optimize(&in, use_fs, 0.0, NULL, b, &rb);
            optimize(&sh, use_fs, 0.0, NULL, c, &rc);
            check_outcome(&sh, c, &rc);
            CHECK(memcmp(a, b, n) == 0);
            CHECK(ra.benefit == rb.benefit && ra.cost_ms == rb.cost_ms && ra.iterations == rb.iterations &&
                  ra.dropped == rb.dropped && ra.single_item == rb.single_item);
            int same = 1;
            for (size_t i = 0; i < n; ++i)
                same &= c[i] == a[perm[i]];
            CHECK(same);
            CHECK_NEAR(rc.benefit, ra.benefit, rel_tol(ra.benefit));
            CHECK(rc.cost_ms == ra.cost_ms && rc.dropped == ra.dropped);
        }
        inst_free(&sh);
        inst_free(&in);
    }
}

/* Frame to frame: last frame's levels mapped by lod_choice_start onto a frame whose benefits moved
 * by up to ±20 % (another hull, other candidates), then fs to the end equals the greedy. */
static void test_fs_previous_frame(void)
{
    rng_state = 808;
    int printed_fs = 0;
    for (int t = 0; t < 100; ++t) {
        size_t n = t % 10 == 9 ? 2000 : (size_t)rng_int(5, 60); /* some at scale: fs filters its heaps */
        struct inst a = inst_random(n, 5, 1.0, 0, 0);
        struct inst b = inst_copy(&a);
        for (size_t c = 0; c < b.cap; ++c)
            b.benefit[c] *= 0.8 + 0.4 * rng_unit();
        b.budget_ms = a.budget_ms * (0.9 + 0.2 * rng_unit());
        reduce(&a);
        reduce(&b);
        uint8_t *ca = malloc(n), *levels = malloc(n), *start = malloc(n), *cf = malloc(n), *cg = malloc(n);
        struct lod_result ra, rf, rg;
        optimize(&a, 0, -1, NULL, ca, &ra);
        struct lod_problem pa = problem(&a), pb = problem(&b);
        lod_level_of_choice(&pa, ca, levels);
        if (t % 5 == 4)
            levels[0] = LOD_UNSEEN; /* a newly visible object starts at its coarsest */
        lod_choice_start(&pb, levels, start);
        for (size_t i = 0; i < n; ++i)
            CHECK(start[i] < b.count[i] || b.count[i] == 0);
        if (t % 5 == 4)
            CHECK(start[0] == 0);
        optimize(&b, 1, 0.0, start, cf, &rf);
        optimize(&b, 0, -1, NULL, cg, &rg);
        check_outcome(&b, cf, &rf);
        /* The same choice; the benefit may be summed in another order (fs keeps a running sum). */
        CHECK(memcmp(cf, cg, n) == 0);
        CHECK_NEAR(rf.benefit, rg.benefit, rel_tol(rg.benefit));
        if (memcmp(cf, cg, n) != 0 && !printed_fs++) {
            print_instance("fs from last frame's choice differs from the greedy", &b, &b, rf.benefit, rg.benefit);
            fprintf(stderr, "  start / fs / greedy per object:");
            for (size_t i = 0; i < n; ++i)
                fprintf(stderr, " %d/%d/%d", start[i], cf[i], cg[i]);
            fprintf(stderr, "\n  fs: iterations %u truncated %d single_item %d; greedy single_item %d\n", rf.iterations,
                    rf.truncated, rf.single_item, rg.single_item);
        }
        free(ca);
        free(levels);
        free(start);
        free(cf);
        free(cg);
        inst_free(&a);
        inst_free(&b);
    }
}

/* Nirenstein et al. §5.5: whatever the limit, the truncated result is feasible and complete. The
 * count of truncated runs is printed, not asserted (it depends on this machine's speed). */
static void test_fs_time_limit(void)
{
    rng_state = 31337;
    const double limits_us[] = {0.001, 0.1, 1, 5, 20, 100};
    int runs = 0, truncated = 0;
    for (int t = 0; t < 6; ++t) {
        size_t n = 3000;
        struct inst in = inst_random(n, 5, 1.0, 0, t == 5);
        reduce(&in);
        uint8_t *start = malloc(n), *choice = malloc(n);
        for (int s = 0; s < 3; ++s) {
            for (size_t i = 0; i < n; ++i) {
                int top = in.count[i] ? in.count[i] - 1 : 0;
                start[i] = (uint8_t)(s == 0 ? 0 : s == 1 ? top : rng_int(0, top));
            }
            for (size_t l = 0; l < sizeof limits_us / sizeof *limits_us; ++l) {
                struct lod_result r;
                optimize(&in, 1, limits_us[l], start, choice, &r);
                check_outcome(&in, choice, &r);
                truncated += r.truncated;
                ++runs;
            }
        }
        free(start);
        free(choice);
        inst_free(&in);
    }
    printf("fs time limit: %d of %d runs truncated, every one within budget and complete\n", truncated, runs);
}

/* Is the point (cost, benefit) on or under object i's reduced candidates' polyline (flat beyond
 * the last)? The hull is an upper hull: no original candidate may lie above it. */
static int under_hull(const struct inst *in, size_t i, double cost, double benefit)
{
    uint32_t f = in->first[i];
    if (in->count[i] == 0 || cost < in->cost_ms[f])
        return 0;
    for (uint32_t k = 0; k + 1 < in->count[i]; ++k) {
        double c0 = in->cost_ms[f + k], c1 = in->cost_ms[f + k + 1];
        if (cost <= c1) {
            double y = in->benefit[f + k] + (in->benefit[f + k + 1] - in->benefit[f + k]) * (cost - c0) / (c1 - c0);
            return benefit <= y + 1e-9 * fmax(1.0, y);
        }
    }
    return benefit <= in->benefit[f + in->count[i] - 1] + 1e-12;
}

static void test_hull_reduce(void)
{
    rng_state = 1234;
    for (int t = 0; t < 300; ++t) {
        struct inst raw = inst_random((size_t)rng_int(1, 10), 9, 1.0, 1, 0);
        size_t bad = 0;
        for (size_t i = 0; i < raw.n; ++i)
            for (uint32_t k = 0; k < raw.count[i]; ++k)
                if (rng_unit() < 0.08) {
                    uint32_t c = raw.first[i] + k;
                    switch (rng_int(0, 3)) {
                    case 0: raw.cost_ms[c] = NAN; break;
                    case 1: raw.benefit[c] = INFINITY; break;
                    case 2: raw.cost_ms[c] = -1.0; break;
                    default: raw.benefit[c] = -0.5; break;
                    }
                    ++bad;
                }
        struct inst in = inst_copy(&raw);
        CHECK(reduce_unbounded(&in) == bad);
        for (size_t i = 0; i < in.n; ++i) {
            uint32_t f = in.first[i];
            CHECK(in.count[i] <= raw.count[i]);
            for (uint32_t k = 0; k < in.count[i]; ++k) {
                CHECK(isfinite(in.cost_ms[f + k]) && in.cost_ms[f + k] >= 0.0);
                CHECK(isfinite(in.benefit[f + k]) && in.benefit[f + k] >= 0.0);
                if (k >= 1) { /* strictly up in cost and benefit */
                    CHECK(in.cost_ms[f + k] > in.cost_ms[f + k - 1] && in.benefit[f + k] > in.benefit[f + k - 1]);
                }
                if (k >= 2) { /* values strictly fall */
                    double v1 = (in.benefit[f + k - 1] - in.benefit[f + k - 2]) / (in.cost_ms[f + k - 1] - in.cost_ms[f + k - 2]);
                    double v2 = (in.benefit[f + k] - in.benefit[f + k - 1]) / (in.cost_ms[f + k] - in.cost_ms[f + k - 1]);
                    CHECK(v2 < v1);
                }
                int found = 0; /* a kept candidate is one of the object's own */
                for (uint32_t j = 0; j < raw.count[i]; ++j) {
                    uint32_t c = raw.first[i] + j;
                    found |= raw.cost_ms[c] == in.cost_ms[f + k] && raw.benefit[c] == in.benefit[f + k] &&
                             raw.level[c] == in.level[f + k];
                }
                CHECK(found);
            }
            int valid = 0;
            for (uint32_t j = 0; j < raw.count[i]; ++j) {
                uint32_t c = raw.first[i] + j;
                if (isfinite(raw.cost_ms[c]) && isfinite(raw.benefit[c]) && raw.cost_ms[c] >= 0 && raw.benefit[c] >= 0) {
                    ++valid;
                    CHECK(under_hull(&in, i, raw.cost_ms[c], raw.benefit[c]));
                }
            }
            CHECK((in.count[i] == 0) == (valid == 0));
        }
        /* What the hull drops the LP never needed. */
        struct lod_problem pr = problem(&raw), pi = problem(&in);
        double lr = lod_lp_bound(&pr, NULL), li = lod_lp_bound(&pi, NULL);
        CHECK_NEAR(li, lr, rel_tol(lr));
        inst_free(&in);
        inst_free(&raw);
    }

    /* Hand cases, one object each. */
    struct inst in = inst_new(1, 4);
    uint8_t choice[1];
    struct lod_result r;
    /* Zero cost: (0, 0) and (0, 5) cost the same; the one that earns more stays. */
    const double zc[] = {0, 0, 2}, zb[] = {0, 5, 6};
    in.count[0] = 3;
    for (int k = 0; k < 3; ++k) {
        in.cost_ms[k] = zc[k];
        in.benefit[k] = zb[k];
        in.level[k] = (uint8_t)(2 - k);
    }
    CHECK(reduce_unbounded(&in) == 0 && in.count[0] == 2 && in.cost_ms[0] == 0 && in.benefit[0] == 5 && in.benefit[1] == 6);
    /* Zero benefit everywhere: only the cheapest is worth keeping. */
    in.count[0] = 3;
    for (int k = 0; k < 3; ++k) {
        in.cost_ms[k] = 1.0 + k;
        in.benefit[k] = 0.0;
        in.level[k] = (uint8_t)(2 - k);
    }
    CHECK(reduce_unbounded(&in) == 0 && in.count[0] == 1 && in.cost_ms[0] == 1.0 && in.level[0] == 2);
    /* Exact ties: the same cost and benefit at two levels; the coarser stays. Then a collinear
     * middle point: its step is worth exactly the next one's, so values would not fall strictly. */
    const double tc[] = {1, 1, 2, 3}, tb[] = {2, 2, 3, 4};
    const uint8_t tl[] = {2, 3, 1, 0};
    in.count[0] = 4;
    for (int k = 0; k < 4; ++k) {
        in.cost_ms[k] = tc[k];
        in.benefit[k] = tb[k];
        in.level[k] = tl[k];
    }
    CHECK(reduce_unbounded(&in) == 0 && in.count[0] == 2 && in.level[0] == 3 && in.level[1] == 0);
    /* Nothing valid: count 0, and the optimizers drop the object without calling it over budget. */
    in.count[0] = 2;
    in.cost_ms[0] = NAN;
    in.cost_ms[1] = INFINITY;
    CHECK(reduce_unbounded(&in) == 2 && in.count[0] == 0);
    in.budget_ms = 10.0;
    optimize(&in, 0, -1, NULL, choice, &r);
    CHECK(choice[0] == LOD_DROPPED && r.dropped == 1 && r.over_budget == 0 && r.cost_ms == 0.0);
    inst_free(&in);
}

/* ---- hard cases: budgets of zero and infinity, zero-cost items, ties, one object, a million ---- */

/* n objects with k candidates each, object i's candidate j costing cost0·2^j (+ i·jitter) and earning
 * benefit0·(2 − 2^−j): a concave hull, so every candidate survives lod_hull_reduce. */
struct hard {
    size_t n;
    uint32_t *id, *first;
    uint8_t *count, *level, *choice_g, *choice_f;
    double *cost, *benefit;
};

static void hard_make(struct hard *h, size_t n, int k, double cost0, double jitter, double benefit0)
{
    h->n = n;
    h->id = malloc(n * sizeof *h->id), h->first = malloc(n * sizeof *h->first);
    h->count = malloc(n), h->choice_g = malloc(n), h->choice_f = malloc(n);
    h->level = malloc(n * (size_t)k), h->cost = malloc(n * (size_t)k * sizeof(double));
    h->benefit = malloc(n * (size_t)k * sizeof(double));
    for (size_t i = 0; i < n; ++i) {
        h->id[i] = (uint32_t)i, h->first[i] = (uint32_t)(i * (size_t)k), h->count[i] = (uint8_t)k;
        for (int j = 0; j < k; ++j) {
            size_t c = i * (size_t)k + (size_t)j;
            h->level[c] = (uint8_t)(k - 1 - j);
            h->cost[c] = cost0 * (double)(1u << j) + jitter * (double)(i % 97);
            h->benefit[c] = benefit0 * (2.0 - 1.0 / (double)(1u << j)) * (1.0 + 1e-3 * (double)(i % 89));
        }
    }
}

static void hard_free(struct hard *h)
{
    free(h->id), free(h->first), free(h->count), free(h->level), free(h->choice_g), free(h->choice_f);
    free(h->cost), free(h->benefit);
}

/* Runs the greedy and fs (from all-cheapest, with time limit limit_us) on budget_ms; both results
 * must be feasible and agree. Returns the greedy's result in *rg. */
static void hard_run(struct hard *h, double budget_ms, double limit_us, struct lod_result *rg)
{
    struct lod_problem p = {h->n, h->id, h->first, h->count, h->cost, h->benefit, h->level, budget_ms, 0.0, NULL};
    size_t cands = 0;
    for (size_t i = 0; i < h->n; ++i)
        cands += h->count[i];
    void *scratch = malloc(lod_scratch_bytes(h->n, cands + 1));
    struct lod_result rf;
    lod_optimize_greedy(&p, scratch, h->choice_g, rg);
    memset(h->choice_f, 0, h->n);
    lod_optimize_fs(&p, limit_us, scratch, h->choice_f, &rf);
    free(scratch);
    CHECK(isfinite(rg->cost_ms) && isfinite(rg->benefit) && rg->cost_ms <= budget_ms);
    CHECK(rf.cost_ms <= budget_ms && !rf.truncated);
    CHECK(memcmp(h->choice_g, h->choice_f, h->n) == 0);
    CHECK_NEAR(rf.benefit, rg->benefit, 1e-9 * (1.0 + rg->benefit));
}

static void test_hard_cases(void)
{
    struct hard h;
    struct lod_result r;
    /* Budget 0 (and negative, and NaN): nothing with a cost fits; everything dropped, said so. */
    const double nothing[] = {0.0, -1.0, NAN};
    for (size_t b = 0; b < 3; ++b) {
        hard_make(&h, 5, 3, 1.0, 0.0, 1.0);
        struct lod_problem p = {h.n, h.id, h.first, h.count, h.cost, h.benefit, h.level, nothing[b], 0.0, NULL};
        void *scratch = malloc(lod_scratch_bytes(h.n, 16));
        lod_optimize_greedy(&p, scratch, h.choice_g, &r);
        CHECK(r.over_budget && r.dropped == 5 && r.cost_ms == 0.0);
        memset(h.choice_f, 0, h.n);
        lod_optimize_fs(&p, 0.0, scratch, h.choice_f, &r);
        CHECK(r.over_budget && r.dropped == 5 && r.cost_ms == 0.0);
        for (size_t i = 0; i < h.n; ++i)
            CHECK(h.choice_g[i] == LOD_DROPPED && h.choice_f[i] == LOD_DROPPED);
        free(scratch);
        hard_free(&h);
    }
    /* Budget +inf, 1e300 and DBL_MAX, and a time limit of +inf: every object at its finest. */
    const double everything[] = {INFINITY, 1e300, DBL_MAX};
    for (size_t b = 0; b < 3; ++b) {
        hard_make(&h, 50, 4, 0.25, 1e-3, 2.0);
        hard_run(&h, everything[b], INFINITY, &r);
        CHECK(!r.over_budget && r.dropped == 0);
        for (size_t i = 0; i < h.n; ++i)
            CHECK(h.choice_g[i] == 3);
        hard_free(&h);
    }
    /* Zero-cost items: free candidates are taken at their best even with a budget of 0. */
    hard_make(&h, 4, 3, 0.0, 0.0, 1.0);
    hard_run(&h, 0.0, 0.0, &r);
    CHECK(!r.over_budget && r.dropped == 0 && r.cost_ms == 0.0);
    struct lod_problem zp = {h.n, h.id, h.first, h.count, h.cost, h.benefit, h.level, 0.0, 0.0, NULL};
    CHECK(lod_lp_bound(&zp, NULL) >= r.benefit - 1e-12);
    hard_free(&h);
    /* Ties: two identical objects, room for one upgrade — the lower object_id gets it, every run. */
    hard_make(&h, 2, 2, 1.0, 0.0, 1.0);
    h.id[0] = 7, h.id[1] = 3;
    h.benefit[2] = h.benefit[0], h.benefit[3] = h.benefit[1]; /* exactly equal values */
    for (int run = 0; run < 3; ++run) {
        hard_run(&h, 3.0, 0.0, &r);
        CHECK(h.choice_g[0] == 0 && h.choice_g[1] == 1);
    }
    hard_free(&h);
    /* A scene of one object: the finest candidate that fits, exactly at the budget's edge. */
    hard_make(&h, 1, 3, 1.0, 0.0, 1.0);
    hard_run(&h, 2.0, 0.0, &r);
    CHECK(h.choice_g[0] == 1 && r.cost_ms == 2.0);
    hard_run(&h, 1.999999, 0.0, &r);
    CHECK(h.choice_g[0] == 0);
    hard_free(&h);
    /* A million objects: the integer cost sums stay exact and within budget; fs equals the greedy. */
    hard_make(&h, 1000000, 3, 1e-4, 1e-7, 1.0);
    hard_run(&h, 150.0, 0.0, &r);
    CHECK(!r.over_budget && r.cost_ms > 149.0);
    hard_free(&h);
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "glpsol") == 0)
        return test_against_glpsol();
    if (argc > 1 && strcmp(argv[1], "hard-cases") == 0) { /* ctest -L hard-cases */
        test_hard_cases();
        test_over_budget();
        test_drop_last();
        test_underused_drop_cases();
        test_exact_errors();
        test_lp_bound_cases();
        return tu_finish("test_lod_optimize hard-cases");
    }
    if (argc > 1) {
        fprintf(stderr, "test_lod_optimize: unknown argument '%s' (none: the solvers and guarantees; glpsol: the "
                        "check against glpsol; hard-cases: the extremes only)\n", argv[1]);
        return 1;
    }
    test_exact_brute_force();
    test_exact_settings_brute_force();
    test_exact_rounding();
    test_exact_errors();
    test_lp_bound_cases();
    test_hull_reduce();
    test_lp_bound_large();
    test_greedy_and_fs_random();
    test_counterexample();
    test_over_budget();
    test_drop_last();
    test_underused_drop_cases();
    test_drop_last_random();
    test_determinism();
    test_fs_previous_frame();
    test_fs_time_limit();
    test_hard_cases();
    return tu_finish("test_lod_optimize");
}
