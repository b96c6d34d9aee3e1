/* Supported headsets on USB through libusb (tracking/usb.h). libusb gives bus, port path, speed and
 * the interfaces from the descriptors without opening the device; which kernel driver holds each
 * interface and whether it has a hidraw node come from sysfs, because libusb can only ask that of
 * a device it may open (root-only /dev/bus/usb nodes, unless a udev rule says otherwise). An
 * interface claimed by a program through libusb shows as bound to "usbfs" (DEVICES.md §3: drivers
 * built on hidapi-libusb detach usbhid, and the hidraw node is gone while they hold it). */
#include <dirent.h>
#include <errno.h>
#include <libusb.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "tracking/usb.h"

static const struct trk_device_info *imu_entry(uint16_t vid, uint16_t pid)
{
    for (size_t i = 0; i < trk_device_table_count; ++i)
        if (trk_device_table[i].vid == vid && trk_device_table[i].pid == pid && trk_device_table[i].role == TRK_ROLE_IMU)
            return &trk_device_table[i];
    return NULL;
}

static const char *speed_name(int speed)
{
    switch (speed) {
    case LIBUSB_SPEED_LOW: return "low (1.5 Mbit/s)";
    case LIBUSB_SPEED_FULL: return "full (12 Mbit/s)";
    case LIBUSB_SPEED_HIGH: return "high (480 Mbit/s)";
    case LIBUSB_SPEED_SUPER: return "super (5 Gbit/s)";
    case LIBUSB_SPEED_SUPER_PLUS: return "super+ (10 Gbit/s)";
    default: return "unknown";
    }
}

/* The interface's driver and hidraw node from /sys/bus/usb/devices/PORT:CONFIG.N. */
static void interface_sysfs(const char *port_path, int config, struct trk_usb_interface *in)
{
    char dir[256], link[256];
    snprintf(dir, sizeof dir, "/sys/bus/usb/devices/%s:%d.%d", port_path, config, in->number);
    char path[300];
    snprintf(path, sizeof path, "%s/driver", dir);
    ssize_t n = readlink(path, link, sizeof link - 1);
    if (n > 0) {
        link[n] = '\0';
        const char *base = strrchr(link, '/');
        snprintf(in->driver, sizeof in->driver, "%.31s", base ? base + 1 : link);
    }
    /* dir/<bus:vid:pid.N>/hidraw/hidrawM */
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d && !in->hidraw[0] && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.' || !strchr(e->d_name, ':'))
            continue;
        char sub[600];
        snprintf(sub, sizeof sub, "%s/%s/hidraw", dir, e->d_name);
        DIR *h = opendir(sub);
        struct dirent *he;
        while (h && (he = readdir(h)) != NULL)
            if (strncmp(he->d_name, "hidraw", 6) == 0) {
                snprintf(in->hidraw, sizeof in->hidraw, "/dev/%.20s", he->d_name);
                break;
            }
        if (h)
            closedir(h);
    }
    if (d)
        closedir(d);
}

static void interface_fix(const struct trk_usb_device_desc *u, struct trk_usb_interface *in)
{
    if (!in->is_imu || in->hidraw[0])
        return;
    char id[64], driver[sizeof in->driver];
    snprintf(id, sizeof id, "%s:1.%d", u->port_path, in->number);
    memcpy(driver, in->driver, sizeof driver);
    if (!in->driver[0])
        snprintf(in->fix, sizeof in->fix,
                 "no kernel driver is bound to interface %d, so there is no hidraw node: `sudo modprobe usbhid` "
                 "(and check it is not blacklisted), or `echo %s | sudo tee /sys/bus/usb/drivers/usbhid/bind`",
                 in->number, id);
    else if (strcmp(in->driver, "usbfs") == 0)
        snprintf(in->fix, sizeof in->fix,
                 "interface %d is claimed by a program through libusb (usbfs: SteamVR, a libusb-based driver, "
                 "libsurvive…), which detached usbhid: close that program; the kernel rebinds usbhid when it "
                 "lets go (else replug)", in->number);
    else if (strcmp(in->driver, "usbhid") == 0)
        snprintf(in->fix, sizeof in->fix,
                 "interface %d is bound to usbhid but has no hidraw node: is the hidraw module loaded "
                 "(`sudo modprobe hidraw`)?", in->number);
    else
        snprintf(in->fix, sizeof in->fix,
                 "interface %d is bound to '%s', not usbhid, so there is no hidraw node: `echo %s | sudo tee "
                 "/sys/bus/usb/drivers/%s/unbind` then `echo %s | sudo tee /sys/bus/usb/drivers/usbhid/bind`",
                 in->number, driver, id, driver, id);
}

int trk_usb_enumerate(struct trk_usb_device_desc *out, int max, struct hl_error *err)
{
    libusb_context *ctx = NULL;
    int rc = libusb_init(&ctx);
    if (rc != 0)
        return hl_fail(err, "libusb: cannot start: %s", libusb_strerror(rc));
    libusb_device **list = NULL;
    ssize_t count = libusb_get_device_list(ctx, &list);
    if (count < 0) {
        libusb_exit(ctx);
        return hl_fail(err, "libusb: cannot list devices: %s", libusb_strerror((int)count));
    }
    int n = 0;
    for (ssize_t i = 0; i < count && n < max; ++i) {
        struct libusb_device_descriptor dd;
        if (libusb_get_device_descriptor(list[i], &dd) != 0)
            continue;
        const struct trk_device_info *info = imu_entry(dd.idVendor, dd.idProduct);
        if (!info)
            continue;
        struct trk_usb_device_desc *u = &out[n++];
        memset(u, 0, sizeof *u);
        u->info = info;
        u->vid = dd.idVendor, u->pid = dd.idProduct;
        u->bus = libusb_get_bus_number(list[i]);
        u->address = libusb_get_device_address(list[i]);
        u->speed = speed_name(libusb_get_device_speed(list[i]));
        uint8_t ports[8];
        int np = libusb_get_port_numbers(list[i], ports, 8);
        int len = snprintf(u->port_path, sizeof u->port_path, "%d-", u->bus);
        for (int p = 0; p < np && len < (int)sizeof u->port_path; ++p)
            len += snprintf(u->port_path + len, sizeof u->port_path - (size_t)len, p ? ".%d" : "%d", ports[p]);
        libusb_device_handle *h = NULL;
        int orc = libusb_open(list[i], &h);
        if (orc == 0)
            libusb_close(h);
        else
            snprintf(u->usb_node_why, sizeof u->usb_node_why, "/dev/bus/usb/%03d/%03d: %s%s", u->bus, u->address,
                     libusb_strerror(orc),
                     orc == LIBUSB_ERROR_ACCESS ? " (harmless for hidraw; the udev rules grant the hidraw node)" : "");
        struct libusb_config_descriptor *cfg = NULL;
        if (libusb_get_active_config_descriptor(list[i], &cfg) != 0 || !cfg)
            continue;
        for (int k = 0; k < cfg->bNumInterfaces && u->interface_count < TRK_USB_MAX_INTERFACES; ++k) {
            struct trk_usb_interface *in = &u->interfaces[u->interface_count++];
            in->number = cfg->interface[k].num_altsetting > 0 ? cfg->interface[k].altsetting[0].bInterfaceNumber : k;
            in->is_imu = info->interface_number < 0 ? in->number == 0 : in->number == info->interface_number;
            interface_sysfs(u->port_path, cfg->bConfigurationValue, in);
            interface_fix(u, in);
        }
        libusb_free_config_descriptor(cfg);
    }
    libusb_free_device_list(list, 1);
    libusb_exit(ctx);
    return n;
}
