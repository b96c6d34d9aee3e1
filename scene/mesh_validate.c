/* From a reader's raw soup to a mesh hmdlod can trust: finite coordinates, exact-position welding,
 * no zero-area faces, normals. Every refusal names the file and the vertex or face (1-based, in the
 * file's order) and says why; non-manifold edges are counted and kept (a warning, not an error:
 * real scans such as beetle.obj have them and still render and decimate). */
#include "scene/lodgen_internal.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

void scn_soup_free(struct scn_soup *s)
{
    if (!s)
        return;
    free(s->positions);
    free(s->normals);
    free(s->indices);
    free(s->face_of_tri);
    memset(s, 0, sizeof *s);
}

static int soup_grow(struct scn_soup *s, uint32_t more)
{
    if (s->triangle_count + (uint64_t)more <= s->triangle_cap)
        return 0;
    uint64_t cap = s->triangle_cap ? s->triangle_cap : 1024;
    while (cap < s->triangle_count + (uint64_t)more)
        cap *= 2;
    if (cap > UINT32_MAX / 3)
        return -1;
    uint32_t *idx = realloc(s->indices, (size_t)cap * 3 * sizeof *idx);
    if (!idx)
        return -1;
    s->indices = idx;
    uint32_t *fot = realloc(s->face_of_tri, (size_t)cap * sizeof *fot);
    if (!fot)
        return -1;
    s->face_of_tri = fot;
    s->triangle_cap = (uint32_t)cap;
    return 0;
}

static double soup_dist2(const struct scn_soup *s, uint32_t a, uint32_t b)
{
    const double *p = s->positions + 3 * (size_t)a, *q = s->positions + 3 * (size_t)b;
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return dx * dx + dy * dy + dz * dz;
}

static void soup_push(struct scn_soup *s, uint32_t a, uint32_t b, uint32_t c, uint32_t face)
{
    uint32_t *t = s->indices + 3 * (size_t)s->triangle_count;
    t[0] = a, t[1] = b, t[2] = c;
    s->face_of_tri[s->triangle_count++] = face;
}

void scn_soup_add_face(struct scn_soup *s, const uint32_t *idx, uint32_t n)
{
    uint32_t face = s->faces_read++;
    if (s->failed)
        return;
    int bad = n < 3;
    for (uint32_t i = 0; i < n && !bad; ++i)
        bad = idx[i] >= s->vertex_count;
    if (bad) {
        if (s->bad_index_faces++ == 0)
            s->first_bad_index_face = face;
        return;
    }
    if (soup_grow(s, n - 2) != 0) {
        s->failed = 1;
        return;
    }
    if (n > 3)
        s->polygons_triangulated++;
    if (n == 4 && soup_dist2(s, idx[1], idx[3]) < soup_dist2(s, idx[0], idx[2])) {
        soup_push(s, idx[0], idx[1], idx[3], face);
        soup_push(s, idx[1], idx[2], idx[3], face);
        return;
    }
    for (uint32_t i = 1; i + 1 < n; ++i)
        soup_push(s, idx[0], idx[i], idx[i + 1], face);
}

/* ---- exact welding: open-addressing hash on the float bit patterns --------------------------- */

