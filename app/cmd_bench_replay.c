/* hmdlod bench replay: its options (bench/replay.c measures). */
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "bench/bench.h"

static const char replay_usage[] =
    "usage: hmdlod bench replay [--frames N] [--render-scale F] [--objects N] [--repeats N] [--results FILE]\n"
    "                           [--quick]\n\n"
    "Replays head motion through the field and auditorium scenes on the Vive profile (11.1 ms display\n"
    "period) with the selectors none and reddy, same trace and frames, and prints frame time, triangles\n"
    "and the none/reddy ratios as Markdown. Traces: the built-in clip, and Corbillon MMSys'18 user1-3\n"
    "from the shared folder when it is present. After one warm-up session, none and reddy run in\n"
    "alternated repeats per trace and scene (none, reddy | reddy, none | ...); the timing ratios are the\n"
    "median of the per-repeat ratios with their range.\n"
    "  --frames N        frames per run from each trace's start (default 600; the built-in clip: whole)\n"
    "  --render-scale F  per-eye resolution factor in (0, 4] (default 1: the display's pixels)\n"
    "  --objects N       objects in the field scene, 1..100000 (default 100)\n"
    "  --repeats N       alternated repeats of none and reddy, 1..100 (default 3; --quick: 2)\n"
    "  --results FILE    also write the output as the section \"" BCH_REPLAY_HEADING "\" of FILE\n"
    "                    (e.g. docs/RESULTS.md; other sections are kept)\n"
    "  --quick           200 frames, 2 repeats, and of the shared traces user1 only\n"
    "The shared folder: $HMDLOD_SHARED, else ../shared, else next to the executable's checkout.\n";

static int parse_args(int argc, char **argv, struct bch_replay_options *b)
{
    b->render_scale = 1.0;
    b->objects = 100;
    for (int i = 1; i < argc; ++i) {
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--quick")) {
            b->quick = 1;
            continue;
        }
        if (!strcmp(argv[i], "--frames")) {
            if (app_parse_long("--frames", val, 1, 100000000, &b->frames) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--render-scale")) {
            if (app_parse_double("--render-scale", val, &b->render_scale) != 0)
                return 1;
            if (!(b->render_scale > 0.0 && b->render_scale <= 4.0)) { /* before minutes of runs, not after */
                fprintf(stderr, "hmdlod: --render-scale: %g is outside (0, 4]\n", b->render_scale);
                return 1;
            }
        } else if (!strcmp(argv[i], "--repeats")) {
            if (app_parse_long("--repeats", val, 1, BCH_MAX_REPEATS, &b->repeats) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--objects")) {
            if (app_parse_long("--objects", val, 1, 100000, &b->objects) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--results") && val) {
            b->results = val;
        } else {
            fprintf(stderr, "hmdlod bench replay: unknown or incomplete option '%s' (try --help)\n", argv[i]);
            return 1;
        }
        ++i;
    }
    return 0;
}

int cmd_bench_replay(int argc, char **argv, int full_argc, char **full_argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(replay_usage, stdout);
        return 0;
    }
    struct bch_replay_options o;
    memset(&o, 0, sizeof o);
    if (parse_args(argc, argv, &o) != 0)
        return 1;
    return bch_replay(&o, full_argc, full_argv);
}
