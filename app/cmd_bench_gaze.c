/* hmdlod bench gaze: its options (bench/gaze.c measures). */
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "bench/bench.h"

static const char gaze_usage[] =
    "usage: hmdlod bench gaze [--frames N] [--objects N] [--render-scale F] [--results FILE] [--quick]\n\n"
    "Replays real traces through the field and auditorium scenes on the Vive with selector reddy under\n"
    "each gaze model (head, vor; tracked where the trace has gaze, also with fs), each with and without\n"
    "the velocity term, against none (the finest LOD), and prints triangles, frame time, the share of\n"
    "the velocity term's saving that survives under vor, and for tracked the saccades and the\n"
    "refinements that missed 28 ms, as Markdown. Traces from the shared folder: Corbillon MMSys'18,\n"
    "Nasrabadi MMSys'19, EDVAM (gaze).\n"
    "  --frames N        frames per run from each trace's start (default 300; --quick 60)\n"
    "  --objects N       objects in the field scene, 1..100000 (default 1000; --quick 300)\n"
    "  --render-scale F  per-eye resolution factor in (0, 4] (default 1; --quick 0.5)\n"
    "  --results FILE    also write the output as the section \"" BCH_GAZE_HEADING "\" of FILE\n"
    "  --quick           fewer frames and objects, half the resolution (75 s of CPU here)\n"
    "Traces: Corbillon user1, Nasrabadi 322SAJ_9, EDVAM participant2.\n"
    "The shared folder: $HMDLOD_SHARED, else ../shared, else next to the executable's checkout.\n";

static int parse_args(int argc, char **argv, struct bch_gaze_options *b)
{
    b->objects = 0; /* 0: the default for the mode */
    b->render_scale = 0.0; /* 0: the default for the mode */
    for (int i = 1; i < argc; ++i) {
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--quick")) {
            b->quick = 1;
            continue;
        }
        if (!strcmp(argv[i], "--frames")) {
            if (app_parse_long("--frames", val, 1, 100000000, &b->frames) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--objects")) {
            if (app_parse_long("--objects", val, 1, 100000, &b->objects) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--render-scale")) {
            if (app_parse_double("--render-scale", val, &b->render_scale) != 0)
                return 1;
            if (!(b->render_scale > 0.0 && b->render_scale <= 4.0)) {
                fprintf(stderr, "hmdlod: --render-scale: %g is outside (0, 4]\n", b->render_scale);
                return 1;
            }
        } else if (!strcmp(argv[i], "--results") && val) {
            b->results = val;
        } else {
            fprintf(stderr, "hmdlod bench gaze: unknown or incomplete option '%s' (try --help)\n", argv[i]);
            return 1;
        }
        ++i;
    }
    if (!b->frames)
        b->frames = b->quick ? 60 : 300;
    if (!b->objects)
        b->objects = b->quick ? 300 : 1000;
    if (!(b->render_scale > 0.0))
        b->render_scale = b->quick ? 0.5 : 1.0;
    return 0;
}

int cmd_bench_gaze(int argc, char **argv, int full_argc, char **full_argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(gaze_usage, stdout);
        return 0;
    }
    struct bch_gaze_options o;
    memset(&o, 0, sizeof o);
    if (parse_args(argc, argv, &o) != 0)
        return 1;
    return bch_gaze(&o, full_argc, full_argv);
}
