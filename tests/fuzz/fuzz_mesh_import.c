/* Fuzz target: mesh import (scn_mesh_import: scene/mesh_import.cpp over OpenMesh IO for OBJ, PLY,
 * OFF and STL, scene/mesh_import_assimp.c over assimp for glTF 2.0), from a scratch file whose
 * extension byte 0 picks. Our code is the checks before the libraries read the file (and the PLY
 * triangle strips, which the PLY check reads itself), then the welding, triangulation, degenerate
 * and index checks after. An imported mesh must keep the promises of scene/lodgen.h: faces,
 * indices in range, finite positions and normals. */
#include "fuzz_util.h"

#include <math.h>

#include "scene/scene.h"

static const char *const names[] = {"fuzz.obj", "fuzz.ply", "fuzz.off", "fuzz.stl", "fuzz.gltf", "fuzz.glb"};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    const char *path = fuzz_write_file(names[data[0] % (sizeof names / sizeof names[0])], data + 1, size - 1);
    struct scn_mesh m = {0};
    struct scn_import_report report;
    struct hl_error err;
    if (scn_mesh_import(path, &m, &report, &err) == 0) {
        FUZZ_CHECK(m.index_count > 0 && m.index_count % 3 == 0, "imported mesh without whole triangles");
        for (uint32_t i = 0; i < m.index_count; ++i)
            FUZZ_CHECK(m.indices[i] < m.vertex_count, "imported index out of range");
        for (uint32_t i = 0; i < 3 * m.vertex_count; ++i)
            FUZZ_CHECK(isfinite(m.positions[i]) && isfinite(m.normals[i]), "imported position or normal not finite");
    }
    scn_mesh_free(&m);
    return 0;
}
