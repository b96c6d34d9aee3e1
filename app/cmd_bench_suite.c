/* hmdlod bench (no sub-bench name): the suite of issue 15. Argument parsing and dispatch only: the
 * run list, the folders and the report are bench/'s (bench/suite.h). Serial runs go through
 * cmd_replay with each run's own argument list, the very line a plan writes, so a serial suite and
 * a parallel plan run the same replays. */
#define _XOPEN_SOURCE 700 /* realpath, readlink */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "app/commands.h"
#include "bench/bench.h"

enum { MAX_MERGE_DIRS = 64 };

void cmd_bench_suite_usage(FILE *f)
{
    fputs("usage: hmdlod bench [--quick|--tiny] [--only GLOB] [--repeats N] --out DIR   run the suite, then its report\n"
          "       hmdlod bench [--quick|--tiny] [--only GLOB] [--repeats N] --plan FILE --out DIR\n"
          "                                                   write one replay line per run and round\n"
          "       hmdlod bench --merge DIR [DIR...] [--out DIR] [--partial]   the report from run folders\n\n"
          "The suite (docs/bench.md): Funkhouser's Table 1 on real traces, speed against image error, Reddy's\n"
          "study, Nirenstein's optimizer timings, Mason-Blake's comparison and the cost model, as DIR/report.md,\n"
          "DIR/*.csv and DIR/plots/*.png (gnuplot). Without --quick: the full sweep (~30-60 min on 2 cores).\n"
          "  --quick        a short version (render scale 0.5, 1 s of one trace; under 5 minutes on 2 cores)\n"
          "  --tiny         a few seconds' version for tests (every table, very short runs)\n"
          "  --only GLOB    only the runs whose id matches GLOB (ids: DIR/runs.csv, e.g. 't1-field-*')\n"
          "  --repeats N    rounds of every run, 1 ... 9 (default 2): each table's runs forward, then backward,\n"
          "                 ...; timing cells are medians over rounds, timing ratios taken per round\n"
          "  --out DIR      the suite's folder: DIR/runs/ID hold the replays (for --merge: the report's\n"
          "                 folder, default the first DIR)\n"
          "  --plan FILE    write the plan instead of running it (without --out: DIR is FILE.d); run it with\n"
          "                 parallel --will-cite -j2 < FILE, or as a Slurm array (scripts/slurm-bench.sh),\n"
          "                 then hmdlod bench --merge DIR\n"
          "  --merge DIR... build the report from DIR/runs (several DIRs: the union, e.g. from several hosts)\n"
          "  --partial      with --merge: report missing runs as such instead of failing\n",
          f);
}

/* This executable's absolute path (plan lines name it). */
static int self_path(char *out, size_t size)
{
    ssize_t len = readlink("/proc/self/exe", out, size - 1);
    if (len <= 0 || (size_t)len >= size - 1)
        return -1;
    out[len] = '\0';
    return 0;
}

/* Creates dir when missing and returns its absolute path; 0, or 1 after the message. */
static int absolute_dir(const char *dir, char *out)
{
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "hmdlod bench: --out %s: cannot create the folder: %s\n", dir, strerror(errno));
        return 1;
    }
    if (!realpath(dir, out)) {
        fprintf(stderr, "hmdlod bench: --out %s: %s\n", dir, strerror(errno));
        return 1;
    }
    if (access(out, W_OK) != 0) {
        fprintf(stderr, "hmdlod bench: --out %s: not a writable folder\n", dir);
        return 1;
    }
    return 0;
}

/* Runs every run of the plan serially, each table's runs in alternated rounds (bch_plan_step), into
 * DIR/runs/ID and DIR/runs-N/ID, with a progress bar over runs. */
