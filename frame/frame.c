/* One frame (DESIGN.md "One frame"): pose → eyes → visible set → viewing geometry → perceptual
 * ceiling and selection → draw. Allocates nothing; every step is timed. */
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include <sys/resource.h>

#include "frame/frame.h"

/* The right eye mirrors the left, so the union of both frusta spans max(L, R) to either side; the
 * eyes sit ±ipd/2 off the head centre, which culling adds to each radius (the planes move out by it).
 * A point p is inside a side plane when n·p ≥ 0 with n the plane's inward normal. */
void frm_cull_frustum_init(struct frm_cull_frustum *f, const struct hmd_profile *display, double near_m)
{
    struct hmd_eye e = hmd_eye_frustum(display, HMD_EYE_LEFT);
    double side = fmax(e.tan_left, e.tan_right);
    f->normals_head[0] = hl_v3_normalize(hl_v3(1, 0, -side));        /* left: x ≥ side·z */
    f->normals_head[1] = hl_v3_normalize(hl_v3(-1, 0, -side));       /* right */
    f->normals_head[2] = hl_v3_normalize(hl_v3(0, -1, -e.tan_up));   /* top */
    f->normals_head[3] = hl_v3_normalize(hl_v3(0, 1, -e.tan_down));  /* bottom */
    f->near_m = near_m;
    f->margin_m = 0.5 * display->ipd_m;
}

/* The head-frame normals rotated into the world, through the head centre, and the near plane near_m
 * in front of it; each moved out by the eye margin so a sphere is kept when any part of it is within
 * reach of either eye. Five rotations, no allocation. */
int frm_cull_frustum_planes(const struct frm_cull_frustum *f, const struct trk_pose *pose, struct scn_plane *planes)
{
    for (int k = 0; k < 5; ++k) {
        hl_vec3d n_head = k < 4 ? f->normals_head[k] : hl_v3(0, 0, -1);
        hl_vec3d n = hl_q_rotate(pose->orientation, n_head);
        planes[k].normal[0] = n.x, planes[k].normal[1] = n.y, planes[k].normal[2] = n.z;
        planes[k].offset_m = -hl_v3_dot(n, pose->position_m) + f->margin_m - (k < 4 ? 0.0 : f->near_m);
    }
    return 5;
}

static uint32_t cull_scene(struct frm_session *s, const struct trk_pose *pose, struct scn_cull_stats *stats)
{
    struct scn_plane planes[5];
    int count = frm_cull_frustum_planes(&s->cull_frustum, pose, planes);
    return scn_cull(&s->scene, planes, count, &s->culler, s->arrays.visible, stats);
}

static void eye_views(const struct frm_session *s, const struct trk_pose *pose, struct rnd_eye_view views[2])
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

/* Orientation-only poses pivot about the neck at the origin; a pose with a position gives the eyes'
 * position already (a headset tracks its display, which sits at the eyes): docs/gaze.md. */
static void head_state_of(const struct frm_session *s, const struct trk_pose *pose, struct acu_head_state *h)
{
    hl_vec3d offset = pose->has_position ? hl_v3(0, 0, 0) : s->neck_to_eye_head_m;
    hl_vec3d position = pose->has_position ? pose->position_m : hl_v3(0, 0, 0);
    hl_vec3d velocity = pose->has_position ? pose->linear_velocity_mps : hl_v3(0, 0, 0);
    acu_head_state_from_neck(pose->orientation, position, velocity, pose->angular_velocity_radps, offset, h);
}

int frm_frame_head_state(struct frm_session *s, double time_s, struct trk_pose *eye_pose,
                         struct acu_head_state *head, struct hl_error *err)
{
    if (trk_source_pose_at(s->source, time_s, eye_pose, err) != 0)
        return -1;
    head_state_of(s, eye_pose, head);
    if (eye_pose->has_gaze) {
        head->has_gaze = 1;
        head->gaze_dir = hl_v3_normalize(hl_q_rotate(eye_pose->orientation, eye_pose->gaze_dir_head));
        head->gaze_angular_velocity_radps = eye_pose->gaze_angular_velocity_radps;
    }
    if (s->gaze == ACU_GAZE_VOR && s->vor.latency_s > 0.0) {
        /* The reflex acts on what the head did latency_s ago; a recorded source can be sampled at
         * any time (clamped to its first pose at the start). */
        struct trk_pose past;
        struct acu_head_state was;
        if (trk_source_pose_at(s->source, time_s - s->vor.latency_s, &past, err) != 0)
            return -1;
        head_state_of(s, &past, &was);
        head->delayed_angular_velocity_radps = was.angular_velocity_radps;
        head->delayed_eye_velocity_mps = was.eye_velocity_mps;
    }
    eye_pose->position_m = head->eye_position_m;
    return 0;
}

