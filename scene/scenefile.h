/* scene/scenefile.h: scene files (JSON, docs/scene-format.md) — meshes, instances, groups with
 * impostors, motion paths. Included by scene/scene.h. */
#ifndef HMDLOD_SCENE_SCENEFILE_H
#define HMDLOD_SCENE_SCENEFILE_H

#include "scene/lodgen.h"

struct scn_scene;

/* How a scene file's mesh entry becomes a lodset: the default resolver (scene/ only) reads .lod
 * files and runs scn_lodgen_build on mesh files; frame/ passes one that also analyses and caches. */
struct scn_asset_resolver {
    int (*resolve)(void *user, const char *path, struct scn_lodset *out, struct hl_error *err);
    void *user;
};
int scn_scenefile_load(const char *path, const struct scn_asset_resolver *resolver /* NULL = default */,
                       struct scn_scene *out, struct hl_error *err);

/* Where the default resolver may keep the chains it makes from mesh files, so that a later load
 * skips the decimation (frame/ keeps them on disk). load fills *out with a chain made earlier from
 * the mesh at `path` whose imported mesh has scn_mesh_hash `hash` and returns 0, else −1 (*out
 * zeroed); save keeps one (failures are the store's to report: never an error of the load). */
struct scn_chain_store {
    int (*load)(void *user, const char *path, uint64_t hash, struct scn_lodset *out);
    void (*save)(void *user, const char *path, uint64_t hash, const struct scn_lodset *set);
    void *user;
};
/* The default resolver: a path ending in .lod (scn_scenefile_path_is_lod) is read as it is; any
 * other file is imported and decimated (meshopt, 4 levels at 1, 1/4, 1/16, 1/64 of the triangles,
 * errors from 2^17 Hausdorff samples per level)
 * unless `user`, NULL or a const struct scn_chain_store *, holds the chain already. */
int scn_scenefile_resolve_default(void *user, const char *path, struct scn_lodset *out, struct hl_error *err);
int scn_scenefile_path_is_lod(const char *path);

#endif
