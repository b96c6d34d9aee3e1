/* lod: which representation each object gets — selectors without a cost model (none, reddy, static,
 * feedback) and the cost-bounded optimizers (fs, mb) with their time limit, the reference solvers
 * (exact, LP bound), benefit and the cost model's arithmetic. Prefix lod_. Pure arrays in and out:
 * no GL, no files, no allocation (scratch memory is the caller's, sized by lod_scratch_bytes). The
 * acuity limits come from acuity/. Together with acuity/ it is the part an engine embeds.
 * PAPERS.md §2 (Funkhouser & Séquin 1993), §3 (Mason & Blake 1997), §4 (Nirenstein et al. 2002). */
#ifndef HMDLOD_LOD_H
#define HMDLOD_LOD_H

#include "acuity/acuity.h"

/* ---- selectors without a cost model ------------------------------------------------------------
 * A chain of LODs, 0 = finest. unique_freq_cpdiam[k] (k ≥ 1) is the spatial frequency of the most
 * visible detail present in LOD k−1 and lost in LOD k, in cycles per object diameter (Reddy §3.2;
 * measured from renders, docs/analysis.md); it falls strictly as k rises. At run time
 * f[c/deg] = f[cycles/diameter] / angular diameter[deg]. Level 0 holds +INFINITY. */
enum { LOD_MAX_LEVELS = 8, LOD_MAX_BANDS = 12 };
struct lod_chain {
    int lod_count;
    double unique_freq_cpdiam[LOD_MAX_LEVELS];
    /* The lost-contrast spectrum (docs/analysis.md), for lod_select_contrast: lost_contrast[l][b] is the
     * band contrast (Peli 1990) level l loses against level 0 in octave band b, centred on 2^b cycles
     * per diameter; ≥ 0, NaN = not measured in that band (counts as visible). band_count 0: no
     * spectrum, the chain is judged by unique_freq_cpdiam alone. Zero-initialise what you do not fill. */
    int band_count; /* 0 … LOD_MAX_BANDS */
    double lost_contrast[LOD_MAX_LEVELS][LOD_MAX_BANDS];
};

struct lod_select_stats {
    uint64_t model_evaluations; /* objects whose H(v,E) was computed */
    uint64_t model_skips;       /* objects inside the H ≥ ξ region */
};

/* Reddy's selector: per object the coarsest LOD whose every removed frequency lies above the
 * acuity limit (so nothing the viewer can resolve is dropped). Inputs are the visible objects'
 * arrays, position-ordered (count entries; index[k] is the scene object, chain_of_object is indexed
 * by it). Writes lod_out[k] and, when not NULL, the limit used ceiling_cpd_out[k] (c/deg); adds to
 * *stats when not NULL. O(count · levels), no allocation. With a cost-bounded optimizer this level
 * is the perceptual ceiling: detail finer than it earns nothing (lod_benefit_fill). */
void lod_select_reddy(const struct acu_limits *lim, const struct lod_chain *chains,
                      const uint32_t *chain_of_object, const uint32_t *index, size_t count,
                      const double *eccentricity_deg, const double *retinal_velocity_degps,
                      const double *angular_diameter_deg, uint8_t *lod_out, double *ceiling_cpd_out,
                      struct lod_select_stats *stats);

/* The contrast criterion (docs/visibility.md): per object the coarsest LOD whose every lost band is
 * invisible — band b lies at ρ_b = 2^b / angular diameter cpd and is invisible when ρ_b/s > ξ or
 * C_b·S(ρ_b, ρ_b·v, E)·k < 1 (acu_contrast_band_sensitivity, acu_csf_band_visible). Where the chain
 * has no spectrum, or the object is so large that frequencies above its measured bands
 * (2^band_count / diameter) are displayable, the measured spectrum cannot speak for all it loses:
 * the object gets the finer of this ceiling and Reddy's (lim, unique_freq_cpdiam). Arrays as
 * lod_select_reddy; stats count CSF lookups (model_evaluations) and objects that needed none.
 * O(count · (levels · bands)) comparisons, at most band_count lookups per object, no allocation. */
