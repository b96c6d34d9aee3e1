/* Scene assembly shared by the built-in scenes: packing LOD chains into one vertex and one index
 * array (so the GPU needs one buffer of each), the per-instance arrays, and the name dispatch. */
#include "scene/scene_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const scn_builtin_names[] = {"field", "auditorium", "domes", NULL};

const char *const *scn_scene_builtin_names(void) { return scn_builtin_names; }

void scn_scene_free(struct scn_scene *s)
{
    if (!s)
        return;
    free(s->positions);
    free(s->normals);
    free(s->indices);
    free(s->chains);
    free(s->instances);
    free(s->center_m);
    free(s->radius_m);
    free(s->chain_of_instance);
    free(s->importance);
    free(s->groups);
    free(s->group_children);
    free(s->group_instances);
    scn_motion_set_free(s->motion);
    *s = (struct scn_scene){0};
}

int scn_scene_build(const char *name, const struct scn_scene_params *params, struct scn_scene *out,
                    struct hl_error *err)
{
    if (!out)
        return hl_fail(err, "scene: no output");
    *out = (struct scn_scene){0};
    struct scn_scene_params p = params ? *params : (struct scn_scene_params){0};
    if (p.seed == 0)
        p.seed = 1;
    int rc;
    if (name && strcmp(name, "field") == 0)
        rc = scn_scene_build_field(&p, out, err);
    else if (name && strcmp(name, "auditorium") == 0)
        rc = scn_scene_build_auditorium(&p, out, err);
    else if (name && strcmp(name, "domes") == 0)
        rc = scn_scene_build_domes(&p, out, err);
    else
        return hl_fail(err, "scene: unknown built-in scene '%s' (built-in: field, auditorium, domes)", name ? name : "(null)");
    if (rc != 0) {
        scn_scene_free(out);
        return rc;
    }
    snprintf(out->name, sizeof out->name, "%s", name);
    return 0;
}

static int scn_scene_reserve(void **p, size_t count, size_t elem)
{
    void *q = realloc(*p, count ? count * elem : 1);
    if (!q)
        return -1;
    *p = q;
    return 0;
}

/* The model-space box around every level's vertices (any level may be drawn; a simplifier may move
 * a vertex outward). An empty chain gets an empty box at the origin. */
static void chain_box(struct scn_chain *c, const struct scn_mesh *meshes, int count)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int l = 0; l < count; ++l)
        for (uint32_t i = 0; i < meshes[l].vertex_count; ++i)
            for (int k = 0; k < 3; ++k) {
                double x = meshes[l].positions[3 * (size_t)i + k];
                lo[k] = x < lo[k] ? x : lo[k];
                hi[k] = x > hi[k] ? x : hi[k];
            }
    for (int k = 0; k < 3; ++k) {
        int empty = !(lo[k] <= hi[k]);
        c->box_min_m[k] = empty ? 0.0 : lo[k];
        c->box_max_m[k] = empty ? 0.0 : hi[k];
    }
}

/* A quarter of the mesh's surface area (scn_lod.front_area_m2). */
static double mesh_front_area(const struct scn_mesh *m)
{
    double area = 0.0;
    for (uint32_t t = 0; t + 2 < m->index_count; t += 3) {
        const float *a = m->positions + 3 * (size_t)m->indices[t], *b = m->positions + 3 * (size_t)m->indices[t + 1],
                    *c = m->positions + 3 * (size_t)m->indices[t + 2];
        double u[3], v[3];
        for (int k = 0; k < 3; ++k)
            u[k] = (double)b[k] - a[k], v[k] = (double)c[k] - a[k];
        double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
        area += 0.5 * sqrt(x * x + y * y + z * z);
    }
    return 0.25 * area;
}

double scn_lod_fill(const struct scn_chain *ch, int level, int box)
{
    double bound_m2;
    if (box) {
        double e[3];
        for (int k = 0; k < 3; ++k)
            e[k] = ch->box_max_m[k] - ch->box_min_m[k];
        bound_m2 = 0.5 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]); /* a quarter of 2(ab + bc + ca) */
    } else {
        bound_m2 = HL_PI * ch->bound_radius_m * ch->bound_radius_m;
    }
    double fill = ch->lods[level].front_area_m2 / bound_m2;
    return bound_m2 > 0.0 && isfinite(fill) ? fill : 1.0;
}

