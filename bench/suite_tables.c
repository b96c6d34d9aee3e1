/* Tables 1 and 2 of the bench report: Funkhouser & Séquin's Table 1 on real traces (with his
 * Figure 7's frame-time series), and speed against error (frame time against measured image error
 * and predicted visible error per selector and budget, per gaze model). docs/bench.md. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/suite_internal.h"

/* Deterministic: the same triangles every time. A controller steered by measured times is not. */
static int is_deterministic(const struct bch_run *run)
{
    if (!strcmp(run->foveation, "adaptive"))
        return 0;
    return !strcmp(run->selector, "none") || !strcmp(run->selector, "static") || !strcmp(run->selector, "reddy");
}

const char *bch_run_label(const struct bch_run *run, char *buf, size_t size)
{
    snprintf(buf, size, "%s%s%s%s", run->selector, run->opt_limit_us > 0 ? "-lim200" : "", run->foveation[0] ? "+" : "",
             run->foveation);
    return buf;
}

/* Goals (issue 15, after Funkhouser & Séquin's 8 % and 130 %): stddev ≤ 3 % and max ≤ 110 % of the target. */
#define GOAL_STDDEV_SHARE 0.03
#define GOAL_MAX_SHARE 1.10

int bch_tables_t1(struct bch_ctx *c, struct hl_error *err)
{
    bch_heading(
        c, "Table 1: Funkhouser's Table 1 on real traces",
        "Per selector on real head motion (Corbillon MMSys'18) through auditorium and field: the "
        "optimizer's time and the frame time relative to the target (the budget, the display period), "
        "after Funkhouser & Séquin 1993 Table 1. Goals: stddev ≤ 3 % and max ≤ 110 % of the target "
        "(he reported 8 % and 130 %). mb-lim200: mb with --opt-limit-us 200. Timings leave frame 0 out (the "
        "driver compiles its shaders there); the series plot shows it. The first row per scene, static "
        "on the still head, does the same work every frame: its stddev is this machine's jitter under "
        "constant load, and stddev_vs_jitter divides each row's stddev by it (≤ 1: within the "
        "machine's own noise). goals_met: (stddev ≤ 3 % or ≤ the jitter) and max ≤ 110 %.\n",
        1);
    static const char *const h[] = {"trace",
                                    "scene",
                                    "selector",
                                    "frames",
                                    "optimizer_us_mean",
                                    "optimizer_us_max",
                                    "frame_pct_mean",
                                    "frame_pct_max",
                                    "frame_pct_stddev",
                                    "stddev_vs_jitter",
                                    "deadline_met_pct",
                                    "goals_met",
                                    "*triangles_per_eye_mean",
                                    "*visible_error_mean",
                                    "deterministic"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t1_funkhouser", c->md, c->echo, c->det, h, 15, err) != 0)
        return -1;
    for (size_t i = 0; i < c->plan->count; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        if (run->table != 1)
            continue;
        const struct bch_result *r = c->results[i].present ? &c->results[i] : NULL;
        char jitter_id[96];
        snprintf(jitter_id, sizeof jitter_id, "t1-%s-still-static", run->scene);
        const struct bch_result *still = bch_find(c, jitter_id);
        double jitter = still ? bch_timing(still, BCH_STAT_SD, BCH_COLUMN(frame_ms)) / still->budget_ms : NAN;
        char cell[15][BCH_CELL], sel[48];
        bch_run_label(run, sel, sizeof sel);
        double target = r ? r->budget_ms : NAN;
        /* timings from frame 1: frame 0 compiles the driver's shaders (10× a frame on llvmpipe) */
        double sd = r ? bch_timing(r, BCH_STAT_SD, BCH_COLUMN(frame_ms)) / target : NAN;
        double mx = r ? bch_timing(r, BCH_STAT_MAX, BCH_COLUMN(frame_ms)) / target : NAN;
        const char *cells[15] = {
            !strcmp(run->motion, "still") ? "still (constant load)" : run->motion,
            run->scene,
            sel,
            r ? bch_cell(cell[0], (double)r->n, 0) : "—",
            bch_cell(cell[1], r ? bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(optimizer_us)) : NAN, 1),
            bch_cell(cell[2], r ? bch_timing(r, BCH_STAT_MAX, BCH_COLUMN(optimizer_us)) : NAN, 1),
            bch_cell(cell[3], r ? 100.0 * bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)) / target : NAN, 1),
            bch_cell(cell[4], 100.0 * mx, 1),
            bch_cell(cell[5], 100.0 * sd, 1),
            bch_cell(cell[9], sd / jitter, 2),
            bch_cell(cell[6], r ? 100.0 * bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(deadline_met)) : NAN, 1),
            !r                                                                  ? "—"
            : (sd <= GOAL_STDDEV_SHARE || sd <= jitter) && mx <= GOAL_MAX_SHARE ? "yes"
                                                                                : "no",
            bch_cell(cell[7], r ? bch_mean(r, r->triangles) : NAN, 1),
            bch_cell(cell[8], r ? r->visible_error_mean : NAN, 4),
            is_deterministic(run) ? "1" : "0"};
        bch_table_row(&t, cells);
    }
    if (bch_table_end(&t, err) != 0)
        return -1;
    /* Figure 7: frame time / target per frame, user1, one file per scene */
    for (int sc = 0; sc < 2; ++sc) {
        const char *scene = sc ? "field" : "auditorium";
        char name[64], data[80], body[4096];
        snprintf(name, sizeof name, "t1_series_%s", scene);
        snprintf(data, sizeof data, "%s.dat", name);
        const struct bch_result *cols[8];
        char labels[8][48];
        int n = 0;
        long frames = 0;
        for (size_t i = 0; i < c->plan->count && n < 8; ++i) {
            const struct bch_run *run = &c->plan->runs[i];
            if (run->table == 1 && !strcmp(run->scene, scene) && !strcmp(run->motion, "user1") &&
                c->results[i].present && c->results[i].frame_ms) {
                cols[n] = &c->results[i];
                bch_run_label(run, labels[n++], sizeof labels[0]);
                frames = c->results[i].n > frames ? c->results[i].n : frames;
            }
        }
        struct hl_out plot;
        FILE *f = bch_plot_data(c, data, &plot, err);
        if (!f)
            return -1;
        fputs("frame", f);
        for (int k = 0; k < n; ++k)
            fprintf(f, " %s", labels[k]);
        fputc('\n', f);
        for (long fr = 0; fr < frames; ++fr) {
            fprintf(f, "%ld", fr);
            for (int k = 0; k < n; ++k)
                fprintf(f, " %.3f", fr < cols[k]->n ? 100.0 * cols[k]->frame_ms[fr] / cols[k]->budget_ms : NAN);
            fputc('\n', f);
        }
        if (hl_out_commit(&plot, err) != 0)
            return -1;
        snprintf(body, sizeof body,
                 "set xlabel 'frame'\nset ylabel 'frame time, %% of the target'\nset key outside right\n"
                 "set yrange [0:*]\nplot for [i=2:%d] '%s' using 1:i with lines title columnheader(i), "
                 "110 with lines dashtype 2 lc rgb 'black' title '110 %%'\n",
                 n + 1, data);
        char title[128];
        snprintf(title, sizeof title, "Frame time per frame, %s, user1 (Funkhouser Figure 7)", scene);
        if (bch_plot(c, name, title, body, n > 0 && frames > 0, err) != 0)
            return -1;
    }
    return 0;
}

