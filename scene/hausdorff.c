/* Two-sided Hausdorff distance between two triangle meshes (the error of an LOD level against the
 * finest one), by dense stratified surface sampling in the manner of Metro (Cignoni, Rocchini &
 * Scopigno 1998), with exact closest points on the other surface found through a bounding-volume
 * hierarchy over its triangles.
 *
 * Sampling with a guarantee: triangle t, longest edge L_t, is cut into k_t² congruent copies of
 * itself (k_t = ⌈L_t / h⌉, the regular k-subdivision) and one uniformly random point is drawn in
 * each copy; every referenced vertex is a sample too. Any point of the surface lies in some copy,
 * whose diameter is L_t / k_t ≤ h, so it is within h of that copy's sample. The distance to the
 * other surface is 1-Lipschitz, hence the true one-sided distance ≤ the sampled maximum + h; h is
 * chosen as small as the sample budget allows (Σ k_t² ≤ samples), and reported as bound_m. */
#include "scene/scene_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { SCN_BVH_LEAF = 4, SCN_BVH_STACK = 96 };
#define SCN_HAUSDORFF_DEFAULT_SAMPLES ((uint64_t)1 << 20)
#define SCN_HAUSDORFF_MAX_SAMPLES ((uint64_t)1 << 32)

static hl_vec3d scn_pos(const struct scn_mesh *m, uint32_t i)
{
    const float *p = m->positions + 3 * (size_t)i;
    return hl_v3(p[0], p[1], p[2]);
}

static double scn_longest_edge(hl_vec3d a, hl_vec3d b, hl_vec3d c)
{
    double ab = hl_v3_length(hl_v3_sub(b, a)), bc = hl_v3_length(hl_v3_sub(c, b)), ca = hl_v3_length(hl_v3_sub(a, c));
    double l = ab > bc ? ab : bc;
    return l > ca ? l : ca;
}

static uint64_t scn_subdivisions(double edge_m, double h_m)
{
    if (!(edge_m > 0) || !(h_m > 0))
        return 1;
    double k = ceil(edge_m / h_m);
    return k < 1 ? 1 : (uint64_t)k;
}

int scn_mesh_check(const struct scn_mesh *m, const char *what, struct hl_error *err)
{
    if (!m || m->failed)
        return hl_fail(err, "%s: no mesh, or its construction ran out of memory", what);
    if (m->index_count < 3 || m->index_count % 3 != 0)
        return hl_fail(err, "%s: %u indices: needs at least one triangle, 3 indices each", what, m->index_count);
    for (uint32_t i = 0; i < m->index_count; ++i)
        if (m->indices[i] >= m->vertex_count)
            return hl_fail(err, "%s: index %u (triangle %u) is %u, the mesh has %u vertices", what, i, i / 3,
                           m->indices[i], m->vertex_count);
    for (size_t i = 0; i < 3 * (size_t)m->vertex_count; ++i)
        if (!isfinite(m->positions[i]))
            return hl_fail(err, "%s: vertex %zu: position is not finite", what, i / 3);
    return 0;
}

void scn_surface_samples_free(struct scn_surface_samples *s)
{
    free(s->points);
    free(s->weight_m2);
    *s = (struct scn_surface_samples){0};
}

