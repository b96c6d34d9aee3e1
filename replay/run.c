/* The replay driver: a head-motion trace on a virtual clock at the display's refresh, through a
 * scene, into per-frame CSV, a summary, and PNG captures. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "replay/run_internal.h"

void rpl_options_defaults(struct rpl_options *o)
{
    memset(o, 0, sizeof *o);
    frm_options_defaults(&o->frame);
}

int rpl_options_check(const struct rpl_options *o, int need_out_dir, enum frm_selector *selector,
                      enum frm_freq_reading *reading, struct hl_error *err)
{
    if (frm_options_check(&o->frame, selector, reading, err) != 0)
        return -1;
    if (need_out_dir && (!o->out_dir || !*o->out_dir))
        return hl_fail(err, "--out: an output folder is required");
    if (o->rate_hz < 0.0 || !isfinite(o->rate_hz) || (o->rate_hz > 0.0 && o->rate_hz < 1.0) || o->rate_hz > 10000.0)
        return hl_fail(err, "--rate: %g Hz is outside [1, 10000]", o->rate_hz);
    if (o->frames < 0 || o->capture_every < 0 || o->reference_every < 0)
        return hl_fail(err, "--frames, --capture and --reference must be >= 0");
    if (o->frames > RPL_MAX_FRAMES)
        return hl_fail(err, "--frames: %ld is more than the %ld frames a replay holds", o->frames, (long)RPL_MAX_FRAMES);
    return 0;
}

/* The options' trace (a raw recording, a trace file or the built-in clip) as the session's source,
 * opened after the display and before the scene (frm_session_open_display, _scene). */
static int open_trace(struct frm_session *s, const struct rpl_options *o, struct hl_error *err)
{
    struct rpl_trace trace;
    int rc = o->raw_path     ? rpl_trace_from_recording(o->raw_path, &trace, err)
             : o->trace_path ? rpl_trace_load(o->trace_path, &trace, err)
                             : rpl_trace_builtin_clip(&trace, err);
    if (rc != 0)
        return -1;
    const struct rpl_trace_report *tr = &trace.report;
    if (o->trace_path && (tr->repeated_timestamps || tr->low_confidence_gaze || tr->placeholder_rows ||
                          tr->held_orientations || tr->speed_outliers)) {
        /* What loading had to do to a file is said once, not silently (docs/trace-format.md). */
        char line[512];
        rpl_trace_report_format(tr, line, sizeof line);
        fprintf(stderr, "hmdlod: note: %s: %s\n", o->trace_path, line);
    }
    s->trace_has_gaze = trace.gaze_dir != NULL;
    s->trace_has_position = trace.position_m != NULL;
    return rpl_trace_source_create(&trace, &s->source, err);
}

/* The session of a replay: display, then the trace, then the rest. */
static int open_session(struct frm_session *s, const struct rpl_options *o, struct hl_error *err)
{
    struct frm_options fo = o->frame;
    fo.source_name = o->raw_path ? o->raw_path : o->trace_path ? o->trace_path : "the built-in clip";
    if (frm_session_open_display(s, &fo, NULL, err) != 0 || open_trace(s, o, err) != 0)
        return -1;
    return frm_session_open_scene(s, &fo, err);
}

static double wall_clock_unix_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int make_dirs(const char *dir, struct hl_error *err)
{
    char path[4096];
    if (snprintf(path, sizeof path, "%s", dir) >= (int)sizeof path)
        return hl_fail(err, "%s: path too long", dir);
    for (char *p = path + 1;; ++p) {
        if (*p == '/' || *p == '\0') {
            char c = *p;
            *p = '\0';
            if (mkdir(path, 0777) != 0 && errno != EEXIST)
                return hl_fail(err, "%s: cannot create folder: %s", path, strerror(errno));
            *p = c;
            if (c == '\0')
                break;
        }
    }
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return hl_fail(err, "%s: not a folder", dir);
    return 0;
}

static int write_png(struct frm_session *s, const uint8_t *rgba, const char *dir, long frame, const char *suffix,
                     struct hl_error *err)
{
    int w, h;
    rnd_renderer_size(s->renderer, &w, &h);
    char path[4096];
    snprintf(path, sizeof path, "%s/frame_%06ld%s.png", dir, frame, suffix);
    return rnd_png_write(path, rgba, w, h, err);
}

