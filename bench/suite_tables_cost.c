/* Tables 4–6 of the bench report: Nirenstein et al.'s optimizer time against the turn and the
 * budget (with and without the time limit, §5.5), Mason & Blake's hierarchical against flat on
 * domes, and the cost model's prediction against the measured frame time over every run. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/suite_internal.h"
#include "replay/replay.h"

static int t4_simplify(struct bch_ctx *c, struct hl_error *err);

/* The optimizer's mean time per head-speed band (frames.csv's head_speed_degps; frame 0 is warm-up),
 * per round, then the median over the rounds; NaN where a band has no frames. */
static void optimizer_by_speed(const struct bch_result *r, double band_us[RPL_SPEED_BAND_COUNT])
{
    double v[RPL_SPEED_BAND_COUNT][BCH_SUITE_MAX_REPEATS];
    int rounds = bch_result_rounds(r);
    for (int q = 0; q < rounds; ++q) {
        const struct bch_result *x = r ? bch_round(r, q) : NULL;
        double sum[RPL_SPEED_BAND_COUNT] = {0}, count[RPL_SPEED_BAND_COUNT] = {0};
        for (long k = 1; x && x->head_speed && x->optimizer_us && k < x->n; ++k) {
            int b = frm_band_of(rpl_speed_band_lower_degps, RPL_SPEED_BAND_COUNT, x->head_speed[k]);
            sum[b] += x->optimizer_us[k], count[b] += 1;
        }
        for (int b = 0; b < RPL_SPEED_BAND_COUNT; ++b)
            v[b][q] = count[b] > 0 ? sum[b] / count[b] : NAN;
    }
    for (int b = 0; b < RPL_SPEED_BAND_COUNT; ++b) {
        struct bch_spread sp;
        bch_spread_of(v[b], rounds, &sp);
        band_us[b] = sp.median;
    }
}

int bch_tables_t4(struct bch_ctx *c, struct hl_error *err)
{
    bch_heading(c, "Table 4: Nirenstein's measurements",
                      "fs on field with the largest object count (user1), over budgets (× the display period), "
                      "without a time limit and with --opt-limit-us 100. Optimizer time per frame, by head speed "
                      "(frames binned from frames.csv's head_speed_degps; — where a band has no frames). "
                      "Table 4b: hierarchy simplifications.\n",
                      0);
    int bands = RPL_SPEED_BAND_COUNT;
    static const char *const h[] = {"budget_x_period", "limit_us",       "optimizer_us_mean", "optimizer_us_max",
                                    "iterations_mean", "truncated_pct",  "frame_ms_mean",     "us_0_10_degps",
                                    "us_10_30_degps",  "us_30_60_degps", "us_60_120_degps",   "us_120plus_degps"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t4_nirenstein", c->md, NULL, c->det, h, 7 + bands, err) != 0)
        return -1;
    struct hl_out plot;
    FILE *f = bch_plot_data(c, "t4_turn.dat", &plot, err);
    if (!f) {
        bch_table_end(&t, err);
        return -1;
    }
    int n_series = 0, has_data = 0;
    char labels[12][48];
    for (size_t i = 0; i < c->plan->count; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        if (run->table != 4 || !strncmp(run->id, "t4s-", 4))
            continue;
        const struct bch_result *r = c->results[i].present ? &c->results[i] : NULL;
        double band_us[RPL_SPEED_BAND_COUNT];
        optimizer_by_speed(r, band_us);
        char cell[7 + RPL_SPEED_BAND_COUNT][BCH_CELL];
        const char *cells[7 + RPL_SPEED_BAND_COUNT] = {
            bch_cell(cell[0], run->factor, 2),
            bch_cell(cell[1], run->opt_limit_us, 0),
            bch_cell(cell[2], r ? bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(optimizer_us)) : NAN, 1),
            bch_cell(cell[3], r ? bch_timing(r, BCH_STAT_MAX, BCH_COLUMN(optimizer_us)) : NAN, 1),
            bch_cell(cell[4], r ? bch_mean(r, r->iterations) : NAN, 1),
            bch_cell(cell[5], r ? 100.0 * bch_mean(r, r->truncated) : NAN, 1),
            bch_cell(cell[6], r ? bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)) : NAN, 3)};
        if (n_series < 12) {
            snprintf(labels[n_series], sizeof labels[n_series], "%gx-%s", run->factor,
                     run->opt_limit_us > 0 ? "limit" : "nolimit");
            fprintf(f, "%s# %s\n", n_series ? "\n\n" : "", labels[n_series]);
        }
        for (int b = 0; b < bands; ++b) {
            double mean = band_us[b];
            cells[7 + b] = bch_cell(cell[7 + b], mean, 1);
            if (n_series < 12)
                fprintf(f, "%g %.3f\n", rpl_speed_band_lower_degps[b], mean);
            has_data |= isfinite(mean);
        }
        ++n_series;
        bch_table_row(&t, cells);
    }
    if (hl_out_commit(&plot, err) != 0) {
        struct hl_error table_err;
        bch_table_end(&t, &table_err);
        return -1;
    }
    if (bch_table_end(&t, err) != 0)
        return -1;
    char body[4096];
    size_t len = (size_t)snprintf(body, sizeof body,
                                  "set xlabel 'head speed band, from deg/s'\nset ylabel "
                                  "'optimizer time mean, us'\nset key outside right\nplot ");
    for (int s = 0; s < n_series && s < 12 && len < sizeof body; ++s)
        len += (size_t)snprintf(body + len, sizeof body - len,
                                "%s't4_turn.dat' index %d using 1:2 with linespoints "
                                "title '%s'",
                                s ? ", " : "", s, labels[s]);
    if (len < sizeof body)
        snprintf(body + len, sizeof body - len, "\n");
    if (bch_plot(c, "t4_turn", "fs optimizer time against head speed (Nirenstein)", body,
                       has_data && n_series > 0, err) != 0)
        return -1;
    return t4_simplify(c, err);
}

