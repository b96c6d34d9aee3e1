/* Gaze models (acuity/gaze.h; derivation in docs/gaze.md "The models"): where the eye looks and how
 * fast it turns in the world, from the head's state. One small computation per frame. */
#include "acuity/acuity.h"

#include <math.h>
#include <string.h>

static const char *const g_names[] = {"head", "vor", "tracked"};

const char *acu_gaze_model_name(enum acu_gaze_model model)
{
    return (unsigned)model < 3 ? g_names[model] : "unknown";
}

int acu_gaze_model_parse(const char *name, enum acu_gaze_model *out)
{
    for (int k = 0; name && k < 3; ++k) {
        if (strcmp(name, g_names[k]) == 0) {
            *out = (enum acu_gaze_model)k;
            return 0;
        }
    }
    return -1;
}

void acu_vor_params_default(struct acu_vor_params *p, double fixation_m)
{
    /* Gain: a fixated world target in the light holds the VOR near 1 (PAPERS.md "The eye in a
     * headset"; Johnston & Sharpe 1994, Exp Brain Res 99:302, visual enhancement of the initial
     * VOR); 0.95 leaves the small under-compensation measured in the light. The high-acceleration
     * gains of 0.61–0.83 in "Behavior of human horizontal VOR in response to
     * high-acceleration stimuli" (Brain Res 1989, 499:153) are for head impulses in the dark
     * and are not the default. Latency: 6–15 ms (the same study), about 10 ms in PAPERS.md. */
    p->gain = 0.95;
    p->latency_s = 0.010;
    p->fixation_m = fixation_m;
}

void acu_head_state_from_neck(hl_quatd orientation, hl_vec3d neck_position_m, hl_vec3d neck_velocity_mps,
                              hl_vec3d angular_velocity_radps, hl_vec3d offset_head_m, struct acu_head_state *out)
{
    memset(out, 0, sizeof *out);
    hl_vec3d offset = hl_q_rotate(orientation, offset_head_m);
    out->eye_position_m = hl_v3_add(neck_position_m, offset);
    /* A point fixed on a body turning at ω moves at ω × r (r from the pivot). */
    out->eye_velocity_mps = hl_v3_add(neck_velocity_mps, hl_v3_cross(angular_velocity_radps, offset));
    out->forward_dir = hl_v3_normalize(hl_q_rotate(orientation, hl_v3(0, 0, -1)));
    out->angular_velocity_radps = angular_velocity_radps;
    out->delayed_angular_velocity_radps = angular_velocity_radps;
    out->delayed_eye_velocity_mps = out->eye_velocity_mps;
    out->gaze_dir = out->forward_dir;
}

/* a − (a·g)g: the part of a across the unit direction g. */
static hl_vec3d across(hl_vec3d a, hl_vec3d g) { return hl_v3_sub(a, hl_v3_scale(g, hl_v3_dot(a, g))); }

/* The eye's world angular velocity that keeps a world point D ahead along g on the fovea while the
 * eye moves at v: g must follow F − eye, so dg/dt = −v⊥/D and ω⊥ = g × dg/dt = g × (−v/D). About g
 * itself the eye rolls with the head: ocular counter-roll is weak (torsional VOR gain well below the
 * horizontal and vertical ones: Tweed et al. 1994, "Rotational kinematics of the human VOR II"),
 * so the head's roll about g is kept in full (the periphery turns about the fovea at that rate). */
static hl_vec3d hold_fixation_radps(hl_vec3d g, hl_vec3d head_radps, hl_vec3d eye_mps, double inv_fixation_m)
{
    hl_vec3d roll = hl_v3_scale(g, hl_v3_dot(head_radps, g));
    return hl_v3_add(roll, hl_v3_cross(g, hl_v3_scale(eye_mps, -inv_fixation_m)));
}

static void vor_viewer(const struct acu_vor_params *vor, const struct acu_head_state *h, struct acu_viewer *v)
{
    hl_vec3d g = h->forward_dir;
    double inv_d = vor->fixation_m > 0.0 ? 1.0 / vor->fixation_m : 0.0; /* +∞ → 0: rotation only */
    /* The eye in the head turns at gain·(required − head), as the head was latency_s ago; the head
     * carries it at today's rate: ω_eye(t) = ω_h(t) + k·(ω_req(t−τ) − ω_h(t−τ)). With k = 1, τ = 0
     * this is ω_req; a head acceleration α leaves ≈ α·τ, gain k leaves (1 − k)·ω⊥. */
    hl_vec3d req = hold_fixation_radps(g, h->delayed_angular_velocity_radps, h->delayed_eye_velocity_mps, inv_d);
    hl_vec3d in_head = hl_v3_scale(hl_v3_sub(req, h->delayed_angular_velocity_radps), vor->gain);
    v->angular_velocity_radps = hl_v3_add(h->angular_velocity_radps, in_head);
    v->gaze_dir = g;
}

