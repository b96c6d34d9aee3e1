/* Foveated layers (render/layers.h): the inset drawn at full resolution under a scissor, the periphery
 * into a smaller framebuffer, and the composite mesh that upsamples the periphery around the inset's
 * inner disc. Guenter et al. 2012 (PAPERS.md §6) blend their layers with a smoothstep over a band
 * and composite in one pass; the mesh here leaves the inner disc out so that its pixels are never
 * touched (an exact inset) and its fragments are never shaded twice. */
#include "render/render_internal.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Azimuths of the composite's rings: the chords of a 64-gon cut into the inner disc by at most
 * 1 − cos(π/64) = 0.12 % of its radius, where the band's weight is still ~1e-4 (invisible in 8 bits). */
enum { RND_LAYER_SEGMENTS = 64 };
enum { RND_LAYER_RING = RND_LAYER_SEGMENTS + 1 };      /* the strip closes on its first azimuth */
enum { RND_LAYER_EYE_VERTICES = 4 * RND_LAYER_RING }; /* band strip, then outer strip */
enum { RND_LAYER_FLOATS = 3 };                         /* NDC x, y; band parameter t */

/* A periphery framebuffer exactly as large as both eyes' peripheries side by side, so its clear is a
 * whole-buffer clear: on llvmpipe a scissored glClear is drawn as a quad, about 4× the whole-buffer
 * clear's time per pixel (calibrate's periphery empty frames, 2160 × 1200 eyes: 5.6 ms at s = 0.75
 * scissored in the eyes' size, 2.3 ms for the whole eyes' size cleared whole; docs/RESULTS.md). */
struct rnd_periphery_target {
    GLuint fbo, color_tex, depth_rb;
    int w, h;       /* 0: an empty slot */
    uint64_t used;  /* the draw that used it last, for replacing the least recently used */
};
/* Slots: one per periphery size in use (the fixed scales need four; Valve's adaptive controller
 * moves between neighbouring levels). Each is at most as large as the eyes. */
enum { RND_PERIPHERY_TARGETS = 5 };
struct rnd_layer_targets {
    struct rnd_periphery_target periphery[RND_PERIPHERY_TARGETS];
    int current;        /* the slot the last draw used */
    uint64_t draws;
    GLuint program, vao, vbo;
    GLint u_source, u_origin, u_size, u_tex;
    float vertices[2 * RND_LAYER_EYE_VERTICES * RND_LAYER_FLOATS];
    /* the last rnd_renderer_draw_layers, for rnd_renderer_composite_layers */
    struct rnd_layers setting;
    struct rnd_layer_plan plan;
    int pending;   /* drawn, not composited into the FBO yet */
};

static const char rnd_layer_vs[] =
    "#version 450 core\n"
    "layout(location = 0) in vec2 a_ndc; /* the eye's viewport */\n"
    "layout(location = 1) in float a_t;  /* 0 at the inset's inner edge, 1 from its outer edge on */\n"
    "out vec2 v_uv;\n"
    "out float v_t;\n"
    "void main() {\n"
    "    v_uv = a_ndc * 0.5 + 0.5;\n"
    "    v_t = a_t;\n"
    "    gl_Position = vec4(a_ndc, 0.0, 1.0);\n"
    "}\n";

/* The periphery's texel centres are clamped to its own eye's rectangle, so the bilinear filter never
 * borrows from the other eye or from what lies beyond the drawn corner. */
static const char rnd_layer_fs[] =
    "#version 450 core\n"
    "in vec2 v_uv;\n"
    "in float v_t;\n"
    "uniform sampler2D u_source;\n"
    "uniform vec2 u_origin; /* the eye's periphery in the texture, pixels */\n"
    "uniform vec2 u_size;\n"
    "uniform vec2 u_tex;    /* the texture's size, pixels */\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    vec2 p = u_origin + clamp(v_uv * u_size, vec2(0.5), u_size - vec2(0.5));\n"
    "    o_color = vec4(texture(u_source, p / u_tex).rgb, smoothstep(0.0, 1.0, v_t));\n"
    "}\n";

/* ---- geometry (pure) ------------------------------------------------------------------------ */