/* Nirenstein et al. 2002 §5.6: mb with its tree simplified 0, 1 and 2 times (--mb-simplify). */
static int t4_simplify(struct bch_ctx *c, struct hl_error *err)
{
    bch_heading(c, "Table 4b: hierarchy simplifications (Nirenstein)",
                      "mb on domes (user1, the display period as budget) with its hierarchy simplified 0, 1 and 2 "
                      "times (--mb-simplify K; docs/optimizer.md): the optimizer considers fewer nodes, so it is "
                      "cheaper, and spends detail less well; with --reference for the image error. Nirenstein found "
                      "one application helped and two degraded.\n",
                      0);
    static const char *const h[] = {"simplify", "optimizer_us_mean", "optimizer_us_max", "iterations_mean",
                                    "triangles_per_eye_mean", "fssim_mean", "ssim_mean", "psnr_db_mean",
                                    "flip_mean", "visible_error_mean", "frame_ms_mean"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t4b_simplify", c->md, NULL, c->det, h, 11, err) != 0)
        return -1;
    for (size_t i = 0; i < c->plan->count; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        if (strncmp(run->id, "t4s-", 4))
            continue;
        const struct bch_result *r = c->results[i].present ? &c->results[i] : NULL;
        char cell[11][BCH_CELL];
        const char *cells[11] = {bch_cell(cell[0], run->mb_simplify, 0),
                                 bch_cell(cell[1], r ? bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(optimizer_us)) : NAN, 1),
                                 bch_cell(cell[2], r ? bch_timing(r, BCH_STAT_MAX, BCH_COLUMN(optimizer_us)) : NAN, 1),
                                 bch_cell(cell[3], r ? bch_mean(r, r->iterations) : NAN, 1),
                                 bch_cell(cell[4], r ? bch_mean(r, r->triangles) : NAN, 1),
                                 bch_cell(cell[5], r ? r->fssim_mean : NAN, 4),
                                 bch_cell(cell[6], r ? r->ssim_mean : NAN, 4),
                                 bch_psnr_cell(cell[7], r),
                                 bch_cell(cell[10], r ? r->flip_mean : NAN, 4),
                                 bch_cell(cell[8], r ? r->visible_error_mean : NAN, 4),
                                 bch_cell(cell[9], r ? bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)) : NAN, 3)};
        bch_table_row(&t, cells);
    }
    return bch_table_end(&t, err);
}

int bch_tables_t5(struct bch_ctx *c, struct hl_error *err)
{
    char text[1024];
    snprintf(text, sizeof text,
             "mb (Mason & Blake's hierarchical optimizer: group impostors for whole groups) against fs (flat) on "
             "domes (user1) at 0.5, 1 and 2 × the scene's full cost. Full cost: the cost model's predicted_ms mean "
             "of selector none over the same frames, computed when the plan was made (calibration/domes-none): "
             "%.3f ms. Objects dropped per frame, image error (--reference) and predicted visible error.\n",
             c->plan->domes_full_ms);
    bch_heading(c, "Table 5: Mason–Blake's comparison on domes", text, 1);
    static const char *const h[] = {
        "selector",   "x_full_cost", "budget_ms",    "dropped_mean",       "visible_mean",  "triangles_per_eye_mean",
        "fssim_mean", "ssim_mean",   "psnr_db_mean", "flip_mean", "visible_error_mean", "frame_ms_mean",
        "deadline_met_pct"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t5_mason_blake", c->md, c->echo, c->det, h, 13, err) != 0)
        return -1;
    for (size_t i = 0; i < c->plan->count; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        if (run->table != 5)
            continue;
        const struct bch_result *r = c->results[i].present ? &c->results[i] : NULL;
        char cell[12][BCH_CELL];
        const char *cells[13] = {
            run->selector,
            bch_cell(cell[0], run->factor, 2),
            bch_cell(cell[1], run->budget_ms, 3),
            bch_cell(cell[2], r ? bch_mean(r, r->dropped) : NAN, 1),
            bch_cell(cell[3], r ? bch_mean(r, r->visible) : NAN, 1),
            bch_cell(cell[4], r ? bch_mean(r, r->triangles) : NAN, 1),
            bch_cell(cell[5], r ? r->fssim_mean : NAN, 4),
            bch_cell(cell[6], r ? r->ssim_mean : NAN, 4),
            bch_psnr_cell(cell[7], r),
            bch_cell(cell[11], r ? r->flip_mean : NAN, 4),
            bch_cell(cell[8], r ? r->visible_error_mean : NAN, 4),
            bch_cell(cell[9], r ? bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)) : NAN, 3),
            bch_cell(cell[10], r ? 100.0 * bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(deadline_met)) : NAN, 1)};
        bch_table_row(&t, cells);
    }
    return bch_table_end(&t, err);
}