int scn_surface_sample(const struct scn_mesh *m, uint64_t target, uint64_t seed, struct scn_surface_samples *out,
                       struct hl_error *err)
{
    *out = (struct scn_surface_samples){0};
    if (scn_mesh_check(m, "surface samples", err) != 0)
        return -1;
    uint32_t tris = m->index_count / 3;
    if (target > SCN_HAUSDORFF_MAX_SAMPLES)
        target = SCN_HAUSDORFF_MAX_SAMPLES;
    double *edge = malloc(sizeof *edge * tris);
    unsigned char *used = calloc(m->vertex_count, 1);
    if (!edge || !used) {
        free(edge), free(used);
        return hl_fail(err, "surface samples: out of memory for %u triangles", tris);
    }
    double max_edge = 0, sum_edge2 = 0;
    uint64_t used_count = 0;
    for (uint32_t t = 0; t < tris; ++t) {
        const uint32_t *ix = m->indices + 3 * (size_t)t;
        edge[t] = scn_longest_edge(scn_pos(m, ix[0]), scn_pos(m, ix[1]), scn_pos(m, ix[2]));
        max_edge = edge[t] > max_edge ? edge[t] : max_edge;
        sum_edge2 += edge[t] * edge[t];
        for (int k = 0; k < 3; ++k)
            if (!used[ix[k]])
                used[ix[k]] = 1, ++used_count;
    }
    /* The smallest h with Σ ⌈L_t/h⌉² ≤ target. At h0/2, h0 = √(ΣL²/target), the count is ≥ 4·target;
     * at h = max L it is one per triangle. Bisection between them; with fewer samples than
     * triangles every triangle still gets one. */
    double h = max_edge;
    if (max_edge > 0 && target > tris) {
        double lo = 0.5 * sqrt(sum_edge2 / (double)target), hi = max_edge;
        for (int it = 0; it < 48 && hi - lo > 1e-9 * hi; ++it) {
            double mid = 0.5 * (lo + hi);
            uint64_t n = 0;
            for (uint32_t t = 0; t < tris && n <= target; ++t) {
                uint64_t k = scn_subdivisions(edge[t], mid);
                n += k * k;
            }
            if (n <= target)
                hi = mid;
            else
                lo = mid;
        }
        h = hi;
    }
    uint64_t count = used_count;
    double spacing = 0;
    for (uint32_t t = 0; t < tris; ++t) {
        uint64_t k = scn_subdivisions(edge[t], h);
        count += k * k;
        double s = edge[t] / (double)k;
        spacing = s > spacing ? s : spacing;
    }
    out->points = malloc(3 * sizeof(double) * count);
    out->weight_m2 = malloc(sizeof(double) * count);
    if (!out->points || !out->weight_m2) {
        free(edge), free(used);
        scn_surface_samples_free(out);
        return hl_fail(err, "surface samples: out of memory for %llu samples", (unsigned long long)count);
    }
    struct scn_rng g = {seed};
    uint64_t n = 0;
    for (uint32_t t = 0; t < tris; ++t) {
        const uint32_t *ix = m->indices + 3 * (size_t)t;
        hl_vec3d a = scn_pos(m, ix[0]), b = scn_pos(m, ix[1]), c = scn_pos(m, ix[2]);
        uint64_t k = scn_subdivisions(edge[t], h);
        double area = 0.5 * hl_v3_length(hl_v3_cross(hl_v3_sub(b, a), hl_v3_sub(c, a)));
        double w = area / (double)(k * k), inv = 1.0 / (double)k;
        hl_vec3d du = hl_v3_scale(hl_v3_sub(b, a), inv), dv = hl_v3_scale(hl_v3_sub(c, a), inv);
        /* Cell (i, j) of the k-grid in barycentric steps du, dv: the upright copy with corners
         * (i,j) (i+1,j) (i,j+1) and, when i+j ≤ k−2, the inverted one (i+1,j) (i,j+1) (i+1,j+1). */
        for (uint64_t i = 0; i < k; ++i)
            for (uint64_t j = 0; i + j < k; ++j)
                for (int flip = 0; flip < 2; ++flip) {
                    if (flip && i + j + 2 > k)
                        break;
                    double r1 = scn_rng_uniform(&g), r2 = scn_rng_uniform(&g);
                    if (r1 + r2 > 1) /* fold the square onto the triangle: uniform in it */
                        r1 = 1 - r1, r2 = 1 - r2;
                    double u = (double)i + (flip ? 1 - r2 : r1), v = (double)j + (flip ? 1 - r1 : r2);
                    hl_vec3d p = hl_v3_add(a, hl_v3_add(hl_v3_scale(du, u), hl_v3_scale(dv, v)));
                    out->points[3 * n] = p.x, out->points[3 * n + 1] = p.y, out->points[3 * n + 2] = p.z;
                    out->weight_m2[n++] = w;
                }
    }
    for (uint32_t v = 0; v < m->vertex_count; ++v)
        if (used[v]) { /* vertices: where a decimated surface strays most; no area of their own */
            hl_vec3d p = scn_pos(m, v);
            out->points[3 * n] = p.x, out->points[3 * n + 1] = p.y, out->points[3 * n + 2] = p.z;
            out->weight_m2[n++] = 0;
        }
    free(edge), free(used);
    out->count = n;
    out->spacing_m = spacing;
    return 0;
}

/* ---- BVH over triangles ------------------------------------------------------------------------ */
struct scn_bvh_node {
    double lo[3], hi[3];
    uint32_t first, count; /* leaf: triangles [first, first+count); inner (count 0): children first, first+1 */
};

void scn_tri_bvh_free(struct scn_tri_bvh *b)
{
    free(b->tri);
    free(b->nodes);
    *b = (struct scn_tri_bvh){0};
}

static void scn_bvh_bounds(const double *tri, uint32_t first, uint32_t count, struct scn_bvh_node *n)
{
    for (int k = 0; k < 3; ++k)
        n->lo[k] = INFINITY, n->hi[k] = -INFINITY;
    for (uint32_t t = first; t < first + count; ++t)
        for (int v = 0; v < 3; ++v)
            for (int k = 0; k < 3; ++k) {
                double x = tri[9 * (size_t)t + 3 * v + k];
                n->lo[k] = x < n->lo[k] ? x : n->lo[k];
                n->hi[k] = x > n->hi[k] ? x : n->hi[k];
            }
}

