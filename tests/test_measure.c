/* scene measures: the Hausdorff distance against brute force over all triangles (same samples,
 * same and independent point–triangle code) and against analytic cases, the sampling bound checked
 * empirically, the mesh hash against a value computed by hand, and lodsets packed into a scene
 * (an off-centre, rotated, scaled instance's world sphere holds all its vertices). */
#include "scene/scene_internal.h"
#include "test_util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double unit_shape(hl_vec3d d) { (void)d; return 1.0; }
static double bumpy_shape(hl_vec3d d) { return 1.0 + 0.15 * sin(5 * d.x) * cos(4 * d.y) + 0.05 * d.z; }

static double dist2_point_segment(hl_vec3d p, hl_vec3d a, hl_vec3d b)
{
    hl_vec3d ab = hl_v3_sub(b, a);
    double len2 = hl_v3_dot(ab, ab), t = len2 > 0 ? hl_v3_dot(hl_v3_sub(p, a), ab) / len2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    hl_vec3d d = hl_v3_sub(p, hl_v3_add(a, hl_v3_scale(ab, t)));
    return hl_v3_dot(d, d);
}

/* An independent point–triangle distance: project onto the plane, keep it if the projection is
 * inside (same-side tests), else the nearest of the three edges. */
static double dist_point_triangle_indep(hl_vec3d p, hl_vec3d a, hl_vec3d b, hl_vec3d c)
{
    hl_vec3d n = hl_v3_cross(hl_v3_sub(b, a), hl_v3_sub(c, a));
    double nn = hl_v3_dot(n, n);
    if (nn > 0) {
        double s = hl_v3_dot(hl_v3_sub(p, a), n) / nn;
        hl_vec3d q = hl_v3_sub(p, hl_v3_scale(n, s));
        double e0 = hl_v3_dot(hl_v3_cross(hl_v3_sub(b, a), hl_v3_sub(q, a)), n);
        double e1 = hl_v3_dot(hl_v3_cross(hl_v3_sub(c, b), hl_v3_sub(q, b)), n);
        double e2 = hl_v3_dot(hl_v3_cross(hl_v3_sub(a, c), hl_v3_sub(q, c)), n);
        if (e0 >= 0 && e1 >= 0 && e2 >= 0)
            return fabs(s) * sqrt(nn);
    }
    double d = dist2_point_segment(p, a, b), d1 = dist2_point_segment(p, b, c), d2 = dist2_point_segment(p, c, a);
    d = d1 < d ? d1 : d;
    d = d2 < d ? d2 : d;
    return sqrt(d);
}

static hl_vec3d vtx(const struct scn_mesh *m, uint32_t i)
{
    return hl_v3(m->positions[3 * i], m->positions[3 * i + 1], m->positions[3 * i + 2]);
}

/* One direction by brute force over every triangle; returns the max, *mean the area-weighted mean,
 * *worst_dev the largest gap to the independent distance. */
static double brute_one_sided(const struct scn_mesh *from, const struct scn_mesh *to, uint64_t n, uint64_t seed,
                              double *mean, double *worst_dev, double *upper, int *mismatches)
{
    struct hl_error err = {""};
    struct scn_surface_samples s;
    struct scn_tri_bvh bvh;
    CHECK(scn_surface_sample(from, n, seed, &s, &err) == 0);
    CHECK(scn_tri_bvh_build(to, &bvh, &err) == 0);
    double worst = 0, sum = 0, wsum = 0;
    *worst_dev = 0, *upper = 0;
    for (uint64_t i = 0; i < s.count; ++i) {
        hl_vec3d p = hl_v3(s.points[3 * i], s.points[3 * i + 1], s.points[3 * i + 2]);
        double best2 = INFINITY, indep = INFINITY;
        for (uint32_t t = 0; t < to->index_count; t += 3) {
            hl_vec3d a = vtx(to, to->indices[t]), b = vtx(to, to->indices[t + 1]), c = vtx(to, to->indices[t + 2]);
            hl_vec3d d = hl_v3_sub(p, scn_closest_on_triangle(p, a, b, c));
            double d2 = hl_v3_dot(d, d);
            best2 = d2 < best2 ? d2 : best2;
            double e = dist_point_triangle_indep(p, a, b, c);
            indep = e < indep ? e : indep;
        }
        double best = sqrt(best2);
        if (scn_tri_bvh_distance(&bvh, p, NULL) != best)
            ++*mismatches;
        double dev = fabs(best - indep);
        *worst_dev = dev > *worst_dev ? dev : *worst_dev;
        worst = best > worst ? best : worst;
        *upper = best + s.reach_m[i] > *upper ? best + s.reach_m[i] : *upper;
        sum += s.weight_m2[i] * best;
        wsum += s.weight_m2[i];
    }
    *mean = sum / wsum;
    scn_surface_samples_free(&s);
    scn_tri_bvh_free(&bvh);
    return worst;
}

