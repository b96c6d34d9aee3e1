/* Conversions of doubles to int64 that cannot invoke undefined behaviour: C11 6.3.1.4 leaves a
 * float-to-integer conversion whose value does not fit undefined, and on x86-64 it silently yields
 * INT64_MIN — the kind of wrap that once turned a huge trace duration into a negative frame count. */
#include "base/base.h"

#include <math.h>

/* Sizes computed from 32-bit counts (vertices, rows, instances) times a small element size fit a
 * 64-bit size_t provably; the project's loaders rely on that. */
_Static_assert(sizeof(size_t) >= 8, "hmdlod needs a 64-bit size_t");

/* 2^63 is exactly representable; every double below it converts. */
#define TWO_POW_63 9223372036854775808.0

int hl_i64_from_double(double x, int64_t *out)
{
    if (!(x >= -TWO_POW_63 && x < TWO_POW_63)) /* also false for NaN */
        return -1;
    *out = (int64_t)x;
    return 0;
}

int64_t hl_i64_from_double_saturating(double x)
{
    if (isnan(x))
        return 0;
    if (x >= TWO_POW_63)
        return INT64_MAX;
    if (x <= -TWO_POW_63)
        return INT64_MIN;
    return (int64_t)x;
}

int hl_ns_from_s(double seconds, int64_t *ns_out)
{
    if (!isfinite(seconds))
        return -1;
    return hl_i64_from_double(nearbyint(seconds * 1e9), ns_out);
}
