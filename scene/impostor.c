/* Group impostors: merge, decimate, check (Mason & Blake 1997 §3: an impostor must cost less and
 * be worth less than any implicit representation by its children, or the optimizer's Value order
 * — and its half-optimality — breaks). */
#include "scene/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

uint32_t scn_scene_find_group(const struct scn_scene *s, const char *name)
{
    for (uint32_t g = 0; s && name && g < s->group_count; ++g)
        if (strcmp(s->groups[g].name, name) == 0)
            return g;
    return SCN_NONE;
}

/* 1 when group h is `root` or lies below it (parents are stored before children, so a parent
 * index is always smaller: the walk ends). */
static int below(const struct scn_scene *s, uint32_t h, uint32_t root)
{
    for (; h != SCN_NONE; h = s->groups[h].parent)
        if (h == root)
            return 1;
    return 0;
}

/* The instance's pose at rest when the scene moves (the impostor is modelled in the group's rest
 * frame, which the replay carries with the group), else as it stands. */
static void rest_pose(const struct scn_scene *s, uint32_t i, hl_vec3d *p, hl_quatd *q)
{
    if (s->motion) {
        *p = s->motion->rest_position_m[i];
        *q = s->motion->rest_rotation[i];
    } else {
        const struct scn_instance *in = &s->instances[i];
        *p = hl_v3(in->position_m[0], in->position_m[1], in->position_m[2]);
        *q = in->rotation;
    }
}

struct weld_key {
    float p[3];
    uint32_t index;
};

static int weld_cmp(const void *a, const void *b)
{
    const struct weld_key *x = a, *y = b;
    for (int k = 0; k < 3; ++k)
        if (x->p[k] != y->p[k])
            return x->p[k] < y->p[k] ? -1 : 1;
    return x->index < y->index ? -1 : x->index > y->index;
}

/* Welds bit-identical positions (a cylinder's caps repeat its rim vertices with other normals), so
 * the decimator sees closed parts rather than open sides and loose caps; normals are then smoothed. */
static int weld(const struct scn_mesh *in, struct scn_mesh *out)
{
    struct weld_key *keys = malloc((in->vertex_count ? in->vertex_count : 1) * sizeof *keys);
    uint32_t *remap = malloc((in->vertex_count ? in->vertex_count : 1) * sizeof *remap);
    if (!keys || !remap) {
        free(keys);
        free(remap);
        return -1;
    }
    for (uint32_t i = 0; i < in->vertex_count; ++i) {
        memcpy(keys[i].p, in->positions + 3 * (size_t)i, sizeof keys[i].p);
        keys[i].index = i;
    }
    qsort(keys, in->vertex_count, sizeof *keys, weld_cmp);
    for (uint32_t k = 0; k < in->vertex_count; ++k) {
        if (k == 0 || memcmp(keys[k].p, keys[k - 1].p, sizeof keys[k].p) != 0)
            scn_mesh_add_vertex(out, hl_v3(keys[k].p[0], keys[k].p[1], keys[k].p[2]), hl_v3(0, 0, 1));
        remap[keys[k].index] = out->vertex_count - 1;
    }
    for (uint32_t t = 0; t + 2 < in->index_count; t += 3) {
        uint32_t a = remap[in->indices[t]], b = remap[in->indices[t + 1]], c = remap[in->indices[t + 2]];
        if (a != b && b != c && a != c)
            scn_mesh_add_triangle(out, a, b, c);
    }
    scn_mesh_smooth_normals(out);
    free(keys);
    free(remap);
    return out->failed ? -1 : 0;
}

/* Appends level 0 of every instance below `group`, in the group's rest frame, and counts what the
 * children cost at their finest and coarsest levels. */
