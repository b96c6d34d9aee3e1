/* examples/embed.c — hmdlod's embeddable core (acuity + lod) in one frame loop, the way an engine
 * would call it. Build against an installed copy:
 *
 *   cmake --install build --prefix /tmp/hl
 *   cc examples/embed.c $(PKG_CONFIG_PATH=/tmp/hl/lib/pkgconfig pkg-config --cflags --libs hmdlod) -o /tmp/embed
 *   /tmp/embed
 *
 * The scene: 1000 objects with bounding spheres on a shell 4–40 m around the viewer, each drawn from
 * one of three 4-level LOD chains (triangles, vertices and Reddy's removed frequencies per level).
 * Per frame, with a head pose (cyclopean eye, gaze) and a stereo display (Vive-like):
 *   1. a frustum cull        spheres against each eye's four side planes and the eye plane (an
 *                            engine has its own; acuity and lod only ever see the visible objects);
 *   2. acu_compute_pixels    projected coverage of each visible sphere, summed over both eyes, and
 *      acu_compute_geometry  eccentricity, retinal velocity and angular diameter;
 *   3. lod_select_reddy      the perceptual ceiling: the coarsest level the viewer cannot tell apart
 *                            from the finest (Reddy 1998) — detail beyond it is worth nothing;
 *   4. lod_cost_object_ms    each candidate level's predicted cost (Funkhouser & Séquin §4);
 *   5. lod_benefit_fill      each candidate's benefit (F&S §5, capped at the ceiling);
 *   6. lod_hull_reduce       candidates cut to the upper convex hull of (cost, benefit);
 *   7. lod_optimize_fs       Funkhouser & Séquin's incremental optimizer (§6) under the budget,
 *                            started from last frame's levels (lod_choice_start).
 * Two frames run, the second after a 4° head turn, to show the incremental start.
 * Memory: every array is sized once for the scene (steps 1–7 allocate nothing per frame). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lod/lod.h"

enum { OBJECTS = 1000, LEVELS = 4, CHAINS = 3 };

/* Three LOD chains, level 0 finest. unique_freq_cpdiam[k]: the highest frequency lost going from
 * level k−1 to k, in cycles per object diameter (measured offline by `hmdlod analyze`; made up here). */
static const uint32_t chain_triangles[CHAINS][LEVELS] = {
    {8000, 2000, 500, 120}, {3000, 900, 260, 60}, {20000, 4800, 1100, 240}};
static const uint32_t chain_vertices[CHAINS][LEVELS] = {
    {4100, 1050, 270, 70}, {1550, 480, 140, 36}, {10200, 2500, 600, 140}};
static const double chain_freq_cpdiam[CHAINS][LEVELS] = {
    {INFINITY, 48.0, 20.0, 8.0}, {INFINITY, 36.0, 14.0, 6.0}, {INFINITY, 64.0, 28.0, 10.0}};

/* A cost model in the additive form with assumed coefficients (`hmdlod calibrate` measures a
 * machine's and writes them to a JSON profile). Triangles, vertices and draws count both eyes. */
static const struct lod_cost_model cost_model = {
    .form = LOD_COST_ADDITIVE,
    .c0_ms = 1.5,
    .c1_ms_per_triangle = 2.0e-5,
    .c2_ms_per_vertex = 5.0e-6,
    .c3_ms_per_pixel = 1.0e-6,
    .c4_ms_per_draw = 0.002,
};
static const double frame_budget_ms = 1000.0 / 90.0; /* the Vive's refresh period */

/* The scene, structure of arrays (what acu_* and lod_* read). */
static double center_m[3 * OBJECTS], radius_m[OBJECTS];
static uint32_t chain_of_object[OBJECTS];
static uint8_t last_level[OBJECTS]; /* level drawn last frame, LOD_UNSEEN if none */

