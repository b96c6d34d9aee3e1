/* Internal to replay/: the row-by-row builder that the parser and the built-in clip share, so a
 * synthetic trace gets exactly the same hemisphere, repeat, gap and outlier handling as a file. */
#ifndef HMDLOD_REPLAY_TRACE_INTERNAL_H
#define HMDLOD_REPLAY_TRACE_INTERNAL_H

#include "replay/replay.h"

/* After this many consecutive speed outliers the next sample is accepted as the new reference:
 * a longer excursion is a real re-orientation (tracking re-acquired), not a glitch. It also bounds
 * the walk past outliers in rpl_trace_sample, which keeps sampling O(log n). */
#define RPL_TRACE_MAX_OUTLIER_RUN 3

struct trace_builder {
    struct rpl_trace *trace;   /* arrays allocated with `capacity` entries */
    size_t capacity;
    hl_quatd prev_raw;         /* previous row's quaternion as read (before any flip) */
    int prev_flipped;          /* whether the previous row was stored negated */
    size_t last_good;          /* index of the latest non-outlier sample (speed reference) */
    size_t outlier_run;        /* consecutive outliers ending at the latest row */
};

/* Allocates arrays for `capacity` rows (position/gaze only when asked). 0 or −1 with err. */
int trace_builder_init(struct trace_builder *b, struct rpl_trace *out, enum rpl_trace_format format,
                       size_t capacity, int has_position, int has_gaze, struct hl_error *err);

/* Appends one validated row: time strictly after the previous row, q unit (project frame, as read,
 * any hemisphere), gaze unit when present. Keeps q in the previous row's hemisphere and updates
 * the report. The caller guarantees count < capacity. */
void trace_builder_push(struct trace_builder *b, double time_s, hl_quatd q_unit, const hl_vec3d *position_m,
                        const hl_vec3d *gaze_unit);

#endif
