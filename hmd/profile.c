/* Profile arithmetic: FOV from tangents, Reddy's ξ (eq. 4), range validation, per-eye frusta and
 * off-axis projections, and hmd_profile_load's built-in-or-file dispatch. */
#include "hmd/hmd.h"

#include <errno.h>
#include <math.h>
#include <string.h>
#include <sys/stat.h>

void hmd_profile_defaults(struct hmd_profile *p)
{
    memset(p, 0, sizeof *p);
    p->ipd_m = 0.063;
    p->aberration[0] = p->aberration[1] = p->aberration[2] = 1.0;
    p->neck_to_eye_m[0] = HMD_NECK_TO_EYE_FORWARD_M;
    p->neck_to_eye_m[1] = HMD_NECK_TO_EYE_UP_M;
    p->peak_luminance_cdm2 = HMD_PEAK_LUMINANCE_DEFAULT_CDM2;
}

hl_vec3d hmd_neck_to_eye_head(const struct hmd_profile *p)
{
    return hl_v3(0.0, p->neck_to_eye_m[1], -p->neck_to_eye_m[0]);
}

void hmd_set_symmetric_fov_deg(struct hmd_profile *p, double h_deg, double v_deg)
{
    p->tan_left = p->tan_right = tan(0.5 * h_deg * HL_RAD_PER_DEG);
    p->tan_up = p->tan_down = tan(0.5 * v_deg * HL_RAD_PER_DEG);
}

/* DEVICES.md conventions: FOV° = atan(L) + atan(R) (× atan(U) + atan(D)); atan, never acos. */
double hmd_fov_horizontal_deg(const struct hmd_profile *p)
{
    return (atan(p->tan_left) + atan(p->tan_right)) * HL_DEG_PER_RAD;
}

double hmd_fov_vertical_deg(const struct hmd_profile *p)
{
    return (atan(p->tan_up) + atan(p->tan_down)) * HL_DEG_PER_RAD;
}

/* Reddy 1998 eq. 4: one pixel is half a contrast cycle, so ξ = pixels / (2 · FOV°) per axis. */
struct hmd_xi hmd_compute_xi(const struct hmd_profile *p)
{
    struct hmd_xi xi;
    double h_deg = hmd_fov_horizontal_deg(p), v_deg = hmd_fov_vertical_deg(p);
    xi.horizontal_cpd = h_deg > 0 ? p->eye_width_px / (2.0 * h_deg) : 0.0;
    xi.vertical_cpd = v_deg > 0 ? p->eye_height_px / (2.0 * v_deg) : 0.0;
    xi.used_cpd = p->xi_override_cpd > 0 ? p->xi_override_cpd
                                         : fmax(xi.horizontal_cpd, xi.vertical_cpd);
    return xi;
}

int hmd_profile_validate(const struct hmd_profile *p, const char *where, struct hl_error *err)
{
    if (!where)
        where = "display";
    if (memchr(p->name, 0, sizeof p->name) == NULL || p->name[0] == 0)
        return hl_fail(err, "%s: field 'name': expected a non-empty string of at most %d bytes", where,
                       HMD_NAME_MAX - 1);
    if (memchr(p->description, 0, sizeof p->description) == NULL)
        return hl_fail(err, "%s: field 'description': not terminated", where);
    if (!(p->eye_width_px >= HMD_PIXELS_MIN && p->eye_width_px <= HMD_PIXELS_MAX && p->eye_height_px >= HMD_PIXELS_MIN &&
          p->eye_height_px <= HMD_PIXELS_MAX))
        return hl_fail(err, "%s: field 'eye_pixels': expected two positive integers, each in [%d, %d] (got %d x %d)",
                       where, HMD_PIXELS_MIN, HMD_PIXELS_MAX, p->eye_width_px, p->eye_height_px);
    const double t[4] = {p->tan_left, p->tan_right, p->tan_up, p->tan_down};
    static const char *const tn[4] = {"left", "right", "up", "down"};
    for (int i = 0; i < 4; ++i)
        if (!(isfinite(t[i]) && t[i] > 0))
            return hl_fail(err, "%s: field 'fov_tangents': '%s' must be a finite number > 0 (got %g)", where,
                           tn[i], t[i]);
    double h_deg = hmd_fov_horizontal_deg(p), v_deg = hmd_fov_vertical_deg(p);
    if (!(h_deg >= HMD_FOV_MIN_DEG && h_deg < 180.0) || !(v_deg >= HMD_FOV_MIN_DEG && v_deg < 180.0))
        return hl_fail(err, "%s: field 'fov_tangents': FOV must be in [%g, 180) deg per axis (got %.6g x %.6g deg)",
                       where, HMD_FOV_MIN_DEG, h_deg, v_deg);
    if (!(p->refresh_hz >= HMD_REFRESH_MIN_HZ && p->refresh_hz <= HMD_REFRESH_MAX_HZ))
        return hl_fail(err, "%s: field 'refresh_hz': expected Hz in [%g, %g] (got %g)", where, HMD_REFRESH_MIN_HZ,
                       HMD_REFRESH_MAX_HZ, p->refresh_hz);
    if (!(p->ipd_m >= 0 && p->ipd_m < HMD_IPD_MAX_M))
        return hl_fail(err, "%s: field 'ipd_m': expected metres in [0, %g) (got %g)", where, HMD_IPD_MAX_M, p->ipd_m);
    /* hypot of two finite numbers is finite; a NaN fails the comparison. */
    if (!(hypot(p->neck_to_eye_m[0], p->neck_to_eye_m[1]) < HMD_NECK_TO_EYE_MAX_M))
        return hl_fail(err, "%s: field 'neck_to_eye_m': expected [forward, up] metres, finite, length below %g (got %g, %g)",
                       where, HMD_NECK_TO_EYE_MAX_M, p->neck_to_eye_m[0], p->neck_to_eye_m[1]);
    for (int i = 0; i < 4; ++i)
        if (!(fabs(p->distortion_k[i]) <= HMD_DISTORTION_K_MAX))
            return hl_fail(err, "%s: field 'distortion_k': coefficients must be finite, each within ±%g (got %g)", where,
                           HMD_DISTORTION_K_MAX, p->distortion_k[i]);
    for (int i = 0; i < 3; ++i)
        if (!(p->aberration[i] >= HMD_ABERRATION_MIN && p->aberration[i] <= HMD_ABERRATION_MAX))
            return hl_fail(err, "%s: field 'aberration': expected three finite numbers in [%g, %g] (got %g)", where,
                           HMD_ABERRATION_MIN, HMD_ABERRATION_MAX, p->aberration[i]);
    if (!(p->xi_override_cpd == 0 || (p->xi_override_cpd >= HMD_XI_MIN_CPD && p->xi_override_cpd <= HMD_XI_MAX_CPD)))
        return hl_fail(err, "%s: field 'xi_cpd': expected cycles/degree in [%g, %g], or 0 for none (got %g)", where,
                       HMD_XI_MIN_CPD, HMD_XI_MAX_CPD, p->xi_override_cpd);
    if (!(p->peak_luminance_cdm2 >= HMD_PEAK_LUMINANCE_MIN_CDM2 &&
          p->peak_luminance_cdm2 <= HMD_PEAK_LUMINANCE_MAX_CDM2))
        return hl_fail(err, "%s: field 'peak_luminance_cdm2': expected cd/m² in [%g, %g] (got %g)", where,
                       HMD_PEAK_LUMINANCE_MIN_CDM2, HMD_PEAK_LUMINANCE_MAX_CDM2, p->peak_luminance_cdm2);
    return 0;
}

