/* scene/scenefile.h: scene files (JSON, docs/scene-format.md) — meshes, instances, groups with
 * impostors, motion paths. Included by scene/scene.h. */
#ifndef HMDLOD_SCENE_SCENEFILE_H
#define HMDLOD_SCENE_SCENEFILE_H

#include "scene/lodgen.h"

struct scn_scene;

/* How a scene file's mesh entry becomes a lodset: the default resolver (scene/ only) reads .lod
 * files and runs scn_lodgen_build on mesh files; replay/ passes one that also analyses and caches. */
struct scn_asset_resolver {
    int (*resolve)(void *user, const char *path, struct scn_lodset *out, struct hl_error *err);
    void *user;
};
int scn_scenefile_load(const char *path, const struct scn_asset_resolver *resolver /* NULL = default */,
                       struct scn_scene *out, struct hl_error *err);

/* The default resolver: a path ending in .lod (scn_scenefile_path_is_lod) is read as it is; any
 * other file is imported and decimated with scn_scenefile_lodgen_params (meshopt, 4 levels at 1,
 * 1/4, 1/16, 1/64 of the triangles). `user` is unused. */
int scn_scenefile_resolve_default(void *user, const char *path, struct scn_lodset *out, struct hl_error *err);
void scn_scenefile_lodgen_params(struct scn_lodgen_params *p);
int scn_scenefile_path_is_lod(const char *path);

#endif
