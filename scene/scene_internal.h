/* scene internals shared by the built-in scene builders, the mesh primitives and the LOD error
 * estimate. Not public: other modules see only scene.h. */
#ifndef HMDLOD_SCENE_INTERNAL_H
#define HMDLOD_SCENE_INTERNAL_H

#include "scene/scene.h"

/* ---- deterministic PRNG ----------------------------------------------------------------------
 * splitmix64 (Steele et al. 2014): tiny, full-period, and identical on every platform, unlike
 * rand(), so a scene seed names the same scene everywhere. */
struct scn_rng {
    uint64_t state;
};
uint64_t scn_rng_next(struct scn_rng *g);
double scn_rng_uniform(struct scn_rng *g); /* [0, 1), 53 random bits */
hl_quatd scn_rng_rotation(struct scn_rng *g); /* uniform over SO(3) (Shoemake 1992) */

/* Primitives, all closed with CCW-outward triangles. `rot` orients the local frame (identity =
 * axis-aligned); boxes get flat faces (24 vertices), cylinders smooth sides and flat caps. */
void scn_mesh_add_box(struct scn_mesh *m, hl_vec3d center, hl_vec3d half, hl_quatd rot);
/* Cylinder along its local +Y, `segments` ≥ 3 around: 4·segments triangles. */
void scn_mesh_add_cylinder(struct scn_mesh *m, hl_vec3d center, double radius, double half_height,
                           int segments, hl_quatd rot);
/* Latitude–longitude sphere with radius radius·shape(direction): rings interior latitude rings and
 * segments longitudes, 2·rings·segments triangles, one vertex per pole. */
void scn_mesh_add_sphere(struct scn_mesh *m, double radius, int rings, int segments,
                         double (*shape)(hl_vec3d dir));

/* ---- scene assembly --------------------------------------------------------------------------- */
/* Appends a chain's levels to the packed arrays: name, level count and each level's range and counts;
 * everything else in the new chain (s->chains[chain_count − 1]) is zero for the caller to fill. */
int scn_scene_pack_chain(struct scn_scene *s, const char *name, const struct scn_mesh *meshes, int count,
                         struct hl_error *err);
/* Appends a chain whose levels are meshes[0] (finest) … meshes[count−1] to the scene's packed
 * arrays, computing counts, bound radius, geometric errors and unique frequencies. */
int scn_scene_add_chain(struct scn_scene *s, const char *name, struct scn_mesh *meshes, int count,
                        struct hl_error *err);
/* Sizes the per-instance arrays for n instances (instances, center_m, radius_m, chain_of_instance). */
int scn_scene_alloc_instances(struct scn_scene *s, uint32_t n, struct hl_error *err);
/* Sets instance i and its world bounding sphere: centre position + rotation·(scale·bound_center_m),
 * radius scale·bound_radius_m. */
void scn_scene_set_instance(struct scn_scene *s, uint32_t i, uint32_t chain, hl_vec3d position,
                            hl_quatd rotation, double scale, const float color[3]);

/* The built-in objects as chains (scene files name them as {"builtin": …}): the field's bumpy
 * sphere (4 levels, 3906…78 triangles) and the auditorium's chair (4 levels, 600…12). */
int scn_field_add_object_chain(struct scn_scene *s, const char *name, struct hl_error *err);
int scn_auditorium_add_chair_chain(struct scn_scene *s, const char *name, struct hl_error *err);

int scn_scene_build_field(const struct scn_scene_params *p, struct scn_scene *s, struct hl_error *err);
int scn_scene_build_auditorium(const struct scn_scene_params *p, struct scn_scene *s, struct hl_error *err);
int scn_scene_build_domes(const struct scn_scene_params *p, struct scn_scene *s, struct hl_error *err);

/* ---- LOD analysis (lod_error.c) --------------------------------------------------------------- */
/* Max over the fine mesh's vertices of the distance to the nearest triangle of the coarse mesh. */
double scn_lod_geometric_error(const struct scn_mesh *fine, const struct scn_mesh *coarse);
/* Cycles per object diameter of the detail lost at geometric error eps on a bounding sphere of
 * radius R (see lod_error.c and docs/scenes.md); +INFINITY for eps = 0 at level 0. */
double scn_lod_unique_freq(double eps_m, double bound_radius_m);
/* Closest point on triangle abc to p (Ericson 2005 §5.1.5), exact also for slivers. */
hl_vec3d scn_closest_on_triangle(hl_vec3d p, hl_vec3d a, hl_vec3d b, hl_vec3d c);

/* ---- surface sampling and nearest triangles (hausdorff.c) ------------------------------------- */
/* 0 if m has ≥ 1 triangle, indices in range and finite positions; else fills err naming `what`. */
int scn_mesh_check(const struct scn_mesh *m, const char *what, struct hl_error *err);
/* The stratified samples scn_mesh_hausdorff uses: every triangle cut into k² copies of itself (cells),
 * one uniform point in each (weight = the cell's area), then every referenced vertex (weight 0). At
 * most about `target` + vertices points; every surface point lies within its cell's sample's reach_m,
 * and so within spacing_m of a sample. Deterministic for a seed. */
struct scn_surface_samples {
    double *points;    /* 3 per sample */
    double *weight_m2; /* the area each sample stands for */
    double *reach_m;   /* every point of the sample's cell is within reach_m of it (0 for vertices) */
    uint64_t count;
    double spacing_m;  /* max reach over all samples is ≤ this: the largest cell's diameter */
};
/* The seeds scn_mesh_hausdorff(a, b, n, seed) samples a and b with. */
#define SCN_HAUSDORFF_SEED_A(seed) (seed)
#define SCN_HAUSDORFF_SEED_B(seed) ((seed) ^ 0xD1B54A32D192ED03ull)
int scn_surface_sample(const struct scn_mesh *m, uint64_t target, uint64_t seed, struct scn_surface_samples *out,
                       struct hl_error *err);
void scn_surface_samples_free(struct scn_surface_samples *s);
/* Bounding-volume hierarchy over a mesh's triangles (copied, double) for closest-point queries. */
struct scn_tri_bvh {
    double *tri; /* 9 per triangle, in the hierarchy's order */
    uint32_t tri_count;
    struct scn_bvh_node *nodes;
    uint32_t node_count;
};
int scn_tri_bvh_build(const struct scn_mesh *m, struct scn_tri_bvh *out, struct hl_error *err);
void scn_tri_bvh_free(struct scn_tri_bvh *b);
/* Distance from p to the nearest triangle: exactly the minimum of |p − scn_closest_on_triangle| over
 * all triangles. *hint (may be NULL; UINT32_MAX = none) seeds the search and receives the winner. */
double scn_tri_bvh_distance(const struct scn_tri_bvh *b, hl_vec3d p, uint32_t *hint);

/* ---- .lod files (lodfile.c) ------------------------------------------------------------------- */
/* CRC-32 (IEEE 802.3, reflected 0xEDB88320, initial and final XOR 0xFFFFFFFF): zlib's crc32(). */
uint32_t scn_crc32(const void *data, size_t n);

#endif