static int layers_valid(const struct rnd_layers *l)
{
    if (!l || !(l->periphery_scale >= RND_LAYER_SCALE_MIN && l->periphery_scale <= 1.0) ||
        !(l->inset_radius_deg >= 0.0) || !isfinite(l->inset_radius_deg) || !(l->blend_deg > 0.0) ||
        !isfinite(l->blend_deg))
        return 0;
    for (int e = 0; e < 2; ++e) {
        const struct hmd_eye *y = &l->eyes[e];
        if (!(y->tan_left > 0.0 && y->tan_right > 0.0 && y->tan_up > 0.0 && y->tan_down > 0.0) ||
            !isfinite(y->tan_left + y->tan_right + y->tan_up + y->tan_down))
            return 0;
        double n = hl_v3_length(l->centre_eye[e]);
        if (!(n > 1e-9) || !isfinite(n))
            return 0;
    }
    return 1;
}

/* An orthonormal frame around the unit centre c: u, v span the plane across it. */
static void cone_frame(hl_vec3d c, hl_vec3d *u, hl_vec3d *v)
{
    hl_vec3d a = fabs(c.x) < 0.9 ? hl_v3(1, 0, 0) : hl_v3(0, 1, 0);
    *u = hl_v3_normalize(hl_v3_cross(a, c));
    *v = hl_v3_cross(c, *u);
}

/* The ring radius_deg around the centre at the RND_LAYER_RING azimuths (the last repeats the first),
 * on the eye's image plane in NDC of its viewport (x right, y up, the frustum's edges at ±1). The
 * azimuths turn by a fixed rotation, so a ring costs four trigonometric calls. The cone stays in
 * front of the eye (radius + the centre's angle < 90°, checked by the caller). */
static void ring_ndc(const struct hmd_eye *y, hl_vec3d c, hl_vec3d u, hl_vec3d v, double radius_deg,
                     double out[RND_LAYER_RING][2])
{
    double r = radius_deg / HL_DEG_PER_RAD, cr = cos(r), sr = sin(r);
    double step_c = cos(2.0 * HL_PI / RND_LAYER_SEGMENTS), step_s = sin(2.0 * HL_PI / RND_LAYER_SEGMENTS);
    double cp = 1.0, sp = 0.0;
    for (int i = 0; i < RND_LAYER_RING; ++i) {
        if (i == RND_LAYER_SEGMENTS)
            cp = 1.0, sp = 0.0; /* close exactly on the first point */
        hl_vec3d w = hl_v3_add(hl_v3_scale(u, cp), hl_v3_scale(v, sp));
        hl_vec3d d = hl_v3_add(hl_v3_scale(c, cr), hl_v3_scale(w, sr));
        double x_t = d.x / -d.z, y_t = d.y / -d.z; /* the image plane at distance 1 */
        out[i][0] = 2.0 * (x_t + y->tan_left) / (y->tan_left + y->tan_right) - 1.0;
        out[i][1] = 2.0 * (y_t + y->tan_down) / (y->tan_up + y->tan_down) - 1.0;
        double next_c = cp * step_c - sp * step_s;
        sp = sp * step_c + cp * step_s, cp = next_c;
    }
}

/* The centre's angle from the eye's axis (−Z), degrees. */
static double centre_off_axis_deg(hl_vec3d c)
{
    return atan2(sqrt(c.x * c.x + c.y * c.y), -c.z) * HL_DEG_PER_RAD;
}

int rnd_layer_plan_make(const struct rnd_layers *l, int eye_w, int eye_h, struct rnd_layer_plan *out)
{
    memset(out, 0, sizeof *out);
    if (!layers_valid(l) || eye_w < 1 || eye_h < 1)
        return -1;
    double s = l->periphery_scale;
    out->periphery_px[0] = (int)fmax(1.0, lround(s * eye_w));
    out->periphery_px[1] = (int)fmax(1.0, lround(s * eye_h));
    for (int e = 0; e < 2; ++e) {
        int *rect = out->inset_rect_px[e];
        hl_vec3d c = hl_v3_normalize(l->centre_eye[e]);
        double outer_deg = l->inset_radius_deg + l->blend_deg;
        if (s >= 1.0) {
            continue; /* one layer: no inset */
        }
        if (centre_off_axis_deg(c) + outer_deg >= RND_LAYER_MAX_CONE_DEG) {
            out->covers[e] = 1;
            rect[0] = rect[1] = 0, rect[2] = eye_w, rect[3] = eye_h;
            out->inset_px += (double)eye_w * eye_h;
            continue;
        }
        out->periphery_px_total += (double)out->periphery_px[0] * out->periphery_px[1];
        if (l->inset_radius_deg <= 0.0)
            continue;
        hl_vec3d u, v;
        cone_frame(c, &u, &v);
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        double ring[RND_LAYER_RING][2];
        ring_ndc(&l->eyes[e], c, u, v, outer_deg, ring);
        for (int i = 0; i < RND_LAYER_SEGMENTS; ++i)
            for (int a = 0; a < 2; ++a)
                lo[a] = fmin(lo[a], ring[i][a]), hi[a] = fmax(hi[a], ring[i][a]);
        /* The chords lie inside the circle; a pixel's margin covers their sagitta and the rounding. */
        double size[2] = {eye_w, eye_h};
        int r0[2], r1[2];
        for (int a = 0; a < 2; ++a) {
            double p0 = floor((lo[a] * 0.5 + 0.5) * size[a]) - 1.0, p1 = ceil((hi[a] * 0.5 + 0.5) * size[a]) + 1.0;
            r0[a] = (int)fmin(fmax(p0, 0.0), size[a]);
            r1[a] = (int)fmin(fmax(p1, 0.0), size[a]);
        }
        if (r1[0] > r0[0] && r1[1] > r0[1]) {
            rect[0] = r0[0], rect[1] = r0[1], rect[2] = r1[0] - r0[0], rect[3] = r1[1] - r0[1];
            out->inset_px += (double)rect[2] * rect[3];
        }
    }
    return 0;
}

