/* The bench suite's run list (issue 15): a fixed, deterministic list of replay configurations, each
 * with an id, for the quick, full and tiny modes. The tables it serves are described in docs/bench.md;
 * the papers behind them in PAPERS.md (Funkhouser & Séquin 1993 Table 1 and Figure 7; Reddy 1997 §6;
 * Nirenstein et al. 2008 §5.5; Mason & Blake 1997). */
#define _XOPEN_SOURCE 700 /* fnmatch */
#include <fnmatch.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hmd/hmd.h"
#include "bench/suite_internal.h"

#define CORBILLON_DIR "data/traces/corbillon-mmsys18"
#define EDVAM_TRACE "data/traces/edvam-gaze/participant2.csv"

/* What each mode sweeps. quick: under 5 minutes on the 2-core llvmpipe machine (render scale 0.5,
 * two thirds of a second of each trace); full: the issue's sweep (~30–60 min there); tiny: seconds, for tests. */
struct mode_cfg {
    long frames, t3_frames, t3d_frames; /* t3d: the per-display runs, many in full */
    double render_scale;
    int users;
    int n_t1_scenes;
    int n_budgets;
    double budgets[4]; /* × the display period */
    int n_static;
    double static_px[6];
    int n_gazes;
    int n_objects;
    int objects[3];
    int n_displays; /* 0: every built-in display */
    const char *displays[4];
    long reference_every;
    int n_t4;
    double t4_budgets[3];
    int n_t5;
    double t5_factors[3];
};

static const struct mode_cfg mode_cfgs[3] = {
    [BCH_QUICK] = {.frames = 60,
                         .t3_frames = 40, /* field with 1000 objects: ~85 ms a frame at half scale */
                         .t3d_frames = 60,
                         .render_scale = 0.5,
                         .users = 1,
                         .n_t1_scenes = 2,
                         .n_budgets = 2,
                         .budgets = {0.5, 1.0},
                         .n_static = 3,
                         .static_px = {32, 256, 2048},
                         .n_gazes = 2,
                         .n_objects = 2,
                         .objects = {100, 1000},
                         .n_displays = 4,
                         .displays = {"vive", "quest3", "varjo-aero", "i-glasses"},
                         .reference_every = 15,
                         .n_t4 = 2,
                         .t4_budgets = {0.5, 1.0},
                         .n_t5 = 3,
                         .t5_factors = {0.5, 1.0, 2.0}},
    [BCH_FULL] = {.frames = 600,
                        .t3_frames = 300,
                        .t3d_frames = 150,
                        .render_scale = 1.0,
                        .users = 3,
                        .n_t1_scenes = 2,
                        .n_budgets = 4,
                        .budgets = {0.5, 0.75, 1.0, 1.5},
                        .n_static = 5,
                        .static_px = {16, 64, 256, 1024, 4096},
                        .n_gazes = 2,
                        .n_objects = 3,
                        .objects = {10, 100, 1000},
                        .n_displays = 0 /* every built-in display */,
                        .reference_every = 20,
                        .n_t4 = 3,
                        .t4_budgets = {0.5, 1.0, 2.0},
                        .n_t5 = 3,
                        .t5_factors = {0.5, 1.0, 2.0}},
    [BCH_TINY] = {.frames = 20,
                        .t3_frames = 20,
                        .t3d_frames = 20,
                        .render_scale = 0.25,
                        .users = 1,
                        .n_t1_scenes = 1,
                        .n_budgets = 1,
                        .budgets = {1.0},
                        .n_static = 1,
                        .static_px = {64},
                        .n_gazes = 1,
                        .n_objects = 1,
                        .objects = {10},
                        .n_displays = 1,
                        .displays = {"vive"},
                        .reference_every = 5,
                        .n_t4 = 1,
                        .t4_budgets = {1.0},
                        .n_t5 = 1,
                        .t5_factors = {1.0}},
};

static const char *const t1_scenes[] = {"auditorium", "field"};
static const char *const t1_selectors[] = {"none", "static", "feedback", "reddy", "fs", "mb", "mb"};
static const char *const gazes[] = {"head", "vor"};
#define T1_LIMITED_US 200.0 /* the brief's "mb with --opt-limit-us 200" */
#define T4_LIMIT_US 100.0

const char *bch_mode_name(enum bch_mode mode)
{
    return mode == BCH_FULL ? "full" : mode == BCH_TINY ? "tiny" : "quick";
}

