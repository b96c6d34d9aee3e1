/* hmdlod bench replay: the same head motion through both built-in scenes on the Vive with the
 * selectors none and reddy, in one run, so that their ratios are measured under the same load.
 * Everything measured comes from rpl_run's summary; this file only runs it and formats. */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/bench.h"
#include "replay/replay.h"

#define CORBILLON_DIR "data/traces/corbillon-mmsys18"

static const char *const scenes[] = {"field", "auditorium"};
static const char *const selectors[] = {"none", "reddy"}; /* none first: the ratios' numerator */
enum { N_SCENES = 2, N_SELECTORS = 2, MAX_TRACES = 4 };

struct bench_trace {
    char label[32];
    char path[4200]; /* "" → the built-in clip */
    long frames;     /* 0 → the whole trace */
};

struct replay_bench {
    struct bch_replay_options o; /* as parsed (app/cmd_bench_replay.c) */
    struct bench_trace traces[MAX_TRACES];
    int n_traces;
    struct rpl_summary sum[MAX_TRACES][N_SCENES][N_SELECTORS];
};

/* The built-in clip always (it needs no files); the Corbillon users when the shared folder is there. */
static void choose_traces(struct replay_bench *b)
{
    long corbillon_frames = b->o.frames ? b->o.frames : b->o.quick ? 200 : 600;
    struct bench_trace *t = &b->traces[b->n_traces++];
    snprintf(t->label, sizeof t->label, "built-in clip");
    t->path[0] = '\0';
    t->frames = b->o.frames ? b->o.frames : b->o.quick ? 200 : 0;
    char shared[4096];
    if (bch_find_shared(shared, sizeof shared) != 0) {
        fprintf(stderr, "hmdlod bench replay: note: the shared data folder is absent (%s); built-in clip only\n",
                shared);
        return;
    }
    for (int user = 1; user <= (b->o.quick ? 1 : 3); ++user) {
        t = &b->traces[b->n_traces++];
        snprintf(t->label, sizeof t->label, "corbillon user%d", user);
        snprintf(t->path, sizeof t->path, "%s/" CORBILLON_DIR "/user%d_quaternion.txt", shared, user);
        t->frames = corbillon_frames;
    }
}

/* Every run into its own folder under a fresh temporary one, removed at the end either way. */
static int run_all(struct replay_bench *b)
{
    char tmp[64];
    if (bch_temp_dir("replay", tmp, sizeof tmp) != 0)
        return 1;
    int total = b->n_traces * N_SCENES * N_SELECTORS, run = 0, rc = 0;
    for (int t = 0; t < b->n_traces && rc == 0; ++t)
        for (int sc = 0; sc < N_SCENES && rc == 0; ++sc)
            for (int se = 0; se < N_SELECTORS && rc == 0; ++se) {
                char out_dir[sizeof tmp + 16];
                snprintf(out_dir, sizeof out_dir, "%s/run%02d", tmp, ++run);
                struct rpl_options o;
                rpl_options_defaults(&o);
                o.trace_path = b->traces[t].path[0] ? b->traces[t].path : NULL;
                o.frame.scene = scenes[sc];
                o.frame.display = "vive";
                o.frame.selector = selectors[se];
                o.out_dir = out_dir;
                o.frames = b->traces[t].frames;
                o.frame.object_count = (int)b->o.objects;
                o.frame.render_scale = b->o.render_scale;
                o.frame.quiet = 1;
                fprintf(stderr, "hmdlod bench replay: run %d of %d: %s, %s, %s\n", run, total, b->traces[t].label,
                        scenes[sc], selectors[se]);
                struct hl_error err = {{0}};
                if (rpl_run(&o, &b->sum[t][sc][se], &err) != 0) {
                    fprintf(stderr, "hmdlod bench replay: %s, %s, %s: %s\n", b->traces[t].label, scenes[sc],
                            selectors[se], err.msg);
                    rc = 1;
                }
            }
    bch_temp_dir_remove(tmp);
    return rc;
}

static void print_scene_table(const struct replay_bench *b, int sc)
{
    const struct rpl_summary *first = &b->sum[0][sc][0];
    if (sc == 0)
        bch_emit("\n### %s (%ld objects)\n\n", scenes[sc], b->o.objects);
    else
        bch_emit("\n### %s\n\n", scenes[sc]);
    bch_emit("| trace | selector | frames | frame ms median / p95 / p99 / max | draw ms median | triangles/eye "
               "mean | triangles vs none | acuity evaluations / visible | within %.1f ms |\n",
               first->budget_ms);
    bch_emit("|---|---|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int t = 0; t < b->n_traces; ++t) {
        for (int se = 0; se < N_SELECTORS; ++se) {
            const struct rpl_summary *s = &b->sum[t][sc][se];
            bch_emit("| %s | %s | %ld | %.2f / %.2f / %.2f / %.2f | %.2f | %.0f | %.3f | %.1f / %.1f | %.1f %% |\n",
                       b->traces[t].label, selectors[se], s->frames, s->frame_ms_median, s->frame_ms_p95,
                       s->frame_ms_p99, s->frame_ms_max, s->draw_ms_median, s->triangles_per_eye_mean,
                       s->triangles_relative_to_none, s->acuity_evaluations_mean, s->visible_mean,
                       100.0 * s->deadline_met_fraction);
        }
        const struct rpl_summary *none = &b->sum[t][sc][0], *reddy = &b->sum[t][sc][1];
        bch_emit("| %s | **none/reddy** | | **×%.2f** median | ×%.2f | **×%.2f** | | | |\n", b->traces[t].label,
                   none->frame_ms_median / reddy->frame_ms_median, none->draw_ms_median / reddy->draw_ms_median,
                   none->triangles_per_eye_mean / reddy->triangles_per_eye_mean);
    }
}

