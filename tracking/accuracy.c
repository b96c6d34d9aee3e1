/* The accuracy metrics of tracking/evaluate.c as an accumulator: tilt RMS/max, heading drift
 * (least-squares slope of the unwrapped heading error), heading RMS/max after a skip, and the
 * prediction-step errors per horizon. evaluate.c's header comment defines each metric; this file
 * only sums. Kept apart so that a tracker outside hmdlod (bench tracking's OpenHMD row) is scored
 * by the very same arithmetic as ours, not by a copy of it. */
#include <math.h>
#include <string.h>

#include "tracking/tracking.h"

void trk_accuracy_init(struct trk_accuracy *acc, double yaw_skip_s)
{
    memset(acc, 0, sizeof *acc);
    acc->yaw_skip_s = yaw_skip_s;
}

void trk_accuracy_add(struct trk_accuracy *acc, double t_s, hl_quatd est, hl_quatd truth)
{
    double te = trk_tilt_error_rad(est, truth);
    acc->tilt2 += te * te;
    if (te > acc->tilt_max)
        acc->tilt_max = te;
    double y = trk_yaw_error_rad(est, truth);
    if (acc->n > 0) { /* unwrap against the previous instant */
        while (y - acc->yaw_prev > HL_PI)
            y -= 2.0 * HL_PI;
        while (y - acc->yaw_prev < -HL_PI)
            y += 2.0 * HL_PI;
    }
    acc->yaw_prev = y;
    if (t_s >= acc->yaw_skip_s) {
        acc->yaw2 += y * y;
        acc->yaw_max = fabs(y) > acc->yaw_max ? fabs(y) : acc->yaw_max;
        ++acc->yaw_n;
    }
    acc->sum_t += t_s;
    acc->sum_y += y;
    acc->sum_tt += t_s * t_s;
    acc->sum_ty += t_s * y;
    ++acc->n;
}

void trk_accuracy_add_horizon(struct trk_accuracy *acc, int h, hl_quatd est, hl_quatd pred, hl_quatd truth,
                              hl_quatd truth_h)
{
    if (h < 0 || h >= TRK_EVAL_HORIZONS)
        return;
    /* Body-frame step: a heading offset between the estimated and true world frames cancels. */
    hl_quatd true_step = hl_q_mul(hl_q_conj(truth), truth_h);
    double e = hl_q_angle_rad(hl_q_mul(hl_q_conj(est), pred), true_step);
    double he = hl_q_angle_rad(hl_q_identity(), true_step);
    double ae = hl_q_angle_rad(pred, truth_h), hae = hl_q_angle_rad(est, truth_h);
    acc->s2[h] += e * e;
    acc->hs2[h] += he * he;
    acc->a2[h] += ae * ae;
    acc->ha2[h] += hae * hae;
    ++acc->m[h];
}

void trk_accuracy_finish(const struct trk_accuracy *acc, struct trk_evaluate_result *res)
{
    res->evaluated = acc->n;
    res->tilt_rms_deg = res->tilt_max_deg = res->yaw_drift_deg_per_min = 0.0;
    res->yaw_rms_deg = res->yaw_max_deg = 0.0;
    if (acc->n > 0) {
        double N = (double)acc->n;
        res->tilt_rms_deg = sqrt(acc->tilt2 / N) * HL_DEG_PER_RAD;
        res->tilt_max_deg = acc->tilt_max * HL_DEG_PER_RAD;
        double den = acc->sum_tt - acc->sum_t * acc->sum_t / N;
        res->yaw_drift_deg_per_min =
            den > 0 ? (acc->sum_ty - acc->sum_t * acc->sum_y / N) / den * HL_DEG_PER_RAD * 60.0 : 0.0;
    }
    if (acc->yaw_n > 0) {
        res->yaw_rms_deg = sqrt(acc->yaw2 / (double)acc->yaw_n) * HL_DEG_PER_RAD;
        res->yaw_max_deg = acc->yaw_max * HL_DEG_PER_RAD;
    }
    for (int h = 0; h < TRK_EVAL_HORIZONS; ++h) {
        res->step_rms_deg[h] = res->hold_step_rms_deg[h] = res->abs_rms_deg[h] = res->hold_abs_rms_deg[h] = 0.0;
        if (acc->m[h] == 0)
            continue;
        double M = (double)acc->m[h];
        res->step_rms_deg[h] = sqrt(acc->s2[h] / M) * HL_DEG_PER_RAD;
        res->hold_step_rms_deg[h] = sqrt(acc->hs2[h] / M) * HL_DEG_PER_RAD;
        res->abs_rms_deg[h] = sqrt(acc->a2[h] / M) * HL_DEG_PER_RAD;
        res->hold_abs_rms_deg[h] = sqrt(acc->ha2[h] / M) * HL_DEG_PER_RAD;
    }
}
