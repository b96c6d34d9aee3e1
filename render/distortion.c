/* The lens distortion pass: the renderer's FBO (both eyes, undistorted) drawn to the output through
 * a per-eye mesh whose vertices carry one source point per colour channel. Pre-distorting on a
 * mesh rather than per pixel is how Monado (u_distortion_mesh.c) and OpenHMD's examples do it: the
 * model is evaluated at (64+1)² vertices per eye, the GPU interpolates between them, and the
 * fragment shader only samples three times. Chromatic aberration: each channel's displacement is
 * scaled by the profile's aberration factor (DEVICES.md §1b, OpenHMD's universal model), so red and
 * blue separate radially — outward for the channel with the smaller factor, whose image is
 * magnified more. */
#include "render/render_internal.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <cglm/cglm.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct rnd_distortion {
    struct rnd_renderer *renderer;
    int out_w, out_h, offscreen, has_lens;
    GLuint program, vao, vbo, ibo;
    GLint u_eye, u_source, u_lens;
    GLint u_layers, u_periphery, u_p_origin, u_p_size, u_p_tex, u_tan, u_centre, u_band; /* foveated layers */
    GLuint fbo, tex; /* offscreen output */
    GLsizei index_count, vertices_per_eye;
    int cells; /* per side of an eye's mesh */
};

enum { RND_DIST_FLOATS = 8 }; /* per vertex: position, uv r, g, b */

static const char rnd_dist_vs[] =
    "#version 450 core\n"
    "layout(location = 0) in vec2 a_position; /* clip space of the whole output */\n"
    "layout(location = 1) in vec2 a_uv_r;     /* the eye's [0,1]^2 */\n"
    "layout(location = 2) in vec2 a_uv_g;\n"
    "layout(location = 3) in vec2 a_uv_b;\n"
    "out vec2 v_uv_r, v_uv_g, v_uv_b;\n"
    "void main() {\n"
    "    v_uv_r = a_uv_r; v_uv_g = a_uv_g; v_uv_b = a_uv_b;\n"
    "    gl_Position = vec4(a_position, 0.0, 1.0);\n"
    "}\n";

/* Points outside the eye's image are black (the lens shows nothing rendered there), and never
 * borrow from the other eye's half of the FBO. With foveated layers (render/layers.h) the pass is
 * also their composite: beyond the inset's inner disc it mixes in the periphery, bilinearly
 * upsampled, by smoothstep across the blend band (its weight taken at the green sample's point);
 * inside the disc the weight is 0 and the source is the FBO's alone, as in a plain frame. */
static const char rnd_dist_fs[] =
    "#version 450 core\n"
    "in vec2 v_uv_r, v_uv_g, v_uv_b;\n"
    "uniform sampler2D u_source; /* both eyes side by side */\n"
    "uniform float u_eye;        /* 0 left, 1 right */\n"
    "uniform int u_lens;         /* 0: one sample per pixel (the three uvs are equal) */\n"
    "uniform int u_layers;       /* 0 plain, 1 inset and periphery, 2 the periphery alone */\n"
    "uniform sampler2D u_periphery;\n"
    "uniform vec2 u_p_origin, u_p_size, u_p_tex; /* this eye's periphery in its texture, pixels */\n"
    "uniform vec4 u_tan;         /* the eye's tangents: left, right, up, down */\n"
    "uniform vec3 u_centre;      /* the inset's centre, eye frame */\n"
    "uniform vec2 u_band;        /* the blend band's inner and outer radius, radians */\n"
    "out vec4 o_color;\n"
    "float inside(vec2 e) { vec2 s = step(vec2(0.0), e) * step(e, vec2(1.0)); return s.x * s.y; }\n"
    "vec2 fbo(vec2 e) { return vec2((u_eye + e.x) * 0.5, e.y); }\n"
    "float weight(vec2 e) {\n"
    "    if (u_layers != 1) return float(u_layers == 2);\n"
    "    vec3 d = normalize(vec3(-u_tan.x + e.x * (u_tan.x + u_tan.y), -u_tan.w + e.y * (u_tan.z + u_tan.w), -1.0));\n"
    "    return smoothstep(u_band.x, u_band.y, atan(length(cross(d, u_centre)), dot(d, u_centre)));\n"
    "}\n"
    "vec3 periphery(vec2 e) {\n"
    "    vec2 p = u_p_origin + clamp(e * u_p_size, vec2(0.5), u_p_size - vec2(0.5));\n"
    "    return texture(u_periphery, p / u_p_tex).rgb;\n"
    "}\n"
    "vec3 source(vec2 e, float w) {\n"
    "    vec3 inset = texture(u_source, fbo(e)).rgb;\n"
    "    return w > 0.0 ? mix(inset, periphery(e), w) : inset;\n"
    "}\n"
    "void main() {\n"
    "    float w = weight(v_uv_g);\n"
    "    if (u_lens == 0) { o_color = vec4(source(v_uv_g, w) * inside(v_uv_g), 1.0); return; }\n"
    "    float r = source(v_uv_r, w).r * inside(v_uv_r);\n"
    "    float g = source(v_uv_g, w).g * inside(v_uv_g);\n"
    "    float b = source(v_uv_b, w).b * inside(v_uv_b);\n"
    "    o_color = vec4(r, g, b, 1.0);\n"
    "}\n";

