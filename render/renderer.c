/* The stereo pass: one FBO holding both eyes side by side, one vertex and one index buffer for the
 * whole scene, one shader. The instances that share a chain, a level and a colour are one instanced
 * draw of that level's index range per eye, their model-to-eye transforms per-instance attributes
 * (draw_list.c). */
#include "render/render_internal.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <stdlib.h>
#include <string.h>

static const char rnd_vs[] =
    "#version 450 core\n"
    "layout(location = 0) in vec3 a_position;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in mat4 i_mv; /* per instance (locations 2–5): model to eye */\n"
    "uniform mat4 u_proj;\n"
    "out vec3 v_normal;\n"
    "void main() {\n"
    "    v_normal = mat3(i_mv) * a_normal; /* rotation × uniform scale: renormalised below */\n"
    "    gl_Position = u_proj * (i_mv * vec4(a_position, 1.0));\n"
    "}\n";

/* Diffuse shading in linear light: the albedo (sRGB-encoded, as a user gives it) is decoded with
 * the sRGB EOTF (IEC 61966-2-1), shaded, and encoded for the RGBA8 target. Multiplying in the
 * encoded space would make an object's shading contrast depend on its albedo, because the EOTF is
 * not a power law; in linear light a shading change's contrast is a ratio of shading terms, the
 * same for every albedo, so the lost-contrast analysis may measure it on grey renders
 * (docs/analysis.md "Albedo"). The ambient 0.0732 is the EOTF of 0.3, the encoded ambient used
 * before, so the lit and unlit sides keep their 14:1 luminance range.
 * Cost: on llvmpipe each pow is a log2 and an exp2 per pixel. The albedo is decoded once per object
 * on the CPU, and the encode's power of a product is the product of powers, (a·s)^(1/2.4) =
 * a^(1/2.4)·s^(1/2.4), so a fragment takes one pow (of its shading s) instead of six: the same
 * values up to float rounding, 30 % off the fill-bound auditorium's draw (docs/RESULTS.md). */
static const char rnd_fs[] =
    "#version 450 core\n"
    "in vec3 v_normal;\n"
    "uniform vec3 u_albedo;      /* linear */\n"
    "uniform vec3 u_albedo_root; /* u_albedo^(1/2.4) */\n"
    "uniform vec3 u_light; /* unit direction towards the light, eye space */\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    float lambert = max(dot(normalize(v_normal), u_light), 0.0);\n"
    "    float shade = 0.0732 + 0.9268 * lambert;\n"
    "    vec3 c = u_albedo * shade;\n"
    "    vec3 encoded = 1.055 * u_albedo_root * pow(shade, 1.0 / 2.4) - 0.055;\n"
    "    o_color = vec4(mix(c * 12.92, encoded, step(vec3(0.0031308), c)), 1.0);\n"
    "}\n";

static int rnd_renderer_build_program(struct rnd_renderer *r, struct hl_error *err)
{
    r->program = rnd_gl_program_build(rnd_vs, rnd_fs, "renderer", err);
    if (!r->program)
        return -1;
    r->u_proj = glGetUniformLocation(r->program, "u_proj");
    r->u_albedo = glGetUniformLocation(r->program, "u_albedo");
    r->u_albedo_root = glGetUniformLocation(r->program, "u_albedo_root");
    r->u_light = glGetUniformLocation(r->program, "u_light");
    return 0;
}

static int rnd_renderer_build_fbo(struct rnd_renderer *r, struct hl_error *err)
{
    unsigned status = rnd_gl_draw_target(2 * r->eye_w, r->eye_h, &r->fbo, &r->color_tex, &r->depth_rb);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return hl_fail(err, "renderer: framebuffer %d×%d incomplete (status 0x%x, GL error 0x%x)", 2 * r->eye_w,
                       r->eye_h, status, (unsigned)glGetError());
    return 0;
}

int rnd_renderer_current(const struct rnd_renderer *r)
{
    return r->window ? rnd_window_make_current(r->window) : rnd_egl_make_current(&r->egl);
}

