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

/* Tracker HID reports → physical IMU samples (docs DEVICES.md §2). A parser is a pure function of its
 * state and the bytes: no I/O, no allocation, no clock. Drivers read reports and feed them here.
 * Every parser returns the number of new samples written to `out` (0..TRK_REPORT_MAX_SAMPLES) or −1
 * with "<device> report: reason" in err; a rejected report changes nothing but `rejected`. */

#define TRK_REPORT_MAX_SAMPLES 3 /* most samples one report of any supported device yields */

/* One IMU sample in the body frame (+X right, +Y up, +Z toward the wearer). device_time_ns is the
 * device counter unwrapped to int64 ns (HDK: the host time the caller passed). Fields without a
 * has_ flag set are zero (orientation: identity). */
struct trk_imu_sample {
    int64_t device_time_ns;
    hl_vec3d gyro_radps;   /* body-frame angular velocity */
    hl_vec3d accel_mps2;   /* body-frame specific force (reads +9.81 on +Y when upright and still) */
    hl_quatd orientation;  /* on-device fused body-to-world orientation (HDK only), w x y z */
    /* Magnetometer (Rift DK1/DK2/CV1 only, DEVICES.md §2b): the field in gauss (i16 × 1e-4, the
     * LibOVR convention), body frame with the gyro's axes (+X right, +Y up, +Z back), raw: the
     * hard-iron offset is still in it. One reading per report, attached to the report's newest
     * sample; the other samples of the report have has_mag = 0. */
    hl_vec3d mag_gauss;
    int has_gyro, has_accel, has_orientation, has_mag;
};

/* Counters every parser keeps. reports + rejected = parse calls; samples = sum of returns. `lost`:
 * samples the device says it produced but never delivered (Rift N > slots, Vive/HDK sequence gaps). */
struct trk_report_counters {
    uint64_t reports, rejected;   /* accepted / refused (−1) reports */
    uint64_t samples;             /* samples emitted */
    uint64_t lost;
    uint64_t duplicates;          /* dropped: already delivered (same time or sequence) */
    uint64_t backward;            /* dropped: timestamp behind the last delivered one */
};

/* Unwrapper for an N-bit device counter (1 ≤ bits ≤ 32) ticking every num/den ns. The first raw
 * value starts the unwrapped count at raw. A modular step d = (raw − last) mod 2^bits is a forward
 * step (wrap included) when 0 < d < 2^(bits−1); d ≥ 2^(bits−1) means the counter went back by
 * 2^bits − d ≤ half the range: a backward sample, not a wrap. */
struct trk_tick_clock {
    uint32_t bits, period_num_ns, period_den;
    int started;
    uint32_t last_raw;
    int64_t ticks; /* unwrapped count at last_raw */
};
void trk_tick_clock_init(struct trk_tick_clock *clock, uint32_t bits, uint32_t period_num_ns, uint32_t period_den);
/* Returns 1 (forward; clock advanced, *ticks_out set), 0 (same raw value as last; *ticks_out set)
 * or −1 (backward; clock untouched). raw is masked to the counter width. */
int trk_tick_clock_unwrap(struct trk_tick_clock *clock, uint32_t raw, int64_t *ticks_out);
int64_t trk_tick_clock_ns(const struct trk_tick_clock *clock, int64_t ticks); /* rounded to the ns */

/* Rift 21-bit packed triple (§2b): 8 bytes, big-endian bit string x|y|z (21 bits each, two's
 * complement) + 1 unused bit. Raw LSB counts; Rift scale is 1e-4 per LSB. */
void trk_unpack_21bit_triple(const uint8_t in[8], int32_t out[3]);
/* Inverse; each value clamped to [−2^20, 2^20 − 1], last bit zero. */
void trk_pack_21bit_triple(const int32_t in[3], uint8_t out[8]);

/* ---- Oculus Rift DK1 (report 0x01) and DK2/CV1 (report 0x0B), §2b ----------------------------
 * Slots are chronological (slot 0 oldest); the report timestamp is the newest valid slot's time
 * and earlier slots are 1 ms apart — DEVICES.md states this for DK2 and we use it for DK1 too.
 * Config flag 0x40 (sensor coords) is assumed clear: samples are already in our body frame. */