static double vive_period_ms(void)
{
    const struct hmd_profile *p = hmd_builtin_find("vive");
    return p ? 1000.0 / p->refresh_hz : 1000.0 / 90.0;
}

struct builder {
    struct bch_plan *plan;
    const struct mode_cfg *cfg;
    size_t capacity;
    int failed;
};

/* A run with the mode's defaults: vive, user1, the mode's frames and render scale. */
static struct bch_run *add(struct builder *b, int table, const char *scene, const char *selector)
{
    if (b->failed)
        return NULL;
    if (b->plan->count == b->capacity) {
        size_t cap = b->capacity ? 2 * b->capacity : 64;
        struct bch_run *r = realloc(b->plan->runs, cap * sizeof *r);
        if (!r) {
            b->failed = 1;
            return NULL;
        }
        b->plan->runs = r, b->capacity = cap;
    }
    struct bch_run *r = &b->plan->runs[b->plan->count++];
    memset(r, 0, sizeof *r);
    r->table = table;
    snprintf(r->motion, sizeof r->motion, "user1");
    snprintf(r->scene, sizeof r->scene, "%s", scene);
    snprintf(r->selector, sizeof r->selector, "%s", selector);
    snprintf(r->display, sizeof r->display, "vive");
    r->frames = b->cfg->frames;
    r->render_scale = b->cfg->render_scale;
    return r;
}

/* Table 1 (Funkhouser & Séquin 1993): every selector on real traces through auditorium and field;
 * first, per scene, static on the still head: the same work every frame, whose frame-time spread is
 * the machine's own jitter under constant load (the goals are read against it too). */
static void plan_t1(struct builder *b)
{
    for (int sc = 0; sc < b->cfg->n_t1_scenes; ++sc) {
        struct bch_run *r = add(b, 1, t1_scenes[sc], "static");
        if (!r)
            return;
        snprintf(r->motion, sizeof r->motion, "still");
        snprintf(r->id, sizeof r->id, "t1-%s-still-static", r->scene);
    }
    for (int u = 1; u <= b->cfg->users; ++u)
        for (int sc = 0; sc < b->cfg->n_t1_scenes; ++sc)
            for (int se = 0; se < 7; ++se) {
                struct bch_run *r = add(b, 1, t1_scenes[sc], t1_selectors[se]);
                if (!r)
                    return;
                snprintf(r->motion, sizeof r->motion, "user%d", u);
                if (se == 6)
                    r->opt_limit_us = T1_LIMITED_US;
                snprintf(r->id, sizeof r->id, "t1-%s-user%d-%s%s", r->scene, u, r->selector, se == 6 ? "-lim200" : "");
            }
    /* Per foveation mode (issue 32 item 6): fs with layers on the lens centres, after the plain rows. */
    for (int u = 1; u <= b->cfg->users; ++u)
        for (int sc = 0; sc < b->cfg->n_t1_scenes; ++sc) {
            struct bch_run *r = add(b, 1, t1_scenes[sc], "fs");
            if (!r)
                return;
            snprintf(r->motion, sizeof r->motion, "user%d", u);
            snprintf(r->foveation, sizeof r->foveation, "fixed");
            snprintf(r->id, sizeof r->id, "t1-%s-user%d-fs-fixed", r->scene, u);
        }
    /* Under the measured gaze (issue 32 item 6, `--gaze tracked`): fs plain and with its inset
     * following the eye tracker (--foveation gaze), on EDVAM participant 2 through auditorium, with
     * --reference: the only trace here with a measured gaze. */
    if (!b->plan->gaze_trace[0])
        return;
    for (int fov = 0; fov < 2; ++fov) {
        struct bch_run *r = add(b, 1, "auditorium", "fs");
        if (!r)
            return;
        snprintf(r->motion, sizeof r->motion, "edvam-p2");
        snprintf(r->gaze, sizeof r->gaze, "tracked");
        snprintf(r->foveation, sizeof r->foveation, "%s", fov ? "gaze" : "");
        r->reference_every = b->cfg->reference_every;
        snprintf(r->id, sizeof r->id, "t1-auditorium-edvam-p2-fs%s", fov ? "-gaze" : "");
    }
}

/* Speed against error: budgets for the cost-bounded selectors, --static-px for static, reddy as it
 * is; each with --reference, per gaze model. On auditorium, where mid-turn frames lose the most. */
