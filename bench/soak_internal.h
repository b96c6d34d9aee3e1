/* Internal to bench/: the two inputs of the soak (soak.c): the looped trace as a pose source and
 * the fake tracker thread. */
#ifndef HMDLOD_BENCH_SOAK_INTERNAL_H
#define HMDLOD_BENCH_SOAK_INTERNAL_H

#include <pthread.h>
#include <stdatomic.h>

#include "bench/bench.h"
#include "live/live.h"
#include "replay/replay.h"
#include "tracking/tracking.h"

/* A pose source over a trace looped on the wall clock (soak_source.c), mirrored: time t lies in loop
 * k = floor((t − t0_s) / span), played forward when k is even and backward (angular velocities
 * negated) when odd, so each loop starts where the last ended — no jump in orientation, no frame
 * dropped at the wrap — and the poses repeat exactly with a period of two spans, so that two whole
 * periods of a run show the same content and their frame times can be compared for drift. Takes
 * the trace's arrays (zeroes *trace). Positions are dropped (a looped walk would jump). */
int bch_soak_source_create(struct rpl_trace *trace, double t0_s, struct trk_pose_source **out, struct hl_error *err);
long bch_soak_source_loops(const struct trk_pose_source *src);     /* wraps passed so far */
double bch_soak_source_period_s(const struct trk_pose_source *src); /* two spans: the content's period */

/* The fake tracker (soak_tracker.c): its own thread feeds one DK2 report per millisecond of the
 * wall clock (absolute sleeps; late ones are fed at once, as a kernel queue would hand them over),
 * made by trk_encoder from the looped IMU rows (device clock continuous across loops, so the 32-bit
 * µs counter wraps as a DK2's does after 71.6 min), through trk_stream_feed (parser + fusion) and
 * trk_stream_pose. Counters are atomics the frame loop reads. */
struct bch_soak_tracker {
    const struct trk_imu_csv_row *rows;
    size_t n;
    int64_t period_ns;
    pthread_t thread;
    int started;
    atomic_int stop, failed;
    atomic_uint_fast64_t reports, rejected, nonfinite, refused, loops;
    /* The rate first and last: reports and the time (ns after the thread's start) when 10 % and 90 %
     * of the duration had passed, taken by this thread between its own reports (1 ms resolution,
     * whatever the frames do), and at its stop. */
    int64_t mark_after_ns[2];
    atomic_uint_fast64_t mark_reports[2];
    atomic_int_fast64_t mark_ns[2], stop_ns;
    char error[600]; /* "soak tracker: " + an hl_error message */
};
int bch_soak_tracker_start(struct bch_soak_tracker *t, const struct trk_imu_csv_row *rows, size_t n,
                           double duration_s, struct hl_error *err);
/* Reports per second over the first and the last 10 % of the duration (after stop); NaN if unknown. */
void bch_soak_tracker_rates(const struct bch_soak_tracker *t, double out[2]);
void bch_soak_tracker_stop(struct bch_soak_tracker *t);

/* The process's memory at one moment (soak_memory.c), KiB; −1 where unknown. RSS from
 * /proc/self/statm; malloc's bytes in use (arenas + mmapped blocks) and free inside its arenas from
 * glibc's mallinfo2; with smaps, the resident pages of /proc/self/smaps summed by kind of mapping:
 * [heap] (the main arena's brk heap), anonymous (thread arenas, large mmapped blocks, a driver's own
 * mappings, JIT code) and file-backed (libraries, mapped files), and the number of mappings. */
struct bch_soak_memory {
    long rss_kib, heap_in_use_kib, heap_free_kib;
    long heap_map_kib, anon_map_kib, file_map_kib, mappings;
    long fds; /* open file descriptors */
};
/* n doubles (malloc; free() them), each set to NaN ("not measured yet") so that every page is written
 * and resident before the clock starts. Not malloc + memset(0): the compiler may merge the two into
 * calloc, which leaves fresh mmapped pages untouched, and they then turn resident as the run fills
 * them (32 bytes a frame, about 5 MB an hour here), counted as the session's growth. NULL when out of
 * memory or n < 1. */
double *bch_soak_series_alloc(long n);
/* with_smaps 0 skips smaps (it walks every mapping's pages: about a millisecond here). */
void bch_soak_memory_read(struct bch_soak_memory *m, int with_smaps);

#endif
