/* Benefit (Funkhouser & Séquin 1993 §5), with Reddy's acuity (1998 §3.3) as the perceptual ceiling in
 * place of the paper's ad-hoc Focus and Motion factors. */
#include <math.h>
#include <stdlib.h>

#include "lod/lod.h"

void lod_benefit_params_default(struct lod_benefit_params *p)
{
    p->base_error = 0.5;
    p->exponent_m = 2.0;
    p->hysteresis_per_level = 1.0;
}

/* §5: Accuracy = 1 − BaseError / Samples^m, Samples never more than the pixels covered.
 * Hysteresis (§5, a factor that falls with the change of level) is applied to the error term, not
 * to the whole benefit: real chains have Samples in the tens to thousands, so the accuracy of
 * neighbouring levels differs by 10⁻⁵–10⁻³, and a multiplicative 1 − h·|ΔL| on the benefit would
 * dwarf every detail difference and freeze the levels. Here a level |ΔL| away from last frame's
 * counts its error (1 + h·|ΔL|) times: a change must remove more error than it costs in popping. */
static double accuracy(const struct lod_benefit_params *p, double samples, double size_px, int levels_changed)
{
    double s = fmax(fmin(samples, size_px), 1.0);
    double power = p->exponent_m == 2.0 ? s * s : p->exponent_m == 1.0 ? s : pow(s, p->exponent_m); /* pow is slow */
    double error = p->base_error / power * (1.0 + p->hysteresis_per_level * levels_changed);
    return fmax(0.0, 1.0 - error);
}

static int levels_changed(uint8_t level, uint8_t previous)
{
    if (previous == LOD_UNSEEN)
        return 0;
    int a = level == LOD_DROP ? LOD_MAX_LEVELS : level;
    int b = previous == LOD_DROP ? LOD_MAX_LEVELS : previous;
    return abs(a - b);
}

void lod_benefit_fill(const struct lod_benefit_params *p, size_t object_count, const uint32_t *first,
                      const uint8_t *count, const uint8_t *level, const uint32_t *samples,
                      const double *size_px, const double *importance, const uint8_t *ceiling_level,
                      const uint8_t *previous_level, double *benefit)
{
    for (size_t i = 0; i < object_count; ++i) {
        double weight = size_px[i] * (importance ? importance[i] : 1.0);
        uint32_t c0 = first[i];
        /* The ceiling level's own benefit first: finer levels earn exactly that and no more. */
        double ceiling_benefit = -1.0;
        for (uint32_t c = c0; c < c0 + count[i]; ++c)
            if (level[c] == ceiling_level[i])
                ceiling_benefit = weight * accuracy(p, samples[c], size_px[i], levels_changed(level[c], previous_level[i]));
        for (uint32_t c = c0; c < c0 + count[i]; ++c) {
            if (level[c] == LOD_DROP) {
                benefit[c] = 0.0;
            } else if (level[c] < ceiling_level[i] && ceiling_benefit >= 0.0) {
                benefit[c] = ceiling_benefit; /* detail beyond the acuity limit is invisible */
            } else {
                benefit[c] = weight * accuracy(p, samples[c], size_px[i], levels_changed(level[c], previous_level[i]));
            }
        }
    }
}
