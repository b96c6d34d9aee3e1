/* A scene file as read (scenefile.c) becomes a scene: each mesh entry one chain (built-in shapes
 * directly, files through the asset resolver), the instances with their world spheres, the groups
 * reordered parents first with their bounds, and the motions. */
#include "scene/scenefile_internal.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

int scn_scenefile_path_is_lod(const char *path)
{
    size_t n = strlen(path);
    return n > 4 && strcasecmp(path + n - 4, ".lod") == 0;
}

int scn_scenefile_resolve_default(void *user, const char *path, struct scn_lodset *out, struct hl_error *err)
{
    const struct scn_chain_store *store = user;
    if (scn_scenefile_path_is_lod(path))
        return scn_lodfile_read(path, out, err);
    struct scn_mesh mesh = {0};
    struct scn_import_report report;
    if (scn_mesh_import(path, &mesh, &report, err) != 0)
        return -1;
    uint64_t hash = scn_mesh_hash(&mesh);
    if (store && store->load(store->user, path, hash, out) == 0) {
        scn_mesh_free(&mesh);
        return 0;
    }
    /* 1, 1/4, 1/16, 1/64 of the triangles: the spacing of Reddy's field object, 3928 → 76; meshopt is
     * fast enough to run at load (PLATFORM.md §7); `hmdlod lodgen` makes a .lod with OpenMesh when
     * the quality matters. */
    /* 2^17 Hausdorff samples per level instead of lodgen's 2^20: the error only feeds the geometric
     * reading here, and a first load of the bunny takes ~1 s instead of ~6 s (bound ~3× looser). */
    struct scn_lodgen_params p = {.simplifier = SCN_SIMPLIFIER_MESHOPT, .ratio_count = 4,
                                  .ratios = {1.0, 1.0 / 4, 1.0 / 16, 1.0 / 64}, .hausdorff_samples = 1u << 17};
    int rc = scn_lodgen_build(&mesh, &p, out, err);
    scn_mesh_free(&mesh);
    if (rc == 0 && store)
        store->save(store->user, path, hash, out);
    return rc;
}

/* One chain per mesh entry. */
static int sf_add_mesh(const struct sf_file *f, const struct sf_mesh *m, const struct scn_asset_resolver *resolver,
                       struct scn_scene *s, struct hl_error *err)
{
    uint32_t chain = s->chain_count;
    int rc = 0;
    switch (m->builtin) {
    case SF_FIELD_OBJECT:
        rc = scn_field_add_object_chain(s, m->name, err);
        break;
    case SF_CHAIR:
        rc = scn_auditorium_add_chair_chain(s, m->name, err);
        break;
    case SF_BOX: {
        struct scn_mesh box = {0};
        scn_mesh_add_box(&box, hl_v3(0, 0, 0), hl_v3(0.5 * m->size_m[0], 0.5 * m->size_m[1], 0.5 * m->size_m[2]),
                         hl_q_identity());
        rc = scn_scene_add_chain(s, m->name, &box, 1, err);
        scn_mesh_free(&box);
        break;
    }
    case SF_FILE: {
        struct stat st;
        int found = stat(m->path, &st) == 0;
        const char *why = !found ? strerror(errno) : !S_ISREG(st.st_mode) ? "not a regular file" : NULL;
        if (why)
            return hl_fail(err, "%s: %s.path: mesh \"%s\": cannot open \"%s\" (looked for %s): %s", f->file,
                           m->where, m->name, m->given, m->path, why);
        struct scn_lodset set;
        memset(&set, 0, sizeof set);
        struct hl_error inner = {{0}};
        if (resolver->resolve(resolver->user, m->path, &set, &inner) != 0) {
            scn_lodset_free(&set);
            return hl_fail(err, "%s: %s.path: mesh \"%s\": %s", f->file, m->where, m->name, inner.msg);
        }
        if (m->recenter) { /* models come in their authoring tool's frame; the scene wants them at 0 */
            for (int l = 0; l < set.level_count; ++l)
                for (uint32_t v = 0; v < set.levels[l].vertex_count; ++v)
                    for (int k = 0; k < 3; ++k)
                        set.levels[l].positions[3 * (size_t)v + k] -= (float)set.center_m[k];
            for (int k = 0; k < 3; ++k) {
                set.aabb_min_m[k] -= set.center_m[k];
                set.aabb_max_m[k] -= set.center_m[k];
                set.center_m[k] = 0.0;
            }
        }
        rc = scn_scene_add_lodset(s, m->name, &set, &inner);
        if (rc != 0)
            hl_fail(err, "%s: %s: mesh \"%s\": %s", f->file, m->where, m->name, inner.msg);
        scn_lodset_free(&set);
        if (rc != 0)
            return -1;
        if (s->chain_count != chain + 1)
            return hl_fail(err, "%s: %s: mesh \"%s\" did not become one chain", f->file, m->where, m->name);
        return 0;
    }
    }
    return rc != 0 ? -1 : 0;
}

