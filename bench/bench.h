/* bench: every benchmark — the sub-benches of `hmdlod bench NAME` (tracking, replay, agree, lodgen,
 * cull, optimizer, gaze, live, soak), the soak (bench/soak.h) and the suite's plan, merge, tables, report
 * and plots (bench/suite.h). Prefix bch_. Bench code may call any module (replay, live, frame and
 * what they use); no module calls bench. It only measures: it never decides what a frame draws.
 * A sub-bench prints Markdown through bch_emit so that --results can store exactly what the
 * terminal showed (bench/context.c). */
#ifndef HMDLOD_BENCH_H
#define HMDLOD_BENCH_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "bench/soak.h"
#include "bench/suite.h"

/* ---- the sub-benches -------------------------------------------------------------------------
 * Each takes its options (parsed by app/cmd_bench_NAME.c) and the whole command line from "bench"
 * on (full_argc/full_argv, for the context lines), prints its Markdown (and stores it as the section
 * BCH_NAME_HEADING of --results' file), and returns the process's exit code: 0, or 1 after saying
 * why on stderr. */

/* hmdlod bench tracking (bench/bench_tracking.c): tracker accuracy and speed on the shared IMU streams. */
#define BCH_TRACKING_HEADING "## Trackers (hmdlod bench tracking)"
struct bch_tracking_options {
    const char *stream;  /* a stream's name (.csv optional), or "all" (NULL: all) */
    double seconds;      /* only the first seconds of each stream; 0: all */
    long repeats;        /* whole-stream timing passes (median reported) */
    const char *results; /* NULL: no results file */
};
int bch_tracking(const struct bch_tracking_options *o, int full_argc, char **full_argv);
void bch_tracking_print_streams(FILE *f); /* the streams' names, each after a space */

/* hmdlod bench cull (bench/bench_cull.c): flat against hierarchical culling of generated scenes. */
#define BCH_CULL_HEADING "## Culling (hmdlod bench cull)"
struct bch_cull_options {
    const char *trace;   /* head motion; NULL: Corbillon user1 from the shared folder, else the built-in clip */
    const char *display; /* the frusta's display profile */
    const char *results; /* NULL: no results file */
    long frames, seed;
    int quick;
};
int bch_cull(const struct bch_cull_options *o, int full_argc, char **full_argv);

/* hmdlod bench gaze (bench/bench_gaze.c): the gaze models against none on real traces. */
#define BCH_GAZE_HEADING "## Gaze models (hmdlod bench gaze)"
struct bch_gaze_options {
    long frames, objects;  /* per run from each trace's start; in the field scene */
    double render_scale;   /* per-eye resolution factor in (0, 4] */
    int quick;
    const char *results;   /* NULL: no results file */
};
int bch_gaze(const struct bch_gaze_options *o, int full_argc, char **full_argv);

/* hmdlod bench live (bench/bench_live.c): the distortion pass's cost and a 90 Hz session's present intervals. */
#define BCH_LIVE_HEADING "## Live session (hmdlod bench live)"
struct bch_live_options {
    long draws;          /* timed distortion passes */
    long frames;         /* frames of the paced session */
    const char *results; /* NULL: no results file */
};
int bch_live(const struct bch_live_options *o, int full_argc, char **full_argv);

/* hmdlod bench lodgen (bench/bench_lodgen.c): the bunny's chain with OpenMesh and with meshoptimizer. */
#define BCH_LODGEN_HEADING "## LOD generation (hmdlod bench lodgen)"
struct bch_lodgen_options {
    long repeats;               /* timed repeats of each chain, 1 … 15 */
    uint64_t hausdorff_samples; /* per mesh */
    const char *results;        /* NULL: no results file */
};
int bch_lodgen(const struct bch_lodgen_options *o, int full_argc, char **full_argv);

/* hmdlod bench optimizer (bench/bench_optimizer*.c): fs against the from-scratch greedy on the core alone. */
#define BCH_OPTIMIZER_HEADING "## Optimizer (hmdlod bench optimizer)"
struct bch_optimizer_options {
    const char *trace, *results; /* trace NULL: Corbillon user2 from the shared folder; results NULL: none */
    long frames, pairs, seed;    /* frames per table, frame pairs per turn bin, placement seed */
    double limit_us, hysteresis; /* limit 0: no time-limited fs; hysteresis when has_hysteresis */
    int quick, has_hysteresis;
};
int bch_optimizer(const struct bch_optimizer_options *o, int full_argc, char **full_argv);

/* hmdlod bench replay (bench/bench_replay.c): none against reddy on both scenes and the real traces. */
#define BCH_REPLAY_HEADING "## Replay (hmdlod bench replay)"
struct bch_replay_options {
    long frames;          /* per run from each trace's start; 0: the defaults (600, --quick 200) */
    double render_scale;  /* per-eye resolution factor in (0, 4] */
    long objects;         /* in the field scene */
    long repeats;         /* alternated repeats of none and reddy, 1 … BCH_MAX_REPEATS; 0: 3 (--quick 2) */
    int quick;
    const char *results;  /* NULL: no results file */
};
int bch_replay(const struct bch_replay_options *o, int full_argc, char **full_argv);