#define TRK_RIFT_DK1_REPORT_ID 0x01
#define TRK_RIFT_DK2_REPORT_ID 0x0B
#define TRK_RIFT_LSB 1e-4 /* m/s² and rad/s per LSB */
struct trk_rift_parser {
    int dk2;                      /* 0: DK1 0x01 (u16 ms clock, 3 slots); 1: DK2/CV1 0x0B (u32 µs, 2 slots) */
    struct trk_tick_clock clock;
    int64_t last_time_ns;         /* newest delivered sample */
    int has_last;
    struct trk_report_counters n;
};
void trk_rift_parser_init(struct trk_rift_parser *p, int dk2);
/* DK1 accepts 62 or 64 bytes (some stacks pad input reports), DK2/CV1 exactly 64. Needs
 * max_out ≥ the slot count (3 DK1, 2 DK2). N > slots ⇒ N − slots counted lost; the running
 * sample count is not read. The magnetometer (DK1 [56..61], DK2/CV1 [44..49], i16 × 1e-4 gauss)
 * goes to the newest sample emitted (none emitted: the reading is dropped); an all-zero triple is
 * taken as "no reading" (has_mag = 0): the Earth's field never reads exactly zero on all axes. */
#define TRK_RIFT_MAG_LSB_GAUSS 1e-4
int trk_rift_parse(struct trk_rift_parser *p, const uint8_t *report, size_t length,
                   struct trk_imu_sample *out, int max_out, struct hl_error *err);

/* Feature/output reports a Rift driver sends (§2b); each writes the bytes and returns their count. */
size_t trk_rift_build_keepalive_dk1(uint8_t out[5], uint16_t command_id, uint16_t interval_ms);      /* 0x08 */
size_t trk_rift_build_keepalive_mux(uint8_t out[6], uint16_t command_id, uint8_t report_id,
                                    uint16_t interval_ms);                                          /* 0x11 */
size_t trk_rift_build_enable_components(uint8_t out[4], uint16_t command_id, uint8_t flags);        /* 0x1D */
#define TRK_RIFT_COMPONENT_DISPLAY 0x01
#define TRK_RIFT_COMPONENT_AUDIO 0x02
#define TRK_RIFT_COMPONENT_LEDS 0x04
/* Config 0x02 (7 B): flags (both open drivers force 0x04 factory calibration | 0x08 auto gyro
 * zero-rate on), interval (report rate = 1000/(1+interval) Hz), u16 that reads 1000 on DK1/DK2. */
size_t trk_rift_build_config(uint8_t out[7], uint16_t command_id, uint8_t flags, uint8_t interval,
                             uint16_t rate_or_keepalive);
#define TRK_RIFT_CONFIG_USE_CALIBRATION 0x04
#define TRK_RIFT_CONFIG_AUTO_CALIBRATE 0x08

/* ---- Sony PSVR sensor interface 4 (64 B, no report ID), §2c ---------------------------------
 * Two samples per report, each with its own 24-bit µs tick (sample 0 first). Device words w0..w2
 * map to x = w1, y = w0, z = −w2; accel 1/16384 g, gyro 0.00105 rad/s (uncertain per §2c). The
 * factory ±1 g calibration and the 500 µs dt clamp of the open drivers are left to the caller. */
#define TRK_PSVR_REPORT_SIZE 64
#define TRK_PSVR_ACCEL_LSB_MPS2 (9.80665 / 16384.0)
#define TRK_PSVR_GYRO_LSB_RADPS 0.00105
struct trk_psvr_parser {
    struct trk_tick_clock clock;
    struct trk_report_counters n;
};
void trk_psvr_parser_init(struct trk_psvr_parser *p);
int trk_psvr_parse(struct trk_psvr_parser *p, const uint8_t *report, size_t length,
                   struct trk_imu_sample *out, int max_out, struct hl_error *err);
