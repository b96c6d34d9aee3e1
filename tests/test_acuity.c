/* Reddy's acuity model against the paper's figures (PAPERS.md §1), its hard numeric cases, the
 * "model only what a scene needs" region, viewing geometry and the Reddy selector. */
#include "acuity/acuity.h"
#include "test_util.h"

#include <math.h>
#include <string.h>

static void test_paper_figures(void)
{
    /* Reddy §4 desktop: ξ = 12.5 → E* ≈ 17° (closed form 16.65), v* ≈ 42 deg/s (42.3), and at
     * E = 10°, M = 0.468 and v ≈ 13 deg/s (13.05). Tolerances: the paper's rounding. */
    CHECK_NEAR(acu_eccentricity_at_acuity_deg(12.5), 16.65, 0.01);
    CHECK_NEAR(acu_velocity_at_acuity_degps(12.5, 0.0), 42.3, 0.05);
    CHECK_NEAR(acu_eccentricity_factor(10.0), 0.468, 0.001);
    CHECK_NEAR(acu_velocity_at_acuity_degps(12.5, 10.0), 13.05, 0.05);
    /* i-glasses: ξ = 4.8 → E* ≈ 29° (28.9), v* ≈ 80 deg/s (80.2); at 15°, M = 0.2476, v ≈ 24 (23.9). */
    CHECK_NEAR(acu_eccentricity_at_acuity_deg(4.8), 28.9, 0.05);
    CHECK_NEAR(acu_velocity_at_acuity_degps(4.8, 0.0), 80.2, 0.1);
    CHECK_NEAR(acu_eccentricity_factor(15.0), 0.2476, 0.0001);
    CHECK_NEAR(acu_velocity_at_acuity_degps(4.8, 15.0), 23.9, 0.1);
    /* The acceptance figure: H(24 deg/s, 15°) ≈ 4.8 c/deg. */
    CHECK_NEAR(acu_acuity_cpd(24.0, 15.0), 4.8, 0.01);
    /* Round trips: the inverses really invert. */
    CHECK_NEAR(acu_acuity_cpd(0.0, acu_eccentricity_at_acuity_deg(12.5)), 12.5, 1e-9);
    CHECK_NEAR(acu_acuity_cpd(acu_velocity_at_acuity_degps(4.8, 15.0), 15.0), 4.8, 1e-9);
}

static void test_continuity(void)
{
    /* Both pieces meet at their knees (PAPERS.md: G(0.825) ≈ 60.01, M(5.79) ≈ 0.9999). */
    CHECK_NEAR(acu_velocity_factor_cpd(0.825), 60.0, 1e-12);
    CHECK_NEAR(acu_velocity_factor_cpd(nextafter(0.825, 1.0)), 60.01, 0.01);
    CHECK_NEAR(acu_eccentricity_factor(5.79), 1.0, 1e-12);
    CHECK_NEAR(acu_eccentricity_factor(nextafter(5.79, 6.0)), 0.9999, 0.0001);
    /* Monotone non-increasing in both arguments over a fine grid. */
    double prev = INFINITY;
    int monotone = 1;
    for (double v = 0.0; v < 200.0; v += 0.01) {
        double g = acu_velocity_factor_cpd(v);
        monotone &= g <= prev + 1e-12;
        prev = g;
    }
    CHECK(monotone);
    prev = INFINITY;
    monotone = 1;
    for (double e = 0.0; e <= 180.0; e += 0.01) {
        double m = acu_eccentricity_factor(e);
        monotone &= m <= prev + 1e-12 && m > 0.0;
        prev = m;
    }
    CHECK(monotone);
}

