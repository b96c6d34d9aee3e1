/* render/cost.h: measuring the machine's cost — timed stereo frames over a grid of triangle counts,
 * screen coverage and draw counts (`hmdlod calibrate`), recorded as plain numbers per frame and
 * object. The fits, their accuracy and the cost profile are replay's (frame/cost.h), which joins
 * this measurement with acuity's coverage estimate and lod's cost arithmetic (DESIGN.md: render
 * depends on scene, hmd and base only). Included by render/render.h. */
#ifndef HMDLOD_RENDER_COST_H
#define HMDLOD_RENDER_COST_H

#include "base/base.h"
#include "hmd/hmd.h"

/* ---- samples ----------------------------------------------------------------------------------
 * One timed frame holds object_count objects, objects[first_object …]. Each object's counts are for
 * both eyes, in the cost model's units (lod.h): triangles and vertices drawn, draw calls, and its
 * world bounding sphere; pixels_px is left 0 here and filled by replay (frm_cost_calibrate) with
 * acu_compute_pixels' estimate — not a rasterised count: the replay predicts with the same
 * estimate. measured_ms is the median over repeats of draw + glFinish. */
struct rnd_cost_object {
    double triangles, vertices, pixels_px, draws;
    double center_m[3], radius_m;
    double fill; /* the level's fill of its bounding disc (scn_lod_fill): pixels_px is the disc's times this */
    double inside_share; /* in an inset grid the share of its image within the inset's rectangles (filled
                          * by replay with pixels_px); 1 otherwise */
};
struct rnd_cost_frame {
    double measured_ms;
    uint32_t first_object, object_count;
};

/* Deterministic split of `count` items into a training part (the first *train_count entries of
 * order) and a held-out part (the rest): a seeded Fisher–Yates shuffle, train share 0.75 rounded,
 * at least one in each when count ≥ 2. order holds count entries. */
void rnd_cost_split(size_t count, uint64_t seed, uint32_t *order, size_t *train_count);


/* ---- measurement (cost.c) ---------------------------------------------------------------------- */
enum { RND_COST_GRID_MAX = 8, RND_COST_EMPTY_EVERY = 8 };
struct rnd_cost_grid {
    int families;                            /* 1: the field's bumpy sphere; 2: also the auditorium's chair */
    int levels;                              /* LOD indices used (the field: 0 = 3906 … 3 = 78 triangles) */
    uint32_t level[RND_COST_GRID_MAX];
    int coverages;                           /* total projected share of each eye's image */
    double coverage[RND_COST_GRID_MAX];
    int counts;                              /* objects per frame (draws = 2 · objects) */
    uint32_t objects[RND_COST_GRID_MAX];
    int repeats;                             /* timed frames per grid point; the median is kept */
    int eye_width_px, eye_height_px;         /* per eye, after the render scale */
    double render_scale;
    double periphery_scale;                  /* 1: plain frames; < 1: each frame drawn as a foveated
                                              * periphery of that linear scale covering the whole eye
                                              * (rnd_renderer_draw_layers, inset radius 0) — the
                                              * periphery layer's cost (frame/layers.h) */
    double inset_radius_deg, inset_blend_deg; /* radius > 0 (scale then 1): each frame drawn as the
                                              * foveal inset alone, that radius and blend band around
                                              * the lens centre, at full resolution under its scissor
                                              * (rnd_renderer_draw_inset) — the inset layer's redrawn
                                              * geometry; the objects are placed over the whole eye
                                              * as for the plain frames: some inside the scissor,
                                              * some across its edge, some outside it */
    char display[HMD_NAME_MAX];
};
/* The default grid (2 families × 4 levels × 5 coverages × 5 counts, 7 repeats) or --quick's
 * (2 × 2 × 2 × 3, 3 repeats), plain frames (periphery_scale 1). */
void rnd_cost_grid_default(struct rnd_cost_grid *g, int quick);

/* One eye of the measurement, as acuity's coverage estimate needs it (head at the origin, looking
 * down −Z): its offset along x, the tangents of its half-angles, its image size. */
struct rnd_cost_eye {
    double offset_x_m, tan_left, tan_right, tan_up, tan_down;
    int width_px, height_px;
};
struct rnd_calibration {
    struct rnd_cost_eye eyes[2];
    struct rnd_cost_eye inset_eyes[2]; /* an inset grid's: each eye's inset rectangle as an image of its
                                        * own (0 × 0 otherwise) */
    struct rnd_cost_frame *frames;   /* one per grid point, in grid order */
    struct rnd_cost_object *objects;
    size_t frame_count, object_count;
    char renderer[128];              /* GL_RENDERER */
    double seconds;                  /* wall time of the measurement */
    /* The frame's fixed cost measured directly: empty stereo frames (clear both eyes, glFinish — the
     * passes every frame makes) timed between the grid's points, in every pass: their median and
     * quartiles. The fit takes the median as c0 instead of guessing it as an intercept. */
    double empty_ms, empty_p25_ms, empty_p75_ms;
    uint32_t empty_frames;
    /* A periphery grid's composite (rnd_renderer_composite_layers: the periphery upsampled over each
     * whole eye), the compositor's work and so not in the frames' times: timed after each empty
     * frame, the median; 0 frames for plain and inset grids. */
    double composite_ms;
    uint32_t composite_frames;
};
/* Renders the field's bumpy sphere and the auditorium's chair (scene/) in stereo on `display` at
 * render_scale: empty frames (the fixed cost, RND_COST_EMPTY_EVERY points apart) and, for every grid point, k copies (at most the 150 chairs the auditorium has) in a grid in front of both eyes sized so their projected coverage totals the
 * requested share; `repeats` passes over the grid, each in a new seeded random order, time one
 * frame per point (hl_clock around rnd_renderer_draw_stereo, which ends with glFinish), and the
 * median over passes is kept — so a busy moment of a shared machine or a slow
 * drift hits one pass of many points, not every repeat of one. A warm-up of the heaviest point
 * comes first, as llvmpipe compiles shaders on first use. Takes seconds; allocates *out (free with
 * rnd_calibration_free). grid->eye_width_px/height_px and display are filled in. With
 * grid->periphery_scale < 1 every frame, the empty ones too, is drawn as that periphery over the whole
 * eye: the objects' counts are the same, their pixels s² as many (frm_cost_calibrate). With
 * grid->inset_radius_deg > 0 every frame is drawn as the inset alone: the same counts, out->inset_eyes
 * the inset's rectangles. */
int rnd_cost_measure(const struct hmd_profile *display, struct rnd_cost_grid *grid, uint64_t seed,
                     struct rnd_calibration *out, struct hl_error *err);
void rnd_calibration_free(struct rnd_calibration *c);

#endif
