/* Live tracker I/O against a fake Rift DK2 under umockdev (PLATFORM.md §6, "library route"): run
 * as `umockdev-wrapper test_hid_umockdev`. The fixtures in tests/data/umockdev/ describe a DK2
 * (2833:0021, interface 0) as hidraw0, the same unit replugged as hidraw1, and a second DK2 whose
 * node answers no ioctl (hidraw2). Reports come from the existing encoder at a constant 90 deg/s yaw,
 * so the fused heading is known. Covered: discovery with strings, interface and an unopenable node
 * explained; the live source streaming and predicting; unplug → LOST with a reason and a frozen
 * pose; replug under a new node name → reopened, OK, poses resume; clean stop; and `hmdlod record`
 * on the replugged node, stopped by SIGINT, writing every report it was sent. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <umockdev.h>

#include "tests/test_hid_util.h"
#include "tests/test_util.h"
#include "tracking/tracking.h"

#define SYS_USB "/sys/devices/pci0000:00/0000:00:14.0/usb1/1-1"
#define SYS_INTF SYS_USB "/1-1:1.0"
#define YAW_RATE_DEG_S 90.0
#define YAW_TOL_DEG 0.5 /* gyro quantised to 1e-4 rad/s; yaw is integrated, not corrected */
#define WAIT_S (5.0 * tu_time_scale()) /* every wait below is bounded by this (longer under valgrind) */

static UMockdevTestbed *tb;
static char data_dir[1024];

