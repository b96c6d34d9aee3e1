/* scene/lodgen.h: from a user's mesh file to an LOD chain — import (OpenMesh IO for OBJ/PLY/OFF/STL,
 * assimp for glTF 2.0), decimation (OpenMesh's quadric decimater with normal-flip and feature-edge
 * guards, or meshoptimizer), and the chain with its errors. Included by scene/scene.h. */
#ifndef HMDLOD_SCENE_LODGEN_H
#define HMDLOD_SCENE_LODGEN_H

#include "scene/lodset.h"

enum scn_simplifier { SCN_SIMPLIFIER_OPENMESH = 0, SCN_SIMPLIFIER_MESHOPT = 1 };

struct scn_import_report {
    uint32_t faces_read, polygons_triangulated, vertices_welded, degenerate_dropped, nonmanifold_edges;
};
/* Imports OBJ/PLY/OFF/STL (OpenMesh IO) or glTF 2.0 .gltf/.glb (assimp) into one welded triangle mesh.
 * Polygons are triangulated (quads along the shorter diagonal), vertices at bit-identical positions
 * merged, zero-area faces dropped and counted; normals are the file's when every vertex has one,
 * else area-weighted. Refused, with "path: vertex/face N: reason" (1-based, file order): a missing,
 * empty or unreadable file, an unsupported extension, no faces, NaN/Inf coordinates, a face naming
 * a missing vertex, only degenerate faces. Non-manifold edges (more than two faces) are a warning:
 * counted in report->nonmanifold_edges, the mesh kept as the file has it. out is owned by the caller
 * (scn_mesh_free); report may be NULL. */
int scn_mesh_import(const char *path, struct scn_mesh *out, struct scn_import_report *report,
                    struct hl_error *err);
/* Decimates `in` to about target_triangles (reports what it reached in out->index_count/3).
 * OpenMesh: quadric priority, normal-flip guard, edges sharper than feature_angle_deg kept as
 * feature lines (0 = 60°, negative = no feature lines), open boundaries kept exactly unless that
 * stops a level short of its target (then freed for it and the rest of the chain). meshopt ignores feature_angle_deg. A target
 * a simplifier cannot reach (non-manifold spots, all collapses illegal) is not an error: out holds
 * where it stopped. out: a new welded mesh with area-weighted normals, owned by the caller. */
int scn_mesh_decimate(const struct scn_mesh *in, uint32_t target_triangles, enum scn_simplifier simplifier,
                      double feature_angle_deg, struct scn_mesh *out, struct hl_error *err);

/* Where a decimation chain's time goes, seconds on the monotonic clock. OpenMesh fills every field
 * (building its half-edge mesh, marking feature lines, initialising the modules, the collapses,
 * garbage collection, copying out with welding and normals); meshopt only decimate_s. */
struct scn_decimate_timing {
    double build_s, feature_s, init_s, decimate_s, gc_s, extract_s;
};
/* Decimates `in` to each of target_tris[0 … count−1] (strictly decreasing) in turn, each level from
 * the previous one: one OpenMesh decimater throughout (PLATFORM.md §7b), or meshopt from the
 * previous level's output. outs[k] as scn_mesh_decimate's out; timing may be NULL. */
int scn_mesh_decimate_chain(const struct scn_mesh *in, const uint32_t *target_tris, int count,
                            enum scn_simplifier simplifier, double feature_angle_deg, struct scn_mesh *outs,
                            struct scn_decimate_timing *timing, struct hl_error *err);

struct scn_lodgen_params {
    enum scn_simplifier simplifier;
    int ratio_count;
    double ratios[SCN_LODSET_MAX_LEVELS];                  /* triangle ratios, ratios[0] = 1 */
    double max_error_px, at_distance_m, fov_deg, width_px; /* --max-error-px E@DIST mode when > 0 */
    double feature_angle_deg;                              /* 0 = default 60 */
    uint32_t hausdorff_samples;                            /* 0 = default */
    void (*progress)(void *user, double fraction);
    void *progress_user;
};
/* Builds the chain (levels, errors via scn_mesh_hausdorff, bounds, hash, geometric frequencies;
 * image frequencies NaN until analysed). Level k ≥ 1 is decimated from level k − 1 (one OpenMesh
 * decimater, or meshopt from the previous level's output).
 * Levels: ratios[k]·T0 triangles (ratios[0] = 1, strictly decreasing, > 0), or in --max-error-px mode
 * (max_error_px > 0, at_distance_m > 0): a candidate chain at ratios 2^(−j/2) down to 16 triangles
 * is measured and level k is the coarsest candidate whose error_m, seen from at_distance_m·2^(k−1),
 * spans ≤ max_error_px on the reference display: width_px pixels across fov_deg (defaults 1080 px
 * over 100°, about one HTC Vive eye); error_px = error_m / distance · width_px / fov_rad.
 * A level the simplifier could not make coarser than the previous one ends the chain there.
 * Bounds: the smaller of Ritter's sphere and the AABB-centred sphere of level 0, grown to hold every
 * level; model coordinates are kept (center_m). freq[k] = {NaN, NaN, R/ε} made strictly decreasing
 * as scene.c does. Every level's normals (level 0's too, replacing a file's) are crease normals
 * (scn_mesh_crease_normals) at the feature angle (default 60°; none: 180°), applied after the errors,
 * bounds and source_hash, which are of the welded meshes; the levels' vertices are split there.
 * progress (may be NULL) gets fractions 0…1. out owned by the caller
 * (scn_lodset_free); zeroed on failure. */
int scn_lodgen_build(const struct scn_mesh *mesh, const struct scn_lodgen_params *p, struct scn_lodset *out,
                     struct hl_error *err);

/* What scn_lodgen_build_timed measured, per level of the result (index 0: nothing), seconds. */
struct scn_lodgen_stats {
    uint32_t target_triangles[SCN_LODSET_MAX_LEVELS]; /* what was asked for each kept level */
    double decimate_s[SCN_LODSET_MAX_LEVELS];         /* share of the chain's decimation time */
    double error_s[SCN_LODSET_MAX_LEVELS];            /* the Hausdorff measure of that level */
    int candidates;                                   /* --max-error-px mode: candidate levels made */
    int stopped_early;                                /* 1: a level could not get coarser; chain cut */
};
/* scn_lodgen_build and its timings (stats may be NULL). */
int scn_lodgen_build_timed(const struct scn_mesh *mesh, const struct scn_lodgen_params *p,
                           struct scn_lodset *out, struct scn_lodgen_stats *stats, struct hl_error *err);
/* "openmesh" / "meshopt"; NULL for an unknown value. */
const char *scn_simplifier_name(enum scn_simplifier s);

#endif
