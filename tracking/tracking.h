/* tracking: where the head is. The pose-source interface every source implements — tracker
 * drivers, raw recordings, and the head-motion traces of replay/. Prefix trk_. Depends on base.
 * Frames: head/body frame +X right, +Y up, +Z toward the wearer (−Z forward); world +Y up.
 *
 * The path of a report: read from a device (hid.h) or a raw recording (recording.h), parsed into
 * body-frame IMU samples (reports.h) and fused (fusion.h) by one device stream (stream.h), which
 * yields poses through the interface (pose_source.h). The topic headers, each self-contained:
 *   tracking/pose_source.h  struct trk_pose and the struct trk_pose_source interface
 *   tracking/reports.h      report parsers, the supported trackers (VID:PID table), encoders and
 *                           the device simulator over them
 *   tracking/fusion.h       the 3-DoF IMU fusion, its prediction, the shared IMU CSV reader
 *   tracking/stream.h       device streams: one parser feeding one fusion, live or replayed
 *   tracking/recording.h    raw recordings: file format, writer, reader
 *   tracking/hid.h          HID devices, discovery, hot-plug and the live tracker source
 *   tracking/evaluate.h     end-to-end accuracy evaluation on the shared IMU streams
 * Other modules include this file only; report_internal.h and hid_internal.h are the module's own. */
#ifndef HMDLOD_TRACKING_H
#define HMDLOD_TRACKING_H

#include "base/base.h"
#include "tracking/pose_source.h"
#include "tracking/reports.h"
#include "tracking/fusion.h"
#include "tracking/stream.h"
#include "tracking/recording.h"
#include "tracking/hid.h"
#include "tracking/usb.h"
#include "tracking/evaluate.h"

#endif
