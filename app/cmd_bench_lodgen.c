/* hmdlod bench lodgen: its options (bench/lodgen.c measures). */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "bench/bench.h"

int cmd_bench_lodgen(int argc, char **argv, int full_argc, char **full_argv)
{
    if (app_wants_help(argc, argv)) {
        printf("usage: hmdlod bench lodgen [--quick] [--repeats N] [--results FILE]\n\n"
               "Imports shared/data/meshes/stanford-bunny.obj and decimates it to 50, 25, 10 and 2 %% of its\n"
               "triangles (one chain, each level from the one before) with OpenMesh and with meshoptimizer;\n"
               "prints the chain time (median of the repeats, import timed apart), each level's triangles and\n"
               "two-sided Hausdorff error, and where OpenMesh's time goes. Markdown output.\n"
               "  --quick         1 repeat and 2^17 Hausdorff samples (default: 3 repeats, 2^20 samples)\n"
               "  --repeats N     timed repeats of each chain (1…15)\n"
               "  --results FILE  also write the output as the section \"" BCH_LODGEN_HEADING "\" of FILE\n");
        return 0;
    }
    struct bch_lodgen_options o = {.repeats = 3, .hausdorff_samples = (uint64_t)1 << 20, .results = NULL};
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--quick")) {
            o.repeats = 1, o.hausdorff_samples = (uint64_t)1 << 17;
        } else if (!strcmp(argv[i], "--repeats")) {
            if (app_parse_long("--repeats", i + 1 < argc ? argv[++i] : NULL, 1, 15, &o.repeats) != 0)
                return 1;
        } else if (!strcmp(argv[i], "--results") && i + 1 < argc) {
            o.results = argv[++i];
        } else {
            fprintf(stderr, "hmdlod bench lodgen: unknown or incomplete option '%s' (try --help)\n", argv[i]);
            return 1;
        }
    }
    return bch_lodgen(&o, full_argc, full_argv);
}
