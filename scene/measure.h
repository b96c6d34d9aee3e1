/* scene/measure.h: measures on meshes — the two-sided Hausdorff distance between LOD levels, a
 * content hash that keys caches, and packing a lodset into a scene. Included by scene/scene.h. */
#ifndef HMDLOD_SCENE_MEASURE_H
#define HMDLOD_SCENE_MEASURE_H

#include "scene/lodset.h"

struct scn_scene;

struct scn_hausdorff {
    double max_m, mean_m, bound_m;
    uint64_t samples;
};
/* Two-sided Hausdorff distance by dense surface sampling (area-weighted, deterministic for a seed),
 * closest points on the other surface through a spatial index. bound_m: the sampling's guaranteed
 * gap (the true distance ≤ max_m + bound_m). */
int scn_mesh_hausdorff(const struct scn_mesh *a, const struct scn_mesh *b, uint64_t samples_per_mesh,
                       uint64_t seed, struct scn_hausdorff *out, struct hl_error *err);
uint64_t scn_mesh_hash(const struct scn_mesh *m); /* FNV-1a 64 over the vertex and index arrays */
/* Packs a lodset as one more chain of the scene (shared buffers; errors and frequency table copied). */
int scn_scene_add_lodset(struct scn_scene *s, const char *name, const struct scn_lodset *set,
                         struct hl_error *err);

#endif