int rnd_distortion_cells(int out_w_px)
{
    /* One vertex per 16 output pixels is finer than the lens model varies (the PanoTools
     * polynomial is smooth), and on llvmpipe each triangle costs set-up time whatever its size. */
    int cells = (out_w_px / 2 + 15) / 16;
    return cells < 8 ? 8 : cells > RND_DISTORTION_CELLS ? RND_DISTORTION_CELLS : cells;
}

void rnd_distortion_source_uv(const struct hmd_profile *p, int eye, int channel, double out_w_eye_px,
                              double out_h_eye_px, const double out_uv[2], double src_uv[2])
{
    struct hmd_eye e = hmd_eye_frustum(p, eye);
    double cu = e.tan_left / (e.tan_left + e.tan_right), cv = e.tan_down / (e.tan_down + e.tan_up);
    double dx = (out_uv[0] - cu) * out_w_eye_px, dy = (out_uv[1] - cv) * out_h_eye_px;
    const double *k = p->distortion_k; /* a, b, c, d */
    double f = 1.0;
    if (k[0] != 0.0 || k[1] != 0.0 || k[2] != 0.0 || k[3] != 0.0) {
        double r = hypot(dx, dy) / (0.5 * out_w_eye_px); /* 1 = the inscribed circle (half the width) */
        f = k[3] + r * (k[2] + r * (k[1] + r * k[0]));
    }
    double s = f * p->aberration[channel < 0 ? 0 : channel > 2 ? 2 : channel];
    src_uv[0] = cu + dx * s / out_w_eye_px;
    src_uv[1] = cv + dy * s / out_h_eye_px;
}

static int rnd_dist_program(struct rnd_distortion *d, struct hl_error *err)
{
    d->program = rnd_gl_program_build(rnd_dist_vs, rnd_dist_fs, "distortion", err);
    if (!d->program)
        return -1;
    d->u_eye = glGetUniformLocation(d->program, "u_eye");
    d->u_source = glGetUniformLocation(d->program, "u_source");
    d->u_lens = glGetUniformLocation(d->program, "u_lens");
    d->u_layers = glGetUniformLocation(d->program, "u_layers");
    d->u_periphery = glGetUniformLocation(d->program, "u_periphery");
    d->u_p_origin = glGetUniformLocation(d->program, "u_p_origin");
    d->u_p_size = glGetUniformLocation(d->program, "u_p_size");
    d->u_p_tex = glGetUniformLocation(d->program, "u_p_tex");
    d->u_tan = glGetUniformLocation(d->program, "u_tan");
    d->u_centre = glGetUniformLocation(d->program, "u_centre");
    d->u_band = glGetUniformLocation(d->program, "u_band");
    return 0;
}

/* The mesh: per eye (N+1)² vertices over its half of the output, clip-space positions built with
 * cglm from the eye's uv, the three channels' source points from rnd_distortion_source_uv (double,
 * then rounded: GL-facing data only is float). Two triangles per cell. */
