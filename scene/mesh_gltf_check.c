/* scene/mesh_gltf_check.c: a glTF 2.0 file checked before assimp 5.2 reads it. assimp trusts the
 * file where the spec bounds it (each found by fuzz_mesh_import):
 *  - it picks its importer by content, not by our extension: an OFF file named .gltf went to its OFF
 *    importer, whose triangulation asserts. So a .glb must start with "glTF" and a .gltf with '{'.
 *  - it allocates a .glb chunk's stated length before reading it (a 644-byte file asked for 1.7 GB):
 *    the header's length must be the file's size and every chunk must lie inside it.
 *  - it fills a sparse accessor from its indices and values without checking that their buffer
 *    views hold sparse.count entries (a heap overflow), and allocates count × element size for an
 *    accessor without a buffer view before reading anything (a 700-byte file asked for 4.8 GB).
 * So the JSON is parsed here (cJSON) and every accessor, buffer view and buffer is held to the
 * spec's bounds (glTF 2.0 §3.6 "Binary data storage", §5.1 accessor, §5.2 sparse): elements inside
 * their buffer view, views inside their buffer, sparse counts ≤ the accessor's, and the zero-filled
 * accessors (no buffer view) together ≤ GLTF_ZERO_FILL_MAX bytes. Each error names the object. */
#include "scene/lodgen_internal.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

/* Accessors without a buffer view are zeros that assimp allocates in full: 256 MiB together is
 * 16 million VEC4 floats, far above a morph target of any mesh this tool decimates. */
#define GLTF_ZERO_FILL_MAX (256.0 * 1024 * 1024)
#define GLTF_COUNT_MAX 2147483647.0 /* counts and lengths assimp keeps in 32-bit fields */
enum { GLB_JSON = 0x4E4F534A };     /* chunk type "JSON" */

/* A .glb's header and chunk headers; the first chunk (JSON, by the spec) is read into *json. */
static int glb_read_json(FILE *f, const char *path, uint64_t file_size, char **json, size_t *json_len,
                         struct hl_error *err)
{
    unsigned char h[12];
    if (fread(h, 1, 12, f) != 12 || memcmp(h, "glTF", 4) != 0)
        return hl_fail(err, "%s: not a binary glTF file (no \"glTF\" magic)", path);
    if (hl_le_get_u32(h + 4) != 2)
        return hl_fail(err, "%s: binary glTF version %u: only version 2 is supported", path, hl_le_get_u32(h + 4));
    uint64_t length = hl_le_get_u32(h + 8);
    if (length != file_size)
        return hl_fail(err, "%s: binary glTF header says %llu bytes, the file has %llu", path,
                       (unsigned long long)length, (unsigned long long)file_size);
    int chunks = 0;
    for (uint64_t at = 12; at < length; ++chunks) {
        if (length - at < 8 || fread(h, 1, 8, f) != 8)
            return hl_fail(err, "%s: byte %llu: binary glTF chunk header cut short", path, (unsigned long long)at);
        uint64_t n = hl_le_get_u32(h);
        if (n > length - at - 8)
            return hl_fail(err, "%s: byte %llu: binary glTF chunk of %llu bytes runs past the end of the file", path,
                           (unsigned long long)at, (unsigned long long)n);
        if (chunks == 0) {
            if (hl_le_get_u32(h + 4) != GLB_JSON)
                return hl_fail(err, "%s: byte %llu: the first binary glTF chunk is not JSON", path,
                               (unsigned long long)at);
            *json = malloc((size_t)n + 1);
            if (!*json)
                return hl_fail(err, "%s: out of memory for a %llu-byte JSON chunk", path, (unsigned long long)n);
            if (fread(*json, 1, (size_t)n, f) != n)
                return hl_fail(err, "%s: cannot read the JSON chunk", path);
            (*json)[n] = 0;
            *json_len = (size_t)n;
        } else if (fseeko(f, (off_t)n, SEEK_CUR) != 0) {
            return hl_fail(err, "%s: cannot seek", path);
        }
        at += 8 + n;
    }
    return chunks > 0 ? 0 : hl_fail(err, "%s: binary glTF file without chunks", path);
}

/* A .gltf: the whole file is its JSON, starting with '{' after an optional byte order mark. */
static int gltf_read_json(const char *path, char **json, size_t *json_len, struct hl_error *err)
{
    if (hl_file_read_all(path, 0, json, json_len, err) != 0)
        return -1;
    size_t i = 0;
    const unsigned char *t = (const unsigned char *)*json;
    if (*json_len >= 3 && t[0] == 0xEF && t[1] == 0xBB && t[2] == 0xBF)
        i = 3;
    while (i < *json_len && (t[i] == ' ' || t[i] == '\t' || t[i] == '\r' || t[i] == '\n'))
        ++i;
    return i < *json_len && t[i] == '{' ? 0 : hl_fail(err, "%s: not a glTF file (JSON starting with '{')", path);
}

