/* Internal to bench/: the per-frame work of `hmdlod bench optimizer` on the embeddable core only
 * (acuity + lod; scene/ for the cull, frame/ for the union frustum): a display's eyes and limits,
 * synthetic 4-level chains, a cost model, and one frame's problem built from a head pose
 * (bench/bench_optimizer_frame.c). The runs behind the tables are bench/bench_optimizer_runs.h's;
 * the tables are printed by bench/bench_optimizer.c. */
#ifndef HMDLOD_BENCH_OPTIMIZER_FRAME_H
#define HMDLOD_BENCH_OPTIMIZER_FRAME_H

#include "hmd/hmd.h"
#include "lod/lod.h"
#include "frame/frame.h"
#include "scene/scene.h"

enum { BCH_OPT_LEVELS = 4, BCH_OPT_CHAINS = 4 };

/* What does not change during a run: both eyes of the display (head frame), Reddy's limits for its
 * ξ, the contrast criterion's limits (its CSF table is the file's own, filled once), the union
 * frustum for the cull, the synthetic chains (with lost-contrast spectra) and the cost model. */
struct bch_opt_view {
    struct hmd_eye eye[2];
    double width_px, height_px;
    struct acu_limits limits;
    struct frm_cull_frustum frustum;
    struct lod_chain chains[BCH_OPT_CHAINS];
    struct lod_cost_model cost;
    struct lod_benefit_params benefit;
    struct acu_contrast_limits contrast; /* the contrast criterion: a castle table at 20 cd/m², k 2 */
    double far_m; /* > 0: a far plane for the cull (the scaling table's fixed view distance) */
};
void bch_opt_view_init(struct bch_opt_view *v, const struct hmd_profile *display);

/* Chain of a scene object: a hash of its id, so neighbours differ and it needs no array. */
static inline uint32_t bch_opt_chain_of(uint32_t object) { return (object * 2654435761u) >> 30; }

/* One frame's arrays, sized once: a problem of up to cap visible objects; visible and last_level
 * have room for all scene_count objects (scn_cull may list them all).
 * The problem p points into them after bch_opt_build. last_level[object] is the level drawn last
 * frame or LOD_UNSEEN: the incremental optimizer's start and the benefit's hysteresis. */
struct bch_opt_work {
    size_t cap, scene_count, n;
    uint32_t *visible, *object_id, *first, *samples, *chain_of_object;
    double *pixels_px, *ecc_deg, *vel_degps, *diam_deg, *cost_ms, *benefit;
    uint8_t *ceiling, *previous, *count, *level, *choice, *choice_ref, *level_out, *last_level;
    int64_t *hull_scratch; /* cap entries, for lod_hull_reduce */
    void *scratch;
    struct lod_problem p;
    double margin_value; /* fs's last lod_result.margin_value: the next frame's value_hint (0 = cold) */
};
int bch_opt_work_alloc(struct bch_opt_work *w, size_t cap, size_t scene_count);
void bch_opt_work_free(struct bch_opt_work *w);
void bch_opt_work_forget(struct bch_opt_work *w); /* every object LOD_UNSEEN: the next frame is a cold start */

/* The visible set of a pose into w->visible (scn_cull: hierarchical when the scene has groups, with
 * v->far_m as a sixth plane when set). Returns how many are visible; w->n is that clamped to w->cap.
 * culler may be NULL for a flat scene. */
size_t bch_opt_cull(const struct bch_opt_view *v, const struct scn_scene *s, struct scn_culler *c,
                 const struct trk_pose *pose, struct bch_opt_work *w);

/* Builds the problem of the visible objects for a pose (DESIGN.md steps 4–6): viewing geometry,
 * projected pixels, Reddy's ceiling, each level's cost, benefit with hysteresis from last_level,
 * the convex hull (capped by budget_ms; +INFINITY: no cap); then lod_choice_start into w->choice.
 * The problem's budget is budget_ms. */
void bch_opt_build(const struct bch_opt_view *v, const struct scn_scene *s, const struct trk_pose *pose,
                double budget_ms, struct bch_opt_work *w);

/* Σ candidate 0 and Σ last (ceiling) candidate cost of the built problem, for the nominal budget. */
void bch_opt_cost_range(const struct bch_opt_work *w, double *coarsest_ms, double *ceiling_ms);

/* Keeps what `choice` draws as last_level for the next frame. */
void bch_opt_remember(struct bch_opt_work *w, const uint8_t *choice);

/* The pose turned by yaw_deg about the world up axis (a snap turn: angular velocity unchanged). */
struct trk_pose bch_opt_pose_turned(const struct trk_pose *pose, double yaw_deg);

#endif