int scn_scene_pack_chain(struct scn_scene *s, const char *name, const struct scn_mesh *meshes, int count,
                         struct hl_error *err)
{
    if (count < 1 || count > SCN_MAX_LODS)
        return hl_fail(err, "scene %s: chain %s: %d levels (1…%d)", s->name, name, count, SCN_MAX_LODS);
    uint64_t nv = s->vertex_count, ni = s->index_count;
    for (int l = 0; l < count; ++l) {
        if (meshes[l].failed)
            return hl_fail(err, "scene: chain %s: out of memory while building level %d", name, l);
        nv += meshes[l].vertex_count;
        ni += meshes[l].index_count;
    }
    if (nv > UINT32_MAX || ni > UINT32_MAX)
        return hl_fail(err, "scene: chain %s: more than 2^32 vertices or indices", name);
    if (scn_scene_reserve((void **)&s->positions, nv * 3, sizeof(float)) ||
        scn_scene_reserve((void **)&s->normals, nv * 3, sizeof(float)) ||
        scn_scene_reserve((void **)&s->indices, ni, sizeof(uint32_t)) ||
        scn_scene_reserve((void **)&s->chains, s->chain_count + 1, sizeof *s->chains))
        return hl_fail(err, "scene: chain %s: out of memory", name);

    struct scn_chain *c = &s->chains[s->chain_count];
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "%s", name);
    c->lod_count = count;
    for (int l = 0; l < count; ++l) {
        const struct scn_mesh *m = &meshes[l];
        struct scn_lod *lod = &c->lods[l];
        lod->first_index = s->index_count;
        lod->index_count = m->index_count;
        lod->triangle_count = m->index_count / 3;
        lod->vertex_count = m->vertex_count;
        lod->front_area_m2 = mesh_front_area(m);
        memcpy(s->positions + 3 * (size_t)s->vertex_count, m->positions, 3 * sizeof(float) * m->vertex_count);
        memcpy(s->normals + 3 * (size_t)s->vertex_count, m->normals, 3 * sizeof(float) * m->vertex_count);
        for (uint32_t k = 0; k < m->index_count; ++k) /* absolute indices: one glDrawElements per LOD */
            s->indices[s->index_count + k] = m->indices[k] + s->vertex_count;
        s->vertex_count += m->vertex_count;
        s->index_count += m->index_count;
    }
    chain_box(c, meshes, count);
    s->chain_count++;
    return 0;
}

int scn_scene_add_chain(struct scn_scene *s, const char *name, struct scn_mesh *meshes, int count,
                        struct hl_error *err)
{
    if (scn_scene_pack_chain(s, name, meshes, count, err) != 0)
        return -1;
    struct scn_chain *c = &s->chains[s->chain_count - 1];
    double r2 = 0;
    for (uint32_t i = 0; i < meshes[0].vertex_count; ++i) {
        const float *q = meshes[0].positions + 3 * (size_t)i;
        double d2 = (double)q[0] * q[0] + (double)q[1] * q[1] + (double)q[2] * q[2];
        r2 = d2 > r2 ? d2 : r2;
    }
    c->bound_radius_m = sqrt(r2);
    for (int l = 0; l < count; ++l) {
        struct scn_lod *lod = &c->lods[l];
        lod->geometric_error_m = l == 0 ? 0.0 : scn_lod_geometric_error(&meshes[0], &meshes[l]);
        lod->unique_freq_cpdiam = scn_lod_unique_freq(lod->geometric_error_m, c->bound_radius_m);
        /* The acuity step needs f strictly decreasing with the level: a coarser level loses larger
         * features, i.e. lower frequencies. A level that happens to be no worse than the previous
         * one is clamped just below it (docs/scenes.md). */
        if (l > 0 && !(lod->unique_freq_cpdiam < c->lods[l - 1].unique_freq_cpdiam))
            lod->unique_freq_cpdiam = c->lods[l - 1].unique_freq_cpdiam * (1.0 - 1e-6);
        lod->freq = (struct scn_level_freq){NAN, NAN, lod->unique_freq_cpdiam};
    }
    return 0;
}

/* The first instance anywhere below group g (depth first), SCN_NONE if none: its colour dresses the
 * group's impostor. */