/* small (valgrind-tests.sh): the brute-force comparison on 5000 samples a side instead of 20000, and
 * the bunny's distances from a tenth of the samples; every vertex is still a sample, so the
 * translated copy's exact support point is still found. */
static int small;

static void test_against_brute_force(void)
{
    struct scn_mesh fine = {0}, coarse = {0};
    scn_mesh_add_sphere(&fine, 1.0, 12, 16, bumpy_shape);  /* 384 triangles */
    scn_mesh_add_sphere(&coarse, 1.0, 5, 8, bumpy_shape);  /* 80 */
    struct hl_error err = {""};
    struct scn_hausdorff h;
    const uint64_t n = small ? 5000 : 20000, seed = 7; /* small: the brute force is most of the time */
    CHECK(scn_mesh_hausdorff(&fine, &coarse, n, seed, &h, &err) == 0);
    double mean_ab, mean_ba, dev_ab, dev_ba, up_a, up_b;
    int mism = 0;
    double max_ab = brute_one_sided(&fine, &coarse, n, SCN_HAUSDORFF_SEED_A(seed), &mean_ab, &dev_ab, &up_a, &mism);
    double max_ba = brute_one_sided(&coarse, &fine, n, SCN_HAUSDORFF_SEED_B(seed), &mean_ba, &dev_ba, &up_b, &mism);
    printf("  sphere 384 vs 80 tris: max %.6f mean %.6f bound %.6f samples %llu (indep. dev %.2g)\n", h.max_m,
           h.mean_m, h.bound_m, (unsigned long long)h.samples, dev_ab > dev_ba ? dev_ab : dev_ba);
    CHECK(mism == 0); /* the BVH answer equals brute force, bit for bit */
    CHECK(h.max_m == (max_ab > max_ba ? max_ab : max_ba));
    CHECK(h.mean_m == 0.5 * (mean_ab + mean_ba));
    CHECK(h.bound_m == (up_a > up_b ? up_a : up_b) - h.max_m);
    CHECK(dev_ab < 1e-12 && dev_ba < 1e-12);
    CHECK(h.max_m > 0.01 && h.max_m < 0.5);
    CHECK(h.samples >= n && h.samples <= 2 * n + fine.vertex_count + coarse.vertex_count);
    /* Deterministic for a seed, and another seed stays within the bound of it. */
    struct scn_hausdorff h2, h3;
    CHECK(scn_mesh_hausdorff(&fine, &coarse, n, seed, &h2, &err) == 0);
    CHECK(memcmp(&h, &h2, sizeof h) == 0);
    CHECK(scn_mesh_hausdorff(&fine, &coarse, n, seed + 1, &h3, &err) == 0);
    CHECK(h3.mean_m != h.mean_m); /* the max sits on a vertex, a sample for every seed */
    CHECK(fabs(h3.max_m - h.max_m) <= h.bound_m + h3.bound_m);
    /* Symmetric: swapping the meshes swaps the directions, not the maximum's meaning. */
    struct scn_hausdorff hs;
    CHECK(scn_mesh_hausdorff(&coarse, &fine, 50000, seed, &hs, &err) == 0);
    CHECK(fabs(hs.max_m - h.max_m) <= h.bound_m + hs.bound_m);
    scn_mesh_free(&fine);
    scn_mesh_free(&coarse);
}