/* An optional whole number in [0, max] (absent: *out = def); -1 with the error otherwise. */
static int gltf_whole(const cJSON *obj, const char *key, double def, double max, double *out, const char *path,
                      const char *what, int index, struct hl_error *err)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!it) {
        *out = def;
        return 0;
    }
    double v = cJSON_IsNumber(it) ? it->valuedouble : -1;
    if (!(v >= 0 && v <= max && v == (double)(long long)v))
        return hl_fail(err, "%s: glTF %s %d: \"%s\" must be a whole number in 0 … %.0f", path, what, index, key, max);
    *out = v;
    return 0;
}

static const cJSON *gltf_array(const cJSON *root, const char *key)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(root, key);
    return cJSON_IsArray(a) ? a : NULL;
}

static int gltf_component_bytes(double type)
{
    switch ((int)type) {
    case 5120: case 5121: return 1; /* (unsigned) byte */
    case 5122: case 5123: return 2; /* (unsigned) short */
    case 5125: case 5126: return 4; /* unsigned int, float */
    default: return 0;
    }
}

static int gltf_type_components(const cJSON *type)
{
    static const char *const names[] = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"};
    static const int counts[] = {1, 2, 3, 4, 4, 9, 16};
    for (int i = 0; i < 7 && cJSON_IsString(type); ++i)
        if (!strcmp(type->valuestring, names[i]))
            return counts[i];
    return 0;
}

/* Buffer views inside their buffers; each view's length into view_len[], its byteStride (0: none)
 * into view_stride[]. */
static int gltf_check_views(const cJSON *root, const char *path, double *view_len, double *view_stride,
                            struct hl_error *err)
{
    const cJSON *buffers = gltf_array(root, "buffers"), *views = gltf_array(root, "bufferViews");
    int nb = cJSON_GetArraySize(buffers), i = 0;
    for (const cJSON *v = views ? views->child : NULL; v; v = v->next, ++i) {
        double b, off, len, stride, blen;
        if (gltf_whole(v, "buffer", -1, GLTF_COUNT_MAX, &b, path, "bufferView", i, err) != 0 ||
            gltf_whole(v, "byteOffset", 0, GLTF_COUNT_MAX, &off, path, "bufferView", i, err) != 0 ||
            gltf_whole(v, "byteLength", -1, GLTF_COUNT_MAX, &len, path, "bufferView", i, err) != 0 ||
            gltf_whole(v, "byteStride", 0, 252, &stride, path, "bufferView", i, err) != 0)
            return -1;
        if (b < 0 || b >= nb || len < 1)
            return hl_fail(err, "%s: glTF bufferView %d: needs a buffer (0 … %d) and a byteLength ≥ 1", path, i,
                           nb - 1);
        if (gltf_whole(cJSON_GetArrayItem(buffers, (int)b), "byteLength", -1, GLTF_COUNT_MAX, &blen, path, "buffer",
                       (int)b, err) != 0)
            return -1;
        if (blen < 1)
            return hl_fail(err, "%s: glTF buffer %.0f: needs a byteLength ≥ 1", path, b);
        if (off + len > blen)
            return hl_fail(err, "%s: glTF bufferView %d: bytes %.0f … %.0f lie outside buffer %.0f's %.0f", path, i,
                           off, off + len, b, blen);
        if (stride != 0 && stride < 4)
            return hl_fail(err, "%s: glTF bufferView %d: byteStride %.0f (4 … 252)", path, i, stride);
        view_len[i] = len;
        view_stride[i] = stride;
    }
    return 0;
}

/* n elements of elem_bytes at the object's byteOffset inside its bufferView, the view's byteStride
 * apart (view_stride NULL or 0: packed, as sparse indices and values always are). */
static int gltf_fits_view(const cJSON *where, const char *path, const char *what, int index, double n,
                          double elem_bytes, int views, const double *view_len, const double *view_stride,
                          struct hl_error *err)
{
    double view, off;
    if (gltf_whole(where, "bufferView", -1, GLTF_COUNT_MAX, &view, path, what, index, err) != 0 ||
        gltf_whole(where, "byteOffset", 0, GLTF_COUNT_MAX, &off, path, what, index, err) != 0)
        return -1;
    if (view < 0 || view >= views)
        return hl_fail(err, "%s: glTF %s %d: bufferView %.0f does not exist (%d views)", path, what, index, view,
                       views);
    double stride = view_stride && view_stride[(int)view] > 0 ? view_stride[(int)view] : elem_bytes;
    double end = off + (n - 1) * stride + elem_bytes;
    if (end > view_len[(int)view])
        return hl_fail(err, "%s: glTF %s %d: %.0f elements of %.0f bytes need %.0f bytes of bufferView %.0f, which "
                       "has %.0f", path, what, index, n, elem_bytes, end, view, view_len[(int)view]);
    return 0;
}

