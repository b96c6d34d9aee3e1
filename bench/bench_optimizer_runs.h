/* Internal to bench/: the runs behind `hmdlod bench optimizer`'s tables (bench/bench_optimizer_runs.c)
 * over the per-frame work of bench/bench_optimizer_frame.h, on a trace's poses (replay/). */
#ifndef HMDLOD_BENCH_OPTIMIZER_RUNS_H
#define HMDLOD_BENCH_OPTIMIZER_RUNS_H

#include "bench/bench_optimizer_frame.h"
#include "replay/replay.h"

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
    /* The perceptual ceiling alone on the same frames: lod_select_reddy (acuity) and
     * lod_select_contrast, alternated; µs medians, the median of the per-frame ratio, CSF lookups and
     * the share of objects whose level differs, per object. */
    double sel_acuity_med, sel_acuity_p99, sel_contrast_med, sel_contrast_p99, sel_ratio_med;
    double sel_lookups_per_object, sel_coarser_share;
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
