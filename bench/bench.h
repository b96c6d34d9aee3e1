/* bench: every benchmark — the sub-benches of `hmdlod bench NAME` (tracking, replay, lodgen, cull,
 * optimizer, gaze, live, soak), the soak (bench/soak.h) and the suite's plan, merge, tables, report
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

/* One sub-bench: argv[0] is its name; full_argc/full_argv start at "bench" (for the context). */
int bch_tracking(int argc, char **argv, int full_argc, char **full_argv); /* bench/tracking.c */
int bch_replay(int argc, char **argv, int full_argc, char **full_argv);   /* bench/replay.c */
int bch_lodgen(int argc, char **argv, int full_argc, char **full_argv);   /* bench/lodgen.c */
int bch_cull(int argc, char **argv, int full_argc, char **full_argv);     /* bench/cull.c */
int bch_optimizer(int argc, char **argv, int full_argc, char **full_argv); /* bench/optimizer.c */
int bch_gaze(int argc, char **argv, int full_argc, char **full_argv);     /* bench/gaze.c */
/* The suite (no sub-bench name): hmdlod bench [--quick] --out DIR, --plan FILE, --merge DIR… (bench/suite.c) */
int bch_suite(int argc, char **argv, int full_argc, char **full_argv);
void bch_suite_usage(FILE *f);
int bch_live(int argc, char **argv, int full_argc, char **full_argv);     /* bench/live.c */
int bch_soak(int argc, char **argv, int full_argc, char **full_argv);     /* bench/soak_report.c */

/* bench cull's generated scene, shared with bench optimizer's scaling table: n objects on a ground
 * grid 2 m apart around the origin, grouped as a quadtree of 4 × 4 (bench/cull.c). Allocates
 * the scene's arrays (scn_scene_free releases them); 0, or −1 with err. */
struct scn_scene;
struct hl_error;
int bch_cull_make_grid(uint32_t n, uint64_t seed, struct scn_scene *s, struct hl_error *err);

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
