/* lod/: the selectors without a cost model, on hand-checked chains (Reddy 1998 §3.3 online stage). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

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

/* The online cost correction (lod.h): a model that under-predicts by 30 % tightens the budget to
 * about budget / 1.3 within a few dozen frames; jitter adds its margin; over-prediction never
 * loosens it; non-finite or non-positive frames are ignored; one wild frame is clamped. */
/* The contrast criterion against the CSF evaluated directly (not the table), on a chain whose bands
 * carry hand-set lost contrasts: the coarsest level whose every displayable band has c·S·k < 1. */
static int expected_contrast_level(const struct lod_chain *ch, double xi, double k, double v, double e, double diam)
{
    for (int l = ch->lod_count - 1; l > 0; --l) {
        int visible = 0;
        for (int b = 0; b < ch->band_count; ++b) {
            double rho = exp2(b) / diam, c = ch->lost_contrast[l][b];
            if (rho > xi || c == 0.0)
                continue;
            double sens = acu_csf_sensitivity(ACU_CSF_CASTLE, rho, rho * v, 100.0,
                                              acu_csf_gabor_area_deg2(rho, ACU_CSF_GABOR_CYCLES), e);
            visible |= !(c * sens * k < 1.0);
        }
        if (!visible)
            return l;
    }
    return 0;
}

static void test_select_contrast(void)
{
    static struct acu_csf_table table; /* 116 KB */
    acu_csf_table_fill_cycles(&table, ACU_CSF_CASTLE, 100.0, ACU_CSF_GABOR_CYCLES);
    /* Bands 1, 2, 4 … 32 cycles per diameter; coarser levels lose more, mostly in the high bands. */
    struct lod_chain chain = {.lod_count = 4, .unique_freq_cpdiam = {INFINITY, 40.0, 12.0, 4.0}, .band_count = 6};
    const double lost[4][6] = {{0, 0, 0, 0, 0, 0},
                               {0, 0, 0, 0.002, 0.01, 0.03},
                               {0, 0.001, 0.01, 0.03, 0.08, 0.15},
                               {0.02, 0.05, 0.1, 0.2, 0.3, 0.4}};
    for (int l = 0; l < 4; ++l) /* row by row: lost_contrast is LOD_MAX_LEVELS × LOD_MAX_BANDS */
        memcpy(chain.lost_contrast[l], lost[l], sizeof lost[l]);
    struct acu_limits lim;
    acu_limits_init(&lim, 10.0, 1.0);
    struct acu_contrast_limits vis;
    acu_contrast_limits_init(&vis, &table, 10.0, 1.0, 1.0);
    /* Hand cases. A 0.5° object: even band 0 (2 cpd) is displayable, band 5 (64 cpd) is not. A 0.05°
     * object: every band is above ξ = 10 cpd (20 cpd and up), nothing displayable is lost → coarsest,
     * whatever the contrast. */
    const uint32_t chain_of[] = {0}, one[] = {0};
    double ecc = 0.0, vel = 0.0, diam = 0.05;
    uint8_t lod = 99;
    struct lod_select_stats stats = {0};
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &lod, &stats);
    CHECK(lod == 3);
    CHECK(stats.model_evaluations == 0); /* no band displayable: no CSF lookup at all */
    /* Random objects against the direct model, away from the threshold's table error (0.01 in log10 S). */
    uint64_t seed = 7;
    int compared = 0, coarser = 0;
    for (int t = 0; t < 4000; ++t) {
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        double u1 = (double)(seed >> 11) / 9007199254740992.0;
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        double u2 = (double)(seed >> 11) / 9007199254740992.0;
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        double u3 = (double)(seed >> 11) / 9007199254740992.0;
        double d = exp2(-4.0 + 8.0 * u1); /* 0.06 … 16° */
        double e = 40.0 * u2, v = u3 < 0.3 ? 0.0 : 30.0 * u3;
        uint8_t got = 99;
        lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &e, &v, &d, &got, NULL);
        /* 2^6 = 64 c/diam ≤ ξ·D: the unmeasured part is displayable → also at most Reddy's level. */
        int want = expected_contrast_level(&chain, 10.0, 1.0, v, e, d);
        if (exp2(chain.band_count) <= 10.0 * d) {
            uint8_t reddy = 99;
            lod_select_reddy(&lim, &chain, chain_of, one, 1, &e, &v, &d, &reddy, NULL, NULL);
            want = want < reddy ? want : reddy;
        }
        int near_threshold = expected_contrast_level(&chain, 10.0, 1.0 / 1.03, v, e, d) !=
                             expected_contrast_level(&chain, 10.0, 1.03, v, e, d);
        if (!near_threshold) {
            CHECK(got == want);
            ++compared;
        }
        coarser += got > 0;
    }
    CHECK(compared > 3500 && coarser > 1000); /* both outcomes exercised */
    /* k: a larger safety factor never chooses a coarser level. */
    for (double d = 0.1; d < 20.0; d *= 1.3) {
        uint8_t a = 0, b = 0;
        struct acu_contrast_limits safe = vis;
        safe.k_scale = 4.0;
        lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &d, &a, NULL);
        lod_select_contrast(&safe, &lim, &chain, chain_of, one, 1, &ecc, &vel, &d, &b, NULL);
        CHECK(b <= a);
    }
    /* An unmeasured band (NaN) that is displayable counts as visible; beyond ξ it does not matter. */
    struct lod_chain nan_chain = chain;
    for (int l = 1; l < 4; ++l)
        nan_chain.lost_contrast[l][0] = NAN;
    diam = 0.5; /* band 0 at 2 cpd: displayable */
    lod_select_contrast(&vis, &lim, &nan_chain, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod == 0);
    diam = 0.05; /* band 0 at 20 cpd > ξ */
    lod_select_contrast(&vis, &lim, &nan_chain, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod == 3);
    /* No spectrum: exactly Reddy's selector. A point (diameter 0): the coarsest, as Reddy's. */
    struct lod_chain bare = {.lod_count = 4, .unique_freq_cpdiam = {INFINITY, 40.0, 12.0, 4.0}};
    for (double d = 0.05; d < 30.0; d *= 1.2)
        for (double e = 0.0; e < 50.0; e += 7.0) {
            uint8_t a = 99, b = 98;
            double v2 = 3.0;
            lod_select_contrast(&vis, &lim, &bare, chain_of, one, 1, &e, &v2, &d, &a, NULL);
            lod_select_reddy(&lim, &bare, chain_of, one, 1, &e, &v2, &d, &b, NULL, NULL);
            CHECK(a == b);
        }
    diam = 0.0;
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod == 3);
    /* s < 1 judges every band at ρ/s: never finer than s = 1. */
    struct acu_contrast_limits scaled = vis;
    scaled.scale = 0.5;
    for (double d = 0.1; d < 20.0; d *= 1.3) {
        uint8_t a = 0, b = 0;
        lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &d, &a, NULL);
        lod_select_contrast(&scaled, &lim, &chain, chain_of, one, 1, &ecc, &vel, &d, &b, NULL);
        CHECK(b >= a);
    }
}