static uint32_t float_bits(float f)
{
    if (f == 0.0f) /* −0 and +0 are the same place */
        f = 0.0f;
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static uint64_t pos_hash(const float *p)
{
    uint64_t h = 1469598103934665603ull; /* FNV-1a over the three bit patterns */
    for (int k = 0; k < 3; ++k) {
        uint32_t u = float_bits(p[k]);
        for (int b = 0; b < 4; ++b)
            h = (h ^ ((u >> (8 * b)) & 0xffu)) * 1099511628211ull;
    }
    return h;
}

static int pos_equal(const float *p, const float *q)
{
    return float_bits(p[0]) == float_bits(q[0]) && float_bits(p[1]) == float_bits(q[1]) &&
           float_bits(p[2]) == float_bits(q[2]);
}

/* remap[v] = the first vertex at v's exact position; returns the number of distinct positions
 * among the n vertices, or −1 when out of memory. */
static long weld_remap(const float *pos, uint32_t n, uint32_t *remap)
{
    size_t cap = 16;
    while (cap < 2 * (size_t)n)
        cap *= 2;
    uint32_t *table = malloc(cap * sizeof *table);
    if (!table)
        return -1;
    memset(table, 0xff, cap * sizeof *table);
    long unique = 0;
    for (uint32_t v = 0; v < n; ++v) {
        const float *p = pos + 3 * (size_t)v;
        size_t slot = (size_t)pos_hash(p) & (cap - 1);
        for (;;) {
            uint32_t w = table[slot];
            if (w == UINT32_MAX) {
                table[slot] = v;
                remap[v] = v;
                ++unique;
                break;
            }
            if (pos_equal(p, pos + 3 * (size_t)w)) {
                remap[v] = w;
                break;
            }
            slot = (slot + 1) & (cap - 1);
        }
    }
    free(table);
    return unique;
}

static double tri_area2(const float *pos, const uint32_t *t)
{
    const float *a = pos + 3 * (size_t)t[0], *b = pos + 3 * (size_t)t[1], *c = pos + 3 * (size_t)t[2];
    hl_vec3d pa = hl_v3(a[0], a[1], a[2]);
    hl_vec3d u = hl_v3_sub(hl_v3(b[0], b[1], b[2]), pa), w = hl_v3_sub(hl_v3(c[0], c[1], c[2]), pa);
    return hl_v3_length(hl_v3_cross(u, w));
}

/* A face is degenerate when its area is zero up to float rounding of its own edges: |u×w| ≤
 * 1e-12·(longest edge)² catches exact repeats and collinear triples, not legitimate slivers. */
static int tri_degenerate(const float *pos, const uint32_t *t)
{
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
        return 1;
    double longest = 0;
    for (int e = 0; e < 3; ++e) {
        const float *p = pos + 3 * (size_t)t[e], *q = pos + 3 * (size_t)t[(e + 1) % 3];
        double d = hl_v3_length(hl_v3((double)p[0] - q[0], (double)p[1] - q[1], (double)p[2] - q[2]));
        longest = d > longest ? d : longest;
    }
    return !(tri_area2(pos, t) > 1e-12 * longest * longest);
}

/* Keeps the referenced vertices (in first-use order), welds and drops degenerate triangles;
 * face_of_tri (may be NULL) is compacted alongside. Returns the number of vertices merged. */
static long weld_compact(struct scn_mesh *m, uint32_t *face_of_tri, uint32_t *dropped, uint32_t *first_dropped)
{
    uint32_t n = m->vertex_count;
    uint32_t *remap = malloc(((size_t)n + 1) * sizeof *remap);
    uint32_t *newidx = malloc(((size_t)n + 1) * sizeof *newidx);
    if (!remap || !newidx) {
        free(remap);
        free(newidx);
        return -1;
    }
    if (weld_remap(m->positions, n, remap) < 0) {
        free(remap);
        free(newidx);
        return -1;
    }
    memset(newidx, 0xff, ((size_t)n + 1) * sizeof *newidx);
    uint32_t out_v = 0, out_t = 0, drop = 0;
    long used_before = 0, distinct = 0;
    uint8_t *seen = calloc((size_t)n + 1, 1);
    if (!seen) {
        free(remap);
        free(newidx);
        return -1;
    }
    for (uint32_t t = 0; t < m->index_count / 3; ++t) {
        uint32_t tri[3];
        for (int k = 0; k < 3; ++k) {
            uint32_t v = m->indices[3 * (size_t)t + k];
            if (!(seen[v] & 1)) {
                seen[v] |= 1;
                ++used_before;
            }
            tri[k] = remap[v];
            if (!(seen[tri[k]] & 2)) {
                seen[tri[k]] |= 2;
                ++distinct;
            }
        }
        if (tri_degenerate(m->positions, tri)) {
            if (drop++ == 0 && first_dropped)
                *first_dropped = face_of_tri ? face_of_tri[t] : t;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            uint32_t r = tri[k];
            if (newidx[r] == UINT32_MAX)
                newidx[r] = out_v++;
            /* In place: out_t ≤ t and this triangle's indices were read into tri[] already. */
            m->indices[3 * (size_t)out_t + k] = newidx[r];
        }
        if (face_of_tri)
            face_of_tri[out_t] = face_of_tri[t];
        ++out_t;
    }
    /* Vertex data gathered into fresh arrays: new slot newidx[r] ← old r. */
    float *pos = malloc(((size_t)out_v * 3 + 1) * sizeof *pos);
    float *nrm = malloc(((size_t)out_v * 3 + 1) * sizeof *nrm);
    if (!pos || !nrm) {
        free(pos);
        free(nrm);
        free(remap);
        free(newidx);
        free(seen);
        return -1;
    }
    for (uint32_t r = 0; r < n; ++r)
        if (newidx[r] != UINT32_MAX) {
            memcpy(pos + 3 * (size_t)newidx[r], m->positions + 3 * (size_t)r, 3 * sizeof *pos);
            if (m->normals)
                memcpy(nrm + 3 * (size_t)newidx[r], m->normals + 3 * (size_t)r, 3 * sizeof *nrm);
            else
                memset(nrm + 3 * (size_t)newidx[r], 0, 3 * sizeof *nrm);
        }
    free(m->positions);
    free(m->normals);
    m->positions = pos, m->normals = nrm;
    m->vertex_count = m->vertex_cap = out_v;
    m->index_count = 3 * out_t;
    /* index_cap stays: the array only shrank */
    if (dropped)
        *dropped = drop;
    /* merged = referenced vertices minus the distinct positions they occupy */
    long merged = used_before - distinct;
    free(remap);
    free(newidx);
    free(seen);
    return merged < 0 ? 0 : merged;
}

long scn_mesh_weld_exact(struct scn_mesh *m)
{
    long merged = weld_compact(m, NULL, NULL, NULL);
    if (merged >= 0)
        scn_mesh_smooth_normals(m);
    return merged;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

long scn_mesh_count_nonmanifold_edges(const struct scn_mesh *m, uint32_t *example_a, uint32_t *example_b)
{
    size_t n = m->index_count;
    uint64_t *e = malloc((n + 1) * sizeof *e);
    if (!e)
        return -1;
    for (size_t t = 0; t + 2 < n; t += 3)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = m->indices[t + k], b = m->indices[t + (k + 1) % 3];
            e[t + k] = a < b ? ((uint64_t)a << 32 | b) : ((uint64_t)b << 32 | a);
        }
    qsort(e, n, sizeof *e, cmp_u64);
    long count = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i;
        while (j < n && e[j] == e[i])
            ++j;
        if (j - i > 2) {
            if (count++ == 0) {
                if (example_a)
                    *example_a = (uint32_t)(e[i] >> 32);
                if (example_b)
                    *example_b = (uint32_t)e[i];
            }
        }
        i = j;
    }
    free(e);
    return count;
}

