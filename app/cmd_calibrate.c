/* hmdlod calibrate: measure this machine's rendering cost, fit Funkhouser & Séquin's max form and
 * the additive form (non-negative, on 75 % of the grid points), judge both on the held-out 25 %,
 * keep the one with the lower held-out p95 relative error and write the cost profile JSON.
 * Argument parsing and messages only: measuring and fitting live in render/ (render/cost.h). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "bench/bench.h"
#include "app/commands.h"
#include "replay/replay.h"

static const char usage[] =
    "usage: hmdlod calibrate --out FILE [--quick] [--seed N] [--render-scale S] [--display NAME] [--no-layers]\n\n"
    "Renders copies of the field's sphere and the auditorium's chair in stereo over a grid of LOD x screen\n"
    "coverage x object count (after a warm-up), times each frame (median of repeats), fits both cost\n"
    "forms with non-negative coefficients on a random 75 % of the grid points and measures them on the\n"
    "other 25 %, keeps the form with the lower held-out 95th-percentile relative error and writes the\n"
    "machine cost profile (docs/cost-model.md). The same grid is then drawn as the foveated periphery\n"
    "at each layer scale (0.75, 0.5, 0.35, 0.25) and fitted again: the periphery's own models, with its\n"
    "composite timed (the compositor's work, reported); and once more as the foveal inset alone (5\n"
    "degrees and its 5-degree blend band around the lens centre, full resolution under its scissor,\n"
    "pixels counted within it): the inset's model, its triangles inside and outside the scissor.\n"
    "  --out FILE        the cost profile JSON to write (atomically)\n"
    "  --quick           a small grid (24 points, 3 repeats): seconds, for tests\n"
    "  --seed N          the split and visiting order (default 1)\n"
    "  --render-scale S  per-eye resolution factor in (0, 4] (default 1: the display's pixels)\n"
    "  --display NAME    built-in display or profile JSON (default vive)\n"
    "  --no-layers       the plain frames only (a profile without periphery or inset models)\n"
    "  --csv FILE        also write every grid point (counts, measured and predicted ms) as CSV\n";

struct calibrate_args {
    const char *out, *display, *csv;
    long seed;
    double render_scale;
    int quick, layers;
};

static int parse_args(int argc, char **argv, struct calibrate_args *a)
{
    *a = (struct calibrate_args){NULL, "vive", NULL, 1, 1.0, 0, 1};
    for (int i = 1; i < argc; ++i) {
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--quick")) {
            a->quick = 1;
            continue;
        }
        if (!strcmp(argv[i], "--no-layers")) {
            a->layers = 0;
            continue;
        }
        if (!strcmp(argv[i], "--out") || !strcmp(argv[i], "--display") || !strcmp(argv[i], "--csv")) {
            if (!val) {
                fprintf(stderr, "hmdlod: %s needs a value\n", argv[i]);
                return -1;
            }
            *(!strcmp(argv[i], "--out") ? &a->out : !strcmp(argv[i], "--csv") ? &a->csv : &a->display) = val;
        } else if (!strcmp(argv[i], "--seed")) {
            if (app_parse_long("--seed", val, 0, 2147483647L, &a->seed) != 0)
                return -1;
        } else if (!strcmp(argv[i], "--render-scale")) {
            if (app_parse_double("--render-scale", val, &a->render_scale) != 0)
                return -1;
            if (!(a->render_scale > 0.0 && a->render_scale <= 4.0)) {
                fprintf(stderr, "hmdlod: --render-scale: %g is outside (0, 4]\n", a->render_scale);
                return -1;
            }
        } else {
            fprintf(stderr, "hmdlod calibrate: unknown option '%s' (try --help)\n", argv[i]);
            return -1;
        }
        ++i;
    }
    if (!a->out) {
        fprintf(stderr, "hmdlod calibrate: --out FILE is required (try --help)\n");
        return -1;
    }
    return 0;
}

/* Before seconds of rendering: can the profile be written at all? (The same temporary beside it that
 * the writer creates, through hl_out, given back at once: nothing is left behind.) */
static int check_writable(const char *path)
{
    struct hl_out o;
    struct hl_error err;
    if (hl_out_open(&o, path, &err) != 0) {
        fprintf(stderr, "hmdlod calibrate: %s\n", err.msg);
        return -1;
    }
    hl_out_abort(&o);
    return 0;
}

/* One grid measured and fitted: both forms on the training points with c0 measured (the expectile
 * chosen as below), the ordinary intercept fits beside them, held-out accuracy, the form kept. */