/* docs/HARD_CASES.md "Visibility": the contrast criterion at the extremes of its inputs. */
static void test_select_contrast_hard_cases(void)
{
    static struct acu_csf_table table;
    struct lod_chain chain = {.lod_count = 3, .unique_freq_cpdiam = {INFINITY, 40.0, 12.0}, .band_count = 7};
    for (int b = 0; b < 7; ++b)
        chain.lost_contrast[1][b] = 0.05, chain.lost_contrast[2][b] = 0.5;
    struct acu_limits lim;
    acu_limits_init(&lim, 10.0, 1.0);
    struct acu_contrast_limits vis;
    acu_contrast_limits_init(&vis, &table, 10.0, 1.0, 1.0);
    const uint32_t chain_of[] = {0}, one[] = {0};
    uint8_t lod = 99;
    double ecc = 0.0, vel = 0.0, diam = 4.0; /* bands at 0.25 … 16 cpd: most displayable */
    /* L → 0: the table at the model's floor (0.02 cd/m²) is finite and the choice defined. */
    acu_csf_table_fill_cycles(&table, ACU_CSF_CASTLE, 0.0, ACU_CSF_GABOR_CYCLES);
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod <= 2);
    acu_csf_table_fill_cycles(&table, ACU_CSF_CASTLE, 100.0, ACU_CSF_GABOR_CYCLES);
    /* v = 0: still; a 50 % loss at 0.25–8 cpd in the fovea is seen, a 5 % one at 4 cpd too (S ≈ 100). */
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod == 0);
    /* v ≥ 1000 deg/s: ω in the kHz, S → 0, nothing lost is visible → coarsest (Reddy's G is 0 there too). */
    vel = 1000.0;
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod == 2);
    vel = 1e12;
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod == 2);
    /* E > 60: held at 60° (acuity/csf.h), the same choice at 90 and 180. */
    vel = 0.0;
    uint8_t at60 = 99, at90 = 98, at180 = 97;
    ecc = 60.0;
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &at60, NULL);
    ecc = 90.0;
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &at90, NULL);
    ecc = 180.0;
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &at180, NULL);
    CHECK(at60 == at90 && at90 == at180);
    /* ρ → 0 (a huge object: band 0 at 1/180 cpd, off the table's grid) and ρ ≫ 60 (a speck). */
    ecc = 0.0;
    diam = 180.0;
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod == 0); /* 2^7/180 < ξ: Reddy's level holds it, which is 0 at the fovea */
    diam = 1e-3;
    lod_select_contrast(&vis, &lim, &chain, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod == 2);
    /* contrast 0 everywhere: nothing is lost → coarsest; contrast > 1 (band contrast) is simply visible. */
    struct lod_chain flat = chain;
    memset(flat.lost_contrast, 0, sizeof flat.lost_contrast);
    diam = 4.0;
    lod_select_contrast(&vis, &lim, &flat, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod == 2);
    flat.lost_contrast[2][3] = 3.0; /* 2 cpd */
    lod_select_contrast(&vis, &lim, &flat, chain_of, one, 1, &ecc, &vel, &diam, &lod, NULL);
    CHECK(lod == 1);
}

/* The perceptual benefit (issue 31 item 4): the visible loss per level against the direct model, and
 * the benefit it gives. */
