/* Benefit (Funkhouser & Séquin 1993 §5), with Reddy's acuity (1998 §3.3) as the perceptual ceiling in
 * place of the paper's ad-hoc Focus and Motion factors; or the perceptual benefit, valued by the
 * visible contrast a level keeps (issue 31 item 4; docs/optimizer.md "Perceptual benefit"). */
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

double lod_benefit_accuracy(const struct lod_benefit_params *p, double samples, double size_px)
{
    return accuracy(p, samples, size_px, 0);
}

static int levels_changed(uint8_t level, uint8_t previous)
{
    if (previous == LOD_UNSEEN)
        return 0;
    int a = level == LOD_DROP ? LOD_MAX_LEVELS : level;
    int b = previous == LOD_DROP ? LOD_MAX_LEVELS : previous;
    return abs(a - b);
}

/* The perceptual benefit's accuracy: 1 − √(D·(1 + h·|ΔL|) / LOD_PERCEPTUAL_LOSS_WHOLE), at least 0.
 * D is the lost contrast in threshold units; what is seen of a contrast above threshold grows
 * compressively, about as its square root (the contrast transducer of Legge & Foley 1980), so a
 * loss four times another counts twice, however large both are. The form 1 / (1 + D) before it
 * counted every D ≫ 1 as the whole object: the chairs by the gaze (D 210–840 at level 1) weighed no
 * more than those 40° out (16–43), and fs sent its finest triangles to the far periphery
 * (docs/RESULTS.md, issue 32 eleventh round). Hysteresis scales the visible loss as it scales
 * Funkhouser's error. */
double lod_benefit_perceptual_accuracy(double loss)
{
    double t = sqrt(fmax(0.0, loss) / LOD_PERCEPTUAL_LOSS_WHOLE);
    return t >= 1.0 ? 0.0 : 1.0 - t;
}

static double perceptual_accuracy(const struct lod_benefit_params *p, double loss, int levels_changed)
{
    return lod_benefit_perceptual_accuracy(loss * (1.0 + p->hysteresis_per_level * levels_changed));
}

static double level_accuracy(const struct lod_benefit_params *p, const double *loss_row, uint8_t level,
                             uint32_t samples, double size_px, uint8_t previous)
{
    int changed = levels_changed(level, previous);
    if (loss_row && !isnan(loss_row[0]) && level < LOD_MAX_LEVELS)
        return perceptual_accuracy(p, loss_row[level], changed);
    return accuracy(p, samples, size_px, changed);
}

void lod_benefit_fill(const struct lod_benefit_params *p, size_t object_count, const uint32_t *first,
                      const uint8_t *count, const uint8_t *level, const uint32_t *samples,
                      const double *size_px, const double *importance, const uint8_t *ceiling_level,
                      const uint8_t *previous_level, const double *visible_loss, double *benefit)
{
    for (size_t i = 0; i < object_count; ++i) {
        double weight = size_px[i] * (importance ? importance[i] : 1.0);
        const double *loss = visible_loss ? visible_loss + i * LOD_MAX_LEVELS : NULL;
        uint32_t c0 = first[i];
        /* The ceiling level's own benefit first: finer levels earn exactly that and no more. */
        double ceiling_benefit = -1.0;
        for (uint32_t c = c0; c < c0 + count[i]; ++c)
            if (level[c] == ceiling_level[i])
                ceiling_benefit = weight * level_accuracy(p, loss, level[c], samples[c], size_px[i], previous_level[i]);
        for (uint32_t c = c0; c < c0 + count[i]; ++c) {
            if (level[c] == LOD_DROP) {
                benefit[c] = 0.0;
            } else if (level[c] < ceiling_level[i] && ceiling_benefit >= 0.0) {
                benefit[c] = ceiling_benefit; /* detail beyond the acuity limit is invisible */
            } else {
                benefit[c] = weight * level_accuracy(p, loss, level[c], samples[c], size_px[i], previous_level[i]);
            }
        }
    }
}