static uint32_t scn_group_first_instance(const struct scn_scene *s, uint32_t g)
{
    const struct scn_group *gr = &s->groups[g];
    if (gr->instance_count > 0)
        return s->group_instances[gr->first_instance];
    for (uint32_t k = 0; k < gr->child_count; ++k) {
        uint32_t i = scn_group_first_instance(s, s->group_children[gr->first_child + k]);
        if (i != SCN_NONE)
            return i;
    }
    return SCN_NONE;
}

int scn_scene_add_impostor_instances(struct scn_scene *s, struct hl_error *err)
{
    uint32_t n = s->instance_count, extra = 0;
    for (uint32_t g = 0; g < s->group_count; ++g)
        extra += s->groups[g].impostor_chain != SCN_NONE;
    if (extra == 0) {
        for (uint32_t g = 0; g < s->group_count; ++g)
            s->groups[g].impostor_instance = SCN_NONE;
        return 0;
    }
    size_t total = (size_t)n + extra;
    if (scn_scene_reserve((void **)&s->instances, total, sizeof *s->instances) ||
        scn_scene_reserve((void **)&s->center_m, 3 * total, sizeof *s->center_m) ||
        scn_scene_reserve((void **)&s->radius_m, total, sizeof *s->radius_m) ||
        scn_scene_reserve((void **)&s->chain_of_instance, total, sizeof *s->chain_of_instance) ||
        (s->importance && scn_scene_reserve((void **)&s->importance, total, sizeof *s->importance)))
        return hl_fail(err, "scene %s: out of memory for %u group impostors", s->name, extra);
    uint32_t k = n;
    for (uint32_t g = 0; g < s->group_count; ++g) {
        struct scn_group *gr = &s->groups[g];
        gr->impostor_instance = SCN_NONE;
        if (gr->impostor_chain == SCN_NONE)
            continue;
        static const float grey[3] = {0.7f, 0.7f, 0.7f};
        uint32_t first = scn_group_first_instance(s, g);
        /* The impostor is modelled in the group's frame (scene/impostor.h): origin at the group's
         * centre, world axes, scale 1. */
        scn_scene_set_instance(s, k, gr->impostor_chain, hl_v3(gr->center_m[0], gr->center_m[1], gr->center_m[2]),
                               hl_q_identity(), 1.0, first != SCN_NONE ? s->instances[first].color : grey);
        if (s->importance)
            s->importance[k] = gr->importance;
        gr->impostor_instance = k++;
    }
    s->impostor_instance_count = extra;
    return 0;
}

int scn_scene_alloc_instances(struct scn_scene *s, uint32_t n, struct hl_error *err)
{
    s->instances = calloc(n ? n : 1, sizeof *s->instances);
    s->center_m = calloc(n ? 3 * (size_t)n : 1, sizeof *s->center_m);
    s->radius_m = calloc(n ? n : 1, sizeof *s->radius_m);
    s->chain_of_instance = calloc(n ? n : 1, sizeof *s->chain_of_instance);
    if (!s->instances || !s->center_m || !s->radius_m || !s->chain_of_instance)
        return hl_fail(err, "scene: out of memory for %u instances", n);
    s->instance_count = n;
    return 0;
}

void scn_scene_set_instance(struct scn_scene *s, uint32_t i, uint32_t chain, hl_vec3d position,
                            hl_quatd rotation, double scale, const float color[3])
{
    struct scn_instance *in = &s->instances[i];
    in->chain = chain;
    in->position_m[0] = position.x, in->position_m[1] = position.y, in->position_m[2] = position.z;
    in->rotation = rotation;
    in->scale = scale;
    memcpy(in->color, color, sizeof in->color);
    /* The chain's sphere centre (model space; 0 for the built-ins) goes through the instance's
     * scale and rotation like any model point. */
    const double *o = s->chains[chain].bound_center_m;
    hl_vec3d c = hl_v3_add(position, hl_q_rotate(rotation, hl_v3_scale(hl_v3(o[0], o[1], o[2]), scale)));
    s->center_m[3 * (size_t)i] = c.x;
    s->center_m[3 * (size_t)i + 1] = c.y;
    s->center_m[3 * (size_t)i + 2] = c.z;
    s->radius_m[i] = s->chains[chain].bound_radius_m * scale;
    s->chain_of_instance[i] = chain;
}