static void plan_t2(struct builder *b)
{
    static const char *const swept[] = {"fs", "mb", "feedback"};
    for (int g = 0; g < b->cfg->n_gazes; ++g) {
        for (int s = 0; s < 3; ++s)
            for (int k = 0; k < b->cfg->n_budgets; ++k) {
                struct bch_run *r = add(b, 2, "auditorium", swept[s]);
                if (!r)
                    return;
                snprintf(r->gaze, sizeof r->gaze, "%s", gazes[g]);
                r->factor = b->cfg->budgets[k];
                r->budget_ms = r->factor * vive_period_ms();
                r->reference_every = b->cfg->reference_every;
                snprintf(r->id, sizeof r->id, "t2-%s-%s-b%g", gazes[g], swept[s], r->factor);
            }
        /* Per foveation mode (issue 32 item 6): fs with layers, and Valve's adaptive quality (static's
         * LODs, the whole eye at the scale its controller sets from the draw time) over the same
         * budgets: the controller's thresholds are shares of the budget. */
        static const char *const layered[][2] = {{"fs", "fixed"}, {"static", "adaptive"}};
        for (int s = 0; s < 2; ++s)
            for (int k = 0; k < b->cfg->n_budgets; ++k) {
                struct bch_run *r = add(b, 2, "auditorium", layered[s][0]);
                if (!r)
                    return;
                snprintf(r->gaze, sizeof r->gaze, "%s", gazes[g]);
                snprintf(r->foveation, sizeof r->foveation, "%s", layered[s][1]);
                r->factor = b->cfg->budgets[k];
                r->budget_ms = r->factor * vive_period_ms();
                r->reference_every = b->cfg->reference_every;
                snprintf(r->id, sizeof r->id, "t2-%s-%s-%s-b%g", gazes[g], layered[s][0], layered[s][1], r->factor);
            }
        for (int k = 0; k < b->cfg->n_static; ++k) {
            struct bch_run *r = add(b, 2, "auditorium", "static");
            if (!r)
                return;
            snprintf(r->gaze, sizeof r->gaze, "%s", gazes[g]);
            r->static_px = b->cfg->static_px[k];
            r->reference_every = b->cfg->reference_every;
            snprintf(r->id, sizeof r->id, "t2-%s-static-px%g", gazes[g], r->static_px);
        }
        struct bch_run *r = add(b, 2, "auditorium", "reddy");
        if (!r)
            return;
        snprintf(r->gaze, sizeof r->gaze, "%s", gazes[g]);
        r->reference_every = b->cfg->reference_every;
        snprintf(r->id, sizeof r->id, "t2-%s-reddy", gazes[g]);
    }
}

/* Reddy's study on field: none against reddy over object counts, size only against size + velocity
 * + eccentricity, still head and real motion (per gaze model); per display the terms' shares; both
 * frequency readings with their image error. */
