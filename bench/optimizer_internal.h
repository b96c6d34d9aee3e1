/* Internal to bench/: the per-frame work of `hmdlod bench optimizer` on the embeddable core only
 * (acuity + lod; scene/ for the cull, replay/ for the trace's poses): a display's eyes and limits,
 * synthetic 4-level chains, a cost model, and one frame's problem built from a head pose
 * (bench/optimizer_frame.c), and the runs behind the tables (bench/optimizer_runs.c); the
 * tables are printed by bench/optimizer.c. */
#ifndef HMDLOD_BENCH_OPTIMIZER_INTERNAL_H
#define HMDLOD_BENCH_OPTIMIZER_INTERNAL_H

#include "hmd/hmd.h"
#include "lod/lod.h"
#include "replay/replay.h"
#include "scene/scene.h"

enum { BCH_OPT_LEVELS = 4, BCH_OPT_CHAINS = 4 };

/* What does not change during a run: both eyes of the display (head frame), Reddy's limits for its
 * ξ, the union frustum for the cull, the synthetic chains and the cost model. */
struct bch_opt_view {
    struct hmd_eye eye[2];
    double width_px, height_px;
    struct acu_limits limits;
    struct frm_cull_frustum frustum;
    struct lod_chain chains[BCH_OPT_CHAINS];
    struct lod_cost_model cost;
    struct lod_benefit_params benefit;
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

/* ---- the runs (bench/optimizer_runs.c) ---------------------------------------------------- */
#define BCH_OPT_RATE_HZ 90.0
#define BCH_OPT_BUDGET_SHARE 0.25 /* nominal budget: this far from the coarsest to the ceiling cost */
enum { BCH_OPT_TURN_BINS = 5 };
extern const double bch_opt_turn_bin_deg[BCH_OPT_TURN_BINS + 1];

/* Nearest-rank percentile p ∈ [0, 1] of v[0 … n−1] (sorts v); NaN when n is 0. */
double bch_opt_percentile(double *v, long n, double p);

struct opt_trace {
    struct rpl_trace t;
    double start_s, span_s;
};
struct opt_case {
    uint32_t target;
    struct scn_scene scene;
    struct bch_opt_work w;
    double budget_ms;
};
struct size_row {
    uint32_t target, scene_objects;
    double visible_mean, budget_ms;
    double fs_med, fs_p99, gr_med, gr_p99, ratio_med, cold_fs_us, cold_gr_us, build_med;
    double iter_med, iter_p99, lp_med, lp_min, equal_share;
    long over_budget, drop_frames, frames;
    double p999; /* of the timed frames' fs µs */
    double setup_med, setup_p999, after_p999; /* fs's O(n) set-up; the rest of the call (the iterations) */
    double mb_med, mb_p99, mb_lp_min; /* Mason & Blake on the same frames, the objects as a flat tree */
};
struct turn_row {
    double fs_med, fs_p99, fs_max, gr_med, iter_med, iter_p99, lp_min, visible_changed;
    long pairs;
};
struct scale_row {
    uint32_t objects, groups;
    double visible_mean, cull_med, build_med, fs_med, total_med, total_p99;
};

/* The trace's pose at frame f at BCH_OPT_RATE_HZ (looped). */
struct trk_pose bch_opt_pose_at_frame(const struct opt_trace *tr, long f);
/* A shell scene sized so that about `target` objects are visible at the trace's first pose, its work
 * arrays and the nominal budget. 0, or −1 when out of memory. */
int bch_opt_setup_case(struct opt_case *c, uint32_t target, const struct bch_opt_view *v, const struct opt_trace *tr,
                    uint64_t seed);
void bch_opt_free_case(struct opt_case *c);
/* `frames` trace frames from a cold start: fs (time limit limit_us, 0 = none) and the greedy on each
 * frame's problem. Fills row; writes the timed frames' fs µs to fs_us_out (frames − 1) when not NULL. */
int bch_opt_run_trace(struct opt_case *c, const struct bch_opt_view *v, const struct opt_trace *tr, long frames,
                   double budget_ms, double limit_us, struct size_row *row, double *fs_us_out);
/* `pairs` turned frame pairs per turn bin; appends each timed fs µs to fs_all[*fs_all_n] when not NULL. */
int bch_opt_run_turns(struct opt_case *c, const struct bch_opt_view *v, const struct opt_trace *tr, long pairs,
                   double budget_ms, double limit_us, uint64_t seed, struct turn_row rows[BCH_OPT_TURN_BINS],
                   double *fs_all, long *fs_all_n);
/* bench cull's grid of `objects` with v->far_m: cull + build + fs per frame. *budget_ms ≤ 0 is set
 * from the first frame and kept for the next calls. */
int bch_opt_run_scale(uint32_t objects, const struct bch_opt_view *v, const struct opt_trace *tr, long frames,
                   uint64_t seed, double *budget_ms, struct scale_row *row);

#endif
