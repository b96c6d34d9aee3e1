/* "field": the test environment of Reddy (1998 §5) — many copies of one object with four LODs of
 * about 3928 / 834 / 254 / 76 triangles scattered around the viewer. Reddy's traces come from
 * free head motion, so objects surround the origin in every direction, not just ahead. */
#include "scene/scene_internal.h"

#include <math.h>

enum { FIELD_DEFAULT_COUNT = 100, FIELD_MAX_COUNT = 100000 };

static const double field_base_radius_m = 0.45, field_bump = 0.12;
static const double field_near_m = 3.0, field_far_m = 40.0;

/* A low-frequency radial bump pattern (a few lobes per great circle): coarse levels visibly lose
 * it, so the LODs differ in the way the acuity model cares about. Smooth, so normals are too. */
static double field_shape(hl_vec3d d)
{
    return 1.0 + field_bump * sin(3.0 * d.x + 1.0) * sin(3.0 * d.y + 2.0) * sin(3.0 * d.z + 0.5) * 2.0;
}

/* (interior rings, longitudes) per level: 2·rings·segments triangles = 3906, 840, 256, 78, within
 * 1–3 % of Reddy's 3928 / 834 / 254 / 76. Segments ≈ 2·(rings + 1) keeps the quads square, except
 * the last level, where 76 ± 5 % leaves only 3 × 13. */
static const int field_levels[4][2] = {{31, 63}, {14, 30}, {8, 16}, {3, 13}};

/* A pleasant, distinguishable palette (Tableau-like, slightly desaturated). */
static const float field_palette[8][3] = {
    {0.89f, 0.45f, 0.36f}, {0.35f, 0.62f, 0.82f}, {0.55f, 0.76f, 0.42f}, {0.93f, 0.76f, 0.35f},
    {0.68f, 0.51f, 0.79f}, {0.40f, 0.76f, 0.71f}, {0.91f, 0.58f, 0.71f}, {0.78f, 0.74f, 0.65f},
};

int scn_field_add_object_chain(struct scn_scene *s, const char *name, struct hl_error *err)
{
    struct scn_mesh levels[4] = {{0}};
    for (int l = 0; l < 4; ++l)
        scn_mesh_add_sphere(&levels[l], field_base_radius_m, field_levels[l][0], field_levels[l][1], field_shape);
    int rc = scn_scene_add_chain(s, name, levels, 4, err);
    for (int l = 0; l < 4; ++l)
        scn_mesh_free(&levels[l]);
    return rc;
}

int scn_scene_build_field(const struct scn_scene_params *p, struct scn_scene *s, struct hl_error *err)
{
    int n = p->object_count == 0 ? FIELD_DEFAULT_COUNT : p->object_count;
    if (n < 1 || n > FIELD_MAX_COUNT)
        return hl_fail(err, "scene field: object_count %d out of range (1…%d, 0 = %d)", p->object_count,
                       FIELD_MAX_COUNT, FIELD_DEFAULT_COUNT);
    snprintf(s->name, sizeof s->name, "field");
    if (scn_field_add_object_chain(s, "bumpy_sphere", err) != 0 || scn_scene_alloc_instances(s, (uint32_t)n, err) != 0)
        return -1;

    struct scn_rng g = {p->seed};
    for (int i = 0; i < n; ++i) {
        /* Direction uniform on the sphere (z uniform in [−1, 1], azimuth uniform). Distance uniform
         * in [near + r, far] rather than uniform in volume, which would put most objects near 40 m
         * where they are a few pixels: this way every distance band holds as many objects, so the
         * LOD choice always has near, middle and far work. No part of an object is within 3 m. */
        double z = 2.0 * scn_rng_uniform(&g) - 1.0, az = 2.0 * HL_PI * scn_rng_uniform(&g);
        double rho = sqrt(fmax(0.0, 1.0 - z * z));
        hl_vec3d dir = hl_v3(rho * cos(az), z, rho * sin(az));
        double scale = 0.5 + scn_rng_uniform(&g);
        double near = field_near_m + s->chains[0].bound_radius_m * scale;
        double dist = near + (field_far_m - near) * scn_rng_uniform(&g);
        hl_quatd rot = scn_rng_rotation(&g);
        const float *color = field_palette[scn_rng_next(&g) % 8];
        scn_scene_set_instance(s, (uint32_t)i, 0, hl_v3_scale(dir, dist), rot, scale, color);
    }
    return 0;
}