/* Control output reports for interface 5: header command, 0x00, 0xAA, payload length. */
size_t trk_psvr_build_power(uint8_t out[8], int on);           /* 0x17, payload 4, byte 0 = on */
size_t trk_psvr_build_vr_mode(uint8_t out[8], int vr);         /* 0x23, payload 4 (assumed), 1 = VR */
size_t trk_psvr_build_tracking_on(uint8_t out[12]);            /* 0x11, payload 00 FF FF FF 00 00 00 00 */

/* ---- HTC Vive / Vive Pro / Index IMU report 0x20 (52 B), §2d --------------------------------
 * A ring of 3 samples with u32 48 MHz time and u8 seq; repeats are skipped by seq (equal to last,
 * last−1, last−2 mod 256), new ones emitted in seq order. value = range/32768 · scale · raw − bias
 * in device axes, then mapped to the body frame by model (Vive: y, z negated; Pro: x, z negated;
 * Index: x' = −y, y' = −x, z' = −z). The JSON IMU→head pose is not applied here. */
#define TRK_VIVE_REPORT_ID 0x20
#define TRK_VIVE_REPORT_SIZE 52
enum trk_vive_model { TRK_VIVE_MODEL_VIVE = 0, TRK_VIVE_MODEL_PRO, TRK_VIVE_MODEL_INDEX };
struct trk_vive_calibration {
    enum trk_vive_model model;
    double gyro_range_radps, accel_range_mps2; /* full scale; defaults 8.726646 and 39.2266 */
    hl_vec3d gyro_scale, accel_scale;          /* JSON gyro_scale/acc_scale, device axes; default 1 */
    hl_vec3d gyro_bias_radps, accel_bias_mps2; /* JSON gyro_bias/acc_bias, device axes; default 0 */
};
void trk_vive_calibration_default(struct trk_vive_calibration *cal, enum trk_vive_model model);
/* Ranges from feature 0x01 mode numbers (MPU-6500): gyro 250·2^n °/s, accel 2·2^n g, n ≤ 4. */
int trk_vive_set_range_modes(struct trk_vive_calibration *cal, unsigned gyro_mode, unsigned accel_mode,
                             struct hl_error *err);
struct trk_vive_parser {
    struct trk_vive_calibration cal; /* set freely between reports */
    struct trk_tick_clock clock;
    int has_seq;
    uint8_t last_seq;
    struct trk_report_counters n;
};
void trk_vive_parser_init(struct trk_vive_parser *p, enum trk_vive_model model);
int trk_vive_parse(struct trk_vive_parser *p, const uint8_t *report, size_t length,
                   struct trk_imu_sample *out, int max_out, struct hl_error *err);

/* ---- OSVR HDK (16 or 32 B, no report ID), §2e -----------------------------------------------
 * One on-chip fused orientation (Q1.14 x y z w) per report, angular velocity (Q6.9 rad/s) when the
 * report version ≥ 2; no raw accel, no device clock: the caller passes the host arrival time.
 * Device→body axes (unverified, §2e says verify on hardware): (x, y, z)_body = (x, z, −y)_device,
 * a −90° turn about X taking the chip's Z-up frame to Y-up, applied to the quaternion's vector part
 * and to ω — defined once in report_hdk.c. Quaternions with norm outside [0.5, 1.5] are rejected. */
#define TRK_HDK_QUAT_LSB (1.0 / 16384.0)
#define TRK_HDK_GYRO_LSB_RADPS (1.0 / 512.0)
struct trk_hdk_parser {
    int has_seq;
    uint8_t last_seq;
    int64_t last_time_ns;
    int has_last;
    unsigned last_version, last_status; /* low / high nibble of byte 0 of the last accepted report */
    struct trk_report_counters n;
};
void trk_hdk_parser_init(struct trk_hdk_parser *p);
int trk_hdk_parse(struct trk_hdk_parser *p, const uint8_t *report, size_t length, int64_t host_time_ns,
                  struct trk_imu_sample *out, int max_out, struct hl_error *err);

