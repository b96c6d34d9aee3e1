/* The hmdlod program: main.c dispatches to one function per subcommand. Each parses its own
 * arguments, prints one clear message on bad input, and returns the process exit code
 * (0 success, 1 bad input or failure). argv[0] is the subcommand's name. */
#ifndef HMDLOD_APP_COMMANDS_H
#define HMDLOD_APP_COMMANDS_H

#include <stdio.h>

int cmd_demo(int argc, char **argv);
int cmd_display(int argc, char **argv);
int cmd_acuity(int argc, char **argv);
int cmd_replay(int argc, char **argv);
int cmd_live(int argc, char **argv);    /* app/cmd_live.c: live session in a window, distortion pass */
int cmd_bench(int argc, char **argv);   /* app/cmd_bench.c: measurements (bench tracking, …) */
/* The sub-benches' options (app/cmd_bench_NAME.c): argv[0] is the sub-bench's name, full_argc/argv
 * start at "bench" (for the context lines). */
int cmd_bench_agree(int argc, char **argv, int full_argc, char **full_argv);
int cmd_bench_cull(int argc, char **argv, int full_argc, char **full_argv);
int cmd_bench_gaze(int argc, char **argv, int full_argc, char **full_argv);
int cmd_bench_live(int argc, char **argv, int full_argc, char **full_argv);
int cmd_bench_lodgen(int argc, char **argv, int full_argc, char **full_argv);
int cmd_bench_optimizer(int argc, char **argv, int full_argc, char **full_argv);
int cmd_bench_replay(int argc, char **argv, int full_argc, char **full_argv);
int cmd_bench_soak(int argc, char **argv, int full_argc, char **full_argv);
int cmd_bench_tracking(int argc, char **argv, int full_argc, char **full_argv);
/* The suite (no sub-bench name): hmdlod bench [--quick] --out DIR, --plan FILE, --merge DIR…
 * (app/cmd_bench_suite.c; the plan, runs and report are bench/suite.h's). */
int cmd_bench_suite(int argc, char **argv, int full_argc, char **full_argv);
void cmd_bench_suite_usage(FILE *f);
int cmd_record(int argc, char **argv);  /* app/cmd_record.c: tracker → raw recording */
int cmd_convert(int argc, char **argv); /* app/cmd_convert.c: raw recording → trace CSV */
int cmd_devices(int argc, char **argv); /* app/cmd_devices.c: supported trackers present, openable or why not */
int cmd_lodgen(int argc, char **argv);  /* app/cmd_lodgen.c: mesh file → LOD chain (.lod) */
int cmd_lodgen_group(int argc, char **argv); /* app/cmd_lodgen_group.c: lodgen --group (the scenes helper) */
int cmd_analyze(int argc, char **argv); /* app/cmd_analyze.c: Reddy's offline analysis of a .lod file */
int cmd_calibrate(int argc, char **argv); /* app/cmd_calibrate.c: machine cost model → cost profile JSON */

/* Shared argument helpers (app/args.c): strict numeric parsing that names the option. */
int app_parse_double(const char *option, const char *text, double *out);
int app_parse_long(const char *option, const char *text, long min, long max, long *out);
int app_wants_help(int argc, char **argv);
/* The foveated layers' options, shared by replay, live and bench (frame/layers.h): --foveation,
 * --periphery-scale, --inset-deg, --blend-deg. 1 when opt is one of them (its value parsed into o;
 * *bad set to 1 with a message on stderr when the value is not a number), 0 otherwise. Ranges are
 * frm_options_check's. */
struct frm_options;
int app_parse_layer_option(const char *opt, const char *val, struct frm_options *o, int *bad);
extern const char app_layer_usage[];

#endif
