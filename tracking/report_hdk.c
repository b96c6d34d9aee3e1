/* OSVR HDK orientation report (16 or 32 bytes, no report ID), DEVICES.md §2e. The BNO070 fuses
 * on-chip: we get a quaternion and (version ≥ 2) angular velocity, no raw IMU and no clock. */
#include "tracking/report_internal.h"

#include <math.h>
#include <string.h>

void trk_hdk_parser_init(struct trk_hdk_parser *p) { memset(p, 0, sizeof *p); }

/* The one place that maps device axes to the body frame. (x, y, z)_body = (x, z, −y)_device: a
 * proper rotation (−90° about X) taking the chip's Z-up frame to our Y-up one. Conjugating a
 * quaternion by it rotates only the vector part, so the same map serves q and ω. DEVICES.md §2e:
 * MO additionally turns +90° about X and −90° about Y, VRPN differs again — verify on hardware,
 * change it here (and in body_to_device) only. */
static hl_vec3d device_to_body(hl_vec3d v) { return hl_v3(v.x, v.z, -v.y); }
static hl_vec3d body_to_device(hl_vec3d v) { return hl_v3(v.x, -v.z, v.y); }

int trk_hdk_parse(struct trk_hdk_parser *p, const uint8_t *report, size_t length, int64_t host_time_ns,
                  struct trk_imu_sample *out, int max_out, struct hl_error *err)
{
    if (!report || (length != 16 && length != 32)) {
        trk_reject(&p->n);
        return hl_fail(err, "osvr hdk report: length %zu, expected 16 or 32 bytes", report ? length : 0);
    }
    /* No report ID: the version nibble stands in for it. */
    unsigned version = report[0] & 0x0F;
    if (version < 1 || version > 3) {
        trk_reject(&p->n);
        return hl_fail(err, "osvr hdk report: version %u, expected 1 to 3", version);
    }
    if (!out || max_out < 1) {
        trk_reject(&p->n);
        return hl_fail(err, "osvr hdk report: room for %d samples, need 1", max_out);
    }
    hl_vec3d qv = hl_v3(trk_rd_i16(report + 2) * TRK_HDK_QUAT_LSB, trk_rd_i16(report + 4) * TRK_HDK_QUAT_LSB,
                        trk_rd_i16(report + 6) * TRK_HDK_QUAT_LSB);
    double qw = trk_rd_i16(report + 8) * TRK_HDK_QUAT_LSB;
    double norm = sqrt(qw * qw + hl_v3_dot(qv, qv));
    if (!(norm >= 0.5 && norm <= 1.5)) {
        trk_reject(&p->n);
        return hl_fail(err, "osvr hdk report: quaternion norm %.4f is no rotation", norm);
    }
    ++p->n.reports;
    p->last_version = version;
    p->last_status = version >= 3 ? (unsigned)(report[0] >> 4) : 0; /* 0x1 video, 0x2 portrait */

    /* The sequence byte is the only way to see repeats and gaps on this device. */
    uint8_t seq = report[1];
    if (p->has_seq) {
        uint8_t d = (uint8_t)(seq - p->last_seq);
        if (d == 0) {
            ++p->n.duplicates;
            return 0;
        }
        if (d <= 127)
            p->n.lost += (uint64_t)(d - 1);
        /* d ≥ 128: a restart or a jump we cannot size; counted as nothing. */
    }
    p->has_seq = 1;
    p->last_seq = seq;
    if (p->has_last && host_time_ns <= p->last_time_ns) {
        trk_count_drop(&p->n, host_time_ns == p->last_time_ns ? 0 : -1);
        return 0;
    }
    p->has_last = 1;
    p->last_time_ns = host_time_ns;

    struct trk_imu_sample *o = &out[0];
    trk_sample_clear(o);
    o->device_time_ns = host_time_ns;
    hl_vec3d bv = device_to_body(qv);
    o->orientation = hl_q_normalize(hl_q(qw, bv.x, bv.y, bv.z));
    o->has_orientation = 1;
    if (version >= 2) {
        o->gyro_radps = device_to_body(hl_v3(trk_rd_i16(report + 10) * TRK_HDK_GYRO_LSB_RADPS,
                                             trk_rd_i16(report + 12) * TRK_HDK_GYRO_LSB_RADPS,
                                             trk_rd_i16(report + 14) * TRK_HDK_GYRO_LSB_RADPS));
        o->has_gyro = 1;
    }
    ++p->n.samples;
    return 1;
}

int trk_hdk_encode(const struct trk_imu_sample *sample, unsigned version, unsigned status, uint8_t sequence,
                   uint8_t *out, size_t out_size, struct hl_error *err)
{
    if (!sample || version < 1 || version > 3 || status > 15)
        return hl_fail(err, "osvr hdk encode: version %u (1 to 3), status %u (0 to 15)", version, status);
    if (!out || (out_size != 16 && out_size != 32))
        return hl_fail(err, "osvr hdk encode: output of %zu bytes, need 16 or 32", out_size);
    memset(out, 0, out_size);
    out[0] = (uint8_t)(version | (version >= 3 ? status << 4 : 0));
    out[1] = sequence;
    hl_quatd q = hl_q_normalize(sample->orientation);
    hl_vec3d dv = body_to_device(hl_v3(q.x, q.y, q.z));
    trk_wr_u16(out + 2, (uint16_t)trk_quantize(dv.x, TRK_HDK_QUAT_LSB, -32768, 32767));
    trk_wr_u16(out + 4, (uint16_t)trk_quantize(dv.y, TRK_HDK_QUAT_LSB, -32768, 32767));
    trk_wr_u16(out + 6, (uint16_t)trk_quantize(dv.z, TRK_HDK_QUAT_LSB, -32768, 32767));
    trk_wr_u16(out + 8, (uint16_t)trk_quantize(q.w, TRK_HDK_QUAT_LSB, -32768, 32767));
    if (version >= 2) {
        hl_vec3d g = body_to_device(sample->gyro_radps);
        trk_wr_u16(out + 10, (uint16_t)trk_quantize(g.x, TRK_HDK_GYRO_LSB_RADPS, -32768, 32767));
        trk_wr_u16(out + 12, (uint16_t)trk_quantize(g.y, TRK_HDK_GYRO_LSB_RADPS, -32768, 32767));
        trk_wr_u16(out + 14, (uint16_t)trk_quantize(g.z, TRK_HDK_GYRO_LSB_RADPS, -32768, 32767));
    }
    return (int)out_size;
}