/* The eyes as acuity/ sees them for projected coverage: the views' poses, the frusta, the image. */
static void acuity_eyes(const struct frm_session *s, const struct rnd_eye_view views[2], struct acu_eye eyes[2])
{
    int w, h;
    rnd_renderer_size(s->renderer, &w, &h);
    for (int e = 0; e < 2; ++e) {
        eyes[e] = (struct acu_eye){
            .position_m = hl_v3(views[e].position_m[0], views[e].position_m[1], views[e].position_m[2]),
            .orientation = views[e].orientation,
            .tan_left = s->eyes[e].tan_left, .tan_right = s->eyes[e].tan_right,
            .tan_up = s->eyes[e].tan_up, .tan_down = s->eyes[e].tan_down,
            .width_px = 0.5 * w, .height_px = h,
        };
    }
}

/* Each eye's frustum and the world gaze in its frame, as render's image measures take them. */
static void frame_eye_gaze(const struct frm_session *s, const struct rnd_eye_view views[2], hl_vec3d gaze_world,
                           struct rnd_eye_gaze gaze[2])
{
    for (int e = 0; e < 2; ++e) {
        hl_vec3d g = hl_q_rotate(hl_q_conj(views[e].orientation), gaze_world);
        gaze[e] = (struct rnd_eye_gaze){s->eyes[e].tan_left, s->eyes[e].tan_right, s->eyes[e].tan_up,
                                        s->eyes[e].tan_down, {g.x, g.y, g.z}};
    }
}

const double frm_retinal_band_lower_degps[FRM_RETINAL_BANDS] = {0.0, 2.0, 10.0, 30.0};

int frm_band_of(const double *lower, int count, double value)
{
    int b = 0;
    while (b + 1 < count && value >= lower[b + 1])
        ++b;
    return b;
}

/* Where the triangles are kept (docs/replay-output.md "triangles_by_band"): the record's sums over
 * the n visible objects. A measurement, so it runs after the frame's timing. */
static void count_in_bands(const struct frm_session *s, const struct frm_frame_arrays *a, uint32_t n,
                           struct frm_frame_record *rec)
{
    for (uint32_t k = 0; k < n; ++k) {
        const struct scn_chain *chain = &s->scene.chains[s->scene.chain_of_instance[a->visible[k]]];
        uint32_t finest = chain->lods[0].triangle_count;
        uint32_t drawn = a->lod[k] == LOD_DROP ? 0 : chain->lods[a->lod[k]].triangle_count;
        int e = frm_band_of(rnd_ecc_band_lower_deg, RND_ECC_BANDS, a->eccentricity_deg[k]);
        int v = frm_band_of(frm_retinal_band_lower_degps, FRM_RETINAL_BANDS, a->velocity_degps[k]);
        rec->ecc_finest[e] += finest, rec->ecc_drawn[e] += drawn;
        rec->retinal_finest[v] += finest, rec->retinal_drawn[v] += drawn;
    }
}

int frm_frame_run(struct frm_session *s, long frame, double time_s, struct frm_frame_record *rec,
                  struct hl_error *err)
{
    struct frm_frame_arrays *a = &s->arrays;
    memset(rec, 0, sizeof *rec);
    rec->frame = frame;
    rec->time_s = time_s;

    struct rusage usage0;
    getrusage(RUSAGE_SELF, &usage0);
    int64_t t0 = hl_clock_now_ns();
    struct trk_pose pose; /* position_m: the cyclopean eye, for the cull, the geometry and the views */
    struct acu_head_state head;
    if (frm_frame_head_state(s, time_s, &pose, &head, err) != 0)
        return -1;
    rec->head_speed_degps = hl_v3_length(pose.angular_velocity_radps) * HL_DEG_PER_RAD;
    frm_select_saccade(&s->select, &pose, time_s); /* saccade suppression (frame/saccade_step.c) */
    const double *object_velocity_mps = frm_motion_step(&s->scene, time_s); /* NULL: static scene */

