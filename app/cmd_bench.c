/* hmdlod bench: reproducible measurements with their context (machine, commit, command line, date),
 * printed as Markdown so a run can go straight into docs/RESULTS.md (--results does that).
 * This file is the dispatch table; each sub-bench's options are parsed in app/cmd_bench_<name>.c
 * and measured by bench/ (bench/bench.h). */
#include <stdio.h>
#include <string.h>

#include "bench/bench.h"
#include "app/commands.h"

struct bench {
    const char *name;
    int (*run)(int argc, char **argv, int full_argc, char **full_argv);
    const char *summary;
};
static const struct bench benches[] = {
    {"tracking", cmd_bench_tracking, "tracker accuracy and parse+fuse speed on the shared IMU streams, per device"},
    {"replay", cmd_bench_replay, "frame time and triangles, selector none vs reddy, on head-motion traces (Vive)"},
    {"agree", cmd_bench_agree, "two identical sessions in one process, alternated: do their mean frame times agree?"},
    {"lodgen", cmd_bench_lodgen, "LOD chain of the bunny: OpenMesh vs meshoptimizer time, triangles, Hausdorff error"},
    {"cull", cmd_bench_cull, "culling time, flat vs hierarchical, on 1k/10k/100k-object scenes under real head motion"},
    {"optimizer", cmd_bench_optimizer, "fs vs from-scratch greedy per frame (1k/10k/100k objects), turn, budget, limit, scaling"},
    {"live", cmd_bench_live, "live session: distortion pass cost at the Vive's resolution, present intervals at 90 Hz"},
    {"soak", cmd_bench_soak, "1 h (--duration-s) of looped replay at 90 Hz and a 1 kHz fake tracker: RSS growth, drift"},
    {"gaze", cmd_bench_gaze, "gaze models head/vor/tracked vs none on real traces: triangles, frame time, saccades"},
};
#define N_BENCHES (sizeof benches / sizeof benches[0])

static void print_bench_usage(FILE *f)
{
    cmd_bench_suite_usage(f);
    fprintf(f, "\n       hmdlod bench <name> [options]   (hmdlod bench <name> --help)\n\nbenches:\n");
    for (size_t i = 0; i < N_BENCHES; ++i)
        fprintf(f, "  %-9s %s\n", benches[i].name, benches[i].summary);
}

int cmd_bench(int argc, char **argv)
{
    if (argc >= 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help"))) {
        print_bench_usage(stdout);
        return 0;
    }
    if (argc < 2 || argv[1][0] == '-') /* no sub-bench name, or options first: the suite */
        return cmd_bench_suite(argc, argv, argc, argv);
    for (size_t i = 0; i < N_BENCHES; ++i)
        if (!strcmp(argv[1], benches[i].name))
            return benches[i].run(argc - 1, argv + 1, argc, argv);
    fprintf(stderr, "hmdlod bench: unknown bench '%s'; known:", argv[1]);
    for (size_t i = 0; i < N_BENCHES; ++i)
        fprintf(stderr, " %s", benches[i].name);
    fprintf(stderr, "\n");
    return 1;
}
