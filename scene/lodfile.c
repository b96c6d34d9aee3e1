/* The .lod file (docs/lod-format.md): a fixed little-endian header, one record per level, the
 * level arrays each 16-byte aligned (so a reader could mmap them), and a CRC-32 over everything
 * before it. Every field is encoded byte by byte (no struct dumps), so the file is the same on
 * every host. The writer is atomic (temporary file, fsync, rename); the reader checks structure,
 * checksum and meaning, and names the byte offset of the first field that is wrong. */
#define _POSIX_C_SOURCE 200809L
#include "scene/scene_internal.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

static const unsigned char scn_lod_magic[8] = {'H', 'M', 'D', 'L', 'O', 'D', 0, 1};

/* Version 1: the chain and its frequency tables. Version 2 adds the lost-contrast spectrum: a
 * 16-byte header tail (band count, reserved, percentile) and 12 f64 bands per level record. The
 * writer writes version 1 when the set has no spectrum (contrast_band_count 0), so a file is only
 * as new as what it holds; the reader reads both. */
enum {
    SCN_LOD_VERSION = 2,
    SCN_LOD_HEADER_SIZE = 144, /* version 1 */
    SCN_LOD_RECORD_SIZE = 72,
    SCN_LOD_HEADER_SIZE_V2 = 160,
    SCN_LOD_RECORD_SIZE_V2 = SCN_LOD_RECORD_SIZE + 8 * SCN_LODSET_MAX_BANDS, /* 168 */
    SCN_LOD_ALIGN = 16,
};
static uint32_t scn_lod_header_size(uint32_t version) { return version >= 2 ? SCN_LOD_HEADER_SIZE_V2 : SCN_LOD_HEADER_SIZE; }
static uint32_t scn_lod_record_size(uint32_t version) { return version >= 2 ? SCN_LOD_RECORD_SIZE_V2 : SCN_LOD_RECORD_SIZE; }
/* A .lod is read whole into memory; 2 GiB is far beyond any LOD chain this project draws (the
 * bunny's full chain is ~4 MB) and keeps every offset below 2^31. */
#define SCN_LOD_MAX_BYTES ((uint64_t)1 << 31)

/* CRC-32 (IEEE 802.3, as PNG): zlib's. */
uint32_t scn_crc32(const void *data, size_t n) { return (uint32_t)crc32_z(0, data, n); }

static uint64_t align_up(uint64_t x) { return (x + SCN_LOD_ALIGN - 1) & ~(uint64_t)(SCN_LOD_ALIGN - 1); }

/* Where each level's arrays start: they follow the records in level order (positions, normals,
 * indices), each on a 16-byte boundary. Returns the end of the last array, before the padding to
 * 16 and the CRC. Counts are uint32, so every product and sum fits uint64 with room to spare. */
struct scn_lod_layout {
    uint64_t positions[SCN_LODSET_MAX_LEVELS], normals[SCN_LODSET_MAX_LEVELS], indices[SCN_LODSET_MAX_LEVELS];
    uint64_t crc_offset, file_size;
};
static void scn_lod_layout(uint32_t version, int levels, const uint32_t *tris, const uint32_t *verts,
                           struct scn_lod_layout *out)
{
    uint64_t at = align_up(scn_lod_header_size(version) + (uint64_t)scn_lod_record_size(version) * (uint64_t)levels);
    for (int l = 0; l < levels; ++l) {
        out->positions[l] = at;
        at = align_up(at + 12 * (uint64_t)verts[l]);
        out->normals[l] = at;
        at = align_up(at + 12 * (uint64_t)verts[l]);
        out->indices[l] = at;
        at = align_up(at + 12 * (uint64_t)tris[l]);
    }
    out->crc_offset = at;
    out->file_size = at + 4;
}