/* ---- supported trackers (for discovery) -------------------------------------------------------- */
enum trk_device_kind {
    TRK_DEVICE_RIFT_DK1, TRK_DEVICE_RIFT_DK2, TRK_DEVICE_RIFT_CV1, TRK_DEVICE_PSVR,
    TRK_DEVICE_VIVE, TRK_DEVICE_VIVE_PRO_INDEX, TRK_DEVICE_HDK
};
enum trk_device_role { TRK_ROLE_IMU, TRK_ROLE_CONTROL }; /* IMU stream, or power/mode interface */
struct trk_device_info {
    const char *name;
    enum trk_device_kind kind;
    enum trk_device_role role;
    uint16_t vid, pid;
    int interface_number;        /* −1: any */
    const char *manufacturer;    /* required USB manufacturer string, or NULL */
    size_t report_size;          /* IMU input report bytes (largest accepted); 0 for control */
    double sample_rate_hz, report_rate_hz; /* native */
};
extern const struct trk_device_info trk_device_table[];
extern const size_t trk_device_table_count;
/* First entry matching vid:pid and interface (an entry with −1 matches any); NULL if none. */
const struct trk_device_info *trk_device_find(uint16_t vid, uint16_t pid, int interface_number);

/* ---- encoders: physical samples → report bytes, quantized like the device ----------------------
 * Inputs are body-frame samples with device_time_ns; values round to the nearest LSB and clamp to
 * the device range; the counter is time/tick mod 2^bits. Each returns the report length or −1. */
/* Rift: samples[0..count) chronological, count ≤ 3 (DK1) or 2 (DK2); n_field is written as N
 * (≥ count; more simulates lost samples). The timestamp is the newest sample's, and so is the
 * magnetometer (zeros when the newest sample has none; ±3.2767 gauss range). */
int trk_rift_encode(int dk2, const struct trk_imu_sample *samples, int count, int n_field,
                    uint8_t *out, size_t out_size, struct hl_error *err);
int trk_psvr_encode(const struct trk_imu_sample samples[2], uint8_t sequence, uint8_t *out, size_t out_size,
                    struct hl_error *err);
/* Vive: the three ring slots as they stand, with their sequence numbers. */
int trk_vive_encode(const struct trk_vive_calibration *cal, const struct trk_imu_sample slots[3],
                    const uint8_t seq[3], uint8_t *out, size_t out_size, struct hl_error *err);
/* HDK: orientation (+ gyro when version ≥ 2); out_size 16 or 32 picks the report size. */
int trk_hdk_encode(const struct trk_imu_sample *sample, unsigned version, unsigned status, uint8_t sequence,
                   uint8_t *out, size_t out_size, struct hl_error *err);

/* A device simulator over the encoders: push samples at the native rate, get reports as the
 * device would send them. */
struct trk_encoder_options {
    int samples_per_report;        /* 0: native (PSVR 2, others 1); Rift > slots ⇒ lost samples */
    int64_t counter_offset_ticks;  /* added to every device counter value, e.g. to start near a wrap */
    uint32_t drop_report_every;    /* every k-th report is withheld (lost on the bus); 0: none */
    unsigned hdk_version;          /* 0: 3 */
    struct trk_vive_calibration vive; /* used when vive.gyro_range_radps > 0, else the model default */
};
struct trk_encoder {
    enum trk_device_kind kind;
    struct trk_encoder_options opt;
    struct trk_imu_sample pending[TRK_REPORT_MAX_SAMPLES]; /* newest last */
    int pending_count, gathered;
    struct trk_imu_sample ring[3];
    uint8_t ring_seq[3];
    int ring_filled, ring_next; /* slot the next sample overwrites */
    uint8_t seq;
    uint64_t reports_built, reports_dropped;
};
void trk_encoder_init(struct trk_encoder *enc, enum trk_device_kind kind, const struct trk_encoder_options *opt);
/* Feeds one sample. Returns the length of the report written to out when one is due, 0 when none
 * is (or it was dropped), −1 with err on bad input. out_size ≥ 64. */
