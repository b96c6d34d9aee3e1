/* The contrast criterion's per-band test (acuity/csf.h "a lost band on an object"): the display's
 * limit first, the contrast sensitivity function only where the band is displayable. */
#include "acuity/acuity.h"

void acu_contrast_limits_init(struct acu_contrast_limits *lim, const struct acu_csf_table *csf, double xi_cpd,
                              double scale, double k_scale)
{
    lim->csf = csf;
    lim->xi_cpd = xi_cpd;
    lim->scale = scale;
    lim->k_scale = k_scale;
    lim->use_velocity = 1;
    lim->use_eccentricity = 1;
}

double acu_contrast_band_sensitivity(const struct acu_contrast_limits *lim, double rho_cpd, double velocity_degps,
                                     double eccentricity_deg)
{
    double rho = rho_cpd / lim->scale; /* Reddy §6 s, as the acuity criterion applies it */
    if (rho > lim->xi_cpd)
        return 0.0; /* the display cannot show it: Reddy eq. 4 */
    double v = lim->use_velocity ? velocity_degps : 0.0;
    double e = lim->use_eccentricity ? eccentricity_deg : 0.0;
    return acu_csf_table_lookup(lim->csf, rho, rho * v, e);
}