void rnd_layer_rect_tangents(double tan_left, double tan_right, double tan_down, double tan_up, double width_px,
                             double height_px, const int rect[4], double out[4])
{
    double tx = (tan_left + tan_right) / width_px, ty = (tan_up + tan_down) / height_px;
    out[0] = tan_left - rect[0] * tx;
    out[1] = -tan_left + (rect[0] + rect[2]) * tx;
    out[2] = tan_down - rect[1] * ty;
    out[3] = -tan_down + (rect[1] + rect[3]) * ty;
}

/* The composite's mesh for one eye: the band strip (inner ring t = 0, outer ring t = 1), then the
 * outer strip from the outer ring to far outside the viewport (t = 1). The three rings of an azimuth
 * lie on one line through the centre's image (they share the plane of the centre and that azimuth,
 * which holds the eye), so the strips never fold. Without an inset: one quad over the viewport. */
static int composite_mesh(const struct rnd_layers *l, int e, float *out)
{
    hl_vec3d c = hl_v3_normalize(l->centre_eye[e]);
    if (l->inset_radius_deg <= 0.0) {
        static const float quad[4][3] = {{-1, -1, 1}, {1, -1, 1}, {-1, 1, 1}, {1, 1, 1}};
        memcpy(out, quad, sizeof quad);
        return 4;
    }
    hl_vec3d u, v;
    cone_frame(c, &u, &v);
    double centre[RND_LAYER_RING][2], inner[RND_LAYER_RING][2], edge[RND_LAYER_RING][2];
    ring_ndc(&l->eyes[e], c, u, v, 0.0, centre);
    ring_ndc(&l->eyes[e], c, u, v, l->inset_radius_deg, inner);
    ring_ndc(&l->eyes[e], c, u, v, l->inset_radius_deg + l->blend_deg, edge);
    float *band = out, *outer = out + 2 * RND_LAYER_RING * RND_LAYER_FLOATS;
    for (int i = 0; i < RND_LAYER_RING; ++i) {
        const double *p = inner[i], *q = edge[i];
        double dx = q[0] - centre[0][0], dy = q[1] - centre[0][1], n = hypot(dx, dy);
        double far_x = centre[0][0] + 8.0 * dx / n, far_y = centre[0][1] + 8.0 * dy / n; /* NDC spans 2 */
        float *b = band + 6 * i, *o = outer + 6 * i;
        b[0] = (float)p[0], b[1] = (float)p[1], b[2] = 0.0f;
        b[3] = (float)q[0], b[4] = (float)q[1], b[5] = 1.0f;
        o[0] = (float)q[0], o[1] = (float)q[1], o[2] = 1.0f;
        o[3] = (float)far_x, o[4] = (float)far_y, o[5] = 1.0f;
    }
    return RND_LAYER_EYE_VERTICES;
}

/* ---- GL ------------------------------------------------------------------------------------- */

static void periphery_target_release(struct rnd_periphery_target *p)
{
    if (p->w > 0) {
        glDeleteFramebuffers(1, &p->fbo);
        glDeleteTextures(1, &p->color_tex);
        glDeleteRenderbuffers(1, &p->depth_rb);
    }
    memset(p, 0, sizeof *p);
}

