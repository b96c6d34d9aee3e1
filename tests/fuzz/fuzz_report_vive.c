/* Fuzz target: HTC Vive / Vive Pro / Index IMU report parser (trk_vive_parse,
 * tracking/report_vive.c). Byte 0 picks the model (mod 3); the rest is a stream of length-prefixed
 * reports fed to one parser (sequence numbers, ring repeats, the 48 MHz clock). */
#include "report_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    struct trk_vive_parser p;
    trk_vive_parser_init(&p, (enum trk_vive_model)(data[0] % 3));
    ++data, --size;
    const uint8_t *report;
    size_t length;
    uint64_t calls = 0, samples = 0;
    while (fuzz_next_chunk(&data, &size, &report, &length) == 0) {
        struct trk_imu_sample out[TRK_REPORT_MAX_SAMPLES];
        struct hl_error err;
        int rc = trk_vive_parse(&p, report, length, out, TRK_REPORT_MAX_SAMPLES, &err);
        fuzz_check_report(rc, TRK_REPORT_MAX_SAMPLES, out, &p.n, ++calls, &samples);
    }
    return 0;
}
