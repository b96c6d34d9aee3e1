/* Fuzz target: OSVR HDK report parser (trk_hdk_parse, tracking/report_hdk.c): a stream of records,
 * each a signed 32-bit host-time step in µs (any sign: host clocks jump) then a length-prefixed
 * report, fed to one parser at the accumulated host time. */
#include "report_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    struct trk_hdk_parser p;
    trk_hdk_parser_init(&p);
    const uint8_t *report;
    size_t length;
    uint64_t calls = 0, samples = 0;
    int64_t host_ns = 0;
    while (size > 0) {
        int32_t step_us = (int32_t)(uint32_t)fuzz_take_le(&data, &size, 4);
        host_ns += (int64_t)step_us * 1000; /* ≤ 2^31 µs a step: 2^31 steps before int64 ns could end */
        if (fuzz_next_chunk(&data, &size, &report, &length) != 0)
            break;
        struct trk_imu_sample out[TRK_REPORT_MAX_SAMPLES];
        struct hl_error err;
        int rc = trk_hdk_parse(&p, report, length, host_ns, out, TRK_REPORT_MAX_SAMPLES, &err);
        fuzz_check_report(rc, TRK_REPORT_MAX_SAMPLES, out, &p.n, ++calls, &samples);
    }
    return 0;
}