int scn_soup_to_mesh(const char *path, struct scn_soup *soup, struct scn_mesh *out,
                     struct scn_import_report *report, struct hl_error *err)
{
    memset(out, 0, sizeof *out);
    struct scn_import_report rep = {0};
    if (soup->failed)
        return hl_fail(err, "%s: out of memory while reading", path);
    rep.faces_read = soup->faces_read;
    rep.polygons_triangulated = soup->polygons_triangulated;
    if (soup->vertex_count == 0)
        return hl_fail(err, "%s: no vertices (not a mesh file?)%s%s", path, soup->reader_note[0] ? "; reader: " : "",
                       soup->reader_note);
    if (soup->bad_index_faces)
        return hl_fail(err, "%s: face %u: refers to a vertex that does not exist (%u such faces, %u vertices)", path,
                       soup->first_bad_index_face + 1, soup->bad_index_faces, soup->vertex_count);
    if (soup->triangle_count == 0)
        return hl_fail(err, "%s: no faces (%u vertices, %u faces read)%s%s", path, soup->vertex_count,
                       soup->faces_read, soup->reader_note[0] ? "; reader: " : "", soup->reader_note);
    for (uint32_t v = 0; v < soup->vertex_count; ++v)
        for (int k = 0; k < 3; ++k) {
            double x = soup->positions[3 * (size_t)v + k];
            if (!isfinite(x))
                return hl_fail(err, "%s: vertex %u: coordinate %c is %s", path, v + 1, "xyz"[k],
                               isnan(x) ? "NaN" : "infinite");
            if (fabs(x) > 3.0e38)
                return hl_fail(err, "%s: vertex %u: coordinate %c = %g is beyond float range", path, v + 1, "xyz"[k],
                               x);
        }
    /* Hand the arrays to a scn_mesh: float positions, the soup's indices. */
    out->positions = malloc((size_t)soup->vertex_count * 3 * sizeof *out->positions);
    if (!out->positions)
        return hl_fail(err, "%s: out of memory", path);
    for (size_t i = 0; i < (size_t)soup->vertex_count * 3; ++i)
        out->positions[i] = (float)soup->positions[i];
    out->normals = soup->normals, soup->normals = NULL;
    out->vertex_count = out->vertex_cap = soup->vertex_count;
    out->indices = soup->indices, soup->indices = NULL;
    out->index_count = 3 * soup->triangle_count;
    out->index_cap = 3 * soup->triangle_cap;
    int file_normals = out->normals != NULL;