static void test_hard_cases(void)
{
    struct hl_error err = {{0}};
    /* v = 0, 1e-12 (still), 119.3 (G crosses 0), 1e6 and ∞: finite, never negative. */
    CHECK(acu_velocity_factor_cpd(0.0) == 60.0);
    CHECK(acu_velocity_factor_cpd(1e-12) == 60.0);
    CHECK_NEAR(acu_velocity_factor_cpd(119.3), 0.0, 0.01);
    CHECK(acu_velocity_factor_cpd(119.4) == 0.0);
    CHECK(acu_velocity_factor_cpd(1e6) == 0.0);
    CHECK(acu_velocity_factor_cpd(INFINITY) == 0.0);
    CHECK(acu_acuity_cpd(INFINITY, 180.0) == 0.0);
    /* E = 0, 180 and out of range are clamped by the model; the boundary check rejects them. */
    CHECK(acu_eccentricity_factor(0.0) == 1.0);
    CHECK(acu_eccentricity_factor(-5.0) == 1.0);
    CHECK_NEAR(acu_eccentricity_factor(180.0), 7.49 / (55.0 * 55.0), 1e-12);
    CHECK(acu_eccentricity_factor(1e9) == acu_eccentricity_factor(180.0));
    CHECK(acu_check_inputs(0.0, 0.0, &err) == 0);
    CHECK(acu_check_inputs(INFINITY, 180.0, &err) == 0);
    CHECK(acu_check_inputs(NAN, 0.0, &err) < 0 && strstr(err.msg, "velocity"));
    CHECK(acu_check_inputs(0.0, NAN, &err) < 0 && strstr(err.msg, "eccentricity"));
    CHECK(acu_check_inputs(-1.0, 0.0, &err) < 0 && strstr(err.msg, "negative"));
    CHECK(acu_check_inputs(0.0, -0.5, &err) < 0 && strstr(err.msg, "[0, 180]"));
    CHECK(acu_check_inputs(0.0, 180.5, &err) < 0);
    /* Inverses at their edges. */
    CHECK(acu_eccentricity_at_acuity_deg(60.0) == 0.0);
    CHECK(isinf(acu_eccentricity_at_acuity_deg(0.0)));
    CHECK(acu_velocity_at_acuity_degps(60.0, 0.0) == 0.0);
    CHECK(acu_velocity_at_acuity_degps(10.0, 90.0) == 0.0); /* unreachable even still */
    CHECK(isinf(acu_velocity_at_acuity_degps(0.0, 0.0)));
}

static void test_skip_region(void)
{
    /* Every (v, E) the limits skip must truly have H ≥ ξ, for several displays' ξ; and points well
     * outside must be evaluated. A dense grid, including the knees exactly. */
    const double xis[] = {3.2, 4.79, 5.38, 11.24, 12.46, 35.6, 59.0};
    for (size_t x = 0; x < sizeof xis / sizeof xis[0]; ++x) {
        struct acu_limits lim;
        acu_limits_init(&lim, xis[x], 1.0);
        int wrong = 0;
        uint64_t evaluations = 0, points = 0;
        for (double v = 0.0; v <= 130.0; v += 0.125) {
            for (double e = 0.0; e <= 60.0; e += 0.0625) {
                uint64_t before = evaluations;
                double limit = acu_limit_cpd(&lim, v, e, &evaluations);
                double exact = fmin(acu_acuity_cpd(v, e), xis[x]);
                ++points;
                if (fabs(limit - exact) > 1e-12)
                    ++wrong;
                if (evaluations == before && acu_acuity_cpd(v, e) < xis[x] - 1e-12)
                    ++wrong;
            }
        }
        CHECK(wrong == 0);
        CHECK(evaluations < points); /* something was skipped */
    }
    struct acu_limits lim;
    acu_limits_init(&lim, 5.38, 0.5);
    uint64_t n = 0;
    CHECK_NEAR(acu_limit_cpd(&lim, 0.0, 0.0, &n), 5.38 * 0.5, 1e-12);
    CHECK(n == 0);
    CHECK_NEAR(acu_limit_cpd(&lim, 200.0, 0.0, &n), 0.0, 1e-12);
    CHECK(n == 1);
    lim.use_velocity = 0;
    CHECK_NEAR(acu_limit_cpd(&lim, 200.0, 0.0, &n), 5.38 * 0.5, 1e-12);
}