static void scn_swap_tri(double *tri, uint32_t a, uint32_t b)
{
    double tmp[9];
    memcpy(tmp, tri + 9 * (size_t)a, sizeof tmp);
    memcpy(tri + 9 * (size_t)a, tri + 9 * (size_t)b, sizeof tmp);
    memcpy(tri + 9 * (size_t)b, tmp, sizeof tmp);
}

static double scn_centroid(const double *tri, uint32_t t, int axis)
{
    const double *p = tri + 9 * (size_t)t;
    return p[axis] + p[3 + axis] + p[6 + axis];
}

int scn_tri_bvh_build(const struct scn_mesh *m, struct scn_tri_bvh *out, struct hl_error *err)
{
    *out = (struct scn_tri_bvh){0};
    if (scn_mesh_check(m, "triangle index", err) != 0)
        return -1;
    uint32_t n = m->index_count / 3;
    out->tri = malloc(9 * sizeof(double) * n);
    out->nodes = malloc(sizeof *out->nodes * (2 * (size_t)n));
    if (!out->tri || !out->nodes) {
        scn_tri_bvh_free(out);
        return hl_fail(err, "triangle index: out of memory for %u triangles", n);
    }
    for (uint32_t t = 0; t < n; ++t)
        for (int v = 0; v < 3; ++v) {
            const float *p = m->positions + 3 * (size_t)m->indices[3 * (size_t)t + v];
            for (int k = 0; k < 3; ++k)
                out->tri[9 * (size_t)t + 3 * v + k] = p[k];
        }
    out->tri_count = n;
    /* Top-down, splitting at the middle of the centroids' extent on its longest axis (O(n) per
     * level); an all-on-one-side split falls back to halving the count. */
    uint32_t node_count = 1, stack[SCN_BVH_STACK], top = 0;
    out->nodes[0].first = 0, out->nodes[0].count = n;
    stack[top++] = 0;
    while (top) {
        struct scn_bvh_node *nd = &out->nodes[stack[--top]];
        scn_bvh_bounds(out->tri, nd->first, nd->count, nd);
        if (nd->count <= SCN_BVH_LEAF || top + 2 > SCN_BVH_STACK)
            continue;
        double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (uint32_t t = nd->first; t < nd->first + nd->count; ++t)
            for (int k = 0; k < 3; ++k) {
                double c = scn_centroid(out->tri, t, k);
                clo[k] = c < clo[k] ? c : clo[k];
                chi[k] = c > chi[k] ? c : chi[k];
            }
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (chi[k] - clo[k] > chi[axis] - clo[axis])
                axis = k;
        double mid = 0.5 * (clo[axis] + chi[axis]);
        uint32_t i = nd->first, j = nd->first + nd->count;
        while (i < j) {
            if (scn_centroid(out->tri, i, axis) < mid)
                ++i;
            else
                scn_swap_tri(out->tri, i, --j);
        }
        uint32_t left = i - nd->first;
        if (left == 0 || left == nd->count)
            left = nd->count / 2; /* coincident centroids: any halving will do */
        uint32_t c = node_count;
        node_count += 2;
        out->nodes[c].first = nd->first, out->nodes[c].count = left;
        out->nodes[c + 1].first = nd->first + left, out->nodes[c + 1].count = nd->count - left;
        nd->first = c, nd->count = 0;
        stack[top++] = c + 1;
        stack[top++] = c;
    }
    out->node_count = node_count;
    return 0;
}

static double scn_box_dist2(const struct scn_bvh_node *n, const double p[3])
{
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        double g = p[k] < n->lo[k] ? n->lo[k] - p[k] : p[k] > n->hi[k] ? p[k] - n->hi[k] : 0;
        d2 += g * g;
    }
    return d2;
}

static double scn_tri_dist2(const double *t, hl_vec3d p)
{
    hl_vec3d q = scn_closest_on_triangle(p, hl_v3(t[0], t[1], t[2]), hl_v3(t[3], t[4], t[5]), hl_v3(t[6], t[7], t[8]));
    hl_vec3d d = hl_v3_sub(p, q);
    return hl_v3_dot(d, d);
}

