/* Procedural meshes: a growable triangle list and the primitives the built-in scenes are made of
 * (boxes, cylinders, bumpy spheres). Everything is closed and wound CCW seen from outside, because
 * the renderer culls back faces. */
#include "scene/scene_internal.h"

#include <math.h>
#include <stdlib.h>

uint64_t scn_rng_next(struct scn_rng *g)
{
    uint64_t z = (g->state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double scn_rng_uniform(struct scn_rng *g) { return (double)(scn_rng_next(g) >> 11) * 0x1.0p-53; }

hl_quatd scn_rng_rotation(struct scn_rng *g)
{
    /* Shoemake, "Uniform random rotations", Graphics Gems III (1992). */
    double u1 = scn_rng_uniform(g), u2 = 2.0 * HL_PI * scn_rng_uniform(g), u3 = 2.0 * HL_PI * scn_rng_uniform(g);
    double a = sqrt(1.0 - u1), b = sqrt(u1);
    return hl_q_normalize(hl_q(b * cos(u3), a * sin(u2), a * cos(u2), b * sin(u3)));
}

void scn_mesh_free(struct scn_mesh *m)
{
    free(m->positions);
    free(m->normals);
    free(m->indices);
    *m = (struct scn_mesh){0};
}

void scn_mesh_aabb(const struct scn_mesh *m, double lo_m[3], double hi_m[3])
{
    for (int k = 0; k < 3; ++k)
        lo_m[k] = INFINITY, hi_m[k] = -INFINITY;
    for (uint32_t i = 0; i < m->vertex_count; ++i)
        for (int k = 0; k < 3; ++k) {
            double v = m->positions[3 * (size_t)i + k];
            lo_m[k] = v < lo_m[k] ? v : lo_m[k];
            hi_m[k] = v > hi_m[k] ? v : hi_m[k];
        }
}

static int scn_mesh_grow(void **p, uint32_t *cap, uint32_t need, size_t elem)
{
    if (need <= *cap)
        return 0;
    uint32_t c = *cap ? *cap : 64;
    while (c < need)
        c *= 2;
    void *q = realloc(*p, (size_t)c * elem);
    if (!q)
        return -1;
    *p = q;
    *cap = c;
    return 0;
}

uint32_t scn_mesh_add_vertex(struct scn_mesh *m, hl_vec3d p, hl_vec3d n)
{
    if (m->failed)
        return 0;
    uint32_t cap_p = m->vertex_cap, cap_n = m->vertex_cap;
    if (scn_mesh_grow((void **)&m->positions, &cap_p, m->vertex_count + 1, 3 * sizeof(float)) ||
        scn_mesh_grow((void **)&m->normals, &cap_n, m->vertex_count + 1, 3 * sizeof(float))) {
        m->failed = 1;
        return 0;
    }
    m->vertex_cap = cap_p;
    float *dp = m->positions + 3 * (size_t)m->vertex_count, *dn = m->normals + 3 * (size_t)m->vertex_count;
    dp[0] = (float)p.x, dp[1] = (float)p.y, dp[2] = (float)p.z;
    dn[0] = (float)n.x, dn[1] = (float)n.y, dn[2] = (float)n.z;
    return m->vertex_count++;
}

void scn_mesh_add_triangle(struct scn_mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    if (m->failed)
        return;
    if (scn_mesh_grow((void **)&m->indices, &m->index_cap, m->index_count + 3, sizeof(uint32_t))) {
        m->failed = 1;
        return;
    }
    m->indices[m->index_count++] = a;
    m->indices[m->index_count++] = b;
    m->indices[m->index_count++] = c;
}

void scn_mesh_add_box(struct scn_mesh *m, hl_vec3d center, hl_vec3d half, hl_quatd rot)
{
    /* Per face: normal axis k, tangent axes chosen so (u × v) = n gives CCW seen from outside. */
    static const int axes[3][2] = {{1, 2}, {2, 0}, {0, 1}};
    double h[3] = {half.x, half.y, half.z};
    for (int k = 0; k < 3; ++k) {
        for (int s = -1; s <= 1; s += 2) {
            double n[3] = {0, 0, 0}, u[3] = {0, 0, 0}, v[3] = {0, 0, 0}, c[3] = {0, 0, 0};
            n[k] = s;
            c[k] = s * h[k];
            u[axes[k][0]] = h[axes[k][0]] * s; /* flipping u on the negative side keeps CCW outward */
            v[axes[k][1]] = h[axes[k][1]];
            hl_vec3d nw = hl_q_rotate(rot, hl_v3(n[0], n[1], n[2]));
            uint32_t base = 0;
            for (int corner = 0; corner < 4; ++corner) {
                double su = (corner == 1 || corner == 2) ? 1 : -1, sv = (corner >= 2) ? 1 : -1;
                hl_vec3d local = hl_v3(c[0] + su * u[0] + sv * v[0], c[1] + su * u[1] + sv * v[1],
                                       c[2] + su * u[2] + sv * v[2]);
                uint32_t id = scn_mesh_add_vertex(m, hl_v3_add(center, hl_q_rotate(rot, local)), nw);
                if (corner == 0)
                    base = id;
            }
            scn_mesh_add_triangle(m, base, base + 1, base + 2);
            scn_mesh_add_triangle(m, base, base + 2, base + 3);
        }
    }
}

void scn_mesh_add_cylinder(struct scn_mesh *m, hl_vec3d center, double radius, double half_height,
                           int segments, hl_quatd rot)
{
    uint32_t side = m->vertex_count;
    for (int i = 0; i < segments; ++i) {
        double a = 2.0 * HL_PI * i / segments;
        hl_vec3d n = hl_v3(cos(a), 0, -sin(a)); /* angle increases CCW seen from +Y */
        hl_vec3d nw = hl_q_rotate(rot, n);
        for (int e = 0; e < 2; ++e) {
            hl_vec3d local = hl_v3(radius * n.x, e ? half_height : -half_height, radius * n.z);
            scn_mesh_add_vertex(m, hl_v3_add(center, hl_q_rotate(rot, local)), nw);
        }
    }
    for (int i = 0; i < segments; ++i) {
        uint32_t b0 = side + 2 * i, t0 = b0 + 1, b1 = side + 2 * ((i + 1) % segments), t1 = b1 + 1;
        scn_mesh_add_triangle(m, b0, b1, t1);
        scn_mesh_add_triangle(m, b0, t1, t0);
    }
    for (int e = 0; e < 2; ++e) { /* caps: a fan around a centre vertex, flat normal */
        double y = e ? half_height : -half_height;
        hl_vec3d nw = hl_q_rotate(rot, hl_v3(0, e ? 1 : -1, 0));
        uint32_t mid = scn_mesh_add_vertex(m, hl_v3_add(center, hl_q_rotate(rot, hl_v3(0, y, 0))), nw);
        for (int i = 0; i < segments; ++i) {
            double a = 2.0 * HL_PI * i / segments;
            scn_mesh_add_vertex(m, hl_v3_add(center, hl_q_rotate(rot, hl_v3(radius * cos(a), y, -radius * sin(a)))), nw);
        }
        for (int i = 0; i < segments; ++i) {
            uint32_t a = mid + 1 + i, b = mid + 1 + (i + 1) % segments;
            if (e)
                scn_mesh_add_triangle(m, mid, a, b);
            else
                scn_mesh_add_triangle(m, mid, b, a);
        }
    }
}

void scn_mesh_add_sphere(struct scn_mesh *m, double radius, int rings, int segments,
                         double (*shape)(hl_vec3d dir))
{
    uint32_t base = m->vertex_count;
    hl_vec3d up = hl_v3(0, 1, 0), down = hl_v3(0, -1, 0);
    uint32_t top = scn_mesh_add_vertex(m, hl_v3_scale(up, radius * shape(up)), up);
    for (int r = 1; r <= rings; ++r) {
        double polar = HL_PI * r / (rings + 1);
        for (int i = 0; i < segments; ++i) {
            double a = 2.0 * HL_PI * i / segments;
            hl_vec3d d = hl_v3(sin(polar) * cos(a), cos(polar), -sin(polar) * sin(a));
            scn_mesh_add_vertex(m, hl_v3_scale(d, radius * shape(d)), d);
        }
    }
    uint32_t bottom = scn_mesh_add_vertex(m, hl_v3_scale(down, radius * shape(down)), down);
#define RING(r, i) (base + 1 + (uint32_t)((r) - 1) * (uint32_t)segments + (uint32_t)((i) % segments))
    for (int i = 0; i < segments; ++i) {
        scn_mesh_add_triangle(m, top, RING(1, i), RING(1, i + 1));
        scn_mesh_add_triangle(m, bottom, RING(rings, i + 1), RING(rings, i));
        for (int r = 1; r < rings; ++r) {
            scn_mesh_add_triangle(m, RING(r, i), RING(r + 1, i), RING(r + 1, i + 1));
            scn_mesh_add_triangle(m, RING(r, i), RING(r + 1, i + 1), RING(r, i + 1));
        }
    }
#undef RING
    scn_mesh_smooth_normals(m);
}

void scn_lodset_free(struct scn_lodset *set)
{
    if (!set)
        return;
    for (int l = 0; l < SCN_LODSET_MAX_LEVELS; ++l)
        scn_mesh_free(&set->levels[l]);
    *set = (struct scn_lodset){0};
}
