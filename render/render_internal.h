/* render internals: the headless EGL context behind the renderer. Not public: other modules see
 * only render.h. */
#ifndef HMDLOD_RENDER_INTERNAL_H
#define HMDLOD_RENDER_INTERNAL_H

#include "render/render.h"

/* The 256 sRGB byte values decoded to linear (IEC 61966-2-1), computed once (analyze_image.c):
 * the analysis's CIELUV and contrast spectrum, and FLIP's colour pipeline (flip.c) read them. */
const double *rnd_srgb_decode_table(void);
/* One sRGB-encoded value in [0, 1] decoded to linear (the same EOTF). */
double rnd_srgb_decode(double c);

/* ---- headless EGL (egl_context.c) --------------------------------------------------------------
 * Opaque handles (EGLDisplay, EGLContext) so that only egl_context.c needs the EGL headers. */
struct rnd_egl {
    void *display, *context;
};
/* Surfaceless Mesa display (else EGL_EXT_platform_device), GL 4.5 core context with no config
 * and no surface, made current. On failure nothing is left open. */
int rnd_egl_create(struct rnd_egl *e, struct hl_error *err);
int rnd_egl_make_current(const struct rnd_egl *e); /* no-op when already current */
void rnd_egl_destroy(struct rnd_egl *e);
/* Switching between a headless EGL context and a window's (egl_context.c, window.c): the owner of
 * the current context, and each side's way to let go of its own before the other makes current. */
extern const void *rnd_current_owner;
void rnd_egl_release_current(void);
void rnd_window_release_current(void);
/* Under AddressSanitizer, keeps Mesa's software driver loaded until exit so LeakSanitizer can
 * attribute its globals (gl_driver_pin.c, PLATFORM.md §4); a no-op otherwise. Called before the
 * first EGL display or GLFW start. */
void rnd_gl_driver_pin(void);

/* ---- one view's draw list (draw_list.c) ------------------------------------------------------ */
struct rnd_draw_batch {
    uint32_t entry, count; /* its members: entries[entry …], nearest first */
    uint32_t slot;         /* its first transform in transforms */
    float depth2_m2;       /* its nearest member's */
};
struct rnd_albedo {
    float srgb[3];            /* the instance's colour these were made from (NaN: none yet) */
    float linear[3], root[3]; /* decoded (sRGB EOTF), and that to the power 1/2.4 */
};
struct rnd_draw_entry {
    float depth2_m2; /* squared distance from the eye to the instance's origin */
    uint32_t k;      /* the entry in the caller's draw list */
    uint32_t chain;  /* the batch key: chain, level and colour (the shader's albedo is per draw) */
    uint8_t level;
    float color[3];
};
/* The drawn entries front to back and in their batches, the batches, their transforms, and each
 * instance's albedo as the shader takes it, for up to cap entries (every instance and impostor of the
 * uploaded scene). */
struct rnd_draw_list {
    struct rnd_draw_entry *entries;
    struct rnd_draw_batch *batches;
    float *transforms; /* 16 a drawn entry, column-major, in batch order */
    struct rnd_albedo *albedo;
    size_t cap;
};
/* Room for `entries` instances, and every albedo to be remade: 0, or −1 out of memory (what was held
 * stays held). */
int rnd_draw_list_reserve(struct rnd_draw_list *l, size_t entries);
void rnd_draw_list_free(struct rnd_draw_list *l);

/* ---- the renderer (renderer.c); layers.c draws through it too ---------------------------------- */
/* The down-blit target of rnd_renderer_mean_luminance: 32×32 per eye, both eyes side by side, so
 * each destination pixel stands for an equal share of either eye (smaller framebuffers use their
 * own size and the copy is exact). */
enum { RND_LUM_W = 64, RND_LUM_H = 32 };

struct rnd_renderer {
    struct rnd_egl egl;
    struct rnd_window *window; /* set: drawing in that window's context instead of a headless one */
    int eye_w, eye_h;
    unsigned fbo, color_tex, depth_rb; /* colour is a texture: the distortion pass samples it */
    unsigned program, vao, vbo, ibo;
    int u_proj, u_albedo, u_albedo_root, u_light;
    unsigned instance_vbo; /* the per-instance transforms of one view's draws */
    uint32_t scene_vertices, scene_indices; /* what is uploaded, to catch a mismatched scene */
    int has_scene;
    char name[128];
    /* rnd_renderer_mean_luminance's down-blit target, made on first use; the read-back buffer lives
     * here so that a per-frame call allocates nothing. */
    unsigned lum_fbo, lum_rb;
    int lum_w, lum_h;
    uint8_t lum_rgba[RND_LUM_W * RND_LUM_H * 4];
    struct rnd_layer_targets *layers; /* the foveated layers' framebuffers and composite (layers.c), made on first use */
    struct rnd_ring_target *rings;    /* the contrast read-back's target and buffers (ring_contrast.c), on first use */
    struct rnd_draw_list list; /* rnd_draw_view's arrays (draw_list.c), sized at upload */
};