    uint32_t dropped = 0, first_dropped = 0;
    long merged = weld_compact(out, soup->face_of_tri, &dropped, &first_dropped);
    if (merged < 0) {
        scn_mesh_free(out);
        return hl_fail(err, "%s: out of memory", path);
    }
    rep.vertices_welded = (uint32_t)merged;
    rep.degenerate_dropped = dropped;
    if (out->index_count == 0) {
        scn_mesh_free(out);
        return hl_fail(err, "%s: face %u: all %u faces are degenerate (zero area)", path, first_dropped + 1,
                       soup->faces_read);
    }
    long nm = scn_mesh_count_nonmanifold_edges(out, NULL, NULL);
    if (nm < 0) {
        scn_mesh_free(out);
        return hl_fail(err, "%s: out of memory", path);
    }
    rep.nonmanifold_edges = (uint32_t)nm;
    /* The file's normals are kept only when every kept vertex has a usable one; a welded vertex keeps
     * its first occurrence's. Otherwise area-weighted (Max 1999 compares weightings; area is what the
     * renderer's procedural meshes use too). */
    for (uint32_t v = 0; file_normals && v < out->vertex_count; ++v) {
        const float *n = out->normals + 3 * (size_t)v;
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        file_normals = isfinite(len) && len > 1e-6;
    }
    if (file_normals) {
        for (uint32_t v = 0; v < out->vertex_count; ++v) {
            float *n = out->normals + 3 * (size_t)v;
            hl_vec3d u = hl_v3_normalize(hl_v3(n[0], n[1], n[2]));
            n[0] = (float)u.x, n[1] = (float)u.y, n[2] = (float)u.z;
        }
    } else {
        scn_mesh_smooth_normals(out);
    }
    if (report)
        *report = rep;
    return 0;
}

/* ---- the front door: which reader, and the file-system failures a reader would garble ----------- */

/* OpenMesh's OBJ reader parses "v x y z" with iostream >> float, which cannot read "nan" or "inf" or
 * a value beyond float range: it skips such a line silently and every later face index then points
 * at the wrong vertex. So OBJ vertex lines are checked here first, with strtod, naming the line. */
