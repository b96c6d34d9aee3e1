/* hmdlod bench tracking: its options (bench/tracking.c measures). */
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "bench/bench.h"

int cmd_bench_tracking(int argc, char **argv, int full_argc, char **full_argv)
{
    if (app_wants_help(argc, argv)) {
        printf("usage: hmdlod bench tracking [--quick] [--stream NAME|all] [--seconds S] [--repeats N]\n"
               "                            [--results FILE]\n\n"
               "Encodes each shared IMU stream (shared/data/imu) into every supported tracker's reports at its\n"
               "native rate, parses and fuses them, and prints accuracy against the ground truth and speed;\n"
               "runs OpenHMD's fusion (libopenhmd, when built in) on the same samples, scored the same way;\n"
               "and quotes the OpenHMD / Monado figures from data/README.md. Markdown output.\n"
               "  --quick         the first 10 s of each stream, 1 timing pass (unless --seconds/--repeats)\n"
               "  --stream NAME   one of the streams below, or all (default)\n"
               "  --seconds S     only the first S seconds of each stream (default: all 60)\n"
               "  --repeats N     whole-stream timing passes, median reported (default 5)\n"
               "  --results FILE  also write the output as the section \"" BCH_TRACKING_HEADING "\" of FILE\n"
               "                  (e.g. docs/RESULTS.md; other sections are kept)\n"
               "streams:");
        bch_tracking_print_streams(stdout);
        printf("\nThe shared folder: $HMDLOD_SHARED, else ../shared, else next to the executable's checkout.\n");
        return 0;
    }
    struct bch_tracking_options o = {.stream = "all", .results = NULL, .seconds = 0, .repeats = 5};
    int quick = 0, repeats_given = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--stream") && i + 1 < argc) {
            o.stream = argv[++i];
        } else if (!strcmp(argv[i], "--seconds")) {
            if (app_parse_double("--seconds", i + 1 < argc ? argv[++i] : NULL, &o.seconds) != 0)
                return 1;
            if (!(o.seconds >= 0.5 && o.seconds <= 1e6)) {
                fprintf(stderr, "hmdlod bench tracking: --seconds %g: need at least 0.5\n", o.seconds);
                return 1;
            }
        } else if (!strcmp(argv[i], "--repeats")) {
            if (app_parse_long("--repeats", i + 1 < argc ? argv[++i] : NULL, 1, 1000, &o.repeats) != 0)
                return 1;
            repeats_given = 1;
        } else if (!strcmp(argv[i], "--quick")) {
            quick = 1;
        } else if (!strcmp(argv[i], "--results") && i + 1 < argc) {
            o.results = argv[++i];
        } else {
            fprintf(stderr, "hmdlod bench tracking: unknown or incomplete option '%s' (try --help)\n", argv[i]);
            return 1;
        }
    }
    if (quick) { /* the suite's quick mode: a short slice, one timing pass, unless told otherwise */
        if (o.seconds == 0)
            o.seconds = 10;
        if (!repeats_given)
            o.repeats = 1;
    }
    return bch_tracking(&o, full_argc, full_argv);
}