static int run_serial(const struct bch_plan *plan, const char *dir)
{
    struct hl_progress bar;
    size_t steps = plan->count * (size_t)bch_plan_rounds(plan);
    hl_progress_begin(&bar, "hmdlod bench", steps);
    for (size_t s = 0; s < steps; ++s) {
        int repeat = 0;
        size_t i = bch_plan_step(plan, s, &repeat);
        char out[PATH_MAX + 128];
        bch_run_dir(dir, plan->runs[i].id, repeat, out, sizeof out);
        char storage[BCH_MAX_ARGS][BCH_ARG_SIZE];
        const char *argv[BCH_MAX_ARGS];
        int argc = bch_run_argv(plan, &plan->runs[i], out, storage, argv, BCH_MAX_ARGS);
        /* The run's folder made here, not by the replay: a link planted at DIR/runs/ID is refused
         * before anything is written through it (hl_dir_make). */
        struct hl_error err;
        if (hl_dir_make(out, &err) != 0) {
            hl_progress_end(&bar);
            fprintf(stderr, "hmdlod bench: %s\n", err.msg);
            return 1;
        }
        if (cmd_replay(argc, (char **)argv) != 0) {
            hl_progress_end(&bar);
            fprintf(stderr,
                    "hmdlod bench: run %s (round %d) failed (its message is above); the runs before it are in "
                    "%s/runs*\n",
                    plan->runs[i].id, repeat + 1, dir);
            return 1;
        }
        hl_progress_update(&bar, s + 1);
    }
    hl_progress_end(&bar);
    return 0;
}

static int report(const struct bch_plan *plan, const char *const *dirs, int n_dirs, const char *out, int partial,
                  int full_argc, char **full_argv)
{
    char exe[PATH_MAX];
    if (self_path(exe, sizeof exe) != 0)
        snprintf(exe, sizeof exe, "hmdlod");
    char *context = bch_context_text(full_argc, full_argv);
    struct bch_report_options o = {plan, dirs, n_dirs, out, context ? context : "", exe, partial, stdout};
    struct hl_error err = {{0}};
    int rc = bch_report(&o, &err);
    free(context);
    if (rc != 0) {
        fprintf(stderr, "hmdlod bench: %s\n", err.msg);
        return 1;
    }
    fprintf(stderr, "hmdlod bench: wrote %s/report.md, its CSVs and plots/\n", out);
    return 0;
}

static int merge(const char *const *dirs, int n_dirs, const char *out, int partial, int full_argc, char **full_argv)
{
    struct bch_plan plan;
    char command[8192];
    struct hl_error err = {{0}};
    if (bch_plan_read(dirs[0], &plan, command, sizeof command, &err) != 0) {
        fprintf(stderr, "hmdlod bench --merge: %s\n", err.msg);
        return 1;
    }
    char abs_out[PATH_MAX];
    int rc = absolute_dir(out ? out : dirs[0], abs_out);
    if (rc == 0)
        rc = report(&plan, dirs, n_dirs, abs_out, partial, full_argc, full_argv);
    bch_plan_free(&plan);
    return rc;
}

