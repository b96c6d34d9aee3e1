/* Table 3 of the bench report: Reddy's study on field (Reddy 1997 §6; PAPERS.md) — the speedup of
 * reddy over none against the object count, size only against size + velocity + eccentricity, still
 * head and real motion per gaze model and visibility criterion; per display the share of the LOD
 * reduction owed to velocity, to eccentricity and to contrast; both frequency readings with their
 * image error; both criteria's image error by eccentricity band (3e) and triangles kept by
 * eccentricity and retinal speed (3f). docs/bench.md. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "hmd/hmd.h"
#include "bench/suite_internal.h"

#define GOAL_SPEEDUP 4.5 /* Reddy's figure: ≥ 4.5× at zero predicted visible error, field, 1000 objects */

/* 1 − triangles drawn / finest over the run: the LOD reduction. */
static double reduction(const struct bch_result *r)
{
    if (!r)
        return NAN;
    double t = bch_mean(r, r->triangles), f = bch_mean(r, r->finest);
    return f > 0 ? 1.0 - t / f : NAN;
}

static const char *const variants[][5] = {
    /* reddy's run, none's run, motion, terms, criterion (docs/visibility.md) */
    {"still-size", "still-none", "still", "size only", "contrast"},
    {"still-full", "still-none", "still", "size + velocity + eccentricity", "contrast"},
    {"real-size", "real-none", "user1", "size only", "contrast"},
    {"real-full-head", "real-none", "user1 (gaze head)", "size + velocity + eccentricity", "contrast"},
    {"real-full-vor", "real-none", "user1 (gaze vor)", "size + velocity + eccentricity", "contrast"},
    {"real-full-head-acuity", "real-none", "user1 (gaze head)", "size + velocity + eccentricity", "acuity"},
    {"real-full-vor-acuity", "real-none", "user1 (gaze vor)", "size + velocity + eccentricity", "acuity"},
};
enum { N_VARIANTS = 7 };

static int speedup_table(struct bch_ctx *c, struct hl_error *err)
{
    static const char *const h[] = {"objects",        "motion",         "terms",       "criterion",
                                    "none_frame_ms",  "reddy_frame_ms", "speedup",     "speedup_min",
                                    "speedup_max",    "*triangle_ratio", "*visible_error_mean", "goal_met",
                                    "deterministic"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t3_reddy_speedup", c->md, c->echo, c->det, h, 13, err) != 0)
        return -1;
    struct hl_out plot;
    FILE *f = bch_plot_data(c, "t3_speedup.dat", &plot, err);
    if (!f) {
        bch_table_end(&t, err);
        return -1;
    }
    fputs("objects", f);
    for (int v = 0; v < N_VARIANTS; ++v)
        fprintf(f, " %s", variants[v][0]);
    fputc('\n', f);
    int has_data = 0;
    int last_objects = -1;
    for (size_t i = 0; i < c->plan->count; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        if (run->table != 3 || strncmp(run->id, "t3-o", 4) || run->objects == last_objects)
            continue;
        last_objects = run->objects;
        fprintf(f, "%d", run->objects);
        for (int v = 0; v < N_VARIANTS; ++v) {
            char id_r[96], id_n[96];
            snprintf(id_r, sizeof id_r, "t3-o%d-%s", run->objects, variants[v][0]);
            snprintf(id_n, sizeof id_n, "t3-o%d-%s", run->objects, variants[v][1]);
            const struct bch_result *r = bch_find(c, id_r), *n = bch_find(c, id_n);
            double fr = r ? bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)) : NAN,
                   fn = n ? bch_timing(n, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)) : NAN;
            double tr = r ? bch_mean(r, r->triangles) : NAN, tn = n ? bch_mean(n, n->triangles) : NAN;
            /* per round: none and reddy of one object count ran in the same pass over the table */
            struct bch_spread sp;
            bch_timing_ratio(n, r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms), &sp);
            double speedup = sp.median, vis = r ? r->visible_error_mean : NAN;
            char cell[9][BCH_CELL];
            const char *goal = "";
            if (run->objects == 1000 && strstr(variants[v][0], "full"))
                goal = !isfinite(speedup) ? "—" : speedup >= GOAL_SPEEDUP && vis == 0.0 ? "yes" : "no";
            const char *cells[13] = {bch_cell(cell[0], run->objects, 0),
                                     variants[v][2],
                                     variants[v][3],
                                     variants[v][4],
                                     bch_cell(cell[1], fn, 3),
                                     bch_cell(cell[2], fr, 3),
                                     bch_cell(cell[3], speedup, 2),
                                     bch_cell(cell[7], sp.min, 2),
                                     bch_cell(cell[8], sp.max, 2),
                                     bch_cell(cell[4], tn / tr, 2),
                                     bch_cell(cell[5], vis, 4),
                                     goal,
                                     "1"};
            bch_table_row(&t, cells);
            fprintf(f, " %.4f", speedup);
            has_data |= isfinite(speedup);
        }
        fputc('\n', f);
    }
    if (hl_out_commit(&plot, err) != 0) {
        struct hl_error table_err;
        bch_table_end(&t, &table_err);
        return -1;
    }
    if (bch_table_end(&t, err) != 0)
        return -1;
    char body[2048];
    snprintf(body, sizeof body,
             "set logscale x\nset xlabel 'objects'\nset ylabel 'frame time of none / of reddy'\nset key left top\n"
             "plot for [i=2:%d] 't3_speedup.dat' using 1:i with linespoints title columnheader(i), "
             "%g with lines dashtype 2 lc rgb 'black' title 'Reddy: 4.5x'\n",
             N_VARIANTS + 1, GOAL_SPEEDUP);
    return bch_plot(c, "t3_speedup", "Speedup of reddy over none on field against the object count", body,
                          has_data, err);
}

