/* Per-frame CSV, summary JSON and the printed table of a replay. Files are written under a
 * temporary name and renamed when complete: an interrupted run leaves no output posing as done. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "replay/run_internal.h"

int rpl_output_open(struct rpl_output *o, const char *dir, int max_lods, struct hl_error *err)
{
    memset(o, 0, sizeof *o);
    snprintf(o->csv_path, sizeof o->csv_path, "%s/frames.csv", dir);
    if (hl_out_open(&o->out, o->csv_path, err) != 0)
        return -1;
    o->csv = o->out.f;
    fputs("frame,time_s,head_speed_degps,visible,acuity_evaluations,triangles_per_eye,triangles_finest", o->csv);
    for (int k = 0; k < max_lods; ++k)
        fprintf(o->csv, ",lod%d", k);
    fputs(",dropped,predicted_ms,optimizer_budget_ms,benefit,lp_bound,lp_gap,lod_changes,iterations,truncated,"
          "over_budget,underused_drop,dropped_px_share,eye_speed_degps,gaze_speed_degps,saccade_phase,refine_pending,refine_miss,visible_error,adapting_luminance_cdm2,"
          "psnr_db,ssim,ssim_rgb,fssim,fssim_e0,fssim_e1,fssim_e2,fssim_e3,px_over_32,flip_mean,flip_median,flip_max,"
          "layer_scale,inset_radius_deg,inset_x_deg,inset_y_deg,layer_loses,inset_px,periphery_px,acuity_us,select_us,"
          "optimizer_us,draw_ms,frame_ms,deadline_met,minor_faults,luminance_us,composite_ms\n", o->csv);
    return 0;
}

/* A number, empty where it is NaN, "inf" for an identical frame's PSNR. */
static void write_optional(FILE *f, const char *format, double v)
{
    if (isnan(v))
        fputc(',', f);
    else if (isinf(v))
        fputs(",inf", f);
    else
        fprintf(f, format, v);
}

/* --reference frames' columns (render/image_error.h, render/flip.h); empty on other frames. */
static void write_image_error(FILE *f, const struct frm_frame_record *r)
{
    if (!r->has_image_error) {
        fputs(",,,,,,,,,,,,", f);
        return;
    }
    const struct rnd_image_error *e = &r->image;
    write_optional(f, ",%.4f", e->psnr_db);
    write_optional(f, ",%.6f", e->ssim);
    write_optional(f, ",%.6f", e->ssim_rgb);
    write_optional(f, ",%.6f", e->fssim);
    for (int b = 0; b < RND_ECC_BANDS; ++b)
        write_optional(f, ",%.6f", e->fssim_band[b]);
    write_optional(f, ",%.6f", e->px_over_32_share);
    fprintf(f, ",%.6f,%.6f,%.6f", r->flip.mean, r->flip.weighted_median, r->flip.max);
}

void rpl_output_row(struct rpl_output *o, const struct frm_frame_record *r, int max_lods)
{
    fprintf(o->csv, "%ld,%.6f,%.3f,%u,%llu,%llu,%llu", r->frame, r->time_s, r->head_speed_degps, r->visible,
            (unsigned long long)r->acuity_evaluations, (unsigned long long)r->triangles_per_eye,
            (unsigned long long)r->triangles_finest);
    for (int k = 0; k < max_lods; ++k)
        fprintf(o->csv, ",%u", r->lod_histogram[k]);
    /* lp_gap: the share of the LP bound the choice misses (empty where no bound was computed). */
    const struct frm_select_record *q = &r->sel;
    fprintf(o->csv, ",%u,%.4f,%.4f,%.6g", q->dropped, q->predicted_ms, q->optimizer_budget_ms, q->benefit);
    if (isfinite(q->lp_bound) && q->lp_bound > 0.0)
        fprintf(o->csv, ",%.6g,%.6f", q->lp_bound, 1.0 - q->benefit / q->lp_bound);
    else
        fputs(",,", o->csv);
    fprintf(o->csv, ",%u,%u,%d,%d,%d,%.6f", q->lod_changes, q->iterations, q->truncated, q->over_budget,
            q->underused_drop, q->dropped_px_share);
    /* The eye's angular speed in the world under the gaze model (deterministic). */
    fprintf(o->csv, ",%.3f", r->eye_speed_degps);
    fprintf(o->csv, ",%.3f,%d,%u,%d", q->gaze_speed_degps, q->saccade_phase, q->refine_pending,
            q->refine_miss); /* saccade_step.c */
    fprintf(o->csv, ",%.6f", r->visible_error);
    write_optional(o->csv, ",%.3f", r->adapting_luminance_cdm2); /* empty under --visibility acuity */
    write_image_error(o->csv, r);
    /* The foveated layers (frame/layers.h): scale 1 and radius 0 when there are none. */
    fprintf(o->csv, ",%.2f,%.3f,%.3f,%.3f,%d,%.0f,%.0f", q->layer_scale, q->inset_radius_deg, r->inset_x_deg,
            r->inset_y_deg, q->layer_loses, r->draw.inset_px, r->draw.periphery_px);
    /* The timings last: everything before them is deterministic (the optimizer's budget aside, which
     * follows the measured overhead and correction). */
    fprintf(o->csv, ",%.2f,%.2f,%.2f,%.3f,%.3f,%d,%ld,%.2f,%.3f\n", r->acuity_us, r->select_us, q->optimizer_us,
            r->draw_ms, r->frame_ms, r->deadline_met, r->minor_faults, r->luminance_us, r->composite_ms);
}

int rpl_output_close(struct rpl_output *o, struct hl_error *err)
{
    o->csv = NULL;
    return hl_out_close(&o->out, err);
}

int rpl_output_commit(struct rpl_output *o, struct hl_error *err)
{
    o->csv = NULL;
    return hl_out_commit(&o->out, err);
}

void rpl_output_abort(struct rpl_output *o)
{
    o->csv = NULL;
    hl_out_abort(&o->out);
}

/* A write that failed (disk full) stops the replay at once, instead of rendering frames no file keeps. */
int rpl_output_failed(const struct rpl_output *o) { return o->csv && ferror(o->csv); }

