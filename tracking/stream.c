/* Device streams: one tracker's parser feeding one fusion (tracking/stream.h). The live driver and the raw
 * recording replay both go through trk_stream_feed, so a recording fuses exactly as it did live. */
#include <math.h>
#include <string.h>

#include "tracking/tracking.h"

void trk_stream_init(struct trk_stream *s, enum trk_device_kind kind, const struct trk_fusion_config *cfg_or_null)
{
    memset(s, 0, sizeof *s);
    s->kind = kind;
    switch (kind) {
    case TRK_DEVICE_RIFT_DK1:
        trk_rift_parser_init(&s->parser.rift, 0);
        break;
    case TRK_DEVICE_RIFT_DK2:
    case TRK_DEVICE_RIFT_CV1: /* the CV1 sends the DK2's 0x0B report */
        trk_rift_parser_init(&s->parser.rift, 1);
        break;
    case TRK_DEVICE_PSVR:
        trk_psvr_parser_init(&s->parser.psvr);
        break;
    case TRK_DEVICE_VIVE:
        trk_vive_parser_init(&s->parser.vive, TRK_VIVE_MODEL_VIVE);
        break;
    case TRK_DEVICE_VIVE_PRO_INDEX:
        /* One USB id for both: the axes differ (tracking/reports.h), and only the headset's JSON config
         * tells them apart, so the driver overwrites parser.vive.cal once it has read it. */
        trk_vive_parser_init(&s->parser.vive, TRK_VIVE_MODEL_PRO);
        break;
    case TRK_DEVICE_HDK:
        trk_hdk_parser_init(&s->parser.hdk);
        break;
    }
    trk_fusion_init(&s->fusion, cfg_or_null);
    s->hdk_last_q = hl_q_identity();
}

static int parse(struct trk_stream *s, const uint8_t *report, size_t length, int64_t host_time_ns,
                 struct trk_imu_sample *out, struct hl_error *err)
{
    switch (s->kind) {
    case TRK_DEVICE_RIFT_DK1:
    case TRK_DEVICE_RIFT_DK2:
    case TRK_DEVICE_RIFT_CV1:
        return trk_rift_parse(&s->parser.rift, report, length, out, TRK_REPORT_MAX_SAMPLES, err);
    case TRK_DEVICE_PSVR:
        return trk_psvr_parse(&s->parser.psvr, report, length, out, TRK_REPORT_MAX_SAMPLES, err);
    case TRK_DEVICE_VIVE:
    case TRK_DEVICE_VIVE_PRO_INDEX:
        return trk_vive_parse(&s->parser.vive, report, length, out, TRK_REPORT_MAX_SAMPLES, err);
    case TRK_DEVICE_HDK:
        return trk_hdk_parse(&s->parser.hdk, report, length, host_time_ns, out, TRK_REPORT_MAX_SAMPLES, err);
    }
    return hl_fail(err, "stream: unknown device kind %d", (int)s->kind);
}

/* HDK: the chip has already fused; integrating its ω again would only add our error to its
 * estimate. The orientation is written into the fusion state (this module owns that struct) so that
 * trk_stream_pose predicts it the same way as for the IMU devices. */
static int take_hdk_orientation(struct trk_stream *s, const struct trk_imu_sample *x)
{
    struct trk_fusion *f = &s->fusion;
    double t_s = (double)x->device_time_ns * 1e-9;
    hl_quatd q = x->orientation;
    if (!isfinite(q.w) || !isfinite(q.x) || !isfinite(q.y) || !isfinite(q.z) || !isfinite(t_s)) {
        ++f->stats.rejected_nonfinite;
        return -1;
    }
    q = hl_q_normalize(q);
    if (f->has_orientation && hl_q_dot(q, f->orientation) < 0.0)
        q = hl_q_neg(q); /* shortest arc: keep the stream continuous */
    hl_vec3d omega = hl_v3(0, 0, 0);
    if (x->has_gyro) {
        omega = x->gyro_radps;
    } else if (f->has_time && t_s > f->last_time_s) {
        /* Version-1 reports carry no ω: the body-frame rate from q_prev* ⊗ q over the host-time
         * step (host arrival times jitter, so this is rough, but it is only used for prediction). */
        omega = hl_v3_scale(hl_q_log(hl_q_mul(hl_q_conj(s->hdk_last_q), q)), 1.0 / (t_s - f->last_time_s));
    }
    ++f->stats.samples;
    f->orientation = q;
    f->omega_radps = omega;
    f->omega_lp_radps = omega;
    f->last_time_s = t_s;
    f->has_time = 1;
    f->has_orientation = 1;
    s->hdk_last_q = q;
    return 0;
}