static int display_table(struct bch_ctx *c, struct hl_error *err)
{
    bch_heading(c, "Table 3b: per display, the share of the LOD reduction owed to velocity, to eccentricity and to contrast",
                      "reddy on field (user1, default gaze), four runs per display: both terms, velocity term off, "
                      "eccentricity term off (all under the contrast criterion), and both terms under the acuity "
                      "criterion (Reddy's H(v, E) at full contrast). reduction = 1 − triangles drawn / finest; owed "
                      "to a term = (reduction with both − reduction without it) / reduction with both; owed to "
                      "contrast = (reduction under contrast − under acuity) / reduction under contrast (negative "
                      "where the contrast criterion keeps more; the shares need not add to 1: size alone, and the "
                      "terms together, do the rest).\n",
                      0);
    static const char *const h[] = {"display",
                                    "xi_cpd",
                                    "*reduction_both",
                                    "*reduction_no_velocity",
                                    "*reduction_no_eccentricity",
                                    "*reduction_acuity",
                                    "*owed_to_velocity",
                                    "*owed_to_eccentricity",
                                    "*owed_to_contrast",
                                    "frame_ms_mean",
                                    "deterministic"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t3b_displays", c->md, NULL, c->det, h, 11, err) != 0)
        return -1;
    for (size_t i = 0; i < c->plan->count; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        if (strncmp(run->id, "t3d-", 4) || run->velocity_off || run->eccentricity_off || run->visibility[0])
            continue;
        char id[96];
        snprintf(id, sizeof id, "t3d-%s-novel", run->display);
        const struct bch_result *nv = bch_find(c, id);
        snprintf(id, sizeof id, "t3d-%s-noecc", run->display);
        const struct bch_result *ne = bch_find(c, id);
        snprintf(id, sizeof id, "t3d-%s-acuity", run->display);
        const struct bch_result *na = bch_find(c, id);
        const struct bch_result *full = c->results[i].present ? &c->results[i] : NULL;
        double rb = reduction(full), rv = reduction(nv), re = reduction(ne), ra = reduction(na);
        const struct hmd_profile *p = hmd_builtin_find(run->display);
        char cell[9][BCH_CELL];
        const char *cells[11] = {run->display,
                                 bch_cell(cell[0], p ? hmd_compute_xi(p).used_cpd : NAN, 2),
                                 bch_cell(cell[1], rb, 4),
                                 bch_cell(cell[2], rv, 4),
                                 bch_cell(cell[3], re, 4),
                                 bch_cell(cell[7], ra, 4),
                                 bch_cell(cell[4], rb > 0 ? (rb - rv) / rb : NAN, 3),
                                 bch_cell(cell[5], rb > 0 ? (rb - re) / rb : NAN, 3),
                                 bch_cell(cell[8], rb > 0 ? (rb - ra) / rb : NAN, 3),
                                 bch_cell(cell[6], full ? bch_timing(full, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)) : NAN, 3),
                                 "1"};
        bch_table_row(&t, cells);
    }
    return bch_table_end(&t, err);
}

