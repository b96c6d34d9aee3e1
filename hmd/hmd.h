/* hmd: what the display is — profiles (built-in table and JSON files), Reddy's highest displayable
 * frequency ξ, and per-eye asymmetric frusta. Prefix hmd_. Depends on base only. */
#ifndef HMDLOD_HMD_H
#define HMDLOD_HMD_H

#include "base/base.h"

enum { HMD_NAME_MAX = 64, HMD_EYE_LEFT = 0, HMD_EYE_RIGHT = 1 };

/* One display. Pixels and FOV are per eye. FOV is four tangent magnitudes for the LEFT eye
 * (temporal = left, nasal = right); the right eye mirrors left↔right. A symmetric FOV of H×V
 * degrees is tan(H/2) on both sides. */
struct hmd_profile {
    char name[HMD_NAME_MAX];
    char description[128];
    int eye_width_px, eye_height_px;
    double tan_left, tan_right, tan_up, tan_down; /* left eye, all > 0 */
    double refresh_hz;                            /* > 0 */
    double ipd_m;                                 /* eye separation, >= 0 */
    double distortion_k[4];                       /* PanoTools a, b, c, d (1,0,0,0-free: all 0 = none) */
    double aberration[3];                         /* per-channel scale r, g, b (1 = none) */
    double xi_override_cpd;                       /* > 0 replaces Reddy eq. 4's ξ; 0 = use eq. 4 */
    /* The cyclopean eye's offset from the neck's rotation centre, head frame: metres forward and up
     * (Oculus SDK neck model by default, HMD_NECK_TO_EYE_*). |offset| < 0.3 m; 0, 0 = eyes at the pivot. */
    double neck_to_eye_m[2];
    double peak_luminance_cdm2; /* display white, cd/m²; 100 by default (DEVICES.md §1d) */
};
/* Oculus SDK OVR_CAPI_Keys.h OVR_DEFAULT_NECK_TO_EYE_HORIZONTAL / _VERTICAL (ANSUR-88 averages). */
#define HMD_NECK_TO_EYE_FORWARD_M 0.0805
#define HMD_NECK_TO_EYE_UP_M 0.075
#define HMD_NECK_TO_EYE_MAX_M 0.3
/* Physically meaningful ranges (docs/display-profile.md "Ranges"): outside them a profile is an
 * error, because the derived numbers stop meaning anything — a FOV of 1e-7 deg gives ξ = 6e9 c/deg
 * and NaN downstream, a refresh of 1e-300 Hz a frame budget of 1e303 ms. */
#define HMD_PIXELS_MIN 16            /* per eye, each axis */
#define HMD_PIXELS_MAX 16384
#define HMD_FOV_MIN_DEG 1.0          /* per axis; the maximum is below 180 */
#define HMD_REFRESH_MIN_HZ 1.0
#define HMD_REFRESH_MAX_HZ 1000.0
#define HMD_IPD_MAX_M 0.1            /* [0, 0.1) */
#define HMD_DISTORTION_K_MAX 10.0    /* |a|, |b|, |c|, |d|: real lenses stay within ~1.5 (DEVICES.md §1b) */
#define HMD_ABERRATION_MIN 0.5       /* per-channel scale; real lenses differ from 1 by ~2 % */
#define HMD_ABERRATION_MAX 2.0
#define HMD_XI_MIN_CPD 0.1           /* override of ξ, when given */
#define HMD_XI_MAX_CPD 1000.0
/* Peak (white) luminance: headsets run at 50–200 cd/m² (Krajancich et al. 2021, DEVICES.md §1d).
 * 1 cd/m² is below any display a contrast sensitivity function would be asked about, and 10000
 * cd/m² is the top of HDR mastering (SMPTE ST 2084); outside them a value is a typo or a wrong unit
 * (nits are cd/m²; a foot-lambert is 3.43 of them). Few headsets publish theirs, so 100 is the
 * documented default (FovVideoVDP's generic HMD). */
#define HMD_PEAK_LUMINANCE_MIN_CDM2 1.0
#define HMD_PEAK_LUMINANCE_MAX_CDM2 10000.0
#define HMD_PEAK_LUMINANCE_DEFAULT_CDM2 100.0

/* Reddy's highest displayable frequency, eq. 4: one pixel is half a cycle. */
struct hmd_xi {
    double horizontal_cpd; /* eye_width_px / (2 · horizontal FOV°) */
    double vertical_cpd;   /* eye_height_px / (2 · vertical FOV°) */
    double used_cpd;       /* the override if set, else max(horizontal, vertical) */
};

/* Built-in table (DEVICES.md §1). Index 0 … hmd_builtin_count()-1; pointers stay valid forever. */
int hmd_builtin_count(void);
const struct hmd_profile *hmd_builtin_at(int index);
const struct hmd_profile *hmd_builtin_find(const char *name); /* case-insensitive; NULL if unknown */

/* Loads `name_or_path`: a built-in name, else a JSON profile file (docs/display-profile.md). On bad input
 * returns -1 with "file: field: reason" in err and leaves *out unspecified. */
int hmd_profile_load(const char *name_or_path, struct hmd_profile *out, struct hl_error *err);
int hmd_profile_load_json(const char *path, struct hmd_profile *out, struct hl_error *err);
/* Checks ranges (pixels > 0, tangents > 0 and < tan(90°), refresh > 0 …); `where` prefixes the message. */
int hmd_profile_validate(const struct hmd_profile *p, const char *where, struct hl_error *err);

double hmd_fov_horizontal_deg(const struct hmd_profile *p); /* atan(L) + atan(R) */
double hmd_fov_vertical_deg(const struct hmd_profile *p);   /* atan(U) + atan(D) */
struct hmd_xi hmd_compute_xi(const struct hmd_profile *p);

/* The cyclopean eye's offset from the neck pivot in the head frame (+Y up, −Z forward), metres. */
hl_vec3d hmd_neck_to_eye_head(const struct hmd_profile *p);

/* One eye's frustum in the head frame (+X right, +Y up, −Z forward). Tangents are magnitudes;
 * the eye sits at (offset_x_m, 0, 0): −ipd/2 for the left eye, +ipd/2 for the right. */
struct hmd_eye {
    double offset_x_m;
    double tan_left, tan_right, tan_up, tan_down;
};
struct hmd_eye hmd_eye_frustum(const struct hmd_profile *p, int eye);

/* Off-axis perspective projection for an eye, column-major 4×4 (OpenGL clip space, depth −1…1). */
void hmd_eye_projection(const struct hmd_eye *eye, double near_m, double far_m, double out_m4[16]);

/* ---- additions -------------------------------------------------------------------------------- */

/* JSON profile files larger than this are rejected unread (a profile is a few hundred bytes). */
enum { HMD_PROFILE_MAX_BYTES = 1 << 20 };

/* Resets *p to an empty profile with the defaults a JSON file may omit: IPD 0.063 m, no distortion
 * (k all 0), no aberration (1, 1, 1), no ξ override, the default neck-to-eye offset, a peak luminance
 * of 100 cd/m². Name, pixels, FOV and refresh are zero. */
void hmd_profile_defaults(struct hmd_profile *p);

/* Sets a symmetric FOV of h_deg × v_deg (full angles, degrees): every tangent is tan(angle/2).
 * Does not validate; call hmd_profile_validate afterwards for user-supplied angles. */
void hmd_set_symmetric_fov_deg(struct hmd_profile *p, double h_deg, double v_deg);

#endif