/* Parents before children (what scn_scene and the cull expect): breadth first from the roots in file
 * order, so that each group's children are consecutive. order[new] = file index. */
static int sf_order_groups(const struct sf_file *f, struct scn_scene *s, const uint32_t *mesh_chain,
                           struct hl_error *err)
{
    uint32_t ng = f->group_count, ni = f->instance_count;
    uint32_t *order = malloc(ng * sizeof *order), *new_of = malloc(ng * sizeof *new_of);
    uint32_t *kids = malloc(ng * sizeof *kids), *kid_start = calloc(ng + 1, sizeof *kid_start);
    uint32_t *member_start = calloc(ng + 1, sizeof *member_start);
    s->groups = calloc(ng, sizeof *s->groups);
    s->group_children = calloc(ng, sizeof *s->group_children);
    s->group_instances = calloc(ni, sizeof *s->group_instances);
    int rc = -1;
    if (!order || !new_of || !kids || !kid_start || !member_start || !s->groups || !s->group_children ||
        !s->group_instances) {
        hl_fail(err, "%s: out of memory for %u groups", f->file, ng);
        goto done;
    }
    s->group_count = ng;
    /* children of each group, in file order (counting sort) */
    for (uint32_t g = 0; g < ng; ++g)
        if (f->groups[g].parent != SCN_NONE)
            kid_start[f->groups[g].parent + 1]++;
    for (uint32_t g = 0; g < ng; ++g)
        kid_start[g + 1] += kid_start[g];
    {
        uint32_t *fill = new_of; /* borrowed as a cursor until the order is known */
        memcpy(fill, kid_start, ng * sizeof *fill);
        for (uint32_t g = 0; g < ng; ++g)
            if (f->groups[g].parent != SCN_NONE)
                kids[fill[f->groups[g].parent]++] = g;
    }
    uint32_t tail = 0;
    for (uint32_t g = 0; g < ng; ++g)
        if (f->groups[g].parent == SCN_NONE)
            order[tail++] = g;
    for (uint32_t head = 0; head < tail; ++head) {
        uint32_t g = order[head];
        s->groups[head].first_child = tail;
        s->groups[head].child_count = kid_start[g + 1] - kid_start[g];
        for (uint32_t k = kid_start[g]; k < kid_start[g + 1]; ++k)
            order[tail++] = kids[k];
    }
    if (tail != ng) { /* sf_check_cycles ran before; this is a guard, not a path */
        hl_fail(err, "%s: groups: %u groups are not reachable from a root (a cycle)", f->file, ng - tail);
        goto done;
    }
    for (uint32_t k = 0; k < ng; ++k)
        new_of[order[k]] = k;
    /* each group's instances in the order its list gave them */
    for (uint32_t i = 0; i < ni; ++i)
        if (f->owner[i] != SCN_NONE)
            member_start[new_of[f->owner[i]] + 1]++;
    for (uint32_t k = 0; k < ng; ++k)
        member_start[k + 1] += member_start[k];
    for (uint32_t i = 0; i < ni; ++i)
        if (f->owner[i] != SCN_NONE)
            s->group_instances[member_start[new_of[f->owner[i]]] + f->member_order[i]] = i;
    for (uint32_t k = 0; k < ng; ++k) {
        const struct sf_group *src = &f->groups[order[k]];
        struct scn_group *g = &s->groups[k];
        snprintf(g->name, sizeof g->name, "%s", src->name);
        g->parent = src->parent == SCN_NONE ? SCN_NONE : new_of[src->parent];
        g->first_instance = member_start[k];
        g->instance_count = member_start[k + 1] - member_start[k];
        g->impostor_chain = src->impostor_mesh == SCN_NONE ? SCN_NONE : mesh_chain[src->impostor_mesh];
        g->importance = src->importance;
        for (uint32_t c = 0; c < g->child_count; ++c)
            s->group_children[g->first_child + c] = g->first_child + c;
    }
    scn_scene_group_bounds(s);
    rc = scn_scene_check_groups(s, err);
    if (rc == 0) /* after the bounds: the impostor sits at its group's centre */
        rc = scn_scene_add_impostor_instances(s, err);
    if (rc == 0 && f->motion_count > 0) {
        if (scn_scene_motion_create(s, err) != 0)
            rc = -1;
        for (uint32_t k = 0; rc == 0 && k < ng; ++k)
            if (f->groups[order[k]].motion != SCN_NONE)
                s->motion->group_motion[k] = f->motions[f->groups[order[k]].motion];
    }
done:
    free(order);
    free(new_of);
    free(kids);
    free(kid_start);
    free(member_start);
    return rc;
}

