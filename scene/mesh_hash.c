/* Content hash of a mesh: the key under which analysis results and .lod files are cached, so it
 * must not depend on the host. FNV-1a 64 (Fowler–Noll–Vo) over the little-endian bytes of the
 * vertex count, the index count, the positions (IEEE-754 binary32) and the indices (uint32).
 * Normals are left out: they derive from the geometry and smoothing choices must not split caches. */
#include "scene/scene_internal.h"

#include <string.h>

static uint64_t scn_fnv1a(uint64_t h, const unsigned char *p, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull; /* FNV-1a 64 prime */
    }
    return h;
}

static uint64_t scn_fnv1a_u32(uint64_t h, uint32_t v)
{
    unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                          (unsigned char)(v >> 24)};
    return scn_fnv1a(h, b, 4);
}

uint64_t scn_mesh_hash(const struct scn_mesh *m)
{
    uint64_t h = 0xcbf29ce484222325ull; /* FNV-1a 64 offset basis */
    if (!m)
        return h;
    h = scn_fnv1a_u32(h, m->vertex_count);
    h = scn_fnv1a_u32(h, m->index_count);
    for (size_t i = 0; i < 3 * (size_t)m->vertex_count; ++i) {
        uint32_t bits;
        memcpy(&bits, &m->positions[i], sizeof bits); /* the float's bit pattern, not its value */
        h = scn_fnv1a_u32(h, bits);
    }
    for (size_t i = 0; i < m->index_count; ++i)
        h = scn_fnv1a_u32(h, m->indices[i]);
    return h;
}
