/* hmdlod bench gaze: the gaze models (acuity/gaze.h) against the finest-LOD baseline on real traces,
 * in one run so their ratios are measured under the same load: Corbillon and Nasrabadi (head only:
 * head, vor) and EDVAM (with measured gaze: also tracked, and its saccades). Each model also runs with
 * the velocity term off (acu_limits.use_velocity = 0) to measure what the velocity term saves and how
 * much of that saving survives under the VOR. Everything measured comes from rpl_run's summary. */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench/bench.h"
#include "replay/replay.h"


static const char *const scenes[] = {"field", "auditorium"};
enum { N_SCENES = 2, MAX_TRACES = 6 };

/* The runs per trace: selector, gaze model, velocity term; tracked only where the trace has gaze. */
enum { M_NONE, M_HEAD, M_HEAD_NOVEL, M_VOR, M_VOR_NOVEL, M_TRACKED, M_TRACKED_FS, N_MODELS };
static const struct model {
    const char *label, *selector, *gaze;
    int velocity_off, needs_gaze;
} models[N_MODELS] = {
    {"none (finest)", "none", "head", 0, 0},
    {"head", "reddy", "head", 0, 0},
    {"head, no velocity term", "reddy", "head", 1, 0},
    {"vor", "reddy", "vor", 0, 0},
    {"vor, no velocity term", "reddy", "vor", 1, 0},
    {"tracked", "reddy", "tracked", 0, 1},
    {"tracked, fs", "fs", "tracked", 0, 1},
};

struct gaze_trace {
    char label[48];
    char path[4200];
    int has_gaze;
};

struct gaze_bench {
    struct bch_gaze_options o; /* as parsed (app/cmd_bench_gaze.c) */
    struct gaze_trace traces[MAX_TRACES];
    int n_traces;
    struct rpl_summary sum[MAX_TRACES][N_SCENES][N_MODELS];
    /* Saccades over the whole log (or --quick's first 1200 frames): tracked, reddy and fs, on a small
     * field at a quarter of the pixels — the classifier and the refinement count, not the timing. */
    struct rpl_summary whole[MAX_TRACES][2];
    long whole_frames;
    int ran[MAX_TRACES][N_SCENES][N_MODELS];
};

static void add_trace(struct gaze_bench *b, const char *shared, const char *label, const char *rel, int has_gaze)
{
    struct gaze_trace *t = &b->traces[b->n_traces++];
    snprintf(t->label, sizeof t->label, "%s", label);
    snprintf(t->path, sizeof t->path, "%s/%s", shared, rel);
    t->has_gaze = has_gaze;
}

static int choose_traces(struct gaze_bench *b)
{
    char shared[4096];
    if (bch_find_shared(shared, sizeof shared) != 0) {
        fprintf(stderr, "hmdlod bench gaze: the shared data folder is absent (%s): no real traces to replay\n", shared);
        return 1;
    }
    add_trace(b, shared, "corbillon user1", "data/traces/corbillon-mmsys18/user1_quaternion.txt", 0);
    add_trace(b, shared, "nasrabadi 322SAJ_9", "data/traces/nasrabadi-mmsys19/322SAJ_9.csv", 0);
    add_trace(b, shared, "edvam participant2", "data/traces/edvam-gaze/participant2.csv", 1);
    return 0;
}