int trk_encoder_push(struct trk_encoder *enc, const struct trk_imu_sample *sample, uint8_t *out, size_t out_size,
                     struct hl_error *err);

/* ==== end of report parsers ==== */

/* ==== fusion and prediction ==== */

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

/* ==== end of fusion and prediction ==== */

/* ==== device streams and raw recordings ==== */

/* A device stream: one tracker's report parser feeding one fusion, the path every report takes
 * whether it comes live from a device or from a raw recording (so replayed raw data is fused
 * exactly as it was live). Plain data, no allocation, no I/O, no clock. */
struct trk_stream {
    enum trk_device_kind kind;
    union {
        struct trk_rift_parser rift; /* DK1, DK2, CV1 */
        struct trk_psvr_parser psvr;
        struct trk_vive_parser vive; /* Vive; Vive Pro / Index (model Pro until the caller sets cal) */
        struct trk_hdk_parser hdk;
    } parser;
    struct trk_fusion fusion;
    uint64_t reports;          /* reports fed (accepted + rejected) */
    uint64_t rejected;         /* reports the parser refused (−1; nothing changed) */
    uint64_t samples;          /* samples the parser produced */
    uint64_t fused;            /* samples the fusion accepted (HDK: orientations taken) */
    uint64_t fusion_refused;   /* samples the fusion refused (non-finite) */
    int64_t newest_time_ns;    /* device time of the newest fused sample (HDK: host time) */
    int has_sample;
    hl_quatd hdk_last_q;       /* HDK: previous on-device orientation (ω from differences, v1) */
};

/* Resets s for a tracker of `kind`. cfg NULL: fusion defaults. */
void trk_stream_init(struct trk_stream *s, enum trk_device_kind kind, const struct trk_fusion_config *cfg_or_null);

/* Parses one report (dispatch on kind) and feeds each new sample to the fusion at its device time
 * (seconds of the unwrapped device clock; HDK has no clock, host_time_ns stands in), then its
 * magnetometer reading, if any, to trk_fusion_update_mag (when cfg.use_magnetometer). HDK gives an
 * on-device fused orientation: it is taken as is (no integration) with its angular velocity, or ω
 * from consecutive orientations for version-1 reports. Returns the number of samples fused, or −1
 * for a rejected report (counted in `rejected`; nothing else changes) with err. */
int trk_stream_feed(struct trk_stream *s, const uint8_t *report, size_t length, int64_t host_time_ns,
                    struct hl_error *err);

/* The latest fused orientation predicted horizon_s ahead (trk_fusion_predict), its angular velocity
 * in the world frame, time_s = device time of the newest sample + horizon_s; no position, gaze locked
 * to the head. Before any sample: identity at time horizon_s. */
void trk_stream_pose(const struct trk_stream *s, double horizon_s, struct trk_pose *out);

/* Raw recordings (docs/raw-recording.md): a versioned, append-only file of the reports exactly as
 * received, each with its host receive time and a CRC-32, so a session can be replayed through the
 * same parser and fusion, or through a better one later. Little-endian throughout.
 *   header (104 B): "HMDLRAW1", u16 version, u16 header size, u16 kind, u16 vid, u16 pid, u16 0,
 *                   i64 host start ns (CLOCK_MONOTONIC), i64 wall start ns (Unix), char name[64],
 *                   u32 CRC-32 of the 100 bytes before it
 *   record (16 + n B): u32 n, i64 host receive ns, n report bytes, u32 CRC-32 of the 12 + n before it */
#define TRK_RECORDING_MAGIC "HMDLRAW1"
#define TRK_RECORDING_VERSION 1
#define TRK_RECORDING_HEADER_SIZE 104
#define TRK_RECORDING_NAME_SIZE 64       /* bytes in the file, NUL-padded; longer names are cut */
#define TRK_RECORDING_RECORD_OVERHEAD 16 /* length + time + CRC */
#define TRK_RECORDING_MAX_REPORT 1024    /* largest report a record may hold (HID: ≤ 64 B in practice) */