static int merge_children(const struct scn_scene *s, uint32_t group, hl_vec3d origin, struct scn_mesh *merged,
                          struct scn_impostor_report *r)
{
    for (uint32_t h = group; h < s->group_count; ++h) {
        if (!below(s, h, group))
            continue;
        const struct scn_group *gr = &s->groups[h];
        for (uint32_t k = 0; k < gr->instance_count; ++k) {
            uint32_t i = s->group_instances[gr->first_instance + k];
            const struct scn_instance *in = &s->instances[i];
            const struct scn_chain *ch = &s->chains[in->chain];
            const struct scn_lod *fine = &ch->lods[0], *coarse = &ch->lods[ch->lod_count - 1];
            r->instances++;
            r->children_triangles_finest += fine->triangle_count;
            r->children_vertices_finest += fine->vertex_count;
            r->children_triangles_coarsest += coarse->triangle_count;
            r->children_vertices_coarsest += coarse->vertex_count;
            /* A chain's level is a contiguous run of the packed vertices: [lowest, highest index]. */
            uint32_t lo = UINT32_MAX, hi = 0;
            for (uint32_t j = 0; j < fine->index_count; ++j) {
                uint32_t v = s->indices[fine->first_index + j];
                lo = v < lo ? v : lo;
                hi = v > hi ? v : hi;
            }
            if (fine->index_count == 0)
                continue;
            hl_vec3d pos;
            hl_quatd rot;
            rest_pose(s, i, &pos, &rot);
            uint32_t base = merged->vertex_count;
            for (uint32_t v = lo; v <= hi; ++v) {
                const float *p = s->positions + 3 * (size_t)v, *n = s->normals + 3 * (size_t)v;
                hl_vec3d world = hl_v3_add(pos, hl_q_rotate(rot, hl_v3_scale(hl_v3(p[0], p[1], p[2]), in->scale)));
                scn_mesh_add_vertex(merged, hl_v3_sub(world, origin), hl_q_rotate(rot, hl_v3(n[0], n[1], n[2])));
            }
            for (uint32_t j = 0; j + 2 < fine->index_count; j += 3) {
                const uint32_t *t = s->indices + fine->first_index + j;
                scn_mesh_add_triangle(merged, base + t[0] - lo, base + t[1] - lo, base + t[2] - lo);
            }
        }
    }
    return merged->failed ? -1 : 0;
}

/* Funkhouser & Séquin 1993 §5: Accuracy = 1 − BaseError / Samples^m, BaseError 0.5. */
static double funkhouser_accuracy(uint64_t samples, double m)
{
    return samples > 0 ? 1.0 - 0.5 / pow((double)samples, m) : 0.0;
}

static void set_bounds(struct scn_lodset *set)
{
    const struct scn_mesh *m = &set->levels[0];
    for (int k = 0; k < 3; ++k)
        set->aabb_min_m[k] = INFINITY, set->aabb_max_m[k] = -INFINITY;
    for (uint32_t i = 0; i < m->vertex_count; ++i)
        for (int k = 0; k < 3; ++k) {
            double v = m->positions[3 * (size_t)i + k];
            set->aabb_min_m[k] = fmin(set->aabb_min_m[k], v);
            set->aabb_max_m[k] = fmax(set->aabb_max_m[k], v);
        }
    for (int k = 0; k < 3; ++k)
        set->center_m[k] = 0.5 * (set->aabb_min_m[k] + set->aabb_max_m[k]);
    double r = 0;
    for (uint32_t i = 0; i < m->vertex_count; ++i) {
        const float *p = m->positions + 3 * (size_t)i;
        r = fmax(r, hl_v3_length(hl_v3_sub(hl_v3(p[0], p[1], p[2]),
                                           hl_v3(set->center_m[0], set->center_m[1], set->center_m[2]))));
    }
    set->radius_m = r;
}

int scn_impostor_build_report(const struct scn_scene *s, uint32_t group, enum scn_simplifier simplifier,
                              uint32_t target_triangles, uint64_t hausdorff_samples, struct scn_lodset *out,
                              struct scn_impostor_report *report, struct hl_error *err)
{
    struct scn_impostor_report local;
    struct scn_impostor_report *r = report ? report : &local;
    memset(r, 0, sizeof *r);
    memset(out, 0, sizeof *out);
    if (!s || group >= s->group_count)
        return hl_fail(err, "impostor: group %u does not exist (the scene has %u)", group, s ? s->group_count : 0);
    const struct scn_group *gr = &s->groups[group];
    if (target_triangles < 1)
        return hl_fail(err, "impostor: group %s: target of 0 triangles", gr->name);

