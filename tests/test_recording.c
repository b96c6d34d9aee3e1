/* Device streams and raw recordings (tracking/stream.c, tracking/recording.c) and raw → trace
 * (replay/trace_raw.c, trace_write.c): round trips, every truncation, every single-byte corruption,
 * a writer killed with SIGKILL at random moments, and the shared IMU stream encoded as Rift DK2
 * reports, recorded, fused back and compared with its ground truth — also through the program
 * (hmdlod convert, hmdlod replay --raw) when HMDLOD_BIN is set. */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS for the SIGKILL test's shared counter (not in POSIX 2008) */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "replay/replay.h"
#include "tests/test_util.h"

static char dir[] = "/tmp/hmdlod-rec-XXXXXX";
static struct hl_error err;

static const char *tmp_path(const char *name)
{
    static char p[4][512];
    static int k;
    k = (k + 1) % 4;
    snprintf(p[k], sizeof p[k], "%s/%s", dir, name);
    return p[k];
}

/* ---- a deterministic record generator: record i is fully known from i ----------------------- */
static size_t gen_len(uint64_t i) { return 1 + (size_t)((i * 2654435761u) % 96); }
static int64_t gen_time(uint64_t i) { return 1000000000LL + (int64_t)i * 1000003 - (int64_t)(i % 7); }
static void gen_bytes(uint64_t i, uint8_t *out, size_t n)
{
    uint64_t x = i * 0x9E3779B97F4A7C15ull + 1;
    for (size_t j = 0; j < n; ++j) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        out[j] = (uint8_t)x;
    }
}

static int write_gen(const char *path, uint64_t count)
{
    struct trk_recording *rec = trk_recording_create(path, TRK_DEVICE_RIFT_DK2, 0x2833, 0x0021, "Rift DK2 test", &err);
    if (!rec)
        return -1;
    uint8_t b[TRK_RECORDING_MAX_REPORT];
    for (uint64_t i = 0; i < count; ++i) {
        gen_bytes(i, b, gen_len(i));
        if (trk_recording_append(rec, gen_time(i), b, gen_len(i), &err) != 0)
            return -1;
    }
    return trk_recording_close(rec, 1, &err);
}

/* Reads the whole file; checks each record is generator record i. Returns the reader's last rc. */
struct read_result {
    int open_ok, rc, torn;
    uint64_t records, torn_bytes, wrong;
    char msg[512];
};
static struct read_result read_all(const char *path)
{
    struct read_result r;
    memset(&r, 0, sizeof r);
    struct hl_error e = {{0}};
    struct trk_recording_reader *rd = trk_recording_open(path, &e);
    if (!rd) {
        r.rc = -1;
        snprintf(r.msg, sizeof r.msg, "%s", e.msg);
        return r;
    }
    r.open_ok = 1;
    uint8_t buf[TRK_RECORDING_MAX_REPORT], want[TRK_RECORDING_MAX_REPORT];
    int64_t t;
    size_t n;
    while ((r.rc = trk_recording_next(rd, &t, buf, sizeof buf, &n, &e)) == 1) {
        uint64_t i = r.records++;
        gen_bytes(i, want, gen_len(i));
        if (n != gen_len(i) || t != gen_time(i) || memcmp(buf, want, n) != 0)
            ++r.wrong;
    }
    if (r.rc < 0)
        snprintf(r.msg, sizeof r.msg, "%s", e.msg);
    r.torn = rd->torn_tail;
    r.torn_bytes = rd->torn_bytes;
    trk_recording_reader_close(rd);
    return r;
}

static void spit(const char *path, const uint8_t *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (n)
        fwrite(b, 1, n, f);
    fclose(f);
}

