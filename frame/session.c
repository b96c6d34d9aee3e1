/* A session's state, opened once: display, the pose source its runner hands in, scene and its
 * measured tables, selector and cost model, renderer. Shared by replay, live and the benches. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <sys/stat.h>

#include "frame/frame.h"

void frm_options_defaults(struct frm_options *o)
{
    memset(o, 0, sizeof *o);
    o->scene = "field";
    o->display = "vive";
    o->selector = "reddy";
    o->frequency_reading = "narrow"; /* docs/analysis.md: why narrow */
    o->object_count = 0; /* each scene's own default: field 100 objects, domes 10 */
    o->seed = 1;
    o->acuity_scale = 1.0;
    o->visibility = "contrast"; /* docs/visibility.md */
    o->csf = "castle";
    o->csf_scale = FRM_CSF_SCALE_DEFAULT;
    o->render_scale = 1.0;
    o->static_px_per_triangle = 64.0;
    o->cost_correction = FRM_CORRECTION_AFFINE;
    o->gaze = "auto";
    o->vor_gain = -1.0;
    o->vor_latency_ms = -1.0;
    o->foveation = "off";
    o->inset_deg = -1.0; /* the resolution ceiling's */
}

int frm_scene_is_file(const char *scene)
{
    size_t len = scene ? strlen(scene) : 0;
    struct stat st;
    return (len > 5 && strcmp(scene + len - 5, ".json") == 0) || (len > 0 && stat(scene, &st) == 0 && S_ISREG(st.st_mode));
}

int frm_options_check(const struct frm_options *o, enum frm_selector *selector, enum frm_freq_reading *reading,
                      struct hl_error *err)
{
    if (frm_freq_reading_parse(o->frequency_reading ? o->frequency_reading : "narrow", reading, err) != 0)
        return -1;
    if (frm_selector_parse(o->selector, selector, err) != 0)
        return -1;
    if (o->budget_ms < 0.0 || !isfinite(o->budget_ms) || o->budget_ms > 10000.0)
        return hl_fail(err, "--budget-ms: %g ms is outside (0, 10000]", o->budget_ms);
    if (o->opt_limit_us < 0.0 || !isfinite(o->opt_limit_us) || o->opt_limit_us > 1e7)
        return hl_fail(err, "--opt-limit-us: %g us is outside [0, 1e7]", o->opt_limit_us);
    if (!(o->static_px_per_triangle > 0.0) || !isfinite(o->static_px_per_triangle))
        return hl_fail(err, "--static-px: %g is not a positive number of pixels", o->static_px_per_triangle);
    if (!(o->within_share == 0.0 || (o->within_share > 0.5 && o->within_share < 1.0)))
        return hl_fail(err, "--within-share: %g is not a share in (0.5, 1)", o->within_share);
    if (!(o->acuity_scale > 0.0 && o->acuity_scale <= 1.0))
        return hl_fail(err, "--acuity-scale: %g is outside (0, 1]", o->acuity_scale);
    enum frm_visibility_criterion criterion;
    enum acu_csf_model csf;
    if (frm_visibility_options(o, &criterion, &csf, err) != 0)
        return -1;
    int perceptual;
    if (frm_benefit_parse(o->benefit, &perceptual, err) != 0)
        return -1;
    if (perceptual && criterion != FRM_VISIBILITY_CONTRAST)
        return hl_fail(err, "--benefit perceptual values levels by their visible contrast: it needs --visibility contrast");
    if (!(o->render_scale > 0.0 && o->render_scale <= 4.0))
        return hl_fail(err, "--render-scale: %g is outside (0, 4]", o->render_scale);
    enum acu_gaze_model model;
    if (o->gaze && strcmp(o->gaze, "auto") != 0 && acu_gaze_model_parse(o->gaze, &model) != 0)
        return hl_fail(err, "--gaze: '%s' is not a gaze model (auto, head, vor, tracked)", o->gaze);
    if (!(o->vor_gain <= 1.2) || !isfinite(o->vor_gain))
        return hl_fail(err, "--vor-gain: %g is outside [0, 1.2]", o->vor_gain);
    if (!(o->vor_latency_ms <= 100.0) || !isfinite(o->vor_latency_ms))
        return hl_fail(err, "--vor-latency-ms: %g ms is outside [0, 100]", o->vor_latency_ms);
    if (!(o->fixation_m <= 1e6) || isnan(o->fixation_m))
        return hl_fail(err, "--fixation-m: %g m is outside (0, 1e6]", o->fixation_m);
    return frm_layers_options_check(o, err);
}