static int capture_frame(struct frm_session *s, uint8_t *rgba, const char *dir, long frame, struct hl_error *err)
{
    if (rnd_renderer_read_rgba(s->renderer, rgba, err) != 0)
        return -1;
    return write_png(s, rgba, dir, frame, "", err);
}

/* The frame count as a double first: a trace spanning 1e300 s, or a refresh of 1e308 Hz, must be an
 * error here, not a conversion whose result C leaves undefined (it came out negative, and the replay
 * wrote no rows and exited 0). */
static int frame_count(const struct rpl_options *o, const struct trk_pose_source *src, double rate_hz, long *out,
                       struct hl_error *err)
{
    const char *what = o->raw_path ? o->raw_path : o->trace_path ? o->trace_path : "the built-in clip";
    double span_s = src->end_time_s - src->start_time_s;
    double frames_d = floor(span_s * rate_hz + 1e-9) + 1.0;
    if (!(rate_hz > 0.0) || !isfinite(frames_d) || frames_d < 1.0 || frames_d > (double)RPL_MAX_FRAMES)
        return hl_fail(err, "%s: %.9g s at %.9g Hz is %.6g frames; a replay holds 1 to %ld", what, span_s, rate_hz,
                       frames_d, (long)RPL_MAX_FRAMES);
    long available = (long)frames_d;
    *out = available;
    if (o->frames == 0)
        return 0;
    if (o->frames > available)
        fprintf(stderr, "hmdlod: note: the trace covers %ld frames at %.6g Hz; replaying %ld holds its last pose\n",
                available, rate_hz, o->frames);
    *out = o->frames;
    return 0;
}

