/* base: the double-precision vector and quaternion helpers on their hard cases. */
#include "base/base.h"
#include "test_util.h"

#include <math.h>
#include <string.h>

static void test_angles(void)
{
    /* atan2 form: exact for tiny angles where acos(dot) returns 0, and for antiparallel vectors. */
    CHECK_NEAR(hl_v3_angle_rad(hl_v3(1, 0, 0), hl_v3(1, 1e-9, 0)), 1e-9, 1e-20);
    CHECK_NEAR(hl_v3_angle_rad(hl_v3(1, 0, 0), hl_v3(-1, 1e-9, 0)), HL_PI - 1e-9, 1e-15);
    CHECK(hl_v3_angle_rad(hl_v3(0, 0, 0), hl_v3(1, 0, 0)) == 0.0);
    CHECK_NEAR(hl_v3_angle_rad(hl_v3(1e200, 0, 0), hl_v3(0, 1e200, 0)), HL_PI / 2, 1e-15);
    CHECK_NEAR(hl_v3_length(hl_v3(3e200, 4e200, 0)), 5e200, 1e186);
    hl_vec3d z = hl_v3_normalize(hl_v3(0, 0, 0));
    CHECK(z.x == 0 && z.y == 0 && z.z == 0);
}

static void test_quaternions(void)
{
    hl_quatd q = hl_q_from_axis_angle(hl_v3(0, 1, 0), HL_PI / 2);
    hl_vec3d v = hl_q_rotate(q, hl_v3(0, 0, -1)); /* forward turned 90° left about +Y → −X */
    CHECK_NEAR(v.x, -1.0, 1e-15);
    CHECK_NEAR(v.z, 0.0, 1e-15);
    /* q and −q are the same rotation: angle 0 between them, log of either is the same vector. */
    CHECK_NEAR(hl_q_angle_rad(q, hl_q_neg(q)), 0.0, 1e-15);
    hl_vec3d r1 = hl_q_log(q), r2 = hl_q_log(hl_q_neg(q));
    CHECK_NEAR(r1.y, HL_PI / 2, 1e-15);
    CHECK_NEAR(r2.y, HL_PI / 2, 1e-15);
    /* exp/log round trip from 1e-12 rad to nearly π. */
    const double angles[] = {0.0, 1e-12, 1e-6, 0.5, 3.0, HL_PI - 1e-9};
    for (size_t i = 0; i < sizeof angles / sizeof angles[0]; ++i) {
        hl_vec3d r = hl_v3_scale(hl_v3_normalize(hl_v3(1, 2, 3)), angles[i]);
        hl_vec3d back = hl_q_log(hl_q_exp(r));
        CHECK_NEAR(hl_v3_length(hl_v3_sub(back, r)), 0.0, 1e-12 + 1e-12 * angles[i]);
    }
    /* slerp takes the short way even when b is given in the other hemisphere. */
    hl_quatd a = hl_q_identity();
    hl_quatd b = hl_q_neg(hl_q_from_axis_angle(hl_v3(0, 0, 1), 0.2));
    hl_quatd mid = hl_q_slerp(a, b, 0.5);
    CHECK_NEAR(hl_q_angle_rad(a, mid), 0.1, 1e-14);
    CHECK_NEAR(hl_q_norm(mid), 1.0, 1e-15);
    /* A tiny step interpolates without 0/0. */
    hl_quatd tiny = hl_q_from_axis_angle(hl_v3(1, 0, 0), 1e-14);
    hl_quatd m2 = hl_q_slerp(a, tiny, 0.5);
    CHECK(isfinite(m2.w) && isfinite(m2.x));
    CHECK(hl_q_normalize(hl_q(0, 0, 0, 0)).w == 1.0);
}

static void test_error(void)
{
    struct hl_error err;
    memset(&err, 0, sizeof err);
    CHECK(hl_fail(&err, "%s:%d: %s", "file.csv", 12, "bad") == -1);
    CHECK(strcmp(err.msg, "file.csv:12: bad") == 0);
    CHECK(hl_fail(NULL, "ignored") == -1);
    int64_t t0 = hl_clock_now_ns(), t1 = hl_clock_now_ns();
    CHECK(t1 >= t0);
}

/* Nearest rank: the smallest value with at least p·n of the samples at or below it. */
static void test_percentiles(void)
{
    double v[] = {5, 1, 4, 2, 3, 10, 9, 8, 7, 6};
    hl_sort_doubles(v, 10);
    for (int i = 0; i < 10; ++i)
        CHECK(v[i] == i + 1);
    CHECK(hl_percentile_sorted(v, 10, 0.5) == 5);   /* 5 of 10 at or below */
    CHECK(hl_percentile_sorted(v, 10, 0.51) == 6);
    CHECK(hl_percentile_sorted(v, 10, 0.99) == 10);
    CHECK(hl_percentile_sorted(v, 10, 0.0) == 1);
    CHECK(hl_percentile_sorted(v, 10, 1.0) == 10);
    CHECK(hl_percentile_sorted(v, 10, 7.0) == 10);  /* out of range clamps to the ends */
    CHECK(hl_percentile_sorted(v, 10, -1.0) == 1);
    CHECK(hl_percentile_sorted(v, 10, NAN) == 1);
    CHECK(hl_percentile_sorted(v, 0, 0.5) == 0.0);
    CHECK(hl_percentile_sorted(v, 1, 0.99) == 1);
    hl_sort_doubles(v, 0);
}

int main(void)
{
    test_percentiles();
    test_angles();
    test_quaternions();
    test_error();
    return tu_finish("test_base");
}
