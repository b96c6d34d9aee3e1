/* scene/mesh.h: an indexed triangle mesh on the CPU — one LOD level, an imported model, a group
 * impostor. Plain arrays: float positions and normals (what the GPU consumes), uint32 indices.
 * Included by scene/scene.h; not meant to be included on its own. */
#ifndef HMDLOD_SCENE_MESH_H
#define HMDLOD_SCENE_MESH_H

#include "base/base.h"

/* Growable: the append functions grow the arrays (amortised doubling) and, if an allocation fails,
 * set `failed` and ignore every later append, so builders check once at the end. The mesh owns its
 * arrays; scn_mesh_free releases them and zeroes the struct. A zeroed struct is a valid empty mesh. */
struct scn_mesh {
    float *positions, *normals; /* 3 per vertex, model space, metres */
    uint32_t vertex_count, vertex_cap;
    uint32_t *indices; /* 3 per triangle, CCW seen from outside, local to this mesh */
    uint32_t index_count, index_cap;
    int failed; /* an allocation failed; every later append is ignored */
};
void scn_mesh_free(struct scn_mesh *m);
uint32_t scn_mesh_add_vertex(struct scn_mesh *m, hl_vec3d p, hl_vec3d n);
void scn_mesh_add_triangle(struct scn_mesh *m, uint32_t a, uint32_t b, uint32_t c);
/* Replaces every normal with the area-weighted average of its faces' normals (smooth shading). */
void scn_mesh_smooth_normals(struct scn_mesh *m);
/* Axis-aligned bounds of the vertices, metres, in double. An empty mesh gives lo = +inf, hi = −inf. */
void scn_mesh_aabb(const struct scn_mesh *m, double lo_m[3], double hi_m[3]);
/* Area-weighted normals, smooth across edges whose dihedral angle is below crease_angle_deg and split
 * across sharper ones and across non-manifold edges: a vertex whose faces form several smooth fans
 * gets one copy per fan (positions duplicated, indices rewritten). Zero-area faces contribute nothing.
 * The mesh is no longer welded afterwards: decimate and measure before, not after. */
void scn_mesh_crease_normals(struct scn_mesh *m, double crease_angle_deg);

#endif
