/* 3-DoF IMU fusion and prediction: an error-state Kalman filter (ESKF) over
 *   δθ   body-frame orientation error, q_true = q ⊗ exp(δθ)       (rad)
 *   δb_g gyro bias error                                           (rad/s)
 *   δb_a accel bias error                                          (m/s²)
 * in double. Why a filter with bias states instead of OpenHMD's / Monado's gated complementary
 * filter (docs/DEVICES.md §5): neither estimates gyro bias, so yaw drifts like plain integration
 * (10–29 °/min on the shared streams), and both stop correcting below 0.05 rad (2.9°), which is why
 * they sit at 1.3–2.8° tilt RMS (data/README.md §5 "figures to beat"). The README also shows that
 * a perfect gravity observer with the ±20 mg accel bias still errs ~1° RMS, so ≤ 1° needs the accel
 * bias as a state: it becomes observable as the head turns, because a body-fixed bias rotates in
 * the world while gravity does not. The Kalman gain is that split, done by the covariance.
 *
 * Per sample (no allocation, block-structured 9×9 algebra, about a few hundred flops):
 *   1. boundary: non-finite input refused; dt ≤ 0 skipped; dt > max_dt_s clamped (all counted);
 *   2. integrate q ← q ⊗ exp((ω − b_g)·dt), renormalise; propagate P;
 *   3. rest detector (EMA variance of the raw gyro, ‖a‖ ≈ g) → zero-rate update of b_g, the only
 *      thing that pins the yaw component of the gyro bias (DEVICES.md §4: "estimate gyro bias
 *      continuously");
 *   4. gravity update from accel, no dead zone, measurement variance inflated by |‖a‖ − g| and by
 *      the lever-arm terms ω²·r and α·r (the shared streams put the IMU 14 cm from the neck pivot,
 *      adding up to ~1 g in fast turns); the applied tilt correction is bounded per second.
 * Yaw is unobservable without a magnetometer: the filter does not pretend to correct it. With one
 * (Rift DK1/DK2/CV1, DEVICES.md §2b; LibOVR 0.2.3 corrected yaw drift this way, OpenHMD and Monado
 * do not, §5), trk_fusion_update_mag adds a heading-only measurement, described above it. */
#include <math.h>
#include <string.h>

#include "tracking/tracking.h"

#define G_MPS2 9.80665 /* data/README.md §5: world gravity −Y, g = 9.80665 */

void trk_fusion_config_default(struct trk_fusion_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    /* data/README.md §5 noise model: gyro 0.01 °/s/√Hz, bias walk 0.002 °/s/√s, accel 300 µg/√Hz.
     * The bias walk is doubled for margin (real parts also drift with temperature, DEVICES.md §4). */
    cfg->gyro_noise_radps_rthz = 0.01 * HL_RAD_PER_DEG;
    cfg->gyro_bias_walk_radps_rts = 2.0 * 0.002 * HL_RAD_PER_DEG;
    cfg->accel_noise_mps2_rthz = 300e-6 * G_MPS2;
    cfg->accel_bias_walk_mps2_rts = 1e-4;
    /* Priors: initial gyro bias uniform ±0.5 °/s, accel bias ±20 mg (σ of uniform = half-width/√3,
     * rounded up). */
    cfg->init_gyro_bias_sigma_radps = 0.5 * HL_RAD_PER_DEG;
    cfg->init_accel_bias_sigma_mps2 = 0.02 * G_MPS2 * 0.7;
    cfg->init_tilt_sigma_rad = 5.0 * HL_RAD_PER_DEG;
    cfg->lever_arm_m = 0.15;  /* head IMU ~10–15 cm from the neck pivot (README: r = (0, .1, −.1)) */
    cfg->accel_gate_mps2 = 2.0;
    cfg->accel_inflate = 30.0;
    cfg->max_tilt_rate_radps = 20.0 * HL_RAD_PER_DEG;
    cfg->max_dt_s = 0.05;     /* 50 ms: beyond that a gap is a dropout, not a sample period */
    cfg->rest_window_s = 0.25;
    cfg->predict_lpf_s = 0.0; /* measured: the raw ω predicts better (tests/test_fusion.c) */
    /* Magnetometer: on; it acts only where samples carry readings (Rift). Noise: ≈ 2 mgauss per
     * axis, the HMC5983 class of the DK2 (its datasheet: ~2 mG at the ±0.88 G range, an assumption
     * for the DK1/CV1 parts); the 1e-4 gauss LSB adds 0.03 mgauss. Gates: the Earth's field is
     * 0.25–0.65 gauss, so 0.05 gauss (≈ 10 %) and 5° of dip catch a nearby magnet or steel while
     * passing noise and tilt-estimate errors (≤ 1°). */
    cfg->use_magnetometer = 1;
    cfg->mag_noise_gauss = 0.002;
    cfg->mag_inflate = 100.0;
    cfg->mag_max_yaw_rate_radps = 1.0 * HL_RAD_PER_DEG;
    cfg->mag_norm_gate_gauss = 0.05;
    cfg->mag_dip_gate_rad = 5.0 * HL_RAD_PER_DEG;
    cfg->mag_min_horizontal_gauss = 0.05;
    cfg->mag_reference_window_s = 0.5;
    cfg->mag_estimate_hard_iron = 1;
    cfg->mag_min_interval_s = 0.005;
    cfg->mag_fit_sigma_gauss = 0.01; /* its σ is conservative: measured errors are ~3× smaller */
}

