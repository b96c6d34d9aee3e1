/* render/layers: foveated layers drawn by headless EGL on the built-in auditorium at the Vive's
 * resolution (issue 32 item 7): inside the inset's inner disc the composite equals the plain
 * full-resolution render pixel for pixel; across the blend band's edges there is no step (the mean
 * absolute difference between neighbouring pixels straddling an edge stays within 1.2× of the same
 * pairs' on the plain frame); the layer plan's rectangles hold the band; masks keep an object out of
 * a layer; bad settings draw nothing; the distortion pass composites layers left uncomposited the
 * same way (no lens: the inner disc is the plain frame's, the rest the composite pass's within a
 * level, no step across the band); the last frame's ring contrast matches a reference computed from
 * the full-resolution read-back, and its cached ring map gives a gaze's figures again exactly. */
#include "render/image_error.h"
#include "render/layers.h"
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

/* The inset alone (what calibrate times): inside each eye's rectangle the full render, bit for bit;
 * outside it the FBO as the frame before left it; every listed instance drawn there, nothing in a
 * periphery, nothing to composite. */
static void test_inset_alone(struct rnd_renderer *r, const struct scn_scene *s, const uint32_t *index,
                             const uint8_t *lod)
{
    struct rnd_eye_view va[2], vb[2];
    hl_vec3d ahead = hl_v3(0, 0, -1);
    struct rnd_layers l = {.periphery_scale = 0.5, .inset_radius_deg = 5.0, .blend_deg = 5.0, .centre_eye = {ahead, ahead}};
    struct hmd_eye unused[2];
    views_at(0, -8, va, l.eyes);
    views_at(30, 0, vb, unused);
    size_t bytes = (size_t)2 * EW * EH * 4;
    uint8_t *a = malloc(bytes), *b = malloc(bytes), *img = malloc(bytes);
    struct hl_error err = {""};
    struct rnd_draw_stats st;
    CHECK(rnd_renderer_draw_stereo(r, s, va, index, lod, s->instance_count, NULL) == 0);
    CHECK(rnd_renderer_read_rgba(r, a, &err) == 0);
    CHECK(rnd_renderer_draw_stereo(r, s, vb, index, lod, s->instance_count, NULL) == 0);
    CHECK(rnd_renderer_read_rgba(r, b, &err) == 0);
    CHECK(rnd_renderer_draw_inset(r, s, va, &l, index, lod, s->instance_count, &st) == 0);
    CHECK(rnd_renderer_read_rgba(r, img, &err) == 0);
    struct rnd_layer_plan plan;
    CHECK(rnd_layer_plan_make(&l, EW, EH, &plan) == 0);
    CHECK(st.inset_triangles > 0 && st.periphery_triangles == 0 && st.periphery_px == 0.0 &&
          st.inset_px == plan.inset_px && st.triangles_per_eye[0] + st.triangles_per_eye[1] == st.inset_triangles);
    long in = 0, in_diff = 0, out = 0, out_diff = 0, differs_ab = 0;
    for (int e = 0; e < 2; ++e) {
        const int *rect = plan.inset_rect_px[e];
        for (int y = 0; y < EH; ++y)
            for (int x = 0; x < EW; ++x) {
                int gl_y = EH - 1 - y; /* rows top to bottom; the rectangle counts from the bottom */
                int inside = x >= rect[0] && x < rect[0] + rect[2] && gl_y >= rect[1] && gl_y < rect[1] + rect[3];
                const uint8_t *p = pix(img, e, x, y);
                differs_ab += memcmp(pix(a, e, x, y), pix(b, e, x, y), 4) != 0;
                if (inside)
                    ++in, in_diff += memcmp(p, pix(a, e, x, y), 4) != 0;
                else
                    ++out, out_diff += memcmp(p, pix(b, e, x, y), 4) != 0;
            }
    }
    printf("inset alone: rectangles %ld px (%ld differ from the full render), outside %ld px (%ld changed)\n", in,
           in_diff, out, out_diff);
    CHECK(differs_ab > 1000); /* the two poses differ, so the checks below can fail */
    CHECK(in > 1000 && in_diff == 0 && out > in && out_diff == 0);
    double px = -1.0;
    CHECK(rnd_renderer_composite_layers(r, &px) == 0 && px == 0.0);
    struct rnd_layers bad = l;
    bad.periphery_scale = 1.0;
    CHECK(rnd_renderer_draw_inset(r, s, va, &bad, index, lod, s->instance_count, &st) != 0);
    bad = l, bad.inset_radius_deg = 0.0;
    CHECK(rnd_renderer_draw_inset(r, s, va, &bad, index, lod, s->instance_count, &st) != 0);
    free(a);
    free(b);
    free(img);
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
/* Ring contrast (render/ring_contrast.c) against a reference computed here from the full-resolution
 * read-back: the reduced image as the 8× linear blit samples it (each reduced pixel the mean of the
 * 2×2 source pixels at its centre), linear luminance, the 3×3 binomial band over its mean, and each
 * pixel's ring by atan2 of its angle from the gaze. Then the ring map's cache: a second gaze and a
 * return to the first give the first's figures exactly. */
struct ring_ref {
    double max_contrast[RND_CONTRAST_RINGS];
    long pixels[RND_CONTRAST_RINGS];
};

static double srgb_to_linear(double v)
{
    v /= 255.0;
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

static void ring_reference(const uint8_t *full, const struct rnd_eye_gaze *gaze, struct ring_ref *out)
{
    memset(out, 0, sizeof *out);
    int w = EW / RND_RING_DOWNSAMPLE, h = EH / RND_RING_DOWNSAMPLE, d = RND_RING_DOWNSAMPLE;
    double *y = malloc((size_t)w * h * sizeof *y);
    for (int e = 0; e < 2; ++e) {
        for (int row = 0; row < h; ++row) /* GL rows, bottom up */
            for (int x = 0; x < w; ++x) {
                double lum = 0.0;
                for (int c = 0; c < 3; ++c) {
                    int sum = 0;
                    for (int dy = 0; dy < 2; ++dy)
                        for (int dx = 0; dx < 2; ++dx)
                            sum += pix(full, e, d * x + d / 2 - 1 + dx, EH - 1 - (d * row + d / 2 - 1 + dy))[c];
                    const double k[3] = {0.2126, 0.7152, 0.0722};
                    lum += k[c] * srgb_to_linear(floor(sum / 4.0 + 0.5));
                }
                y[(size_t)row * w + x] = lum;
            }
        const struct rnd_eye_gaze *g = &gaze[e];
        hl_vec3d gv = hl_v3_normalize(hl_v3(g->gaze_eye[0], g->gaze_eye[1], g->gaze_eye[2]));
        for (int row = 1; row + 1 < h; ++row)
            for (int x = 1; x + 1 < w; ++x) {
                double b = 0.0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx)
                        b += (2 - abs(dx)) * (2 - abs(dy)) * y[(size_t)(row + dy) * w + x + dx] / 16.0;
                double c = fabs(y[(size_t)row * w + x] - b) / (b > 0.001 ? b : 0.001);
                double xt = -g->tan_left + (x + 0.5) / w * (g->tan_left + g->tan_right);
                double yt = -g->tan_down + (row + 0.5) / h * (g->tan_up + g->tan_down);
                hl_vec3d dir = hl_v3_normalize(hl_v3(xt, yt, -1.0));
                double a = atan2(hl_v3_length(hl_v3_cross(dir, gv)), hl_v3_dot(dir, gv)) * HL_DEG_PER_RAD;
                int k = (int)(a / RND_CONTRAST_RING_DEG);
                if (k >= RND_CONTRAST_RINGS)
                    k = RND_CONTRAST_RINGS - 1;
                if (c > out->max_contrast[k])
                    out->max_contrast[k] = c;
                out->pixels[k]++;
            }
    }
    free(y);
}

static void test_ring_contrast(struct rnd_renderer *r, const struct scn_scene *s, const uint32_t *index,
                               const uint8_t *lod)
{
    struct rnd_eye_view v[2];
    struct hmd_eye eyes[2];
    views_at(0, -8, v, eyes);
    struct hl_error err = {""};
    uint8_t *full = malloc((size_t)2 * EW * EH * 4);
    CHECK(rnd_renderer_draw_stereo(r, s, v, index, lod, s->instance_count, NULL) == 0);
    CHECK(rnd_renderer_read_rgba(r, full, &err) == 0);
    struct rnd_eye_gaze at_lens[2], off_axis[2];
    for (int e = 0; e < 2; ++e) {
        struct rnd_eye_gaze g = {eyes[e].tan_left, eyes[e].tan_right, eyes[e].tan_up, eyes[e].tan_down, {0, 0, -1}};
        at_lens[e] = g;
        g.gaze_eye[0] = 0.25, g.gaze_eye[1] = -0.15;
        off_axis[e] = g;
    }
    struct rnd_ring_contrast a1, b, a2;
    CHECK(rnd_renderer_ring_contrast(r, at_lens, &a1, &err) == 0);
    CHECK(rnd_renderer_ring_contrast(r, off_axis, &b, &err) == 0);
    CHECK(rnd_renderer_ring_contrast(r, at_lens, &a2, &err) == 0);
    CHECK(a1.valid && b.valid && a2.valid);
    CHECK(memcmp(a1.max_contrast, a2.max_contrast, sizeof a1.max_contrast) == 0);
    CHECK(memcmp(a1.pixels, a2.pixels, sizeof a1.pixels) == 0 && a1.mean_relative_luminance == a2.mean_relative_luminance);
    CHECK(memcmp(a1.pixels, b.pixels, sizeof a1.pixels) != 0); /* the rings moved with the gaze */
    const struct rnd_eye_gaze *gazes[2] = {at_lens, off_axis};
    const struct rnd_ring_contrast *got[2] = {&a1, &b};
    for (int t = 0; t < 2; ++t) {
        struct ring_ref ref;
        ring_reference(full, gazes[t], &ref);
        int rings_seen = 0;
        for (int k = 0; k < RND_CONTRAST_RINGS; ++k) {
            long dp = labs((long)got[t]->pixels[k] - ref.pixels[k]);
            double dc = fabs(got[t]->max_contrast[k] - ref.max_contrast[k]);
            rings_seen += ref.pixels[k] > 0;
            if (dp > 2 + ref.pixels[k] / 100 || dc > 0.02 + 0.05 * ref.max_contrast[k])
                printf("  gaze %d ring %d: %u px (reference %ld), max contrast %.4f (reference %.4f)\n", t, k,
                       got[t]->pixels[k], ref.pixels[k], got[t]->max_contrast[k], ref.max_contrast[k]);
            /* Pixel counts: only a centre within rounding of a ring's edge may fall either side.
             * Contrast: one 8-bit level of the blit's rounding on a dark pixel moves it a few %. */
            CHECK(dp <= 2 + ref.pixels[k] / 100);
            CHECK(dc <= 0.02 + 0.05 * ref.max_contrast[k]);
        }
        printf("ring contrast, gaze %d: %d rings seen; ring 0 max %.4f (reference %.4f), ring 6 %.4f (%.4f)\n", t,
               rings_seen, got[t]->max_contrast[0], ref.max_contrast[0], got[t]->max_contrast[6], ref.max_contrast[6]);
        CHECK(rings_seen >= 8);
    }
    free(full);
}

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
    test_inset_alone(r, &s, index, lod);
    test_distortion_composite(r, &s, index, lod);
    test_ring_contrast(r, &s, index, lod);
    free(index);
    free(lod);
    scn_scene_free(&s);
    rnd_renderer_destroy(r);
    return tu_finish("layers");
}
