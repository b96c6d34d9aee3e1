/* tracking/hid.h: HID devices, discovery, hot-plug, live source — tracker I/O through hidapi's
 * hidraw backend, the libudev hot-plug monitor and the live tracker pose source. Part of the
 * tracking/tracking.h umbrella; self-contained. */
#ifndef HMDLOD_TRACKING_HID_H
#define HMDLOD_TRACKING_HID_H

#include "base/base.h"
#include "tracking/pose_source.h"
#include "tracking/reports.h"

/* Tracker I/O on Linux through hidapi's hidraw backend (DEVICES.md §3: hidraw keeps the kernel
 * driver, gives interface numbers and reports POLLHUP on unplug; hidapi-libusb would detach the
 * driver and need the usb node). Everything here is thread-compatible: one thread per object.
 * docs/trackers.md says which devices are supported, how permissions work and what is verified. */

#define TRK_HID_PATH_SIZE 256
#define TRK_HID_STRING_SIZE 64
#define TRK_HID_WHY_SIZE 512

/* One supported tracker interface present on the machine: a trk_device_table match by VID:PID and
 * interface (and USB manufacturer where the table requires it). Control interfaces (PSVR iface 5,
 * Vive mainboards; info->role == TRK_ROLE_CONTROL) are listed too: check the role before reading.
 * Strings are UTF-8. can_open: the node opened read-write and answered the report-descriptor ioctl
 * just now; when 0, `why` names the node, the errno text and the fix. */
struct trk_hid_device_desc {
    char path[TRK_HID_PATH_SIZE];        /* hidraw node, e.g. /dev/hidraw3 */
    const struct trk_device_info *info;  /* the table entry it matched */
    uint16_t vid, pid;
    int interface_number;                /* USB interface; −1 when not USB */
    char manufacturer[TRK_HID_STRING_SIZE], product[TRK_HID_STRING_SIZE], serial[TRK_HID_STRING_SIZE];
    int can_open;
    char why[TRK_HID_WHY_SIZE];
};

/* Lists supported trackers present, in hidapi's order (IMU and control interfaces alike), trying to
 * open each. Writes at most max entries and returns how many it wrote (0: none present), or −1 with
 * err when hidapi cannot enumerate at all. */
int trk_hid_enumerate(struct trk_hid_device_desc *out, int max, struct hl_error *err);

/* "Rift DK1 2833:0001, Rift DK2 2833:0021, …": every IMU entry of trk_device_table, for messages
 * such as "no supported head tracker found (looked for: …)". Returns buf. */
const char *trk_hid_supported_list(char *buf, size_t size);

/* An open tracker interface. open: path_or_auto NULL, "" or "auto" takes the first openable IMU
 * interface from trk_hid_enumerate; a path must be the hidraw node of a supported device. Failures
 * say which node, the errno text and the fix (udev rules, another process holding it). Opening does
 * not start streaming: call trk_hid_send_start. Allocates once, at open. */
struct trk_hid_device;
int trk_hid_open(const char *path_or_auto, struct trk_hid_device **out, struct hl_error *err);
/* Reads one input report (cap should be info->report_size: under umockdev the node is a byte stream
 * and a larger buffer would merge queued reports). Returns its length, 0 on timeout (timeout_ms < 0
 * waits forever), −1 on error or disconnect with the reason in err. *host_time_ns (may be NULL): the
 * monotonic clock right after the read returned. No allocation. */
int trk_hid_read(struct trk_hid_device *d, uint8_t *buf, size_t cap, int timeout_ms, int64_t *host_time_ns,
                 struct hl_error *err);
/* Sends what the kind needs before it streams (DEVICES.md §2): Rift — config 0x02 with factory and
 * auto gyro calibration on and sensor coordinates off, then keep-alive (DK1 0x08, DK2/CV1 mux 0x11,
 * 10 s), CV1 enable-components 0x1D (display, audio); PSVR — power, VR mode and tracking on through
 * the control interface 5 of the same unit; Vive — nothing yet (power-on 0x04 has no builder: the
 * headset must already be powered); HDK — nothing. Restarts the keep-alive schedule. */
int trk_hid_send_start(struct trk_hid_device *d, struct hl_error *err);
/* Resends the keep-alive when due at now_ns (DK1 0x08 every 0.8 s as OpenHMD does; DK2/CV1 mux 0x11
 * every 9.5 s as Monado does; others never). Returns 1 sent, 0 not due, −1 with err. */
int trk_hid_keepalive(struct trk_hid_device *d, int64_t now_ns, struct hl_error *err);
/* Reads and discards reports already queued (and, for PSVR and Vive, those arriving in the next
 * 50 ms: both replay stale samples at start, §2c/§2d). Returns the number dropped, −1 with err. */
