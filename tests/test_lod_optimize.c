/* lod/: the reference solvers (exact dynamic program, LP bound) checked against brute force and,
 * with the argument `glpsol`, against GLPK's glpsol run on written models; and the guarantees the
 * cost-bounded optimizers promise (PAPERS.md §2–4): within budget or an explicit over-budget
 * outcome, at least half of the exact optimum (Mason & Blake's guard, with the counterexample to the
 * plain greedy), identical output for identical input whatever the memory order, the incremental
 * optimizer equal to the from-scratch greedy, a time limit that leaves a feasible complete choice,
 * and the hull reduction they all rely on. Instances come from a seeded generator. */
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

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "glpsol") == 0)
        return test_against_glpsol();
    test_exact_brute_force();
    test_exact_rounding();
    test_exact_errors();
    test_lp_bound_cases();
    return tu_finish("test_lod_optimize");
}
