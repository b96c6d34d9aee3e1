/* The live pose source of a head tracker (tracking/hid.h): a reader thread owns the device, reads
 * reports with a short timeout, feeds a trk_stream and sends keep-alives itself — DEVICES.md §4:
 * a starved or render-driven reader misses the Rift's 10 s watchdog (thaytan/OpenHMD #33) and
 * OpenHMD only advanced poses when the app called update (godot_openhmd #13). On unplug it keeps the
 * last orientation without prediction and reopens the device when udev adds it again (§3: neither
 * open driver does; the "hmdlod target" paragraph is what this file implements). */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tracking/hid_internal.h"

#define READ_TIMEOUT_MS 20                  /* bounds stop latency and keep-alive jitter */
#define HOTPLUG_CHECK_NS 20000000LL         /* look at udev events every 20 ms while streaming */
#define SILENCE_MS 1000                     /* no report for 1 s while open: LOST (keep trying); noticed
                                             * within SILENCE_MS + READ_TIMEOUT_MS (tracking/hid.h) */
#define SILENCE_NS (SILENCE_MS * 1000000LL)
#define LOST_POLL_MS 100                    /* wait for udev events this long per loop while lost */
#define RESCAN_FAST_NS 50000000LL           /* after an add event: retry opening every 50 ms … */
#define RESCAN_FAST_WINDOW_NS 5000000000LL  /* … for 5 s: the event may come before the device is
                                             * complete (umockdev adds the sysfs tree piecewise) or
                                             * usable (permissions, driver binding) */
#define RESCAN_SLOW_NS 2000000000LL         /* otherwise every 2 s, in case an event was missed */
#define DEFAULT_MAX_PREDICTION_S 0.040      /* tracking/hid.h: constant-rate prediction good to ~40 ms */
#define MAX_SCAN 16

struct tracker_source {
    struct trk_pose_source base; /* first: the interface pointer is this struct's address */
    char want[TRK_HID_PATH_SIZE];
    char name[TRK_HID_PATH_SIZE + 80];
    double max_prediction_s;
    struct trk_hotplug hotplug;
    int has_hotplug;
    char hotplug_note[200];

    pthread_t thread;
    int thread_started;
    atomic_int stop_flag;

    /* Identity to reopen, set by start. */
    const struct trk_device_info *info;
    char serial[TRK_HID_STRING_SIZE];

    /* Owned by the reader thread (by start/stop while it is not running). */
    struct trk_hid_device *dev;
    int64_t last_report_ns, next_hotplug_check_ns, next_scan_ns, fast_scan_until_ns;
    struct trk_hid_device_desc scan[MAX_SCAN];

    pthread_mutex_t mu; /* guards everything below */
    struct trk_stream stream;
    int has_pose;          /* the stream has fused a sample since it was (re)initialised */
    double newest_host_s;  /* host receive time of the newest fed report */
    enum trk_health health;
    char reason[TRK_HID_WHY_SIZE + 128];
    struct trk_pose frozen; /* last pose before the loss, angular velocity zeroed */
    int has_frozen;
    struct trk_tracker_stats stats;
    struct trk_recording *recording; /* trk_tracker_source_record: every report read, as read */
    int recording_failed;
    char recording_error[sizeof(struct hl_error)];
};

static struct tracker_source *from_base(struct trk_pose_source *src) { return (struct tracker_source *)src; }

