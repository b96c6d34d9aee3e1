/* live: the wall-clock session in a window — frame/'s frame on the wall clock, in a window (a desk
 * or a headset's output), poses from a tracker or from the mouse and keys (the desk pose source),
 * the distortion hand-off, pacing at the display's refresh, the session's log and head recording.
 * Prefix liv_. docs/live.md. It runs frame/ with render/'s window and tracking/'s drivers; it may
 * not touch replay/ or bench/. */
#ifndef HMDLOD_LIVE_H
#define HMDLOD_LIVE_H

#include <stdint.h>
#include <stdio.h>

#include "base/base.h"
#include "tracking/tracking.h"
#include "frame/frame.h"


struct liv_options {
    const struct frm_options *session; /* scene, display, selector, budget, gaze … */
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
void liv_options_defaults(struct liv_options *o);

struct liv_summary {
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
int liv_run(const struct liv_options *o, struct liv_summary *summary, struct hl_error *err);
void liv_summary_print(FILE *f, const struct liv_summary *s);

/* ---- the session's parts (live.c uses them; the soak paces its frames with the pacer) --------- */

/* The desk pose source (desk_source.c): yaw_rate_degps of scripted yaw from t0_s (monotonic s). */
int liv_desk_source_create(double t0_s, double yaw_rate_degps, struct trk_pose_source **out, struct hl_error *err);
/* Mouse and keys: turn by these angles, which took dt_s (for the angular velocity). */
void liv_desk_source_look(struct trk_pose_source *src, double dyaw_rad, double dpitch_rad, double dt_s);

/* Present-interval pacing (live_pace.c): frame k is due at t0 + k·period; self-paced sleeps on the
 * monotonic clock until then; a frame ready after its slot is presented at once and the slots it
 * passed count as missed. */
struct liv_pacer {
    int64_t t0_ns, period_ns, last_present_ns;
    long slot;            /* the slot the next frame is due in */
    long missed;
    int self_paced;
    /* The clock slots are on, Monado style (os_monotonic_get_ns): hl_clock_now_ns unless a test
     * sets another after init; on another clock it sleeps relative to it, so any clock works. */
    int64_t (*clock_ns)(void);
    /* Times the clock moved by more than LIV_PACER_JUMP_NS against the schedule: backward (the slot
     * is re-anchored one period ahead; no sleep of the jump's length) or forward (the slots that
     * passed are counted as missed, and the present interval is not a sample). */
    long clock_jumps;
    /* Idle heap trim: at most every LIV_PACER_TRIM_EVERY_NS, in a frame's slack of at least
     * LIV_PACER_TRIM_SLACK_NS, plan() returns the allocator's free pages to the system (glibc
     * malloc_trim; Mesa's threads free per-frame memory that malloc would otherwise keep resident,
     * so RSS ratchets up over an hour while the heap stays flat: docs/RESULTS.md "Soak"). A test may
     * set trim to its own function (or NULL: none) after init. */
    void (*trim)(void);
    int64_t last_trim_ns, trim_max_ns;
    long trims;
};
#define LIV_PACER_JUMP_NS 1000000000LL /* 1 s: no frame's work or slot lies that far from now */
#define LIV_PACER_TRIM_EVERY_NS 10000000000LL /* 10 s */
#define LIV_PACER_TRIM_SLACK_NS 4000000LL     /* 4 ms: a trim measured 0.06-1.5 ms on llvmpipe */
void liv_pacer_init(struct liv_pacer *p, double rate_hz, int self_paced, int64_t now_ns);
int64_t liv_pacer_due_ns(const struct liv_pacer *p); /* the next frame's display time */
/* Before a frame (self-paced): when now + expected_work_ns (the last frame's work) is past the due
 * slot, moves to the first slot the frame can make, counting the skipped ones as missed, so that the
 * pose is predicted to when the frame will really be shown. Either mode: the idle heap trim, when due
 * and the frame's slack allows it. */
void liv_pacer_plan(struct liv_pacer *p, int64_t expected_work_ns);
/* Before the swap: waits (self-paced) until the slot, counts missed slots when late. */
void liv_pacer_wait(struct liv_pacer *p);
/* After the swap returned at present_ns: the interval since the previous present (0 for the first;
 * also 0 after a present more than LIV_PACER_JUMP_NS before or after the previous one: a clock
 * jump or a stall is not a present interval, and is counted in clock_jumps). */
double liv_pacer_presented(struct liv_pacer *p, int64_t present_ns);

/* Bookkeeping (live_io.c). A growing series of per-frame values, and its statistics: mean,
 * population stddev, median, p99 (nearest rank), max (any may be NULL; sorts in place). */
/* Per-frame times of a session that may run for hours in bounded memory: the first
 * LIV_SERIES_EXACT values are kept exactly (statistics exact); beyond that they are folded into
 * log-spaced bins 0.1 % wide from 1 µs to 100 s (median and p99 then within 0.1 %; mean, stddev and
 * max stay exact, by Welford's update). Memory is fixed after the first push. */
#define LIV_SERIES_EXACT 65536
struct liv_series {
    double *v;      /* exact values while n <= LIV_SERIES_EXACT */
    uint32_t *bins; /* NULL until the exact buffer is full */
    long n;         /* values pushed */
    double mean, m2, max;
};
int liv_series_push(struct liv_series *s, double x); /* 0, or −1 out of memory */
void liv_series_stats(struct liv_series *s, double *mean, double *stddev, double *median, double *p99,
                           double *max);
void liv_series_free(struct liv_series *s);
/* A CSV written beside its name (".partial") and renamed by commit; abort removes it. path NULL:
 * nothing is opened (rows are dropped). record_row writes a head-trace row (t from the first); a row
 * whose time is not after the last row's is dropped and counted (dropped_rows), so the file stays a
 * valid trace (docs/trace-format.md: time never goes back) whatever the clock did. */
struct liv_record {
    FILE *f; /* out.f while open, NULL otherwise */
    struct hl_out out;
    char path[4096];
    double t0_s;
    long rows;
    int paused; /* key R: rows are not written while paused */
    double last_t_s;   /* pose time of the last row written */
    long dropped_rows; /* rows not written because their time did not move forward (a clock jump) */
};
int liv_record_open(struct liv_record *r, const char *path, const char *header, struct hl_error *err);
void liv_record_row(struct liv_record *r, const struct trk_pose *p);
/* After each row: flushes it. On a failed write (disk full) the file is cut back to its complete rows,
 * renamed into place, and −1 says so ("incomplete"); the session then stops (docs/live.md). */
int liv_record_end_row(struct liv_record *r, struct hl_error *err);
int liv_record_commit(struct liv_record *r, struct hl_error *err);
void liv_record_abort(struct liv_record *r);

#endif
