/* Oculus Rift DK1 (input report 0x01) and DK2/CV1 (0x0B) IMU parsers and command builders.
 * Layouts, scales and clocks: DEVICES.md §2b. */
#include "tracking/report_internal.h"

#include <string.h>

#define DK1_SLOTS 3
#define DK2_SLOTS 2
#define SLOT_SPACING_NS 1000000 /* 1000 Hz IMU on every Rift (§2a): slots 1 ms apart */

void trk_rift_parser_init(struct trk_rift_parser *p, int dk2)
{
    memset(p, 0, sizeof *p);
    p->dk2 = dk2 ? 1 : 0;
    /* DK1: u16 milliseconds (wraps 65.536 s); DK2/CV1: u32 microseconds (wraps 71.6 min). */
    if (p->dk2)
        trk_tick_clock_init(&p->clock, 32, 1000, 1);
    else
        trk_tick_clock_init(&p->clock, 16, 1000000, 1);
}

static void decode_slot(const uint8_t *slot, struct trk_imu_sample *s)
{
    int32_t a[3], g[3];
    trk_unpack_21bit_triple(slot, a);     /* accel first, then gyro (§2b) */
    trk_unpack_21bit_triple(slot + 8, g);
    /* With config flag 0x40 clear the HMD frame already is ours (+X right, +Y up, +Z back). */
    s->accel_mps2 = hl_v3(a[0] * TRK_RIFT_LSB, a[1] * TRK_RIFT_LSB, a[2] * TRK_RIFT_LSB);
    s->gyro_radps = hl_v3(g[0] * TRK_RIFT_LSB, g[1] * TRK_RIFT_LSB, g[2] * TRK_RIFT_LSB);
    s->has_accel = 1;
    s->has_gyro = 1;
}

int trk_rift_parse(struct trk_rift_parser *p, const uint8_t *report, size_t length,
                   struct trk_imu_sample *out, int max_out, struct hl_error *err)
{
    const char *dev = p->dk2 ? "rift dk2/cv1 report" : "rift dk1 report";
    uint8_t id = p->dk2 ? TRK_RIFT_DK2_REPORT_ID : TRK_RIFT_DK1_REPORT_ID;
    int slots = p->dk2 ? DK2_SLOTS : DK1_SLOTS;

    if (!report || length == 0) {
        trk_reject(&p->n);
        return hl_fail(err, "%s: empty", dev);
    }
    if (report[0] != id) {
        trk_reject(&p->n);
        return hl_fail(err, "%s: report id 0x%02X, expected 0x%02X", dev, report[0], id);
    }
    /* DK1 input reports are 62 B, 64 B on stacks that pad them (Windows hidapi, §2b). */
    if (p->dk2 ? length != 64 : (length != 62 && length != 64)) {
        trk_reject(&p->n);
        return hl_fail(err, "%s: length %zu, expected %s bytes", dev, length, p->dk2 ? "64" : "62 or 64");
    }
    if (!out || max_out < slots) {
        trk_reject(&p->n);
        return hl_fail(err, "%s: room for %d samples, need %d", dev, max_out, slots);
    }

    unsigned n_new;
    uint32_t raw_time;
    const uint8_t *slot0;
    if (p->dk2) { /* [3] N, [8..11] µs, slots at 12 */
        n_new = report[3];
        raw_time = trk_rd_u32(report + 8);
        slot0 = report + 12;
    } else { /* [1] N, [2..3] ms, slots at 8 */
        n_new = report[1];
        raw_time = trk_rd_u16(report + 2);
        slot0 = report + 8;
    }
    ++p->n.reports;
    int valid = n_new < (unsigned)slots ? (int)n_new : slots;
    /* N counts samples taken since the last report; the slots hold only the newest ones. */
    if (n_new > (unsigned)slots)
        p->n.lost += n_new - (unsigned)slots;
    if (valid == 0)
        return 0;

    int64_t ticks;
    int step = trk_tick_clock_unwrap(&p->clock, raw_time, &ticks);
    if (step == -2) {
        --p->n.reports; /* counted as accepted above: it is refused after all */
        trk_reject(&p->n);
        return hl_fail(err, "rift report: device counter %lld + step passes %lld ticks, beyond int64 nanoseconds",
                       (long long)p->clock.ticks, (long long)trk_tick_clock_max_ticks(&p->clock));
    }
    if (step <= 0) {
        /* The same timestamp again is a repeated report; an older one is stale. */
        if (step == 0)
            p->n.duplicates += (uint64_t)valid;
        else
            p->n.backward += (uint64_t)valid;
        return 0;
    }
    /* The timestamp belongs to the newest valid slot (§2b for DK2; we read DK1 the same way), so
     * slot k of `valid` is (valid−1−k) ms older. A report claiming more new samples than time has
     * passed overlaps what was delivered: those slots count as duplicates. */
    int64_t newest_ns = trk_tick_clock_ns(&p->clock, ticks);
    int emitted = 0;
    for (int k = 0; k < valid; ++k) {
        int64_t t = newest_ns - (int64_t)(valid - 1 - k) * SLOT_SPACING_NS;
        if (p->has_last && t <= p->last_time_ns) {
            ++p->n.duplicates;
            continue;
        }
        struct trk_imu_sample *s = &out[emitted++];
        trk_sample_clear(s);
        s->device_time_ns = t;
        decode_slot(slot0 + 16 * k, s);
        p->last_time_ns = t;
        p->has_last = 1;
    }
    /* One magnetometer reading per report (§2b), taken with the newest slot: attach it there. */
    if (emitted > 0) {
        const uint8_t *mag = report + (p->dk2 ? 44 : 56);
        int16_t mx = trk_rd_i16(mag), my = trk_rd_i16(mag + 2), mz = trk_rd_i16(mag + 4);
        if (mx || my || mz) {
            struct trk_imu_sample *s = &out[emitted - 1];
            s->mag_gauss = hl_v3(mx * TRK_RIFT_MAG_LSB_GAUSS, my * TRK_RIFT_MAG_LSB_GAUSS, mz * TRK_RIFT_MAG_LSB_GAUSS);
            s->has_mag = 1;
        }
    }
    p->n.samples += (uint64_t)emitted;
    return emitted;
}