static int run_all(struct gaze_bench *b)
{
    char tmp[64];
    if (bch_temp_dir("gaze", tmp, sizeof tmp) != 0)
        return 1;
    int total = 0, run = 0, rc = 0;
    for (int t = 0; t < b->n_traces; ++t)
        for (int m = 0; m < N_MODELS; ++m)
            total += N_SCENES * (!models[m].needs_gaze || b->traces[t].has_gaze);
    for (int t = 0; t < b->n_traces && rc == 0; ++t)
        for (int sc = 0; sc < N_SCENES && rc == 0; ++sc)
            for (int m = 0; m < N_MODELS && rc == 0; ++m) {
                if (models[m].needs_gaze && !b->traces[t].has_gaze)
                    continue;
                char out_dir[sizeof tmp + 16];
                snprintf(out_dir, sizeof out_dir, "%s/run%03d", tmp, ++run);
                struct rpl_options o;
                rpl_options_defaults(&o);
                o.trace_path = b->traces[t].path;
                o.frame.scene = scenes[sc];
                o.frame.display = "vive";
                o.frame.selector = models[m].selector;
                o.frame.gaze = models[m].gaze;
                o.frame.velocity_term_off = models[m].velocity_off;
                o.out_dir = out_dir;
                o.frames = b->o.frames;
                o.frame.object_count = (int)b->o.objects;
                o.frame.render_scale = b->o.render_scale;
                o.frame.quiet = 1;
                fprintf(stderr, "hmdlod bench gaze: run %d of %d: %s, %s, %s\n", run, total, b->traces[t].label,
                        scenes[sc], models[m].label);
                struct hl_error err = {{0}};
                if (rpl_run(&o, &b->sum[t][sc][m], &err) != 0) {
                    fprintf(stderr, "hmdlod bench gaze: %s, %s, %s: %s\n", b->traces[t].label, scenes[sc],
                            models[m].label, err.msg);
                    rc = 1;
                }
                b->ran[t][sc][m] = rc == 0;
            }
    static const char *const whole_selectors[2] = {"reddy", "fs"};
    for (int t = 0; t < b->n_traces && rc == 0; ++t)
        for (int k = 0; k < 2 && b->traces[t].has_gaze && rc == 0; ++k) {
            char out_dir[sizeof tmp + 16];
            snprintf(out_dir, sizeof out_dir, "%s/whole%d%d", tmp, t, k);
            struct rpl_options o;
            rpl_options_defaults(&o);
            o.trace_path = b->traces[t].path;
            o.frame.scene = "field";
            o.frame.selector = whole_selectors[k];
            o.frame.gaze = "tracked";
            o.out_dir = out_dir;
            o.frames = b->o.quick ? 1200 : 0;
            o.frame.render_scale = 0.25;
            o.frame.quiet = 1;
            fprintf(stderr, "hmdlod bench gaze: %s, whole log, field (100 objects), tracked, %s\n",
                    b->traces[t].label, whole_selectors[k]);
            struct hl_error err = {{0}};
            if (rpl_run(&o, &b->whole[t][k], &err) != 0) {
                fprintf(stderr, "hmdlod bench gaze: %s, whole log: %s\n", b->traces[t].label, err.msg);
                rc = 1;
            }
        }
    bch_temp_dir_remove(tmp);
    return rc;
}

static void print_saccade_table(const struct gaze_bench *b)
{
    bch_emit("\n### Saccades over the %s (tracked; field, 100 objects, render scale 0.25)\n\n"
               "| trace | selector | frames | saccades | per second | frames suppressed | refinements missing 28 ms "
               "(frames / saccades) | triangles vs none |\n|---|---|--:|--:|--:|--:|--:|--:|\n",
               b->o.quick ? "first 1200 frames" : "whole log");
    static const char *const names[2] = {"reddy", "fs"};
    for (int t = 0; t < b->n_traces; ++t)
        for (int k = 0; k < 2 && b->traces[t].has_gaze; ++k) {
            const struct rpl_summary *s = &b->whole[t][k];
            bch_emit("| %s | %s | %ld | %ld | %.2f | %.1f %% | %ld / %ld (%.1f %%) | %.3f |\n", b->traces[t].label,
                       names[k], s->frames, s->saccades, s->rate_hz * (double)s->saccades / (double)s->frames,
                       100.0 * s->suppressed_fraction, s->refine_miss_frames, s->refine_missed_saccades,
                       100.0 * s->refine_missed_saccade_fraction, s->triangles_relative_to_none);
        }
}

/* (tri_vor_novel − tri_vor) / (tri_head_novel − tri_head): of what the velocity term saves under the
 * head-locked eye, the part it still saves when the VOR holds the fixation. NaN when head saves nothing. */
static double velocity_saving_share(const struct rpl_summary *sum)
{
    double head = sum[M_HEAD_NOVEL].triangles_per_eye_mean - sum[M_HEAD].triangles_per_eye_mean;
    double vor = sum[M_VOR_NOVEL].triangles_per_eye_mean - sum[M_VOR].triangles_per_eye_mean;
    return head > 0.0 ? vor / head : NAN;
}

static void print_scene_table(const struct gaze_bench *b, int sc)
{
    if (sc == 0)
        bch_emit("\n### %s (%ld objects)\n\n", scenes[sc], b->o.objects);
    else
        bch_emit("\n### %s\n\n", scenes[sc]);
    bch_emit("| trace | model | frames | triangles/eye mean | vs none | frame ms median / p95 | frame time vs none "
               "| saccades | frames suppressed | refinements missing 28 ms (frames / saccades) |\n");
    bch_emit("|---|---|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int t = 0; t < b->n_traces; ++t) {
        const struct rpl_summary *none = &b->sum[t][sc][M_NONE];
        for (int m = 0; m < N_MODELS; ++m) {
            if (!b->ran[t][sc][m])
                continue;
            const struct rpl_summary *s = &b->sum[t][sc][m];
            bch_emit("| %s | %s | %ld | %.0f | %.3f | %.2f / %.2f | %.3f |", b->traces[t].label, models[m].label,
                       s->frames, s->triangles_per_eye_mean, s->triangles_per_eye_mean / none->triangles_per_eye_mean,
                       s->frame_ms_median, s->frame_ms_p95, s->frame_ms_median / none->frame_ms_median);
            if (s->gaze_frames > 0)
                bch_emit(" %ld | %.1f %% | %ld / %ld (%.1f %%) |\n", s->saccades, 100.0 * s->suppressed_fraction,
                           s->refine_miss_frames, s->refine_missed_saccades, 100.0 * s->refine_missed_saccade_fraction);
            else
                bch_emit(" – | – | – |\n");
        }
    }
}