void lod_select_contrast(const struct acu_contrast_limits *vis, const struct acu_limits *lim,
                         const struct lod_chain *chains, const uint32_t *chain_of_object, const uint32_t *index,
                         size_t count, const double *eccentricity_deg, const double *retinal_velocity_degps,
                         const double *angular_diameter_deg, uint8_t *lod_out, struct lod_select_stats *stats);

/* The perceptual benefit's input (lod_benefit_fill): per listed object k and level l < lod_count,
 *   D_kl = Σ over displayable bands b of max(0, C_lb·S_b·k − 1),
 * the suprathreshold contrast level l loses against level 0 in units of the threshold (a band seen at
 * twice its threshold adds 1), with S_b and the displayable bands as lod_select_contrast takes them;
 * a NaN contrast where displayable adds 1. Writes visible_loss[k·LOD_MAX_LEVELS + l] (D_k0 = 0; levels
 * ≥ lod_count 0); a chain without a spectrum gets NaN in its whole row. Every displayable band is
 * looked up (no early exit): about 3× lod_select_contrast's lookups. No allocation. */
void lod_visible_loss_contrast(const struct acu_contrast_limits *vis, const struct lod_chain *chains,
                               const uint32_t *chain_of_object, const uint32_t *index, size_t count,
                               const double *eccentricity_deg, const double *retinal_velocity_degps,
                               const double *angular_diameter_deg, double *visible_loss,
                               struct lod_select_stats *stats);

/* The `none` baseline: finest LOD for every listed object. */
void lod_select_finest(size_t count, uint8_t *lod_out);

/* Funkhouser & Séquin §7 "Static": per object the finest LOD whose average triangle covers at least
 * min_px_per_triangle pixels (pixels_px[k] / triangles of the level), else the coarsest.
 * triangles[c·LOD_MAX_LEVELS + l] is chain c's level-l triangle count, lod_count[c] its levels.
 * O(count · levels). */
void lod_select_static(double min_px_per_triangle, const uint32_t *triangles, const uint8_t *lod_count,
                       const uint32_t *chain_of_object, const uint32_t *index, size_t count,
                       const double *pixels_px, uint8_t *lod_out);

/* Funkhouser & Séquin §7 "Feedback", shaped like the adaptive quality of shipping VR runtimes
 * (PAPERS.md §5): the static selector's threshold adapted from the measured frame times. Over 0.9
 * of the budget it drops two quality steps at once (or when the last two frames' trend predicts
 * crossing it), over 0.85 for three frames one step; under 0.7 it climbs one step after 6 frames
 * and two after 12. One step scales the threshold by 1.15 (≈ ±15 % triangles). */
struct lod_feedback {
    double min_px_per_triangle;         /* current threshold, for lod_select_static */
    double lowest_px, highest_px;       /* clamp of the threshold */
    double last_ms;                     /* previous measured frame, 0 before the first */
    int frames_high, frames_cheap;      /* consecutive frames over 0.85 / under 0.7 of the budget */
};
void lod_feedback_init(struct lod_feedback *f, double start_px_per_triangle);
void lod_feedback_update(struct lod_feedback *f, double measured_ms, double budget_ms);

/* ---- the cost model's arithmetic (the coefficients are measured by render/, `hmdlod calibrate`) --
 * Funkhouser & Séquin §4 and an additive form, per object and eye pair, in milliseconds, with
 * e = √(triangles·pixels) the pixels along triangle edges:
 *   LOD_COST_MAX:      max(c1·triangles + c2·vertices, c3·pixels + c5·e) + c4·draws
 *   LOD_COST_ADDITIVE: c1·triangles + c2·vertices + c3·pixels + c5·e + c4·draws
 * and a frame costs c0 + Σ objects. triangles, vertices, draws count both eyes' work; pixels is the
 * fragments the object rasterises, summed over both eyes: its projected bound (acu_compute_pixels)
 * times the level's fill of it (scn_lod_fill; frame's frm_level_cost_ms). Coefficients ≥ 0. The edge
 * term: n triangles sharing p pixels have perimeters ∝ √(p/n) each, so √(n·p) counts the pixels on
 * their edges — the partly covered blocks a tiled rasteriser (llvmpipe: 4×4) visits per triangle,
 * which make a pixel of a finely tessellated object dearer than one of a coarse one; without it the
 * model under-predicted many finely tessellated objects filling the view by half (docs/cost-model.md). */
