/* Per-vertex normals from a mesh's faces: area-weighted smooth normals, and crease normals that
 * stay smooth across gentle edges and split across sharp ones (CAD models' 90° edges would
 * otherwise shade as if rounded, and that smeared shading changes with every decimation). */
#include "scene/scene_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static hl_vec3d pos_of(const struct scn_mesh *m, uint32_t i)
{
    const float *p = m->positions + 3 * (size_t)i;
    return hl_v3(p[0], p[1], p[2]);
}

/* Twice the triangle's area along its normal: the cross product's length is the area weight. */
static hl_vec3d face_cross(const struct scn_mesh *m, uint32_t t)
{
    const uint32_t *v = m->indices + 3 * (size_t)t;
    hl_vec3d a = pos_of(m, v[0]);
    return hl_v3_cross(hl_v3_sub(pos_of(m, v[1]), a), hl_v3_sub(pos_of(m, v[2]), a));
}

void scn_mesh_smooth_normals(struct scn_mesh *m)
{
    if (m->failed)
        return;
    hl_vec3d *acc = calloc(m->vertex_count ? m->vertex_count : 1, sizeof *acc);
    if (!acc) {
        m->failed = 1;
        return;
    }
    for (uint32_t t = 0; t < m->index_count / 3; ++t) {
        hl_vec3d n = face_cross(m, t);
        for (int k = 0; k < 3; ++k) {
            uint32_t v = m->indices[3 * (size_t)t + k];
            acc[v] = hl_v3_add(acc[v], n);
        }
    }
    for (uint32_t i = 0; i < m->vertex_count; ++i) {
        hl_vec3d n = hl_v3_normalize(acc[i]);
        float *d = m->normals + 3 * (size_t)i;
        d[0] = (float)n.x, d[1] = (float)n.y, d[2] = (float)n.z;
    }
    free(acc);
}

/* One undirected edge of a non-degenerate face: key = (low vertex << 32) | high vertex. */
struct half_edge {
    uint64_t key;
    uint32_t face;
};

static int cmp_half_edge(const void *pa, const void *pb)
{
    const struct half_edge *a = pa, *b = pb;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return a->face < b->face ? -1 : a->face > b->face; /* deterministic order within an edge */
}

/* Union-find over corners (3·face + k); path halving keeps it iterative. */
static uint32_t uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static void uf_union(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = uf_find(parent, a), b = uf_find(parent, b);
    if (a != b)
        parent[a < b ? b : a] = a < b ? a : b; /* lower root wins: the result does not depend on order */
}

/* The corner of face t that sits on vertex v (the face is known to use v). */
static uint32_t corner_at(const struct scn_mesh *m, uint32_t t, uint32_t v)
{
    const uint32_t *f = m->indices + 3 * (size_t)t;
    return 3 * t + (f[0] == v ? 0u : f[1] == v ? 1u : 2u);
}

