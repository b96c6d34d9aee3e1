/* lod: which representation each object gets — the selectors (none, reddy; static, feedback and the
 * cost-bounded optimizers to come). Prefix lod_. Pure arrays in and out: no GL, no files, no
 * allocation; the acuity limits come from acuity/. Together with acuity/ it is the part an engine
 * embeds. */
#ifndef HMDLOD_LOD_H
#define HMDLOD_LOD_H

#include "acuity/acuity.h"

/* ---- selectors without a cost model ------------------------------------------------------------
 * A chain of LODs, 0 = finest. unique_freq_cpdiam[k] (k ≥ 1) is the spatial frequency of the most
 * visible detail present in LOD k−1 and lost in LOD k, in cycles per object diameter (Reddy §3.2;
 * measured from renders, docs/analysis.md); it falls strictly as k rises. At run time
 * f[c/deg] = f[cycles/diameter] / angular diameter[deg]. Level 0 holds +INFINITY. */
enum { LOD_MAX_LEVELS = 8 };
struct lod_chain {
    int lod_count;
    double unique_freq_cpdiam[LOD_MAX_LEVELS];
};

struct lod_select_stats {
    uint64_t model_evaluations; /* objects whose H(v,E) was computed */
    uint64_t model_skips;       /* objects inside the H ≥ ξ region */
};

/* Reddy's selector: per object the coarsest LOD whose every removed frequency lies above the
 * acuity limit (so nothing the viewer can resolve is dropped). Inputs are the visible objects'
 * arrays, position-ordered (count entries; index[k] is the scene object, chain_of_object is indexed
 * by it). Writes lod_out[k] and, when not NULL, the limit used ceiling_cpd_out[k] (c/deg); adds to
 * *stats when not NULL. O(count · levels), no allocation. */
void lod_select_reddy(const struct acu_limits *lim, const struct lod_chain *chains,
                      const uint32_t *chain_of_object, const uint32_t *index, size_t count,
                      const double *eccentricity_deg, const double *retinal_velocity_degps,
                      const double *angular_diameter_deg, uint8_t *lod_out, double *ceiling_cpd_out,
                      struct lod_select_stats *stats);

/* The `none` baseline: finest LOD for every listed object. */
void lod_select_finest(size_t count, uint8_t *lod_out);

#endif