static void sleep_ms(int ms)
{
    if (ms >= 50) /* a settling pause, not a poll: as much longer as the test's bounds are */
        ms = (int)(ms * tu_time_scale());
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

static const char *data_path(const char *name)
{
    static char path[1200];
    snprintf(path, sizeof path, "%s/%s", data_dir, name);
    return path;
}

static int add_device(const char *file, const char *node, int with_ioctl)
{
    GError *gerr = NULL;
    /* hid_open_path needs HIDIOCGRDESCSIZE/HIDIOCGRDESC; the DK2 start also sets two features.
     * Loaded before the add, whose uevent the source reacts to at once (as a real node answers). */
    if (with_ioctl && !umockdev_testbed_load_ioctl(tb, node, data_path("dk2.ioctl"), &gerr)) {
        fprintf(stderr, "umockdev: cannot load ioctls for %s: %s\n", node, gerr ? gerr->message : "?");
        g_clear_error(&gerr);
        return -1;
    }
    if (!umockdev_testbed_add_from_file(tb, data_path(file), &gerr)) {
        fprintf(stderr, "umockdev: cannot add %s: %s\n", file, gerr ? gerr->message : "?");
        g_clear_error(&gerr);
        return -1;
    }
    return 0;
}

/* Heading about world +Y: a yaw θ turns the forward −Z into (−sin θ, 0, −cos θ). */
static double yaw_deg(hl_quatd q)
{
    hl_vec3d f = hl_q_rotate(q, hl_v3(0, 0, -1));
    return atan2(-f.x, -f.z) * HL_DEG_PER_RAD;
}

static double wrap_deg(double a)
{
    while (a > 180.0)
        a -= 360.0;
    while (a <= -180.0)
        a += 360.0;
    return a;
}

/* Writes `count` DK2 reports (one sample each, 1 ms apart from device time t0) to the PTY master:
 * constant yaw rate, upright (gravity on +Y). One write() per report: the node is a byte stream
 * and the reader takes exactly 64 bytes at a time (PLATFORM.md §6). */
static int feed(int master, struct trk_encoder *enc, int64_t *device_ns, int count)
{
    for (int i = 0; i < count; ++i) {
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
        if (n < 0) {
            fprintf(stderr, "encoder: %s\n", err.msg);
            return -1;
        }
        if (n == 0)
            continue;
        if (write(master, report, (size_t)n) != n) {
            fprintf(stderr, "write to the fake DK2: %s\n", strerror(errno));
            return -1;
        }
    }
    return 0;
}

static int wait_reports(struct trk_pose_source *src, uint64_t want)
{
    struct trk_tracker_stats st;
    double until = hl_clock_now_s() + WAIT_S;
    while (hl_clock_now_s() < until) {
        if (trk_tracker_source_stats(src, &st) == 0 && st.reports >= want)
            return 0;
        sleep_ms(1);
    }
    fprintf(stderr, "only %llu of %llu reports read in %.0f s\n", (unsigned long long)st.reports,
            (unsigned long long)want, WAIT_S);
    tu_hid_print_state(src);
    return -1;
}

static double wait_health(struct trk_pose_source *src, enum trk_health want, char *reason, size_t size)
{
    double t0 = hl_clock_now_s();
    while (hl_clock_now_s() < t0 + WAIT_S) {
        if (src->health(src, reason, size) == want)
            return hl_clock_now_s() - t0;
        sleep_ms(1);
    }
    return -1.0;
}

static void clean_ptymap(void)
{
    /* Re-adding a node in the same testbed needs the stale PTY map gone (PLATFORM.md §6 step 5). */
    char dir[1200];
    gchar *root = umockdev_testbed_get_root_dir(tb); /* transfer full */
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

static void test_enumerate(void)
{
    struct trk_hid_device_desc list[8];
    struct hl_error err;
    int n = trk_hid_enumerate(list, 8, &err);
    CHECK(n == 2);
    const struct trk_hid_device_desc *good = NULL, *bad = NULL;
    for (int i = 0; i < n; ++i) {
        if (!strcmp(list[i].path, "/dev/hidraw0"))
            good = &list[i];
        if (!strcmp(list[i].path, "/dev/hidraw2"))
            bad = &list[i];
    }
    CHECK(good != NULL);
    CHECK(bad != NULL);
    if (good) {
        CHECK(good->info && good->info->kind == TRK_DEVICE_RIFT_DK2 && good->info->role == TRK_ROLE_IMU);
        CHECK(good->vid == 0x2833 && good->pid == 0x0021);
        CHECK(good->interface_number == 0);
        CHECK(!strcmp(good->manufacturer, "Oculus VR, Inc."));
        CHECK(!strcmp(good->product, "Rift DK2"));
        CHECK(!strcmp(good->serial, "DK2SIM0001"));
        CHECK(good->can_open == 1);
        printf("found %s: %s %s serial %s iface %d, can open\n", good->path, good->manufacturer, good->product,
               good->serial, good->interface_number);
    }
    if (bad) {
        /* (5) a node that cannot be used: the reason names it and says what failed. */
        CHECK(bad->can_open == 0);
        CHECK(strstr(bad->why, "/dev/hidraw2") != NULL);
        CHECK(strstr(bad->why, "HIDIOCGRDESCSIZE") != NULL);
        printf("found %s, cannot open: %s\n", bad->path, bad->why);
    }

    struct trk_hid_device *dev = NULL;
    CHECK(trk_hid_open("/dev/hidraw2", &dev, &err) == -1 && dev == NULL);
    CHECK(strstr(err.msg, "/dev/hidraw2") != NULL);
    printf("open /dev/hidraw2: %s\n", err.msg);
    CHECK(trk_hid_open("/dev/hidraw9", &dev, &err) == -1);
    CHECK(strstr(err.msg, "/dev/hidraw9") != NULL);
    printf("open /dev/hidraw9: %s\n", err.msg);
}

/* Complete records in the recording at path so far (it is being written: a torn tail ends the count). */
static int recorded_count(const char *path)
{
    struct hl_error err;
    struct trk_recording_reader *rd = trk_recording_open(path, &err);
    if (!rd)
        return 0;
    uint8_t report[1024];
    size_t len = 0;
    int64_t host_ns = 0;
    int records = 0;
    while (trk_recording_next(rd, &host_ns, report, sizeof report, &len, &err) == 1)
        ++records;
    trk_recording_reader_close(rd);
    return records;
}

/* `hmdlod record` as a user runs it (program from HMDLOD_BIN; the umockdev preload and testbed
 * reach the child through the environment): it opens the node, drains what was queued, records
 * every report until SIGINT, and leaves a complete recording with the device's identity. */
static void test_record_command(int master)
{
    const char *bin = getenv("HMDLOD_BIN");
    if (!bin || master < 0) {
        printf("skip: HMDLOD_BIN unset; the record command was not run\n");
        return;
    }
    char dir[] = "/tmp/hmdlod-record-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp");
        return;
    }
    char path[256];
    snprintf(path, sizeof path, "%s/session.raw", dir);
    pid_t child = fork();
    if (child == 0) {
        execl(bin, bin, "record", "--device", "/dev/hidraw1", "--out", path, "--seconds", "20", (char *)NULL);
        _exit(127);
    }
    CHECK(child > 0);
    /* The recording exists once the device is open and drained; only then are reports sent. */
    double t0 = hl_clock_now_s();
    while (access(path, F_OK) != 0 && hl_clock_now_s() < t0 + WAIT_S)
        sleep_ms(5);
    sleep_ms(50);
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t device_ns = 5000000;
    const int sent = 250;
    CHECK(feed(master, &enc, &device_ns, sent) == 0);
    /* SIGINT once every report is on disk (polled, bounded), so a slow run (valgrind, a loaded
     * machine) does not read as lost reports; the check below still wants every one. */
    double t1 = hl_clock_now_s();
    while (recorded_count(path) < sent && hl_clock_now_s() < t1 + WAIT_S)
        sleep_ms(50); /* scaled like the bounds: under valgrind a busier poll starves the testbed */
    kill(child, SIGINT);
    int status = 0;
    CHECK(waitpid(child, &status, 0) == child);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);

    struct hl_error err;
    struct trk_recording_reader *rd = trk_recording_open(path, &err);
    CHECK(rd != NULL);
    if (rd) {
        CHECK(rd->info.vid == 0x2833 && rd->info.pid == 0x0021 && rd->info.kind == TRK_DEVICE_RIFT_DK2);
        uint8_t report[1024];
        size_t len = 0;
        int64_t host_ns = 0;
        int records = 0, bad = 0, rc;
        while ((rc = trk_recording_next(rd, &host_ns, report, sizeof report, &len, &err)) == 1) {
            ++records;
            bad += len != 64 || report[0] != 0x0B;
        }
        CHECK(rc == 0 && !rd->torn_tail);
        CHECK(records == sent && bad == 0);
        printf("record: %d of %d reports recorded, stopped by SIGINT, exit %d\n", records, sent,
               WIFEXITED(status) ? WEXITSTATUS(status) : -1);
        trk_recording_reader_close(rd);
    }
    unlink(path);
    rmdir(dir);
}

