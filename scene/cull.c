/* Hierarchical sphere culling (Clark 1976, "Hierarchical geometric models for visible surface
 * algorithms"; the plane masks of Bishop et al. 1998 / Assarsson & Möller 2000): a sphere is outside
 * when it lies wholly behind one plane, inside when wholly in front of all; a group inside a plane
 * passes that plane's verdict to its subtree, so children test only the planes their parent
 * straddled, and a group inside every plane accepts its subtree with no test at all. */
#include "scene/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void scn_culler_free(struct scn_culler *c)
{
    if (!c)
        return;
    free(c->stack_group);
    free(c->stack_mask);
    free(c->loose);
    free(c->roots);
    memset(c, 0, sizeof *c);
}

int scn_culler_init(struct scn_culler *c, const struct scn_scene *s, struct hl_error *err)
{
    memset(c, 0, sizeof *c);
    uint32_t ng = s->group_count, ni = s->instance_count;
    uint8_t *held = calloc(ni ? ni : 1, 1);
    c->stack_group = malloc((ng ? ng : 1) * sizeof *c->stack_group);
    c->stack_mask = malloc((ng ? ng : 1) * sizeof *c->stack_mask);
    c->roots = malloc((ng ? ng : 1) * sizeof *c->roots);
    c->loose = malloc((ni ? ni : 1) * sizeof *c->loose);
    if (!held || !c->stack_group || !c->stack_mask || !c->roots || !c->loose) {
        free(held);
        scn_culler_free(c);
        return hl_fail(err, "scene %s: out of memory for the culler (%u groups)", s->name, ng);
    }
    c->stack_cap = ng;
    for (uint32_t g = 0; g < ng; ++g) {
        const struct scn_group *gr = &s->groups[g];
        if (gr->parent == SCN_NONE)
            c->roots[c->root_count++] = g;
        for (uint32_t k = 0; k < gr->instance_count; ++k)
            held[s->group_instances[gr->first_instance + k]] = 1;
    }
    if (ng > 0)
        for (uint32_t i = 0; i < ni; ++i)
            if (!held[i])
                c->loose[c->loose_count++] = i;
    free(held);
    return 0;
}

/* 0: outside some plane of `mask`. 1: not outside; *straddled gets the planes of `mask` the sphere
 * crosses (those its contents must still be tested against). */
static inline int sphere_classify(const double *center, double radius, const struct scn_plane *planes,
                                  uint32_t mask, uint32_t *straddled, uint64_t *plane_tests)
{
    uint32_t out = 0;
    for (uint32_t m = mask; m; m &= m - 1) {
        int k = __builtin_ctz(m);
        const struct scn_plane *p = &planes[k];
        double d = p->normal[0] * center[0] + p->normal[1] * center[1] + p->normal[2] * center[2] + p->offset_m;
        ++*plane_tests;
        if (d < -radius)
            return 0;
        if (d < radius)
            out |= 1u << k;
    }
    *straddled = out;
    return 1;
}

uint32_t scn_cull_flat(const struct scn_scene *s, const struct scn_plane *planes, int plane_count,
                       uint32_t *visible, struct scn_cull_stats *stats)
{
    struct scn_cull_stats st = {0};
    uint32_t all = plane_count >= 32 ? ~0u : (1u << plane_count) - 1u, n = 0, ignored;
    for (uint32_t i = 0; i < s->instance_count; ++i)
        if (sphere_classify(&s->center_m[3 * (size_t)i], s->radius_m[i], planes, all, &ignored, &st.plane_tests))
            visible[n++] = i;
    st.instances_tested = s->instance_count;
    st.instances_visible = n;
    if (stats)
        *stats = st;
    return n;
}

uint32_t scn_cull(const struct scn_scene *s, const struct scn_plane *planes, int plane_count,
                  struct scn_culler *c, uint32_t *visible, struct scn_cull_stats *stats)
{
    if (s->group_count == 0)
        return scn_cull_flat(s, planes, plane_count, visible, stats);
    struct scn_cull_stats st = {0};
    const uint32_t all = plane_count >= 32 ? ~0u : (1u << plane_count) - 1u;
    uint32_t n = 0, mask;
    for (uint32_t k = 0; k < c->loose_count; ++k) {
        uint32_t i = c->loose[k];
        ++st.instances_tested;
        if (sphere_classify(&s->center_m[3 * (size_t)i], s->radius_m[i], planes, all, &mask, &st.plane_tests))
            visible[n++] = i;
    }
    /* Depth first with an explicit stack: each group is pushed at most once, so group_count entries
     * always suffice. Pushed in reverse so that siblings come out in index order. */
    uint32_t top = 0;
    for (uint32_t k = c->root_count; k-- > 0;) {
        c->stack_group[top] = c->roots[k];
        c->stack_mask[top++] = all;
    }
    while (top > 0) {
        --top;
        const struct scn_group *g = &s->groups[c->stack_group[top]];
        mask = c->stack_mask[top];
        if (g->radius_m < 0.0)
            continue; /* nothing below it */
        if (mask) {
            ++st.groups_tested;
            if (!sphere_classify(g->center_m, g->radius_m, planes, mask, &mask, &st.plane_tests))
                continue;
        }
        ++st.groups_visible;
        const uint32_t *own = s->group_instances + g->first_instance;
        if (mask == 0) {
            for (uint32_t k = 0; k < g->instance_count; ++k)
                visible[n++] = own[k];
        } else {
            for (uint32_t k = 0; k < g->instance_count; ++k) {
                uint32_t i = own[k], ignored;
                ++st.instances_tested;
                if (sphere_classify(&s->center_m[3 * (size_t)i], s->radius_m[i], planes, mask, &ignored,
                                    &st.plane_tests))
                    visible[n++] = i;
            }
        }
        for (uint32_t k = g->child_count; k-- > 0;) {
            c->stack_group[top] = s->group_children[g->first_child + k];
            c->stack_mask[top++] = mask;
        }
    }
    st.instances_visible = n;
    if (stats)
        *stats = st;
    return n;
}

