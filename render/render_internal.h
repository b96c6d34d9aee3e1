/* render internals: the headless EGL context behind the renderer. Not public: other modules see
 * only render.h. */
#ifndef HMDLOD_RENDER_INTERNAL_H
#define HMDLOD_RENDER_INTERNAL_H

#include "render/render.h"

/* The 256 sRGB byte values decoded to linear (IEC 61966-2-1), computed once (analyze_image.c):
 * the analysis's CIELUV and contrast spectrum, and FLIP's colour pipeline (flip.c) read them. */
const double *rnd_srgb_decode_table(void);

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

/* ---- shared by the window and the distortion pass -------------------------------------------- */
void rnd_flip_rows(uint8_t *rgba, int width_px, int height_px); /* bottom-up GL rows to top-down */
unsigned rnd_renderer_color_texture(const struct rnd_renderer *r); /* the FBO's colour (GL_TEXTURE_2D) */

#endif
