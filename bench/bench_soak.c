/* hmdlod bench soak: the soak of issue 17 item 7 (bench/soak.h; docs/bench.md "Soak") — an hour by
 * default of looped replay at 90 Hz on the wall clock beside a fake DK2 streaming at 1 kHz, and
 * whether resident memory grew and frame time drifted. The shared data and the table here (the
 * arguments in app/cmd_bench_soak.c); the run in bench/soak.c. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bench/bench.h"
#include "replay/replay.h"

#define SOAK_TRACE "data/traces/corbillon-mmsys18/user1_quaternion.txt"
#define SOAK_IMU "data/imu/corbillon_user1_t30.csv"
#define SOAK_GROWTH_LIMIT_KIB 1024 /* the goal: growth ≤ 1 MB */
#define SOAK_DRIFT_LIMIT 0.05      /* last/first median within ±5 %: see docs/bench.md "Soak" */


static const char *within(double ratio)
{
    return isfinite(ratio) && fabs(ratio - 1.0) <= SOAK_DRIFT_LIMIT ? "no drift (within ±5 %)" : "DRIFT (beyond ±5 %)";
}

static void print_table(const struct bch_soak_summary *s)
{
    long growth = s->rss_end_kib - s->rss_start_kib;
    bch_emit("%s scene, %s selector, %s profile at %.0f Hz, %.0f s (%.1f s ran), warm-up %.1f s; "
               "%ld frames, %ld missed slots; trace looped %ld times, IMU stream %ld times\n\n",
               s->scene, s->selector, s->display, s->rate_hz, s->duration_s, s->elapsed_s, s->warmup_s, s->frames,
               s->missed_slots, s->trace_loops, s->imu_loops);
    bch_emit("Tracker: fake %s, %s.\n\n", s->tracker, s->feed);
    if (s->period_matched)
        bch_emit("First and last: whole periods of the mirrored trace (%.1f s: forward, then backward), the first "
                   "after the warm-up (%.1f-%.1f s) and the last before the end (%.1f-%.1f s): the same poses, so the "
                   "same content.\n\n", s->period_s, s->stretch_s[0][0], s->stretch_s[0][1], s->stretch_s[1][0],
                   s->stretch_s[1][1]);
    else
        bch_emit("First: the 10 %% of the frames that follow the warm-up (%.1f-%.1f s); last: the run's last 10 %% "
                   "(%.1f-%.1f s). The run is too short for two whole periods of the mirrored trace (%.1f s) after the "
                   "warm-up, so content differs between them too.\n\n", s->stretch_s[0][0], s->stretch_s[0][1],
                   s->stretch_s[1][0], s->stretch_s[1][1], s->period_s);
    bch_emit("| measure | start / first | end / last | change | verdict |\n|---|---:|---:|---:|---|\n");
    long median_growth = s->rss_median_kib[1] - s->rss_median_kib[0];
    if (s->rss_median_kib[0] >= 0 && s->rss_median_kib[1] >= 0)
        bch_emit("| RSS kB, median of the rows in each stretch | %ld | %ld | %+ld | %s |\n", s->rss_median_kib[0],
                   s->rss_median_kib[1], median_growth,
                   median_growth <= SOAK_GROWTH_LIMIT_KIB ? "PASS (growth ≤ 1 MB)" : "FAIL (growth > 1 MB)");
    else
        bch_emit("| RSS kB, median of the rows in each stretch | | | | (a stretch holds no row: see the next) |\n");
    static const char *const map_row[3] = {"[heap] mapping (main arena)", "anonymous mappings",
                                            "file-backed mappings"};
    for (int k = 0; k < 3; ++k)
        if (s->map_median_kib[k][0] >= 0 && s->map_median_kib[k][1] >= 0)
            bch_emit("| resident kB in %s, median of the rows | %ld | %ld | %+ld | (not judged: where RSS moves) |\n",
                       map_row[k], s->map_median_kib[k][0], s->map_median_kib[k][1],
                       s->map_median_kib[k][1] - s->map_median_kib[k][0]);
        else
            bch_emit("| resident kB in %s, median of the rows | | | | (a stretch holds no row) |\n", map_row[k]);
    bch_emit("| RSS kB (after warm-up / at end) | %ld | %ld | %+ld | %s |\n", s->rss_start_kib, s->rss_end_kib, growth,
               growth <= SOAK_GROWTH_LIMIT_KIB ? "within 1 MB (one reading each: content moves it by MBs)"
                                               : "beyond 1 MB (one reading each: content moves it by MBs)");
    bch_emit("| malloc in use kB (mallinfo2) | %ld | %ld | %+ld | (not judged: growth here is a leak, RSS growth "
               "without it is memory the allocator or the GL driver keeps) |\n",
               s->heap_start_kib, s->heap_end_kib, s->heap_end_kib - s->heap_start_kib);
    bch_emit("| idle heap trims (malloc_trim in a frame's slack, every 10 s) | | %ld | longest %.2f ms | "
               "(not judged) |\n", s->heap_trims, s->heap_trim_ms_max);
    bch_emit("| open fds | %ld | %ld | %+ld | %s |\n", s->fds_start, s->fds_end, s->fds_end - s->fds_start,
               s->fds_end <= s->fds_start ? "PASS (no growth)" : "FAIL (fds grew)");
    bch_emit("| frame ms median | %.3f | %.3f | ×%.3f | %s |\n", s->frame_ms[0].median, s->frame_ms[1].median,
               s->frame_ms_ratio, within(s->frame_ms_ratio));
    bch_emit("| frame ms p99 | %.3f | %.3f | ×%.3f | (not judged) |\n", s->frame_ms[0].p99, s->frame_ms[1].p99,
               s->frame_ms[1].p99 / s->frame_ms[0].p99);
    bch_emit("| CPU ms per frame median | %.3f | %.3f | ×%.3f | %s |\n", s->cpu_ms[0].median, s->cpu_ms[1].median,
               s->cpu_ms_ratio, within(s->cpu_ms_ratio));
    bch_emit("| CPU ms per frame p99 | %.3f | %.3f | ×%.3f | (not judged) |\n", s->cpu_ms[0].p99, s->cpu_ms[1].p99,
               s->cpu_ms[1].p99 / s->cpu_ms[0].p99);
    bch_emit("| triangles per eye mean | %.0f | %.0f | ×%.3f | (fs adapts to measured cost) |\n",
               s->triangles_mean[0], s->triangles_mean[1], s->triangles_mean[1] / s->triangles_mean[0]);
    bch_emit("| tracker reports/s | %.1f | %.1f | ×%.3f | %s |\n", s->reports_per_s[0], s->reports_per_s[1],
               s->reports_per_s[1] / s->reports_per_s[0],
               fabs(s->reports_per_s[1] / s->reports_per_s[0] - 1.0) <= SOAK_DRIFT_LIMIT ? "steady" : "CHANGED");
    bch_emit("| fusion output | %llu reports | %llu rejected, %llu refused | %llu non-finite | %s |\n\n",
               (unsigned long long)s->reports, (unsigned long long)s->rejected,
               (unsigned long long)s->fusion_refused, (unsigned long long)s->fusion_nonfinite,
               s->fusion_nonfinite == 0 && s->fusion_refused == 0 ? "PASS (finite throughout)" : "FAIL");
    bch_emit("CPU per frame is CLOCK_PROCESS_CPUTIME_ID across the frame: llvmpipe's render threads and the "
               "tracker thread (about 1000 reports/s) are in it, other processes are not.\n\n");
}