static void test_sampling_bound(void)
{
    /* The stated spacing: random surface points (an independent stream) must all lie within
     * spacing_m of some sample. A sliver is included: it needs samples along its length. */
    struct scn_mesh m = {0};
    scn_mesh_add_sphere(&m, 0.7, 4, 6, bumpy_shape);
    uint32_t a = scn_mesh_add_vertex(&m, hl_v3(2, 0, 0), hl_v3(0, 0, 1));
    uint32_t b = scn_mesh_add_vertex(&m, hl_v3(4, 0, 0), hl_v3(0, 0, 1));
    uint32_t c = scn_mesh_add_vertex(&m, hl_v3(3, 0.01, 0), hl_v3(0, 0, 1));
    scn_mesh_add_triangle(&m, a, b, c);
    (void)scn_mesh_add_vertex(&m, hl_v3(50, 50, 50), hl_v3(0, 0, 1)); /* unreferenced: not sampled */
    struct scn_surface_samples s;
    struct hl_error err = {""};
    CHECK(scn_surface_sample(&m, 3000, 3, &s, &err) == 0);
    double area = 0;
    for (uint32_t t = 0; t < m.index_count; t += 3) {
        hl_vec3d p0 = vtx(&m, m.indices[t]), p1 = vtx(&m, m.indices[t + 1]), p2 = vtx(&m, m.indices[t + 2]);
        area += 0.5 * hl_v3_length(hl_v3_cross(hl_v3_sub(p1, p0), hl_v3_sub(p2, p0)));
    }
    double wsum = 0;
    int far = 0;
    for (uint64_t i = 0; i < s.count; ++i) {
        wsum += s.weight_m2[i];
        if (fabs(s.points[3 * i] - 50) < 1)
            ++far;
    }
    CHECK_NEAR(wsum, area, 1e-12 * area);
    CHECK(far == 0);
    CHECK(s.count <= 3000 + m.vertex_count);
    int reach_over = 0;
    for (uint64_t i = 0; i < s.count; ++i)
        reach_over += !(s.reach_m[i] <= s.spacing_m);
    CHECK(reach_over == 0);
    struct scn_rng g = {12345};
    double worst_ratio = 0;
    int uncovered = 0;
    for (int k = 0; k < 3000; ++k) {
        uint32_t t = 3 * (uint32_t)(scn_rng_uniform(&g) * (m.index_count / 3));
        double r1 = scn_rng_uniform(&g), r2 = scn_rng_uniform(&g);
        if (r1 + r2 > 1)
            r1 = 1 - r1, r2 = 1 - r2;
        hl_vec3d p0 = vtx(&m, m.indices[t]), p1 = vtx(&m, m.indices[t + 1]), p2 = vtx(&m, m.indices[t + 2]);
        hl_vec3d p = hl_v3_add(p0, hl_v3_add(hl_v3_scale(hl_v3_sub(p1, p0), r1), hl_v3_scale(hl_v3_sub(p2, p0), r2)));
        double best = INFINITY, covered = INFINITY;
        for (uint64_t i = 0; i < s.count; ++i) {
            double d = hl_v3_length(hl_v3_sub(p, hl_v3(s.points[3 * i], s.points[3 * i + 1], s.points[3 * i + 2])));
            best = d < best ? d : best;
            covered = d - s.reach_m[i] < covered ? d - s.reach_m[i] : covered;
        }
        uncovered += covered > 1e-12; /* some sample's reach holds p */
        worst_ratio = best / s.spacing_m > worst_ratio ? best / s.spacing_m : worst_ratio;
    }
    printf("  sampling: %llu samples, spacing %.4f m, farthest test point at %.2f spacing\n",
           (unsigned long long)s.count, s.spacing_m, worst_ratio);
    CHECK(worst_ratio <= 1.0);
    CHECK(uncovered == 0);
    CHECK(worst_ratio > 0.1); /* the bound is not absurdly loose */
    scn_surface_samples_free(&s);
    scn_mesh_free(&m);
}

