/* acuity: what can be seen. Reddy's visual acuity model (Reddy 1998 eqs. 1–5), contrast sensitivity
 * (csf.h), per-object viewing geometry batched over plain arrays, and the acuity limit per object
 * (the selectors that use it are in lod/). Prefix acu_. Knows nothing of OpenGL, files or devices;
 * allocates nothing. Angles in degrees (as the paper). */
#ifndef HMDLOD_ACUITY_H
#define HMDLOD_ACUITY_H

#include "base/base.h"
#include "acuity/gaze.h"    /* gaze models: head-locked, VOR, tracked */
#include "acuity/saccade.h" /* saccades and their suppression window */
#include "acuity/csf.h"     /* contrast sensitivity: castleCSF, stelaCSF */

/* ---- Reddy's model --------------------------------------------------------------------------
 * Preconditions for the three below: inputs are not NaN (check at the boundary with
 * acu_check_inputs). v < 0 is treated as its magnitude; E is clamped to [0, 180]. */
double acu_velocity_factor_cpd(double velocity_degps); /* G(v), eq. 2, clamped to [0, 60] */
double acu_eccentricity_factor(double eccentricity_deg); /* M(E), eq. 3, in (0, 1] */
double acu_acuity_cpd(double velocity_degps, double eccentricity_deg); /* H = G·M, eq. 1 */

/* Boundary check for user- or file-supplied values: NaN, negative velocity or eccentricity
 * outside [0, 180] → −1 with the reason in err. +∞ velocity is accepted (H = 0). */
int acu_check_inputs(double velocity_degps, double eccentricity_deg, struct hl_error *err);

/* Inverses used for Reddy's §4 figures (all for a still-or-moving eye at a target acuity):
 * the eccentricity where H(0, E) = target (0 if target ≥ 60, +∞ if target ≤ 0), and the velocity
 * where H(v, E) = target at eccentricity E (0 if unreachable, +∞ if target ≤ 0). */
double acu_eccentricity_at_acuity_deg(double target_cpd);
double acu_velocity_at_acuity_degps(double target_cpd, double eccentricity_deg);

/* ---- per-display limits: model only what a scene needs -------------------------------------- */
struct acu_limits {
    double xi_cpd;        /* highest displayable frequency (eq. 4), > 0 */
    double scale;         /* Reddy §6 global factor s, (0, 1]; 1 = plain perceptual LOD */
    int use_velocity;     /* 0 → treat every object as still on the retina */
    int use_eccentricity; /* 0 → treat every object as at the gaze centre */
    /* Precomputed: H ≥ ξ holds on the union of two rectangles, so objects inside skip the model:
     * (E ≤ 5.79 and v ≤ velocity_xi) or (v ≤ 0.825 and E ≤ eccentricity_xi). */
    double eccentricity_xi_deg; /* E where H(0, E) = ξ */
    double velocity_xi_degps;   /* v where H(v, 0) = ξ */
};
void acu_limits_init(struct acu_limits *lim, double xi_cpd, double scale);
/* min(H(v,E), ξ)·s; skips the model inside the precomputed region and counts evaluations. */
double acu_limit_cpd(const struct acu_limits *lim, double velocity_degps, double eccentricity_deg,
                     uint64_t *model_evaluations);

/* ---- the resolution ceiling (acuity/resolution.c) ---------------------------------------------
 * The eccentricity beyond which nothing above target_cpd is visible, for an image region whose
 * content moves at velocity_degps on the retina: where an image may be drawn at a resolution that
 * displays target_cpd (a foveated periphery at scale s displays s·ξ) and lose nothing visible.
 * Under the contrast criterion for content of band contrast `contrast` (1 = full contrast, the
 * conservative value where the content is not known): the largest over bands ρ in [target, ξ·s] of
 * the E where c·S(ρ/s, ρ/s·v, E)·k falls to 1 (the CSF's eccentricity factor is exponential, so each
 * band's E is closed-form), bands sampled 8 per octave as the table's nodes. Under the acuity
 * criterion: where min(H(v, E), ξ)·s falls to the target (Reddy eqs. 1–3). 0 when the target is
 * at or above what the display shows (or contrast 0); +∞ when the model ignores eccentricity and
 * the detail is seen at the gaze, or the target is ≤ 0. Inputs not NaN (checked at the boundary). */