int cmd_bench_suite(int argc, char **argv, int full_argc, char **full_argv)
{
    enum bch_mode mode = BCH_FULL;
    const char *out = NULL, *plan_file = NULL, *only = NULL;
    const char *merge_dirs[MAX_MERGE_DIRS];
    int n_merge = 0, merging = 0, partial = 0, repeats = BCH_SUITE_DEFAULT_REPEATS, repeats_given = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--quick"))
            mode = BCH_QUICK;
        else if (!strcmp(a, "--tiny"))
            mode = BCH_TINY;
        else if (!strcmp(a, "--partial"))
            partial = 1;
        else if (!strcmp(a, "--merge"))
            merging = 1;
        else if ((!strcmp(a, "--out") || !strcmp(a, "--plan") || !strcmp(a, "--only") || !strcmp(a, "--repeats")) &&
                 !val) {
            fprintf(stderr, "hmdlod bench: %s needs a value\n", a);
            return 1;
        } else if (!strcmp(a, "--out"))
            out = argv[++i];
        else if (!strcmp(a, "--plan"))
            plan_file = argv[++i];
        else if (!strcmp(a, "--only"))
            only = argv[++i];
        else if (!strcmp(a, "--repeats")) {
            char *end;
            long n = strtol(val, &end, 10);
            if (end == val || *end || n < 1 || n > BCH_SUITE_MAX_REPEATS) {
                fprintf(stderr, "hmdlod bench: --repeats '%s': want a whole number 1 ... %d\n", val,
                        BCH_SUITE_MAX_REPEATS);
                return 1;
            }
            repeats = (int)n, repeats_given = 1, ++i;
        }
        else if (merging && a[0] != '-' && n_merge < MAX_MERGE_DIRS)
            merge_dirs[n_merge++] = a;
        else {
            fprintf(stderr, "hmdlod bench: unknown option '%s' (hmdlod bench --help)\n", a);
            return 1;
        }
    }
    if (merging) {
        if (n_merge == 0 || plan_file || only || mode != BCH_FULL || repeats_given) {
            fprintf(stderr, "hmdlod bench: --merge takes run folders (DIR...), and --out or --partial only\n");
            return 1;
        }
        return merge(merge_dirs, n_merge, out, partial, full_argc, full_argv);
    }
    if (partial) {
        fprintf(stderr, "hmdlod bench: --partial goes with --merge\n");
        return 1;
    }
    char plan_out[PATH_MAX];
    if (!out && plan_file) { /* a plan alone: its folder beside it, FILE.d */
        snprintf(plan_out, sizeof plan_out, "%s.d", plan_file);
        out = plan_out;
    }
    if (!out) {
        fprintf(stderr, "hmdlod bench: --out DIR is required (hmdlod bench --help)\n");
        return 1;
    }
    char shared[4096], abs_shared[PATH_MAX], dir[PATH_MAX];
    if (bch_find_shared(shared, sizeof shared) != 0 || !realpath(shared, abs_shared)) {
        fprintf(stderr,
                "hmdlod bench: the shared data folder is absent (%s): the suite replays its real traces; "
                "set HMDLOD_SHARED\n",
                shared);
        return 1;
    }
    if (absolute_dir(out, dir) != 0)
        return 1;
    /* the command stored in suite.txt: how to make this folder again */
    char command[8192];
    size_t len = (size_t)snprintf(command, sizeof command, "hmdlod");
    for (int i = 0; i < full_argc && len < sizeof command; ++i)
        len += (size_t)snprintf(command + len, sizeof command - len, " %s", full_argv[i]);
    struct bch_plan plan;
    struct hl_error err = {{0}};
    fprintf(stderr, "hmdlod bench: preparing %s (still-head trace, domes' full-detail cost)\n", dir);
    if (bch_prepare(dir, mode, only, repeats, abs_shared, command, &plan, &err) != 0) {
        fprintf(stderr, "hmdlod bench: %s\n", err.msg);
        return 1;
    }
    int rc = 0;
    if (plan_file) {
        char exe[PATH_MAX];
        if (self_path(exe, sizeof exe) != 0) {
            fprintf(stderr, "hmdlod bench: cannot find this program's path (/proc/self/exe)\n");
            rc = 1;
        } else if (bch_plan_write(&plan, exe, dir, plan_file, &err) != 0) {
            fprintf(stderr, "hmdlod bench: %s\n", err.msg);
            rc = 1;
        } else {
            fprintf(stderr,
                    "hmdlod bench: wrote %zu runs × %d rounds to %s; run them with  parallel --will-cite -j2 < %s  "
                    "then  hmdlod bench --merge %s\n",
                    plan.count, plan.repeats, plan_file, plan_file, dir);
        }
    } else {
        fprintf(stderr, "hmdlod bench: %zu runs × %d alternated rounds (%s)\n", plan.count, plan.repeats,
                bch_mode_name(mode));
        const char *dirs[1] = {dir};
        rc = run_serial(&plan, dir);
        if (rc == 0)
            rc = report(&plan, dirs, 1, dir, 0, full_argc, full_argv);
    }
    bch_plan_free(&plan);
    return rc;
}