/* OpenMesh's OBJ reader (Debian's build keeps its assertions) aborts the program on a face line
 * that yields no vertex (`assert(!vhandles.empty())`, OBJReader.cc; found by fuzz_mesh_import with
 * "f /1", "f f" and "f 0"). So every word of a face line must start with a vertex number: 1, 2 … or
 * −1 … −(vertices so far), then optionally /texture/normal; an index past the vertices is left to
 * the validation, which names the face. */
/* OpenMesh splits OBJ lines at any isspace blank (scn_lex_blanks), so a face keyword followed by a
 * form feed is still a face (found by fuzz_mesh_import). */

static int obj_is_keyword(const char *c, char k)
{
    return c[0] == k && (c[1] == '\0' || strchr(scn_lex_blanks, c[1]));
}

static int obj_check_face(const char *path, uint64_t lineno, const char *c, uint64_t nv, struct hl_error *err)
{
    int words = 0;
    for (;;) {
        c += strspn(c, scn_lex_blanks);
        if (!*c)
            break;
        const char *w = c;
        size_t len = strcspn(c, scn_lex_blanks);
        c += len;
        ++words;
        char *end = NULL;
        long long v = strtoll(w, &end, 10);
        int ok = end != w && (end == c || *end == '/') && v != 0 && isdigit((unsigned char)w[w[0] == '-' ? 1 : 0]) &&
                 (v > 0 || (uint64_t)(-(v + 1)) < nv);
        if (!ok)
            return hl_fail(err, "%s:%llu: face: '%.*s' is not a vertex number (1 … or −1 … −%llu)", path,
                           (unsigned long long)lineno, (int)(len > 40 ? 40 : len), w, (unsigned long long)nv);
    }
    if (words == 0)
        return hl_fail(err, "%s:%llu: face without vertices", path, (unsigned long long)lineno);
    return 0;
}

static int obj_prescan(const char *path, uint32_t *vertex_lines, struct hl_error *err)
{
    FILE *f = hl_file_open_read(path, NULL, err);
    if (!f)
        return -1;
    char *line = NULL;
    size_t cap = 0;
    uint64_t lineno = 0, nv = 0;
    int rc = 0;
    ssize_t len;
    while (rc == 0 && (len = getline(&line, &cap, f)) > 0) {
        ++lineno;
        if (memchr(line, '\0', (size_t)len)) { /* OpenMesh reads past it; C strings would stop there */
            rc = hl_fail(err, "%s:%llu: NUL byte in a text OBJ file", path, (unsigned long long)lineno);
            break;
        }
        const char *c = line + strspn(line, scn_lex_blanks);
        if (obj_is_keyword(c, 'f')) {
            rc = obj_check_face(path, lineno, c + 1, nv, err);
            continue;
        }
        if (!obj_is_keyword(c, 'v'))
            continue;
        ++nv;
        c += 1; /* strtod skips the blanks */
        for (int k = 0; k < 3 && rc == 0; ++k) {
            char *end = NULL;
            double x = strtod(c, &end);
            if (end == c)
                rc = hl_fail(err, "%s:%llu: vertex %llu: coordinate %c missing or not a number", path,
                             (unsigned long long)lineno, (unsigned long long)nv, "xyz"[k]);
            else if (!isfinite(x))
                rc = hl_fail(err, "%s:%llu: vertex %llu: coordinate %c is %s", path, (unsigned long long)lineno,
                             (unsigned long long)nv, "xyz"[k], isnan(x) ? "NaN" : "infinite");
            else if (fabs(x) > 3.4e38)
                rc = hl_fail(err, "%s:%llu: vertex %llu: coordinate %c = %g is beyond float range", path,
                             (unsigned long long)lineno, (unsigned long long)nv, "xyz"[k], x);
            c = end;
        }
    }
    free(line);
    fclose(f);
    if (rc == 0 && nv >= UINT32_MAX)
        rc = hl_fail(err, "%s: %llu vertices: more than 32-bit indices hold", path, (unsigned long long)nv);
    *vertex_lines = (uint32_t)nv;
    return rc;
}