static void plan_t3(struct builder *b)
{
    static const char *const variants[][4] = {
        /* id part, motion, gaze ("" for none/size: the gaze changes nothing they use), criterion */
        {"still-none", "still", "", ""},
        {"real-none", "user1", "", ""},
        {"still-size", "still", "", ""},
        {"real-size", "user1", "", ""},
        {"still-full", "still", "vor", ""},
        {"real-full-head", "user1", "head", ""},
        {"real-full-vor", "user1", "vor", ""},
        {"real-full-head-acuity", "user1", "head", "acuity"},
        {"real-full-vor-acuity", "user1", "vor", "acuity"},
    };
    for (int o = 0; o < b->cfg->n_objects; ++o)
        for (int v = 0; v < 9; ++v) {
            int is_none = strstr(variants[v][0], "none") != NULL, size_only = strstr(variants[v][0], "size") != NULL;
            struct bch_run *r = add(b, 3, "field", is_none ? "none" : "reddy");
            if (!r)
                return;
            snprintf(r->motion, sizeof r->motion, "%s", variants[v][1]);
            snprintf(r->gaze, sizeof r->gaze, "%s", variants[v][2]);
            snprintf(r->visibility, sizeof r->visibility, "%s", variants[v][3]);
            r->objects = b->cfg->objects[o];
            r->velocity_off = r->eccentricity_off = size_only;
            r->frames = b->cfg->t3_frames;
            snprintf(r->id, sizeof r->id, "t3-o%d-%s", r->objects, variants[v][0]);
        }
    int n_displays = b->cfg->n_displays ? b->cfg->n_displays : hmd_builtin_count();
    for (int d = 0; d < n_displays; ++d) {
        const char *name = b->cfg->n_displays ? b->cfg->displays[d] : hmd_builtin_at(d)->name;
        static const char *const terms[] = {"full", "novel", "noecc", "acuity"};
        for (int t = 0; t < 4; ++t) {
            struct bch_run *r = add(b, 3, "field", "reddy");
            if (!r)
                return;
            snprintf(r->display, sizeof r->display, "%s", name);
            r->velocity_off = t == 1;
            r->eccentricity_off = t == 2;
            if (t == 3) /* both terms, Reddy's full-contrast criterion: what contrast adds */
                snprintf(r->visibility, sizeof r->visibility, "acuity");
            r->frames = b->cfg->t3d_frames;
            snprintf(r->id, sizeof r->id, "t3d-%s-%s", name, terms[t]);
        }
    }
    /* Each criterion under each gaze model with --reference, on the largest field: what it keeps and
     * what the image loses, by eccentricity band and by head speed (Table 3e). */
    static const char *const criteria[] = {"contrast", "acuity"}, *const t3v_gazes[] = {"vor", "head"};
    for (int g = 0; g < 2; ++g)
        for (int k = 0; k < 2; ++k) {
            struct bch_run *r = add(b, 3, "field", "reddy");
            if (!r)
                return;
            snprintf(r->gaze, sizeof r->gaze, "%s", t3v_gazes[g]);
            snprintf(r->visibility, sizeof r->visibility, "%s", criteria[k]);
            r->objects = b->cfg->objects[b->cfg->n_objects - 1];
            r->reference_every = b->cfg->reference_every;
            r->frames = b->cfg->t3_frames;
            snprintf(r->id, sizeof r->id, "t3v-%s-%s", t3v_gazes[g], criteria[k]);
        }
    static const char *const readings[] = {"narrow", "long"};
    for (int k = 0; k < 2; ++k) {
        struct bch_run *r = add(b, 3, "field", "reddy");
        if (!r)
            return;
        snprintf(r->reading, sizeof r->reading, "%s", readings[k]);
        r->reference_every = b->cfg->reference_every;
        r->frames = b->cfg->t3_frames;
        snprintf(r->id, sizeof r->id, "t3r-%s", readings[k]);
    }
}

/* Nirenstein et al.: fs's time against the budget, with and without the time limit, on field with
 * the largest object count (frames are binned by head speed when the report is made); mb with 0, 1
 * and 2 hierarchy simplifications. */
static void plan_t4(struct builder *b)
{
    for (int k = 0; k < b->cfg->n_t4; ++k)
        for (int lim = 0; lim < 2; ++lim) {
            struct bch_run *r = add(b, 4, "field", "fs");
            if (!r)
                return;
            r->objects = b->cfg->objects[b->cfg->n_objects - 1];
            r->factor = b->cfg->t4_budgets[k];
            r->budget_ms = r->factor * vive_period_ms();
            r->opt_limit_us = lim ? T4_LIMIT_US : 0.0;
            snprintf(r->id, sizeof r->id, "t4-b%g-%s", r->factor, lim ? "lim100" : "nolim");
        }
    /* Nirenstein et al. 2002 §5.6: mb's tree simplified 0, 1 and 2 times, on domes (whose groups give
     * it a hierarchy), with its image error. */
    for (int k = 0; k <= 2; ++k) {
        struct bch_run *r = add(b, 4, "domes", "mb");
        if (!r)
            return;
        r->mb_simplify = k;
        r->reference_every = b->cfg->reference_every;
        snprintf(r->id, sizeof r->id, "t4s-mb-simplify%d", k);
    }
}

/* Mason & Blake: mb (hierarchical) against fs (flat) on domes at fractions of the full cost. */
static void plan_t5(struct builder *b)
{
    static const char *const sels[] = {"mb", "fs"};
    for (int k = 0; k < b->cfg->n_t5; ++k)
        for (int s = 0; s < 2; ++s) {
            struct bch_run *r = add(b, 5, "domes", sels[s]);
            if (!r)
                return;
            r->factor = b->cfg->t5_factors[k];
            r->budget_ms = r->factor * b->plan->domes_full_ms;
            r->reference_every = b->cfg->reference_every;
            snprintf(r->id, sizeof r->id, "t5-%s-x%g", sels[s], r->factor);
        }
}

