/* hmdlod bench optimizer: the cost-bounded optimizers' time per frame on the embeddable core alone
 * (acuity + lod; no GL), under a real head trace at 90 Hz. Funkhouser & Séquin's incremental
 * optimizer (fs, §6) against the from-scratch greedy on the same frames, cold start, the share of
 * the LP bound, time against the turn between frames and against the budget as Nirenstein et al.
 * §5.1–5.3 measured it, the time limit (§5.5) and the per-frame work as the full scene grows with a
 * fixed budget (§5.7, Fig. 9). The frame's problem is built in bench/bench_optimizer_frame.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "bench/bench_optimizer_runs.h"


#define OPT_TRACE "data/traces/corbillon-mmsys18/user2_quaternion.txt"

enum { N_SIZES = 3, N_BUDGETS = 4, N_SCALES = 3 };
static const uint32_t sizes[N_SIZES] = {1000, 10000, 100000};
static const double budget_factor[N_BUDGETS] = {0.25, 0.5, 1.0, 2.0};
static const uint32_t scale_objects[N_SCALES] = {10000, 100000, 1000000};
static const double scale_far_m = 50.0;   /* fixed view distance of the scaling table */

/* mb (Mason & Blake's hierarchical optimizer) runs in the trace table on the same frames, the objects
 * as a tree of leaves; the other tables time fs. */
#define BCH_OPT_HAVE_MB 1

/* ---- the bench ----------------------------------------------------------------------------------- */

static const char *goal(int met) { return met ? "met" : "**not met**"; }

