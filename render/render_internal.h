/* render internals: the headless EGL context behind the renderer. Not public: other modules see
 * only render.h. */
#ifndef HMDLOD_RENDER_INTERNAL_H
#define HMDLOD_RENDER_INTERNAL_H

#include "render/render.h"

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

#endif
