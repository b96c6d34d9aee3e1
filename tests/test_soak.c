/* The soak's pieces (bench/soak_internal.h) without a renderer: the mirrored looped trace source
 * (the wrap is seamless: the pose just before and just after each wrap agree; odd loops play the
 * trace backward with the velocity negated; the poses repeat every two spans), the fake tracker thread (reports at about 1 kHz, fusion finite, the IMU stream wraps), and the
 * option ranges. The whole run is tests/soak_smoke.sh. */
#define _DEFAULT_SOURCE /* mincore */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "bench/soak_internal.h"
#include "test_util.h"

/* The per-frame series are resident from the start: every page of a 24 MB series (an hour at
 * 800 Hz, large enough that malloc maps it fresh) is in core (mincore) right after the allocation,
 * before anything writes it, and holds NaN. malloc + memset(0), which the compiler may turn into
 * calloc, fails this on Linux: calloc leaves fresh mapped pages untouched. And the memory readings
 * are sane: resident parts below RSS, more than a few mappings, malloc in use positive. */
static void test_series_and_memory(void)
{
    long n = 3600L * 800;
    double *v = bch_soak_series_alloc(n);
    CHECK(v != NULL);
    if (v) {
        long page = sysconf(_SC_PAGESIZE);
        uintptr_t lo = (uintptr_t)v / (uintptr_t)page * (uintptr_t)page;
        size_t len = (size_t)((uintptr_t)(v + n) - lo), pages = (len + (size_t)page - 1) / (size_t)page;
        unsigned char *in_core = malloc(pages);
        CHECK(in_core && mincore((void *)lo, len, in_core) == 0);
        size_t resident = 0;
        for (size_t i = 0; in_core && i < pages; ++i)
            resident += in_core[i] & 1;
        printf("  series of %ld doubles: %zu of %zu pages resident before any write\n", n, resident, pages);
        CHECK(resident == pages);
        CHECK(isnan(v[0]) && isnan(v[n / 2]) && isnan(v[n - 1]));
        free(in_core);
        free(v);
    }
    CHECK(bch_soak_series_alloc(0) == NULL && bch_soak_series_alloc(-5) == NULL);
    struct bch_soak_memory m;
    bch_soak_memory_read(&m, 1);
    printf("  memory: rss %ld kB, heap map %ld, anon %ld, file %ld kB, %ld mappings, malloc in use %ld kB, fds %ld\n",
           m.rss_kib, m.heap_map_kib, m.anon_map_kib, m.file_map_kib, m.mappings, m.heap_in_use_kib, m.fds);
    CHECK(m.rss_kib > 0 && m.file_map_kib > 0 && m.mappings > 5 && m.fds >= 3);
    CHECK(m.heap_map_kib >= 0 && m.anon_map_kib >= 0);
    CHECK(m.heap_map_kib + m.anon_map_kib + m.file_map_kib <= m.rss_kib + 1024);
    bch_soak_memory_read(&m, 0);
    CHECK(m.rss_kib > 0 && m.mappings == -1 && m.heap_map_kib == -1);
}

/* Angle between two orientations, radians (atan2 of the relative quaternion's parts). */
static double angle_between(hl_quatd a, hl_quatd b)
{
    hl_quatd d = hl_q_mul(a, hl_q_conj(b));
    double s = sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    return 2.0 * atan2(s, fabs(d.w));
}

/* 3 s at 100 Hz: yaw at 30 deg/s with a pitch wobble, so the end differs from the start. */
static int make_trace(struct rpl_trace *t, struct hl_error *err)
{
    size_t cap = 64 + 301 * 96, len = 0;
    char *text = malloc(cap);
    if (!text)
        return -1;
    len += (size_t)snprintf(text + len, cap - len, "t_s,qw,qx,qy,qz\n");
    for (int i = 0; i <= 300; ++i) {
        double t_s = i * 0.01, yaw = 30.0 * HL_RAD_PER_DEG * t_s, pitch = 0.2 * sin(2.0 * t_s);
        hl_quatd q = hl_q_mul(hl_q_from_axis_angle(hl_v3(0, 1, 0), yaw), hl_q_from_axis_angle(hl_v3(1, 0, 0), pitch));
        len += (size_t)snprintf(text + len, cap - len, "%.3f,%.12f,%.12f,%.12f,%.12f\n", t_s, q.w, q.x, q.y, q.z);
    }
    int rc = rpl_trace_parse(text, len, "synthetic", t, err);
    free(text);
    return rc;
}

