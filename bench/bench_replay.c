/* hmdlod bench replay: the same head motion through both built-in scenes on the Vive with the
 * selectors none and reddy — reddy under both visibility criteria, contrast and acuity
 * (docs/visibility.md), and under the gaze models vor and head — in one run, so that their ratios are measured under the same load: per
 * trace and scene, none and reddy in alternated repeats (bench/alternate.c) after one warm-up session.
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
/* The sessions compared: none first (the ratios' numerator; it draws the finest LOD whatever the eye
 * does), then reddy under each criterion, with the eye held on the world (vor, replay's default
 * without an eye tracker) and fixed in the head (head: every turn is retinal motion). */
static const char *const selectors[] = {"none", "reddy", "reddy", "reddy", "reddy"};
static const char *const criteria[] = {"contrast", "contrast", "acuity", "contrast", "acuity"};
static const char *const gazes[] = {"vor", "vor", "vor", "head", "head"};
static const char *const session_labels[] = {"none", "reddy contrast", "reddy acuity", "reddy contrast head",
                                             "reddy acuity head"};
enum { N_SCENES = 2, N_SELECTORS = 5, MAX_TRACES = 4 };
#define WHO "hmdlod bench replay"

struct bench_trace {
    char label[32];
    char path[4200]; /* "" → the built-in clip */
    long frames;     /* 0 → the whole trace */
};

struct replay_bench {
    struct bch_replay_options o; /* as parsed (app/cmd_bench_replay.c) */
    struct bench_trace traces[MAX_TRACES];
    int n_traces;
    int repeats;
    /* [trace][scene][repeat * N_SELECTORS + selector] (bch_alternate_run's layout); the tables show
     * repeat 0, the ratios come from all of them. */
    struct rpl_summary *sum[MAX_TRACES][N_SCENES];
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

static void trace_options(const struct replay_bench *b, int t, int sc, struct rpl_options *out)
{
    for (int se = 0; se < N_SELECTORS; ++se) {
        struct rpl_options *o = &out[se];
        rpl_options_defaults(o);
        o->trace_path = b->traces[t].path[0] ? b->traces[t].path : NULL;
        o->frame.scene = scenes[sc];
        o->frame.display = "vive";
        o->frame.selector = selectors[se];
        o->frame.visibility = criteria[se];
        o->frame.gaze = gazes[se];
        o->frames = b->traces[t].frames;
        o->frame.object_count = (int)b->o.objects;
        o->frame.render_scale = b->o.render_scale;
    }
}

/* One warm-up session (left out: the process's first pays the driver's start), then per trace and
 * scene none and reddy in alternated repeats, each session opened fresh in a temporary folder. */
static int run_all(struct replay_bench *b)
{
    struct rpl_options pair[N_SELECTORS];
    struct rpl_summary warmup;
    trace_options(b, 0, 0, pair);
    fprintf(stderr, WHO ": warm-up session (%s, %s, %s)\n", b->traces[0].label, scenes[0], selectors[0]);
    if (bch_alternate_run(pair, 1, 1, &warmup, WHO) != 0)
        return 1;
    for (int t = 0; t < b->n_traces; ++t)
        for (int sc = 0; sc < N_SCENES; ++sc) {
            b->sum[t][sc] = calloc((size_t)b->repeats * N_SELECTORS, sizeof *b->sum[t][sc]);
            if (!b->sum[t][sc]) {
                fprintf(stderr, WHO ": out of memory\n");
                return 1;
            }
            fprintf(stderr, WHO ": %s, %s\n", b->traces[t].label, scenes[sc]);
            trace_options(b, t, sc, pair);
            if (bch_alternate_run(pair, N_SELECTORS, b->repeats, b->sum[t][sc], WHO) != 0)
                return 1;
        }
    return 0;
}

static double frame_median(const struct rpl_summary *s) { return s->frame_ms_median; }
static double draw_median(const struct rpl_summary *s) { return s->draw_ms_median; }

/* none's figure over session se's, per repeat: their median and range. */
static void ratio_over_repeats(const struct replay_bench *b, int t, int sc, int se,
                               double (*figure)(const struct rpl_summary *), struct bch_spread *out)
{
    double ratio[BCH_MAX_REPEATS];
    for (int r = 0; r < b->repeats; ++r)
        ratio[r] = figure(&b->sum[t][sc][r * N_SELECTORS + 0]) / figure(&b->sum[t][sc][r * N_SELECTORS + se]);
    bch_spread_of(ratio, b->repeats, out);
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
            const struct rpl_summary *s = &b->sum[t][sc][se]; /* repeat 0 */
            bch_emit("| %s | %s | %ld | %.2f / %.2f / %.2f / %.2f | %.2f | %.0f | %.3f | %.1f / %.1f | %.1f %% |\n",
                       b->traces[t].label, session_labels[se], s->frames, s->frame_ms_median, s->frame_ms_p95,
                       s->frame_ms_p99, s->frame_ms_max, s->draw_ms_median, s->triangles_per_eye_mean,
                       s->triangles_relative_to_none, s->acuity_evaluations_mean, s->visible_mean,
                       100.0 * s->deadline_met_fraction);
        }
        const struct rpl_summary *none = &b->sum[t][sc][0];
        for (int se = 1; se < N_SELECTORS; ++se) {
            const struct rpl_summary *reddy = &b->sum[t][sc][se];
            struct bch_spread frame, draw;
            ratio_over_repeats(b, t, sc, se, frame_median, &frame);
            ratio_over_repeats(b, t, sc, se, draw_median, &draw);
            bch_emit("| %s | **none/%s** | | **×%.2f** [%.2f–%.2f] | ×%.2f [%.2f–%.2f] | **×%.2f** | | | |\n",
                     b->traces[t].label, session_labels[se], frame.median, frame.min, frame.max, draw.median,
                     draw.min, draw.max, none->triangles_per_eye_mean / reddy->triangles_per_eye_mean);
        }
    }
}