int bch_soak(const struct bch_soak_options *options, int full_argc, char **full_argv)
{
    struct bch_soak_options o = *options;
    struct hl_error err;
    if (bch_soak_check_options(&o, &err) != 0) { /* before the shared folder: bad arguments say so first */
        fprintf(stderr, "hmdlod bench soak: %s\n", err.msg);
        return 1;
    }
    char shared[4096], trace[4200], imu[4200];
    if (bch_find_shared(shared, sizeof shared) != 0) {
        fprintf(stderr, "hmdlod bench soak: the shared data folder is absent (%s): the soak needs its trace and "
                        "IMU stream\n", shared);
        return 1;
    }
    snprintf(trace, sizeof trace, "%s/" SOAK_TRACE, shared);
    snprintf(imu, sizeof imu, "%s/" SOAK_IMU, shared);
    o.trace_path = trace;
    o.imu_path = imu;
    struct bch_soak_summary s;
    if (bch_soak_run(&o, &s, &err) != 0) {
        fprintf(stderr, "hmdlod bench soak: %s\n", err.msg);
        return 1;
    }
    bch_emit("## Soak (hmdlod bench soak)\n\n");
    bch_print_context(full_argc, full_argv, s.renderer);
    print_table(&s);
    fprintf(stderr, "hmdlod bench soak: wrote %s/soak.csv and %s/summary.json\n", o.out_dir, o.out_dir);
    return 0;
}
