/* bench/soak.h: the soak (issue 17 item 7; docs/bench.md "Soak") — for a long wall-clock duration,
 * the replay frame (session.c, frame.c) over a looped head-motion trace, paced at the display's
 * refresh as a live session is, beside a fake tracker streaming a looped 1 kHz IMU stream as DK2
 * reports through the real parser, stream and fusion (tracking/stream.h) on its own thread. Every
 * sample period it records resident memory, open fds, frames and reports, so that growth and drift
 * over an hour show. Part of the bench/bench.h umbrella. */
#ifndef HMDLOD_BENCH_SOAK_H
#define HMDLOD_BENCH_SOAK_H

#include <stdint.h>

#include "base/base.h"

struct bch_soak_options {
    const char *trace_path; /* head-motion trace, looped end to end (any format rpl_trace_load reads) */
    const char *imu_path;   /* 1 kHz IMU CSV (shared data README §5), looped into DK2 reports */
    const char *out_dir;    /* soak.csv and summary.json; created if missing */
    double duration_s;      /* wall-clock length of the run */
    double sample_s;        /* one soak.csv row per this many seconds */
    double render_scale;    /* per-eye resolution factor of the Vive's pixels */
};
void bch_soak_options_defaults(struct bch_soak_options *o); /* 3600 s, 10 s, 0.5 */
/* The ranges (duration 1 s … 7 days, sample 0.1 s … the duration, render scale (0, 4], an output
 * folder named); the paths are checked when read. 0, or −1 with err naming the option. */
int bch_soak_check_options(const struct bch_soak_options *o, struct hl_error *err);

/* Median and p99 (nearest rank) of a stretch of frames. */
struct bch_soak_stats {
    double median, p99;
};

struct bch_soak_summary {
    double duration_s, warmup_s, rate_hz, elapsed_s;
    long frames, missed_slots, samples;
    long warm_frames;                /* frames done when the warm-up ended */
    long first_frame;                /* where the first stretch starts */
    /* The stretches compared (soak.c choose_stretches): 1 when they are whole periods of the mirrored
     * trace (same content), 0 when they are the first 10 % of the frames after the warm-up and the
     * last 10 % (a run too short for that). Their display times, s after the trace's start. */
    int period_matched;
    double period_s, stretch_s[2][2];
    long rss_median_kib[2];          /* median RSS of the soak.csv rows in each stretch; −1 if none */
    /* the same medians of the rows' resident kB by mapping (soak_internal.h: bch_soak_memory):
     * [0] the [heap] mapping, [1] anonymous mappings, [2] file-backed ones */
    long map_median_kib[3][2];
    long trace_loops, imu_loops;     /* times each input wrapped */
    uint64_t reports, rejected;      /* tracker reports fed; refused by the parser */
    uint64_t fusion_nonfinite;       /* fused poses with a non-finite component (0 when healthy) */
    uint64_t fusion_refused;         /* samples the fusion refused (trk_stream) */
    long rss_start_kib, rss_end_kib; /* /proc/self/statm after the warm-up, at the end */
    long heap_start_kib, heap_end_kib; /* malloc's bytes in use (mallinfo2) then; −1 where unknown */
    long fds_start, fds_end;         /* entries of /proc/self/fd at the same two moments */
    long heap_trims;                 /* idle heap trims the pacer made (live/live.h) */
    double heap_trim_ms_max;         /* the longest of them */
    /* [0]: the first stretch, [1]: the last */
    struct bch_soak_stats frame_ms[2], cpu_ms[2];
    double triangles_mean[2];
    double reports_per_s[2];          /* over the first and the last 10 % of the wall time */
    double frame_ms_ratio, cpu_ms_ratio; /* last / first medians */
    char renderer[128], selector[16], display[64], scene[32], tracker[16];
    char feed[96];                    /* how reports reach the parser */
};

/* Runs the soak; writes out_dir/soak.csv (a row per sample, flushed as it goes under a temporary name,
 * renamed at the end) and out_dir/summary.json. 0, or −1 with err. */
int bch_soak_run(const struct bch_soak_options *o, struct bch_soak_summary *s, struct hl_error *err);

#endif