/* VmHWM is the peak resident set (high-water mark) over the process's life, VmRSS the current one;
 * both in kB (= KiB) in proc(5). Read at the end of a run, so the peak covers loading and frames. */
void rpl_resident_memory(long *vm_hwm_kib, long *vm_rss_kib)
{
    *vm_hwm_kib = *vm_rss_kib = -1;
    FILE *f = fopen("/proc/self/status", "r");
    if (!f)
        return;
    char line[256];
    while (fgets(line, sizeof line, f)) {
        long v;
        if (sscanf(line, "VmHWM: %ld kB", &v) == 1)
            *vm_hwm_kib = v;
        else if (sscanf(line, "VmRSS: %ld kB", &v) == 1)
            *vm_rss_kib = v;
    }
    fclose(f);
}

const double rpl_speed_band_lower_degps[RPL_SPEED_BAND_COUNT] = {0.0, 10.0, 30.0, 60.0, 120.0};

int rpl_accumulator_init(struct rpl_accumulator *a, long frames, long references, struct hl_error *err)
{
    memset(a, 0, sizeof *a);
    a->capacity = frames > 0 ? frames : 1;
    a->warm_frames = frames / 10 > 1 ? frames / 10 : 1;
    a->frame_ms = malloc((size_t)a->capacity * sizeof(double));
    a->draw_ms = malloc((size_t)a->capacity * sizeof(double));
    a->ref_capacity = references > 0 ? references : 1;
    a->ref_psnr_db = malloc((size_t)a->ref_capacity * sizeof(double));
    a->ref_ssim = malloc((size_t)a->ref_capacity * sizeof(double));
    a->ref_fssim = malloc((size_t)a->ref_capacity * sizeof(double));
    if (!a->frame_ms || !a->draw_ms || !a->ref_psnr_db || !a->ref_ssim || !a->ref_fssim) {
        rpl_accumulator_free(a);
        return hl_fail(err, "out of memory for %ld frame times", frames);
    }
    return 0;
}

void rpl_accumulator_free(struct rpl_accumulator *a)
{
    free(a->frame_ms);
    free(a->draw_ms);
    free(a->ref_psnr_db);
    free(a->ref_ssim);
    free(a->ref_fssim);
    a->frame_ms = a->draw_ms = a->ref_psnr_db = a->ref_ssim = a->ref_fssim = NULL;
}


static void accumulate_image_error(struct rpl_accumulator *a, const struct frm_frame_record *r)
{
    const struct rnd_image_error *e = &r->image;
    if (a->ref_n < a->ref_capacity) {
        a->ref_psnr_db[a->ref_n] = e->psnr_db;
        a->ref_ssim[a->ref_n] = e->ssim;
        a->ref_fssim[a->ref_n] = e->fssim;
    }
    ++a->ref_n;
    if (isfinite(e->psnr_db))
        a->ref_psnr_sum += e->psnr_db, a->ref_psnr_finite++;
    else
        a->ref_identical++;
    a->ref_ssim_sum += e->ssim;
    a->ref_ssim_rgb_sum += e->ssim_rgb;
    a->ref_fssim_sum += e->fssim;
    a->ref_over32_sum += e->px_over_32_share;
    a->ref_visible_sum += r->visible_error;
    for (int b = 0; b < RND_ECC_BANDS; ++b)
        if (isfinite(e->fssim_band[b]))
            a->ref_band_sum[b] += e->fssim_band[b], a->ref_band_n[b]++;
    a->ref_flip_sum += r->flip.mean;
    a->ref_flip_median_sum += r->flip.weighted_median;
    a->ref_flip_mean_max = fmax(a->ref_flip_mean_max, r->flip.mean);
    a->ref_flip_max = fmax(a->ref_flip_max, r->flip.max);
    a->ref_flip_ppd = r->flip_ppd;
}

void rpl_accumulate(struct rpl_accumulator *a, const struct frm_frame_record *r)
{
    if (a->n < a->capacity) {
        a->frame_ms[a->n] = r->frame_ms;
        a->draw_ms[a->n] = r->draw_ms;
    }
    int band = frm_band_of(rpl_speed_band_lower_degps, RPL_SPEED_BAND_COUNT, r->head_speed_degps);
    a->band_frames[band]++;
    a->band_triangles[band] += (double)r->triangles_per_eye;
    a->band_finest[band] += (double)r->triangles_finest;
    for (int b = 0; b < RND_ECC_BANDS; ++b)
        a->ecc_drawn[b] += (double)r->ecc_drawn[b], a->ecc_finest[b] += (double)r->ecc_finest[b];
    for (int b = 0; b < FRM_RETINAL_BANDS; ++b)
        a->retinal_drawn[b] += (double)r->retinal_drawn[b], a->retinal_finest[b] += (double)r->retinal_finest[b];
    a->eye_speed_sum += r->eye_speed_degps;
    if (r->frame >= a->warm_frames) {
        a->faults_sum += (double)r->minor_faults;
        a->fault_frames++;
    }
    ++a->n;
    double delta = r->frame_ms - a->frame_mean;
    a->frame_mean += delta / (double)a->n;
    a->frame_m2 += delta * (r->frame_ms - a->frame_mean);
    a->frame_max = fmax(a->frame_max, r->frame_ms);
    if (r->frame >= 1)
        a->frame_sum_after_first += r->frame_ms;
    a->draw_sum += r->draw_ms;
    a->acuity_sum += r->acuity_us;
    a->select_sum += r->select_us;
    a->evals_sum += (double)r->acuity_evaluations;
    a->visible_sum += r->visible;
    a->cull_groups_sum += r->cull_groups_tested;
    a->cull_instances_sum += r->cull_instances_tested;
    a->triangles_sum += (double)r->triangles_per_eye;
    a->finest_sum += (double)r->triangles_finest;
    a->deadlines_met += r->deadline_met;
    const struct frm_select_record *q = &r->sel;
    a->predicted_within += q->predicted_ms <= q->budget_ms;
    a->truncated_frames += q->truncated;
    a->over_budget_frames += q->over_budget;
    a->underused_drop_frames += q->underused_drop;
    a->dropped_sum += q->dropped;
    for (int i = 0; i < FRM_LAYER_SCALES; ++i)
        a->scale_frames[i] += fabs(q->layer_scale - frm_layer_scales[i]) < 1e-9;
    a->lossy_frames += q->layer_loses;
    if (q->layer_scale < 1.0)
        a->inset_radius_sum += q->inset_radius_deg, a->composite_ms_sum += r->composite_ms, a->scale_sum += q->layer_scale;
    a->dropped_px_share_sum += q->dropped_px_share;
    a->dropped_px_share_max = fmax(a->dropped_px_share_max, q->dropped_px_share);
    a->lod_changes_sum += q->lod_changes;
    a->optimizer_us_sum += q->optimizer_us;
    a->optimizer_us_max = fmax(a->optimizer_us_max, q->optimizer_us);
    a->iterations_sum += q->iterations;
    if (isfinite(q->lp_bound) && q->lp_bound > 0.0) {
        double share = q->benefit / q->lp_bound;
        a->benefit_share_min = a->benefit_share_frames ? fmin(a->benefit_share_min, share) : share;
        a->benefit_share_sum += share;
        a->benefit_share_frames++;
    }
    a->visible_error_sum += r->visible_error;
    a->visible_error_max = fmax(a->visible_error_max, r->visible_error);
    if (!isnan(r->adapting_luminance_cdm2)) {
        a->adapting_sum += r->adapting_luminance_cdm2;
        a->adapting_min = a->adapting_frames ? fmin(a->adapting_min, r->adapting_luminance_cdm2) : r->adapting_luminance_cdm2;
        a->adapting_max = fmax(a->adapting_max, r->adapting_luminance_cdm2);
        a->adapting_frames++;
    }
    if (r->has_image_error)
        accumulate_image_error(a, r);
    a->gaze_frames += q->saccade_active; /* saccades (frame/saccade_step.c) */
    a->saccades += q->saccade_started;
    a->suppressed_frames += q->saccade_phase != 0;
    a->refine_miss_frames += q->refine_miss;
    a->refine_missed_saccades += q->refine_missed_saccade;
}

