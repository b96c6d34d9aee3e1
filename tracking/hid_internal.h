/* Internal to tracking/: helpers shared by the HID files (hid.c, hid_discovery.c, hid_hotplug.c,
 * tracker_source.c). Not part of the public API. */
#ifndef HMDLOD_TRACKING_HID_INTERNAL_H
#define HMDLOD_TRACKING_HID_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <wchar.h>

#include "tracking/tracking.h"

/* hid_init once, thread-safely (hidapi's own lazy init is not). 0, or −1 with err. */
int trk_hid_lib_init(struct hl_error *err);

/* The table entry for vid:pid:interface with the manufacturer check the table asks for (VR-Tek
 * reuses the DK1 id, DEVICES.md §2a); NULL when the device is not a supported tracker. */
const struct trk_device_info *trk_hid_match(uint16_t vid, uint16_t pid, int interface_number,
                                            const char *manufacturer);

/* Opens the node read-write and asks for its report-descriptor size, as hid_open_path does, so a
 * failure can be explained with errno (hidapi 0.13.1 loses it: PLATFORM.md §6). 0 when both work;
 * −1 with why = node, errno text, fix. */
int trk_hid_probe_node(const char *path, char *why, size_t why_size);

/* Opens a device trk_hid_enumerate listed (the live source's reopen path: no second enumeration).
 * 0, or −1 with the explained reason. */
int trk_hid_open_desc(const struct trk_hid_device_desc *desc, struct trk_hid_device **out, struct hl_error *err);

/* UTF-8 of a wide hidapi string (UTF-32 on Linux); NULL gives "". Always NUL-terminated. */
void trk_hid_wide_to_utf8(const wchar_t *w, char *out, size_t size);

#endif