/* Per-frame arrays, position-ordered over the visible objects (k), candidates 4 per object (c). */
static uint32_t visible[OBJECTS];
static double pixels_px[OBJECTS];
static double ecc_deg[OBJECTS], vel_degps[OBJECTS], diam_deg[OBJECTS];
static uint8_t ceiling[OBJECTS], previous[OBJECTS], choice[OBJECTS], level_out[OBJECTS];
static uint32_t first[OBJECTS];
static uint8_t count[OBJECTS];
static double cost_ms[OBJECTS * LEVELS], benefit[OBJECTS * LEVELS];
static uint8_t level[OBJECTS * LEVELS];
static uint32_t samples[OBJECTS * LEVELS];
static int64_t hull_scratch[OBJECTS];

/* Deterministic scene: a Fibonacci sphere of directions (even coverage), distances and sizes from a
 * small LCG, so the printout is the same on every machine. */
static void make_scene(void)
{
    uint32_t rng = 12345u;
    for (int i = 0; i < OBJECTS; ++i) {
        double y = 1.0 - 2.0 * (i + 0.5) / OBJECTS, r = sqrt(1.0 - y * y);
        double phi = i * 2.399963229728653; /* the golden angle, radians */
        rng = rng * 1664525u + 1013904223u;
        double dist_m = 4.0 + 36.0 * (rng >> 8) / 16777216.0;
        rng = rng * 1664525u + 1013904223u;
        radius_m[i] = 0.2 + 1.3 * (rng >> 8) / 16777216.0;
        center_m[3 * i] = dist_m * r * cos(phi);
        center_m[3 * i + 1] = dist_m * y;
        center_m[3 * i + 2] = dist_m * r * sin(phi);
        chain_of_object[i] = (uint32_t)i % CHAINS;
        last_level[i] = LOD_UNSEEN;
    }
}

/* Both eyes of a Vive-like display for a head at the origin turned by yaw_deg (about +Y; −Z is
 * forward at yaw 0): eye positions ±IPD/2 along the head's x axis, the left eye's FOV tangents
 * mirrored for the right eye, 1080 × 1200 px each. */
static void make_eyes(double yaw_deg, struct acu_eye eyes[2], struct acu_viewer *viewer)
{
    hl_quatd head = hl_q_from_axis_angle(hl_v3(0, 1, 0), yaw_deg * HL_RAD_PER_DEG);
    const double ipd_m = 0.063;
    for (int e = 0; e < 2; ++e) {
        double side = e == 0 ? -0.5 : 0.5;
        eyes[e].position_m = hl_q_rotate(head, hl_v3(side * ipd_m, 0, 0));
        eyes[e].orientation = head;
        eyes[e].tan_left = e == 0 ? 1.3973 : 1.2505;
        eyes[e].tan_right = e == 0 ? 1.2505 : 1.3973;
        eyes[e].tan_up = 1.4642;
        eyes[e].tan_down = 1.4775;
        eyes[e].width_px = 1080;
        eyes[e].height_px = 1200;
    }
    viewer->eye_position_m = hl_v3(0, 0, 0); /* the cyclopean eye, between the two */
    viewer->gaze_dir = hl_q_rotate(head, hl_v3(0, 0, -1)); /* no eye tracker: gaze = head forward */
    viewer->angular_velocity_radps = hl_v3(0, 0.5, 0);    /* turning left at ~29 °/s */
    viewer->linear_velocity_mps = hl_v3(0, 0, 0);
}

/* Not wholly outside one of the eye's five planes (four sides through the eye, and the eye's own
 * plane): the usual conservative sphere test. Eye frame: +X right, +Y up, −Z forward. */
static int sphere_in_eye(const struct acu_eye *e, const double *c, double r)
{
    hl_vec3d d = hl_q_rotate(hl_q_conj(e->orientation), hl_v3(c[0] - e->position_m.x, c[1] - e->position_m.y,
                                                                c[2] - e->position_m.z));
    const double side[4][3] = {{1, 0, -e->tan_left}, {-1, 0, -e->tan_right}, {0, -1, -e->tan_up}, {0, 1, -e->tan_down}};
    for (int k = 0; k < 4; ++k) {
        double len = sqrt(side[k][0] * side[k][0] + side[k][1] * side[k][1] + side[k][2] * side[k][2]);
        if ((side[k][0] * d.x + side[k][1] * d.y + side[k][2] * d.z) / len < -r)
            return 0;
    }
    return -d.z > -r;
}