static void test_geometry(void)
{
    /* Objects along −Z and to the side; the head turns about +Y at 100 deg/s. */
    const double center[] = {0, 0, -10,  10, 0, 0,  0, 0, 0,  0, 0, 10,  1e6, 1e6, 1e6 - 10};
    const double radius[] = {1, 1, 1, 1, 0.5};
    const uint32_t index[] = {0, 1, 2, 3, 4};
    double ecc[5], vel[5], diam[5];
    struct acu_viewer viewer = {
        .eye_position_m = hl_v3(0, 0, 0),
        .gaze_dir = hl_v3(0, 0, -1),
        .angular_velocity_radps = hl_v3(0, 100.0 * HL_RAD_PER_DEG, 0),
        .linear_velocity_mps = hl_v3(0, 0, 0),
    };
    acu_compute_geometry(&viewer, center, radius, NULL, index, 4, ecc, vel, diam);
    double half = asin(0.1) * HL_DEG_PER_RAD;
    CHECK_NEAR(ecc[0], 0.0, 1e-12);
    CHECK_NEAR(diam[0], 2 * half, 1e-12);
    CHECK_NEAR(vel[0], 100.0, 1e-9);           /* d ⊥ ω: full head rate */
    CHECK_NEAR(ecc[1], 90.0 - half, 1e-9);
    CHECK_NEAR(ecc[2], 0.0, 0.0);              /* eye inside the sphere */
    CHECK_NEAR(diam[2], 180.0, 0.0);
    CHECK_NEAR(vel[2], 100.0, 1e-9);
    CHECK_NEAR(ecc[3], 180.0 - half, 1e-9);    /* behind the viewer */
    /* The far-away object, with the eye next to it: same answers as near the origin. */
    viewer.eye_position_m = hl_v3(1e6, 1e6, 1e6);
    viewer.angular_velocity_radps = hl_v3(0, 0, 0);
    uint32_t far_index = 4;
    acu_compute_geometry(&viewer, center, radius, NULL, &far_index, 1, ecc, vel, diam);
    CHECK_NEAR(ecc[0], 0.0, 1e-12);
    CHECK_NEAR(diam[0], 2 * asin(0.05) * HL_DEG_PER_RAD, 1e-9);
    CHECK_NEAR(vel[0], 0.0, 1e-12);
    /* Eccentricity of a tiny off-axis angle: atan2 keeps it (acos of the dot would give 0). */
    const double tiny_center[] = {1e-7, 0, -1};
    const double tiny_radius[] = {0};
    viewer.eye_position_m = hl_v3(0, 0, 0);
    acu_compute_geometry(&viewer, tiny_center, tiny_radius, NULL, index, 1, ecc, vel, diam);
    CHECK_NEAR(ecc[0], 1e-7 * HL_DEG_PER_RAD, 1e-15);
    /* Translation: an object 10 m ahead passing sideways at 1 m/s moves at 0.1 rad/s. */
    const double moving_vel[] = {1, 0, 0};
    acu_compute_geometry(&viewer, center, radius, moving_vel, index, 1, ecc, vel, diam);
    CHECK_NEAR(vel[0], 0.1 * HL_DEG_PER_RAD, 1e-9);
    /* The head turning the same way cancels it (smooth pursuit by the head). */
    viewer.angular_velocity_radps = hl_v3(0, -0.1, 0);
    acu_compute_geometry(&viewer, center, radius, moving_vel, index, 1, ecc, vel, diam);
    CHECK_NEAR(vel[0], 0.0, 1e-9);
}

/* The eye's own linear velocity (gaze models: head translation and the swing about the neck) enters
 * as motion relative to the eye: an object moving with the eye holds still, a still one 4 m ahead
 * slides at |v|/r, against the eye's motion. */
static void test_geometry_eye_velocity(void)
{
    const double center[] = {0, 0, -4, 2, 0, -4};
    const double radius[] = {0.1, 0.1};
    const double with_eye[] = {0.5, 0, 0, 0.5, 0, 0};
    const uint32_t index[] = {0, 1};
    double ecc[2], vel[2], diam[2];
    struct acu_viewer viewer = {
        .eye_position_m = hl_v3(0, 0, 0),
        .gaze_dir = hl_v3(0, 0, -1),
        .angular_velocity_radps = hl_v3(0, 0, 0),
        .linear_velocity_mps = hl_v3(0.5, 0, 0),
    };
    acu_compute_geometry(&viewer, center, radius, with_eye, index, 2, ecc, vel, diam);
    CHECK_NEAR(vel[0], 0.0, 1e-12);
    CHECK_NEAR(vel[1], 0.0, 1e-12);
    acu_compute_geometry(&viewer, center, radius, NULL, index, 2, ecc, vel, diam);
    CHECK_NEAR(vel[0], 0.125 * HL_DEG_PER_RAD, 1e-9);
    /* the second is 2 m aside at 4 m ahead: r = √20, u⊥ = 0.5·(4/√20) */
    CHECK_NEAR(vel[1], 0.5 * (4.0 / sqrt(20.0)) / sqrt(20.0) * HL_DEG_PER_RAD, 1e-9);
}

