/* Device simulator over the per-device encoders (report_rift.c, report_psvr.c, report_vive.c,
 * report_hdk.c): physical samples in at the native rate, reports out as the device would batch,
 * ring, wrap and lose them. Used by the parser tests, the accuracy tests and the tracking bench. */
#include "tracking/report_internal.h"

#include <string.h>

void trk_encoder_init(struct trk_encoder *enc, enum trk_device_kind kind, const struct trk_encoder_options *opt)
{
    memset(enc, 0, sizeof *enc);
    enc->kind = kind;
    if (opt)
        enc->opt = *opt;
    if (enc->opt.samples_per_report <= 0)
        enc->opt.samples_per_report = kind == TRK_DEVICE_PSVR ? 2 : 1;
    if (kind == TRK_DEVICE_PSVR)
        enc->opt.samples_per_report = 2; /* the report layout holds exactly two */
    if (enc->opt.hdk_version == 0)
        enc->opt.hdk_version = 3;
    if (!(enc->opt.vive.gyro_range_radps > 0))
        trk_vive_calibration_default(&enc->opt.vive,
                                     kind == TRK_DEVICE_VIVE_PRO_INDEX ? TRK_VIVE_MODEL_PRO : TRK_VIVE_MODEL_VIVE);
}

/* The counter offset expressed as time, so the per-device encoders need no offset argument. */
/* Checked: the offset is an option, any int64 — −1 when its time does not fit int64 ns. */
static int offset_ns(enum trk_device_kind kind, int64_t ticks, int64_t *ns)
{
    int64_t scaled;
    switch (kind) {
    case TRK_DEVICE_RIFT_DK1: return hl_i64_mul_checked(ticks, 1000000, ns);
    case TRK_DEVICE_RIFT_DK2:
    case TRK_DEVICE_RIFT_CV1:
    case TRK_DEVICE_PSVR: return hl_i64_mul_checked(ticks, 1000, ns);
    case TRK_DEVICE_VIVE:
    case TRK_DEVICE_VIVE_PRO_INDEX: /* exact when ticks is a multiple of 6 */
        if (hl_i64_mul_checked(ticks, 125, &scaled) != 0)
            return -1;
        *ns = scaled / 6;
        return 0;
    case TRK_DEVICE_HDK:
    default: *ns = 0; return 0;
    }
}

int trk_encoder_push(struct trk_encoder *enc, const struct trk_imu_sample *sample, uint8_t *out, size_t out_size,
                     struct hl_error *err)
{
    if (!sample || !out || out_size < 64)
        return hl_fail(err, "tracking encoder: output of %zu bytes, need 64", out_size);
    struct trk_imu_sample s = *sample;
    int64_t off_ns;
    if (offset_ns(enc->kind, enc->opt.counter_offset_ticks, &off_ns) != 0 ||
        hl_i64_add_checked(s.device_time_ns, off_ns, &s.device_time_ns) != 0)
        return hl_fail(err, "tracking encoder: counter offset %lld ticks at %lld ns: the time does not fit int64 ns",
                       (long long)enc->opt.counter_offset_ticks, (long long)sample->device_time_ns);
    int length = 0;
    switch (enc->kind) {
    case TRK_DEVICE_RIFT_DK1:
    case TRK_DEVICE_RIFT_DK2:
    case TRK_DEVICE_RIFT_CV1: {
        int dk2 = enc->kind != TRK_DEVICE_RIFT_DK1;
        int slots = dk2 ? 2 : 3;
        /* The device keeps only the newest `slots` samples and counts the rest in N. */
        if (enc->pending_count == slots) {
            memmove(enc->pending, enc->pending + 1, sizeof enc->pending[0] * (size_t)(slots - 1));
            --enc->pending_count;
        }
        enc->pending[enc->pending_count++] = s;
        if (++enc->gathered < enc->opt.samples_per_report)
            return 0;
        int n_field = enc->gathered > 255 ? 255 : enc->gathered;
        length = trk_rift_encode(dk2, enc->pending, enc->pending_count, n_field, out, out_size, err);
        enc->pending_count = 0;
        enc->gathered = 0;
        break;
    }
    case TRK_DEVICE_PSVR:
        enc->pending[enc->pending_count++] = s;
        if (enc->pending_count < 2)
            return 0;
        length = trk_psvr_encode(enc->pending, enc->seq++, out, out_size, err);
        enc->pending_count = 0;
        break;
    case TRK_DEVICE_VIVE:
    case TRK_DEVICE_VIVE_PRO_INDEX: {
        /* Each sample overwrites the oldest ring slot, so every report carries the newest
         * sample and repeats the two before it, in rotating slot order — as the device does. */
        uint8_t seq = enc->seq++;
        if (!enc->ring_filled) {
            for (int i = 0; i < 3; ++i) {
                enc->ring[i] = s;
                enc->ring_seq[i] = seq;
            }
            enc->ring_filled = 1;
        }
        enc->ring[enc->ring_next] = s;
        enc->ring_seq[enc->ring_next] = seq;
        enc->ring_next = (enc->ring_next + 1) % 3;
        if (++enc->gathered < enc->opt.samples_per_report)
            return 0;
        enc->gathered = 0;
        length = trk_vive_encode(&enc->opt.vive, enc->ring, enc->ring_seq, out, out_size, err);
        break;
    }
    case TRK_DEVICE_HDK:
        length = trk_hdk_encode(&s, enc->opt.hdk_version, 0, enc->seq++, out, 32, err);
        break;
    default:
        return hl_fail(err, "tracking encoder: unknown device kind %d", (int)enc->kind);
    }
    if (length < 0)
        return -1;
    ++enc->reports_built;
    if (enc->opt.drop_report_every && enc->reports_built % enc->opt.drop_report_every == 0) {
        ++enc->reports_dropped;
        return 0;
    }
    return length;
}
