/* Internal to bench/: OpenHMD's 3-DoF fusion (Debian libopenhmd 0.3.0, through its external-sensor
 * device, PLATFORM.md §10) run on a shared IMU stream and scored by tracking/accuracy.c, the code
 * that scores hmdlod's own fusion. An oracle for bench tracking and its test: it is never on the frame
 * path. Built with libopenhmd when pkg-config finds it (HMDLOD_HAVE_OPENHMD); without it,
 * bch_openhmd_evaluate fails with BCH_OPENHMD_ABSENT and the conversions still work. */
#ifndef HMDLOD_BENCH_TRACKING_OPENHMD_H
#define HMDLOD_BENCH_TRACKING_OPENHMD_H

#include <stddef.h>
#include <stdint.h>

#include "tracking/tracking.h"

#define BCH_OPENHMD_ABSENT "libopenhmd-dev absent"

struct bch_openhmd_result {
    char version[32];                 /* "0.3.0" from ohmd_get_version */
    struct trk_evaluate_result acc;   /* accuracy fields only (trk_accuracy_finish); OpenHMD does not
                                       * predict, so its step/abs figures are the hold ones */
    uint64_t samples;                 /* stream samples fused (all but sample 0, as ours) */
    double warm_error_deg;            /* OpenHMD's orientation after the warm-start sample vs the truth */
    hl_quatd last;                    /* OpenHMD's orientation after the last sample, hmdlod's frame */
    double fuse_ns_per_sample;        /* whole stream, no clock reads in the loop, median of repeats */
    double sample_to_pose_us_median, sample_to_pose_us_p99; /* per sample: setf → update → getf */
};

/* 1 when this build has libopenhmd. */
int bch_openhmd_available(void);

/* Runs OpenHMD's fusion on rows[0..n) (a 1 kHz shared stream or a slice, n ≥ 100), warm started at
 * rows[0]'s truth, and scores it against the truth with yaw_skip_s as trk_evaluate_options; repeats
 * whole-stream timing passes (0: none). 0, or −1 with err (err holds BCH_OPENHMD_ABSENT when the
 * build has no libopenhmd). */
int bch_openhmd_evaluate(const struct trk_imu_csv_row *rows, size_t n, double yaw_skip_s, int repeats,
                           struct bch_openhmd_result *res, struct hl_error *err);

/* The frame conversion, both ways (bench_tracking_openhmd.c says why it is what it is). */
/* One OHMD_EXTERNAL_SENSOR_FUSION record: dt s, gyro xyz rad/s, accel xyz m/s², mag xyz (zero). */
void bch_openhmd_sample(double dt_s, hl_vec3d gyro_radps, hl_vec3d accel_mps2, float out[10]);
/* OHMD_ROTATION_QUAT (x y z w, float) → hmdlod's body-to-world quaternion, normalized, w ≥ 0 not
 * forced. Returns −1 if a component is not finite or the norm is not near 1. */
int bch_openhmd_quat_to_hmdlod(const float q_xyzw[4], hl_quatd *out);

#endif
