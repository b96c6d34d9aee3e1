/* hmdlod devices: the supported head trackers present (hidraw nodes), and for each whether hmdlod
 * can open it — and if not, which node, the errno and the fix (DEVICES.md §3: users of the open
 * drivers got "got -1 bytes" for a missing udev rule). No device is not an error: it says so. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/commands.h"
#include "tracking/tracking.h"

#define MAX_DEVICES 32

static const char usage[] =
    "usage: hmdlod devices\n"
    "  Lists the supported head trackers connected to this machine (Linux hidraw nodes): node, model,\n"
    "  USB VID:PID and interface, manufacturer, product and serial strings, whether the interface is\n"
    "  the head IMU or a control interface, and whether hmdlod can open it. When it cannot, the line\n"
    "  says which node, the system's reason and the fix (permissions: install the udev rules with\n"
    "  sudo scripts/install-udev-rules.sh; busy: another process holds it). docs/trackers.md lists\n"
    "  the supported devices. Then, through libusb, the supported headsets on USB with bus, port path\n"
    "  and speed, which kernel driver holds each interface and its hidraw node — so a headset with no\n"
    "  usable hidraw node (no driver bound, another driver, claimed by a program through libusb) is\n"
    "  still listed, with the fix. Exits 0 when the list could be made, with or without devices.\n";

/* The USB view (tracking/usb.h): printed only when a supported headset is on USB. */
static void print_usb(void)
{
    struct trk_usb_device_desc *usb = calloc(MAX_DEVICES, sizeof *usb);
    struct hl_error err;
    int n = usb ? trk_usb_enumerate(usb, MAX_DEVICES, &err) : -1;
    if (n < 0 && usb)
        printf("USB (libusb): not listed: %s\n", err.msg);
    for (int i = 0; i < n; ++i) {
        const struct trk_usb_device_desc *u = &usb[i];
        printf("USB %s (bus %d, address %d)  %s  %04x:%04x  %s speed\n", u->port_path, u->bus, u->address,
               u->info->name, u->vid, u->pid, u->speed);
        if (u->usb_node_why[0])
            printf("    usb node: %s\n", u->usb_node_why);
        for (int k = 0; k < u->interface_count; ++k) {
            const struct trk_usb_interface *in = &u->interfaces[k];
            printf("    interface %d%s: driver %s, %s\n", in->number, in->is_imu ? " (head IMU)" : "",
                   in->driver[0] ? in->driver : "none", in->hidraw[0] ? in->hidraw : "no hidraw node");
            if (in->fix[0])
                printf("      fix: %s\n", in->fix);
        }
    }
    free(usb);
}

int cmd_devices(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    if (argc > 1) {
        fprintf(stderr, "hmdlod devices: unexpected argument '%s' (try: hmdlod devices --help)\n", argv[1]);
        return 1;
    }
    struct trk_hid_device_desc *list = calloc(MAX_DEVICES, sizeof *list);
    if (!list) {
        fprintf(stderr, "hmdlod devices: out of memory\n");
        return 1;
    }
    struct hl_error err;
    int n = trk_hid_enumerate(list, MAX_DEVICES, &err);
    if (n < 0) {
        fprintf(stderr, "hmdlod devices: %s\n", err.msg);
        free(list);
        return 1;
    }
    if (n == 0) {
        char names[512];
        printf("no supported head tracker found (looked for: %s)\n", trk_hid_supported_list(names, sizeof names));
        free(list);
        print_usb();
        return 0;
    }
    int usable = 0;
    for (int i = 0; i < n; ++i) {
        const struct trk_hid_device_desc *d = &list[i];
        char iface[16] = "-";
        if (d->interface_number >= 0)
            snprintf(iface, sizeof iface, "%d", d->interface_number);
        printf("%s  %s  %04x:%04x interface %s  %s\n", d->path, d->info->name, d->vid, d->pid, iface,
               d->info->role == TRK_ROLE_IMU ? "head IMU" : "control interface (no motion data)");
        printf("    \"%s\" \"%s\"  serial %s\n", d->manufacturer[0] ? d->manufacturer : "?",
               d->product[0] ? d->product : "?", d->serial[0] ? d->serial : "(none)");
        if (d->can_open) {
            printf("    can open: yes\n");
            usable += d->info->role == TRK_ROLE_IMU;
        } else {
            printf("    can open: no: %s\n", d->why);
        }
    }
    printf("%d supported interface%s found, %d head IMU%s usable\n", n, n == 1 ? "" : "s", usable,
           usable == 1 ? "" : "s");
    free(list);
    print_usb();
    return 0;
}