static int rnd_renderer_make(int eye_width_px, int eye_height_px, struct rnd_window *window,
                             struct rnd_renderer **out, struct hl_error *err)
{
    if (!out)
        return hl_fail(err, "renderer: no output");
    *out = NULL;
    if (eye_width_px < 1 || eye_height_px < 1 || eye_width_px > 8192 || eye_height_px > 8192)
        return hl_fail(err, "renderer: eye size %d×%d out of range (1…8192 each)", eye_width_px, eye_height_px);
    struct rnd_renderer *r = calloc(1, sizeof *r);
    if (!r)
        return hl_fail(err, "renderer: out of memory");
    r->eye_w = eye_width_px;
    r->eye_h = eye_height_px;
    r->window = window;
    if (window ? rnd_window_make_current(window) != 0 : rnd_egl_create(&r->egl, err) != 0) {
        if (window)
            hl_fail(err, "renderer: cannot make the window's context current");
        free(r);
        return -1;
    }
    GLint max_rb = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
    if (max_rb > 0 && 2 * eye_width_px > max_rb) {
        hl_fail(err, "renderer: %d px wide exceeds GL_MAX_RENDERBUFFER_SIZE %d", 2 * eye_width_px, max_rb);
        goto fail;
    }
    if (rnd_renderer_build_program(r, err) != 0 || rnd_renderer_build_fbo(r, err) != 0)
        goto fail;
    const char *name = (const char *)glGetString(GL_RENDERER);
    snprintf(r->name, sizeof r->name, "%s", name ? name : "unknown");
    glGenVertexArrays(1, &r->vao);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE); /* meshes are closed and CCW outward */
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
    *out = r;
    return 0;
fail:
    rnd_renderer_destroy(r);
    return -1;
}

int rnd_renderer_create(int eye_width_px, int eye_height_px, struct rnd_renderer **out, struct hl_error *err)
{
    return rnd_renderer_make(eye_width_px, eye_height_px, NULL, out, err);
}

int rnd_renderer_create_in_window(struct rnd_window *window, int eye_width_px, int eye_height_px,
                                  struct rnd_renderer **out, struct hl_error *err)
{
    if (!window)
        return hl_fail(err, "renderer: no window");
    return rnd_renderer_make(eye_width_px, eye_height_px, window, out, err);
}

unsigned rnd_renderer_color_texture(const struct rnd_renderer *r) { return r ? r->color_tex : 0; }

int rnd_renderer_make_current(const struct rnd_renderer *r) { return r ? rnd_renderer_current(r) : -1; }

void rnd_renderer_destroy(struct rnd_renderer *r)
{
    if (!r)
        return;
    if ((r->window || r->egl.context) && rnd_renderer_current(r) == 0) {
        glDeleteBuffers(1, &r->vbo);
        glDeleteBuffers(1, &r->ibo);
        glDeleteBuffers(1, &r->instance_vbo);
        glDeleteVertexArrays(1, &r->vao);
        glDeleteProgram(r->program);
        glDeleteFramebuffers(1, &r->fbo);
        glDeleteTextures(1, &r->color_tex);
        glDeleteRenderbuffers(1, &r->depth_rb);
        glDeleteFramebuffers(1, &r->lum_fbo);
        glDeleteRenderbuffers(1, &r->lum_rb);
        rnd_layer_targets_destroy(r->layers, 1);
        rnd_ring_target_destroy(r->rings, 1);
        r->layers = NULL;
        r->rings = NULL;
    }
    rnd_layer_targets_destroy(r->layers, 0); /* no context: the GL objects went with it */
    rnd_ring_target_destroy(r->rings, 0);
    rnd_egl_destroy(&r->egl);
    rnd_draw_list_free(&r->list);
    free(r);
}

const char *rnd_renderer_name(const struct rnd_renderer *r) { return r ? r->name : ""; }

void rnd_renderer_size(const struct rnd_renderer *r, int *width_px, int *height_px)
{
    if (width_px)
        *width_px = r ? 2 * r->eye_w : 0;
    if (height_px)
        *height_px = r ? r->eye_h : 0;
}