double acu_contrast_resolution_eccentricity_deg(const struct acu_contrast_limits *lim, double contrast,
                                                double velocity_degps, double target_cpd);
double acu_resolution_eccentricity_deg(const struct acu_limits *lim, double velocity_degps, double target_cpd);

/* ---- viewing geometry, batched --------------------------------------------------------------
 * The viewer: cyclopean eye position and gaze in world space, the eye's angular and linear velocity
 * (acu_gaze_viewer fills it for a gaze model).
 * Positions are double so objects 1e6 m from the origin keep millimetres. */
struct acu_viewer {
    hl_vec3d eye_position_m;
    hl_vec3d gaze_dir;               /* unit, world */
    hl_vec3d angular_velocity_radps; /* the EYE's, world frame (the head's for a head-locked eye;
                                      * acu_gaze_viewer fills it for each gaze model) */
    hl_vec3d linear_velocity_mps;    /* the EYE's, world frame: head translation + ω_head × offset
                                      * from the neck (acu_head_state_from_neck) */
};

/* For each of the `count` objects listed in `index` (into the scene arrays center_m[3·i..],
 * radius_m[i], velocity_mps[3·i..] or NULL for static objects), writes position-ordered outputs:
 *   eccentricity_deg[k]     angle from the gaze to the NEAREST point of the bounding sphere, ≥ 0
 *                           (conservative: a big object near the gaze counts as at the gaze);
 *   retinal_velocity_degps  speed of the sphere centre's image on the retina of an eye turning at ω:
 *                           |(u − (u·d)d)/r − ω × d| with d the unit direction, u the velocity relative
 *                           to the eye (object − eye);
 *   angular_diameter_deg    2·asin(radius/distance), 180 when the eye is inside the sphere.
 * An eye inside the sphere gets E = 0 and v = |ω| (the object fills the view and slides with it). */
void acu_compute_geometry(const struct acu_viewer *viewer, const double *center_m, const double *radius_m,
                          const double *velocity_mps, const uint32_t *index, size_t count,
                          double *eccentricity_deg, double *retinal_velocity_degps,
                          double *angular_diameter_deg);

/* Projected coverage, for cost (pixels filled) and benefit (Funkhouser's Size): each bounding sphere
 * projected into each eye, the exact bounding box of its silhouette clipped to the eye's image and
 * weighted π/4 (an aligned ellipse's share of its box; an off-axis one fills less, so coverage is
 * never under-counted), summed over the eyes. A sphere behind an eye or outside its image covers 0
 * there, also one beside the eye reaching behind its plane; one that holds the eye covers the whole
 * image. An eye
 * is its world position, eye-to-world orientation, the tangents of its four half-angles (> 0) and
 * its image size. Writes pixels_px[k] for the objects listed in index. O(count · eyes). */
struct acu_eye {
    hl_vec3d position_m;
    hl_quatd orientation;
    double tan_left, tan_right, tan_up, tan_down;
    double width_px, height_px;
};
void acu_compute_pixels(const struct acu_eye *eyes, int eye_count /* ≤ 4 */, const double *center_m,
                        const double *radius_m, const uint32_t *index, size_t count, double *pixels_px);

/* The same coverage for oriented boxes, exact: box k is its world centre box_center_m[3k..] and
 * three half-axis vectors box_axes_m[9k..] (u, v, w: the box is centre ± u ± v ± w), clipped to the
 * space in front of each eye, projected, its outline clipped to the image, the area summed over the
 * eyes. For the few large objects a sphere overstates — walls and floors hold the eye inside their
 * spheres — take the smaller of the two estimates. Plain arrays, no index. About 1 µs per box. */
void acu_compute_pixels_box(const struct acu_eye *eyes, int eye_count /* ≤ 4 */, const double *box_center_m,
                            const double *box_axes_m, size_t count, double *pixels_px);

#endif
