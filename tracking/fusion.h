/* tracking/fusion.h: fusion and prediction — the 3-DoF IMU filter, its prediction and the shared
 * IMU CSV reader. Part of the tracking/tracking.h umbrella; self-contained. */
#ifndef HMDLOD_TRACKING_FUSION_H
#define HMDLOD_TRACKING_FUSION_H

#include "base/base.h"

/* 3-DoF IMU fusion: an error-state Kalman filter (9 states: body-frame orientation error, gyro
 * bias, accel bias) in double, with gyro integration q ← q ⊗ exp((ω − b_g)·dt), an accelerometer
 * gravity update weighted by how far ‖a‖ is from g and by ‖ω‖ (lever arm), and a zero-rate update
 * at detected rest. Without a magnetometer yaw is unobservable and drifts with the residual gyro
 * bias; with one (Rift, trk_fusion_update_mag) a heading-only measurement holds it to the heading
 * the field had at start (there is no absolute north).
 * Frames: body +X right, +Y up, +Z toward the wearer; world +Y up, gravity −Y, so an upright still
 * device reads accel ≈ (0, +9.81, 0). Quaternions are scalar first (w x y z), body-to-world.
 * The struct is plain data (no allocation anywhere, per sample included); fields are read-only. */

/* Tuning. Noise figures are densities so they do not depend on the sample rate. Defaults fit the
 * MEMS class of the shared imu/ streams (MPU-6500 / BMI055; data/README.md §5 noise model). */
struct trk_fusion_config {
    double gyro_noise_radps_rthz;      /* gyro white noise density, rad/s/√Hz */
    double gyro_bias_walk_radps_rts;   /* gyro bias random walk, rad/s/√s */
    double accel_noise_mps2_rthz;      /* accel white noise density, m/s²/√Hz */
    double accel_bias_walk_mps2_rts;   /* accel bias random walk, m/s²/√s (small: bias ~ constant) */
    double init_gyro_bias_sigma_radps; /* prior σ of the gyro bias per axis */
    double init_accel_bias_sigma_mps2; /* prior σ of the accel bias per axis */
    double init_tilt_sigma_rad;        /* prior σ of the tilt when started from the first accel sample */
    double lever_arm_m;                /* assumed IMU distance from the rotation pivot (weights turns) */
    hl_vec3d imu_offset_m;             /* body-frame pivot→IMU vector whose ω×(ω×r) + α×r is removed
                                        * from the accel before the gravity update; zero = none */
    double accel_gate_mps2;            /* accel samples with |‖a‖ − g| above this are not used */
    double accel_inflate;              /* weight of the unmodelled-acceleration terms in the accel
                                        * variance (they are correlated in time, not white) */
    double max_tilt_rate_radps;        /* bound on the gravity correction applied per second */
    double max_dt_s;                   /* a gap longer than this integrates only max_dt_s (counted) */
    double rest_window_s;              /* stillness must last this long before zero-rate updates */
    double predict_lpf_s;              /* time constant of the ω low-pass used by predict; 0 = raw */
    /* Magnetometer heading correction (trk_fusion_update_mag; fusion.c says how and its limits). */
    int use_magnetometer;              /* 1 (default): readings correct heading; 0: ignored */
    double mag_noise_gauss;            /* white noise σ per axis per reading; default 0.002 */
    double mag_inflate;                /* weight of the correlated errors (hard-iron fit, tilt) in
                                        * the heading variance, as accel_inflate; default 100 */
    double mag_max_yaw_rate_radps;     /* bound on the heading correction per second; default 1 °/s */
    double mag_norm_gate_gauss;        /* reading refused when |‖m − b‖ − reference| exceeds it; 0.05 */
    double mag_dip_gate_rad;           /* refused when its dip differs from the reference's; 5° */
    double mag_min_horizontal_gauss;   /* refused when the horizontal field is weaker; 0.05 */
    double mag_min_interval_s;         /* readings closer than this to the last one used are
                                        * skipped (counted); default 0.005 (≤ 200 Hz) */
    double mag_reference_window_s;     /* the reference heading is the field's over the first this
                                        * long of readings; default 0.5 s */
    hl_vec3d mag_hard_iron_gauss;      /* body-frame hard-iron offset: exact when not estimated, the
                                        * fit's prior otherwise; default 0 */
    int mag_estimate_hard_iron;        /* 1 (default): fitted online; 0: use the offset above */
    double mag_fit_sigma_gauss;        /* fit used once its σ is below this; default 0.01 */
};

