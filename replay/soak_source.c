/* The soak's looped trace (replay/soak_internal.h): the trace source's sampling (rpl_trace_sample)
 * at a time that wraps, each loop turned so it continues the previous one. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "replay/soak_internal.h"

struct soak_source {
    struct trk_pose_source base; /* first, so a base pointer is a soak_source pointer */
    struct rpl_trace trace;
    double t0_s, span_s;
    hl_vec3d step_axis; /* D = q_end ⊗ q_start* as axis and angle: D^k turns by k·angle */
    double step_rad;
    long loops;
};

static int ss_start(struct trk_pose_source *src, struct hl_error *err)
{
    (void)src, (void)err;
    return 0;
}

static void ss_stop(struct trk_pose_source *src) { (void)src; }

static int ss_pose_at(struct trk_pose_source *src, double time_s, struct trk_pose *out, struct hl_error *err)
{
    struct soak_source *ss = (struct soak_source *)src;
    if (!isfinite(time_s))
        return hl_fail(err, "%s: pose requested at a non-finite time", src->name);
    double rel_s = time_s - ss->t0_s;
    if (rel_s < 0.0)
        rel_s = 0.0;
    double k = floor(rel_s / ss->span_s); /* double: no overflow, exact for any realistic count */
    double in_s = rel_s - k * ss->span_s;
    if (in_s > ss->span_s)
        in_s = ss->span_s;
    rpl_trace_sample(&ss->trace, ss->trace.time_s[0] + in_s, out);
    if ((long)k > ss->loops)
        ss->loops = (long)k;
    /* fmod keeps the angle small so that sin/cos stay exact after thousands of loops */
    hl_quatd r = hl_q_from_axis_angle(ss->step_axis, fmod(k * ss->step_rad, 2.0 * HL_PI));
    out->orientation = hl_q_normalize(hl_q_mul(r, out->orientation));
    out->angular_velocity_radps = hl_q_rotate(r, out->angular_velocity_radps);
    out->gaze_angular_velocity_radps = hl_q_rotate(r, out->gaze_angular_velocity_radps);
    out->position_m = hl_v3(0, 0, 0);
    out->linear_velocity_mps = hl_v3(0, 0, 0);
    out->has_position = 0;
    out->time_s = time_s;
    return 0;
}

static enum trk_health ss_health(struct trk_pose_source *src, char *reason, size_t reason_size)
{
    (void)src;
    if (reason && reason_size)
        reason[0] = '\0';
    return TRK_HEALTH_OK;
}

static void ss_destroy(struct trk_pose_source *src)
{
    struct soak_source *ss = (struct soak_source *)src;
    rpl_trace_free(&ss->trace);
    free(ss);
}

long rpl_soak_source_loops(const struct trk_pose_source *src) { return ((const struct soak_source *)src)->loops; }

int rpl_soak_source_create(struct rpl_trace *trace, double t0_s, struct trk_pose_source **out, struct hl_error *err)
{
    *out = NULL;
    if (!trace || trace->count < 2 || !(trace->time_s[trace->count - 1] > trace->time_s[0]))
        return hl_fail(err, "soak: the trace needs at least two samples spanning some time");
    struct soak_source *ss = calloc(1, sizeof *ss);
    if (!ss)
        return hl_fail(err, "soak: out of memory");
    ss->trace = *trace;
    memset(trace, 0, sizeof *trace);
    ss->t0_s = t0_s;
    /* Loop k covers [k·span, (k+1)·span) and is turned by D^k: its first pose is loop k−1's last. */
    size_t n = ss->trace.count;
    double span = ss->trace.time_s[n - 1] - ss->trace.time_s[0];
    ss->span_s = span;
    hl_quatd q0 = ss->trace.orientation[0], q1 = ss->trace.orientation[n - 1];
    hl_quatd d = hl_q_normalize(hl_q_mul(q1, hl_q_conj(q0)));
    if (d.w < 0) /* shortest arc */
        d = hl_q(-d.w, -d.x, -d.y, -d.z);
    double s = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    ss->step_rad = 2.0 * atan2(s, d.w); /* atan2, not acos: exact near identity */
    ss->step_axis = s > 1e-15 ? hl_v3(d.x / s, d.y / s, d.z / s) : hl_v3(0, 1, 0);
    ss->base.name = "looped trace";
    ss->base.start = ss_start;
    ss->base.stop = ss_stop;
    ss->base.pose_at = ss_pose_at;
    ss->base.health = ss_health;
    ss->base.destroy = ss_destroy;
    ss->base.start_time_s = 0.0;
    ss->base.end_time_s = -1.0; /* endless, like a live source */
    *out = &ss->base;
    return 0;
}
