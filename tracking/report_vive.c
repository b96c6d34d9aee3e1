/* HTC Vive / Vive Pro / Index IMU report 0x20: a ring of the 3 latest samples, DEVICES.md §2d. */
#include "tracking/report_internal.h"

#include <string.h>

#define SLOT_SIZE 17 /* accel i16×3, gyro i16×3, time u32 @ 48 MHz, seq u8 */
#define GYRO_DEFAULT_RADPS 8.726646 /* 500 °/s, when feature 0x01 is unreadable */
#define ACCEL_DEFAULT_MPS2 39.2266  /* 4 g */

void trk_vive_calibration_default(struct trk_vive_calibration *cal, enum trk_vive_model model)
{
    cal->model = model;
    cal->gyro_range_radps = GYRO_DEFAULT_RADPS;
    cal->accel_range_mps2 = ACCEL_DEFAULT_MPS2;
    cal->gyro_scale = hl_v3(1, 1, 1);
    cal->accel_scale = hl_v3(1, 1, 1);
    cal->gyro_bias_radps = hl_v3(0, 0, 0);
    cal->accel_bias_mps2 = hl_v3(0, 0, 0);
}

int trk_vive_set_range_modes(struct trk_vive_calibration *cal, unsigned gyro_mode, unsigned accel_mode,
                             struct hl_error *err)
{
    if (gyro_mode > 4 || accel_mode > 4)
        return hl_fail(err, "vive range modes: gyro %u, accel %u; each must be ≤ 4", gyro_mode, accel_mode);
    /* MPU-6500 full-scale encoding: gyro 250·2^n °/s, accel 2·2^n g. */
    cal->gyro_range_radps = 250.0 * (double)(1u << gyro_mode) * HL_RAD_PER_DEG;
    cal->accel_range_mps2 = 2.0 * (double)(1u << accel_mode) * 9.80665;
    return 0;
}

void trk_vive_parser_init(struct trk_vive_parser *p, enum trk_vive_model model)
{
    memset(p, 0, sizeof *p);
    trk_vive_calibration_default(&p->cal, model);
    trk_tick_clock_init(&p->clock, 32, 125, 6); /* 1/48 MHz = 125/6 ns: wraps 89.48 s */
}

/* The one place that maps device axes to the body frame (+X right, +Y up, +Z back), per model. */
static hl_vec3d device_to_body(enum trk_vive_model model, hl_vec3d v)
{
    switch (model) {
    case TRK_VIVE_MODEL_PRO: return hl_v3(-v.x, v.y, -v.z);
    case TRK_VIVE_MODEL_INDEX: return hl_v3(-v.y, -v.x, -v.z);
    case TRK_VIVE_MODEL_VIVE:
    default: return hl_v3(v.x, -v.y, -v.z);
    }
}

/* Inverse of device_to_body (each mapping is its own inverse except for the sign pattern). */
static hl_vec3d body_to_device(enum trk_vive_model model, hl_vec3d v)
{
    switch (model) {
    case TRK_VIVE_MODEL_PRO: return hl_v3(-v.x, v.y, -v.z);
    case TRK_VIVE_MODEL_INDEX: return hl_v3(-v.y, -v.x, -v.z);
    case TRK_VIVE_MODEL_VIVE:
    default: return hl_v3(v.x, -v.y, -v.z);
    }
}

static hl_vec3d scale_words(const uint8_t *w, double range, hl_vec3d scale, hl_vec3d bias)
{
    double lsb = range / 32768.0;
    return hl_v3(lsb * scale.x * trk_rd_i16(w) - bias.x, lsb * scale.y * trk_rd_i16(w + 2) - bias.y,
                 lsb * scale.z * trk_rd_i16(w + 4) - bias.z);
}

int trk_vive_parse(struct trk_vive_parser *p, const uint8_t *report, size_t length,
                   struct trk_imu_sample *out, int max_out, struct hl_error *err)
{
    if (!report || length == 0) {
        trk_reject(&p->n);
        return hl_fail(err, "vive imu report: empty");
    }
    if (report[0] != TRK_VIVE_REPORT_ID) {
        trk_reject(&p->n);
        return hl_fail(err, "vive imu report: report id 0x%02X, expected 0x%02X", report[0], TRK_VIVE_REPORT_ID);
    }
    if (length != TRK_VIVE_REPORT_SIZE) {
        trk_reject(&p->n);
        return hl_fail(err, "vive imu report: length %zu, expected %d bytes", length, TRK_VIVE_REPORT_SIZE);
    }
    if (!out || max_out < 3) {
        trk_reject(&p->n);
        return hl_fail(err, "vive imu report: room for %d samples, need 3", max_out);
    }
    ++p->n.reports;

    const uint8_t *slot[3];
    uint8_t seq[3];
    for (int i = 0; i < 3; ++i) {
        slot[i] = report + 1 + SLOT_SIZE * i;
        seq[i] = slot[i][16];
    }

