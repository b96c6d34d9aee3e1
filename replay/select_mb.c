/* The `mb` selector (Mason & Blake 1997 §4, §8): each frame's representation tree is the visible
 * objects and the groups above them only (DESIGN.md: per-frame work follows the visible part of the
 * hierarchy), nodes numbered groups first in the scene's parents-first order, then the objects in the
 * flat problem's order. Last frame's solution is kept per instance and per group, as levels (not
 * candidate indices, which change with the hull from frame to frame), and mapped back the way
 * lod_choice_start does. */
#include "replay/select_mb.h"

#include <stdlib.h>
#include <string.h>

enum { NONE = UINT32_MAX };

struct rpl_mb {
    uint32_t instance_count, group_count;
    size_t max_visible;
    uint32_t *group_of_instance; /* per instance: the group listing it, NONE */
    uint32_t *node_of_group;     /* per group: its node this frame, NONE outside the frame */
    uint8_t *group_last;         /* per group: last frame's state, LOD_UNSEEN when not in it */
    uint8_t *instance_last;      /* per instance: last level, LOD_MB_BELOW (under an impostor), LOD_UNSEEN */
    uint32_t *groups_seen, *objects_seen; /* last frame's groups and objects, to forget them */
    uint32_t groups_seen_count, objects_seen_count;
    uint32_t *frame_groups;      /* this frame's groups, ascending */
    uint32_t *imp_index;         /* impostor instances of this frame's groups, for their pixels */
    double *imp_px;
    /* the tree (capacity: max_visible + group_count nodes) */
    uint32_t *node_id, *parent, *first_child, *child_count, *child, *first;
    uint8_t *count, *state, *imp_above;
    double *cost_ms, *benefit;
    uint8_t *cand_level;
    void *scratch;
};

void rpl_mb_destroy(struct rpl_mb *mb)
{
    if (!mb)
        return;
    free(mb->group_of_instance), free(mb->node_of_group), free(mb->group_last), free(mb->instance_last);
    free(mb->groups_seen), free(mb->objects_seen), free(mb->frame_groups), free(mb->imp_index), free(mb->imp_px);
    free(mb->node_id), free(mb->parent), free(mb->first_child), free(mb->child_count), free(mb->child);
    free(mb->first), free(mb->count), free(mb->state), free(mb->imp_above), free(mb->cost_ms), free(mb->benefit);
    free(mb->cand_level), free(mb->scratch);
    free(mb);
}

int rpl_mb_create(const struct scn_scene *scene, size_t max_visible, struct rpl_mb **out, struct hl_error *err)
{
    *out = NULL;
    struct rpl_mb *mb = calloc(1, sizeof *mb);
    if (!mb)
        return hl_fail(err, "scene '%s': out of memory for the mb selector", scene->name);
    size_t ni = scene->instance_count ? scene->instance_count : 1, ng = scene->group_count ? scene->group_count : 1;
    size_t nodes = max_visible + scene->group_count + 1, cands = (max_visible + 1) * (LOD_MAX_LEVELS + 1) + ng;
    mb->instance_count = scene->instance_count, mb->group_count = scene->group_count;
    mb->max_visible = max_visible;
    mb->group_of_instance = malloc(ni * sizeof(uint32_t));
    mb->node_of_group = malloc(ng * sizeof(uint32_t));
    mb->group_last = malloc(ng), mb->instance_last = malloc(ni);
    mb->groups_seen = malloc(ng * sizeof(uint32_t)), mb->objects_seen = malloc((max_visible + 1) * sizeof(uint32_t));
    mb->frame_groups = malloc(ng * sizeof(uint32_t)), mb->imp_index = malloc(ng * sizeof(uint32_t));
    mb->imp_px = malloc(ng * sizeof(double));
    mb->node_id = malloc(nodes * sizeof(uint32_t)), mb->parent = malloc(nodes * sizeof(uint32_t));
    mb->first_child = malloc(nodes * sizeof(uint32_t)), mb->child_count = malloc(nodes * sizeof(uint32_t));
    mb->child = malloc(nodes * sizeof(uint32_t)), mb->first = malloc(nodes * sizeof(uint32_t));
    mb->count = malloc(nodes), mb->state = malloc(nodes), mb->imp_above = malloc(nodes);
    mb->cost_ms = malloc(cands * sizeof(double)), mb->benefit = malloc(cands * sizeof(double));
    mb->cand_level = malloc(cands);
    mb->scratch = malloc(lod_mb_scratch_bytes(nodes));
    if (!mb->group_of_instance || !mb->node_of_group || !mb->group_last || !mb->instance_last || !mb->groups_seen ||
        !mb->objects_seen || !mb->frame_groups || !mb->imp_index || !mb->imp_px || !mb->node_id || !mb->parent ||
        !mb->first_child || !mb->child_count || !mb->child || !mb->first || !mb->count || !mb->state ||
        !mb->imp_above || !mb->cost_ms || !mb->benefit || !mb->cand_level || !mb->scratch) {
        rpl_mb_destroy(mb);
        return hl_fail(err, "scene '%s': out of memory for the mb selector (%zu objects, %u groups)", scene->name,
                       max_visible, scene->group_count);
    }
    for (uint32_t i = 0; i < scene->instance_count; ++i)
        mb->group_of_instance[i] = NONE;
    for (uint32_t g = 0; g < scene->group_count; ++g) {
        const struct scn_group *gr = &scene->groups[g];
        for (uint32_t k = 0; k < gr->instance_count; ++k)
            mb->group_of_instance[scene->group_instances[gr->first_instance + k]] = g;
        mb->node_of_group[g] = NONE;
    }
    memset(mb->group_last, LOD_UNSEEN, ng);
    memset(mb->instance_last, LOD_UNSEEN, ni);
    *out = mb;
    return 0;
}

