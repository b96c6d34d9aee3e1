/* hmdlod acuity: Reddy's H(v, E) and min(H, ξ), and the contrast sensitivity S(ρ, ω, L, A, E) with the
 * visibility of a band of given contrast, for one viewing condition (docs/csf.md, docs/visibility.md). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "acuity/acuity.h"
#include "app/commands.h"

static const char usage[] =
    "usage: hmdlod acuity [--velocity DEG_PER_S] [--eccentricity DEG] [--xi CPD]\n"
    "                     [--csf castle|stela] [--frequency CPD] [--luminance CDM2] [--area DEG2]\n"
    "                     [--contrast C]\n"
    "  Prints Reddy's acuity H(v, E) = G(v)·M(E) in cycles/degree (Reddy 1998 eqs. 1-3) and,\n"
    "  with --xi (the display's highest displayable frequency), the acuity used: min(H, xi).\n"
    "  Then the contrast sensitivity S of a pattern at --frequency moving at --velocity on the retina\n"
    "  (temporal frequency frequency x velocity), its threshold contrast 1/S, and whether a band of\n"
    "  --contrast is visible (contrast x S >= 1; docs/csf.md).\n"
    "  --velocity      retinal velocity, deg/s, >= 0 (default 0)\n"
    "  --eccentricity  angle from the gaze, deg, 0..180 (default 0)\n"
    "  --xi            display limit, c/deg, > 0 (e.g. hmdlod display show vive; default: none)\n"
    "  --csf           contrast sensitivity model: castle (default) or stela\n"
    "  --frequency     spatial frequency, c/deg, >= 0 (default 4)\n"
    "  --luminance     adapting luminance, cd/m2, > 0 (default 100)\n"
    "  --area          stimulus area, deg2, > 0 (default: a disc 1.5 periods across, pi (0.75/f)^2,\n"
    "                  the convention the selectors use)\n"
    "  --contrast      the band's contrast, >= 0 (default 1: full contrast)\n";

int cmd_acuity(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    double v = 0.0, e = 0.0, xi = NAN, rho = 4.0, lum = 100.0, area = NAN, contrast = 1.0;
    const char *csf_name = "castle";
    for (int i = 1; i < argc; i += 2) { /* every option takes one value */
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--csf")) {
            if (!value) {
                fprintf(stderr, "hmdlod acuity: --csf needs a value\n");
                return 1;
            }
            csf_name = value;
            continue;
        }
        double *target = !strcmp(argv[i], "--velocity")       ? &v
                         : !strcmp(argv[i], "--eccentricity") ? &e
                         : !strcmp(argv[i], "--xi")           ? &xi
                         : !strcmp(argv[i], "--frequency")    ? &rho
                         : !strcmp(argv[i], "--luminance")    ? &lum
                         : !strcmp(argv[i], "--area")         ? &area
                         : !strcmp(argv[i], "--contrast")     ? &contrast
                                                              : NULL;
        if (!target) {
            fprintf(stderr, "hmdlod acuity: unknown option '%s'\n%s", argv[i], usage);
            return 1;
        }
        if (app_parse_double(argv[i], value, target) != 0)
            return 1;
    }
    struct hl_error err;
    enum acu_csf_model model;
    if (acu_csf_model_parse(csf_name, &model) != 0) {
        fprintf(stderr, "hmdlod acuity: --csf: unknown model '%s' (known: castle, stela)\n", csf_name);
        return 1;
    }
    if (isnan(area) && rho > 0.0)
        area = acu_csf_gabor_area_deg2(rho, ACU_CSF_GABOR_CYCLES);
    if (acu_check_inputs(v, e, &err) != 0 || acu_csf_check_inputs(rho, rho * v, lum, area, e, &err) != 0 ||
        acu_csf_check_contrast(contrast, 1.0, &err) != 0) {
        fprintf(stderr, "hmdlod acuity: %s\n", err.msg);
        return 1;
    }
    if (!isnan(xi) && !(xi > 0.0 && isfinite(xi))) {
        fprintf(stderr, "hmdlod acuity: --xi: %g must be a finite number > 0\n", xi);
        return 1;
    }
    double g = acu_velocity_factor_cpd(v), m = acu_eccentricity_factor(e), h = g * m;
    printf("velocity      %10.4g deg/s   G(v) = %.4f c/deg\n", v, g);
    printf("eccentricity  %10.4g deg     M(E) = %.4f\n", e, m);
    printf("acuity H      %10.4f c/deg   (Reddy: the highest frequency seen at full contrast)\n", h);
    if (!isnan(xi))
        printf("min(H, xi)    %10.4f c/deg   (xi = %.4g c/deg: %s)\n", fmin(h, xi), xi,
               h >= xi ? "the display limits, the eye does not" : "the eye limits");
    double s = acu_csf_sensitivity(model, rho, rho * v, lum, area, e);
    printf("csf           %10s       frequency %.4g c/deg, temporal %.4g Hz, luminance %.4g cd/m2, area %.6g deg2\n",
           acu_csf_model_name(model), rho, rho * v, lum, area);
    printf("sensitivity   %10.2f\n", s);
    printf("threshold     %10.4f       (contrast at which it becomes visible, 1/S)\n", s > 0.0 ? 1.0 / s : INFINITY);
    int displayable = isnan(xi) || rho <= xi;
    int visible = displayable && s > 0.0 && acu_csf_band_visible(contrast, s, 1.0);
    printf("contrast      %10.4g       %s (%.4g x %.4g = %.4g %s 1%s)\n", contrast, visible ? "visible" : "invisible",
           contrast, s, contrast * s, contrast * s >= 1.0 ? ">=" : "<", displayable ? "" : "; above xi: not displayed");
    return 0;
}