/* CRC-32 (IEEE 802.3, reflected 0xEDB88320, as zlib's crc32): start with crc = 0. */
uint32_t trk_crc32(uint32_t crc, const void *data, size_t length);

/* Writer. create truncates or creates path and writes the header (host start = now). NULL with err
 * on failure (no file left behind). append writes one record with one write() from a buffer in the
 * writer (no allocation per record): after a kill at most the last record is torn. Data reach the
 * kernel at each append (no user-space buffer), so they survive the process dying; surviving power
 * loss needs close with sync_to_disk (fsync). length 1..TRK_RECORDING_MAX_REPORT. After a failed
 * write the writer refuses further appends. close returns 0, or −1 if anything failed (the file is
 * closed and freed either way). */
struct trk_recording;
struct trk_recording *trk_recording_create(const char *path, enum trk_device_kind kind, uint16_t vid, uint16_t pid,
                                           const char *name, struct hl_error *err);
int trk_recording_append(struct trk_recording *rec, int64_t host_time_ns, const uint8_t *report, size_t length,
                         struct hl_error *err);
uint64_t trk_recording_records(const struct trk_recording *rec); /* appended so far */
int trk_recording_close(struct trk_recording *rec, int sync_to_disk, struct hl_error *err);

/* Reader. open checks the header (magic, version, header CRC, kind); NULL with "path: byte N:
 * reason". next returns 1 with one record (report copied into buf, cap ≥ its length), 0 at the end,
 * −1 with "path: byte N: reason" for a corrupt record in the middle. A torn tail — an incomplete last
 * record, or a last record (or zero-filled rest of the file) failing its length or CRC check — ends
 * the file normally: next returns 0 and sets torn_tail and torn_bytes. Lengths are checked against
 * TRK_RECORDING_MAX_REPORT and the file before anything is read; the reader allocates only itself. */
struct trk_recording_info {
    unsigned version;
    enum trk_device_kind kind;
    uint16_t vid, pid;
    char name[TRK_RECORDING_NAME_SIZE + 1];
    int64_t host_start_ns, wall_start_unix_ns;
};
struct trk_recording_reader {
    struct trk_recording_info info;
    uint64_t file_size, offset;  /* offset: next record */
    uint64_t records;            /* complete records returned */
    int torn_tail;               /* 1 when the end was a torn record */
    uint64_t torn_bytes;         /* bytes ignored at the end */
    FILE *file;
    char *path;
    uint8_t buf[TRK_RECORDING_RECORD_OVERHEAD + TRK_RECORDING_MAX_REPORT];
};
struct trk_recording_reader *trk_recording_open(const char *path, struct hl_error *err);
int trk_recording_next(struct trk_recording_reader *r, int64_t *host_time_ns, uint8_t *buf, size_t cap,
                       size_t *length, struct hl_error *err);
void trk_recording_reader_close(struct trk_recording_reader *r);

/* ==== end of device streams and raw recordings ==== */

/* ==== HID devices, discovery, hot-plug, live source ==== */

/* Tracker I/O on Linux through hidapi's hidraw backend (DEVICES.md §3: hidraw keeps the kernel
 * driver, gives interface numbers and reports POLLHUP on unplug; hidapi-libusb would detach the
 * driver and need the usb node). Everything here is thread-compatible: one thread per object.
 * docs/trackers.md says which devices are supported, how permissions work and what is verified. */

#define TRK_HID_PATH_SIZE 256
#define TRK_HID_STRING_SIZE 64
#define TRK_HID_WHY_SIZE 512

/* One supported tracker interface present on the machine: a trk_device_table match by VID:PID and
 * interface (and USB manufacturer where the table requires it). Control interfaces (PSVR iface 5,
 * Vive mainboards; info->role == TRK_ROLE_CONTROL) are listed too: check the role before reading.
 * Strings are UTF-8. can_open: the node opened read-write and answered the report-descriptor ioctl
 * just now; when 0, `why` names the node, the errno text and the fix. */
