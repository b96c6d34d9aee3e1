/* The bench report: every run read back from its folder (DIR/runs/ID), then report.md, one CSV per
 * table, deterministic.txt, runs.csv (each run's plan line) and the plots. Built from the folders
 * only, so a serial run, a parallel plan and a merge of several hosts' folders give one report. */
#define _XOPEN_SOURCE 700 /* fork, execvp, chdir */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench/suite_internal.h"

/* ---- tables ------------------------------------------------------------------------------------ */

const char *bch_cell(char *cell, double v, int digits)
{
    if (isfinite(v))
        snprintf(cell, BCH_CELL, "%.*f", digits, v);
    else
        snprintf(cell, BCH_CELL, "—");
    return cell;
}

const char *bch_psnr_cell(char *cell, const struct bch_result *r)
{
    if (r && !isfinite(r->psnr_db_mean) && r->ref_frames > 0 && r->identical_frames == r->ref_frames) {
        snprintf(cell, BCH_CELL, "inf");
        return cell;
    }
    return bch_cell(cell, r ? r->psnr_db_mean : NAN, 2);
}

static void both(struct bch_table *t, const char *s)
{
    fputs(s, t->md);
    if (t->echo)
        fputs(s, t->echo);
}

int bch_table_begin(struct bch_table *t, const char *dir, const char *name, FILE *md, FILE *echo, FILE *det,
                          const char *const *headers, int cols, struct hl_error *err)
{
    memset(t, 0, sizeof *t);
    t->md = md, t->echo = echo, t->cols = cols;
    snprintf(t->csv_path, sizeof t->csv_path, "%s/%s.csv", dir, name);
    if (hl_out_open(&t->csv_out, t->csv_path, err) != 0)
        return -1;
    t->csv = t->csv_out.f;
    fprintf(det, "%s.csv:", name);
    int first_det = 1;
    both(t, "\n|");
    for (int c = 0; c < cols; ++c) {
        const char *h = headers[c];
        int deterministic = h[0] == '*';
        if (deterministic) {
            ++h;
            t->has_deterministic = 1;
            fprintf(det, "%s%s", first_det ? " " : ",", h);
            first_det = 0;
        }
        fprintf(t->csv, "%s%s", c ? "," : "", h);
        both(t, " ");
        both(t, h);
        both(t, deterministic ? " † |" : " |");
    }
    fputc('\n', det);
    fputc('\n', t->csv);
    both(t, "\n|");
    for (int c = 0; c < cols; ++c)
        both(t, c == 0 ? "---|" : "--:|");
    both(t, "\n");
    return 0;
}

void bch_table_row(struct bch_table *t, const char *const *cells)
{
    both(t, "|");
    for (int c = 0; c < t->cols; ++c) {
        both(t, " ");
        both(t, cells[c]);
        both(t, " |");
        fprintf(t->csv, "%s%s", c ? "," : "", strcmp(cells[c], "—") ? cells[c] : "");
    }
    fputc('\n', t->csv);
    both(t, "\n");
}

int bch_table_end(struct bch_table *t, struct hl_error *err)
{
    if (t->has_deterministic)
        both(t, "\n† deterministic: the same inputs give the same figure on rows whose `deterministic` is 1 "
                "(selectors none, static, reddy; fs, mb and feedback steer by measured times). `");
    else
        both(t, "\nEvery column follows measured times (none is deterministic). `");
    fputs(strrchr(t->csv_path, '/') + 1, t->md);
    if (t->echo)
        fputs(strrchr(t->csv_path, '/') + 1, t->echo);
    both(t, "` holds the rows.\n");
    t->csv = NULL;
    return hl_out_commit(&t->csv_out, err);
}

/* ---- plots ------------------------------------------------------------------------------------- */

int bch_have_gnuplot(void)
{
    const char *path = getenv("PATH");
    if (!path)
        return 0;
    char dir[4096];
    for (const char *p = path; *p;) {
        size_t len = strcspn(p, ":");
        snprintf(dir, sizeof dir, "%.*s/gnuplot", (int)len, p);
        if (access(dir, X_OK) == 0)
            return 1;
        p += len + (p[len] == ':');
    }
    return 0;
}