/* ---- format basics ---------------------------------------------------------------------------- */
static void test_crc_and_round_trip(void)
{
    CHECK(trk_crc32(0, "123456789", 9) == 0xCBF43926u); /* the standard check value */
    const char *p = tmp_path("rt.raw");
    CHECK(write_gen(p, 50) == 0);
    struct read_result r = read_all(p);
    CHECK(r.open_ok && r.rc == 0 && r.records == 50 && r.wrong == 0 && !r.torn);

    struct trk_recording_reader *rd = trk_recording_open(p, &err);
    CHECK(rd != NULL);
    if (rd) {
        CHECK(rd->info.version == 1 && rd->info.kind == TRK_DEVICE_RIFT_DK2);
        CHECK(rd->info.vid == 0x2833 && rd->info.pid == 0x0021);
        CHECK(!strcmp(rd->info.name, "Rift DK2 test"));
        CHECK(rd->info.host_start_ns > 0 && rd->info.wall_start_unix_ns > 1500000000LL * 1000000000LL);
        /* A caller buffer smaller than the record is an error, not an overrun. */
        uint8_t small[4];
        int64_t t;
        size_t n;
        for (int i = 0; i < 50; ++i) {
            if (gen_len((uint64_t)i) > sizeof small) {
                int rc;
                while ((rc = trk_recording_next(rd, &t, small, sizeof small, &n, &err)) == 1)
                    ;
                CHECK(rc == -1 && strstr(err.msg, "does not fit"));
                break;
            }
        }
        trk_recording_reader_close(rd);
    }

    /* The writer refuses what it cannot record; a long name is cut to 64 bytes. */
    char longname[200];
    memset(longname, 'n', sizeof longname - 1);
    longname[sizeof longname - 1] = 0;
    struct trk_recording *rec = trk_recording_create(tmp_path("long.raw"), TRK_DEVICE_HDK, 1, 2, longname, &err);
    CHECK(rec != NULL);
    uint8_t b[TRK_RECORDING_MAX_REPORT + 1] = {0};
    CHECK(trk_recording_append(rec, 1, b, 0, &err) == -1);
    CHECK(trk_recording_append(rec, 1, b, sizeof b, &err) == -1);
    CHECK(trk_recording_append(rec, 1, b, TRK_RECORDING_MAX_REPORT, &err) == 0);
    CHECK(trk_recording_records(rec) == 1);
    CHECK(trk_recording_close(rec, 0, &err) == 0);
    rd = trk_recording_open(tmp_path("long.raw"), &err);
    CHECK(rd && strlen(rd->info.name) == TRK_RECORDING_NAME_SIZE && rd->info.kind == TRK_DEVICE_HDK);
    trk_recording_reader_close(rd);
    CHECK(trk_recording_create(tmp_path("no/such/dir.raw"), TRK_DEVICE_HDK, 1, 2, "x", &err) == NULL);
    CHECK(strstr(err.msg, "no/such/dir.raw") != NULL);
    CHECK(trk_recording_open(tmp_path("absent.raw"), &err) == NULL && strstr(err.msg, "absent.raw"));
}

/* Every prefix: short of the header → error naming a byte; else every complete record and the rest
 * as a torn tail, never an error. */
static void test_truncation(void)
{
    const char *p = tmp_path("trunc-src.raw"), *q = tmp_path("trunc.raw");
    CHECK(write_gen(p, 12) == 0);
    size_t size;
    uint8_t *all = (uint8_t *)tu_read_file(p, &size);
    /* record boundaries */
    size_t ends[13], nb = 0, off = TRK_RECORDING_HEADER_SIZE;
    ends[nb++] = off;
    for (uint64_t i = 0; i < 12; ++i)
        ends[nb++] = off += TRK_RECORDING_RECORD_OVERHEAD + gen_len(i);
    CHECK(off == size);
    int bad = 0;
    for (size_t len = 0; len <= size; ++len) {
        spit(q, all, len);
        struct read_result r = read_all(q);
        if (len < TRK_RECORDING_HEADER_SIZE) {
            bad += r.open_ok || !strstr(r.msg, "byte ") || !strstr(r.msg, "trunc.raw");
            continue;
        }
        uint64_t complete = 0;
        while (complete + 1 < nb && ends[complete + 1] <= len)
            ++complete;
        int want_torn = ends[complete] != len;
        bad += !(r.open_ok && r.rc == 0 && r.records == complete && r.wrong == 0 && r.torn == want_torn &&
                 r.torn_bytes == (want_torn ? len - ends[complete] : 0));
    }
    CHECK(bad == 0);
    printf("truncation: %zu prefixes of a %zu-byte, 12-record file: %d wrong\n", size + 1, size, bad);
    free(all);
}

/* Flip one byte anywhere (three masks): an error naming the offset, or a torn tail; never a clean
 * read of the whole file, never a record that differs from what was written. */
