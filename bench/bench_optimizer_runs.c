/* The runs behind `hmdlod bench optimizer`'s tables (bench/bench_optimizer.c prints them): the
 * synthetic shell scenes, the trace's frames, fs against the greedy per frame, the turn pairs and the
 * scaling scenes. Each run times only the calls it names; everything is allocated before it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "bench/bench_optimizer_runs.h"

const double bch_opt_turn_bin_deg[BCH_OPT_TURN_BINS + 1] = {0, 1, 5, 20, 60, 180};

/* ---- small statistics ---------------------------------------------------------------------------- */

/* Nearest rank (v is sorted in place). */
double bch_opt_percentile(double *v, long n, double p)
{
    if (n <= 0)
        return NAN;
    hl_sort_doubles(v, (size_t)n);
    return hl_percentile_sorted(v, (size_t)n, p);
}
static double minimum(const double *v, long n)
{
    double m = INFINITY;
    for (long i = 0; i < n; ++i)
        m = fmin(m, v[i]);
    return m;
}
static double us_since(int64_t t0_ns) { return (double)(hl_clock_now_ns() - t0_ns) * 1e-3; }

/* ---- scenes -------------------------------------------------------------------------------------- */

static uint64_t mix_next(uint64_t *s) /* splitmix64 */
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static double mix_uniform(uint64_t *s) { return (double)(mix_next(s) >> 11) * 0x1.0p-53; }

/* m objects on a shell 4–40 m around the viewer, directions on a Fibonacci sphere (even in every
 * direction: the trace's users look all around), radii 0.2–1 m; a flat scene (no groups). */
static int make_shell(uint32_t m, uint64_t seed, struct scn_scene *s)
{
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "shell%u", m);
    s->instance_count = m;
    s->center_m = malloc(3 * (size_t)m * sizeof(double));
    s->radius_m = malloc((size_t)m * sizeof(double));
    if (!s->center_m || !s->radius_m)
        return -1;
    uint64_t rng = seed;
    for (uint32_t i = 0; i < m; ++i) {
        double y = 1.0 - 2.0 * (i + 0.5) / m, r = sqrt(fmax(0.0, 1.0 - y * y)), phi = i * 2.399963229728653;
        double d = 4.0 + 36.0 * mix_uniform(&rng);
        s->center_m[3 * (size_t)i] = d * r * cos(phi);
        s->center_m[3 * (size_t)i + 1] = d * y;
        s->center_m[3 * (size_t)i + 2] = d * r * sin(phi);
        s->radius_m[i] = 0.2 + 0.8 * mix_uniform(&rng);
    }
    return 0;
}

/* ---- the trace ----------------------------------------------------------------------------------- */

struct trk_pose bch_opt_pose_at_frame(const struct opt_trace *tr, long f)
{
    struct trk_pose pose;
    rpl_trace_sample(&tr->t, tr->start_s + fmod((double)f / BCH_OPT_RATE_HZ, tr->span_s > 0 ? tr->span_s : 1.0), &pose);
    if (!pose.has_position)
        pose.position_m = hl_v3(0, 0, 0);
    return pose;
}

/* ---- one size: fs against the greedy on the trace's frames ------------------------------------- */




