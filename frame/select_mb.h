/* Internal to frame/: the `mb` selector's glue (Mason & Blake 1997) — the frame's representation
 * tree built from the visible objects and their ancestor groups, each visible group's impostor priced
 * and valued, lod_optimize_mb run from last frame's solution, and its answer turned into levels for
 * the visible objects and impostor instances to draw. Sized once per scene; a frame allocates nothing. */
#ifndef HMDLOD_FRAME_SELECT_MB_H
#define HMDLOD_FRAME_SELECT_MB_H

#include "acuity/acuity.h"
#include "lod/lod.h"
#include "scene/scene.h"

struct frm_mb;

/* For scene (its instances, groups and impostor instances must not change afterwards) and up to
 * max_visible visible objects a frame. simplify: Nirenstein et al.'s hierarchy simplification (§5.6)
 * applied that many times (0 = none): every group whose subtree is at most `simplify` groups deep
 * becomes a leaf of the tree, its objects removed, with as candidates its impostor and the union of
 * its visible objects each at one shared level (the nearest its hull keeps) — fewer, coarser choices
 * for the optimizer to consider. 0, or −1 with err on out of memory or simplify outside [0, 8]. */
int frm_mb_create(const struct scn_scene *scene, size_t max_visible, int simplify, struct frm_mb **out,
                  struct hl_error *err);
void frm_mb_destroy(struct frm_mb *mb); /* NULL is fine */

/* One frame. p is the flat problem over the visible objects (p->object_id[i] = scene instance,
 * candidates hull-reduced, cost without c0, budget_ms the optimizer's budget); cost and bp price and
 * value the impostors the same way (both eyes' triangles and vertices, 2 draws, the impostor
 * instance's projected pixels in eyes[0..1]; Funkhouser's benefit at the group's importance). An
 * object below a group with an impostor loses its null impostor (LOD_DROP): the group's impostor is
 * its coarse representation, and a hole in an opened group is what §8's assessors judged worst.
 * Writes level_out[i] per visible object (LOD_DROP where an impostor above it is drawn instead or it
 * was dropped), the impostor instances to draw in extra_index/extra_level (room for group_count;
 * *extra_count of them) and the optimizer's result in *r (cost_ms and benefit include the impostors).
 * time_limit_us: Nirenstein's limit, 0 = none. O(visible + their ancestor groups). */
void frm_mb_select(struct frm_mb *mb, const struct scn_scene *scene, const struct lod_problem *p,
                   const struct lod_cost_model *cost, const struct lod_benefit_params *bp,
                   const struct acu_eye eyes[2], double time_limit_us, uint8_t *level_out, uint32_t *extra_index,
                   uint8_t *extra_level, size_t *extra_count, struct lod_result *r);

/* After frm_mb_select: lod_tree_underused_drop on that frame's tree and answer (impostors included,
 * against the optimizer's budget p->budget_ms); 0 before the first frame. */
int frm_mb_underused_drop(const struct frm_mb *mb, double fraction);

#endif