int rnd_renderer_upload_scene(struct rnd_renderer *r, const struct scn_scene *scene, struct hl_error *err)
{
    if (!r || !scene)
        return hl_fail(err, "renderer: no renderer or scene");
    if (rnd_renderer_current(r) != 0)
        return hl_fail(err, "renderer: cannot make the context current");
    size_t entries = (size_t)scene->instance_count + scene->impostor_instance_count;
    if (rnd_draw_list_reserve(&r->list, entries) != 0)
        return hl_fail(err, "renderer: out of memory for the draw list of %zu instances", entries);
    while (glGetError() != GL_NO_ERROR) {
    }
    if (!r->vbo)
        glGenBuffers(1, &r->vbo);
    if (!r->ibo)
        glGenBuffers(1, &r->ibo);
    /* One buffer: all positions, then all normals (non-interleaved, so the scene's arrays copy as is). */
    GLsizeiptr half = (GLsizeiptr)scene->vertex_count * 3 * (GLsizeiptr)sizeof(float);
    glBindVertexArray(r->vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glBufferData(GL_ARRAY_BUFFER, half * 2 > 0 ? half * 2 : 4, NULL, GL_STATIC_DRAW);
    if (half > 0) {
        glBufferSubData(GL_ARRAY_BUFFER, 0, half, scene->positions);
        glBufferSubData(GL_ARRAY_BUFFER, half, half, scene->normals);
    }
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, (const void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, (const void *)(uintptr_t)half);
    /* The per-instance transforms: a mat4 attribute takes four locations, one column each. */
    if (!r->instance_vbo)
        glGenBuffers(1, &r->instance_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, r->instance_vbo);
    for (int c = 0; c < 4; ++c) {
        glEnableVertexAttribArray(2 + c);
        glVertexAttribPointer(2 + c, 4, GL_FLOAT, GL_FALSE, 16 * sizeof(float), (const void *)(uintptr_t)(4 * c * sizeof(float)));
        glVertexAttribDivisor(2 + c, 1);
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo); /* recorded in the VAO */
    GLsizeiptr isize = (GLsizeiptr)scene->index_count * (GLsizeiptr)sizeof(uint32_t);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, isize > 0 ? isize : 4, isize > 0 ? scene->indices : NULL, GL_STATIC_DRAW);
    glBindVertexArray(0);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        r->has_scene = 0;
        return hl_fail(err, "renderer: uploading scene %s (%u vertices, %u indices) failed: GL error 0x%x",
                       scene->name, scene->vertex_count, scene->index_count, (unsigned)e);
    }
    r->scene_vertices = scene->vertex_count;
    r->scene_indices = scene->index_count;
    r->has_scene = 1;
    return 0;
}

/* A bad entry draws nothing rather than half a frame. */
int rnd_check_draw(const struct rnd_renderer *r, const struct scn_scene *scene, const uint32_t *index,
                          const uint8_t *lod, size_t count)
{
    if (!r || !scene || (count > 0 && (!index || !lod)) || !r->has_scene ||
        scene->vertex_count != r->scene_vertices || scene->index_count != r->scene_indices)
        return -1;
    for (size_t k = 0; k < count; ++k) {
        if (index[k] >= scene->instance_count + scene->impostor_instance_count || /* objects, then impostors */
            index[k] >= r->list.cap) /* not in the uploaded scene's per-instance arrays */
            return -1;
        uint32_t c = scene->instances[index[k]].chain;
        if (c >= scene->chain_count || (lod[k] != 255 && lod[k] >= scene->chains[c].lod_count))
            return -1;
    }
    return 0;
}