/* ---- commands (§2b feature reports) ---------------------------------------------------------------- */

size_t trk_rift_build_keepalive_dk1(uint8_t out[5], uint16_t command_id, uint16_t interval_ms)
{
    out[0] = 0x08;
    trk_wr_u16(out + 1, command_id);
    trk_wr_u16(out + 3, interval_ms);
    return 5;
}

size_t trk_rift_build_keepalive_mux(uint8_t out[6], uint16_t command_id, uint8_t report_id, uint16_t interval_ms)
{
    out[0] = 0x11;
    trk_wr_u16(out + 1, command_id);
    out[3] = report_id; /* the IN report to keep alive: 0x0B for the IMU stream */
    trk_wr_u16(out + 4, interval_ms);
    return 6;
}

size_t trk_rift_build_enable_components(uint8_t out[4], uint16_t command_id, uint8_t flags)
{
    out[0] = 0x1D; /* CV1: without the display bit the panel stays dark */
    trk_wr_u16(out + 1, command_id);
    out[3] = flags;
    return 4;
}

size_t trk_rift_build_config(uint8_t out[7], uint16_t command_id, uint8_t flags, uint8_t interval,
                             uint16_t rate_or_keepalive)
{
    out[0] = 0x02;
    trk_wr_u16(out + 1, command_id);
    out[3] = flags;
    out[4] = interval;
    trk_wr_u16(out + 5, rate_or_keepalive); /* OH: keep-alive ms; MO: sample rate (read-only) */
    return 7;
}

/* ---- encoder ------------------------------------------------------------------------------------- */

int trk_rift_encode(int dk2, const struct trk_imu_sample *samples, int count, int n_field,
                    uint8_t *out, size_t out_size, struct hl_error *err)
{
    int slots = dk2 ? DK2_SLOTS : DK1_SLOTS;
    size_t size = dk2 ? 64 : 62;
    if (count < 0 || count > slots || n_field < count || n_field > 255)
        return hl_fail(err, "rift encode: %d samples with N = %d (slots %d)", count, n_field, slots);
    if (!out || out_size < size)
        return hl_fail(err, "rift encode: output of %zu bytes, need %zu", out_size, size);
    memset(out, 0, size);
    int64_t t = count > 0 ? samples[count - 1].device_time_ns : 0;
    uint8_t *slot0;
    if (dk2) {
        out[0] = TRK_RIFT_DK2_REPORT_ID;
        out[3] = (uint8_t)n_field;
        trk_wr_u32(out + 8, trk_ns_to_counter(t, 32, 1000, 1, 0));
        slot0 = out + 12;
    } else {
        out[0] = TRK_RIFT_DK1_REPORT_ID;
        out[1] = (uint8_t)n_field;
        trk_wr_u16(out + 2, (uint16_t)trk_ns_to_counter(t, 16, 1000000, 1, 0));
        slot0 = out + 8;
    }
    for (int k = 0; k < count; ++k) {
        const struct trk_imu_sample *s = &samples[k];
        int32_t a[3] = {trk_quantize(s->accel_mps2.x, TRK_RIFT_LSB, -0x100000, 0xFFFFF),
                        trk_quantize(s->accel_mps2.y, TRK_RIFT_LSB, -0x100000, 0xFFFFF),
                        trk_quantize(s->accel_mps2.z, TRK_RIFT_LSB, -0x100000, 0xFFFFF)};
        int32_t g[3] = {trk_quantize(s->gyro_radps.x, TRK_RIFT_LSB, -0x100000, 0xFFFFF),
                        trk_quantize(s->gyro_radps.y, TRK_RIFT_LSB, -0x100000, 0xFFFFF),
                        trk_quantize(s->gyro_radps.z, TRK_RIFT_LSB, -0x100000, 0xFFFFF)};
        trk_pack_21bit_triple(a, slot0 + 16 * k);
        trk_pack_21bit_triple(g, slot0 + 16 * k + 8);
    }
    if (count > 0 && samples[count - 1].has_mag) {
        const hl_vec3d m = samples[count - 1].mag_gauss;
        uint8_t *mag = out + (dk2 ? 44 : 56);
        trk_wr_u16(mag, (uint16_t)(int16_t)trk_quantize(m.x, TRK_RIFT_MAG_LSB_GAUSS, -32768, 32767));
        trk_wr_u16(mag + 2, (uint16_t)(int16_t)trk_quantize(m.y, TRK_RIFT_MAG_LSB_GAUSS, -32768, 32767));
        trk_wr_u16(mag + 4, (uint16_t)(int16_t)trk_quantize(m.z, TRK_RIFT_MAG_LSB_GAUSS, -32768, 32767));
    }
    return (int)size;
}
