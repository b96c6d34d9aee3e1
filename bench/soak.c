/* The soak (bench/soak.h; issue 17 item 7). One process, two threads: this one runs the replay
 * frame (frm_frame_run, the code `hmdlod replay` and `hmdlod live` use) over a looped trace, paced
 * by the live loop's pacer (live_pace.c) on the wall clock at the display's refresh; the other is the
 * fake tracker (soak_tracker.c). Threads rather than one loop that also drains the tracker, because
 * a live tracker's reports arrive while a frame renders (tracking/hid.c reads on its own thread too),
 * and 1 kHz pacing inside an 11 ms frame loop would bunch them. Everything the run keeps per frame is
 * allocated and touched before the clock starts, so resident memory measures the session, not the
 * bookkeeping. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "live/live.h"
#include "bench/soak_internal.h"

void bch_soak_options_defaults(struct bch_soak_options *o)
{
    memset(o, 0, sizeof *o);
    o->duration_s = 3600.0;
    o->sample_s = 10.0;
    o->render_scale = 0.5;
}

static double process_cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sorts v[0..n) (n > 0) in place; its median (the lower of the middle two). */
static double sort_median(double *v, long n)
{
    qsort(v, (size_t)n, sizeof *v, compare_double);
    return v[(n - 1) / 2];
}

/* Median and p99 (nearest rank) of v[0..n), sorted into scratch. */
static struct bch_soak_stats stretch_stats(const double *v, long n, double *scratch)
{
    struct bch_soak_stats st = {NAN, NAN};
    if (n <= 0)
        return st;
    memcpy(scratch, v, (size_t)n * sizeof *v);
    st.median = sort_median(scratch, n);
    long r = (long)ceil(0.99 * (double)n);
    st.p99 = scratch[(r < 1 ? 1 : r) - 1];
    return st;
}

static double mean_of(const double *v, long n)
{
    double s = 0;
    for (long i = 0; i < n; ++i)
        s += v[i];
    return n > 0 ? s / (double)n : NAN;
}

enum { SOAK_MEMORY_COLUMNS = 4 }; /* the memory kept per row for the stretch medians */

struct soak_run {
    struct frm_session session;
    int session_open;
    struct bch_soak_tracker tracker;
    struct trk_imu_csv_row *rows;
    double *frame_ms, *cpu_ms, *triangles, *scratch;
    double *display_s;          /* each frame's display time, s after the looped trace's t0 */
    long capacity;
    double t0_s;                /* the looped trace's start on the monotonic clock */
    double *sample_t_s;         /* each soak.csv row's time (s after t0_s) */
    double *sample_kib[SOAK_MEMORY_COLUMNS]; /* and its RSS, [heap], anonymous and file-backed resident kB */
    long sample_capacity, samples;
    struct hl_out csv; /* soak.csv, a row marked every sample (base.h: hl_out) */
    int csv_open;
};

static int open_csv(struct soak_run *r, const char *dir, struct hl_error *err)
{
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return hl_fail(err, "%s: cannot create folder: %s", dir, strerror(errno));
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return hl_fail(err, "%s: not a folder", dir);
    char path[4096];
    if (snprintf(path, sizeof path, "%s/soak.csv", dir) >= (int)sizeof path)
        return hl_fail(err, "%s: path too long", dir);
    if (hl_out_open(&r->csv, path, err) != 0)
        return -1;
    r->csv_open = 1;
    fprintf(r->csv.f, "t_s,rss_kib,heap_kib,open_fds,frames,reports,missed_slots,frame_ms_mean,cpu_ms_mean,triangles_mean,"
                      "fusion_nonfinite,trace_loops,imu_loops,heap_free_kib,heap_map_kib,anon_map_kib,file_map_kib,"
                      "mappings\n");
    return hl_out_mark(&r->csv, err);
}

/* A JSON number, or null where it is not finite (a stretch with no frames): JSON has no NaN. */
static void json_num(FILE *f, const char *key, double v, const char *tail)
{
    if (isfinite(v))
        fprintf(f, "\"%s\": %.4f%s", key, v, tail);
    else
        fprintf(f, "\"%s\": null%s", key, tail);
}