static void set_prior(struct trk_fusion *f, double tilt_sigma_rad)
{
    memset(f->P, 0, sizeof f->P);
    double s2[3] = {tilt_sigma_rad * tilt_sigma_rad,
                    f->cfg.init_gyro_bias_sigma_radps * f->cfg.init_gyro_bias_sigma_radps,
                    f->cfg.init_accel_bias_sigma_mps2 * f->cfg.init_accel_bias_sigma_mps2};
    for (int i = 0; i < 9; ++i)
        f->P[i][i] = s2[i / 3];
}

void trk_fusion_init(struct trk_fusion *f, const struct trk_fusion_config *cfg)
{
    memset(f, 0, sizeof *f);
    if (cfg)
        f->cfg = *cfg;
    else
        trk_fusion_config_default(&f->cfg);
    f->orientation = hl_q_identity();
    set_prior(f, f->cfg.init_tilt_sigma_rad);
    f->mag.hard_iron_gauss = f->cfg.mag_hard_iron_gauss;
    f->mag.hard_iron_ok = !f->cfg.mag_estimate_hard_iron;
}

static int finite3(hl_vec3d v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

int trk_fusion_set_orientation(struct trk_fusion *f, hl_quatd q, double tilt_sigma_rad)
{
    if (!isfinite(q.w) || !isfinite(q.x) || !isfinite(q.y) || !isfinite(q.z) || !isfinite(tilt_sigma_rad) ||
        hl_q_norm(q) < 1e-6)
        return -1;
    f->orientation = hl_q_normalize(q);
    f->has_orientation = 1;
    set_prior(f, tilt_sigma_rad > 1e-6 ? tilt_sigma_rad : 1e-6);
    return 0;
}

/* Orientation whose body up-axis is the measured specific force, heading 0: the shortest rotation
 * taking body +Y... expressed as body-to-world: it rotates the measured "up" (a/‖a‖) onto world +Y. */
static hl_quatd tilt_from_accel(hl_vec3d a)
{
    hl_vec3d up = hl_v3_normalize(a);
    hl_vec3d y = hl_v3(0, 1, 0);
    hl_vec3d axis = hl_v3_cross(up, y);
    double angle = hl_v3_angle_rad(up, y);
    if (hl_v3_length(axis) < 1e-12)
        return angle < 1.0 ? hl_q_identity() : hl_q(0, 1, 0, 0); /* upside down: 180° about X */
    return hl_q_from_axis_angle(hl_v3_normalize(axis), angle);
}

/* 3×3 rotation matrix of a unit quaternion (v' = R v). */
static void quat_to_mat(hl_quatd q, double R[3][3])
{
    double w = q.w, x = q.x, y = q.y, z = q.z;
    R[0][0] = 1 - 2 * (y * y + z * z); R[0][1] = 2 * (x * y - w * z);     R[0][2] = 2 * (x * z + w * y);
    R[1][0] = 2 * (x * y + w * z);     R[1][1] = 1 - 2 * (x * x + z * z); R[1][2] = 2 * (y * z - w * x);
    R[2][0] = 2 * (x * z - w * y);     R[2][1] = 2 * (y * z + w * x);     R[2][2] = 1 - 2 * (x * x + y * y);
}

/* Covariance propagation for F = [[A, −dt·I, 0], [0, I, 0], [0, 0, I]], A = exp(−[ω]×dt) (the
 * body-frame error rotates against the step), written block-wise: only the δθ row/column change.
 *   Ptt' = A Ptt Aᵀ − dt (A Ptg + Pgt Aᵀ) + dt² Pgg,  Ptg' = A Ptg − dt Pgg,  Pta' = A Pta − dt Pga. */
static void propagate_cov(struct trk_fusion *f, double A[3][3], double dt)
{
    double (*P)[9] = f->P;
    double APt[3][9]; /* A · P[0:3][0:9] − dt · P[3:6][0:9]: the new δθ rows before the right factor */
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 9; ++j)
            APt[i][j] = A[i][0] * P[0][j] + A[i][1] * P[1][j] + A[i][2] * P[2][j] - dt * P[3 + i][j];
    /* Ptt' = APt[:, 0:3] Aᵀ − dt · APt[:, 3:6] */
    double Ptt[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            Ptt[i][j] = APt[i][0] * A[j][0] + APt[i][1] * A[j][1] + APt[i][2] * A[j][2] - dt * APt[i][3 + j];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
            P[i][j] = 0.5 * (Ptt[i][j] + Ptt[j][i]);
        for (int j = 3; j < 9; ++j)
            P[i][j] = P[j][i] = APt[i][j];
    }
    double qt = f->cfg.gyro_noise_radps_rthz * f->cfg.gyro_noise_radps_rthz * dt;
    double qg = f->cfg.gyro_bias_walk_radps_rts * f->cfg.gyro_bias_walk_radps_rts * dt;
    double qa = f->cfg.accel_bias_walk_mps2_rts * f->cfg.accel_bias_walk_mps2_rts * dt;
    for (int i = 0; i < 3; ++i) {
        P[i][i] += qt;
        P[3 + i][3 + i] += qg;
        P[6 + i][6 + i] += qa;
    }
    /* Yaw is unobservable, so its variance grows without bound over hours. Cap every diagonal at
     * (1 rad)² by a congruence D P D (keeps P positive semi-definite, unlike clipping one entry). */
    for (int i = 0; i < 3; ++i) {
        if (P[i][i] > 1.0) {
            double s = 1.0 / sqrt(P[i][i]);
            for (int j = 0; j < 9; ++j) {
                P[i][j] *= s;
                P[j][i] *= s;
            }
        }
    }
}

