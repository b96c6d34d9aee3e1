/* The soak's looped trace (bench/soak_internal.h): the trace source's sampling (rpl_trace_sample)
 * at a time that runs forward through the trace and back again, so that the pose never jumps and
 * the content repeats exactly every two spans. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/soak_internal.h"

struct soak_source {
    struct trk_pose_source base; /* first, so a base pointer is a soak_source pointer */
    struct rpl_trace trace;
    double t0_s, span_s;
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
    int backward = fmod(k, 2.0) != 0.0;
    rpl_trace_sample(&ss->trace, ss->trace.time_s[0] + (backward ? ss->span_s - in_s : in_s), out);
    if ((long)k > ss->loops)
        ss->loops = (long)k;
    if (backward) { /* the trace played in reverse: the head turns the other way at the same speed */
        out->angular_velocity_radps = hl_v3_scale(out->angular_velocity_radps, -1.0);
        out->gaze_angular_velocity_radps = hl_v3_scale(out->gaze_angular_velocity_radps, -1.0);
    }
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

long bch_soak_source_loops(const struct trk_pose_source *src) { return ((const struct soak_source *)src)->loops; }

double bch_soak_source_period_s(const struct trk_pose_source *src)
{
    return 2.0 * ((const struct soak_source *)src)->span_s;
}

int bch_soak_source_create(struct rpl_trace *trace, double t0_s, struct trk_pose_source **out, struct hl_error *err)
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
    /* Loop k covers [k·span, (k+1)·span): forward when k is even, backward when odd. */
    size_t n = ss->trace.count;
    ss->span_s = ss->trace.time_s[n - 1] - ss->trace.time_s[0];
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
