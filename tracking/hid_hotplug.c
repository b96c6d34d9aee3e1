/* Hot-plug of trackers through a libudev monitor (DEVICES.md §3: neither open driver reopens a
 * replugged headset; hmdlod watches add/remove of hidraw nodes). The "udev" group delivers events
 * after udev's rules ran, so a freshly added node already carries its uaccess ACL. PLATFORM.md §6:
 * umockdev's add/remove uevents reach such a monitor, which is how the tests drive it. */
#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <libudev.h>

#include "tracking/hid_internal.h"

int trk_hotplug_init(struct trk_hotplug *h, struct hl_error *err)
{
    memset(h, 0, sizeof *h);
    h->udev = udev_new();
    if (!h->udev)
        return hl_fail(err, "hot-plug: udev_new failed: %s", strerror(errno));
    h->monitor = udev_monitor_new_from_netlink(h->udev, "udev");
    if (!h->monitor) {
        int e = errno;
        trk_hotplug_destroy(h);
        return hl_fail(err, "hot-plug: cannot listen to udev events (netlink): %s", strerror(e));
    }
    if (udev_monitor_filter_add_match_subsystem_devtype(h->monitor, "hidraw", NULL) < 0 ||
        udev_monitor_enable_receiving(h->monitor) < 0) {
        int e = errno;
        trk_hotplug_destroy(h);
        return hl_fail(err, "hot-plug: cannot enable the udev monitor: %s", strerror(e));
    }
    return 0;
}

int trk_hotplug_fd(const struct trk_hotplug *h) { return h->monitor ? udev_monitor_get_fd(h->monitor) : -1; }

int trk_hotplug_poll(struct trk_hotplug *h, int timeout_ms)
{
    struct pollfd p = {trk_hotplug_fd(h), POLLIN, 0};
    if (p.fd < 0)
        return -1;
    int r = poll(&p, 1, timeout_ms);
    if (r < 0)
        return errno == EINTR ? 0 : -1;
    return r > 0 && (p.revents & POLLIN) ? 1 : 0;
}

/* vid, pid from the hid parent's HID_ID "bus:VVVVVVVV:PPPPPPPP", the interface from the usb
 * interface parent; the USB manufacturer string for the table's manufacturer check. */
static const struct trk_device_info *identify(struct udev_device *dev, struct trk_hotplug_event *ev)
{
    struct udev_device *hid = udev_device_get_parent_with_subsystem_devtype(dev, "hid", NULL);
    const char *id = hid ? udev_device_get_property_value(hid, "HID_ID") : NULL;
    unsigned bus, vid, pid;
    if (!id || sscanf(id, "%x:%x:%x", &bus, &vid, &pid) != 3 || vid > 0xFFFF || pid > 0xFFFF)
        return NULL;
    ev->vid = (uint16_t)vid;
    ev->pid = (uint16_t)pid;
    ev->interface_number = -1;
    struct udev_device *intf = udev_device_get_parent_with_subsystem_devtype(dev, "usb", "usb_interface");
    const char *num = intf ? udev_device_get_sysattr_value(intf, "bInterfaceNumber") : NULL;
    if (num)
        ev->interface_number = (int)strtol(num, NULL, 16);
    struct udev_device *usb = udev_device_get_parent_with_subsystem_devtype(dev, "usb", "usb_device");
    const char *manufacturer = usb ? udev_device_get_sysattr_value(usb, "manufacturer") : NULL;
    return trk_hid_match(ev->vid, ev->pid, ev->interface_number, manufacturer);
}

int trk_hotplug_next_event(struct trk_hotplug *h, struct trk_hotplug_event *ev)
{
    if (!h->monitor)
        return 0;
    for (;;) {
        struct udev_device *dev = udev_monitor_receive_device(h->monitor); /* non-blocking socket */
        if (!dev)
            return 0;
        const char *action = udev_device_get_action(dev);
        const char *node = udev_device_get_devnode(dev);
        memset(ev, 0, sizeof *ev);
        int keep = 0;
        if (action && node && !strcmp(action, "remove")) {
            ev->action = TRK_HOTPLUG_REMOVE;
            ev->interface_number = -1;
            keep = 1;
        } else if (action && node && !strcmp(action, "add")) {
            ev->action = TRK_HOTPLUG_ADD;
            /* Unidentified adds are delivered too: the parents may not be readable yet (umockdev
             * builds the sysfs tree piecewise), so a listener should rescan rather than ignore it. */
            ev->interface_number = -1;
            ev->info = identify(dev, ev);
            keep = 1;
        }
        if (keep)
            snprintf(ev->devnode, sizeof ev->devnode, "%s", node);
        udev_device_unref(dev);
        if (keep)
            return 1;
    }
}

void trk_hotplug_destroy(struct trk_hotplug *h)
{
    if (h->monitor)
        udev_monitor_unref(h->monitor);
    if (h->udev)
        udev_unref(h->udev);
    h->monitor = NULL;
    h->udev = NULL;
}
