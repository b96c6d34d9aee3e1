/* Gaze models (acuity/gaze.h) through the viewing geometry: fixations during fast head turns, pursuit,
 * translation parallax, the eyes' offset from the neck, and the VOR's gain and latency residuals.
 * Every retinal speed is also computed independently: a finite difference of the object's direction
 * in the eye's frame over a small step, the eye moved by its linear and turned by its angular
 * velocity. */
#include <math.h>
#include <string.h>

#include "acuity/acuity.h"
#include "test_util.h"

static const double DT_S = 1e-6;

/* Retinal speed (deg/s) of a point p moving at w for an eye at viewer's position moving and turning
 * at viewer's velocities: the angle its eye-frame direction sweeps in DT_S, over DT_S. */
static double finite_difference_degps(const struct acu_viewer *v, hl_vec3d p, hl_vec3d w)
{
    hl_vec3d d0 = hl_v3_normalize(hl_v3_sub(p, v->eye_position_m));
    hl_vec3d e1 = hl_v3_add(v->eye_position_m, hl_v3_scale(v->linear_velocity_mps, DT_S));
    hl_vec3d p1 = hl_v3_add(p, hl_v3_scale(w, DT_S));
    hl_vec3d d1 = hl_v3_normalize(hl_v3_sub(p1, e1));
    hl_quatd turn = hl_q_exp(hl_v3_scale(v->angular_velocity_radps, DT_S)); /* eye frame at t + dt */
    hl_vec3d d1_eye = hl_q_rotate(hl_q_conj(turn), d1);
    return hl_v3_angle_rad(d0, d1_eye) / DT_S * HL_DEG_PER_RAD;
}

/* acu_compute_geometry's retinal speed and eccentricity for one small sphere at p moving at w. */
static double geometry_degps(const struct acu_viewer *v, hl_vec3d p, hl_vec3d w, double *ecc_deg)
{
    double c[3] = {p.x, p.y, p.z}, r = 1e-4, vel[3] = {w.x, w.y, w.z};
    uint32_t idx = 0;
    double ecc, speed, diam;
    acu_compute_geometry(v, c, &r, vel, &idx, 1, &ecc, &speed, &diam);
    if (ecc_deg)
        *ecc_deg = ecc;
    return speed;
}

/* Both computations, which must agree; returns the geometry's. */
static double retinal_degps(const struct acu_viewer *v, hl_vec3d p, hl_vec3d w)
{
    double g = geometry_degps(v, p, w, NULL);
    double fd = finite_difference_degps(v, p, w);
    CHECK_NEAR(g, fd, 1e-3 + 1e-4 * fd);
    return g;
}

static struct acu_vor_params vor_ideal(double fixation_m)
{
    struct acu_vor_params p;
    acu_vor_params_default(&p, fixation_m);
    p.gain = 1.0;
    p.latency_s = 0.0;
    return p;
}

static void test_names(void)
{
    enum acu_gaze_model m;
    for (int k = 0; k < 3; ++k) {
        CHECK(acu_gaze_model_parse(acu_gaze_model_name((enum acu_gaze_model)k), &m) == 0);
        CHECK((int)m == k);
    }
    CHECK(acu_gaze_model_parse("auto", &m) == -1);
    CHECK(acu_gaze_model_parse("Head", &m) == -1);
    CHECK(acu_gaze_model_parse(NULL, &m) == -1);
    struct acu_vor_params p;
    acu_vor_params_default(&p, 3.0);
    CHECK(p.gain > 0.9 && p.gain <= 1.0 && p.latency_s > 0.005 && p.latency_s < 0.016 && p.fixation_m == 3.0);
}

/* Head turns of 50–300 deg/s about an upright axis through the neck while the gaze holds a world
 * point straight ahead at the fixation distance: vor (ideal) and tracked (the measured gaze still in
 * the world) read ≈ 0 for it; head reads the head speed (plus the small parallax of the eyes'
 * swing about the neck). */