int bch_optimizer(const struct bch_optimizer_options *options, int full_argc, char **full_argv)
{
    struct bch_optimizer_options o = *options;
    char trace_buf[4200];
    struct hl_error err = {{0}};
    struct hmd_profile display;
    if (hmd_profile_load("vive", &display, &err) != 0) {
        fprintf(stderr, "hmdlod bench optimizer: %s\n", err.msg);
        return 1;
    }
    const char *trace_label = o.trace;
    if (!o.trace) {
        char shared[4096];
        if (bch_find_shared(shared, sizeof shared) != 0) {
            fprintf(stderr, "hmdlod bench optimizer: the shared data folder is absent (%s); give --trace FILE\n", shared);
            return 1;
        }
        snprintf(trace_buf, sizeof trace_buf, "%s/" OPT_TRACE, shared);
        o.trace = trace_buf;
        trace_label = "Corbillon MMSys'18 user2";
    }
    struct opt_trace tr;
    if (rpl_trace_load(o.trace, &tr.t, &err) != 0) {
        fprintf(stderr, "hmdlod bench optimizer: %s\n", err.msg);
        return 1;
    }
    tr.start_s = tr.t.time_s[0];
    tr.span_s = tr.t.time_s[tr.t.count - 1] - tr.start_s;
    /* The runs index frames as long: a span of 1e300 s must be refused, not converted (C11 6.3.1.4). */
    if (!(tr.span_s * BCH_OPT_RATE_HZ < (double)RPL_MAX_FRAMES)) {
        fprintf(stderr, "hmdlod bench optimizer: %s: a span of %.9g s is more than %ld frames at %g Hz\n", o.trace,
                tr.span_s, (long)RPL_MAX_FRAMES, (double)BCH_OPT_RATE_HZ);
        rpl_trace_free(&tr.t);
        return 1;
    }
    struct bch_opt_view view;
    bch_opt_view_init(&view, &display);
    if (o.has_hysteresis)
        view.benefit.hysteresis_per_level = o.hysteresis;

    int rc = 1;
    struct opt_case cases[N_SIZES];
    memset(cases, 0, sizeof cases);
    struct size_row rows[N_SIZES], rows_still[N_SIZES];
    struct turn_row turns[BCH_OPT_TURN_BINS];
    struct size_row budgets[N_BUDGETS];
    struct size_row limited[2];
    struct scale_row scales[N_SCALES];
    long limit_n = 0;
    double *limit_all = malloc((size_t)(2 * o.frames + BCH_OPT_TURN_BINS * o.pairs) * sizeof(double));
    if (!limit_all)
        goto done;
    for (int k = 0; k < N_SIZES; ++k) {
        fprintf(stderr, "hmdlod bench optimizer: %u visible objects, %ld frames\n", sizes[k], o.frames);
        if (bch_opt_setup_case(&cases[k], sizes[k], &view, &tr, (uint64_t)o.seed) != 0 ||
            bch_opt_run_trace(&cases[k], &view, &tr, o.frames, cases[k].budget_ms, 0.0, &rows[k], NULL) != 0) {
            fprintf(stderr, "hmdlod bench optimizer: out of memory for %u objects\n", sizes[k]);
            goto done;
        }
    }
    /* The same frames with no hysteresis: with Funkhouser's accuracy nearly saturated (1 − 0.5/v² is
     * above 0.999 from 26 vertices), hysteresis alone can hold every level where it was, and fs then
     * has nothing to do; this run shows the optimizer's work when levels are free to move. */
    struct bch_opt_view view_free = view;
    view_free.benefit.hysteresis_per_level = 0.0;
    int run_free = view.benefit.hysteresis_per_level > 0;
    for (int k = 0; k < N_SIZES && run_free; ++k) {
        fprintf(stderr, "hmdlod bench optimizer: %u visible objects, no hysteresis\n", sizes[k]);
        if (bch_opt_run_trace(&cases[k], &view_free, &tr, o.frames, cases[k].budget_ms, 0.0, &rows_still[k], NULL) != 0)
            goto done;
    }
    struct opt_case *c10k = &cases[1];
    const double budget_10k_ms = c10k->budget_ms; /* kept for the tables: the cases are freed first */
    fprintf(stderr, "hmdlod bench optimizer: turns, %ld pairs per bin\n", o.pairs);
    if (bch_opt_run_turns(c10k, &view, &tr, o.pairs, c10k->budget_ms, 0.0, (uint64_t)o.seed, turns, NULL, NULL) != 0)
        goto done;
    fprintf(stderr, "hmdlod bench optimizer: budgets\n");
    for (int b = 0; b < N_BUDGETS; ++b)
        if (bch_opt_run_trace(c10k, &view, &tr, o.frames, budget_factor[b] * c10k->budget_ms, 0.0, &budgets[b], NULL) != 0)
            goto done;
    struct turn_row limited_turns[BCH_OPT_TURN_BINS];
    if (o.limit_us > 0) {
        fprintf(stderr, "hmdlod bench optimizer: time limit %.0f µs\n", o.limit_us);
        for (int k = 0; k < 2; ++k)
            if (bch_opt_run_trace(&cases[k + 1], &view, &tr, o.frames, cases[k + 1].budget_ms, o.limit_us, &limited[k],
                          limit_all + limit_n) != 0)
                goto done;
            else
                limit_n += o.frames - 1;
        if (bch_opt_run_turns(c10k, &view, &tr, o.pairs, c10k->budget_ms, o.limit_us, (uint64_t)o.seed, limited_turns,
                      limit_all, &limit_n) != 0)
            goto done;
    }
    for (int k = 0; k < N_SIZES; ++k)
        bch_opt_free_case(&cases[k]);
    memset(cases, 0, sizeof cases);
    struct bch_opt_view far_view = view;
    far_view.far_m = scale_far_m;
    double scale_budget_ms = 0;
    for (int k = 0; k < N_SCALES; ++k) {
        fprintf(stderr, "hmdlod bench optimizer: scaling, %u objects\n", scale_objects[k]);
        if (bch_opt_run_scale(scale_objects[k], &far_view, &tr, o.frames, (uint64_t)o.seed, &scale_budget_ms, &scales[k]) != 0)
            goto done;
    }

    if (o.results && bch_copy_begin() != 0) {
        fprintf(stderr, "hmdlod bench optimizer: out of memory\n");
        goto done;
    }
    bch_emit(BCH_OPTIMIZER_HEADING "\n\n");
    bch_print_context(full_argc, full_argv, NULL);
    bch_emit("- head motion: %s at %.0f Hz, %ld frames per run; eyes: %s; 4 LODs per object; no GL (acuity + lod only)\n",
               trace_label, BCH_OPT_RATE_HZ, o.frames, display.name);
    char load[128] = "unknown";
    FILE *lf = fopen("/proc/loadavg", "r");
    if (lf) {
        if (fgets(load, sizeof load, lf))
            load[strcspn(load, "\n")] = '\0';
        fclose(lf);
    }
    bch_emit("- load average at the end (1, 5, 15 min; other work on the machine): %s\n", load);
    bch_emit("- benefit: base error %.2f, m %.0f (samples = vertices), hysteresis %.3f per level\n\n", view.benefit.base_error,
               view.benefit.exponent_m, view.benefit.hysteresis_per_level);
    bch_emit("### fs against the from-scratch greedy, per frame\n\n");
    bch_emit("| objects visible (scene) | budget ms | fs µs median / p99 | greedy µs median / p99 | **greedy / fs** (median) | "
               "cold start µs fs / greedy | fs iterations median / p99 | benefit / LP bound median / min | fs = greedy | "
               "cost > budget | frames with drops | build µs median | mb µs median / p99 | mb benefit / LP min |\n");
    bch_emit("|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int pass = 0; pass < 1 + run_free; ++pass)
        for (int k = 0; k < N_SIZES; ++k) {
            const struct size_row *r = pass ? &rows_still[k] : &rows[k];
            if (pass && k == 0)
                bch_emit("| *the same, hysteresis 0* | | | | | | | | | | | | | |\n");
            bch_emit("| %.0f (%u) | %.3f | %.1f / %.1f | %.1f / %.1f | **×%.1f** | %.1f / %.1f | %.0f / %.0f | %.4f / %.4f | "
                       "%.1f %% | %ld | %ld | %.0f | %.1f / %.1f | %.4f |\n",
                       r->visible_mean, r->scene_objects, r->budget_ms, r->fs_med, r->fs_p99, r->gr_med, r->gr_p99,
                       r->ratio_med, r->cold_fs_us, r->cold_gr_us, r->iter_med, r->iter_p99, r->lp_med, r->lp_min,
                       100.0 * r->equal_share, r->over_budget, r->drop_frames, r->build_med, r->mb_med, r->mb_p99,
                       r->mb_lp_min);
        }
    bch_emit("\nmb (Mason & Blake, hierarchical): %s\n", BCH_OPT_HAVE_MB ? "its columns above, on the same frames with the objects as a flat tree (no groups: it must equal the greedy; the domes scene in replay exercises the hierarchy)" : "not in this build (lod_optimize_mb is not on this branch yet); the hook is marked in bench/bench_optimizer.c");
    const struct size_row *r10 = &rows[1], *r100 = &rows[2];
    double lp_min_all = fmin(fmin(rows[0].lp_min, r10->lp_min), r100->lp_min);
    bch_emit("\nGoals (issue 13): 10k fs median %.1f µs ≤ 100: %s; cold start %.2f ms ≤ 5: %s; 100k fs median %.1f µs ≤ "
               "1000: %s; greedy/fs at 10k ×%.1f ≥ 20: %s; benefit ≥ 99 %% of the LP bound on every frame (min %.2f %%): %s.\n",
               r10->fs_med, goal(r10->fs_med <= 100), r10->cold_fs_us * 1e-3, goal(r10->cold_fs_us <= 5000), r100->fs_med,
               goal(r100->fs_med <= 1000), r10->ratio_med, goal(r10->ratio_med >= 20), 100 * lp_min_all,
               goal(lp_min_all >= 0.99));
    if (run_free)
        bch_emit("With hysteresis 0: 10k fs median %.1f µs, greedy/fs ×%.1f; 100k fs median %.1f µs, greedy/fs ×%.1f; "
                   "LP share min %.2f %%.\n",
                   rows_still[1].fs_med, rows_still[1].ratio_med, rows_still[2].fs_med, rows_still[2].ratio_med,
                   100 * fmin(fmin(rows_still[0].lp_min, rows_still[1].lp_min), rows_still[2].lp_min));

    bch_emit("\n### The perceptual ceiling per frame: contrast against acuity (issue 31)\n\n");
    bch_emit("| objects visible | acuity (lod_select_reddy) µs median / p99 | contrast (lod_select_contrast) µs median / p99 | "
               "**contrast / acuity** (median of per-frame ratios) | CSF lookups per object | objects coarser under contrast |\n"
               "|--:|--:|--:|--:|--:|--:|\n");
    for (int k = 0; k < N_SIZES; ++k) {
        const struct size_row *r = &rows[k];
        bch_emit("| %.0f | %.1f / %.1f | %.1f / %.1f | **×%.2f** | %.2f | %.1f %% |\n", r->visible_mean, r->sel_acuity_med,
                   r->sel_acuity_p99, r->sel_contrast_med, r->sel_contrast_p99, r->sel_ratio_med, r->sel_lookups_per_object,
                   100 * r->sel_coarser_share);
    }
    bch_emit("\nBoth on the frames of the first table, timed apart on the same arrays in alternating order; the chains carry "
               "lost-contrast spectra of 7 bands as `hmdlod analyze` measured them on the field object and the chair; "
               "castle CSF at 20 cd/m², k 2, ξ of the display. Goal (issue 31): contrast ≤ 2× acuity at 10k objects "
               "(×%.2f): %s.\n", r10->sel_ratio_med, goal(r10->sel_ratio_med <= 2.0));

    bch_emit("\n### fs time against the turn between frames (10k objects, budget %.3f ms)\n\n", budget_10k_ms);
    bch_emit("| turn ° | pairs | objects newly visible | fs µs median / p99 / max | fs iterations median / p99 | greedy µs median | "
               "benefit / LP bound min |\n|--|--:|--:|--:|--:|--:|--:|\n");
    for (int b = 0; b < BCH_OPT_TURN_BINS; ++b) {
        const struct turn_row *t = &turns[b];
        bch_emit("| %.0f–%.0f | %ld | %.1f %% | %.1f / %.1f / %.1f | %.0f / %.0f | %.1f | %.4f |\n", bch_opt_turn_bin_deg[b],
                   bch_opt_turn_bin_deg[b + 1], t->pairs, 100 * t->visible_changed, t->fs_med, t->fs_p99, t->fs_max, t->iter_med,
                   t->iter_p99, t->gr_med, t->lp_min);
    }
    bch_emit("\n### fs time against the budget (10k objects)\n\n");
    bch_emit("| budget | ms | fs µs median / p99 | fs iterations median / p99 | greedy µs median | greedy / fs | cold start µs | "
               "benefit / LP bound min | frames with drops |\n|--|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int b = 0; b < N_BUDGETS; ++b) {
        const struct size_row *r = &budgets[b];
        bch_emit("| %.2f× | %.3f | %.1f / %.1f | %.0f / %.0f | %.1f | ×%.1f | %.1f | %.4f | %ld of %ld |\n",
                   budget_factor[b], r->budget_ms, r->fs_med, r->fs_p99, r->iter_med, r->iter_p99, r->gr_med, r->ratio_med,
                   r->cold_fs_us, r->lp_min, r->drop_frames, r->frames);
    }
    if (o.limit_us > 0) {
        long turn_n = limit_n - 2 * (o.frames - 1);
        double turn_p999 = bch_opt_percentile(limit_all + 2 * (o.frames - 1), turn_n, 0.999);
        double p999 = bch_opt_percentile(limit_all, limit_n, 0.999);
        bch_emit("\n### fs with the time limit %.0f µs (Nirenstein et al. §5.5)\n\n", o.limit_us);
        bch_emit("| frames | fs µs median / p99 / **p99.9** | p99.9 / limit | set-up µs median / p99.9 | after set-up µs p99.9 "
                   "/ limit | fs iterations median | benefit / LP bound median / min | cold start µs |\n"
                   "|--|--:|--:|--:|--:|--:|--:|--:|\n");
        for (int k = 0; k < 2; ++k)
            bch_emit("| %uk objects, trace | %.1f / %.1f / **%.1f** | ×%.2f | %.1f / %.1f | %.1f / ×%.2f | %.0f | %.4f / %.4f "
                       "| %.1f |\n", sizes[k + 1] / 1000, limited[k].fs_med, limited[k].fs_p99, limited[k].p999,
                       limited[k].p999 / o.limit_us, limited[k].setup_med, limited[k].setup_p999, limited[k].after_p999,
                       limited[k].after_p999 / o.limit_us, limited[k].iter_med, limited[k].lp_med, limited[k].lp_min,
                       limited[k].cold_fs_us);
        const struct turn_row *lt = &limited_turns[BCH_OPT_TURN_BINS - 1];
        bch_emit("| 10k objects, all turn pairs (60–180° shown) | %.1f / %.1f / **%.1f** (all bins) | ×%.2f | | | %.0f | – / %.4f "
                   "| |\n", lt->fs_med, lt->fs_p99, turn_p999, turn_p999 / o.limit_us, lt->iter_med, lt->lp_min);
        bch_emit("\np99.9 of all %ld limited calls: %.1f µs = %.2f × the limit (goal ≤ 1.10: %s). The limit is checked "
                   "before every iteration, and past it no O(n) heap rebuild is started (the iteration's raise is taken back "
                   "instead); fs's set-up (O(n) over the objects: it makes last frame's choice valid and prices it) runs "
                   "before the first check, so the limit bounds the call only where the set-up fits well inside it. A "
                   "wall-clock p99.9 on a shared machine also holds its preemptions.\n",
                   limit_n, p999, p999 / o.limit_us, goal(p999 <= 1.1 * o.limit_us));
    }
    bch_emit("\n### Per-frame work as the full scene grows (fixed budget %.3f ms, view distance %.0f m)\n\n", scale_budget_ms,
               scale_far_m);
    bch_emit("| scene objects | groups | visible mean | cull µs median | build µs median | fs µs median | **total µs median** / p99 |\n"
               "|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int k = 0; k < N_SCALES; ++k) {
        const struct scale_row *s = &scales[k];
        bch_emit("| %u | %u | %.0f | %.1f | %.1f | %.1f | **%.1f** / %.1f |\n", s->objects, s->groups, s->visible_mean,
                   s->cull_med, s->build_med, s->fs_med, s->total_med, s->total_p99);
    }
    bch_emit("| growth ×%.0f | | ×%.2f | ×%.2f | ×%.2f | ×%.2f | **×%.2f** |\n",
               (double)scales[N_SCALES - 1].objects / scales[0].objects, scales[N_SCALES - 1].visible_mean / fmax(scales[0].visible_mean, 1e-9),
               scales[N_SCALES - 1].cull_med / scales[0].cull_med, scales[N_SCALES - 1].build_med / scales[0].build_med,
               scales[N_SCALES - 1].fs_med / scales[0].fs_med, scales[N_SCALES - 1].total_med / scales[0].total_med);
    bch_emit("\nHow measured (bench/bench_optimizer.c, bench/bench_optimizer_frame.c, bench/bench_optimizer_runs.c): each frame takes the trace's head pose "
               "(slerp, looped) and does what an engine embedding acuity + lod does: cull (scn_cull against the union of "
               "both eye frusta), then acu_compute_geometry, acu_compute_pixels, lod_select_reddy (the ceiling), each "
               "level's cost from an additive model with llvmpipe-like coefficients (assumed: c0 1.5 ms, 4e-5 ms/triangle, "
               "1e-5 ms/vertex, 1.5e-6 ms/pixel, 0.01 ms/draw), lod_benefit_fill with hysteresis from last frame's levels, "
               "lod_hull_reduce. fs (lod_optimize_fs from lod_choice_start of last frame's levels) and the from-scratch "
               "greedy (lod_optimize_greedy) then solve the same problem, timed with CLOCK_MONOTONIC around each call; the "
               "LP bound is lod_lp_bound. Objects: four synthetic 4-level chains (40–20 000 triangles) on a shell 4–40 m "
               "around the viewer (Fibonacci directions, radii 0.2–1 m, seed %ld), the shell sized so that about the "
               "stated count is visible at the trace's first pose. The budget is fixed per size: the cheapest choice's "
               "cost plus %.0f %% of the way to every object at its ceiling on the first frame. Cold start = the first "
               "frame (every object unseen). Turns: three coherent frames, then the same pose snapped by a yaw in the bin "
               "(alternating sides, angular velocity kept); fs starts from the third frame's levels. Scaling: bench "
               "cull's ground grid (2 m apart, quadtree groups of 4 × 4) 1×, 10×, 100× with a far plane at %.0f m, so the "
               "visible part stays the same while the scene grows; timed = cull + build + fs. A shared machine: compare "
               "the ratios within one run.\n",
               o.seed, 100 * BCH_OPT_BUDGET_SHARE, scale_far_m);
    rc = bch_copy_finish(o.results, BCH_OPTIMIZER_HEADING, "hmdlod bench optimizer", 0);
done:
    for (int k = 0; k < N_SIZES; ++k)
        bch_opt_free_case(&cases[k]);
    free(limit_all);
    rpl_trace_free(&tr.t);
    return rc;
}
