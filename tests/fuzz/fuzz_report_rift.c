/* Fuzz target: Oculus Rift report parser (trk_rift_parse, tracking/report_rift.c). Byte 0 bit 0
 * picks DK1 (report 0x01) or DK2/CV1 (0x0B); the rest is a stream of length-prefixed reports fed to
 * one parser, so the tick clock's unwrapping sees wraps, repeats and backward steps. */
#include "report_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    struct trk_rift_parser p;
    trk_rift_parser_init(&p, data[0] & 1);
    ++data, --size;
    const uint8_t *report;
    size_t length;
    uint64_t calls = 0, samples = 0;
    int64_t last_ns = 0;
    int has_last = 0;
    while (fuzz_next_chunk(&data, &size, &report, &length) == 0) {
        struct trk_imu_sample out[TRK_REPORT_MAX_SAMPLES];
        struct hl_error err;
        int rc = trk_rift_parse(&p, report, length, out, TRK_REPORT_MAX_SAMPLES, &err);
        fuzz_check_report(rc, TRK_REPORT_MAX_SAMPLES, out, &p.n, ++calls, &samples);
        /* duplicates and backward samples are dropped: delivered times strictly increase */
        for (int i = 0; i < rc; ++i) {
            FUZZ_CHECK(!has_last || out[i].device_time_ns > last_ns, "Rift delivered a sample not after the last");
            last_ns = out[i].device_time_ns, has_last = 1;
        }
    }
    return 0;
}