/* hmdlod bench agree (bench/bench_agree.c): two identical sessions in one process, alternated, agree? */
#define BCH_AGREE_HEADING "## Session agreement (hmdlod bench agree)"
struct bch_agree_options {
    long repeats;        /* alternated repeats of A and A′, 2 … BCH_MAX_REPEATS */
    long frames;         /* per session from the clip's start; 0: the whole built-in clip */
    double render_scale; /* per-eye resolution factor in (0, 4] */
    const char *results; /* NULL: no results file */
};
int bch_agree(const struct bch_agree_options *o, int full_argc, char **full_argv);

/* hmdlod bench soak (bench/bench_soak.c): checks o (bch_soak_check_options), takes the trace and
 * the IMU stream from the shared folder (o's paths are replaced), runs the soak and prints its table. */
int bch_soak(const struct bch_soak_options *o, int full_argc, char **full_argv);


/* bench cull's generated scene, shared with bench optimizer's scaling table: n objects on a ground
 * grid 2 m apart around the origin, grouped as a quadtree of 4 × 4 (bench/bench_cull.c). Allocates
 * the scene's arrays (scn_scene_free releases them); 0, or −1 with err. */
struct scn_scene;
struct hl_error;
int bch_cull_make_grid(uint32_t n, uint64_t seed, struct scn_scene *s, struct hl_error *err);

/* ---- alternated repeats (bench/alternate.c) ---------------------------------------------------
 * Ratios between sessions measured in one process follow run order: the first session pays warm-up
 * costs, and a machine's load drifts. So a ratio is taken from repeats: n sessions run `repeats`
 * times, round r forward when r is even and backward when odd (ABC CBA ABC …), each session opened
 * fresh (rpl_run); a steady drift then spreads the per-repeat ratios instead of biasing their median,
 * since every session is first as often as last. */
struct rpl_options;
struct rpl_summary;
enum { BCH_MAX_REPEATS = 100 };

/* Which of the n configurations runs at position k of round `repeat`. */
int bch_alternate_index(int repeat, int k, int n);
/* The order of two rounds as words, "none, reddy, fs | fs, reddy, none | …" (always NUL-terminated). */
void bch_alternate_order(int n, const char *const *names, char *out, size_t size);
/* Runs configs[0..n) `repeats` times in the alternated order; sums[r * n + k] is configuration k's
 * summary in repeat r. Each session writes into its own folder under a fresh temporary one, removed at
 * the end either way (configs' out_dir is ignored; quiet is set). `who` prefixes the progress lines on
 * stderr (NULL: none). 0, or 1 after saying why on stderr. */
int bch_alternate_run(const struct rpl_options *configs, int n, int repeats, struct rpl_summary *sums,
                      const char *who);

/* Median (the mean of the middle two for an even count), min and max of the finite values among
 * the first BCH_MAX_REPEATS of v; all NaN and n 0 when there are none. */
struct bch_spread {
    double median, min, max;
    int n; /* finite values used */
};
void bch_spread_of(const double *v, int n, struct bch_spread *out);
/* Over the repeats of bch_alternate_run's sums: configuration k's mean frame time (frame 0 left out,
 * rpl_summary.frame_ms_mean_after_first), and the per-repeat ratio num / den of those means. */
void bch_mean_spread(const struct rpl_summary *sums, int n, int repeats, int k, struct bch_spread *out);
void bch_ratio_spread(const struct rpl_summary *sums, int n, int repeats, int num, int den, struct bch_spread *out);

/* printf to stdout, and to the results copy while one is open. */
void bch_emit(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

/* Starts keeping a copy of what bch_emit prints; 0, or −1 when out of memory. */
int bch_copy_begin(void);
/* Ends the copy. When rc is 0, stores it as the section `heading` of the file `results` and says so
 * on stderr prefixed by `who` ("hmdlod bench tracking"). Returns rc, or 1 when writing failed. */
int bch_copy_finish(const char *results, const char *heading, const char *who, int rc);

/* The context lines: command, machine (CPU, cores), commit, date, and the GL renderer when the
 * bench renders (renderer NULL: no such line). */
void bch_print_context(int full_argc, char **full_argv, const char *renderer);
/* The same lines (renderer aside) as a malloc'd string for a report to carry; NULL when out of memory. */
char *bch_context_text(int full_argc, char **full_argv);
/* The short commit of the source tree (with " (with uncommitted changes)"), or "unknown". */
void bch_commit(char *out, size_t size);

/* The shared data folder: $HMDLOD_SHARED, else ../shared, else next to the executable's checkout.
 * 0 and its path, or −1 (out holds the path that was looked for). */
int bch_find_shared(char *out, size_t size);

/* A fresh folder /tmp/hmdlod-bench-NAME-XXXXXX for a bench's replays (path ≥ 64 bytes); 0, or −1
 * after saying why on stderr. bch_temp_dir_remove deletes it and everything in it. */
int bch_temp_dir(const char *name, char *path, size_t size);
void bch_temp_dir_remove(const char *path);

/* Replaces (or appends) the section starting at `heading` in the Markdown file at path. */
int bch_write_results_section(const char *path, const char *heading, const char *body);

#endif