/* The reference frames' figures (NaN where none were compared); sorts the stored ones. */
static void finish_image_error(struct rpl_accumulator *a, struct rpl_summary *s)
{
    long stored = a->ref_n < a->ref_capacity ? a->ref_n : a->ref_capacity;
    double n = (double)a->ref_n;
    s->reference_frames = a->ref_n;
    s->identical_frames = a->ref_identical;
    s->psnr_db_mean = a->ref_psnr_finite ? a->ref_psnr_sum / (double)a->ref_psnr_finite : a->ref_n ? INFINITY : NAN;
    s->ssim_mean = a->ref_n ? a->ref_ssim_sum / n : NAN;
    s->ssim_rgb_mean = a->ref_n ? a->ref_ssim_rgb_sum / n : NAN;
    s->fssim_mean = a->ref_n ? a->ref_fssim_sum / n : NAN;
    s->px_over_32_share_mean = a->ref_n ? a->ref_over32_sum / n : NAN;
    s->visible_error_reference_mean = a->ref_n ? a->ref_visible_sum / n : NAN;
    s->flip_ppd = a->ref_n ? a->ref_flip_ppd : NAN;
    s->flip_mean = a->ref_n ? a->ref_flip_sum / n : NAN;
    s->flip_median_mean = a->ref_n ? a->ref_flip_median_sum / n : NAN;
    s->flip_mean_max = a->ref_n ? a->ref_flip_mean_max : NAN;
    s->flip_max = a->ref_n ? a->ref_flip_max : NAN;
    for (int b = 0; b < RND_ECC_BANDS; ++b)
        s->fssim_band_mean[b] = a->ref_band_n[b] ? a->ref_band_sum[b] / (double)a->ref_band_n[b] : NAN;
    hl_sort_doubles(a->ref_psnr_db, (size_t)stored);
    hl_sort_doubles(a->ref_ssim, (size_t)stored);
    hl_sort_doubles(a->ref_fssim, (size_t)stored);
    s->psnr_db_min = stored ? a->ref_psnr_db[0] : NAN;
    s->ssim_min = stored ? a->ref_ssim[0] : NAN;
    s->fssim_min = stored ? a->ref_fssim[0] : NAN;
    s->psnr_db_p5 = stored ? hl_percentile_sorted(a->ref_psnr_db, (size_t)stored, 0.05) : NAN;
    s->ssim_p5 = stored ? hl_percentile_sorted(a->ref_ssim, (size_t)stored, 0.05) : NAN;
    s->fssim_p5 = stored ? hl_percentile_sorted(a->ref_fssim, (size_t)stored, 0.05) : NAN;
}