static void test_fixation_during_head_turns(void)
{
    const hl_vec3d offset = hl_v3(0, 0.075, -0.0805);
    const double fixation_m = 4.0;
    for (double speed_degps = 50; speed_degps <= 300; speed_degps += 50) {
        hl_vec3d omega = hl_v3(0, speed_degps * HL_RAD_PER_DEG, 0);
        struct acu_head_state h;
        acu_head_state_from_neck(hl_q_identity(), hl_v3(0, 0, 0), hl_v3(0, 0, 0), omega, offset, &h);
        hl_vec3d target = hl_v3_add(h.eye_position_m, hl_v3_scale(h.forward_dir, fixation_m));
        struct acu_vor_params vor = vor_ideal(fixation_m);
        struct acu_viewer v;
        CHECK(acu_gaze_viewer(ACU_GAZE_VOR, &vor, &h, &v) == 0);
        CHECK_NEAR(retinal_degps(&v, target, hl_v3(0, 0, 0)), 0.0, 1e-6 * speed_degps);

        h.has_gaze = 1;
        h.gaze_dir = h.forward_dir;
        h.gaze_angular_velocity_radps = hl_v3(0, 0, 0); /* the gaze holds still in the world */
        CHECK(acu_gaze_viewer(ACU_GAZE_TRACKED, NULL, &h, &v) == 0);
        /* The eyes still translate (ω × offset): a target at 4 m slides by |v⊥|/r, under 2 % here. */
        double tracked = retinal_degps(&v, target, hl_v3(0, 0, 0));
        CHECK(tracked < 0.021 * speed_degps);
        h.eye_velocity_mps = hl_v3(0, 0, 0); /* about the eye itself: exactly still */
        CHECK(acu_gaze_viewer(ACU_GAZE_TRACKED, NULL, &h, &v) == 0);
        CHECK_NEAR(retinal_degps(&v, target, hl_v3(0, 0, 0)), 0.0, 1e-6 * speed_degps);

        acu_head_state_from_neck(hl_q_identity(), hl_v3(0, 0, 0), hl_v3(0, 0, 0), omega, hl_v3(0, 0, 0), &h);
        target = hl_v3(0, 0, -fixation_m);
        CHECK(acu_gaze_viewer(ACU_GAZE_HEAD, NULL, &h, &v) == 0);
        CHECK_NEAR(retinal_degps(&v, target, hl_v3(0, 0, 0)), speed_degps, 1e-9 * speed_degps);
        /* A still world under a pure rotation about the eye: every object ≈ 0 under the ideal VOR
         * (yaw with the gaze level has no roll about the gaze). */
        CHECK(acu_gaze_viewer(ACU_GAZE_VOR, &vor, &h, &v) == 0);
        for (int k = 0; k < 8; ++k) {
            hl_vec3d p = hl_v3(3.0 * cos(k), 2.0 * sin(0.7 * k), -1.0 - k);
            CHECK_NEAR(retinal_degps(&v, p, hl_v3(0, 0, 0)), 0.0, 1e-9);
        }
    }
}

/* Smooth pursuit: an object crossing at 2 m/s, 3 m ahead; the tracked gaze follows it (its angular
 * velocity d × w⊥/r), so the object reads ≈ 0; the head model reads |w⊥|/r; a still object at the
 * same place reads the pursuit speed (the background slides during pursuit). */
static void test_pursuit(void)
{
    struct acu_head_state h;
    acu_head_state_from_neck(hl_q_identity(), hl_v3(0, 0, 0), hl_v3(0, 0, 0), hl_v3(0, 0, 0), hl_v3(0, 0, 0), &h);
    hl_vec3d p = hl_v3(0.5, 0.2, -3.0), w = hl_v3(2.0, 0, 0);
    double r = hl_v3_length(p);
    hl_vec3d d = hl_v3_normalize(p);
    hl_vec3d w_perp = hl_v3_sub(w, hl_v3_scale(d, hl_v3_dot(w, d)));
    h.has_gaze = 1;
    h.gaze_dir = d;
    h.gaze_angular_velocity_radps = hl_v3_cross(d, hl_v3_scale(w_perp, 1.0 / r));
    struct acu_viewer v;
    CHECK(acu_gaze_viewer(ACU_GAZE_TRACKED, NULL, &h, &v) == 0);
    double ecc;
    CHECK_NEAR(geometry_degps(&v, p, w, &ecc), 0.0, 1e-9);
    CHECK_NEAR(retinal_degps(&v, p, w), 0.0, 1e-9);
    CHECK(ecc < 1e-3);
    double pursuit_degps = hl_v3_length(w_perp) / r * HL_DEG_PER_RAD;
    CHECK_NEAR(retinal_degps(&v, p, hl_v3(0, 0, 0)), pursuit_degps, 1e-9);
    CHECK(acu_gaze_viewer(ACU_GAZE_HEAD, NULL, &h, &v) == 0);
    CHECK_NEAR(retinal_degps(&v, p, w), pursuit_degps, 1e-9);
}

