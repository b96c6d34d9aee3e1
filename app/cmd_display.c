/* hmdlod display: list the built-in display profiles, or show one (built-in or JSON file) with its
 * FOV, Reddy's ξ (eq. 4) and the §4 figures: where and how fast detail beyond ξ may drop. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "acuity/acuity.h"
#include "app/commands.h"
#include "hmd/hmd.h"

static const char usage[] =
    "usage: hmdlod display list\n"
    "       hmdlod display show NAME|FILE\n"
    "  list   the built-in display profiles: pixels per eye, FOV, refresh, xi\n"
    "  show   one display (a built-in name, any case, or a JSON profile; docs/display-profile.md):\n"
    "         geometry, Reddy's highest displayable frequency xi (eq. 4) and the eccentricity and\n"
    "         retinal velocities beyond which detail finer than xi cannot be seen (Reddy 1998 s4)\n";

static const char usage_list[] =
    "usage: hmdlod display list\n"
    "  One row per built-in display: name, pixels per eye (w x h), FOV per eye (h x v degrees,\n"
    "  from the four frustum tangents), refresh in Hz, and xi in cycles/degree (Reddy eq. 4).\n";

static const char usage_show[] =
    "usage: hmdlod display show NAME|FILE\n"
    "  NAME is a built-in (see hmdlod display list; case does not matter); anything else is read\n"
    "  as a JSON display profile (docs/display-profile.md). Prints the profile, xi horizontal /\n"
    "  vertical / used (c/deg), and Reddy's s4 figures for that xi:\n"
    "    E*   eccentricity (deg) beyond which a still eye cannot resolve xi\n"
    "    v*   retinal velocity (deg/s) beyond which the gaze centre cannot resolve xi\n"
    "    v(E) retinal velocity needed at 5, 10, 15, 20 deg eccentricity (0 = detail may drop\n"
    "         even with a still eye there)\n";

static int wants_help(const char *arg) { return !strcmp(arg, "--help") || !strcmp(arg, "-h"); }

static int cmd_list(void)
{
    printf("%-14s  %14s  %17s  %12s  %15s\n", "name", "px/eye (w x h)", "FOV h x v (deg)", "refresh (Hz)",
           "xi used (c/deg)");
    for (int i = 0; i < hmd_builtin_count(); ++i) {
        const struct hmd_profile *p = hmd_builtin_at(i);
        struct hmd_xi xi = hmd_compute_xi(p);
        char px[32], fov[32];
        snprintf(px, sizeof px, "%d x %d", p->eye_width_px, p->eye_height_px);
        snprintf(fov, sizeof fov, "%.1f x %.1f", hmd_fov_horizontal_deg(p), hmd_fov_vertical_deg(p));
        printf("%-14s  %14s  %17s  %12.4g  %15.2f\n", p->name, px, fov, p->refresh_hz, xi.used_cpd);
    }
    return 0;
}

/* One "label  value" row; labels are ASCII so printf widths align. */
#define ROW "  %-42s "