enum lod_cost_form { LOD_COST_MAX = 0, LOD_COST_ADDITIVE = 1 };
struct lod_cost_model {
    enum lod_cost_form form;
    double c0_ms;              /* per frame: clear, state, finish */
    double c1_ms_per_triangle;
    double c2_ms_per_vertex;
    double c3_ms_per_pixel;
    double c4_ms_per_draw;
    double c5_ms_per_edge_px;  /* per √(triangles·pixels); 0 in profiles that predate it */
};
double lod_cost_object_ms(const struct lod_cost_model *m, double triangles, double vertices, double pixels,
                          double draws);

/* Online correction from measured frame times: a smoothed ratio measured / predicted (exponential,
 * weight `alpha` per frame, clamped to [0.25, 4]) and its smoothed variance. The budget handed to the
 * optimizer is divided by ratio + spread·σ when that is above 1, so a model that under-predicts on
 * this machine stops breaking the budget after a few frames, and a frame-to-frame jitter of σ is
 * covered with spread standard deviations to spare (2: about 98 % of frames for normal jitter). It
 * never loosens the budget: predicted cost stays within it. */
struct lod_cost_correction {
    double ratio;    /* start at 1 */
    double variance; /* of the ratio, smoothed like it */
    double alpha;    /* (0, 1]; 0.1 by default */
    double spread;   /* standard deviations of margin; 2 by default */
};
void lod_cost_correction_init(struct lod_cost_correction *c, double alpha);
/* Ignores non-finite or non-positive inputs (a frame with nothing predicted says nothing). */
void lod_cost_correction_update(struct lod_cost_correction *c, double measured_ms, double predicted_ms);
double lod_cost_correction_budget_ms(const struct lod_cost_correction *c, double budget_ms);

/* Affine online correction: measured ≈ a + b·x with x the objects' part of the prediction
 * (predicted − c0), fitted by exponentially weighted least squares (forgetting factor `lambda` per
 * frame) with a weak prior at the model (a = c0, b = 1). Where the ratio above scales the whole
 * budget — so a per-frame cost the model under-counts (clear, flush, read-back) shrinks it even when
 * little is drawn, the less drawn the more, until nearly nothing is — this corrects the fixed part
 * and the per-object part separately. The optimizer's budget for the objects is
 * (budget − a − margin) / b; never more than the model's own budget − c0 until
 * LOD_COST_RLS_LOOSEN_AFTER frames are in, and never more than LOD_COST_RLS_LOOSEN_MAX times it
 * (below). The margin is the
 * within_share quantile of the last LOD_COST_RLS_WINDOW frames' a-priori errors (spread·σ until 32
 * frames are in): frame times on a shared CPU are not normal — a frame preempted for one scheduler
 * tick runs 4 ms late, on 5–10 % of the frames here — and 2σ of such errors kept 87–95 % of the
 * frames within the budget, not the 97.7 % it would for normal jitter. The fit is solved in closed form every frame from five weighted sums, with a and b
 * held in their bounds by solving on the bound (a recursive-least-squares filter clamped after each
 * step does not know it was clamped: at half scale it drove b to its bound and the budget to 13 %
 * of the frame, issue 30). Frames that all draw alike leave a + b·x̄ fixed by the data and the rest
 * to the prior, which puts an unexplained cost mostly on a when x̄ is small (prior_x_ms below): an
 * under-counted fixed cost never shrinks the objects' budget. Each frame's error enters σ clipped to
 * 3σ (at least 0.3 ms): one preempted frame must not shrink the next fifty frames' budgets. */
enum { LOD_COST_RLS_WINDOW = 192 }; /* frames of a-priori errors the margin is read from (~2 s) */
/* The share of frames the margin aims to keep within the budget by default. 0.99 (issue 32's goal)
 * as a plain quantile kept 98.2–98.5 % of the layered auditorium's frames within it against
 * 95.7–97.3 %, for about 0.015 of fSSIM, but a window with rare long preemptions made it the
 * preemption; with the tail rule (lod_cost_rls_margin_ms) it measured within the run-to-run spread
 * of 0.97 (docs/RESULTS.md, issue 32 fifth round). */
