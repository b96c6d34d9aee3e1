/* Saccades and the suppression of vision around them (acuity/saccade.h).
 *
 * Classifier: I-VT, the velocity-threshold identification of Salvucci & Goldberg (2000, "Identifying
 * fixations and saccades in eye-tracking protocols", ETRA '00 pp. 71–78): a sample whose gaze speed
 * is above a threshold belongs to a saccade. As in Nyström & Holmqvist (2010, Behav. Res. Methods
 * 42(1):188–204), a saccade starts at a high threshold (their peak threshold starts at 100 deg/s)
 * and ends at a lower one, so noise around one threshold cannot split a saccade into several.
 *
 * Thresholds. I-VT thresholds in the literature run from 30 deg/s (clean data at 250 Hz and more,
 * e.g. Tobii's I-VT filter) to 100 deg/s and beyond for noisy or low-rate data. The gaze this
 * project replays is noisy: EDVAM (the only tracked gaze in ../shared/data) holds the point of gaze
 * and the camera rounded to 0.1 m at ~31 Hz, so a single 0.1 m step of the gaze point at the median
 * distance of 4.3 m already reads as ~45 deg/s, at 1.5 m as ~130 deg/s. Measured on both EDVAM
 * files (world gaze L − C, consecutive samples with confidence ≥ 0.8; docs/gaze.md "Measurements"):
 * median 0–6 deg/s, p90 67–107, p95 101–157 deg/s. Onset at 100 deg/s sits above the p90 of that
 * noise and keeps 5–12 % of steps, the share of time natural viewing spends in saccades (about
 * 3 saccades/s of 30–50 ms). Offset at half the onset ends a saccade once the gaze has clearly slowed.
 *
 * Suppression. Visual sensitivity drops from about 50 ms before a saccade to about 50 ms after its
 * end (Volkmann 1986, "Human visual suppression", Vision Res. 26(9):1401–1416; Ross, Morrone,
 * Goldberg & Burr 2001, "Changes in visual perception at the time of saccades", TINS 24(2):113–121).
 * The window before the onset cannot be used online (the saccade is not yet known), so only the
 * 50 ms after the end are.
 *
 * Refinement: a coarse-to-fine LOD change after a gaze shift went unnoticed when it completed within
 * 28 ms (Chwesiuk & Mantiuk, EG 2016 poster; PAPERS.md "The eye in a headset"). */
#include <math.h>

#include "acuity/saccade.h"

void acu_saccade_params_default(struct acu_saccade_params *p)
{
    p->onset_degps = 100.0;      /* Nyström & Holmqvist 2010; above EDVAM's noise p90 (see above) */
    p->offset_degps = 50.0;      /* half the onset: hysteresis */
    p->suppression_s = 0.050;    /* Volkmann 1986; Ross et al. 2001 */
    p->refine_deadline_s = 0.028; /* Chwesiuk & Mantiuk 2016 */
}

void acu_saccade_init(struct acu_saccade_state *s)
{
    s->phase = ACU_SACCADE_NONE;
    s->saccade_end_s = -INFINITY;
    s->refine_due_s = INFINITY;
    s->saccades = 0;
}

enum acu_saccade_phase acu_saccade_update(struct acu_saccade_state *s, const struct acu_saccade_params *p,
                                          double time_s, double gaze_speed_degps)
{
    /* NaN (no gaze this sample) compares false everywhere: it starts nothing and ends a saccade. */
    int fast = gaze_speed_degps >= p->onset_degps;
    int slow = !(gaze_speed_degps >= p->offset_degps);
    switch (s->phase) {
    case ACU_SACCADE_IN:
        if (slow) {
            s->saccade_end_s = time_s;
            s->phase = ACU_SACCADE_SUPPRESSED;
        }
        break;
    case ACU_SACCADE_NONE:
    case ACU_SACCADE_SUPPRESSED:
        if (fast) { /* a new saccade, also one inside the last one's window */
            s->phase = ACU_SACCADE_IN;
            s->refine_due_s = INFINITY;
            s->saccades++;
            return s->phase;
        }
        break;
    }
    if (s->phase == ACU_SACCADE_SUPPRESSED && time_s >= s->saccade_end_s + p->suppression_s) {
        s->phase = ACU_SACCADE_NONE;
        s->refine_due_s = s->saccade_end_s + p->suppression_s + p->refine_deadline_s;
    }
    return s->phase;
}

void acu_saccade_refined(struct acu_saccade_state *s)
{
    s->refine_due_s = INFINITY;
}
