/* LOD selectors that need no cost model: `none` (finest) and Reddy's perceptual selector. */
#include "lod/lod.h"

#include <math.h>
#include <string.h>

void lod_select_finest(size_t count, uint8_t *lod_out) { memset(lod_out, 0, count); }

/* Reddy 1998 §3.3 online stage: the LOD "whose highest unique spatial frequency lies immediately
 * below the limit of vision". Level k drops the detail of frequencies f_1 … f_k (f falls with k),
 * so level k is safe while its lowest dropped frequency f_k (in c/deg at the object's current
 * angular size) is still above the acuity limit. */
static int reddy_level(const struct lod_chain *chain, double limit_cpd, double diameter_deg)
{
    if (!(diameter_deg > 0.0))
        return chain->lod_count - 1; /* a point: nothing of it is resolvable */
    /* f[c/deg] > limit  ⇔  f[cycles/diameter] > limit · diameter[deg]: no division per level. */
    double limit_cpdiam = limit_cpd * diameter_deg;
    int lod = 0;
    while (lod + 1 < chain->lod_count && chain->unique_freq_cpdiam[lod + 1] > limit_cpdiam)
        ++lod;
    return lod;
}

void lod_select_reddy(const struct acu_limits *lim, const struct lod_chain *chains,
                      const uint32_t *chain_of_object, const uint32_t *index, size_t count,
                      const double *eccentricity_deg, const double *retinal_velocity_degps,
                      const double *angular_diameter_deg, uint8_t *lod_out, double *ceiling_cpd_out,
                      struct lod_select_stats *stats)
{
    uint64_t evaluations = 0;
    for (size_t k = 0; k < count; ++k) {
        const struct lod_chain *chain = &chains[chain_of_object[index[k]]];
        double limit_cpd = acu_limit_cpd(lim, retinal_velocity_degps[k], eccentricity_deg[k], &evaluations);
        lod_out[k] = (uint8_t)reddy_level(chain, limit_cpd, angular_diameter_deg[k]);
        if (ceiling_cpd_out)
            ceiling_cpd_out[k] = limit_cpd;
    }
    if (stats) {
        stats->model_evaluations += evaluations;
        stats->model_skips += count - evaluations;
    }
}

/* The bands of a chain's spectrum that are read: band_count clamped to 0 … LOD_MAX_BANDS. */
static int chain_bands(const struct lod_chain *chain)
{
    return chain->band_count < 0 ? 0 : chain->band_count < LOD_MAX_BANDS ? chain->band_count : LOD_MAX_BANDS;
}

/* The contrast criterion for one object with a spectrum: the coarsest level whose every lost band is
 * invisible. Levels are judged against level 0, each on its own (a coarser level that passes is
 * taken even if a finer one measured worse). A band's sensitivity is the same for every level, so it
 * is looked up once, when a level first needs it; bands the display cannot show are never visible
 * and never looked up. */
static int contrast_level(const struct acu_contrast_limits *vis, double log10_k, const struct lod_chain *chain,
                          double velocity_degps, double eccentricity_deg, double diameter_deg, uint64_t *lookups)
{
    int bands = chain_bands(chain);
    struct acu_contrast_object obj;
    acu_contrast_object_init(vis, diameter_deg, velocity_degps, eccentricity_deg, bands, &obj);
    double log10_s[LOD_MAX_BANDS];
    unsigned looked_up = 0; /* bit b: log10_s[b] is set */
    for (int l = chain->lod_count - 1; l > 0; --l) {
        int visible = 0;
        for (int b = 0; b < obj.displayable_bands && !visible; ++b) {
            double c = chain->lost_contrast[l][b];
            if (c == 0.0)
                continue; /* nothing lost in this band */
            if (!(looked_up & (1u << b))) {
                log10_s[b] = acu_contrast_object_log10_s(vis, &obj, b);
                looked_up |= 1u << b;
                ++*lookups;
            }
            visible = acu_csf_band_visible_log10(c, log10_s[b], vis->k_scale, log10_k);
        }
        if (!visible)
            return l;
    }
    return 0;
}