int bch_opt_setup_case(struct opt_case *c, uint32_t target, const struct bch_opt_view *v, const struct opt_trace *tr,
                      uint64_t seed)
{
    memset(c, 0, sizeof *c);
    c->target = target;
    /* A pilot shell of 5·target objects tells the visible share at the trace's first pose; the scene
     * is then sized so that about `target` objects are visible there. */
    struct scn_scene pilot;
    if (make_shell(5 * target, seed, &pilot) != 0)
        return -1;
    struct bch_opt_work pw;
    if (bch_opt_work_alloc(&pw, 1, pilot.instance_count) != 0) {
        scn_scene_free(&pilot);
        return -1;
    }
    struct trk_pose p0 = bch_opt_pose_at_frame(tr, 0);
    uint32_t seen = (uint32_t)bch_opt_cull(v, &pilot, NULL, &p0, &pw);
    bch_opt_work_free(&pw);
    scn_scene_free(&pilot);
    uint32_t m = (uint32_t)ceil(5.0 * target * target / fmax(seen, 1));
    if (make_shell(m, seed, &c->scene) != 0 || bch_opt_work_alloc(&c->w, m, m) != 0)
        return -1;
    /* The nominal budget, fixed for the run: the cheapest choice's cost plus a quarter of the way to
     * every object at its perceptual ceiling, on the first frame — a budget that binds (the llvmpipe
     * model's absolute figures would leave 10k objects far over any frame time). */
    bch_opt_cull(v, &c->scene, NULL, &p0, &c->w);
    bch_opt_build(v, &c->scene, &p0, INFINITY, &c->w);
    double lo, hi;
    bch_opt_cost_range(&c->w, &lo, &hi);
    c->budget_ms = lo + BCH_OPT_BUDGET_SHARE * (hi - lo);
    bch_opt_work_forget(&c->w);
    return 0;
}

void bch_opt_free_case(struct opt_case *c)
{
    bch_opt_work_free(&c->w);
    scn_scene_free(&c->scene);
}

/* Runs `frames` frames from a cold start with budget_ms; fills the row. */
/* The frame's objects as a Mason–Blake tree of leaves under the imaginary root, and mb's per-object
 * state carried between frames by object id (the visible set changes from frame to frame). */
struct flat_tree {
    uint32_t *parent, *zero; /* every node a root; no children */
    uint8_t *state, *state_of_id;
    void *scratch;
};

static int flat_tree_alloc(struct flat_tree *t, uint32_t max_objects)
{
    size_t n = max_objects ? max_objects : 1;
    t->parent = malloc(n * sizeof(uint32_t));
    t->zero = calloc(n, sizeof(uint32_t));
    t->state = malloc(n);
    t->state_of_id = malloc(n);
    t->scratch = malloc(lod_mb_scratch_bytes(n));
    if (!t->parent || !t->zero || !t->state || !t->state_of_id || !t->scratch)
        return -1;
    for (size_t i = 0; i < n; ++i)
        t->parent[i] = LOD_MB_ROOT;
    memset(t->state_of_id, LOD_UNSEEN, n);
    return 0;
}

static void flat_tree_free(struct flat_tree *t)
{
    free(t->parent), free(t->zero), free(t->state), free(t->state_of_id), free(t->scratch);
}

static struct lod_tree flat_tree_of(const struct flat_tree *t, const struct lod_problem *p)
{
    return (struct lod_tree){p->object_count, p->object_id, t->parent, t->zero, t->zero, t->zero,
                             p->first, p->count, p->cost_ms, p->benefit, p->budget_ms};
}

/* Last frame's candidate per object (as a level), mapped to this frame's candidates as fs's start. */
static void flat_tree_start(struct flat_tree *t, const struct lod_problem *p)
{
    for (size_t i = 0; i < p->object_count; ++i)
        t->state[i] = t->state_of_id[p->object_id[i]];
    lod_choice_start(p, t->state, t->state);
}

static void flat_tree_remember(struct flat_tree *t, const struct lod_problem *p)
{
    for (size_t i = 0; i < p->object_count; ++i) {
        uint8_t s = t->state[i];
        t->state_of_id[p->object_id[i]] = s < p->count[i] ? p->level[p->first[i] + s] : LOD_DROP;
    }
}

/* The perceptual ceiling of the built frame under both criteria, timed apart on the same arrays;
 * contrast_first alternates the order between frames so neither always finds the caches warm. The
 * frame's own ceiling (w->ceiling, Reddy's) is untouched: the optimizers below see the same problem
 * either way. Counts the contrast criterion's CSF lookups and its objects coarser than Reddy's. */
