/* The desk pose source of a live session without a tracker (--device none, or none found): the
 * head turns by mouse and keys, plus an optional scripted yaw at a constant rate so that a session
 * (a test, a bench) is deterministic in its motion. Orientation is yaw about world +Y then pitch
 * about the head's +X; the position is the origin (frame.c's neck model puts the eyes ahead of
 * it, as for orientation-only traces). */
#include <math.h>
#include <stdlib.h>

#include "live/live.h"

struct desk_source {
    struct trk_pose_source base; /* first, so a base pointer is a desk_source pointer */
    double t0_s, yaw_rate_radps;
    double look_yaw_rad, look_pitch_rad;   /* from the mouse and keys */
    double look_yaw_radps, look_pitch_radps; /* of the last look step, for the acuity model */
};

static int ds_start(struct trk_pose_source *src, struct hl_error *err)
{
    (void)src, (void)err;
    return 0;
}

static void ds_stop(struct trk_pose_source *src) { (void)src; }

static int ds_pose_at(struct trk_pose_source *src, double time_s, struct trk_pose *out, struct hl_error *err)
{
    struct desk_source *d = (struct desk_source *)src;
    if (!isfinite(time_s))
        return hl_fail(err, "%s: pose requested at a non-finite time", src->name);
    trk_pose_init_still(out, time_s);
    double yaw = d->look_yaw_rad + d->yaw_rate_radps * (time_s - d->t0_s);
    double pitch = fmax(-1.4, fmin(1.4, d->look_pitch_rad));
    hl_quatd qy = hl_q_from_axis_angle(hl_v3(0, 1, 0), yaw), qp = hl_q_from_axis_angle(hl_v3(1, 0, 0), pitch);
    out->orientation = hl_q_mul(qy, qp);
    /* World frame: yaw about +Y, pitch about the yawed head's +X (pitch's own axis). */
    hl_vec3d pitch_axis = hl_q_rotate(qy, hl_v3(1, 0, 0));
    out->angular_velocity_radps = hl_v3_add(hl_v3(0, d->yaw_rate_radps + d->look_yaw_radps, 0),
                                            hl_v3_scale(pitch_axis, d->look_pitch_radps));
    return 0;
}

static enum trk_health ds_health(struct trk_pose_source *src, char *reason, size_t reason_size)
{
    (void)src;
    if (reason && reason_size)
        reason[0] = '\0';
    return TRK_HEALTH_OK;
}

static void ds_destroy(struct trk_pose_source *src) { free(src); }

int liv_desk_source_create(double t0_s, double yaw_rate_degps, struct trk_pose_source **out, struct hl_error *err)
{
    *out = NULL;
    if (!isfinite(yaw_rate_degps) || fabs(yaw_rate_degps) > 1000.0)
        return hl_fail(err, "--yaw-degps: %g deg/s is outside [-1000, 1000]", yaw_rate_degps);
    struct desk_source *d = calloc(1, sizeof *d);
    if (!d)
        return hl_fail(err, "desk source: out of memory");
    d->t0_s = t0_s;
    d->yaw_rate_radps = yaw_rate_degps * HL_RAD_PER_DEG;
    d->base.name = "desk (mouse and keys)";
    d->base.start = ds_start;
    d->base.stop = ds_stop;
    d->base.pose_at = ds_pose_at;
    d->base.health = ds_health;
    d->base.destroy = ds_destroy;
    d->base.start_time_s = t0_s;
    d->base.end_time_s = t0_s - 1.0; /* live: no span */
    *out = &d->base;
    return 0;
}

void liv_desk_source_look(struct trk_pose_source *src, double dyaw_rad, double dpitch_rad, double dt_s)
{
    struct desk_source *d = (struct desk_source *)src;
    d->look_yaw_rad += dyaw_rad;
    d->look_pitch_rad = fmax(-1.4, fmin(1.4, d->look_pitch_rad + dpitch_rad));
    d->look_yaw_radps = dt_s > 0.0 ? dyaw_rad / dt_s : 0.0;
    d->look_pitch_radps = dt_s > 0.0 ? dpitch_rad / dt_s : 0.0;
}