static void add_quad(struct scn_mesh *m, hl_vec3d o, hl_vec3d u, hl_vec3d v)
{
    hl_vec3d n = hl_v3_normalize(hl_v3_cross(u, v));
    uint32_t a = scn_mesh_add_vertex(m, o, n), b = scn_mesh_add_vertex(m, hl_v3_add(o, u), n);
    uint32_t c = scn_mesh_add_vertex(m, hl_v3_add(hl_v3_add(o, u), v), n), d = scn_mesh_add_vertex(m, hl_v3_add(o, v), n);
    scn_mesh_add_triangle(m, a, b, c);
    scn_mesh_add_triangle(m, a, c, d);
}

static void translate(struct scn_mesh *m, hl_vec3d t)
{
    for (uint32_t i = 0; i < m->vertex_count; ++i) {
        m->positions[3 * i] += (float)t.x;
        m->positions[3 * i + 1] += (float)t.y;
        m->positions[3 * i + 2] += (float)t.z;
    }
}

static void test_analytic(void)
{
    struct hl_error err = {""};
    struct scn_hausdorff h;
    /* Two parallel unit squares d apart: every point is exactly d from the other. */
    struct scn_mesh sq0 = {0}, sq1 = {0};
    add_quad(&sq0, hl_v3(0, 0, 0), hl_v3(1, 0, 0), hl_v3(0, 1, 0));
    add_quad(&sq1, hl_v3(0, 0, 0.25), hl_v3(1, 0, 0), hl_v3(0, 1, 0));
    CHECK(scn_mesh_hausdorff(&sq0, &sq1, 5000, 1, &h, &err) == 0);
    CHECK_NEAR(h.max_m, 0.25, 1e-12);
    CHECK_NEAR(h.mean_m, 0.25, 1e-12);
    CHECK(h.bound_m > 0 && h.bound_m < 0.05);
    /* Identical meshes: 0. */
    struct scn_mesh sph = {0}, sph2 = {0};
    scn_mesh_add_sphere(&sph, 1.0, 24, 48, bumpy_shape);
    scn_mesh_add_sphere(&sph2, 1.0, 24, 48, bumpy_shape);
    CHECK(scn_mesh_hausdorff(&sph, &sph2, 100000, 2, &h, &err) == 0);
    CHECK(h.max_m < 1e-6 && h.mean_m < 1e-7); /* float vertices, double samples: rounding only */
    /* A cube [-1,1]³ against the unit sphere inscribed in it: the corners are √3 − 1 from the
     * sphere, the farthest the two get. The tessellated sphere lies inside the true one by at most
     * 1 − cos(π/48)·cos(π/96) (its facets' sag), so the distance is within that above √3 − 1. */
    struct scn_mesh cube = {0}, ball = {0};
    scn_mesh_add_box(&cube, hl_v3(0, 0, 0), hl_v3(1, 1, 1), hl_q_identity());
    scn_mesh_add_sphere(&ball, 1.0, 47, 96, unit_shape);
    CHECK(scn_mesh_hausdorff(&cube, &ball, 60000, 3, &h, &err) == 0);
    double sag = 1 - cos(HL_PI / 48) * cos(HL_PI / 96);
    printf("  cube vs inscribed sphere: max %.6f (√3−1 = %.6f, sag %.4f) bound %.5f\n", h.max_m, sqrt(3) - 1, sag,
           h.bound_m);
    CHECK(h.max_m >= sqrt(3) - 1 - 1e-6); /* a cube corner is a sample */
    CHECK(h.max_m <= sqrt(3) - 1 + sag + 1e-6);
    /* A closed box against itself translated by t: |t| (a corner moves |t| off the other box),
     * sampled from below within the bound. */
    struct scn_mesh box = {0}, moved = {0};
    scn_mesh_add_box(&box, hl_v3(0.3, -0.2, 0.1), hl_v3(0.5, 0.4, 0.3), hl_q_from_axis_angle(hl_v3(0, 0, 1), 0));
    scn_mesh_add_box(&moved, hl_v3(0.3, -0.2, 0.1), hl_v3(0.5, 0.4, 0.3), hl_q_identity());
    hl_vec3d t = hl_v3(0.03, -0.02, 0.01);
    translate(&moved, t);
    CHECK(scn_mesh_hausdorff(&box, &moved, 50000, 4, &h, &err) == 0);
    CHECK(h.max_m <= hl_v3_length(t) + 1e-6);
    CHECK(h.max_m + h.bound_m >= hl_v3_length(t) - 1e-6);
    CHECK_NEAR(h.max_m, hl_v3_length(t), 1e-6); /* the corner is a vertex sample */
    /* Bad input is refused with a message, not a crash. */
    struct scn_mesh empty = {0};
    err.msg[0] = 0;
    CHECK(scn_mesh_hausdorff(&empty, &box, 100, 1, &h, &err) < 0 && strstr(err.msg, "mesh A"));
    CHECK(h.max_m == 0 && h.samples == 0);
    moved.indices[5] = 999;
    err.msg[0] = 0;
    CHECK(scn_mesh_hausdorff(&box, &moved, 100, 1, &h, &err) < 0 && strstr(err.msg, "mesh B") &&
          strstr(err.msg, "999"));
    moved.indices[5] = 0;
    moved.positions[4] = NAN;
    CHECK(scn_mesh_hausdorff(&box, &moved, 100, 1, &h, &err) < 0 && strstr(err.msg, "not finite"));
    scn_mesh_free(&sq0), scn_mesh_free(&sq1), scn_mesh_free(&sph), scn_mesh_free(&sph2);
    scn_mesh_free(&cube), scn_mesh_free(&ball), scn_mesh_free(&box), scn_mesh_free(&moved);
}

