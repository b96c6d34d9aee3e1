/* render/layers: foveated layers drawn by headless EGL on the built-in auditorium at the Vive's
 * resolution (issue 32 item 7): inside the inset's inner disc the composite equals the plain
 * full-resolution render pixel for pixel; across the blend band's edges there is no step (the mean
 * absolute difference between neighbouring pixels straddling an edge stays within 1.2× of the same
 * pairs' on the plain frame); the layer plan's rectangles hold the band; masks keep an object out of
 * a layer; bad settings draw nothing; the distortion pass composites layers left uncomposited the
 * same way (no lens: the inner disc is the plain frame's, the rest the composite pass's within a
 * level, no step across the band). */
#include "render/render.h"
#include "test_util.h"

#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const struct hmd_profile *vive;
static int EW, EH;

static void views_at(double yaw_deg, double pitch_deg, struct rnd_eye_view v[2], struct hmd_eye eyes[2])
{
    hl_quatd yaw = hl_q_from_axis_angle(hl_v3(0, 1, 0), yaw_deg * HL_RAD_PER_DEG);
    hl_quatd head = hl_q_mul(yaw, hl_q_from_axis_angle(hl_v3(1, 0, 0), pitch_deg * HL_RAD_PER_DEG));
    for (int e = 0; e < 2; ++e) {
        eyes[e] = hmd_eye_frustum(vive, e);
        hl_vec3d off = hl_q_rotate(head, hl_v3(eyes[e].offset_x_m, 0, 0)); /* seated: eyes 1.2 m up */
        v[e].position_m[0] = off.x, v[e].position_m[1] = 1.2 + off.y, v[e].position_m[2] = off.z;
        v[e].orientation = head;
        hmd_eye_projection(&eyes[e], 0.05, 200.0, v[e].projection);
    }
}

/* Angle (deg) between pixel (x, y) of an eye image (rows top to bottom) and the centre direction. */
static double pixel_angle_deg(const struct hmd_eye *eye, hl_vec3d centre, int x, int y)
{
    double xt = -eye->tan_left + (x + 0.5) / EW * (eye->tan_left + eye->tan_right);
    double yt = eye->tan_up - (y + 0.5) / EH * (eye->tan_up + eye->tan_down);
    hl_vec3d d = hl_v3_normalize(hl_v3(xt, yt, -1.0));
    return atan2(hl_v3_length(hl_v3_cross(d, centre)), hl_v3_dot(d, centre)) * HL_DEG_PER_RAD;
}

static const uint8_t *pix(const uint8_t *img, int eye, int x, int y)
{
    return img + 4 * ((size_t)y * 2 * EW + (size_t)eye * EW + (size_t)x);
}

static double pair_diff(const uint8_t *a, const uint8_t *b)
{
    return (fabs((double)a[0] - b[0]) + fabs((double)a[1] - b[1]) + fabs((double)a[2] - b[2])) / 3.0;
}

/* Horizontal and vertical neighbours one on each side of the edge at edge_deg: the mean absolute
 * difference in img, over the pairs that straddle the edge in this eye. */
static double straddle_mad(const uint8_t *img, int eye, const struct hmd_eye *y, hl_vec3d c, double edge_deg, int *pairs)
{
    double sum = 0.0;
    int n = 0;
    for (int row = 0; row + 1 < EH; ++row)
        for (int x = 0; x + 1 < EW; ++x) {
            int in = pixel_angle_deg(y, c, x, row) < edge_deg;
            if (in != (pixel_angle_deg(y, c, x + 1, row) < edge_deg))
                sum += pair_diff(pix(img, eye, x, row), pix(img, eye, x + 1, row)), ++n;
            if (in != (pixel_angle_deg(y, c, x, row + 1) < edge_deg))
                sum += pair_diff(pix(img, eye, x, row), pix(img, eye, x, row + 1)), ++n;
        }
    *pairs = n;
    return n ? sum / n : 0.0;
}

