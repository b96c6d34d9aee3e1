/* render/window.h: the live session's output — a GLFW window (desk or fullscreen on a headset's
 * output), the monitors GLFW sees, and the lens distortion pass with chromatic aberration. Part of
 * the render/render.h umbrella. */
#ifndef HMDLOD_RENDER_WINDOW_H
#define HMDLOD_RENDER_WINDOW_H

#include "base/base.h"
#include "hmd/hmd.h"

struct rnd_renderer;

/* ---- monitors -------------------------------------------------------------------------------- */
struct rnd_monitor_info {
    char name[128];
    int width_px, height_px;
    double refresh_hz;  /* 0 when the server does not say (Xvfb) */
    int x_px, y_px;     /* position on the virtual desktop */
    int width_mm, height_mm;
    int looks_like_headset; /* mode is a built-in profile's two eyes, or the name is a headset's */
};
/* Lists up to max monitors (needs a display: DISPLAY under X). Returns how many, or −1 with err. */
int rnd_monitor_list(struct rnd_monitor_info *out, int max, struct hl_error *err);

/* ---- window ---------------------------------------------------------------------------------- */
struct rnd_window;
struct rnd_window_params {
    const char *title;
    int width_px, height_px; /* windowed size; fullscreen takes the monitor's mode */
    int monitor;             /* −1: a window on the desktop; else fullscreen on that monitor index */
};
/* Opens the window with an OpenGL 4.5 core context and makes it current. */
int rnd_window_create(const struct rnd_window_params *p, struct rnd_window **out, struct hl_error *err);
void rnd_window_destroy(struct rnd_window *w); /* NULL is fine */
int rnd_window_make_current(struct rnd_window *w);
void rnd_window_size(const struct rnd_window *w, int *width_px, int *height_px); /* framebuffer pixels */
double rnd_window_refresh_hz(const struct rnd_window *w); /* its monitor's (or the primary's); 0 unknown */
void rnd_window_poll(struct rnd_window *w);               /* events: keys, mouse, close */
int rnd_window_should_close(const struct rnd_window *w);  /* the window's close button */
void rnd_window_swap(struct rnd_window *w);
void rnd_window_set_swap_interval(struct rnd_window *w, int interval);
void rnd_window_set_title(struct rnd_window *w, const char *title);
/* Keys pressed since the last call, one at a time: letters and digits as upper-case ASCII, '+', '-',
 * ' ', and the codes below. Returns 1 with *key, 0 when none is queued. */
enum { RND_KEY_ESCAPE = 27, RND_KEY_UP = 256, RND_KEY_DOWN, RND_KEY_LEFT, RND_KEY_RIGHT };
int rnd_window_next_key(struct rnd_window *w, int *key);
/* Pointer motion while the left button is held, since the last call (mouse look). */
void rnd_window_mouse_delta(struct rnd_window *w, double *dx_px, double *dy_px);
/* Reads the back buffer (what was drawn and is about to be swapped): width·height·4 bytes, top row first. */
int rnd_window_read_rgba(struct rnd_window *w, uint8_t *rgba, struct hl_error *err);

/* A renderer drawing in the window's context (instead of rnd_renderer_create's headless EGL one). */
int rnd_renderer_create_in_window(struct rnd_window *window, int eye_width_px, int eye_height_px,
                                  struct rnd_renderer **out, struct hl_error *err);
int rnd_renderer_make_current(const struct rnd_renderer *r);

/* ---- distortion pass ------------------------------------------------------------------------- */
/* Per eye, a mesh of up to RND_DISTORTION_CELLS² cells (one per 16 output pixels, at least 8², so 64²
 * at the Vive's 1080 pixels per eye: rnd_distortion_cells) over the eye's half of the output; each vertex has
 * one source position per colour channel (chromatic aberration), as Monado and OpenHMD build it.
 * PanoTools model (DEVICES.md §1b): r is the output point's distance from the lens centre with 1 =
 * half the eye's width; the source point is r·(d + c·r + b·r² + a·r³) out along the same direction,
 * times the channel's aberration scale. The lens centre is where the eye's optical axis meets the
 * image (its frustum's tangents). k all zero: no distortion (source = output), aberration kept. */
enum { RND_DISTORTION_CELLS = 64 };
int rnd_distortion_cells(int out_w_px); /* cells per side of an eye's mesh for a 2-eye output this wide */
struct rnd_distortion;
/* out_w×out_h: the output (both eyes side by side). offscreen: draw into its own texture (tests,
 * bench) instead of the current context's window. The renderer's context must be current. */
int rnd_distortion_create(struct rnd_renderer *r, const struct hmd_profile *p, int out_w_px, int out_h_px,
                          int offscreen, struct rnd_distortion **out, struct hl_error *err);
void rnd_distortion_destroy(struct rnd_distortion *d);
int rnd_distortion_has_lens(const struct rnd_distortion *d); /* 0: the profile had no coefficients */
/* Draws both eyes from the renderer's FBO. finish: wait for the GPU, so the caller's timer measures it.
 * When the renderer's last draw was layered and not composited (rnd_renderer_draw_layers without
 * rnd_renderer_composite_layers), this pass composites the layers as it samples (render/layers.h). */
int rnd_distortion_draw(struct rnd_distortion *d, int finish, struct hl_error *err);
/* Offscreen only: the output, out_w·out_h·4 bytes, top row first. */
int rnd_distortion_read_rgba(struct rnd_distortion *d, uint8_t *rgba, struct hl_error *err);
/* The mesh's source point of one channel (0 r, 1 g, 2 b) for an output point, both in the eye's
 * [0,1]² (x right, y up), for tests and docs: the same double-precision function the mesh uses. */
void rnd_distortion_source_uv(const struct hmd_profile *p, int eye, int channel, double out_w_eye_px,
                              double out_h_eye_px, const double out_uv[2], double src_uv[2]);

#endif