static void print_band_table(const struct replay_bench *b)
{
    bch_emit("\n### reddy: share of the finest-LOD triangles drawn, by head speed (frames)\n\n| scene | trace |");
    for (int k = 0; k < RPL_SPEED_BAND_COUNT; ++k) {
        if (k + 1 < RPL_SPEED_BAND_COUNT)
            bch_emit(" %g–%g °/s |", rpl_speed_band_lower_degps[k], rpl_speed_band_lower_degps[k + 1]);
        else
            bch_emit(" ≥%g °/s |", rpl_speed_band_lower_degps[k]);
    }
    bch_emit("\n|---|---|");
    for (int k = 0; k < RPL_SPEED_BAND_COUNT; ++k)
        bch_emit("--:|");
    bch_emit("\n");
    for (int sc = 0; sc < N_SCENES; ++sc)
        for (int t = 0; t < b->n_traces; ++t) {
            const struct rpl_summary *s = &b->sum[t][sc][1];
            bch_emit("| %s | %s |", scenes[sc], b->traces[t].label);
            for (int k = 0; k < RPL_SPEED_BAND_COUNT; ++k) {
                if (s->band_frames[k] > 0 && isfinite(s->band_triangle_share[k]))
                    bch_emit(" %.1f %% (%ld) |", 100.0 * s->band_triangle_share[k], s->band_frames[k]);
                else
                    bch_emit(" – (%ld) |", s->band_frames[k]);
            }
            bch_emit("\n");
        }
}

static void print_notes(const struct replay_bench *b, double wall_s)
{
    const struct rpl_summary *s = &b->sum[0][0][0];
    const char *cpu = strstr(s->renderer, "llvmpipe") ? "llvmpipe on this machine's cores, shared with everything "
                                                         "else running"
                                                       : "the renderer above, on a machine shared with whatever "
                                                         "else runs";
    bch_emit("\nHow measured (replay/run.c, frame/frame.c): %d runs in %.0f s. Each run replays its trace from "
               "the start on a virtual clock at the display's %.0f Hz (frame f at t0 + f / %.0f s, whatever the "
               "wall clock did), both eyes rendered headless at render scale %g of the %s profile's pixels; none always "
               "draws the finest LOD, reddy picks each object's LOD from the acuity model and each level's "
               "measured frequency table (the default reading, narrow: the thickest lost feature, "
               "docs/analysis.md). Frame time = pose + "
               "cull + geometry + select + draw, the draw waited with glFinish; draw = the GL part alone; "
               "percentiles are nearest rank. triangles vs none = triangles drawn / the finest-LOD triangles of "
               "the same frames; none/reddy = none's figure divided by reddy's. Head speed is the trace's angular "
               "speed at each frame. The renderer is %s: timings vary by ±20 %% from run to run (PLATFORM.md), "
               "so compare the ratios within one run rather than figures across runs.\n",
               b->n_traces * N_SCENES * N_SELECTORS, wall_s, 1000.0 / s->budget_ms, 1000.0 / s->budget_ms,
               b->o.render_scale, s->display, cpu);
}

int bch_replay(const struct bch_replay_options *o, int full_argc, char **full_argv)
{
    struct replay_bench b;
    memset(&b, 0, sizeof b);
    b.o = *o;
    choose_traces(&b);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    if (run_all(&b) != 0)
        return 1;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double wall_s = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    if (b.o.results && bch_copy_begin() != 0) {
        fprintf(stderr, "hmdlod bench replay: out of memory\n");
        return 1;
    }
    /* Printed after the runs: the renderer line of the context comes from a summary. */
    bch_emit(BCH_REPLAY_HEADING "\n\n");
    bch_print_context(full_argc, full_argv, b.sum[0][0][0].renderer);
    for (int sc = 0; sc < N_SCENES; ++sc)
        print_scene_table(&b, sc);
    print_band_table(&b);
    print_notes(&b, wall_s);
    return bch_copy_finish(b.o.results, BCH_REPLAY_HEADING, "hmdlod bench replay", 0);
}
