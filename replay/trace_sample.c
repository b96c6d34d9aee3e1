/* Sampling a trace at any time: slerp between the good samples that bracket t; angular and linear
 * velocity from a ±RPL_VELOCITY_HALF_WINDOW_S window, the world gaze's angular velocity from a
 * ±RPL_GAZE_VELOCITY_HALF_WINDOW_S one. No allocation; binary search, O(log n). */
#include "replay/trace_internal.h"

#include <math.h>

/* Largest index i with time_s[i] <= t, for t within [time_s[0], time_s[n−1]]. */
static size_t find_floor(const struct rpl_trace *tr, double t)
{
    size_t lo = 0, hi = tr->count - 1;
    while (lo < hi) {
        size_t mid = lo + (hi - lo + 1) / 2;
        if (tr->time_s[mid] <= t)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

static int is_outlier(const struct rpl_trace *tr, size_t i) { return tr->outlier && tr->outlier[i]; }

/* The good samples around t (outliers skipped; runs are at most RPL_TRACE_MAX_OUTLIER_RUN long and
 * sample 0 is never one, so the walks are short). *u is the fraction from lo to hi; lo == hi at the
 * clamped ends. */
static void bracket(const struct rpl_trace *tr, double t, size_t *lo_out, size_t *hi_out, double *u_out)
{
    size_t n = tr->count;
    if (!(t > tr->time_s[0])) /* also catches NaN */
        t = tr->time_s[0];
    if (t > tr->time_s[n - 1])
        t = tr->time_s[n - 1];
    size_t lo = find_floor(tr, t);
    while (lo > 0 && is_outlier(tr, lo))
        --lo;
    size_t hi = lo + 1;
    while (hi < n && (is_outlier(tr, hi) || tr->time_s[hi] <= t))
        ++hi; /* past outliers; a sample at or before t after lo can only be an outlier */
    if (hi >= n) {
        /* No good sample after t: hold the last good one. */
        *lo_out = *hi_out = lo;
        *u_out = 0.0;
        return;
    }
    double span = tr->time_s[hi] - tr->time_s[lo];
    double u = (t - tr->time_s[lo]) / span;
    *lo_out = lo;
    *hi_out = hi;
    *u_out = u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u);
}

static hl_quatd orientation_at(const struct rpl_trace *tr, double t)
{
    size_t lo, hi;
    double u;
    bracket(tr, t, &lo, &hi, &u);
    if (lo == hi || u == 0.0)
        return tr->orientation[lo];
    return hl_q_slerp(tr->orientation[lo], tr->orientation[hi], u);
}

static hl_vec3d position_at(const struct rpl_trace *tr, double t)
{
    size_t lo, hi;
    double u;
    bracket(tr, t, &lo, &hi, &u);
    hl_vec3d a = tr->position_m[lo], b = tr->position_m[hi];
    return hl_v3_add(a, hl_v3_scale(hl_v3_sub(b, a), u));
}

/* Head-frame gaze at t: normalised lerp (gaze steps between samples are small); antipodal
 * neighbours (a zero mid-point) keep the earlier direction rather than inventing one. */
static hl_vec3d gaze_head_at(const struct rpl_trace *tr, size_t lo, size_t hi, double u)
{
    hl_vec3d a = tr->gaze_dir[lo], b = tr->gaze_dir[hi];
    hl_vec3d g = hl_v3_add(a, hl_v3_scale(hl_v3_sub(b, a), u));
    double len = hl_v3_length(g);
    return len > 1e-9 ? hl_v3_scale(g, 1.0 / len) : a;
}

/* The gaze in the world at t: g_w = q(t) · g_head(t). */
static hl_vec3d gaze_world_at(const struct rpl_trace *tr, double t)
{
    size_t lo, hi;
    double u;
    bracket(tr, t, &lo, &hi, &u);
    hl_quatd q = (lo == hi || u == 0.0) ? tr->orientation[lo] : hl_q_slerp(tr->orientation[lo], tr->orientation[hi], u);
    return hl_q_rotate(q, gaze_head_at(tr, lo, hi, u));
}

/* The window [t − h, t + h] clamped to the trace; its span is 0 at a one-row trace or NaN t. */
static void window(const struct rpl_trace *tr, double t, double h, double *ta, double *tb)
{
    double t0 = tr->time_s[0], t1 = tr->time_s[tr->count - 1];
    *ta = isfinite(t) ? t - h : t0;
    *tb = isfinite(t) ? t + h : t0;
    if (*ta < t0)
        *ta = t0;
    if (*tb > t1)
        *tb = t1;
}

void rpl_trace_sample(const struct rpl_trace *trace, double time_s, struct trk_pose *out)
{
    trk_pose_init_still(out, time_s);
    if (!trace || trace->count == 0)
        return;
    const struct rpl_trace *tr = trace;

    size_t lo, hi;
    double u;
    bracket(tr, time_s, &lo, &hi, &u);
    out->orientation = (lo == hi || u == 0.0) ? tr->orientation[lo]
                                              : hl_q_slerp(tr->orientation[lo], tr->orientation[hi], u);
    if (tr->position_m) {
        hl_vec3d a = tr->position_m[lo], b = tr->position_m[hi];
        out->position_m = hl_v3_add(a, hl_v3_scale(hl_v3_sub(b, a), u));
        out->has_position = 1;
    }
    if (tr->gaze_dir) {
        out->gaze_dir_head = gaze_head_at(tr, lo, hi, u);
        out->has_gaze = 1;
    }

    /* Angular velocity over a window, not per step: the Corbillon traces are quantised to 0.1°, so
     * a single 17 ms step reads ±6 deg/s of noise; ±25 ms averages that down. Both window ends are
     * slerped orientations, so across a gap the rate is the gap's mean rate, never a spike. For
     * body-to-world q, q(t+h) = exp(ω_world·2h) ⊗ q(t−h), hence ω_world = log(q2 ⊗ q1*) / span.
     * The linear velocity is the central difference of the interpolated positions over the same
     * window, so across a gap it too is the gap's mean rate. */
    double ta, tb;
    window(tr, time_s, RPL_VELOCITY_HALF_WINDOW_S, &ta, &tb);
    double span_s = tb - ta;
    if (span_s > 1e-9) {
        hl_quatd qa = orientation_at(tr, ta), qb = orientation_at(tr, tb);
        out->angular_velocity_radps = hl_v3_scale(hl_q_log(hl_q_mul(qb, hl_q_conj(qa))), 1.0 / span_s);
        if (tr->position_m)
            out->linear_velocity_mps = hl_v3_scale(hl_v3_sub(position_at(tr, tb), position_at(tr, ta)), 1.0 / span_s);
    }

    /* The world gaze's rate over a narrower window: saccades last 20–80 ms, and a ±5 ms window keeps
     * 85–99 % of a minimum-jerk saccade's peak where ±25 ms keeps 21–77 %. At 31 Hz
     * (EDVAM) the window is shorter than a step, so the rate is that step's own: nothing finer
     * exists there. ω = (g_a × g_b)/|g_a × g_b| · atan2(|g_a × g_b|, g_a·g_b) / span. */
    if (tr->gaze_dir) {
        window(tr, time_s, RPL_GAZE_VELOCITY_HALF_WINDOW_S, &ta, &tb);
        span_s = tb - ta;
        if (span_s > 1e-9) {
            hl_vec3d ga = gaze_world_at(tr, ta), gb = gaze_world_at(tr, tb);
            hl_vec3d axis = hl_v3_cross(ga, gb);
            double s = hl_v3_length(axis);
            if (s > 1e-15)
                out->gaze_angular_velocity_radps = hl_v3_scale(axis, atan2(s, hl_v3_dot(ga, gb)) / (s * span_s));
        }
    }
}