int acu_gaze_viewer(enum acu_gaze_model model, const struct acu_vor_params *vor,
                    const struct acu_head_state *head, struct acu_viewer *viewer)
{
    viewer->eye_position_m = head->eye_position_m;
    viewer->linear_velocity_mps = head->eye_velocity_mps;
    if (model == ACU_GAZE_HEAD) {
        viewer->gaze_dir = head->forward_dir;
        viewer->angular_velocity_radps = head->angular_velocity_radps;
        return 0;
    }
    struct acu_vor_params fallback;
    if (!vor) {
        acu_vor_params_default(&fallback, INFINITY);
        vor = &fallback;
    }
    if (model == ACU_GAZE_VOR || !head->has_gaze) {
        vor_viewer(vor, head, viewer);
        return model == ACU_GAZE_VOR ? 0 : -1;
    }
    /* Tracked: the measured gaze's own rate across itself (a direction has no roll), and the head's
     * roll about it as for the VOR. Pursuit of an object moving at w makes ω⊥ = d × (w⊥/r), which
     * cancels that object's image motion in acu_compute_geometry. */
    hl_vec3d g = head->gaze_dir;
    viewer->gaze_dir = g;
    viewer->angular_velocity_radps = hl_v3_add(across(head->gaze_angular_velocity_radps, g),
                                               hl_v3_scale(g, hl_v3_dot(head->angular_velocity_radps, g)));
    return 0;
}

void acu_gaze_hold_target(const struct acu_head_state *head, const double *center_m, const double *radius_m,
                          const double *velocity_mps, const uint32_t *index, size_t count, double target_deg,
                          double fallback_m, struct acu_viewer *viewer)
{
    hl_vec3d g = viewer->gaze_dir, e = viewer->eye_position_m;
    /* The nearest sphere the gaze ray meets (what is in front hides what is behind), else the one it
     * passes nearest within target_deg. */
    double best_deg = target_deg, best_m = INFINITY, target_m = fallback_m;
    hl_vec3d target_mps = hl_v3(0, 0, 0);
    for (size_t k = 0; k < count; ++k) {
        uint32_t i = index[k];
        hl_vec3d d = hl_v3_sub(hl_v3(center_m[3 * (size_t)i], center_m[3 * (size_t)i + 1], center_m[3 * (size_t)i + 2]), e);
        double r = hl_v3_length(d);
        if (!(r > radius_m[i]))
            continue; /* the eye inside the sphere: no direction to hold */
        /* the gaze ray's angle from the sphere's edge (≤ 0: it meets the sphere) — atan2, not acos */
        double off_deg = atan2(hl_v3_length(hl_v3_cross(d, g)), hl_v3_dot(d, g)) * HL_DEG_PER_RAD -
                         asin(radius_m[i] / r) * HL_DEG_PER_RAD;
        double met_m = off_deg <= 0.0 ? r : INFINITY;
        if (met_m < best_m || (!isfinite(best_m) && off_deg < best_deg)) {
            best_deg = off_deg;
            best_m = met_m;
            target_m = r;
            target_mps = velocity_mps ? hl_v3(velocity_mps[3 * (size_t)i], velocity_mps[3 * (size_t)i + 1],
                                              velocity_mps[3 * (size_t)i + 2])
                                      : hl_v3(0, 0, 0);
        }
    }
    double inv_m = target_m > 0.0 && isfinite(target_m) ? 1.0 / target_m : 0.0;
    /* Holding a point that moves at w is holding a still one while the eye moves at v − w. */
    hl_vec3d fixation = hold_fixation_radps(g, head->angular_velocity_radps, viewer->linear_velocity_mps, inv_m);
    hl_vec3d pursuit = hold_fixation_radps(g, head->angular_velocity_radps,
                                           hl_v3_sub(viewer->linear_velocity_mps, target_mps), inv_m);
    hl_vec3d measured = viewer->angular_velocity_radps;
    double to_fixation = hl_v3_length(hl_v3_sub(measured, fixation));
    viewer->angular_velocity_radps = hl_v3_length(hl_v3_sub(measured, pursuit)) < to_fixation ? pursuit : fixation;
}