/* A PLY file's strips (decoded by scn_ply_check: OpenMesh does not read them) join the faces OpenMesh
 * read, after them in the face numbering, through the same door: index range, then welding and the
 * zero-area test in scn_soup_to_mesh. The soup is freed on error. */
static int soup_add_strips(const char *path, struct scn_soup *soup, const struct scn_ply_strips *strips,
                           struct hl_error *err)
{
    for (uint32_t t = 0; t < strips->triangle_count; ++t)
        scn_soup_add_face(soup, strips->indices + 3 * (size_t)t, 3);
    if (strips->elements == 0 || soup->faces_read > 0 || soup->vertex_count == 0)
        return 0;
    /* said here: validation's "no faces" would quote OpenMesh's note that it skipped the strips */
    scn_soup_free(soup);
    return hl_fail(err, "%s: no faces: its triangle strips (%llu indices) give no triangle without a repeated "
                   "index, and it has no face element", path, (unsigned long long)strips->items);
}

static int ext_is(const char *ext, const char *want)
{
    for (; *ext && *want; ++ext, ++want)
        if ((*ext | 0x20) != *want)
            return 0;
    return !*ext && !*want;
}

int scn_mesh_import(const char *path, struct scn_mesh *out, struct scn_import_report *report, struct hl_error *err)
{
    memset(out, 0, sizeof *out);
    if (report)
        memset(report, 0, sizeof *report);
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash))
        return hl_fail(err, "%s: no file extension; supported: .obj .ply .off .stl .gltf .glb", path);
    const char *ext = dot + 1;
    int om = ext_is(ext, "obj") || ext_is(ext, "ply") || ext_is(ext, "off") || ext_is(ext, "stl");
    int gltf = ext_is(ext, "gltf") || ext_is(ext, "glb");
    if (!om && !gltf)
        return hl_fail(err, "%s: unsupported extension '.%s'; supported: .obj .ply .off .stl .gltf .glb", path, ext);
    struct stat st;
    if (stat(path, &st) != 0)
        return hl_fail(err, "%s: cannot open: %s", path, strerror(errno));
    if (S_ISDIR(st.st_mode))
        return hl_fail(err, "%s: is a directory, not a mesh file", path);
    /* A readable regular file, opened without blocking (a FIFO is refused here, before OpenMesh or
     * assimp could wait on it): the readers' own messages are vaguer. */
    uint64_t size = 0;
    FILE *probe = hl_file_open_read(path, &size, err);
    if (!probe)
        return -1;
    fclose(probe);
    if (size == 0)
        return hl_fail(err, "%s: empty file (0 bytes)", path);
    uint32_t obj_vertices = 0;
    int is_obj = ext_is(ext, "obj");
    if (is_obj && obj_prescan(path, &obj_vertices, err) != 0)
        return -1;
    struct scn_ply_strips strips = {0};
    if (ext_is(ext, "ply") && scn_ply_check(path, &strips, err) != 0)
        return -1;
    if ((ext_is(ext, "off") && scn_off_check(path, size, err) != 0) ||
        (gltf && scn_gltf_check(path, ext_is(ext, "glb"), size, err) != 0))
        return -1;
    struct scn_soup soup;
    int rc = om ? scn_om_read(path, &soup, strips.elements > 0, err) : scn_assimp_read(path, &soup, err);
    if (rc == 0)
        rc = soup_add_strips(path, &soup, &strips, err);
    scn_ply_strips_free(&strips);
    if (rc != 0)
        return rc;
    if (is_obj && soup.vertex_count != obj_vertices) {
        uint32_t got = soup.vertex_count;
        scn_soup_free(&soup);
        return hl_fail(err, "%s: OpenMesh read %u of its %u vertex lines; face indices would be wrong", path, got,
                       obj_vertices);
    }
    rc = scn_soup_to_mesh(path, &soup, out, report, err);
    scn_soup_free(&soup);
    return rc;
}