void rpl_accumulator_finish(struct rpl_accumulator *a, struct rpl_summary *s)
{
    double n = a->n > 0 ? (double)a->n : 1.0;
    long stored = a->n < a->capacity ? a->n : a->capacity;
    hl_sort_doubles(a->frame_ms, (size_t)stored);
    hl_sort_doubles(a->draw_ms, (size_t)stored);
    s->frame_ms_median = hl_percentile_sorted(a->frame_ms, (size_t)stored, 0.5);
    s->frame_ms_p95 = hl_percentile_sorted(a->frame_ms, (size_t)stored, 0.95);
    s->frame_ms_p99 = hl_percentile_sorted(a->frame_ms, (size_t)stored, 0.99);
    s->draw_ms_median = hl_percentile_sorted(a->draw_ms, (size_t)stored, 0.5);
    s->frames = a->n;
    s->minor_faults_per_frame = a->fault_frames > 0 ? a->faults_sum / (double)a->fault_frames : NAN;
    s->minor_faults_from_frame = a->warm_frames;
    s->frame_ms_mean = a->frame_mean;
    s->frame_ms_mean_after_first = a->n > 1 ? a->frame_sum_after_first / (double)(a->n - 1) : NAN;
    s->frame_ms_max = a->frame_max;
    s->frame_ms_stddev = a->n > 1 ? sqrt(a->frame_m2 / (double)(a->n - 1)) : 0.0;
    s->draw_ms_mean = a->draw_sum / n;
    s->acuity_us_mean = a->acuity_sum / n;
    s->select_us_mean = a->select_sum / n;
    s->acuity_evaluations_mean = a->evals_sum / n;
    s->visible_mean = a->visible_sum / n;
    s->eye_speed_degps_mean = a->eye_speed_sum / n;
    s->cull_groups_tested_mean = a->cull_groups_sum / n;
    s->cull_instances_tested_mean = a->cull_instances_sum / n;
    s->triangles_per_eye_mean = a->triangles_sum / n;
    s->triangles_relative_to_none = a->finest_sum > 0 ? a->triangles_sum / a->finest_sum : 1.0;
    s->deadline_met_fraction = (double)a->deadlines_met / n;
    s->predicted_within_fraction = (double)a->predicted_within / n;
    s->truncated_fraction = (double)a->truncated_frames / n;
    s->over_budget_fraction = (double)a->over_budget_frames / n;
    s->underused_drops = a->underused_drop_frames;
    s->dropped_mean = a->dropped_sum / n;
    for (int i = 0; i < FRM_LAYER_SCALES; ++i)
        s->scale_frames[i] = a->scale_frames[i];
    long layered = a->n - a->scale_frames[0]; /* every frame not at scale 1, the adaptive mode's included */
    s->lossy_frames = a->lossy_frames;
    s->inset_radius_deg_mean = layered ? a->inset_radius_sum / (double)layered : NAN;
    s->composite_ms_mean = layered ? a->composite_ms_sum / (double)layered : NAN;
    s->scale_mean = layered ? a->scale_sum / (double)layered : NAN;
    s->dropped_px_share_mean = a->dropped_px_share_sum / n;
    s->dropped_px_share_max = a->dropped_px_share_max;
    s->optimizer_us_mean = a->optimizer_us_sum / n;
    s->optimizer_us_max = a->optimizer_us_max;
    s->iterations_mean = a->iterations_sum / n;
    s->benefit_share_of_lp_mean = a->benefit_share_frames ? a->benefit_share_sum / (double)a->benefit_share_frames : NAN;
    s->benefit_share_of_lp_min = a->benefit_share_frames ? a->benefit_share_min : NAN;
    /* per visible object per second: changes / (object-frames) × frames per second; the caller
     * knows the rate and scales (rpl_run). */
    s->lod_changes_per_object_s = a->visible_sum > 0 ? a->lod_changes_sum / a->visible_sum : 0.0;
    s->gaze_frames = a->gaze_frames, s->saccades = a->saccades, s->suppressed_frames = a->suppressed_frames;
    s->suppressed_fraction = (double)a->suppressed_frames / n;
    s->refine_miss_frames = a->refine_miss_frames, s->refine_missed_saccades = a->refine_missed_saccades;
    s->refine_missed_saccade_fraction = a->saccades ? (double)a->refine_missed_saccades / (double)a->saccades : 0.0;
    s->visible_error_mean = a->visible_error_sum / n;
    s->visible_error_max = a->visible_error_max;
    s->adapting_luminance_cdm2_mean = a->adapting_frames ? a->adapting_sum / (double)a->adapting_frames : NAN;
    s->adapting_luminance_cdm2_min = a->adapting_frames ? a->adapting_min : NAN;
    s->adapting_luminance_cdm2_max = a->adapting_frames ? a->adapting_max : NAN;
    finish_image_error(a, s);
    for (int b = 0; b < RPL_SPEED_BAND_COUNT; ++b) {
        s->band_frames[b] = a->band_frames[b];
        s->band_triangle_share[b] = a->band_finest[b] > 0 ? a->band_triangles[b] / a->band_finest[b] : NAN;
    }
    for (int b = 0; b < RND_ECC_BANDS; ++b)
        s->ecc_triangle_share[b] = a->ecc_finest[b] > 0 ? a->ecc_drawn[b] / a->ecc_finest[b] : NAN;
    for (int b = 0; b < FRM_RETINAL_BANDS; ++b)
        s->retinal_triangle_share[b] = a->retinal_finest[b] > 0 ? a->retinal_drawn[b] / a->retinal_finest[b] : NAN;
}

/* A number, or null where it is not finite (JSON has no NaN or infinity). */
static void add_number_or_null(cJSON *o, const char *name, double v)
{
    if (isfinite(v))
        cJSON_AddNumberToObject(o, name, v);
    else
        cJSON_AddNullToObject(o, name);
}

/* An array of bands: {from_key: lower[b], value_key: value[b] or null}, b < count. */
static void add_band_array(cJSON *o, const char *name, const char *from_key, const double *lower,
                           const char *value_key, const double *value, int count)
{
    cJSON *bands = cJSON_AddArrayToObject(o, name);
    for (int b = 0; b < count; ++b) {
        cJSON *band = cJSON_CreateObject();
        cJSON_AddNumberToObject(band, from_key, lower[b]);
        add_number_or_null(band, value_key, value[b]);
        cJSON_AddItemToArray(bands, band);
    }
}

static void add_stat(cJSON *o, const char *name, double mean, double min, double p5)
{
    cJSON *stat = cJSON_AddObjectToObject(o, name);
    add_number_or_null(stat, "mean", mean);
    add_number_or_null(stat, "min", min);
    add_number_or_null(stat, "p5", p5);
}

/* "image_error": what --reference measured (docs/replay-output.md), null when nothing was compared. */
static void add_image_error(cJSON *root, const struct rpl_summary *s)
{
    if (s->reference_frames <= 0) {
        cJSON_AddNullToObject(root, "image_error");
        return;
    }
    cJSON *e = cJSON_AddObjectToObject(root, "image_error");
    cJSON_AddNumberToObject(e, "frames", (double)s->reference_frames);
    cJSON_AddNumberToObject(e, "identical_frames", (double)s->identical_frames);
    add_stat(e, "psnr_db", s->psnr_db_mean, s->psnr_db_min, s->psnr_db_p5);
    add_stat(e, "ssim", s->ssim_mean, s->ssim_min, s->ssim_p5);
    add_number_or_null(e, "ssim_rgb_mean", s->ssim_rgb_mean);
    add_stat(e, "fssim", s->fssim_mean, s->fssim_min, s->fssim_p5);
    add_band_array(e, "fssim_bands", "from_deg", rnd_ecc_band_lower_deg, "ssim_mean", s->fssim_band_mean,
                   RND_ECC_BANDS);
    add_number_or_null(e, "px_over_32_share_mean", s->px_over_32_share_mean);
    add_number_or_null(e, "visible_error_mean", s->visible_error_reference_mean);
    cJSON *flip = cJSON_AddObjectToObject(e, "flip");
    add_number_or_null(flip, "ppd", s->flip_ppd);
    add_number_or_null(flip, "mean", s->flip_mean);
    add_number_or_null(flip, "mean_max", s->flip_mean_max);
    add_number_or_null(flip, "weighted_median_mean", s->flip_median_mean);
    add_number_or_null(flip, "max", s->flip_max);
}