int frm_layers_options_check(const struct frm_options *o, struct hl_error *err)
{
    enum frm_foveation_mode mode;
    if (frm_foveation_parse(o->foveation, &mode, err) != 0)
        return -1;
    int known = o->periphery_scale == 0.0;
    for (int i = 0; i < FRM_LAYER_SCALES; ++i)
        known |= o->periphery_scale == frm_layer_scales[i];
    if (!known)
        return hl_fail(err, "--periphery-scale: %g is not one of 1, 0.75, 0.5, 0.35, 0.25", o->periphery_scale);
    if (isnan(o->inset_deg) || o->inset_deg > 60.0)
        return hl_fail(err, "--inset-deg: %g is outside [0, 60]", o->inset_deg);
    if (!(o->blend_deg >= 0.0 && o->blend_deg <= 20.0))
        return hl_fail(err, "--blend-deg: %g is outside (0, 20]", o->blend_deg);
    if ((mode == FRM_FOVEATION_OFF || mode == FRM_FOVEATION_ADAPTIVE) &&
        (o->periphery_scale != 0.0 || o->inset_deg >= 0.0 || o->blend_deg != 0.0))
        return hl_fail(err, "--periphery-scale, --inset-deg and --blend-deg need --foveation fixed or gaze (%s "
                            "has no inset%s)", frm_foveation_name(mode),
                       mode == FRM_FOVEATION_ADAPTIVE ? ", and its controller sets the scale" : "");
    return 0;
}

/* The VOR's default fixation distance: the median distance from the first frame's eye to the
 * instances' bounding spheres (0 inside one), clamped to [0.5, 50] m — a viewer fixates what the
 * scene holds, neither the headset's lens nor the horizon. Computed once at load. */
static int scene_fixation_m(const struct scn_scene *scene, hl_vec3d eye_m, double *out, struct hl_error *err)
{
    uint32_t n = scene->instance_count;
    *out = 50.0;
    if (n == 0)
        return 0;
    double *d = malloc((size_t)n * sizeof *d);
    if (!d)
        return hl_fail(err, "out of memory for the fixation distance of %u objects", n);
    for (uint32_t i = 0; i < n; ++i) {
        const double *c = &scene->center_m[3 * i];
        double r = hl_v3_length(hl_v3_sub(hl_v3(c[0], c[1], c[2]), eye_m)) - scene->radius_m[i];
        d[i] = r > 0.0 ? r : 0.0;
    }
    hl_sort_doubles(d, n);
    double median = n % 2 ? d[n / 2] : 0.5 * (d[n / 2 - 1] + d[n / 2]);
    free(d);
    *out = fmin(fmax(median, 0.5), 50.0);
    return 0;
}

/* The model: auto is tracked when the trace has gaze, else vor; tracked without gaze is refused
 * before the scene is built. */
static int session_gaze_model(struct frm_session *s, const struct frm_options *o, struct hl_error *err)
{
    if (!o->gaze || strcmp(o->gaze, "auto") == 0)
        s->gaze = s->trace_has_gaze ? ACU_GAZE_TRACKED : ACU_GAZE_VOR;
    else if (acu_gaze_model_parse(o->gaze, &s->gaze) != 0)
        return hl_fail(err, "--gaze: '%s' is not a gaze model (auto, head, vor, tracked)", o->gaze);
    if (s->gaze == ACU_GAZE_TRACKED && !s->trace_has_gaze)
        return hl_fail(err, "--gaze tracked: %s has no gaze columns (use --gaze vor or head)",
                       o->source_name ? o->source_name : "the pose source");
    return 0;
}

/* The VOR's parameters and the eyes' offset; needs the source and the scene. */
static int session_gaze_params(struct frm_session *s, const struct frm_options *o, struct hl_error *err)
{
    s->neck_to_eye_head_m = hmd_neck_to_eye_head(&s->display);
    struct trk_pose start;
    struct acu_head_state head;
    if (frm_frame_head_state(s, s->source->start_time_s, &start, &head, err) != 0)
        return -1;
    double fixation_m = o->fixation_m;
    if (!(fixation_m > 0.0) && scene_fixation_m(&s->scene, head.eye_position_m, &fixation_m, err) != 0)
        return -1;
    acu_vor_params_default(&s->vor, fixation_m);
    if (o->vor_gain >= 0.0)
        s->vor.gain = o->vor_gain;
    if (o->vor_latency_ms >= 0.0)
        s->vor.latency_s = o->vor_latency_ms * 1e-3;
    return 0;
}

