/* tracking/pose_source.h: the pose-source interface — struct trk_pose, struct trk_pose_source (a
 * small struct of function pointers) and its inline call helpers. Part of the tracking/tracking.h
 * umbrella; self-contained. */
#ifndef HMDLOD_TRACKING_POSE_SOURCE_H
#define HMDLOD_TRACKING_POSE_SOURCE_H

#include "base/base.h"

/* One head pose at a time. Orientation is body-to-world (v_world = q v_body q*). */
struct trk_pose {
    double time_s;
    hl_quatd orientation;
    hl_vec3d position_m;          /* world; zero when the source has no position */
    hl_vec3d angular_velocity_radps; /* world frame */
    hl_vec3d linear_velocity_mps; /* world frame, of position_m; zero when the source has no position.
                                   * Trace sources: over ±25 ms, like the angular velocity */
    hl_vec3d gaze_dir_head;       /* unit, head frame; (0,0,−1) when eye locked to the head */
    hl_vec3d gaze_angular_velocity_radps; /* world frame, of the gaze in the world (eye + head); zero
                                           * when the source has no gaze. Perpendicular to the gaze:
                                           * a turn about the gaze axis does not move it. Trace
                                           * sources: over ±5 ms (docs/trace-format.md §4) */
    int has_position;
    int has_gaze;
};

enum trk_health { TRK_HEALTH_OK = 0, TRK_HEALTH_LOST, TRK_HEALTH_ERROR };

/* The interface, Monado-style: a small struct of function pointers. `pose_at` returns the pose for
 * a display time (predicted by live sources, interpolated by recorded ones); 0 or −1 with err. */
struct trk_pose_source {
    const char *name;
    int (*start)(struct trk_pose_source *src, struct hl_error *err);
    void (*stop)(struct trk_pose_source *src);
    int (*pose_at)(struct trk_pose_source *src, double time_s, struct trk_pose *out, struct hl_error *err);
    enum trk_health (*health)(struct trk_pose_source *src, char *reason, size_t reason_size);
    void (*destroy)(struct trk_pose_source *src);
    double start_time_s, end_time_s; /* span of a recorded source; end < start for a live one */
};

/* A still, upright head looking down −Z, eye locked to the head. */
void trk_pose_init_still(struct trk_pose *pose, double time_s);

static inline int trk_source_pose_at(struct trk_pose_source *src, double t_s, struct trk_pose *out,
                                     struct hl_error *err)
{
    return src->pose_at(src, t_s, out, err);
}

static inline void trk_source_destroy(struct trk_pose_source *src)
{
    if (src && src->destroy)
        src->destroy(src);
}

#endif