static void test_loop_source(void)
{
    struct rpl_trace trace;
    struct hl_error err;
    CHECK(make_trace(&trace, &err) == 0);
    hl_quatd q_start = trace.orientation[0], q_end = trace.orientation[trace.count - 1];
    struct trk_pose_source *src = NULL;
    const double t0 = 1000.0, span = 3.0;
    CHECK(bch_soak_source_create(&trace, t0, &src, &err) == 0);
    if (!src)
        return;
    CHECK(trace.count == 0); /* ownership moved */
    struct trk_pose a, b, c;
    /* before t0: held at the start */
    CHECK(trk_source_pose_at(src, t0 - 5.0, &a, &err) == 0);
    CHECK_NEAR(angle_between(a.orientation, q_start), 0.0, 1e-9);
    /* each wrap: 1 ms before and after are 1 ms of a 30 deg/s turn apart, not a jump */
    for (int k = 1; k <= 5; ++k) {
        double w = t0 + k * span;
        CHECK(trk_source_pose_at(src, w - 0.001, &a, &err) == 0);
        CHECK(trk_source_pose_at(src, w + 0.001, &b, &err) == 0);
        CHECK(angle_between(a.orientation, b.orientation) < 0.002 * 40.0 * HL_RAD_PER_DEG);
        CHECK(trk_source_pose_at(src, w, &c, &err) == 0);
        CHECK(c.time_s == w);
        /* an odd loop starts at the trace's end, going back */
        CHECK(isfinite(c.angular_velocity_radps.y) && (k % 2 ? -1.0 : 1.0) * c.angular_velocity_radps.y > 0.0);
    }
    /* the first wrap lands on the trace's last orientation */
    CHECK(trk_source_pose_at(src, t0 + span, &c, &err) == 0);
    CHECK_NEAR(angle_between(c.orientation, q_end), 0.0, 1e-6);
    /* loop 2 is loop 0 (the content's period is two spans); loop 1 is loop 0 backward */
    CHECK(bch_soak_source_period_s(src) == 2.0 * span);
    CHECK(trk_source_pose_at(src, t0 + 0.7, &a, &err) == 0);
    CHECK(trk_source_pose_at(src, t0 + 2.0 * span + 0.7, &b, &err) == 0);
    CHECK_NEAR(angle_between(b.orientation, a.orientation), 0.0, 1e-9);
    CHECK_NEAR(b.angular_velocity_radps.y, a.angular_velocity_radps.y, 1e-9);
    CHECK(trk_source_pose_at(src, t0 + span - 0.7, &a, &err) == 0);
    CHECK(trk_source_pose_at(src, t0 + span + 0.7, &b, &err) == 0);
    CHECK_NEAR(angle_between(b.orientation, a.orientation), 0.0, 1e-9);
    CHECK(a.angular_velocity_radps.y > 0.0);
    CHECK_NEAR(b.angular_velocity_radps.y, -a.angular_velocity_radps.y, 1e-9);
    CHECK(bch_soak_source_loops(src) == 5);
    /* after a day of loops (28800, even) the pose is loop 0's at the same instant, unit and finite */
    CHECK(trk_source_pose_at(src, t0 + 86400.0 + 0.25, &a, &err) == 0);
    CHECK(trk_source_pose_at(src, t0 + 0.25, &b, &err) == 0);
    CHECK_NEAR(angle_between(a.orientation, b.orientation), 0.0, 1e-6);
    CHECK_NEAR(sqrt(a.orientation.w * a.orientation.w + a.orientation.x * a.orientation.x +
                    a.orientation.y * a.orientation.y + a.orientation.z * a.orientation.z), 1.0, 1e-12);
    CHECK(trk_source_pose_at(src, NAN, &a, &err) == -1);
    CHECK(strstr(err.msg, "non-finite") != NULL);
    trk_source_destroy(src);
    /* a one-sample trace cannot loop */
    struct rpl_trace one;
    const char *text = "t_s,qw,qx,qy,qz\n0,1,0,0,0\n";
    CHECK(rpl_trace_parse(text, strlen(text), "one", &one, &err) == 0);
    CHECK(bch_soak_source_create(&one, 0.0, &src, &err) == -1 && src == NULL);
    rpl_trace_free(&one);
}