/* Draws the listed instances with one view into the current viewport (the caller has bound the FBO,
 * program and VAO): entries whose mask[k] & layer_bit is 0 are skipped (mask NULL: none). Instances
 * sharing a chain, level and colour go in one instanced draw, batches nearest first. Returns the
 * triangles drawn and adds the draw calls (one per batch) to *calls (draw_list.c). */
uint64_t rnd_draw_view(struct rnd_renderer *r, const struct scn_scene *scene, const struct rnd_eye_view *v,
                       const uint32_t *index, const uint8_t *lod, const uint8_t *mask, unsigned layer_bit,
                       size_t count, uint32_t *calls);
/* Checks a draw list against the uploaded scene (renderer.c): 0, or −1 for a bad entry. */
int rnd_check_draw(const struct rnd_renderer *r, const struct scn_scene *scene, const uint32_t *index,
                   const uint8_t *lod, size_t count);
/* The renderer's context is current (a no-op when it already is): 0 or −1 (renderer.c). */
int rnd_renderer_current(const struct rnd_renderer *r);
/* Frees the layers' targets (layers.c), and their GL objects when delete_gl (the renderer's context
 * is current). NULL: nothing. */
void rnd_layer_targets_destroy(struct rnd_layer_targets *t, int delete_gl);

/* The last draw's layers, for the passes that composite them themselves (layers.c): the distortion
 * pass and the contrast read-back. 1 with *out filled when the last draw was layered and its
 * composite has not been drawn into the FBO (rnd_renderer_composite_layers); 0 otherwise. */
struct rnd_layer_view {
    int global;                  /* no inset: the periphery is the whole eye */
    unsigned periphery_tex;      /* both eyes' peripheries side by side from its corner */
    int periphery_w, periphery_h, tex_w, tex_h; /* one eye's periphery; the texture */
    float tan[2][4];             /* per eye: left, right, up, down */
    float centre[2][3];          /* per eye: the inset's centre, unit, eye frame */
    float inner_rad, outer_rad;  /* the blend band, radians from the centre */
};
int rnd_layers_last(const struct rnd_renderer *r, struct rnd_layer_view *out);
/* A plain draw: the FBO no longer holds layers (layers.c; NULL: nothing). */
void rnd_layers_forget(struct rnd_layer_targets *t);
/* Draws the last layered frame's composite into the framebuffer fbo of eye_w × eye_h per eye (both
 * eyes side by side), as rnd_renderer_composite_layers does into the renderer's own (layers.c);
 * the target holds the insets (or a reduced copy of them) already. */
void rnd_layers_composite_into(struct rnd_renderer *r, unsigned fbo, int eye_w, int eye_h);

/* Frees the contrast read-back's target (ring_contrast.c), its GL objects when delete_gl. */
void rnd_ring_target_destroy(struct rnd_ring_target *t, int delete_gl);

/* ---- single-view draws for the offline analysis (renderer.c, used by analyze.c) ----------------
 * rect_px = x, y (from the bottom-left, GL convention), width, height inside the FBO. */
/* Clears the rectangle and draws one instance of the uploaded scene at one LOD into it with `view`
 * (same shader and light as the stereo pass). Does not wait: the read-back does. */
int rnd_renderer_draw_rect(struct rnd_renderer *r, const struct scn_scene *scene, const struct rnd_eye_view *view,
                           uint32_t instance, uint8_t lod, const int rect_px[4]);
/* Reads the rectangle into rgba (width·height·4 bytes), rows top to bottom. */
int rnd_renderer_read_rect(struct rnd_renderer *r, const int rect_px[4], uint8_t *rgba, struct hl_error *err);

/* ---- GLSL programs (gl_program.c) ------------------------------------------------------------ */
/* Compiles and links a vertex and a fragment shader in the current context; the program's name, or 0
 * with "who: … shader does not compile / link: log" in err. */
unsigned rnd_gl_program_build(const char *vertex_src, const char *fragment_src, const char *who, struct hl_error *err);

/* ---- GL objects made alike in several places (renderer.c) -------------------------------------- */
/* An RGBA8 2D texture of w × h, linear filtering, clamped at its edges: what the passes sample. */
unsigned rnd_gl_color_texture(int w, int h);
/* A framebuffer to draw into: a colour texture (rnd_gl_color_texture) and a 24-bit depth renderbuffer,
 * w × h, left bound to GL_FRAMEBUFFER; its completeness status. The renderer's eyes and the layers'
 * peripheries. */
unsigned rnd_gl_draw_target(int w, int h, unsigned *fbo_out, unsigned *color_tex_out, unsigned *depth_rb_out);
/* A framebuffer with one RGBA8 renderbuffer of w × h (*rb_out), left bound to GL_FRAMEBUFFER; its
 * completeness status (GL_FRAMEBUFFER_COMPLETE when usable). For small read-back targets. */
unsigned rnd_gl_readback_target(int w, int h, unsigned *fbo_out, unsigned *rb_out);

/* ---- shared by the window and the distortion pass -------------------------------------------- */
void rnd_flip_rows(uint8_t *rgba, int width_px, int height_px); /* bottom-up GL rows to top-down */
unsigned rnd_renderer_color_texture(const struct rnd_renderer *r); /* the FBO's colour (GL_TEXTURE_2D) */

#endif