static void test_corruption(void)
{
    const char *p = tmp_path("corr-src.raw"), *q = tmp_path("corr.raw");
    CHECK(write_gen(p, 12) == 0);
    size_t size;
    uint8_t *all = (uint8_t *)tu_read_file(p, &size);
    const uint8_t masks[3] = {0x01, 0x80, 0xFF};
    int bad = 0, errors = 0, torn = 0;
    for (size_t at = 0; at < size; ++at) {
        for (int m = 0; m < 3; ++m) {
            all[at] ^= masks[m];
            spit(q, all, size);
            all[at] ^= masks[m];
            struct read_result r = read_all(q);
            if (r.wrong)
                ++bad, fprintf(stderr, "corruption at %zu: a wrong record was returned\n", at);
            if (r.rc < 0) {
                ++errors;
                if (!strstr(r.msg, "corr.raw: byte "))
                    ++bad, fprintf(stderr, "corruption at %zu: message '%s'\n", at, r.msg);
            } else if (r.torn) {
                ++torn;
            } else {
                ++bad, fprintf(stderr, "corruption at %zu mask %02x: read cleanly (%llu records)\n", at, masks[m],
                               (unsigned long long)r.records);
            }
        }
    }
    CHECK(bad == 0);
    printf("corruption: %zu single-byte flips: %d errors naming the offset, %d torn tails, %d bad\n", size * 3,
           errors, torn, bad);

    /* A 4 GB length field: an error, and nothing sized from it (ASan would see a 4 GB malloc). */
    uint8_t *big = malloc(size);
    memcpy(big, all, size);
    memset(big + TRK_RECORDING_HEADER_SIZE, 0xFF, 4);
    spit(q, big, size);
    struct read_result r = read_all(q);
    CHECK(r.rc == -1 && strstr(r.msg, "byte 104: record length 4294967295"));
    /* Bad magic, bad version. */
    memcpy(big, all, size);
    big[3] = 'x';
    spit(q, big, size);
    r = read_all(q);
    CHECK(!r.open_ok && strstr(r.msg, "byte 0:"));
    memcpy(big, all, size);
    big[8] = 2;
    spit(q, big, size);
    r = read_all(q);
    CHECK(!r.open_ok && strstr(r.msg, "byte 8: format version 2"));
    free(big);

    /* A zero-filled tail (power loss after the size grew): the complete records, then torn. */
    uint8_t *z = calloc(size + 300, 1);
    memcpy(z, all, size);
    spit(q, z, size + 300);
    r = read_all(q);
    CHECK(r.rc == 0 && r.records == 12 && r.wrong == 0 && r.torn && r.torn_bytes == 300);
    free(z);
    free(all);
}