struct trk_hid_device_desc {
    char path[TRK_HID_PATH_SIZE];        /* hidraw node, e.g. /dev/hidraw3 */
    const struct trk_device_info *info;  /* the table entry it matched */
    uint16_t vid, pid;
    int interface_number;                /* USB interface; −1 when not USB */
    char manufacturer[TRK_HID_STRING_SIZE], product[TRK_HID_STRING_SIZE], serial[TRK_HID_STRING_SIZE];
    int can_open;
    char why[TRK_HID_WHY_SIZE];
};

/* Lists supported trackers present, in hidapi's order (IMU and control interfaces alike), trying to
 * open each. Writes at most max entries and returns how many it wrote (0: none present), or −1 with
 * err when hidapi cannot enumerate at all. */
int trk_hid_enumerate(struct trk_hid_device_desc *out, int max, struct hl_error *err);

/* "Rift DK1 2833:0001, Rift DK2 2833:0021, …": every IMU entry of trk_device_table, for messages
 * such as "no supported head tracker found (looked for: …)". Returns buf. */
const char *trk_hid_supported_list(char *buf, size_t size);

/* An open tracker interface. open: path_or_auto NULL, "" or "auto" takes the first openable IMU
 * interface from trk_hid_enumerate; a path must be the hidraw node of a supported device. Failures
 * say which node, the errno text and the fix (udev rules, another process holding it). Opening does
 * not start streaming: call trk_hid_send_start. Allocates once, at open. */
struct trk_hid_device;
int trk_hid_open(const char *path_or_auto, struct trk_hid_device **out, struct hl_error *err);
/* Reads one input report (cap should be info->report_size: under umockdev the node is a byte stream
 * and a larger buffer would merge queued reports). Returns its length, 0 on timeout (timeout_ms < 0
 * waits forever), −1 on error or disconnect with the reason in err. *host_time_ns (may be NULL): the
 * monotonic clock right after the read returned. No allocation. */
int trk_hid_read(struct trk_hid_device *d, uint8_t *buf, size_t cap, int timeout_ms, int64_t *host_time_ns,
                 struct hl_error *err);
/* Sends what the kind needs before it streams (DEVICES.md §2): Rift — config 0x02 with factory and
 * auto gyro calibration on and sensor coordinates off, then keep-alive (DK1 0x08, DK2/CV1 mux 0x11,
 * 10 s), CV1 enable-components 0x1D (display, audio); PSVR — power, VR mode and tracking on through
 * the control interface 5 of the same unit; Vive — nothing yet (power-on 0x04 has no builder: the
 * headset must already be powered); HDK — nothing. Restarts the keep-alive schedule. */
int trk_hid_send_start(struct trk_hid_device *d, struct hl_error *err);
/* Resends the keep-alive when due at now_ns (DK1 0x08 every 0.8 s as OpenHMD does; DK2/CV1 mux 0x11
 * every 9.5 s as Monado does; others never). Returns 1 sent, 0 not due, −1 with err. */
int trk_hid_keepalive(struct trk_hid_device *d, int64_t now_ns, struct hl_error *err);
/* Reads and discards reports already queued (and, for PSVR and Vive, those arriving in the next
 * 50 ms: both replay stale samples at start, §2c/§2d). Returns the number dropped, −1 with err. */
int trk_hid_drain(struct trk_hid_device *d, struct hl_error *err);
const struct trk_device_info *trk_hid_info(const struct trk_hid_device *d);
const struct trk_hid_device_desc *trk_hid_desc(const struct trk_hid_device *d); /* path, strings */
void trk_hid_close(struct trk_hid_device *d); /* NULL is fine */

/* Hot-plug: a libudev monitor on the "udev" netlink group (events after udev's rules ran, so the
 * uaccess ACL is in place), subsystem hidraw, add and remove only. An add is identified from its
 * parents' HID_ID and bInterfaceNumber: info is the table entry, or NULL for an unsupported device
 * or one whose parents cannot be read yet (rescan with trk_hid_enumerate shortly). A remove carries
 * only the node name (the device is gone). */