static void test_perceptual_benefit(void)
{
    static struct acu_csf_table table;
    acu_csf_table_fill_cycles(&table, ACU_CSF_CASTLE, 100.0, ACU_CSF_GABOR_CYCLES);
    struct lod_chain chains[2] = {{.lod_count = 4, .unique_freq_cpdiam = {INFINITY, 40.0, 12.0, 4.0}, .band_count = 6},
                                  {.lod_count = 3, .unique_freq_cpdiam = {INFINITY, 20.0, 5.0}}}; /* 2nd: no spectrum */
    const double lost[4][6] = {{0, 0, 0, 0, 0, 0},
                               {0, 0, 0, 0.002, 0.01, 0.03},
                               {0, 0.001, 0.01, 0.03, 0.08, 0.15},
                               {0.02, 0.05, NAN, 0.2, 0.3, 0.4}};
    for (int l = 0; l < 4; ++l) /* row by row: lost_contrast is LOD_MAX_LEVELS × LOD_MAX_BANDS */
        memcpy(chains[0].lost_contrast[l], lost[l], sizeof lost[l]);
    struct acu_contrast_limits vis;
    acu_contrast_limits_init(&vis, &table, 10.0, 1.0, 2.0);
    enum { N = 400 };
    uint32_t chain_of[N], index[N];
    double e[N], v[N], d[N], loss[N * LOD_MAX_LEVELS];
    uint64_t seed = 3;
    for (int k = 0; k < N; ++k) {
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        chain_of[k] = k % 7 == 0, index[k] = (uint32_t)k;
        d[k] = exp2(-4.0 + 9.0 * (double)(seed >> 11) / 9007199254740992.0); /* 0.06 … 32° */
        e[k] = (double)(k % 41), v[k] = k % 3 ? 0.0 : (double)(k % 17);
    }
    d[1] = 0.0; /* a point */
    struct lod_select_stats st = {0};
    lod_visible_loss_contrast(&vis, chains, chain_of, index, N, e, v, d, loss, &st);
    CHECK(st.model_evaluations > 0);
    double worst = 0.0;
    int positive = 0;
    for (int k = 0; k < N; ++k) {
        const double *row = loss + k * LOD_MAX_LEVELS;
        if (chain_of[k] == 1) { /* no spectrum: NaN, so the benefit falls back to Funkhouser's */
            CHECK(isnan(row[0]));
            continue;
        }
        CHECK(row[0] == 0.0);
        for (int l = 4; l < LOD_MAX_LEVELS; ++l)
            CHECK(row[l] == 0.0);
        for (int l = 1; l < 4; ++l) {
            double want = 0.0;
            for (int b = 0; b < 6 && d[k] > 0.0; ++b) {
                double rho = exp2(b) / d[k];
                if (rho > 10.0)
                    break;
                double c = lost[l][b];
                if (isnan(c)) {
                    want += 1.0;
                    continue;
                }
                double sens = acu_csf_sensitivity(ACU_CSF_CASTLE, rho, rho * v[k], 100.0,
                                                  acu_csf_gabor_area_deg2(rho, ACU_CSF_GABOR_CYCLES), e[k]);
                want += fmax(0.0, c * sens * 2.0 - 1.0);
            }
            /* The table is within 0.01 in log10 S of the model (acuity/csf.h): 2.3 % on c·S. */
            worst = fmax(worst, fabs(row[l] - want) / fmax(1.0, want));
            positive += row[l] > 0.0;
        }
    }
    printf("visible loss against the direct model: worst relative difference %.4f, %d positive\n", worst, positive);
    CHECK(worst < 0.03 && positive > 100);

    /* The benefit: size · (1 − √(D·(1 + h·|ΔL|) / LOD_PERCEPTUAL_LOSS_WHOLE)), at least 0; finer than
     * the ceiling earns the ceiling's; a NaN row keeps Funkhouser's accuracy; a drop earns 0. The
     * losses here are the order of the chairs' by the gaze on the auditorium (210–840 at level 1, up
     * to 12 000 at level 3): they must stay apart, where 1 / (1 + D) put them all within 0.5 % of 0. */
    struct lod_benefit_params bp;
    lod_benefit_params_default(&bp);
    const uint32_t first[2] = {0, 5}, samples[8] = {0, 20, 60, 200, 900, 30, 90, 400};
    const uint8_t count[2] = {5, 3}, level[8] = {LOD_DROP, 3, 2, 1, 0, 2, 1, 0};
    const double px[2] = {1000.0, 500.0};
    const uint8_t ceiling[2] = {1, 0}, previous[2] = {LOD_UNSEEN, 1};
    double rows[2 * LOD_MAX_LEVELS] = {0, 2500.0, 10000.0, 40000.0}; /* √(D / 90 000) = 1/6, 1/3, 2/3 */
    for (int l = 0; l < LOD_MAX_LEVELS; ++l)
        rows[LOD_MAX_LEVELS + l] = NAN;
    double benefit[8], funk[8];
    lod_benefit_fill(&bp, 2, first, count, level, samples, px, NULL, ceiling, previous, rows, benefit);
    lod_benefit_fill(&bp, 2, first, count, level, samples, px, NULL, ceiling, previous, NULL, funk);
    CHECK(benefit[0] == 0.0);
    CHECK(fabs(benefit[1] - 1000.0 / 3.0) < 1e-9);
    CHECK(fabs(benefit[2] - 2000.0 / 3.0) < 1e-9);
    CHECK(fabs(benefit[3] - 5000.0 / 6.0) < 1e-9);
    CHECK(benefit[4] == benefit[3]); /* level 0 is finer than the ceiling (1) */
    for (int c = 5; c < 8; ++c)
        CHECK(benefit[c] == funk[c]); /* no spectrum */
    /* Hysteresis scales the visible loss: one level from last frame's counts it twice. */
    const uint8_t previous2[2] = {2, 1};
    lod_benefit_fill(&bp, 2, first, count, level, samples, px, NULL, ceiling, previous2, rows, benefit);
    CHECK(fabs(benefit[2] - 2000.0 / 3.0) < 1e-9);                        /* level 2 = last frame's */
    CHECK(fabs(benefit[3] - 1000.0 * (1.0 - sqrt(5000.0 / 90000.0))) < 1e-9); /* one step away */
    /* Compressive, not saturating: four times the loss takes twice as much; past the whole, 0. */
    double taken_d = 1.0 - lod_benefit_perceptual_accuracy(400.0);
    double taken_4d = 1.0 - lod_benefit_perceptual_accuracy(4.0 * 400.0);
    CHECK(fabs(taken_4d - 2.0 * taken_d) < 1e-12);
    CHECK(lod_benefit_perceptual_accuracy(0.0) == 1.0);
    CHECK(lod_benefit_perceptual_accuracy(2.0 * LOD_PERCEPTUAL_LOSS_WHOLE) == 0.0);
}