static void set_state_locked(struct tracker_source *s, enum trk_health h, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static void set_state_locked(struct tracker_source *s, enum trk_health h, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(s->reason, sizeof s->reason, fmt, ap);
    va_end(ap);
    s->health = h;
}

/* Keep the orientation, stop predicting: angular velocity zero (§3 "hmdlod target"). */
static void freeze_locked(struct tracker_source *s)
{
    if (!s->has_pose)
        return;
    trk_stream_pose(&s->stream, 0.0, &s->frozen);
    s->frozen.angular_velocity_radps = hl_v3(0, 0, 0);
    s->has_frozen = 1;
}

static void lose(struct tracker_source *s, const char *why)
{
    trk_hid_close(s->dev);
    s->dev = NULL;
    int64_t now = hl_clock_now_ns();
    /* No immediate rescan: the node may linger until udev finishes removing it. Then slow rescans
     * only; an add event speeds them up. */
    s->next_scan_ns = now + RESCAN_SLOW_NS / 4;
    s->fast_scan_until_ns = now;
    pthread_mutex_lock(&s->mu);
    freeze_locked(s);
    s->has_pose = 0;
    s->stats.disconnects++;
    s->stats.connected = 0;
    set_state_locked(s, TRK_HEALTH_LOST, "%s lost: %s; holding the last orientation, waiting for it to come back%s",
                     s->info->name, why, s->hotplug_note);
    pthread_mutex_unlock(&s->mu);
}

/* Start reports, stale reports out, a fresh stream (its timestamp unwrapping and fusion start-up
 * belong to the previous connection). Takes ownership of dev; 0, or −1 with err (dev closed). */
static int begin_streaming(struct tracker_source *s, struct trk_hid_device *dev, int reconnect, struct hl_error *err)
{
    if (trk_hid_send_start(dev, err) != 0) {
        trk_hid_close(dev);
        return -1;
    }
    int dropped = trk_hid_drain(dev, err);
    if (dropped < 0) {
        trk_hid_close(dev);
        return -1;
    }
    s->dev = dev;
    s->last_report_ns = hl_clock_now_ns();
    s->next_hotplug_check_ns = s->last_report_ns;
    pthread_mutex_lock(&s->mu);
    trk_stream_init(&s->stream, s->info->kind, NULL);
    s->has_pose = 0;
    s->stats.drained += (uint64_t)dropped;
    s->stats.connected = 1;
    if (reconnect)
        s->stats.reconnects++;
    snprintf(s->stats.path, sizeof s->stats.path, "%s", trk_hid_desc(dev)->path);
    set_state_locked(s, TRK_HEALTH_LOST, "%s %s at %s: waiting for its first report", s->info->name,
                     reconnect ? "reopened" : "opened", trk_hid_desc(dev)->path);
    pthread_mutex_unlock(&s->mu);
    return 0;
}

static int matches_identity(const struct tracker_source *s, const struct trk_hid_device_desc *d)
{
    if (d->info->role != TRK_ROLE_IMU || d->info->kind != s->info->kind)
        return 0;
    return !s->serial[0] || !d->serial[0] || !strcmp(s->serial, d->serial);
}

static void try_reopen(struct tracker_source *s, int64_t now)
{
    struct hl_error err;
    s->next_scan_ns = now + (now < s->fast_scan_until_ns ? RESCAN_FAST_NS : RESCAN_SLOW_NS);
    int n = trk_hid_enumerate(s->scan, MAX_SCAN, &err);
    for (int i = 0; i < n; ++i) {
        const struct trk_hid_device_desc *d = &s->scan[i];
        if (!matches_identity(s, d))
            continue;
        struct trk_hid_device *dev = NULL;
        if (!d->can_open || trk_hid_open_desc(d, &dev, &err) != 0 || begin_streaming(s, dev, 1, &err) != 0) {
            pthread_mutex_lock(&s->mu);
            set_state_locked(s, TRK_HEALTH_LOST, "%s is back at %s but cannot be used yet: %s (retrying)",
                             s->info->name, d->path, d->can_open ? err.msg : d->why);
            pthread_mutex_unlock(&s->mu);
            continue;
        }
        return;
    }
}

static void lost_step(struct tracker_source *s)
{
    struct trk_hotplug_event ev;
    /* Sleep until an event, the next scheduled scan or LOST_POLL_MS (stop latency), whichever first. */
    int64_t wait_ms = (s->next_scan_ns - hl_clock_now_ns()) / 1000000;
    wait_ms = wait_ms < 0 ? 0 : wait_ms > LOST_POLL_MS ? LOST_POLL_MS : wait_ms;
    if (s->has_hotplug) {
        trk_hotplug_poll(&s->hotplug, (int)wait_ms);
    } else {
        struct timespec ts = {0, (long)wait_ms * 1000000L};
        nanosleep(&ts, NULL);
    }
    int64_t now = hl_clock_now_ns();
    while (s->has_hotplug && trk_hotplug_next_event(&s->hotplug, &ev) == 1) {
        if (ev.action == TRK_HOTPLUG_ADD && (!ev.info || (ev.info->kind == s->info->kind && ev.info->role == TRK_ROLE_IMU))) {
            s->next_scan_ns = now;
            s->fast_scan_until_ns = now + RESCAN_FAST_WINDOW_NS;
        }
    }
    if (now >= s->next_scan_ns && !atomic_load(&s->stop_flag))
        try_reopen(s, now);
}

static void streaming_step(struct tracker_source *s, uint8_t *buf, size_t cap)
{
    struct hl_error err;
    int64_t now = hl_clock_now_ns();
    int k = trk_hid_keepalive(s->dev, now, &err);
    if (k < 0) {
        lose(s, err.msg);
        return;
    }
    int64_t host_ns = 0;
    int n = trk_hid_read(s->dev, buf, cap, READ_TIMEOUT_MS, &host_ns, &err);
    if (n < 0) {
        lose(s, err.msg);
        return;
    }
    pthread_mutex_lock(&s->mu);
    s->stats.keepalives += (uint64_t)k;
    if (n > 0) {
        struct hl_error ferr;
        s->last_report_ns = host_ns;
        s->stats.reports++;
        if (s->recording && !s->recording_failed) {
            /* Before parsing: a raw recording keeps what the device sent, rejected reports too. */
            struct hl_error rerr;
            if (trk_recording_append(s->recording, host_ns, buf, (size_t)n, &rerr) != 0) {
                s->recording_failed = 1;
                snprintf(s->recording_error, sizeof s->recording_error, "%s", rerr.msg);
            } else {
                s->stats.recorded++;
            }
        }
        int fused = trk_stream_feed(&s->stream, buf, (size_t)n, host_ns, &ferr);
        if (fused < 0) {
            s->stats.rejected++; /* one bad report is not a lost device; counted for status */
        } else {
            s->stats.samples_fused += (uint64_t)fused;
            s->newest_host_s = (double)host_ns * 1e-9;
            if (s->stream.has_sample)
                s->has_pose = 1;
            if (s->has_pose && s->health != TRK_HEALTH_OK)
                set_state_locked(s, TRK_HEALTH_OK, "%s streaming from %s", s->info->name, trk_hid_desc(s->dev)->path);
        }
    } else if (host_ns - s->last_report_ns > SILENCE_NS && s->health == TRK_HEALTH_OK) {
        freeze_locked(s);
        s->has_pose = 0; /* OK again with the next fused report */
        s->stats.stalls++;
        set_state_locked(s, TRK_HEALTH_LOST, "%s at %s: no reports for %d ms (keep-alive not honoured?); "
                         "holding the last orientation, no prediction", s->info->name, trk_hid_desc(s->dev)->path,
                         SILENCE_MS);
    }
    pthread_mutex_unlock(&s->mu);

    if (s->has_hotplug && host_ns >= s->next_hotplug_check_ns) {
        s->next_hotplug_check_ns = host_ns + HOTPLUG_CHECK_NS;
        struct trk_hotplug_event ev;
        while (s->dev && trk_hotplug_next_event(&s->hotplug, &ev) == 1) {
            /* The remove uevent may come before the read fails (or instead of it). */
            if (ev.action == TRK_HOTPLUG_REMOVE && !strcmp(ev.devnode, trk_hid_desc(s->dev)->path)) {
                char why[TRK_HID_PATH_SIZE + 32];
                snprintf(why, sizeof why, "unplugged (udev removed %s)", ev.devnode);
                lose(s, why);
            }
        }
    }
}

static void *reader_main(void *arg)
{
    struct tracker_source *s = arg;
    uint8_t buf[64]; /* every supported report is ≤ 64 B (DEVICES.md §2a); no allocation per report */
    size_t cap = s->info->report_size && s->info->report_size <= sizeof buf ? s->info->report_size : sizeof buf;
    while (!atomic_load(&s->stop_flag)) {
        if (s->dev)
            streaming_step(s, buf, cap);
        else
            lost_step(s);
    }
    return NULL;
}

static int src_start(struct trk_pose_source *src, struct hl_error *err)
{
    struct tracker_source *s = from_base(src);
    if (s->thread_started)
        return 0;
    struct trk_hid_device *dev = NULL;
    if (trk_hid_open(s->want, &dev, err) != 0)
        return -1;
    const struct trk_hid_device_desc *d = trk_hid_desc(dev);
    if (d->info->role != TRK_ROLE_IMU) {
        hl_fail(err, "%s is the %s, which gives no head motion: pick the IMU interface (hmdlod devices)", d->path,
                d->info->name);
        trk_hid_close(dev);
        return -1;
    }
    s->info = d->info;
    snprintf(s->serial, sizeof s->serial, "%s", d->serial);
    snprintf(s->name, sizeof s->name, "%.60s (%s)", d->info->name, d->path);
    if (begin_streaming(s, dev, 0, err) != 0)
        return -1;
    atomic_store(&s->stop_flag, 0);
    int rc = pthread_create(&s->thread, NULL, reader_main, s);
    if (rc != 0) {
        trk_hid_close(s->dev);
        s->dev = NULL;
        return hl_fail(err, "%s: cannot start the reader thread: %s", s->name, strerror(rc));
    }
    s->thread_started = 1;
    return 0;
}

static void src_stop(struct trk_pose_source *src)
{
    struct tracker_source *s = from_base(src);
    if (!s->thread_started)
        return;
    atomic_store(&s->stop_flag, 1);
    pthread_join(s->thread, NULL);
    s->thread_started = 0;
    trk_hid_close(s->dev);
    s->dev = NULL;
    pthread_mutex_lock(&s->mu);
    freeze_locked(s);
    s->has_pose = 0;
    s->stats.connected = 0;
    set_state_locked(s, TRK_HEALTH_LOST, "%s: stopped", s->name);
    pthread_mutex_unlock(&s->mu);
}

static int src_pose_at(struct trk_pose_source *src, double time_s, struct trk_pose *out, struct hl_error *err)
{
    struct tracker_source *s = from_base(src);
    if (!isfinite(time_s))
        return hl_fail(err, "%s: pose requested for a non-finite time", s->name);
    pthread_mutex_lock(&s->mu);
    if (s->health == TRK_HEALTH_OK && s->has_pose) {
        double horizon = time_s - s->newest_host_s;
        if (horizon < 0)
            horizon = 0; /* asked for the past: the newest pose is as close as we have */
        if (horizon > s->max_prediction_s)
            horizon = s->max_prediction_s;
        trk_stream_pose(&s->stream, horizon, out);
    } else if (s->has_frozen) {
        *out = s->frozen;
    } else {
        trk_pose_init_still(out, time_s);
    }
    pthread_mutex_unlock(&s->mu);
    out->time_s = time_s;
    return 0;
}

static enum trk_health src_health(struct trk_pose_source *src, char *reason, size_t reason_size)
{
    struct tracker_source *s = from_base(src);
    pthread_mutex_lock(&s->mu);
    enum trk_health h = s->health;
    if (reason && reason_size)
        snprintf(reason, reason_size, "%s", s->reason);
    pthread_mutex_unlock(&s->mu);
    return h;
}

static void src_destroy(struct trk_pose_source *src)
{
    struct tracker_source *s = from_base(src);
    src_stop(src);
    if (s->recording) {
        struct hl_error err;
        trk_recording_close(s->recording, 1, &err);
    }
    trk_hotplug_destroy(&s->hotplug);
    pthread_mutex_destroy(&s->mu);
    free(s);
}

int trk_tracker_source_create(const char *path_or_auto, double max_prediction_s, struct trk_pose_source **out,
                              struct hl_error *err)
{
    *out = NULL;
    if (!isfinite(max_prediction_s))
        return hl_fail(err, "tracker: prediction limit is not a number");
    struct tracker_source *s = calloc(1, sizeof *s);
    if (!s)
        return hl_fail(err, "tracker: out of memory");
    snprintf(s->want, sizeof s->want, "%s", path_or_auto && path_or_auto[0] ? path_or_auto : "auto");
    snprintf(s->name, sizeof s->name, "head tracker (%s)", s->want);
    s->max_prediction_s = max_prediction_s > 0 ? max_prediction_s : DEFAULT_MAX_PREDICTION_S;
    struct hl_error herr;
    if (trk_hotplug_init(&s->hotplug, &herr) == 0) {
        s->has_hotplug = 1;
    } else {
        /* Not fatal: the thread rescans every 2 s instead of waiting for events. */
        snprintf(s->hotplug_note, sizeof s->hotplug_note, " (%.120s; rescanning every %.0f s)", herr.msg,
                 RESCAN_SLOW_NS * 1e-9);
    }
    pthread_mutex_init(&s->mu, NULL);
    atomic_init(&s->stop_flag, 0);
    s->health = TRK_HEALTH_LOST;
    snprintf(s->reason, sizeof s->reason, "not started");
    s->base.name = s->name;
    s->base.start = src_start;
    s->base.stop = src_stop;
    s->base.pose_at = src_pose_at;
    s->base.health = src_health;
    s->base.destroy = src_destroy;
    s->base.start_time_s = 0.0;
    s->base.end_time_s = -1.0; /* live: end < start */
    *out = &s->base;
    return 0;
}

int trk_tracker_source_stats(struct trk_pose_source *src, struct trk_tracker_stats *out)
{
    if (!src || src->destroy != src_destroy)
        return -1;
    struct tracker_source *s = from_base(src);
    pthread_mutex_lock(&s->mu);
    *out = s->stats;
    pthread_mutex_unlock(&s->mu);
    return 0;
}

int trk_tracker_source_record(struct trk_pose_source *src, const char *path, struct hl_error *err)
{
    if (!src || src->destroy != src_destroy)
        return hl_fail(err, "raw recording: not a tracker source");
    struct tracker_source *s = from_base(src);
    struct trk_recording *rec = NULL;
    if (path) {
        if (!s->info)
            return hl_fail(err, "%s: raw recording: the tracker is not started", path);
        rec = trk_recording_create(path, s->info->kind, s->info->vid, s->info->pid, s->info->name, err);
        if (!rec)
            return -1;
    }
    pthread_mutex_lock(&s->mu);
    struct trk_recording *old = s->recording;
    int failed = s->recording_failed;
    char why[sizeof s->recording_error];
    snprintf(why, sizeof why, "%s", s->recording_error);
    s->recording = rec;
    s->recording_failed = 0;
    s->recording_error[0] = '\0';
    pthread_mutex_unlock(&s->mu);
    if (!old)
        return 0;
    int rc = trk_recording_close(old, 1, err);
    if (failed)
        return hl_fail(err, "raw recording: a write failed: %.400s", why);
    return rc;
}
