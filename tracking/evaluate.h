/* tracking/evaluate.h: accuracy evaluation — end to end (encode, parse, fuse) on the shared IMU
 * streams against their ground truth. Part of the tracking/tracking.h umbrella; self-contained. */
#ifndef HMDLOD_TRACKING_EVALUATE_H
#define HMDLOD_TRACKING_EVALUATE_H

#include "base/base.h"
#include "tracking/fusion.h"
#include "tracking/reports.h"

/* End-to-end tracker accuracy on the shared IMU streams (data/README.md §5): the stream's body-frame
 * samples are encoded into each device's reports at its native rate (trk_encoder), parsed and fused
 * (the same path as live data), and the estimate is compared with the ground truth — tilt, yaw drift,
 * prediction error — and timed. tracking/evaluate.c documents how each device's samples are made. */
#define TRK_EVAL_HORIZONS 3 /* prediction horizons: 10, 20, 40 ms */

/* Tilt error, rad: the angle between the true and the estimated world up (+Y) seen in the body
 * frame — heading plays no part. Both orientations body-to-world, unit. */
double trk_tilt_error_rad(hl_quatd estimate, hl_quatd truth);
/* Heading error, rad in (−π, π]: the twist about world +Y of estimate ⊗ truth*. */
double trk_yaw_error_rad(hl_quatd estimate, hl_quatd truth);
extern const double trk_eval_horizons_s[TRK_EVAL_HORIZONS];

/* The accuracy metrics, instant by instant (tracking/accuracy.c): trk_evaluate_device accumulates
 * its figures through these, and so does any other tracker measured beside it (bench tracking's
 * OpenHMD row), so both are computed by exactly the same code. Plain data; init before use. */
struct trk_accuracy {
    double yaw_skip_s;                       /* yaw RMS/max ignore instants before this */
    uint64_t n, yaw_n;                       /* instants added; of those, after yaw_skip_s */
    double tilt2, tilt_max, yaw_prev, sum_t, sum_y, sum_tt, sum_ty, yaw2, yaw_max; /* rad, s */
    double s2[TRK_EVAL_HORIZONS], hs2[TRK_EVAL_HORIZONS], a2[TRK_EVAL_HORIZONS], ha2[TRK_EVAL_HORIZONS];
    uint64_t m[TRK_EVAL_HORIZONS];           /* instants with horizon h inside the stream */
};
void trk_accuracy_init(struct trk_accuracy *acc, double yaw_skip_s);
/* One instant t_s (s from the stream start): estimate and truth, body-to-world, unit. Tilt, and
 * the heading error unwrapped against the previous instant for the least-squares drift slope. */
void trk_accuracy_add(struct trk_accuracy *acc, double t_s, hl_quatd est, hl_quatd truth);
/* Horizon h of the instant just added: pred = the estimate predicted to t + horizon h (est itself
 * for a tracker that does not predict), truth_h = the truth there. */
void trk_accuracy_add_horizon(struct trk_accuracy *acc, int h, hl_quatd est, hl_quatd pred, hl_quatd truth,
                              hl_quatd truth_h);

struct trk_evaluate_options {
    const struct trk_fusion_config *fusion; /* NULL: defaults */
    uint32_t drop_report_every;      /* simulate bus losses: every k-th report withheld; 0: none */
    double counter_wrap_at_s;        /* > 0: start the device counter so it wraps this far into the
                                      * stream (no effect on the HDK, which has no counter) */
    double pose_horizon_s;           /* horizon of the timed report → predicted pose; default 0.020 */
    int timing_repeats;              /* whole-stream parse+fuse timing passes (median); 0: no timing */
    /* OSVR HDK on-chip error model (an assumption, not a measurement; evaluate.c says why): the
     * reported orientation = truth rotated by a yaw drift about world +Y and a slowly varying
     * (first-order Gauss–Markov) error on each world axis; ω = true mean rate + white noise. */
    double hdk_yaw_drift_deg_per_min;  /* default 0.5 */
    double hdk_error_sigma_deg;        /* default 0.1 per axis */
    double hdk_error_tau_s;            /* correlation time, default 1 s */
    double hdk_gyro_noise_degps_rthz;  /* default 0.01 (the stream's gyro noise density) */
    uint64_t seed;                     /* HDK error model and Rift magnetometer draws; default 1 */
    /* Rift magnetometer synthesis (evaluate.c): body reading = R(q_true)ᵀ·B + hard iron + white
     * noise, quantized by the encoder to 1e-4 gauss, one per report. */
    int rift_magnetometer;             /* 1 (default): synthesize; 0: reports carry none */
    double mag_field_gauss;            /* ‖B‖, default 0.48 (mid-latitude Europe) */
    double mag_dip_deg;                /* inclination below the horizon, default 60 */
    double mag_noise_gauss;            /* per axis per reading, default 0.002 */
    double mag_hard_iron_max_gauss;    /* each axis of the offset uniform in ±this, default 0.25 */
    int mag_hard_iron_known;           /* 1: the fusion is given the true offset (a calibrated headset,
                                        * as LibOVR's calibration step); 0 (default): it fits it online */
    double yaw_skip_s;                 /* yaw RMS/max ignore the first this long; default 5 */
};
void trk_evaluate_options_default(struct trk_evaluate_options *opt);

