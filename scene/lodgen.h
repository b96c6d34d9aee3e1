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
/* Imports OBJ/PLY/OFF/STL (OpenMesh IO) or glTF 2.0 .gltf/.glb (assimp) into one welded triangle mesh. */
int scn_mesh_import(const char *path, struct scn_mesh *out, struct scn_import_report *report,
                    struct hl_error *err);
/* Decimates `in` to about target_triangles (reports what it reached in out->index_count/3). */
int scn_mesh_decimate(const struct scn_mesh *in, uint32_t target_triangles, enum scn_simplifier simplifier,
                      double feature_angle_deg, struct scn_mesh *out, struct hl_error *err);

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
 * image frequencies NaN until analysed). */
int scn_lodgen_build(const struct scn_mesh *mesh, const struct scn_lodgen_params *p, struct scn_lodset *out,
                     struct hl_error *err);

#endif