static int rnd_dist_mesh(struct rnd_distortion *d, const struct hmd_profile *p, struct hl_error *err)
{
    const int N = d->cells, n1 = N + 1;
    size_t verts = (size_t)n1 * n1, floats = 2 * verts * RND_DIST_FLOATS, indices = (size_t)N * N * 6;
    float *v = malloc(floats * sizeof *v);
    uint32_t *ix = malloc(indices * sizeof *ix);
    if (!v || !ix) {
        free(v);
        free(ix);
        return hl_fail(err, "distortion: out of memory for the mesh");
    }
    double eye_w = 0.5 * d->out_w, eye_h = d->out_h;
    float *o = v;
    for (int eye = 0; eye < 2; ++eye) {
        /* eye's [0,1]² → clip space of the whole output: x ∈ [−1,0] or [0,1], y ∈ [−1,1] */
        vec2 ndc_scale = {1.0f, 2.0f}, ndc_offset = {eye == 0 ? -1.0f : 0.0f, -1.0f};
        for (int j = 0; j < n1; ++j)
            for (int i = 0; i < n1; ++i) {
                double uv[2] = {(double)i / N, (double)j / N};
                vec2 pos = {(float)uv[0], (float)uv[1]};
                glm_vec2_mul(pos, ndc_scale, pos);
                glm_vec2_add(pos, ndc_offset, pos);
                glm_vec2_copy(pos, o);
                for (int c = 0; c < 3; ++c) {
                    double src[2];
                    rnd_distortion_source_uv(p, eye, c, eye_w, eye_h, uv, src);
                    o[2 + 2 * c] = (float)src[0];
                    o[3 + 2 * c] = (float)src[1];
                }
                o += RND_DIST_FLOATS;
            }
    }
    uint32_t *q = ix;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            uint32_t a = (uint32_t)(j * n1 + i), b = a + 1, c = a + (uint32_t)n1, e = c + 1;
            *q++ = a, *q++ = b, *q++ = e, *q++ = a, *q++ = e, *q++ = c; /* CCW seen from the viewer */
        }
    glGenVertexArrays(1, &d->vao);
    glGenBuffers(1, &d->vbo);
    glGenBuffers(1, &d->ibo);
    glBindVertexArray(d->vao);
    glBindBuffer(GL_ARRAY_BUFFER, d->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(floats * sizeof *v), v, GL_STATIC_DRAW);
    for (GLuint a = 0; a < 4; ++a) {
        glEnableVertexAttribArray(a);
        glVertexAttribPointer(a, 2, GL_FLOAT, GL_FALSE, RND_DIST_FLOATS * sizeof(float),
                              (const void *)(uintptr_t)(2 * a * sizeof(float)));
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, d->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(indices * sizeof *ix), ix, GL_STATIC_DRAW);
    glBindVertexArray(0);
    free(v);
    free(ix);
    d->index_count = (GLsizei)indices;
    d->vertices_per_eye = (GLsizei)verts;
    return 0;
}

static int rnd_dist_target(struct rnd_distortion *d, struct hl_error *err)
{
    glGenFramebuffers(1, &d->fbo);
    glGenTextures(1, &d->tex);
    glBindTexture(GL_TEXTURE_2D, d->tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, d->out_w, d->out_h);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, d->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, d->tex, 0);
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return status == GL_FRAMEBUFFER_COMPLETE ? 0 : hl_fail(err, "distortion: output %d×%d incomplete", d->out_w, d->out_h);
}

int rnd_distortion_create(struct rnd_renderer *r, const struct hmd_profile *p, int out_w_px, int out_h_px,
                          int offscreen, struct rnd_distortion **out, struct hl_error *err)
{
    *out = NULL;
    if (!r || !p)
        return hl_fail(err, "distortion: no renderer or profile");
    if (out_w_px < 2 || out_h_px < 1 || out_w_px > 16384 || out_h_px > 16384)
        return hl_fail(err, "distortion: output %d×%d out of range", out_w_px, out_h_px);
    if (rnd_renderer_make_current(r) != 0)
        return hl_fail(err, "distortion: cannot make the renderer's context current");
    struct rnd_distortion *d = calloc(1, sizeof *d);
    if (!d)
        return hl_fail(err, "distortion: out of memory");
    d->renderer = r;
    d->out_w = out_w_px, d->out_h = out_h_px, d->offscreen = offscreen;
    d->cells = rnd_distortion_cells(out_w_px);
    const double *k = p->distortion_k;
    d->has_lens = k[0] != 0.0 || k[1] != 0.0 || k[2] != 0.0 || k[3] != 0.0 || p->aberration[0] != 1.0 ||
                  p->aberration[1] != 1.0 || p->aberration[2] != 1.0;
    while (glGetError() != GL_NO_ERROR) {
    }
    if (rnd_dist_program(d, err) != 0 || rnd_dist_mesh(d, p, err) != 0 || (offscreen && rnd_dist_target(d, err) != 0))
        goto fail;
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        hl_fail(err, "distortion: setting up failed: GL error 0x%x", (unsigned)e);
        goto fail;
    }
    *out = d;
    return 0;