    struct scn_cull_stats cull = {0};
    uint32_t n = cull_scene(s, &pose, &cull);
    rec->visible = n;
    rec->cull_groups_tested = cull.groups_tested;
    rec->cull_instances_tested = cull.instances_tested;
    struct acu_viewer viewer;
    /* −1 only for tracked on a sample without a gaze (a trace without any is refused at start):
     * that frame falls back to vor, as acu_gaze_viewer fills it. */
    (void)acu_gaze_viewer(s->gaze, &s->vor, &head, &viewer);
    const struct frm_saccade *sac = &s->select.saccade; /* active: tracked, with a measured gaze */
    int target_held = sac->active && sac->state.phase == ACU_SACCADE_NONE; /* outside saccades */
    if (target_held)
        acu_gaze_hold_target(&head, s->scene.center_m, s->scene.radius_m, object_velocity_mps, a->visible, n,
                             ACU_GAZE_TARGET_DEG, s->vor.fixation_m, &viewer);
    rec->eye_speed_degps = hl_v3_length(viewer.angular_velocity_radps) * HL_DEG_PER_RAD;
    acu_compute_geometry(&viewer, s->scene.center_m, s->scene.radius_m, object_velocity_mps, a->visible, n,
                         a->eccentricity_deg, a->velocity_degps, a->diameter_deg);
    int64_t t1 = hl_clock_now_ns();

    struct rnd_eye_view views[2];
    eye_views(s, &pose, views);
    struct acu_eye eyes[2];
    acuity_eyes(s, views, eyes);
    const struct frm_visibility *vis = &s->visibility;
    struct frm_view_inputs in = {a->visible, n, a->eccentricity_deg, a->velocity_degps, a->diameter_deg,
                                 &s->limits, s->chains, eyes, vis->table ? &vis->limits : NULL};
    rec->adapting_luminance_cdm2 = vis->table ? vis->adapting_luminance_cdm2 : NAN;
    size_t extra = 0;
    if (s->layers.mode != FRM_FOVEATION_OFF) { /* the layer candidates, priced by the selection */
        int w, h;
        rnd_renderer_size(s->renderer, &w, &h);
        double xi = s->limits.xi_cpd * fmin(1.0, 0.5 * w / s->display.eye_width_px); /* what the image shows */
        struct frm_layers_view lv = {&viewer, pose.orientation, s->eyes, w / 2, h, 0.5 * s->display.ipd_m,
                                     target_held};
        frm_layers_plan(&s->layers, &lv, &s->limits, vis->table ? &vis->limits : NULL, xi, s->scene.center_m,
                        s->scene.radius_m, a->visible, n, a->eccentricity_deg, a->velocity_degps);
    }
    frm_select_frame(&s->select, &s->scene, &in, a->lod, a->draw_index + n, a->draw_lod + n, &extra, &rec->sel);
    rec->acuity_evaluations = rec->sel.acuity_evaluations;
    for (uint32_t k = 0; k < n; ++k) {
        const struct scn_chain *chain = &s->scene.chains[s->scene.chain_of_instance[a->visible[k]]];
        rec->triangles_finest += chain->lods[0].triangle_count;
        if (a->lod[k] != LOD_DROP)
            rec->lod_histogram[a->lod[k]]++;
        a->draw_index[k] = a->visible[k];
        a->draw_lod[k] = a->lod[k];
    }
    int64_t t2 = hl_clock_now_ns();

