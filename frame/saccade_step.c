/* Saccade suppression and the 28 ms refinement rule in a replay frame (frame/select.h; the classifier
 * is acuity/saccade.c). During a saccade and its suppression window every object's perceptual ceiling
 * is its coarsest level, so the selectors that follow the ceiling draw the coarsest level the budget
 * wants (fs and mb see no benefit above it: lod_benefit_fill). Once the window ends, refinement back to
 * the ceiling is due within refine_deadline_s (Chwesiuk & Mantiuk 2016: 28 ms). What is counted:
 *   target       what the saccade took away: the coarser of the object's ceiling now and its level on
 *                the frame before the saccade began (its ceiling if it was not drawn then). A budgeted
 *                selector (fs, mb) often leaves an object below its ceiling in steady state; that is
 *                its choice, not a refinement owed after a saccade;
 *   pending      an object drawn coarser than its target (LOD_DROP counts as coarser) whose target
 *                shows more on screen: more samples within its pixels, min(vertices, pixels_px), the
 *                detail measure of the benefit (Funkhouser & Séquin 1993 §5) — an object covering a few
 *                pixels shows no more at a finer level, and fs rightly keeps it coarse;
 *   unbudgeted   a pending object whose raise to its target, alone, fits the frame's slack (the
 *                optimizer's budget less the predicted cost of what it drew; +∞ for reddy, which has no
 *                budget). The rest are coarse because of the budget, which is not a refinement delay.
 *   miss         a frame later than refine_due_s with an unbudgeted object left.
 * The refinement is complete at the first frame with no unbudgeted object; a new saccade ends it too.
 * With layers, the target is no finer than what the chosen setting shows of the object (its periphery
 * ceiling where only the periphery shows it) and raises are priced as that setting prices them.
 *
 * The boost (issue 32 item 5), while a refinement is owed:
 *   hysteresis   fs's hysteresis (Funkhouser & Séquin §5: a level k steps from the previous one counts
 *                its error 1 + k times) is measured from the level before the saccade, not from the
 *                suppressed frames' coarsest: those were not seen, so going back is no change to the
 *                viewer and staying coarse is one. Measured from the coarsest, the way back was worth
 *                less than the step that stops the greedy, and fs left the object coarse with most of
 *                the budget unused (EDVAM participant 2: 27 of 113 saccades missed, render scale 0.25);
 *   raise        after the choice, each pending object whose raise to its target fits what the
 *                optimizer's budget has left is raised, nearest the gaze first — the greedy stops at
 *                its first step that does not fit, and the slack it leaves may hold the refinement.
 * Allocates nothing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "frame/layers.h"
#include "frame/select.h"
#include "tracking/tracking.h"

void frm_select_saccade(struct frm_select *s, const struct trk_pose *pose, double time_s)
{
    struct frm_saccade *q = &s->saccade;
    q->active = pose->has_gaze && !s->saccade_off;
    q->started = 0;
    q->time_s = time_s;
    q->speed_degps = 0.0;
    if (!q->active)
        return;
    /* The gaze's speed in the world (eye + head), not in the head: under the VOR the eye turns fast in
     * the head while the gaze holds still (acuity/saccade.h). */
    double speed_degps = q->speed_degps = hl_v3_length(pose->gaze_angular_velocity_radps) * HL_DEG_PER_RAD;
    long before = q->state.saccades;
    enum acu_saccade_phase was = q->state.phase;
    acu_saccade_update(&q->state, &q->params, time_s, speed_degps);
    q->started = q->state.saccades != before;
    if (q->started)
        q->missed = 0;
    /* The levels before it, unless vision was already suppressed (a saccade in the last one's window):
     * last frame's levels are then the lowered ones. */
    if (q->started && was == ACU_SACCADE_NONE)
        memcpy(q->level_before, s->level_of_instance, s->level_capacity);
}

/* 1 while a refinement is owed: the suppression has ended, not yet refined (frm_saccade_account). */
static int refinement_owed(const struct frm_select *s)
{
    const struct frm_saccade *q = &s->saccade;
    return q->active && q->state.phase == ACU_SACCADE_NONE && isfinite(q->state.refine_due_s);
}

uint8_t frm_saccade_seen_level(const struct frm_select *s, uint32_t instance)
{
    return refinement_owed(s) ? s->saccade.level_before[instance] : s->level_of_instance[instance];
}

void frm_saccade_lower_ceilings(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in)
{
    if (!s->saccade.active || s->saccade.state.phase == ACU_SACCADE_NONE)
        return;
    for (size_t k = 0; k < in->count; ++k) {
        uint8_t levels = s->chain_lod_count[scene->chain_of_instance[in->visible[k]]];
        if (levels > 0)
            s->ceiling_level[k] = (uint8_t)(levels - 1);
    }
}