int main(void)
{
    /* umockdev_in_mock_environment() says no until a testbed exists; the preload is what matters. */
    const char *preload = getenv("LD_PRELOAD");
    if (!preload || !strstr(preload, "umockdev-preload")) {
        fprintf(stderr, "skip: run under umockdev-wrapper (PLATFORM.md §6)\n");
        return 77;
    }
    const char *src_dir = getenv("HMDLOD_SOURCE");
    snprintf(data_dir, sizeof data_dir, "%s/tests/data/umockdev", src_dir ? src_dir : ".");

    tb = umockdev_testbed_new();
    if (add_device("dk2-hidraw0.umockdev", "/dev/hidraw0", 1) != 0 ||
        add_device("dk2-noioctl-hidraw2.umockdev", "/dev/hidraw2", 0) != 0) {
        g_object_unref(tb);
        return 1;
    }
    int master = umockdev_testbed_get_dev_fd(tb, "/dev/hidraw0");
    CHECK(master >= 0);

    /* (1) discovery, and (5) the unopenable node. */
    test_enumerate();

    /* (2) the live source: auto picks the openable DK2 (not hidraw2), streams, predicts. */
    struct trk_pose_source *src = NULL;
    struct hl_error err;
    char reason[768];
    CHECK(trk_tracker_source_create("auto", 0.040, &src, &err) == 0);
    if (!src) {
        fprintf(stderr, "%s\n", err.msg);
        return tu_finish("test_hid_umockdev");
    }
    if (src->start(src, &err) != 0) {
        fprintf(stderr, "start: %s\n", err.msg);
        CHECK(!"start failed");
        trk_source_destroy(src);
        g_object_unref(tb);
        return tu_finish("test_hid_umockdev");
    }
    printf("source %s started\n", src->name);
    CHECK(strstr(src->name, "/dev/hidraw0") != NULL);

    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t device_ns = 5000000000LL; /* the device clock need not start at 0 */
    const int n1 = 400;
    CHECK(feed(master, &enc, &device_ns, n1) == 0);
    CHECK(wait_reports(src, n1) == 0);
    CHECK(wait_health(src, TRK_HEALTH_OK, reason, sizeof reason) >= 0);
    printf("health OK: %s\n", reason);

    struct trk_pose now_pose, ahead;
    double expect = YAW_RATE_DEG_S * (n1 - 1) * 1e-3; /* the first sample only starts the clock */
    CHECK(src->pose_at(src, hl_clock_now_s() - 10.0, &now_pose, &err) == 0); /* past: horizon 0 */
    CHECK_NEAR(yaw_deg(now_pose.orientation), expect, YAW_TOL_DEG);
    CHECK_NEAR(now_pose.angular_velocity_radps.y * HL_DEG_PER_RAD, YAW_RATE_DEG_S, 0.5);
    /* Far future: the horizon is capped at 40 ms → 3.6° ahead. */
    CHECK(src->pose_at(src, hl_clock_now_s() + 10.0, &ahead, &err) == 0);
    CHECK_NEAR(wrap_deg(yaw_deg(ahead.orientation) - yaw_deg(now_pose.orientation)), YAW_RATE_DEG_S * 0.040, 0.2);
    printf("yaw after %d reports: %.3f deg (expected %.3f ± %.1f); capped prediction +%.3f deg\n", n1,
           yaw_deg(now_pose.orientation), expect, YAW_TOL_DEG,
           wrap_deg(yaw_deg(ahead.orientation) - yaw_deg(now_pose.orientation)));

    /* (3) unplug mid-stream: remove uevent, hang up the PTY (dup2 keeps the fd valid for the
     * testbed), then remove the sysfs devices leaf first (PLATFORM.md §6 steps 3–4). */
    CHECK(feed(master, &enc, &device_ns, 100) == 0);
    CHECK(wait_reports(src, n1 + 100) == 0);
    double last_yaw = YAW_RATE_DEG_S * (n1 + 100 - 1) * 1e-3;
    umockdev_testbed_uevent(tb, SYS_INTF "/0003:2833:0021.0001/hidraw/hidraw0", "remove");
    int devnull = open("/dev/null", O_RDWR | O_CLOEXEC);
    CHECK(devnull >= 0 && dup2(devnull, master) == master);
    close(devnull);
    double detect_s = wait_health(src, TRK_HEALTH_LOST, reason, sizeof reason);
    CHECK(detect_s >= 0 && detect_s < 1.0);
    CHECK(strstr(reason, "lost") != NULL);
    printf("unplug detected in %.1f ms: %s\n", detect_s * 1e3, reason);
    struct trk_pose frozen;
    CHECK(src->pose_at(src, hl_clock_now_s() + 0.02, &frozen, &err) == 0);
    CHECK_NEAR(yaw_deg(frozen.orientation), last_yaw, YAW_TOL_DEG);
    CHECK(hl_v3_length(frozen.angular_velocity_radps) == 0.0);
    struct trk_pose frozen_later;
    sleep_ms(50);
    CHECK(src->pose_at(src, hl_clock_now_s() + 0.5, &frozen_later, &err) == 0);
    CHECK(hl_q_angle_rad(frozen.orientation, frozen_later.orientation) == 0.0); /* no prediction */

    umockdev_testbed_remove_device(tb, SYS_INTF "/0003:2833:0021.0001/hidraw/hidraw0");
    umockdev_testbed_remove_device(tb, SYS_INTF "/0003:2833:0021.0001");
    umockdev_testbed_remove_device(tb, SYS_INTF);
    umockdev_testbed_remove_device(tb, SYS_USB);
    struct trk_hid_device_desc list[8];
    CHECK(trk_hid_enumerate(list, 8, &err) == 1); /* only the unopenable hidraw2 remains */
    sleep_ms(300); /* let the source rescan with the device gone: it must stay LOST */
    CHECK(src->health(src, reason, sizeof reason) == TRK_HEALTH_LOST);
    printf("while unplugged: %s\n", reason);

    /* (4) replug as hidraw1: the source reopens it, re-sends the start reports, restarts the stream. */
    clean_ptymap();
    double t_plug = hl_clock_now_s();
    CHECK(add_device("dk2-hidraw1.umockdev", "/dev/hidraw1", 1) == 0);
    int master1 = umockdev_testbed_get_dev_fd(tb, "/dev/hidraw1");
    CHECK(master1 >= 0);
    struct trk_tracker_stats st;
    double reopen_s = -1;
    while (hl_clock_now_s() < t_plug + WAIT_S) {
        if (getenv("HMDLOD_TEST_VERBOSE")) {
            static char last[768];
            src->health(src, reason, sizeof reason);
            if (strcmp(last, reason))
                printf("  %.1f ms: %s\n", (hl_clock_now_s() - t_plug) * 1e3, reason);
            snprintf(last, sizeof last, "%s", reason);
        }
        if (trk_tracker_source_stats(src, &st) == 0 && st.reconnects == 1 && st.connected) {
            reopen_s = hl_clock_now_s() - t_plug;
            break;
        }
        sleep_ms(1);
    }
    CHECK(reopen_s >= 0);
    if (reopen_s < 0)
        tu_hid_print_state(src);
    CHECK(!strcmp(st.path, "/dev/hidraw1"));
    printf("reopened %s %.1f ms after the add\n", st.path, reopen_s * 1e3);

    /* A replugged device restarts its clock; the stream must accept that (fresh unwrapping). */
    struct trk_encoder enc1;
    trk_encoder_init(&enc1, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t device1_ns = 1000000;
    const int n2 = 300;
    if (master1 >= 0)
        CHECK(feed(master1, &enc1, &device1_ns, 10) == 0); /* fits the PTY buffer: no blocking */
    double ok_s = wait_health(src, TRK_HEALTH_OK, reason, sizeof reason);
    CHECK(ok_s >= 0);
    double resume_s = hl_clock_now_s() - t_plug;
    if (master1 >= 0)
        CHECK(feed(master1, &enc1, &device1_ns, n2 - 10) == 0);
    CHECK(wait_reports(src, n1 + 100 + n2) == 0);
    printf("health OK again %.1f ms after the add: %s\n", resume_s * 1e3, reason);
    struct trk_pose p1, p2;
    CHECK(src->pose_at(src, hl_clock_now_s() - 10.0, &p1, &err) == 0);
    /* Heading restarts at 0 after a reopen (no magnetometer; tracking.h says so). */
    double expect2 = YAW_RATE_DEG_S * (n2 - 1) * 1e-3;
    CHECK_NEAR(yaw_deg(p1.orientation), expect2, YAW_TOL_DEG);
    if (master1 >= 0)
        CHECK(feed(master1, &enc1, &device1_ns, 100) == 0);
    CHECK(wait_reports(src, n1 + 200 + n2) == 0);
    CHECK(src->pose_at(src, hl_clock_now_s() - 10.0, &p2, &err) == 0);
    CHECK_NEAR(wrap_deg(yaw_deg(p2.orientation) - yaw_deg(p1.orientation)), YAW_RATE_DEG_S * 0.100, YAW_TOL_DEG);
    printf("after replug: yaw %.3f deg (expected %.3f), then +%.3f deg over 100 reports\n", yaw_deg(p1.orientation),
           expect2, wrap_deg(yaw_deg(p2.orientation) - yaw_deg(p1.orientation)));
    CHECK(trk_tracker_source_stats(src, &st) == 0);
    CHECK(st.disconnects == 1 && st.reconnects == 1 && st.rejected == 0);
    printf("stats: %llu reports, %llu rejected, %llu fused, %llu disconnects, %llu reconnects, %llu drained\n",
           (unsigned long long)st.reports, (unsigned long long)st.rejected, (unsigned long long)st.samples_fused,
           (unsigned long long)st.disconnects, (unsigned long long)st.reconnects, (unsigned long long)st.drained);
    printf("timings: unplug detected in %.1f ms, reopened %.1f ms and streaming (OK) %.1f ms after replug\n",
           detect_s * 1e3, reopen_s * 1e3, resume_s * 1e3);

    /* Clean shutdown: stop joins the reader thread; the source still answers afterwards. */
    double t_stop = hl_clock_now_s();
    src->stop(src);
    CHECK(hl_clock_now_s() - t_stop < 0.5);
    CHECK(src->health(src, reason, sizeof reason) == TRK_HEALTH_LOST);
    CHECK(src->pose_at(src, hl_clock_now_s(), &p1, &err) == 0);
    trk_source_destroy(src);
    test_record_command(master1);
    g_object_unref(tb);
    return tu_finish("test_hid_umockdev");
}
