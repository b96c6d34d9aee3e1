/* tracking/usb.h: supported headsets as USB devices, through libusb — what hidapi alone cannot tell
 * (DESIGN.md, dependencies): a headset whose IMU interface has no usable hidraw node (no kernel
 * driver bound, another driver bound, the interface claimed through usbfs) is still listed, with
 * its bus, port, speed and the fix. Part of the tracking/tracking.h umbrella; self-contained. */
#ifndef HMDLOD_TRACKING_USB_H
#define HMDLOD_TRACKING_USB_H

#include "base/base.h"
#include "tracking/reports.h"

#define TRK_USB_MAX_INTERFACES 8

struct trk_usb_interface {
    int number;
    char driver[32];   /* the kernel driver bound to it (sysfs), "" when none; "usbfs": claimed by a program */
    char hidraw[32];   /* its hidraw node (/dev/hidrawN), "" when none */
    int is_imu;        /* the table's IMU interface of this device */
    char fix[480];     /* when the IMU interface has no hidraw node: why and what to do; else "" */
};

struct trk_usb_device_desc {
    const struct trk_device_info *info; /* the table's IMU entry for its VID:PID */
    uint16_t vid, pid;
    int bus, address;
    char port_path[32];  /* sysfs name, e.g. "1-1.4" (bus-port.port…) */
    const char *speed;   /* "high (480 Mbit/s)" … */
    char usb_node_why[160]; /* /dev/bus/usb/BBB/DDD cannot be opened: why ("" when it can) */
    int interface_count;
    struct trk_usb_interface interfaces[TRK_USB_MAX_INTERFACES];
};

/* Lists the supported headsets on USB (VID:PID of an IMU entry of trk_device_table), at most max.
 * Returns how many, or −1 with err when libusb cannot start. */
int trk_usb_enumerate(struct trk_usb_device_desc *out, int max, struct hl_error *err);

#endif
