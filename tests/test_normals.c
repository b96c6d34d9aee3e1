/* scn_mesh_crease_normals (scene/mesh_normals.c): a cube split into its 6 flat faces at 60° and kept
 * whole at 100°, a smooth sphere left alone, a non-manifold edge split, a zero-area face ignored,
 * and fandisk's LOD chain: every level's normals unit length, NaN-free and within the crease angle of
 * every face that uses them, with source_hash still the welded import's. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene/scene.h"
#include "scene/scene_internal.h"
#include "tests/test_util.h"

static hl_vec3d pos(const struct scn_mesh *m, uint32_t i)
{
    const float *p = m->positions + 3 * (size_t)i;
    return hl_v3(p[0], p[1], p[2]);
}

static hl_vec3d nrm(const struct scn_mesh *m, uint32_t i)
{
    const float *n = m->normals + 3 * (size_t)i;
    return hl_v3(n[0], n[1], n[2]);
}

static hl_vec3d face_normal(const struct scn_mesh *m, uint32_t t)
{
    const uint32_t *f = m->indices + 3 * (size_t)t;
    hl_vec3d a = pos(m, f[0]);
    return hl_v3_cross(hl_v3_sub(pos(m, f[1]), a), hl_v3_sub(pos(m, f[2]), a));
}

/* Every normal finite and unit length (float rounding allowed). */
static int normals_unit(const struct scn_mesh *m)
{
    for (uint32_t i = 0; i < m->vertex_count; ++i) {
        double len = hl_v3_length(nrm(m, i));
        if (!isfinite(len) || fabs(len - 1.0) > 1e-5)
            return 0;
    }
    return 1;
}

/* The largest angle, degrees, between a non-degenerate face's normal and the normal of any of its
 * corners' vertices. */
static double worst_corner_angle_deg(const struct scn_mesh *m)
{
    double worst_rad = 0;
    for (uint32_t t = 0; t < m->index_count / 3; ++t) {
        hl_vec3d fn = face_normal(m, t);
        if (!(hl_v3_length(fn) > 0))
            continue;
        for (int k = 0; k < 3; ++k) {
            hl_vec3d n = nrm(m, m->indices[3 * (size_t)t + k]);
            double a = atan2(hl_v3_length(hl_v3_cross(fn, n)), hl_v3_dot(fn, n));
            worst_rad = a > worst_rad ? a : worst_rad;
        }
    }
    return worst_rad / HL_RAD_PER_DEG;
}

/* The unit cube as 8 shared corners and 12 CCW-outward triangles (what a welded import gives). */
static void welded_cube(struct scn_mesh *m)
{
    memset(m, 0, sizeof *m);
    for (int i = 0; i < 8; ++i)
        scn_mesh_add_vertex(m, hl_v3(i & 1, (i >> 1) & 1, (i >> 2) & 1), hl_v3(0, 0, 1));
    static const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int q = 0; q < 6; ++q) {
        scn_mesh_add_triangle(m, quads[q][0], quads[q][1], quads[q][2]);
        scn_mesh_add_triangle(m, quads[q][0], quads[q][2], quads[q][3]);
    }
}

static void test_cube(void)
{
    struct scn_mesh m;
    welded_cube(&m);
    CHECK(!m.failed && m.vertex_count == 8 && m.index_count == 36);
    for (uint32_t t = 0; t < 12; ++t) /* the fixture itself: outward faces */
        CHECK(hl_v3_dot(face_normal(&m, t), hl_v3_sub(pos(&m, m.indices[3 * t]), hl_v3(0.5, 0.5, 0.5))) > 0);
    scn_mesh_crease_normals(&m, 60.0);
    CHECK(!m.failed && m.vertex_count == 24 && m.index_count == 36);
    CHECK(normals_unit(&m));
    /* Each vertex's normal is its face's axis exactly: one component ±1, the others 0. */
    int axis_aligned = 1;
    for (uint32_t i = 0; i < m.vertex_count; ++i) {
        hl_vec3d n = nrm(&m, i);
        double big = fmax(fabs(n.x), fmax(fabs(n.y), fabs(n.z)));
        axis_aligned &= big == 1.0 && fabs(n.x) + fabs(n.y) + fabs(n.z) == 1.0;
    }
    CHECK(axis_aligned);
    CHECK(worst_corner_angle_deg(&m) < 1e-6);
    /* Every corner still on the position it had: the copies are of the same eight points. */
    int on_corners = 1;
    for (uint32_t i = 0; i < m.vertex_count; ++i) {
        hl_vec3d p = pos(&m, i);
        on_corners &= (p.x == 0 || p.x == 1) && (p.y == 0 || p.y == 1) && (p.z == 0 || p.z == 1);
    }
    CHECK(on_corners);
    scn_mesh_free(&m);

    /* Above the cube's 90°: one smooth fan per corner, nothing split, normals pointing outwards. */
    welded_cube(&m);
    scn_mesh_crease_normals(&m, 100.0);
    CHECK(!m.failed && m.vertex_count == 8 && m.index_count == 36);
    CHECK(normals_unit(&m));
    int outward = 1;
    for (uint32_t i = 0; i < m.vertex_count; ++i) {
        hl_vec3d d = hl_v3_normalize(hl_v3_sub(pos(&m, i), hl_v3(0.5, 0.5, 0.5)));
        outward &= hl_v3_dot(d, nrm(&m, i)) > 0.9;
    }
    CHECK(outward);
    scn_mesh_free(&m);

    /* A zero-area face (three collinear corners) adds no vertex and no NaN. */
    welded_cube(&m);
    uint32_t mid = scn_mesh_add_vertex(&m, hl_v3(0.5, 0, 0), hl_v3(0, 0, 0));
    scn_mesh_add_triangle(&m, 0, mid, 1);
    scn_mesh_crease_normals(&m, 60.0);
    CHECK(!m.failed && m.vertex_count == 25 && m.index_count == 39);
    CHECK(normals_unit(&m));
    scn_mesh_free(&m);
}

