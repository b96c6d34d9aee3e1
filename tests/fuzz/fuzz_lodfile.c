/* Fuzz target: .lod files (scn_lodfile_read, scene/lodfile.c, docs/lod-format.md) from a scratch
 * file, the bytes as they are; the fuzz_lodfile_repair twin (FUZZ_LODFILE_REPAIR) first makes the
 * magic, version, sizes and CRC right so that the fuzzer reaches the level records and arrays. A set that loads must keep its promises (indices in range, finite positions). */
#include "fuzz_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"
#include "scene/scene_internal.h"

#ifdef FUZZ_LODFILE_REPAIR
static void put_le(unsigned char *p, uint64_t v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        p[i] = (unsigned char)(v >> (8 * i));
}
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
#ifdef FUZZ_LODFILE_REPAIR
    /* the header's magic, version (2 when the input says 2, else 1), its header size (160 or 144)
     * and file size, and the trailing CRC-32 made right (docs/lod-format.md); everything else is
     * the input's */
    int v2 = size > 8 && data[8] == 2;
    size_t header = v2 ? 160 : 144;
    size_t n = size < header + 4 ? header + 4 : size;
    unsigned char *b = calloc(n, 1);
    if (!b)
        return 0;
    memcpy(b, data, size);
    memcpy(b, "HMDLOD\0\1", 8);
    put_le(b + 8, v2 ? 2 : 1, 4);
    put_le(b + 16, header, 4);
    put_le(b + 24, n, 8);
    put_le(b + n - 4, scn_crc32(b, n - 4), 4);
    const char *path = fuzz_write_file("fuzz.lod", b, n);
    free(b);
#else
    const char *path = fuzz_write_file("fuzz.lod", data, size);
#endif
    struct scn_lodset set;
    struct hl_error err;
    if (scn_lodfile_read(path, &set, &err) == 0) {
        FUZZ_CHECK(set.level_count >= 1 && set.level_count <= SCN_LODSET_MAX_LEVELS, "level count out of range");
        for (int l = 0; l < set.level_count; ++l) {
            const struct scn_mesh *m = &set.levels[l];
            for (uint32_t i = 0; i < m->index_count; ++i)
                FUZZ_CHECK(m->indices[i] < m->vertex_count, "index out of range in a loaded .lod");
            for (uint32_t i = 0; i < 3 * m->vertex_count; ++i)
                FUZZ_CHECK(isfinite(m->positions[i]), "position not finite in a loaded .lod");
        }
        scn_lodset_free(&set);
    }
    return 0;
}
