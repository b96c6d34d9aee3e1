/* tracking/stream.h: device streams — one tracker's report parser feeding one fusion, live or
 * replayed from a raw recording. Part of the tracking/tracking.h umbrella; self-contained. */
#ifndef HMDLOD_TRACKING_STREAM_H
#define HMDLOD_TRACKING_STREAM_H

#include "base/base.h"
#include "tracking/fusion.h"
#include "tracking/pose_source.h"
#include "tracking/reports.h"

/* A device stream: one tracker's report parser feeding one fusion, the path every report takes
 * whether it comes live from a device or from a raw recording (so replayed raw data is fused
 * exactly as it was live). Plain data, no allocation, no I/O, no clock. */
struct trk_stream {
    enum trk_device_kind kind;
    union {
        struct trk_rift_parser rift; /* DK1, DK2, CV1 */
        struct trk_psvr_parser psvr;
        struct trk_vive_parser vive; /* Vive; Vive Pro / Index (model Pro until the caller sets cal) */
        struct trk_hdk_parser hdk;
    } parser;
    struct trk_fusion fusion;
    uint64_t reports;          /* reports fed (accepted + rejected) */
    uint64_t rejected;         /* reports the parser refused (−1; nothing changed) */
    uint64_t samples;          /* samples the parser produced */
    uint64_t fused;            /* samples the fusion accepted (HDK: orientations taken) */
    uint64_t fusion_refused;   /* samples the fusion refused (non-finite) */
    int64_t newest_time_ns;    /* device time of the newest fused sample (HDK: host time) */
    int has_sample;
    /* A device counter that jumps back and stays back (the device restarted its clock without
     * re-enumerating) would make every later sample "backward" for up to half the counter's range
     * (36 min on a DK2). After TRK_STREAM_RESYNC_REPORTS reports in a row that gave only backward
     * samples the parser's clock restarts and the new counter is offset (time_offset_ns) to go on
     * 1 ms after the newest fused sample: times stay increasing, the fusion continues, and
     * counter_resets says it happened. A forward jump needs nothing: the fusion clamps the gap. */
    uint64_t counter_resets;
    int backward_run;          /* consecutive reports that gave only backward samples */
    int offset_pending;        /* the next sample sets time_offset_ns */
    int64_t time_offset_ns;    /* added to every device time from the parser */
    hl_quatd hdk_last_q;       /* HDK: previous on-device orientation (ω from differences, v1) */
};

#define TRK_STREAM_RESYNC_REPORTS 32 /* 32 ms at 1 kHz; PSVR's stale replay is drained before (§2c) */

/* Resets s for a tracker of `kind`. cfg NULL: fusion defaults. */
void trk_stream_init(struct trk_stream *s, enum trk_device_kind kind, const struct trk_fusion_config *cfg_or_null);

/* Parses one report (dispatch on kind) and feeds each new sample to the fusion at its device time
 * (seconds of the unwrapped device clock; HDK has no clock, host_time_ns stands in), then its
 * magnetometer reading, if any, to trk_fusion_update_mag (when cfg.use_magnetometer). HDK gives an
 * on-device fused orientation: it is taken as is (no integration) with its angular velocity, or ω
 * from consecutive orientations for version-1 reports. Returns the number of samples fused, or −1
 * for a rejected report (counted in `rejected`; nothing else changes) with err. */
int trk_stream_feed(struct trk_stream *s, const uint8_t *report, size_t length, int64_t host_time_ns,
                    struct hl_error *err);

/* The latest fused orientation predicted horizon_s ahead (trk_fusion_predict), its angular velocity
 * in the world frame, time_s = device time of the newest sample + horizon_s; no position, gaze locked
 * to the head. Before any sample: identity at time horizon_s. */
void trk_stream_pose(const struct trk_stream *s, double horizon_s, struct trk_pose *out);

#endif
