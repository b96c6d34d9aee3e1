/* hmdlod bench agree: its options (bench/bench_agree.c measures). */
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "bench/bench.h"

static const char agree_usage[] =
    "usage: hmdlod bench agree [--repeats N] [--frames N] [--render-scale F] [--results FILE] [--quick]\n\n"
    "Runs the same replay session twice, A and A' with identical options, in alternated repeats in one\n"
    "process (A, A' | A', A | ...; one warm-up session first, left out), for two sessions: field with\n"
    "selector none and auditorium with reddy, both on the built-in clip and the Vive profile. Prints each\n"
    "one's mean frame time (frame 0 left out), the ratio A/A' as the median of the per-repeat ratios with\n"
    "its range, the spread the repeats show, and PASS when A/A' is within 5 % of 1 and within that\n"
    "spread. A benchmark: its figures follow the machine's load.\n"
    "  --repeats N       alternated repeats, 2..100 (default 3)\n"
    "  --frames N        frames per session from the clip's start (default: the whole clip, 721)\n"
    "  --render-scale F  per-eye resolution factor in (0, 4] (default 1: the display's pixels)\n"
    "  --results FILE    also write the output as the section \"" BCH_AGREE_HEADING "\" of FILE\n"
    "  --quick           2 repeats of 200 frames at render scale 0.5 (options after it win)\n";

static int parse_args(int argc, char **argv, struct bch_agree_options *o)
{
    o->repeats = 3;
    o->render_scale = 1.0;
    for (int i = 1; i < argc; ++i) {
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--quick")) {
            o->repeats = 2;
            o->frames = 200;
            o->render_scale = 0.5;
            continue;
        }
        if (!strcmp(argv[i], "--repeats")) {
            /* Two at least: one repeat has no spread to judge the ratio by. */
            if (app_parse_long("--repeats", val, 2, BCH_MAX_REPEATS, &o->repeats) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--frames")) {
            if (app_parse_long("--frames", val, 1, 100000000, &o->frames) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--render-scale")) {
            if (app_parse_double("--render-scale", val, &o->render_scale) != 0)
                return 1;
            if (!(o->render_scale > 0.0 && o->render_scale <= 4.0)) { /* before minutes of runs, not after */
                fprintf(stderr, "hmdlod: --render-scale: %g is outside (0, 4]\n", o->render_scale);
                return 1;
            }
        } else if (!strcmp(argv[i], "--results") && val) {
            o->results = val;
        } else {
            fprintf(stderr, "hmdlod bench agree: unknown or incomplete option '%s' (try --help)\n", argv[i]);
            return 1;
        }
        ++i;
    }
    return 0;
}

int cmd_bench_agree(int argc, char **argv, int full_argc, char **full_argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(agree_usage, stdout);
        return 0;
    }
    struct bch_agree_options o;
    memset(&o, 0, sizeof o);
    if (parse_args(argc, argv, &o) != 0)
        return 1;
    return bch_agree(&o, full_argc, full_argv);
}