int rnd_renderer_draw_stereo(struct rnd_renderer *r, const struct scn_scene *scene,
                             const struct rnd_eye_view views[2], const uint32_t *index, const uint8_t *lod,
                             size_t count, struct rnd_draw_stats *stats)
{
    if (stats)
        *stats = (struct rnd_draw_stats){{0, 0}, 0, 0, 0, 0.0, 0.0};
    if (!views || rnd_check_draw(r, scene, index, lod, count) != 0)
        return -1;
    if (rnd_renderer_current(r) != 0)
        return -1;
    rnd_layers_forget(r->layers); /* the FBO holds a plain frame from here on */
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    glViewport(0, 0, 2 * r->eye_w, r->eye_h);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUseProgram(r->program);
    glBindVertexArray(r->vao);
    uint32_t calls = 0;
    for (int eye = 0; eye < 2; ++eye) {
        glViewport(eye * r->eye_w, 0, r->eye_w, r->eye_h);
        uint64_t tris = rnd_draw_view(r, scene, &views[eye], index, lod, NULL, 0, count, &calls);
        if (stats)
            stats->triangles_per_eye[eye] = tris;
    }
    glBindVertexArray(0);
    glFinish(); /* the caller's timer must cover the GPU work, not just the command submission */
    if (stats)
        stats->draw_calls = calls;
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

int rnd_renderer_draw_rect(struct rnd_renderer *r, const struct scn_scene *scene, const struct rnd_eye_view *view,
                           uint32_t instance, uint8_t lod, const int rect_px[4])
{
    if (!r || !view || !rect_px || rect_px[0] < 0 || rect_px[1] < 0 || rect_px[2] < 1 || rect_px[3] < 1 ||
        rect_px[0] + rect_px[2] > 2 * r->eye_w || rect_px[1] + rect_px[3] > r->eye_h ||
        rnd_check_draw(r, scene, &instance, &lod, 1) != 0 || rnd_renderer_current(r) != 0)
        return -1;
    rnd_layers_forget(r->layers);
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    glViewport(rect_px[0], rect_px[1], rect_px[2], rect_px[3]);
    glScissor(rect_px[0], rect_px[1], rect_px[2], rect_px[3]); /* clear this rectangle only */
    glEnable(GL_SCISSOR_TEST);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
    glUseProgram(r->program);
    glBindVertexArray(r->vao);
    uint32_t calls = 0;
    rnd_draw_view(r, scene, view, &instance, &lod, NULL, 0, 1, &calls);
    glBindVertexArray(0);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

int rnd_renderer_read_rect(struct rnd_renderer *r, const int rect_px[4], uint8_t *rgba, struct hl_error *err)
{
    if (!r || !rgba || !rect_px)
        return hl_fail(err, "renderer: no renderer, rectangle or buffer");
    int x = rect_px[0], y = rect_px[1], w = rect_px[2], h = rect_px[3];
    if (x < 0 || y < 0 || w < 1 || h < 1 || x + w > 2 * r->eye_w || y + h > r->eye_h)
        return hl_fail(err, "renderer: rectangle %d,%d %d×%d outside the %d×%d framebuffer", x, y, w, h,
                       2 * r->eye_w, r->eye_h);
    if (rnd_renderer_current(r) != 0)
        return hl_fail(err, "renderer: cannot make the context current");
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(x, y, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        return hl_fail(err, "renderer: glReadPixels failed: GL error 0x%x", (unsigned)e);
    rnd_flip_rows(rgba, w, h);
    return 0;
}

void rnd_flip_rows(uint8_t *rgba, int w, int h)
{
    /* GL's row 0 is the bottom; images want the top first. Swap in place: no allocation. */
    size_t stride = (size_t)w * 4;
    for (int row = 0; row < h / 2; ++row) {
        uint8_t *a = rgba + (size_t)row * stride, *b = rgba + (size_t)(h - 1 - row) * stride;
        for (size_t i = 0; i < stride; ++i) {
            uint8_t t = a[i];
            a[i] = b[i];
            b[i] = t;
        }
    }
}

int rnd_renderer_read_rgba(struct rnd_renderer *r, uint8_t *rgba, struct hl_error *err)
{
    if (!r || !rgba)
        return hl_fail(err, "renderer: no renderer or buffer");
    const int rect[4] = {0, 0, 2 * r->eye_w, r->eye_h};
    return rnd_renderer_read_rect(r, rect, rgba, err);
}

unsigned rnd_gl_color_texture(int w, int h)
{
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, w, h);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    return tex;
}

unsigned rnd_gl_draw_target(int w, int h, unsigned *fbo_out, unsigned *color_tex_out, unsigned *depth_rb_out)
{
    *color_tex_out = rnd_gl_color_texture(w, h);
    glGenRenderbuffers(1, depth_rb_out);
    glBindRenderbuffer(GL_RENDERBUFFER, *depth_rb_out);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    glGenFramebuffers(1, fbo_out);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo_out);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *color_tex_out, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, *depth_rb_out);
    return glCheckFramebufferStatus(GL_FRAMEBUFFER);
}

