/* acuity/saccade.h: saccades and the suppression of vision around them. Part of the
 * acuity/acuity.h umbrella. A velocity-threshold classifier (I-VT) over the gaze's speed in the
 * world (eye + head: under the VOR the eye turns fast in the head while the gaze holds still, so
 * eye-in-head speed would call every head turn a saccade). During a saccade and a short window
 * after it vision is suppressed and objects may drop to the coarsest level the budget wants; after
 * it, refinement back to the perceptual ceiling must be issued within refine_deadline_s
 * (Chwesiuk & Mantiuk: 28 ms). Thresholds are cited in saccade.c. Allocates nothing. */
#ifndef HMDLOD_ACUITY_SACCADE_H
#define HMDLOD_ACUITY_SACCADE_H

#include "base/base.h"

struct acu_saccade_params {
    double onset_degps;       /* gaze speed above which a saccade starts */
    double offset_degps;      /* speed below which it ends (≤ onset: hysteresis) */
    double suppression_s;     /* vision stays suppressed this long after the saccade ends */
    double refine_deadline_s; /* refinement to the ceiling due within this after suppression ends */
};
/* 100 / 50 deg/s, 50 ms, 28 ms (each cited in saccade.c). Precondition of acu_saccade_update:
 * 0 < offset ≤ onset, both finite; suppression_s, refine_deadline_s ≥ 0. */
void acu_saccade_params_default(struct acu_saccade_params *p);

enum acu_saccade_phase {
    ACU_SACCADE_NONE = 0,       /* vision as usual */
    ACU_SACCADE_IN = 1,         /* inside a saccade: suppressed */
    ACU_SACCADE_SUPPRESSED = 2, /* in the window after one: still suppressed */
};

struct acu_saccade_state {
    enum acu_saccade_phase phase;
    double saccade_end_s;   /* when the last saccade ended (−∞ before any) */
    double refine_due_s;    /* when refinement is due (+∞ when nothing is pending) */
    long saccades;          /* saccades seen */
};
void acu_saccade_init(struct acu_saccade_state *s);

/* One sample at time_s (non-decreasing) with the gaze's world speed in deg/s (NaN → treated as no
 * saccade: it starts none and ends one in progress). A saccade starts at speed ≥ onset (also inside
 * the last one's window: counted as a new one) and ends at the first sample below offset; the window
 * then runs suppression_s from that sample's time. The first sample at or past the window's end is
 * NONE again and sets refine_due_s = window end + refine_deadline_s. Returns the sample's phase. */
enum acu_saccade_phase acu_saccade_update(struct acu_saccade_state *s, const struct acu_saccade_params *p,
                                          double time_s, double gaze_speed_degps);
/* The caller has refined everything the last saccade let drop: refine_due_s back to +∞. */
void acu_saccade_refined(struct acu_saccade_state *s);

#endif