/* Linear interpolation of y at x over points sorted by x; NaN outside their range. */
static double interpolate(const double *x, const double *y, int n, double at)
{
    for (int i = 0; i + 1 < n; ++i)
        if (at >= x[i] && at <= x[i + 1])
            return x[i + 1] > x[i] ? y[i] + (y[i + 1] - y[i]) * (at - x[i]) / (x[i + 1] - x[i]) : y[i];
    return n == 1 && at == x[0] ? y[0] : NAN;
}

/* A Table 2 run of this gaze model, selector and foveation mode ("" off). */
static int t2_run_is(const struct bch_run *run, const char *gaze, const char *selector, const char *foveation)
{
    return run->table == 2 && !strcmp(run->gaze, gaze) && !strcmp(run->selector, selector) &&
           !strcmp(run->foveation, foveation);
}

/* A selector's (fSSIM, frame ms) points in one gaze model and foveation mode ("" off), sorted by
 * fSSIM; returns the count. */
static int curve(const struct bch_ctx *c, const char *gaze, const char *selector, const char *foveation, double *x,
                 double *y)
{
    int n = 0;
    for (size_t i = 0; i < c->plan->count && n < 8; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        const struct bch_result *r = &c->results[i];
        if (!t2_run_is(run, gaze, selector, foveation) || !r->present || !isfinite(r->fssim_mean))
            continue;
        int k = n++;
        while (k > 0 && x[k - 1] > r->fssim_mean) {
            x[k] = x[k - 1], y[k] = y[k - 1];
            --k;
        }
        x[k] = r->fssim_mean, y[k] = bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms));
    }
    return n;
}

/* Table 2's curves: selector, foveation ("" off), the label (and data file part). */
static const char *const t2_series[][3] = {{"static", "", "static"}, {"feedback", "", "feedback"},
                                           {"reddy", "", "reddy"},   {"fs", "", "fs"},
                                           {"mb", "", "mb"},         {"fs", "fixed", "fs-layers"},
                                           {"static", "adaptive", "valve-adaptive"}};