static void test_cost_correction(void)
{
    struct lod_cost_correction c;
    lod_cost_correction_init(&c, 0.1);
    CHECK(lod_cost_correction_budget_ms(&c, 11.0) == 11.0);
    for (int f = 0; f < 300; ++f) /* the start's transient decays as 0.9 per frame */
        lod_cost_correction_update(&c, 1.3 * 8.0, 8.0);
    CHECK_NEAR(c.ratio, 1.3, 1e-3);
    CHECK(c.variance < 1e-6);
    CHECK_NEAR(lod_cost_correction_budget_ms(&c, 11.0), 11.0 / 1.3, 0.01);
    /* Jitter ±10 % around 1.3: the budget leaves room for about two standard deviations. */
    for (int f = 0; f < 400; ++f)
        lod_cost_correction_update(&c, (1.3 + (f % 2 ? 0.1 : -0.1)) * 8.0, 8.0);
    double sigma = sqrt(c.variance);
    CHECK(sigma > 0.05 && sigma < 0.15);
    CHECK_NEAR(lod_cost_correction_budget_ms(&c, 11.0), 11.0 / (c.ratio + 2.0 * sigma), 1e-12);
    CHECK(lod_cost_correction_budget_ms(&c, 11.0) < 11.0 / 1.35);
    /* Over-prediction: the ratio falls below 1, the budget stays the budget. */
    struct lod_cost_correction over;
    lod_cost_correction_init(&over, 0.1);
    for (int f = 0; f < 100; ++f)
        lod_cost_correction_update(&over, 0.5 * 8.0, 8.0);
    CHECK(over.ratio < 0.6);
    CHECK(lod_cost_correction_budget_ms(&over, 11.0) == 11.0);
    /* Ignored inputs leave it as it was; a 100× frame moves it by at most the clamp. */
    struct lod_cost_correction before = c;
    lod_cost_correction_update(&c, NAN, 8.0);
    lod_cost_correction_update(&c, 8.0, 0.0);
    lod_cost_correction_update(&c, -1.0, 8.0);
    lod_cost_correction_update(&c, INFINITY, 8.0);
    CHECK(c.ratio == before.ratio && c.variance == before.variance);
    lod_cost_correction_update(&c, 800.0, 8.0);
    CHECK(c.ratio <= 4.0 && c.variance <= 16.0);
    CHECK(isfinite(lod_cost_correction_budget_ms(&c, 11.0)) && lod_cost_correction_budget_ms(&c, 11.0) > 0.0);
}

/* The feedback controller (lod.h): over 0.9 of the budget it drops two steps at once, over 0.85 for
 * three frames one step, under 0.7 it climbs one step after 6 frames and two after 12. */
static void test_feedback(void)
{
    struct lod_feedback f;
    lod_feedback_init(&f, 64.0);
    lod_feedback_update(&f, 10.5, 11.0); /* 0.95: two steps coarser at once */
    CHECK_NEAR(f.min_px_per_triangle, 64.0 * 1.15 * 1.15, 1e-9);
    lod_feedback_init(&f, 64.0);
    for (int k = 0; k < 3; ++k)
        lod_feedback_update(&f, 9.6, 11.0); /* 0.87, flat trend */
    CHECK_NEAR(f.min_px_per_triangle, 64.0 * 1.15, 1e-9);
    lod_feedback_init(&f, 64.0);
    for (int k = 0; k < 5; ++k)
        lod_feedback_update(&f, 5.0, 11.0);
    CHECK(f.min_px_per_triangle == 64.0); /* climbs slowly: nothing before the sixth cheap frame */
    lod_feedback_update(&f, 5.0, 11.0);
    CHECK_NEAR(f.min_px_per_triangle, 64.0 / 1.15, 1e-9);
    for (int k = 0; k < 6; ++k)
        lod_feedback_update(&f, 5.0, 11.0);
    CHECK_NEAR(f.min_px_per_triangle, 64.0 / 1.15 / 1.15 / 1.15, 1e-9);
    /* A rising trend that will cross the budget next frame acts now. */
    lod_feedback_init(&f, 64.0);
    lod_feedback_update(&f, 6.0, 11.0);
    lod_feedback_update(&f, 8.8, 11.0); /* 0.8 now, 11.6 predicted */
    CHECK_NEAR(f.min_px_per_triangle, 64.0 * 1.15 * 1.15, 1e-9);
    /* Bad measurements are ignored. */
    double was = f.min_px_per_triangle;
    lod_feedback_update(&f, NAN, 11.0);
    lod_feedback_update(&f, 5.0, 0.0);
    CHECK(f.min_px_per_triangle == was);
}

/* The affine correction (lod.h): it recovers measured = a + b·x from varied frames; after frames
 * that drew little it does not carry the constant's error over to the objects, as the ratio does;
 * frames that all cost the same do not wind its covariance up. */