/* One frame: steps 1–7 of the header. Returns the number of visible objects. */
static size_t run_frame(const struct acu_limits *lim, const struct lod_chain *chains, double yaw_deg,
                        void *scratch, struct lod_result *result, double *lp_bound)
{
    struct acu_eye eyes[2];
    struct acu_viewer viewer;
    make_eyes(yaw_deg, eyes, &viewer);

    /* 1. The visible objects: in either eye's frustum. */
    size_t n = 0;
    for (uint32_t i = 0; i < OBJECTS; ++i)
        if (sphere_in_eye(&eyes[0], &center_m[3 * i], radius_m[i]) || sphere_in_eye(&eyes[1], &center_m[3 * i], radius_m[i]))
            visible[n++] = i;

    /* 2–3. Coverage, viewing geometry and the perceptual ceiling of the visible objects (a static
     * scene: no object velocities). acu_compute_pixels is conservative: a sphere reaching behind an
     * eye's plane counts as filling its image, so it must not serve as the cull. */
    acu_compute_pixels(eyes, 2, center_m, radius_m, visible, n, pixels_px);
    acu_compute_geometry(&viewer, center_m, radius_m, NULL, visible, n, ecc_deg, vel_degps, diam_deg);
    lod_select_reddy(lim, chains, chain_of_object, visible, n, ecc_deg, vel_degps, diam_deg, ceiling, NULL, NULL);

    /* 4. Candidates, cheapest (coarsest) first: candidate j of object k draws level LEVELS−1−j. */
    for (size_t k = 0; k < n; ++k) {
        uint32_t c = chain_of_object[visible[k]];
        first[k] = (uint32_t)(k * LEVELS);
        count[k] = LEVELS;
        previous[k] = last_level[visible[k]];
        for (int j = 0; j < LEVELS; ++j) {
            size_t at = k * LEVELS + (size_t)j;
            int l = LEVELS - 1 - j;
            level[at] = (uint8_t)l;
            samples[at] = chain_vertices[c][l]; /* Gouraud: samples are vertices, m = 2 */
            cost_ms[at] = lod_cost_object_ms(&cost_model, 2.0 * chain_triangles[c][l], 2.0 * chain_vertices[c][l],
                                             pixels_px[k], 2.0);
        }
    }

    /* 5–6. Benefit (size · accuracy · hysteresis, nothing above the ceiling), then the hull, which
     * also drops levels that could not fit even with every other object at its coarsest. */
    double budget_ms = frame_budget_ms - cost_model.c0_ms;
    struct lod_benefit_params bp;
    lod_benefit_params_default(&bp);
    lod_benefit_fill(&bp, n, first, count, level, samples, pixels_px, NULL, ceiling, previous, NULL, benefit);
    size_t bad = lod_hull_reduce(n, first, count, cost_ms, benefit, level, budget_ms, hull_scratch);
    if (bad)
        fprintf(stderr, "embed: %zu candidates had non-finite or negative cost or benefit\n", bad);

    /* 7. The optimizer, from last frame's levels, under the budget less the frame's fixed cost. */
    uint32_t object_id[OBJECTS];
    memcpy(object_id, visible, n * sizeof *visible);
    struct lod_problem p = {
        .object_count = n, .object_id = object_id, .first = first, .count = count,
        .cost_ms = cost_ms, .benefit = benefit, .level = level,
        .budget_ms = budget_ms,
    };
    lod_choice_start(&p, previous, choice);
    lod_optimize_fs(&p, 0.0, scratch, choice, result);
    lod_level_of_choice(&p, choice, level_out);
    *lp_bound = lod_lp_bound(&p, scratch);

    /* Remember what was drawn, for next frame's start and hysteresis. */
    for (uint32_t i = 0; i < OBJECTS; ++i)
        last_level[i] = LOD_UNSEEN;
    for (size_t k = 0; k < n; ++k)
        last_level[visible[k]] = level_out[k];
    return n;
}