/* ---- SIGKILL: a writer killed at random moments loses at most its last record ----------------- */
static void test_sigkill(void)
{
    struct shared {
        _Atomic uint64_t confirmed; /* records whose append returned */
        _Atomic int ready;
    };
    struct shared *sh = mmap(NULL, sizeof *sh, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    CHECK(sh != MAP_FAILED);
    if (sh == MAP_FAILED)
        return;
    srand(12345);
    const int runs = 20;
    int bad = 0, torn_tails = 0;
    uint64_t total = 0, min_records = UINT64_MAX, max_records = 0;
    for (int run = 0; run < runs; ++run) {
        const char *p = tmp_path("kill.raw");
        unlink(p);
        atomic_store(&sh->confirmed, 0);
        atomic_store(&sh->ready, 0);
        pid_t pid = fork();
        if (pid == 0) {
            struct hl_error e;
            struct trk_recording *rec = trk_recording_create(p, TRK_DEVICE_RIFT_DK2, 0x2833, 0x0021, "kill", &e);
            if (!rec)
                _exit(2);
            atomic_store(&sh->ready, 1);
            uint8_t b[TRK_RECORDING_MAX_REPORT];
            for (uint64_t i = 0;; ++i) {
                gen_bytes(i, b, gen_len(i));
                if (trk_recording_append(rec, gen_time(i), b, gen_len(i), &e) != 0)
                    _exit(3);
                atomic_store(&sh->confirmed, i + 1);
            }
        }
        CHECK(pid > 0);
        while (!atomic_load(&sh->ready)) {
            int status;
            if (waitpid(pid, &status, WNOHANG) == pid) { /* the child failed before writing */
                ++bad;
                goto next;
            }
            struct timespec poll = {0, 100000};
            nanosleep(&poll, NULL);
        }
        {
            long ms = 1 + rand() % 30;
            struct timespec ts = {0, ms * 1000000L};
            nanosleep(&ts, NULL);
            kill(pid, SIGKILL);
            int status;
            waitpid(pid, &status, 0);
            CHECK(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
            uint64_t confirmed = atomic_load(&sh->confirmed);
            struct read_result r = read_all(p);
            /* All confirmed records are there and intact; at most one more (written, not yet
             * confirmed) and at most one torn record after them. */
            int ok = r.open_ok && r.rc == 0 && r.wrong == 0 && r.records >= confirmed && r.records <= confirmed + 1;
            if (!ok) {
                ++bad;
                fprintf(stderr, "sigkill run %d: confirmed %llu, read %llu, wrong %llu, rc %d %s\n", run,
                        (unsigned long long)confirmed, (unsigned long long)r.records, (unsigned long long)r.wrong,
                        r.rc, r.msg);
            }
            torn_tails += r.torn;
            total += r.records;
            if (r.records < min_records)
                min_records = r.records;
            if (r.records > max_records)
                max_records = r.records;
        }
    next:;
    }
    CHECK(bad == 0);
    printf("sigkill: %d runs, %llu records read (%llu..%llu per run), %d torn tails, %d bad\n", runs,
           (unsigned long long)total, (unsigned long long)min_records, (unsigned long long)max_records, torn_tails,
           bad);
    munmap(sh, sizeof *sh);
}

/* ---- streams ---------------------------------------------------------------------------------- */
static void test_stream_basics(void)
{
    struct trk_stream s;
    trk_stream_init(&s, TRK_DEVICE_RIFT_DK2, NULL);
    struct trk_pose pose;
    trk_stream_pose(&s, 0.01, &pose);
    CHECK(pose.orientation.w == 1.0 && fabs(pose.time_s - 0.01) < 1e-12);
    uint8_t junk[10] = {0x0B};
    CHECK(trk_stream_feed(&s, junk, sizeof junk, 0, &err) == -1);
    CHECK(s.rejected == 1 && s.reports == 1 && s.samples == 0 && !s.has_sample);

    /* Still and upright, 1 kHz: tilt from gravity, time = device time. */
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    int fused = 0;
    for (int i = 0; i < 200; ++i) {
        struct trk_imu_sample x;
        memset(&x, 0, sizeof x);
        x.device_time_ns = 5000000000LL + i * 1000000LL;
        x.accel_mps2 = hl_v3(0, 9.80665, 0);
        x.orientation = hl_q_identity();
        x.has_gyro = x.has_accel = 1;
        uint8_t r[64];
        int len = trk_encoder_push(&enc, &x, r, sizeof r, &err);
        if (len > 0)
            fused += trk_stream_feed(&s, r, (size_t)len, 0, &err);
    }
    CHECK(fused == 200 && s.fused == 200);
    trk_stream_pose(&s, 0.02, &pose);
    CHECK_NEAR(pose.time_s, 5.199 + 0.02, 1e-9);
    CHECK(hl_q_angle_rad(pose.orientation, hl_q_identity()) < 1e-3);

    /* HDK: the on-device orientation is taken as is; ω rotates into the world frame. */
    trk_stream_init(&s, TRK_DEVICE_HDK, NULL);
    struct trk_imu_sample h;
    memset(&h, 0, sizeof h);
    h.orientation = hl_q_from_axis_angle(hl_v3(0, 1, 0), 0.5);
    h.gyro_radps = hl_v3(0, 1.0, 0); /* 1 rad/s about body +Y = world +Y here */
    h.has_gyro = h.has_orientation = 1;
    uint8_t r[32];
    int len = trk_hdk_encode(&h, 3, 0, 1, r, sizeof r, &err);
    CHECK(len > 0);
    CHECK(trk_stream_feed(&s, r, (size_t)len, 7000000000LL, &err) == 1);
    trk_stream_pose(&s, 0.0, &pose);
    CHECK(hl_q_angle_rad(pose.orientation, h.orientation) < 1e-3);
    CHECK_NEAR(pose.time_s, 7.0, 1e-9);
    CHECK_NEAR(pose.angular_velocity_radps.y, 1.0, 3e-3);
    trk_stream_pose(&s, 0.1, &pose);
    CHECK_NEAR(hl_q_angle_rad(pose.orientation, h.orientation), 0.1, 3e-3);
}

/* Feeds DK2 reports of a constant yaw rate (one sample each) from device time *t_ns; returns the
 * samples fused. */
static int feed_dk2(struct trk_stream *s, struct trk_encoder *enc, int64_t *t_ns, int count, double yaw_degps)
{
    int fused = 0;
    for (int i = 0; i < count; ++i) {
        struct trk_imu_sample x;
        memset(&x, 0, sizeof x);
        x.device_time_ns = *t_ns;
        x.gyro_radps = hl_v3(0, yaw_degps * HL_RAD_PER_DEG, 0);
        x.accel_mps2 = hl_v3(0, 9.80665, 0);
        x.orientation = hl_q_identity();
        x.has_gyro = x.has_accel = 1;
        *t_ns += 1000000;
        uint8_t r[64];
        int len = trk_encoder_push(enc, &x, r, sizeof r, &err);
        int k = len > 0 ? trk_stream_feed(s, r, (size_t)len, 0, &err) : 0;
        fused += k > 0 ? k : 0;
    }
    return fused;
}

/* Device counters that jump (docs/HARD_CASES.md "Faults"): back and staying back (the device
 * restarted its clock without re-enumerating) — resynchronised after TRK_STREAM_RESYNC_REPORTS
 * reports, times still increasing, counted; forward by 10 min — a gap the fusion clamps; forward by
 * 1 h on the DK2's 32-bit µs counter — modularly 11.6 min back, so the same resync. Output finite. */
static void test_counter_jumps(void)
{
    struct trk_stream s;
    trk_stream_init(&s, TRK_DEVICE_RIFT_DK2, NULL);
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t t = 5000000000LL;
    CHECK(feed_dk2(&s, &enc, &t, 200, 90.0) == 200);
    int64_t newest = s.newest_time_ns;
    hl_quatd q0 = s.fusion.orientation;

    /* Reset: the counter starts again at 1 ms. */
    struct trk_encoder enc2;
    trk_encoder_init(&enc2, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t t2 = 1000000;
    int fused = feed_dk2(&s, &enc2, &t2, 300, 90.0);
    CHECK(s.counter_resets == 1);
    CHECK(fused == 300 - TRK_STREAM_RESYNC_REPORTS);
    CHECK(s.parser.rift.n.backward == (uint64_t)TRK_STREAM_RESYNC_REPORTS); /* dropped, and said so */
    /* Continues 1 ms after the newest sample before the reset. */
    CHECK(s.newest_time_ns == newest + (int64_t)fused * 1000000);
    double turned_deg = hl_q_angle_rad(q0, s.fusion.orientation) * HL_DEG_PER_RAD;
    CHECK_NEAR(turned_deg, 90.0 * fused * 1e-3, 0.5); /* the first after the reset is 1 ms after the last: it turns too */
    printf("counter reset: %d of 300 samples fused after %d dropped, time %.3f s → %.3f s, turned %.2f deg\n", fused,
           TRK_STREAM_RESYNC_REPORTS, newest * 1e-9, s.newest_time_ns * 1e-9, turned_deg);

    /* Forward by 10 min: one clamped gap, no reset. */
    uint64_t gaps = s.fusion.stats.clamped_gaps;
    t2 += 600LL * 1000000000LL;
    newest = s.newest_time_ns;
    CHECK(feed_dk2(&s, &enc2, &t2, 50, 90.0) == 50);
    CHECK(s.fusion.stats.clamped_gaps == gaps + 1 && s.counter_resets == 1);
    CHECK(s.newest_time_ns > newest + 599LL * 1000000000LL);

    /* Forward by 1 h: past half the 32-bit µs range, read as a step back, then resynchronised. */
    t2 += 3600LL * 1000000000LL;
    newest = s.newest_time_ns;
    fused = feed_dk2(&s, &enc2, &t2, 100, 90.0);
    CHECK(s.counter_resets == 2 && fused == 100 - TRK_STREAM_RESYNC_REPORTS);
    CHECK(s.newest_time_ns > newest);
    struct trk_pose pose;
    trk_stream_pose(&s, 0.02, &pose);
    CHECK(isfinite(pose.time_s) && isfinite(pose.orientation.w) && fabs(hl_q_norm(pose.orientation) - 1.0) < 1e-9);

    /* A short run of stale reports (fewer than the threshold) is dropped, not a reset. */
    trk_stream_init(&s, TRK_DEVICE_RIFT_DK2, NULL);
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    t = 5000000000LL;
    CHECK(feed_dk2(&s, &enc, &t, 100, 0.0) == 100);
    int64_t back = 4000000000LL;
    trk_encoder_init(&enc2, TRK_DEVICE_RIFT_DK2, NULL);
    CHECK(feed_dk2(&s, &enc2, &back, TRK_STREAM_RESYNC_REPORTS - 1, 0.0) == 0);
    CHECK(feed_dk2(&s, &enc, &t, 10, 0.0) == 10 && s.counter_resets == 0);
}

/* ---- end to end on the shared IMU stream ------------------------------------------------------- */
static double tilt_err_rad(hl_quatd est, hl_quatd truth)
{
    hl_vec3d y = hl_v3(0, 1, 0);
    return hl_v3_angle_rad(hl_q_rotate(hl_q_conj(est), y), hl_q_rotate(hl_q_conj(truth), y));
}

static int run_program(char *const argv[], const char *quiet_out)
{
    pid_t pid = fork();
    if (pid == 0) {
        int fd = open(quiet_out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
        }
        /* Under ASan LeakSanitizer stays on in the child: hmdlod pins the GL driver that would
         * otherwise read as leaking (render/gl_driver_pin.c, PLATFORM.md §4). */
        execv(argv[0], argv);
        _exit(127);
    }
    int status;
    if (pid < 0 || waitpid(pid, &status, 0) != pid || !WIFEXITED(status))
        return -1;
    return WEXITSTATUS(status);
}

static void test_end_to_end(void)
{
    const char *csv = tu_shared_path("data/imu/corbillon_user1_t30.csv");
    if (!csv)
        return;
    struct trk_imu_csv_row *rows;
    size_t count;
    if (trk_imu_csv_read(csv, &rows, &count, &err) != 0) {
        fprintf(stderr, "%s\n", err.msg);
        CHECK(0);
        return;
    }
    const size_t n = count < 10000 ? count : 10000; /* the first 10 s at 1 kHz */
    const char *raw = tmp_path("user1-dk2.raw");
    struct trk_recording *rec = trk_recording_create(raw, TRK_DEVICE_RIFT_DK2, 0x2833, 0x0021, "Rift DK2 (sim)", &err);
    CHECK(rec != NULL);
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_RIFT_DK2, NULL);
    int64_t t0_ns = 123456789000LL; /* a device clock that does not start at 0 */
    size_t reports = 0;
    for (size_t k = 0; k < n && rec; ++k) {
        struct trk_imu_sample x;
        memset(&x, 0, sizeof x);
        x.device_time_ns = t0_ns + (int64_t)llround(rows[k].t_s * 1e9);
        x.gyro_radps = rows[k].gyro_radps;
        x.accel_mps2 = rows[k].accel_mps2;
        x.orientation = hl_q_identity();
        x.has_gyro = x.has_accel = 1;
        uint8_t r[64];
        int len = trk_encoder_push(&enc, &x, r, sizeof r, &err);
        CHECK(len >= 0);
        /* Host receive time: the sample time plus a USB delay that varies 0.5–1.5 ms. */
        if (len > 0 && trk_recording_append(rec, x.device_time_ns + 500000 + (int64_t)(k * 7919 % 1000) * 1000,
                                            r, (size_t)len, &err) == 0)
            ++reports;
    }
    CHECK(trk_recording_close(rec, 0, &err) == 0);
    CHECK(reports == n);

    struct rpl_trace tr;
    int rc = rpl_trace_from_recording(raw, &tr, &err);
    CHECK(rc == 0);
    if (rc != 0) {
        fprintf(stderr, "%s\n", err.msg);
        trk_imu_csv_free(rows);
        return;
    }
    /* One row per report (DK2 at its native 1 sample per report), at the device time from 0. */
    CHECK(tr.count == n);
    CHECK(tr.time_s[0] == 0.0);
    double sum2 = 0, maxe = 0;
    size_t m = 0, time_bad = 0;
    for (size_t i = 0; i < tr.count && i < n; ++i) {
        if (fabs(tr.time_s[i] - rows[i].t_s) > 1e-6)
            ++time_bad;
        if (rows[i].t_s < 2.0)
            continue;
        double e = tilt_err_rad(tr.orientation[i], rows[i].truth) * HL_DEG_PER_RAD;
        sum2 += e * e;
        maxe = e > maxe ? e : maxe;
        ++m;
    }
    double rms = m ? sqrt(sum2 / (double)m) : 1e9;
    /* The recording path is the live path: the same samples fed straight to a fusion (no reports,
     * no file) give the same orientations — up to the rounding of the device-time offset. */
    struct trk_fusion *f = malloc(sizeof *f);
    trk_fusion_init(f, NULL);
    double max_diff = 0;
    for (size_t k = 0; k < n && k < tr.count; ++k) {
        trk_fusion_update(f, rows[k].t_s, rows[k].gyro_radps, rows[k].accel_mps2, 1);
        double d = hl_q_angle_rad(f->orientation, tr.orientation[k]);
        max_diff = d > max_diff ? d : max_diff;
    }
    free(f);
    printf("end to end: largest difference from fusing the CSV rows directly: %.3g°\n", max_diff * HL_DEG_PER_RAD);
    CHECK(max_diff < 1e-6);
    printf("end to end: user1 t30, 10 s as %zu Rift DK2 reports → recording → trace: tilt error after 2 s "
           "RMS %.3f°, max %.3f° (cold start)\n",
           reports, rms, maxe);
    CHECK(time_bad == 0);
    /* Tolerance 1°: the fusion's goal on these streams (tests/test_fusion.c, ≤ 1° tilt RMS), which
     * the DK2 encoding cannot spoil — its 1e-4 LSB is the CSV's own quantization, so the reports
     * carry the same numbers. The first 2 s are left out: a cold start takes its tilt from the first
     * accel sample, which the ±20 mg accel bias and the lever arm put off by up to ~1.5°. */
    CHECK(rms < 1.0);

    /* CSV round trip: times to the printed ns, orientations to %.17g (renormalised on load). */
    const char *out_csv = tmp_path("user1-dk2.csv");
    CHECK(rpl_trace_write_csv(&tr, out_csv, &err) == 0);
    struct rpl_trace back;
    rc = rpl_trace_load(out_csv, &back, &err);
    CHECK(rc == 0);
    if (rc == 0) {
        CHECK(back.count == tr.count);
        size_t bad = 0;
        for (size_t i = 0; i < back.count && i < tr.count; ++i)
            if (fabs(back.time_s[i] - tr.time_s[i]) > 0.6e-9 || hl_q_dot(back.orientation[i], tr.orientation[i]) <= 0 ||
                hl_q_angle_rad(back.orientation[i], tr.orientation[i]) > 1e-9)
                ++bad;
        CHECK(bad == 0);
        rpl_trace_free(&back);
    }
    /* Atomic write: a failure leaves nothing behind. */
    CHECK(rpl_trace_write_csv(&tr, tmp_path("no-dir/x.csv"), &err) == -1 && strstr(err.msg, "no-dir/x.csv"));

    /* A torn recording converts all its complete records, with the same result. */
    size_t size;
    uint8_t *all = (uint8_t *)tu_read_file(raw, &size);
    const char *torn = tmp_path("torn.raw");
    spit(torn, all, size - 30);
    free(all);
    struct rpl_trace tt;
    CHECK(rpl_trace_from_recording(torn, &tt, &err) == 0);
    if (tt.count) {
        CHECK(tt.count == tr.count - 1);
        CHECK(!memcmp(&tt.orientation[tt.count - 1], &tr.orientation[tt.count - 1], sizeof(hl_quatd)));
        rpl_trace_free(&tt);
    }
    rpl_trace_free(&tr);
    trk_imu_csv_free(rows);

    /* Through the program. */
    const char *bin = getenv("HMDLOD_BIN");
    if (!bin || access(bin, X_OK) != 0) {
        printf("skip: HMDLOD_BIN is unset or not built; the program-level checks were not run\n");
        return;
    }
    /* tmp_path's buffers rotate: keep each path the child needs in its own array. */
    char raw_p[512], conv_p[512], log_p[512], out_p[512], bad_p[512];
    snprintf(raw_p, sizeof raw_p, "%s", raw);
    snprintf(conv_p, sizeof conv_p, "%s", tmp_path("conv.csv"));
    snprintf(log_p, sizeof log_p, "%s", tmp_path("program.log"));
    snprintf(out_p, sizeof out_p, "%s", tmp_path("replay-out"));
    snprintf(bad_p, sizeof bad_p, "%s", tmp_path("bad.csv"));
    char *conv[] = {(char *)bin, "convert", raw_p, "--to", conv_p, NULL};
    CHECK(run_program(conv, log_p) == 0);
    CHECK(rpl_trace_load(conv_p, &back, &err) == 0 && back.count == n);
    rpl_trace_free(&back);
    char *rep[] = {(char *)bin, "replay", "--raw", raw_p, "--scene", "field", "--display", "vive",
                   "--selector", "reddy", "--frames", "30", "--render-scale", "0.25", "--quiet",
                   "--out", out_p, NULL};
    CHECK(run_program(rep, log_p) == 0);
    struct stat st;
    CHECK(stat(tmp_path("replay-out/frames.csv"), &st) == 0 && st.st_size > 0);
    CHECK(stat(tmp_path("replay-out/summary.json"), &st) == 0 && st.st_size > 0);
    /* A CSV is no recording: exit 1 and no output. */
    char *bad[] = {(char *)bin, "convert", conv_p, "--to", bad_p, NULL};
    CHECK(run_program(bad, log_p) == 1);
    CHECK(access(bad_p, F_OK) != 0);
}

/* Writes an HDK recording (the HDK's sample time is the host arrival time) of one report per time. */
static int write_hdk(const char *path, const int64_t *times, int count)
{
    struct trk_recording *rec = trk_recording_create(path, TRK_DEVICE_HDK, 0x1532, 0x0b00, "HDK test", &err);
    if (!rec)
        return -1;
    struct trk_encoder enc;
    trk_encoder_init(&enc, TRK_DEVICE_HDK, NULL);
    int written = 0;
    for (int64_t t = 0; written < count && t < 1000000000; t += 1000000) {
        struct trk_imu_sample s;
        memset(&s, 0, sizeof s);
        s.device_time_ns = t;
        s.orientation = hl_q_from_axis_angle(hl_v3(0, 1, 0), 0.01 * written);
        s.has_orientation = 1;
        uint8_t b[64];
        int len = trk_encoder_push(&enc, &s, b, sizeof b, &err);
        if (len < 0)
            return -1;
        if (len > 0 && trk_recording_append(rec, times[written++], b, (size_t)len, &err) != 0)
            return -1;
    }
    return trk_recording_close(rec, 1, &err);
}

/* Host times at the ends of int64: their difference is an error naming the file and record, never a
 * wrapped (negative) time that would silently drop the row; near INT64_MAX they still work. */
static void test_host_time_extremes(void)
{
    const char *path = tmp_path("hdk_extreme.raw");
    const int64_t apart[2] = {INT64_MIN + 1000, INT64_MAX - 1000};
    CHECK(write_hdk(path, apart, 2) == 0);
    struct rpl_trace tr;
    memset(&err, 0, sizeof err);
    CHECK(rpl_trace_from_recording(path, &tr, &err) == -1 && strstr(err.msg, "hdk_extreme.raw: record 2:") &&
          strstr(err.msg, "int64"));

    const char *late = tmp_path("hdk_late.raw");
    const int64_t near_max[3] = {INT64_MAX - 2000000, INT64_MAX - 1000000, INT64_MAX};
    CHECK(write_hdk(late, near_max, 3) == 0);
    int rc = rpl_trace_from_recording(late, &tr, &err);
    CHECK(rc == 0 && tr.count == 3);
    if (rc == 0) {
        CHECK_NEAR(tr.time_s[2] - tr.time_s[0], 0.002, 1e-12);
        rpl_trace_free(&tr);
    } else {
        fprintf(stderr, "%s\n", err.msg);
    }
}

int main(int argc, char **argv)
{
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    if (argc > 1 && strcmp(argv[1], "hard-cases") == 0) { /* ctest -L hard-cases */
        test_host_time_extremes();
        test_truncation();
        test_counter_jumps();
    } else {
        test_host_time_extremes();
        test_crc_and_round_trip();
        test_truncation();
        test_corruption();
        test_sigkill();
        test_stream_basics();
        test_counter_jumps();
        test_end_to_end();
    }
    if (tu_failures == 0) {
        char cmd[600];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
        if (system(cmd) != 0)
            fprintf(stderr, "could not remove %s\n", dir);
    } else {
        printf("outputs kept in %s\n", dir);
    }
    return tu_finish("test_recording");
}