static void test_composite(struct rnd_renderer *r, const struct scn_scene *s, const uint32_t *index,
                           const uint8_t *lod, double yaw_deg, double pitch_deg, hl_vec3d centre, double scale)
{
    struct rnd_eye_view v[2];
    struct rnd_layers l = {.periphery_scale = scale, .inset_radius_deg = 15.0, .blend_deg = 6.0,
                           .centre_eye = {centre, centre}};
    views_at(yaw_deg, pitch_deg, v, l.eyes);
    size_t bytes = (size_t)2 * EW * EH * 4;
    uint8_t *full = malloc(bytes), *fov = malloc(bytes);
    struct hl_error err = {""};
    struct rnd_draw_stats st;
    CHECK(rnd_renderer_draw_stereo(r, s, v, index, lod, s->instance_count, NULL) == 0);
    CHECK(rnd_renderer_read_rgba(r, full, &err) == 0);
    CHECK(rnd_renderer_draw_layers(r, s, v, &l, index, lod, NULL, NULL, s->instance_count, &st) == 0);
    double composite_px = 0.0;
    CHECK(rnd_renderer_composite_layers(r, &composite_px) == 0);
    CHECK(composite_px > 0.5 * 2 * EW * EH && composite_px < 2.0 * EW * EH);
    CHECK(rnd_renderer_read_rgba(r, fov, &err) == 0);
    CHECK(st.inset_triangles > 0 && st.periphery_triangles > 0 && st.periphery_px > 0 && st.inset_px > 0);
    hl_vec3d c = hl_v3_normalize(centre);
    long inside = 0, inside_diff = 0, outside = 0, outside_diff = 0;
    for (int e = 0; e < 2; ++e)
        for (int y = 0; y < EH; ++y)
            for (int x = 0; x < EW; ++x) {
                double a = pixel_angle_deg(&l.eyes[e], c, x, y);
                int same = !memcmp(pix(full, e, x, y), pix(fov, e, x, y), 4);
                if (a < l.inset_radius_deg - 0.25)
                    ++inside, inside_diff += !same;
                else if (a > l.inset_radius_deg + l.blend_deg + 0.25)
                    ++outside, outside_diff += !same;
            }
    printf("layers s %.2f yaw %g pitch %g centre (%.2f %.2f %.2f): inner disc %ld px, %ld differ; beyond the band "
           "%ld px, %ld differ (%.1f %%)\n",
           scale, yaw_deg, pitch_deg, c.x, c.y, c.z, inside, inside_diff, outside, outside_diff,
           outside ? 100.0 * outside_diff / outside : 0.0);
    CHECK(inside > 1000 && inside_diff == 0);            /* the inset is the full render, bit for bit */
    CHECK(outside > 1000 && outside_diff > outside / 50); /* and the periphery is really coarser */
    /* No step at either edge of the band: straddling pairs differ no more than on the plain frame. */
    const double edges[2] = {l.inset_radius_deg, l.inset_radius_deg + l.blend_deg};
    for (int k = 0; k < 2; ++k)
        for (int e = 0; e < 2; ++e) {
            int n_fov = 0, n_full = 0;
            double m_fov = straddle_mad(fov, e, &l.eyes[e], c, edges[k], &n_fov);
            double m_full = straddle_mad(full, e, &l.eyes[e], c, edges[k], &n_full);
            printf("  eye %d edge %.0f deg: neighbours across it differ %.3f (plain frame %.3f, %d pairs)\n", e,
                   edges[k], m_fov, m_full, n_fov);
            CHECK(n_fov > 100 && m_fov <= 1.2 * m_full + 1e-9);
        }
    free(full);
    free(fov);
}

