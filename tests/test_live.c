/* live/'s pieces that need no window: the pacer (slots, missed slots when a frame is late,
 * intervals) and the desk pose source (scripted yaw, mouse look, angular velocity in the world). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "live/live.h"
#include "test_util.h"

/* The pacer's slot arithmetic on a clock that advances 0.1 ms each time it is read, so no check
 * depends on how fast this machine is or how loaded (a real 5 ms slot missed under load once made
 * the exact-slot checks fail). wait's relative sleep on an injected clock is a real one of the
 * remaining time, and its final spin ends because every read moves this clock on. */
static int64_t stepping_ns;
static long stepping_reads;
static int64_t stepping_clock_ns(void)
{
    stepping_reads++;
    return stepping_ns += 100000;
}

static void test_pacer(void)
{
    struct liv_pacer p;
    stepping_ns = 1000000000;
    liv_pacer_init(&p, 200.0, 1, stepping_ns); /* 5 ms slots */
    p.clock_ns = stepping_clock_ns;
    p.trim = NULL;
    CHECK(p.period_ns == 5000000);
    CHECK(liv_pacer_due_ns(&p) == 1000000000 + 5000000); /* the first frame one period ahead */
    /* On time: each present is at or after its slot, and the slots advance by one. */
    for (int k = 0; k < 5; ++k) {
        int64_t due = liv_pacer_due_ns(&p);
        liv_pacer_wait(&p);
        int64_t t = stepping_clock_ns();
        CHECK(t >= due && t - due < 1000000); /* the spin ends within a few reads of the slot */
        double interval = liv_pacer_presented(&p, t);
        CHECK(k == 0 ? interval == 0.0 : interval > 0.0);
        CHECK(liv_pacer_due_ns(&p) == due + 5000000);
    }
    CHECK(p.missed == 0);
    /* Late by more than two slots: those slots are missed and the next frame is due after now. */
    stepping_ns += 12000000;
    long slot = p.slot;
    liv_pacer_wait(&p);
    CHECK(p.missed >= 2 && p.missed <= 3);
    CHECK(p.slot == slot + p.missed);
    liv_pacer_presented(&p, stepping_clock_ns());
    CHECK(liv_pacer_due_ns(&p) > stepping_ns);
    /* Planned: a frame expected to take 12 ms from a slot 5 ms away aims two slots later. */
    liv_pacer_init(&p, 200.0, 1, stepping_ns); /* first slot 5 ms ahead */
    p.clock_ns = stepping_clock_ns;
    p.trim = NULL;
    int64_t first = liv_pacer_due_ns(&p);
    liv_pacer_plan(&p, 12000000);
    CHECK(p.missed == 2); /* ready 12.1 ms after now, 7.1 ms past the slot: two slots skipped */
    CHECK(liv_pacer_due_ns(&p) == first + p.missed * 5000000);
    long planned = p.missed;
    liv_pacer_plan(&p, 0); /* now it fits: nothing changes */
    CHECK(p.missed == planned);
    /* Throttled (the swap waits): wait returns at once without reading the clock or sleeping; a
     * present two periods after the last counts one missed. */
    liv_pacer_init(&p, 100.0, 0, 0);
    p.clock_ns = stepping_clock_ns;
    liv_pacer_presented(&p, 1000000000);
    liv_pacer_presented(&p, 1010000000);
    CHECK(p.missed == 0);
    liv_pacer_presented(&p, 1030000000);
    CHECK(p.missed == 1);
    long reads = stepping_reads, slot_before = p.slot;
    liv_pacer_wait(&p);
    CHECK(stepping_reads == reads && p.slot == slot_before && p.missed == 1);
}

static void test_desk_source(void)
{
    struct trk_pose_source *src = NULL;
    struct hl_error err;
    CHECK(liv_desk_source_create(10.0, 30.0, &src, &err) == 0);
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
    liv_desk_source_look(src, 0.0, 2.0 * HL_RAD_PER_DEG, 0.02);
    CHECK(trk_source_pose_at(src, 13.0, &p, &err) == 0);
    CHECK_NEAR(p.angular_velocity_radps.z * HL_DEG_PER_RAD, -100.0, 1e-6);
    f = hl_q_rotate(p.orientation, hl_v3(0, 0, -1));
    CHECK_NEAR(asin(f.y) * HL_DEG_PER_RAD, 2.0, 1e-9); /* looking up */
    /* No motion the next frame: the look's velocity is gone. */
    liv_desk_source_look(src, 0.0, 0.0, 0.02);
    CHECK(trk_source_pose_at(src, 13.0, &p, &err) == 0);
    CHECK_NEAR(hl_v3_length(hl_v3_sub(p.angular_velocity_radps, hl_v3(0, 30.0 * HL_RAD_PER_DEG, 0))), 0.0, 1e-12);
    CHECK(trk_source_pose_at(src, NAN, &p, &err) != 0);
    trk_source_destroy(src);
    struct trk_pose_source *bad = NULL;
    CHECK(liv_desk_source_create(0.0, NAN, &bad, &err) != 0 && bad == NULL);
}