#define LOD_COST_WITHIN_SHARE_DEFAULT 0.97
/* How far the fit may loosen the model's budget: a profile measured on a slower day priced the
 * auditorium's frames at three times what they took (issue 32), and the budget it left unused was
 * paid for with objects coarsened by the gaze (SSIM 0.85 there). The fit's slope is learnt from the
 * loads drawn so far; a larger load may cost more per model millisecond (a periphery scale of 0.5
 * priced with a slope learnt at 0.25), so the loosening is bounded: unbounded it ran away (within
 * 58 %), at 2× it kept 97 % of the frames within the budget, at 1.5× 99.5–100 % (docs/RESULTS.md
 * issue 32 eleventh round). Only after LOD_COST_RLS_LOOSEN_AFTER frames: a few frames say little. */
#define LOD_COST_RLS_LOOSEN_MAX 1.5
enum { LOD_COST_RLS_LOOSEN_AFTER = 64 };
struct lod_cost_rls {
    double a_ms, b;          /* measured ≈ a_ms + b · x */
    double s1, sx, sxx, sm, sxm; /* exponentially weighted Σ1, Σx, Σx², Σm, Σxm */
    double residual_var;     /* smoothed squared a-priori error (clipped), ms² */
    double c0_ms, lambda, spread;
    double within_share;     /* the share of frames the margin aims to keep within the budget, in (0.5, 1) */
    double recent_error_ms[LOD_COST_RLS_WINDOW]; /* the last frames' a-priori errors, a ring */
    uint32_t recent_count, recent_next;
};
void lod_cost_rls_init(struct lod_cost_rls *c, double c0_ms, double lambda);
/* x_ms = predicted − c0 of the drawn frame. Ignores non-finite or negative inputs. */
void lod_cost_rls_update(struct lod_cost_rls *c, double measured_ms, double x_ms);
/* The margin the budget keeps for the frame-to-frame error (see above), ≥ 0, ms. O(window). */
double lod_cost_rls_margin_ms(const struct lod_cost_rls *c);
/* What the objects may cost (excluding c0), ≥ 0. */
double lod_cost_rls_objects_budget_ms(const struct lod_cost_rls *c, double budget_ms);
/* The same without the margin: what the objects may cost for the fitted frame to take the whole
 * budget, (budget − a) / b, bounded as the budget above; ≥ 0. Not a budget to plan every frame
 * with (half such frames would be late), but the line past which a frame is expected to be late:
 * what drawing everything at its coarsest may use before an object is dropped. */
double lod_cost_rls_objects_expected_ms(const struct lod_cost_rls *c, double budget_ms);

/* ---- one frame's candidates ---------------------------------------------------------------------
 * Object i (0 … object_count−1) owns candidates first[i] … first[i]+count[i]−1 of the candidate
 * arrays, cheapest first: candidate 0 is its coarsest representation (or the null one, LOD_DROP,
 * where the scene allows drawing nothing). level[c] is the scene LOD a candidate draws (0 = finest,
 * LOD_DROP = nothing). object_id[i] is a stable id (the scene instance): every tie is broken by it,
 * then by candidate, never by memory order. cost_ms excludes the frame's c0, which the caller
 * takes off the budget. */
enum { LOD_DROP = 255,       /* level: draw nothing (null impostor) */
       LOD_UNSEEN = 254,     /* previous level of an object that was not drawn last frame */
       LOD_DROPPED = 255 };  /* choice: dropped because even the cheapest candidates cannot fit */
struct lod_problem {
    size_t object_count;
    const uint32_t *object_id;
    const uint32_t *first;
    const uint8_t *count;     /* ≥ 1 after lod_hull_reduce, except objects with no valid candidate */
    const double *cost_ms;    /* per candidate, finite, ≥ 0 */
    const double *benefit;    /* per candidate, finite, ≥ 0 */
    const uint8_t *level;     /* per candidate */
    double budget_ms;         /* for Σ cost_ms of the chosen candidates */
    double value_hint;        /* optional, fs only: last frame's lod_result.margin_value, which lets
                               * fs set up in one pass over the objects instead of two; 0 = none */
    const uint8_t *keep;      /* optional, per object: 1 = never dropped when not all fit (its
                               * candidate 0 stays; the caller's budget must hold every kept object's
                               * candidate 0, or the kept objects alone exceed it); NULL = none */
};