static int cmd_show(const char *what)
{
    struct hmd_profile p;
    struct hl_error err;
    if (hmd_profile_load(what, &p, &err) != 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        return 1;
    }
    struct hmd_xi xi = hmd_compute_xi(&p);
    double h_deg = hmd_fov_horizontal_deg(&p), v_deg = hmd_fov_vertical_deg(&p);

    printf("display %s%s%s\n", p.name, p.description[0] ? " - " : "", p.description);
    printf(ROW "%d x %d\n", "pixels per eye (w x h, px)", p.eye_width_px, p.eye_height_px);
    printf(ROW "%.2f x %.2f\n", "FOV per eye (h x v, deg)", h_deg, v_deg);
    printf(ROW "L %.4f  R %.4f  U %.4f  D %.4f\n", "tangents, left eye (L temporal)", p.tan_left, p.tan_right,
           p.tan_up, p.tan_down);
    printf(ROW "%.4g\n", "refresh (Hz)", p.refresh_hz);
    printf(ROW "%.1f\n", "IPD (mm)", p.ipd_m * 1000.0);
    printf(ROW "%.1f forward, %.1f up\n", "eyes from the neck pivot (mm)", p.neck_to_eye_m[0] * 1000.0,
           p.neck_to_eye_m[1] * 1000.0);
    if (p.distortion_k[0] || p.distortion_k[1] || p.distortion_k[2] || p.distortion_k[3])
        printf(ROW "%.4g %.4g %.4g %.4g\n", "distortion k (a b c d)", p.distortion_k[0], p.distortion_k[1],
               p.distortion_k[2], p.distortion_k[3]);
    else
        printf(ROW "none\n", "distortion k (a b c d)");
    printf(ROW "%.4g %.4g %.4g\n", "aberration (r g b scale)", p.aberration[0], p.aberration[1], p.aberration[2]);
    printf(ROW "%.4g\n", "peak luminance (cd/m2)", p.peak_luminance_cdm2);

    printf("\nhighest displayable frequency xi (Reddy eq. 4: px / (2 FOV))\n");
    printf(ROW "%.2f\n", "xi horizontal (c/deg)", xi.horizontal_cpd);
    printf(ROW "%.2f\n", "xi vertical (c/deg)", xi.vertical_cpd);
    printf(ROW "%.2f%s\n", "xi used (c/deg)", xi.used_cpd, p.xi_override_cpd > 0 ? "  (override)" : "  (max)");

    printf("\nwhere detail finer than xi may drop (Reddy 1998 s4, H(v,E) = G(v) M(E))\n");
    double e_star = acu_eccentricity_at_acuity_deg(xi.used_cpd);
    if (xi.used_cpd >= 60.0 * acu_eccentricity_factor(5.79))
        printf(ROW "0 (xi >= 60 c/deg: the eye never resolves xi)\n", "still eye: eccentricity beyond (deg)");
    else
        printf(ROW "%.1f\n", "still eye: eccentricity beyond (deg)", e_star);
    printf(ROW "%.1f\n", "gaze centre: velocity beyond (deg/s)", acu_velocity_at_acuity_degps(xi.used_cpd, 0.0));
    static const double ecc_deg[4] = {5, 10, 15, 20};
    for (int i = 0; i < 4; ++i) {
        char label[64];
        snprintf(label, sizeof label, "at %2.0f deg eccentricity: velocity (deg/s)", ecc_deg[i]);
        double v = acu_velocity_at_acuity_degps(xi.used_cpd, ecc_deg[i]);
        if (v > 0)
            printf(ROW "%.1f\n", label, v);
        else
            printf(ROW "0 (any motion: not resolvable even still)\n", label);
    }
    return 0;
}

int cmd_display(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "hmdlod display: missing verb (list or show)\n%s", usage);
        return 1;
    }
    const char *verb = argv[1];
    if (wants_help(verb)) {
        fputs(usage, stdout);
        return 0;
    }
    if (!strcmp(verb, "list")) {
        if (argc >= 3 && wants_help(argv[2])) {
            fputs(usage_list, stdout);
            return 0;
        }
        if (argc > 2) {
            fprintf(stderr, "hmdlod display list: unexpected argument '%s' (takes none)\n", argv[2]);
            return 1;
        }
        return cmd_list();
    }
    if (!strcmp(verb, "show")) {
        for (int i = 2; i < argc; ++i)
            if (wants_help(argv[i])) {
                fputs(usage_show, stdout);
                return 0;
            }
        if (argc < 3) {
            fprintf(stderr, "hmdlod display show: missing NAME or FILE (see hmdlod display list)\n");
            return 1;
        }
        if (argc > 3) {
            fprintf(stderr, "hmdlod display show: unexpected argument '%s' (one display at a time)\n", argv[3]);
            return 1;
        }
        return cmd_show(argv[2]);
    }
    fprintf(stderr, "hmdlod display: unknown verb '%s' (list or show; hmdlod display --help)\n", verb);
    return 1;
}