int rpl_summary_stage_json(const char *dir, const struct rpl_summary *s, struct hl_out *out, struct hl_error *err)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "format", "hmdlod-summary-1");
    cJSON_AddStringToObject(root, "scene", s->scene);
    cJSON_AddStringToObject(root, "display", s->display);
    cJSON_AddStringToObject(root, "selector", s->selector);
    cJSON_AddStringToObject(root, "renderer", s->renderer);
    cJSON_AddStringToObject(root, "benefit", s->benefit); /* docs/optimizer.md "Perceptual benefit" */
    cJSON *wall = cJSON_AddObjectToObject(root, "wall_clock");
    cJSON_AddStringToObject(wall, "host", s->host);
    cJSON_AddNumberToObject(wall, "start_unix_s", s->wall_start_unix_s);
    cJSON_AddNumberToObject(wall, "end_unix_s", s->wall_end_unix_s);
    cJSON *crit = cJSON_AddObjectToObject(root, "visibility"); /* docs/visibility.md */
    cJSON_AddStringToObject(crit, "criterion", s->visibility);
    cJSON_AddStringToObject(crit, "csf", s->csf);
    cJSON_AddNumberToObject(crit, "csf_scale", s->csf_scale);
    cJSON_AddNumberToObject(crit, "peak_luminance_cdm2", s->peak_luminance_cdm2);
    add_number_or_null(crit, "adapting_luminance_cdm2_mean", s->adapting_luminance_cdm2_mean);
    add_number_or_null(crit, "adapting_luminance_cdm2_min", s->adapting_luminance_cdm2_min);
    add_number_or_null(crit, "adapting_luminance_cdm2_max", s->adapting_luminance_cdm2_max);
    cJSON_AddNumberToObject(crit, "table_refills", (double)s->csf_table_refills);
    cJSON *gaze = cJSON_AddObjectToObject(root, "gaze");
    cJSON_AddStringToObject(gaze, "model", s->gaze);
    cJSON_AddNumberToObject(gaze, "fixation_m", s->fixation_m);
    cJSON_AddNumberToObject(gaze, "vor_gain", s->vor_gain);
    cJSON_AddNumberToObject(gaze, "vor_latency_ms", s->vor_latency_ms);
    cJSON *neck = cJSON_AddArrayToObject(gaze, "neck_to_eye_m");
    cJSON_AddItemToArray(neck, cJSON_CreateNumber(s->trace_has_position ? 0.0 : s->neck_to_eye_m[0]));
    cJSON_AddItemToArray(neck, cJSON_CreateNumber(s->trace_has_position ? 0.0 : s->neck_to_eye_m[1]));
    cJSON_AddBoolToObject(gaze, "trace_has_position", s->trace_has_position);
    cJSON_AddBoolToObject(gaze, "trace_has_gaze", s->trace_has_gaze);
    cJSON_AddNumberToObject(gaze, "eye_speed_degps_mean", s->eye_speed_degps_mean);
    cJSON_AddNumberToObject(root, "frames", (double)s->frames);
    cJSON_AddNumberToObject(root, "budget_ms", s->budget_ms);
    cJSON_AddNumberToObject(root, "frame_ms_mean", s->frame_ms_mean);
    if (isfinite(s->frame_ms_mean_after_first))
        cJSON_AddNumberToObject(root, "frame_ms_mean_after_first", s->frame_ms_mean_after_first);
    else
        cJSON_AddNullToObject(root, "frame_ms_mean_after_first");
    cJSON_AddNumberToObject(root, "frame_ms_max", s->frame_ms_max);
    cJSON_AddNumberToObject(root, "frame_ms_stddev", s->frame_ms_stddev);
    cJSON_AddNumberToObject(root, "frame_ms_median", s->frame_ms_median);
    cJSON_AddNumberToObject(root, "frame_ms_p95", s->frame_ms_p95);
    cJSON_AddNumberToObject(root, "frame_ms_p99", s->frame_ms_p99);
    cJSON_AddNumberToObject(root, "draw_ms_median", s->draw_ms_median);
    cJSON_AddNumberToObject(root, "draw_ms_mean", s->draw_ms_mean);
    cJSON_AddNumberToObject(root, "acuity_us_mean", s->acuity_us_mean);
    cJSON_AddNumberToObject(root, "select_us_mean", s->select_us_mean);
    cJSON_AddNumberToObject(root, "acuity_evaluations_mean", s->acuity_evaluations_mean);
    cJSON_AddNumberToObject(root, "visible_mean", s->visible_mean);
    cJSON_AddNumberToObject(root, "scene_instances", (double)s->scene_instances);
    cJSON_AddNumberToObject(root, "scene_groups", (double)s->scene_groups);
    cJSON_AddNumberToObject(root, "cull_groups_tested_mean", s->cull_groups_tested_mean);
    cJSON_AddNumberToObject(root, "cull_instances_tested_mean", s->cull_instances_tested_mean);
    if (s->vm_hwm_kib >= 0)
        cJSON_AddNumberToObject(root, "vm_hwm_kib", (double)s->vm_hwm_kib);
    else
        cJSON_AddNullToObject(root, "vm_hwm_kib");
    if (s->vm_rss_kib >= 0)
        cJSON_AddNumberToObject(root, "vm_rss_kib", (double)s->vm_rss_kib);
    else
        cJSON_AddNullToObject(root, "vm_rss_kib");
    cJSON_AddNumberToObject(root, "triangles_per_eye_mean", s->triangles_per_eye_mean);
    cJSON_AddNumberToObject(root, "triangles_relative_to_none", s->triangles_relative_to_none);
    cJSON_AddNumberToObject(root, "deadline_met_fraction", s->deadline_met_fraction);
    if (isfinite(s->minor_faults_per_frame))
        cJSON_AddNumberToObject(root, "minor_faults_per_frame", s->minor_faults_per_frame);
    else
        cJSON_AddNullToObject(root, "minor_faults_per_frame");
    cJSON_AddNumberToObject(root, "minor_faults_from_frame", (double)s->minor_faults_from_frame);
    cJSON_AddStringToObject(root, "cost_profile", s->cost_profile);
    cJSON_AddStringToObject(root, "cost_correction", s->cost_correction);
    if (isfinite(s->within_share))
        cJSON_AddNumberToObject(root, "within_share_target", s->within_share);
    else
        cJSON_AddNullToObject(root, "within_share_target");
    cJSON_AddNumberToObject(root, "rate_hz", s->rate_hz);
    cJSON_AddNumberToObject(root, "predicted_within_budget_fraction", s->predicted_within_fraction);
    cJSON_AddNumberToObject(root, "frame_ms_p99_share_of_budget", s->frame_ms_p99_share_of_budget);
    cJSON_AddNumberToObject(root, "frame_ms_stddev_share_of_budget", s->frame_ms_stddev_share_of_budget);
    cJSON_AddNumberToObject(root, "optimizer_truncated_fraction", s->truncated_fraction);
    cJSON_AddNumberToObject(root, "over_budget_fraction", s->over_budget_fraction);
    cJSON_AddNumberToObject(root, "dropped_mean", s->dropped_mean);
    cJSON *layers = cJSON_AddObjectToObject(root, "layers"); /* docs/replay-output.md "layers" */
    cJSON_AddStringToObject(layers, "foveation", s->foveation);
    cJSON *scales = cJSON_AddArrayToObject(layers, "frames_per_scale");
    for (int i = 0; i < FRM_LAYER_SCALES; ++i) {
        cJSON *e = cJSON_CreateObject();
        cJSON_AddNumberToObject(e, "scale", frm_layer_scales[i]);
        cJSON_AddNumberToObject(e, "frames", (double)s->scale_frames[i]);
        cJSON_AddItemToArray(scales, e);
    }
    cJSON_AddNumberToObject(layers, "lossy_frames", (double)s->lossy_frames);
    if (isfinite(s->inset_radius_deg_mean)) {
        cJSON_AddNumberToObject(layers, "inset_radius_deg_mean", s->inset_radius_deg_mean);
        cJSON_AddNumberToObject(layers, "composite_ms_mean", s->composite_ms_mean);
        cJSON_AddNumberToObject(layers, "scale_mean", s->scale_mean);
    } else {
        cJSON_AddNullToObject(layers, "inset_radius_deg_mean");
        cJSON_AddNullToObject(layers, "composite_ms_mean");
        cJSON_AddNullToObject(layers, "scale_mean");
    }
    cJSON_AddNumberToObject(root, "underused_drops", (double)s->underused_drops);
    cJSON_AddNumberToObject(root, "dropped_px_share_mean", s->dropped_px_share_mean);
    cJSON_AddNumberToObject(root, "dropped_px_share_max", s->dropped_px_share_max);
    cJSON_AddNumberToObject(root, "frame_ms_mean_share_of_budget", s->frame_ms_mean / s->budget_ms);
    cJSON_AddNumberToObject(root, "optimizer_us_mean", s->optimizer_us_mean);
    cJSON_AddNumberToObject(root, "optimizer_us_max", s->optimizer_us_max);
    cJSON_AddNumberToObject(root, "optimizer_iterations_mean", s->iterations_mean);
    cJSON_AddNumberToObject(root, "lod_changes_per_object_s", s->lod_changes_per_object_s);
    if (isfinite(s->benefit_share_of_lp_mean)) {
        cJSON_AddNumberToObject(root, "benefit_share_of_lp_mean", s->benefit_share_of_lp_mean);
        cJSON_AddNumberToObject(root, "benefit_share_of_lp_min", s->benefit_share_of_lp_min);
    } else {
        cJSON_AddNullToObject(root, "benefit_share_of_lp_mean");
        cJSON_AddNullToObject(root, "benefit_share_of_lp_min");
    }
    if (s->gaze_frames > 0) { /* saccades (frame/saccade_step.c): only when the trace has gaze */
        cJSON *sac = cJSON_AddObjectToObject(root, "saccades");
        cJSON_AddNumberToObject(sac, "count", (double)s->saccades);
        cJSON_AddNumberToObject(sac, "suppressed_frames", (double)s->suppressed_frames);
        cJSON_AddNumberToObject(sac, "suppressed_fraction", s->suppressed_fraction);
        cJSON_AddNumberToObject(sac, "refine_miss_frames", (double)s->refine_miss_frames);
        cJSON_AddNumberToObject(sac, "refine_missed_saccades", (double)s->refine_missed_saccades);
        cJSON_AddNumberToObject(sac, "refine_missed_saccade_fraction", s->refine_missed_saccade_fraction);
    }
    cJSON *vis = cJSON_AddObjectToObject(root, "visible_error"); /* predicted, every frame */
    cJSON_AddNumberToObject(vis, "mean", s->visible_error_mean);
    cJSON_AddNumberToObject(vis, "max", s->visible_error_max);
    add_image_error(root, s);
    cJSON *bands = cJSON_AddArrayToObject(root, "head_speed_bands");
    for (int b = 0; b < RPL_SPEED_BAND_COUNT; ++b) {
        cJSON *band = cJSON_CreateObject();
        cJSON_AddNumberToObject(band, "from_degps", rpl_speed_band_lower_degps[b]);
        cJSON_AddNumberToObject(band, "frames", (double)s->band_frames[b]);
        if (isfinite(s->band_triangle_share[b]))
            cJSON_AddNumberToObject(band, "triangle_share", s->band_triangle_share[b]);
        else
            cJSON_AddNullToObject(band, "triangle_share");
        cJSON_AddItemToArray(bands, band);
    }
    /* Where the triangles were kept, per object (docs/replay-output.md). */
    cJSON *kept = cJSON_AddObjectToObject(root, "triangles_by_band");
    add_band_array(kept, "eccentricity", "from_deg", rnd_ecc_band_lower_deg, "triangle_share", s->ecc_triangle_share,
                   RND_ECC_BANDS);
    add_band_array(kept, "retinal_speed", "from_degps", frm_retinal_band_lower_degps, "triangle_share",
                   s->retinal_triangle_share, FRM_RETINAL_BANDS);
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    if (!text)
        return hl_fail(err, "%s/summary.json: out of memory", dir);

    char path[4096];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    size_t n = strlen(text);
    text[n] = '\n'; /* cJSON's NUL becomes the final newline: the buffer is written by length */
    int rc = hl_out_open(out, path, err);
    if (rc == 0) {
        (void)fwrite(text, 1, n + 1, out->f); /* a failed write is the close's error, with its reason */
        rc = hl_out_close(out, err);
    }
    free(text);
    return rc;
}

