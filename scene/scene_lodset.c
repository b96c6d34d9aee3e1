/* A lodset (an asset: lodgen's output, a .lod file) becomes one chain of a scene: its levels go
 * into the shared vertex and index arrays like the built-in chains, and its measured errors,
 * frequency table and lost-contrast spectrum are copied rather than recomputed. */
#include "scene/scene_internal.h"

#include <math.h>

int scn_scene_add_lodset(struct scn_scene *s, const char *name, const struct scn_lodset *set,
                         struct hl_error *err)
{
    if (!s || !set)
        return hl_fail(err, "scene: add lodset: no scene or no lodset");
    if (!name)
        name = "lodset";
    if (set->level_count < 1 || set->level_count > SCN_MAX_LODS)
        return hl_fail(err, "scene: lodset %s: %d levels (1…%d)", name, set->level_count, SCN_MAX_LODS);
    for (int l = 0; l < set->level_count; ++l) {
        char what[96];
        snprintf(what, sizeof what, "scene: lodset %s: level %d", name, l);
        if (scn_mesh_check(&set->levels[l], what, err) != 0)
            return -1;
        if (l > 0 && set->levels[l].index_count >= set->levels[l - 1].index_count)
            return hl_fail(err, "scene: lodset %s: level %d has %u triangles, not fewer than level %d", name, l,
                           set->levels[l].index_count / 3, l - 1);
    }
    if (!isfinite(set->center_m[0]) || !isfinite(set->center_m[1]) || !isfinite(set->center_m[2]) ||
        !(set->radius_m >= 0) || !isfinite(set->radius_m))
        return hl_fail(err, "scene: lodset %s: bounding sphere is not finite", name);
    if (set->contrast_band_count < 0 || set->contrast_band_count > SCN_LODSET_MAX_BANDS)
        return hl_fail(err, "scene: lodset %s: %d contrast bands (0…%d)", name, set->contrast_band_count,
                       SCN_LODSET_MAX_BANDS);
    if (scn_scene_pack_chain(s, name, set->levels, set->level_count, err) != 0)
        return -1;
    struct scn_chain *c = &s->chains[s->chain_count - 1];
    /* The sphere about the lodset's own centre, not the model origin (an off-centre model would get
     * a needlessly large one); grown, if need be, to hold every level's vertices, since a
     * simplifier may move a vertex outside the finest level's sphere and any level may be drawn. */
    double r = set->radius_m;
    for (int l = 0; l < set->level_count; ++l) {
        const struct scn_mesh *m = &set->levels[l];
        for (uint32_t i = 0; i < m->vertex_count; ++i) {
            const float *q = m->positions + 3 * (size_t)i;
            double d = hl_v3_length(hl_v3_sub(hl_v3(q[0], q[1], q[2]),
                                              hl_v3(set->center_m[0], set->center_m[1], set->center_m[2])));
            r = d > r ? d : r;
        }
    }
    for (int k = 0; k < 3; ++k)
        c->bound_center_m[k] = set->center_m[k];
    c->bound_radius_m = r;
    c->analysis_views = set->analysis_views;
    c->analysis_size_px = set->analysis_size_px;
    /* The spectrum travels as measured (NaN bands included); unused bands stay 0 so that a chain
     * never shows a value its asset did not hold. */
    c->contrast_band_count = set->contrast_band_count;
    c->contrast_percentile = set->contrast_band_count ? set->contrast_percentile : 0.0;
    for (int l = 0; l < set->level_count; ++l) {
        struct scn_lod *lod = &c->lods[l];
        lod->geometric_error_m = set->error_m[l];
        lod->freq = set->freq[l];
        for (int b = 0; b < SCN_LODSET_MAX_BANDS; ++b)
            lod->lost_contrast[b] = b < set->contrast_band_count ? set->lost_contrast[l][b] : 0.0;
        /* The geometric reading for now (`hmdlod analyze` chooses among the readings later); a
         * lodset that lacks it gets R/ε like the built-in chains, and the same strict decrease. */
        double f = set->freq[l].geometric_cpdiam;
        if (isnan(f))
            f = scn_lod_unique_freq(set->error_m[l], r);
        if (l > 0 && !(f < c->lods[l - 1].unique_freq_cpdiam))
            f = c->lods[l - 1].unique_freq_cpdiam * (1.0 - 1e-6);
        lod->unique_freq_cpdiam = f;
    }
    return 0;
}