    struct rnd_draw_stats draw = {0};
    struct rnd_layers setting;
    const struct rnd_layers *layers = NULL;
    if (s->layers.mode != FRM_FOVEATION_OFF) {
        const hl_quatd orientation[2] = {views[0].orientation, views[1].orientation};
        frm_layers_setting(&s->layers, s->eyes, orientation, &setting);
        hl_vec3d c = hl_q_rotate(hl_q_conj(pose.orientation), s->layers.centre_world);
        rec->inset_x_deg = atan2(c.x, -c.z) * HL_DEG_PER_RAD;
        rec->inset_y_deg = atan2(c.y, -c.z) * HL_DEG_PER_RAD;
        frm_layers_masks(&s->layers, n, extra);
        frm_layers_periphery_levels(&s->layers, a->draw_lod, n, extra);
        layers = &setting;
    }
    if (rnd_renderer_draw_layers(s->renderer, &s->scene, views, layers, a->draw_index, a->draw_lod,
                                 layers ? s->layers.periphery_lod : NULL, layers ? s->layers.mask : NULL, n + extra,
                                 &draw) != 0)
        return hl_fail(err, "frame %ld: drawing failed", frame);
    int64_t t3 = hl_clock_now_ns();
    /* The layers' composite is the compositor's work, timed apart (render/render.h, docs/foveation.md);
     * a session with a distortion pass (live) leaves it to that pass. */
    if (!s->composite_in_distortion && rnd_renderer_composite_layers(s->renderer, &rec->composite_px) != 0)
        return hl_fail(err, "frame %ld: compositing the layers failed", frame);
    int64_t t3c = layers ? hl_clock_now_ns() : t3;
    rec->composite_ms = (double)(t3c - t3) * 1e-6; /* exactly 0 for a plain frame */
    if (s->layers.mode != FRM_FOVEATION_OFF) { /* what the content needs: next frame's ceilings (frame/layers.h) */
        struct rnd_eye_gaze gaze[2];
        frame_eye_gaze(s, views, viewer.gaze_dir, gaze);
        struct hl_error read_err;
        if (rnd_renderer_ring_contrast(s->renderer, gaze, &s->layers.rings, &read_err) != 0)
            return hl_fail(err, "frame %ld: reading the content's contrast failed: %s", frame, read_err.msg);
        /* The same read-back holds the composited image's mean: the eye adapts to it (the FBO alone
         * holds only the insets when the distortion pass composites). */
        if (s->visibility.table)
            frm_visibility_adapt(&s->visibility, s->layers.rings.mean_relative_luminance);
    } else if (s->visibility.table) { /* the eye adapts to what it saw: next frame's luminance (frame/visibility.c) */
        double mean = NAN;
        struct hl_error read_err;
        if (rnd_renderer_mean_luminance(s->renderer, &mean, &read_err) != 0)
            return hl_fail(err, "frame %ld: reading the mean luminance failed: %s", frame, read_err.msg);
        frm_visibility_adapt(&s->visibility, mean);
    }
    int64_t t4 = hl_clock_now_ns();
    struct rusage usage1;
    getrusage(RUSAGE_SELF, &usage1);
    /* Fresh pages every frame are a cost the timings hide (docs/replay-output.md "minor_faults"). */
    rec->minor_faults = usage1.ru_minflt - usage0.ru_minflt;

    rec->triangles_per_eye = draw.triangles_per_eye[0];
    rec->draw = draw;
    rec->acuity_us = (double)(t1 - t0) * 1e-3;
    rec->select_us = (double)(t2 - t1) * 1e-3 - rec->sel.lp_us;
    rec->draw_ms = (double)(t3 - t2) * 1e-6;
    if (s->layers.mode == FRM_FOVEATION_ADAPTIVE) /* Valve's controller reacts to the draw (frame/layers.h) */
        frm_adaptive_update(&s->layers.adaptive, rec->draw_ms, s->select.budget_ms);
    rec->luminance_us = (double)(t4 - t3c) * 1e-3;
    /* The adaptation is part of the frame for the selectors it steers; for none, static and feedback
     * it serves only the predicted visible error, a measurement taken outside the frame's time. */
    int64_t frame_end = frm_selector_uses_ceiling(s->selector) ? t4 : t3;
    rec->frame_ms = (double)(frame_end - t0) * 1e-6 - rec->sel.lp_us * 1e-3 - (frame_end > t3 ? rec->composite_ms : 0.0);
    rec->deadline_met = rec->frame_ms <= s->select.budget_ms;
    frm_select_measured(&s->select, &rec->sel, rec->draw_ms, rec->frame_ms);
    rec->visible_error = frm_select_visible_error(&s->select, &s->scene, &in, a->lod); /* after the timing */
    count_in_bands(s, a, n, rec);
    s->frame_views[0] = views[0], s->frame_views[1] = views[1];
    s->frame_gaze_dir = viewer.gaze_dir;
    return 0;
}