static void test_hash(void)
{
    /* python3: h = FNV-1a 64 over struct.pack('<II', 3, 3) + struct.pack('<9f', 0,0,0, 1,0,0,
     * 0,0.5,0.25) + struct.pack('<3I', 0,1,2) → 0x1d0ec50ef22b72a8 */
    struct scn_mesh m = {0};
    scn_mesh_add_vertex(&m, hl_v3(0, 0, 0), hl_v3(0, 0, 1));
    scn_mesh_add_vertex(&m, hl_v3(1, 0, 0), hl_v3(0, 0, 1));
    scn_mesh_add_vertex(&m, hl_v3(0, 0.5, 0.25), hl_v3(0, 0, 1));
    scn_mesh_add_triangle(&m, 0, 1, 2);
    CHECK(scn_mesh_hash(&m) == 0x1d0ec50ef22b72a8ull);
    m.normals[0] = 0.5f; /* normals are not hashed */
    CHECK(scn_mesh_hash(&m) == 0x1d0ec50ef22b72a8ull);
    m.positions[7] = 0.5000001f;
    CHECK(scn_mesh_hash(&m) != 0x1d0ec50ef22b72a8ull);
    struct scn_mesh empty = {0};
    /* Empty mesh: FNV-1a of eight zero bytes. */
    uint64_t h = 0xcbf29ce484222325ull;
    for (int i = 0; i < 8; ++i)
        h = (h ^ 0) * 0x100000001b3ull;
    CHECK(scn_mesh_hash(&empty) == h);
    scn_mesh_free(&m);
}