FILE *bch_plot_data(struct bch_ctx *c, const char *name, struct hl_out *out, struct hl_error *err)
{
    char path[4400];
    snprintf(path, sizeof path, "%s/plots/%s", c->dir, name);
    return hl_out_open(out, path, err) == 0 ? out->f : NULL;
}

/* gnuplot NAME.gp run in DIR/plots (the scripts name their files relatively); its messages (range
 * warnings on short runs, mostly) go to DIR/plots/gnuplot.log. 0 when it exited 0. */
static int run_gnuplot(const char *plots_dir, const char *script)
{
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        if (chdir(plots_dir) != 0)
            _exit(127);
        int log = open("gnuplot.log", O_WRONLY | O_CREAT | O_APPEND | O_NOFOLLOW | O_CLOEXEC, 0666);
        if (log >= 0)
            dup2(log, STDERR_FILENO), close(log);
        execlp("gnuplot", "gnuplot", script, (char *)NULL);
        _exit(127);
    }
    int status = 0;
    if (waitpid(pid, &status, 0) < 0)
        return -1;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : -1;
}

int bch_plot(struct bch_ctx *c, const char *name, const char *title, const char *body, int has_data,
                   struct hl_error *err)
{
    char gp[4500], plots[4300], script[128];
    snprintf(plots, sizeof plots, "%s/plots", c->dir);
    snprintf(script, sizeof script, "%s.gp", name);
    snprintf(gp, sizeof gp, "%s/%s", plots, script);
    struct hl_out out;
    if (hl_out_open(&out, gp, err) != 0)
        return -1;
    FILE *f = out.f;
    fprintf(f, "# %s (hmdlod bench; run in this folder: gnuplot %s)\n", title, script);
    fprintf(f, "set terminal pngcairo size 900,600 noenhanced\nset output '%s.png'\nset title '%s'\n", name, title);
    fprintf(f, "set datafile missing 'NaN'\nset grid\n");
    if (has_data)
        fputs(body, f);
    else /* an empty plot would stop gnuplot ("all points undefined") and leave no image */
        fputs("set label 1 'not measured in these runs' at graph 0.5, graph 0.5 center\n"
              "plot [0:1][0:1] -1 notitle\n",
              f);
    if (hl_out_commit(&out, err) != 0)
        return -1;
    fprintf(c->md, "\n![%s](plots/%s.png) (`plots/%s`)\n", title, name, script);
    if (c->gnuplot && run_gnuplot(plots, script) != 0)
        fprintf(c->md, "\n(gnuplot failed on plots/%s; its message is in plots/gnuplot.log)\n", script);
    return 0;
}

void bch_heading(struct bch_ctx *c, const char *heading, const char *text, int echo)
{
    fprintf(c->md, "\n## %s\n\n%s- renderer: %s\n\n%s\n", heading, c->context, c->renderer, text);
    if (echo && c->echo)
        fprintf(c->echo, "\n## %s\n\n%s\n", heading, text);
}

/* ---- the report -------------------------------------------------------------------------------- */

