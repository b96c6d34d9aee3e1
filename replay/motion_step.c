/* The per-frame motion update (DESIGN.md "One frame", before the visible set): every moving
 * instance and group is put where its motion path says at the frame's time, from the rest poses
 * (closed form, so there is no drift and a replay at any rate sees the same poses), and each
 * instance's world velocity is kept for the acuity step, whose retinal velocity then includes the
 * object's own motion (Reddy 1998 §3.1: what matters is the image's speed on the retina).
 * Allocates nothing: the scene's motion set was sized when the scene was built. */
#include <math.h>

#include "replay/replay.h"
#include "scene/scene.h"

static hl_vec3d rest_center(const struct scn_motion_set *set, uint32_t g)
{
    return hl_v3(set->rest_group_center_m[3 * g], set->rest_group_center_m[3 * g + 1],
                 set->rest_group_center_m[3 * g + 2]);
}

/* A group's motion carries everything below it: apply g's own map, then each ancestor's. */
static void carry_by_groups(const struct scn_scene *s, uint32_t g, hl_vec3d *p, hl_quatd *q, hl_vec3d *v)
{
    for (; g != SCN_NONE; g = s->groups[g].parent)
        scn_rigid_apply(&s->motion->group_rigid[g], p, q, v);
}

static void grow_to(double *radius, const double *center, const double *c, double r)
{
    double reach = hypot(hypot(c[0] - center[0], c[1] - center[1]), c[2] - center[2]) + r;
    if (reach > *radius)
        *radius = reach;
}

const double *rpl_motion_step(struct scn_scene *s, double t_s)
{
    struct scn_motion_set *set = s->motion;
    if (!set)
        return NULL;
    for (uint32_t g = 0; g < s->group_count; ++g) /* own maps; a group turns about its centre by default */
        scn_motion_rigid(&set->group_motion[g], t_s, rest_center(set, g), &set->group_rigid[g]);
    for (uint32_t g = 0; g < s->group_count; ++g) {
        hl_vec3d c = rest_center(set, g);
        hl_quatd q = hl_q_identity();
        carry_by_groups(s, g, &c, &q, NULL);
        struct scn_group *gr = &s->groups[g];
        gr->center_m[0] = c.x, gr->center_m[1] = c.y, gr->center_m[2] = c.z;
        set->group_rotation[g] = q;
    }
    for (uint32_t i = 0; i < s->instance_count; ++i) {
        struct scn_instance *in = &s->instances[i];
        hl_vec3d p = set->rest_position_m[i];
        hl_quatd q = set->rest_rotation[i];
        /* The bounding-sphere centre (the chain's centre through the instance's scale and rotation;
         * the origin for the built-ins) rides the same maps, which also give its exact velocity. */
        const double *o = s->chains[in->chain].bound_center_m;
        hl_vec3d c = hl_v3_add(p, hl_q_rotate(q, hl_v3_scale(hl_v3(o[0], o[1], o[2]), in->scale)));
        hl_vec3d v = hl_v3(0, 0, 0);
        struct scn_rigid own; /* the instance's own motion turns it about its position by default */
        scn_motion_rigid(&set->instance_motion[i], t_s, p, &own);
        scn_rigid_apply(&own, &p, &q, NULL);
        scn_rigid_apply(&own, &c, NULL, &v);
        carry_by_groups(s, set->group_of_instance[i], &p, &q, NULL);
        carry_by_groups(s, set->group_of_instance[i], &c, NULL, &v);
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
            grow_to(&r, gr->center_m, child->center_m, child->radius_m);
        }
        gr->radius_m = r;
    }
    return set->velocity_mps;
}
