/* Fuzz target: scene files (scn_scenefile_load, scene/scenefile.c + scenefile_build.c) from a
 * scratch file. Mesh files the scene names are resolved to a small tetrahedron chain without
 * reading them (importing is fuzz_mesh_import's, and decimating whatever file the fuzzer names
 * would only be slow); built-in shapes, instances, groups, impostors and motions are the real
 * code. A scene that loads is freed (LeakSanitizer checks). */
#include "fuzz_util.h"

#include <math.h>
#include <string.h>

#include "scene/scene.h"

static int resolve_tetrahedron(void *user, const char *path, struct scn_lodset *out, struct hl_error *err)
{
    (void)user, (void)path;
    memset(out, 0, sizeof *out);
    struct scn_mesh *m = &out->levels[0];
    const hl_vec3d v[4] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    for (int i = 0; i < 4; ++i)
        scn_mesh_add_vertex(m, v[i], v[i]);
    scn_mesh_add_triangle(m, 0, 1, 2);
    scn_mesh_add_triangle(m, 0, 3, 1);
    scn_mesh_add_triangle(m, 0, 2, 3);
    scn_mesh_add_triangle(m, 1, 3, 2);
    if (m->failed) {
        scn_mesh_free(m);
        return hl_fail(err, "out of memory");
    }
    scn_mesh_smooth_normals(m);
    out->level_count = 1;
    out->error_m[0] = out->error_rel[0] = 0.0;
    out->freq[0].narrow_cpdiam = out->freq[0].long_cpdiam = out->freq[0].geometric_cpdiam = INFINITY;
    out->radius_m = sqrt(3.0);
    for (int k = 0; k < 3; ++k)
        out->aabb_min_m[k] = -1.0, out->aabb_max_m[k] = 1.0;
    strcpy(out->simplifier, "procedural");
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_file("fuzz-scene.json", data, size);
    const struct scn_asset_resolver resolver = {resolve_tetrahedron, NULL};
    struct scn_scene s;
    struct hl_error err;
    if (scn_scenefile_load(path, &resolver, &s, &err) == 0)
        scn_scene_free(&s);
    return 0;
}