int rpl_run(const struct rpl_options *o, struct rpl_summary *summary, struct hl_error *err)
{
    struct frm_session s;
    memset(&s, 0, sizeof s);
    memset(summary, 0, sizeof *summary);
    struct rpl_output out;
    memset(&out, 0, sizeof out);
    struct hl_out summary_out;
    memset(&summary_out, 0, sizeof summary_out);
    struct rpl_accumulator acc;
    memset(&acc, 0, sizeof acc);
    uint8_t *rgba = NULL, *ref_rgba = NULL;
    struct rnd_image_error_work *image_work = NULL;
    int rc = -1;

    /* The inputs (trace, scene, display) are opened before the output folder is made, so bad input
     * leaves no empty folder behind. */
    if (rpl_options_check(o, 1, &s.selector, &s.reading, err) != 0 || open_session(&s, o, err) != 0 ||
        make_dirs(o->out_dir, err) != 0)
        goto done;
    double rate_hz = o->rate_hz > 0.0 ? o->rate_hz : s.display.refresh_hz;
    long frames = 0;
    if (frame_count(o, s.source, rate_hz, &frames, err) != 0)
        goto done;
    if (o->capture_every > 0 || o->reference_every > 0) {
        int w, h;
        rnd_renderer_size(s.renderer, &w, &h);
        rgba = malloc((size_t)w * (size_t)h * 4);
        if (!rgba) {
            hl_fail(err, "out of memory for captures");
            goto done;
        }
        if (o->reference_every > 0 && ((ref_rgba = malloc((size_t)w * (size_t)h * 4)) == NULL ||
                                       rnd_image_error_work_create(w, h, &image_work, err) != 0)) {
            if (!ref_rgba)
                hl_fail(err, "out of memory for reference frames");
            goto done;
        }
    }
    if (rpl_output_open(&out, o->out_dir, s.max_lods, err) != 0)
        goto done;

    long references = o->reference_every > 0 ? (frames - 1) / o->reference_every + 1 : 0;
    if (rpl_accumulator_init(&acc, frames, references, err) != 0)
        goto done;
    struct hl_progress progress;
    hl_progress_begin(&progress, "replay", (uint64_t)frames);
    summary->wall_start_unix_s = wall_clock_unix_s();
    for (long f = 0; f < frames; ++f) {
        /* Virtual clock: frame f is displayed at start + f / rate, whatever the wall clock did. */
        double t_s = s.source->start_time_s + (double)f / rate_hz;
        struct frm_frame_record rec;
        if (frm_frame_run(&s, f, t_s, &rec, err) != 0)
            goto done;
        int captured = o->capture_every > 0 && f % o->capture_every == 0;
        if (captured && capture_frame(&s, rgba, o->out_dir, f, err) != 0)
            goto done;
        if (o->reference_every > 0 && f % o->reference_every == 0) {
            if (frm_frame_reference(&s, &rec, rgba, captured, ref_rgba, image_work, err) != 0)
                goto done;
            /* A captured frame gets its reference beside it, for the eye to compare. */
            if (captured && write_png(&s, ref_rgba, o->out_dir, f, "_reference", err) != 0)
                goto done;
        }
        rpl_output_row(&out, &rec, s.max_lods);
        if (rpl_output_failed(&out)) { /* disk full: the commit names the file and why, and keeps none */
            (void)rpl_output_commit(&out, err);
            goto done;
        }
        rpl_accumulate(&acc, &rec);
        hl_progress_update(&progress, (uint64_t)f + 1);
    }
    hl_progress_end(&progress);
    summary->wall_end_unix_s = wall_clock_unix_s();
    if (gethostname(summary->host, sizeof summary->host) != 0)
        summary->host[0] = '\0';
    summary->host[sizeof summary->host - 1] = '\0'; /* POSIX leaves a truncated name unterminated */
    if (rpl_output_close(&out, err) != 0)
        goto done;

    rpl_accumulator_finish(&acc, summary);
    summary->budget_ms = s.select.budget_ms;
    summary->rate_hz = rate_hz;
    summary->lod_changes_per_object_s *= rate_hz;
    summary->frame_ms_p99_share_of_budget = summary->frame_ms_p99 / summary->budget_ms;
    summary->frame_ms_stddev_share_of_budget = summary->frame_ms_stddev / summary->budget_ms;
    snprintf(summary->cost_profile, sizeof summary->cost_profile, "%s", s.cost_label);
    snprintf(summary->cost_correction, sizeof summary->cost_correction, "%s",
             s.select.correct == FRM_CORRECTION_AFFINE ? "affine" : s.select.correct == FRM_CORRECTION_RATIO ? "ratio" : "off");
    summary->within_share = s.select.correct == FRM_CORRECTION_AFFINE ? s.select.rls.within_share : NAN;
    snprintf(summary->renderer, sizeof summary->renderer, "%s", rnd_renderer_name(s.renderer));
    snprintf(summary->selector, sizeof summary->selector, "%s", o->frame.selector);
    snprintf(summary->scene, sizeof summary->scene, "%s", o->frame.scene);
    summary->scene_instances = s.scene.instance_count;
    summary->scene_groups = s.scene.group_count;
    rpl_resident_memory(&summary->vm_hwm_kib, &summary->vm_rss_kib);
    snprintf(summary->display, sizeof summary->display, "%s", s.display.name);
    snprintf(summary->gaze, sizeof summary->gaze, "%s", acu_gaze_model_name(s.gaze));
    snprintf(summary->foveation, sizeof summary->foveation, "%s", frm_foveation_name(s.layers.mode));
    snprintf(summary->visibility, sizeof summary->visibility, "%s", frm_visibility_name(s.visibility.criterion));
    snprintf(summary->csf, sizeof summary->csf, "%s", acu_csf_model_name(s.visibility.csf));
    summary->csf_scale = o->frame.csf_scale;
    snprintf(summary->benefit, sizeof summary->benefit, "%s", s.select.perceptual_benefit ? "perceptual" : "funkhouser");
    summary->peak_luminance_cdm2 = s.visibility.peak_luminance_cdm2;
    summary->csf_table_refills = s.visibility.refills;
    summary->fixation_m = s.vor.fixation_m;
    summary->vor_gain = s.vor.gain;
    summary->vor_latency_ms = s.vor.latency_s * 1e3;
    summary->neck_to_eye_m[0] = s.display.neck_to_eye_m[0];
    summary->neck_to_eye_m[1] = s.display.neck_to_eye_m[1];
    summary->trace_has_position = s.trace_has_position;
    summary->trace_has_gaze = s.trace_has_gaze;
    /* Both files complete on disk before either is renamed: a full disk leaves the previous pair. */
    if (rpl_summary_stage_json(o->out_dir, summary, &summary_out, err) != 0 || rpl_output_commit(&out, err) != 0 ||
        hl_out_commit(&summary_out, err) != 0)
        goto done;
    rc = 0;
    if (rc == 0 && !o->frame.quiet)
        rpl_summary_print(stdout, summary);
done:
    rpl_accumulator_free(&acc);
    rpl_output_abort(&out);
    hl_out_abort(&summary_out);
    free(rgba);
    free(ref_rgba);
    rnd_image_error_work_destroy(image_work);
    frm_session_close(&s);
    return rc;
}
