/* What the umockdev tracker tests (test_hid_umockdev, test_hid_faults) share. */
#ifndef HMDLOD_TEST_HID_UTIL_H
#define HMDLOD_TEST_HID_UTIL_H

#include "tracking/tracking.h"

/* Prints to stderr everything a failed wait needs explained: the source's counters (reports,
 * rejected, drained, disconnects, reconnects, stalls, keep-alives), whether it is connected and to
 * which node, and its health with the reason. For the failure path of a bounded wait. */
void tu_hid_print_state(struct trk_pose_source *src);

#endif
