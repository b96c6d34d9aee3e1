/* acuity/gaze.h: where the eye looks and how it turns — the gaze models of DESIGN.md step 4.
 * Part of the acuity/acuity.h umbrella. A gaze model turns the head's state (and a measured gaze
 * when there is one) into the viewer that acu_compute_geometry takes: the cyclopean eye's position
 * and linear velocity, the gaze direction, and the EYE's angular velocity in the world, so that the
 * retinal velocity |u⊥/r − ω_eye × d| is the image's speed on the retina under that model.
 *   head     Reddy's desktop assumption: the eye is fixed in the head (ω_eye = ω_head).
 *   vor      the vestibulo-ocular reflex holds a world point fixation_m ahead of the head on the
 *            fovea, with a gain and a latency (PAPERS.md "The eye in a headset").
 *   tracked  a measured gaze: eccentricity from it, ω_eye from its own angular velocity (smooth
 *            pursuit of a followed object cancels that object's motion).
 * Per frame the model is one small computation; the per-object work stays in acu_compute_geometry.
 * Allocates nothing. */
#ifndef HMDLOD_ACUITY_GAZE_H
#define HMDLOD_ACUITY_GAZE_H

#include "base/base.h"

enum acu_gaze_model { ACU_GAZE_HEAD = 0, ACU_GAZE_VOR = 1, ACU_GAZE_TRACKED = 2 };

/* "head", "vor", "tracked"; acu_gaze_model_parse returns 0, or −1 for any other name. */
const char *acu_gaze_model_name(enum acu_gaze_model model);
int acu_gaze_model_parse(const char *name, enum acu_gaze_model *out);

/* The VOR's parameters. gain: eye-in-head velocity over the velocity that would hold the
 * fixation exactly (1 = perfect); latency_s: how long the eye lags the head; fixation_m: distance
 * of the fixated world point along the gaze (> 0; +∞ allowed: rotation only, no parallax). */
struct acu_vor_params {
    double gain;
    double latency_s;
    double fixation_m;
};
/* Literature defaults (cited in gaze.c) with the given fixation distance. */
void acu_vor_params_default(struct acu_vor_params *p, double fixation_m);

/* The head as a gaze model needs it, world frame. The eye position already includes the eyes'
 * offset from the neck's rotation centre (so a pure head rotation translates the eyes). The
 * delayed fields are the same quantities latency_s earlier (equal to the current ones when the
 * caller has no history). */
struct acu_head_state {
    hl_vec3d eye_position_m;                 /* cyclopean eye */
    hl_vec3d eye_velocity_mps;               /* its linear velocity: head translation + ω × offset */
    hl_vec3d forward_dir;                    /* head forward, unit */
    hl_vec3d angular_velocity_radps;         /* head, now */
    hl_vec3d delayed_angular_velocity_radps; /* head, latency_s ago */
    hl_vec3d delayed_eye_velocity_mps;       /* eye, latency_s ago */
    hl_vec3d gaze_dir;                       /* measured gaze, unit (tracked only) */
    hl_vec3d gaze_angular_velocity_radps;    /* measured gaze's angular velocity (tracked only) */
    int has_gaze;
};

/* Fills *out's eye and head fields from a head pose pivoting about the neck: eye = neck + q·offset,
 * eye velocity = neck velocity + ω × (q·offset) (a pure head turn translates the eyes). offset_head
 * is the neck-to-eye vector in the head frame (+Y up, −Z forward; hmd_neck_to_eye_head); a pose that
 * already gives the eyes' position passes a zero offset. Delayed fields = current ones; gaze unset. */
void acu_head_state_from_neck(hl_quatd orientation, hl_vec3d neck_position_m, hl_vec3d neck_velocity_mps,
                              hl_vec3d angular_velocity_radps, hl_vec3d offset_head_m, struct acu_head_state *out);

struct acu_viewer;
/* Fills *viewer for the model. tracked without a measured gaze (has_gaze 0) → −1 and *viewer is
 * filled as vor would; 0 otherwise. vor may be NULL for head and tracked. */
int acu_gaze_viewer(enum acu_gaze_model model, const struct acu_vor_params *vor,
                    const struct acu_head_state *head, struct acu_viewer *viewer);

/* How far from an object's bounding sphere a measured gaze may fall and still be on it: a headset
 * eye tracker's accuracy is about 0.5–1.1° (HTC's figure for the Vive Pro Eye), and EDVAM rounds its
 * gaze point to 0.1 m (about 1.5° at its median 3–4 m). */
#define ACU_GAZE_TARGET_DEG 2.0
/* Tracked, outside a saccade: the eye holds what it looks at still on the fovea — a world point
 * (fixation) or a moving object (pursuit) — while the measured gaze's rate carries the tracker's
 * noise (EDVAM's 0.1 m rounding reads as 25–45 deg/s between fixations, which made every object look
 * that fast on the retina). The target is the nearest visible object whose bounding sphere the gaze
 * ray meets, else the one it passes nearest within target_deg, else a world point fallback_m along
 * the gaze. Of holding the target
 * as it moves (pursuit) and holding a world point at its distance (fixation), *viewer's rate becomes
 * the one nearer its measured rate; a still target makes both the fixation. The head's roll about
 * the gaze is kept. Arrays as acu_compute_geometry's (velocity_mps NULL: a static scene); O(count). */
void acu_gaze_hold_target(const struct acu_head_state *head, const double *center_m, const double *radius_m,
                          const double *velocity_mps, const uint32_t *index, size_t count, double target_deg,
                          double fallback_m, struct acu_viewer *viewer);

#endif