/* Projected coverage against pixels counted one by one: a pixel is covered when its ray through the
 * pixel centre passes within the sphere (the exact silhouette). The estimate is the silhouette's
 * exact bounding box × π/4 (rising to 1 as the image clips the box): exact on the view axis, within
 * 5 % off axis, at most 20 % over where the image clips it. */
static double count_pixels(const struct acu_eye *e, const double *c, double r)
{
    double covered = 0.0;
    hl_vec3d rel = hl_v3(c[0] - e->position_m.x, c[1] - e->position_m.y, c[2] - e->position_m.z);
    hl_vec3d d = hl_q_rotate(hl_q_conj(e->orientation), rel);
    for (int py = 0; py < (int)e->height_px; ++py)
        for (int px = 0; px < (int)e->width_px; ++px) {
            double tx = -e->tan_left + (px + 0.5) / e->width_px * (e->tan_left + e->tan_right);
            double ty = e->tan_up - (py + 0.5) / e->height_px * (e->tan_up + e->tan_down);
            hl_vec3d ray = hl_v3_normalize(hl_v3(tx, ty, -1.0));
            double along = hl_v3_dot(d, ray);
            hl_vec3d off = hl_v3_sub(d, hl_v3_scale(ray, along));
            covered += along > 0.0 && hl_v3_dot(off, off) <= r * r;
        }
    return covered;
}

static void test_pixels(void)
{
    struct acu_eye eye = {hl_v3(0, 0, 0), hl_q_identity(), 1.0, 1.0, 1.0, 1.0, 400, 400};
    uint32_t index[1] = {0};
    double px, r = 1.0;
    double ahead[3] = {0, 0, -10};
    acu_compute_pixels(&eye, 1, ahead, &r, index, 1, &px);
    double counted = count_pixels(&eye, ahead, r);
    printf("pixels: ahead %.0f estimated, %.0f counted\n", px, counted);
    CHECK_NEAR(px, counted, 0.03 * counted);
    double aside[3] = {4, 2, -10}; /* off axis: the ellipse's bounding square */
    acu_compute_pixels(&eye, 1, aside, &r, index, 1, &px);
    counted = count_pixels(&eye, aside, r);
    printf("pixels: off axis %.0f estimated, %.0f counted\n", px, counted);
    CHECK_NEAR(px, counted, 0.05 * counted);
    double edge[3] = {10, 0, -10}; /* centred on the right edge: about half inside */
    acu_compute_pixels(&eye, 1, edge, &r, index, 1, &px);
    counted = count_pixels(&eye, edge, r);
    printf("pixels: at the edge %.0f estimated, %.0f counted\n", px, counted);
    CHECK(px >= counted && px <= 1.2 * counted);
    double beside[3] = {-10, 0, 0.5}; /* reaching behind the eye's plane, outside the image */
    acu_compute_pixels(&eye, 1, beside, &r, index, 1, &px);
    CHECK(px == 0.0);
    double near_edge[3] = {-1.0, 0, 0.2}; /* behind the plane but reaching into the image's left edge */
    acu_compute_pixels(&eye, 1, near_edge, &r, index, 1, &px);
    counted = count_pixels(&eye, near_edge, r);
    printf("pixels: from behind the eye's plane %.0f estimated, %.0f counted\n", px, counted);
    CHECK(px >= counted && px <= 1.2 * counted && px > 0.0);
    double behind[3] = {0, 0, 10}, outside[3] = {0, 30, -10}, around[3] = {0.2, 0, 0};
    acu_compute_pixels(&eye, 1, behind, &r, index, 1, &px);
    CHECK(px == 0.0);
    acu_compute_pixels(&eye, 1, outside, &r, index, 1, &px);
    CHECK(px == 0.0);
    acu_compute_pixels(&eye, 1, around, &r, index, 1, &px);
    CHECK(px == 400.0 * 400.0);
    /* Two eyes sum; a turned eye sees the sphere it faces (eye-to-world: 90° about +Y faces −X). */
    struct acu_eye two[2] = {eye, eye};
    two[1].orientation = hl_q(cos(HL_PI / 4), 0, sin(HL_PI / 4), 0);
    double left[3] = {-10, 0, 0};
    acu_compute_pixels(two, 2, left, &r, index, 1, &px);
    CHECK_NEAR(px, count_pixels(&two[1], left, r), 0.03 * count_pixels(&two[1], left, r));
}