/* Visible object k's target (what the saccade took from it: the coarser of the finest level the
 * setting shows and its level before the saccade) when it is pending — drawn coarser and the target
 * shows more samples within its pixels; else −1. */
static int pending_target(const struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                          const uint8_t *lod, const struct frm_layer_candidate *layer, size_t k)
{
    uint8_t before = s->saccade.level_before[in->visible[k]];
    uint8_t finest = layer ? frm_layers_shown_ceiling(s->layers, layer, k) : s->ceiling_level[k];
    uint8_t target = before != LOD_UNSEEN && before != LOD_DROP && before > finest ? before : finest;
    if (lod[k] != LOD_DROP && lod[k] <= target)
        return -1;
    const struct scn_chain *ch = &scene->chains[scene->chain_of_instance[in->visible[k]]];
    double px = s->pixels_px[k];
    double shown = lod[k] == LOD_DROP ? 0.0 : fmin(ch->lods[lod[k]].vertex_count, px);
    return fmin(ch->lods[target].vertex_count, px) > shown ? target : -1;
}

/* What raising object k from lod to target costs under the setting, ms. */
static double raise_ms(const struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                       const struct frm_layer_candidate *layer, size_t k, uint8_t from, int target)
{
    const struct scn_chain *ch = &scene->chains[scene->chain_of_instance[in->visible[k]]];
    return frm_select_level_cost_ms(s, layer, ch, target, k) -
           (from == LOD_DROP ? 0.0 : frm_select_level_cost_ms(s, layer, ch, from, k));
}

static int refine_entry_compare(const void *a, const void *b)
{
    const struct frm_refine_entry *x = a, *y = b;
    if (x->eccentricity_deg != y->eccentricity_deg)
        return x->eccentricity_deg < y->eccentricity_deg ? -1 : 1;
    return (x->instance > y->instance) - (x->instance < y->instance);
}

uint32_t frm_saccade_refine(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                            uint8_t *lod, const struct frm_layer_candidate *layer, double budget_ms)
{
    if (!refinement_owed(s) || s->selector != FRM_SELECT_FS)
        return 0;
    if (layer && layer->scale >= 1.0)
        layer = NULL;
    size_t n = 0;
    for (size_t k = 0; k < in->count; ++k) { /* an object's target does not depend on the others' levels */
        int target = pending_target(s, scene, in, lod, layer, k);
        if (target >= 0)
            s->saccade.refine[n++] =
                (struct frm_refine_entry){in->eccentricity_deg[k], in->visible[k], (uint32_t)k, (uint8_t)target};
    }
    if (n == 0)
        return 0;
    qsort(s->saccade.refine, n, sizeof *s->saccade.refine, refine_entry_compare);
    double slack_ms = budget_ms;
    for (size_t k = 0; k < in->count; ++k)
        if (lod[k] != LOD_DROP)
            slack_ms -= frm_select_level_cost_ms(s, layer, &scene->chains[scene->chain_of_instance[in->visible[k]]],
                                                 lod[k], k);
    uint32_t raised = 0;
    for (size_t j = 0; j < n; ++j) {
        const struct frm_refine_entry *e = &s->saccade.refine[j];
        double ms = raise_ms(s, scene, in, layer, e->k, lod[e->k], e->target);
        if (ms <= slack_ms) {
            slack_ms -= ms;
            lod[e->k] = e->target;
            ++raised;
        }
    }
    return raised;
}

void frm_saccade_account(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                         const uint8_t *lod, const struct frm_layer_candidate *layer, struct frm_select_record *rec)
{
    struct frm_saccade *q = &s->saccade;
    rec->saccade_active = q->active;
    rec->saccade_phase = q->active ? (int)q->state.phase : ACU_SACCADE_NONE;
    rec->saccade_started = q->started;
    rec->gaze_speed_degps = q->speed_degps;
    if (!refinement_owed(s) || !frm_selector_uses_ceiling(s->selector))
        return;
    if (layer && layer->scale >= 1.0)
        layer = NULL;
    /* The optimizer's budget excludes c0 and the setting's own overhead; the prediction holds both. */
    double slack_ms = s->selector == FRM_SELECT_REDDY
                          ? INFINITY
                          : rec->optimizer_budget_ms -
                                (rec->predicted_ms - s->cost.c0_ms - (layer ? layer->overhead_ms : 0.0));
    for (size_t k = 0; k < in->count; ++k) {
        int target = pending_target(s, scene, in, lod, layer, k);
        if (target < 0)
            continue;
        rec->refine_pending++;
        rec->refine_unbudgeted += raise_ms(s, scene, in, layer, k, lod[k], target) <= slack_ms;
    }
    if (rec->refine_unbudgeted == 0) {
        acu_saccade_refined(&q->state);
        return;
    }
    if (q->time_s > q->state.refine_due_s) {
        rec->refine_miss = 1;
        rec->refine_missed_saccade = !q->missed;
        q->missed = 1;
    }
}