static void select_both(const struct bch_opt_view *v, struct bch_opt_work *w, int contrast_first, uint8_t *level,
                        double *acuity_us, double *contrast_us, uint64_t *lookups, uint64_t *coarser)
{
    for (int pass = 0; pass < 2; ++pass) {
        int64_t t0 = hl_clock_now_ns();
        if ((pass == 0) == (contrast_first != 0)) {
            struct lod_select_stats st = {0};
            lod_select_contrast(&v->contrast, &v->limits, v->chains, w->chain_of_object, w->visible, w->n, w->ecc_deg,
                                w->vel_degps, w->diam_deg, level, &st);
            *contrast_us = us_since(t0);
            *lookups += st.model_evaluations;
            for (size_t k = 0; k < w->n; ++k)
                *coarser += level[k] > w->ceiling[k];
        } else {
            lod_select_reddy(&v->limits, v->chains, w->chain_of_object, w->visible, w->n, w->ecc_deg, w->vel_degps,
                             w->diam_deg, level, NULL, NULL);
            *acuity_us = us_since(t0);
        }
    }
}

int bch_opt_run_trace(struct opt_case *c, const struct bch_opt_view *v, const struct opt_trace *tr, long frames,
                     double budget_ms, double limit_us, struct size_row *row, double *fs_us_out)
{
    struct bch_opt_work *w = &c->w;
    double *fs_us = malloc((size_t)frames * sizeof(double)), *gr_us = malloc((size_t)frames * sizeof(double));
    double *ratio = malloc((size_t)frames * sizeof(double)), *build_us = malloc((size_t)frames * sizeof(double));
    double *iter = malloc((size_t)frames * sizeof(double)), *lp = malloc((size_t)frames * sizeof(double));
    double *mb_us = malloc((size_t)frames * sizeof(double)), *mb_lp = malloc((size_t)frames * sizeof(double));
    double *setup = malloc((size_t)frames * sizeof(double)), *after = malloc((size_t)frames * sizeof(double));
    double *sel = malloc((size_t)frames * 3 * sizeof(double)); /* acuity µs, contrast µs, ratio */
    uint8_t *sel_level = malloc(w->cap ? w->cap : 1);
    struct flat_tree ft;
    if (!fs_us || !gr_us || !ratio || !build_us || !iter || !lp || !mb_us || !mb_lp || !setup || !after || !sel ||
        !sel_level || flat_tree_alloc(&ft, c->scene.instance_count) != 0) {
        free(fs_us), free(gr_us), free(ratio), free(build_us), free(iter), free(lp), free(mb_us), free(mb_lp);
        free(setup), free(after), free(sel), free(sel_level);
        return -1;
    }
    double *sel_acuity = sel, *sel_contrast = sel + frames, *sel_ratio = sel + 2 * frames;
    uint64_t sel_lookups = 0, sel_objects = 0, sel_coarser = 0;
    memset(row, 0, sizeof *row);
    row->target = c->target, row->scene_objects = c->scene.instance_count, row->budget_ms = budget_ms;
    bch_opt_work_forget(w);
    long timed = 0, equal = 0;
    for (long f = 0; f < frames; ++f) {
        struct trk_pose pose = bch_opt_pose_at_frame(tr, f);
        bch_opt_cull(v, &c->scene, NULL, &pose, w);
        int64_t t0 = hl_clock_now_ns();
        bch_opt_build(v, &c->scene, &pose, budget_ms, w);
        double b_us = us_since(t0);
        double a_us = 0, k_us = 0;
        select_both(v, w, f & 1, sel_level, &a_us, &k_us, &sel_lookups, &sel_coarser);
        sel_objects += w->n;
        struct lod_result rf, rg;
        t0 = hl_clock_now_ns();
        lod_optimize_fs(&w->p, limit_us, w->scratch, w->choice, &rf);
        double f_us = us_since(t0);
        w->margin_value = rf.margin_value;
        t0 = hl_clock_now_ns();
        lod_optimize_greedy(&w->p, w->scratch, w->choice_ref, &rg);
        double g_us = us_since(t0);
        /* mb on the same problem as a tree of leaves (no groups): its own state from last frame. */
        struct lod_tree tree = flat_tree_of(&ft, &w->p);
        struct lod_result rm;
        flat_tree_start(&ft, &w->p);
        t0 = hl_clock_now_ns();
        lod_optimize_mb(&tree, limit_us, ft.scratch, ft.state, &rm);
        double m_us = us_since(t0);
        flat_tree_remember(&ft, &w->p);
        double bound = lod_lp_bound(&w->p, w->scratch);
        if (rf.cost_ms > budget_ms * (1 + 1e-12) + 1e-12)
            row->over_budget++; /* the guarantee broken: must stay 0 */
        row->drop_frames += rf.over_budget != 0;
        row->visible_mean += (double)w->n;
        if (f == 0) { /* a cold start: every object unseen, fs starts from the coarsest */
            row->cold_fs_us = f_us, row->cold_gr_us = g_us;
        } else {
            fs_us[timed] = f_us, gr_us[timed] = g_us, ratio[timed] = g_us / fmax(f_us, 1e-3);
            setup[timed] = rf.setup_us, after[timed] = f_us - rf.setup_us;
            build_us[timed] = b_us, iter[timed] = rf.iterations;
            lp[timed] = bound > 0 ? rf.benefit / bound : 1.0;
            mb_us[timed] = m_us;
            mb_lp[timed] = bound > 0 ? rm.benefit / bound : 1.0;
            sel_acuity[timed] = a_us, sel_contrast[timed] = k_us, sel_ratio[timed] = k_us / fmax(a_us, 1e-3);
            if (fabs(rf.benefit - rg.benefit) <= 1e-9 * fmax(1.0, fabs(rg.benefit)))
                ++equal;
            if (fs_us_out)
                fs_us_out[timed] = f_us;
            ++timed;
        }
        bch_opt_remember(w, w->choice);
    }
    row->frames = frames;
    row->visible_mean /= (double)frames;
    row->fs_med = bch_opt_percentile(fs_us, timed, 0.5), row->fs_p99 = bch_opt_percentile(fs_us, timed, 0.99);
    row->p999 = bch_opt_percentile(fs_us, timed, 0.999);
    row->gr_med = bch_opt_percentile(gr_us, timed, 0.5), row->gr_p99 = bch_opt_percentile(gr_us, timed, 0.99);
    row->ratio_med = bch_opt_percentile(ratio, timed, 0.5), row->build_med = bch_opt_percentile(build_us, timed, 0.5);
    row->iter_med = bch_opt_percentile(iter, timed, 0.5), row->iter_p99 = bch_opt_percentile(iter, timed, 0.99);
    row->lp_min = minimum(lp, timed), row->lp_med = bch_opt_percentile(lp, timed, 0.5);
    row->equal_share = timed ? (double)equal / (double)timed : 1.0;
    row->mb_med = bch_opt_percentile(mb_us, timed, 0.5), row->mb_p99 = bch_opt_percentile(mb_us, timed, 0.99);
    row->mb_lp_min = minimum(mb_lp, timed);
    row->setup_med = bch_opt_percentile(setup, timed, 0.5), row->setup_p999 = bch_opt_percentile(setup, timed, 0.999);
    row->after_p999 = bch_opt_percentile(after, timed, 0.999);
    row->sel_acuity_med = bch_opt_percentile(sel_acuity, timed, 0.5);
    row->sel_acuity_p99 = bch_opt_percentile(sel_acuity, timed, 0.99);
    row->sel_contrast_med = bch_opt_percentile(sel_contrast, timed, 0.5);
    row->sel_contrast_p99 = bch_opt_percentile(sel_contrast, timed, 0.99);
    row->sel_ratio_med = bch_opt_percentile(sel_ratio, timed, 0.5);
    row->sel_lookups_per_object = sel_objects ? (double)sel_lookups / (double)sel_objects : 0.0;
    row->sel_coarser_share = sel_objects ? (double)sel_coarser / (double)sel_objects : 0.0;
    flat_tree_free(&ft);
    free(fs_us), free(gr_us), free(ratio), free(build_us), free(iter), free(lp), free(mb_us), free(mb_lp);
    free(setup), free(after), free(sel), free(sel_level);
    return 0;
}

