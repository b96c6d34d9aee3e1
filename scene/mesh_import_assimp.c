/* glTF 2.0 (.gltf/.glb) through assimp's C API. The node hierarchy is baked into the vertices
 * (aiProcess_PreTransformVertices) so that every mesh of the file lands in model space as the file
 * places it; all meshes become one soup. Points and lines are skipped (aiProcess_SortByPType). */
#include "scene/lodgen_internal.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <stdlib.h>
#include <string.h>

int scn_assimp_read(const char *path, struct scn_soup *soup, struct hl_error *err)
{
    memset(soup, 0, sizeof *soup);
    /* No aiProcess_FindInvalidData / ValidateDataStructure fix-ups that would hide bad input:
     * NaN coordinates must reach validation and be refused there with their vertex number. */
    unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                     aiProcess_PreTransformVertices;
    const struct aiScene *sc = aiImportFile(path, flags);
    if (!sc) {
        const char *why = aiGetErrorString();
        return hl_fail(err, "%s: assimp cannot read it: %s", path, why && *why ? why : "unknown error");
    }
    uint64_t nv = 0;
    for (unsigned m = 0; m < sc->mNumMeshes; ++m)
        nv += sc->mMeshes[m]->mNumVertices;
    if (nv >= UINT32_MAX / 3) {
        aiReleaseImport(sc);
        return hl_fail(err, "%s: %llu vertices: more than hmdlod's 32-bit indices hold", path, (unsigned long long)nv);
    }
    soup->positions = malloc(((size_t)nv * 3 + 1) * sizeof *soup->positions);
    int all_normals = nv > 0;
    for (unsigned m = 0; m < sc->mNumMeshes; ++m)
        all_normals = all_normals && sc->mMeshes[m]->mNormals != NULL;
    if (all_normals)
        soup->normals = malloc(((size_t)nv * 3 + 1) * sizeof *soup->normals);
    if (!soup->positions || (all_normals && !soup->normals)) {
        aiReleaseImport(sc);
        scn_soup_free(soup);
        return hl_fail(err, "%s: out of memory while reading", path);
    }
    uint32_t base = 0;
    for (unsigned m = 0; m < sc->mNumMeshes; ++m) {
        const struct aiMesh *mesh = sc->mMeshes[m];
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            double *p = soup->positions + 3 * ((size_t)base + v);
            p[0] = mesh->mVertices[v].x, p[1] = mesh->mVertices[v].y, p[2] = mesh->mVertices[v].z;
            if (all_normals) {
                float *n = soup->normals + 3 * ((size_t)base + v);
                n[0] = mesh->mNormals[v].x, n[1] = mesh->mNormals[v].y, n[2] = mesh->mNormals[v].z;
            }
        }
        soup->vertex_count = base + mesh->mNumVertices;
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const struct aiFace *face = &mesh->mFaces[f];
            if (face->mNumIndices < 3) /* points and lines: not surfaces */
                continue;
            uint32_t small[3], *idx = small, n = face->mNumIndices;
            if (n > 3 && !(idx = malloc(n * sizeof *idx))) { /* not after aiProcess_Triangulate */
                soup->failed = 1;
                break;
            }
            for (uint32_t k = 0; k < n; ++k)
                idx[k] = face->mIndices[k] < mesh->mNumVertices ? base + face->mIndices[k] : UINT32_MAX;
            scn_soup_add_face(soup, idx, n);
            if (idx != small)
                free(idx);
        }
        base += mesh->mNumVertices;
    }
    aiReleaseImport(sc);
    if (soup->failed) {
        scn_soup_free(soup);
        return hl_fail(err, "%s: out of memory while reading", path);
    }
    return 0;
}
