/* hmdlod convert: a raw tracker recording → the project's trace CSV, through the same parser and
 * fusion as a live session (rpl_trace_from_recording), written atomically. */
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "replay/replay.h"

static const char convert_usage[] =
    "usage: hmdlod convert FILE --to OUT.csv\n"
    "  Converts a raw tracker recording (hmdlod record; docs/raw-recording.md) into a head-motion\n"
    "  trace: every report goes through the device's parser and the IMU fusion, one row per report\n"
    "  (t_s,qw,qx,qy,qz; device time from 0, fused body-to-world orientation). The CSV is written to\n"
    "  a temporary file and renamed, so OUT.csv is either complete or absent. A torn tail (a\n"
    "  recording cut off mid-record) is noted and skipped; a corrupt record is an error.\n"
    "  --to OUT.csv   the trace to write (replaced if it exists)\n";

int cmd_convert(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(convert_usage, stdout);
        return 0;
    }
    const char *in = NULL, *out = NULL;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--to")) {
            if (i + 1 >= argc) {
                fprintf(stderr, "hmdlod: --to needs a value\n");
                return 1;
            }
            out = argv[++i];
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            fprintf(stderr, "hmdlod: unknown option '%s'\n%s", argv[i], convert_usage);
            return 1;
        } else if (!in) {
            in = argv[i];
        } else {
            fprintf(stderr, "hmdlod convert: one recording at a time ('%s' is extra)\n", argv[i]);
            return 1;
        }
    }
    if (!in || !out) {
        fprintf(stderr, "hmdlod convert: %s is required\n%s", !in ? "FILE" : "--to OUT.csv", convert_usage);
        return 1;
    }
    struct rpl_trace trace;
    struct hl_error err;
    if (rpl_trace_from_recording(in, &trace, &err) != 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        return 1;
    }
    int rc = rpl_trace_write_csv(&trace, out, &err);
    if (rc != 0)
        fprintf(stderr, "hmdlod: %s\n", err.msg);
    else
        printf("wrote %s: %zu rows, %.3f s (%zu gaps over %.0f ms)\n", out, trace.count,
               trace.time_s[trace.count - 1], trace.report.gaps, RPL_TRACE_GAP_S * 1000.0);
    rpl_trace_free(&trace);
    return rc != 0;
}
