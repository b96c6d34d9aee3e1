/* Internal to app/: what every `hmdlod bench` sub-bench shares (app/bench_context.c). A bench prints
 * Markdown through bench_emit so that --results can store exactly what the terminal showed. */
#ifndef HMDLOD_APP_BENCH_H
#define HMDLOD_APP_BENCH_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* One sub-bench: argv[0] is its name; full_argc/full_argv start at "bench" (for the context). */
int bench_tracking(int argc, char **argv, int full_argc, char **full_argv); /* app/bench_tracking.c */
int bench_replay(int argc, char **argv, int full_argc, char **full_argv);   /* app/bench_replay.c */
int bench_lodgen(int argc, char **argv, int full_argc, char **full_argv);   /* app/bench_lodgen.c */
int bench_cull(int argc, char **argv, int full_argc, char **full_argv);     /* app/bench_cull.c */
int bench_optimizer(int argc, char **argv, int full_argc, char **full_argv); /* app/bench_optimizer.c */
int bench_gaze(int argc, char **argv, int full_argc, char **full_argv);     /* app/bench_gaze.c */
/* The suite (no sub-bench name): hmdlod bench [--quick] --out DIR, --plan FILE, --merge DIR… (app/bench_suite.c) */
int bench_suite(int argc, char **argv, int full_argc, char **full_argv);
void bench_suite_usage(FILE *f);
int bench_live(int argc, char **argv, int full_argc, char **full_argv);     /* app/bench_live.c */
int bench_soak(int argc, char **argv, int full_argc, char **full_argv);     /* app/bench_soak.c */

/* bench cull's generated scene, shared with bench optimizer's scaling table: n objects on a ground
 * grid 2 m apart around the origin, grouped as a quadtree of 4 × 4 (app/bench_cull.c). Allocates
 * the scene's arrays (scn_scene_free releases them); 0, or −1 with err. */
struct scn_scene;
struct hl_error;
int bench_cull_make_grid(uint32_t n, uint64_t seed, struct scn_scene *s, struct hl_error *err);

/* printf to stdout, and to the results copy while one is open. */
void bench_emit(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

/* Starts keeping a copy of what bench_emit prints; 0, or −1 when out of memory. */
int bench_copy_begin(void);
/* Ends the copy. When rc is 0, stores it as the section `heading` of the file `results` and says so
 * on stderr prefixed by `who` ("hmdlod bench tracking"). Returns rc, or 1 when writing failed. */
int bench_copy_finish(const char *results, const char *heading, const char *who, int rc);

/* The context lines: command, machine (CPU, cores), commit, date, and the GL renderer when the
 * bench renders (renderer NULL: no such line). */
void bench_print_context(int full_argc, char **full_argv, const char *renderer);
/* The same lines (renderer aside) as a malloc'd string for a report to carry; NULL when out of memory. */
char *bench_context_text(int full_argc, char **full_argv);
/* The short commit of the source tree (with " (with uncommitted changes)"), or "unknown". */
void bench_commit(char *out, size_t size);

/* The shared data folder: $HMDLOD_SHARED, else ../shared, else next to the executable's checkout.
 * 0 and its path, or −1 (out holds the path that was looked for). */
int bench_find_shared(char *out, size_t size);

/* A fresh folder /tmp/hmdlod-bench-NAME-XXXXXX for a bench's replays (path ≥ 64 bytes); 0, or −1
 * after saying why on stderr. bench_temp_dir_remove deletes it and everything in it. */
int bench_temp_dir(const char *name, char *path, size_t size);
void bench_temp_dir_remove(const char *path);

/* Replaces (or appends) the section starting at `heading` in the Markdown file at path. */
int bench_write_results_section(const char *path, const char *heading, const char *body);

#endif
