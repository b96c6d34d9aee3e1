/* The row builder shared by the trace parser and the built-in clip (see trace_internal.h). */
#include "replay/trace_internal.h"

#include <stdlib.h>
#include <string.h>

void rpl_trace_free(struct rpl_trace *trace)
{
    if (!trace)
        return;
    free(trace->time_s);
    free(trace->orientation);
    free(trace->position_m);
    free(trace->gaze_dir);
    free(trace->outlier);
    memset(trace, 0, sizeof *trace);
}

int trace_builder_init(struct trace_builder *b, struct rpl_trace *out, enum rpl_trace_format format,
                       size_t capacity, int has_position, int has_gaze, struct hl_error *err)
{
    memset(b, 0, sizeof *b);
    memset(out, 0, sizeof *out);
    out->format = format;
    if (capacity == 0)
        capacity = 1;
    out->time_s = malloc(capacity * sizeof *out->time_s);
    out->orientation = malloc(capacity * sizeof *out->orientation);
    out->outlier = calloc(capacity, 1);
    if (has_position)
        out->position_m = malloc(capacity * sizeof *out->position_m);
    if (has_gaze)
        out->gaze_dir = malloc(capacity * sizeof *out->gaze_dir);
    if (!out->time_s || !out->orientation || !out->outlier || (has_position && !out->position_m) ||
        (has_gaze && !out->gaze_dir)) {
        rpl_trace_free(out);
        return hl_fail(err, "trace: out of memory for %zu rows", capacity);
    }
    b->trace = out;
    b->capacity = capacity;
    return 0;
}

void trace_builder_push(struct trace_builder *b, double time_s, hl_quatd q, const hl_vec3d *position_m,
                        const hl_vec3d *gaze_unit)
{
    struct rpl_trace *tr = b->trace;
    struct rpl_trace_report *rep = &tr->report;
    size_t i = tr->count;
    hl_quatd raw = q;
    int flipped = 0;

    if (i > 0) {
        hl_quatd p = b->prev_raw;
        /* The file's own sign change is what counts as a flip: each one is a place where naive
         * interpolation would take the long way round. Keeping the stored sequence continuous
         * means carrying the negation forward until the file flips back. */
        int changed_hemisphere = hl_q_dot(raw, p) < 0.0;
        if (changed_hemisphere)
            ++rep->sign_flips;
        flipped = b->prev_flipped ^ changed_hemisphere;
        if (raw.w == p.w && raw.x == p.x && raw.y == p.y && raw.z == p.z)
            ++rep->repeated_samples; /* stale tracker sample: kept, it still marks a time */
    }
    if (flipped)
        q = hl_q_neg(q);

    tr->time_s[i] = time_s;
    tr->orientation[i] = q;
    tr->outlier[i] = 0;
    if (tr->position_m)
        tr->position_m[i] = position_m ? *position_m : hl_v3(0, 0, 0);
    if (tr->gaze_dir)
        tr->gaze_dir[i] = gaze_unit ? *gaze_unit : hl_v3(0, 0, -1);

    if (i > 0) {
        double dt_s = time_s - tr->time_s[i - 1];
        if (dt_s > RPL_TRACE_GAP_S) {
            ++rep->gaps;
            if (dt_s > rep->longest_gap_s)
                rep->longest_gap_s = dt_s;
        }
        /* Per-step speed between consecutive rows, outliers included: the raw figure. */
        double step_degps = hl_q_angle_rad(tr->orientation[i - 1], q) * HL_DEG_PER_RAD / dt_s;
        if (step_degps > rep->max_step_speed_degps)
            rep->max_step_speed_degps = step_degps;
        /* Outliers are judged against the last good sample, so the row that returns from a
         * one-sample spike is not itself taken for a spike. */
        size_t g = b->last_good;
        double ref_degps = hl_q_angle_rad(tr->orientation[g], q) * HL_DEG_PER_RAD / (time_s - tr->time_s[g]);
        if (ref_degps > RPL_TRACE_OUTLIER_DEGPS && b->outlier_run < RPL_TRACE_MAX_OUTLIER_RUN) {
            tr->outlier[i] = 1;
            ++rep->speed_outliers;
            ++b->outlier_run;
        } else {
            b->last_good = i;
            b->outlier_run = 0;
        }
    }
    b->prev_raw = raw;
    b->prev_flipped = flipped;
    tr->count = i + 1;
    rep->rows = tr->count;
}
