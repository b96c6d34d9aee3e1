/* Making a suite's folder: the still-head trace, the full-detail cost of domes that t5's budgets are
 * fractions of, and DIR/suite.txt, from which --merge rebuilds the very same plan. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bench/suite_internal.h"
#include "replay/replay.h"

static int make_dir(const char *path, struct hl_error *err)
{
    if (mkdir(path, 0777) == 0 || errno == EEXIST) {
        struct stat st;
        if (stat(path, &st) == 0 && S_ISDIR(st.st_mode) && access(path, W_OK) == 0)
            return 0;
        return hl_fail(err, "%s: not a writable folder", path);
    }
    return hl_fail(err, "%s: cannot create the folder: %s", path, strerror(errno));
}

/* A head that does not move (docs/trace-format.md §1): identity at 100 Hz for `seconds`. Reddy's
 * still-head condition: only size and eccentricity can coarsen a level. */
static int write_still_trace(const char *path, double seconds, struct hl_error *err)
{
    size_t n = (size_t)ceil(seconds * 100.0) + 1;
    struct rpl_trace t;
    memset(&t, 0, sizeof t);
    t.count = n;
    t.time_s = malloc(n * sizeof *t.time_s);
    t.orientation = malloc(n * sizeof *t.orientation);
    int rc = -1;
    if (!t.time_s || !t.orientation) {
        hl_fail(err, "%s: out of memory", path);
    } else {
        for (size_t i = 0; i < n; ++i) {
            t.time_s[i] = (double)i / 100.0;
            t.orientation[i] = hl_q_identity();
        }
        rc = rpl_trace_write_csv(&t, path, err);
    }
    free(t.time_s);
    free(t.orientation);
    return rc;
}

/* The cost model's prediction for domes at full detail (selector none) over t5's frames: the runs'
 * budgets are 0.5, 1 and 2 × this. A prediction, not a measurement, so the budgets are the same on
 * every machine using the same cost profile (docs/bench.md, Table 5). */
static int domes_full_cost(const char *out_dir, enum bch_mode mode, const char *shared, double *full_ms,
                           struct hl_error *err)
{
    struct bch_plan probe; /* t5's settings, from a plan made with a placeholder cost */
    if (bch_plan_make(mode, "t5-*", shared, out_dir, 1.0, &probe, err) != 0)
        return -1;
    struct bch_run run = probe.runs[0];
    char calib[4300], dir[4400];
    snprintf(calib, sizeof calib, "%s/calibration", out_dir);
    snprintf(dir, sizeof dir, "%s/domes-none", calib);
    struct rpl_options o;
    rpl_options_defaults(&o);
    o.trace_path = probe.traces[0];
    o.frame.scene = "domes";
    o.frame.display = run.display;
    o.frame.selector = "none";
    o.frames = run.frames;
    o.frame.render_scale = run.render_scale;
    o.out_dir = dir;
    o.frame.quiet = 1;
    bch_plan_free(&probe);
    if (hl_dir_make(calib, err) != 0 || hl_dir_make(dir, err) != 0)
        return -1;
    struct rpl_summary sum;
    if (rpl_run(&o, &sum, err) != 0)
        return -1;
    struct bch_result r;
    if (bch_result_load(dir, &r, err) != 0)
        return -1;
    *full_ms = bch_mean(&r, r.predicted_ms);
    bch_result_free(&r);
    if (!(*full_ms > 0.0))
        return hl_fail(err, "%s/frames.csv: no predicted cost to size t5's budgets by", dir);
    return 0;
}