int main(void)
{
    make_scene();
    struct lod_chain chains[CHAINS];
    for (int c = 0; c < CHAINS; ++c) {
        chains[c].lod_count = LEVELS;
        for (int l = 0; l < LEVELS; ++l)
            chains[c].unique_freq_cpdiam[l] = chain_freq_cpdiam[c][l];
    }
    /* ξ, Reddy eq. 4: the display's highest frequency, pixels / (2 · FOV°), the larger axis. */
    double fov_h_deg = (atan(1.3973) + atan(1.2505)) * HL_DEG_PER_RAD;
    double fov_v_deg = (atan(1.4642) + atan(1.4775)) * HL_DEG_PER_RAD;
    double xi_cpd = fmax(1080 / (2 * fov_h_deg), 1200 / (2 * fov_v_deg));
    struct acu_limits lim;
    acu_limits_init(&lim, xi_cpd, 1.0);

    void *scratch = malloc(lod_scratch_bytes(OBJECTS, (size_t)OBJECTS * LEVELS));
    if (!scratch) {
        fprintf(stderr, "embed: out of memory\n");
        return 1;
    }
    printf("hmdlod embed example: %d objects x %d LODs, display xi %.2f c/deg, budget %.2f ms (%.2f ms fixed)\n",
           OBJECTS, LEVELS, xi_cpd, frame_budget_ms, cost_model.c0_ms);
    const double yaw_deg[2] = {0.0, 4.0};
    int ok = 1;
    for (int f = 0; f < 2; ++f) {
        struct lod_result r;
        double lp;
        size_t n = run_frame(&lim, chains, yaw_deg[f], scratch, &r, &lp);
        unsigned hist[LEVELS + 1] = {0}, ceil_hist[LEVELS] = {0};
        for (size_t k = 0; k < n; ++k) {
            hist[level_out[k] < LEVELS ? level_out[k] : LEVELS]++; /* LOD_DROP counts as dropped */
            ceil_hist[ceiling[k] < LEVELS ? ceiling[k] : LEVELS - 1]++;
        }
        double predicted_ms = cost_model.c0_ms + r.cost_ms;
        printf("\nframe %d (yaw %.0f deg): %zu visible objects\n", f, yaw_deg[f], n);
        printf("  chosen levels   0: %u  1: %u  2: %u  3: %u  dropped: %u\n", hist[0], hist[1], hist[2], hist[3],
               hist[LEVELS]);
        printf("  Reddy ceilings  0: %u  1: %u  2: %u  3: %u\n", ceil_hist[0], ceil_hist[1], ceil_hist[2],
               ceil_hist[3]);
        printf("  predicted cost %.3f ms of budget %.3f ms: %s\n", predicted_ms, frame_budget_ms,
               predicted_ms <= frame_budget_ms + 1e-9 ? "within" : "OVER");
        printf("  benefit %.1f = %.2f %% of the LP bound %.1f; %u fs iterations, %.1f us%s\n", r.benefit,
               lp > 0 ? 100.0 * r.benefit / lp : 100.0, lp, r.iterations, r.elapsed_us,
               r.over_budget ? "; over budget even at the coarsest levels" : "");
        printf("  object  ecc deg  diam deg  pixels  ceiling  level\n");
        for (size_t k = 0; k < n; k += n / 5 > 0 ? n / 5 : 1)
            printf("  %6u  %7.1f  %8.2f  %6.0f  %7u  %5u\n", visible[k], ecc_deg[k], diam_deg[k], pixels_px[k],
                   ceiling[k], level_out[k]);
        if (predicted_ms > frame_budget_ms + 1e-9 && !r.over_budget)
            ok = 0;
    }
    free(scratch);
    return ok ? 0 : 1;
}