static double rand01(uint64_t *state) /* xorshift64*: reproducible test poses */
{
    *state ^= *state >> 12, *state ^= *state << 25, *state ^= *state >> 27;
    return (double)((*state * 2685821657736338717ull) >> 11) * 0x1.0p-53;
}

/* An independent count for boxes: every pixel centre's ray tested against the box by slabs along
 * its three (orthogonal) axes, in front of the eye only. */
static double count_box_pixels(const struct acu_eye *e, const double *c, const double *axes)
{
    double covered = 0.0;
    hl_vec3d o = hl_v3_sub(e->position_m, hl_v3(c[0], c[1], c[2])), u[3];
    double half[3];
    for (int k = 0; k < 3; ++k) {
        hl_vec3d a = hl_v3(axes[3 * k], axes[3 * k + 1], axes[3 * k + 2]);
        half[k] = hl_v3_length(a);
        u[k] = hl_v3_scale(a, 1.0 / half[k]);
    }
    for (int py = 0; py < (int)e->height_px; ++py)
        for (int px = 0; px < (int)e->width_px; ++px) {
            double tx = -e->tan_left + (px + 0.5) / e->width_px * (e->tan_left + e->tan_right);
            double ty = e->tan_up - (py + 0.5) / e->height_px * (e->tan_up + e->tan_down);
            hl_vec3d ray = hl_q_rotate(e->orientation, hl_v3(tx, ty, -1.0));
            double t0 = 0.0, t1 = INFINITY;
            for (int k = 0; k < 3 && t0 <= t1; ++k) {
                double oo = hl_v3_dot(o, u[k]), dd = hl_v3_dot(ray, u[k]);
                if (fabs(dd) < 1e-300) {
                    if (fabs(oo) > half[k])
                        t1 = -1.0;
                    continue;
                }
                double a = (-half[k] - oo) / dd, b = (half[k] - oo) / dd;
                t0 = fmax(t0, fmin(a, b)), t1 = fmin(t1, fmax(a, b));
            }
            covered += t0 <= t1;
        }
    return covered;
}

/* Boxes: exact against the count (within the pixel grid's edge error) in front, partly outside the
 * image, straddling the eye's plane (a floor under and behind the viewer), around the eye, behind
 * it; and on random boxes in random poses. Also a room's surfaces: each one's sphere holds the eye,
 * so spheres claim the image six times over, boxes about once. */
