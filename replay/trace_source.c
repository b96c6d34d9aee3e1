/* The trace as a trk_pose_source (Monado style: the base struct first, the trace after it). */
#include "replay/trace_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct trace_source {
    struct trk_pose_source base; /* first, so a base pointer is a trace_source pointer */
    struct rpl_trace trace;
};

static int ts_start(struct trk_pose_source *src, struct hl_error *err)
{
    (void)src, (void)err;
    return 0; /* recorded: nothing to start */
}

static void ts_stop(struct trk_pose_source *src) { (void)src; }

static int ts_pose_at(struct trk_pose_source *src, double time_s, struct trk_pose *out, struct hl_error *err)
{
    struct trace_source *ts = (struct trace_source *)src;
    if (!isfinite(time_s))
        return hl_fail(err, "%s: pose requested at a non-finite time", src->name);
    rpl_trace_sample(&ts->trace, time_s, out);
    return 0;
}

static enum trk_health ts_health(struct trk_pose_source *src, char *reason, size_t reason_size)
{
    (void)src;
    if (reason && reason_size)
        reason[0] = '\0';
    return TRK_HEALTH_OK;
}

static void ts_destroy(struct trk_pose_source *src)
{
    struct trace_source *ts = (struct trace_source *)src;
    rpl_trace_free(&ts->trace);
    free(ts);
}

int rpl_trace_source_create(struct rpl_trace *trace, struct trk_pose_source **out, struct hl_error *err)
{
    if (out)
        *out = NULL;
    if (!trace || !out || trace->count == 0)
        return hl_fail(err, "trace source: empty trace");
    struct trace_source *ts = calloc(1, sizeof *ts);
    if (!ts)
        return hl_fail(err, "trace source: out of memory");
    ts->trace = *trace;
    memset(trace, 0, sizeof *trace); /* ownership moves to the source */
    ts->base.name = "trace";
    ts->base.start = ts_start;
    ts->base.stop = ts_stop;
    ts->base.pose_at = ts_pose_at;
    ts->base.health = ts_health;
    ts->base.destroy = ts_destroy;
    ts->base.start_time_s = ts->trace.time_s[0];
    ts->base.end_time_s = ts->trace.time_s[ts->trace.count - 1];
    *out = &ts->base;
    return 0;
}
