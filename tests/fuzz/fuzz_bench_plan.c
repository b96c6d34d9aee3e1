/* Fuzz target: bench suite files (bch_plan_read, bench/suite_prepare.c), which read DIR/suite.txt:
 * the bytes become suite.txt in the scratch folder. A plan read is freed (LeakSanitizer checks). */
#include "fuzz_util.h"

#include "bench/bench.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_write_file("suite.txt", data, size);
    struct bch_plan plan;
    char command[4096];
    struct hl_error err;
    if (bch_plan_read(fuzz_temp_path(NULL), &plan, command, sizeof command, &err) == 0)
        bch_plan_free(&plan);
    return 0;
}
