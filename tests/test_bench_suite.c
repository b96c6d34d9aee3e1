/* The bench suite's rounds (bench/suite.h, issue 30 item 2): the serial order alternates each table's
 * runs round by round and covers every run and round once; a timing cell is the median over rounds,
 * a timing ratio is taken round by round; the foveation runs (issue 32 item 6) reach the replay with
 * their mode and budget and are named by it. Pure: no replay runs here (bench_suite_test.sh runs them). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/suite_internal.h"
#include "test_util.h"

/* Every (run, round) once; within a table's block, round r goes forward when r is even and backward
 * when odd; a block's rounds all come before the next block's. */
static void test_plan_order(int repeats)
{
    struct bch_plan plan;
    struct hl_error err;
    CHECK(bch_plan_make(BCH_QUICK, NULL, "/shared", "/out", 10.0, &plan, &err) == 0);
    if (plan.count == 0)
        return;
    plan.repeats = repeats;
    size_t steps = plan.count * (size_t)repeats;
    int *seen = calloc(steps, sizeof *seen);
    size_t prev_i = 0;
    int prev_repeat = -1, order_ok = 1, block_ok = 1, max_table = 0;
    for (size_t s = 0; s < steps; ++s) {
        int repeat = -1;
        size_t i = bch_plan_step(&plan, s, &repeat);
        CHECK(i < plan.count && repeat >= 0 && repeat < repeats);
        if (i >= plan.count || repeat < 0 || repeat >= repeats)
            break;
        ++seen[i * (size_t)repeats + (size_t)repeat];
        int table = plan.runs[i].table;
        if (table < max_table)
            block_ok = 0; /* a table's block came back after the next had started */
        max_table = table > max_table ? table : max_table;
        if (s > 0 && repeat == prev_repeat && plan.runs[prev_i].table == table)
            order_ok &= repeat % 2 == 0 ? i == prev_i + 1 : i + 1 == prev_i;
        prev_i = i, prev_repeat = repeat;
    }
    int once = 1;
    for (size_t k = 0; k < steps; ++k)
        once &= seen[k] == 1;
    CHECK(once);
    CHECK(order_ok);
    CHECK(block_ok);
    int repeat = 0;
    CHECK(bch_plan_step(&plan, steps, &repeat) == plan.count); /* past the end */
    /* the first table's first run opens round 1, and its first run closes round 2 */
    CHECK(bch_plan_step(&plan, 0, &repeat) == 0 && repeat == 0);
    size_t n1 = 0;
    while (n1 < plan.count && plan.runs[n1].table == plan.runs[0].table)
        ++n1;
    if (repeats >= 2) {
        CHECK(bch_plan_step(&plan, n1, &repeat) == n1 - 1 && repeat == 1);
        CHECK(bch_plan_step(&plan, 2 * n1 - 1, &repeat) == 0 && repeat == 1);
    }
    free(seen);
    bch_plan_free(&plan);
}

static void test_run_dir(void)
{
    char buf[256];
    bch_run_dir("/o", "t1-field-user1-fs", 0, buf, sizeof buf);
    CHECK(!strcmp(buf, "/o/runs/t1-field-user1-fs"));
    bch_run_dir("/o", "t1-field-user1-fs", 2, buf, sizeof buf);
    CHECK(!strcmp(buf, "/o/runs-3/t1-field-user1-fs"));
    bch_runs_dir("/o", 1, buf, sizeof buf);
    CHECK(!strcmp(buf, "/o/runs-2"));
}

/* A run with per-round frame times: frame 0 (shader compiles) is left out of every figure. */
static void fill(struct bch_result *r, double *storage, double first, double rest)
{
    memset(r, 0, sizeof *r);
    r->present = 1;
    r->n = 4;
    storage[0] = first;
    for (int k = 1; k < 4; ++k)
        storage[k] = rest;
    r->frame_ms = storage;
}

/* Table 7's tail: frames 1…100 at 1…100 ms (frame 0, the shader compile, at 1000), budget 50 ms:
 * p99 99 ms (nearest rank), half the frames within; with a second round at twice the times, the
 * medians of the two rounds. */
static void test_frame_tail(void)
{
    double a[101], b[101];
    struct bch_result r, more;
    memset(&r, 0, sizeof r);
    memset(&more, 0, sizeof more);
    a[0] = b[0] = 1000.0;
    for (int i = 1; i <= 100; ++i)
        a[i] = i, b[i] = 2.0 * i;
    r.present = more.present = 1;
    r.n = more.n = 101;
    r.budget_ms = more.budget_ms = 50.0;
    r.frame_ms = a, more.frame_ms = b;
    double p99 = 0.0, within = 0.0;
    bch_frame_tail(&r, &p99, &within);
    CHECK_NEAR(p99, 99.0, 1e-12);
    CHECK_NEAR(within, 0.5, 1e-12);
    r.rounds = 2, r.more = &more; /* round 2: p99 198 ms, 25 % within */
    bch_frame_tail(&r, &p99, &within);
    CHECK_NEAR(p99, 0.5 * (99.0 + 198.0), 1e-12);
    CHECK_NEAR(within, 0.5 * (0.5 + 0.25), 1e-12);
    r.rounds = 1, r.more = NULL, r.n = 1; /* frame 0 alone: nothing to say */
    bch_frame_tail(&r, &p99, &within);
    CHECK(isnan(p99) && isnan(within));
}