static void print_band_table(const struct replay_bench *b)
{
    bch_emit("\n### reddy: share of the finest-LOD triangles drawn, by head speed (frames)\n\n| scene | trace | "
             "criterion | gaze |");
    for (int k = 0; k < RPL_SPEED_BAND_COUNT; ++k) {
        if (k + 1 < RPL_SPEED_BAND_COUNT)
            bch_emit(" %g–%g °/s |", rpl_speed_band_lower_degps[k], rpl_speed_band_lower_degps[k + 1]);
        else
            bch_emit(" ≥%g °/s |", rpl_speed_band_lower_degps[k]);
    }
    bch_emit("\n|---|---|---|---|");
    for (int k = 0; k < RPL_SPEED_BAND_COUNT; ++k)
        bch_emit("--:|");
    bch_emit("\n");
    for (int sc = 0; sc < N_SCENES; ++sc)
        for (int t = 0; t < b->n_traces; ++t)
            for (int se = 1; se < N_SELECTORS; ++se) {
                const struct rpl_summary *s = &b->sum[t][sc][se]; /* reddy, repeat 0 (deterministic) */
                bch_emit("| %s | %s | %s | %s |", scenes[sc], b->traces[t].label, criteria[se], gazes[se]);
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
    char order[64];
    bch_alternate_order(N_SELECTORS, session_labels, order, sizeof order);
    bch_emit("\nHow measured (replay/run.c, frame/frame.c, bench/alternate.c): %d runs in %.0f s: one warm-up "
             "session (left out), then per trace and scene none, reddy under the contrast criterion and reddy under "
             "the acuity criterion (docs/visibility.md), each with the eye held on the world (vor) and fixed in the "
             "head (the rows marked head; docs/gaze.md), in %d alternated repeats in one process, "
             "order %s, each session opened fresh. Each run replays its trace from "
             "the start on a virtual clock at the display's %.0f Hz (frame f at t0 + f / %.0f s, whatever the "
             "wall clock did), both eyes rendered headless at render scale %g of the %s profile's pixels; none always "
             "draws the finest LOD; reddy contrast picks the coarsest LOD whose every lost band (the measured "
             "lost-contrast spectrum) is below castleCSF's threshold at the default k; reddy acuity picks it from "
             "Reddy's H(v, E) and each level's measured frequency table (the default reading, narrow: the thickest "
             "lost feature, docs/analysis.md). Frame time = pose + "
             "cull + geometry + select + draw, the draw waited with glFinish; draw = the GL part alone; "
             "percentiles are nearest rank. The selector rows are the first repeat's sessions. triangles vs none = "
             "triangles drawn / the finest-LOD triangles of the same frames; none/reddy = none's figure divided by "
             "reddy's, for the timings the median of the per-repeat ratios [min–max] (triangles are deterministic). "
             "Head speed is the trace's angular "
             "speed at each frame. The renderer is %s: timings vary by ±20 %% from run to run (PLATFORM.md), "
             "so compare the ratios within one run rather than figures across runs.\n",
             1 + b->n_traces * N_SCENES * N_SELECTORS * b->repeats, wall_s, b->repeats, order,
             1000.0 / s->budget_ms, 1000.0 / s->budget_ms, b->o.render_scale, s->display, cpu);
}

int bch_replay(const struct bch_replay_options *o, int full_argc, char **full_argv)
{
    struct replay_bench b;
    memset(&b, 0, sizeof b);
    b.o = *o;
    b.repeats = (int)(o->repeats ? o->repeats : o->quick ? 2 : 3);
    choose_traces(&b);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    int rc = run_all(&b);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double wall_s = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    if (rc == 0 && b.o.results && bch_copy_begin() != 0) {
        fprintf(stderr, WHO ": out of memory\n");
        rc = 1;
    }
    if (rc == 0) {
        /* Printed after the runs: the renderer line of the context comes from a summary. */
        bch_emit(BCH_REPLAY_HEADING "\n\n");
        bch_print_context(full_argc, full_argv, b.sum[0][0][0].renderer);
        for (int sc = 0; sc < N_SCENES; ++sc)
            print_scene_table(&b, sc);
        print_band_table(&b);
        print_notes(&b, wall_s);
        rc = bch_copy_finish(b.o.results, BCH_REPLAY_HEADING, WHO, 0);
    }
    for (int t = 0; t < MAX_TRACES; ++t)
        for (int sc = 0; sc < N_SCENES; ++sc)
            free(b.sum[t][sc]);
    return rc;
}