enum { T2_SERIES = sizeof t2_series / sizeof t2_series[0] };

static int t2_plot(struct bch_ctx *c, const char *gaze, struct hl_error *err)
{
    /* one data file per selector: frame ms, fSSIM, SSIM, PSNR, visible error */
    int has[4] = {0, 0, 0, 0};
    for (int s = 0; s < T2_SERIES; ++s) {
        char data[64];
        snprintf(data, sizeof data, "t2_%s_%s.dat", gaze, t2_series[s][2]);
        struct hl_out plot;
        FILE *f = bch_plot_data(c, data, &plot, err);
        if (!f)
            return -1;
        fputs("# frame_ms fssim ssim psnr_db visible_error\n", f);
        for (size_t i = 0; i < c->plan->count; ++i) {
            const struct bch_run *run = &c->plan->runs[i];
            const struct bch_result *r = &c->results[i];
            if (!t2_run_is(run, gaze, t2_series[s][0], t2_series[s][1]) || !r->present)
                continue;
            double v[5] = {bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)), r->fssim_mean, r->ssim_mean, r->psnr_db_mean,
                           r->visible_error_mean};
            for (int k = 0; k < 4; ++k)
                has[k] |= isfinite(v[0]) && isfinite(v[k + 1]);
            fprintf(f, "%.4f %.6f %.6f %.4f %.6f\n", v[0], v[1], v[2], v[3], v[4]);
        }
        if (hl_out_commit(&plot, err) != 0)
            return -1;
    }
    static const char *const ylabels[4] = {"foveated SSIM", "SSIM", "PSNR, dB", "predicted visible error"};
    char body[8192];
    size_t len = (size_t)snprintf(body, sizeof body,
                                  "set terminal pngcairo size 1200,900 noenhanced\n"
                                  "set output 't2_pareto_%s.png'\nset multiplot layout 2,2 title "
                                  "'Speed against error, gaze %s'\nunset title\nset xlabel 'frame time mean, ms'\n",
                                  gaze, gaze);
    for (int k = 0; k < 4 && len < sizeof body; ++k) {
        len += (size_t)snprintf(body + len, sizeof body - len, "set ylabel '%s'\n", ylabels[k]);
        if (!has[k]) {
            len += (size_t)snprintf(body + len, sizeof body - len,
                                    "set label 1 'not measured' at graph 0.5, graph 0.5 center\n"
                                    "plot [0:1][0:1] -1 notitle\nunset label 1\n");
            continue;
        }
        len += (size_t)snprintf(body + len, sizeof body - len, "plot ");
        for (int s = 0; s < T2_SERIES && len < sizeof body; ++s)
            len += (size_t)snprintf(body + len, sizeof body - len,
                                    "%s't2_%s_%s.dat' using 1:%d with linespoints "
                                    "title '%s'",
                                    s ? ", " : "", gaze, t2_series[s][2], k + 2, t2_series[s][2]);
        len += (size_t)snprintf(body + len, sizeof body - len, "\n");
    }
    if (len < sizeof body)
        snprintf(body + len, sizeof body - len, "unset multiplot\n");
    char name[64], title[96];
    snprintf(name, sizeof name, "t2_pareto_%s", gaze);
    snprintf(title, sizeof title, "Frame time against image error and predicted visible error, gaze %s", gaze);
    return bch_plot(c, name, title, body, 1, err);
}