/* The summary's statistics: population stddev, median, nearest-rank p99, max. */
static void test_series(void)
{
    struct liv_series s = {0};
    int pushed = 0;
    for (int i = 1; i <= 1500; ++i) /* 1500 … 1, exact: sorted for the statistics */
        pushed += liv_series_push(&s, (double)(1501 - i)) == 0;
    CHECK(pushed == 1500);
    double mean, sd, median, p99, max;
    liv_series_stats(&s, &mean, &sd, &median, &p99, &max);
    CHECK_NEAR(mean, 750.5, 1e-9);
    CHECK_NEAR(sd, sqrt((1500.0 * 1500.0 - 1.0) / 12.0), 1e-9); /* uniform 1..n: variance (n²−1)/12 */
    CHECK_NEAR(median, 750.5, 1e-12);
    CHECK_NEAR(p99, 1485.0, 1e-12); /* ceil(0.99·1500) = the 1485th smallest */
    CHECK_NEAR(max, 1500.0, 1e-12);
    liv_series_free(&s);

    /* A session stopped before its first frame: an empty series (no array at all) gives zeros, and
     * never hands a sort a NULL pointer (UBSan: nonnull argument). */
    struct liv_series empty = {0};
    mean = sd = median = p99 = max = -1;
    liv_series_stats(&empty, &mean, &sd, &median, &p99, &max);
    CHECK(mean == 0 && sd == 0 && median == 0 && p99 == 0 && max == 0);
}

/* An hours-long session: past LIV_SERIES_EXACT values the series folds into bins, its memory
 * stays what it was, mean, stddev and max stay exact and median and p99 come within 0.1 %. */
static void test_series_long(void)
{
    struct liv_series s = {0};
    const long n = 3 * LIV_SERIES_EXACT + 7; /* about 36 min at 90 Hz */
    int ok = 1;
    double *exact_v = NULL;
    uint32_t *bins = NULL;
    for (long i = 0; i < n; ++i) {
        ok &= liv_series_push(&s, 1.0 + (double)(i % 1000) * 0.02) == 0; /* 1 … 20.98 ms */
        if (i == LIV_SERIES_EXACT)
            exact_v = s.v, bins = s.bins;
    }
    CHECK(ok && s.n == n && bins != NULL && s.v == exact_v && s.bins == bins);
    double sum = 0, sq = 0, mean, sd, median, p99, max;
    for (long i = 0; i < n; ++i)
        sum += 1.0 + (double)(i % 1000) * 0.02;
    double m = sum / (double)n;
    for (long i = 0; i < n; ++i) {
        double d = 1.0 + (double)(i % 1000) * 0.02 - m;
        sq += d * d;
    }
    liv_series_stats(&s, &mean, &sd, &median, &p99, &max);
    CHECK_NEAR(mean, m, 1e-9 * m);
    CHECK_NEAR(sd, sqrt(sq / (double)n), 1e-9);
    CHECK_NEAR(max, 20.98, 1e-12);
    /* Exact order statistics: the values are 1 + 0.02·j, j = 0 … 999, nearly uniformly repeated. */
    double *all = malloc((size_t)n * sizeof *all);
    CHECK(all != NULL);
    if (all) {
        for (long i = 0; i < n; ++i)
            all[i] = 1.0 + (double)(i % 1000) * 0.02;
        hl_sort_doubles(all, (size_t)n);
        double exact_median = n % 2 ? all[n / 2] : 0.5 * (all[n / 2 - 1] + all[n / 2]);
        double exact_p99 = all[(long)ceil(0.99 * (double)n) - 1];
        CHECK_NEAR(median, exact_median, 1e-3 * exact_median);
        CHECK_NEAR(p99, exact_p99, 1e-3 * exact_p99);
        free(all);
    }
    liv_series_free(&s);
    CHECK(s.v == NULL && s.bins == NULL && s.n == 0);
}

