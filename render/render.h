/* render: drawing and its cost. Headless EGL (surfaceless Mesa) OpenGL 4.5 core, one FBO holding
 * both eyes side by side, indexed meshes in GPU buffers, PNG capture, and the built-in procedural
 * scenes with their LOD chains. Prefix rnd_. Never decides what to draw: callers pass the list. */
#ifndef HMDLOD_RENDER_H
#define HMDLOD_RENDER_H

#include "base/base.h"
#include "hmd/hmd.h"

enum { RND_MAX_LODS = 8, RND_NAME_MAX = 32 };

/* ---- scenes (CPU side) -------------------------------------------------------------------------
 * All chains' vertices and indices live in one packed array each; an LOD is a range in them. */
struct rnd_lod {
    uint32_t first_index, index_count; /* range in scene.indices (3 per triangle) */
    uint32_t triangle_count, vertex_count;
    double geometric_error_m;  /* max distance from the finest level's vertices to this level's surface */
    double unique_freq_cpdiam; /* see acuity.h; derived from geometric_error_m (docs/scenes.md) */
};

struct rnd_chain {
    char name[RND_NAME_MAX];
    int lod_count;
    struct rnd_lod lods[RND_MAX_LODS];
    double bound_radius_m; /* bounding sphere about the model origin, at scale 1 */
};

struct rnd_instance {
    uint32_t chain;
    double position_m[3];
    hl_quatd rotation; /* model to world, w x y z */
    double scale;
    float color[3];
};

struct rnd_scene {
    char name[RND_NAME_MAX];
    float *positions; /* 3 per vertex, model space */
    float *normals;   /* 3 per vertex */
    uint32_t vertex_count;
    uint32_t *indices; /* absolute vertex indices */
    uint32_t index_count;
    struct rnd_chain *chains;
    uint32_t chain_count;
    struct rnd_instance *instances;
    uint32_t instance_count;
    double *center_m; /* world bounding-sphere centres, 3 per instance (structure of arrays for acuity) */
    double *radius_m; /* world bounding-sphere radii, 1 per instance */
    uint32_t *chain_of_instance;
};

struct rnd_scene_params {
    int object_count; /* field: 1…100000, 0 = default 100 (auditorium ignores it) */
    uint64_t seed;    /* placement seed (default 1) */
};

/* Built-in scenes: "field" (Reddy §5: N copies of one object with 4 LODs of about 3928/834/254/76
 * triangles, randomly placed around the viewer) and "auditorium" (Funkhouser §7: rows of chairs
 * with several LODs, walls and a stage, ~90k triangles at full detail). Deterministic for a seed. */
int rnd_scene_build(const char *name, const struct rnd_scene_params *params, struct rnd_scene *out,
                    struct hl_error *err);
void rnd_scene_free(struct rnd_scene *scene);
const char *const *rnd_scene_builtin_names(void); /* NULL-terminated */

/* ---- renderer ------------------------------------------------------------------------------- */
struct rnd_renderer;

/* Creates a surfaceless EGL context (GL 4.5 core) and an RGBA8+depth FBO of 2·eye_width × height. */
int rnd_renderer_create(int eye_width_px, int eye_height_px, struct rnd_renderer **out, struct hl_error *err);
void rnd_renderer_destroy(struct rnd_renderer *r);
const char *rnd_renderer_name(const struct rnd_renderer *r); /* GL_RENDERER, e.g. "llvmpipe (LLVM 15…)" */
int rnd_renderer_upload_scene(struct rnd_renderer *r, const struct rnd_scene *scene, struct hl_error *err);

/* One eye: where it is (world, double) and where it looks (eye-to-world rotation; the eye looks
 * down −Z, +Y up), plus its projection (hmd_eye_projection). */
struct rnd_eye_view {
    double position_m[3];
    hl_quatd orientation;
    double projection[16];
};

struct rnd_draw_stats {
    uint64_t triangles_per_eye[2];
    uint32_t draw_calls;
};

/* Clears and draws the listed instances (index[k], at LOD lod[k]; lod 255 = skip) into both eyes:
 * left eye in the left half, right eye in the right half. Model-view matrices are built relative to
 * the eye in double, so far-from-origin scenes keep precision. Waits for the GPU (glFinish) so the
 * caller's timer measures the draw. */
int rnd_renderer_draw_stereo(struct rnd_renderer *r, const struct rnd_scene *scene,
                             const struct rnd_eye_view views[2], const uint32_t *index, const uint8_t *lod,
                             size_t count, struct rnd_draw_stats *stats);

/* Reads the FBO into rgba (2·eye_width·height·4 bytes), rows top to bottom. */
int rnd_renderer_read_rgba(struct rnd_renderer *r, uint8_t *rgba, struct hl_error *err);
void rnd_renderer_size(const struct rnd_renderer *r, int *width_px, int *height_px);

/* Writes an 8-bit RGBA PNG atomically (temporary file, then rename): no half-written PNG is left. */
int rnd_png_write(const char *path, const uint8_t *rgba, int width_px, int height_px, struct hl_error *err);

#endif