static void test_cost_rls(void)
{
    struct lod_cost_rls c;
    lod_cost_rls_init(&c, 2.0, 0.98);
    for (int f = 0; f < 400; ++f) {
        double x = 2.0 + 6.0 * (double)(f % 7) / 6.0;
        lod_cost_rls_update(&c, 4.0 + 1.2 * x, x);
    }
    /* The prior (a tenth of a frame at a = 2, b = 1 against ~50 frames of data) pulls a little. */
    CHECK_NEAR(c.a_ms, 4.0, 0.03);
    CHECK_NEAR(c.b, 1.2, 0.005);
    CHECK_NEAR(lod_cost_rls_objects_budget_ms(&c, 11.0), (11.0 - c.a_ms - lod_cost_rls_margin_ms(&c)) / c.b, 1e-12);
    CHECK(lod_cost_rls_objects_budget_ms(&c, 11.0) > 5.4 && lod_cost_rls_objects_budget_ms(&c, 11.0) < 5.9);

    /* A sparse view, then a dense one. The model under-counts the per-frame constant (c0 2.07 ms,
     * truly 4.4 ms); the sparse view's objects cost 0.5 ms, all of which the optimizer takes. When
     * the view turns to a dense part, what may the objects cost? The truth: 11.1 − 4.4 = 6.7 ms.
     * The ratio (4.9 / 2.57 = 1.9) shrinks the whole budget and leaves them 3.7 ms; the affine fit
     * puts the error where the frames put it, on the constant. */
    const double budget = 11.1, c0 = 2.07, truth_c0 = 4.4, sparse_x = 0.5;
    struct lod_cost_rls affine;
    struct lod_cost_correction ratio;
    lod_cost_rls_init(&affine, c0, 0.98);
    lod_cost_correction_init(&ratio, 0.1);
    for (int f = 0; f < 300; ++f) {
        double jitter = 0.05 * ((f * 7919) % 11 - 5) / 5.0; /* ±0.05 ms */
        lod_cost_rls_update(&affine, truth_c0 + sparse_x + jitter, sparse_x);
        lod_cost_correction_update(&ratio, truth_c0 + sparse_x + jitter, c0 + sparse_x);
    }
    double xa = lod_cost_rls_objects_budget_ms(&affine, budget);
    double xr = fmax(0.0, lod_cost_correction_budget_ms(&ratio, budget) - c0);
    printf("corrections after a sparse view (model c0 %.2f ms, true %.2f ms, budget %.1f ms): the objects may cost "
           "%.2f ms (affine) against %.2f ms (ratio); the truth allows %.2f ms\n", c0, truth_c0, budget, xa, xr,
           budget - truth_c0);
    CHECK(xa <= budget - truth_c0);
    CHECK(xa > budget - truth_c0 - 0.6);
    CHECK(xr < 4.0);

    /* Frame times with a tail: one frame in ten preempted for a 4 ms scheduler tick, the rest within
     * ±0.2 ms. Two standard deviations (≈ 2.4 ms) would let those frames all break the budget; the
     * 97 % quantile of the errors is a tick, so the margin holds them. */
    struct lod_cost_rls tail;
    lod_cost_rls_init(&tail, 2.0, 0.98);
    for (int f = 0; f < 600; ++f) {
        double x = 3.0 + (double)(f % 5);
        double e = f % 10 == 3 ? 4.0 : 0.2 * ((double)((f * 7919) % 11) - 5.0) / 5.0;
        lod_cost_rls_update(&tail, 2.0 + x + e, x);
    }
    double sigma2 = 2.0 * sqrt(tail.residual_var), margin = lod_cost_rls_margin_ms(&tail);
    printf("a tail of 4 ms ticks on 10 %% of the frames: margin %.2f ms (97 %% quantile) against 2 sigma %.2f ms\n",
           margin, sigma2);
    CHECK(margin > 3.0 && margin < 4.5);
    CHECK(sigma2 < margin);

    /* At a 99 % share the margin follows the tail where it continues the body: errors spread evenly
     * over 4 ms (about the fit, ±2 ms) put the 99 % quantile 0.08 ms past the 97 % one. Where it does
     * not — 2 % of the frames preempted for 15 ms on the same body — the margin stays at the 97 %
     * quantile: keeping 15 ms in hand would not save those frames. */
    struct lod_cost_rls even, spikes;
    lod_cost_rls_init(&even, 2.0, 0.98);
    lod_cost_rls_init(&spikes, 2.0, 0.98);
    even.within_share = spikes.within_share = 0.99;
    for (int f = 0; f < 600; ++f) {
        double x = 3.0 + (double)(f % 5);
        double e = 4.0 * (double)((f * 7919) % 193) / 192.0; /* 0 … 4 ms, evenly */
        lod_cost_rls_update(&even, 2.0 + x + e, x);
        lod_cost_rls_update(&spikes, 2.0 + x + (f % 50 == 7 ? 15.0 : e), x);
    }
    double m_even = lod_cost_rls_margin_ms(&even), m_spikes = lod_cost_rls_margin_ms(&spikes);
    even.within_share = spikes.within_share = 0.97;
    double m_even97 = lod_cost_rls_margin_ms(&even), m_spikes97 = lod_cost_rls_margin_ms(&spikes);
    printf("margin at 99 %% (97 %%): even tail %.2f ms (%.2f), 2 %% of 15 ms spikes %.2f ms (%.2f)\n", m_even,
           m_even97, m_spikes, m_spikes97);
    CHECK(m_even > m_even97 + 0.03);
    CHECK(m_spikes == m_spikes97 && m_spikes < 5.0);

    /* The same x every frame: the data fix a + 5·b and nothing else; the prior splits the 2 ms the
     * model missed (9 against c0 2 + 5) 80 : 20 between a and b (prior_x 10 ms: 10² / (10² + 5²)),
     * and it stays there, however many such frames come. */
    struct lod_cost_rls flat;
    lod_cost_rls_init(&flat, 2.0, 0.98);
    for (int f = 0; f < 2000; ++f)
        lod_cost_rls_update(&flat, 9.0, 5.0);
    CHECK_NEAR(flat.a_ms, 2.0 + 0.8 * 2.0, 0.02);
    CHECK_NEAR(flat.b, 1.0 + 0.2 * 2.0 / 5.0, 0.005);
    CHECK_NEAR(flat.a_ms + flat.b * 5.0, 9.0, 5e-3); /* the frames it saw, predicted right but for the prior's pull */
    struct lod_cost_rls keep = flat;
    lod_cost_rls_update(&flat, NAN, 5.0);
    lod_cost_rls_update(&flat, 9.0, -1.0);
    lod_cost_rls_update(&flat, 0.0, 5.0);
    CHECK(flat.a_ms == keep.a_ms && flat.b == keep.b && flat.s1 == keep.s1 && flat.residual_var == keep.residual_var);
    lod_cost_rls_update(&flat, 1e6, 5.0); /* one wild frame: clamped, still a usable budget */
    CHECK(flat.b <= 4.0 && flat.a_ms <= 4.0 * 2.0 + 10.0);
    CHECK(lod_cost_rls_objects_budget_ms(&flat, 11.0) >= 0.0);
    CHECK(lod_cost_rls_objects_budget_ms(&flat, 11.0) <= 11.0 - 2.0);
}

/* One preempted frame (issue 32): on this host one frame in twenty or so runs 3–6 ms late whatever
 * it draws. The first frame fed to the correction was one such (13.0 ms where the model said 8.1
 * and the frames around drew 7.0): fitted alone it set a line through it, the lighter frames after
 * made it steeper, and fs dropped 68 objects for 25 frames; later, one such frame cost 22 objects
 * for 6 frames, and at 32 frames the margin, read as a quantile of 32 errors, was that frame. The
 * frames around a spike say what the machine does; the spike must not decide the next budgets. */
