/* hmdlod bench live: its options (bench/live.c measures). */
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "bench/bench.h"

static const char live_bench_usage[] =
    "usage: hmdlod bench live [--draws N] [--frames N] [--results FILE]\n\n"
    "Times the lens distortion pass at the Vive's resolution (2160 x 1200) headless, with the DK2's\n"
    "PanoTools coefficients and aberration and without (the Vive's built-in profile has none), and,\n"
    "when DISPLAY is set (run it under xvfb-run -a), a 90 Hz live session whose frame fits its budget\n"
    "(field with 10 objects, render scale 0.1, a 320 x 180 window) with its present intervals, as Markdown.\n"
    "  --draws N         distortion passes timed per case (default 200)\n"
    "  --frames N        frames of the live session (default 900: 10 s)\n"
    "  --results FILE    also write the output as the section \"" BCH_LIVE_HEADING "\" of FILE\n";

int cmd_bench_live(int argc, char **argv, int full_argc, char **full_argv)
{
    struct bch_live_options o = {.draws = 200, .frames = 900, .results = NULL};
    for (int i = 1; i < argc; ++i) {
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            fputs(live_bench_usage, stdout);
            return 0;
        }
        if (!val) {
            fprintf(stderr, "hmdlod bench live: %s needs a value (try --help)\n", argv[i]);
            return 1;
        }
        ++i;
        if (!strcmp(argv[i - 1], "--draws")) {
            if (app_parse_long("--draws", val, 1, 100000, &o.draws))
                return 1;
        } else if (!strcmp(argv[i - 1], "--frames")) {
            if (app_parse_long("--frames", val, 2, 10000000, &o.frames))
                return 1;
        } else if (!strcmp(argv[i - 1], "--results")) {
            o.results = val;
        } else {
            fprintf(stderr, "hmdlod bench live: unknown option '%s'\n%s", argv[i - 1], live_bench_usage);
            return 1;
        }
    }
    return bch_live(&o, full_argc, full_argv);
}
