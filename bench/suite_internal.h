/* Internal to bench/'s suite: a run's results as read back from its folder, the table writer
 * (Markdown + CSV + optional echo) and the plots. */
#ifndef HMDLOD_BENCH_SUITE_INTERNAL_H
#define HMDLOD_BENCH_SUITE_INTERNAL_H

#include <stddef.h>
#include <stdio.h>

#include "bench/bench.h"

/* A run read back from DIR/runs/ID: summary.json's error figures and frames.csv's columns. Numbers
 * absent from the files are NaN (the report prints "—"). */
struct bch_result {
    int present;
    char renderer[128];
    char host[64];                          /* summary.json's wall_clock; "" when absent */
    double wall_start_unix_s, wall_end_unix_s; /* NaN when absent (folders made before they were kept) */
    double budget_ms;
    double visible_error_mean, visible_error_max;
    double ref_frames, identical_frames, psnr_db_mean, psnr_db_min, ssim_mean, ssim_min, ssim_rgb_mean, fssim_mean,
        fssim_min, fssim_p5, px_over_32;
    double fssim_band[4];
    double flip_mean; /* FLIP (render/flip.h), mean over the compared frames; NaN without --reference */
    /* summary.json's triangles_by_band: share of the finest triangles drawn per eccentricity band (the
     * image error's) and per retinal-speed band (frm_retinal_band_lower_degps); NaN when absent */
    double kept_ecc[4], kept_retinal[4];
    long n; /* frames */
    /* per frame (n each; NULL where the column is absent) */
    double *frame_ms, *draw_ms, *predicted_ms, *head_speed, *optimizer_us, *triangles, *finest, *dropped, *iterations,
        *truncated, *deadline_met, *visible, *visible_error;
    double *layer_scale, *inset_radius_deg; /* the foveated layers' setting (1 and 0: the plain frame) */
    /* The plan's rounds of this run (bench/suite.h): this one is the first; more[k] the (k+2)-th, each
     * loaded like this one (present 0 where its folder was missing). rounds 1 and more NULL with one. */
    int rounds;
    struct bch_result *more;
};

int bch_result_load(const char *run_dir, struct bch_result *r, struct hl_error *err);
void bch_result_free(struct bch_result *r);
/* Mean, max and sample standard deviation of a column (NaN for a missing column or no frames). */
double bch_mean(const struct bch_result *r, const double *col);
double bch_max(const struct bch_result *r, const double *col);
double bch_stddev(const struct bch_result *r, const double *col);
/* The same from frame `first` on (timings leave frame 0 out: the driver compiles its shaders there). */
double bch_mean_from(const struct bch_result *r, const double *col, long first);
double bch_max_from(const struct bch_result *r, const double *col, long first);
double bch_stddev_from(const struct bch_result *r, const double *col, long first);

/* A timing column's statistic over a run's rounds: each round's mean, max or sample standard deviation
 * of the column from frame 1 on (frame 0 compiles the driver's shaders), then the median over the
 * rounds loaded. column: BCH_COLUMN(frame_ms) and the like. NaN for a NULL run or no figure. */
enum bch_stat { BCH_STAT_MEAN, BCH_STAT_MAX, BCH_STAT_SD };
/* The rounds a run holds (loaded or missing), 1 … BCH_SUITE_MAX_REPEATS; 1 for NULL. */
int bch_result_rounds(const struct bch_result *r);
/* Round k (0-based) of a run when it was loaded, else NULL. */
const struct bch_result *bch_round(const struct bch_result *r, int k);
#define BCH_COLUMN(name) offsetof(struct bch_result, name)
double bch_timing(const struct bch_result *r, enum bch_stat stat, size_t column);
/* From frame 1 on, each round's 99th percentile of frame_ms (nearest rank) and share of frames within
 * the round's budget_ms, then the median over the rounds; NaN without frames (Table 7). */