int bch_prepare(const char *out_dir, enum bch_mode mode, const char *only, int repeats, const char *shared,
                      const char *command, struct bch_plan *plan, struct hl_error *err)
{
    char runs[4300], path[4300];
    if (repeats < 1 || repeats > BCH_SUITE_MAX_REPEATS)
        return hl_fail(err, "bench plan: %d rounds: want 1 … %d", repeats, BCH_SUITE_MAX_REPEATS);
    if (make_dir(out_dir, err) != 0)
        return -1;
    for (int r = 0; r < repeats; ++r) { /* every round's runs folder, before any plan line runs */
        bch_runs_dir(out_dir, r, runs, sizeof runs);
        if (hl_dir_make(runs, err) != 0)
            return -1;
    }
    snprintf(path, sizeof path, "%s/still-head.csv", out_dir);
    if (write_still_trace(path, 600.0 / 90.0 + 1.0, err) != 0) /* the longest run: 600 frames at 90 Hz */
        return -1;
    double full_ms = 0.0;
    if (domes_full_cost(out_dir, mode, shared, &full_ms, err) != 0)
        return -1;
    if (bch_plan_make(mode, only, shared, out_dir, full_ms, plan, err) != 0)
        return -1;
    plan->repeats = repeats;
    snprintf(path, sizeof path, "%s/suite.txt", out_dir);
    struct hl_out out;
    if (hl_out_open(&out, path, err) != 0) {
        bch_plan_free(plan);
        return -1;
    }
    FILE *f = out.f;
    fprintf(f,
            "format hmdlod-bench-suite-1\nmode %s\nonly %s\nrepeats %d\nshared %s\nout %s\ndomes_full_ms %.17g\n"
            "command %s\n",
            bch_mode_name(mode), plan->only, repeats, shared, out_dir, full_ms, command);
    if (hl_out_commit(&out, err) != 0) {
        bch_plan_free(plan);
        return -1;
    }
    return 0;
}

int bch_plan_read(const char *dir, struct bch_plan *plan, char *command, size_t command_size,
                        struct hl_error *err)
{
    char path[4300];
    snprintf(path, sizeof path, "%s/suite.txt", dir);
    FILE *f = fopen(path, "r");
    if (!f)
        return hl_fail(err, "%s: cannot read (%s): not a folder made by hmdlod bench --out or --plan", path,
                       strerror(errno));
    char line[8192], mode[16] = "", only[128] = "", shared[4096] = "", out[4096] = "";
    double full_ms = 0.0;
    int format_ok = 0;
    long repeats = 1; /* folders made before the suite had rounds: one */
    command[0] = '\0';
    for (int lineno = 1; fgets(line, sizeof line, f); ++lineno) {
        line[strcspn(line, "\n")] = '\0';
        char *sp = strchr(line, ' ');
        const char *val = sp ? sp + 1 : "";
        if (sp)
            *sp = '\0';
        if (!strcmp(line, "format"))
            format_ok = !strcmp(val, "hmdlod-bench-suite-1");
        else if (!strcmp(line, "mode"))
            snprintf(mode, sizeof mode, "%s", val);
        else if (!strcmp(line, "only"))
            snprintf(only, sizeof only, "%s", val);
        else if (!strcmp(line, "shared"))
            snprintf(shared, sizeof shared, "%s", val);
        else if (!strcmp(line, "out"))
            snprintf(out, sizeof out, "%s", val);
        else if (!strcmp(line, "repeats")) {
            char *end;
            repeats = strtol(val, &end, 10);
            if (end == val || *end || repeats < 1 || repeats > BCH_SUITE_MAX_REPEATS) {
                fclose(f);
                return hl_fail(err, "%s:%d: repeats '%s': want 1 … %d", path, lineno, val, BCH_SUITE_MAX_REPEATS);
            }
        } else if (!strcmp(line, "domes_full_ms"))
            full_ms = strtod(val, NULL);
        else if (!strcmp(line, "command"))
            snprintf(command, command_size, "%s", val);
        else {
            fclose(f);
            return hl_fail(err, "%s:%d: unknown key '%s'", path, lineno, line);
        }
    }
    fclose(f);
    if (!format_ok)
        return hl_fail(err, "%s: not an hmdlod-bench-suite-1 file", path);
    enum bch_mode m;
    if (!strcmp(mode, "quick"))
        m = BCH_QUICK;
    else if (!strcmp(mode, "full"))
        m = BCH_FULL;
    else if (!strcmp(mode, "tiny"))
        m = BCH_TINY;
    else
        return hl_fail(err, "%s: mode: '%s' is not quick, full or tiny", path, mode);
    /* the folder the plan was made for (its lines name it), even when merged elsewhere */
    if (bch_plan_make(m, only, shared, out[0] ? out : dir, full_ms, plan, err) != 0) {
        char why[512];
        snprintf(why, sizeof why, "%s", err ? err->msg : "");
        return hl_fail(err, "%s: %s", path, why);
    }
    plan->repeats = (int)repeats;
    return 0;
}
