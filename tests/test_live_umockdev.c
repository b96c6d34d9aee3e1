/* A scripted live session whose tracker is the fake Rift DK2 of test_hid_umockdev (umockdev, PLATFORM.md
 * §6), in an Xvfb window: run as `with_xvfb.sh umockdev-wrapper test_live_umockdev` (ctest does). A
 * feeder thread streams DK2 reports at a constant yaw rate, unplugs the DK2 midway (remove uevent,
 * hung-up node), replugs it as hidraw1 and streams again, then stops the session with SIGINT. Checked:
 * the session used the tracker, saw one loss and one resumption, held the pose while unplugged (the
 * head trace's yaw does not move then), turned while streaming, rendered frames, and its capture and
 * head trace are complete. The feeder moves on when the session's head trace (rows flushed per
 * frame into the temporary beside head.csv) shows what the checks need — turning, then the pose held
 * for a second of trace time, then turning again — not after fixed times a loaded machine can
 * overrun; each wait is bounded (120 s × HMDLOD_TEST_TIME_SCALE). */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <umockdev.h>

#include "live/live.h"
#include "tests/test_util.h"
#include "tracking/tracking.h"

#define SYS_USB "/sys/devices/pci0000:00/0000:00:14.0/usb1/1-1"
#define SYS_INTF SYS_USB "/1-1:1.0"
#define YAW_RATE_DEG_S 90.0

static UMockdevTestbed *tb;
static char data_dir[1024];
static char trace_dir[256]; /* where the session writes head.csv */
static volatile int feeder_failed, session_done;
static double unplug_s, replug_s; /* monotonic, when the feeder did them */

static void sleep_ms(int ms)
{
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

static const char *data_path(const char *name)
{
    static char path[1200];
    snprintf(path, sizeof path, "%s/%s", data_dir, name);
    return path;
}

static int add_device(const char *file, const char *node)
{
    GError *gerr = NULL;
    if (!umockdev_testbed_load_ioctl(tb, node, data_path("dk2.ioctl"), &gerr) ||
        !umockdev_testbed_add_from_file(tb, data_path(file), &gerr)) {
        fprintf(stderr, "umockdev: %s: %s\n", file, gerr ? gerr->message : "?");
        g_clear_error(&gerr);
        return -1;
    }
    return 0;
}

static void clean_ptymap(void)
{
    char dir[1200];
    gchar *root = umockdev_testbed_get_root_dir(tb);
    snprintf(dir, sizeof dir, "%s/dev/.ptymap", root);
    g_free(root);
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        char p[1500];
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        unlink(p);
    }
    closedir(d);
}

static double yaw_deg(double qw, double qx, double qy, double qz)
{
    hl_vec3d f = hl_q_rotate(hl_q(qw, qx, qy, qz), hl_v3(0, 0, -1));
    return atan2(-f.x, -f.z) * HL_DEG_PER_RAD;
}

/* What the checks read from a head trace. Before the first report the pose is still; after the
 * first turn, the longest run of equal yaws is the unplugged stretch (its length in the trace's time:
 * frames may miss slots on a loaded machine), and turning must come back after it. */
struct trace_stats {
    long rows, moving_rows, moving_after_longest;
    double longest_s;
    int header_ok;
};

/* The stats of the head trace at path (whole lines only: the session may be writing it). */
static void trace_stats_read(const char *path, struct trace_stats *st)
{
    memset(st, 0, sizeof *st);
    FILE *f = fopen(path, "r");
    char line[256];
    if (!f)
        return;
    double prev_yaw = 0, prev_t = 0, run_start_s = -1;
    if (fgets(line, sizeof line, f)) {
        st->header_ok = strcmp(line, "t_s,qw,qx,qy,qz\n") == 0;
        while (fgets(line, sizeof line, f) && strchr(line, '\n')) {
            double t, qw, qx, qy, qz;
            if (sscanf(line, "%lf,%lf,%lf,%lf,%lf", &t, &qw, &qx, &qy, &qz) != 5)
                break;
            double yaw = yaw_deg(qw, qx, qy, qz);
            if (st->rows > 0) {
                double d = fabs(yaw - prev_yaw);
                d = d > 180 ? 360 - d : d;
                if (d > 0.5) {
                    st->moving_rows++, st->moving_after_longest++;
                    run_start_s = -1;
                } else if (d == 0.0 && st->moving_rows > 0) {
                    if (run_start_s < 0)
                        run_start_s = prev_t;
                    if (t - run_start_s > st->longest_s) {
                        st->longest_s = t - run_start_s;
                        st->moving_after_longest = 0;
                    }
                }
            }
            prev_yaw = yaw;
            prev_t = t;
            st->rows++;
        }
    }
    fclose(f);
}

