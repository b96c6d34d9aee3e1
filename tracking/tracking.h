/* tracking: where the head is. The pose-source interface every source implements — tracker
 * drivers, raw recordings, and the head-motion traces of replay/. Prefix trk_. Depends on base.
 * Frames: head/body frame +X right, +Y up, +Z toward the wearer (−Z forward); world +Y up. */
#ifndef HMDLOD_TRACKING_H
#define HMDLOD_TRACKING_H

#include "base/base.h"

/* One head pose at a time. Orientation is body-to-world (v_world = q v_body q*). */
struct trk_pose {
    double time_s;
    hl_quatd orientation;
    hl_vec3d position_m;          /* world; zero when the source has no position */
    hl_vec3d angular_velocity_radps; /* world frame */
    hl_vec3d gaze_dir_head;       /* unit, head frame; (0,0,−1) when eye locked to the head */
    int has_position;
    int has_gaze;
};

enum trk_health { TRK_HEALTH_OK = 0, TRK_HEALTH_LOST, TRK_HEALTH_ERROR };

/* The interface, Monado-style: a small struct of function pointers. `pose_at` returns the pose for
 * a display time (predicted by live sources, interpolated by recorded ones); 0 or −1 with err. */
struct trk_pose_source {
    const char *name;
    int (*start)(struct trk_pose_source *src, struct hl_error *err);
    void (*stop)(struct trk_pose_source *src);
    int (*pose_at)(struct trk_pose_source *src, double time_s, struct trk_pose *out, struct hl_error *err);
    enum trk_health (*health)(struct trk_pose_source *src, char *reason, size_t reason_size);
    void (*destroy)(struct trk_pose_source *src);
    double start_time_s, end_time_s; /* span of a recorded source; end < start for a live one */
};

/* A still, upright head looking down −Z, eye locked to the head. */
void trk_pose_init_still(struct trk_pose *pose, double time_s);

static inline int trk_source_pose_at(struct trk_pose_source *src, double t_s, struct trk_pose *out,
                                     struct hl_error *err)
{
    return src->pose_at(src, t_s, out, err);
}

static inline void trk_source_destroy(struct trk_pose_source *src)
{
    if (src && src->destroy)
        src->destroy(src);
}

/* ==== report parsers (pure functions of the bytes) ==== */

/* ==== end of report parsers ==== */

/* ==== fusion and prediction ==== */

/* 3-DoF IMU fusion: an error-state Kalman filter (9 states: body-frame orientation error, gyro
 * bias, accel bias) in double, with gyro integration q ← q ⊗ exp((ω − b_g)·dt), an accelerometer
 * gravity update weighted by how far ‖a‖ is from g and by ‖ω‖ (lever arm), and a zero-rate update
 * at detected rest. No magnetometer: yaw is unobservable and drifts with the residual gyro bias.
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
    double accel_gate_mps2;            /* accel samples with |‖a‖ − g| above this are not used */
    double max_tilt_rate_radps;        /* bound on the gravity correction applied per second */
    double max_dt_s;                   /* a gap longer than this integrates only max_dt_s (counted) */
    double rest_window_s;              /* stillness must last this long before zero-rate updates */
    double predict_lpf_s;              /* time constant of the ω low-pass used by predict; 0 = raw */
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
    uint64_t rest_updates;      /* zero-rate (gyro bias) updates applied at rest */
};

struct trk_fusion {
    hl_quatd orientation;        /* body-to-world estimate, unit */
    hl_vec3d gyro_bias_radps;    /* body frame */
    hl_vec3d accel_bias_mps2;    /* body frame */
    hl_vec3d omega_radps;        /* latest bias-corrected angular velocity, body frame */
    hl_vec3d omega_lp_radps;     /* low-passed ω (predict_lpf_s), body frame */
    double last_time_s;          /* timestamp of the latest accepted sample */
    double P[9][9];              /* error covariance: [δθ body (rad), δb_g (rad/s), δb_a (m/s²)] */
    hl_vec3d rest_mean_radps, rest_var;  /* EMA of raw gyro and of its variance (rest detector) */
    double rest_time_s;          /* how long the detector has seen stillness */
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

/* Orientation horizon_s after the latest sample, by constant body angular velocity (the latest
 * bias-corrected ω, low-passed if predict_lpf_s > 0). On the shared streams this cuts the 20 ms step
 * error ~20× and stays useful to 40 ms (see tests/test_fusion.c); horizon ≤ 0 returns the estimate. */
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

/* ==== end of fusion and prediction ==== */

#endif