struct calibration_fit {
    double periphery_scale, inset_radius_deg;
    struct frm_inset_cost inset;          /* an inset grid's own model (frm_cost_fit_inset) */
    struct frm_cost_fit_report inset_report;
    struct frm_cost_accuracy inset_acc;
    double inset_tau;
    struct rnd_calibration cal;
    uint32_t *order;
    size_t train;
    struct lod_cost_model fits[2], free_fits[2];
    struct frm_cost_fit_report reports[2], free_reports[2];
    struct frm_cost_accuracy acc[2], free_acc[2];
    double tau[2];
    int keep;
};

static void calibration_fit_free(struct calibration_fit *c)
{
    free(c->order);
    rnd_calibration_free(&c->cal);
    memset(c, 0, sizeof *c);
}

static void print_fit(const char *name, const struct lod_cost_model *m, const struct frm_cost_fit_report *fit,
                      const struct frm_cost_accuracy *acc)
{
    printf("  %-8s  %7.3f  %10.5f  %10.5f  %9.4f  %9.3f  %9.4f   %6.1f %%   %6.1f %%  %6.1f %%  %6.1f %%\n", name,
           m->c0_ms, m->c1_ms_per_triangle * 1e3, m->c2_ms_per_vertex * 1e3, m->c3_ms_per_pixel * 1e6,
           m->c4_ms_per_draw * 1e3, m->c5_ms_per_edge_px * 1e6, 100.0 * fit->rms_relative, 100.0 * acc->median_rel,
           100.0 * acc->p95_rel, 100.0 * acc->under5_share);
}

/* One row per grid point of every measured grid (the plain frames, each periphery scale, the inset):
 * its sums over objects, the measured median and both fits' predictions. */
static int write_csv(const char *path, const struct calibration_fit *fits, int count)
{
    struct hl_out out;
    struct hl_error err;
    if (hl_out_open(&out, path, &err) != 0) {
        fprintf(stderr, "hmdlod calibrate: %s\n", err.msg);
        return -1;
    }
    FILE *f = out.f;
    fprintf(f, "periphery_scale,point,objects,triangles,vertices,pixels_px,draws,measured_ms,predicted_max_ms,"
               "predicted_additive_ms,held_out,inset_radius_deg,triangles_inside,predicted_inset_ms\n");
    for (int i = 0; i < count; ++i) {
        const struct calibration_fit *c = &fits[i];
        for (size_t n = 0; n < c->cal.frame_count; ++n) {
            const struct rnd_cost_frame *fr = &c->cal.frames[c->order[n]];
            double t = 0, v = 0, p = 0, d = 0, inside = 0;
            for (uint32_t k = 0; k < fr->object_count; ++k) {
                const struct rnd_cost_object *o = &c->cal.objects[fr->first_object + k];
                t += o->triangles, v += o->vertices, p += o->pixels_px, d += o->draws;
                inside += o->inside_share * o->triangles;
            }
            int inset = c->inset_radius_deg > 0.0;
            fprintf(f, "%g,%u,%u,%.0f,%.0f,%.0f,%.0f,%.4f,%.4f,%.4f,%d,%g,%.0f,%.4f\n", c->periphery_scale, c->order[n],
                    fr->object_count, t, v, p, d, fr->measured_ms, frm_cost_predict_frame_ms(&c->fits[0], fr, c->cal.objects),
                    frm_cost_predict_frame_ms(&c->fits[1], fr, c->cal.objects), n >= c->train, c->inset_radius_deg,
                    inside, inset ? frm_cost_predict_inset_frame_ms(&c->inset, fr, c->cal.objects) : 0.0);
        }
    }
    if (hl_out_commit(&out, &err) != 0) {
        fprintf(stderr, "hmdlod calibrate: %s\n", err.msg);
        return -1;
    }
    return 0;
}

/* The 1-minute load average (/proc/loadavg), or −1: other work on the CPUs is in every frame time
 * measured, so the profile says how busy the machine was. */
static double load_average(void)
{
    double load = -1;
    FILE *f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%lf", &load) != 1)
            load = -1;
        fclose(f);
    }
    return load;
}

static const enum lod_cost_form calibrate_forms[2] = {LOD_COST_MAX, LOD_COST_ADDITIVE};
static const double expectiles[] = {0.5, 0.75, 0.9, 0.95, 0.98};