/* ---- time against the turn between frames ------------------------------------------------------- */


/* K pairs per bin: three coherent frames of the trace (cold start, then two fs frames), then the
 * same pose snapped by a yaw drawn uniformly in the bin (alternating sides); fs from the third
 * frame's levels is timed on the turned frame, with the greedy on the same problem. */
int bch_opt_run_turns(struct opt_case *c, const struct bch_opt_view *v, const struct opt_trace *tr, long pairs,
                     double budget_ms, double limit_us, uint64_t seed, struct turn_row rows[BCH_OPT_TURN_BINS],
                     double *fs_all, long *fs_all_n)
{
    struct bch_opt_work *w = &c->w;
    double *fs_us = malloc((size_t)pairs * sizeof(double)), *gr_us = malloc((size_t)pairs * sizeof(double));
    double *iter = malloc((size_t)pairs * sizeof(double)), *lp = malloc((size_t)pairs * sizeof(double));
    uint8_t *was = malloc(w->scene_count);
    if (!fs_us || !gr_us || !iter || !lp || !was) {
        free(fs_us), free(gr_us), free(iter), free(lp), free(was);
        return -1;
    }
    uint64_t rng = seed ^ 0x5bd1e995u;
    long trace_frames = (long)(tr->span_s * BCH_OPT_RATE_HZ);
    for (int b = 0; b < BCH_OPT_TURN_BINS; ++b) {
        struct turn_row *r = &rows[b];
        memset(r, 0, sizeof *r);
        for (long k = 0; k < pairs; ++k) {
            long f = 3 + (long)((double)(b * pairs + k) / (double)(BCH_OPT_TURN_BINS * pairs) * (double)(trace_frames - 4));
            bch_opt_work_forget(w);
            for (long g = f - 2; g <= f; ++g) {
                struct trk_pose pg = bch_opt_pose_at_frame(tr, g);
                bch_opt_cull(v, &c->scene, NULL, &pg, w);
                bch_opt_build(v, &c->scene, &pg, budget_ms, w);
                struct lod_result rr;
                lod_optimize_fs(&w->p, 0.0, w->scratch, w->choice, &rr);
                w->margin_value = rr.margin_value;
                bch_opt_remember(w, w->choice);
            }
            memcpy(was, w->last_level, w->scene_count);
            double yaw = bch_opt_turn_bin_deg[b] + (bch_opt_turn_bin_deg[b + 1] - bch_opt_turn_bin_deg[b]) * mix_uniform(&rng);
            struct trk_pose pa = bch_opt_pose_at_frame(tr, f), pb = bch_opt_pose_turned(&pa, (k & 1) ? yaw : -yaw);
            bch_opt_cull(v, &c->scene, NULL, &pb, w);
            bch_opt_build(v, &c->scene, &pb, budget_ms, w);
            size_t changed = 0;
            for (size_t i = 0; i < w->n; ++i)
                changed += was[w->visible[i]] == LOD_UNSEEN;
            struct lod_result rf, rg;
            int64_t t0 = hl_clock_now_ns();
            lod_optimize_fs(&w->p, limit_us, w->scratch, w->choice, &rf);
            fs_us[k] = us_since(t0);
            w->margin_value = rf.margin_value;
            t0 = hl_clock_now_ns();
            lod_optimize_greedy(&w->p, w->scratch, w->choice_ref, &rg);
            gr_us[k] = us_since(t0);
            double bound = lod_lp_bound(&w->p, w->scratch);
            iter[k] = rf.iterations;
            lp[k] = bound > 0 ? rf.benefit / bound : 1.0;
            r->visible_changed += w->n ? (double)changed / (double)w->n : 0.0;
            if (fs_all)
                fs_all[(*fs_all_n)++] = fs_us[k];
        }
        r->pairs = pairs;
        r->visible_changed /= (double)pairs;
        r->fs_max = bch_opt_percentile(fs_us, pairs, 1.0);
        r->fs_med = bch_opt_percentile(fs_us, pairs, 0.5), r->fs_p99 = bch_opt_percentile(fs_us, pairs, 0.99);
        r->gr_med = bch_opt_percentile(gr_us, pairs, 0.5);
        r->iter_med = bch_opt_percentile(iter, pairs, 0.5), r->iter_p99 = bch_opt_percentile(iter, pairs, 0.99);
        r->lp_min = minimum(lp, pairs);
    }
    free(fs_us), free(gr_us), free(iter), free(lp), free(was);
    return 0;
}

