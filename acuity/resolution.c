/* The perceptual ceiling of resolution (issue 32, DESIGN.md step 5): beyond which eccentricity an
 * image may lose everything above a frequency without a visible change. The layers' periphery at
 * scale s displays up to s·ξ; detail above it is lost there, and is invisible where no band above
 * s·ξ reaches the threshold. Under the contrast criterion the CSF is separable in eccentricity,
 * S(ρ, ω, E) = S(ρ, ω, 0)·10^(−(e_a + ρ·e_f)·E) (stelaCSF and castleCSF alike, PAPERS.md §6), so the
 * eccentricity at which a band of contrast c falls to threshold has a closed form per band. */
#include <math.h>

#include "acuity/acuity.h"

/* Bands sampled per octave between the target and ξ: the table's own node spacing (csf.h). */
#define RESOLUTION_BANDS_PER_OCTAVE 8.0

double acu_contrast_resolution_eccentricity_deg(const struct acu_contrast_limits *lim, double contrast,
                                                double velocity_degps, double target_cpd)
{
    if (!(target_cpd > 0.0) || !(contrast > 0.0))
        return target_cpd > 0.0 ? 0.0 : INFINITY; /* no contrast: nothing to see; no target: all */
    const struct acu_csf_table *t = lim->csf;
    double v = lim->use_velocity ? fabs(velocity_degps) : 0.0;
    double log10_ck = log10(contrast * lim->k_scale);
    double worst = 0.0;
    /* ρ from the target up to the highest displayable band (ρ/s ≤ ξ), and ξ·s itself. */
    double top = lim->xi_cpd * lim->scale;
    if (target_cpd >= top)
        return 0.0;
    double octaves = log2(top / target_cpd);
    int steps = (int)ceil(octaves * RESOLUTION_BANDS_PER_OCTAVE);
    for (int i = 0; i <= steps; ++i) {
        double rho_cpd = i == steps ? top : target_cpd * exp2((double)i / RESOLUTION_BANDS_PER_OCTAVE);
        double rho = rho_cpd / lim->scale; /* Reddy §6 s, as acu_contrast_band_sensitivity */
        double log10_s0 = log10(acu_csf_table_lookup(t, rho, rho * v, 0.0));
        double excess = log10_s0 + log10_ck; /* > 0: visible at the fovea */
        if (!(excess > 0.0))
            continue;
        if (!lim->use_eccentricity)
            return INFINITY; /* seen at the gaze, and eccentricity is not modelled */
        double slope = t->ecc_a + rho * t->ecc_f; /* log10 S lost per degree */
        double e = slope > 0.0 ? excess / slope : INFINITY;
        worst = e > worst ? e : worst;
    }
    return worst;
}

double acu_resolution_eccentricity_deg(const struct acu_limits *lim, double velocity_degps, double target_cpd)
{
    if (!(target_cpd > 0.0))
        return INFINITY;
    if (target_cpd >= lim->xi_cpd * lim->scale)
        return 0.0; /* min(H, ξ)·s never exceeds it */
    double g = acu_velocity_factor_cpd(lim->use_velocity ? velocity_degps : 0.0) * lim->scale;
    if (!(g > target_cpd))
        return 0.0; /* motion alone keeps H·s at or below the target everywhere */
    if (!lim->use_eccentricity)
        return INFINITY;
    /* H(v, E)·s = G(v)·M(E)·s ≤ target ⇔ H(0, E) = 60·M(E) ≤ 60·target / (G(v)·s) (Reddy eqs. 1–3). */
    return acu_eccentricity_at_acuity_deg(acu_acuity_cpd(0.0, 0.0) * target_cpd / g);
}