int frm_session_open_display(struct frm_session *s, const struct frm_options *o, const struct frm_session_made *made,
                             struct hl_error *err)
{
    if (made) { /* adopted now, so that frm_session_close closes them even when opening fails */
        s->source = made->source;
        s->renderer = made->renderer;
    }
    if (hmd_profile_load(o->display, &s->display, err) != 0)
        return -1;
    s->eyes[0] = hmd_eye_frustum(&s->display, HMD_EYE_LEFT);
    s->eyes[1] = hmd_eye_frustum(&s->display, HMD_EYE_RIGHT);
    s->near_m = 0.05;
    frm_cull_frustum_init(&s->cull_frustum, &s->display, s->near_m);
    acu_limits_init(&s->limits, hmd_compute_xi(&s->display).used_cpd, o->acuity_scale);
    s->limits.use_velocity = !o->velocity_term_off; /* bench gaze: the velocity term's saving */
    s->limits.use_eccentricity = !o->eccentricity_term_off;
    if (frm_visibility_open(&s->visibility, o, &s->display, &s->limits, err) != 0)
        return -1;
    s->far_m = 2000.0;
    return 0;
}

int frm_session_open_scene(struct frm_session *s, const struct frm_options *o, struct hl_error *err)
{
    if (!s->source)
        return hl_fail(err, "frame: a session needs a pose source");
    if (session_gaze_model(s, o, err) != 0)
        return -1;

    if (frm_scene_is_file(o->scene)) {
        /* The resolver turns each mesh entry into a lodset: by default the cached one, which keeps
         * mesh files' chains in the cache (frame/asset_resolver.c); a caller may pass its own. */
        if (scn_scenefile_load(o->scene, o->resolver ? o->resolver : frm_cached_resolver(), &s->scene, err) != 0)
            return -1;
    } else {
        struct scn_scene_params params = {.object_count = o->object_count, .seed = o->seed};
        if (scn_scene_build(o->scene, &params, &s->scene, err) != 0)
            return -1;
    }
    if (scn_culler_init(&s->culler, &s->scene, err) != 0 || session_gaze_params(s, o, err) != 0)
        return -1;
    /* The measured tables (cached after the first run); selector none and the geometric reading
     * never read them. */
    if (s->selector != FRM_SELECT_NONE &&
        (s->reading != FRM_READING_GEOMETRIC || s->visibility.criterion == FRM_VISIBILITY_CONTRAST)) {
        struct rnd_analyze_params ap;
        frm_assets_params(&ap);
        struct frm_assets_report ar;
        if (frm_assets_prepare(&s->scene, &ap, s->reading, &ar, err) != 0)
            return -1;
        if (ar.chains_analysed > 0 && !o->quiet)
            fprintf(stderr, "hmdlod: analysed %u chain%s of %s (%d views, %d px) in %.2f s%s\n", ar.chains_analysed,
                    ar.chains_analysed == 1 ? "" : "s", o->scene, ap.views, ap.size_px, ar.analysis_s,
                    ar.cache_unwritable ? "" : "; cached for later runs");
    }
    uint32_t n = s->scene.instance_count;
    s->chains = calloc(s->scene.chain_count, sizeof *s->chains);
    s->arrays.visible = calloc(n ? n : 1, sizeof *s->arrays.visible);
    s->arrays.eccentricity_deg = calloc(n ? n : 1, sizeof(double));
    s->arrays.velocity_degps = calloc(n ? n : 1, sizeof(double));
    s->arrays.diameter_deg = calloc(n ? n : 1, sizeof(double));
    s->arrays.lod = calloc(n ? n : 1, 1);
    s->arrays.draw_index = calloc((size_t)n + s->scene.group_count + 1, sizeof(uint32_t));
    s->arrays.draw_lod = calloc((size_t)n + s->scene.group_count + 1, 1);
    if (!s->chains || !s->arrays.visible || !s->arrays.eccentricity_deg || !s->arrays.velocity_degps ||
        !s->arrays.diameter_deg || !s->arrays.lod || !s->arrays.draw_index || !s->arrays.draw_lod)
        return hl_fail(err, "scene '%s': out of memory for %u objects", o->scene, n);
    for (uint32_t c = 0; c < s->scene.chain_count; ++c) {
        const struct scn_chain *chain = &s->scene.chains[c];
        s->chains[c].lod_count = chain->lod_count;
        for (int k = 0; k < chain->lod_count; ++k)
            s->chains[c].unique_freq_cpdiam[k] = chain->lods[k].unique_freq_cpdiam;
        /* The lost-contrast spectrum, when the analysis measured one (frame/assets.c). */
        s->chains[c].band_count = chain->contrast_band_count < LOD_MAX_BANDS ? chain->contrast_band_count : LOD_MAX_BANDS;
        for (int k = 0; k < chain->lod_count && k < LOD_MAX_LEVELS; ++k)
            for (int b = 0; b < s->chains[c].band_count; ++b)
                s->chains[c].lost_contrast[k][b] = chain->lods[k].lost_contrast[b];
        if (chain->lod_count > s->max_lods)
            s->max_lods = chain->lod_count;
    }

    s->select.selector = s->selector;
    s->select.budget_ms = o->budget_ms > 0.0 ? o->budget_ms : 1000.0 / s->display.refresh_hz;
    s->select.opt_limit_us = o->opt_limit_us;
    s->select.static_px = o->static_px_per_triangle;
    s->select.correct = o->cost_correction;
    s->select.mb_simplify = o->mb_simplify;
    if (frm_benefit_parse(o->benefit, &s->select.perceptual_benefit, err) != 0)
        return -1;
    s->select.saccade_onset_degps = o->saccade_onset_degps; /* frame/saccade_step.c */
    s->select.saccade_off = s->gaze != ACU_GAZE_TRACKED; /* head, vor: no eye tracker, no saccades known */
    struct frm_layer_costs layer_costs;
    if (frm_cost_model_load(o->cost_profile, &s->select.cost, &layer_costs, s->cost_label,
                            sizeof s->cost_label, err) != 0 ||
        frm_select_init(&s->select, &s->scene, err) != 0)
        return -1;
    if (o->within_share > 0.0) /* 0: the default; the range was checked (frm_options_check) */
        s->select.rls.within_share = o->within_share;
    enum frm_foveation_mode foveation;
    if (frm_foveation_parse(o->foveation, &foveation, err) != 0 ||
        frm_layers_init(&s->layers, foveation, o->blend_deg, o->periphery_scale, o->inset_deg, n,
                        s->scene.group_count, err) != 0)
        return -1;
    s->layers.cost = layer_costs;
    s->layers.costed = 1;
    s->select.layers = &s->layers;

    int eye_w = (int)lround(s->display.eye_width_px * o->render_scale);
    int eye_h = (int)lround(s->display.eye_height_px * o->render_scale);
    if (!s->renderer && rnd_renderer_create(eye_w > 0 ? eye_w : 1, eye_h > 0 ? eye_h : 1, &s->renderer, err) != 0)
        return -1;
    if (rnd_renderer_upload_scene(s->renderer, &s->scene, err) != 0)
        return -1;
    return frm_frame_warm_up(s, err);
}

int frm_session_open(struct frm_session *s, const struct frm_options *o, const struct frm_session_made *made,
                     struct hl_error *err)
{
    if (frm_session_open_display(s, o, made, err) != 0)
        return -1;
    return frm_session_open_scene(s, o, err);
}

void frm_session_close(struct frm_session *s)
{
    if (s->renderer)
        rnd_renderer_destroy(s->renderer);
    trk_source_destroy(s->source);
    scn_culler_free(&s->culler);
    scn_scene_free(&s->scene);
    frm_visibility_close(&s->visibility);
    free(s->chains);
    free(s->arrays.visible);
    free(s->arrays.eccentricity_deg);
    free(s->arrays.velocity_degps);
    free(s->arrays.diameter_deg);
    free(s->arrays.lod);
    free(s->arrays.draw_index);
    free(s->arrays.draw_lod);
    frm_select_free(&s->select);
    frm_layers_free(&s->layers);
    memset(s, 0, sizeof *s);
}