/* ---- scaling: cull + build + optimize as the full scene grows ----------------------------------- */


int bch_opt_run_scale(uint32_t objects, const struct bch_opt_view *v, const struct opt_trace *tr, long frames,
                     uint64_t seed, double *budget_ms, struct scale_row *row)
{
    struct scn_scene s;
    struct scn_culler cu = {0};
    struct bch_opt_work w;
    struct hl_error err = {{0}};
    memset(row, 0, sizeof *row);
    if (bch_cull_make_grid(objects, seed, &s, &err) != 0 || scn_culler_init(&cu, &s, &err) != 0) {
        fprintf(stderr, "hmdlod bench optimizer: %s\n", err.msg);
        scn_scene_free(&s);
        return -1;
    }
    double *cull = malloc((size_t)frames * sizeof(double)), *build = malloc((size_t)frames * sizeof(double));
    double *fs = malloc((size_t)frames * sizeof(double)), *total = malloc((size_t)frames * sizeof(double));
    int rc = -1;
    /* Visible objects are bounded by the view distance, not the scene: 20 000 is far above them. */
    if (!cull || !build || !fs || !total || bch_opt_work_alloc(&w, 20000, objects) != 0)
        goto done;
    row->objects = objects, row->groups = s.group_count;
    for (long f = 0; f < frames; ++f) {
        struct trk_pose pose = bch_opt_pose_at_frame(tr, f);
        int64_t t0 = hl_clock_now_ns();
        bch_opt_cull(v, &s, &cu, &pose, &w);
        int64_t t1 = hl_clock_now_ns();
        bch_opt_build(v, &s, &pose, *budget_ms > 0 ? *budget_ms : INFINITY, &w);
        if (*budget_ms <= 0) { /* the first scene's first frame fixes the budget for all three */
            double lo, hi;
            bch_opt_cost_range(&w, &lo, &hi);
            *budget_ms = w.p.budget_ms = lo + BCH_OPT_BUDGET_SHARE * (hi - lo);
        }
        int64_t t2 = hl_clock_now_ns();
        struct lod_result r;
        lod_optimize_fs(&w.p, 0.0, w.scratch, w.choice, &r);
        int64_t t3 = hl_clock_now_ns();
        w.margin_value = r.margin_value;
        cull[f] = (double)(t1 - t0) * 1e-3, build[f] = (double)(t2 - t1) * 1e-3, fs[f] = (double)(t3 - t2) * 1e-3;
        total[f] = (double)(t3 - t0) * 1e-3;
        row->visible_mean += (double)w.n;
        bch_opt_remember(&w, w.choice);
    }
    row->visible_mean /= (double)frames;
    row->cull_med = bch_opt_percentile(cull, frames, 0.5), row->build_med = bch_opt_percentile(build, frames, 0.5);
    row->fs_med = bch_opt_percentile(fs, frames, 0.5), row->total_med = bch_opt_percentile(total, frames, 0.5);
    row->total_p99 = bch_opt_percentile(total, frames, 0.99);
    bch_opt_work_free(&w);
    rc = 0;
done:
    free(cull), free(build), free(fs), free(total);
    scn_culler_free(&cu);
    scn_scene_free(&s);
    return rc;
}
