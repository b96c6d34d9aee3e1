/* Fuzz target: bench suite files (rpl_bench_plan_read, replay/bench_prepare.c), which read DIR/suite.txt:
 * the bytes become suite.txt in the scratch folder. A plan read is freed (LeakSanitizer checks). */
#include "fuzz_util.h"

#include "replay/replay.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_write_file("suite.txt", data, size);
    struct rpl_bench_plan plan;
    char command[4096];
    struct hl_error err;
    if (rpl_bench_plan_read(fuzz_temp_path(NULL), &plan, command, sizeof command, &err) == 0)
        rpl_bench_plan_free(&plan);
    return 0;
}
