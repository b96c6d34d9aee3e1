/* The trace report as one line, for wherever a loaded trace is announced. */
#include "replay/trace_internal.h"

#include <stdio.h>

void rpl_trace_report_format(const struct rpl_trace_report *r, char *buf, size_t size)
{
    if (!buf || size == 0)
        return;
    int k = snprintf(buf, size,
                     "%zu rows, %zu sign flips, %zu repeated samples, %zu gaps over %.0f ms (longest %.0f ms), "
                     "%zu speed outliers, %zu repeated timestamps in %zu runs",
                     r->rows, r->sign_flips, r->repeated_samples, r->gaps, RPL_TRACE_GAP_S * 1000.0,
                     r->longest_gap_s * 1000.0, r->speed_outliers, r->repeated_timestamps, r->timestamp_runs);
    if (k < 0 || (size_t)k >= size)
        return;
    if (r->low_confidence_gaze || r->placeholder_rows || r->held_orientations)
        snprintf(buf + k, size - (size_t)k,
                 ", %zu rows without a measured gaze (interpolated), %zu placeholder rows skipped, "
                 "%zu near-vertical forwards held",
                 r->low_confidence_gaze, r->placeholder_rows, r->held_orientations);
}
