/* hmdlod acuity: Reddy's H(v, E) and min(H, ξ) for one viewing condition. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "acuity/acuity.h"
#include "app/commands.h"

static const char usage[] =
    "usage: hmdlod acuity --velocity DEG_PER_S --eccentricity DEG [--xi CPD]\n"
    "  Prints Reddy's acuity H(v, E) = G(v)·M(E) in cycles/degree (Reddy 1998 eqs. 1-3) and,\n"
    "  with --xi (the display's highest displayable frequency), the acuity used: min(H, xi).\n"
    "  --velocity      retinal velocity, deg/s, >= 0 (default 0)\n"
    "  --eccentricity  angle from the gaze, deg, 0..180 (default 0)\n"
    "  --xi            display limit, c/deg, > 0 (e.g. hmdlod display show vive)\n";

int cmd_acuity(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    double v = 0.0, e = 0.0, xi = NAN;
    for (int i = 1; i < argc; i += 2) { /* every option takes one value */
        const char *value = i + 1 < argc ? argv[i + 1] : NULL;
        double *target = !strcmp(argv[i], "--velocity")       ? &v
                         : !strcmp(argv[i], "--eccentricity") ? &e
                         : !strcmp(argv[i], "--xi")           ? &xi
                                                              : NULL;
        if (!target) {
            fprintf(stderr, "hmdlod acuity: unknown option '%s'\n%s", argv[i], usage);
            return 1;
        }
        if (app_parse_double(argv[i], value, target) != 0)
            return 1;
    }
    struct hl_error err;
    if (acu_check_inputs(v, e, &err) != 0) {
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
    printf("acuity H      %10.4f c/deg\n", h);
    if (!isnan(xi))
        printf("min(H, xi)    %10.4f c/deg   (xi = %.4g c/deg: %s)\n", fmin(h, xi), xi,
               h >= xi ? "the display limits, the eye does not" : "the eye limits");
    return 0;
}