int bch_plan_make(enum bch_mode mode, const char *only, const char *shared, const char *out_dir,
                        double domes_full_ms, struct bch_plan *plan, struct hl_error *err)
{
    memset(plan, 0, sizeof *plan);
    if (!(domes_full_ms > 0.0 && isfinite(domes_full_ms)))
        return hl_fail(err, "bench plan: the full-detail cost of domes (%g ms) is not a positive number",
                       domes_full_ms);
    plan->mode = mode;
    plan->domes_full_ms = domes_full_ms;
    plan->repeats = 1;
    snprintf(plan->only, sizeof plan->only, "%s", only ? only : "");
    snprintf(plan->shared, sizeof plan->shared, "%s", shared);
    snprintf(plan->out_dir, sizeof plan->out_dir, "%s", out_dir);
    snprintf(plan->still_trace, sizeof plan->still_trace, "%s/still-head.csv", out_dir);
    for (int u = 0; u < 3; ++u)
        snprintf(plan->traces[u], sizeof plan->traces[u], "%s/" CORBILLON_DIR "/user%d_quaternion.txt", shared, u + 1);
    snprintf(plan->gaze_trace, sizeof plan->gaze_trace, "%s/" EDVAM_TRACE, shared);
    if (access(plan->gaze_trace, R_OK) != 0)
        plan->gaze_trace[0] = '\0';
    struct builder b = {plan, &mode_cfgs[mode], 0, 0};
    plan_t1(&b);
    plan_t2(&b);
    plan_t3(&b);
    plan_t4(&b);
    plan_t5(&b);
    if (b.failed) {
        bch_plan_free(plan);
        return hl_fail(err, "bench plan: out of memory");
    }
    if (plan->only[0]) { /* keep the runs whose id matches the glob */
        size_t kept = 0;
        for (size_t i = 0; i < plan->count; ++i)
            if (fnmatch(plan->only, plan->runs[i].id, 0) == 0)
                plan->runs[kept++] = plan->runs[i];
        plan->count = kept;
        if (kept == 0) {
            bch_plan_free(plan);
            return hl_fail(err, "bench plan: --only '%s' matches no run id (ids look like t1-field-user1-fs)", only);
        }
    }
    return 0;
}

void bch_plan_free(struct bch_plan *plan)
{
    free(plan->runs);
    plan->runs = NULL;
    plan->count = 0;
}

static const char *num(char storage[][BCH_ARG_SIZE], int *used, double v)
{
    snprintf(storage[*used], BCH_ARG_SIZE, "%.17g", v);
    /* %.17g round-trips; shorten when a shorter form reads back the same (whole numbers as such:
     * replay's integer options take no exponent) */
    if (v == floor(v) && fabs(v) < 1e15)
        snprintf(storage[*used], BCH_ARG_SIZE, "%.0f", v);
    else
        for (int digits = 1; digits < 17; ++digits) {
            char shorter[BCH_ARG_SIZE];
            snprintf(shorter, sizeof shorter, "%.*g", digits, v);
            if (strtod(shorter, NULL) == v) {
                snprintf(storage[*used], BCH_ARG_SIZE, "%s", shorter);
                break;
            }
        }
    return storage[(*used)++];
}

int bch_run_argv(const struct bch_plan *plan, const struct bch_run *run, const char *out_dir,
                       char storage[][BCH_ARG_SIZE], const char **argv, int max)
{
    int argc = 0, used = 0;
#define ARG(s)                                                                                                         \
    do {                                                                                                               \
        if (argc < max - 1)                                                                                            \
            argv[argc++] = (s);                                                                                        \
    } while (0)
    ARG("replay");
    ARG("--trace");
    if (!strcmp(run->motion, "still")) {
        ARG(plan->still_trace);
    } else if (!strcmp(run->motion, "edvam-p2")) {
        ARG(plan->gaze_trace);
    } else {
        int u = run->motion[4] - '1';
        ARG(plan->traces[u < 0 || u > 2 ? 0 : u]);
    }
    ARG("--scene");
    ARG(run->scene);
    ARG("--display");
    ARG(run->display);
    ARG("--selector");
    ARG(run->selector);
    ARG("--frames");
    ARG(num(storage, &used, (double)run->frames));
    ARG("--render-scale");
    ARG(num(storage, &used, run->render_scale));
    if (run->gaze[0]) {
        ARG("--gaze");
        ARG(run->gaze);
    }
    if (run->reading[0]) {
        ARG("--frequency-reading");
        ARG(run->reading);
    }
    if (run->visibility[0]) {
        ARG("--visibility");
        ARG(run->visibility);
    }
    if (run->foveation[0]) {
        ARG("--foveation");
        ARG(run->foveation);
    }
    if (run->objects > 0) {
        ARG("--objects");
        ARG(num(storage, &used, run->objects));
    }
    if (run->budget_ms > 0.0) {
        ARG("--budget-ms");
        ARG(num(storage, &used, run->budget_ms));
    }
    if (run->opt_limit_us > 0.0) {
        ARG("--opt-limit-us");
        ARG(num(storage, &used, run->opt_limit_us));
    }
    if (run->static_px > 0.0) {
        ARG("--static-px");
        ARG(num(storage, &used, run->static_px));
    }
    if (run->velocity_off) {
        ARG("--velocity-term");
        ARG("off");
    }
    if (run->eccentricity_off) {
        ARG("--eccentricity-term");
        ARG("off");
    }
    if (run->mb_simplify > 0) {
        ARG("--mb-simplify");
        ARG(num(storage, &used, run->mb_simplify));
    }
    if (run->reference_every > 0) {
        ARG("--reference");
        ARG(num(storage, &used, (double)run->reference_every));
    }
    if (out_dir) {
        ARG("--out");
        ARG(out_dir);
    }
    ARG("--quiet");
#undef ARG
    argv[argc] = NULL;
    return argc;
}