void scn_mesh_crease_normals(struct scn_mesh *m, double crease_angle_deg)
{
    if (m->failed)
        return;
    uint32_t tri_count = m->index_count / 3, corner_count = 3 * tri_count;
    hl_vec3d *fn = malloc(((size_t)tri_count + 1) * sizeof *fn);
    uint8_t *degenerate = calloc((size_t)tri_count + 1, 1);
    struct half_edge *he = malloc(((size_t)corner_count + 1) * sizeof *he);
    uint32_t *parent = malloc(((size_t)corner_count + 1) * sizeof *parent);
    uint32_t *root_vertex = malloc(((size_t)corner_count + 1) * sizeof *root_vertex);
    uint8_t *vertex_used = calloc((size_t)m->vertex_count + 1, 1);
    if (!fn || !degenerate || !he || !parent || !root_vertex || !vertex_used)
        goto out_of_memory;

    /* Face normals, unnormalised (length = twice the area: the area weight; the dihedral angle
     * below does not depend on it). A face with zero area (or with a repeated vertex) has no direction and so
     * contributes nothing and joins no fan. */
    uint32_t he_count = 0;
    for (uint32_t t = 0; t < tri_count; ++t) {
        const uint32_t *f = m->indices + 3 * (size_t)t;
        fn[t] = face_cross(m, t);
        double len = hl_v3_length(fn[t]);
        degenerate[t] = !(len > 0) || !isfinite(len) || f[0] == f[1] || f[1] == f[2] || f[0] == f[2];
        if (degenerate[t])
            continue;
        for (int k = 0; k < 3; ++k) {
            uint32_t a = f[k], b = f[(k + 1) % 3];
            uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
            he[he_count++] = (struct half_edge){((uint64_t)lo << 32) | hi, t};
        }
    }
    for (uint32_t c = 0; c < corner_count; ++c)
        parent[c] = c;
    qsort(he, he_count, sizeof *he, cmp_half_edge);

    /* Join the corners of two faces at both ends of an edge they share when the edge is smooth:
     * exactly two faces and a dihedral angle (between the face normals, atan2 form: exact near 0°
     * and 180°, where acos loses digits) below the crease angle. Three or more faces on one edge
     * (non-manifold) have no single dihedral angle: treated as a crease. */
    double crease_rad = crease_angle_deg * HL_RAD_PER_DEG;
    for (uint32_t i = 0; i < he_count;) {
        uint32_t j = i + 1;
        while (j < he_count && he[j].key == he[i].key)
            ++j;
        if (j - i == 2) {
            uint32_t t1 = he[i].face, t2 = he[i + 1].face;
            hl_vec3d n1 = fn[t1], n2 = fn[t2];
            double angle_rad = hl_v3_angle_rad(n1, n2); /* atan2 form (base/) */
            if (angle_rad < crease_rad) {
                uint32_t a = (uint32_t)(he[i].key >> 32), b = (uint32_t)he[i].key;
                uf_union(parent, corner_at(m, t1, a), corner_at(m, t2, a));
                uf_union(parent, corner_at(m, t1, b), corner_at(m, t2, b));
            }
        }
        i = j;
    }

    /* One vertex per (vertex, fan): the first fan met at a vertex keeps its index, later ones get
     * copies appended. Degenerate faces' corners keep the original index. */
    uint32_t new_count = m->vertex_count;
    for (uint32_t c = 0; c < corner_count; ++c)
        root_vertex[c] = UINT32_MAX;
    for (uint32_t c = 0; c < corner_count; ++c) {
        if (degenerate[c / 3])
            continue;
        uint32_t r = uf_find(parent, c), v = m->indices[c];
        if (root_vertex[r] == UINT32_MAX) {
            if (!vertex_used[v])
                vertex_used[v] = 1, root_vertex[r] = v;
            else
                root_vertex[r] = new_count++;
        }
    }
    if (new_count > m->vertex_count) {
        float *p = realloc(m->positions, (size_t)new_count * 3 * sizeof(float));
        if (p)
            m->positions = p;
        float *n = p ? realloc(m->normals, (size_t)new_count * 3 * sizeof(float)) : NULL;
        if (n)
            m->normals = n;
        if (!p || !n)
            goto out_of_memory;
        m->vertex_cap = new_count;
    }
    hl_vec3d *acc = calloc((size_t)new_count + 1, sizeof *acc);
    if (!acc)
        goto out_of_memory;
    for (uint32_t c = 0; c < corner_count; ++c) {
        if (degenerate[c / 3])
            continue;
        uint32_t nv = root_vertex[uf_find(parent, c)], v = m->indices[c];
        if (nv >= m->vertex_count)
            memcpy(m->positions + 3 * (size_t)nv, m->positions + 3 * (size_t)v, 3 * sizeof(float));
        acc[nv] = hl_v3_add(acc[nv], fn[c / 3]);
        m->indices[c] = nv;
    }
    for (uint32_t i = 0; i < new_count; ++i) {
        float *d = m->normals + 3 * (size_t)i;
        hl_vec3d n = hl_v3_normalize(acc[i]);
        if (!(hl_v3_length(n) > 0.5)) { /* only degenerate faces or none: keep a finite unit normal */
            n = hl_v3_normalize(hl_v3(d[0], d[1], d[2]));
            if (!(hl_v3_length(n) > 0.5) || !isfinite(n.x + n.y + n.z))
                n = hl_v3(0, 0, 1);
        }
        d[0] = (float)n.x, d[1] = (float)n.y, d[2] = (float)n.z;
    }
    m->vertex_count = new_count;
    free(acc);
    goto done;
out_of_memory:
    m->failed = 1;
done:
    free(fn);
    free(degenerate);
    free(he);
    free(parent);
    free(root_vertex);
    free(vertex_used);
}
