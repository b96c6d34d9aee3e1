/* One frame (DESIGN.md "One frame"): pose → eyes → visible set → viewing geometry → perceptual
 * ceiling and selection → draw. Allocates nothing; every step is timed. */
#include <math.h>
#include <string.h>

#include "replay/run_internal.h"

/* The right eye mirrors the left, so the union of both frusta spans max(L, R) to either side; the
 * eyes sit ±ipd/2 off the head centre, which culling adds to each radius. A point p is inside a side
 * plane when n·p ≥ 0 with n the plane's inward normal. */
void rpl_cull_planes_init(struct rpl_session *s)
{
    const struct hmd_eye *e = &s->eyes[HMD_EYE_LEFT];
    double side = fmax(e->tan_left, e->tan_right);
    s->cull_normals[0] = hl_v3_normalize(hl_v3(1, 0, -side));            /* left: x ≥ side·z */
    s->cull_normals[1] = hl_v3_normalize(hl_v3(-1, 0, -side));           /* right */
    s->cull_normals[2] = hl_v3_normalize(hl_v3(0, -1, -e->tan_up));      /* top */
    s->cull_normals[3] = hl_v3_normalize(hl_v3(0, 1, -e->tan_down));     /* bottom */
}

static int sphere_in_union_frustum(const struct rpl_session *s, hl_vec3d p, double radius_m)
{
    if (-p.z < s->near_m - radius_m)
        return 0;
    for (int k = 0; k < 4; ++k)
        if (hl_v3_dot(s->cull_normals[k], p) < -radius_m)
            return 0;
    return 1;
}

static uint32_t cull_scene(const struct rpl_session *s, const struct trk_pose *pose)
{
    const struct scn_scene *sc = &s->scene;
    hl_quatd world_to_head = hl_q_conj(pose->orientation);
    double eye_margin_m = 0.5 * s->display.ipd_m;
    uint32_t n = 0;
    for (uint32_t i = 0; i < sc->instance_count; ++i) {
        /* Eye-relative in double before rotating: far-from-origin scenes keep their precision. */
        hl_vec3d rel = hl_v3_sub(hl_v3(sc->center_m[3 * i], sc->center_m[3 * i + 1], sc->center_m[3 * i + 2]),
                                 pose->position_m);
        if (sphere_in_union_frustum(s, hl_q_rotate(world_to_head, rel), sc->radius_m[i] + eye_margin_m))
            s->arrays.visible[n++] = i;
    }
    return n;
}

static void eye_views(const struct rpl_session *s, const struct trk_pose *pose, struct rnd_eye_view views[2])
{
    for (int eye = 0; eye < 2; ++eye) {
        hl_vec3d offset = hl_q_rotate(pose->orientation, hl_v3(s->eyes[eye].offset_x_m, 0, 0));
        views[eye].position_m[0] = pose->position_m.x + offset.x;
        views[eye].position_m[1] = pose->position_m.y + offset.y;
        views[eye].position_m[2] = pose->position_m.z + offset.z;
        views[eye].orientation = pose->orientation;
        hmd_eye_projection(&s->eyes[eye], s->near_m, s->far_m, views[eye].projection);
    }
}

int rpl_frame_run(struct rpl_session *s, long frame, double time_s, struct rpl_frame_record *rec,
                  struct hl_error *err)
{
    struct rpl_frame_arrays *a = &s->arrays;
    memset(rec, 0, sizeof *rec);
    rec->frame = frame;
    rec->time_s = time_s;

    int64_t t0 = hl_clock_now_ns();
    struct trk_pose pose;
    if (trk_source_pose_at(s->source, time_s, &pose, err) != 0)
        return -1;
    if (!pose.has_position)
        pose.position_m = hl_v3(0, 0, 0);
    rec->head_speed_degps = hl_v3_length(pose.angular_velocity_radps) * HL_DEG_PER_RAD;

    uint32_t n = cull_scene(s, &pose);
    rec->visible = n;
    struct acu_viewer viewer = {
        .eye_position_m = pose.position_m,
        .gaze_dir = hl_v3_normalize(hl_q_rotate(pose.orientation, pose.has_gaze ? pose.gaze_dir_head
                                                                                : hl_v3(0, 0, -1))),
        .angular_velocity_radps = pose.angular_velocity_radps,
        .linear_velocity_mps = hl_v3(0, 0, 0),
    };
    acu_compute_geometry(&viewer, s->scene.center_m, s->scene.radius_m, NULL, a->visible, n,
                         a->eccentricity_deg, a->velocity_degps, a->diameter_deg);
    int64_t t1 = hl_clock_now_ns();

    struct acu_select_stats stats = {0};
    if (s->selector == RPL_SELECT_REDDY)
        acu_select_reddy(&s->limits, s->chains, s->scene.chain_of_instance, a->visible, n, a->eccentricity_deg,
                         a->velocity_degps, a->diameter_deg, a->lod, a->ceiling_cpd, &stats);
    else
        acu_select_finest(n, a->lod);
    rec->acuity_evaluations = stats.model_evaluations;
    for (uint32_t k = 0; k < n; ++k) {
        const struct scn_chain *chain = &s->scene.chains[s->scene.chain_of_instance[a->visible[k]]];
        rec->triangles_finest += chain->lods[0].triangle_count;
        rec->lod_histogram[a->lod[k]]++;
    }
    int64_t t2 = hl_clock_now_ns();

    struct rnd_eye_view views[2];
    eye_views(s, &pose, views);
    struct rnd_draw_stats draw = {{0}, 0};
    if (rnd_renderer_draw_stereo(s->renderer, &s->scene, views, a->visible, a->lod, n, &draw) != 0)
        return hl_fail(err, "frame %ld: drawing failed", frame);
    int64_t t3 = hl_clock_now_ns();

    rec->triangles_per_eye = draw.triangles_per_eye[0];
    rec->acuity_us = (double)(t1 - t0) * 1e-3;
    rec->select_us = (double)(t2 - t1) * 1e-3;
    rec->draw_ms = (double)(t3 - t2) * 1e-6;
    rec->frame_ms = (double)(t3 - t0) * 1e-6;
    rec->deadline_met = rec->frame_ms <= 1000.0 / s->display.refresh_hz;
    return 0;
}