/* Translation only: the eye moves sideways at v with the ideal VOR fixating D ahead; objects on the
 * line of sight at depth r read |v|·|1/r − 1/D| rad/s (on either side of the fixation the image slides
 * opposite ways; at D it holds). Off-axis objects are checked against the finite difference only. */
static void test_translation_parallax(void)
{
    const double fixation_m = 2.0;
    const hl_vec3d vel = hl_v3(0.8, 0, 0);
    const double depths_m[] = {0.3, 0.5, 1.0, 2.0, 5.0, 20.0, 1000.0};
    struct acu_head_state h;
    acu_head_state_from_neck(hl_q_identity(), hl_v3(1, 1.6, 2), vel, hl_v3(0, 0, 0), hl_v3(0, 0, 0), &h);
    struct acu_vor_params vor = vor_ideal(fixation_m);
    struct acu_viewer v;
    CHECK(acu_gaze_viewer(ACU_GAZE_VOR, &vor, &h, &v) == 0);
    for (size_t k = 0; k < sizeof depths_m / sizeof depths_m[0]; ++k) {
        double r = depths_m[k];
        hl_vec3d p = hl_v3_add(h.eye_position_m, hl_v3(0, 0, -r));
        double expected = 0.8 * fabs(1.0 / r - 1.0 / fixation_m) * HL_DEG_PER_RAD;
        CHECK_NEAR(retinal_degps(&v, p, hl_v3(0, 0, 0)), expected, 1e-9 * (1 + expected));
        retinal_degps(&v, hl_v3_add(p, hl_v3(0.3 * r, -0.2 * r, 0)), hl_v3(0, 0, 0));
    }
    /* Fixation at infinity: no eye turn, so everything reads its plain parallax |v|/r. */
    vor.fixation_m = INFINITY;
    CHECK(acu_gaze_viewer(ACU_GAZE_VOR, &vor, &h, &v) == 0);
    CHECK_NEAR(hl_v3_length(v.angular_velocity_radps), 0.0, 0.0);
    CHECK_NEAR(retinal_degps(&v, hl_v3_add(h.eye_position_m, hl_v3(0, 0, -4.0)), hl_v3(0, 0, 0)),
               0.2 * HL_DEG_PER_RAD, 1e-9);
}

/* The eyes sit forward and up of the neck: a pure head rotation moves them. Their velocity matches
 * a finite difference of their positions along the rotation, and it turns a near object's world
 * direction while a far object's stays. */
