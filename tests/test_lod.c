/* lod/: the selectors without a cost model, on hand-checked chains (Reddy 1998 §3.3 online stage). */
#include <math.h>

#include "lod/lod.h"
#include "test_util.h"

static void test_select_reddy(void)
{
    /* One chain: 4 LODs whose removed detail has 40, 12, 4 cycles per diameter. */
    struct lod_chain chain = {.lod_count = 4, .unique_freq_cpdiam = {INFINITY, 40.0, 12.0, 4.0}};
    const uint32_t chain_of[] = {0, 0, 0, 0, 0};
    const uint32_t index[] = {0, 1, 2, 3, 4};
    /* Limit ξ = 10 at the fovea and still: level k is safe while f_k / diameter > 10. */
    const double ecc[] = {0, 0, 0, 0, 30};
    const double vel[] = {0, 0, 0, 0, 0};
    const double diam[] = {10.0, 2.0, 0.5, 0.1, 2.0};
    uint8_t lod[5];
    double ceiling[5];
    struct acu_limits lim;
    struct lod_select_stats stats = {0};
    acu_limits_init(&lim, 10.0, 1.0);
    lod_select_reddy(&lim, &chain, chain_of, index, 5, ecc, vel, diam, lod, ceiling, &stats);
    CHECK(lod[0] == 0); /* 40/10 = 4 c/deg < 10: visible */
    CHECK(lod[1] == 1); /* 40/2 = 20 > 10, 12/2 = 6 < 10 */
    CHECK(lod[2] == 2); /* 24 > 10, then 4/0.5 = 8 < 10 */
    CHECK(lod[3] == 3);
    /* At 30° eccentricity H = 60·M(30) = 4.49 c/deg: 12/2 = 6 > 4.49, 4/2 = 2 < 4.49 → level 2. */
    CHECK(lod[4] == 2);
    CHECK_NEAR(ceiling[4], 60.0 * 7.49 / (10.0 * 10.0), 1e-9);
    CHECK(stats.model_evaluations == 1 && stats.model_skips == 4);
    /* Faster eyes only go coarser: velocity never raises the LOD. */
    const double fast[] = {150, 150, 150, 150, 150};
    uint8_t lod_fast[5];
    lod_select_reddy(&lim, &chain, chain_of, index, 5, ecc, fast, diam, lod_fast, NULL, NULL);
    for (int k = 0; k < 5; ++k)
        CHECK(lod_fast[k] >= lod[k] && lod_fast[k] == 3);
    uint8_t finest[5] = {9, 9, 9, 9, 9};
    lod_select_finest(5, finest);
    CHECK(finest[0] == 0 && finest[4] == 0);
}

int main(void)
{
    test_select_reddy();
    return tu_finish("test_lod");
}