    /* Classify each slot by its seq distance d from the last delivered seq: 1..127 new; 0, 255,
     * 254 (= last, last−1, last−2) a repeat of the ring; anything else is far from where we are. */
    enum { NEW, REPEAT, FAR } kind[3];
    uint8_t d[3];
    int resync = !p->has_seq;
    if (!resync) {
        int far = 0;
        for (int i = 0; i < 3; ++i) {
            d[i] = (uint8_t)(seq[i] - p->last_seq);
            kind[i] = (d[i] >= 1 && d[i] <= 127) ? NEW : (d[i] == 0 || d[i] >= 254) ? REPEAT : FAR;
            far += kind[i] == FAR;
        }
        /* A whole ring far from the last seq (first contact, ≥ 128 reports missed, or a replay):
         * re-anchor on this ring and let the timestamps decide what is new. */
        resync = far == 3;
    }
    uint8_t anchor = p->last_seq;
    if (resync) {
        /* The newest slot is the one no other slot is ahead of (mod 256); anchor 3 before it. */
        int newest = 0;
        for (int i = 0; i < 3; ++i) {
            int ahead = 0;
            for (int j = 0; j < 3; ++j)
                ahead |= (uint8_t)(seq[j] - seq[i]) >= 1 && (uint8_t)(seq[j] - seq[i]) <= 127;
            if (!ahead) {
                newest = i;
                break;
            }
        }
        anchor = (uint8_t)(seq[newest] - 3);
        for (int i = 0; i < 3; ++i) {
            d[i] = (uint8_t)(seq[i] - anchor);
            kind[i] = (d[i] >= 1 && d[i] <= 3) ? NEW : FAR;
        }
    }

    /* Order the new slots by seq (three elements: insertion sort); repeats and duplicates within
     * the ring are dropped and counted. */
    int order[3], count = 0;
    for (int i = 0; i < 3; ++i) {
        if (kind[i] != NEW) {
            if (kind[i] == REPEAT)
                ++p->n.duplicates;
            else
                ++p->n.backward;
            continue;
        }
        int pos = count;
        while (pos > 0 && d[order[pos - 1]] > d[i])
            --pos;
        if (pos > 0 && d[order[pos - 1]] == d[i]) { /* the same seq twice in one ring */
            ++p->n.duplicates;
            continue;
        }
        for (int m = count; m > pos; --m)
            order[m] = order[m - 1];
        order[pos] = i;
        ++count;
    }
    if (count == 0)
        return 0;
    /* Seqs skipped between the last delivered one and the newest here were lost on the way. */
    uint8_t d_max = d[order[count - 1]];
    if (!resync)
        p->n.lost += (uint64_t)(d_max - count);

    int emitted = 0;
    for (int k = 0; k < count; ++k) {
        const uint8_t *s = slot[order[k]];
        struct trk_imu_sample *o = trk_sample_begin_at_tick(&p->clock, &p->n, trk_rd_u32(s + 12), &out[emitted]);
        if (!o && p->clock.overflowed) {
            --p->n.reports; /* counted as accepted above: it is refused after all */
            trk_reject(&p->n);
            return hl_fail(err, "vive report: device counter passes %lld ticks, beyond int64 nanoseconds",
                           (long long)trk_tick_clock_max_ticks(&p->clock));
        }
        if (!o)
            continue;
        ++emitted;
        const struct trk_vive_calibration *c = &p->cal;
        o->accel_mps2 = device_to_body(c->model, scale_words(s, c->accel_range_mps2, c->accel_scale, c->accel_bias_mps2));
        o->gyro_radps = device_to_body(c->model, scale_words(s + 6, c->gyro_range_radps, c->gyro_scale, c->gyro_bias_radps));
        o->has_accel = 1;
        o->has_gyro = 1;
    }
    /* After a resync only a ring that delivered something moves the anchor, so a replayed stale
     * ring cannot drag it back. */
    if (!resync || emitted > 0) {
        p->last_seq = (uint8_t)(anchor + d_max);
        p->has_seq = 1;
    }
    p->n.samples += (uint64_t)emitted;
    return emitted;
}

/* ---- encoder ----------------------------------------------------------------------------------- */

static int16_t quantize_axis(double value, double lsb, double scale, double bias)
{
    /* Inverse of value = lsb · scale · raw − bias. */
    double denom = lsb * scale;
    if (!(denom != 0.0))
        return 0;
    return (int16_t)trk_quantize(value + bias, denom, -32768, 32767);
}

static void put_vec(uint8_t *w, hl_vec3d dev, double range, hl_vec3d scale, hl_vec3d bias)
{
    double lsb = range / 32768.0;
    trk_wr_u16(w, (uint16_t)quantize_axis(dev.x, lsb, scale.x, bias.x));
    trk_wr_u16(w + 2, (uint16_t)quantize_axis(dev.y, lsb, scale.y, bias.y));
    trk_wr_u16(w + 4, (uint16_t)quantize_axis(dev.z, lsb, scale.z, bias.z));
}

int trk_vive_encode(const struct trk_vive_calibration *cal, const struct trk_imu_sample slots[3],
                    const uint8_t seq[3], uint8_t *out, size_t out_size, struct hl_error *err)
{
    if (!cal || !slots || !seq || !out || out_size < TRK_VIVE_REPORT_SIZE)
        return hl_fail(err, "vive encode: output of %zu bytes, need %d", out_size, TRK_VIVE_REPORT_SIZE);
    memset(out, 0, TRK_VIVE_REPORT_SIZE);
    out[0] = TRK_VIVE_REPORT_ID;
    for (int i = 0; i < 3; ++i) {
        uint8_t *s = out + 1 + SLOT_SIZE * i;
        put_vec(s, body_to_device(cal->model, slots[i].accel_mps2), cal->accel_range_mps2, cal->accel_scale,
                cal->accel_bias_mps2);
        put_vec(s + 6, body_to_device(cal->model, slots[i].gyro_radps), cal->gyro_range_radps, cal->gyro_scale,
                cal->gyro_bias_radps);
        trk_wr_u32(s + 12, trk_ns_to_counter(slots[i].device_time_ns, 32, 125, 6, 0));
        s[16] = seq[i];
    }
    return TRK_VIVE_REPORT_SIZE;
}