/* ---- parsing (shared by the reader and the writer's self-check) ------------------------------- */
#define SCN_LOD_FAIL(off, ...) scn_lod_fail(err, label, (uint64_t)(off), __VA_ARGS__)
static int scn_lod_fail(struct hl_error *err, const char *label, uint64_t off, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
static int scn_lod_fail(struct hl_error *err, const char *label, uint64_t off, const char *fmt, ...)
{
    char why[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    return hl_fail(err, "%s: byte %llu: %s", label, (unsigned long long)off, why);
}

/* A frequency reading: NaN (not measured) or finite and > 0; +Inf only at level 0 (it loses nothing). */
static int scn_lod_freq_ok(double f, int level)
{
    if (isnan(f))
        return 1;
    if (isinf(f))
        return f > 0 && level == 0;
    return f > 0;
}

static int scn_lod_need(const char *label, uint64_t size, uint64_t off, uint64_t n, const char *what,
                        struct hl_error *err)
{
    if (off + n <= size)
        return 0;
    return SCN_LOD_FAIL(off, "file ends inside the %s (the file is %llu bytes; a v1 header is %d)", what,
                        (unsigned long long)size, SCN_LOD_HEADER_SIZE);
}

/* A lost-contrast reading: NaN (no object pixel in that band from any view) or finite and ≥ 0. */
static int scn_lod_contrast_ok(double c) { return isnan(c) || (isfinite(c) && c >= 0); }

/* Checks the bytes b[0 … size) and, when out is not NULL, decodes them into *out (which the
 * caller has zeroed and frees on failure). */
static int scn_lod_parse(const unsigned char *b, uint64_t size, const char *label, struct scn_lodset *out,
                         struct hl_error *err)
{
    /* Structure first, in file order, so a truncated or foreign file gets the first reason. */
    uint64_t n_magic = size < 8 ? size : 8;
    if (memcmp(b, scn_lod_magic, (size_t)n_magic) != 0)
        return SCN_LOD_FAIL(0, "bad magic: not a .lod file (expected \"HMDLOD\\0\\1\")");
    if (scn_lod_need(label, size, 0, 8, "magic", err) || scn_lod_need(label, size, 8, 4, "format version", err))
        return -1;
    uint32_t version = hl_le_get_u32(b + 8);
    if (version > SCN_LOD_VERSION)
        return SCN_LOD_FAIL(8, "written by a newer hmdlod: version %u, this reads %d", version, SCN_LOD_VERSION);
    if (version == 0)
        return SCN_LOD_FAIL(8, "format version 0 is not valid (this reads %d)", SCN_LOD_VERSION);
    if (scn_lod_need(label, size, 12, 4, "flags", err) || scn_lod_need(label, size, 16, 4, "header size", err))
        return -1;
    uint32_t header_size = hl_le_get_u32(b + 16), hsize = scn_lod_header_size(version), rsize = scn_lod_record_size(version);
    if (header_size != hsize)
        return SCN_LOD_FAIL(16, "header size %u, version %u has %u", header_size, version, hsize);
    if (scn_lod_need(label, size, 20, 4, "level count", err) || scn_lod_need(label, size, 24, 8, "file size", err))
        return -1;
    uint64_t declared = hl_le_get_u64(b + 24);
    if (declared != size)
        return SCN_LOD_FAIL(24, "the header declares %llu bytes but the file has %llu (%s)",
                            (unsigned long long)declared, (unsigned long long)size,
                            size < declared ? "truncated" : "bytes appended or size corrupt");
    if (size < hsize + 4)
        return SCN_LOD_FAIL(24, "declared size %llu is too small for the %u-byte header and the CRC",
                            (unsigned long long)size, hsize);
    /* The checksum next: past it, a wrong field is a wrong writer, not a damaged file. */
    uint32_t stored = hl_le_get_u32(b + size - 4), computed = scn_crc32(b, (size_t)(size - 4));
    if (stored != computed)
        return SCN_LOD_FAIL(size - 4, "CRC-32 mismatch (stored 0x%08x, computed 0x%08x): the file is damaged",
                            stored, computed);

    uint32_t flags = hl_le_get_u32(b + 12);
    if (flags != 0)
        return SCN_LOD_FAIL(12, "unknown flags 0x%08x (version %u defines none)", flags, version);
    uint32_t levels = hl_le_get_u32(b + 20);
    if (levels < 1 || levels > SCN_LODSET_MAX_LEVELS)
        return SCN_LOD_FAIL(20, "%u levels (1…%d)", levels, SCN_LODSET_MAX_LEVELS);
    if (hsize + (uint64_t)rsize * levels + 4 > size)
        return SCN_LOD_FAIL(20, "%u level records do not fit in the %llu-byte file", levels, (unsigned long long)size);

    const unsigned char *name = b + 32;
    size_t name_len = strnlen((const char *)name, 16);
    if (name_len == 16)
        return SCN_LOD_FAIL(32, "simplifier name is not NUL-terminated within 16 bytes");
    for (size_t i = 0; i < 16; ++i)
        if (i < name_len ? (name[i] < 0x21 || name[i] > 0x7e) : name[i] != 0)
            return SCN_LOD_FAIL(32 + i, "simplifier name: byte 0x%02x is not %s", name[i],
                                i < name_len ? "printable ASCII" : "NUL padding");
    double bounds[10]; /* centre 3, radius, min 3, max 3 at bytes 56 … 135 */
    for (int i = 0; i < 10; ++i) {
        bounds[i] = hl_le_get_f64(b + 56 + 8 * i);
        if (!isfinite(bounds[i]))
            return SCN_LOD_FAIL(56 + 8 * i, "bounds: %g is not finite", bounds[i]);
    }
    if (bounds[3] < 0)
        return SCN_LOD_FAIL(80, "negative bounding radius %g", bounds[3]);
    for (int k = 0; k < 3; ++k)
        if (bounds[4 + k] > bounds[7 + k])
            return SCN_LOD_FAIL(88 + 8 * k, "bounding box min %g > max %g on axis %d", bounds[4 + k], bounds[7 + k], k);
    uint32_t views = hl_le_get_u32(b + 136), view_px = hl_le_get_u32(b + 140);
    if (views > INT_MAX)
        return SCN_LOD_FAIL(136, "analysis view count %u too large", views);
    if (view_px > INT_MAX)
        return SCN_LOD_FAIL(140, "analysis size %u px too large", view_px);
    uint32_t bands = 0;
    double percentile = 0.0;
    if (version >= 2) { /* the spectrum's header tail */
        bands = hl_le_get_u32(b + 144);
        if (bands > SCN_LODSET_MAX_BANDS)
            return SCN_LOD_FAIL(144, "%u contrast bands (0…%d)", bands, SCN_LODSET_MAX_BANDS);
        if (hl_le_get_u32(b + 148) != 0)
            return SCN_LOD_FAIL(148, "reserved field 0x%08x is not 0", hl_le_get_u32(b + 148));
        percentile = hl_le_get_f64(b + 152);
        if (bands ? !(percentile > 0 && percentile <= 100) : percentile != 0)
            return SCN_LOD_FAIL(152, "contrast percentile %g (%s)", percentile,
                                bands ? "in (0, 100] with bands" : "0 without bands");
    }

    uint32_t tris[SCN_LODSET_MAX_LEVELS], verts[SCN_LODSET_MAX_LEVELS];
    for (uint32_t l = 0; l < levels; ++l) {
        const unsigned char *r = b + hsize + rsize * l;
        uint64_t ro = hsize + rsize * (uint64_t)l;
        tris[l] = hl_le_get_u32(r);
        verts[l] = hl_le_get_u32(r + 4);
        if (tris[l] < 1 || tris[l] > UINT32_MAX / 3)
            return SCN_LOD_FAIL(ro, "level %u: %u triangles (1…%u)", l, tris[l], UINT32_MAX / 3);
        if (l > 0 && tris[l] >= tris[l - 1])
            return SCN_LOD_FAIL(ro, "level %u has %u triangles, not fewer than level %u's %u", l, tris[l], l - 1,
                                tris[l - 1]);
        if (verts[l] < 3)
            return SCN_LOD_FAIL(ro + 4, "level %u: %u vertices (at least 3)", l, verts[l]);
    }
    struct scn_lod_layout lay;
    scn_lod_layout(version, (int)levels, tris, verts, &lay);
    for (uint32_t l = 0; l < levels; ++l) {
        uint64_t ro = hsize + rsize * (uint64_t)l;
        const unsigned char *r = b + ro;
        uint64_t want[3] = {lay.positions[l], lay.normals[l], lay.indices[l]};
        static const char *const what[3] = {"positions", "normals", "indices"};
        for (int k = 0; k < 3; ++k) {
            uint64_t at = hl_le_get_u64(r + 8 + 8 * k);
            if (at != want[k])
                return SCN_LOD_FAIL(ro + 8 + 8 * k, "level %u: %s at byte %llu, the layout puts them at %llu", l,
                                    what[k], (unsigned long long)at, (unsigned long long)want[k]);
        }
        uint64_t end = lay.indices[l] + 12 * (uint64_t)tris[l];
        if (end > size - 4)
            return SCN_LOD_FAIL(ro, "level %u: %u triangles and %u vertices need bytes up to %llu, past the file's "
                                    "%llu", l, tris[l], verts[l], (unsigned long long)end, (unsigned long long)size);
        double e[5];
        for (int k = 0; k < 5; ++k)
            e[k] = hl_le_get_f64(r + 32 + 8 * k);
        if (!isfinite(e[0]) || e[0] < 0)
            return SCN_LOD_FAIL(ro + 32, "level %u: error %g m is not finite and ≥ 0", l, e[0]);
        if (!isfinite(e[1]) || e[1] < 0)
            return SCN_LOD_FAIL(ro + 40, "level %u: relative error %g is not finite and ≥ 0", l, e[1]);
        for (int k = 2; k < 5; ++k)
            if (!scn_lod_freq_ok(e[k], (int)l))
                return SCN_LOD_FAIL(ro + 8 * (4 + k), "level %u: frequency %g c/diam (NaN, or > 0 and finite%s)", l,
                                    e[k], l == 0 ? ", or +inf" : "; +inf only at level 0");
        for (uint32_t k = 0; version >= 2 && k < SCN_LODSET_MAX_BANDS; ++k) {
            uint64_t oc = ro + SCN_LOD_RECORD_SIZE + 8 * (uint64_t)k;
            double c = hl_le_get_f64(b + oc);
            if (k >= bands && c != 0) /* zero bits too: -0.0 is not padding */
                return SCN_LOD_FAIL(oc, "level %u: contrast band %u: %g beyond the %u bands (must be 0)", l, k, c, bands);
            if (k < bands && l == 0 && c != 0)
                return SCN_LOD_FAIL(oc, "level 0: contrast band %u: %g (level 0 loses nothing: 0)", k, c);
            if (k < bands && !scn_lod_contrast_ok(c))
                return SCN_LOD_FAIL(oc, "level %u: contrast band %u: %g (NaN, or finite and ≥ 0)", l, k, c);
            if (k >= bands && hl_le_get_u64(b + oc) != 0)
                return SCN_LOD_FAIL(oc, "level %u: contrast band %u: not zero bytes beyond the %u bands", l, k, bands);
        }
    }
    if (lay.file_size != size)
        return SCN_LOD_FAIL(24, "file size %llu, the level counts give %llu", (unsigned long long)size,
                            (unsigned long long)lay.file_size);

    /* The arrays: finite floats, indices inside their level. Decoded as they are checked. */
    if (out) {
        out->level_count = (int)levels;
        for (uint32_t l = 0; l < levels; ++l) {
            struct scn_mesh *m = &out->levels[l];
            m->positions = malloc(12 * (size_t)verts[l]);
            m->normals = malloc(12 * (size_t)verts[l]);
            m->indices = malloc(12 * (size_t)tris[l]);
            if (!m->positions || !m->normals || !m->indices)
                return hl_fail(err, "%s: out of memory for level %u (%u vertices)", label, l, verts[l]);
            m->vertex_count = m->vertex_cap = verts[l];
            m->index_count = m->index_cap = 3 * tris[l];
        }
    }
    for (uint32_t l = 0; l < levels; ++l) {
        struct scn_mesh *m = out ? &out->levels[l] : NULL;
        for (uint64_t i = 0; i < 3 * (uint64_t)verts[l]; ++i) {
            uint64_t op = lay.positions[l] + 4 * i, on = lay.normals[l] + 4 * i;
            float p = hl_le_get_f32(b + op), nrm = hl_le_get_f32(b + on);
            if (!isfinite(p))
                return SCN_LOD_FAIL(op, "level %u: vertex %llu: position %g is not finite", l,
                                    (unsigned long long)(i / 3), p);
            if (!isfinite(nrm))
                return SCN_LOD_FAIL(on, "level %u: vertex %llu: normal %g is not finite", l,
                                    (unsigned long long)(i / 3), nrm);
            if (m)
                m->positions[i] = p, m->normals[i] = nrm;
        }
        for (uint64_t i = 0; i < 3 * (uint64_t)tris[l]; ++i) {
            uint64_t oi = lay.indices[l] + 4 * i;
            uint32_t v = hl_le_get_u32(b + oi);
            if (v >= verts[l])
                return SCN_LOD_FAIL(oi, "level %u: triangle %llu: index %u, the level has %u vertices", l,
                                    (unsigned long long)(i / 3), v, verts[l]);
            if (m)
                m->indices[i] = v;
        }
    }
    if (out) {
        for (uint32_t l = 0; l < levels; ++l) {
            const unsigned char *r = b + hsize + rsize * l;
            for (uint32_t k = 0; k < bands; ++k)
                out->lost_contrast[l][k] = hl_le_get_f64(r + SCN_LOD_RECORD_SIZE + 8 * k);
            out->error_m[l] = hl_le_get_f64(r + 32);
            out->error_rel[l] = hl_le_get_f64(r + 40);
            out->freq[l] = (struct scn_level_freq){hl_le_get_f64(r + 48), hl_le_get_f64(r + 56), hl_le_get_f64(r + 64)};
        }
        memcpy(out->simplifier, name, 16);
        out->source_hash = hl_le_get_u64(b + 48);
        for (int k = 0; k < 3; ++k) {
            out->center_m[k] = bounds[k];
            out->aabb_min_m[k] = bounds[4 + k];
            out->aabb_max_m[k] = bounds[7 + k];
        }
        out->radius_m = bounds[3];
        out->analysis_views = (int)views;
        out->analysis_size_px = (int)view_px;
        out->contrast_band_count = (int)bands;
        out->contrast_percentile = percentile;
    }
    return 0;
}

/* ---- reading ---------------------------------------------------------------------------------- */
int scn_lodfile_read(const char *path, struct scn_lodset *out, struct hl_error *err)
{
    if (!out)
        return hl_fail(err, "lodfile: no output");
    *out = (struct scn_lodset){0};
    if (!path)
        return hl_fail(err, "lodfile: no path");
    /* base/file.c: a FIFO or device is refused before it can block; at most the 2 GiB a .lod holds. */
    char *text = NULL;
    size_t size = 0;
    if (hl_file_read_all(path, SCN_LOD_MAX_BYTES, &text, &size, err) != 0)
        return -1;
    unsigned char *buf = (unsigned char *)text;
    int rc = scn_lod_parse(buf, size, path, out, err);
    free(buf);
    if (rc != 0)
        scn_lodset_free(out); /* frees what was decoded and zeroes *out */
    return rc;
}

/* ---- writing ---------------------------------------------------------------------------------- */
static int scn_lod_encode(const char *path, const struct scn_lodset *set, unsigned char **out_buf,
                          uint64_t *out_size, struct hl_error *err)
{
    if (set->level_count < 1 || set->level_count > SCN_LODSET_MAX_LEVELS)
        return hl_fail(err, "%s: %d levels (1…%d)", path, set->level_count, SCN_LODSET_MAX_LEVELS);
    uint32_t tris[SCN_LODSET_MAX_LEVELS], verts[SCN_LODSET_MAX_LEVELS];
    for (int l = 0; l < set->level_count; ++l) {
        const struct scn_mesh *m = &set->levels[l];
        if (m->failed)
            return hl_fail(err, "%s: level %d: its mesh ran out of memory while being built", path, l);
        if (m->index_count % 3 != 0)
            return hl_fail(err, "%s: level %d: %u indices, not a multiple of 3", path, l, m->index_count);
        if ((m->vertex_count && (!m->positions || !m->normals)) || (m->index_count && !m->indices))
            return hl_fail(err, "%s: level %d: missing arrays", path, l);
        tris[l] = m->index_count / 3;
        verts[l] = m->vertex_count;
    }
    if (set->contrast_band_count < 0 || set->contrast_band_count > SCN_LODSET_MAX_BANDS)
        return hl_fail(err, "%s: %d contrast bands (0…%d)", path, set->contrast_band_count, SCN_LODSET_MAX_BANDS);
    uint32_t version = set->contrast_band_count > 0 ? 2 : 1; /* the oldest version that holds the set */
    uint32_t hsize = scn_lod_header_size(version), rsize = scn_lod_record_size(version);
    struct scn_lod_layout lay;
    scn_lod_layout(version, set->level_count, tris, verts, &lay);
    if (lay.file_size > SCN_LOD_MAX_BYTES)
        return hl_fail(err, "%s: %llu bytes, more than the 2 GiB a .lod file may hold", path,
                       (unsigned long long)lay.file_size);
    unsigned char *b = calloc(1, (size_t)lay.file_size); /* padding stays zero */
    if (!b)
        return hl_fail(err, "%s: out of memory for %llu bytes", path, (unsigned long long)lay.file_size);
    memcpy(b, scn_lod_magic, 8);
    hl_le_put_u32(b + 8, version);
    hl_le_put_u32(b + 12, 0);
    hl_le_put_u32(b + 16, hsize);
    hl_le_put_u32(b + 20, (uint32_t)set->level_count);
    hl_le_put_u64(b + 24, lay.file_size);
    memcpy(b + 32, set->simplifier, strnlen(set->simplifier, 15)); /* at most 15 + NUL */
    hl_le_put_u64(b + 48, set->source_hash);
    for (int k = 0; k < 3; ++k) {
        hl_le_put_f64(b + 56 + 8 * k, set->center_m[k]);
        hl_le_put_f64(b + 88 + 8 * k, set->aabb_min_m[k]);
        hl_le_put_f64(b + 112 + 8 * k, set->aabb_max_m[k]);
    }
    hl_le_put_f64(b + 80, set->radius_m);
    hl_le_put_u32(b + 136, set->analysis_views < 0 ? UINT32_MAX : (uint32_t)set->analysis_views);
    hl_le_put_u32(b + 140, set->analysis_size_px < 0 ? UINT32_MAX : (uint32_t)set->analysis_size_px);
    if (version >= 2) { /* reserved u32 at 148 stays 0 */
        hl_le_put_u32(b + 144, (uint32_t)set->contrast_band_count);
        hl_le_put_f64(b + 152, set->contrast_percentile);
    }
    for (int l = 0; l < set->level_count; ++l) {
        const struct scn_mesh *m = &set->levels[l];
        unsigned char *r = b + hsize + rsize * l;
        for (int k = 0; version >= 2 && k < set->contrast_band_count; ++k)
            hl_le_put_f64(r + SCN_LOD_RECORD_SIZE + 8 * k, set->lost_contrast[l][k]);
        hl_le_put_u32(r, tris[l]);
        hl_le_put_u32(r + 4, verts[l]);
        hl_le_put_u64(r + 8, lay.positions[l]);
        hl_le_put_u64(r + 16, lay.normals[l]);
        hl_le_put_u64(r + 24, lay.indices[l]);
        hl_le_put_f64(r + 32, set->error_m[l]);
        hl_le_put_f64(r + 40, set->error_rel[l]);
        hl_le_put_f64(r + 48, set->freq[l].narrow_cpdiam);
        hl_le_put_f64(r + 56, set->freq[l].long_cpdiam);
        hl_le_put_f64(r + 64, set->freq[l].geometric_cpdiam);
        for (size_t i = 0; i < 3 * (size_t)verts[l]; ++i) {
            hl_le_put_f32(b + lay.positions[l] + 4 * i, m->positions[i]);
            hl_le_put_f32(b + lay.normals[l] + 4 * i, m->normals[i]);
        }
        for (size_t i = 0; i < 3 * (size_t)tris[l]; ++i)
            hl_le_put_u32(b + lay.indices[l] + 4 * i, m->indices[i]);
    }
    hl_le_put_u32(b + lay.crc_offset, scn_crc32(b, (size_t)lay.crc_offset));
    *out_buf = b;
    *out_size = lay.file_size;
    return 0;
}

int scn_lodfile_write(const char *path, const struct scn_lodset *set, struct hl_error *err)
{
    if (!path || !set)
        return hl_fail(err, "lodfile: no path or no lodset");
    unsigned char *b = NULL;
    uint64_t size = 0;
    if (scn_lod_encode(path, set, &b, &size, err) != 0)
        return -1;
    /* The reader's checks on the encoded bytes: a lodset the reader would refuse is never written. */
    char label[600];
    snprintf(label, sizeof label, "%s (refusing to write)", path);
    if (scn_lod_parse(b, size, label, NULL, err) != 0) {
        free(b);
        return -1;
    }
    /* hl_out: a temporary beside path, fsync'd and renamed, so no reader sees half a .lod. */
    struct hl_error werr;
    int rc = hl_out_write_all(path, b, (size_t)size, &werr);
    free(b);
    if (rc != 0) /* hl_out left whatever was at path as it was */
        return hl_fail(err, "%s (nothing written)", werr.msg);
    return 0;
}
