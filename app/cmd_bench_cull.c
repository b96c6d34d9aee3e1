/* hmdlod bench cull: its options (bench/cull.c measures). */
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "bench/bench.h"

static const char cull_usage[] =
    "usage: hmdlod bench cull [--trace FILE] [--frames N] [--display NAME|FILE] [--seed S] [--results FILE] [--quick]\n\n"
    "Culls generated scenes of 1k, 10k and 100k objects (a ground grid around the viewer, grouped as a\n"
    "quadtree of 4 x 4) against the union of both eye frusta along a head-motion trace, once testing every\n"
    "object (flat) and once walking the groups (hierarchical), and prints per-frame time (median, p95),\n"
    "visible groups and objects, spheres tested, the flat/hierarchical ratios and a least-squares fit of\n"
    "the hierarchical time to what it did, as Markdown.\n"
    "  --trace FILE      head motion (default: Corbillon MMSys'18 user1 from the shared folder, else the\n"
    "                    built-in clip)\n"
    "  --frames N        frames at the display's refresh (default 2000; --quick 300)\n"
    "  --display NAME    display profile for the frusta (default vive)\n"
    "  --seed S          placement seed (default 1)\n"
    "  --results FILE    also write the output as the section \"" BCH_CULL_HEADING "\" of FILE\n";


static int parse_args(int argc, char **argv, struct bch_cull_options *o)
{
    o->display = "vive";
    o->seed = 1;
    for (int i = 1; i < argc; ++i) {
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--quick")) {
            o->quick = 1;
            continue;
        }
        if (!val) {
            fprintf(stderr, "hmdlod bench cull: %s needs a value (try --help)\n", argv[i]);
            return 1;
        }
        if (!strcmp(argv[i], "--trace"))
            o->trace = val;
        else if (!strcmp(argv[i], "--display"))
            o->display = val;
        else if (!strcmp(argv[i], "--results"))
            o->results = val;
        else if (!strcmp(argv[i], "--frames")) {
            if (app_parse_long("--frames", val, 1, 10000000, &o->frames) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--seed")) {
            if (app_parse_long("--seed", val, 0, 2147483647, &o->seed) != 0)
                return 1;
        } else {
            fprintf(stderr, "hmdlod bench cull: unknown option '%s' (try --help)\n", argv[i]);
            return 1;
        }
        ++i;
    }
    if (!o->frames)
        o->frames = o->quick ? 300 : 2000;
    return 0;
}

int cmd_bench_cull(int argc, char **argv, int full_argc, char **full_argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(cull_usage, stdout);
        return 0;
    }
    struct bch_cull_options o;
    memset(&o, 0, sizeof o);
    if (parse_args(argc, argv, &o) != 0)
        return 1;
    return bch_cull(&o, full_argc, full_argv);
}
