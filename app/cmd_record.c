/* hmdlod record: raw reports from a head tracker into a raw recording (docs/raw-recording.md), so a
 * session can be replayed (hmdlod replay --raw) or converted (hmdlod convert) later, through this
 * fusion or a better one. The reports are stored as received; nothing is parsed on the way. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "app/commands.h"
#include "tracking/tracking.h"

static const char record_usage[] =
    "usage: hmdlod record --device auto|PATH --out FILE [--seconds S]\n"
    "  Records a head tracker's raw HID reports, each with its host receive time and a CRC, into an\n"
    "  append-only raw recording. Stops on Ctrl-C (SIGINT), SIGTERM or after S seconds, then closes\n"
    "  the file (fsync) and prints the counts. Killed outright, the file keeps every report written\n"
    "  but the last one, which readers report as a torn tail.\n"
    "  --device auto|PATH  the first supported tracker (auto, the default) or a hidraw node\n"
    "  --out FILE          the recording to write (replaced if it exists)\n"
    "  --seconds S         stop after S seconds (default: until interrupted)\n";

static volatile sig_atomic_t stop_requested;
static void on_signal(int sig) { stop_requested = sig; }

/* ---- the device part: open, read one report, close ----------------------------------------- */
struct record_device {
    struct trk_hid_device *hid;
    enum trk_device_kind kind;
    uint16_t vid, pid;
    char name[128];
    size_t report_size;
};

static int record_device_open(const char *path_or_auto, struct record_device *d, struct hl_error *err)
{
    memset(d, 0, sizeof *d);
    if (trk_hid_open(path_or_auto, &d->hid, err) != 0)
        return -1;
    const struct trk_device_info *info = trk_hid_info(d->hid);
    const struct trk_hid_device_desc *desc = trk_hid_desc(d->hid);
    d->kind = info->kind;
    d->vid = desc->vid;
    d->pid = desc->pid;
    d->report_size = info->report_size ? info->report_size : 64;
    snprintf(d->name, sizeof d->name, "%s%s%s", info->name, desc->serial[0] ? " " : "", desc->serial);
    if (trk_hid_send_start(d->hid, err) != 0 || trk_hid_drain(d->hid, err) < 0) {
        trk_hid_close(d->hid);
        d->hid = NULL;
        return -1;
    }
    return 0;
}

/* One report: its length, 0 on timeout, −1 with err when the device is gone. Sends keep-alives. */
static int record_device_read(struct record_device *d, uint8_t *buf, size_t cap, int64_t *host_ns,
                              struct hl_error *err)
{
    if (trk_hid_keepalive(d->hid, hl_clock_now_ns(), err) < 0)
        return -1;
    return trk_hid_read(d->hid, buf, cap < d->report_size ? cap : d->report_size, 100, host_ns, err);
}

static void record_device_close(struct record_device *d)
{
    trk_hid_close(d->hid);
    d->hid = NULL;
}

/* ---- the command ----------------------------------------------------------------------------- */
int cmd_record(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(record_usage, stdout);
        return 0;
    }
    const char *device = "auto", *out = NULL;
    double seconds = 0.0;
    for (int i = 1; i < argc; ++i) {
        const char *opt = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!val) {
            fprintf(stderr, "hmdlod: %s needs a value\n", opt);
            return 1;
        }
        ++i;
        if (!strcmp(opt, "--device"))
            device = val;
        else if (!strcmp(opt, "--out"))
            out = val;
        else if (!strcmp(opt, "--seconds")) {
            if (app_parse_double(opt, val, &seconds) != 0)
                return 1;
            if (!(seconds > 0) || !(seconds <= 1e9)) { /* 31 years: the deadline in ns fits int64 */
                fprintf(stderr, "hmdlod: --seconds: %s is not a positive duration of at most 1e9 s\n", val);
                return 1;
            }
        } else {
            fprintf(stderr, "hmdlod: unknown option '%s'\n%s", opt, record_usage);
            return 1;
        }
    }
    if (!out) {
        fprintf(stderr, "hmdlod record: --out FILE is required\n%s", record_usage);
        return 1;
    }

    struct hl_error err;
    struct record_device dev;
    if (record_device_open(device, &dev, &err) != 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        return 1;
    }
    struct trk_recording *rec = trk_recording_create(out, dev.kind, dev.vid, dev.pid, dev.name, &err);
    if (!rec) {
        record_device_close(&dev);
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        return 1;
    }
    /* No SA_RESTART: a blocked read returns at once on Ctrl-C instead of at its timeout. */
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);

    printf("recording %s (%04x:%04x) to %s%s\n", dev.name, dev.vid, dev.pid, out,
           seconds > 0 ? "" : " until Ctrl-C");
    int64_t start_ns = hl_clock_now_ns(), deadline_ns = start_ns + (int64_t)(seconds * 1e9);
    uint64_t bytes = 0;
    int failed = 0;
    char lost[sizeof err.msg] = "";
    uint8_t buf[TRK_RECORDING_MAX_REPORT];
    int64_t last_report_ns = start_ns;
    int silent = 0;
    while (!stop_requested && (seconds <= 0 || hl_clock_now_ns() < deadline_ns)) {
        int64_t host_ns = 0;
        int n = record_device_read(&dev, buf, sizeof buf, &host_ns, &err);
        if (n < 0) {
            if (stop_requested)
                break; /* the read was interrupted by the signal, not a device failure */
            snprintf(lost, sizeof lost, "%s", err.msg); /* unplugged or read error: keep what we have */
            break;
        }
        if (n == 0) {
            /* Silence is said once, as the live source says it (tracking/hid.h), and recording goes on. */
            if (!silent && hl_clock_now_ns() - last_report_ns > 1000000000LL) {
                fprintf(stderr, "hmdlod: %s: no reports for 1000 ms (still recording)\n", dev.name);
                silent = 1;
            }
            continue;
        }
        if (silent)
            fprintf(stderr, "hmdlod: %s: reports again after %.0f ms\n", dev.name, (double)(host_ns - last_report_ns) * 1e-6);
        silent = 0;
        last_report_ns = host_ns;
        if (trk_recording_append(rec, host_ns, buf, (size_t)n, &err) != 0) {
            fprintf(stderr, "hmdlod: %s\n", err.msg);
            failed = 1;
            break;
        }
        bytes += (uint64_t)n;
    }
    uint64_t records = trk_recording_records(rec);
    record_device_close(&dev);
    if (trk_recording_close(rec, 1, &err) != 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        failed = 1;
    }
    double elapsed_s = (double)(hl_clock_now_ns() - start_ns) * 1e-9;
    if (records == 0 && !failed) {
        unlink(out); /* a recording of nothing would only look like one */
        fprintf(stderr, "hmdlod: no report arrived in %.1f s%s%s; %s not written\n", elapsed_s,
                lost[0] ? ": " : "", lost, out);
        return 1;
    }
    printf("recorded %llu reports (%llu report bytes) in %.1f s, %.0f reports/s, to %s\n",
           (unsigned long long)records, (unsigned long long)bytes, elapsed_s,
           elapsed_s > 0 ? (double)records / elapsed_s : 0.0, out);
    if (lost[0]) {
        fprintf(stderr, "hmdlod: the device was lost: %s (the recording holds everything before)\n", lost);
        return 1;
    }
    return failed;
}