static void test_cost_rls_spike(void)
{
    const double budget = 11.1, c0 = 0.8, x = 7.3;
    struct lod_cost_rls c;
    lod_cost_rls_init(&c, c0, 0.98);
    double before = lod_cost_rls_objects_budget_ms(&c, budget);
    lod_cost_rls_update(&c, 13.0, x); /* the first frame: preempted */
    double after_first = lod_cost_rls_objects_budget_ms(&c, budget), least = after_first;
    for (int f = 1; f < 60; ++f) { /* then the machine as it is: 0.85 of the model, ± 0.2 ms */
        double jitter = 0.2 * ((double)((f * 7919) % 11) - 5.0) / 5.0;
        lod_cost_rls_update(&c, c0 + 0.85 * x + jitter, x);
        least = fmin(least, lod_cost_rls_objects_budget_ms(&c, budget));
    }
    double settled = lod_cost_rls_objects_budget_ms(&c, budget);
    /* The model was truly off, though: the frames' own error is learnt (within 0.3 ms of the truth). */
    CHECK_NEAR(c.a_ms + c.b * x, c0 + 0.85 * x, 0.3);

    /* Steady state on a machine slower than its model (1.15×), so the fit, not the model, sets the
     * budget; then one frame 6 ms late. */
    struct lod_cost_rls slow;
    lod_cost_rls_init(&slow, c0, 0.98);
    for (int f = 0; f < 300; ++f) {
        double xf = 5.0 + (double)(f % 5) * 0.5, jitter = 0.2 * ((double)((f * 7919) % 11) - 5.0) / 5.0;
        lod_cost_rls_update(&slow, c0 + 1.15 * xf + jitter, xf);
    }
    double steady = lod_cost_rls_objects_budget_ms(&slow, budget);
    lod_cost_rls_update(&slow, c0 + 1.15 * x + 6.0, x);
    double after_spike = lod_cost_rls_objects_budget_ms(&slow, budget);
    printf("one preempted frame: objects' budget %.2f ms before the first frame, %.2f after it (a 5 ms spike), least "
           "in the next 60 frames %.2f, at frame 60 %.2f; a machine 1.15x its model: steady %.2f, after a 6 ms spike "
           "%.2f\n", before, after_first, least, settled, steady, after_spike);
    CHECK(after_first >= 0.75 * before);
    CHECK(least >= 0.75 * before); /* not the spike's margin either, when the window holds 32 errors */
    CHECK(steady < budget - c0 - 0.5);
    CHECK(after_spike >= 0.985 * steady); /* a 4σ clip alone: 0.980 */
}

/* A synthetic machine in closed loop (issue 30 item 3): its true fixed cost is twice the model's
 * (5.0 ms against 2.5), its objects cost what the model says. Each frame fs chooses within the
 * corrected objects' budget, the machine "measures" 2·c0 + the chosen cost (± 2 % jitter), and the
 * correction learns from it. The affine correction must settle where the truth is — the objects
 * may cost about 11.1 − 5.0 = 6.1 ms — and stay there; the ratio correction, which divides the
 * whole budget, is run beside it to show the spiral the test guards against: every frame that
 * draws less makes the fixed cost a larger share of the measured frame, so the ratio rises and the
 * objects get less again. */
enum { SYN_OBJECTS = 87, SYN_LEVELS = 4, SYN_SHELL = 7 };
struct synthetic_machine {
    uint32_t id[SYN_OBJECTS], first[SYN_OBJECTS];
    uint8_t count[SYN_OBJECTS], level[SYN_OBJECTS * SYN_LEVELS], choice[SYN_OBJECTS];
    double cost[SYN_OBJECTS * SYN_LEVELS], benefit[SYN_OBJECTS * SYN_LEVELS];
    void *scratch;
};

static void synthetic_problem(struct synthetic_machine *m, size_t visible, double budget_ms, struct lod_problem *p)
{
    for (uint32_t i = 0; i < SYN_OBJECTS; ++i) {
        m->id[i] = i, m->first[i] = i * SYN_LEVELS, m->count[i] = SYN_LEVELS;
        if (i >= SYN_OBJECTS - SYN_SHELL) { /* a room's shell: one level each, fill-bound, worth its pixels */
            m->count[i] = 1;
            m->level[m->first[i]] = 0;
            m->cost[m->first[i]] = 0.6;
            m->benefit[m->first[i]] = 0.6 * 3e5;
            continue;
        }
        double scale = 0.5 + (double)(i % 7) / 6.0; /* objects of different sizes */
        for (int k = 0; k < SYN_LEVELS; ++k) {      /* coarsest first: cost rises, returns fall */
            uint32_t c = i * SYN_LEVELS + (uint32_t)k;
            m->level[c] = (uint8_t)(SYN_LEVELS - 1 - k);
            m->cost[c] = scale * 0.02 * pow(3.0, k);
            m->benefit[c] = scale * 1000.0 * (1.0 - 0.5 * pow(0.3, k));
        }
    }
    *p = (struct lod_problem){visible, m->id, m->first, m->count, m->cost, m->benefit, m->level, budget_ms, 0.0, NULL};
}

/* Runs `frames` frames, the first 100 looking at a sparse part (3 objects), then at
 * everything; returns the objects' budget of the last frame, *first_dense that of the first frame
 * on the dense part, *min_late the least objects' budget after frame 150 and *within the share of
 * frames after frame 50 whose measured time kept the budget. */
struct synthetic_truth {
    double model_c0, true_c0; /* the profile's fixed cost and the machine's */
    double object_scale;      /* what the objects truly cost, × the model's */
    int spike_every;          /* every so many frames one preempted frame, 20 ms late (0: none) */
    double knee_ms;           /* > 0: the objects' model cost past which they cost object_scale_above */
    double object_scale_above;
};