void lod_select_contrast(const struct acu_contrast_limits *vis, const struct acu_limits *lim,
                         const struct lod_chain *chains, const uint32_t *chain_of_object, const uint32_t *index,
                         size_t count, const double *eccentricity_deg, const double *retinal_velocity_degps,
                         const double *angular_diameter_deg, uint8_t *lod_out, struct lod_select_stats *stats)
{
    uint64_t lookups = 0, evaluations = 0, without = 0;
    double xi_cpdiam_per_deg = vis->xi_cpd * vis->scale; /* a band at f c/diam is displayable iff f/D ≤ ξ·s */
    double log10_k = log10(vis->k_scale);
    for (size_t k = 0; k < count; ++k) {
        const struct lod_chain *chain = &chains[chain_of_object[index[k]]];
        double diameter_deg = angular_diameter_deg[k];
        uint64_t before = lookups;
        int lod;
        if (!(diameter_deg > 0.0)) {
            lod = chain->lod_count - 1; /* a point: nothing of it is resolvable (as Reddy's) */
        } else {
            int bands = chain_bands(chain);
            lod = bands > 0 ? contrast_level(vis, log10_k, chain, retinal_velocity_degps[k], eccentricity_deg[k],
                                             diameter_deg, &lookups)
                            : 0;
            /* What the spectrum did not measure, above its last band, may be displayable: then it
             * cannot vouch for the object alone, and Reddy's reading holds it at least as fine. */
            if (bands == 0 || (double)(1u << bands) <= xi_cpdiam_per_deg * diameter_deg) {
                double limit_cpd = acu_limit_cpd(lim, retinal_velocity_degps[k], eccentricity_deg[k], &evaluations);
                int reddy = reddy_level(chain, limit_cpd, diameter_deg);
                lod = bands > 0 && lod < reddy ? lod : reddy;
            }
        }
        without += lookups == before;
        lod_out[k] = (uint8_t)lod;
    }
    if (stats) {
        stats->model_evaluations += lookups + evaluations;
        stats->model_skips += without;
    }
}

void lod_visible_loss_contrast(const struct acu_contrast_limits *vis, const struct lod_chain *chains,
                               const uint32_t *chain_of_object, const uint32_t *index, size_t count,
                               const double *eccentricity_deg, const double *retinal_velocity_degps,
                               const double *angular_diameter_deg, double *visible_loss,
                               struct lod_select_stats *stats)
{
    uint64_t lookups = 0, without = 0;
    double log10_k = log10(vis->k_scale);
    for (size_t k = 0; k < count; ++k) {
        const struct lod_chain *chain = &chains[chain_of_object[index[k]]];
        double *row = visible_loss + k * LOD_MAX_LEVELS;
        memset(row, 0, LOD_MAX_LEVELS * sizeof *row);
        int bands = chain_bands(chain);
        double diameter_deg = angular_diameter_deg[k];
        if (bands == 0) {
            for (int l = 0; l < LOD_MAX_LEVELS; ++l)
                row[l] = NAN;
            ++without;
            continue;
        }
        if (!(diameter_deg > 0.0)) {
            ++without;
            continue; /* a point: nothing of it is visible, whatever the level */
        }
        struct acu_contrast_object obj;
        acu_contrast_object_init(vis, diameter_deg, retinal_velocity_degps[k], eccentricity_deg[k], bands, &obj);
        without += obj.displayable_bands == 0;
        for (int b = 0; b < obj.displayable_bands; ++b) {
            double log10_s = acu_contrast_object_log10_s(vis, &obj, b);
            ++lookups;
            /* c·S·k − 1 = 10^(log10 c + log10 S + log10 k) − 1: once per band, the power per level. */
            double sk = pow(10.0, log10_s + log10_k);
            for (int l = 1; l < chain->lod_count && l < LOD_MAX_LEVELS; ++l) {
                double c = chain->lost_contrast[l][b];
                if (isnan(c))
                    row[l] += 1.0;
                else if (fabs(c) * sk > 1.0)
                    row[l] += fabs(c) * sk - 1.0;
            }
        }
    }
    if (stats) {
        stats->model_evaluations += lookups;
        stats->model_skips += without;
    }
}

/* Funkhouser & Séquin 1993 §7 "Static": the average triangle of the chosen level covers at least the
 * threshold; finer levels have more, smaller triangles, so walk from the finest until it holds. */
void lod_select_static(double min_px_per_triangle, const uint32_t *triangles, const uint8_t *lod_count,
                       const uint32_t *chain_of_object, const uint32_t *index, size_t count,
                       const double *pixels_px, uint8_t *lod_out)
{
    for (size_t k = 0; k < count; ++k) {
        uint32_t c = chain_of_object[index[k]];
        int levels = lod_count[c] > 0 ? lod_count[c] : 1;
        int lod = 0;
        while (lod + 1 < levels && pixels_px[k] < min_px_per_triangle * (double)triangles[c * LOD_MAX_LEVELS + lod])
            ++lod;
        lod_out[k] = (uint8_t)lod;
    }
}