/* An inset grid's own model, with the expectile chosen as for the forms. 0 or −1 (printed). */
static int fit_inset(struct calibration_fit *c)
{
    struct hl_error err = {{0}};
    for (size_t t = 0; t < sizeof expectiles / sizeof *expectiles; ++t) {
        c->inset_tau = expectiles[t];
        if (frm_cost_fit_inset(c->cal.empty_ms, c->inset_tau, c->cal.frames, c->order, c->train, c->cal.objects,
                               &c->inset, &c->inset_report, &err) != 0) {
            fprintf(stderr, "hmdlod calibrate: fitting the inset's model: %s\n", err.msg);
            return -1;
        }
        if (frm_cost_evaluate_inset(&c->inset, c->cal.frames, c->order, c->train, c->cal.objects).under5_share <= 0.05)
            break;
    }
    c->inset_acc = frm_cost_evaluate_inset(&c->inset, c->cal.frames, c->order + c->train,
                                           c->cal.frame_count - c->train, c->cal.objects);
    return 0;
}

/* Measures grid g (its periphery_scale and inset_radius_deg say plain frames, a periphery or the
 * inset) and fits it. 0 or −1 (the message printed). */
static int measure_and_fit(const struct hmd_profile *display, struct rnd_cost_grid *g, long seed,
                           struct calibration_fit *c)
{
    memset(c, 0, sizeof *c);
    c->periphery_scale = g->periphery_scale;
    c->inset_radius_deg = g->inset_radius_deg;
    struct hl_error err = {{0}};
    if (frm_cost_calibrate(display, g, (uint64_t)seed, &c->cal, &err) != 0) {
        fprintf(stderr, "hmdlod calibrate: %s\n", err.msg);
        return -1;
    }
    c->order = malloc(c->cal.frame_count * sizeof *c->order);
    if (!c->order) {
        fprintf(stderr, "hmdlod calibrate: out of memory\n");
        return -1;
    }
    rnd_cost_split(c->cal.frame_count, (uint64_t)seed, c->order, &c->train);
    size_t held = c->cal.frame_count - c->train;
    for (int f = 0; f < 2; ++f) {
        /* Kept: c0 as measured and the smallest expectile whose fit under-predicts at most 5 % of the
         * training points by more than 5 % — under-prediction is what breaks a budget, and the goal
         * for held-out points is 10 %. The intercept fit is printed beside it as the old reference. */
        int rc = 0;
        for (size_t t = 0; t < sizeof expectiles / sizeof *expectiles && rc == 0; ++t) {
            c->tau[f] = expectiles[t];
            if (frm_cost_fit_fixed(calibrate_forms[f], c->cal.empty_ms, c->tau[f], c->cal.frames, c->order, c->train,
                                   c->cal.objects, &c->fits[f], &c->reports[f], &err) != 0)
                rc = -1;
            else if (frm_cost_evaluate(&c->fits[f], c->cal.frames, c->order, c->train, c->cal.objects).under5_share <= 0.05)
                break;
        }
        if (rc == 0 && frm_cost_fit(calibrate_forms[f], c->cal.frames, c->order, c->train, c->cal.objects,
                                    &c->free_fits[f], &c->free_reports[f], &err) != 0)
            rc = -1;
        if (rc != 0) {
            fprintf(stderr, "hmdlod calibrate: fitting the %s form: %s\n", frm_cost_form_name(calibrate_forms[f]),
                    err.msg);
            return -1;
        }
        c->acc[f] = frm_cost_evaluate(&c->fits[f], c->cal.frames, c->order + c->train, held, c->cal.objects);
        c->free_acc[f] = frm_cost_evaluate(&c->free_fits[f], c->cal.frames, c->order + c->train, held, c->cal.objects);
    }
    c->keep = c->acc[1].p95_rel < c->acc[0].p95_rel ? 1 : 0; /* a tie keeps Funkhouser's max */
    return g->inset_radius_deg > 0.0 ? fit_inset(c) : 0;
}

static void print_header(void)
{
    printf("  form        c0 ms   c1 us/tri  c2 us/vert   c3 ns/px  c4 us/draw  c5 ns/edge  train rms  held-out"
           " median    p95  under >5 %%\n");
}

/* The plain frames' fits in full: both forms, the expectiles, the intercept fits, what was kept. */
static void print_plain(const struct calibration_fit *c, long seed)
{
    printf("fitted on %zu points, held out %zu (seed %ld); relative errors |predicted - measured| / measured\n",
           c->train, c->cal.frame_count - c->train, seed);
    print_header();
    for (int f = 0; f < 2; ++f)
        print_fit(frm_cost_form_name(calibrate_forms[f]), &c->fits[f], &c->reports[f], &c->acc[f]);
    printf("  (c0 measured; expectile %.2f for max, %.2f for additive: the least that under-predicts at most\n"
           "  5 %% of the training points by more than 5 %%)\n", c->tau[0], c->tau[1]);
    printf("  ordinary fit with c0 fitted as an intercept (not kept):\n");
    for (int f = 0; f < 2; ++f)
        print_fit(frm_cost_form_name(calibrate_forms[f]), &c->free_fits[f], &c->free_reports[f], &c->free_acc[f]);
    printf("kept: %s (held-out p95 %.1f %% against %.1f %%)\n", frm_cost_form_name(calibrate_forms[c->keep]),
           100.0 * c->acc[c->keep].p95_rel, 100.0 * c->acc[!c->keep].p95_rel);
}

