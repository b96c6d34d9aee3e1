/* One open tracker interface over hidapi-hidraw: open with explained failures, timed reads, the
 * start and keep-alive reports each kind needs (DEVICES.md §2b–§2e), and draining stale reports. */
#include <errno.h>
#include <stdio.h>
#include <sys/stat.h>
#include <stdlib.h>
#include <string.h>

#include <hidapi.h>

#include "tracking/hid_internal.h"

#define MAX_ENUM 32
#define KEEPALIVE_INTERVAL_MS 10000  /* what both open drivers ask the Rift for (§2b 0x08 / 0x11) */
#define DK1_KEEPALIVE_PERIOD_NS 800000000LL   /* OH: resend after (1000 − 200) ms, §2b 0x08 */
#define MUX_KEEPALIVE_PERIOD_NS 9500000000LL  /* MO: 10 s mux resent after 9.5 s, §2b 0x11 */
#define STALE_DRAIN_NS 50000000LL            /* MO drains Vive IMU reports 50 ms; PSVR replays (§2c) */

struct trk_hid_device {
    hid_device *h;
    struct trk_hid_device_desc desc;
    uint16_t command_id;
    int keepalive_armed;
    int64_t next_keepalive_ns;
};

static uint16_t next_command(struct trk_hid_device *d) { return ++d->command_id; }

static const char *hid_message(hid_device *h, char *buf, size_t size)
{
    trk_hid_wide_to_utf8(h ? hid_error(h) : NULL, buf, size);
    if (!buf[0])
        snprintf(buf, size, "no reason given");
    return buf;
}

int trk_hid_open_desc(const struct trk_hid_device_desc *desc, struct trk_hid_device **out, struct hl_error *err)
{
    *out = NULL;
    /* hidapi 0.13.1's failure path after a failed HIDIOCGRDESCSIZE writes its error into the device
     * it has just freed, and hid_error(NULL) then says "Success" (PLATFORM.md §6). So do its two
     * steps (open, ioctl) ourselves first: we get errno, and hidapi never takes that path. */
    char why[TRK_HID_WHY_SIZE];
    if (trk_hid_probe_node(desc->path, why, sizeof why) != 0)
        return hl_fail(err, "%s: %s", desc->info->name, why);
    hid_device *h = hid_open_path(desc->path);
    if (!h)
        return hl_fail(err, "%s: hid_open_path(%s) failed just after the node opened and answered its ioctl "
                            "(unplugged meanwhile?)",
                       desc->info->name, desc->path);
    struct trk_hid_device *d = calloc(1, sizeof *d);
    if (!d) {
        hid_close(h);
        return hl_fail(err, "%s: out of memory", desc->path);
    }
    d->h = h;
    d->desc = *desc;
    d->desc.can_open = 1;
    d->desc.why[0] = '\0';
    *out = d;
    return 0;
}

int trk_hid_open(const char *path_or_auto, struct trk_hid_device **out, struct hl_error *err)
{
    *out = NULL;
    int want_auto = !path_or_auto || !path_or_auto[0] || !strcmp(path_or_auto, "auto");
    struct trk_hid_device_desc *list = calloc(MAX_ENUM, sizeof *list);
    if (!list)
        return hl_fail(err, "out of memory");
    int n = trk_hid_enumerate(list, MAX_ENUM, err);
    int rc = -1;
    if (n < 0)
        goto done;
    if (want_auto) {
        const struct trk_hid_device_desc *first_blocked = NULL;
        for (int i = 0; i < n; ++i) {
            if (list[i].info->role != TRK_ROLE_IMU)
                continue;
            if (list[i].can_open) {
                rc = trk_hid_open_desc(&list[i], out, err);
                goto done;
            }
            if (!first_blocked)
                first_blocked = &list[i];
        }
        if (first_blocked) {
            hl_fail(err, "found %s at %s but cannot use it: %s", first_blocked->info->name, first_blocked->path,
                    first_blocked->why);
        } else {
            char names[400];
            hl_fail(err, "no supported head tracker found (looked for: %s)",
                    trk_hid_supported_list(names, sizeof names));
        }
        goto done;
    }
    for (int i = 0; i < n; ++i) {
        if (strcmp(list[i].path, path_or_auto) == 0) {
            rc = trk_hid_open_desc(&list[i], out, err);
            goto done;
        }
    }
    {
        char names[400];
        struct stat st; /* stat, not open: opening a FIFO given as a device path would block */
        int exists = stat(path_or_auto, &st) == 0 || errno != ENOENT;
        if (exists)
            hl_fail(err, "%s is not a supported head tracker's hidraw node (supported: %s; see hmdlod devices)",
                    path_or_auto, trk_hid_supported_list(names, sizeof names));
        else
            hl_fail(err, "%s: no such device node (see hmdlod devices)", path_or_auto);
    }
done:
    free(list);
    return rc;
}