/* Funkhouser & Séquin §5 with Reddy's ceiling in place of Focus and Motion:
 *   benefit = size_px · importance · max(0, 1 − base_error · (1 + h·|level − previous|) / samples^m)
 * where samples = min(samples of the level, size_px) (at least 1) and h = hysteresis_per_level
 * (|…| = 0 for an unseen object; LOD_DROP counts as level LOD_MAX_LEVELS). Hysteresis scales the
 * error, not the benefit: accuracies of real levels differ by 10⁻⁵–10⁻³, which a factor on the
 * whole benefit would swamp (docs/optimizer.md). Every
 * level finer than the object's ceiling level earns exactly what the ceiling level earns — detail
 * beyond what the viewer can resolve is worth nothing, so lod_hull_reduce removes it. LOD_DROP earns
 * 0. samples[c] per candidate (vertices for Gouraud, m = 2; triangles for flat, m = 1);
 * importance NULL = all 1; ceiling_level and previous_level per object. Writes benefit[c]. */
struct lod_benefit_params {
    double base_error;          /* 0.5 (Funkhouser) */
    double exponent_m;          /* 2: Gouraud shading, samples = vertices */
    double hysteresis_per_level; /* 1: a level one step from last frame's counts its error twice */
};
void lod_benefit_params_default(struct lod_benefit_params *p);
/* Funkhouser's accuracy of one rendering (§5): 1 − base_error / Samples^m, Samples = min(samples,
 * size_px) and at least 1, without hysteresis; in [0, 1). What lod_benefit_fill values a level by. */
double lod_benefit_accuracy(const struct lod_benefit_params *p, double samples, double size_px);
/* The visible loss, in threshold units, at which the perceptual benefit counts an object as lost
 * whole (worth what dropping it is worth): 300², beyond any level's loss measured on the built-in
 * scenes (at most ~12 000 by the gaze), so no two levels' losses tie at 0. */
#define LOD_PERCEPTUAL_LOSS_WHOLE 90000.0
/* The perceptual benefit's accuracy of a visible loss D ≥ 0 (threshold units), without hysteresis:
 * max(0, 1 − √(D / LOD_PERCEPTUAL_LOSS_WHOLE)); 1 for D = 0. */
double lod_benefit_perceptual_accuracy(double loss);
/* visible_loss: NULL for Funkhouser's accuracy above. Else the perceptual benefit (docs/optimizer.md
 * "Perceptual benefit"; lod_visible_loss_contrast): object i's level l is worth
 *   size_px · importance · max(0, 1 − √(D_il · (1 + h·|level − previous|) / LOD_PERCEPTUAL_LOSS_WHOLE)),
 * D_il = visible_loss[i·LOD_MAX_LEVELS + l], the suprathreshold contrast it loses in threshold units
 * (0: nothing visible lost, worth the full size; the square root: what is seen of a contrast above
 * threshold grows about as its square root); an object whose row starts with NaN (no spectrum)
 * keeps Funkhouser's accuracy. The ceiling rule and LOD_DROP = 0 hold as above. */
void lod_benefit_fill(const struct lod_benefit_params *p, size_t object_count, const uint32_t *first,
                      const uint8_t *count, const uint8_t *level, const uint32_t *samples,
                      const double *size_px, const double *importance, const uint8_t *ceiling_level,
                      const uint8_t *previous_level, const double *visible_loss, double *benefit);

/* Reduces each object's candidates in place to the upper convex hull of (cost, benefit) from its
 * cheapest one, so benefit rises strictly with cost and the value Δbenefit/Δcost of each step up
 * falls (the diminishing returns the greedy, fs and mb rely on). Dropped: candidates with a
 * non-finite or negative cost or benefit (counted in the return value); with a finite budget_ms
 * that the cheapest candidates fit in, candidates that cannot fit even with every other object at
 * its cheapest (the hull is then taken
 * over those that can, so no fitting level hides under one that never fits); candidates that cost
 * at least as much as a cheaper one and earn no more (ties: the cheaper, then the coarser, stays);
 * and candidates under the hull — a level worth less per millisecond than the step past it, which
 * the greedy would never stop at. An object left with no candidate gets count 0 (the optimizers
 * mark it LOD_DROPPED). Candidates of one object must be at most LOD_MAX_LEVELS + 1. scratch holds
 * object_count int64 (unused when budget_ms is +INFINITY: no budget cap). O(candidates). */