/* The slot of size w × h, made (in an empty or the least recently used slot) when none is: its
 * first use allocates, which the session's warm-up does for every fixed scale. 0, or −1 (GL error). */
static int periphery_target_use(struct rnd_layer_targets *t, int w, int h)
{
    int slot = -1, oldest = 0;
    for (int i = 0; i < RND_PERIPHERY_TARGETS && slot < 0; ++i)
        if (t->periphery[i].w == w && t->periphery[i].h == h)
            slot = i;
    if (slot < 0) {
        for (int i = 1; i < RND_PERIPHERY_TARGETS; ++i)
            if (t->periphery[i].used < t->periphery[oldest].used)
                oldest = i; /* an empty slot has used 0 */
        struct rnd_periphery_target *p = &t->periphery[oldest];
        periphery_target_release(p);
        unsigned status = rnd_gl_draw_target(w, h, &p->fbo, &p->color_tex, &p->depth_rb);
        p->w = w, p->h = h;
        if (status != GL_FRAMEBUFFER_COMPLETE || glGetError() != GL_NO_ERROR) {
            periphery_target_release(p);
            return -1;
        }
        slot = oldest;
    }
    t->periphery[slot].used = ++t->draws;
    t->current = slot;
    return 0;
}

void rnd_layer_targets_destroy(struct rnd_layer_targets *t, int delete_gl)
{
    if (!t)
        return;
    if (delete_gl) {
        for (int i = 0; i < RND_PERIPHERY_TARGETS; ++i)
            periphery_target_release(&t->periphery[i]);
        glDeleteProgram(t->program);
        glDeleteVertexArrays(1, &t->vao);
        glDeleteBuffers(1, &t->vbo);
    }
    free(t);
}

static int layer_targets_make(struct rnd_renderer *r)
{
    if (r->layers)
        return 0;
    struct rnd_layer_targets *t = calloc(1, sizeof *t);
    if (!t)
        return -1;
    struct hl_error err;
    t->program = rnd_gl_program_build(rnd_layer_vs, rnd_layer_fs, "layer composite", &err);
    if (!t->program) {
        free(t);
        return -1;
    }
    t->u_source = glGetUniformLocation(t->program, "u_source");
    t->u_origin = glGetUniformLocation(t->program, "u_origin");
    t->u_size = glGetUniformLocation(t->program, "u_size");
    t->u_tex = glGetUniformLocation(t->program, "u_tex");
    glGenVertexArrays(1, &t->vao);
    glGenBuffers(1, &t->vbo);
    glBindVertexArray(t->vao);
    glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof t->vertices, NULL, GL_STREAM_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, RND_LAYER_FLOATS * sizeof(float), (const void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, RND_LAYER_FLOATS * sizeof(float),
                          (const void *)(2 * sizeof(float)));
    glBindVertexArray(0);
    if (glGetError() != GL_NO_ERROR) {
        rnd_layer_targets_destroy(t, 1);
        return -1;
    }
    r->layers = t;
    return 0;
}

/* Step 1: the insets, full resolution, each under its scissor, into the renderer's FBO. */
static void draw_insets(struct rnd_renderer *r, const struct scn_scene *scene, const struct rnd_eye_view views[2],
                        const struct rnd_layer_plan *plan, const uint32_t *index, const uint8_t *lod,
                        const uint8_t *mask, size_t count, struct rnd_draw_stats *st)
{
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    glEnable(GL_SCISSOR_TEST);
    for (int e = 0; e < 2; ++e) {
        const int *rect = plan->inset_rect_px[e];
        if (rect[2] < 1 || rect[3] < 1)
            continue;
        glViewport(e * r->eye_w, 0, r->eye_w, r->eye_h);
        glScissor(e * r->eye_w + rect[0], rect[1], rect[2], rect[3]);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        uint64_t tris = rnd_draw_view(r, scene, &views[e], index, lod, plan->covers[e] ? NULL : mask, RND_LAYER_INSET,
                                      count, &st->draw_calls);
        st->triangles_per_eye[e] += tris;
        st->inset_triangles += tris;
    }
    glDisable(GL_SCISSOR_TEST);
}

