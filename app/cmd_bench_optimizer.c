/* hmdlod bench optimizer: its options (bench/optimizer.c measures). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/commands.h"
#include "bench/bench.h"

static const char opt_usage[] =
    "usage: hmdlod bench optimizer [--trace FILE] [--frames N] [--turn-pairs K] [--opt-limit-us T] [--hysteresis H]\n"
    "                              [--seed S] [--results FILE] [--quick]\n\n"
    "Times the cost-bounded optimizers on synthetic frames built by the embeddable core (acuity + lod):\n"
    "1k / 10k / 100k visible objects x 4 LODs on a shell around the viewer, head motion from a real trace at\n"
    "90 Hz, Vive eyes. Per frame: fs (incremental from last frame) vs the from-scratch greedy on the same\n"
    "problem, cold start, iterations, benefit as a share of the LP bound; fs time against the turn between\n"
    "frames and against the budget (10k objects); with --opt-limit-us the time-limited fs; and the per-frame\n"
    "cull + build + optimize time as a ground-grid scene grows 1x / 10x / 100x with a fixed view distance.\n"
    "  --trace FILE       head motion (default: Corbillon MMSys'18 user2 from the shared folder)\n"
    "  --frames N         frames per table (default 900; --quick 150)\n"
    "  --turn-pairs K     frame pairs per turn bin (default 60; --quick 15)\n"
    "  --opt-limit-us T   also run fs with Nirenstein's time limit T µs (10k and 100k objects)\n"
    "  --hysteresis H     error multiplier per level changed from last frame (default lod's, 1)\n"
    "  --seed S           placement seed (default 1)\n"
    "  --results FILE     also write the output as the section \"" BCH_OPTIMIZER_HEADING "\" of FILE\n";


static int parse_args(int argc, char **argv, struct bch_optimizer_options *o)
{
    o->seed = 1;
    for (int i = 1; i < argc; ++i) {
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--quick")) {
            o->quick = 1;
            continue;
        }
        if (!val) {
            fprintf(stderr, "hmdlod bench optimizer: %s needs a value (try --help)\n", argv[i]);
            return 1;
        }
        long lv;
        if (!strcmp(argv[i], "--trace"))
            o->trace = val;
        else if (!strcmp(argv[i], "--results"))
            o->results = val;
        else if (!strcmp(argv[i], "--frames")) {
            if (app_parse_long("--frames", val, 2, 1000000, &o->frames) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--turn-pairs")) {
            if (app_parse_long("--turn-pairs", val, 1, 100000, &o->pairs) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--opt-limit-us")) {
            if (app_parse_long("--opt-limit-us", val, 1, 10000000, &lv) != 0)
                return 1;
            o->limit_us = (double)lv;
        } else if (!strcmp(argv[i], "--hysteresis")) {
            char *end = NULL;
            o->hysteresis = strtod(val, &end);
            if (end == val || *end || !(o->hysteresis >= 0.0 && o->hysteresis <= 1.0)) {
                fprintf(stderr, "hmdlod bench optimizer: --hysteresis: '%s' is not a number in [0, 1]\n", val);
                return 1;
            }
            o->has_hysteresis = 1;
        } else if (!strcmp(argv[i], "--seed")) {
            if (app_parse_long("--seed", val, 0, 2147483647, &o->seed) != 0)
                return 1;
        } else {
            fprintf(stderr, "hmdlod bench optimizer: unknown option '%s' (try --help)\n", argv[i]);
            return 1;
        }
        ++i;
    }
    if (!o->frames)
        o->frames = o->quick ? 150 : 900;
    if (!o->pairs)
        o->pairs = o->quick ? 15 : 60;
    return 0;
}

int cmd_bench_optimizer(int argc, char **argv, int full_argc, char **full_argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(opt_usage, stdout);
        return 0;
    }
    struct bch_optimizer_options o;
    memset(&o, 0, sizeof o);
    if (parse_args(argc, argv, &o) != 0)
        return 1;
    return bch_optimizer(&o, full_argc, full_argv);
}