static void test_timing(void)
{
    /* none: 10, 20, 12 ms in rounds 1–3; reddy: 5, 16, 6. Medians: none 12, reddy 6, their ratio 2.
     * Per round: 2.0, 1.25, 2.0 → median 2.0, min 1.25. With round 3 of reddy missing the median
     * of the ratios is (2.0 + 1.25) / 2. */
    double fa[3][4], fb[3][4];
    struct bch_result none, reddy, none_more[2], reddy_more[2];
    fill(&none, fa[0], 1000.0, 10.0);
    fill(&none_more[0], fa[1], 1000.0, 20.0);
    fill(&none_more[1], fa[2], 1000.0, 12.0);
    fill(&reddy, fb[0], 1000.0, 5.0);
    fill(&reddy_more[0], fb[1], 1000.0, 16.0);
    fill(&reddy_more[1], fb[2], 1000.0, 6.0);
    none.rounds = reddy.rounds = 3;
    none.more = none_more, reddy.more = reddy_more;
    CHECK_NEAR(bch_timing(&none, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)), 12.0, 1e-12);
    CHECK_NEAR(bch_timing(&reddy, BCH_STAT_MAX, BCH_COLUMN(frame_ms)), 6.0, 1e-12);
    CHECK_NEAR(bch_timing(&reddy, BCH_STAT_SD, BCH_COLUMN(frame_ms)), 0.0, 1e-12);
    struct bch_spread sp;
    bch_timing_ratio(&none, &reddy, BCH_STAT_MEAN, BCH_COLUMN(frame_ms), &sp);
    CHECK(sp.n == 3);
    CHECK_NEAR(sp.median, 2.0, 1e-12);
    CHECK_NEAR(sp.min, 1.25, 1e-12);
    CHECK_NEAR(sp.max, 2.0, 1e-12);
    reddy_more[1].present = 0;
    bch_timing_ratio(&none, &reddy, BCH_STAT_MEAN, BCH_COLUMN(frame_ms), &sp);
    CHECK(sp.n == 2);
    CHECK_NEAR(sp.median, 0.5 * (2.0 + 1.25), 1e-12);
    CHECK_NEAR(bch_timing(&reddy, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)), 0.5 * (5.0 + 16.0), 1e-12);
    /* one round: the run's own figure; a column the run lacks: NaN */
    none.rounds = 1, none.more = NULL;
    CHECK_NEAR(bch_timing(&none, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)), 10.0, 1e-12);
    CHECK(isnan(bch_timing(&none, BCH_STAT_MEAN, BCH_COLUMN(optimizer_us))));
    CHECK(isnan(bch_timing(NULL, BCH_STAT_MEAN, BCH_COLUMN(frame_ms))));
}

/* The quick plan's layered and adaptive runs: --foveation and the budget in their replay arguments,
 * their table label; per gaze model, over the same budgets as plain fs. */
static int argv_has(const char *const *argv, int argc, const char *a, const char *b)
{
    for (int i = 0; i + 1 < argc; ++i)
        if (!strcmp(argv[i], a) && (!b || !strcmp(argv[i + 1], b)))
            return 1;
    return 0;
}

static void test_foveation_runs(void)
{
    struct bch_plan plan;
    struct hl_error err;
    CHECK(bch_plan_make(BCH_QUICK, NULL, "/shared", "/out", 10.0, &plan, &err) == 0);
    int fixed = 0, adaptive = 0, plain_fs = 0, t1_fixed = 0;
    for (size_t i = 0; i < plan.count; ++i) {
        const struct bch_run *run = &plan.runs[i];
        char storage[BCH_MAX_ARGS][BCH_ARG_SIZE], label[48];
        const char *argv[BCH_MAX_ARGS];
        int argc = bch_run_argv(&plan, run, "/out/x", storage, argv, BCH_MAX_ARGS);
        int has_fov = argv_has(argv, argc, "--foveation", NULL);
        CHECK(has_fov == (run->foveation[0] != 0));
        if (run->table == 2 && !strcmp(run->foveation, "fixed")) {
            ++fixed;
            CHECK(!strcmp(run->selector, "fs") && argv_has(argv, argc, "--foveation", "fixed"));
            CHECK(argv_has(argv, argc, "--budget-ms", NULL) && argv_has(argv, argc, "--reference", NULL));
            CHECK(!strcmp(bch_run_label(run, label, sizeof label), "fs+fixed"));
        } else if (run->table == 2 && !strcmp(run->foveation, "adaptive")) {
            ++adaptive;
            CHECK(!strcmp(run->selector, "static") && argv_has(argv, argc, "--budget-ms", NULL));
            CHECK(!strcmp(bch_run_label(run, label, sizeof label), "static+adaptive"));
        } else if (run->table == 2 && !strcmp(run->selector, "fs")) {
            ++plain_fs;
        } else if (run->table == 1 && !strcmp(run->foveation, "fixed")) {
            ++t1_fixed;
        }
    }
    CHECK(fixed > 0 && fixed == plain_fs && adaptive == plain_fs);
    CHECK(t1_fixed == 2); /* quick: user1, auditorium and field */
    bch_plan_free(&plan);
}

int main(void)
{
    test_plan_order(1);
    test_plan_order(2);
    test_plan_order(3);
    test_run_dir();
    test_timing();
    test_frame_tail();
    test_foveation_runs();
    return tu_finish("test_bench_suite");
}