static void test_tracker(void)
{
    enum { N = 150 }; /* 150 ms of an upright, slowly turning IMU at 1 kHz: wraps twice in 0.4 s */
    struct trk_imu_csv_row rows[N];
    for (int i = 0; i < N; ++i) {
        memset(&rows[i], 0, sizeof rows[i]);
        rows[i].t_s = i * 0.001;
        rows[i].gyro_radps = hl_v3(0.0, 0.3, 0.0);
        rows[i].accel_mps2 = hl_v3(0.0, 9.81, 0.0);
        rows[i].truth = hl_q_from_axis_angle(hl_v3(0, 1, 0), 0.3 * rows[i].t_s);
    }
    struct bch_soak_tracker t;
    struct hl_error err;
    int64_t t0 = hl_clock_now_ns();
    CHECK(bch_soak_tracker_start(&t, rows, N, 0.4, &err) == 0);
    /* until 400 reports (the stream wraps twice), or 20 s on a machine that starves the thread */
    struct timespec ts = {0, 5000000};
    while ((atomic_load(&t.reports) < 400 || hl_clock_now_ns() - t0 < 600000000LL) &&
           hl_clock_now_ns() - t0 < 20000000000LL)
        nanosleep(&ts, NULL); /* and past the run's 0.4 s, so the last stretch (from 0.36 s) has reports */
    bch_soak_tracker_stop(&t);
    double elapsed_ms = (double)(hl_clock_now_ns() - t0) * 1e-6;
    uint64_t reports = atomic_load(&t.reports);
    CHECK(reports >= 400);
    CHECK((double)reports <= elapsed_ms + 2.0); /* paced by the clock: never faster than 1 kHz */
    double rates[2];
    bch_soak_tracker_rates(&t, rates);
    /* The first stretch starts with the clock, so it is paced; the last one may catch up after the thread
     * was starved (as a hidraw queue delivers after a stall), so only its whole-run bound holds. */
    CHECK(rates[0] > 0.0 && rates[0] <= 1100.0 && rates[1] > 0.0 && isfinite(rates[1]));
    CHECK(atomic_load(&t.rejected) == 0);
    CHECK(atomic_load(&t.nonfinite) == 0);
    CHECK(atomic_load(&t.refused) == 0);
    CHECK(atomic_load(&t.failed) == 0);
    CHECK(atomic_load(&t.loops) >= 1);
    bch_soak_tracker_stop(&t); /* twice: harmless */
    /* a stream whose rows do not advance is refused before a thread starts */
    rows[N - 1].t_s = 0.0;
    CHECK(bch_soak_tracker_start(&t, rows, N, 0.4, &err) == -1);
    CHECK(strstr(err.msg, "IMU stream") != NULL);
}

static void test_options(void)
{
    struct bch_soak_options o;
    struct hl_error err;
    bch_soak_options_defaults(&o);
    CHECK(o.duration_s == 3600.0 && o.sample_s == 10.0 && o.render_scale == 0.5);
    CHECK(bch_soak_check_options(&o, &err) == -1 && strstr(err.msg, "--out"));
    o.out_dir = "x";
    CHECK(bch_soak_check_options(&o, &err) == 0);
    o.duration_s = 0.5;
    CHECK(bch_soak_check_options(&o, &err) == -1 && strstr(err.msg, "--duration-s"));
    o.duration_s = INFINITY;
    CHECK(bch_soak_check_options(&o, &err) == -1 && strstr(err.msg, "--duration-s"));
    o.duration_s = 60.0, o.sample_s = 61.0;
    CHECK(bch_soak_check_options(&o, &err) == -1 && strstr(err.msg, "--sample-s"));
    o.sample_s = NAN;
    CHECK(bch_soak_check_options(&o, &err) == -1 && strstr(err.msg, "--sample-s"));
    o.sample_s = 1.0, o.render_scale = 0.0;
    CHECK(bch_soak_check_options(&o, &err) == -1 && strstr(err.msg, "--render-scale"));
}

int main(void)
{
    test_loop_source();
    test_tracker();
    test_options();
    test_series_and_memory();
    return tu_finish("soak");
}