int cmd_calibrate(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(usage, stdout);
        return 0;
    }
    struct calibrate_args a;
    if (parse_args(argc, argv, &a) != 0 || check_writable(a.out) != 0)
        return 1;
    struct hl_error err = {{0}};
    struct hmd_profile display;
    if (hmd_profile_load(a.display, &display, &err) != 0) {
        fprintf(stderr, "hmdlod calibrate: %s\n", err.msg);
        return 1;
    }
    struct frm_cost_profile prof;
    memset(&prof, 0, sizeof prof);
    struct rnd_cost_grid *g = &prof.grid;
    rnd_cost_grid_default(g, a.quick);
    g->render_scale = a.render_scale;
    /* The plain frames first, then (unless --no-layers) each periphery scale of the foveated layers
     * (frame/layers.h), the same grid drawn as that periphery over the whole eye, then the inset alone
     * at the fovea's radius (what fs gives it, FRM_LAYER_FOVEA_DEG) around the lens centre. */
    struct calibration_fit fits[1 + FRM_COST_PERIPHERY_MAX + 1];
    memset(fits, 0, sizeof fits);
    int measured = 0, rc = 0;
    prof.load_before = load_average();
    for (int i = 0; i < (a.layers ? FRM_LAYER_SCALES + 1 : 1) && rc == 0; ++i) {
        struct rnd_cost_grid grid = *g;
        grid.periphery_scale = i < FRM_LAYER_SCALES ? frm_layer_scales[i] : 1.0;
        if (i == FRM_LAYER_SCALES)
            grid.inset_radius_deg = FRM_LAYER_FOVEA_DEG, grid.inset_blend_deg = FRM_LAYER_BLEND_DEG_DEFAULT;
        if (measure_and_fit(&display, &grid, a.seed, &fits[measured++]) != 0)
            rc = 1;
        else if (i == 0)
            *g = grid; /* eye size and display filled in */
    }
    prof.load_after = load_average();
    if (rc != 0)
        goto done;
    const struct calibration_fit *plain = &fits[0];
    double seconds = 0.0;
    for (int i = 0; i < measured; ++i)
        seconds += fits[i].cal.seconds;
    printf("calibrate: %zu grid points (%d objects x %d levels x %d coverages x %d counts, median of %d) on %s,\n"
           "  display %s at %d x %d per eye%s, measured in %.1f s\n",
           plain->cal.frame_count, g->families, g->levels, g->coverages, g->counts, g->repeats, plain->cal.renderer,
           display.name, g->eye_width_px, g->eye_height_px,
           measured > 1 ? ", plain, as the periphery at each layer scale and as the inset" : "", seconds);
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    if (prof.load_before >= 0)
        printf("  machine load (1-min average) %.2f before, %.2f after, on %ld cores%s\n", prof.load_before,
               prof.load_after, cores,
               prof.load_after > 0.5 * (double)cores || prof.load_before > 0.5 * (double)cores
                   ? ": other work shared the CPUs, and its time is in every frame measured"
                   : "");
    printf("fixed cost: %u empty frames (clear both eyes, glFinish) among the points: median %.3f ms "
           "(quartiles %.3f … %.3f)\n",
           plain->cal.empty_frames, plain->cal.empty_ms, plain->cal.empty_p25_ms, plain->cal.empty_p75_ms);
    print_plain(plain, a.seed);
    if (measured > 1) {
        /* Each periphery's kept form; its c0 is its own empty frame (the layer's clear, not the eye's). */
        printf("periphery layers (inset radius 0, pixels at the periphery's resolution; held out as above):\n");
        print_header();
        for (int i = 1; i < measured - 1; ++i) {
            const struct calibration_fit *c = &fits[i];
            char name[32];
            snprintf(name, sizeof name, "s %.2f %c", c->periphery_scale, calibrate_forms[c->keep] == LOD_COST_MAX ? 'M' : 'A');
            print_fit(name, &c->fits[c->keep], &c->reports[c->keep], &c->acc[c->keep]);
            struct frm_cost_periphery *p = &prof.periphery[prof.periphery_count++];
            p->scale = c->periphery_scale;
            p->model = c->fits[c->keep];
            p->held_out = c->acc[c->keep];
            p->fixed = (struct frm_cost_fixed){c->cal.empty_ms, c->cal.empty_p25_ms, c->cal.empty_p75_ms,
                                               c->cal.empty_frames};
            p->composite_ms = c->cal.composite_ms;
        }
        printf("  composite (the compositor's, not in the frame time; the periphery over both whole eyes, median of %u):",
               fits[1].cal.composite_frames);
        for (int i = 1; i < measured - 1; ++i)
            printf("%s s %.2f %.3f ms", i > 1 ? "," : "", fits[i].periphery_scale, fits[i].cal.composite_ms);
        printf("\n");
        printf("  (M: the max form kept, A: the additive; c0 the periphery's empty frame, median of %u … %u)\n",
               fits[1].cal.empty_frames, fits[measured - 2].cal.empty_frames);
        /* The inset: its own model, and the plain frame's on the same frames (how a replay priced
         * the inset before it had one, every triangle a plain frame's). */
        const struct calibration_fit *c = &fits[measured - 1];
        size_t held = c->cal.frame_count - c->train;
        struct frm_cost_accuracy as_plain = frm_cost_evaluate(&plain->fits[plain->keep], c->cal.frames,
                                                              c->order + c->train, held, c->cal.objects);
        double ratio = 0.0;
        for (size_t n = c->train; n < c->cal.frame_count; ++n) {
            const struct rnd_cost_frame *fr = &c->cal.frames[c->order[n]];
            ratio += fr->measured_ms / frm_cost_predict_frame_ms(&plain->fits[plain->keep], fr, c->cal.objects);
        }
        printf("inset layer alone (%.0f degrees + %.0f blend around the lens centre, full resolution under its "
               "scissor; pixels within its rectangle; c1 a triangle inside it):\n",
               c->inset_radius_deg, (double)FRM_LAYER_BLEND_DEG_DEFAULT);
        print_header();
        print_fit("inset", &c->inset.model, &c->inset_report, &c->inset_acc);
        printf("  a triangle outside the scissor: %.1f ns (inside: %.1f ns + its vertices); expectile %.2f\n",
               c->inset.outside_ms_per_triangle * 1e6, c->inset.model.c1_ms_per_triangle * 1e6, c->inset_tau);
        printf("  the plain frame's model on these frames, every triangle a plain frame's: held-out median %.1f %%, "
               "p95 %.1f %%, measured / predicted %.2f on average\n",
               100.0 * as_plain.median_rel, 100.0 * as_plain.p95_rel, held ? ratio / (double)held : 0.0);
        prof.inset_measured = 1;
        prof.inset = (struct frm_cost_inset){c->inset_radius_deg, FRM_LAYER_BLEND_DEG_DEFAULT, c->inset,
                                             c->inset_acc,
                                             {c->cal.empty_ms, c->cal.empty_p25_ms, c->cal.empty_p75_ms,
                                              c->cal.empty_frames}};
    }
    if (a.csv && write_csv(a.csv, fits, measured) != 0) {
        rc = 1;
        goto done;
    }
    prof.model = plain->fits[plain->keep];
    prof.fixed = (struct frm_cost_fixed){plain->cal.empty_ms, plain->cal.empty_p25_ms, plain->cal.empty_p75_ms,
                                         plain->cal.empty_frames};
    prof.held_out = plain->acc[plain->keep];
    prof.held_out_other = plain->acc[!plain->keep];
    time_t now = time(NULL);
    struct tm tm_utc;
    gmtime_r(&now, &tm_utc);
    strftime(prof.date, sizeof prof.date, "%Y-%m-%d %H:%M UTC", &tm_utc);
    bch_commit(prof.commit, sizeof prof.commit);
    snprintf(prof.label, sizeof prof.label, "hmdlod calibrate%s, seed %ld, c0 measured, expectile %.2f",
             a.quick ? " --quick" : "", a.seed, plain->tau[plain->keep]);
    snprintf(prof.renderer, sizeof prof.renderer, "%s", plain->cal.renderer);
    snprintf(prof.display, sizeof prof.display, "%s", display.name);
    prof.eye_width_px = g->eye_width_px, prof.eye_height_px = g->eye_height_px;
    if (frm_cost_profile_write(a.out, &prof, &err) != 0) {
        fprintf(stderr, "hmdlod calibrate: %s\n", err.msg);
        rc = 1;
    } else {
        printf("wrote %s\n", a.out);
    }
done:
    for (int i = 0; i < measured; ++i)
        calibration_fit_free(&fits[i]);
    return rc;
}
