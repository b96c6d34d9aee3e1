/* Faults of a live tracker under umockdev (issue 17 item 6; PLATFORM.md §6): run as
 * `umockdev-wrapper test_hid_faults`. The fake Rift DK2 of test_hid_umockdev (tests/data/umockdev)
 * streams through the real hidapi-hidraw read path while it misbehaves:
 *   - short and over-long reports: each refused and counted, the stream goes on;
 *   - a device that stops sending: noticed within 1 s + one read timeout ("no reports for 1000 ms"),
 *     the pose held with no prediction, streaming again when reports return;
 *   - a read that fails mid-stream with no remove event (the node hung up: the kernel's hidraw
 *     answers such a read with EIO and POLLHUP, as the PTY here does): LOST naming the node, and no
 *     busy reconnect loop while the dead node stays listed;
 *   - 100 unplug/replug cycles in a row (a new node name each time): each replug reopened and
 *     streaming; file descriptors, heap and RSS not grown beyond what the testbed itself keeps.
 *   - `hmdlod record` on a device that goes silent: said once, resumption said, every report kept.
 * Run with the argument `cycles N` to change the count (default 100). */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/resource.h>
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
#define WAIT_S (5.0 * tu_time_scale()) /* every wait below is bounded by this (longer under valgrind) */

static UMockdevTestbed *tb;
static char data_dir[1024];

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