/* What the synthetic machine takes for objects the model prices at x ms. */
static double synthetic_objects_ms(const struct synthetic_truth *t, double x)
{
    if (t->knee_ms <= 0.0 || x <= t->knee_ms)
        return t->object_scale * x;
    return t->object_scale * t->knee_ms + t->object_scale_above * (x - t->knee_ms);
}
static double synthetic_run(int affine, const struct synthetic_truth *t, int frames, double *first_dense,
                            double *min_late, double *within)
{
    const double budget = 11.1, model_c0 = t->model_c0, true_c0 = t->true_c0;
    struct synthetic_machine m;
    m.scratch = malloc(lod_scratch_bytes(SYN_OBJECTS, SYN_OBJECTS * SYN_LEVELS));
    memset(m.choice, 0, sizeof m.choice);
    struct lod_cost_rls rls;
    struct lod_cost_correction ratio;
    lod_cost_rls_init(&rls, model_c0, 0.98);
    lod_cost_correction_init(&ratio, 0.1);
    double objects_ms = 0.0;
    int kept = 0;
    *min_late = INFINITY;
    for (int f = 0; f < frames; ++f) {
        objects_ms = affine ? lod_cost_rls_objects_budget_ms(&rls, budget)
                            : fmax(0.0, lod_cost_correction_budget_ms(&ratio, budget) - model_c0);
        if (f >= 150)
            *min_late = fmin(*min_late, objects_ms);
        if (f == 100)
            *first_dense = objects_ms;
        struct lod_problem p;
        synthetic_problem(&m, f < 100 ? 3 : SYN_OBJECTS, objects_ms, &p);
        struct lod_result r;
        lod_optimize_fs(&p, 0.0, m.scratch, m.choice, &r);
        double jitter = 0.4 * ((double)((f * 7919) % 11) - 5.0) / 5.0; /* ±0.4 ms: other work */
        double measured = true_c0 + synthetic_objects_ms(t, r.cost_ms) + jitter;
        kept += f >= 50 && measured <= budget;
        if (t->spike_every > 0 && f % t->spike_every == t->spike_every - 1)
            measured += 20.0; /* not counted against the budget: no correction can foresee it */
        if (affine)
            lod_cost_rls_update(&rls, measured, r.cost_ms);
        else
            lod_cost_correction_update(&ratio, measured, model_c0 + r.cost_ms);
    }
    *within = (double)kept / (double)(frames - 50);
    free(m.scratch);
    return objects_ms;
}

static void test_cost_correction_no_spiral(void)
{
    double affine_dense, affine_min, affine_within, ratio_dense, ratio_min, ratio_within;
    const struct synthetic_truth twice = {2.5, 5.0, 1.0, 0, 0.0, 0.0};
    double affine_end = synthetic_run(1, &twice, 400, &affine_dense, &affine_min, &affine_within);
    double ratio_end = synthetic_run(0, &twice, 400, &ratio_dense, &ratio_min, &ratio_within);
    printf("synthetic machine, fixed cost twice the model's (5.0 ms against 2.5 ± 0.4), budget 11.1 ms (the truth "
           "allows the objects 6.1 ms): affine — on entering the dense view %.2f ms, least later %.2f, at the end "
           "%.2f, frames within budget %.1f %%; ratio — %.2f, %.2f, %.2f, %.1f %%\n",
           affine_dense, affine_min, affine_end, 100.0 * affine_within, ratio_dense, ratio_min, ratio_end,
           100.0 * ratio_within);
    /* No spiral: once settled the objects keep at least 80 % of what the truth allows, never more
     * than it, and the frames keep the budget (the 2σ margin covers the ±0.4 ms jitter). */
    CHECK(affine_min >= 0.8 * 6.1);
    CHECK(affine_end <= 6.1);
    CHECK(affine_within >= 0.97);
    /* What the sparse view taught: the affine fit put the error on the constant, so the dense view
     * gets the objects' share at once; the ratio learnt "everything costs 1.8×" and shrinks it. */
    CHECK(affine_dense >= 0.8 * 6.1);
    CHECK(ratio_dense < 0.8 * affine_dense);

    /* A full-scale profile at half scale (replay --render-scale 0.5, docs/RESULTS.md issue 30): the
     * model's fixed cost is three times the machine's (1.39 ms against 0.44), the objects cost 1.2×
     * the model, and one frame in 40 is preempted by 20 ms. A clamped recursive-least-squares filter
     * ran b to its bound here and left the objects 1.4 ms of an 11.1 ms frame measured at 3 ms. The
     * truth allows (11.1 − 0.44) / 1.2 = 8.9 ms; the fit must leave at least 70 % of it after the
     * view turns dense (the spikes widen the margin a little, they must not collapse it). */
    const struct synthetic_truth half = {1.39, 0.44, 1.2, 40, 0.0, 0.0};
    double half_dense, half_min, half_within;
    double half_end = synthetic_run(1, &half, 600, &half_dense, &half_min, &half_within);
    printf("synthetic machine, fixed cost a third of the model's, objects 1.2x, a 20 ms spike every 40 frames (the "
           "truth allows the objects 8.9 ms): affine — least after frame 150 %.2f ms, at the end %.2f, frames within "
           "budget %.1f %%\n", half_min, half_end, 100.0 * half_within);
    CHECK(half_min >= 0.7 * 8.9);
    CHECK(half_end <= 8.9);
    CHECK(half_within >= 0.97);
}

/* A machine faster than its model (issue 32: the built-in llvmpipe profile, measured on a slower
 * day, priced the auditorium's frames at three times what they took, and fs coarsened objects by
 * the gaze to fit a budget it was using 40 % of). The fit may loosen the model's budget, by at most
 * LOD_COST_RLS_LOOSEN_MAX and only once LOD_COST_RLS_LOOSEN_AFTER frames are in: its slope is
 * learnt from the loads drawn so far, and a load beyond them may cost more per model millisecond —
 * unbounded, a slope learnt at a periphery scale of 0.25 priced 0.5 and the frames ran away. */
