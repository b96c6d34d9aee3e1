/* The per-frame motion update (DESIGN.md "One frame", before the visible set): every moving
 * instance and group is put where its motion path says at the frame's time, from the rest poses
 * (closed form, so there is no drift and a replay at any rate sees the same poses), and each
 * instance's world velocity is kept for the acuity step, whose retinal velocity then includes the
 * object's own motion (Reddy 1998 §3.1: what matters is the image's speed on the retina).
 * Allocates nothing: the scene's motion set was sized when the scene was built. */
#include <math.h>

#include "frame/frame.h"
#include "scene/scene.h"

static void mat_from_quat(hl_quatd q, double m[9])
{
    double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z, xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    double wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    m[0] = 1 - 2 * (yy + zz), m[1] = 2 * (xy - wz), m[2] = 2 * (xz + wy);
    m[3] = 2 * (xy + wz), m[4] = 1 - 2 * (xx + zz), m[5] = 2 * (yz - wx);
    m[6] = 2 * (xz - wy), m[7] = 2 * (yz + wx), m[8] = 1 - 2 * (xx + yy);
}

static inline hl_vec3d mat_mul(const double m[9], hl_vec3d v)
{
    return hl_v3(m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
                 m[6] * v.x + m[7] * v.y + m[8] * v.z);
}

static inline hl_quatd quat_mul(hl_quatd a, hl_quatd b) /* Hamilton product, inlined for the per-instance loop */
{
    return hl_q(a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w);
}

/* A group's frame: its own map (about its rest centre unless it names a pivot), then its parent's
 * frame, already computed (parents are stored first). The moved centre's velocity is the exact
 * chain rule: v' = ω_p × (c' − c'_p) + V_p + M_p·v_own. */
static void group_frame(struct scn_scene *s, uint32_t g, double t_s)
{
    struct scn_motion_set *set = s->motion;
    struct scn_group_frame *f = &set->group_frame[g];
    const struct scn_motion *m = &set->group_motion[g];
    hl_vec3d rest = hl_v3(set->rest_group_center_m[3 * g], set->rest_group_center_m[3 * g + 1],
                          set->rest_group_center_m[3 * g + 2]);
    struct scn_rigid *r = &set->group_rigid[g];
    scn_motion_rigid(m, t_s, rest, r);
    hl_vec3d c = rest, v = hl_v3(0, 0, 0);
    hl_quatd q = hl_q_identity();
    scn_rigid_apply(r, &c, &q, &v);
    hl_vec3d omega = r->omega_radps;
    int moving = m->flags != 0;
    uint32_t p = s->groups[g].parent;
    if (p != SCN_NONE && set->group_frame[p].moving) {
        const struct scn_group_frame *fp = &set->group_frame[p];
        hl_vec3d arm = mat_mul(fp->m, hl_v3_sub(c, fp->rest_center_m));
        c = hl_v3_add(fp->center_m, arm);
        v = hl_v3_add(hl_v3_add(hl_v3_cross(fp->omega_radps, arm), fp->center_velocity_mps), mat_mul(fp->m, v));
        omega = hl_v3_add(fp->omega_radps, mat_mul(fp->m, omega));
        q = hl_q_normalize(quat_mul(fp->rotation, q));
        moving = 1;
    }
    f->rotation = q;
    mat_from_quat(q, f->m);
    f->rest_center_m = rest, f->center_m = c;
    f->omega_radps = omega, f->center_velocity_mps = v;
    f->moving = moving;
    struct scn_group *gr = &s->groups[g];
    gr->center_m[0] = c.x, gr->center_m[1] = c.y, gr->center_m[2] = c.z;
    set->group_rotation[g] = q;
}

static void grow_to(double *radius, const double *center, const double *c, double r)
{
    double dx = c[0] - center[0], dy = c[1] - center[1], dz = c[2] - center[2];
    double reach = sqrt(dx * dx + dy * dy + dz * dz) + r;
    if (reach > *radius)
        *radius = reach;
}