struct hmd_eye hmd_eye_frustum(const struct hmd_profile *p, int eye)
{
    struct hmd_eye e;
    e.tan_up = p->tan_up;
    e.tan_down = p->tan_down;
    if (eye == HMD_EYE_RIGHT) { /* mirror: the left eye's temporal side is the right eye's nasal side */
        e.offset_x_m = 0.5 * p->ipd_m;
        e.tan_left = p->tan_right;
        e.tan_right = p->tan_left;
    } else {
        e.offset_x_m = -0.5 * p->ipd_m;
        e.tan_left = p->tan_left;
        e.tan_right = p->tan_right;
    }
    return e;
}

/* glFrustum with l = −tan_left·n, r = tan_right·n, b = −tan_down·n, t = tan_up·n. The n's cancel in
 * the x/y rows, so the matrix depends on near/far only through the depth row. Column-major. */
void hmd_eye_projection(const struct hmd_eye *eye, double near_m, double far_m, double out_m4[16])
{
    const double w = eye->tan_left + eye->tan_right, h = eye->tan_up + eye->tan_down;
    memset(out_m4, 0, 16 * sizeof out_m4[0]);
    out_m4[0] = 2.0 / w;                                  /* 2n/(r−l) */
    out_m4[5] = 2.0 / h;                                  /* 2n/(t−b) */
    out_m4[8] = (eye->tan_right - eye->tan_left) / w;     /* (r+l)/(r−l) */
    out_m4[9] = (eye->tan_up - eye->tan_down) / h;        /* (t+b)/(t−b) */
    out_m4[10] = -(far_m + near_m) / (far_m - near_m);
    out_m4[11] = -1.0;
    out_m4[14] = -2.0 * far_m * near_m / (far_m - near_m);
}

int hmd_profile_load(const char *name_or_path, struct hmd_profile *out, struct hl_error *err)
{
    if (!name_or_path || !*name_or_path)
        return hl_fail(err, "no display given (a built-in name or a JSON profile file)");
    const struct hmd_profile *b = hmd_builtin_find(name_or_path);
    if (b) {
        *out = *b;
        return 0;
    }
    struct stat st;
    if (stat(name_or_path, &st) != 0 && errno == ENOENT) {
        char names[400];
        size_t used = 0;
        names[0] = 0;
        for (int i = 0; i < hmd_builtin_count() && used < sizeof names; ++i) {
            int n = snprintf(names + used, sizeof names - used, "%s%s", i ? ", " : "", hmd_builtin_at(i)->name);
            if (n < 0)
                break;
            used += (size_t)n;
        }
        return hl_fail(err, "unknown display '%s' (not a built-in; no such file). Built-ins: %s", name_or_path,
                       names);
    }
    return hmd_profile_load_json(name_or_path, out, err);
}
