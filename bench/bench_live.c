/* hmdlod bench live: what the live session adds to a frame and how evenly it presents. (1) The
 * distortion pass's cost per frame at the Vive's resolution (2160 × 1200, both eyes), headless,
 * with and without lens coefficients (no anchor publishes it). (2) When a display is reachable
 * (DISPLAY, e.g. under xvfb-run -a), a live session at 90 Hz whose frame fits its budget (a small
 * window and render scale) and its present-interval median, p99 and stddev (the target:
 * stddev ≤ 1 ms at 90 Hz under Xvfb with self-pacing). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench/bench.h"
#include "render/render.h"
#include "live/live.h"
#include "replay/replay.h"



static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Times n passes (each waits for the GPU) after 10 unmeasured ones; median, p99, mean in ms. */
static int time_pass(struct rnd_renderer *r, const struct hmd_profile *p, long n, double out[3], struct hl_error *err)
{
    struct rnd_distortion *d = NULL;
    int w, h;
    rnd_renderer_size(r, &w, &h);
    if (rnd_distortion_create(r, p, w, h, 1, &d, err) != 0)
        return -1;
    double *t = malloc((size_t)n * sizeof *t), sum = 0;
    int rc = t ? 0 : hl_fail(err, "out of memory");
    for (long i = -10; rc == 0 && i < n; ++i) {
        int64_t t0 = hl_clock_now_ns();
        rc = rnd_distortion_draw(d, 1, err);
        if (i >= 0)
            sum += t[i] = (double)(hl_clock_now_ns() - t0) * 1e-6;
    }
    if (rc == 0) {
        qsort(t, (size_t)n, sizeof *t, compare_double);
        out[0] = t[n / 2], out[1] = t[(long)ceil(0.99 * (double)n) - 1], out[2] = sum / (double)n;
    }
    free(t);
    rnd_distortion_destroy(d);
    return rc;
}

static int distortion_table(long draws)
{
    struct hl_error err;
    const struct hmd_profile *vive = hmd_builtin_find("vive"), *dk2 = hmd_builtin_find("dk2");
    struct rnd_renderer *r = NULL;
    if (rnd_renderer_create(vive->eye_width_px, vive->eye_height_px, &r, &err) != 0) {
        fprintf(stderr, "hmdlod bench live: %s\n", err.msg);
        return 1;
    }
    struct hmd_profile lens = *vive; /* the Vive's frusta and pixels with the DK2's lens and aberration */
    memcpy(lens.distortion_k, dk2->distortion_k, sizeof lens.distortion_k);
    memcpy(lens.aberration, dk2->aberration, sizeof lens.aberration);
    double with[3], without[3];
    int rc = time_pass(r, &lens, draws, with, &err) == 0 && time_pass(r, vive, draws, without, &err) == 0 ? 0 : 1;
    if (rc == 0) {
        bch_emit("### Distortion pass, %d x %d (both eyes), %d x %d cells per eye, %ld passes\n\n",
                   2 * vive->eye_width_px, vive->eye_height_px, rnd_distortion_cells(2 * vive->eye_width_px),
                   rnd_distortion_cells(2 * vive->eye_width_px), draws);
        bch_emit("| case | median ms | p99 ms | mean ms |\n|---|---:|---:|---:|\n");
        bch_emit("| DK2 lens + aberration (3 samples/pixel) | %.3f | %.3f | %.3f |\n", with[0], with[1], with[2]);
        bch_emit("| no lens (Vive built-in: 1 sample/pixel) | %.3f | %.3f | %.3f |\n\n", without[0], without[1],
                   without[2]);
    } else {
        fprintf(stderr, "hmdlod bench live: %s\n", err.msg);
    }
    rnd_renderer_destroy(r);
    return rc;
}

static int pacing_table(long frames)
{
    if (!getenv("DISPLAY")) {
        bch_emit("### Present intervals\n\nskipped: no DISPLAY (run under xvfb-run -a)\n\n");
        return 0;
    }
    struct frm_options so;
    frm_options_defaults(&so);
    so.scene = "field";
    so.display = "vive";
    so.render_scale = 0.1;
    struct liv_options o;
    liv_options_defaults(&o);
    o.session = &so;
    o.device = "none";
    o.frames = frames;
    o.yaw_degps = 20.0;
    so.object_count = 10; /* a frame that fits 11.1 ms on llvmpipe: the table is about pacing */
    o.window_w_px = 320, o.window_h_px = 180;
    o.quiet_status = 1;
    struct liv_summary s;
    struct hl_error err;
    if (liv_run(&o, &s, &err) != 0) {
        fprintf(stderr, "hmdlod bench live: %s\n", err.msg);
        return 1;
    }
    bch_emit("### Present intervals, live session at %.0f Hz (%s)\n\n", s.rate_hz, s.pacing);
    bch_emit("field scene with 10 objects, Vive profile at render scale 0.1, %d x %d window, desk source turning "
               "20 deg/s, %ld frames (%ld within the budget)\n\n", s.window_w, s.window_h, s.frames, s.deadlines_met);
    bch_emit("| present median ms | p99 ms | stddev ms | max ms | missed slots | frame mean ms | frame p99 ms | "
               "distortion mean ms | start to present mean ms | p99 ms |\n"
               "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    bch_emit("| %.3f | %.3f | %.3f | %.3f | %ld | %.3f | %.3f | %.3f | %.3f | %.3f |\n\n", s.present_median_ms,
               s.present_p99_ms, s.present_stddev_ms, s.present_max_ms, s.missed_frames, s.frame_mean_ms, s.frame_p99_ms,
               s.distortion_mean_ms, s.to_present_mean_ms, s.to_present_p99_ms);
    bch_emit("Between two frames that both made their slots (%ld intervals): median %.3f ms, p99 %.3f ms, "
               "stddev %.3f ms.\n\n", s.on_time_intervals, s.on_time_median_ms, s.on_time_p99_ms, s.on_time_stddev_ms);
    FILE *load = fopen("/proc/loadavg", "r");
    double l1 = -1;
    if (load) {
        if (fscanf(load, "%lf", &l1) != 1)
            l1 = -1;
        fclose(load);
    }
    if (l1 >= 0)
        bch_emit("load average (1 min) at the end: %.2f on %ld cores: other work shares the CPUs with llvmpipe\n\n", l1,
                   sysconf(_SC_NPROCESSORS_ONLN));
    return 0;
}

int bch_live(const struct bch_live_options *o, int full_argc, char **full_argv)
{
    const char *results = o->results;
    if (results && bch_copy_begin() != 0) {
        fprintf(stderr, "hmdlod bench live: out of memory\n");
        return 1;
    }
    bch_emit(BCH_LIVE_HEADING "\n\n");
    bch_print_context(full_argc, full_argv, "llvmpipe (headless EGL; the window's GLX under Xvfb)");
    int rc = distortion_table(o->draws);
    if (rc == 0)
        rc = pacing_table(o->frames);
    return bch_copy_finish(results, BCH_LIVE_HEADING, "hmdlod bench live", rc);
}