/* summary.json into o (open, not yet committed). */
static void write_summary_json(FILE *f, const struct bch_soak_summary *s)
{
    fprintf(f, "{\n  \"duration_s\": %.3f,\n  \"elapsed_s\": %.3f,\n  \"warmup_s\": %.3f,\n  \"rate_hz\": %.3f,\n",
            s->duration_s, s->elapsed_s, s->warmup_s, s->rate_hz);
    fprintf(f, "  \"renderer\": \"%s\",\n  \"selector\": \"%s\",\n  \"display\": \"%s\",\n  \"scene\": \"%s\",\n",
            s->renderer, s->selector, s->display, s->scene);
    fprintf(f, "  \"tracker\": \"%s\",\n  \"feed\": \"%s\",\n", s->tracker, s->feed);
    fprintf(f, "  \"warm_frames\": %ld,\n  \"first_stretch_frame\": %ld,\n", s->warm_frames, s->first_frame);
    fprintf(f, "  \"period_matched\": %s,\n  \"content_period_s\": %.3f,\n", s->period_matched ? "true" : "false",
            s->period_s);
    fprintf(f, "  \"first_stretch_s\": [%.3f, %.3f],\n  \"last_stretch_s\": [%.3f, %.3f],\n", s->stretch_s[0][0],
            s->stretch_s[0][1], s->stretch_s[1][0], s->stretch_s[1][1]);
    fprintf(f, "  \"rss_median_first_kib\": %ld,\n  \"rss_median_last_kib\": %ld,\n", s->rss_median_kib[0],
            s->rss_median_kib[1]);
    const char *map_name[3] = {"heap_map", "anon_map", "file_map"};
    for (int k = 0; k < 3; ++k)
        fprintf(f, "  \"%s_median_first_kib\": %ld,\n  \"%s_median_last_kib\": %ld,\n", map_name[k],
                s->map_median_kib[k][0], map_name[k], s->map_median_kib[k][1]);
    fprintf(f, "  \"frames\": %ld,\n  \"missed_slots\": %ld,\n  \"samples\": %ld,\n  \"trace_loops\": %ld,\n"
               "  \"imu_loops\": %ld,\n", s->frames, s->missed_slots, s->samples, s->trace_loops, s->imu_loops);
    fprintf(f, "  \"reports\": %llu,\n  \"reports_rejected\": %llu,\n  \"fusion_nonfinite\": %llu,\n"
               "  \"fusion_refused\": %llu,\n", (unsigned long long)s->reports, (unsigned long long)s->rejected,
            (unsigned long long)s->fusion_nonfinite, (unsigned long long)s->fusion_refused);
    fprintf(f, "  \"rss_start_kib\": %ld,\n  \"rss_end_kib\": %ld,\n  \"rss_growth_kib\": %ld,\n"
               "  \"fds_start\": %ld,\n  \"fds_end\": %ld,\n", s->rss_start_kib, s->rss_end_kib,
            s->rss_end_kib - s->rss_start_kib, s->fds_start, s->fds_end);
    fprintf(f, "  \"heap_start_kib\": %ld,\n  \"heap_end_kib\": %ld,\n", s->heap_start_kib, s->heap_end_kib);
    fprintf(f, "  \"heap_trims\": %ld,\n  \"heap_trim_ms_max\": %.3f,\n", s->heap_trims, s->heap_trim_ms_max);
    const char *part[2] = {"first", "last"};
    for (int i = 0; i < 2; ++i) {
        fprintf(f, "  \"%s\": {", part[i]);
        json_num(f, "frame_ms_median", s->frame_ms[i].median, ", ");
        json_num(f, "frame_ms_p99", s->frame_ms[i].p99, ", ");
        json_num(f, "cpu_ms_median", s->cpu_ms[i].median, ", ");
        json_num(f, "cpu_ms_p99", s->cpu_ms[i].p99, ", ");
        json_num(f, "triangles_mean", s->triangles_mean[i], ", ");
        json_num(f, "reports_per_s", s->reports_per_s[i], "},\n");
    }
    fputs("  ", f);
    json_num(f, "frame_ms_median_ratio", s->frame_ms_ratio, ",\n  ");
    json_num(f, "cpu_ms_median_ratio", s->cpu_ms_ratio, "\n}\n");
}