/* An injected clock (liv_pacer.clock_ns) that jumps: the monotonic one plus an offset. */
static int64_t clock_offset_ns;
static int64_t jumping_clock_ns(void) { return hl_clock_now_ns() + clock_offset_ns; }

/* One self-paced frame: plan, wait, present. Returns the present interval; *wait_ms the real time
 * wait took. */
static double paced_frame(struct liv_pacer *p, double *wait_ms)
{
    liv_pacer_plan(p, 0);
    int64_t t0 = hl_clock_now_ns();
    liv_pacer_wait(p);
    *wait_ms = (double)(hl_clock_now_ns() - t0) * 1e-6;
    return liv_pacer_presented(p, p->clock_ns());
}

/* The idle heap trim (live_pace.c) on a hand-driven clock: 35 s of 100 Hz frames that leave 8 ms of
 * slack trim at 10, 20 and 30 s (the trim's own 1 ms counted); frames with 3 ms of slack (< 4 ms)
 * never trim; a trim never makes a frame miss its slot. */
static int64_t manual_ns;
static long manual_trims;
static int64_t manual_clock_ns(void) { return manual_ns; }
static void manual_trim(void)
{
    manual_trims++;
    manual_ns += 1000000;
}

static void test_pacer_trim(void)
{
    const int64_t work_ns[2] = {2000000, 7000000};
    const long want_trims[2] = {3, 0};
    for (int run = 0; run < 2; ++run) {
        struct liv_pacer p;
        manual_ns = 0, manual_trims = 0;
        liv_pacer_init(&p, 100.0, 1, 0);
        p.clock_ns = manual_clock_ns;
        p.trim = manual_trim;
        while (manual_ns < 35000000000LL) {
            liv_pacer_plan(&p, work_ns[run]);
            manual_ns += work_ns[run];
            CHECK(manual_ns <= liv_pacer_due_ns(&p));
            manual_ns = liv_pacer_due_ns(&p); /* the sleep until the slot */
            liv_pacer_presented(&p, manual_ns);
        }
        CHECK(p.trims == want_trims[run] && manual_trims == want_trims[run]);
        CHECK(p.missed == 0);
        CHECK(p.trim_max_ns == (want_trims[run] ? 1000000 : 0));
    }
    /* After the clock went back an hour, the next trim is 10 s of the new clock later, not an hour. */
    struct liv_pacer p;
    manual_ns = 3600000000000LL, manual_trims = 0;
    liv_pacer_init(&p, 100.0, 0, manual_ns);
    p.clock_ns = manual_clock_ns;
    p.trim = manual_trim;
    manual_ns = 0;
    liv_pacer_plan(&p, 0);
    manual_ns = 10000000000LL;
    p.t0_ns = manual_ns + 10000000 - p.slot * p.period_ns; /* the display's phase, as presented() keeps it */
    liv_pacer_plan(&p, 0);
    CHECK(manual_trims == 1);
}

/* The pacer's clock jumping ±1 h (docs/HARD_CASES.md "Faults"): no hang (a backward jump must not
 * become an hour's sleep), no interval of ±1 h in the statistics, slots and display times finite
 * and increasing again from the next frame, the jump counted. */
