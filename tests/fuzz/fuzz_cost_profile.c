/* Fuzz target: cost profiles (frm_cost_profile_read, frame/cost_profile.c) from a scratch file. */
#include "fuzz_util.h"

#include "frame/frame.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_file("fuzz-cost.json", data, size);
    struct frm_cost_profile p;
    struct hl_error err;
    (void)frm_cost_profile_read(path, &p, &err);
    return 0;
}