static void clean_ptymap(void)
{
    /* Re-adding a node in the same testbed needs the stale PTY map gone (PLATFORM.md §6 step 5). */
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

/* Plugs the DK2 in as /dev/hidraw<k> (hid instance k + 1): the fixture dk2-hidraw0.umockdev with
 * the node renamed. A testbed cannot re-add a node name it once had (PLATFORM.md §6 step 5), so
 * every replug gets a new one, as the kernel also does while the old node is still held open. */
static int plug(int k)
{
    static char *fixture;
    size_t size = 0;
    if (!fixture && !(fixture = tu_read_file(data_path("dk2-hidraw0.umockdev"), &size)))
        return -1;
    GString *text = g_string_new(NULL);
    char inst[32], node[32], minor[32], dev[32];
    snprintf(inst, sizeof inst, "0021.%04X", k + 1);
    snprintf(node, sizeof node, "hidraw%d", k);
    snprintf(minor, sizeof minor, "MINOR=%d", k);
    snprintf(dev, sizeof dev, "dev=240:%d", k);
    struct {
        const char *from, *to;
    } subst[] = {{"0021.0001", inst}, {"hidraw0", node}, {"MINOR=0", minor}, {"dev=240:0", dev}};
    for (const char *p = fixture; *p;) {
        size_t i, n = sizeof subst / sizeof subst[0];
        for (i = 0; i < n && strncmp(p, subst[i].from, strlen(subst[i].from)); ++i) {
        }
        if (i < n) {
            g_string_append(text, subst[i].to);
            p += strlen(subst[i].from);
        } else {
            g_string_append_c(text, *p++);
        }
    }
    char path[40];
    snprintf(path, sizeof path, "/dev/hidraw%d", k);
    GError *gerr = NULL;
    clean_ptymap();
    int ok = umockdev_testbed_load_ioctl(tb, path, data_path("dk2.ioctl"), &gerr) &&
             umockdev_testbed_add_from_string(tb, text->str, &gerr);
    g_string_free(text, TRUE);
    if (!ok) {
        fprintf(stderr, "umockdev: %s: %s\n", path, gerr ? gerr->message : "?");
        g_clear_error(&gerr);
        return -1;
    }
    return umockdev_testbed_get_dev_fd(tb, path);
}

/* Hangs up node k's PTY (dup2 keeps the fd valid for the testbed): the reader's next read fails. */
static void hang_up(int master)
{
    int devnull = open("/dev/null", O_RDWR | O_CLOEXEC);
    if (devnull >= 0) {
        dup2(devnull, master);
        close(devnull);
    }
}

static void remove_sysfs(int k, int send_uevent)
{
    char hid[256], hidraw[300];
    snprintf(hid, sizeof hid, SYS_INTF "/0003:2833:0021.%04X", k + 1);
    snprintf(hidraw, sizeof hidraw, "%s/hidraw/hidraw%d", hid, k);
    if (send_uevent)
        umockdev_testbed_uevent(tb, hidraw, "remove");
    umockdev_testbed_remove_device(tb, hidraw);
    umockdev_testbed_remove_device(tb, hid);
    umockdev_testbed_remove_device(tb, SYS_INTF);
    umockdev_testbed_remove_device(tb, SYS_USB);
}

static int encode(struct trk_encoder *enc, int64_t *device_ns, uint8_t report[64])
{
    struct trk_imu_sample smp;
    memset(&smp, 0, sizeof smp);
    smp.device_time_ns = *device_ns;
    smp.gyro_radps = hl_v3(0, YAW_RATE_DEG_S * HL_RAD_PER_DEG, 0);
    smp.accel_mps2 = hl_v3(0, 9.80665, 0);
    smp.orientation = hl_q_identity();
    smp.has_gyro = smp.has_accel = 1;
    *device_ns += 1000000;
    struct hl_error err;
    return trk_encoder_push(enc, &smp, report, 64, &err);
}

/* `count` DK2 reports, 1 ms of device time apart, one write() each (PLATFORM.md §6). */
static int feed(int master, struct trk_encoder *enc, int64_t *device_ns, int count)
{
    for (int i = 0; i < count; ++i) {
        uint8_t report[64];
        int n = encode(enc, device_ns, report);
        if (n < 0 || (n > 0 && write(master, report, (size_t)n) != n)) {
            fprintf(stderr, "write to the fake DK2: %s\n", strerror(errno));
            return -1;
        }
    }
    return 0;
}

static struct trk_tracker_stats stats_of(struct trk_pose_source *src)
{
    struct trk_tracker_stats st;
    memset(&st, 0, sizeof st);
    trk_tracker_source_stats(src, &st);
    return st;
}

static int wait_reports(struct trk_pose_source *src, uint64_t want)
{
    double until = hl_clock_now_s() + WAIT_S;
    while (hl_clock_now_s() < until) {
        if (stats_of(src).reports >= want)
            return 0;
        sleep_ms(1);
    }
    fprintf(stderr, "only %llu of %llu reports read in %.0f s\n", (unsigned long long)stats_of(src).reports,
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

static double yaw_deg(hl_quatd q)
{
    hl_vec3d f = hl_q_rotate(q, hl_v3(0, 0, -1));
    return atan2(-f.x, -f.z) * HL_DEG_PER_RAD;
}

static int count_fds(void)
{
    DIR *d = opendir("/proc/self/fd");
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        n += e->d_name[0] != '.';
    closedir(d);
    return n - 1; /* the directory's own fd */
}

static long rss_kib(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    long pages = 0, resident = 0;
    if (!f)
        return -1;
    if (fscanf(f, "%ld %ld", &pages, &resident) != 2)
        resident = -1;
    fclose(f);
    return resident < 0 ? -1 : resident * (sysconf(_SC_PAGESIZE) / 1024);
}

static double cpu_s(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) + 1e-6 * (double)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

/* Short and over-long reports: a real hidraw read hands out one report, cut to the buffer; here a
 * 30-byte write is one short read and a 100-byte write is one whole report plus a 36-byte tail. */
static void test_bad_lengths(struct trk_pose_source *src, int master, struct trk_encoder *enc, int64_t *device_ns)
{
    struct trk_tracker_stats st0 = stats_of(src);
    uint8_t shortr[30];
    memset(shortr, 0, sizeof shortr);
    shortr[0] = 0x0B;
    CHECK(write(master, shortr, sizeof shortr) == (ssize_t)sizeof shortr);
    sleep_ms(150); /* longer than the reader's completion of a short read (8 × 5 ms) */
    uint8_t longr[100];
    CHECK(encode(enc, device_ns, longr) == 64);
    memset(longr + 64, 0xFF, sizeof longr - 64);
    CHECK(write(master, longr, sizeof longr) == (ssize_t)sizeof longr);
    sleep_ms(150);
    CHECK(wait_reports(src, st0.reports + 3) == 0);
    struct trk_tracker_stats st1 = stats_of(src);
    CHECK(st1.rejected == st0.rejected + 2);      /* the short one and the tail */
    CHECK(st1.samples_fused == st0.samples_fused + 1); /* the over-long one's report */
    CHECK(feed(master, enc, device_ns, 20) == 0);
    CHECK(wait_reports(src, st1.reports + 20) == 0);
    struct trk_tracker_stats st2 = stats_of(src);
    CHECK(st2.samples_fused == st1.samples_fused + 20 && st2.rejected == st1.rejected);
    char reason[768];
    CHECK(src->health(src, reason, sizeof reason) == TRK_HEALTH_OK);
    printf("short and over-long reports: %llu rejected, stream goes on (%s)\n",
           (unsigned long long)(st2.rejected - st0.rejected), reason);
}

/* The device stops sending, then speaks again. */
static void test_silence(struct trk_pose_source *src, int master, struct trk_encoder *enc, int64_t *device_ns)
{
    struct hl_error err;
    char reason[768];
    struct trk_tracker_stats st0 = stats_of(src);
    CHECK(feed(master, enc, device_ns, 20) == 0);
    CHECK(wait_reports(src, st0.reports + 20) == 0);
    double t_last = hl_clock_now_s();
    /* Before the silence is noticed the pose is still predicted, but never past the 40 ms cap. */
    struct trk_pose p0, far;
    CHECK(src->pose_at(src, t_last - 10.0, &p0, &err) == 0);
    CHECK(src->pose_at(src, t_last + 10.0, &far, &err) == 0);
    CHECK(fabs(yaw_deg(far.orientation) - yaw_deg(p0.orientation)) <= YAW_RATE_DEG_S * 0.040 + 0.2);
    /* A caller whose clock jumped an hour either way: the horizon is clamped to [0, 40 ms]. */
    struct trk_pose back_1h, ahead_1h;
    CHECK(src->pose_at(src, t_last - 3600.0, &back_1h, &err) == 0);
    CHECK(src->pose_at(src, t_last + 3600.0, &ahead_1h, &err) == 0);
    CHECK(hl_q_angle_rad(back_1h.orientation, p0.orientation) < 1e-9);
    CHECK(fabs(yaw_deg(ahead_1h.orientation) - yaw_deg(p0.orientation)) <= YAW_RATE_DEG_S * 0.040 + 0.2);
    CHECK(back_1h.time_s == t_last - 3600.0 && ahead_1h.time_s == t_last + 3600.0);
    double lost_s = wait_health(src, TRK_HEALTH_LOST, reason, sizeof reason);
    double detect_s = hl_clock_now_s() - t_last;
    CHECK(lost_s >= 0);
    /* 1 s + one 20 ms read timeout; the upper margin is for a loaded machine. */
    CHECK(detect_s >= 0.95 && detect_s < 1.6);
    CHECK(strstr(reason, "no reports for 1000 ms") != NULL && strstr(reason, "/dev/hidraw0") != NULL);
    printf("silence noticed %.0f ms after the last report: %s\n", detect_s * 1e3, reason);
    struct trk_pose h1, h2;
    CHECK(src->pose_at(src, hl_clock_now_s(), &h1, &err) == 0);
    CHECK(src->pose_at(src, hl_clock_now_s() + 1.0, &h2, &err) == 0);
    CHECK(hl_v3_length(h1.angular_velocity_radps) == 0.0);
    CHECK(hl_q_angle_rad(h1.orientation, h2.orientation) == 0.0);     /* held, not predicted */
    CHECK(fabs(yaw_deg(h1.orientation) - yaw_deg(p0.orientation)) < 0.01); /* the last pose */
    struct trk_tracker_stats st1 = stats_of(src);
    CHECK(st1.stalls == st0.stalls + 1 && st1.disconnects == st0.disconnects && st1.connected);
    /* The device's clock kept running meanwhile; it speaks again. */
    *device_ns += 1200000000LL;
    CHECK(feed(master, enc, device_ns, 20) == 0);
    double ok_s = wait_health(src, TRK_HEALTH_OK, reason, sizeof reason);
    CHECK(ok_s >= 0);
    CHECK(wait_reports(src, st1.reports + 20) == 0);
    struct trk_pose p1;
    CHECK(src->pose_at(src, hl_clock_now_s() - 10.0, &p1, &err) == 0);
    CHECK(isfinite(yaw_deg(p1.orientation)) && yaw_deg(p1.orientation) > yaw_deg(p0.orientation));
    printf("reports again: OK after %.1f ms (%s)\n", ok_s * 1e3, reason);
}

/* A read that fails with the node still listed (no remove uevent). */
static void test_read_error(struct trk_pose_source *src, int master)
{
    char reason[768];
    struct trk_tracker_stats st0 = stats_of(src);
    hang_up(master);
    double lost_s = wait_health(src, TRK_HEALTH_LOST, reason, sizeof reason);
    CHECK(lost_s >= 0 && lost_s < 1.0);
    CHECK(strstr(reason, "/dev/hidraw0") != NULL && strstr(reason, "read failed") != NULL);
    printf("read error noticed in %.1f ms: %s\n", lost_s * 1e3, reason);
    /* The dead node stays in sysfs: the source retries on its slow schedule, not in a loop. */
    double c0 = cpu_s();
    sleep_ms(1500);
    double used = cpu_s() - c0;
    struct trk_tracker_stats st1 = stats_of(src);
    CHECK(st1.disconnects == st0.disconnects + 1);
    CHECK(!st1.connected && st1.reconnects == st0.reconnects);
    CHECK(used < 0.3);
    src->health(src, reason, sizeof reason);
    CHECK(strstr(reason, "/dev/hidraw0") != NULL);
    printf("1.5 s with the dead node listed: %.0f ms of CPU, still %s\n", used * 1e3, reason);
    remove_sysfs(0, 1);
}

/* One replug as node k and an unplug; 0 when it streamed in between. */
static int cycle(struct trk_pose_source *src, int k)
{
    char reason[768];
    struct trk_tracker_stats st0 = stats_of(src);
    int master = plug(k);
    if (master < 0)
        return -1;
    double until = hl_clock_now_s() + WAIT_S;
    while (hl_clock_now_s() < until && !(stats_of(src).reconnects > st0.reconnects && stats_of(src).connected))
        sleep_ms(1);
    int rc = stats_of(src).reconnects > st0.reconnects ? 0 : -1;
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t device_ns = 1000000;
    if (rc == 0 && (feed(master, &enc, &device_ns, 12) != 0 || wait_reports(src, st0.reports + 12) != 0 ||
                    wait_health(src, TRK_HEALTH_OK, reason, sizeof reason) < 0))
        rc = -1;
    char hidraw[300];
    snprintf(hidraw, sizeof hidraw, SYS_INTF "/0003:2833:0021.%04X/hidraw/hidraw%d", k + 1, k);
    umockdev_testbed_uevent(tb, hidraw, "remove");
    hang_up(master);
    until = hl_clock_now_s() + WAIT_S;
    while (hl_clock_now_s() < until && stats_of(src).connected)
        sleep_ms(1);
    if (stats_of(src).connected)
        rc = -1;
    remove_sysfs(k, 0);
    if (rc != 0) {
        fprintf(stderr, "cycle on hidraw%d failed\n", k);
        tu_hid_print_state(src);
    }
    return rc;
}

struct growth {
    int fds;
    long heap_b, rss_kib;
    double seconds;
};

/* n plug/unplug cycles with no source listening (node names from 1000 up), after one more. */
static struct growth testbed_cycles(int n)
{
    struct growth g;
    double t0 = 0;
    int f0 = 0;
    size_t h0 = 0;
    long r0 = 0;
    for (int i = -1; i < n; ++i) {
        if (i == 0) { /* the first one (not counted) sets the testbed's one-time state up */
            t0 = hl_clock_now_s();
            f0 = count_fds();
            h0 = mallinfo2().uordblks;
            r0 = rss_kib();
        }
        int m = plug(1001 + i);
        char hidraw[300];
        snprintf(hidraw, sizeof hidraw, SYS_INTF "/0003:2833:0021.%04X/hidraw/hidraw%d", 1001 + i + 1, 1001 + i);
        umockdev_testbed_uevent(tb, hidraw, "remove");
        if (m >= 0)
            hang_up(m);
        remove_sysfs(1001 + i, 0);
    }
    g.fds = count_fds() - f0;
    g.heap_b = (long)mallinfo2().uordblks - (long)h0;
    g.rss_kib = rss_kib() - r0;
    g.seconds = hl_clock_now_s() - t0;
    return g;
}

static void test_cycles(struct trk_pose_source *src, int cycles, const struct growth *testbed)
{
    double t0 = hl_clock_now_s();
    int failed = 0;
    CHECK(cycle(src, 1) == 0); /* the first one warms hidapi, udev and glib up */
    int fds0 = count_fds();
    size_t heap0 = mallinfo2().uordblks;
    long rss0 = rss_kib();
    struct trk_tracker_stats st0 = stats_of(src);
    for (int i = 1; i < cycles; ++i)
        failed += cycle(src, i + 1) != 0;
    CHECK(failed == 0);
    int fds1 = count_fds();
    size_t heap1 = mallinfo2().uordblks;
    long rss1 = rss_kib();
    struct trk_tracker_stats st1 = stats_of(src);
    CHECK(st1.reconnects - st0.reconnects == (uint64_t)(cycles - 1));
    CHECK(st1.disconnects - st0.disconnects == (uint64_t)(cycles - 1));
    /* Charged to the source: the growth beyond what the same cycles cost the testbed alone. A leak
     * of one trk_hid_device (1 KB) per cycle shows as +58 KB here (tried); the testbed's own heap
     * growth varies by a few KB per cycle around its mean (glib tables): −31 to +1 KB in four runs. */
    int fds_source = (fds1 - fds0) - testbed->fds;
    long heap_source = ((long)heap1 - (long)heap0) - testbed->heap_b;
    /* A leaked fd a cycle shows as +99, one every tenth cycle as +10. The testbed's own count varies
     * by a few fds between its run and this one under load (−1 and −2 seen on a loaded machine,
     * where == 0 failed; +1 once under ASan with a second build beside it): ±2 is its variation. */
    CHECK(fds_source <= 2);
    CHECK(fds_source >= -8);
    CHECK(heap_source <= 32 * 1024);
    CHECK(rss1 - rss0 - testbed->rss_kib <= 1024);
    printf("testbed alone, %d cycles in %.1f s: +%d fds, %+ld B heap, %+ld KiB RSS\n", cycles - 1,
           testbed->seconds, testbed->fds, testbed->heap_b, testbed->rss_kib);
    printf("%d unplug/replug cycles in %.1f s (%d failed), %llu reconnects; over the last %d: fds %d → %d, "
           "heap %zu → %zu B, RSS %ld → %ld KiB; beyond the testbed's own: %+d fds, %+ld B heap, %+ld KiB RSS\n",
           cycles, hl_clock_now_s() - t0, failed, (unsigned long long)st1.reconnects, cycles - 1, fds0, fds1, heap0,
           heap1, rss0, rss1, fds_source, heap_source, rss1 - rss0 - testbed->rss_kib);
}

/* `hmdlod record` (HMDLOD_BIN) on a DK2 that goes silent for 1.3 s: it says so once, says when
 * reports return, and the recording holds every report. Run with no source holding the node. */
static void test_record_silence(void)
{
    const char *bin = getenv("HMDLOD_BIN");
    if (!bin) {
        printf("skip: HMDLOD_BIN unset; the record command was not run\n");
        return;
    }
    char dir[] = "/tmp/hmdlod-faults-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp");
        return;
    }
    char path[256], errpath[256];
    snprintf(path, sizeof path, "%s/silent.raw", dir);
    snprintf(errpath, sizeof errpath, "%s/stderr.txt", dir);
    const int k = 500;
    int master = plug(k);
    CHECK(master >= 0);
    pid_t child = fork();
    if (child == 0) {
        int fd = open(errpath, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0)
            dup2(fd, 2);
        execl(bin, bin, "record", "--device", "/dev/hidraw500", "--out", path, "--seconds", "20", (char *)NULL);
        _exit(127);
    }
    CHECK(child > 0);
    double t0 = hl_clock_now_s();
    while (access(path, F_OK) != 0 && hl_clock_now_s() < t0 + WAIT_S)
        sleep_ms(5);
    sleep_ms(50);
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t device_ns = 1000000;
    CHECK(feed(master, &enc, &device_ns, 20) == 0);
    sleep_ms(1300);
    CHECK(feed(master, &enc, &device_ns, 20) == 0);
    sleep_ms(300);
    kill(child, SIGINT);
    int status = 0;
    CHECK(waitpid(child, &status, 0) == child);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    size_t size = 0;
    char *text = tu_read_file(errpath, &size);
    CHECK(text && strstr(text, "Oculus Rift DK2 DK2SIM0001: no reports for 1000 ms (still recording)") &&
          strstr(text, "reports again after"));
    if (text)
        printf("record, silent device: %s", text);
    free(text);
    struct hl_error err;
    struct trk_recording_reader *rd = trk_recording_open(path, &err);
    CHECK(rd != NULL);
    if (rd) {
        uint8_t report[1024];
        size_t len = 0;
        int64_t host_ns = 0;
        int records = 0, rc;
        while ((rc = trk_recording_next(rd, &host_ns, report, sizeof report, &len, &err)) == 1)
            ++records;
        CHECK(rc == 0 && records == 40);
        trk_recording_reader_close(rd);
    }
    hang_up(master);
    remove_sysfs(k, 1);
    unlink(path);
    unlink(errpath);
    rmdir(dir);
}

int main(int argc, char **argv)
{
    const char *preload = getenv("LD_PRELOAD");
    if (!preload || !strstr(preload, "umockdev-preload")) {
        fprintf(stderr, "skip: run under umockdev-wrapper (PLATFORM.md §6)\n");
        return 77;
    }
    int cycles = 100;
    if (argc == 3 && !strcmp(argv[1], "cycles"))
        cycles = atoi(argv[2]) > 1 ? atoi(argv[2]) : 2;
    const char *src_dir = getenv("HMDLOD_SOURCE");
    snprintf(data_dir, sizeof data_dir, "%s/tests/data/umockdev", src_dir ? src_dir : ".");
    tb = umockdev_testbed_new();
    /* What the testbed itself keeps per plugged node (its PTY master and ioctl socket, glib
     * bookkeeping), measured with no tracker source running, so that the cycles below can be
     * charged only with what the source keeps. */
    struct growth testbed = testbed_cycles(cycles - 1);
    int master = plug(0);
    CHECK(master >= 0);
    if (master < 0) {
        g_object_unref(tb);
        return tu_finish("test_hid_faults");
    }

    struct trk_pose_source *src = NULL;
    struct hl_error err;
    CHECK(trk_tracker_source_create("auto", 0.040, &src, &err) == 0);
    if (!src || src->start(src, &err) != 0) {
        fprintf(stderr, "tracker: %s\n", err.msg);
        CHECK(!"start failed");
        trk_source_destroy(src);
        g_object_unref(tb);
        return tu_finish("test_hid_faults");
    }
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t device_ns = 5000000000LL;
    char reason[768];
    CHECK(feed(master, &enc, &device_ns, 50) == 0);
    CHECK(wait_reports(src, 50) == 0);
    CHECK(wait_health(src, TRK_HEALTH_OK, reason, sizeof reason) >= 0);

    test_bad_lengths(src, master, &enc, &device_ns);
    test_silence(src, master, &enc, &device_ns);
    test_read_error(src, master);
    test_cycles(src, cycles, &testbed);

    double t_stop = hl_clock_now_s();
    trk_source_destroy(src);
    CHECK(hl_clock_now_s() - t_stop < 0.5);
    test_record_silence();
    g_object_unref(tb);
    return tu_finish("test_hid_faults");
}
