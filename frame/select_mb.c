/* The `mb` selector (Mason & Blake 1997 §4, §8): each frame's representation tree is the visible
 * objects and the groups above them only (DESIGN.md: per-frame work follows the visible part of the
 * hierarchy), nodes numbered groups first in the scene's parents-first order, then the objects in the
 * flat problem's order. Last frame's solution is kept per instance and per group, as levels (not
 * candidate indices, which change with the hull from frame to frame), and mapped back the way
 * lod_choice_start does. */
#include "frame/select_mb.h"
#include "frame/select.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { NONE = UINT32_MAX };

struct frm_mb {
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
    size_t tree_nodes;     /* the last frame's tree and budget, for frm_mb_underused_drop */
    double tree_budget_ms;
    /* hierarchy simplification (Nirenstein et al. §5.6): per group COLLAPSED (a leaf of the tree),
     * UNDER (below one: not in the tree) or 0; per instance its collapsed ancestor or NONE; per frame
     * the visible objects' nodes (NONE under a collapsed group) and each collapsed node's objects */
    int simplify;
    uint8_t *collapse;
    uint32_t *collapsed_of_instance;
    uint32_t *node_of_object, *members_first, *members_count, *members;
};

enum { COLLAPSED = 1, UNDER = 2 };
/* A collapsed group's impostor among its candidates' levels: coarser than any shared level, finer
 * than LOD_MB_BELOW and the other states (start_of_level orders by level). */
enum { IMPOSTOR_LEVEL = 250 };

void frm_mb_destroy(struct frm_mb *mb)
{
    if (!mb)
        return;
    free(mb->group_of_instance), free(mb->node_of_group), free(mb->group_last), free(mb->instance_last);
    free(mb->groups_seen), free(mb->objects_seen), free(mb->frame_groups), free(mb->imp_index), free(mb->imp_px);
    free(mb->node_id), free(mb->parent), free(mb->first_child), free(mb->child_count), free(mb->child);
    free(mb->first), free(mb->count), free(mb->state), free(mb->imp_above), free(mb->cost_ms), free(mb->benefit);
    free(mb->cand_level), free(mb->scratch);
    free(mb->collapse), free(mb->collapsed_of_instance), free(mb->node_of_object), free(mb->members_first);
    free(mb->members_count), free(mb->members);
    free(mb);
}

/* Which groups simplification turns into leaves: those whose subtree is at most `simplify` groups deep
 * (a group of objects only is 1 deep) and whose parent is deeper; the groups and objects below them
 * leave the tree. Groups are in parents-first order, so one reverse pass finds the depths. */
static void mark_collapsed(struct frm_mb *mb, const struct scn_scene *scene)
{
    uint32_t ng = scene->group_count;
    memset(mb->collapse, 0, ng ? ng : 1);
    for (uint32_t i = 0; i < scene->instance_count; ++i)
        mb->collapsed_of_instance[i] = NONE;
    if (mb->simplify == 0)
        return;
    for (uint32_t g = 0; g < ng; ++g)
        mb->node_of_group[g] = 1; /* borrowed as the depth; reset to NONE below */
    for (uint32_t g = ng; g-- > 0;) {
        uint32_t pg = scene->groups[g].parent;
        if (pg != SCN_NONE && mb->node_of_group[pg] < mb->node_of_group[g] + 1)
            mb->node_of_group[pg] = mb->node_of_group[g] + 1;
    }
    for (uint32_t g = 0; g < ng; ++g) { /* parents first: a parent's mark is known */
        uint32_t pg = scene->groups[g].parent;
        if (pg != SCN_NONE && mb->collapse[pg])
            mb->collapse[g] = UNDER;
        else if ((int)mb->node_of_group[g] <= mb->simplify)
            mb->collapse[g] = COLLAPSED;
    }
    for (uint32_t i = 0; i < scene->instance_count; ++i) {
        uint32_t top = NONE;
        for (uint32_t g = mb->group_of_instance[i]; g != NONE && g != SCN_NONE; g = scene->groups[g].parent)
            if (mb->collapse[g] == COLLAPSED)
                top = g;
        mb->collapsed_of_instance[i] = top;
    }
    for (uint32_t g = 0; g < ng; ++g)
        mb->node_of_group[g] = NONE;
}