static int u32_cmp(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

static int group_has_impostor(const struct scn_scene *scene, uint32_t g)
{
    const struct scn_group *gr = &scene->groups[g];
    return gr->impostor_chain != SCN_NONE && gr->impostor_instance != SCN_NONE &&
           scene->chains[gr->impostor_chain].lod_count > 0;
}

/* Nodes, parents and children of this frame's tree; returns the number of group nodes. */
static uint32_t build_structure(struct rpl_mb *mb, const struct scn_scene *scene, const struct lod_problem *p)
{
    uint32_t ng = 0;
    for (size_t i = 0; i < p->object_count; ++i) /* the ancestors of visible objects, once each */
        for (uint32_t g = mb->group_of_instance[p->object_id[i]]; g != NONE && mb->node_of_group[g] == NONE;
             g = scene->groups[g].parent) {
            mb->node_of_group[g] = 0;
            mb->frame_groups[ng++] = g;
        }
    qsort(mb->frame_groups, ng, sizeof *mb->frame_groups, u32_cmp); /* the scene's parents-first order */
    size_t nodes = ng + p->object_count;
    for (uint32_t k = 0; k < ng; ++k) {
        uint32_t g = mb->frame_groups[k], pg = scene->groups[g].parent;
        mb->node_of_group[g] = k;
        mb->node_id[k] = scene->instance_count + g; /* stable and apart from the objects' ids */
        mb->parent[k] = pg == SCN_NONE ? LOD_MB_ROOT : mb->node_of_group[pg];
        mb->imp_above[k] = group_has_impostor(scene, g) || (pg != SCN_NONE && mb->imp_above[mb->parent[k]]);
    }
    for (size_t i = 0; i < p->object_count; ++i) {
        uint32_t k = ng + (uint32_t)i, g = mb->group_of_instance[p->object_id[i]];
        mb->node_id[k] = p->object_id[i];
        mb->parent[k] = g == NONE ? LOD_MB_ROOT : mb->node_of_group[g];
        mb->imp_above[k] = g != NONE && mb->imp_above[mb->parent[k]];
    }
    /* children contiguous per parent, in node order */
    memset(mb->child_count, 0, nodes * sizeof *mb->child_count);
    for (size_t k = 0; k < nodes; ++k)
        if (mb->parent[k] != LOD_MB_ROOT)
            mb->child_count[mb->parent[k]]++;
    uint32_t at = 0;
    for (size_t k = 0; k < nodes; ++k) {
        mb->first_child[k] = at;
        at += mb->child_count[k];
        mb->child_count[k] = 0;
    }
    for (size_t k = 0; k < nodes; ++k) {
        uint32_t q = mb->parent[k];
        if (q != LOD_MB_ROOT)
            mb->child[mb->first_child[q] + mb->child_count[q]++] = (uint32_t)k;
    }
    return ng;
}

/* Candidate index for last frame's level: the same level or the nearest coarser (lod_choice_start). */
static uint8_t start_of_level(const uint8_t *level, uint8_t count, uint8_t last)
{
    if (last == LOD_UNSEEN || count == 0)
        return 0;
    if (last == LOD_MB_BELOW)
        return LOD_MB_BELOW;
    for (int j = count - 1; j >= 0; --j)
        if (level[j] >= last) /* LOD_DROP = 255 is the coarsest of all */
            return (uint8_t)j;
    return 0;
}

void rpl_mb_select(struct rpl_mb *mb, const struct scn_scene *scene, const struct lod_problem *p,
                   const struct lod_cost_model *cost, const struct lod_benefit_params *bp,
                   const struct acu_eye eyes[2], double time_limit_us, uint8_t *level_out, uint32_t *extra_index,
                   uint8_t *extra_level, size_t *extra_count, struct lod_result *r)
{
    *extra_count = 0;
    size_t n = p->object_count < mb->max_visible ? p->object_count : mb->max_visible;
    struct lod_problem pv = *p;
    pv.object_count = n;
    uint32_t ng = build_structure(mb, scene, &pv);
    size_t nodes = ng + n;

    /* The impostors' projected pixels (of the impostor instance's sphere: what is drawn, and what
     * the frame's predicted cost counts), in one batch. */
    uint32_t ni = 0;
    for (uint32_t k = 0; k < ng; ++k)
        if (group_has_impostor(scene, mb->frame_groups[k]))
            mb->imp_index[ni++] = scene->groups[mb->frame_groups[k]].impostor_instance;
    acu_compute_pixels(eyes, 2, scene->center_m, scene->radius_m, mb->imp_index, ni, mb->imp_px);

    uint32_t c = 0, j = 0;
    for (uint32_t k = 0; k < ng; ++k) {
        uint32_t g = mb->frame_groups[k];
        const struct scn_group *gr = &scene->groups[g];
        mb->first[k] = c;
        mb->count[k] = 0;
        mb->state[k] = mb->group_last[g];
        if (!group_has_impostor(scene, g))
            continue;
        /* One impostor level, both eyes, 2 draws like an object (replay/select.c); Funkhouser's
         * benefit at the group's importance, no hysteresis (it has one level). */
        const struct scn_lod *lod = &scene->chains[gr->impostor_chain].lods[0];
        double px = mb->imp_px[j++];
        mb->cost_ms[c] = lod_cost_object_ms(cost, 2.0 * lod->triangle_count, 2.0 * lod->vertex_count, px, 2.0);
        const uint32_t first0 = 0, samples = lod->vertex_count;
        const uint8_t count1 = 1, level0 = 0, ceiling0 = 0, unseen = LOD_UNSEEN;
        const double importance = gr->importance;
        lod_benefit_fill(bp, 1, &first0, &count1, &level0, &samples, &px, &importance, &ceiling0, &unseen,
                         &mb->benefit[c]);
        mb->cand_level[c] = 0;
        mb->count[k] = 1;
        ++c;
    }
    for (size_t i = 0; i < n; ++i) {
        uint32_t k = ng + (uint32_t)i, f = p->first[i];
        uint8_t cnt = p->count[i];
        /* Under an impostor the null impostor goes: the group's impostor is the coarse choice. The rest
         * of the hull stays a hull (a suffix of a concave chain). */
        if (mb->imp_above[k] && cnt > 1 && p->level[f] == LOD_DROP)
            ++f, --cnt;
        mb->first[k] = c;
        mb->count[k] = cnt;
        memcpy(&mb->cost_ms[c], &p->cost_ms[f], cnt * sizeof(double));
        memcpy(&mb->benefit[c], &p->benefit[f], cnt * sizeof(double));
        memcpy(&mb->cand_level[c], &p->level[f], cnt);
        mb->state[k] = start_of_level(&mb->cand_level[c], cnt, mb->instance_last[p->object_id[i]]);
        c += cnt;
    }

    struct lod_tree t = {nodes, mb->node_id, mb->parent, mb->first_child, mb->child_count, mb->child, mb->first,
                         mb->count, mb->cost_ms, mb->benefit, p->budget_ms};
    lod_optimize_mb(&t, time_limit_us, mb->scratch, mb->state, r);

    /* Last frame is forgotten, this one remembered (as levels, and BELOW under a drawn impostor). */
    for (uint32_t k = 0; k < mb->objects_seen_count; ++k)
        mb->instance_last[mb->objects_seen[k]] = LOD_UNSEEN;
    for (uint32_t k = 0; k < mb->groups_seen_count; ++k)
        mb->group_last[mb->groups_seen[k]] = LOD_UNSEEN;
    for (uint32_t k = 0; k < ng; ++k) {
        uint32_t g = mb->frame_groups[k];
        uint8_t s = mb->state[k];
        if (s < LOD_MB_BELOW) {
            extra_index[*extra_count] = scene->groups[g].impostor_instance;
            extra_level[(*extra_count)++] = mb->cand_level[mb->first[k] + s];
        }
        mb->group_last[g] = s == LOD_DROPPED ? LOD_UNSEEN : s;
        mb->groups_seen[k] = g;
        mb->node_of_group[g] = NONE;
    }
    mb->groups_seen_count = ng;
    for (size_t i = 0; i < n; ++i) {
        uint32_t k = ng + (uint32_t)i, inst = p->object_id[i];
        uint8_t s = mb->state[k];
        level_out[i] = s < LOD_MB_BELOW ? mb->cand_level[mb->first[k] + s] : LOD_DROP;
        mb->instance_last[inst] = s < LOD_MB_BELOW ? level_out[i] : s == LOD_MB_BELOW ? LOD_MB_BELOW : LOD_UNSEEN;
        mb->objects_seen[i] = inst;
    }
    for (size_t i = n; i < p->object_count; ++i) /* beyond the capacity given at create: not drawn */
        level_out[i] = LOD_DROP;
    mb->objects_seen_count = (uint32_t)n;
}