void bch_frame_tail(const struct bch_result *r, double *p99_ms, double *within_share);
/* The ratio of two runs' timing statistic taken round by round — round k of num over round k of den,
 * which ran in the same pass over their table — with its median and min–max over the rounds. */
void bch_timing_ratio(const struct bch_result *num, const struct bch_result *den, enum bch_stat stat, size_t column,
                      struct bch_spread *out);

/* ---- tables: one Markdown table in report.md, the same rows in DIR/NAME.csv ----------------------- */
enum { BCH_MAX_COLS = 20, BCH_CELL = 48 };
struct bch_table {
    FILE *md, *csv, *echo; /* echo NULL: not printed; csv is csv_out.f */
    struct hl_out csv_out;
    char csv_path[4300];
    int cols;
    int has_deterministic;
};
/* Opens DIR/name.csv (temporary name), writes the heading's table header in md (and echo), and
 * appends the deterministic columns (those marked '*' at the start of their name; the mark is
 * dropped in the CSV) to the list det (DIR/deterministic.txt). */
int bch_table_begin(struct bch_table *t, const char *dir, const char *name, FILE *md, FILE *echo, FILE *det,
                          const char *const *headers, int cols, struct hl_error *err);
/* A row of cols cells; "—" (missing) goes into the CSV as an empty field. */
void bch_table_row(struct bch_table *t, const char *const *cells);
int bch_table_end(struct bch_table *t, struct hl_error *err);
/* A number into a cell: "%.*f", or "—" when not finite. */
const char *bch_cell(char *cell, double v, int digits);
/* A run's name in the tables: its selector, "-lim200" with an optimizer limit, "+MODE" with
 * foveation (fs+fixed, static+adaptive); into buf. */
const char *bch_run_label(const struct bch_run *run, char *buf, size_t size);
/* PSNR mean in dB; "inf" when every compared frame was identical (PSNR +∞, which the mean leaves out). */
const char *bch_psnr_cell(char *cell, const struct bch_result *r);

/* ---- the tables (bench_tables.c) and plots (bench_plot.c) ------------------------------------------- */
struct bch_ctx {
    const struct bch_plan *plan;
    struct bch_result *results; /* plan->count, in plan order */
    const char *dir;                  /* out_dir */
    FILE *md, *echo, *det;
    const char *context;
    const char *renderer; /* the first run's GL renderer */
    int gnuplot;          /* 1 when gnuplot is on PATH */
};
/* "## heading", the context lines, then text (how to read the table) in report.md, and on echo
 * when `echo` is set. */
void bch_heading(struct bch_ctx *c, const char *heading, const char *text, int echo);
/* The result of the run with this id, or NULL when it is not in the plan or missing. */
const struct bch_result *bch_find(const struct bch_ctx *c, const char *id);
int bch_tables_t1(struct bch_ctx *c, struct hl_error *err);
int bch_tables_t2(struct bch_ctx *c, struct hl_error *err);
int bch_tables_t3(struct bch_ctx *c, struct hl_error *err);
int bch_tables_t4(struct bch_ctx *c, struct hl_error *err);
int bch_tables_t5(struct bch_ctx *c, struct hl_error *err);
int bch_tables_t6(struct bch_ctx *c, struct hl_error *err);
int bch_tables_t7(struct bch_ctx *c, struct hl_error *err);

/* Writes DIR/plots/NAME.gp from the script body (after the terminal and output lines) and, with
 * gnuplot present, runs it (output DIR/plots/NAME.png). A data-less plot (has_data 0) gets a
 * placeholder that says so. Appends the image link to md. 0, or −1 when writing failed. */
int bch_plot(struct bch_ctx *c, const char *name, const char *title, const char *body, int has_data,
                   struct hl_error *err);
/* Opens DIR/plots/NAME (a data file) for writing through *out (base.h: commit it with hl_out_commit,
 * or hl_out_abort); out->f, or NULL with err. */
FILE *bch_plot_data(struct bch_ctx *c, const char *name, struct hl_out *out, struct hl_error *err);
int bch_have_gnuplot(void);

#endif