static void print_image_error(FILE *f, const struct rpl_summary *s)
{
    fprintf(f, "  image error against full detail, %ld frames (%ld identical):\n", s->reference_frames,
            s->identical_frames);
    fprintf(f, "    %-32s %10.2f mean, %.2f min, %.2f p5 dB\n", "PSNR", s->psnr_db_mean, s->psnr_db_min,
            s->psnr_db_p5);
    fprintf(f, "    %-32s %10.4f mean, %.4f min, %.4f p5 (RGB %.4f)\n", "SSIM (luminance)", s->ssim_mean, s->ssim_min,
            s->ssim_p5, s->ssim_rgb_mean);
    fprintf(f, "    %-32s %10.4f mean, %.4f min, %.4f p5\n", "foveated SSIM (Reddy M(E))", s->fssim_mean,
            s->fssim_min, s->fssim_p5);
    fprintf(f, "    %-32s", "SSIM by eccentricity");
    for (int b = 0; b < RND_ECC_BANDS; ++b) {
        if (b + 1 < RND_ECC_BANDS)
            fprintf(f, "%s%g-%g deg %.4f", b ? ", " : " ", rnd_ecc_band_lower_deg[b], rnd_ecc_band_lower_deg[b + 1],
                    s->fssim_band_mean[b]);
        else
            fprintf(f, ", >= %g deg %.4f", rnd_ecc_band_lower_deg[b], s->fssim_band_mean[b]);
    }
    fprintf(f, "\n    %-32s %10.2f %%\n", "pixels off by > 32 levels", 100.0 * s->px_over_32_share_mean);
    fprintf(f, "    %-32s %10.4f\n", "predicted visible error (these)", s->visible_error_reference_mean);
    fprintf(f, "    %-32s %10.4f mean, %.4f worst frame, %.4f weighted median, %.4f worst pixel\n", "FLIP (LDR)",
            s->flip_mean, s->flip_mean_max, s->flip_median_mean, s->flip_max);
    fprintf(f, "    %-32s %10.2f\n", "  at pixels per degree", s->flip_ppd);
}