static void test_eye_offset(void)
{
    const hl_vec3d offset = hl_v3(0, 0.075, -0.0805);
    hl_quatd q = hl_q_normalize(hl_q(0.9, 0.1, 0.4, -0.05));
    hl_vec3d omega = hl_v3(0.5, 2.0, -0.3);
    struct acu_head_state h0, h1;
    acu_head_state_from_neck(q, hl_v3(0, 0, 0), hl_v3(0, 0, 0), omega, offset, &h0);
    hl_quatd q1 = hl_q_mul(hl_q_exp(hl_v3_scale(omega, DT_S)), q); /* world-frame ω: left multiply */
    acu_head_state_from_neck(q1, hl_v3(0, 0, 0), hl_v3(0, 0, 0), omega, offset, &h1);
    hl_vec3d fd = hl_v3_scale(hl_v3_sub(h1.eye_position_m, h0.eye_position_m), 1.0 / DT_S);
    CHECK_NEAR(hl_v3_length(hl_v3_sub(fd, h0.eye_velocity_mps)), 0.0, 1e-5);
    CHECK_NEAR(hl_v3_length(hl_v3_sub(h0.eye_position_m, hl_q_rotate(q, offset))), 0.0, 1e-15);
    CHECK_NEAR(hl_v3_length(h0.eye_position_m), hypot(0.075, 0.0805), 1e-12);

    hl_vec3d near = hl_v3_add(h0.eye_position_m, hl_v3_scale(h0.forward_dir, 0.3));
    hl_vec3d far = hl_v3_add(h0.eye_position_m, hl_v3_scale(h0.forward_dir, 1000.0));
    hl_vec3d dn0 = hl_v3_normalize(hl_v3_sub(near, h0.eye_position_m));
    hl_vec3d dn1 = hl_v3_normalize(hl_v3_sub(near, h1.eye_position_m));
    hl_vec3d df0 = hl_v3_normalize(hl_v3_sub(far, h0.eye_position_m));
    hl_vec3d df1 = hl_v3_normalize(hl_v3_sub(far, h1.eye_position_m));
    double near_radps = hl_v3_angle_rad(dn0, dn1) / DT_S, far_radps = hl_v3_angle_rad(df0, df1) / DT_S;
    CHECK(near_radps > 0.3);
    CHECK(far_radps < 1e-3);
    /* The ideal VOR fixating the near object holds it; with a zero offset it would not have moved. */
    struct acu_vor_params vor = vor_ideal(0.3);
    struct acu_viewer v;
    CHECK(acu_gaze_viewer(ACU_GAZE_VOR, &vor, &h0, &v) == 0);
    /* ω has a roll part about the gaze, kept by the model: it turns the image about the fovea only */
    CHECK_NEAR(retinal_degps(&v, near, hl_v3(0, 0, 0)), 0.0, 1e-9);
}

/* The reflex's residuals: gain k under a steady turn leaves (1 − k)·ω on the fixated object; latency τ
 * under a head acceleration α leaves k·α·τ (ω(t) − k·ω(t − τ) with k = 1). */
static void test_vor_residuals(void)
{
    struct acu_head_state h;
    hl_vec3d omega = hl_v3(0, 150 * HL_RAD_PER_DEG, 0);
    acu_head_state_from_neck(hl_q_identity(), hl_v3(0, 0, 0), hl_v3(0, 0, 0), omega, hl_v3(0, 0, 0), &h);
    hl_vec3d target = hl_v3(0, 0, -3.0);
    struct acu_vor_params vor = vor_ideal(3.0);
    struct acu_viewer v;
    for (double k = 0.0; k <= 1.2; k += 0.1) {
        vor.gain = k;
        CHECK(acu_gaze_viewer(ACU_GAZE_VOR, &vor, &h, &v) == 0);
        CHECK_NEAR(retinal_degps(&v, target, hl_v3(0, 0, 0)), fabs(1.0 - k) * 150.0, 1e-9);
    }
    /* α = 3000 deg/s², τ = 10 ms: the eye answers the head of 10 ms ago, 30 deg/s slower. */
    const double alpha_degps2 = 3000.0, tau_s = 0.010, t_s = 0.05;
    vor.gain = 1.0;
    vor.latency_s = tau_s;
    h.angular_velocity_radps = hl_v3(0, alpha_degps2 * t_s * HL_RAD_PER_DEG, 0);
    h.delayed_angular_velocity_radps = hl_v3(0, alpha_degps2 * (t_s - tau_s) * HL_RAD_PER_DEG, 0);
    CHECK(acu_gaze_viewer(ACU_GAZE_VOR, &vor, &h, &v) == 0);
    CHECK_NEAR(retinal_degps(&v, target, hl_v3(0, 0, 0)), alpha_degps2 * tau_s, 1e-9);
    /* Default parameters under a steady 200 deg/s turn: (1 − 0.95)·200 = 10 deg/s. */
    acu_vor_params_default(&vor, 3.0);
    h.angular_velocity_radps = h.delayed_angular_velocity_radps = hl_v3(0, 200 * HL_RAD_PER_DEG, 0);
    CHECK(acu_gaze_viewer(ACU_GAZE_VOR, &vor, &h, &v) == 0);
    CHECK_NEAR(retinal_degps(&v, target, hl_v3(0, 0, 0)), (1.0 - vor.gain) * 200.0, 1e-9);
}

/* Roll about the gaze is kept (no ocular counter-roll): the fixated centre holds, the periphery at
 * eccentricity E turns at |ω_roll|·sin E. */