/* Counters for what the boundary refused or clamped, and what the filter did. */
struct trk_fusion_stats {
    uint64_t samples;           /* calls to trk_fusion_update */
    uint64_t integrated;        /* samples whose gyro was integrated */
    uint64_t skipped_time;      /* dt ≤ 0: equal or backward timestamps, not integrated */
    uint64_t clamped_gaps;      /* dt > max_dt_s: integrated over max_dt_s only */
    uint64_t rejected_nonfinite;/* NaN/Inf in time, gyro or accel: sample ignored entirely */
    uint64_t accel_updates;     /* gravity updates applied */
    uint64_t accel_gated;       /* accel samples refused by the ‖a‖ gate */
    uint64_t accel_deweighted;  /* gravity updates redone with more variance (rate bound) */
    uint64_t rest_updates;      /* zero-rate (gyro bias) updates applied at rest */
    uint64_t mag_readings;      /* calls to trk_fusion_update_mag */
    uint64_t mag_rejected_nonfinite; /* NaN/Inf or zero reading, or no orientation yet: ignored */
    uint64_t mag_waiting;       /* taken for the reference / hard-iron fit only (not yet usable) */
    uint64_t mag_decimated;     /* skipped: within mag_min_interval_s of the last one used */
    uint64_t mag_gated_norm, mag_gated_dip, mag_gated_horizontal; /* disturbance / weak-field gates */
    uint64_t mag_updates;       /* heading updates applied */
    uint64_t mag_rate_limited;  /* of those, scaled down to the heading-rate bound */
    uint64_t mag_fits;          /* hard-iron fit solves */
};

/* Magnetometer state: the reference field and the online hard-iron fit (fusion.c). */
struct trk_fusion_mag {
    hl_vec3d hard_iron_gauss;    /* body-frame offset in use */
    int hard_iron_ok;            /* configured, or the fit is well enough determined */
    double fit_ata[3][3], fit_aty[3]; /* normal equations of (I − Q) b = m_a − Q m (fusion.c) */
    hl_vec3d anchor_mag_gauss;   /* reading of the last anchor */
    hl_quatd anchor_dq;          /* gyro rotation since it: body(now) → body(anchor) */
    double anchor_time_s;
    int has_anchor;
    uint64_t fit_points, fit_points_solved, fit_anchors; /* rows taken / at the last solve; anchors */
    double fit_sigma_gauss;      /* σ of the offset at the last solve (vertical part weighted) */
    hl_vec3d ref_sum_Rm;         /* Σ R·m over the reference window (world frame) */
    double ref_sum_R[3][3];      /* Σ R over the window: B_ref = (Σ R m − (Σ R) b) / n */
    double ref_n, ref_start_s;
    int ref_started, has_ref;
    double ref_heading_rad, ref_norm_gauss, ref_dip_rad; /* of B_ref; heading atan2(−z, x) */
    double last_time_s;
    int has_time;
};