int trk_hid_drain(struct trk_hid_device *d, struct hl_error *err);
const struct trk_device_info *trk_hid_info(const struct trk_hid_device *d);
const struct trk_hid_device_desc *trk_hid_desc(const struct trk_hid_device *d); /* path, strings */
void trk_hid_close(struct trk_hid_device *d); /* NULL is fine */

/* Hot-plug: a libudev monitor on the "udev" netlink group (events after udev's rules ran, so the
 * uaccess ACL is in place), subsystem hidraw, add and remove only. An add is identified from its
 * parents' HID_ID and bInterfaceNumber: info is the table entry, or NULL for an unsupported device
 * or one whose parents cannot be read yet (rescan with trk_hid_enumerate shortly). A remove carries
 * only the node name (the device is gone). */
enum trk_hotplug_action { TRK_HOTPLUG_ADD = 1, TRK_HOTPLUG_REMOVE = 2 };
struct trk_hotplug_event {
    enum trk_hotplug_action action;
    char devnode[TRK_HID_PATH_SIZE];
    const struct trk_device_info *info; /* add: the table entry or NULL (see above); remove: NULL */
    uint16_t vid, pid;                  /* add only */
    int interface_number;               /* add only; −1 when not USB */
};
struct udev;
struct udev_monitor;
struct trk_hotplug {
    struct udev *udev;
    struct udev_monitor *monitor;
};
int trk_hotplug_init(struct trk_hotplug *h, struct hl_error *err);
int trk_hotplug_fd(const struct trk_hotplug *h); /* pollable (POLLIN); −1 before init */
/* Waits up to timeout_ms (0: just checks) for the monitor to be readable: 1, 0 on timeout, −1 on error. */
int trk_hotplug_poll(struct trk_hotplug *h, int timeout_ms);
/* Takes the next pending event without blocking: 1 with *ev filled, 0 when none is pending.
 * Events that do not concern trackers are consumed and skipped. */
int trk_hotplug_next_event(struct trk_hotplug *h, struct trk_hotplug_event *ev);
void trk_hotplug_destroy(struct trk_hotplug *h);

/* The live pose source of a head tracker. start opens the device (path or auto, as trk_hid_open),
 * sends the start reports and runs a reader thread that reads reports, feeds a trk_stream and sends
 * keep-alives on the device's own schedule, independent of rendering. pose_at(t, host monotonic
 * seconds as hl_clock_now_s) predicts the newest pose to t, the horizon capped at max_prediction_s
 * (≤ 0: 0.040 s, where the fusion's constant-rate prediction stays good); time_s is set to t.
 * Health: OK while reports flow; LOST with the reason on unplug, read error or a 1 s silence
 * (noticed within 1.02 s of the last report: "no reports for 1000 ms") — then pose_at returns the
 * last pose with zero angular velocity (no prediction). While reports flow, or in the silence before
 * it is noticed, prediction never reaches past the newest report's host time + max_prediction_s. A
 * silent device that speaks again returns to OK with its next fused report (same stream). The thread watches
 * hot-plug and reopens a matching device when one is added (any node name; same serial when known),
 * re-sends the start reports, re-initialises the stream (timestamp unwrapping, fusion start-up;
 * heading restarts at 0, and a magnetometer's reference, being relative, is captured anew), drains
 * stale reports and returns to OK on the first new report. Before the first report pose_at gives
 * a still pose (health says why). stop joins the thread and closes the device; destroy stops first. */
int trk_tracker_source_create(const char *path_or_auto, double max_prediction_s, struct trk_pose_source **out,
                              struct hl_error *err);

/* Counters of a tracker source (for status lines and tests); −1 if src is not a tracker source. */
struct trk_tracker_stats {
    uint64_t reports;          /* reports read and fed */
    uint64_t rejected;         /* of those, refused by the parser */
    uint64_t samples_fused;
    uint64_t disconnects;      /* losses of the device (read error, remove event) */
    uint64_t stalls;           /* silences of 1 s while open ("no reports for 1000 ms"; not a disconnect) */
    uint64_t reconnects;       /* successful reopens after a loss (start reports sent, drained) */
    uint64_t keepalives;       /* keep-alive reports sent */
    uint64_t drained;          /* stale reports dropped after (re)opening */
    uint64_t recorded;         /* reports written to the raw recording (trk_tracker_source_record) */
    int connected;             /* the device is open now */
    char path[TRK_HID_PATH_SIZE]; /* node in use, or last used */
};
int trk_tracker_source_stats(struct trk_pose_source *src, struct trk_tracker_stats *out);

/* Raw recording of a started tracker source (tracking/recording.h): from now on every report the
 * reader thread reads is appended, as read, with its host receive time — across unplug and replug.
 * path NULL stops and closes (fsync) the recording in progress. 0, or −1 with err (also when an
 * append had failed: the recording stops at the first failed write). */
int trk_tracker_source_record(struct trk_pose_source *src, const char *path, struct hl_error *err);

#endif