struct trk_evaluate_result {
    enum trk_device_kind kind;
    double duration_s;               /* stream span evaluated */
    double device_rate_hz;           /* samples per second produced for the device */
    uint64_t device_samples;         /* samples encoded (at the native rate) */
    uint64_t reports_built, reports_dropped; /* by the encoder (drops simulated) */
    uint64_t reports_fed, reports_rejected;  /* fed to the parser / refused by it */
    uint64_t samples_parsed, samples_fused, lost, duplicates, backward; /* parser and fusion counters */
    uint64_t evaluated;              /* instants compared with the truth (one per delivered report) */
    uint64_t gyro_clipped;           /* samples with a gyro axis beyond the device's range */
    double tilt_rms_deg, tilt_max_deg;
    double yaw_drift_deg_per_min;    /* least-squares slope of the heading error */
    double yaw_rms_deg, yaw_max_deg; /* heading error after yaw_skip_s (warm start: truth heading) */
    /* Rift with a synthesized magnetometer: the same figures with the fusion ignoring it (today's
     * behaviour), the offset the fit found, and the fusion's magnetometer counters. has_mag = 0:
     * no magnetometer, the nomag_ fields equal the ones above. */
    int has_mag;
    double nomag_tilt_rms_deg, nomag_yaw_drift_deg_per_min, nomag_yaw_rms_deg, nomag_yaw_max_deg;
    double hard_iron_error_gauss;    /* ‖fitted − true offset‖ at the end; −1 if never fitted */
    /* The same with the fusion given the true offset (a calibrated headset); equal to the figures
     * above when mag_hard_iron_known or no magnetometer. */
    double cal_yaw_drift_deg_per_min, cal_yaw_rms_deg, cal_yaw_max_deg;
    uint64_t mag_updates, mag_gated; /* heading updates applied / readings refused by the gates */
    /* Per horizon: body-frame step error est⁻¹⊗pred vs truth(t)⁻¹⊗truth(t+h), RMS, and the hold
     * baseline (identity step); absolute error angle(pred, truth(t+h)) vs hold angle(est, truth(t+h)). */
    double step_rms_deg[TRK_EVAL_HORIZONS], hold_step_rms_deg[TRK_EVAL_HORIZONS];
    double abs_rms_deg[TRK_EVAL_HORIZONS], hold_abs_rms_deg[TRK_EVAL_HORIZONS];
    double parse_fuse_ns_per_sample;  /* median over repeats of (whole-stream feed time) / samples fused */
    double report_to_pose_us_median, report_to_pose_us_p99; /* bytes in hand → predicted pose */
};

/* Writes res's evaluated, tilt_rms/max, yaw_drift, yaw_rms/max and per-horizon step/hold/abs
 * figures (degrees) from acc; other fields untouched. */
void trk_accuracy_finish(const struct trk_accuracy *acc, struct trk_evaluate_result *res);

/* Short name of a device kind ("Rift DK1", …, "OSVR HDK"). */
const char *trk_evaluate_device_name(enum trk_device_kind kind);

/* Evaluates one device on rows[0..n) (a 1 kHz shared stream or a slice of one; n ≥ 100). opt NULL:
 * defaults. Allocates its buffers once per call (none per sample). 0, or −1 with err. */
int trk_evaluate_device(enum trk_device_kind kind, const struct trk_imu_csv_row *rows, size_t n,
                        const struct trk_evaluate_options *opt, struct trk_evaluate_result *res,
                        struct hl_error *err);

#endif