double scn_tri_bvh_distance(const struct scn_tri_bvh *b, hl_vec3d p, uint32_t *hint)
{
    /* Branch and bound. The previous query's triangle (samples come in surface order, so it is
     * usually the answer again) gives a tight first bound. A box is skipped only when it is farther
     * than the best by more than rounding could explain, so the result equals the minimum over all
     * triangles of the same point–triangle computation (tests compare it with brute force). */
    double best2 = INFINITY, pp[3] = {p.x, p.y, p.z};
    uint32_t best_t = UINT32_MAX;
    if (hint && *hint < b->tri_count) {
        best_t = *hint;
        best2 = scn_tri_dist2(b->tri + 9 * (size_t)best_t, p);
    }
    uint32_t stack[SCN_BVH_STACK], top = 0;
    stack[top++] = 0;
    while (top) {
        const struct scn_bvh_node *n = &b->nodes[stack[--top]];
        if (scn_box_dist2(n, pp) > best2 * (1 + 1e-9))
            continue;
        if (n->count) {
            for (uint32_t t = n->first; t < n->first + n->count; ++t) {
                double d2 = scn_tri_dist2(b->tri + 9 * (size_t)t, p);
                if (d2 < best2)
                    best2 = d2, best_t = t;
            }
            continue;
        }
        double dl = scn_box_dist2(&b->nodes[n->first], pp), dr = scn_box_dist2(&b->nodes[n->first + 1], pp);
        if (top + 2 > SCN_BVH_STACK) /* cannot happen: depth ≤ the build's stack */
            break;
        if (dl <= dr) { /* nearer child on top: it is searched first */
            stack[top++] = n->first + 1;
            stack[top++] = n->first;
        } else {
            stack[top++] = n->first;
            stack[top++] = n->first + 1;
        }
    }
    if (hint)
        *hint = best_t;
    return sqrt(best2);
}

/* ---- the measure ------------------------------------------------------------------------------- */
static int scn_one_sided(const struct scn_mesh *from, const struct scn_tri_bvh *to, uint64_t samples,
                         uint64_t seed, double *max_m, double *mean_m, double *spacing_m, uint64_t *count,
                         struct hl_error *err)
{
    struct scn_surface_samples s;
    if (scn_surface_sample(from, samples, seed, &s, err) != 0)
        return -1;
    double worst = 0, sum = 0, wsum = 0;
    uint32_t hint = UINT32_MAX;
    for (uint64_t i = 0; i < s.count; ++i) {
        double d = scn_tri_bvh_distance(to, hl_v3(s.points[3 * i], s.points[3 * i + 1], s.points[3 * i + 2]), &hint);
        worst = d > worst ? d : worst;
        sum += s.weight_m2[i] * d;
        wsum += s.weight_m2[i];
    }
    *max_m = worst;
    *mean_m = wsum > 0 ? sum / wsum : worst; /* all triangles degenerate: the vertices speak alone */
    *spacing_m = s.spacing_m;
    *count = s.count;
    scn_surface_samples_free(&s);
    return 0;
}

int scn_mesh_hausdorff(const struct scn_mesh *a, const struct scn_mesh *b, uint64_t samples_per_mesh,
                       uint64_t seed, struct scn_hausdorff *out, struct hl_error *err)
{
    if (!out)
        return hl_fail(err, "hausdorff: no output");
    *out = (struct scn_hausdorff){0};
    if (scn_mesh_check(a, "hausdorff: mesh A", err) != 0 || scn_mesh_check(b, "hausdorff: mesh B", err) != 0)
        return -1;
    if (samples_per_mesh == 0)
        samples_per_mesh = SCN_HAUSDORFF_DEFAULT_SAMPLES;
    struct scn_tri_bvh ta, tb;
    if (scn_tri_bvh_build(a, &ta, err) != 0)
        return -1;
    if (scn_tri_bvh_build(b, &tb, err) != 0) {
        scn_tri_bvh_free(&ta);
        return -1;
    }
    double max_ab, mean_ab, h_a, max_ba, mean_ba, h_b;
    uint64_t n_a, n_b;
    int rc = scn_one_sided(a, &tb, samples_per_mesh, SCN_HAUSDORFF_SEED_A(seed), &max_ab, &mean_ab, &h_a, &n_a, err);
    if (rc == 0) /* a different stream for B, so A vs A does not sample the same points twice */
        rc = scn_one_sided(b, &ta, samples_per_mesh, SCN_HAUSDORFF_SEED_B(seed), &max_ba, &mean_ba, &h_b, &n_b, err);
    scn_tri_bvh_free(&ta);
    scn_tri_bvh_free(&tb);
    if (rc != 0)
        return rc;
    out->max_m = max_ab > max_ba ? max_ab : max_ba;
    out->mean_m = 0.5 * (mean_ab + mean_ba);
    out->bound_m = h_a > h_b ? h_a : h_b;
    out->samples = n_a + n_b;
    return 0;
}