/* POSIX shell single quoting: ' becomes '\''. */
static void put_quoted(FILE *f, const char *s)
{
    if (s[0] && strspn(s, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-./=+,:@") == strlen(s)) {
        fputs(s, f);
        return;
    }
    fputc('\'', f);
    for (; *s; ++s)
        if (*s == '\'')
            fputs("'\\''", f);
        else
            fputc(*s, f);
    fputc('\'', f);
}

int bch_plan_rounds(const struct bch_plan *plan)
{
    return plan->repeats < 1 ? 1 : plan->repeats > BCH_SUITE_MAX_REPEATS ? BCH_SUITE_MAX_REPEATS : plan->repeats;
}

void bch_runs_dir(const char *out_dir, int repeat, char *buf, size_t size)
{
    if (repeat <= 0)
        snprintf(buf, size, "%s/runs", out_dir);
    else
        snprintf(buf, size, "%s/runs-%d", out_dir, repeat + 1);
}

void bch_run_dir(const char *out_dir, const char *id, int repeat, char *buf, size_t size)
{
    char runs[4300];
    bch_runs_dir(out_dir, repeat, runs, sizeof runs);
    snprintf(buf, size, "%s/%s", runs, id);
}

size_t bch_plan_step(const struct bch_plan *plan, size_t step, int *repeat)
{
    size_t rounds = (size_t)bch_plan_rounds(plan);
    /* Blocks: runs in a row that serve one table. Each block runs all its rounds before the next. */
    for (size_t first = 0; first < plan->count;) {
        size_t n = 1;
        while (first + n < plan->count && plan->runs[first + n].table == plan->runs[first].table)
            ++n;
        if (step < n * rounds) {
            *repeat = (int)(step / n);
            return first + (size_t)bch_alternate_index(*repeat, (int)(step % n), (int)n);
        }
        step -= n * rounds;
        first += n;
    }
    *repeat = 0;
    return plan->count; /* past the end */
}

void bch_run_line(const struct bch_plan *plan, const struct bch_run *run, int repeat, const char *exe,
                        const char *out_dir, FILE *f)
{
    char dir[4400];
    bch_run_dir(out_dir, run->id, repeat, dir, sizeof dir);
    char storage[BCH_MAX_ARGS][BCH_ARG_SIZE];
    const char *argv[BCH_MAX_ARGS];
    int argc = bch_run_argv(plan, run, dir, storage, argv, BCH_MAX_ARGS);
    put_quoted(f, exe);
    for (int i = 0; i < argc; ++i) {
        fputc(' ', f);
        put_quoted(f, argv[i]);
    }
}

int bch_plan_write(const struct bch_plan *plan, const char *exe, const char *out_dir, const char *path,
                         struct hl_error *err)
{
    struct hl_out out;
    if (hl_out_open(&out, path, err) != 0)
        return -1;
    FILE *f = out.f;
    size_t steps = plan->count * (size_t)bch_plan_rounds(plan);
    for (size_t s = 0; s < steps; ++s) {
        int repeat = 0;
        size_t i = bch_plan_step(plan, s, &repeat);
        bch_run_line(plan, &plan->runs[i], repeat, exe, out_dir, f);
        fputc('\n', f);
    }
    return hl_out_commit(&out, err);
}
