/* Fuzz target: a bench run read back (bch_result_load, bench/suite_load.c), which reads
 * DIR/summary.json and DIR/frames.csv: the bytes up to the first NUL become summary.json, the rest
 * frames.csv (no NUL: no frames.csv, a run whose frames are missing). The statistics over each
 * column must not read outside it. */
#include "fuzz_util.h"

#include <stdio.h>
#include <string.h>

#include "bench/suite_internal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const uint8_t *nul = memchr(data, 0, size);
    size_t summary = nul ? (size_t)(nul - data) : size;
    fuzz_write_file("summary.json", data, summary);
    if (nul)
        fuzz_write_file("frames.csv", nul + 1, size - summary - 1);
    else
        remove(fuzz_temp_path("frames.csv"));
    struct bch_result r;
    struct hl_error err;
    if (bch_result_load(fuzz_temp_path(NULL), &r, &err) == 0) {
        const double *cols[] = {r.frame_ms, r.draw_ms, r.predicted_ms, r.triangles, r.visible_error};
        for (size_t i = 0; i < sizeof cols / sizeof cols[0]; ++i) {
            (void)bch_mean(&r, cols[i]);
            (void)bch_stddev_from(&r, cols[i], 1);
            (void)bch_max_from(&r, cols[i], 1);
        }
        bch_result_free(&r);
    }
    return 0;
}