/* |relative error| median and p95 (nearest rank) and the share under-predicted by more than 5 %. */
static void error_stats(double *rel, size_t n, double *median, double *p95, double *under5)
{
    size_t under = 0;
    for (size_t i = 0; i < n; ++i) {
        under += rel[i] < -0.05;
        rel[i] = fabs(rel[i]);
    }
    hl_sort_doubles(rel, n);
    *median = n ? hl_percentile_sorted(rel, n, 0.5) : NAN;
    *p95 = n ? hl_percentile_sorted(rel, n, 0.95) : NAN;
    *under5 = n ? (double)under / (double)n : NAN;
}

int bch_tables_t6(struct bch_ctx *c, struct hl_error *err)
{
    bch_heading(c, "Table 6: the cost model, predicted against measured",
                      "Every frame of every run: the cost model's predicted_ms against the measured frame_ms and "
                      "draw_ms (frames.csv). Relative error = (predicted − measured) / measured; under > 5 %: the "
                      "share of frames predicted more than 5 % too cheap (what breaks a budget). Frame 0 of each run "
                      "(driver warm-up) is left out.\n",
                      0);
    static const char *const h[] = {
        "scene", "measured", "frames", "abs_rel_error_median", "abs_rel_error_p95", "under_predicted_5pct_share"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t6_cost_model", c->md, NULL, c->det, h, 6, err) != 0)
        return -1;
    size_t total = 0;
    for (size_t i = 0; i < c->plan->count; ++i)
        total += (size_t)c->results[i].n;
    double *rel = malloc((total ? total : 1) * sizeof *rel);
    struct hl_out plot;
    FILE *f = bch_plot_data(c, "t6_cost.dat", &plot, err);
    if (!rel || !f) {
        free(rel);
        if (f)
            hl_out_abort(&plot);
        bch_table_end(&t, err);
        return rel ? -1 : hl_fail(err, "bench report: out of memory");
    }
    fputs("# predicted_ms frame_ms draw_ms\n", f);
    static const char *const scenes[] = {"auditorium", "field", "domes", "all"};
    int has_data = 0;
    for (int sc = 0; sc < 4; ++sc)
        for (int m = 0; m < 2; ++m) {
            size_t n = 0;
            for (size_t i = 0; i < c->plan->count; ++i) {
                const struct bch_result *r = &c->results[i];
                if (!r->present || !r->predicted_ms || !r->frame_ms || !r->draw_ms ||
                    (sc < 3 && strcmp(c->plan->runs[i].scene, scenes[sc])))
                    continue;
                for (long k = 1; k < r->n; ++k) {
                    double measured = m ? r->draw_ms[k] : r->frame_ms[k], p = r->predicted_ms[k];
                    if (isfinite(p) && measured > 0) {
                        rel[n++] = (p - measured) / measured;
                        if (sc == 3 && m == 0) {
                            fprintf(f, "%.4f %.4f %.4f\n", p, r->frame_ms[k], r->draw_ms[k]);
                            has_data = 1;
                        }
                    }
                }
            }
            double med, p95, under;
            error_stats(rel, n, &med, &p95, &under);
            char cell[4][BCH_CELL];
            const char *cells[6] = {scenes[sc],
                                    m ? "draw_ms" : "frame_ms",
                                    bch_cell(cell[0], (double)n, 0),
                                    bch_cell(cell[1], med, 3),
                                    bch_cell(cell[2], p95, 3),
                                    bch_cell(cell[3], under, 3)};
            bch_table_row(&t, cells);
        }
    free(rel);
    if (hl_out_commit(&plot, err) != 0) {
        struct hl_error table_err;
        bch_table_end(&t, &table_err);
        return -1;
    }
    if (bch_table_end(&t, err) != 0)
        return -1;
    static const char body[] = "set xlabel 'predicted, ms'\nset ylabel 'measured, ms'\nset key left top\n"
                               "plot 't6_cost.dat' using 1:2 with points pt 7 ps 0.3 title 'frame_ms', "
                               "'' using 1:3 with points pt 7 ps 0.3 title 'draw_ms', x with lines lc rgb 'black' "
                               "title 'measured = predicted'\n";
    return bch_plot(c, "t6_cost", "Cost model: predicted against measured, every frame of every run", body,
                          has_data, err);
}