enum trk_hotplug_action { TRK_HOTPLUG_ADD = 1, TRK_HOTPLUG_REMOVE = 2 };
struct trk_hotplug_event {
    enum trk_hotplug_action action;
    char devnode[TRK_HID_PATH_SIZE];
    const struct trk_device_info *info; /* add: the table entry or NULL (see above); remove: NULL */
    uint16_t vid, pid;                  /* add only */
    int interface_number;               /* add only; −1 when not USB */
};
struct udev;
struct udev_monitor;
struct trk_hotplug {
    struct udev *udev;
    struct udev_monitor *monitor;
};
int trk_hotplug_init(struct trk_hotplug *h, struct hl_error *err);
int trk_hotplug_fd(const struct trk_hotplug *h); /* pollable (POLLIN); −1 before init */
/* Waits up to timeout_ms (0: just checks) for the monitor to be readable: 1, 0 on timeout, −1 on error. */
int trk_hotplug_poll(struct trk_hotplug *h, int timeout_ms);
/* Takes the next pending event without blocking: 1 with *ev filled, 0 when none is pending.
 * Events that do not concern trackers are consumed and skipped. */
int trk_hotplug_next_event(struct trk_hotplug *h, struct trk_hotplug_event *ev);
void trk_hotplug_destroy(struct trk_hotplug *h);

/* The live pose source of a head tracker. start opens the device (path or auto, as trk_hid_open),
 * sends the start reports and runs a reader thread that reads reports, feeds a trk_stream and sends
 * keep-alives on the device's own schedule, independent of rendering. pose_at(t, host monotonic
 * seconds as hl_clock_now_s) predicts the newest pose to t, the horizon capped at max_prediction_s
 * (≤ 0: 0.040 s, where the fusion's constant-rate prediction stays good); time_s is set to t.
 * Health: OK while reports flow; LOST with the reason on unplug, read error or a 1 s silence —
 * then pose_at returns the last pose with zero angular velocity (no prediction). The thread watches
 * hot-plug and reopens a matching device when one is added (any node name; same serial when known),
 * re-sends the start reports, re-initialises the stream (timestamp unwrapping, fusion start-up;
 * heading restarts at 0, and a magnetometer's reference, being relative, is captured anew), drains
 * stale reports and returns to OK on the first new report. Before the first report pose_at gives
 * a still pose (health says why). stop joins the thread and closes the device; destroy stops first. */
int trk_tracker_source_create(const char *path_or_auto, double max_prediction_s, struct trk_pose_source **out,
                              struct hl_error *err);

/* Counters of a tracker source (for status lines and tests); −1 if src is not a tracker source. */
struct trk_tracker_stats {
    uint64_t reports;          /* reports read and fed */
    uint64_t rejected;         /* of those, refused by the parser */
    uint64_t samples_fused;
    uint64_t disconnects;      /* losses of the device (read error, remove event) */
    uint64_t reconnects;       /* successful reopens after a loss (start reports sent, drained) */
    uint64_t keepalives;       /* keep-alive reports sent */
    uint64_t drained;          /* stale reports dropped after (re)opening */
    int connected;             /* the device is open now */
    char path[TRK_HID_PATH_SIZE]; /* node in use, or last used */
};
int trk_tracker_source_stats(struct trk_pose_source *src, struct trk_tracker_stats *out);

/* ==== end of HID devices, discovery, hot-plug, live source ==== */

/* ==== accuracy evaluation ==== */

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

/* Short name of a device kind ("Rift DK1", …, "OSVR HDK"). */
const char *trk_evaluate_device_name(enum trk_device_kind kind);

/* Evaluates one device on rows[0..n) (a 1 kHz shared stream or a slice of one; n ≥ 100). opt NULL:
 * defaults. Allocates its buffers once per call (none per sample). 0, or −1 with err. */
int trk_evaluate_device(enum trk_device_kind kind, const struct trk_imu_csv_row *rows, size_t n,
                        const struct trk_evaluate_options *opt, struct trk_evaluate_result *res,
                        struct hl_error *err);

/* ==== end of accuracy evaluation ==== */

#endif