static void test_pacer_clock_jumps(void)
{
    const int64_t hour_ns = 3600LL * 1000000000LL;
    struct liv_pacer p;
    clock_offset_ns = 0;
    liv_pacer_init(&p, 200.0, 1, jumping_clock_ns()); /* 5 ms slots */
    p.clock_ns = jumping_clock_ns;
    double wait_ms, iv;
    for (int i = 0; i < 5; ++i)
        paced_frame(&p, &wait_ms);
    CHECK(p.clock_jumps == 0);
    long missed0 = p.missed;

    clock_offset_ns -= hour_ns; /* backward */
    iv = paced_frame(&p, &wait_ms);
    CHECK(wait_ms < 1000.0); /* not an hour (nor a second, even on a loaded machine) */
    CHECK(iv == 0.0);
    CHECK(p.clock_jumps == 1);
    CHECK(p.missed == missed0);
    int64_t due = liv_pacer_due_ns(&p);
    /* Re-anchored to the jumped clock: within a second of it (an hour off before), whatever the
     * machine's load did to this thread since. */
    CHECK(llabs(due - jumping_clock_ns()) < LIV_PACER_JUMP_NS);
    int ok = 1;
    for (int i = 0; i < 5; ++i) {
        int64_t before = liv_pacer_due_ns(&p);
        iv = paced_frame(&p, &wait_ms);
        ok &= iv > 0 && iv < LIV_PACER_JUMP_NS * 1e-6 && liv_pacer_due_ns(&p) > before;
    }
    CHECK(ok);
    printf("pacer, clock 1 h back: wait %.2f ms, jumps %ld, intervals after it %.2f ms\n", wait_ms, p.clock_jumps, iv);

    clock_offset_ns += 2 * hour_ns; /* forward, 1 h past where it was */
    long missed1 = p.missed;
    iv = paced_frame(&p, &wait_ms);
    CHECK(wait_ms < 1000.0); /* not an hour (nor a second, even on a loaded machine) */
    CHECK(iv == 0.0);
    CHECK(p.clock_jumps == 2);
    /* Two hours of slots (the schedule was re-anchored an hour back) passed without a frame: missed,
     * as a stall would have them (finite). */
    CHECK(labs(p.missed - missed1 - 2 * 3600L * 200) <= 200); /* ± a second of slots for a loaded machine */
    ok = 1;
    for (int i = 0; i < 5; ++i) {
        int64_t before = liv_pacer_due_ns(&p);
        iv = paced_frame(&p, &wait_ms);
        ok &= iv > 0 && iv < LIV_PACER_JUMP_NS * 1e-6 && liv_pacer_due_ns(&p) > before;
    }
    CHECK(ok);
    printf("pacer, clock 1 h forward: %ld slots missed, jumps %ld, intervals after it %.2f ms\n", p.missed - missed1,
           p.clock_jumps, iv);

    /* Throttled by the display: the swap's return times jump. */
    liv_pacer_init(&p, 100.0, 0, 0);
    CHECK(liv_pacer_presented(&p, 2 * hour_ns) == 0.0);
    CHECK_NEAR(liv_pacer_presented(&p, 2 * hour_ns + 10000000), 10.0, 1e-9);
    CHECK(liv_pacer_presented(&p, hour_ns) == 0.0);
    CHECK(p.clock_jumps == 1);
    CHECK_NEAR(liv_pacer_presented(&p, hour_ns + 10000000), 10.0, 1e-9);
    CHECK(liv_pacer_presented(&p, 3 * hour_ns) == 0.0);
    CHECK(p.clock_jumps == 2 && p.missed == 0);
    CHECK(liv_pacer_due_ns(&p) > 3 * hour_ns && liv_pacer_due_ns(&p) <= 3 * hour_ns + 10000000);
}

/* The head trace stays a valid trace when the pose times jump back: rows that do not move forward
 * are dropped and counted, never written out of order. */
static void test_record_order(void)
{
    char dir[] = "/tmp/hmdlod-live-record-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    char path[256];
    snprintf(path, sizeof path, "%s/head.csv", dir);
    struct liv_record r;
    struct hl_error err;
    CHECK(liv_record_open(&r, path, "t_s,qw,qx,qy,qz\n", &err) == 0);
    const double times[] = {5000.0, 5000.1, 5000.1 - 3600.0, 5000.1, 5000.2, 8600.2};
    for (size_t i = 0; i < sizeof times / sizeof times[0]; ++i) {
        struct trk_pose pose;
        trk_pose_init_still(&pose, times[i]);
        liv_record_row(&r, &pose);
    }
    CHECK(r.rows == 4 && r.dropped_rows == 2);
    CHECK(liv_record_commit(&r, &err) == 0);
    size_t size = 0;
    char *text = tu_read_file(path, &size);
    CHECK(text != NULL);
    if (text) {
        double last = -1.0, t;
        int rows = 0, ordered = 1;
        for (char *line = strchr(text, '\n'); line && line[1]; line = strchr(line + 1, '\n')) {
            if (sscanf(line + 1, "%lf,", &t) == 1) {
                ordered &= t > last;
                last = t;
                ++rows;
            }
        }
        CHECK(rows == 4 && ordered);
        CHECK_NEAR(last, 3600.2, 1e-6);
        free(text);
    }
    remove(path);
    rmdir(dir);
}

int main(void)
{
    test_pacer_clock_jumps();
    test_record_order();
    test_series();
    test_series_long();
    test_pacer();
    test_pacer_trim();
    test_desk_source();
    return tu_finish("live");
}
