/* Reddy 1998 §2–4: the visual acuity model H(v, E) = G(v)·M(E) and its inverses. */
#include "acuity/acuity.h"

#include <math.h>

/* Reddy 1998 eq. 2 constants: G(v) = 60 for v ≤ 0.825 deg/s, else −27.78·log10(v) + 57.69. */
#define REDDY_G_MAX_CPD 60.0
#define REDDY_G_KNEE_DEGPS 0.825
#define REDDY_G_SLOPE 27.78
#define REDDY_G_OFFSET 57.69
/* Reddy 1998 eq. 3: M(E) = 1 for E ≤ 5.79°, else 7.49 / (0.3·E + 1)². */
#define REDDY_M_KNEE_DEG 5.79
#define REDDY_M_NUM 7.49
#define REDDY_M_SLOPE 0.3

double acu_velocity_factor_cpd(double velocity_degps)
{
    double v = fabs(velocity_degps);
    if (v <= REDDY_G_KNEE_DEGPS)
        return REDDY_G_MAX_CPD;
    double g = REDDY_G_OFFSET - REDDY_G_SLOPE * log10(v);
    /* G reaches 0 near 119.3 deg/s and would go negative: nothing is resolvable beyond it. */
    return g > 0.0 ? g : 0.0;
}

double acu_eccentricity_factor(double eccentricity_deg)
{
    double e = eccentricity_deg < 0.0 ? 0.0 : eccentricity_deg > 180.0 ? 180.0 : eccentricity_deg;
    if (e <= REDDY_M_KNEE_DEG)
        return 1.0;
    double d = REDDY_M_SLOPE * e + 1.0;
    return REDDY_M_NUM / (d * d);
}

double acu_acuity_cpd(double velocity_degps, double eccentricity_deg)
{
    return acu_velocity_factor_cpd(velocity_degps) * acu_eccentricity_factor(eccentricity_deg);
}

int acu_check_inputs(double velocity_degps, double eccentricity_deg, struct hl_error *err)
{
    if (isnan(velocity_degps))
        return hl_fail(err, "velocity: not a number");
    if (velocity_degps < 0.0)
        return hl_fail(err, "velocity: %g deg/s is negative (give a speed, >= 0)", velocity_degps);
    if (isnan(eccentricity_deg))
        return hl_fail(err, "eccentricity: not a number");
    if (eccentricity_deg < 0.0 || eccentricity_deg > 180.0)
        return hl_fail(err, "eccentricity: %g deg is outside [0, 180]", eccentricity_deg);
    return 0;
}

double acu_eccentricity_at_acuity_deg(double target_cpd)
{
    if (!(target_cpd > 0.0))
        return INFINITY;
    if (target_cpd >= REDDY_G_MAX_CPD)
        return 0.0;
    /* 60·M(E) = target: inside the flat part (E ≤ 5.79) M is 1, so the crossing lies beyond it
     * only when target < 60·M(5.79); solving eq. 3 for E gives the closed form of PAPERS.md §1. */
    double e = (sqrt(REDDY_M_NUM * REDDY_G_MAX_CPD / target_cpd) - 1.0) / REDDY_M_SLOPE;
    return e > REDDY_M_KNEE_DEG ? e : REDDY_M_KNEE_DEG;
}

double acu_velocity_at_acuity_degps(double target_cpd, double eccentricity_deg)
{
    if (!(target_cpd > 0.0))
        return INFINITY;
    double g_needed = target_cpd / acu_eccentricity_factor(eccentricity_deg);
    if (g_needed >= REDDY_G_MAX_CPD)
        return 0.0; /* even a still eye cannot resolve the target there */
    double v = pow(10.0, (REDDY_G_OFFSET - g_needed) / REDDY_G_SLOPE);
    return v > REDDY_G_KNEE_DEGPS ? v : REDDY_G_KNEE_DEGPS;
}

void acu_limits_init(struct acu_limits *lim, double xi_cpd, double scale)
{
    lim->xi_cpd = xi_cpd;
    lim->scale = scale;
    lim->use_velocity = 1;
    lim->use_eccentricity = 1;
    lim->eccentricity_xi_deg = acu_eccentricity_at_acuity_deg(xi_cpd);
    lim->velocity_xi_degps = acu_velocity_at_acuity_degps(xi_cpd, 0.0);
    /* ξ above H's peak (60 c/deg, the eye's still foveal acuity): H ≥ ξ holds nowhere, so the skip
     * region is empty. The inverses return 0 there, which would leave the point v = 0, E ≤ 5.79
     * "inside" and hand out ξ instead of H (docs/HARD_CASES.md, ξ above 60 c/deg). */
    if (!(acu_acuity_cpd(0.0, 0.0) >= xi_cpd))
        lim->eccentricity_xi_deg = lim->velocity_xi_degps = -1.0;
}

double acu_limit_cpd(const struct acu_limits *lim, double velocity_degps, double eccentricity_deg,
                     uint64_t *model_evaluations)
{
    double v = lim->use_velocity ? velocity_degps : 0.0;
    double e = lim->use_eccentricity ? eccentricity_deg : 0.0;
    /* Model only what a scene needs: on either rectangle one factor is at its maximum and the other
     * alone keeps H ≥ ξ, so min(H, ξ) = ξ without evaluating log10 and the division. */
    int inside = (e <= REDDY_M_KNEE_DEG && v <= lim->velocity_xi_degps) ||
                 (v <= REDDY_G_KNEE_DEGPS && e <= lim->eccentricity_xi_deg);
    double limit = lim->xi_cpd;
    if (!inside) {
        if (model_evaluations)
            ++*model_evaluations;
        double h = acu_acuity_cpd(v, e);
        if (h < limit)
            limit = h;
    }
    return limit * lim->scale;
}