/* Sequential scalar Kalman update for a measurement row h = [h_θ (3), 0 0 0, e_idx] (accel rows:
 * h_θ from [u]×, idx an accel-bias state; zero-rate rows: h_θ = 0, idx a gyro-bias state), residual
 * y (reduced here by h·dx from earlier rows of the same measurement), variance r; accumulates dx.
 * The sparse h and the symmetric P update (upper triangle, mirrored) keep it ~150 flops. */
static void scalar_update(struct trk_fusion *f, const double ht[3], int idx, double y, double r, double dx[9])
{
    double (*P)[9] = f->P;
    double Ph[9];
    for (int i = 0; i < 9; ++i)
        Ph[i] = P[i][0] * ht[0] + P[i][1] * ht[1] + P[i][2] * ht[2] + P[i][idx];
    double s = r + ht[0] * Ph[0] + ht[1] * Ph[1] + ht[2] * Ph[2] + Ph[idx];
    if (!(s > 0))
        return;
    double innov = y - (ht[0] * dx[0] + ht[1] * dx[1] + ht[2] * dx[2] + dx[idx]);
    double inv = 1.0 / s;
    for (int i = 0; i < 9; ++i) {
        double k = Ph[i] * inv;
        dx[i] += k * innov;
        for (int j = i; j < 9; ++j)
            P[i][j] -= k * Ph[j];
    }
    for (int i = 1; i < 9; ++i)
        for (int j = 0; j < i; ++j)
            P[i][j] = P[j][i];
}

/* Folds the error state into the nominal state (the reset Jacobian I − [δθ/2]× is ≈ I for the
 * sub-degree corrections here and is left out). The tilt part is bounded per second. */
static void inject(struct trk_fusion *f, double dx[9], double dt)
{
    hl_vec3d dth = hl_v3(dx[0], dx[1], dx[2]);
    double n = hl_v3_length(dth);
    double lim = f->cfg.max_tilt_rate_radps * dt;
    if (f->cfg.max_tilt_rate_radps > 0 && n > lim)
        dth = hl_v3_scale(dth, lim / n);
    f->orientation = hl_q_normalize(hl_q_mul(f->orientation, hl_q_exp(dth)));
    f->gyro_bias_radps = hl_v3_add(f->gyro_bias_radps, hl_v3(dx[3], dx[4], dx[5]));
    f->accel_bias_mps2 = hl_v3_add(f->accel_bias_mps2, hl_v3(dx[6], dx[7], dx[8]));
}

static void accel_update(struct trk_fusion *f, hl_vec3d a, hl_vec3d w_raw, double dt)
{
    double an = hl_v3_length(a);
    double dev = fabs(an - G_MPS2);
    if (dev > f->cfg.accel_gate_mps2) {
        f->stats.accel_gated++;
        return;
    }
    /* Predicted specific force in the body: u = Rᵀ (0, g, 0), plus the lever-arm terms of a known
     * pivot→IMU offset r when configured: f = Rᵀg + α×r + ω×(ω×r) (data/README.md §5 accel model). */
    hl_vec3d u = hl_q_rotate(hl_q_conj(f->orientation), hl_v3(0, G_MPS2, 0));
    hl_vec3d w = hl_v3_sub(w_raw, f->gyro_bias_radps);
    hl_vec3d r_off = f->cfg.imu_offset_m;
    hl_vec3d lever = hl_v3_add(hl_v3_cross(f->alpha_radps2, r_off), hl_v3_cross(w, hl_v3_cross(w, r_off)));
    hl_vec3d pred = hl_v3_add(hl_v3_add(u, lever), f->accel_bias_mps2);
    hl_vec3d y = hl_v3_sub(a, pred);
    /* Measurement variance: white noise per sample, plus the non-gravity terms the model leaves
     * out, each treated as noise of its size: what |‖a‖ − g| shows directly, and the centripetal
     * ω²·L and tangential α·L of an unknown lever arm L (only their residual when r is given).
     * These errors are correlated in time (head motion is band-limited to ~8 Hz, README step 3),
     * so they are inflated further: 30 samples of one slow excursion are not 30 independent looks. */
    double w2 = hl_v3_dot(w, w);
    double alpha = hl_v3_length(f->alpha_radps2);
    double L = f->cfg.lever_arm_m;
    double sa = f->cfg.accel_noise_mps2_rthz / sqrt(dt > 1e-4 ? dt : 1e-4);
    double ext = dev * dev + (w2 * L) * (w2 * L) + (alpha * L) * (alpha * L);
    double r = sa * sa + f->cfg.accel_inflate * ext;
    /* Rows: y ≈ [u]× δθ + δb_a (since Rᵀ_true g = exp(−δθ)ᵀ... = u − δθ × u = u + u × δθ). */
    double ux = u.x, uy = u.y, uz = u.z;
    const double rows[3][3] = {{0, -uz, uy}, {uz, 0, -ux}, {-uy, ux, 0}};
    const double ys[3] = {y.x, y.y, y.z};
    /* Bounded correction rate without breaking the filter: if this update would turn the estimate
     * by more than max_tilt_rate·dt, it is redone with a larger variance (de-weighted) instead of
     * clamping the state after the fact, which would leave P claiming a correction that was never
     * applied (the residual would then leak into the bias states). Rare: large errors only. */
    double lim = f->cfg.max_tilt_rate_radps * dt;
    double P0[9][9];
    memcpy(P0, f->P, sizeof P0); /* ~650 bytes: cheap next to the update itself */
    double dx[9];
    for (int iter = 0;; ++iter) {
        memset(dx, 0, sizeof dx);
        for (int i = 0; i < 3; ++i)
            scalar_update(f, rows[i], 6 + i, ys[i], r, dx);
        double turn = sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]);
        if (!(f->cfg.max_tilt_rate_radps > 0) || turn <= lim || iter == 6)
            break; /* after 6 tries inject() clamps what is left (a few % over) */
        r *= 1.2 * turn / lim; /* converges in a few tries whether P or r dominates */
        f->stats.accel_deweighted++;
        memcpy(f->P, P0, sizeof P0);
    }
    inject(f, dx, dt);
    f->stats.accel_updates++;
}

