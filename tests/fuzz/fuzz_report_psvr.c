/* Fuzz target: Sony PSVR sensor report parser (trk_psvr_parse, tracking/report_psvr.c): a stream of
 * length-prefixed reports fed to one parser. */
#include "report_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    struct trk_psvr_parser p;
    trk_psvr_parser_init(&p);
    const uint8_t *report;
    size_t length;
    uint64_t calls = 0, samples = 0;
    while (fuzz_next_chunk(&data, &size, &report, &length) == 0) {
        struct trk_imu_sample out[TRK_REPORT_MAX_SAMPLES];
        struct hl_error err;
        int rc = trk_psvr_parse(&p, report, length, out, TRK_REPORT_MAX_SAMPLES, &err);
        fuzz_check_report(rc, TRK_REPORT_MAX_SAMPLES, out, &p.n, ++calls, &samples);
    }
    return 0;
}