static void test_pixels_box(void)
{
    struct acu_eye eye = {hl_v3(0, 0, 0), hl_q_identity(), 1.2, 1.0, 0.9, 1.1, 240, 200};
    struct {
        double c[3], axes[9];
        const char *what;
    } cases[] = {
        {{0, 0, -8}, {1, 0, 0, 0, 0.5, 0, 0, 0, 0.3}, "ahead"},
        {{7, 1, -8}, {1, 0, 0, 0, 0.5, 0, 0, 0, 0.3}, "across the right edge"},
        {{0, -1.2, 0}, {5, 0, 0, 0, 0.05, 0, 0, 0, 8}, "a floor under and behind the eye"},
        {{0, 0, 0.5}, {1, 0, 0, 0, 1, 0, 0, 0, 1}, "around the eye"},
        {{0, 0, 5}, {1, 0, 0, 0, 1, 0, 0, 0, 1}, "behind"},
        {{-3, 0, 0}, {0.2, 0, 0, 0, 0.2, 0, 0, 0, 3}, "a wall beside the eye reaching ahead"},
    };
    double worst = 0.0;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        double px, counted = count_box_pixels(&eye, cases[k].c, cases[k].axes);
        acu_compute_pixels_box(&eye, 1, cases[k].c, cases[k].axes, 1, &px);
        printf("box pixels: %s %.0f computed, %.0f counted\n", cases[k].what, px, counted);
        CHECK(fabs(px - counted) <= 0.02 * counted + 300.0); /* edge pixels: ~ perimeter */
        worst = fmax(worst, fabs(px - counted) / fmax(counted, 1.0));
    }
    uint64_t rng = 99;
    worst = 0.0;
    for (int t = 0; t < 60; ++t) {
        double c[3], axes[9], r[4];
        for (int k = 0; k < 3; ++k)
            c[k] = (rand01(&rng) - 0.5) * 12.0;
        for (int k = 0; k < 4; ++k)
            r[k] = rand01(&rng) - 0.5;
        hl_quatd q = hl_q_normalize(hl_q(r[0], r[1], r[2], r[3]));
        for (int k = 0; k < 3; ++k) {
            hl_vec3d a = hl_q_rotate(q, hl_v3(k == 0, k == 1, k == 2));
            double h = 0.05 + 2.0 * rand01(&rng);
            axes[3 * k] = a.x * h, axes[3 * k + 1] = a.y * h, axes[3 * k + 2] = a.z * h;
        }
        double px, counted = count_box_pixels(&eye, c, axes);
        acu_compute_pixels_box(&eye, 1, c, axes, 1, &px);
        CHECK(fabs(px - counted) <= 0.02 * counted + 300.0);
        if (counted > 2000.0)
            worst = fmax(worst, fabs(px - counted) / counted);
    }
    printf("box pixels: worst relative difference to the count %.4f (random boxes over 2000 px)\n", worst);

    /* A 14 × 6 × 20 m room of six thin slabs around the eye: spheres claim 6 images, boxes ~1. */
    const double room[6][6] = {{0, -1.3, -4, 7, 0.1, 10}, {0, 4.9, -4, 7, 0.1, 10}, {-7.1, 1.8, -4, 0.1, 3, 10},
                               {7.1, 1.8, -4, 0.1, 3, 10}, {0, 1.8, -14.1, 7, 3, 0.1}, {0, 1.8, 6.1, 7, 3, 0.1}};
    double sphere_sum = 0.0, box_sum = 0.0;
    for (int k = 0; k < 6; ++k) {
        double axes[9] = {room[k][3], 0, 0, 0, room[k][4], 0, 0, 0, room[k][5]}, px, radius;
        radius = sqrt(room[k][3] * room[k][3] + room[k][4] * room[k][4] + room[k][5] * room[k][5]);
        uint32_t index[1] = {0};
        acu_compute_pixels(&eye, 1, room[k], &radius, index, 1, &px);
        sphere_sum += px;
        acu_compute_pixels_box(&eye, 1, room[k], axes, 1, &px);
        box_sum += px;
    }
    double image = eye.width_px * eye.height_px;
    printf("box pixels: a room's six surfaces: spheres %.2f images, boxes %.2f\n", sphere_sum / image, box_sum / image);
    CHECK(sphere_sum >= 4.0 * image);
    CHECK(box_sum >= 0.99 * image && box_sum <= 1.3 * image);
}

/* ξ above 60 c/deg (a display finer than the eye, or a 6e3 c/deg override): H never reaches ξ, so
 * the skip region is empty, every point is modelled, and the limit is H itself — finite, ≤ 60. */
static void test_xi_above_60(void)
{
    const double xis[] = {60.0, 60.000001, 80.0, 1000.0};
    for (size_t x = 0; x < sizeof xis / sizeof xis[0]; ++x) {
        struct acu_limits lim;
        acu_limits_init(&lim, xis[x], 1.0);
        uint64_t evaluations = 0, points = 0;
        int wrong = 0;
        for (double v = 0.0; v <= 130.0; v += 2.5)
            for (double e = 0.0; e <= 180.0; e += 5.0) {
                double limit = acu_limit_cpd(&lim, v, e, &evaluations);
                ++points;
                wrong += !(isfinite(limit) && limit <= 60.0 && fabs(limit - fmin(acu_acuity_cpd(v, e), xis[x])) < 1e-12);
            }
        CHECK(wrong == 0);
        if (xis[x] > 60.0)
            CHECK(evaluations == points); /* nothing may be skipped: H < ξ everywhere */
        uint64_t n = 0;
        CHECK(acu_limit_cpd(&lim, 0.0, 0.0, &n) == 60.0);
    }
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "hard-cases") == 0) { /* ctest -L hard-cases */
        test_hard_cases();
        test_xi_above_60();
        test_skip_region();
        test_geometry();
        return tu_finish("test_acuity hard-cases");
    }
    test_xi_above_60();
    test_paper_figures();
    test_continuity();
    test_hard_cases();
    test_skip_region();
    test_geometry();
    test_geometry_eye_velocity();
    test_pixels();
    test_pixels_box();
    return tu_finish("test_acuity");
}