/* The stats of the head trace the session is writing (its temporary beside head.csv). */
static void live_trace_stats(struct trace_stats *st)
{
    memset(st, 0, sizeof *st);
    DIR *d = opendir(trace_dir);
    struct dirent *e;
    char path[600] = "";
    while (d && (e = readdir(d)) != NULL)
        if (strncmp(e->d_name, "head.csv.tmp.", 13) == 0)
            snprintf(path, sizeof path, "%s/%s", trace_dir, e->d_name);
    if (d)
        closedir(d);
    if (path[0])
        trace_stats_read(path, st);
}

/* Streams for `ms` of wall time: 10 reports (1 ms of device time each) every 10 ms. */
static int stream(int master, struct trk_encoder *enc, int64_t *device_ns, int ms)
{
    for (int t = 0; t < ms; t += 10) {
        for (int i = 0; i < 10; ++i) {
            struct trk_imu_sample smp;
            memset(&smp, 0, sizeof smp);
            smp.device_time_ns = *device_ns;
            smp.gyro_radps = hl_v3(0, YAW_RATE_DEG_S * HL_RAD_PER_DEG, 0);
            smp.accel_mps2 = hl_v3(0, 9.80665, 0);
            smp.orientation = hl_q_identity();
            smp.has_gyro = smp.has_accel = 1;
            *device_ns += 1000000;
            uint8_t report[64];
            struct hl_error err;
            int n = trk_encoder_push(enc, &smp, report, sizeof report, &err);
            if (n < 0 || (n > 0 && write(master, report, (size_t)n) != n))
                return -1;
        }
        sleep_ms(10);
    }
    return 0;
}

/* What the feeder waits for in the session's head trace. */
enum until { UNTIL_ROWS, UNTIL_TURNED, UNTIL_HELD, UNTIL_TURNED_AGAIN };
static int reached(enum until u)
{
    struct trace_stats st;
    live_trace_stats(&st);
    switch (u) {
    case UNTIL_ROWS: /* the session runs: its tracker opened before the first frame */
        return st.rows >= 1;
    case UNTIL_TURNED:
        return st.moving_rows >= 20; /* with the rest, at least the 30 frames the checks want */
    case UNTIL_HELD: /* the checks want 0.8 s */
        return st.longest_s >= 1.0;
    case UNTIL_TURNED_AGAIN:
        return st.moving_after_longest >= 10;
    }
    return 0;
}
static const char *const until_names[] = {"a first row", "20 turning rows", "the pose held for 1 s",
                                          "10 turning rows after the held pose"};

/* Streams to `master` (when >= 0; else waits) until the session's trace shows `u`, within the bound. */
static int stream_until(int master, struct trk_encoder *enc, int64_t *device_ns, enum until u)
{
    double until = hl_clock_now_s() + 120.0 * tu_time_scale();
    while (!reached(u)) {
        if (hl_clock_now_s() > until) {
            fprintf(stderr, "feeder: the head trace did not show %s within %.0f s\n", until_names[u],
                    120.0 * tu_time_scale());
            return -1;
        }
        if (master < 0)
            sleep_ms(50);
        else if (stream(master, enc, device_ns, 50) != 0)
            return -1;
    }
    return 0;
}