const struct bch_result *bch_find(const struct bch_ctx *c, const char *id)
{
    for (size_t i = 0; i < c->plan->count; ++i)
        if (!strcmp(c->plan->runs[i].id, id))
            return c->results[i].present ? &c->results[i] : NULL;
    return NULL;
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* Loads round `repeat` of run id from the first of the folders that has it into *r (r NULL: only looks);
 * 1 when found, 0 when no folder has it, −1 with err when one has it but it does not read. */
static int load_round(const struct bch_report_options *o, const char *id, int repeat, struct bch_result *r,
                      struct hl_error *err)
{
    for (int d = 0; d < o->dir_count; ++d) {
        char dir[4400], summary[4500];
        bch_run_dir(o->dirs[d], id, repeat, dir, sizeof dir);
        snprintf(summary, sizeof summary, "%s/summary.json", dir);
        if (!exists(summary))
            continue;
        return r && bch_result_load(dir, r, err) != 0 ? -1 : 1;
    }
    return 0;
}

static void note_missing(const char *id, int repeat, size_t *n_missing, char *missing, size_t missing_size)
{
    size_t len = strlen(missing);
    if (*n_missing < 8) {
        if (repeat == 0)
            snprintf(missing + len, missing_size - len, "%s%s", *n_missing ? ", " : "", id);
        else
            snprintf(missing + len, missing_size - len, "%s%s (round %d)", *n_missing ? ", " : "", id, repeat + 1);
    }
    ++*n_missing;
}

/* Loads every run's every round from the first folder that has it; lists the missing ones in *missing
 * (a run with its first round missing counts as missing, whatever its other rounds). */
static int load_all(const struct bch_report_options *o, struct bch_result *results, size_t *n_missing,
                    size_t *n_missing_runs, char *missing, size_t missing_size, struct hl_error *err)
{
    *n_missing = *n_missing_runs = 0;
    missing[0] = '\0';
    int rounds = bch_plan_rounds(o->plan);
    for (size_t i = 0; i < o->plan->count; ++i) {
        const char *id = o->plan->runs[i].id;
        int found = load_round(o, id, 0, &results[i], err);
        if (found < 0)
            return -1;
        if (!found) { /* the run is missing; count its other rounds all the same */
            note_missing(id, 0, n_missing, missing, missing_size);
            ++*n_missing_runs;
            for (int k = 1; k < rounds; ++k)
                if (load_round(o, id, k, NULL, err) == 0)
                    note_missing(id, k, n_missing, missing, missing_size);
            continue;
        }
        results[i].rounds = rounds;
        if (rounds > 1 && !(results[i].more = calloc((size_t)rounds - 1, sizeof *results[i].more)))
            return hl_fail(err, "bench report: out of memory");
        for (int k = 1; k < rounds; ++k) {
            found = load_round(o, id, k, &results[i].more[k - 1], err);
            if (found < 0)
                return -1;
            if (!found)
                note_missing(id, k, n_missing, missing, missing_size);
        }
    }
    return 0;
}

static int write_runs_csv(const struct bch_report_options *o, const struct bch_result *results,
                          struct hl_error *err)
{
    char path[4300];
    snprintf(path, sizeof path, "%s/runs.csv", o->out_dir);
    struct hl_out out;
    if (hl_out_open(&out, path, err) != 0)
        return -1;
    FILE *f = out.f;
    fputs("id,table,present,rounds_present,frames,renderer,command\n", f);
    for (size_t i = 0; i < o->plan->count; ++i) {
        const struct bch_run *r = &o->plan->runs[i];
        int rounds = results[i].present;
        for (int k = 0; k + 1 < results[i].rounds; ++k)
            rounds += results[i].more[k].present;
        fprintf(f, "%s,%d,%d,%d,%ld,\"%s\",\"", r->id, r->table, results[i].present, rounds, results[i].n,
                results[i].renderer);
        /* the plan line, CSV-quoted (a double quote doubled) */
        char *line = NULL;
        size_t len = 0;
        FILE *m = open_memstream(&line, &len);
        if (m) {
            bch_run_line(o->plan, r, 0, o->exe, o->plan->out_dir, m);
            fclose(m);
            for (const char *p = line; p && *p; ++p)
                fputs(*p == '"' ? "\"\"" : (char[2]){*p, 0}, f);
            free(line);
        }
        fputs("\"\n", f);
    }
    return hl_out_commit(&out, err);
}

/* The report's folder (given) may be reached through a link; plots/ inside it is made here, so a link
 * planted there is refused (hl_dir_make). */
static int make_dir(const char *path, struct hl_error *err)
{
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return hl_fail(err, "%s: cannot create the folder: %s", path, strerror(errno));
    if (access(path, W_OK) != 0)
        return hl_fail(err, "%s: not a writable folder", path);
    return 0;
}

/* One context line on how the runs shared the machine, from each run's wall-clock span and host
 * (summary.json): runs whose spans overlap on one host ran in parallel (GNU parallel, a Slurm array
 * on one node), so their timing columns measured a shared machine; runs from several hosts measured
 * different machines. Deterministic columns are not affected either way. */
static void timing_note(const struct bch_plan *plan, const struct bch_result *results, char *out, size_t size)
{
    /* every round of every run, as one list */
    size_t count = 0, cap = 0;
    for (size_t i = 0; i < plan->count; ++i)
        cap += (size_t)bch_result_rounds(&results[i]);
    const struct bch_result **all = malloc((cap ? cap : 1) * sizeof *all);
    out[0] = '\0';
    if (!all)
        return;
    for (size_t i = 0; i < plan->count; ++i) {
        all[count++] = &results[i];
        for (int k = 0; k + 1 < results[i].rounds; ++k)
            all[count++] = &results[i].more[k];
    }
    size_t timed = 0, present = 0, overlapped = 0, hosts = 0;
    for (size_t i = 0; i < count; ++i) {
        const struct bch_result *a = all[i];
        if (!a->present)
            continue;
        ++present;
        if (!(isfinite(a->wall_start_unix_s) && isfinite(a->wall_end_unix_s)))
            continue;
        ++timed;
        int new_host = 1, overlaps = 0;
        for (size_t j = 0; j < count; ++j) {
            const struct bch_result *b = all[j];
            if (j == i || !b->present || strcmp(a->host, b->host) != 0)
                continue;
            if (j < i && isfinite(b->wall_start_unix_s))
                new_host = 0;
            if (a->wall_start_unix_s < b->wall_end_unix_s && b->wall_start_unix_s < a->wall_end_unix_s)
                overlaps = 1;
        }
        hosts += (size_t)new_host;
        overlapped += (size_t)overlaps;
    }
    free(all);
    size_t used = 0;
    if (plan->repeats > 1)
        used += (size_t)snprintf(out, size,
                                 "- timing: %d alternated rounds of every run (each table's runs forward, then "
                                 "backward, …): a timing cell is the median of its rounds' figures, Table 3's "
                                 "speedup the median of its per-round ratios; Figure 7's per-frame series and Table "
                                 "6's frames come from the first round\n",
                                 plan->repeats);
    else
        used += (size_t)snprintf(out, size, "- timing: one round of every run (`--repeats 1`): timing cells and "
                                            "ratios come from single runs, in plan order\n");
    if (used < size && timed < present)
        used += (size_t)snprintf(out + used, size - used,
                                 "- timing: %zu of %zu runs have no wall-clock span in summary.json "
                                 "(made by an older hmdlod): whether they ran in parallel is unknown\n",
                                 present - timed, present);
    if (used >= size || timed == 0)
        return;
    if (overlapped)
        used += (size_t)snprintf(out + used, size - used,
                                 "- timing: **from parallel runs** — %zu of %zu runs ran while another run of this "
                                 "plan ran on the same host, so their timing columns (frame, draw and optimizer "
                                 "time, deadline share, and every figure of fs, mb and feedback) shared the "
                                 "machine: compare them with each other, not with a serial run's; † columns are "
                                 "unaffected\n",
                                 overlapped, timed);
    else
        used += (size_t)snprintf(out + used, size - used,
                                 "- timing: serial — no run overlapped another on its host\n");
    if (used < size && hosts > 1)
        snprintf(out + used, size - used,
                 "- timing: runs from %zu hosts: timing columns mix machines (compare rows of one host)\n", hosts);
}

static int write_report(const struct bch_report_options *o, struct bch_result *results, size_t n_missing,
                        size_t n_missing_runs, const char *missing, struct hl_error *err)
{
    char plots[4300], md_path[4300], det_path[4300];
    snprintf(plots, sizeof plots, "%s/plots", o->out_dir);
    if (make_dir(o->out_dir, err) != 0 || hl_dir_make(plots, err) != 0)
        return -1;
    char log[4400];
    snprintf(log, sizeof log, "%s/gnuplot.log", plots);
    unlink(log); /* this report's messages only */
    snprintf(md_path, sizeof md_path, "%s/report.md", o->out_dir);
    snprintf(det_path, sizeof det_path, "%s/deterministic.txt", o->out_dir);
    struct hl_out md_out, det_out;
    if (hl_out_open(&md_out, md_path, err) != 0)
        return -1;
    if (hl_out_open(&det_out, det_path, err) != 0) {
        hl_out_abort(&md_out);
        return -1;
    }
    FILE *md = md_out.f, *det = det_out.f;
    fputs("# Deterministic columns of each table (on rows whose `deterministic` is 1)\n", det);
    const char *renderer = "unknown";
    for (size_t i = 0; i < o->plan->count; ++i)
        if (results[i].present) {
            renderer = results[i].renderer;
            break;
        }
    /* The timing note goes under every table, with the rest of the context. */
    char note[1536];
    timing_note(o->plan, results, note, sizeof note);
    size_t context_len = strlen(o->context) + strlen(note) + 1;
    char *context = malloc(context_len);
    if (!context) {
        hl_out_abort(&md_out);
        hl_out_abort(&det_out);
        return hl_fail(err, "bench report: out of memory");
    }
    snprintf(context, context_len, "%s%s", o->context, note);
    struct bch_ctx c = {
        o->plan, results, o->out_dir, md, o->echo, det, context, renderer, bch_have_gnuplot()};
    if (o->echo)
        fprintf(o->echo, "# hmdlod bench report (%s): %s/report.md\n\n%s- renderer: %s\n",
                bch_mode_name(o->plan->mode), o->out_dir, context, renderer);
    size_t rounds = (size_t)bch_plan_rounds(o->plan);
    fprintf(md,
            "# hmdlod bench report (%s)\n\n%s- renderer: %s\n- runs: %zu of %zu, %zu round(s) each: %zu of %zu "
            "replays (each run's replay command: runs.csv)\n",
            bch_mode_name(o->plan->mode), context, renderer, o->plan->count - n_missing_runs, o->plan->count, rounds,
            o->plan->count * rounds - n_missing, o->plan->count * rounds);
    if (!c.gnuplot)
        fputs("\n**gnuplot is not on PATH: the plots' scripts are in plots/*.gp, but no PNG was made** (install "
              "gnuplot-nox, then run `gnuplot NAME.gp` in plots/).\n",
              md);
    if (n_missing)
        fprintf(md,
                "\n**Partial report.** %zu run(s) or round(s) missing: %s%s; the cells of a missing run read —, "
                "a missing round leaves its run's timing cells to the rounds present.\n",
                n_missing, missing, n_missing > 8 ? ", …" : "");
    int rc = 0;
    int (*const tables[])(struct bch_ctx *, struct hl_error *) = {
        bch_tables_t1, bch_tables_t2, bch_tables_t3,
        bch_tables_t4, bch_tables_t5, bch_tables_t6, bch_tables_t7,
    };
    for (int k = 0; k < 7 && rc == 0; ++k)
        rc = tables[k](&c, err);
    free(context);
    if (rc != 0) {
        hl_out_abort(&md_out);
        hl_out_abort(&det_out);
        return -1;
    }
    if (hl_out_commit(&det_out, err) != 0) {
        hl_out_abort(&md_out);
        return -1;
    }
    if (hl_out_commit(&md_out, err) != 0)
        return -1;
    return write_runs_csv(o, results, err);
}

int bch_report(const struct bch_report_options *o, struct hl_error *err)
{
    struct bch_result *results = calloc(o->plan->count ? o->plan->count : 1, sizeof *results);
    if (!results)
        return hl_fail(err, "bench report: out of memory");
    size_t n_missing = 0, n_missing_runs = 0;
    char missing[1024];
    int rc = load_all(o, results, &n_missing, &n_missing_runs, missing, sizeof missing, err);
    if (rc == 0 && n_missing_runs == o->plan->count)
        rc = hl_fail(err, "%s: no runs found (no %s/runs/ID/summary.json for any of the plan's %zu runs)", o->dirs[0],
                     o->dirs[0], o->plan->count);
    else if (rc == 0 && n_missing && !o->partial)
        rc = hl_fail(err,
                     "%zu of %zu replays missing (%s%s): run the rest of the plan, merge the other hosts' "
                     "folders too, or pass --partial",
                     n_missing, o->plan->count * (size_t)bch_plan_rounds(o->plan), missing,
                     n_missing > 8 ? ", …" : "");
    if (rc == 0)
        rc = write_report(o, results, n_missing, n_missing_runs, missing, err);
    for (size_t i = 0; i < o->plan->count; ++i)
        bch_result_free(&results[i]);
    free(results);
    return rc;
}