static void test_add_lodset(void)
{
    /* An off-centre object: a bumpy sphere at (5, 2, −3) then a box, as a lodset centred there. */
    struct scn_lodset set = {0};
    hl_vec3d c = hl_v3(5, 2, -3);
    scn_mesh_add_sphere(&set.levels[0], 0.8, 10, 16, bumpy_shape);
    translate(&set.levels[0], c);
    scn_mesh_add_box(&set.levels[1], hl_v3(5, 2, -3), hl_v3(0.7, 0.9, 0.6), hl_q_identity());
    set.level_count = 2;
    set.center_m[0] = c.x, set.center_m[1] = c.y, set.center_m[2] = c.z;
    set.radius_m = 0.8; /* deliberately too small for the box corners: packing must grow it */
    set.error_m[1] = 0.12;
    set.freq[0] = (struct scn_level_freq){INFINITY, INFINITY, INFINITY};
    set.freq[1] = (struct scn_level_freq){21.5, 7.25, NAN};
    struct scn_scene s = {0};
    struct hl_error err = {""};
    CHECK(scn_scene_build("field", &(struct scn_scene_params){.object_count = 3}, &s, &err) == 0);
    uint32_t before = s.chain_count, vbefore = s.vertex_count;
    CHECK(scn_scene_add_lodset(&s, "blob", &set, &err) == 0);
    CHECK(s.chain_count == before + 1);
    const struct scn_chain *ch = &s.chains[before];
    CHECK(strcmp(ch->name, "blob") == 0 && ch->lod_count == 2);
    CHECK(ch->lods[1].geometric_error_m == 0.12);
    CHECK(ch->lods[1].freq.narrow_cpdiam == 21.5 && ch->lods[1].freq.long_cpdiam == 7.25 &&
          isnan(ch->lods[1].freq.geometric_cpdiam));
    CHECK(isinf(ch->lods[0].unique_freq_cpdiam));
    CHECK_NEAR(ch->lods[1].unique_freq_cpdiam, ch->bound_radius_m / 0.12, 1e-12); /* NaN → R/ε */
    CHECK(ch->bound_radius_m >= sqrt(0.7 * 0.7 + 0.9 * 0.9 + 0.6 * 0.6) - 1e-6);
    CHECK(ch->bound_radius_m < 1.5); /* about the centre, not the origin (|c| ≈ 6.2) */
    /* The box level's mean front-facing area: a quarter of 2(ab + bc + ca) for its 1.4 × 1.8 × 1.2 m;
     * its fill of the bounding disc, and of the chain's box (which the sphere level widens to ±0.8). */
    double front_m2 = 0.25 * 2.0 * (1.4 * 1.8 + 1.8 * 1.2 + 1.2 * 1.4);
    CHECK_NEAR(ch->lods[1].front_area_m2, front_m2, 1e-5);
    /* (front_area_m2 is summed from the mesh's float positions: 1e-5 relative) */
    CHECK_NEAR(scn_lod_fill(ch, 1, 0), front_m2 / (HL_PI * ch->bound_radius_m * ch->bound_radius_m), 1e-5);
    double e[3] = {ch->box_max_m[0] - ch->box_min_m[0], ch->box_max_m[1] - ch->box_min_m[1],
                   ch->box_max_m[2] - ch->box_min_m[2]};
    CHECK(e[0] > 1.4 && e[2] > 1.2);
    CHECK_NEAR(scn_lod_fill(ch, 1, 1), front_m2 / (0.5 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0])), 1e-5);
    CHECK(scn_lod_fill(ch, 1, 1) < 1.0 && scn_lod_fill(ch, 1, 1) > 0.7);
    /* the bumpy sphere of radius about 0.8 in a bound grown to the box's corners: about (0.8 / R)², the
     * bumps (±15 %) moving it a little */
    double r = 0.8 / ch->bound_radius_m;
    CHECK_NEAR(scn_lod_fill(ch, 0, 0), r * r, 0.15 * r * r);
    CHECK(s.vertex_count == vbefore + set.levels[0].vertex_count + set.levels[1].vertex_count);
    CHECK(ch->lods[1].first_index == ch->lods[0].first_index + ch->lods[0].index_count);
    for (uint32_t k = 0; k < ch->lods[1].index_count; ++k) /* indices made absolute */
        CHECK(s.indices[ch->lods[1].first_index + k] == set.levels[1].indices[k] + vbefore + set.levels[0].vertex_count);
    /* Instances with rotation and scale: the world sphere holds every world vertex of both levels. */
    uint32_t chain = before, n = 4;
    free(s.instances), free(s.center_m), free(s.radius_m), free(s.chain_of_instance);
    CHECK(scn_scene_alloc_instances(&s, n, &err) == 0);
    struct scn_rng g = {99};
    float color[3] = {1, 1, 1};
    int outside = 0;
    for (uint32_t i = 0; i < n; ++i) {
        double slack_min = INFINITY;
        hl_vec3d pos = hl_v3(10 * scn_rng_uniform(&g) - 5, 3 * scn_rng_uniform(&g), -20 * scn_rng_uniform(&g));
        hl_quatd rot = scn_rng_rotation(&g);
        double scale = 0.3 + 3 * scn_rng_uniform(&g);
        scn_scene_set_instance(&s, i, chain, pos, rot, scale, color);
        hl_vec3d wc = hl_v3(s.center_m[3 * i], s.center_m[3 * i + 1], s.center_m[3 * i + 2]);
        for (int l = 0; l < ch->lod_count; ++l)
            for (uint32_t k = 0; k < set.levels[l].vertex_count; ++k) {
                hl_vec3d w = hl_v3_add(pos, hl_q_rotate(rot, hl_v3_scale(vtx(&set.levels[l], k), scale)));
                double gap = s.radius_m[i] - hl_v3_length(hl_v3_sub(w, wc));
                outside += gap < -1e-9;
                slack_min = gap < slack_min ? gap : slack_min;
            }
        CHECK(slack_min < 1e-6 * s.radius_m[i]); /* and tight: a box corner touches it */
    }
    CHECK(outside == 0);
    /* A lodset whose levels do not decrease is refused, the scene left as it was. */
    struct scn_lodset bad = {0};
    scn_mesh_add_box(&bad.levels[0], hl_v3(0, 0, 0), hl_v3(1, 1, 1), hl_q_identity());
    scn_mesh_add_box(&bad.levels[1], hl_v3(0, 0, 0), hl_v3(1, 1, 1), hl_q_identity());
    bad.level_count = 2;
    uint32_t chains = s.chain_count;
    err.msg[0] = 0;
    CHECK(scn_scene_add_lodset(&s, "bad", &bad, &err) < 0 && strstr(err.msg, "not fewer"));
    CHECK(s.chain_count == chains);
    scn_lodset_free(&bad);
    scn_lodset_free(&set);
    scn_scene_free(&s);
}

