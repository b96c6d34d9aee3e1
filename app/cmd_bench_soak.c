/* hmdlod bench soak: its options (bench/soak_report.c and bench/soak.c run it). */
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "bench/bench.h"

static const char soak_usage[] =
    "usage: hmdlod bench soak [--duration-s S] [--out DIR] [--render-scale F] [--sample-s S]\n\n"
    "For S seconds of wall time (default 3600), replays the Corbillon user 1 trace looped end to end\n"
    "(field scene, fs selector, Vive profile, headless EGL) paced at the display's 90 Hz, while a fake\n"
    "DK2 streams the shared 1 kHz IMU stream (looped) through the report parser, stream and fusion on\n"
    "its own thread. Writes DIR/soak.csv (a row per sample) and DIR/summary.json and prints resident\n"
    "memory growth, frame-time and CPU-per-frame drift, tracker rate and fd growth with the verdicts.\n"
    "  --duration-s S    wall-clock length, 1 ... 604800 s (default 3600)\n"
    "  --sample-s S      one soak.csv row every S seconds (default 10, or the duration if shorter)\n"
    "  --render-scale F  per-eye resolution factor of the Vive's pixels (default 0.5)\n"
    "  --out DIR         output folder (default hmdlod-soak)\n"
    "Needs the shared data folder: $HMDLOD_SHARED, else ../shared, else next to the executable's checkout.\n";

int cmd_bench_soak(int argc, char **argv, int full_argc, char **full_argv)
{
    struct bch_soak_options o;
    bch_soak_options_defaults(&o);
    o.out_dir = "hmdlod-soak";
    int sample_given = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            fputs(soak_usage, stdout);
            return 0;
        }
        const char *opt = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(opt, "--duration-s") && strcmp(opt, "--sample-s") && strcmp(opt, "--render-scale") &&
            strcmp(opt, "--out")) {
            fprintf(stderr, "hmdlod bench soak: unknown option '%s' (try --help)\n", opt);
            return 1;
        }
        if (!val) {
            fprintf(stderr, "hmdlod bench soak: %s needs a value (try --help)\n", opt);
            return 1;
        }
        ++i;
        if (!strcmp(opt, "--out")) {
            o.out_dir = val;
            continue;
        }
        sample_given |= !strcmp(opt, "--sample-s");
        double *dst = !strcmp(opt, "--duration-s") ? &o.duration_s : !strcmp(opt, "--sample-s") ? &o.sample_s
                                                                                               : &o.render_scale;
        if (app_parse_double(opt, val, dst))
            return 1;
    }
    if (!sample_given && o.sample_s > o.duration_s)
        o.sample_s = o.duration_s; /* a short run still gets its one row without being told */
    return bch_soak(&o, full_argc, full_argv);
}
