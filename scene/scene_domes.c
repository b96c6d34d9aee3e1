/* "domes": the experiment of Mason & Blake (1997 §8) — geodesic domes built from cylinders. Each
 * cylinder (strut) has six drawable LODs plus the null impostor ("no representation", the
 * non-hierarchical case); each dome is one group whose impostor is a low-resolution sphere (the
 * hierarchical case); the domes rotate about their own axes and oscillate towards and away from the
 * viewer "so as to force the continual update of the detail levels". docs/domes.md has the numbers.
 *
 * The paper gives neither the dome frequency nor the number of domes; here each dome is the
 * frequency-2 geodesic sphere (the icosahedron with every edge halved and pushed out to the sphere:
 * 42 hubs, 120 struts in two lengths) — a full sphere because its impostor is "a low resolution
 * sphere approximation". */
#include "scene/scene_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { DOMES_DEFAULT_COUNT = 10, DOMES_MAX_COUNT = 1000, DOMES_LEVELS = 6 };
enum { GEO_VERTICES = 42, GEO_EDGES = 120, GEO_FACES = 80 };

/* Segments around each strut per LOD: 4·segments triangles = 96/64/48/32/24/16, strictly fewer. */
static const int domes_segments[DOMES_LEVELS] = {24, 16, 12, 8, 6, 4};
static const double domes_strut_radius = 0.025;         /* at unit dome radius */
static const int domes_impostor_rings = 4, domes_impostor_segments = 8; /* 64 triangles */
static const double domes_near_m = 8.0, domes_far_m = 30.0;

static const float domes_palette[6][3] = {
    {0.85f, 0.72f, 0.40f}, {0.55f, 0.70f, 0.85f}, {0.80f, 0.50f, 0.45f},
    {0.55f, 0.78f, 0.55f}, {0.75f, 0.60f, 0.82f}, {0.82f, 0.82f, 0.78f},
};

struct geodesic {
    hl_vec3d v[GEO_VERTICES];
    int edge[GEO_EDGES][2];
    int vertex_count, edge_count;
};

static int geo_vertex(struct geodesic *g, hl_vec3d p)
{
    p = hl_v3_normalize(p);
    for (int i = 0; i < g->vertex_count; ++i) { /* 42 points: a linear search is the clearest */
        hl_vec3d d = hl_v3_sub(g->v[i], p);
        if (hl_v3_dot(d, d) < 1e-18)
            return i;
    }
    g->v[g->vertex_count] = p;
    return g->vertex_count++;
}

static void geo_edge(struct geodesic *g, int a, int b)
{
    for (int e = 0; e < g->edge_count; ++e)
        if ((g->edge[e][0] == a && g->edge[e][1] == b) || (g->edge[e][0] == b && g->edge[e][1] == a))
            return;
    g->edge[g->edge_count][0] = a, g->edge[g->edge_count][1] = b;
    g->edge_count++;
}

