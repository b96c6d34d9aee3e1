/* replay/live.h: the live session — the frame loop on the wall clock, in a window (a desk or a
 * headset's output), poses from a tracker or from the mouse and keys, the distortion pass, pacing
 * at the display's refresh. Part of the replay/replay.h umbrella. docs/live.md. */
#ifndef HMDLOD_REPLAY_LIVE_H
#define HMDLOD_REPLAY_LIVE_H

#include <stdio.h>

struct frm_options;

struct rpl_live_options {
    const struct frm_options *session; /* scene, display, selector, budget, gaze …; out_dir unused */
    const char *device;       /* "none" (desk), "auto" (a tracker if one is found, else desk) or a hidraw path */
    int monitor;              /* −1: a window on the desktop; else fullscreen on that monitor */
    long frames;              /* 0: until Esc, the window's close button or SIGINT */
    const char *capture_path; /* PNG of the distorted output at the end (and on key C); NULL: none */
    const char *record_path;  /* head trace CSV (t_s,qw,qx,qy,qz) of the session; NULL: none. With a
                               * tracker also its raw reports, .csv replaced by .raw */
    const char *log_path;     /* per-frame CSV (times, present interval, missed slots); NULL: none */
    double yaw_degps;         /* desk: scripted yaw rate added to the mouse (deterministic motion) */
    double rate_hz;           /* 0: the display profile's refresh */
    int quiet_status;         /* no status line on the terminal */
    int window_w_px, window_h_px; /* windowed size; 0: the display's two eyes, scaled to fit the monitor */
};
void rpl_live_options_defaults(struct rpl_live_options *o);

struct rpl_live_summary {
    long frames, missed_frames;  /* missed: refresh slots that passed without a new frame */
    double rate_hz, period_ms, budget_ms;
    int self_paced;              /* 1: paced on the monotonic clock (swap interval did not throttle) */
    double present_median_ms, present_p99_ms, present_stddev_ms, present_max_ms; /* intervals */
    /* The same over the intervals between two frames that both made their slots: the pacing's own
     * jitter, without the frames that did not fit (the "when the frame fits its budget"). */
    double on_time_median_ms, on_time_p99_ms, on_time_stddev_ms;
    long on_time_intervals;
    double frame_mean_ms, frame_p99_ms, distortion_mean_ms, distortion_p99_ms;
    double to_present_mean_ms, to_present_p99_ms; /* frame start (pose asked for) to the swap's return */
    double triangles_mean, optimizer_us_mean;
    long deadlines_met;
    int window_w, window_h, has_lens;
    long tracker_losses, tracker_resumes;
    char source[96], display[64], scene[64], selector[32], renderer[128], pacing[160];
    char gaze[16];                  /* at the end (keys change it, as they do the selector and terms) */
    int velocity_term, eccentricity_term;
    char capture[512];          /* path written, or empty */
    char raw_record[512];       /* the tracker's raw recording beside --record's CSV, or empty */
    long raw_reports;
};

/* Runs a live session until its frames are done or the user stops it; fills *summary. 0 or −1 with err. */
int rpl_live_run(const struct rpl_live_options *o, struct rpl_live_summary *summary, struct hl_error *err);
void rpl_live_summary_print(FILE *f, const struct rpl_live_summary *s);

#endif
