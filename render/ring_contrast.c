/* The content's contrast by eccentricity (render/layers.h "What the content needs"): the last frame,
 * box-filtered down to a quarter of its size on the GPU, read back, and on the CPU the band-limited
 * contrast of its finest band (Peli 1990: the band image over the local mean, PAPERS.md §6) — the
 * largest in each ring of eccentricity around each eye's gaze. Tursun et al. 2019 predict the
 * resolution a region needs from a low-resolution version of the frame in the same way. */
#include "render/render_internal.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Linear luminance below this (the display's black, about a 1/300 of its white after the sRGB
 * EOTF of code value 3) counts as this in the local mean: the contrast of a step from black stays
 * finite, and a dark region's noise is not read as contrast. */
#define RING_MEAN_FLOOR 0.001

/* RING_NONE marks the reduced image's border pixels, which have no 3×3 neighbourhood. */
enum { RING_NONE = 0xff };

struct rnd_ring_target {
    unsigned fbo, rb;
    int w, h; /* both eyes side by side */
    uint8_t *rgba;
    float *y; /* linear luminance, then scratch */
    /* Each reduced pixel's ring, kept while the eyes' gaze and frusta stay as they were: under head
     * and vor the gaze is the lens centre, so the map is made once; tracked gaze remakes it. */
    uint8_t *ring;
    struct rnd_eye_gaze ring_gaze[2];
    int ring_valid;
};

void rnd_ring_target_destroy(struct rnd_ring_target *t, int delete_gl)
{
    if (!t)
        return;
    if (delete_gl) {
        glDeleteFramebuffers(1, &t->fbo);
        glDeleteRenderbuffers(1, &t->rb);
    }
    free(t->rgba);
    free(t->y);
    free(t->ring);
    free(t);
}

static int ring_target_make(struct rnd_renderer *r, struct hl_error *err)
{
    if (r->rings)
        return 0;
    struct rnd_ring_target *t = calloc(1, sizeof *t);
    if (!t)
        return hl_fail(err, "renderer: out of memory for the contrast read-back");
    t->w = 2 * (r->eye_w / RND_RING_DOWNSAMPLE > 0 ? r->eye_w / RND_RING_DOWNSAMPLE : 1);
    t->h = r->eye_h / RND_RING_DOWNSAMPLE > 0 ? r->eye_h / RND_RING_DOWNSAMPLE : 1;
    t->rgba = malloc((size_t)t->w * t->h * 4);
    t->y = malloc((size_t)t->w * t->h * 2 * sizeof(float));
    t->ring = malloc((size_t)t->w * t->h);
    GLenum status = rnd_gl_readback_target(t->w, t->h, &t->fbo, &t->rb);
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    if (!t->rgba || !t->y || !t->ring || status != GL_FRAMEBUFFER_COMPLETE || glGetError() != GL_NO_ERROR) {
        rnd_ring_target_destroy(t, 1);
        return hl_fail(err, "renderer: contrast read-back target %d×%d incomplete", 2 * r->eye_w / RND_RING_DOWNSAMPLE,
                       r->eye_h / RND_RING_DOWNSAMPLE);
    }
    r->rings = t;
    return 0;
}

/* 3×3 binomial blur of one eye's luminance (clamped at its edges): src → dst, w × h, row stride. */
static void blur3(const float *src, float *dst, int w, int h, int stride)
{
    for (int y = 0; y < h; ++y) {
        const float *up = src + (size_t)(y > 0 ? y - 1 : y) * stride, *mid = src + (size_t)y * stride;
        const float *dn = src + (size_t)(y + 1 < h ? y + 1 : y) * stride;
        float *out = dst + (size_t)y * stride;
        for (int x = 0; x < w; ++x) {
            int l = x > 0 ? x - 1 : x, r = x + 1 < w ? x + 1 : x;
            float row_up = up[l] + 2.0f * up[x] + up[r], row_mid = mid[l] + 2.0f * mid[x] + mid[r];
            float row_dn = dn[l] + 2.0f * dn[x] + dn[r];
            out[x] = (row_up + 2.0f * row_mid + row_dn) * (1.0f / 16.0f);
        }
    }
}

/* The map stays while the frusta are the same and the gaze moved less than RING_GAZE_SAME (in
 * direction cosines, ~0.2 µrad): the eye-frame gaze of a fixed gaze carries the rounding of each
 * frame's pose (~1e-16), and only a pixel centre that close to a ring's edge could change ring. */
#define RING_GAZE_SAME 1e-7
static hl_vec3d gaze_dir(const struct rnd_eye_gaze *g)
{
    return hl_v3_normalize(hl_v3(g->gaze_eye[0], g->gaze_eye[1], g->gaze_eye[2]));
}

static int same_gaze(const struct rnd_eye_gaze *a, const struct rnd_eye_gaze *b)
{
    if (a->tan_left != b->tan_left || a->tan_right != b->tan_right || a->tan_up != b->tan_up ||
        a->tan_down != b->tan_down)
        return 0;
    hl_vec3d da = gaze_dir(a), db = gaze_dir(b);
    return fabs(da.x - db.x) <= RING_GAZE_SAME && fabs(da.y - db.y) <= RING_GAZE_SAME &&
           fabs(da.z - db.z) <= RING_GAZE_SAME;
}

/* Each reduced pixel's ring of angle from its eye's gaze. Thresholds as cosines: a pixel's ring is
 * found by comparing its direction's dot product with the gaze against them, one square root per
 * pixel and no trigonometry. gaze: validated (non-zero direction). */