static double unit_shape(hl_vec3d dir)
{
    (void)dir;
    return 1.0;
}

static void test_sphere(void)
{
    struct scn_mesh m = {0};
    scn_mesh_add_sphere(&m, 1.0, 15, 32, unit_shape); /* neighbouring faces ≤ about 12° apart */
    uint32_t nv = m.vertex_count, ni = m.index_count;
    scn_mesh_crease_normals(&m, 60.0);
    CHECK(!m.failed && m.vertex_count == nv && m.index_count == ni);
    CHECK(normals_unit(&m));
    int radial = 1;
    for (uint32_t i = 0; i < m.vertex_count; ++i)
        radial &= hl_v3_dot(hl_v3_normalize(pos(&m, i)), nrm(&m, i)) > 0.995;
    CHECK(radial);
    scn_mesh_free(&m);
}

/* Three triangles on one edge 0–1: no single dihedral angle, so a crease even at 179°: vertices 0
 * and 1 get one copy per face (3 each), the three apexes stay. A fourth face joined smoothly to the
 * first along 1–2 shows the rest of the mesh is still smoothed. */
static void test_nonmanifold(void)
{
    struct scn_mesh m = {0};
    scn_mesh_add_vertex(&m, hl_v3(0, 0, 0), hl_v3(0, 0, 1));
    scn_mesh_add_vertex(&m, hl_v3(1, 0, 0), hl_v3(0, 0, 1));
    scn_mesh_add_vertex(&m, hl_v3(0.5, 1, 0), hl_v3(0, 0, 1));
    scn_mesh_add_vertex(&m, hl_v3(0.5, -1, 0), hl_v3(0, 0, 1));
    scn_mesh_add_vertex(&m, hl_v3(0.5, 0, 1), hl_v3(0, 0, 1));
    scn_mesh_add_vertex(&m, hl_v3(1.5, 1, 0.1), hl_v3(0, 0, 1));
    scn_mesh_add_triangle(&m, 0, 1, 2);
    scn_mesh_add_triangle(&m, 1, 0, 3);
    scn_mesh_add_triangle(&m, 0, 1, 4);
    scn_mesh_add_triangle(&m, 1, 5, 2);
    scn_mesh_crease_normals(&m, 179.0);
    CHECK(!m.failed && m.vertex_count == 6 + 2 + 2);
    CHECK(normals_unit(&m));
    /* faces 0 and 3 share their copies of vertices 1 and 2 (smooth edge 1–2) */
    CHECK(m.indices[1] == m.indices[9] && m.indices[2] == m.indices[11]);
    /* the three faces on edge 0–1 use three different copies of vertex 0 */
    CHECK(m.indices[0] != m.indices[4] && m.indices[0] != m.indices[6] && m.indices[4] != m.indices[6]);
    scn_mesh_free(&m);
}

static void test_fandisk_chain(int small)
{
    const char *path = tu_shared_path("data/meshes/fandisk.obj");
    if (!path)
        return;
    struct hl_error err = {{0}};
    struct scn_mesh m;
    struct scn_import_report r;
    CHECK(scn_mesh_import(path, &m, &r, &err) == 0);
    struct scn_lodgen_params p = {0};
    p.ratio_count = 4;
    p.ratios[0] = 1, p.ratios[1] = 0.5, p.ratios[2] = 0.25, p.ratios[3] = 0.125;
    p.hausdorff_samples = small ? 1u << 14 : 0; /* the levels' errors are not what this test checks */
    struct scn_lodset set;
    CHECK(scn_lodgen_build(&m, &p, &set, &err) == 0);
    CHECK(set.level_count == 4);
    CHECK(set.source_hash == scn_mesh_hash(&m)); /* the welded import's, not the split level 0's */
    for (int l = 0; l < set.level_count; ++l) {
        const struct scn_mesh *lv = &set.levels[l];
        double worst_deg = worst_corner_angle_deg(lv);
        printf("fandisk level %d: %u triangles, %u vertices, worst normal-to-face angle %.2f°\n", l,
               lv->index_count / 3, lv->vertex_count, worst_deg);
        CHECK(normals_unit(lv));
        CHECK(worst_deg < 60.0);
    }
    /* Level 0 keeps the import's triangles and positions; only creases add vertices. */
    CHECK(set.levels[0].index_count == m.index_count && set.levels[0].vertex_count > m.vertex_count);
    int same_positions = 1;
    for (uint32_t t = 0; t < m.index_count; ++t)
        for (int k = 0; k < 3; ++k)
            same_positions &= set.levels[0].positions[3 * (size_t)set.levels[0].indices[t] + k] ==
                              m.positions[3 * (size_t)m.indices[t] + k];
    CHECK(same_positions);
    scn_lodset_free(&set);
    scn_mesh_free(&m);
}

int main(int argc, char **argv)
{
    /* "small" (scripts/valgrind-tests.sh: memcheck runs this ~50x slower): the same checks, with the
     * chain's Hausdorff errors measured at 2^14 samples a mesh instead of the default 2^20. */
    int small = argc > 1 && strcmp(argv[1], "small") == 0;
    test_cube();
    test_sphere();
    test_nonmanifold();
    test_fandisk_chain(small);
    return tu_finish(small ? "normals small" : "normals");
}