/* Step 2: the peripheries, s·width × s·height each, side by side in a framebuffer of their size. */
static void draw_peripheries(struct rnd_renderer *r, const struct scn_scene *scene,
                             const struct rnd_eye_view views[2], const struct rnd_layer_plan *plan,
                             const uint32_t *index, const uint8_t *lod, const uint8_t *mask, size_t count,
                             struct rnd_draw_stats *st)
{
    int pw = plan->periphery_px[0], ph = plan->periphery_px[1];
    glBindFramebuffer(GL_FRAMEBUFFER, r->layers->periphery[r->layers->current].fbo);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    for (int e = 0; e < 2; ++e) {
        if (plan->covers[e])
            continue;
        glViewport(e * pw, 0, pw, ph);
        uint64_t tris = rnd_draw_view(r, scene, &views[e], index, lod, mask, RND_LAYER_PERIPHERY, count, &st->draw_calls);
        st->triangles_per_eye[e] += tris;
        st->periphery_triangles += tris;
    }
}

/* Step 3: the periphery upsampled over each eye, around the inset's inner disc. */
static double composite(struct rnd_renderer *r, const struct rnd_layers *l, const struct rnd_layer_plan *plan,
                        unsigned target_fbo, int eye_w, int eye_h)
{
    struct rnd_layer_targets *t = r->layers;
    double shaded_px = 0.0;
    int counts[2] = {0, 0};
    for (int e = 0; e < 2; ++e)
        if (!plan->covers[e])
            counts[e] = composite_mesh(l, e, t->vertices + (size_t)e * RND_LAYER_EYE_VERTICES * RND_LAYER_FLOATS);
    glBindFramebuffer(GL_FRAMEBUFFER, target_fbo);
    glUseProgram(t->program);
    glBindVertexArray(t->vao);
    glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof t->vertices, t->vertices, GL_STREAM_DRAW); /* orphans last frame's */
    glActiveTexture(GL_TEXTURE0);
    const struct rnd_periphery_target *p = &t->periphery[t->current];
    glBindTexture(GL_TEXTURE_2D, p->color_tex);
    glUniform1i(t->u_source, 0);
    glUniform2f(t->u_size, (float)plan->periphery_px[0], (float)plan->periphery_px[1]);
    glUniform2f(t->u_tex, (float)p->w, (float)p->h);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    /* Only colour follows the weight; the target's alpha stays 1. */
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    for (int e = 0; e < 2; ++e) {
        if (!counts[e])
            continue;
        glViewport(e * eye_w, 0, eye_w, eye_h);
        glUniform2f(t->u_origin, (float)(e * plan->periphery_px[0]), 0.0f);
        GLint first = e * RND_LAYER_EYE_VERTICES;
        if (counts[e] == 4) { /* no inset: the periphery is the eye */
            glDrawArrays(GL_TRIANGLE_STRIP, first, 4);
        } else {
            glEnable(GL_BLEND);
            glDrawArrays(GL_TRIANGLE_STRIP, first, 2 * RND_LAYER_RING);
            glDisable(GL_BLEND); /* beyond the band the weight is 1: plain writes */
            glDrawArrays(GL_TRIANGLE_STRIP, first + 2 * RND_LAYER_RING, 2 * RND_LAYER_RING);
        }
        /* What it shades: the eye less the inner disc's rectangle share, an estimate for the record. */
        double inner = l->inset_radius_deg > 0.0
                           ? (double)plan->inset_rect_px[e][2] * plan->inset_rect_px[e][3] *
                                 pow(l->inset_radius_deg / (l->inset_radius_deg + l->blend_deg), 2.0) * (HL_PI / 4.0)
                           : 0.0;
        shaded_px += (double)eye_w * eye_h * (1.0 - inner / ((double)r->eye_w * r->eye_h));
    }
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    return shaded_px;
}

int rnd_renderer_draw_layers(struct rnd_renderer *r, const struct scn_scene *scene, const struct rnd_eye_view views[2],
                             const struct rnd_layers *layers, const uint32_t *index, const uint8_t *lod,
                             const uint8_t *periphery_lod, const uint8_t *mask, size_t count,
                             struct rnd_draw_stats *stats)
{
    if (r && r->layers)
        r->layers->pending = 0;
    if (!layers || layers->periphery_scale >= 1.0)
        return rnd_renderer_draw_stereo(r, scene, views, index, lod, count, stats);
    struct rnd_draw_stats st = {0};
    if (stats)
        *stats = st;
    struct rnd_layer_plan plan;
    if (!periphery_lod)
        periphery_lod = lod;
    if (!views || !r || rnd_layer_plan_make(layers, r->eye_w, r->eye_h, &plan) != 0 ||
        rnd_check_draw(r, scene, index, lod, count) != 0 ||
        (periphery_lod != lod && rnd_check_draw(r, scene, index, periphery_lod, count) != 0) ||
        rnd_renderer_current(r) != 0)
        return -1;
    if (layer_targets_make(r) != 0 || periphery_target_use(r->layers, 2 * plan.periphery_px[0], plan.periphery_px[1]) != 0)
        return -1;
    glUseProgram(r->program);
    glBindVertexArray(r->vao);
    draw_insets(r, scene, views, &plan, index, lod, mask, count, &st);
    draw_peripheries(r, scene, views, &plan, index, periphery_lod, mask, count, &st);
    glBindVertexArray(0);
    glFinish(); /* the caller's timer covers the GPU work */
    st.inset_px = plan.inset_px;
    st.periphery_px = plan.periphery_px_total;
    if (stats)
        *stats = st;
    if (glGetError() != GL_NO_ERROR)
        return -1;
    r->layers->setting = *layers;
    r->layers->plan = plan;
    r->layers->pending = 1;
    return 0;
}