/* A hard switch with no band (blend 0.01°) at a coarse scale steps at the edge: the check above can fail. */
static void test_step_detected(struct rnd_renderer *r, const struct scn_scene *s, const uint32_t *index,
                               const uint8_t *lod)
{
    struct rnd_eye_view v[2];
    hl_vec3d ahead = hl_v3(0, 0, -1);
    struct rnd_layers l = {.periphery_scale = 0.25, .inset_radius_deg = 15.0, .blend_deg = 0.01, .centre_eye = {ahead, ahead}};
    views_at(0, -8, v, l.eyes);
    size_t bytes = (size_t)2 * EW * EH * 4;
    uint8_t *full = malloc(bytes), *fov = malloc(bytes);
    struct hl_error err = {""};
    CHECK(rnd_renderer_draw_stereo(r, s, v, index, lod, s->instance_count, NULL) == 0);
    CHECK(rnd_renderer_read_rgba(r, full, &err) == 0);
    CHECK(rnd_renderer_draw_layers(r, s, v, &l, index, lod, NULL, NULL, s->instance_count, NULL) == 0);
    CHECK(rnd_renderer_composite_layers(r, NULL) == 0);
    CHECK(rnd_renderer_read_rgba(r, fov, &err) == 0);
    int n = 0;
    double m_fov = straddle_mad(fov, 0, &l.eyes[0], ahead, 15.005, &n);
    double m_full = straddle_mad(full, 0, &l.eyes[0], ahead, 15.005, &n);
    printf("no band, s 0.25: neighbours across the edge differ %.3f (plain frame %.3f)\n", m_fov, m_full);
    CHECK(m_fov > 1.2 * m_full);
    free(full);
    free(fov);
}

/* Inset radius 0: the periphery alone (global dynamic resolution); a mask keeps entries out of it. */
static void test_global_and_masks(struct rnd_renderer *r, const struct scn_scene *s, const uint32_t *index,
                                  const uint8_t *lod)
{
    struct rnd_eye_view v[2];
    hl_vec3d ahead = hl_v3(0, 0, -1);
    struct rnd_layers l = {.periphery_scale = 0.5, .inset_radius_deg = 0.0, .blend_deg = 5.0, .centre_eye = {ahead, ahead}};
    views_at(0, -8, v, l.eyes);
    struct rnd_draw_stats st;
    uint8_t *mask = malloc(s->instance_count);
    memset(mask, RND_LAYER_BOTH, s->instance_count);
    CHECK(rnd_renderer_draw_layers(r, s, v, &l, index, lod, NULL, mask, s->instance_count, &st) == 0);
    CHECK(st.inset_triangles == 0 && st.inset_px == 0 && st.periphery_triangles > 0);
    CHECK(fabs(st.periphery_px - 2.0 * lround(0.5 * EW) * lround(0.5 * EH)) < 0.5);
    uint64_t all = st.periphery_triangles;
    memset(mask, RND_LAYER_INSET, s->instance_count); /* nobody in the periphery */
    CHECK(rnd_renderer_draw_layers(r, s, v, &l, index, lod, NULL, mask, s->instance_count, &st) == 0);
    CHECK(st.periphery_triangles == 0 && all > 0);
    /* s = 1: the plain frame, masks ignored. */
    l.periphery_scale = 1.0;
    CHECK(rnd_renderer_draw_layers(r, s, v, &l, index, lod, NULL, mask, s->instance_count, &st) == 0);
    CHECK(st.triangles_per_eye[0] > 0 && st.inset_px == 0 && st.periphery_px == 0);
    double px = -1.0;
    CHECK(rnd_renderer_composite_layers(r, &px) == 0 && px == 0.0); /* a plain frame: nothing to composite */
    /* Bad settings: nothing drawn, −1. */
    struct rnd_layers bad = l;
    bad.periphery_scale = 0.1;
    CHECK(rnd_renderer_draw_layers(r, s, v, &bad, index, lod, NULL, NULL, s->instance_count, &st) != 0);
    bad = l, bad.periphery_scale = 0.5, bad.blend_deg = 0.0;
    CHECK(rnd_renderer_draw_layers(r, s, v, &bad, index, lod, NULL, NULL, s->instance_count, &st) != 0);
    bad = l, bad.periphery_scale = 0.5, bad.inset_radius_deg = NAN;
    CHECK(rnd_renderer_draw_layers(r, s, v, &bad, index, lod, NULL, NULL, s->instance_count, &st) != 0);
    bad = l, bad.periphery_scale = 0.5, bad.centre_eye[1] = hl_v3(0, 0, 0);
    CHECK(rnd_renderer_draw_layers(r, s, v, &bad, index, lod, NULL, NULL, s->instance_count, &st) != 0);
    free(mask);
}