size_t lod_hull_reduce(size_t object_count, const uint32_t *first, uint8_t *count, double *cost_ms,
                       double *benefit, uint8_t *level, double budget_ms, int64_t *scratch);

/* ---- cost-bounded optimizers ---------------------------------------------------------------------
 * Every optimizer writes choice[i], a candidate index of object i or LOD_DROPPED, and fills a
 * result. Predicted cost ≤ budget always; when even every object's candidate 0 does not fit, objects
 * are dropped, lowest benefit per cost of candidate 0 first (ties by object_id), until the rest
 * fits, and over_budget is set. Drops are the last resort: the dropped objects are then offered back
 * at candidate 0, highest benefit per cost first (ties by object_id), each taken where it still
 * fits, before any step up — so in the final choice no dropped object's candidate 0 fits in
 * budget − cost (lod_choice_underused_drop with fraction 1 is 0). lod_level_of_choice maps choices
 * to scene levels for drawing. */
struct lod_result {
    double cost_ms, benefit;  /* Σ over the chosen candidates */
    uint32_t iterations;      /* increments + decrements (fs), steps taken (greedy) */
    uint32_t dropped;         /* objects marked LOD_DROPPED */
    int over_budget;          /* 1: the cheapest candidates alone exceeded the budget */
    int truncated;            /* 1: stopped at the time limit (the choice is still feasible) */
    int single_item;          /* 1: the best single upgrade beat the greedy (the ½-optimal guard) */
    uint32_t heap_rebuilds;   /* fs: times its filtered heaps had to be rebuilt over every object */
    double setup_us;          /* fs: its O(n) set-up before the first iteration, which a time limit
                              * cannot cut short (Nirenstein's limit bounds the iterations) */
    double margin_value;      /* fs: the value Δbenefit/Δcost where taken and untaken steps meet
                               * (> 0, or 0 when unknown): next frame's lod_problem.value_hint */
    double elapsed_us;
};
/* Scratch bytes the optimizers need for up to max_objects objects and max_candidates candidates. */
size_t lod_scratch_bytes(size_t max_objects, size_t max_candidates);
void lod_level_of_choice(const struct lod_problem *p, const uint8_t *choice, uint8_t *level_out);

/* 1 when the choice spends under fraction × p->budget_ms and some object marked LOD_DROPPED (with a
 * candidate: count ≥ 1) would fit at its candidate 0 in budget − cost; else 0. Costs are summed and
 * fits decided as the optimizers decide them (whole 1e-8 ms units, each candidate rounded up, the
 * budget down). A frame the optimizers should never produce (issue 30: fraction 0.7 in replay's CSV;
 * fraction 1 checks the rule above). 0 for an empty problem, fraction ≤ 0 or NaN. Pure, O(n). */
int lod_choice_underused_drop(const struct lod_problem *p, const uint8_t *choice, double fraction);

/* From-scratch greedy (Funkhouser & Séquin §6 with Mason & Blake's guard, §3): every object at its
 * candidate 0, then the steps up in falling value, stopping at the first that does not fit, then
 * compared with the single best upgrade. ≥ ½ of the optimum. O(n log n) in the steps. The reference
 * the incremental optimizer must equal. */
void lod_optimize_greedy(const struct lod_problem *p, void *scratch, uint8_t *choice, struct lod_result *r);

/* Funkhouser & Séquin's incremental optimizer (§6), time-limited as Nirenstein et al. §5.5: starts
 * from choice[] as given (last frame's, mapped by lod_choice_start), raises the object with the
 * highest value of its next step, lowers those with the lowest value of their current step until it
 * fits, and stops when one object goes up and down in the same iteration or nothing can rise. Every
 * iteration ends feasible, so time_limit_us (0 = none) may stop it anywhere. Equals
 * lod_optimize_greedy when it runs to the end, whatever p->value_hint says (the hint only centres
 * its heaps' filters: with last frame's r->margin_value set-up is one pass over the objects, without
 * it two). O(n) to set up plus O(log n) per iteration. */
void lod_optimize_fs(const struct lod_problem *p, double time_limit_us, void *scratch, uint8_t *choice,
                     struct lod_result *r);