/* One line of the summary: the share of the finest triangles drawn per band ("—" for an empty band). */
static void print_triangle_bands(FILE *f, const char *what, const char *unit, const double *lower,
                                 const double *share, int count)
{
    fprintf(f, "  share of finest triangles drawn, by %s:", what);
    for (int b = 0; b < count; ++b) {
        char range[48], value[16];
        if (b + 1 < count)
            snprintf(range, sizeof range, "%g-%g %s", lower[b], lower[b + 1], unit);
        else
            snprintf(range, sizeof range, ">= %g %s", lower[b], unit);
        if (isfinite(share[b]))
            snprintf(value, sizeof value, "%.3f", share[b]);
        else
            snprintf(value, sizeof value, "—");
        fprintf(f, "%s %s %s", b ? "," : "", range, value);
    }
    fprintf(f, "\n");
}

void rpl_summary_print(FILE *f, const struct rpl_summary *s)
{
    fprintf(f, "\n%s on %s, selector %s, %ld frames (renderer: %s)\n", s->scene, s->display, s->selector,
            s->frames, s->renderer);
    fprintf(f, "  %-34s %10.3f ms; cost model: %s; correction %s", "budget", s->budget_ms, s->cost_profile,
            s->cost_correction);
    if (isfinite(s->within_share))
        fprintf(f, " (margin for %.3g %% within)", 100.0 * s->within_share);
    fputc('\n', f);
    if (strcmp(s->gaze, "vor") == 0)
        fprintf(f, "  %-34s %10s, fixation %.3g m, gain %.3g, latency %.3g ms\n", "gaze model", s->gaze,
                s->fixation_m, s->vor_gain, s->vor_latency_ms);
    else
        fprintf(f, "  %-34s %10s\n", "gaze model", s->gaze);
    if (s->trace_has_position)
        fprintf(f, "  %-34s %10s\n", "eyes", "the trace's positions");
    else
        fprintf(f, "  %-34s %10.1f forward, %.1f up (mm)\n", "eyes from the neck pivot", 1e3 * s->neck_to_eye_m[0],
                1e3 * s->neck_to_eye_m[1]);
    fprintf(f, "  %-34s %10.1f deg/s\n", "eye angular speed mean (world)", s->eye_speed_degps_mean);
    fprintf(f, "  %-34s %10.3f / %.3f / %.3f ms\n", "frame time mean / max / stddev", s->frame_ms_mean,
            s->frame_ms_max, s->frame_ms_stddev);
    fprintf(f, "  %-34s %10.3f / %.3f / %.3f ms\n", "frame time median / p95 / p99", s->frame_ms_median,
            s->frame_ms_p95, s->frame_ms_p99);
    fprintf(f, "  %-34s %10.3f / %.3f ms\n", "draw time mean / median (both eyes)", s->draw_ms_mean,
            s->draw_ms_median);
    fprintf(f, "  %-34s %10.1f us\n", "cull + viewing geometry mean", s->acuity_us_mean);
    fprintf(f, "  %-34s %10.1f us\n", "selection mean", s->select_us_mean);
    fprintf(f, "  %-34s %10.1f of %.1f visible\n", "acuity model evaluations / frame", s->acuity_evaluations_mean,
            s->visible_mean);
    fprintf(f, "  %-34s %10.1f groups, %.1f objects\n", "cull sphere tests / frame", s->cull_groups_tested_mean,
            s->cull_instances_tested_mean);
    fprintf(f, "  %-34s %10.0f\n", "triangles per eye mean", s->triangles_per_eye_mean);
    fprintf(f, "  %-34s %10.3f\n", "triangles relative to none", s->triangles_relative_to_none);
    fprintf(f, "  %-34s %10.1f %%\n", "frames within the budget", 100.0 * s->deadline_met_fraction);
    fprintf(f, "  %-34s %10.1f %%\n", "frames predicted within the budget", 100.0 * s->predicted_within_fraction);
    fprintf(f, "  %-34s %10.1f / %.1f %% of the budget\n", "frame time p99 / stddev", 100.0 * s->frame_ms_p99_share_of_budget,
            100.0 * s->frame_ms_stddev_share_of_budget);
    fprintf(f, "  %-34s %10.3f\n", "LOD changes per object per second", s->lod_changes_per_object_s);
    if (s->iterations_mean > 0.0 || s->optimizer_us_mean > 0.0)
        fprintf(f, "  %-34s %10.1f / %.1f us, %.1f iterations, %.1f %% truncated, %.1f %% over budget\n",
                "optimizer mean / max", s->optimizer_us_mean, s->optimizer_us_max, s->iterations_mean,
                100.0 * s->truncated_fraction, 100.0 * s->over_budget_fraction);
    if (s->iterations_mean > 0.0 || s->optimizer_us_mean > 0.0) {
        fprintf(f, "  %-34s %10.1f %% of the budget\n", "frame time mean", 100.0 * s->frame_ms_mean / s->budget_ms);
        fprintf(f, "  %-34s %10.1f of %.1f visible; %.2f %% of their pixels mean, %.2f %% max\n",
                "objects dropped / frame", s->dropped_mean, s->visible_mean, 100.0 * s->dropped_px_share_mean,
                100.0 * s->dropped_px_share_max);
        fprintf(f, "  %-34s %10ld frames\n", "dropped while 30 % stayed unused", s->underused_drops);
    }
    if (strcmp(s->foveation, "off") != 0) {
        char used[160] = "";
        size_t len = 0;
        for (int i = 0; i < FRM_LAYER_SCALES; ++i)
            if (s->scale_frames[i] > 0 && len < sizeof used)
                len += (size_t)snprintf(used + len, sizeof used - len, "%s%g: %ld", len ? ", " : "", frm_layer_scales[i],
                                        s->scale_frames[i]);
        fprintf(f, "  %-34s %10s; frames per periphery scale %s\n", "foveated layers", s->foveation, used);
        if (isfinite(s->inset_radius_deg_mean))
            fprintf(f, "  %-34s %10.1f deg inset mean, scale %.3f mean, %ld frames lossy, composite %.2f ms (not in "
                       "the frame time)\n",
                    "layered frames", s->inset_radius_deg_mean, s->scale_mean, s->lossy_frames, s->composite_ms_mean);
    }
    if (isfinite(s->benefit_share_of_lp_mean))
        fprintf(f, "  %-34s %10.4f mean, %.4f min\n", "benefit / LP bound", s->benefit_share_of_lp_mean,
                s->benefit_share_of_lp_min);
    if (s->vm_hwm_kib >= 0 && s->vm_rss_kib >= 0)
        fprintf(f, "  %-34s %10.1f / %.1f MiB\n", "resident memory peak / at the end", s->vm_hwm_kib / 1024.0,
                s->vm_rss_kib / 1024.0);
    if (isfinite(s->minor_faults_per_frame)) /* fresh pages cost time the frame pays (docs/replay-output.md) */
        fprintf(f, "  %-34s %10.1f (steady state: frames %ld on)\n", "minor page faults / frame",
                s->minor_faults_per_frame, s->minor_faults_from_frame);
    if (s->gaze_frames > 0) { /* saccades (frame/saccade_step.c): only when the trace has gaze */
        fprintf(f, "  %-34s %10ld, %.1f %% of frames suppressed\n", "saccades", s->saccades,
                100.0 * s->suppressed_fraction);
        fprintf(f, "  %-34s %10ld frames, %ld saccades (%.1f %%)\n", "refinements missing 28 ms", s->refine_miss_frames,
                s->refine_missed_saccades, 100.0 * s->refine_missed_saccade_fraction);
    }
    if (!strcmp(s->visibility, "contrast"))
        fprintf(f, "  %-34s %10s (%s CSF, k %g; adapting %.1f cd/m2 mean, %.1f … %.1f)\n", "visibility", "contrast",
                s->csf, s->csf_scale, s->adapting_luminance_cdm2_mean, s->adapting_luminance_cdm2_min,
                s->adapting_luminance_cdm2_max);
    else
        fprintf(f, "  %-34s %10s (Reddy's H(v, E) at full contrast)\n", "visibility", s->visibility);
    fprintf(f, "  %-34s %10.4f mean, %.4f max\n", "predicted visible error", s->visible_error_mean,
            s->visible_error_max);
    if (s->reference_frames > 0)
        print_image_error(f, s);
    fprintf(f, "  share of finest triangles drawn, by head speed:\n");
    for (int b = 0; b < RPL_SPEED_BAND_COUNT; ++b) {
        if (s->band_frames[b] == 0)
            continue;
        char label[64];
        if (b + 1 < RPL_SPEED_BAND_COUNT)
            snprintf(label, sizeof label, "%g-%g deg/s", rpl_speed_band_lower_degps[b], rpl_speed_band_lower_degps[b + 1]);
        else
            snprintf(label, sizeof label, ">= %g deg/s", rpl_speed_band_lower_degps[b]);
        fprintf(f, "    %-32s %10.3f  (%ld frames)\n", label, s->band_triangle_share[b], s->band_frames[b]);
    }
    print_triangle_bands(f, "eccentricity", "deg", rnd_ecc_band_lower_deg, s->ecc_triangle_share, RND_ECC_BANDS);
    print_triangle_bands(f, "retinal speed", "deg/s", frm_retinal_band_lower_degps, s->retinal_triangle_share,
                         FRM_RETINAL_BANDS);
}