static void *feeder(void *arg)
{
    (void)arg;
    int master = umockdev_testbed_get_dev_fd(tb, "/dev/hidraw0");
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t device_ns = 5000000000LL;
    if (master < 0 || stream_until(-1, NULL, NULL, UNTIL_ROWS) != 0 ||
        stream_until(master, &enc, &device_ns, UNTIL_TURNED) != 0)
        goto fail;
    /* Unplug as test_hid_umockdev does it (PLATFORM.md §6 steps 3–4). */
    unplug_s = hl_clock_now_s();
    umockdev_testbed_uevent(tb, SYS_INTF "/0003:2833:0021.0001/hidraw/hidraw0", "remove");
    int devnull = open("/dev/null", O_RDWR | O_CLOEXEC);
    if (devnull < 0 || dup2(devnull, master) != master)
        goto fail;
    close(devnull);
    umockdev_testbed_remove_device(tb, SYS_INTF "/0003:2833:0021.0001/hidraw/hidraw0");
    umockdev_testbed_remove_device(tb, SYS_INTF "/0003:2833:0021.0001");
    umockdev_testbed_remove_device(tb, SYS_INTF);
    umockdev_testbed_remove_device(tb, SYS_USB);
    if (stream_until(-1, NULL, NULL, UNTIL_HELD) != 0)
        goto fail;
    clean_ptymap();
    replug_s = hl_clock_now_s();
    if (add_device("dk2-hidraw1.umockdev", "/dev/hidraw1") != 0)
        goto fail;
    int master1 = umockdev_testbed_get_dev_fd(tb, "/dev/hidraw1");
    struct trk_encoder enc1;
    trk_encoder_init(&enc1, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t device1_ns = 1000000;
    if (master1 < 0 || stream_until(master1, &enc1, &device1_ns, UNTIL_TURNED_AGAIN) != 0)
        goto fail;
    kill(getpid(), SIGINT); /* the user's Ctrl-C: the session ends cleanly */
    /* Reports until it has: a second of silence before it stops would count as a second loss. Not
     * blocking: once the session has closed the node, nothing drains it. */
    int fl = fcntl(master1, F_GETFL);
    if (fl >= 0)
        fcntl(master1, F_SETFL, fl | O_NONBLOCK);
    double until = hl_clock_now_s() + 120.0 * tu_time_scale();
    while (!session_done && hl_clock_now_s() < until)
        if (stream(master1, &enc1, &device1_ns, 50) != 0)
            break;
    return NULL;
fail:
    feeder_failed = 1;
    kill(getpid(), SIGINT);
    return NULL;
}

int main(void)
{
    /* umockdev_in_mock_environment() says no until a testbed exists; the preload is what matters. */
    const char *preload = getenv("LD_PRELOAD");
    if (!preload || !strstr(preload, "umockdev-preload")) {
        fprintf(stderr, "skip: run under umockdev-wrapper (ctest does)\n");
        return 77;
    }
    if (!getenv("DISPLAY")) {
        fprintf(stderr, "skip: run under tests/with_xvfb.sh (ctest does)\n");
        return 77;
    }
    const char *src_dir = getenv("HMDLOD_SOURCE");
    snprintf(data_dir, sizeof data_dir, "%s/tests/data/umockdev", src_dir ? src_dir : ".");
    tb = umockdev_testbed_new();
    if (add_device("dk2-hidraw0.umockdev", "/dev/hidraw0") != 0)
        return 1;

    char dir[] = "/tmp/hmdlod-live-umockdev-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    snprintf(trace_dir, sizeof trace_dir, "%s", dir);
    char capture[256], record[256];
    snprintf(capture, sizeof capture, "%s/live.png", dir);
    snprintf(record, sizeof record, "%s/head.csv", dir);

    struct frm_options so;
    frm_options_defaults(&so);
    so.scene = "field";
    so.display = "dk2";
    so.render_scale = 0.2;
    so.gaze = "head";
    struct liv_options o;
    liv_options_defaults(&o);
    o.session = &so;
    o.device = "auto";
    o.capture_path = capture;
    o.record_path = record;
    o.window_w_px = 320, o.window_h_px = 180;
    o.rate_hz = 30; /* llvmpipe on a loaded machine: the test is about poses, not pacing */
    pthread_t th;
    CHECK(pthread_create(&th, NULL, feeder, NULL) == 0);
    struct liv_summary s;
    struct hl_error err = {""};
    int rc = liv_run(&o, &s, &err);
    session_done = 1;
    pthread_join(th, NULL);
    if (rc != 0)
        fprintf(stderr, "live: %s\n", err.msg);
    CHECK(rc == 0);
    CHECK(!feeder_failed);
    liv_summary_print(stdout, &s);
    CHECK(strstr(s.source, "hidraw0") != NULL); /* the tracker, not the desk */
    CHECK(s.tracker_losses == 1);
    CHECK(s.tracker_resumes == 1);
    CHECK(s.frames >= 30);
    CHECK(strcmp(s.capture, capture) == 0 && access(capture, R_OK) == 0);
    /* The raw recording beside the CSV: every report the tracker read, across the replug. */
    char raw[256];
    snprintf(raw, sizeof raw, "%s/head.raw", dir);
    CHECK(strcmp(s.raw_record, raw) == 0);
    struct trk_recording_reader *rd = trk_recording_open(raw, &err);
    CHECK(rd != NULL);
    long records = 0;
    if (rd) {
        int64_t t_ns;
        uint8_t buf[TRK_RECORDING_MAX_REPORT];
        int r;
        size_t len;
        while ((r = trk_recording_next(rd, &t_ns, buf, sizeof buf, &len, &err)) == 1)
            ++records;
        CHECK(r == 0);
        trk_recording_reader_close(rd);
    }
    printf("raw recording: %ld records (%ld in the summary)\n", records, s.raw_reports);
    CHECK(records == s.raw_reports && records >= 100);
    remove(raw);

    /* The head trace: rows of the session; yaw turning while streaming, held while unplugged. */
    struct trace_stats st;
    trace_stats_read(record, &st);
    CHECK(st.header_ok);
    printf("head trace: %ld rows, %ld turning; pose held for %.2f s after turning, %ld turning rows after that; "
           "unplugged for %.2f s\n", st.rows, st.moving_rows, st.longest_s, st.moving_after_longest,
           replug_s - unplug_s);
    CHECK(st.rows == s.frames);
    CHECK(st.moving_rows >= 10);         /* 90 deg/s while streaming: 3 deg a frame at 30 Hz */
    CHECK(st.longest_s >= 0.8);          /* held while unplugged, not extrapolated */
    CHECK(st.moving_after_longest >= 5); /* and turning again after the replug */
    remove(capture);
    remove(record);
    rmdir(dir);
    g_object_unref(tb);
    return tu_finish("test_live_umockdev");
}
