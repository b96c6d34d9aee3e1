/* The row builder shared by the trace parsers, the raw-recording reader and the built-in clip (see
 * trace_internal.h): push stores rows as read; finish resolves repeated timestamps and fills the
 * time-dependent part of the report. */
#include <math.h>
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
    b->prev_raw = raw;
    b->prev_flipped = flipped;
    tr->count = i + 1;
    rep->rows = tr->count;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of the steps between consecutive distinct times; 0 when there are none, −1 when out of
 * memory. The median, not the mean: a log at 1 kHz rounded to 10 ms steps by exactly 10 ms, and a
 * few long gaps must not widen that. */
static double median_distinct_step(const double *t, size_t n)
{
    double *steps = malloc((n > 1 ? n - 1 : 1) * sizeof *steps);
    if (!steps)
        return -1.0;
    size_t k = 0;
    for (size_t i = 1; i < n; ++i)
        if (t[i] > t[i - 1])
            steps[k++] = t[i] - t[i - 1];
    double median = 0.0;
    if (k > 0) {
        qsort(steps, k, sizeof *steps, cmp_double);
        median = steps[k / 2];
    }
    free(steps);
    return median;
}

/* Rows that share a timestamp were sampled during one tick of a coarse clock: they keep their order
 * and are placed evenly over [T, T + s), s = min(next distinct time − T, median step) — the tick
 * they fell in, never stretched across a gap. Exact for a truncating clock; a rounding clock leaves
 * them a constant half tick late, which shifts latency but not velocity. */
static int spread_timestamps(struct rpl_trace *tr, const char *name, size_t first_row_line, struct hl_error *err)
{
    size_t n = tr->count;
    size_t i = 1;
    while (i < n && tr->time_s[i] != tr->time_s[i - 1])
        ++i;
    if (i >= n)
        return 0; /* the usual case: no repeated time, nothing allocated */
    double step = median_distinct_step(tr->time_s, n);
    if (step < 0.0)
        return hl_fail(err, "%s: out of memory spreading repeated timestamps", name);
    if (step == 0.0)
        return hl_fail(err, "%s:%zu: all %zu rows share one time (%.9g s): no rate to spread them over", name,
                       first_row_line, n, tr->time_s[0]);
    struct rpl_trace_report *rep = &tr->report;
    for (size_t start = 0; start < n;) {
        size_t end = start + 1;
        while (end < n && tr->time_s[end] == tr->time_s[start])
            ++end;
        size_t run = end - start;
        if (run > 1) {
            double t0 = tr->time_s[start];
            double span = end < n && tr->time_s[end] - t0 < step ? tr->time_s[end] - t0 : step;
            for (size_t k = 1; k < run; ++k) {
                tr->time_s[start + k] = t0 + span * (double)k / (double)run;
                /* Near the double's limits (1e308 s) the spacing is below its resolution, or the sum
                 * overflows: the rows would stay equal or pass the next time, so the trace is refused
                 * rather than left non-increasing. */
                double x = tr->time_s[start + k];
                if (!(x > tr->time_s[start + k - 1]) || !isfinite(x) || (end < n && !(x < tr->time_s[end])))
                    return hl_fail(err, "%s: %zu rows share the time %.9g s, too large to place them apart "
                                        "(%.3g s steps are beyond its resolution)",
                                   name, run, t0, span / (double)run);
            }
            ++rep->timestamp_runs;
            rep->repeated_timestamps += run - 1;
        }
        start = end;
    }
    rep->timestamp_step_s = step;
    return 0;
}

/* Gaps, per-step speed and outliers, on the final times. */
static void judge_steps(struct rpl_trace *tr)
{
    struct rpl_trace_report *rep = &tr->report;
    size_t last_good = 0, outlier_run = 0;
    for (size_t i = 1; i < tr->count; ++i) {
        double t = tr->time_s[i];
        hl_quatd q = tr->orientation[i];
        double dt_s = t - tr->time_s[i - 1];
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
        double ref_degps = hl_q_angle_rad(tr->orientation[last_good], q) * HL_DEG_PER_RAD / (t - tr->time_s[last_good]);
        if (ref_degps > RPL_TRACE_OUTLIER_DEGPS && outlier_run < RPL_TRACE_MAX_OUTLIER_RUN) {
            tr->outlier[i] = 1;
            ++rep->speed_outliers;
            ++outlier_run;
        } else {
            last_good = i;
            outlier_run = 0;
        }
    }
}

int trace_builder_finish(struct trace_builder *b, const char *name, size_t first_row_line, struct hl_error *err)
{
    struct rpl_trace *tr = b->trace;
    if (spread_timestamps(tr, name ? name : "trace", first_row_line, err) != 0) {
        rpl_trace_free(tr);
        return -1;
    }
    judge_steps(tr);
    return 0;
}
