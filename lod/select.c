/* LOD selectors that need no cost model: `none` (finest) and Reddy's perceptual selector. */
#include "lod/lod.h"

#include <string.h>

void lod_select_finest(size_t count, uint8_t *lod_out) { memset(lod_out, 0, count); }

/* Reddy 1998 §3.3 online stage: the LOD "whose highest unique spatial frequency lies immediately
 * below the limit of vision". Level k drops the detail of frequencies f_1 … f_k (f falls with k),
 * so level k is safe while its lowest dropped frequency f_k (in c/deg at the object's current
 * angular size) is still above the acuity limit. */
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
        double diameter_deg = angular_diameter_deg[k];
        int lod = 0;
        if (diameter_deg > 0.0) {
            /* f[c/deg] > limit  ⇔  f[cycles/diameter] > limit · diameter[deg]: no division per level. */
            double limit_cpdiam = limit_cpd * diameter_deg;
            while (lod + 1 < chain->lod_count && chain->unique_freq_cpdiam[lod + 1] > limit_cpdiam)
                ++lod;
        } else {
            lod = chain->lod_count - 1; /* a point: nothing of it is resolvable */
        }
        lod_out[k] = (uint8_t)lod;
        if (ceiling_cpd_out)
            ceiling_cpd_out[k] = limit_cpd;
    }
    if (stats) {
        stats->model_evaluations += evaluations;
        stats->model_skips += count - evaluations;
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