int trk_hid_read(struct trk_hid_device *d, uint8_t *buf, size_t cap, int timeout_ms, int64_t *host_time_ns,
                 struct hl_error *err)
{
    int n = hid_read_timeout(d->h, buf, cap, timeout_ms);
    /* A real hidraw node returns one whole report per read. A byte-stream node (umockdev's PTY,
     * PLATFORM.md §6) can hand out part of one when the reader wakes mid-write, and every later
     * read would then straddle two reports. For kinds whose reports have one fixed size, finish a
     * short read: on real hardware this never runs (their reports are never shorter). */
    size_t fixed = d->desc.info->role == TRK_ROLE_IMU && d->desc.info->kind != TRK_DEVICE_RIFT_DK1 &&
                           d->desc.info->kind != TRK_DEVICE_HDK
                       ? d->desc.info->report_size
                       : 0;
    for (int tries = 0; n > 0 && fixed && cap == fixed && (size_t)n < cap && tries < 8; ++tries) {
        int m = hid_read_timeout(d->h, buf + n, cap - (size_t)n, 5);
        if (m < 0)
            n = -1;
        else if (m == 0)
            break; /* leave it short: the parser rejects it, the next read starts afresh */
        else
            n += m;
    }
    if (host_time_ns)
        *host_time_ns = hl_clock_now_ns();
    if (n < 0) {
        /* hidraw reports POLLHUP/POLLERR on unplug (DEVICES.md §3); hidapi says "device disconnected". */
        char msg[200];
        return hl_fail(err, "%s (%s): read failed: %s", d->desc.path, d->desc.info->name,
                       hid_message(d->h, msg, sizeof msg));
    }
    return n;
}

static int send_feature(struct trk_hid_device *d, const uint8_t *buf, size_t len, const char *what,
                        struct hl_error *err)
{
    if (hid_send_feature_report(d->h, buf, len) < 0) {
        char msg[200];
        return hl_fail(err, "%s (%s): sending %s (feature 0x%02x, %zu B) failed: %s", d->desc.path,
                       d->desc.info->name, what, buf[0], len, hid_message(d->h, msg, sizeof msg));
    }
    return 0;
}

static int send_rift_keepalive(struct trk_hid_device *d, struct hl_error *err)
{
    uint8_t buf[8];
    size_t n;
    if (d->desc.info->kind == TRK_DEVICE_RIFT_DK1)
        n = trk_rift_build_keepalive_dk1(buf, next_command(d), KEEPALIVE_INTERVAL_MS);
    else
        n = trk_rift_build_keepalive_mux(buf, next_command(d), TRK_RIFT_DK2_REPORT_ID, KEEPALIVE_INTERVAL_MS);
    return send_feature(d, buf, n, "keep-alive", err);
}

static int start_rift(struct trk_hid_device *d, struct hl_error *err)
{
    /* Config 0x02: keep what the device has, force factory calibration and automatic gyro zero-rate
     * recalibration on (both drivers do, §2b; OpenHMD #25: drift without them), and sensor
     * coordinates (0x40) off because our parser assumes the HMD frame. Full rate: interval 0. */
    uint8_t cfg[8] = {0x02};
    uint8_t flags = 0;
    uint16_t rate = 1000;
    if (hid_get_feature_report(d->h, cfg, 7) >= 7) {
        flags = cfg[3];
        rate = (uint16_t)(cfg[5] | (cfg[6] << 8));
    }
    flags = (uint8_t)((flags | TRK_RIFT_CONFIG_USE_CALIBRATION | TRK_RIFT_CONFIG_AUTO_CALIBRATE) & ~0x40);
    size_t n = trk_rift_build_config(cfg, next_command(d), flags, 0, rate);
    if (send_feature(d, cfg, n, "config", err) != 0)
        return -1;
    if (d->desc.info->kind == TRK_DEVICE_RIFT_CV1) {
        /* Without 0x1D the CV1 panel stays dark (§2b); LEDs only matter for optical tracking. */
        uint8_t comp[4];
        n = trk_rift_build_enable_components(comp, next_command(d),
                                             TRK_RIFT_COMPONENT_DISPLAY | TRK_RIFT_COMPONENT_AUDIO);
        if (send_feature(d, comp, n, "enable components", err) != 0)
            return -1;
    }
    return send_rift_keepalive(d, err);
}

/* PSVR: the sensor interface (4) only streams once the control interface (5) of the same unit has
 * powered the headset and switched it to VR mode (§2c). */