static void rest_update(struct trk_fusion *f, hl_vec3d w_raw, hl_vec3d a, int has_accel, double dt)
{
    /* EMA (τ = rest_window/2) of the raw gyro and of its per-axis variance. At rest the variance is
     * the white noise alone (5.5e-3 rad/s per axis per sample at 1 kHz); real "still" heads move a
     * few °/s, which this threshold refuses. Stillness must also show in the accel. */
    double tau = 0.5 * f->cfg.rest_window_s;
    double k = dt / (tau + dt);
    hl_vec3d d = hl_v3_sub(w_raw, f->rest_mean_radps);
    f->rest_mean_radps = hl_v3_add(f->rest_mean_radps, hl_v3_scale(d, k));
    f->rest_var = hl_v3_scale(hl_v3_add(f->rest_var, hl_v3(k * d.x * d.x, k * d.y * d.y, k * d.z * d.z)), 1 - k);
    double sn2 = f->cfg.gyro_noise_radps_rthz * f->cfg.gyro_noise_radps_rthz / dt; /* per-sample var */
    double var = f->rest_var.x + f->rest_var.y + f->rest_var.z;
    hl_vec3d wc = hl_v3_sub(w_raw, f->gyro_bias_radps);
    /* A slow smooth turn has low variance too; what refuses it is the mean rate: it must be within
     * what the bias is still uncertain by (3σ) plus 0.1 °/s. Once the bias is learnt, a head turning
     * slower than that is the only thing mistaken for bias (and 0.1 °/s = 6 °/min of yaw). */
    double bias_sd = sqrt(f->P[3][3] + f->P[4][4] + f->P[5][5]);
    int still = var < 3.0 * 2.0 * sn2 &&
                hl_v3_length(hl_v3_sub(f->rest_mean_radps, f->gyro_bias_radps)) < 3.0 * bias_sd + 0.1 * HL_RAD_PER_DEG &&
                hl_v3_length(wc) < 0.1 && (!has_accel || fabs(hl_v3_length(a) - G_MPS2) < 0.5);
    f->rest_time_s = still ? f->rest_time_s + dt : 0.0;
    if (f->rest_time_s < f->cfg.rest_window_s)
        return;
    /* Zero-rate update: true ω = 0, so ω_raw = b_g + noise. Its variance is the white noise plus a
     * floor for sub-threshold motion (0.2 °/s). */
    double r = sn2 + (0.2 * HL_RAD_PER_DEG) * (0.2 * HL_RAD_PER_DEG);
    double dx[9] = {0};
    const double ys[3] = {wc.x, wc.y, wc.z};
    static const double zero3[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
        scalar_update(f, zero3, 3 + i, ys[i], r, dx);
    inject(f, dx, dt);
    f->stats.rest_updates++;
}

int trk_fusion_update(struct trk_fusion *f, double t_s, hl_vec3d gyro_radps, hl_vec3d accel_mps2, int has_accel)
{
    f->stats.samples++;
    if (!isfinite(t_s) || !finite3(gyro_radps) || (has_accel && !finite3(accel_mps2))) {
        f->stats.rejected_nonfinite++; /* DESIGN.md: bad input caught at the boundary, never state */
        return -1;
    }
    if (!f->has_orientation && has_accel && hl_v3_length(accel_mps2) > 0.5 * G_MPS2) {
        f->orientation = tilt_from_accel(accel_mps2); /* cold start: tilt from gravity, heading 0 */
        f->has_orientation = 1;
    }
    if (!f->has_time) {
        /* The first sample has no dt (README: sample 0 covers (−1 ms, 0]): take its time only. */
        f->has_time = 1;
        f->last_time_s = t_s;
        f->omega_radps = f->omega_lp_radps = hl_v3_sub(gyro_radps, f->gyro_bias_radps);
        f->rest_mean_radps = gyro_radps;
        f->stats.skipped_time++;
        return 1;
    }
    double dt = t_s - f->last_time_s;
    if (!(dt > 0)) {
        f->stats.skipped_time++; /* equal or backward timestamp: nothing to integrate */
        return 1;
    }
    f->last_time_s = t_s;
    if (dt > f->cfg.max_dt_s) {
        /* A gap: the gyro sample describes at most the last period, not the whole gap. Integrate
         * max_dt_s of it; the covariance still grows for the full gap (below). */
        f->stats.clamped_gaps++;
        double gap = dt;
        dt = f->cfg.max_dt_s;
        double extra = gap - dt;
        double qt = f->cfg.gyro_noise_radps_rthz * f->cfg.gyro_noise_radps_rthz * extra;
        for (int i = 0; i < 3; ++i)
            f->P[i][i] += qt + f->P[3 + i][3 + i] * extra * extra;
        f->rest_time_s = 0;
    }

    hl_vec3d w = hl_v3_sub(gyro_radps, f->gyro_bias_radps);
    hl_quatd dq = hl_q_exp(hl_v3_scale(w, dt));
    f->orientation = hl_q_normalize(hl_q_mul(f->orientation, dq));
    if (f->mag.has_anchor) /* magnetometer devices only: the hard-iron fit's gyro-only rotation */
        f->mag.anchor_dq = hl_q_normalize(hl_q_mul(f->mag.anchor_dq, dq));
    double R[3][3], A[3][3];
    quat_to_mat(dq, R);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            A[i][j] = R[j][i];
    propagate_cov(f, A, dt);
    f->stats.integrated++;

    /* Angular acceleration from successive gyro samples, low-passed (τ = 10 ms): the raw
     * difference has ~8 rad/s² of noise per axis at 1 kHz (gyro σ 5.5e-3 rad/s / 1 ms). */
    {
        hl_vec3d wn = hl_v3_sub(gyro_radps, f->gyro_bias_radps);
        hl_vec3d araw = hl_v3_scale(hl_v3_sub(wn, f->omega_radps), 1.0 / dt);
        double ka = dt / (0.010 + dt);
        f->alpha_radps2 = hl_v3_add(f->alpha_radps2, hl_v3_scale(hl_v3_sub(araw, f->alpha_radps2), ka));
    }
    rest_update(f, gyro_radps, accel_mps2, has_accel, dt);
    if (has_accel)
        accel_update(f, accel_mps2, gyro_radps, dt);

    /* Latest bias-corrected ω (after this sample's bias update) and its optional low-pass. */
    f->omega_radps = hl_v3_sub(gyro_radps, f->gyro_bias_radps);
    if (f->cfg.predict_lpf_s > 0) {
        double k = dt / (f->cfg.predict_lpf_s + dt);
        f->omega_lp_radps = hl_v3_add(f->omega_lp_radps, hl_v3_scale(hl_v3_sub(f->omega_radps, f->omega_lp_radps), k));
    } else {
        f->omega_lp_radps = f->omega_radps;
    }
    return 0;
}

void trk_fusion_predict(const struct trk_fusion *f, double horizon_s, hl_quatd *q_out)
{
    if (!(horizon_s > 0)) {
        *q_out = f->orientation;
        return;
    }
    /* Constant body angular velocity: the axis is fixed in the body, so one exp is exact for it
     * (Monado's relation-history extrapolation does the same; OpenHMD does not predict, DEVICES.md
     * §5). Angular acceleration is left out: differentiating the gyro amplifies its noise. */
    *q_out = hl_q_normalize(hl_q_mul(f->orientation, hl_q_exp(hl_v3_scale(f->omega_lp_radps, horizon_s))));
}

/* ---- magnetometer heading correction ------------------------------------------------------------
 *
 * Model: m_body = Rᵀ B + b + noise, B the (unknown, constant) world field, b the hard-iron offset of
 * the headset (body-fixed: speaker magnets, screws). There is no absolute north, so the reference is
 * the heading B had at start: B_ref = mean of R(m − b) over the first mag_reference_window_s of
 * readings. Its sums Σ R m and Σ R are kept, so B_ref is recomputed exactly whenever b improves
 * (no drift of the reference through refits).
 *
 * Hard iron (mag_estimate_hard_iron): gyro-aided least squares (mag_fit_add below): each reading
 * and an anchor reading up to 0.5 s older, with the gyro's rotation Q between them, give
 * (I − Q) b = m_a − Q m, linear in b alone; 3×3 normal equations (no storage per reading), a weak
 * prior (σ 0.5 gauss) at the configured offset, solved every 100 readings, used once the offset's σ
 * (horizontal part, plus the vertical part at sin²(10°), a typical head tilt) is below
 * mag_fit_sigma_gauss. Why not a sphere fit ‖m − b‖ = ρ (tried first): head motion keeps the
 * readings on a band of the sphere, leaving b along the vertical confounded with ρ — 0.02–0.08 gauss
 * off on the shared streams whenever the head tilts across the field's heading; the gyro sees b to
 * first order in any rotation. Measured (evaluate.c's synthetic field): offset within 0.002–0.013
 * gauss after 60 s, used from ~10–15 s in. Limits: the heading drifts uncorrected until then (the
 * reference stays the start's, so the error is then pulled back at ≤ 1 °/s); a head that only turns
 * about one axis leaves b along it undetermined (harmless until it tilts, which determines it); soft
 * iron (a scaled, skewed ellipsoid) is not modelled; readings disturbed before the reference exists
 * enter the fit; the offset is assumed constant for the session.
 *
 * Update: w = R(m − b) in the world; its heading ψ = atan2(−w_z, w_x) (rotation by α about +Y adds
 * α). Gates: |‖w‖ − ‖B_ref‖| > mag_norm_gate, |dip − dip_ref| > mag_dip_gate (a disturbance), or
 * horizontal field < mag_min_horizontal. Innovation ψ_ref − ψ(w). Its linearisation in the world
 * rotation error φ = R δθ is (−w_x w_y/h², 1, −w_y w_z/h²) · φ: heading one-for-one, plus tilt
 * leaking in through the dip (tan dip ≈ 1.7 at 60°), so the innovation variance accounts for the
 * tilt uncertainty. The gain is then restricted to the heading (δθ along the body-frame vertical u)
 * and to the vertical gyro bias (u·δb_g, the component only heading observes), zero on the accel
 * bias, and scaled down if the heading step would exceed mag_max_yaw_rate·dt. P is updated with the
 * form valid for any gain, P − K hᵀP − P h Kᵀ + s K Kᵀ, so it stays consistent with what was applied.
 * Per reading used (≤ 200 Hz, mag_min_interval_s): ~300 flops, plus a 3×3 solve every 100 of them. */

#define MAG_FIT_ANCHOR_S 0.5   /* rows pair each reading with the anchor up to this old */
#define MAG_FIT_EVERY 100      /* rows between solves (0.5 s at 200 Hz) */
#define MAG_FIT_MIN_ANCHORS 10
#define MAG_FIT_PRIOR_GAUSS 0.5

static double wrap_pi(double a)
{
    while (a > HL_PI)
        a -= 2.0 * HL_PI;
    while (a <= -HL_PI)
        a += 2.0 * HL_PI;
    return a;
}

/* Recomputes the reference field from the window sums and the offset in use. */
static void mag_make_reference(struct trk_fusion_mag *m)
{
    hl_vec3d b = m->hard_iron_gauss;
    const double (*S)[3] = m->ref_sum_R;
    hl_vec3d Sb = hl_v3(S[0][0] * b.x + S[0][1] * b.y + S[0][2] * b.z, S[1][0] * b.x + S[1][1] * b.y + S[1][2] * b.z,
                        S[2][0] * b.x + S[2][1] * b.y + S[2][2] * b.z);
    hl_vec3d B = hl_v3_scale(hl_v3_sub(m->ref_sum_Rm, Sb), 1.0 / m->ref_n);
    double h = sqrt(B.x * B.x + B.z * B.z);
    m->ref_norm_gauss = hl_v3_length(B);
    m->ref_heading_rad = atan2(-B.z, B.x);
    m->ref_dip_rad = atan2(-B.y, h); /* positive: field points below the horizon (north hemisphere) */
    m->has_ref = 1;
}

/* Solves the 3×3 normal equations (with the prior) by Gauss–Jordan, the inverse alongside for the
 * offset's covariance; returns 1 when the offset is taken. */
static int mag_fit_solve(struct trk_fusion *f, hl_vec3d up_body)
{
    struct trk_fusion_mag *m = &f->mag;
    /* One pair's residual has σ ≈ √2·σ_m (two readings), ×2 for unmodelled soft iron and
     * orientation error: the prior's weight in the same units. */
    double sy = 2.0 * sqrt(2.0) * (f->cfg.mag_noise_gauss > 1e-4 ? f->cfg.mag_noise_gauss : 1e-4);
    double lambda = (sy / MAG_FIT_PRIOR_GAUSS) * (sy / MAG_FIT_PRIOR_GAUSS);
    const double pr[3] = {f->cfg.mag_hard_iron_gauss.x, f->cfg.mag_hard_iron_gauss.y, f->cfg.mag_hard_iron_gauss.z};
    double A[3][7];
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            A[i][j] = m->fit_ata[i][j] + (i == j ? lambda : 0.0);
            A[i][3 + j] = i == j ? 1.0 : 0.0;
        }
        A[i][6] = m->fit_aty[i] + lambda * pr[i];
    }
    for (int c = 0; c < 3; ++c) {
        int piv = c;
        for (int r = c + 1; r < 3; ++r)
            if (fabs(A[r][c]) > fabs(A[piv][c]))
                piv = r;
        if (!(fabs(A[piv][c]) > 1e-300))
            return 0;
        if (piv != c)
            for (int j = 0; j < 7; ++j) {
                double t = A[c][j];
                A[c][j] = A[piv][j];
                A[piv][j] = t;
            }
        double inv = 1.0 / A[c][c];
        for (int j = 0; j < 7; ++j)
            A[c][j] *= inv;
        for (int r = 0; r < 3; ++r) {
            if (r == c)
                continue;
            double k = A[r][c];
            for (int j = 0; j < 7; ++j)
                A[r][j] -= k * A[c][j];
        }
    }
    hl_vec3d b = hl_v3(A[0][6], A[1][6], A[2][6]);
    if (!finite3(b))
        return 0;
    f->stats.mag_fits++;
    /* Covariance sy²·(AᵀA)⁻¹: the horizontal part (trace − uᵀCu) sets the heading error directly;
     * the vertical part leaks in by sin(tilt) once the head tilts: counted at 10° (sin² ≈ 0.03). */
    const double u[3] = {up_body.x, up_body.y, up_body.z};
    double tr = 0, uCu = 0;
    for (int i = 0; i < 3; ++i) {
        tr += A[i][3 + i];
        for (int j = 0; j < 3; ++j)
            uCu += u[i] * A[i][3 + j] * u[j];
    }
    double per_anchor = m->fit_anchors > 0 ? (double)m->fit_points / (double)m->fit_anchors : 1.0;
    double var = sy * sy * per_anchor * ((tr - uCu) + 0.03 * uCu);
    m->fit_sigma_gauss = sqrt(var > 0 ? var : 0);
    if (m->fit_anchors < MAG_FIT_MIN_ANCHORS || m->fit_sigma_gauss > f->cfg.mag_fit_sigma_gauss)
        return 0;
    m->hard_iron_gauss = b;
    m->hard_iron_ok = 1;
    return 1;
}

