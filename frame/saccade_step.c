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
 * Allocates nothing. */
#include <math.h>
#include <string.h>

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

void frm_saccade_account(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                         const uint8_t *lod, struct frm_select_record *rec)
{
    struct frm_saccade *q = &s->saccade;
    rec->saccade_active = q->active;
    rec->saccade_phase = q->active ? (int)q->state.phase : ACU_SACCADE_NONE;
    rec->saccade_started = q->started;
    rec->gaze_speed_degps = q->speed_degps;
    if (!q->active || q->state.phase != ACU_SACCADE_NONE || !isfinite(q->state.refine_due_s) ||
        !frm_selector_uses_ceiling(s->selector))
        return;
    double slack_ms = s->selector == FRM_SELECT_REDDY ? INFINITY
                                                      : rec->optimizer_budget_ms - (rec->predicted_ms - s->cost.c0_ms);
    for (size_t k = 0; k < in->count; ++k) {
        uint8_t before = q->level_before[in->visible[k]];
        uint8_t ceiling = before != LOD_UNSEEN && before != LOD_DROP && before > s->ceiling_level[k] ? before
                                                                                                  : s->ceiling_level[k];
        if (lod[k] != LOD_DROP && lod[k] <= ceiling)
            continue;
        const struct scn_chain *ch = &scene->chains[scene->chain_of_instance[in->visible[k]]];
        double px = s->pixels_px[k];
        double shown = lod[k] == LOD_DROP ? 0.0 : fmin(ch->lods[lod[k]].vertex_count, px);
        if (!(fmin(ch->lods[ceiling].vertex_count, px) > shown))
            continue;
        rec->refine_pending++;
        double raise_ms = frm_level_cost_ms(&s->cost, ch, ceiling, px, s->boxed[k]) -
                          (lod[k] == LOD_DROP ? 0.0 : frm_level_cost_ms(&s->cost, ch, lod[k], px, s->boxed[k]));
        rec->refine_unbudgeted += raise_ms <= slack_ms;
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