    hl_vec3d origin = s->motion ? hl_v3(s->motion->rest_group_center_m[3 * group],
                                        s->motion->rest_group_center_m[3 * group + 1],
                                        s->motion->rest_group_center_m[3 * group + 2])
                                : hl_v3(gr->center_m[0], gr->center_m[1], gr->center_m[2]);
    struct scn_mesh raw = {0}, merged = {0}, decimated = {0};
    int rc = -1;
    if (merge_children(s, group, origin, &raw, r) != 0 || weld(&raw, &merged) != 0) {
        hl_fail(err, "impostor: group %s: out of memory while merging", gr->name);
        goto done;
    }
    r->merged_triangles = merged.index_count / 3;
    r->merged_vertices = merged.vertex_count;
    if (r->instances == 0 || merged.index_count == 0) {
        hl_fail(err, "impostor: group %s: nothing below it to stand for", gr->name);
        goto done;
    }
    /* No feature lines (negative angle): they would lock every strut's cap rims, and an impostor is
     * a distant stand-in, where the silhouette matters and creases do not. */
    if (scn_mesh_decimate(&merged, target_triangles, simplifier, -1.0, &decimated, err) != 0)
        goto done;
    r->impostor_triangles = decimated.index_count / 3;
    r->impostor_vertices = decimated.vertex_count;
    r->accuracy_impostor = funkhouser_accuracy(r->impostor_vertices, 2.0);
    r->accuracy_children_coarsest = funkhouser_accuracy(r->children_vertices_coarsest, 2.0);
    r->accuracy_children_finest = funkhouser_accuracy(r->children_vertices_finest, 2.0);

    /* Mason & Blake §3: cheaper than the cheapest implicit representation (every child at its
     * coarsest drawable level) in both cost terms (Funkhouser's C1·polygons + C2·vertices) ... */
    r->cheaper = r->impostor_triangles < r->children_triangles_coarsest &&
                 r->impostor_vertices < r->children_vertices_coarsest;
    if (!r->cheaper) {
        char why[160];
        if (target_triangles < r->children_triangles_coarsest)
            snprintf(why, sizeof why, "the simplifier stopped above the %u asked for", target_triangles);
        else
            snprintf(why, sizeof why, "ask for fewer than %llu triangles", (unsigned long long)r->children_triangles_coarsest);
        hl_fail(err,
                "impostor: group %s: %u triangles / %u vertices do not cost less than its children at their "
                "coarsest (%llu / %llu), Mason & Blake's requirement: %s",
                gr->name, r->impostor_triangles, r->impostor_vertices, (unsigned long long)r->children_triangles_coarsest,
                (unsigned long long)r->children_vertices_coarsest, why);
        goto done;
    }
    /* ... and worth less: it must lose something (measured, so the cheap cost check comes first)
     * and score a lower accuracy. */
    if (scn_mesh_hausdorff(&merged, &decimated, hausdorff_samples, 1, &r->error, err) != 0)
        goto done;
    r->worse = r->error.max_m > 0.0 && r->accuracy_impostor < r->accuracy_children_coarsest;
    if (!r->worse) {
        hl_fail(err, "impostor: group %s: not worth less than its children (Hausdorff error %.6g m, accuracy %.12f vs %.12f)",
                gr->name, r->error.max_m, r->accuracy_impostor, r->accuracy_children_coarsest);
        goto done;
    }

    out->level_count = 1;
    out->levels[0] = decimated;
    decimated = (struct scn_mesh){0};
    out->error_m[0] = r->error.max_m;
    set_bounds(out);
    out->error_rel[0] = out->radius_m > 0 ? out->error_m[0] / out->radius_m : 0.0;
    out->freq[0] = (struct scn_level_freq){NAN, NAN, out->error_m[0] > 0 ? out->radius_m / out->error_m[0] : INFINITY};
    out->source_hash = scn_mesh_hash(&merged);
    snprintf(out->simplifier, sizeof out->simplifier, "impostor");
    rc = 0;
done:
    scn_mesh_free(&raw);
    scn_mesh_free(&merged);
    scn_mesh_free(&decimated);
    if (rc != 0)
        scn_lodset_free(out);
    return rc;
}

int scn_impostor_build(const struct scn_scene *s, uint32_t group, enum scn_simplifier simplifier,
                       uint32_t target_triangles, struct scn_lodset *out, struct hl_error *err)
{
    return scn_impostor_build_report(s, group, simplifier, target_triangles, 0, out, NULL, err);
}