static void print_velocity_table(const struct gaze_bench *b)
{
    bch_emit("\n### The velocity term's saving under the VOR\n\n"
               "| scene | trace | head: saved by velocity (triangles/eye) | vor: saved by velocity | share that "
               "survives under vor |\n|---|---|--:|--:|--:|\n");
    for (int sc = 0; sc < N_SCENES; ++sc)
        for (int t = 0; t < b->n_traces; ++t) {
            const struct rpl_summary *sum = b->sum[t][sc];
            double head = sum[M_HEAD_NOVEL].triangles_per_eye_mean - sum[M_HEAD].triangles_per_eye_mean;
            double vor = sum[M_VOR_NOVEL].triangles_per_eye_mean - sum[M_VOR].triangles_per_eye_mean;
            double share = velocity_saving_share(sum);
            if (isfinite(share))
                bch_emit("| %s | %s | %.0f | %.0f | %.1f %% |\n", scenes[sc], b->traces[t].label, head, vor,
                           100.0 * share);
            else
                bch_emit("| %s | %s | %.0f | %.0f | – |\n", scenes[sc], b->traces[t].label, head, vor);
        }
}

static void print_notes(const struct gaze_bench *b, double wall_s, int runs)
{
    const struct rpl_summary *s = &b->sum[0][0][M_NONE];
    bch_emit("\nHow measured: %d runs in %.0f s, each %ld frames from the trace's start on a virtual clock at the "
               "%s's %.0f Hz, both eyes rendered headless at render scale %g (renderer above). none draws the finest "
               "LOD; the others select with reddy (tracked, fs: the cost-bounded fs with the display's budget) "
               "under the gaze model named (docs/gaze.md). \"no velocity term\" sets acu_limits.use_velocity = 0: "
               "every object still on the retina. vs none = the model's mean triangles per eye (or median frame "
               "time) over none's, same trace, scene and frames. Share that survives under vor = (tri_vor_novel − "
               "tri_vor) / (tri_head_novel − tri_head), triangles per eye: of what the velocity term saves with the "
               "eye fixed in the head, the part it still saves when the VOR holds the fixated point on the fovea. "
               "Saccades: I-VT on the gaze's world speed (onset 100, offset 50 deg/s), suppression 50 ms after each, "
               "refinement due 28 ms after that (acuity/saccade.c); a miss is a frame past the deadline with an "
               "object still coarser than its target (the coarser of its ceiling and its level before the saccade) "
               "that the budget had room to raise (frame/saccade_step.c). "
               "Timings vary by ±20 %% between runs on a shared machine: compare ratios within one run.\n",
               runs, wall_s, b->o.frames, s->display, s->rate_hz, b->o.render_scale);
}

int bch_gaze(const struct bch_gaze_options *o, int full_argc, char **full_argv)
{
    static struct gaze_bench b; /* the summaries are large */
    memset(&b, 0, sizeof b);
    b.o = *o;
    if (choose_traces(&b) != 0)
        return 1;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    if (run_all(&b) != 0)
        return 1;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double wall_s = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    int runs = 0;
    for (int t = 0; t < b.n_traces; ++t)
        for (int sc = 0; sc < N_SCENES; ++sc)
            for (int m = 0; m < N_MODELS; ++m)
                runs += b.ran[t][sc][m];
    if (b.o.results && bch_copy_begin() != 0) {
        fprintf(stderr, "hmdlod bench gaze: out of memory\n");
        return 1;
    }
    bch_emit(BCH_GAZE_HEADING "\n\n");
    bch_print_context(full_argc, full_argv, b.sum[0][0][M_NONE].renderer);
    for (int sc = 0; sc < N_SCENES; ++sc)
        print_scene_table(&b, sc);
    print_velocity_table(&b);
    print_saccade_table(&b);
    print_notes(&b, wall_s, runs);
    return bch_copy_finish(b.o.results, BCH_GAZE_HEADING, "hmdlod bench gaze", 0);
}
