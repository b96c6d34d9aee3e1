/* LOD analysis: how far a coarse level strays from the finest one (geometric error) and the
 * spatial frequency of the detail it loses, the quantity Reddy's acuity model compares against
 * the eye's and the display's limits (Reddy 1998 §3.2; docs/scenes.md). */
#include "scene/scene_internal.h"

#include <math.h>

/* Ericson, Real-Time Collision Detection §5.1.5: Voronoi regions of the vertices, then the edges,
 * else the face. Exact for degenerate slivers too. Shared with the Hausdorff measure (hausdorff.c). */
hl_vec3d scn_closest_on_triangle(hl_vec3d p, hl_vec3d a, hl_vec3d b, hl_vec3d c)
{
    hl_vec3d ab = hl_v3_sub(b, a), ac = hl_v3_sub(c, a), ap = hl_v3_sub(p, a);
    double d1 = hl_v3_dot(ab, ap), d2 = hl_v3_dot(ac, ap);
    if (d1 <= 0 && d2 <= 0)
        return a;
    hl_vec3d bp = hl_v3_sub(p, b);
    double d3 = hl_v3_dot(ab, bp), d4 = hl_v3_dot(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return b;
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
        return hl_v3_add(a, hl_v3_scale(ab, d1 / (d1 - d3)));
    hl_vec3d cp = hl_v3_sub(p, c);
    double d5 = hl_v3_dot(ab, cp), d6 = hl_v3_dot(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return c;
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
        return hl_v3_add(a, hl_v3_scale(ac, d2 / (d2 - d6)));
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return hl_v3_add(b, hl_v3_scale(hl_v3_sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
    double denom = va + vb + vc;
    if (denom <= 0) /* zero-area triangle that slipped through: nearest vertex is good enough */
        return a;
    double v = vb / denom, w = vc / denom;
    return hl_v3_add(a, hl_v3_add(hl_v3_scale(ab, v), hl_v3_scale(ac, w)));
}

static hl_vec3d scn_vertex(const struct scn_mesh *m, uint32_t i)
{
    const float *p = m->positions + 3 * (size_t)i;
    return hl_v3(p[0], p[1], p[2]);
}

double scn_lod_geometric_error(const struct scn_mesh *fine, const struct scn_mesh *coarse)
{
    /* One-sided Hausdorff distance sampled at the fine vertices. Brute force: O(V·T) is at most a
     * few million point–triangle tests for the built-in chains, done once per scene build. */
    double worst = 0;
    for (uint32_t v = 0; v < fine->vertex_count; ++v) {
        hl_vec3d p = scn_vertex(fine, v);
        double best = INFINITY;
        for (uint32_t t = 0; t + 2 < coarse->index_count && best > worst; t += 3) {
            hl_vec3d q = scn_closest_on_triangle(p, scn_vertex(coarse, coarse->indices[t]),
                                                 scn_vertex(coarse, coarse->indices[t + 1]),
                                                 scn_vertex(coarse, coarse->indices[t + 2]));
            hl_vec3d d = hl_v3_sub(p, q);
            double dist = sqrt(hl_v3_dot(d, d));
            if (dist < best)
                best = dist;
        }
        /* `best > worst` above stops early: once p is known to be within worst, it cannot raise it. */
        if (best > worst && best < INFINITY)
            worst = best;
    }
    return worst;
}

double scn_lod_unique_freq(double eps_m, double bound_radius_m)
{
    /* What a level loses is a thin sliver between the two surfaces: ε across, a chord long.
     * Reddy (1998 §3.2) measures each lost feature's extent at several orientations and keeps the
     * HIGHEST frequency, i.e. the narrowest extent, ε. That extent is half a cycle, so the
     * frequency is f = 2R / (2ε) = R / ε cycles per object diameter (docs/scenes.md compares the
     * conservative reading, the sliver's length). ε ≥ R (the whole object lost) gives 1 cycle per
     * diameter at most; never below one half-cycle across the object. */
    double r = bound_radius_m;
    if (!(eps_m > 0))
        return INFINITY;
    if (!(r > 0))
        return 0.5;
    double f = r / eps_m;
    return f > 0.5 ? f : 0.5;
}