/* soak.csv and summary.json belong together: both closed (every write checked, synced) before
 * either is renamed into place, so a full disk leaves neither new file (base.h: hl_out_close). */
static int commit_outputs(struct soak_run *r, const char *dir, const struct bch_soak_summary *s,
                          struct hl_error *err)
{
    char path[4096];
    struct hl_out json;
    if (snprintf(path, sizeof path, "%s/summary.json", dir) >= (int)sizeof path)
        return hl_fail(err, "%s: path too long", dir);
    if (hl_out_open(&json, path, err) != 0)
        return -1;
    write_summary_json(json.f, s);
    if (hl_out_close(&r->csv, err) != 0 || hl_out_close(&json, err) != 0 || hl_out_commit(&r->csv, err) != 0) {
        hl_out_abort(&json);
        return -1;
    }
    r->csv_open = 0;
    return hl_out_commit(&json, err);
}

/* Index of the first frame shown at or after t_s (display times increase), from lo on. */
static long frame_at(const struct soak_run *r, long lo, long hi, double t_s)
{
    while (lo < hi) {
        long mid = lo + (hi - lo) / 2;
        if (r->display_s[mid] < t_s)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The two stretches compared for drift. Where the run holds them, whole periods of the mirrored
 * trace (soak_internal.h): the first that starts after the warm-up and the last that ends before
 * the run does, so both show the same poses and the same content, and a difference between them is
 * the program's. Otherwise (a run shorter than the warm-up and three periods) the 10 % of the
 * frames after the warm-up and the last 10 %, where content differs too. */
static void choose_stretches(const struct soak_run *r, double period_s, struct bch_soak_summary *s, long from[2],
                             long count[2])
{
    long n = s->frames;
    s->period_s = period_s;
    s->period_matched = 0;
    if (n > 1 && s->warm_frames < n) {
        double a = period_s * ceil(r->display_s[s->warm_frames] / period_s);
        double b1 = period_s * floor(r->display_s[n - 1] / period_s), b0 = b1 - period_s;
        if (b0 >= a + period_s) {
            s->period_matched = 1;
            double edge[2][2] = {{a, a + period_s}, {b0, b1}};
            for (int j = 0; j < 2; ++j) {
                from[j] = frame_at(r, 0, n, edge[j][0]);
                count[j] = frame_at(r, from[j], n, edge[j][1]) - from[j];
                s->stretch_s[j][0] = edge[j][0], s->stretch_s[j][1] = edge[j][1];
            }
            return;
        }
    }
    long tenth = n / 10 > 0 ? n / 10 : (n > 0 ? 1 : 0);
    /* the first stretch starts after the warm-up (the driver's and the cost correction's settling
     * is not drift), unless that leaves no room before the last stretch */
    from[0] = s->warm_frames + tenth <= n - tenth ? s->warm_frames : 0;
    from[1] = n - tenth;
    count[0] = count[1] = tenth;
    for (int j = 0; j < 2; ++j) {
        s->stretch_s[j][0] = tenth > 0 ? r->display_s[from[j]] : 0.0;
        s->stretch_s[j][1] = tenth > 0 ? r->display_s[from[j] + tenth - 1] : 0.0;
    }
}

/* Median of one memory column (sample_kib[k]) over the soak.csv rows taken within [t0_s, t1_s] (s
 * after the trace's t0); −1 if none. */
static long sample_median_kib(struct soak_run *r, int k, double t0_s, double t1_s)
{
    long m = 0;
    for (long i = 0; i < r->samples; ++i)
        if (r->sample_t_s[i] >= t0_s && r->sample_t_s[i] <= t1_s)
            r->scratch[m++] = r->sample_kib[k][i];
    return m > 0 ? (long)sort_median(r->scratch, m) : -1;
}

int bch_soak_check_options(const struct bch_soak_options *o, struct hl_error *err)
{
    if (!o->out_dir || !*o->out_dir)
        return hl_fail(err, "--out: an output folder is required");
    if (!(o->duration_s >= 1.0 && o->duration_s <= 7.0 * 86400.0))
        return hl_fail(err, "--duration-s: %g s is outside [1, 604800]", o->duration_s);
    if (!(o->sample_s >= 0.1 && o->sample_s <= o->duration_s))
        return hl_fail(err, "--sample-s: %g s is outside [0.1, the duration %g s]", o->sample_s, o->duration_s);
    if (!(o->render_scale > 0.0 && o->render_scale <= 4.0))
        return hl_fail(err, "--render-scale: %g is outside (0, 4]", o->render_scale);
    return 0;
}

/* Opens the trace, the IMU stream and the session, and sizes the per-frame arrays. */
static int soak_open(struct soak_run *r, const struct bch_soak_options *o, double *rate_hz, struct hl_error *err)
{
    struct rpl_trace trace;
    size_t n_rows = 0;
    if (trk_imu_csv_read(o->imu_path, &r->rows, &n_rows, err) != 0 || rpl_trace_load(o->trace_path, &trace, err) != 0)
        return -1;
    struct frm_session_made made = {NULL, NULL};
    r->t0_s = hl_clock_now_s();
    if (bch_soak_source_create(&trace, r->t0_s, &made.source, err) != 0) {
        rpl_trace_free(&trace);
        return -1;
    }
    struct frm_options so;
    frm_options_defaults(&so);
    so.scene = "field";
    so.display = "vive";
    so.selector = "fs";
    so.render_scale = o->render_scale;
    so.quiet = 1;
    enum frm_selector sel;
    enum frm_freq_reading reading;
    r->session_open = 1; /* frm_session_open adopts the source even when it fails: close it then too */
    if (frm_options_check(&so, &sel, &reading, err) != 0) {
        trk_source_destroy(made.source);
        r->session_open = 0;
        return -1;
    }
    if (frm_session_open(&r->session, &so, &made, err) != 0)
        return -1;
    *rate_hz = r->session.display.refresh_hz;
    /* every frame the duration can hold at the refresh, plus a second of slack */
    r->capacity = (long)ceil(o->duration_s * *rate_hz) + (long)ceil(*rate_hz) + 1;
    r->frame_ms = bch_soak_series_alloc(r->capacity), r->cpu_ms = bch_soak_series_alloc(r->capacity);
    r->triangles = bch_soak_series_alloc(r->capacity), r->scratch = bch_soak_series_alloc(r->capacity);
    r->display_s = bch_soak_series_alloc(r->capacity);
    /* a row per sample period and the one after the last full period */
    r->sample_capacity = (long)ceil(o->duration_s / o->sample_s) + 2;
    r->sample_t_s = bch_soak_series_alloc(r->sample_capacity);
    int sample_ok = r->sample_t_s != NULL;
    for (int k = 0; k < SOAK_MEMORY_COLUMNS; ++k)
        sample_ok &= (r->sample_kib[k] = bch_soak_series_alloc(r->sample_capacity)) != NULL;
    if (!r->frame_ms || !r->cpu_ms || !r->triangles || !r->scratch || !r->display_s || !sample_ok)
        return hl_fail(err, "soak: out of memory for %ld frames", r->capacity);
    return bch_soak_tracker_start(&r->tracker, r->rows, n_rows, o->duration_s, err);
}

static void soak_close(struct soak_run *r)
{
    bch_soak_tracker_stop(&r->tracker);
    if (r->session_open)
        frm_session_close(&r->session);
    trk_imu_csv_free(r->rows);
    free(r->frame_ms), free(r->cpu_ms), free(r->triangles), free(r->scratch), free(r->display_s);
    free(r->sample_t_s);
    for (int k = 0; k < SOAK_MEMORY_COLUMNS; ++k)
        free(r->sample_kib[k]);
    if (r->csv_open)
        hl_out_abort(&r->csv);
}

/* One soak.csv row: the state now and the means of the frames since the previous row. */
static int sample_row(struct soak_run *r, double t_s, long frames, long from, long missed, struct hl_error *err)
{
    struct bch_soak_tracker *t = &r->tracker;
    struct bch_soak_memory m;
    bch_soak_memory_read(&m, 1);
    if (r->samples < r->sample_capacity) {
        r->sample_t_s[r->samples] = hl_clock_now_s() - r->t0_s;
        const long kib[SOAK_MEMORY_COLUMNS] = {m.rss_kib, m.heap_map_kib, m.anon_map_kib, m.file_map_kib};
        for (int k = 0; k < SOAK_MEMORY_COLUMNS; ++k)
            r->sample_kib[k][r->samples] = (double)kib[k];
        r->samples++;
    }
    fprintf(r->csv.f, "%.3f,%ld,%ld,%ld,%ld,%llu,%ld,%.4f,%.4f,%.1f,%llu,%ld,%llu,%ld,%ld,%ld,%ld,%ld\n", t_s, m.rss_kib,
            m.heap_in_use_kib, m.fds, frames,
            (unsigned long long)atomic_load(&t->reports), missed, mean_of(r->frame_ms + from, frames - from),
            mean_of(r->cpu_ms + from, frames - from), mean_of(r->triangles + from, frames - from),
            (unsigned long long)atomic_load(&t->nonfinite), bch_soak_source_loops(r->session.source),
            (unsigned long long)atomic_load(&t->loops), m.heap_free_kib, m.heap_map_kib, m.anon_map_kib,
            m.file_map_kib, m.mappings);
    return hl_out_mark(&r->csv, err); /* flushed: a long run can be watched (tail -f on the temporary) */
}

static int soak_loop(struct soak_run *r, const struct bch_soak_options *o, double rate_hz, struct bch_soak_summary *s,
                     struct hl_error *err)
{
    struct liv_pacer pacer;
    int64_t start_ns = hl_clock_now_ns();
    liv_pacer_init(&pacer, rate_hz, 1, start_ns);
    const int64_t duration_ns = (int64_t)llround(o->duration_s * 1e9), sample_ns = (int64_t)llround(o->sample_s * 1e9);
    const int64_t warmup_ns = (int64_t)llround(s->warmup_s * 1e9);
    int64_t next_sample_ns = start_ns + sample_ns, last_work_ns = 0;
    int warm = 0;
    long f = 0, row_from = 0;
    for (; f < r->capacity; ++f) {
        int64_t now = hl_clock_now_ns();
        if (now - start_ns >= duration_ns)
            break;
        if (atomic_load(&r->tracker.failed))
            return hl_fail(err, "%s", r->tracker.error);
        liv_pacer_plan(&pacer, last_work_ns);
        double display_s = (double)liv_pacer_due_ns(&pacer) * 1e-9;
        struct frm_frame_record rec;
        double cpu0 = process_cpu_s();
        int64_t t0 = hl_clock_now_ns();
        if (frm_frame_run(&r->session, f, display_s, &rec, err) != 0)
            return -1;
        int64_t t1 = hl_clock_now_ns();
        r->cpu_ms[f] = (process_cpu_s() - cpu0) * 1e3;
        r->frame_ms[f] = (double)(t1 - t0) * 1e-6;
        r->triangles[f] = (double)rec.triangles_per_eye;
        r->display_s[f] = display_s - r->t0_s;
        last_work_ns = t1 - t0;
        liv_pacer_wait(&pacer);
        now = hl_clock_now_ns();
        liv_pacer_presented(&pacer, now);
        if (!warm && now - start_ns >= warmup_ns) {
            struct bch_soak_memory m;
            bch_soak_memory_read(&m, 0);
            s->rss_start_kib = m.rss_kib, s->heap_start_kib = m.heap_in_use_kib, s->fds_start = m.fds;
            s->warm_frames = f + 1;
            warm = 1;
        }
        if (now >= next_sample_ns) {
            if (sample_row(r, (double)(now - start_ns) * 1e-9, f + 1, row_from, pacer.missed, err) != 0)
                return -1;
            s->samples++;
            row_from = f + 1;
            next_sample_ns += sample_ns;
        }
    }
    int64_t end_ns = hl_clock_now_ns();
    if (row_from < f) { /* the stretch after the last full sample period */
        if (sample_row(r, (double)(end_ns - start_ns) * 1e-9, f, row_from, pacer.missed, err) != 0)
            return -1;
        s->samples++;
    }
    s->elapsed_s = (double)(end_ns - start_ns) * 1e-9;
    struct bch_soak_memory m;
    bch_soak_memory_read(&m, 0);
    s->rss_end_kib = m.rss_kib, s->heap_end_kib = m.heap_in_use_kib, s->fds_end = m.fds;
    if (!warm)
        s->rss_start_kib = s->rss_end_kib, s->heap_start_kib = s->heap_end_kib, s->fds_start = s->fds_end;
    s->frames = f;
    s->missed_slots = pacer.missed;
    s->heap_trims = pacer.trims;
    s->heap_trim_ms_max = (double)pacer.trim_max_ns * 1e-6;
    return 0;
}

int bch_soak_run(const struct bch_soak_options *o, struct bch_soak_summary *s, struct hl_error *err)
{
    memset(s, 0, sizeof *s);
    if (bch_soak_check_options(o, err) != 0)
        return -1;
    if (!o->trace_path || !o->imu_path)
        return hl_fail(err, "soak: a trace and an IMU stream are needed");
    struct soak_run r;
    memset(&r, 0, sizeof r);
    double rate_hz = 0;
    s->duration_s = o->duration_s;
    s->warmup_s = fmin(60.0, 0.1 * o->duration_s);
    int rc = open_csv(&r, o->out_dir, err); /* first: a bad --out fails before the session loads */
    if (rc == 0)
        rc = soak_open(&r, o, &rate_hz, err);
    if (rc == 0) {
        s->rate_hz = rate_hz;
        snprintf(s->renderer, sizeof s->renderer, "%s", rnd_renderer_name(r.session.renderer));
        snprintf(s->selector, sizeof s->selector, "fs");
        snprintf(s->display, sizeof s->display, "%s", r.session.display.name);
        snprintf(s->scene, sizeof s->scene, "field");
        snprintf(s->tracker, sizeof s->tracker, "DK2");
        snprintf(s->feed, sizeof s->feed, "reports straight into trk_stream_feed (no hidapi/umockdev)");
        rc = soak_loop(&r, o, rate_hz, s, err);
    }
    bch_soak_tracker_stop(&r.tracker);
    if (rc == 0) {
        s->reports = atomic_load(&r.tracker.reports);
        s->rejected = atomic_load(&r.tracker.rejected);
        s->fusion_nonfinite = atomic_load(&r.tracker.nonfinite);
        s->fusion_refused = atomic_load(&r.tracker.refused);
        s->imu_loops = (long)atomic_load(&r.tracker.loops);
        bch_soak_tracker_rates(&r.tracker, s->reports_per_s);
        s->trace_loops = bch_soak_source_loops(r.session.source);
        long from[2], count[2];
        choose_stretches(&r, bch_soak_source_period_s(r.session.source), s, from, count);
        s->first_frame = from[0];
        const double *series[2] = {r.frame_ms, r.cpu_ms};
        struct bch_soak_stats *out[2] = {s->frame_ms, s->cpu_ms};
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                out[k][j] = stretch_stats(series[k] + from[j], count[j], r.scratch);
        for (int j = 0; j < 2; ++j) {
            s->triangles_mean[j] = mean_of(r.triangles + from[j], count[j]);
            s->rss_median_kib[j] = sample_median_kib(&r, 0, s->stretch_s[j][0], s->stretch_s[j][1]);
            for (int k = 0; k < 3; ++k)
                s->map_median_kib[k][j] = sample_median_kib(&r, k + 1, s->stretch_s[j][0], s->stretch_s[j][1]);
        }
        s->frame_ms_ratio = s->frame_ms[1].median / s->frame_ms[0].median;
        s->cpu_ms_ratio = s->cpu_ms[1].median / s->cpu_ms[0].median;
        rc = commit_outputs(&r, o->out_dir, s, err);
    }
    soak_close(&r);
    return rc;
}
