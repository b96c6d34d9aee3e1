/* scene/measure.h: measures on meshes — the two-sided Hausdorff distance between LOD levels, a
 * content hash that keys caches, and packing a lodset into a scene. Included by scene/scene.h. */
#ifndef HMDLOD_SCENE_MEASURE_H
#define HMDLOD_SCENE_MEASURE_H

#include "scene/lodset.h"

struct scn_scene;

struct scn_hausdorff {
    double max_m;    /* sampled two-sided distance, max of both directions; ≤ the true distance */
    double mean_m;   /* area-weighted mean distance, averaged over both directions */
    double bound_m;  /* the true two-sided distance ≤ max_m + bound_m */
    uint64_t samples; /* points measured, both directions together */
};
/* Two-sided Hausdorff distance by dense surface sampling (area-weighted, deterministic for a seed),
 * closest points on the other surface through a spatial index. bound_m: the sampling's guaranteed
 * gap (the true distance ≤ max_m + bound_m). Each triangle of each mesh is cut into k² copies of
 * itself, one random point in each, k = ⌈longest edge / h⌉ with h the least that keeps the total
 * ≤ samples_per_mesh (0 = default 2^20; at least one per triangle), plus every referenced vertex;
 * bound_m ≤ the largest copy's diameter h (see hausdorff.c), halving for 4× the samples: bunny vs
 * its 50 % level at 10^6 samples per mesh, max 0.16 mm, bound 0.53 mm (0.4 % of its radius), ~1 s.
 * Meshes need ≥ 1 triangle, valid indices and finite positions; unreferenced vertices are ignored.
 * Cost ~ O(samples · log triangles), single-threaded; docs/lod-format.md gives measured times. */
int scn_mesh_hausdorff(const struct scn_mesh *a, const struct scn_mesh *b, uint64_t samples_per_mesh,
                       uint64_t seed, struct scn_hausdorff *out, struct hl_error *err);
/* FNV-1a 64 over the little-endian bytes of vertex_count (u32), index_count (u32), the positions
 * (f32 bit patterns) and the indices (u32); normals are not hashed. Same value on every host. */
uint64_t scn_mesh_hash(const struct scn_mesh *m);
/* Packs a lodset as one more chain of the scene (shared buffers; errors, frequency table and
 * lost-contrast spectrum copied; more than SCN_LODSET_MAX_BANDS bands is refused).
 * The chain's sphere is centred on set->center_m (scn_chain.bound_center_m) and grown to hold every
 * level's vertices; unique_freq_cpdiam = the geometric reading (R/ε where it is NaN), kept strictly
 * decreasing. The set stays the caller's. */
int scn_scene_add_lodset(struct scn_scene *s, const char *name, const struct scn_lodset *set,
                         struct hl_error *err);

#endif