static void ring_map_make(struct rnd_ring_target *t, const struct rnd_eye_gaze *gaze)
{
    int ew = t->w / 2;
    double cos_edge[RND_CONTRAST_RINGS];
    for (int k = 0; k < RND_CONTRAST_RINGS; ++k)
        cos_edge[k] = cos((k + 1) * RND_CONTRAST_RING_DEG * HL_RAD_PER_DEG);
    memset(t->ring, RING_NONE, (size_t)t->w * t->h);
    for (int e = 0; e < 2; ++e) {
        const struct rnd_eye_gaze *g = &gaze[e];
        hl_vec3d d = gaze_dir(g);
        double gx = d.x, gy = d.y, gz = d.z;
        double sx = (g->tan_left + g->tan_right) / ew, sy = (g->tan_up + g->tan_down) / t->h;
        for (int row = 1; row + 1 < t->h; ++row) {
            double yt = -g->tan_down + (row + 0.5) * sy; /* GL rows: bottom up */
            uint8_t *out = t->ring + (size_t)row * t->w + (size_t)e * ew;
            for (int x = 1; x + 1 < ew; ++x) {
                double xt = -g->tan_left + (x + 0.5) * sx;
                double dot = (xt * gx + yt * gy - gz) / sqrt(xt * xt + yt * yt + 1.0);
                int k = 0;
                while (k + 1 < RND_CONTRAST_RINGS && dot < cos_edge[k])
                    ++k;
                out[x] = (uint8_t)k;
            }
        }
        t->ring_gaze[e] = *g;
    }
    t->ring_valid = 1;
}

int rnd_renderer_ring_contrast(struct rnd_renderer *r, const struct rnd_eye_gaze *gaze,
                               struct rnd_ring_contrast *out, struct hl_error *err)
{
    memset(out, 0, sizeof *out);
    if (!r || !gaze)
        return hl_fail(err, "renderer: no renderer or gaze");
    if (rnd_renderer_current(r) != 0)
        return hl_fail(err, "renderer: cannot make the context current");
    while (glGetError() != GL_NO_ERROR) {
    }
    if (ring_target_make(r, err) != 0)
        return -1;
    struct rnd_ring_target *t = r->rings;
    GLboolean scissor = glIsEnabled(GL_SCISSOR_TEST);
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->fbo);
    /* One blit for both eyes when the reduction is exact: each destination pixel's bilinear tap then
     * lies between the 2×2 source pixels at its centre, never across the eyes' seam (a second blit
     * costs llvmpipe ~0.3 ms of set-up). Otherwise each eye on its own, so no pixel mixes the two. */
    int ew = t->w / 2;
    if (r->eye_w == ew * RND_RING_DOWNSAMPLE && r->eye_h == t->h * RND_RING_DOWNSAMPLE)
        glBlitFramebuffer(0, 0, 2 * r->eye_w, r->eye_h, 0, 0, t->w, t->h, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    else
        for (int e = 0; e < 2; ++e)
            glBlitFramebuffer(e * r->eye_w, 0, (e + 1) * r->eye_w, r->eye_h, e * ew, 0, (e + 1) * ew, t->h,
                              GL_COLOR_BUFFER_BIT, GL_LINEAR);
    /* Layers the FBO does not hold composited (the distortion pass composites them): their composite
     * at this size, over the reduced insets. */
    rnd_layers_composite_into(r, t->fbo, ew, t->h);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, t->w, t->h, GL_RGBA, GL_UNSIGNED_BYTE, t->rgba);
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    if (scissor)
        glEnable(GL_SCISSOR_TEST);
    GLenum e_gl = glGetError();
    if (e_gl != GL_NO_ERROR)
        return hl_fail(err, "renderer: contrast down-blit or read-back failed: GL error 0x%x", (unsigned)e_gl);

    const double *lin = rnd_srgb_decode_table();
    size_t n = (size_t)t->w * t->h;
    float *y = t->y, *blur = t->y + n;
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const uint8_t *p = t->rgba + 4 * i;
        y[i] = (float)(0.2126 * lin[p[0]] + 0.7152 * lin[p[1]] + 0.0722 * lin[p[2]]);
        sum += y[i];
    }
    out->mean_relative_luminance = sum / (double)n;
    for (int e = 0; e < 2; ++e) {
        const double *g = gaze[e].gaze_eye;
        if (!(g[0] * g[0] + g[1] * g[1] + g[2] * g[2] > 0.0))
            return hl_fail(err, "renderer: eye %d has no gaze direction", e);
    }
    if (!t->ring_valid || !same_gaze(&t->ring_gaze[0], &gaze[0]) || !same_gaze(&t->ring_gaze[1], &gaze[1]))
        ring_map_make(t, gaze);
    for (int e = 0; e < 2; ++e)
        blur3(y + e * ew, blur + e * ew, ew, t->h, t->w);
    for (size_t i = 0; i < n; ++i) {
        int k = t->ring[i];
        if (k == RING_NONE)
            continue;
        /* The finest band over the local mean (Peli 1990): |Y − blur(Y)| / blur(Y). */
        double local = blur[i] > RING_MEAN_FLOOR ? blur[i] : RING_MEAN_FLOOR;
        double contrast = fabs((double)y[i] - blur[i]) / local;
        if (contrast > out->max_contrast[k])
            out->max_contrast[k] = contrast;
        out->pixels[k]++;
    }
    out->valid = 1;
    return 0;
}
