/* tracking/reports.h: report parsers (pure functions of the bytes), the supported trackers
 * (VID:PID table for discovery) and the encoders with their device simulator. Part of the
 * tracking/tracking.h umbrella; self-contained. */
#ifndef HMDLOD_TRACKING_REPORTS_H
#define HMDLOD_TRACKING_REPORTS_H

#include "base/base.h"

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
    int overflowed; /* sticky: a step was refused because its time would not fit int64 ns */
};
void trk_tick_clock_init(struct trk_tick_clock *clock, uint32_t bits, uint32_t period_num_ns, uint32_t period_den);
/* Returns 1 (forward; clock advanced, *ticks_out set), 0 (same raw value as last; *ticks_out set),
 * −1 (backward; clock untouched) or −2 (the step would take the count past trk_tick_clock_max_ticks,
 * whose time no longer fits int64 ns: clock untouched, `overflowed` set; the parsers refuse the
 * report with an error rather than wrap). raw is masked to the counter width. */
int trk_tick_clock_unwrap(struct trk_tick_clock *clock, uint32_t raw, int64_t *ticks_out);
int64_t trk_tick_clock_max_ticks(const struct trk_tick_clock *clock); /* largest count whose ns fits */
/* Rounded to the ns. Exact for |ticks| ≤ trk_tick_clock_max_ticks (all the unwrapper yields);
 * beyond, saturates at INT64_MIN / INT64_MAX instead of wrapping. */
int64_t trk_tick_clock_ns(const struct trk_tick_clock *clock, int64_t ticks);

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

#endif