static void test_cost_correction_loosens(void)
{
    const double budget = 11.1, model_c0 = 1.1, model_objects = budget - model_c0;
    struct lod_cost_rls c;
    lod_cost_rls_init(&c, model_c0, 0.98);
    int f = 0;
    for (; f < LOD_COST_RLS_LOOSEN_AFTER - 1; ++f) {
        double x = 6.0 + (double)(f % 5) * 0.5, jitter = 0.2 * ((double)((f * 7919) % 11) - 5.0) / 5.0;
        lod_cost_rls_update(&c, 0.9 + 0.35 * x + jitter, x);
        CHECK(lod_cost_rls_objects_budget_ms(&c, budget) <= model_objects + 1e-12); /* not yet */
    }
    lod_cost_rls_update(&c, 0.9 + 0.35 * 7.0, 7.0);
    double loosened = lod_cost_rls_objects_budget_ms(&c, budget);
    CHECK_NEAR(loosened, LOD_COST_RLS_LOOSEN_MAX * model_objects, 1e-9); /* the fit allows 29 ms: capped */
    CHECK(lod_cost_rls_objects_expected_ms(&c, budget) <= LOD_COST_RLS_LOOSEN_MAX * model_objects + 1e-9);

    /* In closed loop: uniformly fast (objects 0.35× the model, fixed cost 0.9 against 1.1), and fast
     * only up to a knee (past 8 ms of the model's price each millisecond costs 1.0: the truth allows
     * 8 + (11.1 − 0.9 − 2.8) = 15.4 ms of model cost, the cap 15.0) or steeply past it (2.0: the truth
     * allows 11.7, below the cap — the fit must find the knee's slope from the late frames). */
    const struct synthetic_truth fast = {model_c0, 0.9, 0.35, 0, 0.0, 0.0};
    const struct synthetic_truth knee = {model_c0, 0.9, 0.35, 0, 8.0, 1.0};
    const struct synthetic_truth steep = {model_c0, 0.9, 0.35, 0, 8.0, 2.0};
    double dense, least, within, end;
    end = synthetic_run(1, &fast, 400, &dense, &least, &within);
    printf("synthetic machine 0.35x its model: objects' budget %.2f ms at frame 100, least after 150 %.2f, at the "
           "end %.2f (the model's %.2f), within %.1f %%\n", dense, least, end, model_objects, 100.0 * within);
    CHECK_NEAR(end, LOD_COST_RLS_LOOSEN_MAX * model_objects, 1e-9);
    CHECK(least >= model_objects);
    CHECK(within >= 0.99);
    end = synthetic_run(1, &knee, 400, &dense, &least, &within);
    printf("the same, 1.0x past a knee at 8 ms (the truth allows 15.4): %.2f, %.2f, %.2f, within %.1f %%\n", dense,
           least, end, 100.0 * within);
    CHECK(end <= 15.4);
    CHECK(within >= 0.97);
    end = synthetic_run(1, &steep, 400, &dense, &least, &within);
    printf("the same, 2.0x past the knee (the truth allows 11.7): %.2f, %.2f, %.2f, within %.1f %%\n", dense, least,
           end, 100.0 * within);
    CHECK(end <= 11.7);
    CHECK(least >= 0.8 * 11.7);
    CHECK(within >= 0.97);
}

/* Drop last, and never what the caller keeps (issue 30 item 4): a room's shell — three one-level
 * objects of 2 ms each, worth their pixels — and twenty chairs at 0.03–0.8 ms. Under a budget the
 * coarsest of everything does not fit, the chairs are cheaper per benefit, and without `keep` the
 * drop-to-fit takes out shell pieces first... with it, the shell stays and the chairs make room;
 * with a budget that cannot hold even the shell, the shell still stays (the frame runs late) and
 * everything else goes. fs and the greedy agree. */
static void test_keep(void)
{
    enum { N = 23, SHELL = 3, LV = 2 };
    uint32_t id[N], first[N];
    uint8_t count[N], level[N * LV], keep[N], choice_fs[N], choice_g[N];
    double cost[N * LV], benefit[N * LV];
    uint32_t c = 0;
    for (uint32_t i = 0; i < N; ++i) {
        id[i] = i, first[i] = c, keep[i] = i < SHELL;
        if (i < SHELL) { /* fill-bound: 2 ms for 1e6 pixels of benefit */
            count[i] = 1, level[c] = 0, cost[c] = 2.0, benefit[c] = 1e6 * 0.9;
            ++c;
            continue;
        }
        count[i] = LV;
        double s = 1.0 + (double)(i % 4);
        level[c] = 1, cost[c] = 0.03 * s, benefit[c] = 2e4 * s * 0.9; /* 6e5 per ms: more than the shell's 4.5e5 */
        level[c + 1] = 0, cost[c + 1] = 0.2 * s, benefit[c + 1] = 2e4 * s;
        c += 2;
    }
    void *scratch = malloc(lod_scratch_bytes(N, c));
    const double budgets[] = {7.0, 1.0}; /* the coarsest of all: 6 + 1.5 ms */
    for (int b = 0; b < 2; ++b) {
        for (int with_keep = 0; with_keep < 2; ++with_keep) {
            struct lod_problem p = {N, id, first, count, cost, benefit, level, budgets[b], 0.0, with_keep ? keep : NULL};
            struct lod_result rf, rg;
            memset(choice_fs, 0, sizeof choice_fs);
            lod_optimize_fs(&p, 0.0, scratch, choice_fs, &rf);
            lod_optimize_greedy(&p, scratch, choice_g, &rg);
            CHECK(memcmp(choice_fs, choice_g, sizeof choice_fs) == 0);
            int shell_drawn = 0, chairs_drawn = 0;
            for (uint32_t i = 0; i < N; ++i)
                (i < SHELL ? &shell_drawn : &chairs_drawn)[0] += choice_fs[i] != LOD_DROPPED;
            printf("keep: budget %.1f ms, %s: shell %d of %d drawn, chairs %d of %d, cost %.2f ms\n", budgets[b],
                   with_keep ? "shell kept" : "nothing kept", shell_drawn, SHELL, chairs_drawn, N - SHELL, rf.cost_ms);
            if (with_keep) {
                CHECK(shell_drawn == SHELL);
                CHECK(b == 0 ? rf.cost_ms <= budgets[b] + 1e-9 : chairs_drawn == 0);
            } else {
                CHECK(shell_drawn < SHELL); /* what the test guards against */
                CHECK(rf.cost_ms <= budgets[b] + 1e-9);
            }
        }
    }
    free(scratch);
}

int main(void)
{
    test_select_reddy();
    test_select_contrast();
    test_select_contrast_hard_cases();
    test_perceptual_benefit();
    test_cost_correction();
    test_cost_correction_no_spiral();
    test_cost_correction_loosens();
    test_feedback();
    test_cost_rls();
    test_cost_rls_spike();
    test_keep();
    return tu_finish("test_lod");
}
