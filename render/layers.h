/* render/layers.h: foveated layers (Guenter et al. 2012, two of their three; PAPERS.md §6). Per eye a
 * full-resolution INSET around a centre direction (the lens centre, or the measured gaze) and the
 * PERIPHERY at a linear scale s of the eye's resolution, composited with a smooth radial blend.
 *
 * How a foveated frame is drawn (rnd_renderer_draw_layers):
 *   1. inset — into the renderer's own framebuffer, with the eye's own viewport and projection and a
 *      scissor on the inset's bounding rectangle (the blend band's outer edge): inside it every pixel
 *      is the full-resolution render's, bit for bit, because the rasterisation is the same and only
 *      the scissor differs (a sub-frustum projection would move vertices by float rounding);
 *   2. periphery — into a second framebuffer at s·width × s·height per eye, same projection;
 *   3. composite — the periphery, bilinearly upsampled, drawn over the eye as a mesh that leaves out
 *      the inset's inner disc: across the blend band (inner radius → outer radius, in degrees from
 *      the centre) its weight rises as smoothstep, beyond it the periphery replaces what is there.
 *      Inside the inner disc nothing is drawn, so the inset's pixels stay as they are.
 * The caller says which objects each layer draws (a mask per draw entry): the frame culls each
 * layer against its part of the view (DESIGN.md: render never decides what to draw).
 * s = 1 draws the plain stereo frame (rnd_renderer_draw_stereo): one layer. An inset radius of 0
 * draws the periphery alone, upsampled: global dynamic resolution. Part of render/render.h. */
#ifndef HMDLOD_RENDER_LAYERS_H
#define HMDLOD_RENDER_LAYERS_H

#include "base/base.h"
#include "hmd/hmd.h"

/* Draw-entry mask bits: which layers draw the entry (both eyes). */
enum { RND_LAYER_INSET = 1, RND_LAYER_PERIPHERY = 2, RND_LAYER_BOTH = 3 };

/* The periphery's scale range, and the widest inset: the outer edge (radius + blend band) plus the
 * centre's angle from the eye's axis must stay under RND_LAYER_MAX_CONE_DEG so the band projects
 * onto the image plane; an inset that would reach past it covers the eye (rnd_layer_plan.covers). */
#define RND_LAYER_SCALE_MIN 0.125
#define RND_LAYER_MAX_CONE_DEG 80.0

struct rnd_layers {
    double periphery_scale;  /* s in [RND_LAYER_SCALE_MIN, 1]; 1 = no layers (the plain frame) */
    double inset_radius_deg; /* the inner disc, full resolution, ≥ 0; 0 = no inset (global scale) */
    double blend_deg;        /* the band beyond it where the periphery fades in, > 0 */
    hl_vec3d centre_eye[2];  /* per eye: the inset's centre, a direction in the eye frame (−Z ahead) */
    struct hmd_eye eyes[2];  /* per eye: the frustum's four tangents (offset_x_m unused) */
};

/* What a layer setting draws, per eye, in pixels of that eye's image (x from the left, y from the
 * bottom as GL counts): the inset's rectangle (0 wide when there is none), the periphery's size, and
 * covers = 1 when the inset's outer edge would not project (RND_LAYER_MAX_CONE_DEG) — that eye is
 * then drawn as one full-resolution inset. */
struct rnd_layer_plan {
    int inset_rect_px[2][4];  /* x, y, width, height */
    int periphery_px[2];      /* width, height (the same for both eyes) */
    int covers[2];
    double inset_px, periphery_px_total; /* pixels the two layers shade, both eyes */
};

/* The plan for eye images of eye_w × eye_h pixels. 0, or −1 when the layer setting is out of range
 * (scale outside [RND_LAYER_SCALE_MIN, 1], negative or non-finite radius, blend ≤ 0, a zero centre,
 * a non-positive tangent). Pure: no GL. */
int rnd_layer_plan_make(const struct rnd_layers *l, int eye_w_px, int eye_h_px, struct rnd_layer_plan *out);

/* The tangents {left, right, down, up} of the part of an eye image that rect (x, y, width, height in
 * pixels, y from the bottom) covers, for an eye of those tangents and width_px × height_px: the
 * rectangle as an image of its own, for coverage estimates within an inset. Pure. */
void rnd_layer_rect_tangents(double tan_left, double tan_right, double tan_down, double tan_up, double width_px,
                             double height_px, const int rect[4], double out[4]);

/* ---- what the content needs (ring_contrast.c) ------------------------------------------------
 * The band-limited contrast (Peli 1990) of the last frame by eccentricity: the FBO reduced to
 * 1/RND_RING_DOWNSAMPLE of its size per axis by a linear down-blit (one for both eyes when the
 * reduction is exact; each reduced pixel is then the mean of the 2×2 pixels at its centre, a
 * sample rather than a box, so an edge keeps its full contrast), read back, and for each
 * pixel its finest band over the local mean, |Y − blur(Y)| / blur(Y) (Y linear luminance, blur 3×3
 * binomial); the largest in each RND_CONTRAST_RING_DEG-wide ring of angle from the eye's gaze (the
 * last ring takes everything beyond). The measured band lies at a quarter to a half of the reduced
 * image's Nyquist frequency — below the frequencies a periphery at s ≥ 0.25 loses — so using it for
 * those assumes band contrast does not grow with frequency above it: true of the edges and shading
 * ramps these renders hold (a step's band contrast is the same in every band) and of natural images
 * (amplitude ∝ 1/f); a fine texture seen only above the band would be missed (docs/foveation.md).
 * Tursun et al. 2019 likewise predict what a region needs from a low-resolution version of the
 * frame. When the last draw was layered and not composited into the FBO (the distortion pass
 * composites it), the layers are composited at the reduced size first. Each reduced pixel's ring is
 * kept in a map made again only when a gaze or frustum changes (under head and vor: once). Allocates
 * its target and buffers on first use (warm-up), nothing after. */
enum { RND_RING_DOWNSAMPLE = 8, RND_CONTRAST_RINGS = 18 };
#define RND_CONTRAST_RING_DEG 5.0
struct rnd_ring_contrast {
    double max_contrast[RND_CONTRAST_RINGS]; /* ring k: [5k, 5k + 5) degrees from the gaze */
    uint32_t pixels[RND_CONTRAST_RINGS];     /* reduced-image pixels that fell in it (0: none seen) */
    double mean_relative_luminance;          /* the reduced image's mean Y (0…1), both eyes: what
                                              * rnd_renderer_mean_luminance estimates, from a box
                                              * filter of every pixel rather than a subsample */
    int valid;
};
struct rnd_renderer;
struct rnd_eye_gaze;
/* gaze: two, per eye its frustum's tangents and gaze direction in the eye frame (render/image_error.h). */
int rnd_renderer_ring_contrast(struct rnd_renderer *r, const struct rnd_eye_gaze *gaze,
                               struct rnd_ring_contrast *out, struct hl_error *err);

#endif