int bch_tables_t2(struct bch_ctx *c, struct hl_error *err)
{
    bch_heading(c, "Table 2: speed against error",
                      "On auditorium (user1), each selector over a sweep of its setting: the budget (× the display "
                      "period) for fs, mb and feedback, --static-px for static; reddy as it is; per foveation mode: "
                      "fs+fixed (fs with foveated layers on the lens centres) and static+adaptive (Valve's "
                      "adaptive quality: the whole eye at the scale its controller sets) over the same budgets. "
                      "Every run has "
                      "--reference: image error against the full-detail frame (fSSIM: SSIM weighted by Reddy's "
                      "M(E) around the gaze; SSIM on luminance; PSNR over RGB; px>32: share of pixels off by more "
                      "than 32 levels; FLIP: LDR-FLIP mean at the display's pixels per degree) beside the model's predicted visible error. Higher fSSIM is better.\n",
                      0);
    static const char *const h[] = {"gaze",
                                    "selector",
                                    "setting",
                                    "frame_ms_mean",
                                    "frame_pct_of_period",
                                    "*fssim_mean",
                                    "*fssim_p5",
                                    "*ssim_mean",
                                    "*psnr_db_mean",
                                    "*px_over_32",
                                    "*flip_mean",
                                    "*visible_error_mean",
                                    "*triangles_per_eye_mean",
                                    "deterministic"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t2_speed_error", c->md, NULL, c->det, h, 14, err) != 0)
        return -1;
    const double period_ms = 1000.0 / 90.0; /* vive */
    for (size_t i = 0; i < c->plan->count; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        if (run->table != 2)
            continue;
        const struct bch_result *r = c->results[i].present ? &c->results[i] : NULL;
        char cell[11][BCH_CELL], setting[48], label[48];
        if (run->static_px > 0)
            snprintf(setting, sizeof setting, "%g px/triangle", run->static_px);
        else if (run->factor > 0)
            snprintf(setting, sizeof setting, "%g × period", run->factor);
        else
            snprintf(setting, sizeof setting, "acuity");
        double fm = r ? bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)) : NAN;
        const char *cells[14] = {run->gaze,
                                 bch_run_label(run, label, sizeof label),
                                 setting,
                                 bch_cell(cell[0], fm, 3),
                                 bch_cell(cell[1], 100.0 * fm / period_ms, 1),
                                 bch_cell(cell[2], r ? r->fssim_mean : NAN, 4),
                                 bch_cell(cell[3], r ? r->fssim_p5 : NAN, 4),
                                 bch_cell(cell[4], r ? r->ssim_mean : NAN, 4),
                                 bch_psnr_cell(cell[5], r),
                                 bch_cell(cell[6], r ? r->px_over_32 : NAN, 4),
                                 bch_cell(cell[9], r ? r->flip_mean : NAN, 4),
                                 bch_cell(cell[7], r ? r->visible_error_mean : NAN, 4),
                                 bch_cell(cell[8], r ? bch_mean(r, r->triangles) : NAN, 1),
                                 is_deterministic(run) ? "1" : "0"};
        bch_table_row(&t, cells);
    }
    if (bch_table_end(&t, err) != 0)
        return -1;

    /* At equal fSSIM: each fs/mb point against static's and feedback's curves, interpolated. */
    bch_heading(c, "Table 2b: at equal fSSIM, fs/mb frame time ÷ static's and ÷ feedback's",
                      "Each fs, mb and fs+fixed point of Table 2 against the static, feedback, Valve adaptive "
                      "(static+adaptive) and, for fs+fixed, plain fs curves of the same gaze model, interpolated "
                      "linearly at the point's fSSIM (— where the fSSIM lies outside that curve's range or was not "
                      "measured: the curves do not overlap there). Goals: ≤ 0.5 against static, ≤ 1 against "
                      "feedback; for fs+fixed (issue 32) also < 1 against Valve adaptive.\n",
                      1);
    static const char *const h2[] = {"gaze",          "selector",        "budget_x_period",   "fssim_mean",
                                     "frame_ms_mean", "ratio_to_static", "ratio_to_feedback", "ratio_to_adaptive",
                                     "ratio_to_fs"};
    if (bch_table_begin(&t, c->dir, "t2b_equal_fssim", c->md, c->echo, c->det, h2, 9, err) != 0)
        return -1;
    for (int g = 0; g < 2; ++g) {
        const char *gaze = g ? "vor" : "head";
        double sx[8], sy[8], fx[8], fy[8], ax[8], ay[8], px[8], py[8];
        int ns = curve(c, gaze, "static", "", sx, sy), nf = curve(c, gaze, "feedback", "", fx, fy);
        int na = curve(c, gaze, "static", "adaptive", ax, ay), np = curve(c, gaze, "fs", "", px, py);
        for (size_t i = 0; i < c->plan->count; ++i) {
            const struct bch_run *run = &c->plan->runs[i];
            const struct bch_result *r = c->results[i].present ? &c->results[i] : NULL;
            if (run->table != 2 || strcmp(run->gaze, gaze) ||
                (strcmp(run->selector, "fs") && strcmp(run->selector, "mb")))
                continue;
            double q = r ? r->fssim_mean : NAN, fm = r ? bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)) : NAN;
            double to_fs = run->foveation[0] ? fm / interpolate(px, py, np, q) : NAN;
            char cell[7][BCH_CELL], label[48];
            const char *cells[9] = {gaze,
                                    bch_run_label(run, label, sizeof label),
                                    bch_cell(cell[0], run->factor, 2),
                                    bch_cell(cell[1], q, 4),
                                    bch_cell(cell[2], fm, 3),
                                    bch_cell(cell[3], fm / interpolate(sx, sy, ns, q), 3),
                                    bch_cell(cell[4], fm / interpolate(fx, fy, nf, q), 3),
                                    bch_cell(cell[5], fm / interpolate(ax, ay, na, q), 3),
                                    bch_cell(cell[6], to_fs, 3)};
            bch_table_row(&t, cells);
        }
    }
    if (bch_table_end(&t, err) != 0)
        return -1;
    for (int g = 0; g < 2; ++g)
        if (t2_plot(c, g ? "vor" : "head", err) != 0)
            return -1;
    return 0;
}