const double *frm_motion_step(struct scn_scene *s, double t_s)
{
    struct scn_motion_set *set = s->motion;
    if (!set)
        return NULL;
    for (uint32_t g = 0; g < s->group_count; ++g)
        group_frame(s, g, t_s);
    /* Group impostors ride their group's frame: modelled about its rest centre with world axes
     * (scene/impostor.h), so the frame's centre and rotation are the instance's pose. */
    for (uint32_t g = 0; g < s->group_count; ++g) {
        uint32_t k = s->groups[g].impostor_instance;
        if (k == SCN_NONE)
            continue;
        const struct scn_group_frame *f = &set->group_frame[g];
        struct scn_instance *in = &s->instances[k];
        in->position_m[0] = f->center_m.x, in->position_m[1] = f->center_m.y, in->position_m[2] = f->center_m.z;
        in->rotation = f->rotation;
        const double *o = s->chains[in->chain].bound_center_m;
        hl_vec3d c = hl_v3_add(f->center_m, mat_mul(f->m, hl_v3_scale(hl_v3(o[0], o[1], o[2]), in->scale)));
        double *cm = s->center_m + 3 * (size_t)k;
        cm[0] = c.x, cm[1] = c.y, cm[2] = c.z;
    }
    for (uint32_t i = 0; i < s->instance_count; ++i) {
        struct scn_instance *in = &s->instances[i];
        const struct scn_motion *own = &set->instance_motion[i];
        hl_vec3d p = set->rest_position_m[i];
        hl_quatd q = set->rest_rotation[i];
        /* The bounding-sphere centre (the chain's centre through the instance's scale and rotation;
         * the origin for the built-ins) rides the same maps, which also give its exact velocity. */
        const double *o = s->chains[in->chain].bound_center_m;
        int offset = o[0] != 0.0 || o[1] != 0.0 || o[2] != 0.0;
        hl_vec3d c = offset ? hl_v3_add(p, hl_q_rotate(q, hl_v3_scale(hl_v3(o[0], o[1], o[2]), in->scale))) : p;
        hl_vec3d v = hl_v3(0, 0, 0);
        if (own->flags) { /* its own motion first, turning about its position by default */
            struct scn_rigid r;
            scn_motion_rigid(own, t_s, p, &r);
            if (offset)
                scn_rigid_apply(&r, &c, NULL, &v);
            scn_rigid_apply(&r, &p, &q, offset ? NULL : &v);
            if (!offset)
                c = p;
        }
        uint32_t g = set->group_of_instance[i];
        if (g != SCN_NONE && set->group_frame[g].moving) { /* then everything above it */
            const struct scn_group_frame *f = &set->group_frame[g];
            hl_vec3d arm_c = mat_mul(f->m, hl_v3_sub(c, f->rest_center_m));
            v = hl_v3_add(hl_v3_add(hl_v3_cross(f->omega_radps, arm_c), f->center_velocity_mps), mat_mul(f->m, v));
            c = hl_v3_add(f->center_m, arm_c);
            p = offset ? hl_v3_add(f->center_m, mat_mul(f->m, hl_v3_sub(p, f->rest_center_m))) : c;
            q = quat_mul(f->rotation, q); /* unit times unit, recomputed from rest each frame: no drift */
        }
        in->position_m[0] = p.x, in->position_m[1] = p.y, in->position_m[2] = p.z;
        in->rotation = q;
        double *cm = s->center_m + 3 * (size_t)i, *vel = set->velocity_mps + 3 * (size_t)i;
        cm[0] = c.x, cm[1] = c.y, cm[2] = c.z;
        vel[0] = v.x, vel[1] = v.y, vel[2] = v.z;
    }
    /* Group spheres, children before parents (groups are stored parents first): about the moved
     * rest centre, just wide enough for everything below — an instance with its own motion may
     * leave its group's rest sphere, and the hierarchical cull must still contain it. */
    for (uint32_t g = s->group_count; g-- > 0;) {
        struct scn_group *gr = &s->groups[g];
        if (gr->instance_count == 0 && gr->child_count == 0)
            continue; /* nothing below: the rest radius stands */
        double r = 0;
        for (uint32_t k = 0; k < gr->instance_count; ++k) {
            uint32_t i = s->group_instances[gr->first_instance + k];
            grow_to(&r, gr->center_m, s->center_m + 3 * (size_t)i, s->radius_m[i]);
        }
        for (uint32_t k = 0; k < gr->child_count; ++k) {
            const struct scn_group *child = &s->groups[s->group_children[gr->first_child + k]];
            if (child->radius_m >= 0) /* −1 marks an empty group (scn_scene_group_bounds) */
                grow_to(&r, gr->center_m, child->center_m, child->radius_m);
        }
        gr->radius_m = r;
    }
    return set->velocity_mps;
}