/* The layers' own cost per scale (frame/layers.h): empty frames with the layers (an inset of 20°
 * on the lens centre) against empty plain frames, alternated, medians of FRM_LAYER_OVERHEAD_FRAMES
 * each — the clears, which no object pays (the composite is the compositor's, timed apart). Before
 * the clock starts; also makes the layers' framebuffer and program and runs the composite once
 * (their first use costs tens of ms on llvmpipe). The difference can be negative (the layers clear
 * less than the whole eye): it is kept, so a candidate's overhead is what it saves or adds. */
enum { FRM_LAYER_OVERHEAD_FRAMES = 7 };
static int measure_layer_overheads(struct frm_session *s, const struct rnd_eye_view views[2], struct hl_error *err)
{
    double plain[FRM_LAYER_OVERHEAD_FRAMES], layered[FRM_LAYER_OVERHEAD_FRAMES];
    struct rnd_layers l = {.inset_radius_deg = 20.0, .blend_deg = s->layers.blend_deg,
                           .centre_eye = {hl_v3(0, 0, -1), hl_v3(0, 0, -1)}, .eyes = {s->eyes[0], s->eyes[1]}};
    uint32_t none_index = 0;
    uint8_t none_lod = 0;
    s->layers.overhead_ms[0] = 0.0;
    for (int i = 1; i < FRM_LAYER_SCALES; ++i) {
        l.periphery_scale = frm_layer_scales[i];
        for (int rep = -1; rep < FRM_LAYER_OVERHEAD_FRAMES; ++rep) { /* rep −1: untimed first use */
            int64_t t0 = hl_clock_now_ns();
            if (rnd_renderer_draw_stereo(s->renderer, &s->scene, views, &none_index, &none_lod, 0, NULL) != 0)
                return hl_fail(err, "the renderer's empty warm-up frame failed");
            int64_t t1 = hl_clock_now_ns();
            if (rnd_renderer_draw_layers(s->renderer, &s->scene, views, &l, &none_index, &none_lod, NULL, NULL, 0, NULL) != 0)
                return hl_fail(err, "the layers' warm-up frame failed (scale %g)", l.periphery_scale);
            int64_t t2 = hl_clock_now_ns();
            if (rep >= 0)
                plain[rep] = (double)(t1 - t0) * 1e-6, layered[rep] = (double)(t2 - t1) * 1e-6;
            if (rnd_renderer_composite_layers(s->renderer, NULL) != 0) /* first use here, not in frame 0 */
                return hl_fail(err, "the layers' warm-up composite failed (scale %g)", l.periphery_scale);
        }
        hl_sort_doubles(plain, FRM_LAYER_OVERHEAD_FRAMES);
        hl_sort_doubles(layered, FRM_LAYER_OVERHEAD_FRAMES);
        s->layers.overhead_ms[i] = hl_percentile_sorted(layered, FRM_LAYER_OVERHEAD_FRAMES, 0.5) -
                                   hl_percentile_sorted(plain, FRM_LAYER_OVERHEAD_FRAMES, 0.5);
    }
    return 0;
}