static int reading_table(struct bch_ctx *c, struct hl_error *err)
{
    bch_heading(c, "Table 3c: the two frequency readings and their image error",
                      "reddy on field (user1) with --frequency-reading narrow (the thickest lost feature) and long "
                      "(the longest lost chord; docs/analysis.md), with --reference.\n",
                      0);
    static const char *const h[] = {"reading",       "*triangle_share", "*fssim_mean", "*ssim_mean",
                                    "*psnr_db_mean", "*px_over_32",     "*flip_mean",  "*visible_error_mean",
                                    "frame_ms_mean", "deterministic"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t3c_readings", c->md, NULL, c->det, h, 10, err) != 0)
        return -1;
    for (size_t i = 0; i < c->plan->count; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        if (strncmp(run->id, "t3r-", 4))
            continue;
        const struct bch_result *r = c->results[i].present ? &c->results[i] : NULL;
        char cell[8][BCH_CELL];
        const char *cells[10] = {run->reading,
                                bch_cell(cell[0], r ? 1.0 - reduction(r) : NAN, 4),
                                bch_cell(cell[1], r ? r->fssim_mean : NAN, 4),
                                bch_cell(cell[2], r ? r->ssim_mean : NAN, 4),
                                bch_psnr_cell(cell[3], r),
                                bch_cell(cell[4], r ? r->px_over_32 : NAN, 4),
                                bch_cell(cell[7], r ? r->flip_mean : NAN, 4),
                                bch_cell(cell[5], r ? r->visible_error_mean : NAN, 4),
                                bch_cell(cell[6], r ? bch_timing(r, BCH_STAT_MEAN, BCH_COLUMN(frame_ms)) : NAN, 3),
                                "1"};
        bch_table_row(&t, cells);
    }
    return bch_table_end(&t, err);
}

static int criterion_table(struct bch_ctx *c, struct hl_error *err)
{
    bch_heading(c, "Table 3e: the two visibility criteria, image error by eccentricity",
                      "reddy on field (user1, the largest object count) under --visibility contrast (castle CSF, the "
                      "default k) and acuity, per gaze model, with --reference: the share of the finest triangles "
                      "drawn and the image error against the full-detail frame (foveated SSIM; SSIM in the "
                      "eccentricity bands around the gaze; FLIP).\n",
                      0);
    static const char *const h[] = {"gaze",         "criterion",     "*triangle_share", "*fssim_mean",
                                    "*ssim_0_5.79", "*ssim_5.79_15", "*ssim_15_30",     "*ssim_30_up",
                                    "*flip_mean",   "deterministic"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t3e_criteria", c->md, c->echo, c->det, h, 10, err) != 0)
        return -1;
    for (size_t i = 0; i < c->plan->count; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        if (strncmp(run->id, "t3v-", 4))
            continue;
        const struct bch_result *r = c->results[i].present ? &c->results[i] : NULL;
        char cell[7][BCH_CELL];
        const char *cells[10] = {run->gaze,
                                 run->visibility,
                                 bch_cell(cell[0], r ? 1.0 - reduction(r) : NAN, 4),
                                 bch_cell(cell[1], r ? r->fssim_mean : NAN, 4),
                                 bch_cell(cell[2], r ? r->fssim_band[0] : NAN, 4),
                                 bch_cell(cell[3], r ? r->fssim_band[1] : NAN, 4),
                                 bch_cell(cell[4], r ? r->fssim_band[2] : NAN, 4),
                                 bch_cell(cell[5], r ? r->fssim_band[3] : NAN, 4),
                                 bch_cell(cell[6], r ? r->flip_mean : NAN, 4),
                                 "1"};
        bch_table_row(&t, cells);
    }
    return bch_table_end(&t, err);
}

static int kept_table(struct bch_ctx *c, struct hl_error *err)
{
    bch_heading(c, "Table 3f: the two visibility criteria, triangles kept by eccentricity and by retinal speed",
                      "The runs of Table 3e: per object and frame, the share of its finest triangles drawn, summed by "
                      "the object's eccentricity band (as the SSIM bands) and by its retinal-speed band (deg/s, under "
                      "the run's gaze model: under vor the eye holds the world and what it looks at barely moves on "
                      "the retina; under head every turn is retinal motion); — where no object fell in a band.\n",
                      0);
    static const char *const h[] = {"gaze",          "criterion",     "*kept_0_5.79",  "*kept_5.79_15", "*kept_15_30",
                                    "*kept_30_up",   "*kept_0_2dps",  "*kept_2_10dps", "*kept_10_30dps",
                                    "*kept_30up_dps", "deterministic"};
    struct bch_table t;
    if (bch_table_begin(&t, c->dir, "t3f_kept", c->md, c->echo, c->det, h, 11, err) != 0)
        return -1;
    for (size_t i = 0; i < c->plan->count; ++i) {
        const struct bch_run *run = &c->plan->runs[i];
        if (strncmp(run->id, "t3v-", 4))
            continue;
        const struct bch_result *r = c->results[i].present ? &c->results[i] : NULL;
        char cell[8][BCH_CELL];
        const char *cells[11] = {run->gaze, run->visibility};
        for (int b = 0; b < 4; ++b) {
            cells[2 + b] = bch_cell(cell[b], r ? r->kept_ecc[b] : NAN, 4);
            cells[6 + b] = bch_cell(cell[4 + b], r ? r->kept_retinal[b] : NAN, 4);
        }
        cells[10] = "1";
        bch_table_row(&t, cells);
    }
    return bch_table_end(&t, err);
}

int bch_tables_t3(struct bch_ctx *c, struct hl_error *err)
{
    bch_heading(c, "Table 3: Reddy's study on field",
                      "Speedup = none's frame time mean / reddy's over the same frames and motion, taken per round "
                      "(the two ran in the same pass over the table) — the median over rounds, with min and max; "
                      "frame times are medians over rounds; triangle ratio = "
                      "none's triangles / reddy's. still: the suite's still-head trace (still-head.csv); size only: "
                      "--velocity-term off --eccentricity-term off. Goal (Reddy 1997): ≥ 4.5× at zero predicted "
                      "visible error with 1000 objects, per gaze model.\n",
                      1);
    if (speedup_table(c, err) != 0 || display_table(c, err) != 0 || reading_table(c, err) != 0 ||
        criterion_table(c, err) != 0)
        return -1;
    return kept_table(c, err);
}