/* Gyro-aided rows: between an anchor reading a and a later reading, the body rotated by Q, the
 * bias-corrected gyro integrated since the anchor (trk_fusion_update keeps it) — not the fused
 * orientations, whose accel and heading corrections (~0.1–0.3°) would be as large as the signal.
 * Over the anchor window (0.5 s) the gyro's own error is ~0.01°. The field is fixed in
 * the world, so m_a − b = Q (m − b): (I − Q) b = m_a − Q m, three rows linear in b alone — no
 * reference heading or magnitude needed, and every component of b is seen that the rotation moves
 * (all but its axis), to first order. Every reading adds its rows; they share the anchor's noise,
 * which the covariance accounts for by counting anchors, not rows. */
static void mag_fit_add(struct trk_fusion *f, double t_s, hl_vec3d mag)
{
    struct trk_fusion_mag *m = &f->mag;
    double age = t_s - m->anchor_time_s;
    if (!m->has_anchor || !(age >= 0) || age > MAG_FIT_ANCHOR_S) {
        m->has_anchor = 1;
        m->anchor_mag_gauss = mag;
        m->anchor_dq = hl_q_identity();
        m->anchor_time_s = t_s;
        m->fit_anchors++;
        return;
    }
    hl_quatd dq = m->anchor_dq; /* body(now) → body(anchor), gyro only */
    double Q[3][3];
    quat_to_mat(dq, Q);
    hl_vec3d qm = hl_v3(Q[0][0] * mag.x + Q[0][1] * mag.y + Q[0][2] * mag.z,
                        Q[1][0] * mag.x + Q[1][1] * mag.y + Q[1][2] * mag.z,
                        Q[2][0] * mag.x + Q[2][1] * mag.y + Q[2][2] * mag.z);
    const double y[3] = {m->anchor_mag_gauss.x - qm.x, m->anchor_mag_gauss.y - qm.y, m->anchor_mag_gauss.z - qm.z};
    /* (I − Q)ᵀ(I − Q) = 2I − Q − Qᵀ (Q orthonormal): no 3×3 product needed. */
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
            m->fit_ata[i][j] += (i == j ? 2.0 : 0.0) - Q[i][j] - Q[j][i];
        m->fit_aty[i] += y[i] - (Q[0][i] * y[0] + Q[1][i] * y[1] + Q[2][i] * y[2]);
    }
    m->fit_points++;
}