/* The distortion pass as the composite (live): with a lens-free profile and an output the FBO's size
 * it samples each pixel's centre, so inside the inner disc it must equal the plain frame's pass bit
 * for bit, beyond the band the composite pass's image within a level or two (the same bilinear
 * samples; the band's weight is per pixel there, per vertex in the composite's mesh), and across the
 * band's edges keep the no-step bound. */
static void test_distortion_composite(struct rnd_renderer *r, const struct scn_scene *s, const uint32_t *index,
                                      const uint8_t *lod)
{
    struct hmd_profile flat = *vive;
    for (int i = 0; i < 4; ++i)
        flat.distortion_k[i] = 0.0;
    flat.aberration[0] = flat.aberration[1] = flat.aberration[2] = 1.0;
    struct hl_error err = {""};
    struct rnd_distortion *d = NULL;
    CHECK(rnd_distortion_create(r, &flat, 2 * EW, EH, 1, &d, &err) == 0);
    if (!d)
        return;
    CHECK(!rnd_distortion_has_lens(d));
    struct rnd_eye_view v[2];
    hl_vec3d c = hl_v3_normalize(hl_v3(-0.2, 0.1, -1.0));
    struct rnd_layers l = {.periphery_scale = 0.35, .inset_radius_deg = 14.0, .blend_deg = 5.0, .centre_eye = {c, c}};
    views_at(-15, -6, v, l.eyes);
    size_t bytes = (size_t)2 * EW * EH * 4;
    uint8_t *plain = malloc(bytes), *pass = malloc(bytes), *fov = malloc(bytes);
    CHECK(rnd_renderer_draw_stereo(r, s, v, index, lod, s->instance_count, NULL) == 0);
    CHECK(rnd_distortion_draw(d, 1, &err) == 0 && rnd_distortion_read_rgba(d, plain, &err) == 0);
    CHECK(rnd_renderer_draw_layers(r, s, v, &l, index, lod, NULL, NULL, s->instance_count, NULL) == 0);
    CHECK(rnd_distortion_draw(d, 1, &err) == 0 && rnd_distortion_read_rgba(d, fov, &err) == 0);
    CHECK(rnd_distortion_draw(d, 1, &err) == 0 && rnd_distortion_read_rgba(d, pass, &err) == 0);
    CHECK(!memcmp(fov, pass, bytes)); /* the layers stay the last draw's until the next one */
    CHECK(rnd_renderer_composite_layers(r, NULL) == 0 && rnd_renderer_read_rgba(r, pass, &err) == 0);
    long inside = 0, inside_diff = 0, beyond = 0, beyond_far = 0;
    int worst = 0;
    for (int e = 0; e < 2; ++e)
        for (int y = 0; y < EH; ++y)
            for (int x = 0; x < EW; ++x) {
                double a = pixel_angle_deg(&l.eyes[e], c, x, y);
                const uint8_t *p = pix(plain, e, x, y), *f = pix(fov, e, x, y), *q = pix(pass, e, x, y);
                if (a < l.inset_radius_deg - 0.25) {
                    ++inside, inside_diff += memcmp(p, f, 3) != 0;
                } else if (a > l.inset_radius_deg + l.blend_deg + 0.25) {
                    ++beyond;
                    for (int ch = 0; ch < 3; ++ch) {
                        int dd = abs((int)f[ch] - (int)q[ch]);
                        worst = dd > worst ? dd : worst;
                        beyond_far += dd > 2;
                    }
                }
            }
    printf("distortion-pass composite: inner disc %ld px, %ld differ from the plain pass; beyond the band %ld px, "
           "largest difference from the composite pass %d levels (%ld samples over 2)\n",
           inside, inside_diff, beyond, worst, beyond_far);
    CHECK(inside > 1000 && inside_diff == 0);
    CHECK(beyond > 1000 && beyond_far == 0);
    const double edges[2] = {l.inset_radius_deg, l.inset_radius_deg + l.blend_deg};
    for (int k = 0; k < 2; ++k)
        for (int e = 0; e < 2; ++e) {
            int n_fov = 0, n_plain = 0;
            double m_fov = straddle_mad(fov, e, &l.eyes[e], c, edges[k], &n_fov);
            double m_plain = straddle_mad(plain, e, &l.eyes[e], c, edges[k], &n_plain);
            printf("  eye %d edge %.0f deg: %.3f (plain %.3f)\n", e, edges[k], m_fov, m_plain);
            CHECK(n_fov > 100 && m_fov <= 1.2 * m_plain + 1e-9);
        }
    /* A plain draw after it: the pass is plain again. */
    CHECK(rnd_renderer_draw_stereo(r, s, v, index, lod, s->instance_count, NULL) == 0);
    CHECK(rnd_distortion_draw(d, 1, &err) == 0 && rnd_distortion_read_rgba(d, fov, &err) == 0);
    CHECK(!memcmp(fov, plain, bytes));
    rnd_distortion_destroy(d);
    free(plain);
    free(pass);
    free(fov);
}