/* ---- invariants and bounds ---------------------------------------------------------------------- */

int scn_scene_check_groups(const struct scn_scene *s, struct hl_error *err)
{
    uint32_t ng = s->group_count, ni = s->instance_count;
    if (ng == 0)
        return 0;
    uint32_t *owner = malloc((ni ? ni : 1) * sizeof *owner);
    uint8_t *listed = calloc(ng, 1);
    int rc = -1;
    if (!owner || !listed) {
        hl_fail(err, "scene %s: out of memory checking %u groups", s->name, ng);
        goto done;
    }
    for (uint32_t i = 0; i < ni; ++i)
        owner[i] = SCN_NONE;
    for (uint32_t g = 0; g < ng; ++g) {
        const struct scn_group *gr = &s->groups[g];
        if (gr->parent != SCN_NONE && gr->parent >= g) {
            hl_fail(err, "scene %s: groups[%u] (%s): parent %u does not come before it", s->name, g, gr->name,
                    gr->parent);
            goto done;
        }
        if ((uint64_t)gr->first_child + gr->child_count > ng ||
            (uint64_t)gr->first_instance + gr->instance_count > ni) {
            hl_fail(err, "scene %s: groups[%u] (%s): child or instance range out of bounds", s->name, g, gr->name);
            goto done;
        }
        for (uint32_t k = 0; k < gr->child_count; ++k) {
            uint32_t c = s->group_children[gr->first_child + k];
            if (c >= ng || s->groups[c].parent != g || listed[c]) {
                hl_fail(err, "scene %s: groups[%u] (%s): child %u is not its own or is listed twice", s->name, g,
                        gr->name, c);
                goto done;
            }
            listed[c] = 1;
        }
        for (uint32_t k = 0; k < gr->instance_count; ++k) {
            uint32_t i = s->group_instances[gr->first_instance + k];
            if (i >= ni || owner[i] != SCN_NONE) {
                hl_fail(err, "scene %s: groups[%u] (%s): instance %u is out of range or in two groups", s->name,
                        g, gr->name, i);
                goto done;
            }
            owner[i] = g;
        }
    }
    for (uint32_t g = 0; g < ng; ++g)
        if (s->groups[g].parent != SCN_NONE && !listed[g]) {
            hl_fail(err, "scene %s: groups[%u] (%s): not among its parent's children", s->name, g, s->groups[g].name);
            goto done;
        }
    rc = 0;
done:
    free(owner);
    free(listed);
    return rc;
}

/* A sphere around spheres: the centre of their bounding box, the radius reaching the farthest one.
 * Not minimal (Ritter 1990 or Welzl 1991 would be tighter) but always containing, and cheap. */
void scn_scene_group_bounds(struct scn_scene *s)
{
    for (uint32_t g = s->group_count; g-- > 0;) { /* parents come before children: reverse = children first */
        struct scn_group *gr = &s->groups[g];
        double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        int any = 0;
        for (int pass = 0; pass < 2; ++pass) {
            double c[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])}, r = 0.0;
            for (uint32_t k = 0; k < gr->instance_count + gr->child_count; ++k) {
                const double *pc;
                double pr;
                if (k < gr->instance_count) {
                    uint32_t i = s->group_instances[gr->first_instance + k];
                    pc = &s->center_m[3 * (size_t)i], pr = s->radius_m[i];
                } else {
                    const struct scn_group *ch = &s->groups[s->group_children[gr->first_child + k - gr->instance_count]];
                    if (ch->radius_m < 0.0)
                        continue;
                    pc = ch->center_m, pr = ch->radius_m;
                }
                if (pass == 0) {
                    any = 1;
                    for (int a = 0; a < 3; ++a) {
                        lo[a] = fmin(lo[a], pc[a] - pr);
                        hi[a] = fmax(hi[a], pc[a] + pr);
                    }
                } else {
                    double d = hl_v3_length(hl_v3(pc[0] - c[0], pc[1] - c[1], pc[2] - c[2])) + pr;
                    r = fmax(r, d);
                }
            }
            if (pass == 1) {
                memcpy(gr->center_m, c, sizeof c);
                /* One part in 10^12 of slack: the containing test in double rounding must not fail. */
                gr->radius_m = any ? r * (1.0 + 1e-12) : -1.0;
                if (!any)
                    gr->center_m[0] = gr->center_m[1] = gr->center_m[2] = 0.0;
            }
        }
    }
}
