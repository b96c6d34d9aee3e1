/* base: the double-precision vector and quaternion helpers, checked time arithmetic and bounded
 * file reading, on their hard cases (docs/HARD_CASES.md). */
#define _GNU_SOURCE /* setenv, mkdtemp */
#include "base/base.h"
#include "test_util.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

/* hl_v3_length against hypot (the oracle) from 1e-300 to 1e300, across both edges of its fast
 * range, with components of very different sizes; and infinities, NaN, zero, subnormals. */
static void test_length(void)
{
    unsigned long long x = 88172645463325252ull; /* xorshift64 */
    double worst_ulp = 0.0;
    for (int i = 0; i < 200000; ++i) {
        double c[3];
        for (int k = 0; k < 3; ++k) {
            x ^= x << 13, x ^= x >> 7, x ^= x << 17;
            double mant = (double)(x >> 11) * 0x1p-53;               /* [0, 1) */
            int e = (int)((x >> 3) % 1993) - 996;                    /* 2^-996 .. 2^996 */
            if (i % 2)
                e = (int)((x >> 3) % 80) + (i % 4 == 1 ? -450 : 460); /* near the two edges */
            c[k] = ldexp(mant, e) * ((x & 1) ? -1.0 : 1.0);
        }
        double want = hypot(hypot(c[0], c[1]), c[2]);
        double got = hl_v3_length(hl_v3(c[0], c[1], c[2]));
        double ulp = want > 0 ? fabs(got - want) / (nextafter(want, INFINITY) - want) : fabs(got);
        worst_ulp = fmax(worst_ulp, ulp);
    }
    printf("hl_v3_length vs hypot: worst %.2f ulp over 200000 vectors\n", worst_ulp);
    CHECK(worst_ulp <= 3.0); /* 1.5 from the sum and sqrt, 1 from hypot itself */
    CHECK(hl_v3_length(hl_v3(INFINITY, NAN, 0)) == INFINITY);
    CHECK(isnan(hl_v3_length(hl_v3(NAN, 1, 0))));
    CHECK(hl_v3_length(hl_v3(0, 0, 0)) == 0.0);
    CHECK_NEAR(hl_v3_length(hl_v3(3e-320, 4e-320, 0)), 5e-320, 1e-323);
    CHECK(hl_v3_length(hl_v3(1.7e308, 1.7e308, 0)) == INFINITY);
    CHECK_NEAR(hl_v3_length(hl_v3(1e308, 1e308, 0)) / 1e308, sqrt(2.0), 1e-15);
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

/* INT64 edges: every checked operation fits exactly up to the edge and refuses one past it. */
static void test_checked_int64(void)
{
    int64_t r = 0;
    CHECK(hl_i64_add_checked(INT64_MAX - 1, 1, &r) == 0 && r == INT64_MAX);
    CHECK(hl_i64_add_checked(INT64_MAX, 1, &r) == -1 && r == INT64_MAX); /* untouched on failure */
    CHECK(hl_i64_add_checked(INT64_MIN, -1, &r) == -1);
    CHECK(hl_i64_sub_checked(INT64_MIN + 1, 1, &r) == 0 && r == INT64_MIN);
    CHECK(hl_i64_sub_checked(INT64_MIN, 1, &r) == -1);
    CHECK(hl_i64_sub_checked(INT64_MAX, INT64_MIN, &r) == -1); /* two host times at opposite ends */
    CHECK(hl_i64_sub_checked(0, INT64_MIN, &r) == -1);
    CHECK(hl_i64_mul_checked(INT64_MAX / 1000000, 1000000, &r) == 0 && r == INT64_MAX / 1000000 * 1000000);
    CHECK(hl_i64_mul_checked(INT64_MAX / 1000000 + 1, 1000000, &r) == -1); /* ms ticks → ns, one past */
    CHECK(hl_i64_mul_checked(INT64_MIN, -1, &r) == -1);
    CHECK(hl_i64_mul_checked(-1, INT64_MAX, &r) == 0 && r == -INT64_MAX);
    size_t z = 0;
    CHECK(hl_size_mul_checked(SIZE_MAX / 8, 8, &z) == 0);
    CHECK(hl_size_mul_checked(SIZE_MAX / 8 + 1, 8, &z) == -1);

    /* Doubles → int64: NaN, ±inf and anything at or past 2^63 refused; −2^63 itself fits. */
    CHECK(hl_i64_from_double(NAN, &r) == -1);
    CHECK(hl_i64_from_double(INFINITY, &r) == -1);
    CHECK(hl_i64_from_double(-INFINITY, &r) == -1);
    CHECK(hl_i64_from_double(9223372036854775808.0, &r) == -1);
    CHECK(hl_i64_from_double(-9223372036854775808.0, &r) == 0 && r == INT64_MIN);
    CHECK(hl_i64_from_double(9223372036854774784.0, &r) == 0 && r == 9223372036854774784LL); /* largest below */
    CHECK(hl_i64_from_double(1e300, &r) == -1);
    CHECK(hl_i64_from_double(-2.9, &r) == 0 && r == -2);
    CHECK(hl_i64_from_double_saturating(INFINITY) == INT64_MAX);
    CHECK(hl_i64_from_double_saturating(-1e300) == INT64_MIN);
    CHECK(hl_i64_from_double_saturating(NAN) == 0);
    CHECK(hl_i64_from_double_saturating(12.7) == 12);
    CHECK(hl_ns_from_s(1.5, &r) == 0 && r == 1500000000);
    CHECK(hl_ns_from_s(-1e-9, &r) == 0 && r == -1);
    CHECK(hl_ns_from_s(9.3e9, &r) == -1); /* 295 years: past int64 ns */
    CHECK(hl_ns_from_s(NAN, &r) == -1);
    CHECK(hl_ns_from_s(-INFINITY, &r) == -1);
}

static char g_dir[64];

/* One buffer per name: the paths stay valid together. */
static const char *tmp_file(const char *name)
{
    static char bufs[8][128];
    static int next;
    char *buf = bufs[next++ % 8];
    snprintf(buf, sizeof bufs[0], "%s/%s", g_dir, name);
    return buf;
}

/* Non-regular files are refused at once (a FIFO without a writer would block a plain open), the
 * size limit holds for the default and the environment variable, and a missing file keeps ENOENT. */
static void test_files(void)
{
    snprintf(g_dir, sizeof g_dir, "/tmp/hmdlod_test_base_XXXXXX");
    if (!mkdtemp(g_dir)) {
        CHECK(!"mkdtemp");
        return;
    }
    struct hl_error err = {{0}};
    char *buf = NULL;
    size_t len = 0;

    const char *fifo = tmp_file("fifo");
    CHECK(mkfifo(fifo, 0600) == 0);
    int64_t t0 = hl_clock_now_ns();
    CHECK(hl_file_read_all(fifo, 0, &buf, &len, &err) == -1 && strstr(err.msg, "not a regular file (a FIFO)"));
    CHECK(hl_file_open_read(fifo, NULL, &err) == NULL && errno == EINVAL);
    CHECK(hl_clock_now_ns() - t0 < 1000000000LL); /* no wait for a writer */
    CHECK(hl_file_read_all("/dev/zero", 0, &buf, &len, &err) == -1 &&
          strstr(err.msg, "/dev/zero: not a regular file (a character device)"));
    CHECK(hl_file_read_all(g_dir, 0, &buf, &len, &err) == -1 && strstr(err.msg, "(a directory)"));
    CHECK(hl_file_read_all(tmp_file("absent"), 0, &buf, &len, &err) == -1 && errno == ENOENT &&
          strstr(err.msg, "cannot open"));

    const char *small = tmp_file("small");
    FILE *f = fopen(small, "wb");
    fputs("0123456789", f);
    fclose(f);
    CHECK(hl_file_read_all(small, 10, &buf, &len, &err) == 0 && len == 10 && buf[10] == '\0' &&
          memcmp(buf, "0123456789", 10) == 0);
    free(buf);
    CHECK(hl_file_read_all(small, 9, &buf, &len, &err) == -1 && buf == NULL &&
          strstr(err.msg, "10 bytes, more than the 9 bytes limit") && !strstr(err.msg, HL_FILE_MAX_BYTES_ENV));
    const char *empty = tmp_file("empty");
    fclose(fopen(empty, "wb"));
    CHECK(hl_file_read_all(empty, 0, &buf, &len, &err) == 0 && len == 0 && buf[0] == '\0');
    free(buf);

    /* The default limit: 1 GiB, the environment variable lowers or raises it, junk is ignored. */
    CHECK(hl_file_max_bytes() == HL_FILE_DEFAULT_MAX_BYTES || getenv(HL_FILE_MAX_BYTES_ENV));
    setenv(HL_FILE_MAX_BYTES_ENV, "5", 1);
    CHECK(hl_file_max_bytes() == 5);
    CHECK(hl_file_read_all(small, 0, &buf, &len, &err) == -1 && strstr(err.msg, "more than the 5 bytes limit") &&
          strstr(err.msg, "raise it with hmdlod --max-input-bytes N, or " HL_FILE_MAX_BYTES_ENV));
    setenv(HL_FILE_MAX_BYTES_ENV, "-5", 1);
    CHECK(hl_file_max_bytes() == HL_FILE_DEFAULT_MAX_BYTES);
    setenv(HL_FILE_MAX_BYTES_ENV, "12abc", 1);
    CHECK(hl_file_max_bytes() == HL_FILE_DEFAULT_MAX_BYTES);
    setenv(HL_FILE_MAX_BYTES_ENV, "0", 1);
    CHECK(hl_file_max_bytes() == HL_FILE_DEFAULT_MAX_BYTES);
    unsetenv(HL_FILE_MAX_BYTES_ENV);
    /* A sparse file of 2 GiB: refused from its size alone, nothing allocated or read. */
    const char *sparse = tmp_file("sparse");
    f = fopen(sparse, "wb");
    CHECK(f && ftruncate(fileno(f), (off_t)2 << 30) == 0);
    fclose(f);
    CHECK(hl_file_read_all(sparse, 0, &buf, &len, &err) == -1 && strstr(err.msg, "more than the 1 GiB limit"));

    remove(fifo), remove(small), remove(empty), remove(sparse);
    rmdir(g_dir);
}

int main(void)
{
    test_percentiles();
    test_angles();
    test_length();
    test_quaternions();
    test_error();
    test_checked_int64();
    test_files();
    return tu_finish("test_base");
}
