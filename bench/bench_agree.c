/* hmdlod bench agree: does a session measure the same in one process whatever ran before it? The
 * same session twice (A and A′, identical options) in alternated repeats, and their mean frame times
 * compared with the spread the repeats themselves show (issue 30 item 2). A benchmark, not a timed
 * test: the figures follow the machine's load, so they are printed with a verdict, not asserted. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "replay/replay.h"

/* The goal: two identical sessions in one process agree in mean frame time within 5 %. */
#define AGREE_TOLERANCE 0.05

struct agree_config {
    const char *scene, *selector;
};
/* field/none is the demo's first session; auditorium/reddy runs the acuity model on the other scene. */
static const struct agree_config configs[] = {{"field", "none"}, {"auditorium", "reddy"}};
enum { N_CONFIGS = (int)(sizeof configs / sizeof configs[0]) };

struct agree_result {
    struct rpl_summary warmup; /* the process's first session: run, reported, left out (first config only) */
    struct rpl_summary *sums;  /* [repeats][2]: A, A′ */
    struct bch_spread a, a2, ratio;
    double spread;             /* the larger of A's and A′'s (max − min) / median over the repeats */
};

static void config_options(const struct bch_agree_options *o, const struct agree_config *c, struct rpl_options *out)
{
    rpl_options_defaults(out);
    out->frame.scene = c->scene;
    out->frame.display = "vive";
    out->frame.selector = c->selector;
    out->frame.render_scale = o->render_scale;
    out->frames = o->frames; /* 0: the whole built-in clip */
}

static int measure(const struct bch_agree_options *o, int c, struct agree_result *res)
{
    struct rpl_options pair[2];
    config_options(o, &configs[c], &pair[0]);
    pair[1] = pair[0];
    if (c == 0) {
        /* Warm-up: whatever the process pays once (driver start, first compiles, caches) falls here,
         * and its figure beside the timed ones shows how much that is. */
        fprintf(stderr, "hmdlod bench agree: warm-up session (%s, %s)\n", configs[c].scene, configs[c].selector);
        if (bch_alternate_run(pair, 1, 1, &res->warmup, "hmdlod bench agree") != 0)
            return 1;
    }
    res->sums = calloc((size_t)o->repeats * 2, sizeof *res->sums);
    if (!res->sums) {
        fprintf(stderr, "hmdlod bench agree: out of memory\n");
        return 1;
    }
    if (bch_alternate_run(pair, 2, (int)o->repeats, res->sums, "hmdlod bench agree") != 0)
        return 1;
    bch_mean_spread(res->sums, 2, (int)o->repeats, 0, &res->a);
    bch_mean_spread(res->sums, 2, (int)o->repeats, 1, &res->a2);
    bch_ratio_spread(res->sums, 2, (int)o->repeats, 0, 1, &res->ratio);
    res->spread = fmax((res->a.max - res->a.min) / res->a.median, (res->a2.max - res->a2.min) / res->a2.median);
    return 0;
}

static void print_table(const struct bch_agree_options *o, const struct agree_result *res)
{
    bch_emit("\n| session | frames | A ms median [min–max] | A′ ms median [min–max] | A/A′ median [min–max] | "
             "spread | within 5 %% | within spread | verdict |\n");
    bch_emit("|---|--:|--:|--:|--:|--:|:-:|:-:|:-:|\n");
    for (int c = 0; c < N_CONFIGS; ++c) {
        const struct agree_result *r = &res[c];
        double off = fabs(r->ratio.median - 1.0);
        int within_goal = off <= AGREE_TOLERANCE, within_spread = off <= r->spread;
        bch_emit("| %s, built-in clip, vive, %s | %ld | %.2f [%.2f–%.2f] | %.2f [%.2f–%.2f] | %.3f [%.3f–%.3f] | "
                 "%.1f %% | %s | %s | **%s** |\n",
                 configs[c].scene, configs[c].selector, r->sums[0].frames, r->a.median, r->a.min, r->a.max,
                 r->a2.median, r->a2.min, r->a2.max, r->ratio.median, r->ratio.min, r->ratio.max, 100.0 * r->spread,
                 within_goal ? "yes" : "no", within_spread ? "yes" : "no",
                 within_goal && within_spread ? "PASS" : "FAIL");
    }
    /* Each repeat's ratio with the session that ran first in it: an order effect shows as ratios that
     * flip with the order, a difference between A and A′ as ratios on one side whatever the order. */
    bch_emit("\nA/A′ per repeat (the session that ran first):");
    for (int c = 0; c < N_CONFIGS; ++c) {
        const struct agree_result *r = &res[c];
        bch_emit("%s %s, %s:", c ? ";" : "", configs[c].scene, configs[c].selector);
        for (long k = 0; k < o->repeats; ++k)
            bch_emit(" %.3f (%s)", r->sums[2 * k].frame_ms_mean_after_first / r->sums[2 * k + 1].frame_ms_mean_after_first,
                     bch_alternate_index((int)k, 0, 2) == 0 ? "A" : "A′");
    }
    bch_emit(".\n");
    const struct rpl_summary *w = &res[0].warmup;
    bch_emit("\nWarm-up (the process's first session, %s, %s, left out): %.2f ms mean, %.3f × the timed A's "
             "median.\n",
             configs[0].scene, configs[0].selector, w->frame_ms_mean_after_first,
             w->frame_ms_mean_after_first / res[0].a.median);
    char order[128];
    const char *const names[2] = {"A", "A′"};
    bch_alternate_order(2, names, order, sizeof order);
    bch_emit("\nHow measured (bench/bench_agree.c, bench/alternate.c): one warm-up session first (the first "
             "row's, left out), then per row %ld alternated repeats of A and A′ — identical options — in one "
             "process, order %s, each session opened fresh (rpl_run: scene, renderer, selector), frame 0 left out "
             "of every mean (the driver compiles its shaders there). Render scale %g. A ms = mean frame time per "
             "session, median over the repeats [min–max]; A/A′ = median of the per-repeat ratios [min–max]; "
             "spread = the larger of A's and A′'s (max − min) / median over the repeats, the session-to-session "
             "noise the repeats show. PASS when |A/A′ − 1| ≤ 5 %% (the goal) and ≤ the spread (no difference "
             "beyond the noise). Timings follow the machine's load: judge on a machine left to the bench.\n",
             o->repeats, order, o->render_scale);
}

int bch_agree(const struct bch_agree_options *o, int full_argc, char **full_argv)
{
    struct agree_result res[N_CONFIGS];
    memset(res, 0, sizeof res);
    int rc = 0;
    for (int c = 0; c < N_CONFIGS && rc == 0; ++c)
        rc = measure(o, c, &res[c]);
    if (rc == 0 && o->results && bch_copy_begin() != 0) {
        fprintf(stderr, "hmdlod bench agree: out of memory\n");
        rc = 1;
    }
    if (rc == 0) {
        bch_emit(BCH_AGREE_HEADING "\n\n");
        bch_print_context(full_argc, full_argv, res[0].sums[0].renderer);
        print_table(o, res);
        rc = bch_copy_finish(o->results, BCH_AGREE_HEADING, "hmdlod bench agree", 0);
    }
    for (int c = 0; c < N_CONFIGS; ++c)
        free(res[c].sums);
    return rc;
}