struct trk_fusion {
    hl_quatd orientation;        /* body-to-world estimate, unit */
    hl_vec3d gyro_bias_radps;    /* body frame */
    hl_vec3d accel_bias_mps2;    /* body frame */
    hl_vec3d omega_radps;        /* latest bias-corrected angular velocity, body frame */
    hl_vec3d omega_lp_radps;     /* low-passed ω (predict_lpf_s), body frame */
    hl_vec3d alpha_radps2;       /* angular acceleration from gyro differences, low-passed, body */
    double last_time_s;          /* timestamp of the latest accepted sample */
    double P[9][9];              /* error covariance: [δθ body (rad), δb_g (rad/s), δb_a (m/s²)] */
    hl_vec3d rest_mean_radps, rest_var;  /* EMA of raw gyro and of its variance (rest detector) */
    double rest_time_s;          /* how long the detector has seen stillness */
    struct trk_fusion_mag mag;
    int has_time, has_orientation;
    struct trk_fusion_config cfg;
    struct trk_fusion_stats stats;
};

/* Fills cfg with the defaults described above. */
void trk_fusion_config_default(struct trk_fusion_config *cfg);

/* Resets f. cfg NULL means defaults (copied). The orientation is unknown until the first sample
 * with accel (tilt from gravity, heading 0) or trk_fusion_set_orientation (a "warm start"). */
void trk_fusion_init(struct trk_fusion *f, const struct trk_fusion_config *cfg);

/* Warm start: sets the orientation (body-to-world, normalised here) with prior σ tilt_sigma_rad on
 * every axis; call before the first update. Non-finite input is ignored and returns −1. */
int trk_fusion_set_orientation(struct trk_fusion *f, hl_quatd q_body_to_world, double tilt_sigma_rad);

/* One IMU sample: time t_s (device clock, seconds), body gyro (rad/s) and, when has_accel, body
 * specific force (m/s²). Returns 0 when integrated, 1 when skipped (dt ≤ 0, or the first sample,
 * which has no dt), −1 when refused (non-finite input; the state is untouched). All counted. */
int trk_fusion_update(struct trk_fusion *f, double t_s, hl_vec3d gyro_radps, hl_vec3d accel_mps2,
                      int has_accel);

/* One magnetometer reading (body frame, gauss, hard iron included) taken at t_s, after the update
 * of the sample it came with. Corrects heading only (rotation about world +Y) and the gyro bias
 * along the vertical, as a Kalman measurement whose applied heading change is bounded per second;
 * tilt and accel bias are never touched. Returns 0 when applied, 1 when only collected (reference
 * window, hard-iron fit not ready) or gated (disturbance, weak horizontal field, disabled), −1 when
 * refused (non-finite or zero reading, no orientation yet). All counted; the state is untouched
 * by a refused or gated reading except the fit and reference sums. */
int trk_fusion_update_mag(struct trk_fusion *f, double t_s, hl_vec3d mag_gauss);

/* Orientation horizon_s after the latest sample, by constant body angular velocity (the latest
 * bias-corrected ω; low-passed if predict_lpf_s > 0, which measured worse). Measured on the shared
 * streams, RMS step error vs holding: 10 ms 0.02–0.03° vs 0.5–0.9°, 20 ms 0.07–0.10° vs 1.1–1.8°,
 * 40 ms 0.25–0.39° vs 2.2–3.6°: good to ~40 ms (past that ignored α dominates). horizon ≤ 0: q. */
void trk_fusion_predict(const struct trk_fusion *f, double horizon_s, hl_quatd *q_out);

/* One row of the shared IMU CSV (data/README.md §5): t_s,gx,gy,gz,ax,ay,az,qw,qx,qy,qz. */
struct trk_imu_csv_row {
    double t_s;
    hl_vec3d gyro_radps, accel_mps2; /* body frame */
    hl_quatd truth;                  /* body-to-world ground truth, w x y z */
};

/* Reads a whole IMU CSV into *rows_out (malloc'd; free with trk_imu_csv_free). Strict: exact header,
 * 11 finite numbers a row, LF-terminated last row, unit truth quaternion; errors say file:line. */
int trk_imu_csv_read(const char *path, struct trk_imu_csv_row **rows_out, size_t *count_out,
                     struct hl_error *err);
void trk_imu_csv_free(struct trk_imu_csv_row *rows);

#endif