int rnd_renderer_draw_inset(struct rnd_renderer *r, const struct scn_scene *scene, const struct rnd_eye_view views[2],
                            const struct rnd_layers *layers, const uint32_t *index, const uint8_t *lod, size_t count,
                            struct rnd_draw_stats *stats)
{
    struct rnd_draw_stats st = {0};
    if (stats)
        *stats = st;
    struct rnd_layer_plan plan;
    if (!r || !views || !layers || layers->periphery_scale >= 1.0 || !(layers->inset_radius_deg > 0.0) ||
        rnd_layer_plan_make(layers, r->eye_w, r->eye_h, &plan) != 0 || rnd_check_draw(r, scene, index, lod, count) != 0 ||
        rnd_renderer_current(r) != 0)
        return -1;
    if (r->layers)
        r->layers->pending = 0;
    glUseProgram(r->program);
    glBindVertexArray(r->vao);
    draw_insets(r, scene, views, &plan, index, lod, NULL, count, &st);
    glBindVertexArray(0);
    glFinish(); /* the caller's timer covers the GPU work */
    st.inset_px = plan.inset_px;
    if (stats)
        *stats = st;
    return glGetError() != GL_NO_ERROR ? -1 : 0;
}

int rnd_renderer_composite_layers(struct rnd_renderer *r, double *composite_px)
{
    if (composite_px)
        *composite_px = 0.0;
    if (!r || !r->layers || !r->layers->pending)
        return 0; /* a plain frame: nothing to composite */
    if (rnd_renderer_current(r) != 0)
        return -1;
    double shaded_px = composite(r, &r->layers->setting, &r->layers->plan, r->fbo, r->eye_w, r->eye_h);
    glFinish();
    r->layers->pending = 0;
    if (composite_px)
        *composite_px = shaded_px;
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

void rnd_layers_forget(struct rnd_layer_targets *t)
{
    if (t)
        t->pending = 0;
}

int rnd_layers_last(const struct rnd_renderer *r, struct rnd_layer_view *out)
{
    const struct rnd_layer_targets *t = r ? r->layers : NULL;
    if (!t || !t->pending)
        return 0;
    const struct rnd_layers *l = &t->setting;
    out->global = !(l->inset_radius_deg > 0.0);
    const struct rnd_periphery_target *p = &t->periphery[t->current];
    out->periphery_tex = p->color_tex;
    out->periphery_w = t->plan.periphery_px[0], out->periphery_h = t->plan.periphery_px[1];
    out->tex_w = p->w, out->tex_h = p->h;
    for (int e = 0; e < 2; ++e) {
        const struct hmd_eye *y = &l->eyes[e];
        out->tan[e][0] = (float)y->tan_left, out->tan[e][1] = (float)y->tan_right;
        out->tan[e][2] = (float)y->tan_up, out->tan[e][3] = (float)y->tan_down;
        hl_vec3d c = hl_v3_normalize(l->centre_eye[e]);
        out->centre[e][0] = (float)c.x, out->centre[e][1] = (float)c.y, out->centre[e][2] = (float)c.z;
    }
    out->inner_rad = (float)(l->inset_radius_deg / HL_DEG_PER_RAD);
    out->outer_rad = (float)((l->inset_radius_deg + l->blend_deg) / HL_DEG_PER_RAD);
    return 1;
}

void rnd_layers_composite_into(struct rnd_renderer *r, unsigned fbo, int eye_w, int eye_h)
{
    if (r->layers && r->layers->pending)
        (void)composite(r, &r->layers->setting, &r->layers->plan, fbo, eye_w, eye_h);
}
