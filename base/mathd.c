#include "base/base.h"

#include <math.h>
#include <stdlib.h>

double hl_v3_length(hl_vec3d a)
{
    /* sqrt(a·a) wherever the sum of squares is a normal double far from underflow: there every
     * square that underflows is < 2^-120 of the sum, so the result is within 3 ulp of hypot's (2
     * measured, tests/test_base.c). Two hypot calls cost ~10x more and were a third of the fusion's
     * time per sample. Outside that range (|a| above ~1e150 or below ~1e-135), infinities and NaN:
     * hypot, which neither overflows nor loses the small ones. */
    double s = a.x * a.x + a.y * a.y + a.z * a.z;
    if (s >= 0x1p-900 && s <= 0x1p+1000)
        return sqrt(s);
    return hypot(hypot(a.x, a.y), a.z);
}

hl_vec3d hl_v3_normalize(hl_vec3d a)
{
    double len = hl_v3_length(a);
    if (!(len > 0.0) || !isfinite(len))
        return len > 0.0 ? hl_v3_scale(a, 0.0) : a;
    return hl_v3_scale(a, 1.0 / len);
}

double hl_v3_angle_rad(hl_vec3d a, hl_vec3d b)
{
    /* atan2 keeps full precision where acos of a near-±1 dot would lose half the digits. */
    double s = hl_v3_length(hl_v3_cross(a, b));
    double c = hl_v3_dot(a, b);
    if (s == 0.0 && c == 0.0)
        return 0.0;
    return atan2(s, c);
}

hl_quatd hl_q_mul(hl_quatd a, hl_quatd b)
{
    return hl_q(a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
                a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w);
}

double hl_q_norm(hl_quatd q) { return sqrt(hl_q_dot(q, q)); }

hl_quatd hl_q_normalize(hl_quatd q)
{
    double n = hl_q_norm(q);
    if (!(n > 0.0) || !isfinite(n))
        return hl_q_identity();
    return hl_q(q.w / n, q.x / n, q.y / n, q.z / n);
}

hl_vec3d hl_q_rotate(hl_quatd q, hl_vec3d v)
{
    /* v' = v + 2w(u×v) + 2u×(u×v), u = vector part: cheaper than two products, same result. */
    hl_vec3d u = hl_v3(q.x, q.y, q.z);
    hl_vec3d t = hl_v3_scale(hl_v3_cross(u, v), 2.0);
    return hl_v3_add(hl_v3_add(v, hl_v3_scale(t, q.w)), hl_v3_cross(u, t));
}

hl_quatd hl_q_from_axis_angle(hl_vec3d axis, double angle_rad)
{
    hl_vec3d n = hl_v3_normalize(axis);
    double s = sin(0.5 * angle_rad);
    return hl_q(cos(0.5 * angle_rad), n.x * s, n.y * s, n.z * s);
}

hl_quatd hl_q_exp(hl_vec3d r)
{
    double angle = hl_v3_length(r);
    double half = 0.5 * angle;
    /* sin(half)/angle → 1/2 − angle²/48 near zero; the series avoids 0/0. */
    double k = angle < 1e-8 ? 0.5 - angle * angle / 48.0 : sin(half) / angle;
    return hl_q(cos(half), r.x * k, r.y * k, r.z * k);
}

hl_vec3d hl_q_log(hl_quatd q)
{
    if (q.w < 0.0)
        q = hl_q_neg(q); /* shortest arc */
    double s = sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
    double angle = 2.0 * atan2(s, q.w);
    double k = s < 1e-12 ? 2.0 / (q.w > 0.0 ? q.w : 1.0) : angle / s;
    return hl_v3(q.x * k, q.y * k, q.z * k);
}

double hl_q_angle_rad(hl_quatd a, hl_quatd b)
{
    return hl_v3_length(hl_q_log(hl_q_mul(hl_q_conj(a), b)));
}

hl_quatd hl_q_slerp(hl_quatd a, hl_quatd b, double t)
{
    if (hl_q_dot(a, b) < 0.0)
        b = hl_q_neg(b);
    /* a ⊗ exp(t·log(a* ⊗ b)): stable for tiny and large angles alike. */
    hl_vec3d r = hl_q_log(hl_q_mul(hl_q_conj(a), b));
    return hl_q_normalize(hl_q_mul(a, hl_q_exp(hl_v3_scale(r, t))));
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void hl_sort_doubles(double *v, size_t n)
{
    if (n > 1)
        qsort(v, n, sizeof *v, compare_doubles);
}

double hl_percentile_sorted(const double *sorted, size_t n, double p)
{
    if (n == 0)
        return 0.0;
    double rank = ceil(p * (double)n); /* p outside [0, 1] or NaN clamps to the ends */
    size_t i = rank >= 1.0 ? (rank < (double)n ? (size_t)rank - 1 : n - 1) : 0;
    return sorted[i];
}
