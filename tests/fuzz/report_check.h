/* tests/fuzz/report_check.h: the promises every report parser makes (tracking/reports.h), checked
 * after each call by the fuzz_report_* targets: a return of −1 or 0…max_out, counters that add up
 * (reports + rejected = calls, samples = the sum of the returns) and finite samples. */
#ifndef HMDLOD_FUZZ_REPORT_CHECK_H
#define HMDLOD_FUZZ_REPORT_CHECK_H

#include <math.h>

#include "fuzz_util.h"
#include "tracking/reports.h"

static inline int fuzz_vec_finite(hl_vec3d v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

static inline void fuzz_check_report(int rc, int max_out, const struct trk_imu_sample *out,
                                     const struct trk_report_counters *n, uint64_t calls, uint64_t *samples)
{
    FUZZ_CHECK(rc >= -1 && rc <= max_out, "parser returned outside -1..max_out");
    if (rc > 0)
        *samples += (uint64_t)rc;
    FUZZ_CHECK(n->reports + n->rejected == calls, "reports + rejected != parse calls");
    FUZZ_CHECK(n->samples == *samples, "samples counter != sum of returns");
    for (int i = 0; i < rc; ++i) {
        const struct trk_imu_sample *s = &out[i];
        FUZZ_CHECK(fuzz_vec_finite(s->gyro_radps) && fuzz_vec_finite(s->accel_mps2) && fuzz_vec_finite(s->mag_gauss),
                   "sample not finite");
        FUZZ_CHECK(isfinite(s->orientation.w + s->orientation.x + s->orientation.y + s->orientation.z),
                   "sample orientation not finite");
        FUZZ_CHECK(i == 0 || s->device_time_ns > out[i - 1].device_time_ns, "samples of one report not in time order");
    }
}

#endif