fail:
    rnd_distortion_destroy(d);
    return -1;
}

void rnd_distortion_destroy(struct rnd_distortion *d)
{
    if (!d)
        return;
    if (rnd_renderer_make_current(d->renderer) == 0) {
        glDeleteProgram(d->program);
        glDeleteVertexArrays(1, &d->vao);
        glDeleteBuffers(1, &d->vbo);
        glDeleteBuffers(1, &d->ibo);
        glDeleteFramebuffers(1, &d->fbo);
        glDeleteTextures(1, &d->tex);
    }
    free(d);
}

int rnd_distortion_has_lens(const struct rnd_distortion *d) { return d ? d->has_lens : 0; }

int rnd_distortion_draw(struct rnd_distortion *d, int finish, struct hl_error *err)
{
    if (!d || rnd_renderer_make_current(d->renderer) != 0)
        return hl_fail(err, "distortion: no pass or no context");
    glBindFramebuffer(GL_FRAMEBUFFER, d->offscreen ? d->fbo : 0);
    glViewport(0, 0, d->out_w, d->out_h);
    GLboolean depth = glIsEnabled(GL_DEPTH_TEST), cull = glIsEnabled(GL_CULL_FACE);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glUseProgram(d->program);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, rnd_renderer_color_texture(d->renderer));
    glUniform1i(d->u_source, 0);
    glUniform1i(d->u_lens, d->has_lens);
    struct rnd_layer_view lv;
    int layered = rnd_layers_last(d->renderer, &lv);
    glUniform1i(d->u_layers, layered ? (lv.global ? 2 : 1) : 0);
    glUniform1i(d->u_periphery, 1);
    if (layered) {
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, lv.periphery_tex);
        glActiveTexture(GL_TEXTURE0);
        glUniform2f(d->u_p_size, (float)lv.periphery_w, (float)lv.periphery_h);
        glUniform2f(d->u_p_tex, (float)lv.tex_w, (float)lv.tex_h);
        glUniform2f(d->u_band, lv.inner_rad, lv.outer_rad);
    }
    glBindVertexArray(d->vao);
    for (int eye = 0; eye < 2; ++eye) {
        glUniform1f(d->u_eye, (float)eye);
        if (layered) {
            glUniform2f(d->u_p_origin, (float)(eye * lv.periphery_w), 0.0f);
            glUniform4fv(d->u_tan, 1, lv.tan[eye]);
            glUniform3fv(d->u_centre, 1, lv.centre[eye]);
        }
        glDrawElementsBaseVertex(GL_TRIANGLES, d->index_count, GL_UNSIGNED_INT, NULL, eye * d->vertices_per_eye);
    }
    glBindVertexArray(0);
    if (layered) {
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, 0);
        glActiveTexture(GL_TEXTURE0);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    glClearColor(0.1f, 0.1f, 0.12f, 1.0f); /* the renderer's clear colour, restored with its state */
    if (depth)
        glEnable(GL_DEPTH_TEST);
    if (cull)
        glEnable(GL_CULL_FACE);
    if (finish)
        glFinish();
    GLenum e = glGetError();
    return e == GL_NO_ERROR ? 0 : hl_fail(err, "distortion: drawing failed: GL error 0x%x", (unsigned)e);
}

int rnd_distortion_read_rgba(struct rnd_distortion *d, uint8_t *rgba, struct hl_error *err)
{
    if (!d || !d->offscreen || !rgba)
        return hl_fail(err, "distortion: not an offscreen pass, or no buffer");
    if (rnd_renderer_make_current(d->renderer) != 0)
        return hl_fail(err, "distortion: cannot make the context current");
    glBindFramebuffer(GL_READ_FRAMEBUFFER, d->fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, d->out_w, d->out_h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR)
        return hl_fail(err, "distortion: glReadPixels failed: GL error 0x%x", (unsigned)e);
    rnd_flip_rows(rgba, d->out_w, d->out_h);
    return 0;
}
