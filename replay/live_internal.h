/* Internal to replay/: the pieces of the live session (live.c). */
#ifndef HMDLOD_REPLAY_LIVE_INTERNAL_H
#define HMDLOD_REPLAY_LIVE_INTERNAL_H

#include <stdint.h>
#include "replay/run_internal.h"
#include "tracking/tracking.h"

/* The desk pose source (desk_source.c): yaw_rate_degps of scripted yaw from t0_s (monotonic s). */
int rpl_desk_source_create(double t0_s, double yaw_rate_degps, struct trk_pose_source **out, struct hl_error *err);
/* Mouse and keys: turn by these angles, which took dt_s (for the angular velocity). */
void rpl_desk_source_look(struct trk_pose_source *src, double dyaw_rad, double dpitch_rad, double dt_s);

/* Present-interval pacing (live_pace.c): frame k is due at t0 + k·period; self-paced sleeps on the
 * monotonic clock until then; a frame ready after its slot is presented at once and the slots it
 * passed count as missed. */
struct rpl_pacer {
    int64_t t0_ns, period_ns, last_present_ns;
    long slot;            /* the slot the next frame is due in */
    long missed;
    int self_paced;
    /* The clock slots are on, Monado style (os_monotonic_get_ns): hl_clock_now_ns unless a test
     * sets another after init; on another clock it sleeps relative to it, so any clock works. */
    int64_t (*clock_ns)(void);
    /* Times the clock moved by more than RPL_PACER_JUMP_NS against the schedule: backward (the slot
     * is re-anchored one period ahead; no sleep of the jump's length) or forward (the slots that
     * passed are counted as missed, and the present interval is not a sample). */
    long clock_jumps;
    /* Idle heap trim: at most every RPL_PACER_TRIM_EVERY_NS, in a frame's slack of at least
     * RPL_PACER_TRIM_SLACK_NS, plan() returns the allocator's free pages to the system (glibc
     * malloc_trim; Mesa's threads free per-frame memory that malloc would otherwise keep resident,
     * so RSS ratchets up over an hour while the heap stays flat: docs/RESULTS.md "Soak"). A test may
     * set trim to its own function (or NULL: none) after init. */
    void (*trim)(void);
    int64_t last_trim_ns, trim_max_ns;
    long trims;
};
#define RPL_PACER_JUMP_NS 1000000000LL /* 1 s: no frame's work or slot lies that far from now */
#define RPL_PACER_TRIM_EVERY_NS 10000000000LL /* 10 s */
#define RPL_PACER_TRIM_SLACK_NS 4000000LL     /* 4 ms: a trim measured 0.06-1.5 ms on llvmpipe */
void rpl_pacer_init(struct rpl_pacer *p, double rate_hz, int self_paced, int64_t now_ns);
int64_t rpl_pacer_due_ns(const struct rpl_pacer *p); /* the next frame's display time */
/* Before a frame (self-paced): when now + expected_work_ns (the last frame's work) is past the due
 * slot, moves to the first slot the frame can make, counting the skipped ones as missed, so that the
 * pose is predicted to when the frame will really be shown. Either mode: the idle heap trim, when due
 * and the frame's slack allows it. */
void rpl_pacer_plan(struct rpl_pacer *p, int64_t expected_work_ns);
/* Before the swap: waits (self-paced) until the slot, counts missed slots when late. */
void rpl_pacer_wait(struct rpl_pacer *p);
/* After the swap returned at present_ns: the interval since the previous present (0 for the first;
 * also 0 after a present more than RPL_PACER_JUMP_NS before or after the previous one: a clock
 * jump or a stall is not a present interval, and is counted in clock_jumps). */
double rpl_pacer_presented(struct rpl_pacer *p, int64_t present_ns);

/* Bookkeeping (live_io.c). A growing series of per-frame values, and its statistics: mean,
 * population stddev, median, p99 (nearest rank), max (any may be NULL; sorts in place). */
/* Per-frame times of a session that may run for hours in bounded memory: the first
 * RPL_LIVE_SERIES_EXACT values are kept exactly (statistics exact); beyond that they are folded into
 * log-spaced bins 0.1 % wide from 1 µs to 100 s (median and p99 then within 0.1 %; mean, stddev and
 * max stay exact, by Welford's update). Memory is fixed after the first push. */
#define RPL_LIVE_SERIES_EXACT 65536
struct rpl_live_series {
    double *v;      /* exact values while n <= RPL_LIVE_SERIES_EXACT */
    uint32_t *bins; /* NULL until the exact buffer is full */
    long n;         /* values pushed */
    double mean, m2, max;
};
int rpl_live_series_push(struct rpl_live_series *s, double x); /* 0, or −1 out of memory */
void rpl_live_series_stats(struct rpl_live_series *s, double *mean, double *stddev, double *median, double *p99,
                           double *max);
void rpl_live_series_free(struct rpl_live_series *s);
/* A CSV written beside its name (".partial") and renamed by commit; abort removes it. path NULL:
 * nothing is opened (rows are dropped). record_row writes a head-trace row (t from the first); a row
 * whose time is not after the last row's is dropped and counted (dropped_rows), so the file stays a
 * valid trace (docs/trace-format.md: time never goes back) whatever the clock did. */
struct rpl_live_record {
    FILE *f; /* out.f while open, NULL otherwise */
    struct hl_out out;
    char path[4096];
    double t0_s;
    long rows;
    int paused; /* key R: rows are not written while paused */
    double last_t_s;   /* pose time of the last row written */
    long dropped_rows; /* rows not written because their time did not move forward (a clock jump) */
};
int rpl_live_record_open(struct rpl_live_record *r, const char *path, const char *header, struct hl_error *err);
void rpl_live_record_row(struct rpl_live_record *r, const struct trk_pose *p);
/* After each row: flushes it. On a failed write (disk full) the file is cut back to its complete rows,
 * renamed into place, and −1 says so ("incomplete"); the session then stops (docs/live.md). */
int rpl_live_record_end_row(struct rpl_live_record *r, struct hl_error *err);
int rpl_live_record_commit(struct rpl_live_record *r, struct hl_error *err);
void rpl_live_record_abort(struct rpl_live_record *r);

#endif
