/* Sony PSVR sensor-interface parser (64-byte unnumbered report) and control-report builders.
 * Layout, axes, scales and clock: DEVICES.md §2c. */
#include "tracking/report_internal.h"

#include <string.h>

static const size_t sample_offset[2] = {16, 32}; /* tick u32, gyro w0..w2, accel w0..w2 */

void trk_psvr_parser_init(struct trk_psvr_parser *p)
{
    memset(p, 0, sizeof *p);
    trk_tick_clock_init(&p->clock, 24, 1000, 1); /* 24-bit µs tick in a u32: wraps 16.78 s */
}

/* Device words → body frame: x = w1, y = w0, z = −w2 (both open drivers, §2c). */
static hl_vec3d psvr_axes(const uint8_t *w, double lsb)
{
    return hl_v3(trk_rd_i16(w + 2) * lsb, trk_rd_i16(w) * lsb, -trk_rd_i16(w + 4) * lsb);
}

int trk_psvr_parse(struct trk_psvr_parser *p, const uint8_t *report, size_t length,
                   struct trk_imu_sample *out, int max_out, struct hl_error *err)
{
    /* No report ID on this interface: the length is the only framing check. */
    if (!report || length != TRK_PSVR_REPORT_SIZE) {
        trk_reject(&p->n);
        return hl_fail(err, "psvr report: length %zu, expected %d bytes", report ? length : 0, TRK_PSVR_REPORT_SIZE);
    }
    if (!out || max_out < 2) {
        trk_reject(&p->n);
        return hl_fail(err, "psvr report: room for %d samples, need 2", max_out);
    }
    ++p->n.reports;
    int emitted = 0;
    for (int k = 0; k < 2; ++k) {
        const uint8_t *s = report + sample_offset[k];
        /* Each sample carries its own tick (≈500 µs apart). Stale ticks — the unit replays a
         * previous session's queue at start — come out as backward and are dropped. The open
         * drivers' clamp of odd deltas to 500 µs is a fusion policy, not applied here. */
        struct trk_imu_sample *o = trk_sample_begin_at_tick(&p->clock, &p->n, trk_rd_u32(s) & 0xFFFFFFu, &out[emitted]);
        if (!o && p->clock.overflowed) {
            --p->n.reports; /* counted as accepted above: it is refused after all */
            trk_reject(&p->n);
            return hl_fail(err, "psvr report: device counter passes %lld ticks, beyond int64 nanoseconds",
                           (long long)trk_tick_clock_max_ticks(&p->clock));
        }
        if (!o)
            continue;
        ++emitted;
        o->gyro_radps = psvr_axes(s + 4, TRK_PSVR_GYRO_LSB_RADPS);
        o->accel_mps2 = psvr_axes(s + 10, TRK_PSVR_ACCEL_LSB_MPS2);
        o->has_gyro = 1;
        o->has_accel = 1;
    }
    p->n.samples += (uint64_t)emitted;
    return emitted;
}

/* ---- control output reports (interface 5) ------------------------------------------------------ */

static size_t control_header(uint8_t *out, uint8_t command, uint8_t payload_length)
{
    out[0] = command;
    out[1] = 0x00; /* MO writes 0x00; OH's power command puts 0x76 here (§2c) */
    out[2] = 0xAA;
    out[3] = payload_length;
    return 4;
}

size_t trk_psvr_build_power(uint8_t out[8], int on)
{
    control_header(out, 0x17, 4);
    memset(out + 4, 0, 4);
    out[4] = on ? 1 : 0;
    return 8;
}

size_t trk_psvr_build_vr_mode(uint8_t out[8], int vr)
{
    /* DEVICES.md gives the command and value, not the payload length: 4 bytes like power. */
    control_header(out, 0x23, 4);
    memset(out + 4, 0, 4);
    out[4] = vr ? 1 : 0;
    return 8;
}

size_t trk_psvr_build_tracking_on(uint8_t out[12])
{
    static const uint8_t payload[8] = {0x00, 0xFF, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x00};
    control_header(out, 0x11, 8);
    memcpy(out + 4, payload, 8);
    return 12;
}

/* ---- encoder ----------------------------------------------------------------------------------- */

static void put_words(uint8_t *w, hl_vec3d v, double lsb)
{
    /* Inverse of psvr_axes: w0 = y, w1 = x, w2 = −z. */
    trk_wr_u16(w, (uint16_t)trk_quantize(v.y, lsb, -32768, 32767));
    trk_wr_u16(w + 2, (uint16_t)trk_quantize(v.x, lsb, -32768, 32767));
    trk_wr_u16(w + 4, (uint16_t)trk_quantize(-v.z, lsb, -32768, 32767));
}

int trk_psvr_encode(const struct trk_imu_sample samples[2], uint8_t sequence, uint8_t *out, size_t out_size,
                    struct hl_error *err)
{
    if (!samples || !out || out_size < TRK_PSVR_REPORT_SIZE)
        return hl_fail(err, "psvr encode: output of %zu bytes, need %d", out_size, TRK_PSVR_REPORT_SIZE);
    memset(out, 0, TRK_PSVR_REPORT_SIZE);
    for (int k = 0; k < 2; ++k) {
        uint8_t *s = out + sample_offset[k];
        trk_wr_u32(s, trk_ns_to_counter(samples[k].device_time_ns, 24, 1000, 1, 0));
        put_words(s + 4, samples[k].gyro_radps, TRK_PSVR_GYRO_LSB_RADPS);
        put_words(s + 10, samples[k].accel_mps2, TRK_PSVR_ACCEL_LSB_MPS2);
    }
    out[63] = sequence;
    return TRK_PSVR_REPORT_SIZE;
}