/* The plan: the rectangle holds the band's outer ring; an inset reaching past 80° covers the eye. */
static void test_plan(void)
{
    struct rnd_eye_view v[2];
    hl_vec3d c = hl_v3_normalize(hl_v3(0.3, -0.1, -1.0));
    struct rnd_layers l = {.periphery_scale = 0.35, .inset_radius_deg = 12.0, .blend_deg = 4.0, .centre_eye = {c, c}};
    views_at(0, 0, v, l.eyes);
    struct rnd_layer_plan p;
    CHECK(rnd_layer_plan_make(&l, EW, EH, &p) == 0);
    CHECK(p.periphery_px[0] == lround(0.35 * EW) && p.periphery_px[1] == lround(0.35 * EH));
    for (int e = 0; e < 2; ++e) {
        const int *rect = p.inset_rect_px[e];
        CHECK(!p.covers[e] && rect[2] > 0 && rect[3] > 0);
        /* every pixel within 16° of the centre is inside the rectangle (rows bottom-up in the rect) */
        int outside = 0;
        for (int y = 0; y < EH; ++y)
            for (int x = 0; x < EW; ++x)
                if (pixel_angle_deg(&l.eyes[e], c, x, y) <= 16.0) {
                    int gy = EH - 1 - y;
                    outside += x < rect[0] || x >= rect[0] + rect[2] || gy < rect[1] || gy >= rect[1] + rect[3];
                }
        CHECK(outside == 0);
    }
    l.inset_radius_deg = 70.0;
    CHECK(rnd_layer_plan_make(&l, EW, EH, &p) == 0);
    CHECK(p.covers[0] && p.covers[1] && p.periphery_px_total == 0 && p.inset_px == 2.0 * EW * EH);
    l.periphery_scale = 2.0;
    CHECK(rnd_layer_plan_make(&l, EW, EH, &p) != 0);
}

int main(void)
{
    dlopen("/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so", RTLD_NOW | RTLD_NODELETE); /* PLATFORM.md §4 */
    vive = hmd_builtin_find("vive");
    CHECK(vive != NULL);
    if (!vive)
        return tu_finish("layers");
    EW = vive->eye_width_px, EH = vive->eye_height_px;
    test_plan();
    struct hl_error err = {""};
    struct rnd_renderer *r = NULL;
    if (rnd_renderer_create(EW, EH, &r, &err) != 0) {
        printf("skip: no headless OpenGL 4.5: %s\n", err.msg);
        return tu_failures ? tu_finish("layers") : 77;
    }
    struct scn_scene s = {0};
    CHECK(scn_scene_build("auditorium", NULL, &s, &err) == 0);
    CHECK(rnd_renderer_upload_scene(r, &s, &err) == 0);
    uint32_t *index = malloc(s.instance_count * sizeof *index);
    uint8_t *lod = calloc(s.instance_count, 1);
    for (uint32_t i = 0; i < s.instance_count; ++i)
        index[i] = i;
    test_composite(r, &s, index, lod, 0, -8, hl_v3(0, 0, -1), 0.5);           /* fixed: the lens centre */
    test_composite(r, &s, index, lod, 20, -5, hl_v3(0.25, -0.15, -1.0), 0.35); /* gaze off the axis */
    test_step_detected(r, &s, index, lod);
    test_global_and_masks(r, &s, index, lod);
    test_distortion_composite(r, &s, index, lod);
    free(index);
    free(lod);
    scn_scene_free(&s);
    rnd_renderer_destroy(r);
    return tu_finish("layers");
}
