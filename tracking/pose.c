#include "tracking/tracking.h"

/* The interface itself is header-only; this file keeps the static library non-empty and holds the
 * one shared default: a still, upright head looking down −Z. */
void trk_pose_init_still(struct trk_pose *pose, double time_s)
{
    pose->time_s = time_s;
    pose->orientation = hl_q_identity();
    pose->position_m = hl_v3(0, 0, 0);
    pose->angular_velocity_radps = hl_v3(0, 0, 0);
    pose->linear_velocity_mps = hl_v3(0, 0, 0);
    pose->gaze_angular_velocity_radps = hl_v3(0, 0, 0);
    pose->gaze_dir_head = hl_v3(0, 0, -1);
    pose->has_position = 0;
    pose->has_gaze = 0;
}