/* The bunny (if ../shared is there): against its 50 % level the BVH agrees with brute force on a
 * subset of samples; against itself translated by t the distance is |t| (the support point in t's
 * direction moves |t| off the other copy, and nothing moves more). HMDLOD_MEASURE_SAMPLES sets the
 * samples per mesh of the timed run (default 200000); the time is printed, never checked. */
static void test_bunny(void)
{
    const char *path = tu_shared_path("data/meshes/stanford-bunny.obj");
    if (!path)
        return;
    struct hl_error err = {""};
    struct scn_mesh bunny = {0}, half = {0}, moved = {0};
    CHECK(scn_mesh_import(path, &bunny, NULL, &err) == 0);
    CHECK(scn_mesh_decimate(&bunny, bunny.index_count / 6, SCN_SIMPLIFIER_MESHOPT, 0, &half, &err) == 0);
    if (bunny.index_count == 0 || half.index_count == 0) {
        printf("  bunny: %s\n", err.msg);
        scn_mesh_free(&bunny), scn_mesh_free(&half);
        return;
    }
    const char *env = getenv("HMDLOD_MEASURE_SAMPLES");
    uint64_t n = env && *env ? strtoull(env, NULL, 10) : small ? 20000 : 200000, n_check = small ? 20000 : 100000;
    struct scn_hausdorff h;
    double t0 = hl_clock_now_s();
    CHECK(scn_mesh_hausdorff(&bunny, &half, n, 1, &h, &err) == 0);
    double t1 = hl_clock_now_s();
    printf("  bunny %u vs %u tris, %llu samples per mesh: max %.4g m mean %.4g m bound %.4g m, %llu samples, "
           "%.3f s\n", bunny.index_count / 3, half.index_count / 3, (unsigned long long)n, h.max_m, h.mean_m,
           h.bound_m, (unsigned long long)h.samples, t1 - t0);
    CHECK(h.max_m > 0 && h.max_m < 0.005);
    /* 300 samples of the bunny, brute force over the half level's triangles. */
    struct scn_surface_samples s;
    struct scn_tri_bvh bvh;
    CHECK(scn_surface_sample(&bunny, 300, 5, &s, &err) == 0 && scn_tri_bvh_build(&half, &bvh, &err) == 0);
    int mism = 0;
    uint32_t hint = UINT32_MAX;
    for (uint64_t i = 0; i < s.count; i += s.count / 300) {
        hl_vec3d p = hl_v3(s.points[3 * i], s.points[3 * i + 1], s.points[3 * i + 2]);
        double best2 = INFINITY;
        for (uint32_t t = 0; t < half.index_count; t += 3) {
            hl_vec3d d = hl_v3_sub(p, scn_closest_on_triangle(p, vtx(&half, half.indices[t]), vtx(&half, half.indices[t + 1]),
                                                              vtx(&half, half.indices[t + 2])));
            best2 = hl_v3_dot(d, d) < best2 ? hl_v3_dot(d, d) : best2;
        }
        mism += scn_tri_bvh_distance(&bvh, p, &hint) != sqrt(best2);
    }
    CHECK(mism == 0);
    scn_surface_samples_free(&s);
    scn_tri_bvh_free(&bvh);
    /* Translated copy. */
    moved = bunny;
    moved.positions = malloc(12 * (size_t)bunny.vertex_count);
    moved.normals = malloc(12 * (size_t)bunny.vertex_count);
    moved.indices = malloc(4 * (size_t)bunny.index_count);
    memcpy(moved.positions, bunny.positions, 12 * (size_t)bunny.vertex_count);
    memcpy(moved.normals, bunny.normals, 12 * (size_t)bunny.vertex_count);
    memcpy(moved.indices, bunny.indices, 4 * (size_t)bunny.index_count);
    hl_vec3d t = hl_v3(0.002, -0.001, 0.0015);
    translate(&moved, t);
    CHECK(scn_mesh_hausdorff(&bunny, &moved, n_check, 2, &h, &err) == 0);
    printf("  bunny vs itself moved %.5f m: max %.6f bound %.6f\n", hl_v3_length(t), h.max_m, h.bound_m);
    CHECK(h.max_m <= hl_v3_length(t) + 1e-6 && h.max_m + h.bound_m >= hl_v3_length(t) - 1e-6);
    CHECK_NEAR(h.max_m, hl_v3_length(t), 1e-6); /* float rounding of the moved vertices only */
    CHECK(scn_mesh_hausdorff(&bunny, &bunny, n_check, 2, &h, &err) == 0);
    CHECK(h.max_m < 1e-9);
    scn_mesh_free(&bunny), scn_mesh_free(&half), scn_mesh_free(&moved);
}

int main(int argc, char **argv)
{
    small = argc > 1 && strcmp(argv[1], "small") == 0;
    test_hash();
    test_against_brute_force();
    test_sampling_bound();
    test_analytic();
    test_add_lodset();
    test_bunny();
    return tu_finish(small ? "measure small" : "measure");
}
