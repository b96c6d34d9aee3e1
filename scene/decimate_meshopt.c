/* meshoptimizer's simplifier (0.18, called from C): edge collapses ranked by a quadric error
 * (Garland & Heckbert 1997) on a position-welded index buffer, 20–30× faster than OpenMesh on the
 * shared meshes (PLATFORM.md §7b). Each level is simplified from the previous one, like the OpenMesh
 * chain, so the whole chain costs about one simplification of the full mesh. */
#include "scene/lodgen_internal.h"

#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

/* Position-only welding first (meshopt_generateVertexRemap): meshopt_simplify collapses only along
 * edges it sees as shared, so split vertices would keep seams open. */
static int meshopt_weld(const struct scn_mesh *in, struct scn_mesh *out)
{
    memset(out, 0, sizeof *out);
    size_t nv = in->vertex_count, ni = in->index_count;
    unsigned *remap = malloc((nv + 1) * sizeof *remap);
    if (!remap)
        return -1;
    size_t unique = meshopt_generateVertexRemap(remap, in->indices, ni, in->positions, nv, 3 * sizeof(float));
    out->positions = malloc((unique * 3 + 1) * sizeof(float));
    out->indices = malloc((ni + 1) * sizeof(uint32_t));
    if (!out->positions || !out->indices) {
        free(remap);
        scn_mesh_free(out);
        return -1;
    }
    meshopt_remapVertexBuffer(out->positions, in->positions, nv, 3 * sizeof(float), remap);
    meshopt_remapIndexBuffer(out->indices, in->indices, ni, remap);
    out->vertex_count = out->vertex_cap = (uint32_t)unique;
    out->index_count = out->index_cap = (uint32_t)ni;
    free(remap);
    return 0;
}

/* One simplification of `cur` (welded, no normals needed) to about target triangles into `out`,
 * unused vertices dropped, normals area-weighted. */
static int meshopt_level(const struct scn_mesh *cur, uint32_t target, struct scn_mesh *out)
{
    memset(out, 0, sizeof *out);
    size_t ni = cur->index_count;
    uint32_t *idx = malloc((ni + 1) * sizeof *idx);
    if (!idx)
        return -1;
    float result_error = 0;
    /* target_error 1 (relative to the mesh extent) = no error limit: the count decides, as with
     * OpenMesh. Options 0: borders may move (meshopt_SimplifyLockBorder would freeze open edges). */
    size_t n = meshopt_simplify(idx, cur->indices, ni, cur->positions, cur->vertex_count, 3 * sizeof(float),
                                (size_t)target * 3, 1.0f, 0, &result_error);
    unsigned *remap = malloc(((size_t)cur->vertex_count + 1) * sizeof *remap);
    if (!remap) {
        free(idx);
        return -1;
    }
    size_t nv = meshopt_optimizeVertexFetchRemap(remap, idx, n, cur->vertex_count);
    out->positions = malloc((nv * 3 + 1) * sizeof(float));
    out->normals = malloc((nv * 3 + 1) * sizeof(float));
    out->indices = malloc((n + 1) * sizeof(uint32_t));
    if (!out->positions || !out->normals || !out->indices) {
        free(idx);
        free(remap);
        scn_mesh_free(out);
        return -1;
    }
    meshopt_remapVertexBuffer(out->positions, cur->positions, cur->vertex_count, 3 * sizeof(float), remap);
    meshopt_remapIndexBuffer(out->indices, idx, n, remap);
    out->vertex_count = out->vertex_cap = (uint32_t)nv;
    out->index_count = out->index_cap = (uint32_t)n;
    free(idx);
    free(remap);
    scn_mesh_smooth_normals(out);
    return out->failed ? -1 : 0;
}

int scn_meshopt_decimate_chain(const struct scn_mesh *in, const uint32_t *target_tris, int count,
                               struct scn_mesh *outs, const struct scn_chain_observer *obs, struct hl_error *err)
{
    for (int k = 0; k < count; ++k)
        memset(&outs[k], 0, sizeof outs[k]);
    struct scn_mesh welded;
    if (meshopt_weld(in, &welded) != 0)
        return hl_fail(err, "meshoptimizer: out of memory");
    const struct scn_mesh *cur = &welded;
    for (int k = 0; k < count; ++k) {
        if (meshopt_level(cur, target_tris[k], &outs[k]) != 0) {
            scn_mesh_free(&welded);
            for (int j = 0; j <= k; ++j)
                scn_mesh_free(&outs[j]);
            return hl_fail(err, "meshoptimizer: out of memory");
        }
        cur = &outs[k];
        if (obs && obs->level_done)
            obs->level_done(obs->user, k);
    }
    scn_mesh_free(&welded);
    return 0;
}