static void test_torsion(void)
{
    struct acu_head_state h;
    hl_vec3d omega = hl_v3(0, 0, -1.0); /* roll about the forward axis, 57 deg/s */
    acu_head_state_from_neck(hl_q_identity(), hl_v3(0, 0, 0), hl_v3(0, 0, 0), omega, hl_v3(0, 0, 0), &h);
    struct acu_vor_params vor = vor_ideal(5.0);
    struct acu_viewer v;
    CHECK(acu_gaze_viewer(ACU_GAZE_VOR, &vor, &h, &v) == 0);
    CHECK_NEAR(retinal_degps(&v, hl_v3(0, 0, -5), hl_v3(0, 0, 0)), 0.0, 1e-9);
    double e = 30 * HL_RAD_PER_DEG, ecc;
    hl_vec3d p = hl_v3(5 * sin(e), 0, -5 * cos(e));
    CHECK_NEAR(retinal_degps(&v, p, hl_v3(0, 0, 0)), sin(e) * HL_DEG_PER_RAD, 1e-9);
    geometry_degps(&v, p, hl_v3(0, 0, 0), &ecc);
    CHECK_NEAR(ecc, 30.0, 0.01);
}

/* tracked without a measured gaze: −1 and the viewer as vor would fill it. */
static void test_tracked_without_gaze(void)
{
    struct acu_head_state h;
    acu_head_state_from_neck(hl_q_identity(), hl_v3(0, 0, 0), hl_v3(0.3, 0, 0), hl_v3(0, 1, 0), hl_v3(0, 0, 0), &h);
    struct acu_vor_params vor;
    acu_vor_params_default(&vor, 2.0);
    struct acu_viewer a, b;
    CHECK(acu_gaze_viewer(ACU_GAZE_TRACKED, &vor, &h, &a) == -1);
    CHECK(acu_gaze_viewer(ACU_GAZE_VOR, &vor, &h, &b) == 0);
    CHECK(memcmp(&a, &b, sizeof a) == 0);
    /* The tracked gaze sets the eccentricity: 40° aside, an object ahead is 40° out. */
    h.has_gaze = 1;
    h.gaze_dir = hl_v3(sin(40 * HL_RAD_PER_DEG), 0, -cos(40 * HL_RAD_PER_DEG));
    CHECK(acu_gaze_viewer(ACU_GAZE_TRACKED, &vor, &h, &a) == 0);
    double ecc;
    geometry_degps(&a, hl_v3(0, 0, -10), hl_v3(0, 0, 0), &ecc);
    CHECK_NEAR(ecc, 40.0, 0.01);
}

/* A measured gaze's noise outside saccades (acu_gaze_hold_target): the eye looks 3 m ahead at a small
 * object in front of a large one on the same line and beside others, the head translating sideways at
 * 0.3 m/s and turning 20 deg/s about the gaze (roll). The tracker reports 40 deg/s across the gaze
 * (EDVAM's rounding between fixations): held, the object at the gaze reads 0 (not the large one
 * behind, whose sphere the ray meets too), the one 1.5 m further reads the parallax |v|·|1/r − 1/D|,
 * and the roll is kept. A moving object at the gaze with a measured rate near its pursuit's is
 * pursued (it reads 0, the background slides); with a measured rate near 0 it is not (it slides).
 * No object near the gaze: a world point at the fallback distance is held. */