/* Class I, frequency 2: each icosahedron face splits into four by its edge midpoints. */
static void geodesic_build(struct geodesic *g)
{
    const double t = (1.0 + sqrt(5.0)) / 2.0;
    static const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                     {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                     {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                     {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    const hl_vec3d ico[12] = {hl_v3(-1, t, 0), hl_v3(1, t, 0), hl_v3(-1, -t, 0), hl_v3(1, -t, 0),
                              hl_v3(0, -1, t), hl_v3(0, 1, t), hl_v3(0, -1, -t), hl_v3(0, 1, -t),
                              hl_v3(t, 0, -1), hl_v3(t, 0, 1), hl_v3(-t, 0, -1), hl_v3(-t, 0, 1)};
    memset(g, 0, sizeof *g);
    for (int f = 0; f < 20; ++f) {
        hl_vec3d a = ico[faces[f][0]], b = ico[faces[f][1]], c = ico[faces[f][2]];
        int ia = geo_vertex(g, a), ib = geo_vertex(g, b), ic = geo_vertex(g, c);
        int iab = geo_vertex(g, hl_v3_add(a, b)), ibc = geo_vertex(g, hl_v3_add(b, c)), ica = geo_vertex(g, hl_v3_add(c, a));
        int tri[4][3] = {{ia, iab, ica}, {ib, ibc, iab}, {ic, ica, ibc}, {iab, ibc, ica}};
        for (int k = 0; k < 4; ++k)
            for (int j = 0; j < 3; ++j)
                geo_edge(g, tri[k][j], tri[k][(j + 1) % 3]);
    }
}

/* Shortest-arc rotation taking +Y onto the unit vector d (d = −Y: half a turn about X). */
static hl_quatd rotation_from_y(hl_vec3d d)
{
    hl_vec3d y = hl_v3(0, 1, 0), axis = hl_v3_cross(y, d);
    double s = hl_v3_length(axis);
    if (s < 1e-12)
        return hl_v3_dot(y, d) > 0 ? hl_q_identity() : hl_q_from_axis_angle(hl_v3(1, 0, 0), HL_PI);
    return hl_q_from_axis_angle(hl_v3_scale(axis, 1.0 / s), hl_v3_angle_rad(y, d));
}

static double dome_unit_shape(hl_vec3d d)
{
    (void)d;
    return 1.0;
}

static int domes_alloc_groups(struct scn_scene *s, uint32_t n_groups, uint32_t n_instances, struct hl_error *err)
{
    s->groups = calloc(n_groups, sizeof *s->groups);
    s->group_instances = calloc(n_instances ? n_instances : 1, sizeof *s->group_instances);
    s->group_children = calloc(1, sizeof *s->group_children); /* no child groups: never indexed */
    if (!s->groups || !s->group_instances || !s->group_children)
        return hl_fail(err, "scene domes: out of memory for %u groups", n_groups);
    s->group_count = n_groups;
    return 0;
}

int scn_scene_build_domes(const struct scn_scene_params *p, struct scn_scene *s, struct hl_error *err)
{
    int n = p->object_count == 0 ? DOMES_DEFAULT_COUNT : p->object_count;
    if (n < 1 || n > DOMES_MAX_COUNT)
        return hl_fail(err, "scene domes: object_count %d out of range (1…%d domes, 0 = %d)", p->object_count,
                       DOMES_MAX_COUNT, DOMES_DEFAULT_COUNT);
    snprintf(s->name, sizeof s->name, "domes");
    struct geodesic geo;
    geodesic_build(&geo);

    /* Strut chains, one per strut length (two for frequency 2), at unit dome radius: an instance's
     * scale is its dome's radius, so every dome shares the same chains. */
    double lengths[GEO_EDGES];
    int length_class[GEO_EDGES], class_count = 0;
    double class_length[GEO_EDGES];
    for (int e = 0; e < geo.edge_count; ++e) {
        lengths[e] = hl_v3_length(hl_v3_sub(geo.v[geo.edge[e][0]], geo.v[geo.edge[e][1]]));
        int c = 0;
        while (c < class_count && fabs(class_length[c] - lengths[e]) > 1e-9)
            ++c;
        if (c == class_count)
            class_length[class_count++] = lengths[e];
        length_class[e] = c;
    }
    for (int c = 0; c < class_count; ++c) {
        struct scn_mesh levels[DOMES_LEVELS] = {{0}};
        for (int l = 0; l < DOMES_LEVELS; ++l)
            scn_mesh_add_cylinder(&levels[l], hl_v3(0, 0, 0), domes_strut_radius, 0.5 * class_length[c],
                                  domes_segments[l], hl_q_identity());
        char name[SCN_NAME_MAX];
        snprintf(name, sizeof name, "strut_%c", 'a' + c);
        int rc = scn_scene_add_chain(s, name, levels, DOMES_LEVELS, err);
        for (int l = 0; l < DOMES_LEVELS; ++l)
            scn_mesh_free(&levels[l]);
        if (rc != 0)
            return -1;
        s->chains[s->chain_count - 1].null_impostor = 1; /* Mason & Blake §8: "no representation" */
    }

    uint32_t struts = (uint32_t)geo.edge_count;
    if (scn_scene_alloc_instances(s, (uint32_t)n * struts, err) != 0 ||
        domes_alloc_groups(s, (uint32_t)n, (uint32_t)n * struts, err) != 0)
        return -1;

    struct scn_rng g = {p->seed};
    double placed_c[DOMES_MAX_COUNT][3], placed_r[DOMES_MAX_COUNT];
    for (int d = 0; d < n; ++d) {
        /* Anywhere around the viewer (head turns reveal more), at most 20° above or below the
         * horizon, 8–30 m away; a few tries keep domes (with their swing) from interpenetrating. */
        double radius = 1.5 + 1.5 * scn_rng_uniform(&g), dist = 0, az = 0, el = 0;
        hl_vec3d c = hl_v3(0, 0, 0);
        for (int attempt = 0; attempt < 64; ++attempt) {
            az = 2.0 * HL_PI * scn_rng_uniform(&g);
            el = (scn_rng_uniform(&g) - 0.5) * 40.0 * HL_RAD_PER_DEG;
            dist = domes_near_m + radius + (domes_far_m - domes_near_m - radius) * scn_rng_uniform(&g);
            c = hl_v3(dist * cos(el) * sin(az), dist * sin(el), -dist * cos(el) * cos(az));
            int clear = 1;
            for (int k = 0; k < d && clear; ++k) {
                hl_vec3d o = hl_v3(placed_c[k][0], placed_c[k][1], placed_c[k][2]);
                clear = hl_v3_length(hl_v3_sub(c, o)) > 1.5 * (radius + placed_r[k]) + 2.0;
            }
            if (clear)
                break;
        }
        placed_c[d][0] = c.x, placed_c[d][1] = c.y, placed_c[d][2] = c.z, placed_r[d] = radius;
        const float *color = domes_palette[scn_rng_next(&g) % 6];

        /* The impostor: a low-resolution sphere through the struts' outer surface, in the group's
         * frame (origin at the dome's centre), at the dome's size: one chain per dome, one level. */
        struct scn_mesh sphere = {0};
        scn_mesh_add_sphere(&sphere, radius * (1.0 + domes_strut_radius), domes_impostor_rings,
                            domes_impostor_segments, dome_unit_shape);
        char name[SCN_NAME_MAX];
        snprintf(name, sizeof name, "dome%d_impostor", d);
        int rc = scn_scene_add_chain(s, name, &sphere, 1, err);
        scn_mesh_free(&sphere);
        if (rc != 0)
            return -1;

        struct scn_group *gr = &s->groups[d];
        snprintf(gr->name, sizeof gr->name, "dome%d", d);
        gr->parent = SCN_NONE;
        gr->first_child = 0, gr->child_count = 0;
        gr->first_instance = (uint32_t)d * struts, gr->instance_count = struts;
        gr->impostor_chain = s->chain_count - 1;
        gr->impostor_instance = SCN_NONE; /* scn_scene_add_impostor_instances, below */
        gr->importance = 1.0;
        gr->center_m[0] = c.x, gr->center_m[1] = c.y, gr->center_m[2] = c.z;
        double group_r = 0;
        for (uint32_t e = 0; e < struts; ++e) {
            uint32_t i = (uint32_t)d * struts + e;
            hl_vec3d a = geo.v[geo.edge[e][0]], b = geo.v[geo.edge[e][1]];
            hl_vec3d mid = hl_v3_add(c, hl_v3_scale(hl_v3_add(a, b), 0.5 * radius));
            hl_quatd rot = rotation_from_y(hl_v3_scale(hl_v3_sub(b, a), 1.0 / lengths[e]));
            scn_scene_set_instance(s, i, (uint32_t)length_class[e], mid, rot, radius, color);
            s->group_instances[i] = i;
            double reach = hl_v3_length(hl_v3_sub(mid, c)) + s->radius_m[i];
            group_r = reach > group_r ? reach : group_r;
        }
        gr->radius_m = group_r;
    }

    if (scn_scene_add_impostor_instances(s, err) != 0)
        return -1;

    /* Motion (set after the rest poses are final): each dome spins about a near-vertical axis
     * through its centre and swings along the line of sight. */
    if (scn_scene_motion_create(s, err) != 0)
        return -1;
    for (int d = 0; d < n; ++d) {
        struct scn_motion *m = &s->motion->group_motion[d];
        hl_vec3d c = hl_v3(placed_c[d][0], placed_c[d][1], placed_c[d][2]);
        double tilt = 20.0 * HL_RAD_PER_DEG * scn_rng_uniform(&g), tilt_az = 2.0 * HL_PI * scn_rng_uniform(&g);
        m->flags = SCN_MOTION_SPIN | SCN_MOTION_OSCILLATE;
        m->spin_axis = hl_v3(sin(tilt) * cos(tilt_az), cos(tilt), sin(tilt) * sin(tilt_az));
        m->spin_rate_degps = (15.0 + 30.0 * scn_rng_uniform(&g)) * (scn_rng_next(&g) & 1 ? 1.0 : -1.0);
        m->spin_pivot_set = 0; /* about the group's centre */
        double dist = hl_v3_length(c);
        m->osc_direction = hl_v3_scale(c, 1.0 / dist); /* towards / away from the viewer at the origin */
        /* Never closer than 3 m to the viewer's eyes: amplitude ≤ dist − radius − 3. */
        m->osc_amplitude_m = fmin(0.25 * dist, dist - placed_r[d] - 3.0);
        m->osc_period_s = 4.0 + 6.0 * scn_rng_uniform(&g);
        m->osc_phase_deg = 360.0 * scn_rng_uniform(&g);
    }
    return 0;
}