int frm_frame_warm_up(struct frm_session *s, struct hl_error *err)
{
    const struct scn_scene *scene = &s->scene;
    uint32_t total = scene->instance_count + scene->impostor_instance_count;
    uint32_t *index = malloc((size_t)(scene->chain_count ? scene->chain_count : 1) * LOD_MAX_LEVELS * sizeof *index);
    uint8_t *lod = malloc((size_t)(scene->chain_count ? scene->chain_count : 1) * LOD_MAX_LEVELS);
    uint8_t *seen = calloc(scene->chain_count ? scene->chain_count : 1, 1);
    int rc = -1;
    if (!index || !lod || !seen) {
        hl_fail(err, "out of memory for the renderer's warm-up");
        goto done;
    }
    /* One instance of each chain at each of its levels: every mesh range and the pipeline are used
     * once before the clock starts. */
    size_t n = 0;
    for (uint32_t i = 0; i < total; ++i) {
        uint32_t c = scene->chain_of_instance[i];
        if (c >= scene->chain_count || seen[c])
            continue;
        seen[c] = 1;
        for (int l = 0; l < scene->chains[c].lod_count && l < LOD_MAX_LEVELS; ++l)
            index[n] = i, lod[n++] = (uint8_t)l;
    }
    struct trk_pose pose; /* any view does: what is warmed is the pipeline and the buffers */
    trk_pose_init_still(&pose, 0.0);
    struct rnd_eye_view views[2];
    eye_views(s, &pose, views);
    struct rnd_draw_stats draw = {0};
    if (rnd_renderer_draw_stereo(s->renderer, scene, views, index, lod, n, &draw) != 0) {
        hl_fail(err, "the renderer's warm-up draw failed");
        goto done;
    }
    if (s->layers.mode != FRM_FOVEATION_OFF) {
        struct rnd_eye_gaze gaze[2];
        struct rnd_ring_contrast rings; /* discarded: the first frame's content is not known yet */
        frame_eye_gaze(s, views, hl_q_rotate(pose.orientation, hl_v3(0, 0, -1)), gaze);
        if (measure_layer_overheads(s, views, err) != 0 || rnd_renderer_ring_contrast(s->renderer, gaze, &rings, err) != 0)
            goto done;
    }
    /* The contrast criterion's read-back makes its small framebuffer and blit path on first use
     * (about 80 ms on llvmpipe): here, not in frame 0. The value is discarded. */
    double mean = NAN;
    struct hl_error read_err;
    if (s->visibility.table && rnd_renderer_mean_luminance(s->renderer, &mean, &read_err) != 0) {
        hl_fail(err, "the renderer's warm-up luminance read failed: %s", read_err.msg);
        goto done;
    }
    rc = 0;
done:
    free(index);
    free(lod);
    free(seen);
    return rc;
}

static double reddy_weight(double eccentricity_deg, void *user)
{
    (void)user;
    return acu_eccentricity_factor(eccentricity_deg); /* Reddy 1998 eq. 3: error counts as it is seen */
}

int frm_frame_reference(struct frm_session *s, struct frm_frame_record *rec, uint8_t *test, int test_read,
                        uint8_t *ref, struct rnd_image_error_work *w, struct hl_error *err)
{
    struct frm_frame_arrays *a = &s->arrays;
    if (!test_read && rnd_renderer_read_rgba(s->renderer, test, err) != 0)
        return -1;
    /* The same visible set at full detail (selector none's choice), no group impostors. */
    for (uint32_t k = 0; k < rec->visible; ++k) {
        a->draw_index[k] = a->visible[k];
        a->draw_lod[k] = 0;
    }
    struct rnd_draw_stats draw = {0};
    if (rnd_renderer_draw_stereo(s->renderer, &s->scene, s->frame_views, a->draw_index, a->draw_lod, rec->visible,
                                 &draw) != 0)
        return hl_fail(err, "frame %ld: drawing its full-detail reference failed", rec->frame);
    if (rnd_renderer_read_rgba(s->renderer, ref, err) != 0)
        return -1;
    struct rnd_eye_gaze gaze[2];
    frame_eye_gaze(s, s->frame_views, s->frame_gaze_dir, gaze);
    int width, height;
    rnd_renderer_size(s->renderer, &width, &height);
    if (rnd_image_error_compute(w, test, ref, width, height, 2, gaze, reddy_weight, NULL, &rec->image, err) != 0)
        return -1;
    /* FLIP's observer: the pixels per degree at the centre of the eye images (horizontal, the eyes'
     * mean): a rendered eye of W px spans tan_left + tan_right on the image plane at distance 1. */
    double ppd = 0.0;
    for (int e = 0; e < 2; ++e)
        ppd += 0.5 * (width / 2) / (s->eyes[e].tan_left + s->eyes[e].tan_right) / HL_DEG_PER_RAD;
    rec->flip_ppd = ppd;
    if (rnd_flip_compute(test, ref, width, height, 2, ppd, &rec->flip, NULL, err) != 0)
        return -1;
    rec->has_image_error = 1;
    return 0;
}
