/* bench/suite.h: the bench suite (issue 15) — a fixed, deterministic list of replays (the plan),
 * each one `hmdlod replay` configuration with an id, and the report built from their output folders
 * (DIR/runs/ID/summary.json and frames.csv), never from in-memory results, so that runs made one by
 * one, under GNU parallel or as a Slurm array give the same report. Part of the bench/bench.h umbrella.
 * docs/bench.md describes the tables. */
#ifndef HMDLOD_BENCH_SUITE_H
#define HMDLOD_BENCH_SUITE_H

#include <stddef.h>
#include <stdio.h>

#include "base/base.h"

enum bch_mode { BCH_QUICK = 0, BCH_FULL = 1, BCH_TINY = 2 };

/* One run: what the replay is given (no output folder; bch_run_argv adds it). */
struct bch_run {
    char id[96];
    int table;       /* 1 … 5: the table it serves (6, the cost model, reads every run; 7, the layers,
                      * reads the runs of 1 and 2 with foveation) */
    char motion[16]; /* "user1" … "user3" (Corbillon), "still" (the suite's still-head trace),
                      * "edvam-p2" (EDVAM participant 2, with its eye tracker's gaze) */
    char scene[16], selector[16], display[64];
    char gaze[8];        /* "" → replay's default (vor for traces without gaze) */
    char reading[8];     /* "" → narrow */
    char visibility[12]; /* "" → replay's default criterion (contrast); "acuity": Reddy's H(v, E) */
    char foveation[12];  /* "" → off; "fixed" (layers on the lens centres), "adaptive" (Valve's
                          * global scaling): --foveation (docs/foveation.md) */
    double factor;       /* the sweep value: × the display period (t2, t4), × full cost (t5); 0 none */
    double budget_ms;    /* 0 → the display's period */
    double opt_limit_us; /* 0 → no limit */
    double static_px;    /* 0 → replay's default */
    int objects;         /* 0 → the scene's default */
    int velocity_off, eccentricity_off;
    int mb_simplify;       /* mb: Nirenstein's hierarchy simplification applied this many times */
    long frames, reference_every;
    double render_scale;
};

struct bch_plan {
    enum bch_mode mode;
    char only[128];         /* glob over run ids ("" = every run) */
    char shared[4096];      /* the shared data folder (traces) */
    char out_dir[4096];     /* DIR the plan was made for: its lines write DIR/runs/ID */
    char still_trace[4200]; /* DIR/still-head.csv */
    char traces[3][4200];   /* Corbillon MMSys'18 user1 … user3 under the shared folder */
    char gaze_trace[4200];  /* EDVAM participant 2 (head and measured gaze); "" when not readable: its
                             * runs (motion "edvam-p2") are then left out of the plan */
    double domes_full_ms;   /* predicted cost of domes at full detail (t5's budgets), ms */
    int repeats;            /* alternated rounds of every run (1 … BCH_SUITE_MAX_REPEATS; bch_plan_step) */
    struct bch_run *runs;
    size_t count;
};

/* Every run is made `repeats` times (issue 30 item 2), so that a timing figure is the median over
 * rounds and a timing ratio between two runs of a table is taken per round: the runs of one table
 * (a block of consecutive runs with the same `table`) go forward in the first round, backward in the
 * second, and so on (bench/alternate.c), so a drift of the machine's load moves both sides of a
 * ratio alike. The first round writes DIR/runs/ID, round N ≥ 2 DIR/runs-N/ID (bch_prepare makes
 * the folders). */
enum { BCH_SUITE_MAX_REPEATS = 9, BCH_SUITE_DEFAULT_REPEATS = 2 };
/* The plan's rounds, held to 1 … BCH_SUITE_MAX_REPEATS (a plan made without setting them has one). */
int bch_plan_rounds(const struct bch_plan *plan);
/* The folder of round `repeat` (0-based) under out_dir: DIR/runs, DIR/runs-2, …; into buf. */
void bch_runs_dir(const char *out_dir, int repeat, char *buf, size_t size);
/* The folder of a run's round `repeat` (0-based) under out_dir, into buf. */
void bch_run_dir(const char *out_dir, const char *id, int repeat, char *buf, size_t size);
/* The serial order: step 0 … count·repeats − 1 of the plan → the run's index, and its round in
 * *repeat. Pure. */
size_t bch_plan_step(const struct bch_plan *plan, size_t step, int *repeat);

/* The run list for mode, filtered by the glob `only` (NULL or "" = all), one round (set
 * plan->repeats for more). Needs domes_full_ms (> 0) from bch_prepare or a suite file. Pure: no
 * files touched. 0, or −1 with err. */
int bch_plan_make(enum bch_mode mode, const char *only, const char *shared, const char *out_dir,
                        double domes_full_ms, struct bch_plan *plan, struct hl_error *err);
void bch_plan_free(struct bch_plan *plan);
const char *bch_mode_name(enum bch_mode mode);

/* Makes DIR (and DIR/runs), writes the still-head trace DIR/still-head.csv, predicts the full-detail
 * cost of domes with a short `none` replay into DIR/calibration (the cost model's predicted_ms mean
 * over t5's frames), builds the plan with `repeats` rounds and writes DIR/suite.txt (mode, glob,
 * rounds, shared folder, that cost and `command`, the line that made it) so that --merge rebuilds the
 * same plan. 0, or −1 with err. */
int bch_prepare(const char *out_dir, enum bch_mode mode, const char *only, int repeats, const char *shared,
                      const char *command, struct bch_plan *plan, struct hl_error *err);
/* Reads DIR/suite.txt and rebuilds its plan; *command gets the stored command line. */
int bch_plan_read(const char *dir, struct bch_plan *plan, char *command, size_t command_size,
                        struct hl_error *err);

/* The replay arguments of a run, argv[0] = "replay", ending with --out out_dir --quiet; pointers
 * into the run, the plan and storage (≥ 40 × 32 bytes). Returns argc (≤ max − 1; argv[argc] NULL). */
enum { BCH_MAX_ARGS = 48, BCH_ARG_SIZE = 32 };
int bch_run_argv(const struct bch_plan *plan, const struct bch_run *run, const char *out_dir,
                       char storage[][BCH_ARG_SIZE], const char **argv, int max);
/* One shell line: 'exe' replay … --out 'DIR/runs[-N]/ID' --quiet, every word shell-quoted. */
void bch_run_line(const struct bch_plan *plan, const struct bch_run *run, int repeat, const char *exe,
                        const char *out_dir, FILE *f);
/* Writes the plan (one line per run and round, in the serial order) to path via a temporary file
 * and rename. 0, or −1. */
int bch_plan_write(const struct bch_plan *plan, const char *exe, const char *out_dir, const char *path,
                         struct hl_error *err);

/* The report: reads each run from the first of dirs holding DIR/runs/ID/summary.json, and writes
 * out_dir/report.md, out_dir/NAME.csv, out_dir/deterministic.txt, out_dir/plots/NAME.gp and .png
 * (gnuplot, when on PATH). context: Markdown lines (command, machine, commit, date) put under every
 * table; key tables are also printed on `echo` (NULL: not printed). Missing runs: −1 with err
 * naming them, unless partial (then they are listed in the report and their cells are "—"). */
struct bch_report_options {
    const struct bch_plan *plan;
    const char *const *dirs;
    int dir_count;
    const char *out_dir;
    const char *context;
    const char *exe; /* this hmdlod, for the plan lines in runs.csv */
    int partial;
    FILE *echo;
};
int bch_report(const struct bch_report_options *o, struct hl_error *err);

#endif
