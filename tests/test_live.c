/* replay/'s live pieces that need no window: the pacer (slots, missed slots when a frame is late,
 * intervals) and the desk pose source (scripted yaw, mouse look, angular velocity in the world). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "replay/live_internal.h"
#include "test_util.h"

static void sleep_ms(double ms)
{
    struct timespec ts = {(time_t)(ms / 1000), (long)(fmod(ms, 1000.0) * 1e6)};
    nanosleep(&ts, NULL);
}

static void test_pacer(void)
{
    struct rpl_pacer p;
    int64_t now = hl_clock_now_ns();
    rpl_pacer_init(&p, 200.0, 1, now); /* 5 ms slots */
    CHECK(p.period_ns == 5000000);
    CHECK(rpl_pacer_due_ns(&p) == now + 5000000); /* the first frame one period ahead */
    /* On time: each present is at or after its slot, and the slots advance by one. */
    for (int k = 0; k < 5; ++k) {
        int64_t due = rpl_pacer_due_ns(&p);
        rpl_pacer_wait(&p);
        int64_t t = hl_clock_now_ns();
        CHECK(t >= due);
        double interval = rpl_pacer_presented(&p, t);
        CHECK(k == 0 ? interval == 0.0 : interval > 0.0);
        CHECK(rpl_pacer_due_ns(&p) == due + 5000000);
    }
    CHECK(p.missed == 0);
    /* Late by more than two slots: those slots are missed and the next frame is due after now. */
    sleep_ms(12.0);
    long slot = p.slot;
    rpl_pacer_wait(&p);
    CHECK(p.missed >= 2 && p.missed <= 4);
    CHECK(p.slot == slot + p.missed);
    rpl_pacer_presented(&p, hl_clock_now_ns());
    CHECK(rpl_pacer_due_ns(&p) > hl_clock_now_ns() - 1000000);
    /* Planned: a frame expected to take 12 ms from a slot 5 ms away aims two slots later. */
    rpl_pacer_init(&p, 200.0, 1, hl_clock_now_ns()); /* first slot 5 ms ahead */
    int64_t first = rpl_pacer_due_ns(&p);
    rpl_pacer_plan(&p, 12000000);
    CHECK(p.missed >= 2 && p.missed <= 3); /* 2 unless this thread stalled for milliseconds */
    CHECK(rpl_pacer_due_ns(&p) == first + p.missed * 5000000);
    long planned = p.missed;
    rpl_pacer_plan(&p, 0); /* now it fits: nothing changes */
    CHECK(p.missed == planned);
    /* Throttled (the swap waits): wait returns at once; a present two periods after the last counts one missed. */
    rpl_pacer_init(&p, 100.0, 0, 0);
    rpl_pacer_presented(&p, 1000000000);
    rpl_pacer_presented(&p, 1010000000);
    CHECK(p.missed == 0);
    rpl_pacer_presented(&p, 1030000000);
    CHECK(p.missed == 1);
    int64_t t0 = hl_clock_now_ns();
    rpl_pacer_wait(&p);
    CHECK(hl_clock_now_ns() - t0 < 1000000);
}

static void test_desk_source(void)
{
    struct trk_pose_source *src = NULL;
    struct hl_error err;
    CHECK(rpl_desk_source_create(10.0, 30.0, &src, &err) == 0);
    if (!src)
        return;
    struct trk_pose p;
    CHECK(trk_source_pose_at(src, 10.0, &p, &err) == 0);
    CHECK_NEAR(hl_q_angle_rad(p.orientation, hl_q_identity()), 0.0, 1e-12);
    CHECK(trk_source_pose_at(src, 13.0, &p, &err) == 0); /* 3 s at 30 deg/s: 90° about +Y */
    hl_vec3d f = hl_q_rotate(p.orientation, hl_v3(0, 0, -1));
    CHECK_NEAR(atan2(-f.x, -f.z) * HL_DEG_PER_RAD, 90.0, 1e-9);
    CHECK_NEAR(p.angular_velocity_radps.y * HL_DEG_PER_RAD, 30.0, 1e-9);
    /* A look step of 2° of pitch over 0.02 s: 100 deg/s about the yawed head's +X (world −Z at 90° yaw). */
    rpl_desk_source_look(src, 0.0, 2.0 * HL_RAD_PER_DEG, 0.02);
    CHECK(trk_source_pose_at(src, 13.0, &p, &err) == 0);
    CHECK_NEAR(p.angular_velocity_radps.z * HL_DEG_PER_RAD, -100.0, 1e-6);
    f = hl_q_rotate(p.orientation, hl_v3(0, 0, -1));
    CHECK_NEAR(asin(f.y) * HL_DEG_PER_RAD, 2.0, 1e-9); /* looking up */
    /* No motion the next frame: the look's velocity is gone. */
    rpl_desk_source_look(src, 0.0, 0.0, 0.02);
    CHECK(trk_source_pose_at(src, 13.0, &p, &err) == 0);
    CHECK_NEAR(hl_v3_length(hl_v3_sub(p.angular_velocity_radps, hl_v3(0, 30.0 * HL_RAD_PER_DEG, 0))), 0.0, 1e-12);
    CHECK(trk_source_pose_at(src, NAN, &p, &err) != 0);
    trk_source_destroy(src);
    struct trk_pose_source *bad = NULL;
    CHECK(rpl_desk_source_create(0.0, NAN, &bad, &err) != 0 && bad == NULL);
}

/* The summary's statistics: population stddev, median, nearest-rank p99, max. */
static void test_series(void)
{
    struct rpl_live_series s = {0};
    int pushed = 0;
    for (int i = 1; i <= 1500; ++i) /* 1500 … 1: past the first capacity (1024), so it grows */
        pushed += rpl_live_series_push(&s, (double)(1501 - i)) == 0;
    CHECK(pushed == 1500);
    double mean, sd, median, p99, max;
    rpl_live_series_stats(&s, &mean, &sd, &median, &p99, &max);
    CHECK_NEAR(mean, 750.5, 1e-9);
    CHECK_NEAR(sd, sqrt((1500.0 * 1500.0 - 1.0) / 12.0), 1e-9); /* uniform 1..n: variance (n²−1)/12 */
    CHECK_NEAR(median, 750.5, 1e-12);
    CHECK_NEAR(p99, 1485.0, 1e-12); /* ceil(0.99·1500) = the 1485th smallest */
    CHECK_NEAR(max, 1500.0, 1e-12);
    free(s.v);

    /* A session stopped before its first frame: an empty series (no array at all) gives zeros, and
     * never hands qsort a NULL pointer (UBSan: nonnull argument). */
    struct rpl_live_series empty = {0};
    mean = sd = median = p99 = max = -1;
    rpl_live_series_stats(&empty, &mean, &sd, &median, &p99, &max);
    CHECK(mean == 0 && sd == 0 && median == 0 && p99 == 0 && max == 0);
}

int main(void)
{
    test_series();
    test_pacer();
    test_desk_source();
    return tu_finish("live");
}
