/* The built-in 8 s clip for `hmdlod demo`, generated in code so the demo needs no file. Yaw is about
 * world +Y (positive turns left), pitch about the head's +X (positive looks up). */
#include "replay/trace_internal.h"

#include <math.h>

#define CLIP_RATE_HZ 60.0
#define CLIP_DURATION_S 8.0
/* A minimum-jerk turn of D degrees over T seconds peaks at 1.875·D/T deg/s. */
#define FAST_TURN_DEG 90.0
#define FAST_TURN_PEAK_DEGPS 270.0
#define BACK_TURN_PEAK_DEGPS 120.0

/* Minimum-jerk position profile 10s³ − 15s⁴ + 6s⁵ on s ∈ [0, 1], clamped outside. */
static double min_jerk(double s)
{
    if (s <= 0.0)
        return 0.0;
    if (s >= 1.0)
        return 1.0;
    return s * s * s * (10.0 + s * (-15.0 + 6.0 * s));
}

/* yaw and pitch (deg) at t. Segments: still 0–1 s; look-around 1–4 s; fast turn; still 1 s; slower
 * turn back; still to the end. */
static void clip_angles(double t, double *yaw_deg, double *pitch_deg)
{
    const double look_start = 1.0, look_len = 3.0;
    const double fast_start = look_start + look_len;
    const double fast_len = 1.875 * FAST_TURN_DEG / FAST_TURN_PEAK_DEGPS; /* 0.625 s */
    const double back_start = fast_start + fast_len + 1.0;
    const double back_len = 1.875 * FAST_TURN_DEG / BACK_TURN_PEAK_DEGPS; /* 1.406 s */
    *yaw_deg = 0.0;
    *pitch_deg = 0.0;
    if (t >= look_start && t < fast_start) {
        /* ±30° at 1/3 Hz (one full cycle fits the 3 s, so it ends where it began), with 0.5 s
         * minimum-jerk fades so velocity starts and ends at zero; a small 5° pitch at 2/3 Hz. */
        double tau = t - look_start;
        double fade = min_jerk(tau / 0.5) * min_jerk((look_len - tau) / 0.5);
        *yaw_deg = 30.0 * sin(2.0 * HL_PI * tau / look_len) * fade;
        *pitch_deg = 5.0 * sin(4.0 * HL_PI * tau / look_len) * fade;
    } else if (t >= fast_start && t < back_start) {
        *yaw_deg = FAST_TURN_DEG * min_jerk((t - fast_start) / fast_len);
    } else if (t >= back_start) {
        *yaw_deg = FAST_TURN_DEG * (1.0 - min_jerk((t - back_start) / back_len));
    }
}

int rpl_trace_builtin_clip(struct rpl_trace *out, struct hl_error *err)
{
    size_t rows = (size_t)lround(CLIP_DURATION_S * CLIP_RATE_HZ) + 1;
    struct trace_builder b;
    if (trace_builder_init(&b, out, RPL_TRACE_HMDLOD_CSV, rows, 0, 0, err) != 0)
        return -1;
    for (size_t i = 0; i < rows; ++i) {
        double t = (double)i / CLIP_RATE_HZ;
        double yaw_deg, pitch_deg;
        clip_angles(t, &yaw_deg, &pitch_deg);
        hl_quatd q = hl_q_mul(hl_q_from_axis_angle(hl_v3(0, 1, 0), yaw_deg * HL_RAD_PER_DEG),
                              hl_q_from_axis_angle(hl_v3(1, 0, 0), pitch_deg * HL_RAD_PER_DEG));
        trace_builder_push(&b, t, hl_q_normalize(q), NULL, NULL);
    }
    return trace_builder_finish(&b, "built-in clip", 0, err);
}