int trk_fusion_update_mag(struct trk_fusion *f, double t_s, hl_vec3d mag_gauss)
{
    struct trk_fusion_mag *m = &f->mag;
    f->stats.mag_readings++;
    if (!isfinite(t_s) || !finite3(mag_gauss) || !(hl_v3_length(mag_gauss) > 1e-6) || !f->has_orientation) {
        f->stats.mag_rejected_nonfinite++; /* never reaches the state, the fit or the reference */
        return -1;
    }
    if (!f->cfg.use_magnetometer) {
        f->stats.mag_waiting++;
        return 1;
    }
    /* Decimation: a heading held at ≤ 1 °/s needs no 1 kHz updates, and its variance is dominated
     * by correlated errors that more readings do not average (mag_inflate); the HMC5983 class
     * itself samples at most 220 Hz, so 1 kHz reports repeat it. */
    if (m->has_time && t_s - m->last_time_s < f->cfg.mag_min_interval_s - 1e-7 && t_s >= m->last_time_s) {
        f->stats.mag_decimated++;
        return 1;
    }
    double dt = m->has_time ? t_s - m->last_time_s : 0.0;
    if (m->has_time && !(dt > 0))
        dt = 0.0;
    if (dt > f->cfg.max_dt_s)
        dt = f->cfg.max_dt_s;
    m->last_time_s = t_s;
    m->has_time = 1;

    double R[3][3];
    quat_to_mat(f->orientation, R);
    hl_vec3d up_b = hl_v3(R[1][0], R[1][1], R[1][2]); /* world +Y in the body: row 1 of R */

    /* Reference window: sums of R m and R (usable with any later offset). */
    if (!m->ref_started) {
        m->ref_started = 1;
        m->ref_start_s = t_s;
    }
    int in_window = t_s - m->ref_start_s <= f->cfg.mag_reference_window_s;
    if (in_window) {
        hl_vec3d Rm = hl_q_rotate(f->orientation, mag_gauss);
        m->ref_sum_Rm = hl_v3_add(m->ref_sum_Rm, Rm);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                m->ref_sum_R[i][j] += R[i][j];
        m->ref_n += 1.0;
    }

    /* Hard-iron fit: every reading until the reference exists, then only those passing the norm
     * gate (a disturbance must not move the offset). */
    if (f->cfg.mag_estimate_hard_iron) {
        int take = 1;
        if (m->has_ref) {
            double nrm = hl_v3_length(hl_v3_sub(mag_gauss, m->hard_iron_gauss));
            take = fabs(nrm - m->ref_norm_gauss) <= f->cfg.mag_norm_gate_gauss;
        }
        if (take) {
            mag_fit_add(f, t_s, mag_gauss);
            if (m->fit_points >= m->fit_points_solved + MAG_FIT_EVERY) {
                m->fit_points_solved = m->fit_points;
                if (mag_fit_solve(f, up_b) && !in_window && m->ref_n > 0)
                    mag_make_reference(m);
            }
        }
    }
    if (in_window || !m->hard_iron_ok || m->ref_n <= 0) {
        f->stats.mag_waiting++;
        return 1;
    }
    if (!m->has_ref)
        mag_make_reference(m);

    /* Reading in the world frame, and the gates. */
    hl_vec3d w = hl_q_rotate(f->orientation, hl_v3_sub(mag_gauss, m->hard_iron_gauss));
    double h2 = w.x * w.x + w.z * w.z, h = sqrt(h2);
    if (h < f->cfg.mag_min_horizontal_gauss) {
        f->stats.mag_gated_horizontal++;
        return 1;
    }
    if (fabs(hl_v3_length(w) - m->ref_norm_gauss) > f->cfg.mag_norm_gate_gauss) {
        f->stats.mag_gated_norm++;
        return 1;
    }
    if (fabs(atan2(-w.y, h) - m->ref_dip_rad) > f->cfg.mag_dip_gate_rad) {
        f->stats.mag_gated_dip++;
        return 1;
    }
    double innov = wrap_pi(m->ref_heading_rad - atan2(-w.z, w.x));

    /* h in the world (heading + tilt through the dip), then in the body: h_b = Rᵀ h_w. */
    hl_vec3d hw = hl_v3(-w.x * w.y / h2, 1.0, -w.y * w.z / h2);
    double ht[3];
    for (int i = 0; i < 3; ++i)
        ht[i] = R[0][i] * hw.x + R[1][i] * hw.y + R[2][i] * hw.z;
    double (*P)[9] = f->P;
    double Ph[9];
    for (int i = 0; i < 9; ++i)
        Ph[i] = P[i][0] * ht[0] + P[i][1] * ht[1] + P[i][2] * ht[2];
    /* White noise per reading, plus the correlated errors (offset fit, quantization) inflated as the
     * accel's are: they do not average out over consecutive readings. */
    double fit_s = f->cfg.mag_estimate_hard_iron ? m->fit_sigma_gauss : 0.0;
    double r = (f->cfg.mag_noise_gauss * f->cfg.mag_noise_gauss +
                f->cfg.mag_inflate * (fit_s * fit_s + 1e-8 / 12.0)) / h2;
    double S = r + ht[0] * Ph[0] + ht[1] * Ph[1] + ht[2] * Ph[2];
    if (!(S > 0) || !isfinite(innov))
        return 1;
    /* Gain restricted to heading (δθ ∥ u) and the vertical gyro bias (δb_g ∥ u); none on δb_a. */
    const double u[3] = {up_b.x, up_b.y, up_b.z};
    double kt = (u[0] * Ph[0] + u[1] * Ph[1] + u[2] * Ph[2]) / S;
    double kg = (u[0] * Ph[3] + u[1] * Ph[4] + u[2] * Ph[5]) / S;
    double scale = 1.0;
    double lim = f->cfg.mag_max_yaw_rate_radps * dt;
    if (f->cfg.mag_max_yaw_rate_radps > 0 && fabs(kt * innov) > lim) {
        scale = fabs(kt * innov) > 0 ? lim / fabs(kt * innov) : 0.0;
        f->stats.mag_rate_limited++;
    }
    double K[9] = {scale * kt * u[0], scale * kt * u[1], scale * kt * u[2],
                   scale * kg * u[0], scale * kg * u[1], scale * kg * u[2], 0, 0, 0};
    for (int i = 0; i < 6; ++i) /* K is zero on δb_a: rows/columns 6..8 change only against 0..5 */
        for (int j = i; j < 9; ++j) {
            P[i][j] += -K[i] * Ph[j] - Ph[i] * K[j] + S * K[i] * K[j];
            P[j][i] = P[i][j];
        }
    double dx[9];
    for (int i = 0; i < 9; ++i)
        dx[i] = K[i] * innov;
    /* exp(δθ) to first order (δθ ≤ 1 °/s · dt, ~1e-5 rad): saves the sin/cos; renormalised. */
    f->orientation = hl_q_normalize(hl_q_mul(f->orientation, hl_q(1.0, 0.5 * dx[0], 0.5 * dx[1], 0.5 * dx[2])));
    f->gyro_bias_radps = hl_v3_add(f->gyro_bias_radps, hl_v3(dx[3], dx[4], dx[5]));
    f->stats.mag_updates++;
    return 0;
}
