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
    "usage: hmdlod calibrate --out FILE [--quick] [--seed N] [--render-scale S] [--display NAME]\n\n"
    "Renders copies of the field's sphere and the auditorium's chair in stereo over a grid of LOD x screen\n"
    "coverage x object count (after a warm-up), times each frame (median of repeats), fits both cost\n"
    "forms with non-negative coefficients on a random 75 % of the grid points and measures them on the\n"
    "other 25 %, keeps the form with the lower held-out 95th-percentile relative error and writes the\n"
    "machine cost profile (docs/cost-model.md).\n"
    "  --out FILE        the cost profile JSON to write (atomically)\n"
    "  --quick           a small grid (24 points, 3 repeats): seconds, for tests\n"
    "  --seed N          the split and visiting order (default 1)\n"
    "  --render-scale S  per-eye resolution factor in (0, 4] (default 1: the display's pixels)\n"
    "  --display NAME    built-in display or profile JSON (default vive)\n"
    "  --csv FILE        also write every grid point (counts, measured and predicted ms) as CSV\n";

struct calibrate_args {
    const char *out, *display, *csv;
    long seed;
    double render_scale;
    int quick;
};

static int parse_args(int argc, char **argv, struct calibrate_args *a)
{
    *a = (struct calibrate_args){NULL, "vive", NULL, 1, 1.0, 0};
    for (int i = 1; i < argc; ++i) {
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--quick")) {
            a->quick = 1;
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

static void print_fit(const char *name, const struct lod_cost_model *m, const struct frm_cost_fit_report *fit,
                      const struct frm_cost_accuracy *acc)
{
    printf("  %-8s  %7.3f  %10.5f  %10.5f  %9.4f  %9.3f  %9.4f   %6.1f %%   %6.1f %%  %6.1f %%  %6.1f %%\n", name,
           m->c0_ms, m->c1_ms_per_triangle * 1e3, m->c2_ms_per_vertex * 1e3, m->c3_ms_per_pixel * 1e6,
           m->c4_ms_per_draw * 1e3, m->c5_ms_per_edge_px * 1e6, 100.0 * fit->rms_relative, 100.0 * acc->median_rel,
           100.0 * acc->p95_rel, 100.0 * acc->under5_share);
}

/* One row per grid point: its sums over objects, the measured median and both fits' predictions. */
static int write_csv(const char *path, const struct rnd_calibration *cal, const uint32_t *order, size_t train,
                     const struct lod_cost_model fits[2])
{
    struct hl_out out;
    struct hl_error err;
    if (hl_out_open(&out, path, &err) != 0) {
        fprintf(stderr, "hmdlod calibrate: %s\n", err.msg);
        return -1;
    }
    FILE *f = out.f;
    fprintf(f, "point,objects,triangles,vertices,pixels_px,draws,measured_ms,predicted_max_ms,predicted_additive_ms,"
               "held_out\n");
    for (size_t n = 0; n < cal->frame_count; ++n) {
        const struct rnd_cost_frame *fr = &cal->frames[order[n]];
        double t = 0, v = 0, p = 0, d = 0;
        for (uint32_t k = 0; k < fr->object_count; ++k) {
            const struct rnd_cost_object *o = &cal->objects[fr->first_object + k];
            t += o->triangles, v += o->vertices, p += o->pixels_px, d += o->draws;
        }
        fprintf(f, "%u,%u,%.0f,%.0f,%.0f,%.0f,%.4f,%.4f,%.4f,%d\n", order[n], fr->object_count, t, v, p, d,
                fr->measured_ms, frm_cost_predict_frame_ms(&fits[0], fr, cal->objects),
                frm_cost_predict_frame_ms(&fits[1], fr, cal->objects), n >= train);
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
    struct rnd_calibration cal;
    prof.load_before = load_average();
    if (frm_cost_calibrate(&display, g, (uint64_t)a.seed, &cal, &err) != 0) {
        fprintf(stderr, "hmdlod calibrate: %s\n", err.msg);
        return 1;
    }
    prof.load_after = load_average();
    printf("calibrate: %zu grid points (%d objects x %d levels x %d coverages x %d counts, median of %d) on %s,\n"
           "  display %s at %d x %d per eye, measured in %.1f s\n",
           cal.frame_count, g->families, g->levels, g->coverages, g->counts, g->repeats, cal.renderer, display.name,
           g->eye_width_px, g->eye_height_px, cal.seconds);
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    if (prof.load_before >= 0)
        printf("  machine load (1-min average) %.2f before, %.2f after, on %ld cores%s\n", prof.load_before,
               prof.load_after, cores,
               prof.load_after > 0.5 * (double)cores || prof.load_before > 0.5 * (double)cores
                   ? ": other work shared the CPUs, and its time is in every frame measured"
                   : "");

    uint32_t *order = malloc(cal.frame_count * sizeof *order);
    if (!order) {
        fprintf(stderr, "hmdlod calibrate: out of memory\n");
        rnd_calibration_free(&cal);
        return 1;
    }
    size_t train = 0;
    rnd_cost_split(cal.frame_count, (uint64_t)a.seed, order, &train);
    size_t held = cal.frame_count - train;
    struct lod_cost_model fits[2], free_fits[2];
    struct frm_cost_fit_report reports[2], free_reports[2];
    struct frm_cost_accuracy acc[2], free_acc[2];
    static const enum lod_cost_form forms[2] = {LOD_COST_MAX, LOD_COST_ADDITIVE};
    int rc = 0;
    printf("fixed cost: %u empty frames (clear both eyes, glFinish) among the points: median %.3f ms "
           "(quartiles %.3f … %.3f)\n",
           cal.empty_frames, cal.empty_ms, cal.empty_p25_ms, cal.empty_p75_ms);
    double tau[2] = {0.5, 0.5};
    for (int f = 0; f < 2 && rc == 0; ++f) {
        /* Kept: c0 as measured and the smallest expectile whose fit under-predicts at most 5 % of the
         * training points by more than 5 % — under-prediction is what breaks a budget, and the goal
         * for held-out points is 10 %. The intercept fit is printed beside it as the old reference. */
        static const double expectiles[] = {0.5, 0.75, 0.9, 0.95, 0.98};
        for (size_t t = 0; t < sizeof expectiles / sizeof *expectiles && rc == 0; ++t) {
            tau[f] = expectiles[t];
            if (frm_cost_fit_fixed(forms[f], cal.empty_ms, tau[f], cal.frames, order, train, cal.objects, &fits[f],
                                   &reports[f], &err) != 0)
                rc = 1;
            else if (frm_cost_evaluate(&fits[f], cal.frames, order, train, cal.objects).under5_share <= 0.05)
                break;
        }
        if (rc == 0 &&
            frm_cost_fit(forms[f], cal.frames, order, train, cal.objects, &free_fits[f], &free_reports[f], &err) != 0)
            rc = 1;
        if (rc != 0) {
            fprintf(stderr, "hmdlod calibrate: fitting the %s form: %s\n", frm_cost_form_name(forms[f]), err.msg);
            break;
        }
        acc[f] = frm_cost_evaluate(&fits[f], cal.frames, order + train, held, cal.objects);
        free_acc[f] = frm_cost_evaluate(&free_fits[f], cal.frames, order + train, held, cal.objects);
    }
    if (rc == 0) {
        printf("fitted on %zu points, held out %zu (seed %ld); relative errors |predicted - measured| / measured\n",
               train, held, a.seed);
        printf("  form        c0 ms   c1 us/tri  c2 us/vert   c3 ns/px  c4 us/draw  c5 ns/edge  train rms  held-out"
               " median    p95  under >5 %%\n");
        for (int f = 0; f < 2; ++f)
            print_fit(frm_cost_form_name(forms[f]), &fits[f], &reports[f], &acc[f]);
        printf("  (c0 measured; expectile %.2f for max, %.2f for additive: the least that under-predicts at most\n"
               "  5 %% of the training points by more than 5 %%)\n", tau[0], tau[1]);
        printf("  ordinary fit with c0 fitted as an intercept (not kept):\n");
        for (int f = 0; f < 2; ++f)
            print_fit(frm_cost_form_name(forms[f]), &free_fits[f], &free_reports[f], &free_acc[f]);
        if (a.csv && write_csv(a.csv, &cal, order, train, fits) != 0)
            rc = 1;
        int keep = acc[1].p95_rel < acc[0].p95_rel ? 1 : 0; /* a tie keeps Funkhouser's max */
        printf("kept: %s (held-out p95 %.1f %% against %.1f %%)\n", frm_cost_form_name(forms[keep]),
               100.0 * acc[keep].p95_rel, 100.0 * acc[!keep].p95_rel);
        prof.model = fits[keep];
        prof.fixed = (struct frm_cost_fixed){cal.empty_ms, cal.empty_p25_ms, cal.empty_p75_ms, cal.empty_frames};
        prof.held_out = acc[keep];
        prof.held_out_other = acc[!keep];
        time_t now = time(NULL);
        struct tm tm_utc;
        gmtime_r(&now, &tm_utc);
        strftime(prof.date, sizeof prof.date, "%Y-%m-%d %H:%M UTC", &tm_utc);
        bch_commit(prof.commit, sizeof prof.commit);
        snprintf(prof.label, sizeof prof.label, "hmdlod calibrate%s, seed %ld, c0 measured, expectile %.2f",
                 a.quick ? " --quick" : "", a.seed, tau[keep]);
        snprintf(prof.renderer, sizeof prof.renderer, "%s", cal.renderer);
        snprintf(prof.display, sizeof prof.display, "%s", display.name);
        prof.eye_width_px = g->eye_width_px, prof.eye_height_px = g->eye_height_px;
        if (frm_cost_profile_write(a.out, &prof, &err) != 0) {
            fprintf(stderr, "hmdlod calibrate: %s\n", err.msg);
            rc = 1;
        } else {
            printf("wrote %s\n", a.out);
        }
    }
    free(order);
    rnd_calibration_free(&cal);
    return rc;
}