static void test_hold_target(void)
{
    struct acu_head_state h;
    hl_vec3d roll = hl_v3(0, 0, -20.0 * HL_RAD_PER_DEG);
    acu_head_state_from_neck(hl_q_identity(), hl_v3(0, 0, 0), hl_v3(0.3, 0, 0), roll, hl_v3(0, 0, 0), &h);
    h.has_gaze = 1;
    h.gaze_dir = hl_v3(0, 0, -1);
    h.gaze_angular_velocity_radps = hl_v3(0, 40.0 * HL_RAD_PER_DEG, 0); /* noise: a yaw the eye did not make */
    double center[9] = {0.0, 0.0, -3.0, 0.0, 0.0, -4.5, 1.5, 0.0, -3.0};
    double radius[3] = {0.05, 1.0, 0.05};
    uint32_t all[3] = {0, 1, 2};
    struct acu_viewer v;
    CHECK(acu_gaze_viewer(ACU_GAZE_TRACKED, NULL, &h, &v) == 0);
    double noisy = retinal_degps(&v, hl_v3(0, 0, -3.0), hl_v3(0, 0, 0));
    acu_gaze_hold_target(&h, center, radius, NULL, all, 3, ACU_GAZE_TARGET_DEG, 50.0, &v);
    double held = retinal_degps(&v, hl_v3(0, 0, -3.0), hl_v3(0, 0, 0));
    double behind = retinal_degps(&v, hl_v3(0, 0, -4.5), hl_v3(0, 0, 0));
    double want_behind = 0.3 * fabs(1.0 / 4.5 - 1.0 / 3.0) * HL_DEG_PER_RAD;
    printf("hold: the gazed object %.2f deg/s with the noise, %.2e held; 1.5 m behind it %.3f (parallax %.3f)\n",
           noisy, held, behind, want_behind);
    CHECK(noisy > 30.0); /* 40 deg/s less the 5.7 the translation turns the object */
    CHECK_NEAR(held, 0.0, 1e-9);
    CHECK_NEAR(behind, want_behind, 1e-9);
    CHECK_NEAR(hl_v3_dot(v.angular_velocity_radps, h.gaze_dir), hl_v3_dot(roll, h.gaze_dir), 1e-12); /* roll kept */

    /* Pursuit or not: object 0 moves at 1.5 m/s sideways (its pursuit: about 28.6 deg/s less the head's). */
    double velocity[9] = {1.5, 0, 0, 0, 0, 0, 0, 0, 0};
    hl_vec3d w = hl_v3(1.5, 0, 0);
    hl_vec3d follow = hl_v3_cross(h.gaze_dir, hl_v3_scale(hl_v3_sub(w, h.eye_velocity_mps), 1.0 / 3.0));
    h.gaze_angular_velocity_radps = hl_v3_add(follow, hl_v3(0, 0.05, 0)); /* near it, with noise */
    CHECK(acu_gaze_viewer(ACU_GAZE_TRACKED, NULL, &h, &v) == 0);
    acu_gaze_hold_target(&h, center, radius, velocity, all, 3, ACU_GAZE_TARGET_DEG, 50.0, &v);
    CHECK_NEAR(retinal_degps(&v, hl_v3(0, 0, -3.0), w), 0.0, 1e-9);
    double slide = retinal_degps(&v, hl_v3(1.5, 0, -3.0), hl_v3(0, 0, 0));
    CHECK(slide > 20.0); /* the background slides during pursuit */
    h.gaze_angular_velocity_radps = hl_v3(0, 0.05, 0); /* near a fixation's: the object passes */
    CHECK(acu_gaze_viewer(ACU_GAZE_TRACKED, NULL, &h, &v) == 0);
    acu_gaze_hold_target(&h, center, radius, velocity, all, 3, ACU_GAZE_TARGET_DEG, 50.0, &v);
    double passing = retinal_degps(&v, hl_v3(0, 0, -3.0), w);
    CHECK_NEAR(passing, 1.5 / 3.0 * HL_DEG_PER_RAD, 1e-6); /* its own speed across a held world point */

    /* The gaze 30° up, off every object: a world point 50 m along it is held. */
    h.gaze_dir = hl_v3_normalize(hl_v3(0, sin(30.0 * HL_RAD_PER_DEG), -cos(30.0 * HL_RAD_PER_DEG)));
    h.gaze_angular_velocity_radps = hl_v3(0, 40.0 * HL_RAD_PER_DEG, 0);
    CHECK(acu_gaze_viewer(ACU_GAZE_TRACKED, NULL, &h, &v) == 0);
    acu_gaze_hold_target(&h, center, radius, NULL, all, 3, ACU_GAZE_TARGET_DEG, 50.0, &v);
    CHECK_NEAR(retinal_degps(&v, hl_v3_scale(h.gaze_dir, 50.0), hl_v3(0, 0, 0)), 0.0, 1e-9);
}

int main(void)
{
    test_names();
    test_fixation_during_head_turns();
    test_pursuit();
    test_translation_parallax();
    test_eye_offset();
    test_vor_residuals();
    test_torsion();
    test_tracked_without_gaze();
    test_hold_target();
    return tu_finish("test_gaze");
}