int frm_mb_create(const struct scn_scene *scene, size_t max_visible, int simplify, struct frm_mb **out,
                  struct hl_error *err)
{
    *out = NULL;
    if (simplify < 0 || simplify > 8)
        return hl_fail(err, "--mb-simplify: %d is outside [0, 8]", simplify);
    struct frm_mb *mb = calloc(1, sizeof *mb);
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
    mb->simplify = simplify;
    mb->collapse = malloc(ng), mb->collapsed_of_instance = malloc(ni * sizeof(uint32_t));
    mb->node_of_object = malloc((max_visible + 1) * sizeof(uint32_t));
    mb->members_first = malloc(ng * sizeof(uint32_t)), mb->members_count = malloc(ng * sizeof(uint32_t));
    mb->members = malloc((max_visible + 1) * sizeof(uint32_t));
    if (!mb->collapse || !mb->collapsed_of_instance || !mb->node_of_object || !mb->members_first ||
        !mb->members_count || !mb->members) {
        frm_mb_destroy(mb);
        return hl_fail(err, "scene '%s': out of memory for the mb selector", scene->name);
    }
    if (!mb->group_of_instance || !mb->node_of_group || !mb->group_last || !mb->instance_last || !mb->groups_seen ||
        !mb->objects_seen || !mb->frame_groups || !mb->imp_index || !mb->imp_px || !mb->node_id || !mb->parent ||
        !mb->first_child || !mb->child_count || !mb->child || !mb->first || !mb->count || !mb->state ||
        !mb->imp_above || !mb->cost_ms || !mb->benefit || !mb->cand_level || !mb->scratch) {
        frm_mb_destroy(mb);
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
    mark_collapsed(mb, scene);
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

/* Nodes, parents and children of this frame's tree; returns the number of group nodes and sets
 * *object_nodes. Groups under a collapsed one and objects under a collapsed group are not nodes. */
static uint32_t build_structure(struct frm_mb *mb, const struct scn_scene *scene, const struct lod_problem *p,
                                uint32_t *object_nodes)
{
    uint32_t ng = 0;
    for (size_t i = 0; i < p->object_count; ++i) /* the ancestors of visible objects, once each */
        for (uint32_t g = mb->group_of_instance[p->object_id[i]]; g != NONE && mb->node_of_group[g] == NONE;
             g = scene->groups[g].parent) {
            mb->node_of_group[g] = 0;
            mb->frame_groups[ng++] = g;
        }
    qsort(mb->frame_groups, ng, sizeof *mb->frame_groups, u32_cmp); /* the scene's parents-first order */
    uint32_t kept = 0;
    for (uint32_t k = 0; k < ng; ++k) { /* those under a collapsed group leave the tree */
        uint32_t g = mb->frame_groups[k];
        if (mb->collapse[g] == UNDER)
            mb->node_of_group[g] = NONE;
        else
            mb->frame_groups[kept++] = g;
    }
    ng = kept;
    for (uint32_t k = 0; k < ng; ++k) {
        uint32_t g = mb->frame_groups[k], pg = scene->groups[g].parent;
        mb->node_of_group[g] = k;
        mb->node_id[k] = scene->instance_count + g; /* stable and apart from the objects' ids */
        mb->parent[k] = pg == SCN_NONE ? LOD_MB_ROOT : mb->node_of_group[pg];
        mb->imp_above[k] = group_has_impostor(scene, g) || (pg != SCN_NONE && mb->imp_above[mb->parent[k]]);
        mb->members_count[k] = 0;
    }
    uint32_t no = 0;
    for (size_t i = 0; i < p->object_count; ++i) {
        uint32_t top = mb->collapsed_of_instance[p->object_id[i]];
        if (top != NONE) { /* a member of its collapsed group's node */
            mb->node_of_object[i] = NONE;
            mb->members_count[mb->node_of_group[top]]++;
            continue;
        }
        uint32_t k = ng + no++, g = mb->group_of_instance[p->object_id[i]];
        mb->node_of_object[i] = k;
        mb->node_id[k] = p->object_id[i];
        mb->parent[k] = g == NONE ? LOD_MB_ROOT : mb->node_of_group[g];
        mb->imp_above[k] = g != NONE && mb->imp_above[mb->parent[k]];
    }
    uint32_t at = 0; /* members contiguous per collapsed node, in object order */
    for (uint32_t k = 0; k < ng; ++k) {
        mb->members_first[k] = at;
        at += mb->members_count[k];
        mb->members_count[k] = 0;
    }
    for (size_t i = 0; i < p->object_count; ++i) {
        uint32_t top = mb->collapsed_of_instance[p->object_id[i]];
        if (top != NONE) {
            uint32_t k = mb->node_of_group[top];
            mb->members[mb->members_first[k] + mb->members_count[k]++] = (uint32_t)i;
        }
    }
    size_t nodes = ng + no;
    /* children contiguous per parent, in node order */
    memset(mb->child_count, 0, nodes * sizeof *mb->child_count);
    for (size_t k = 0; k < nodes; ++k)
        if (mb->parent[k] != LOD_MB_ROOT)
            mb->child_count[mb->parent[k]]++;
    at = 0;
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
    *object_nodes = no;
    return ng;
}

/* Object i's candidate for a collapsed group's shared level l: the finest drawn level at or coarser
 * than l that its hull kept, else its coarsest drawn one; −1 when it has none (only LOD_DROP). */
static int member_candidate(const struct lod_problem *p, size_t i, uint8_t l)
{
    int best = -1, coarsest = -1;
    for (uint32_t c = p->first[i]; c < p->first[i] + p->count[i]; ++c) {
        uint8_t v = p->level[c];
        if (v == LOD_DROP)
            continue;
        if (v >= l && (best < 0 || v < p->level[best]))
            best = (int)c;
        if (coarsest < 0 || v > p->level[coarsest])
            coarsest = (int)c;
    }
    return best >= 0 ? best : coarsest;
}

/* A collapsed group's candidates from c on: its impostor (when it has one, already at c) and, for each
 * shared level, the union of its visible objects there (Σ cost, Σ benefit); hull-reduced like an
 * object's. Returns the candidates written. */
static uint8_t collapsed_candidates(struct frm_mb *mb, const struct lod_problem *p, uint32_t k, uint32_t c,
                                    uint8_t with_impostor)
{
    uint8_t levels = 0;
    for (uint32_t m = 0; m < mb->members_count[k]; ++m) {
        size_t i = mb->members[mb->members_first[k] + m];
        for (uint32_t q = p->first[i]; q < p->first[i] + p->count[i]; ++q)
            if (p->level[q] != LOD_DROP && p->level[q] + 1 > levels)
                levels = (uint8_t)(p->level[q] + 1);
    }
    if (levels > LOD_MAX_LEVELS)
        levels = LOD_MAX_LEVELS;
    uint8_t n = with_impostor;
    for (int l = levels - 1; l >= 0; --l, ++n) {
        double cost = 0.0, benefit = 0.0;
        for (uint32_t m = 0; m < mb->members_count[k]; ++m) {
            size_t i = mb->members[mb->members_first[k] + m];
            int q = member_candidate(p, i, (uint8_t)l);
            if (q >= 0)
                cost += p->cost_ms[q], benefit += p->benefit[q];
        }
        mb->cost_ms[c + n] = cost;
        mb->benefit[c + n] = benefit;
        mb->cand_level[c + n] = (uint8_t)l;
    }
    uint32_t first = c;
    lod_hull_reduce(1, &first, &n, mb->cost_ms, mb->benefit, mb->cand_level, INFINITY, NULL);
    return n;
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

void frm_mb_select(struct frm_mb *mb, const struct scn_scene *scene, const struct lod_problem *p,
                   const struct lod_cost_model *cost, const struct lod_benefit_params *bp,
                   const struct acu_eye eyes[2], double time_limit_us, uint8_t *level_out, uint32_t *extra_index,
                   uint8_t *extra_level, size_t *extra_count, struct lod_result *r)
{
    *extra_count = 0;
    size_t n = p->object_count < mb->max_visible ? p->object_count : mb->max_visible;
    struct lod_problem pv = *p;
    pv.object_count = n;
    uint32_t object_nodes = 0;
    uint32_t ng = build_structure(mb, scene, &pv, &object_nodes);
    size_t nodes = ng + object_nodes;

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
        uint8_t with_impostor = 0;
        if (group_has_impostor(scene, g)) {
            /* One impostor level, both eyes, 2 draws like an object (frame/select.c); Funkhouser's
             * benefit at the group's importance, no hysteresis (it has one level). */
            const struct scn_lod *lod = &scene->chains[gr->impostor_chain].lods[0];
            double px = mb->imp_px[j++];
            mb->cost_ms[c] = frm_level_cost_ms(cost, &scene->chains[gr->impostor_chain], 0, px, 0);
            const uint32_t first0 = 0, samples = lod->vertex_count;
            const uint8_t count1 = 1, level0 = 0, ceiling0 = 0, unseen = LOD_UNSEEN;
            const double importance = gr->importance;
            lod_benefit_fill(bp, 1, &first0, &count1, &level0, &samples, &px, &importance, &ceiling0, &unseen,
                             NULL, &mb->benefit[c]);
            mb->cand_level[c] = mb->collapse[g] == COLLAPSED ? IMPOSTOR_LEVEL : 0;
            with_impostor = 1;
        }
        if (mb->collapse[g] == COLLAPSED) { /* a leaf now: last frame's choice kept as a level */
            mb->count[k] = collapsed_candidates(mb, &pv, k, c, with_impostor);
            mb->state[k] = start_of_level(&mb->cand_level[c], mb->count[k], mb->group_last[g]);
        } else {
            mb->count[k] = with_impostor;
        }
        c += mb->count[k];
    }
    for (size_t i = 0; i < n; ++i) {
        uint32_t k = mb->node_of_object[i], f = p->first[i];
        if (k == NONE)
            continue;
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
    mb->tree_nodes = nodes, mb->tree_budget_ms = p->budget_ms;

    /* Last frame is forgotten, this one remembered (as levels, and BELOW under a drawn impostor). */
    for (uint32_t k = 0; k < mb->objects_seen_count; ++k)
        mb->instance_last[mb->objects_seen[k]] = LOD_UNSEEN;
    for (uint32_t k = 0; k < mb->groups_seen_count; ++k)
        mb->group_last[mb->groups_seen[k]] = LOD_UNSEEN;
    for (uint32_t k = 0; k < ng; ++k) {
        uint32_t g = mb->frame_groups[k];
        uint8_t s = mb->state[k];
        uint8_t level = s < LOD_MB_BELOW ? mb->cand_level[mb->first[k] + s] : LOD_DROP;
        int collapsed = mb->collapse[g] == COLLAPSED;
        /* A group's one candidate is its impostor; a collapsed group's are its impostor and its objects
         * at shared levels. */
        if (s < LOD_MB_BELOW && (!collapsed || level == IMPOSTOR_LEVEL)) {
            extra_index[*extra_count] = scene->groups[g].impostor_instance;
            extra_level[(*extra_count)++] = 0;
        }
        if (collapsed) {
            for (uint32_t m = 0; m < mb->members_count[k]; ++m) {
                size_t i = mb->members[mb->members_first[k] + m];
                int q = s < LOD_MB_BELOW && level != IMPOSTOR_LEVEL ? member_candidate(&pv, i, level) : -1;
                level_out[i] = q >= 0 ? p->level[q] : LOD_DROP;
            }
            mb->group_last[g] = s < LOD_MB_BELOW ? level : s == LOD_MB_BELOW ? LOD_MB_BELOW : LOD_UNSEEN;
        } else {
            mb->group_last[g] = s == LOD_DROPPED ? LOD_UNSEEN : s;
        }
        mb->groups_seen[k] = g;
        mb->node_of_group[g] = NONE;
    }
    mb->groups_seen_count = ng;
    for (size_t i = 0; i < n; ++i) {
        uint32_t k = mb->node_of_object[i], inst = p->object_id[i];
        mb->objects_seen[i] = inst;
        if (k == NONE) /* under a collapsed group: its level was set above */
            continue;
        uint8_t s = mb->state[k];
        level_out[i] = s < LOD_MB_BELOW ? mb->cand_level[mb->first[k] + s] : LOD_DROP;
        mb->instance_last[inst] = s < LOD_MB_BELOW ? level_out[i] : s == LOD_MB_BELOW ? LOD_MB_BELOW : LOD_UNSEEN;
    }
    for (size_t i = n; i < p->object_count; ++i) /* beyond the capacity given at create: not drawn */
        level_out[i] = LOD_DROP;
    mb->objects_seen_count = (uint32_t)n;
}

int frm_mb_underused_drop(const struct frm_mb *mb, double fraction)
{
    struct lod_tree t = {mb->tree_nodes, mb->node_id, mb->parent, mb->first_child, mb->child_count, mb->child,
                         mb->first, mb->count, mb->cost_ms, mb->benefit, mb->tree_budget_ms};
    return lod_tree_underused_drop(&t, mb->state, fraction);
}