/* The parser's counters and clock, for the resync (HDK has no device clock: NULL). */
static struct trk_report_counters *parser_counters(struct trk_stream *s, struct trk_tick_clock **clock)
{
    switch (s->kind) {
    case TRK_DEVICE_RIFT_DK1:
    case TRK_DEVICE_RIFT_DK2:
    case TRK_DEVICE_RIFT_CV1:
        *clock = &s->parser.rift.clock;
        return &s->parser.rift.n;
    case TRK_DEVICE_PSVR:
        *clock = &s->parser.psvr.clock;
        return &s->parser.psvr.n;
    case TRK_DEVICE_VIVE:
    case TRK_DEVICE_VIVE_PRO_INDEX:
        *clock = &s->parser.vive.clock;
        return &s->parser.vive.n;
    case TRK_DEVICE_HDK:
        break;
    }
    *clock = NULL;
    return NULL;
}

/* Restarts the device clock's unwrapping (keeping the parser's calibration) after a counter reset. */
static void resync_clock(struct trk_stream *s, struct trk_tick_clock *clock)
{
    clock->started = 0;
    clock->overflowed = 0;
    if (s->kind == TRK_DEVICE_RIFT_DK1 || s->kind == TRK_DEVICE_RIFT_DK2 || s->kind == TRK_DEVICE_RIFT_CV1)
        s->parser.rift.has_last = 0;
    if (s->kind == TRK_DEVICE_VIVE || s->kind == TRK_DEVICE_VIVE_PRO_INDEX)
        s->parser.vive.has_seq = 0;
    s->counter_resets++;
    s->backward_run = 0;
    s->offset_pending = s->has_sample;
}

int trk_stream_feed(struct trk_stream *s, const uint8_t *report, size_t length, int64_t host_time_ns,
                    struct hl_error *err)
{
    struct trk_imu_sample samples[TRK_REPORT_MAX_SAMPLES];
    ++s->reports;
    if (!report) {
        ++s->rejected;
        return hl_fail(err, "stream: no report bytes");
    }
    struct trk_tick_clock *clock;
    struct trk_report_counters *pc = parser_counters(s, &clock);
    uint64_t backward0 = pc ? pc->backward : 0;
    int n = parse(s, report, length, host_time_ns, samples, err);
    if (n < 0) {
        ++s->rejected;
        return -1;
    }
    if (n == 0 && pc && pc->backward > backward0) {
        if (++s->backward_run >= TRK_STREAM_RESYNC_REPORTS)
            resync_clock(s, clock);
    } else if (n > 0) {
        s->backward_run = 0;
    }
    if (n > 0 && s->offset_pending) {
        /* Go on 1 ms after the newest fused sample (the devices' sample period, §2). */
        int64_t t;
        if (hl_i64_add_checked(s->newest_time_ns, 1000000, &t) != 0 ||
            hl_i64_sub_checked(t, samples[0].device_time_ns, &s->time_offset_ns) != 0) {
            ++s->rejected;
            return hl_fail(err, "stream: device counter reset at %lld ns: the new time base does not fit int64 ns",
                           (long long)s->newest_time_ns);
        }
        s->offset_pending = 0;
    }
    for (int i = 0; i < n && s->time_offset_ns != 0 && s->kind != TRK_DEVICE_HDK; ++i) {
        if (hl_i64_add_checked(samples[i].device_time_ns, s->time_offset_ns, &samples[i].device_time_ns) != 0) {
            ++s->rejected;
            return hl_fail(err, "stream: device time %lld ns + counter-reset offset %lld ns passes int64",
                           (long long)samples[i].device_time_ns, (long long)s->time_offset_ns);
        }
    }
    int fused = 0;
    for (int i = 0; i < n; ++i) {
        const struct trk_imu_sample *x = &samples[i];
        ++s->samples;
        int rc;
        if (x->has_orientation) {
            rc = take_hdk_orientation(s, x);
        } else {
            /* Device time in seconds: int64 ns → double keeps sub-µs resolution for months. */
            rc = trk_fusion_update(&s->fusion, (double)x->device_time_ns * 1e-9, x->gyro_radps, x->accel_mps2,
                                   x->has_accel);
        }
        if (rc < 0) {
            ++s->fusion_refused;
            continue;
        }
        /* Rift: the report's magnetometer reading, after the sample it was taken with. */
        if (x->has_mag && s->fusion.cfg.use_magnetometer)
            trk_fusion_update_mag(&s->fusion, (double)x->device_time_ns * 1e-9, x->mag_gauss);
        ++s->fused;
        ++fused;
        s->newest_time_ns = x->device_time_ns;
        s->has_sample = 1;
    }
    return fused;
}

void trk_stream_pose(const struct trk_stream *s, double horizon_s, struct trk_pose *out)
{
    double t_s = s->has_sample ? (double)s->newest_time_ns * 1e-9 : 0.0;
    trk_pose_init_still(out, t_s + horizon_s);
    trk_fusion_predict(&s->fusion, horizon_s, &out->orientation);
    /* The fusion's ω is body-frame; the pose's is world-frame. With a constant body rate the world
     * rate is constant too (the axis is the rotation's own), so either orientation rotates it. */
    out->angular_velocity_radps = hl_q_rotate(s->fusion.orientation, s->fusion.omega_radps);
}
