/* scene/motion.h: motion paths of instances and groups — a spin about an axis, an oscillation
 * along a direction, and looping keyframed offsets, any combination (Mason & Blake 1997 §8: the
 * domes "rotate around their own axes and oscillate towards and away from the viewer", so that the
 * optimizer must keep changing detail). Included by scene/scene.h. docs/domes.md has the JSON form.
 *
 * A motion maps a base pose (the pose at rest, t = 0 gives it back when the keyframes start at a
 * zero offset) to the pose at time t:
 *     p(t) = c + R(t)·(p0 − c) + a·sin(2π t / T + φ)·d + k(t),      q(t) = R(t)·q0,
 * R(t) the rotation by rate·t about `axis` through the pivot c, d the oscillation direction, k(t) the
 * keyframe offset (linear between keys, looping). A group's motion carries everything below it:
 * an instance's world pose is its own motion, then its group's, then the parent group's … */
#ifndef HMDLOD_SCENE_MOTION_H
#define HMDLOD_SCENE_MOTION_H

#include "base/base.h"

struct cJSON;

enum { SCN_MOTION_SPIN = 1u, SCN_MOTION_OSCILLATE = 2u, SCN_MOTION_KEYFRAMES = 4u };
enum { SCN_MOTION_MAX_KEYS = 32 };

struct scn_motion {
    unsigned flags; /* SCN_MOTION_* bits; 0 = still */
    /* spin */
    hl_vec3d spin_axis; /* unit */
    double spin_rate_degps;
    int spin_pivot_set;  /* 0: about the base position (an instance turns in place; a group about its centre) */
    hl_vec3d spin_pivot_m; /* world (the parent's frame), when set */
    /* oscillation */
    hl_vec3d osc_direction; /* unit */
    double osc_amplitude_m, osc_period_s, osc_phase_deg;
    /* keyframes: offsets from the base position; key_t_s[0] = 0, strictly increasing; the path loops
     * with period key_t_s[key_count − 1] (repeat the first offset last for a closed loop) */
    int key_count; /* ≥ 2 when SCN_MOTION_KEYFRAMES is set */
    double key_t_s[SCN_MOTION_MAX_KEYS];
    hl_vec3d key_offset_m[SCN_MOTION_MAX_KEYS];
};

/* The rigid map a motion applies at time t: x ↦ pivot + R·(x − pivot) + offset, and its rates:
 * angular velocity omega (world, rad/s) and the offset's velocity. */
struct scn_rigid {
    hl_quatd rotation;
    hl_vec3d pivot_m, offset_m;
    hl_vec3d omega_radps, offset_velocity_mps;
};

/* The rigid map of motion m at t_s; default_pivot_m is used when m has no pivot of its own. A NULL
 * or still motion gives the identity with zero rates. Pure; allocates nothing. */
void scn_motion_rigid(const struct scn_motion *m, double t_s, hl_vec3d default_pivot_m, struct scn_rigid *out);
/* Applies r to a pose moving with velocity *velocity_mps in r's source frame (zero for a pose at
 * rest); updates all three in place: v ← ω × R(p − c) + R·v + offset rate (exact chain rule). */
void scn_rigid_apply(const struct scn_rigid *r, hl_vec3d *position_m, hl_quatd *rotation, hl_vec3d *velocity_mps);

/* Pose and velocity at t_s of something at base_position / base_rotation moved by m (pivot
 * defaults to base_position). velocity_mps may be NULL. Pure; allocates nothing. */
void scn_motion_eval(const struct scn_motion *m, double t_s, hl_vec3d base_position, hl_quatd base_rotation,
                     hl_vec3d *position, hl_quatd *rotation, hl_vec3d *velocity_mps);

/* Checks a motion filled by hand: unit-able axis and direction, finite numbers, amplitude ≥ 0,
 * period > 0, keys from 0 strictly increasing. 0 or −1 with the reason (prefixed by `where`). */
int scn_motion_check(const struct scn_motion *m, const char *where, struct hl_error *err);

/* Parses a scene file's "motion" object (docs/domes.md):
 *   {"spin": {"axis": [x,y,z], "rate_degps": r, "pivot_m": [x,y,z]},          pivot optional
 *    "oscillate": {"direction": [x,y,z], "amplitude_m": a, "period_s": T, "phase_deg": φ},  phase optional
 *    "keyframes": [{"t_s": 0, "offset_m": [x,y,z]}, …]}                         ≥ 2 keys
 * Every member optional, unknown keys refused. Errors name json_path ("scene.json: instances[3].motion")
 * and the member. *out is zeroed first (still) and filled on success. */
int scn_motion_parse(const struct cJSON *node, const char *json_path, struct scn_motion *out, struct hl_error *err);

/* ---- a scene's motion ----------------------------------------------------------------------------
 * Owned by the scene (scn_scene.motion, NULL in a static scene). The rest poses are what motions
 * start from each frame (no drift); the velocity array is what the frame loop hands the acuity
 * step. Sized once: moving a scene allocates nothing. */
struct scn_scene;
/* Where a group's frame is at one time, its own motion and its ancestors' composed: a rest point x
 * goes to center_m + M·(x − rest_center_m) and moves at omega × (x' − center_m) + center_velocity
 * (a rigid motion's velocity field; arms stay local, so far-from-origin scenes keep precision). */
struct scn_group_frame {
    double m[9];                 /* the composed rotation, row-major */
    hl_quatd rotation;           /* the same as a unit quaternion */
    hl_vec3d rest_center_m, center_m;
    hl_vec3d omega_radps, center_velocity_mps;
    int moving;                  /* 0: identity at rest (no motion on the group or above it) */
};
struct scn_motion_set {
    struct scn_motion *instance_motion; /* instance_count entries, flags 0 = still */
    struct scn_motion *group_motion;    /* group_count entries */
    hl_vec3d *rest_position_m;          /* instance_count: positions at rest */
    hl_quatd *rest_rotation;            /* instance_count */
    double *rest_group_center_m;        /* 3 per group: group centres at rest */
    double *rest_group_radius_m;        /* per group */
    uint32_t *group_of_instance;        /* instance_count: the group listing it, SCN_NONE if none */
    double *velocity_mps;               /* 3 per instance: world velocity of each centre at the last move */
    hl_quatd *group_rotation;           /* group_count: world rotation of each group's frame at the last
                                         * move (its origin is the group's rest centre, moved: center_m);
                                         * an impostor chain, modelled in that frame, is drawn with it */
    struct scn_rigid *group_rigid;      /* group_count: scratch for one move (each group's own map) */
    struct scn_group_frame *group_frame; /* group_count: scratch for one move (composed) */
};
/* Creates s->motion with every instance and group still, capturing the current instance poses and
 * group spheres as the rest poses: call once the instances and groups are final, then fill
 * instance_motion / group_motion. Fails on out of memory or an instance listed by two groups. */
int scn_scene_motion_create(struct scn_scene *s, struct hl_error *err);
void scn_motion_set_free(struct scn_motion_set *set); /* frees the arrays and the set; NULL is fine */

#endif