unsigned rnd_gl_readback_target(int w, int h, unsigned *fbo_out, unsigned *rb_out)
{
    glGenFramebuffers(1, fbo_out);
    glGenRenderbuffers(1, rb_out);
    glBindRenderbuffer(GL_RENDERBUFFER, *rb_out);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo_out);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, *rb_out);
    return glCheckFramebufferStatus(GL_FRAMEBUFFER);
}

/* The small RGBA8 target of the luminance down-blit, made once. */
static int rnd_lum_target(struct rnd_renderer *r, struct hl_error *err)
{
    if (r->lum_fbo)
        return 0;
    r->lum_w = 2 * r->eye_w < RND_LUM_W ? 2 * r->eye_w : RND_LUM_W; /* both even: eyes stay halves */
    r->lum_h = r->eye_h < RND_LUM_H ? r->eye_h : RND_LUM_H;
    GLenum status = rnd_gl_readback_target(r->lum_w, r->lum_h, &r->lum_fbo, &r->lum_rb);
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    GLenum e = glGetError();
    if (status != GL_FRAMEBUFFER_COMPLETE || e != GL_NO_ERROR) {
        glDeleteFramebuffers(1, &r->lum_fbo);
        glDeleteRenderbuffers(1, &r->lum_rb);
        r->lum_fbo = r->lum_rb = 0; /* the next call tries again rather than reading a broken target */
        return hl_fail(err, "renderer: luminance target %d×%d incomplete (status 0x%x, GL error 0x%x)", r->lum_w,
                       r->lum_h, (unsigned)status, (unsigned)e);
    }
    return 0;
}

int rnd_renderer_mean_luminance(struct rnd_renderer *r, double *mean_relative_out, struct hl_error *err)
{
    if (!r || !mean_relative_out)
        return hl_fail(err, "renderer: no renderer or output");
    if (rnd_renderer_current(r) != 0)
        return hl_fail(err, "renderer: cannot make the context current");
    while (glGetError() != GL_NO_ERROR) { /* an earlier call's error is not this one's */
    }
    if (rnd_lum_target(r, err) != 0)
        return -1;
    /* The blit honours the scissor test; the whole framebuffer is wanted. */
    GLboolean scissor = glIsEnabled(GL_SCISSOR_TEST);
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->lum_fbo);
    glBlitFramebuffer(0, 0, 2 * r->eye_w, r->eye_h, 0, 0, r->lum_w, r->lum_h, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, r->lum_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, r->lum_w, r->lum_h, GL_RGBA, GL_UNSIGNED_BYTE, r->lum_rgba);
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo); /* as the draws leave it */
    if (scissor)
        glEnable(GL_SCISSOR_TEST);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        return hl_fail(err, "renderer: luminance down-blit or read-back failed: GL error 0x%x", (unsigned)e);
    /* Rec. 709 / sRGB primaries: Y of linear R, G, B. */
    const double *lin = rnd_srgb_decode_table();
    double sum = 0.0;
    size_t n = (size_t)r->lum_w * (size_t)r->lum_h;
    for (size_t i = 0; i < n; ++i) {
        const uint8_t *p = r->lum_rgba + 4 * i;
        sum += 0.2126 * lin[p[0]] + 0.7152 * lin[p[1]] + 0.0722 * lin[p[2]];
    }
    *mean_relative_out = sum / (double)n;
    return 0;
}