/* Starting choice for lod_optimize_fs: per object the candidate drawing previous_level[i] (the
 * level it had last frame), or the nearest coarser one; candidate 0 for LOD_UNSEEN. */
void lod_choice_start(const struct lod_problem *p, const uint8_t *previous_level, uint8_t *choice);

/* ---- reference solvers, for measurement only (lod/reference.c) ---------------------------------- */
/* The LP relaxation's optimum, an upper bound on any choice's benefit: the greedy's steps over the
 * hull with the first that does not fit taken fractionally. Walks each object's upper hull itself,
 * so an unreduced problem gets its true bound too; candidates with a non-finite or negative cost or
 * benefit are skipped. When the cheapest candidates alone exceed the budget it bounds the choices
 * that draw each object once or drop it (every object gains a free null point). scratch is unused
 * (may be NULL). Returns 0 for a negative or NaN budget. O(p · Σ k²), k candidates per object, p ≤ 8
 * radix passes (3 on distinct values): about 2–4 ms for 10,000 objects × 4 here, no allocation. */
double lod_lp_bound(const struct lod_problem *p, void *scratch);

/* Exact optimum by dynamic programming over cost in whole quanta of cost_quantum_ms: costs rounded
 * UP, the budget DOWN, so the choice always fits the real budget; it is optimal among choices whose
 * rounded cost fits (the true optimum when costs are multiples of the quantum; at least the optimum
 * for budget − object_count · quantum otherwise). Any problem, reduced or not; invalid candidates
 * skipped as lod_hull_reduce drops them. Objects are dropped (LOD_DROPPED) only when the cheapest
 * candidates exceed the real budget, as the optimizers do. work: lod_solve_exact_bytes(p, q) bytes,
 * aligned for double; nothing else is allocated. Writes choice[i] and *benefit_out (when not NULL).
 * Returns 0 (all drawn), 1 (over budget: drops allowed), −1 (work missing, too small or misaligned,
 * or the instance too large: lod_solve_exact_bytes returned 0), −2 (the quantum is too coarse: the
 * cheapest candidates fit but not once rounded up), −3 (quantum ≤ 0 or non-finite, or budget NaN,
 * negative or infinite). Deterministic: ties keep the lower candidate index. O(candidates · W) time,
 * W = budget / quantum; for measurement on small instances only. */
size_t lod_solve_exact_bytes(const struct lod_problem *p, double cost_quantum_ms);
int lod_solve_exact(const struct lod_problem *p, double cost_quantum_ms, void *work, size_t work_bytes,
                    uint8_t *choice, double *benefit_out);

/* ---- the layer choice (issue 32; frame/layers.h) ----------------------------------------------------
 * With foveated layers a frame is one knapsack per candidate layer setting: problems[s] prices and
 * values every object under setting s, with s's own budget (its overhead taken out). The setting is
 * an outer choice, so the optimum over settings and levels together is the best of the settings'
 * optima and the LP bound of the union the largest of theirs. Best: a setting that draws every
 * object (lod_solve_exact returns 0) before one that must drop (dropping is the last resort, as the
 * frame's choice), then the highest benefit, the lower index on a tie. For measurement only.
 * Returns what lod_solve_exact returned for the winner (0 or 1), or the first error of any setting
 * (< 0); *setting_out and choice (the winner's) and *benefit_out are written on success. work: the
 * largest lod_solve_exact_bytes of the settings (lod_solve_exact_settings_bytes). */
size_t lod_solve_exact_settings_bytes(const struct lod_problem *problems, size_t count, double cost_quantum_ms);
int lod_solve_exact_settings(const struct lod_problem *problems, size_t count, double cost_quantum_ms, void *work,
                             size_t work_bytes, uint8_t *choice, size_t *setting_out, double *benefit_out);
double lod_lp_bound_settings(const struct lod_problem *problems, size_t count);