static int gltf_check_accessors(const cJSON *root, const char *path, int views, const double *view_len,
                                const double *view_stride, struct hl_error *err)
{
    double zero_fill = 0;
    int i = 0;
    const cJSON *accessors = gltf_array(root, "accessors");
    for (const cJSON *a = accessors ? accessors->child : NULL; a; a = a->next, ++i) {
        double count, ctype;
        if (gltf_whole(a, "count", 0, GLTF_COUNT_MAX, &count, path, "accessor", i, err) != 0 ||
            gltf_whole(a, "componentType", 0, 65535, &ctype, path, "accessor", i, err) != 0)
            return -1;
        int comps = gltf_type_components(cJSON_GetObjectItemCaseSensitive(a, "type"));
        double elem = (double)gltf_component_bytes(ctype) * comps;
        if (count < 1 || elem == 0)
            return hl_fail(err, "%s: glTF accessor %d: needs a count ≥ 1, a componentType and a type", path, i);
        if (cJSON_GetObjectItemCaseSensitive(a, "bufferView")) {
            if (gltf_fits_view(a, path, "accessor", i, count, elem, views, view_len, view_stride, err) != 0)
                return -1;
        } else if ((zero_fill += count * elem) > GLTF_ZERO_FILL_MAX) {
            return hl_fail(err, "%s: glTF accessor %d: accessors without a bufferView add up to %.0f bytes of zeros "
                           "(at most %.0f)", path, i, zero_fill, GLTF_ZERO_FILL_MAX);
        }
        const cJSON *sparse = cJSON_GetObjectItemCaseSensitive(a, "sparse");
        if (!sparse)
            continue;
        double n, itype;
        const cJSON *idx = cJSON_GetObjectItemCaseSensitive(sparse, "indices");
        const cJSON *val = cJSON_GetObjectItemCaseSensitive(sparse, "values");
        if (gltf_whole(sparse, "count", 0, GLTF_COUNT_MAX, &n, path, "sparse accessor", i, err) != 0 ||
            gltf_whole(idx, "componentType", 0, 65535, &itype, path, "sparse accessor", i, err) != 0)
            return -1;
        int ibytes = gltf_component_bytes(itype);
        if (n < 1 || n > count || !cJSON_IsObject(idx) || !cJSON_IsObject(val) ||
            (itype != 5121 && itype != 5123 && itype != 5125))
            return hl_fail(err, "%s: glTF accessor %d: sparse needs a count 1 … %.0f, indices of an unsigned "
                           "componentType and values", path, i, count);
        if (gltf_fits_view(idx, path, "sparse indices of accessor", i, n, ibytes, views, view_len, NULL, err) != 0 ||
            gltf_fits_view(val, path, "sparse values of accessor", i, n, elem, views, view_len, NULL, err) != 0)
            return -1;
    }
    return 0;
}

int scn_gltf_check(const char *path, int glb, uint64_t file_size, struct hl_error *err)
{
    char *json = NULL;
    size_t len = 0;
    int rc;
    if (glb) {
        FILE *f = fopen(path, "rb");
        if (!f)
            return hl_fail(err, "%s: cannot open: %s", path, strerror(errno));
        rc = glb_read_json(f, path, file_size, &json, &len, err);
        fclose(f);
    } else {
        rc = gltf_read_json(path, &json, &len, err);
    }
    cJSON *root = NULL;
    if (rc == 0 && !cJSON_IsObject(root = cJSON_ParseWithLength(json, len)))
        rc = hl_fail(err, "%s: the glTF JSON does not parse (or is not an object)", path);
    free(json);
    int views = rc == 0 ? cJSON_GetArraySize(gltf_array(root, "bufferViews")) : 0;
    double *view_len = rc == 0 ? calloc((size_t)views + 1, sizeof *view_len) : NULL;
    double *view_stride = rc == 0 ? calloc((size_t)views + 1, sizeof *view_stride) : NULL;
    if (rc == 0 && (!view_len || !view_stride))
        rc = hl_fail(err, "%s: out of memory", path);
    if (rc == 0)
        rc = gltf_check_views(root, path, view_len, view_stride, err);
    if (rc == 0)
        rc = gltf_check_accessors(root, path, views, view_len, view_stride, err);
    free(view_len);
    free(view_stride);
    cJSON_Delete(root);
    return rc;
}
