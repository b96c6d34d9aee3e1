/* render: drawing and its cost. Headless EGL (surfaceless Mesa) OpenGL 4.5 core, one FBO holding
 * both eyes side by side, the scene's meshes (scene/) in GPU buffers, PNG capture. Prefix rnd_.
 * Never decides what to draw: callers pass the list. */
#ifndef HMDLOD_RENDER_H
#define HMDLOD_RENDER_H

#include "base/base.h"
#include "hmd/hmd.h"
#include "scene/scene.h"

/* ---- renderer ------------------------------------------------------------------------------- */
struct rnd_renderer;

/* Creates a surfaceless EGL context (GL 4.5 core) and an RGBA8+depth FBO of 2·eye_width × height. */
int rnd_renderer_create(int eye_width_px, int eye_height_px, struct rnd_renderer **out, struct hl_error *err);
void rnd_renderer_destroy(struct rnd_renderer *r);
const char *rnd_renderer_name(const struct rnd_renderer *r); /* GL_RENDERER, e.g. "llvmpipe (LLVM 15…)" */
int rnd_renderer_upload_scene(struct rnd_renderer *r, const struct scn_scene *scene, struct hl_error *err);

/* One eye: where it is (world, double) and where it looks (eye-to-world rotation; the eye looks
 * down −Z, +Y up), plus its projection (hmd_eye_projection). */
struct rnd_eye_view {
    double position_m[3];
    hl_quatd orientation;
    double projection[16];
};

struct rnd_draw_stats {
    uint64_t triangles_per_eye[2]; /* every layer's, for a foveated frame */
    uint32_t draw_calls;           /* instanced draws: one per batch of a chain, level and colour */
    /* A foveated frame (rnd_renderer_draw_layers; 0 for a plain one): triangles each layer drew (both
     * eyes), and the pixels it shaded: the insets' rectangles, the peripheries. */
    uint64_t inset_triangles, periphery_triangles;
    double inset_px, periphery_px;
};

/* Clears and draws the listed instances (index[k], at LOD lod[k]; lod 255 = skip) into both eyes:
 * left eye in the left half, right eye in the right half. Model-view matrices are built relative to
 * the eye in double, so far-from-origin scenes keep precision. Waits for the GPU (glFinish) so the
 * caller's timer measures the draw. */
int rnd_renderer_draw_stereo(struct rnd_renderer *r, const struct scn_scene *scene,
                             const struct rnd_eye_view views[2], const uint32_t *index, const uint8_t *lod,
                             size_t count, struct rnd_draw_stats *stats);

/* ---- foveated layers (render/layers.h) ---- */
#include "render/layers.h"
/* Draws the listed instances in layers (render/layers.h): entry k into the layers its mask[k] names
 * (RND_LAYER_INSET, RND_LAYER_PERIPHERY; mask NULL: both) at level lod[k] in the insets and
 * periphery_lod[k] in the peripheries (NULL: lod; a coarser level where the periphery's resolution
 * cannot show the difference) — the insets into the FBO, the peripheries into the layers' own
 * framebuffer (made on the first foveated frame). Waits for the GPU like
 * rnd_renderer_draw_stereo. layers NULL or a scale of 1: rnd_renderer_draw_stereo (masks ignored).
 * −1 on a bad list or layer setting (nothing drawn) or a GL error. */
int rnd_renderer_draw_layers(struct rnd_renderer *r, const struct scn_scene *scene, const struct rnd_eye_view views[2],
                             const struct rnd_layers *layers, const uint32_t *index, const uint8_t *lod,
                             const uint8_t *periphery_lod, const uint8_t *mask, size_t count,
                             struct rnd_draw_stats *stats);
/* The insets alone — rnd_renderer_draw_layers' first step, each eye's full-resolution inset under its
 * scissor into the FBO, every listed instance at lod[k] — and glFinish: the layer's redrawn geometry
 * and pixels as `calibrate` times them (render/cost.h). Nothing is left to composite. layers' scale
 * must be below 1 and its radius above 0; −1 otherwise, on a bad list, or on a GL error. */
int rnd_renderer_draw_inset(struct rnd_renderer *r, const struct scn_scene *scene, const struct rnd_eye_view views[2],
                            const struct rnd_layers *layers, const uint32_t *index, const uint8_t *lod, size_t count,
                            struct rnd_draw_stats *stats);
/* Composites the last rnd_renderer_draw_layers into the FBO that rnd_renderer_read_rgba, the mean
 * luminance and the distortion pass read, and waits for it; a no-op (0) after a plain frame. Apart
 * from the draw because it is the compositor's work: a headset runtime composites submitted layers
 * in its distortion pass, which a plain frame also pays for (docs/foveation.md "What a frame pays").
 * *composite_px (may be NULL): the pixels it shaded. 0, or −1 on a GL error. */
int rnd_renderer_composite_layers(struct rnd_renderer *r, double *composite_px);

/* Reads the FBO into rgba (2·eye_width·height·4 bytes), rows top to bottom. */
int rnd_renderer_read_rgba(struct rnd_renderer *r, uint8_t *rgba, struct hl_error *err);
void rnd_renderer_size(const struct rnd_renderer *r, int *width_px, int *height_px);

/* The mean relative luminance (0…1) of the whole FBO, both eyes, as the last draw left it — the
 * adapting luminance a contrast sensitivity function needs is the display's peak luminance
 * (hmd_profile.peak_luminance_cdm2) times this. Pixels are sRGB-encoded 8-bit, decoded with the
 * module's table and weighted Y = 0.2126 R + 0.7152 G + 0.0722 B (Rec. 709 / sRGB primaries).
 * Cheap enough per frame: one GL_LINEAR glBlitFramebuffer down to 64×32 (32×32 per eye; smaller
 * framebuffers are copied as they are) and a read-back of that into a buffer the renderer holds,
 * made on first use; nothing is allocated per call. An ESTIMATE, not the exact mean: a linear
 * down-blit samples only ~4 source pixels per destination pixel (a subsample, not a box average),
 * and it averages encoded values before decoding (which reads a little dark where bright and dark
 * mix). Against the exact mean of a full read-back (tests/test_render.c: the built-in scenes at
 * 1080×1200 per eye, six head directions, llvmpipe) it was off by at most 0.00083 absolute, 5.6 %
 * relative, mostly low (those frames are dark: means 0.012–0.051); over three runs it took
 * 0.06–0.3 ms a call there, against 0.65–1.8 ms for the full read-back alone. Reads the FBO the
 * eyes were drawn into, not a window's distorted output. −1 with a message on a GL failure. */
int rnd_renderer_mean_luminance(struct rnd_renderer *r, double *mean_relative_out, struct hl_error *err);

/* Writes an 8-bit RGBA PNG atomically (temporary file, then rename): no half-written PNG is left. */
int rnd_png_write(const char *path, const uint8_t *rgba, int width_px, int height_px, struct hl_error *err);

/* ---- live output: window, monitors, distortion pass ------------------------------------------ */
#include "render/window.h"

/* ---- offline spatial-frequency analysis (Reddy 1998 §3.2–3.3) -------------------------------- */
#include "render/analyze.h"

/* ---- image error against a reference frame (PSNR, SSIM, foveated SSIM) ------------------ */
#include "render/image_error.h"

/* ---- FLIP, the error seen flipping between a frame and its reference (LDR-FLIP, HPG 2020) ---- */
#include "render/flip.h"

/* ---- the machine cost model and its profile (PAPERS.md §2, §5) ------------------------------ */
#include "render/cost.h"

#endif