int sf_file_build(const struct sf_file *f, const struct scn_asset_resolver *resolver, struct scn_scene *s,
                  struct hl_error *err)
{
    static const struct scn_asset_resolver default_resolver = {scn_scenefile_resolve_default, NULL};
    if (!resolver)
        resolver = &default_resolver;
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "%s", f->name);
    uint32_t *mesh_chain = malloc(f->mesh_count * sizeof *mesh_chain);
    int rc = -1;
    if (!mesh_chain) {
        hl_fail(err, "%s: out of memory", f->file);
        goto done;
    }
    for (uint32_t m = 0; m < f->mesh_count; ++m) {
        mesh_chain[m] = s->chain_count;
        if (sf_add_mesh(f, &f->meshes[m], resolver, s, err) != 0)
            goto done;
    }
    uint32_t ni = f->instance_count;
    if (scn_scene_alloc_instances(s, ni, err) != 0)
        goto done;
    s->importance = malloc(ni * sizeof *s->importance);
    if (!s->importance) {
        hl_fail(err, "%s: out of memory for %u instances", f->file, ni);
        goto done;
    }
    for (uint32_t i = 0; i < ni; ++i) {
        const struct sf_instance *in = &f->instances[i];
        /* The world sphere follows the chain's own (an imported model need not be centred on its
         * origin): centre p + R·(s·c), radius s·r, as scn_scene_set_instance computes it. */
        scn_scene_set_instance(s, i, mesh_chain[in->mesh], in->position_m, in->rotation, in->scale, in->color);
        s->importance[i] = in->importance;
    }
    if (f->group_count > 0) {
        if (sf_order_groups(f, s, mesh_chain, err) != 0)
            goto done;
    } else if (f->motion_count > 0 && scn_scene_motion_create(s, err) != 0) {
        goto done;
    }
    if (s->motion)
        for (uint32_t i = 0; i < ni; ++i)
            if (f->instances[i].motion != SCN_NONE)
                s->motion->instance_motion[i] = f->motions[f->instances[i].motion];
    rc = 0;
done:
    free(mesh_chain);
    if (rc != 0)
        scn_scene_free(s);
    return rc;
}
