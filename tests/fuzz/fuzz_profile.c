/* Fuzz target: display profiles (hmd_profile_load_json, hmd/profile_json.c) from a scratch file.
 * A profile that loads must pass hmd_profile_validate again and give a finite ξ and FOV: the
 * validation's ranges are what keep NaN out of every summary (docs/display-profile.md). */
#include "fuzz_util.h"

#include <math.h>

#include "hmd/hmd.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_file("fuzz-profile.json", data, size);
    struct hmd_profile p;
    struct hl_error err;
    if (hmd_profile_load_json(path, &p, &err) == 0) {
        FUZZ_CHECK(hmd_profile_validate(&p, "fuzz", &err) == 0, "a loaded profile fails validation");
        struct hmd_xi xi = hmd_compute_xi(&p);
        FUZZ_CHECK(isfinite(xi.used_cpd) && xi.used_cpd > 0, "loaded profile gives a non-finite xi");
        FUZZ_CHECK(isfinite(hmd_fov_horizontal_deg(&p)) && isfinite(hmd_fov_vertical_deg(&p)),
                   "loaded profile gives a non-finite FOV");
        hl_vec3d e = hmd_neck_to_eye_head(&p);
        FUZZ_CHECK(isfinite(e.x) && isfinite(e.y) && isfinite(e.z), "neck-to-eye offset not finite");
    }
    return 0;
}