/* ---- hierarchy (Mason & Blake 1997) -------------------------------------------------------------
 * A representation tree over one frame's visible part of the scene hierarchy: nodes are groups and
 * objects (leaves), numbered parents before children (parent[n] < n, LOD_MB_ROOT for a root; several
 * roots hang under an imaginary root). A node's candidates are laid out as in lod_problem (cheapest
 * first, hull-reduced per node): a group's are its impostors (count 0: none), a leaf's its levels
 * (maybe LOD_DROP first). A node is explicit (one of its candidates) or, if it has children,
 * implicit (represented by them). Opening a group costs its children's cheapest choices; an impostor
 * candidate that does not cost less and earn less than that (§3's requirement), or that lies under the
 * hull through it, is ignored for the frame; a group left with none behaves as one without impostor. */
enum { LOD_MB_ROOT = UINT32_MAX };
enum { LOD_MB_BELOW = 252, /* state: not in the representation tree (an ancestor is explicit or dropped) */
       LOD_MB_OPEN = 253 }; /* state: implicit, represented by its children */
struct lod_tree {
    size_t node_count;
    const uint32_t *node_id;     /* stable id per node: every tie is broken by it, never by memory order */
    const uint32_t *parent;      /* parent[n] < n, or LOD_MB_ROOT */
    const uint32_t *first_child; /* node n's children are child[first_child[n] … + child_count[n] − 1] */
    const uint32_t *child_count; /* 0: a leaf */
    const uint32_t *child;
    const uint32_t *first;       /* candidates, as in lod_problem */
    const uint8_t *count;        /* leaf: ≥ 1 (0: no valid candidate, always LOD_DROPPED); group: 0 = no impostor */
    const double *cost_ms;       /* per candidate, finite, ≥ 0 */
    const double *benefit;       /* per candidate, finite, ≥ 0 */
    double budget_ms;            /* for Σ cost_ms over the representation tree's leaves */
};

/* Scratch bytes lod_optimize_mb needs for up to max_nodes nodes (about 190 per node). */
size_t lod_mb_scratch_bytes(size_t max_nodes);

/* state[n] for the cheapest representation: each root and each implicit-only group open down to the
 * first node with a candidate, which takes its candidate 0; everything under it LOD_MB_BELOW. O(n). */
void lod_mb_start_cheapest(const struct lod_tree *t, uint8_t *state);

/* Mason & Blake §4, time-limited as Nirenstein et al. §5.5. state[n] in/out: a candidate index
 * (explicit), LOD_MB_OPEN, LOD_MB_BELOW or LOD_DROPPED. On input last frame's solution (anything
 * inconsistent is repaired: a node the tree needs but state does not give gets its cheapest
 * choice); on output the frame's choice. Each iteration increments the root — the terminal whose
 * next step (a leaf's next candidate or a group's opening into its children) has the highest value
 * Δbenefit/Δcost — and then decrements while over budget the terminal whose last step has the
 * lowest value (a candidate down, or closing a group whose children are all at their cheapest). The
 * highest and lowest values of each subtree are kept per node and updated post-order along the
 * changed path only; the imaginary root keeps its children in two tournament trees. Stops when (1) within
 * budget and nothing can rise, (2) over budget and nothing can fall — then representation-tree
 * leaves are dropped, lowest benefit per cost first (ties by node_id), until the rest fits; dropped
 * ones that still fit come back, highest benefit per cost first, as in lod_optimize_greedy; over_budget
 * is set and the rest rises into what the drops freed — or (3) the
 * terminal just incremented is decremented. Ties: the lower node_id rises first, the higher falls
 * first (the reverse of the rising order). Then the ½-optimal guard (§6): the cheapest
 * representation with the single best candidate of one of its leaves, if that earns more. Every
 * iteration ends complete and, unless over budget, within budget, so time_limit_us (0 = none),
 * counted from the call, may stop it after any iteration but the first (truncated; the guard is
 * then skipped). With no groups it equals
 * lod_optimize_greedy. O(n) set-up, O(depth · fan-out + log roots) per iteration; no allocation. */
void lod_optimize_mb(const struct lod_tree *t, double time_limit_us, void *scratch, uint8_t *state,
                     struct lod_result *r);

/* lod_choice_underused_drop on a representation tree: 1 when the explicit nodes' candidates cost
 * under fraction × t->budget_ms and some node marked LOD_DROPPED (with a candidate) would fit at
 * its candidate 0 in budget − cost; else 0. state as lod_optimize_mb writes it. Pure, O(n). */
int lod_tree_underused_drop(const struct lod_tree *t, const uint8_t *state, double fraction);

#endif
