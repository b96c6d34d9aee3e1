/* Fuzz target: the report stream feeding fusion (tracking/stream.c + fusion.c), the path every live
 * or recorded report takes. Byte 0 picks the tracker kind (mod 7) and, in bit 7, the magnetometer
 * correction off; then records: a signed 32-bit host-time step in µs and a length-prefixed report.
 * After every report the stream's pose (now and 20 ms ahead) must be finite and unit, and the
 * counters must add up. */
#include "fuzz_util.h"

#include <math.h>

#include "tracking/tracking.h"

static void check_pose(const struct trk_pose *p)
{
    const hl_quatd *q = &p->orientation;
    double n = q->w * q->w + q->x * q->x + q->y * q->y + q->z * q->z;
    FUZZ_CHECK(isfinite(n) && fabs(n - 1.0) < 1e-6, "stream orientation not finite and unit");
    FUZZ_CHECK(isfinite(p->time_s), "stream pose time not finite");
    FUZZ_CHECK(isfinite(p->angular_velocity_radps.x) && isfinite(p->angular_velocity_radps.y) &&
                   isfinite(p->angular_velocity_radps.z),
               "stream angular velocity not finite");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    struct trk_fusion_config cfg;
    trk_fusion_config_default(&cfg);
    cfg.use_magnetometer = !(data[0] & 0x80);
    static struct trk_stream s; /* large: kept off the stack */
    trk_stream_init(&s, (enum trk_device_kind)((data[0] & 0x7f) % 7), &cfg);
    ++data, --size;
    int64_t host_ns = 0;
    uint64_t feeds = 0;
    while (size > 0) {
        int32_t step_us = (int32_t)(uint32_t)fuzz_take_le(&data, &size, 4);
        host_ns += (int64_t)step_us * 1000;
        const uint8_t *report;
        size_t length;
        if (fuzz_next_chunk(&data, &size, &report, &length) != 0)
            break;
        struct hl_error err;
        int rc = trk_stream_feed(&s, report, length, host_ns, &err);
        ++feeds;
        FUZZ_CHECK(rc >= -1 && rc <= TRK_REPORT_MAX_SAMPLES, "stream feed returned out of range");
        FUZZ_CHECK(s.reports == feeds, "stream reports != feeds");
        FUZZ_CHECK(s.fused + s.fusion_refused <= s.samples || s.kind == TRK_DEVICE_HDK,
                   "stream fused more samples than the parser gave");
        struct trk_pose pose;
        trk_stream_pose(&s, 0.0, &pose);
        check_pose(&pose);
        trk_stream_pose(&s, 0.02, &pose);
        check_pose(&pose);
    }
    return 0;
}