static int start_psvr(struct trk_hid_device *d, struct hl_error *err)
{
    struct trk_hid_device_desc list[MAX_ENUM];
    int n = trk_hid_enumerate(list, MAX_ENUM, err);
    if (n < 0)
        return -1;
    const struct trk_hid_device_desc *ctl = NULL;
    for (int i = 0; i < n; ++i) {
        if (list[i].info->kind != TRK_DEVICE_PSVR || list[i].info->role != TRK_ROLE_CONTROL)
            continue;
        if (!ctl || (d->desc.serial[0] && !strcmp(list[i].serial, d->desc.serial)))
            ctl = &list[i];
    }
    if (!ctl)
        return hl_fail(err, "%s (%s): the PSVR control interface 5 is missing, so the headset cannot be powered "
                            "on (is the processor unit connected by USB?)",
                       d->desc.path, d->desc.info->name);
    char why[TRK_HID_WHY_SIZE];
    if (trk_hid_probe_node(ctl->path, why, sizeof why) != 0) /* before hidapi: see trk_hid_open_desc */
        return hl_fail(err, "PSVR control interface: %s", why);
    hid_device *h = hid_open_path(ctl->path);
    if (!h)
        return hl_fail(err, "PSVR control interface %s: hid_open_path failed (unplugged meanwhile?)", ctl->path);
    uint8_t power[8], vr[8], track[12];
    struct {
        const uint8_t *buf;
        size_t len;
        const char *what;
    } steps[3] = {
        {power, trk_psvr_build_power(power, 1), "power on"},
        {vr, trk_psvr_build_vr_mode(vr, 1), "VR mode"},
        {track, trk_psvr_build_tracking_on(track), "tracking on"},
    };
    for (int i = 0; i < 3; ++i) {
        if (hid_write(h, steps[i].buf, steps[i].len) < 0) {
            char msg[200];
            hl_fail(err, "PSVR control interface %s: sending %s failed: %s", ctl->path, steps[i].what,
                    hid_message(h, msg, sizeof msg));
            hid_close(h);
            return -1;
        }
    }
    hid_close(h);
    return 0;
}

int trk_hid_send_start(struct trk_hid_device *d, struct hl_error *err)
{
    int rc = 0;
    d->keepalive_armed = 0;
    switch (d->desc.info->kind) {
    case TRK_DEVICE_RIFT_DK1:
    case TRK_DEVICE_RIFT_DK2:
    case TRK_DEVICE_RIFT_CV1:
        if (d->desc.info->role != TRK_ROLE_IMU)
            break;
        rc = start_rift(d, err);
        if (rc == 0) {
            d->keepalive_armed = 1;
            d->next_keepalive_ns = hl_clock_now_ns() + (d->desc.info->kind == TRK_DEVICE_RIFT_DK1
                                                            ? DK1_KEEPALIVE_PERIOD_NS
                                                            : MUX_KEEPALIVE_PERIOD_NS);
        }
        break;
    case TRK_DEVICE_PSVR:
        if (d->desc.info->role == TRK_ROLE_IMU)
            rc = start_psvr(d, err);
        break;
    case TRK_DEVICE_VIVE:
    case TRK_DEVICE_VIVE_PRO_INDEX:
        /* The mainboard power-on (feature 0x04, §2d) has no builder yet: the headset streams only
         * when something else (SteamVR, Monado) has powered it. docs/trackers.md says so. */
    case TRK_DEVICE_HDK: /* streams on its own (§2e) */
        break;
    }
    return rc;
}

int trk_hid_keepalive(struct trk_hid_device *d, int64_t now_ns, struct hl_error *err)
{
    if (!d->keepalive_armed || now_ns < d->next_keepalive_ns)
        return 0;
    int64_t period = d->desc.info->kind == TRK_DEVICE_RIFT_DK1 ? DK1_KEEPALIVE_PERIOD_NS : MUX_KEEPALIVE_PERIOD_NS;
    /* Schedule first: a failing device is not hammered every loop; the read error will tell. */
    d->next_keepalive_ns = now_ns + period;
    if (send_rift_keepalive(d, err) != 0)
        return -1;
    return 1;
}

int trk_hid_drain(struct trk_hid_device *d, struct hl_error *err)
{
    uint8_t buf[64];
    size_t cap = d->desc.info->report_size ? d->desc.info->report_size : sizeof buf;
    if (cap > sizeof buf)
        cap = sizeof buf;
    int dropped = 0;
    for (int i = 0; i < 4096; ++i) { /* bounded: a device streaming faster than we drain */
        int n = trk_hid_read(d, buf, cap, 0, NULL, err);
        if (n < 0)
            return -1;
        if (n == 0)
            break;
        ++dropped;
    }
    enum trk_device_kind k = d->desc.info->kind;
    if (k == TRK_DEVICE_PSVR || k == TRK_DEVICE_VIVE || k == TRK_DEVICE_VIVE_PRO_INDEX) {
        int64_t until = hl_clock_now_ns() + STALE_DRAIN_NS;
        for (;;) {
            int64_t left_ms = (until - hl_clock_now_ns()) / 1000000;
            if (left_ms <= 0)
                break;
            int n = trk_hid_read(d, buf, cap, (int)left_ms, NULL, err);
            if (n < 0)
                return -1;
            if (n > 0)
                ++dropped;
        }
    }
    return dropped;
}

const struct trk_device_info *trk_hid_info(const struct trk_hid_device *d) { return d->desc.info; }

const struct trk_hid_device_desc *trk_hid_desc(const struct trk_hid_device *d) { return &d->desc; }

void trk_hid_close(struct trk_hid_device *d)
{
    if (!d)
        return;
    hid_close(d->h);
    free(d);
}
