/* The soak's fake tracker (bench/soak_internal.h): a thread that streams a looped 1 kHz IMU file as
 * DK2 reports into trk_stream at the wall clock's pace. Not through hidapi/umockdev: a umockdev
 * script replays a recorded ioctl/read log at its own timing and is meant for seconds, not an hour
 * of 1 kHz reads; the bytes here take the path after the read (parser, stream, fusion), which is
 * where a live session's per-report state lives. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "bench/soak_internal.h"

static void sleep_until_ns(int64_t t_ns)
{
    struct timespec ts = {(time_t)(t_ns / 1000000000), (long)(t_ns % 1000000000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR) {
    }
}

static int pose_finite(const struct trk_pose *p)
{
    return isfinite(p->orientation.w) && isfinite(p->orientation.x) && isfinite(p->orientation.y) &&
           isfinite(p->orientation.z) && isfinite(p->angular_velocity_radps.x) &&
           isfinite(p->angular_velocity_radps.y) && isfinite(p->angular_velocity_radps.z);
}

static void *tracker_main(void *arg)
{
    struct bch_soak_tracker *t = arg;
    struct trk_stream stream;  /* ~1 KB of plain data: on this thread's stack, touched by no one else */
    struct trk_encoder enc;
    trk_stream_init(&stream, TRK_DEVICE_RIFT_DK2, NULL);
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    /* A fixed Earth field (0.5 gauss, 60° dip, heading north) read through the true orientation:
     * the DK2 reports a magnetometer, and the fusion's heading correction runs on it (DEVICES.md §2b). */
    const double dip = 60.0 * HL_RAD_PER_DEG;
    const hl_vec3d field = hl_v3(0.0, -0.5 * sin(dip), -0.5 * cos(dip));
    int64_t t0 = hl_clock_now_ns();
    uint8_t report[64];
    struct hl_error err;
    for (uint64_t k = 0; !atomic_load(&t->stop); ++k) {
        int64_t due = t0 + (int64_t)k * t->period_ns;
        if (hl_clock_now_ns() < due)
            sleep_until_ns(due);
        size_t i = (size_t)(k % t->n);
        if (i == 0 && k > 0)
            atomic_fetch_add(&t->loops, 1);
        const struct trk_imu_csv_row *row = &t->rows[i];
        struct trk_imu_sample s;
        memset(&s, 0, sizeof s);
        s.device_time_ns = (int64_t)k * t->period_ns; /* continuous across loops */
        s.gyro_radps = row->gyro_radps;
        s.accel_mps2 = row->accel_mps2;
        s.orientation = hl_q(1, 0, 0, 0);
        s.mag_gauss = hl_q_rotate(hl_q_conj(row->truth), field);
        s.has_gyro = s.has_accel = s.has_mag = 1;
        int len = trk_encoder_push(&enc, &s, report, sizeof report, &err);
        if (len < 0) {
            snprintf(t->error, sizeof t->error, "soak tracker: %s", err.msg);
            atomic_store(&t->failed, 1);
            break;
        }
        if (len == 0)
            continue;
        if (trk_stream_feed(&stream, report, (size_t)len, hl_clock_now_ns(), &err) < 0)
            atomic_fetch_add(&t->rejected, 1);
        struct trk_pose pose;
        trk_stream_pose(&stream, 0.0, &pose);
        if (!pose_finite(&pose))
            atomic_fetch_add(&t->nonfinite, 1);
        atomic_store(&t->refused, stream.fusion_refused);
        uint64_t done = atomic_fetch_add(&t->reports, 1) + 1;
        int64_t since = hl_clock_now_ns() - t0;
        for (int m = 0; m < 2; ++m)
            if (atomic_load(&t->mark_ns[m]) == 0 && since >= t->mark_after_ns[m]) {
                atomic_store(&t->mark_reports[m], done);
                atomic_store(&t->mark_ns[m], since);
            }
        atomic_store(&t->stop_ns, since);
    }
    return NULL;
}

int bch_soak_tracker_start(struct bch_soak_tracker *t, const struct trk_imu_csv_row *rows, size_t n,
                           double duration_s, struct hl_error *err)
{
    memset(t, 0, sizeof *t);
    if (n < 2 || !(rows[n - 1].t_s > rows[0].t_s))
        return hl_fail(err, "soak: the IMU stream needs at least two rows spanning some time");
    t->rows = rows;
    t->n = n;
    /* the stream's own rate (1 kHz for the shared files), rounded to whole ns */
    t->period_ns = (int64_t)llround((rows[n - 1].t_s - rows[0].t_s) / (double)(n - 1) * 1e9);
    if (t->period_ns < 100000 || t->period_ns > 100000000)
        return hl_fail(err, "soak: the IMU stream's step (%lld ns) is outside 0.1 … 100 ms", (long long)t->period_ns);
    atomic_init(&t->stop, 0);
    atomic_init(&t->failed, 0);
    atomic_init(&t->reports, 0);
    atomic_init(&t->rejected, 0);
    atomic_init(&t->nonfinite, 0);
    atomic_init(&t->refused, 0);
    atomic_init(&t->loops, 0);
    int64_t duration_ns = (int64_t)llround(duration_s * 1e9); /* ≤ 7 days: fits */
    t->mark_after_ns[0] = duration_ns / 10 > 1 ? duration_ns / 10 : 1;
    t->mark_after_ns[1] = duration_ns - duration_ns / 10 > 1 ? duration_ns - duration_ns / 10 : 1;
    for (int m = 0; m < 2; ++m) {
        atomic_init(&t->mark_reports[m], 0);
        atomic_init(&t->mark_ns[m], 0);
    }
    atomic_init(&t->stop_ns, 0);
    int rc = pthread_create(&t->thread, NULL, tracker_main, t);
    if (rc != 0)
        return hl_fail(err, "soak: cannot start the tracker thread: %s", strerror(rc));
    t->started = 1;
    return 0;
}

void bch_soak_tracker_stop(struct bch_soak_tracker *t)
{
    if (!t->started)
        return;
    atomic_store(&t->stop, 1);
    pthread_join(t->thread, NULL);
    t->started = 0;
}

void bch_soak_tracker_rates(const struct bch_soak_tracker *t, double out[2])
{
    int64_t m0 = atomic_load(&t->mark_ns[0]), m1 = atomic_load(&t->mark_ns[1]), end = atomic_load(&t->stop_ns);
    uint64_t r0 = atomic_load(&t->mark_reports[0]), r1 = atomic_load(&t->mark_reports[1]);
    uint64_t total = atomic_load(&t->reports);
    out[0] = m0 > 0 ? (double)r0 / ((double)m0 * 1e-9) : NAN;
    out[1] = m1 > 0 && end > m1 ? (double)(total - r1) / ((double)(end - m1) * 1e-9) : NAN;
}
