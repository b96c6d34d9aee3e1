/* Steps 5–7 of a frame (DESIGN.md "One frame"): Reddy's perceptual ceiling, each candidate's cost
 * (the machine's cost profile) and benefit (Funkhouser & Séquin 1993 §5 capped at the ceiling), and
 * the selector. Everything here is sized in frm_select_init; a frame allocates nothing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "frame/cost.h"
#include "frame/select.h"
#include "frame/select_mb.h"

static const char *const selector_names[] = {"none", "reddy", "static", "feedback", "fs", "mb"};

int frm_selector_parse(const char *name, enum frm_selector *out, struct hl_error *err)
{
    for (int k = 0; k < (int)(sizeof selector_names / sizeof *selector_names); ++k)
        if (name && !strcmp(name, selector_names[k])) {
            *out = (enum frm_selector)k;
            return 0;
        }
    return hl_fail(err, "--selector: unknown selector '%s' (known: none, reddy, static, feedback, fs, mb)",
                   name ? name : "");
}

int frm_benefit_parse(const char *name, int *perceptual, struct hl_error *err)
{
    const char *b = name ? name : FRM_BENEFIT_DEFAULT;
    if (strcmp(b, "perceptual") != 0 && strcmp(b, "funkhouser") != 0)
        return hl_fail(err, "--benefit: unknown benefit '%s' (known: perceptual, funkhouser)", b);
    *perceptual = strcmp(b, "perceptual") == 0;
    return 0;
}

int frm_cost_model_load(const char *path, struct lod_cost_model *out, struct frm_layer_costs *layers_out,
                        char *label_out, size_t label_size, struct hl_error *err)
{
    struct frm_cost_profile profile;
    if (path) {
        if (frm_cost_profile_read(path, &profile, err) != 0)
            return -1;
        snprintf(label_out, label_size, "%s (%s form, %s)", path, frm_cost_form_name(profile.model.form),
                 profile.renderer);
    } else {
        frm_cost_profile_builtin_llvmpipe(&profile);
        snprintf(label_out, label_size, "%s", profile.label);
    }
    *out = profile.model;
    if (layers_out) {
        for (int i = 0; i < FRM_LAYER_SCALES; ++i) {
            layers_out->periphery[i] = profile.model; /* where the profile has no model for a scale */
            for (int k = 0; k < profile.periphery_count && i > 0; ++k)
                if (fabs(profile.periphery[k].scale - frm_layer_scales[i]) <= 1e-9)
                    layers_out->periphery[i] = profile.periphery[k].model;
        }
        layers_out->inset = profile.inset.cost; /* zero where the profile has none: not used then */
        layers_out->periphery_count = profile.periphery_count;
        layers_out->inset_measured = profile.inset_measured;
    }
    size_t len = strlen(label_out);
    if (profile.periphery_count > 0 && len < label_size)
        snprintf(label_out + len, label_size - len, "; periphery models at %d layer scales", profile.periphery_count);
    len = strlen(label_out);
    if (profile.inset_measured && len < label_size)
        snprintf(label_out + len, label_size - len, "; an inset model (%g degrees)", profile.inset.radius_deg);
    return 0;
}

int frm_select_init(struct frm_select *s, const struct scn_scene *scene, struct hl_error *err)
{
    size_t n = scene->instance_count ? scene->instance_count : 1;
    size_t cands = n * (LOD_MAX_LEVELS + 1);
    size_t chains = scene->chain_count ? scene->chain_count : 1;
    s->pixels_px = calloc(n, sizeof(double));
    s->boxed = calloc(n, 1);
    s->ceiling_level = calloc(n, 1);
    s->previous_level = calloc(n, 1);
    s->seen_level = calloc(n, 1);
    s->keep = calloc(n, 1);
    s->coarsest_ms = calloc(n, sizeof(double));
    s->choice = calloc(n, 1);
    s->first = calloc(n, sizeof(uint32_t));
    s->count = calloc(n, 1);
    s->cand_cost_ms = calloc(cands, sizeof(double));
    s->cand_benefit = calloc(cands, sizeof(double));
    s->cand_level = calloc(cands, 1);
    s->cand_samples = calloc(cands, sizeof(uint32_t));
    s->level_of_instance = malloc(n);
    s->last_visible = calloc(n, sizeof(uint32_t));
    s->chain_triangles = calloc(chains * LOD_MAX_LEVELS, sizeof(uint32_t));
    s->chain_lod_count = calloc(chains, 1);
    s->scratch = malloc(lod_scratch_bytes(n, cands));
    s->saccade.level_before = malloc(n);
    s->saccade.refine = calloc(n, sizeof *s->saccade.refine);
    if (s->perceptual_benefit && (s->selector == FRM_SELECT_FS || s->selector == FRM_SELECT_MB) &&
        !(s->visible_loss = calloc(n * LOD_MAX_LEVELS, sizeof(double))))
        return hl_fail(err, "scene '%s': out of memory for the visible loss of %zu objects", scene->name, n);
    if (!s->pixels_px || !s->boxed || !s->ceiling_level || !s->previous_level || !s->seen_level || !s->keep || !s->coarsest_ms || !s->choice || !s->first || !s->count ||
        !s->cand_cost_ms || !s->cand_benefit || !s->cand_level || !s->cand_samples || !s->level_of_instance ||
        !s->last_visible || !s->chain_triangles || !s->chain_lod_count || !s->scratch || !s->saccade.level_before ||
        !s->saccade.refine)
        return hl_fail(err, "scene '%s': out of memory for the selector's arrays (%zu objects)", scene->name, n);
    memset(s->level_of_instance, LOD_UNSEEN, n);
    s->level_capacity = n;
    memset(s->saccade.level_before, LOD_UNSEEN, n);
    for (uint32_t c = 0; c < scene->chain_count; ++c) {
        const struct scn_chain *ch = &scene->chains[c];
        s->chain_lod_count[c] = (uint8_t)(ch->lod_count < LOD_MAX_LEVELS ? ch->lod_count : LOD_MAX_LEVELS);
        for (int l = 0; l < s->chain_lod_count[c]; ++l)
            s->chain_triangles[c * LOD_MAX_LEVELS + l] = ch->lods[l].triangle_count;
    }
    if (s->selector == FRM_SELECT_MB && frm_mb_create(scene, n, s->mb_simplify, &s->mb, err) != 0)
        return -1;
    lod_benefit_params_default(&s->benefit);
    acu_saccade_params_default(&s->saccade.params);
    if (!isfinite(s->saccade_onset_degps))
        return hl_fail(err, "--saccade-onset-degps: %g is not a finite speed", s->saccade_onset_degps);
    if (s->saccade_onset_degps > 0.0) { /* ≤ 0: the default; the offset keeps the default's ratio */
        s->saccade.params.offset_degps *= s->saccade_onset_degps / s->saccade.params.onset_degps;
        s->saccade.params.onset_degps = s->saccade_onset_degps;
    }
    acu_saccade_init(&s->saccade.state);
    lod_cost_correction_init(&s->correction, 0.1);
    lod_cost_rls_init(&s->rls, s->cost.c0_ms, 0.98);
    s->frames_measured = 0;
    lod_feedback_init(&s->feedback, s->static_px > 0.0 ? s->static_px : 64.0);
    return 0;
}

void frm_select_free(struct frm_select *s)
{
    free(s->pixels_px);
    free(s->boxed);
    free(s->ceiling_level);
    free(s->previous_level);
    free(s->seen_level);
    free(s->keep);
    free(s->coarsest_ms);
    free(s->choice);
    free(s->first);
    free(s->count);
    free(s->cand_cost_ms);
    free(s->cand_benefit);
    free(s->cand_level);
    free(s->cand_samples);
    free(s->visible_loss);
    free(s->level_of_instance);
    free(s->last_visible);
    free(s->chain_triangles);
    free(s->chain_lod_count);
    free(s->scratch);
    free(s->saccade.level_before);
    free(s->saccade.refine);
    frm_mb_destroy(s->mb);
    s->mb = NULL;
}

/* The candidate's inset pixels per visible object, once per candidate and frame (frame/layers.h). */
static void layer_prepare(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                          const struct frm_layer_candidate *layer)
{
    if (!layer || layer->scale >= 1.0)
        return;
    int c = (int)(layer - s->layers->cand);
    if (s->layers->inset_px_of != c)
        frm_layers_inset_pixels(s->layers, c, scene, in->eyes, in->visible, in->count, s->pixels_px);
}

double frm_select_level_cost_ms(const struct frm_select *s, const struct frm_layer_candidate *layer,
                                const struct scn_chain *ch, int level, size_t k)
{
    if (!layer || layer->scale >= 1.0)
        return frm_level_cost_ms(&s->cost, ch, level, s->pixels_px[k], s->boxed[k]);
    return frm_layers_level_cost_ms(s->layers, layer, &s->cost, ch, level, s->pixels_px[k], s->boxed[k], k);
}

/* Σ over the visible objects of their coarsest level's cost under `layer`, each written to
 * s->coarsest_ms[k] for build_problem to reuse (it prices every level after). */
static double coarsest_sum_ms(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                              const struct frm_layer_candidate *layer)
{
    double sum_ms = 0.0;
    for (size_t k = 0; k < in->count; ++k) {
        int chain = scene->chain_of_instance[in->visible[k]];
        s->coarsest_ms[k] = frm_select_level_cost_ms(s, layer, &scene->chains[chain], s->chain_lod_count[chain] - 1, k);
        sum_ms += s->coarsest_ms[k];
    }
    return sum_ms;
}

/* The frame's problem over the visible objects: per object its levels coarsest first (the null
 * impostor before them where the chain allows drawing nothing), priced and valued, then reduced to
 * the convex hull. budget_ms: what the objects may cost with the correction's margin; expected_ms
 * (≥ budget_ms): without it. Drop last (issue 32): the margin is for frame-to-frame jitter, and
 * spending it is the lesser loss — a frame of 86 objects here kept a 2.6 ms margin, ran at 77 % of
 * its budget and dropped 16 objects, 60 frames long. So when every object's coarsest level fits in
 * expected_ms, all are kept and the budget rises to hold them; past that, objects are dropped as
 * before. */
static struct lod_problem build_problem(struct frm_select *s, const struct scn_scene *scene,
                                        const struct frm_view_inputs *in, double budget_ms, double expected_ms,
                                        const struct frm_layer_candidate *layer)
{
    double image_px = 0.0, kept_ms = 0.0;
    layer_prepare(s, scene, in, layer);
    for (int e = 0; e < 2; ++e)
        image_px += in->eyes[e].width_px * in->eyes[e].height_px;
    int priced = expected_ms > budget_ms; /* s->coarsest_ms holds this candidate's coarsest levels */
    int keep_all = priced && coarsest_sum_ms(s, scene, in, layer) <= expected_ms;
    uint32_t c = 0;
    for (size_t k = 0; k < in->count; ++k) {
        uint32_t inst = in->visible[k];
        const struct scn_chain *ch = &scene->chains[scene->chain_of_instance[inst]];
        s->first[k] = c;
        s->keep[k] = keep_all || s->pixels_px[k] >= FRM_KEEP_IMAGE_SHARE * image_px;
        if (ch->null_impostor && !s->keep[k]) {
            s->cand_level[c] = LOD_DROP;
            s->cand_cost_ms[c] = 0.0;
            s->cand_samples[c] = 0;
            ++c;
        }
        int coarsest = s->chain_lod_count[scene->chain_of_instance[inst]] - 1;
        for (int l = coarsest; l >= 0; --l, ++c) {
            s->cand_level[c] = (uint8_t)l;
            s->cand_cost_ms[c] = priced && l == coarsest ? s->coarsest_ms[k] : frm_select_level_cost_ms(s, layer, ch, l, k);
            s->cand_samples[c] = ch->lods[l].vertex_count; /* Gouraud: m = 2 (§5) */
        }
        s->count[k] = (uint8_t)(c - s->first[k]);
        s->previous_level[k] = s->level_of_instance[inst];
        s->seen_level[k] = frm_saccade_seen_level(s, inst);
        if (s->keep[k] && s->count[k] > 0)
            kept_ms += s->cand_cost_ms[s->first[k]];
    }
    /* Drop last, and never what fills a large part of the view: the kept objects' coarsest levels
     * are in the frame whatever the budget says (the frame then runs late rather than show a hole). */
    budget_ms = fmax(budget_ms, kept_ms + 1e-6); /* lod/ rounds each cost up to 1e-8 ms */
    lod_benefit_fill(&s->benefit, in->count, s->first, s->count, s->cand_level, s->cand_samples, s->pixels_px,
                     NULL, s->ceiling_level, s->seen_level, s->visible_loss_valid ? s->visible_loss : NULL,
                     s->cand_benefit);
    if (scene->importance)
        for (size_t k = 0; k < in->count; ++k)
            for (uint32_t j = s->first[k]; j < s->first[k] + s->count[k]; ++j)
                s->cand_benefit[j] *= scene->importance[in->visible[k]];
    if (layer && layer->loses) /* what a coarser periphery than the ceiling takes away (frame/layers.h) */
        for (size_t k = 0; k < in->count; ++k) {
            if (s->visible_loss_valid) { /* the perceptual benefit: its own units, D */
                double share = frm_layers_benefit_share(s->layers, layer, k);
                for (uint32_t j = s->first[k]; j < s->first[k] + s->count[k]; ++j)
                    s->cand_benefit[j] *= share;
                continue;
            }
            /* Funkhouser's: each level at its accuracy with the periphery's samples; a level finer
             * than the ceiling is valued as the ceiling (coarsest first, so it comes before them). */
            double ceiling_samples = 0.0;
            for (uint32_t j = s->first[k]; j < s->first[k] + s->count[k]; ++j) {
                if (s->cand_level[j] == LOD_DROP)
                    continue;
                double samples = s->cand_samples[j];
                if (s->cand_level[j] == s->ceiling_level[k])
                    ceiling_samples = samples;
                else if (s->cand_level[j] < s->ceiling_level[k] && ceiling_samples > 0.0)
                    samples = ceiling_samples;
                s->cand_benefit[j] *=
                    frm_layers_level_share(s->layers, layer, k, &s->benefit, samples, s->pixels_px[k]);
            }
        }
    lod_hull_reduce(in->count, s->first, s->count, s->cand_cost_ms, s->cand_benefit, s->cand_level, budget_ms,
                    (int64_t *)s->scratch); /* before the optimizer: the scratch is free */
    return (struct lod_problem){in->count, in->visible, s->first, s->count, s->cand_cost_ms, s->cand_benefit,
                                s->cand_level, budget_ms, s->fs_margin_value, s->keep};
}

/* c0 + Σ predicted cost of what is drawn, for any selector. */
static double predicted_ms(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                           const uint8_t *lod, const struct frm_layer_candidate *layer)
{
    layer_prepare(s, scene, in, layer);
    double sum = s->cost.c0_ms + (layer ? layer->overhead_ms : 0.0);
    for (size_t k = 0; k < in->count; ++k) {
        if (lod[k] == LOD_DROP)
            continue;
        const struct scn_chain *ch = &scene->chains[scene->chain_of_instance[in->visible[k]]];
        sum += frm_select_level_cost_ms(s, layer, ch, lod[k], k);
    }
    return sum;
}

/* The selectors that do not price pixels take the cheapest candidate that loses nothing: the
 * resolution ceiling, as reddy takes the LOD ceiling. */
static void choose_layers_lossless(struct frm_select *s, const struct scn_scene *scene,
                                   const struct frm_view_inputs *in, const uint8_t *lod)
{
    struct frm_layers *l = s->layers;
    double best = INFINITY;
    for (int c = 0; c < l->cand_count; ++c) {
        if (l->cand[c].loses && l->cand_count > 1)
            continue;
        double ms = predicted_ms(s, scene, in, lod, &l->cand[c]);
        if (ms < best)
            best = ms, l->chosen = c;
    }
}

/* The optimizer's result in the frame's record. */
static void record_result(struct frm_select_record *rec, const struct lod_result *r)
{
    rec->iterations = r->iterations;
    rec->dropped = r->dropped;
    rec->truncated = r->truncated;
    rec->over_budget = r->over_budget;
    rec->optimizer_us = r->elapsed_us;
    rec->benefit = r->benefit;
}

/* The estimated pixels of the objects a choice drops. */
static double dropped_pixels(const struct frm_select *s, const struct lod_problem *p, const uint8_t *choice)
{
    double px = 0.0;
    for (size_t k = 0; k < p->object_count; ++k)
        if (choice[k] == LOD_DROPPED || (p->count[k] > 0 && p->level[p->first[k] + choice[k]] == LOD_DROP))
            px += s->pixels_px[k]; /* dropped by the optimizer, or its null impostor chosen */
    return px;
}

/* fs with layers: one knapsack per candidate setting, each with its own overhead out of the budget,
 * every candidate solved (issue 32 item 3: the setting with the highest benefit) — the lossy ones,
 * solved only when no lossless one held every object, were never weighed against the lossless ones'
 * 15–40° insets. The best outcome wins (frm_layers_outcome_better: the least late, then the fewest
 * dropped pixels, then the least margin spent, then the highest benefit, then the least visible loss
 * to the periphery's scale, then the cheapest). lod_out
 * gets the winner's levels. */
static void solve_fs_layers(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                            double budget, double expected, uint8_t *lod_out, struct frm_select_record *rec,
                            struct lod_result *best)
{
    struct frm_layers *l = s->layers;
    double margin = s->fs_margin_value, lp = -INFINITY;
    struct frm_layer_outcome best_outcome = {INFINITY, INFINITY, INFINITY, 0.0, INFINITY, INFINITY};
    double lp_us = 0.0, opt_us = 0.0;
    uint32_t iterations = 0;
    int have = 0;
    for (int c = 0; c < l->cand_count; ++c) {
        const struct frm_layer_candidate *cand = &l->cand[c];
        double cand_budget = fmax(0.0, budget - cand->overhead_ms);
        double cand_expected = fmax(cand_budget, expected - cand->overhead_ms);
        struct lod_problem p = build_problem(s, scene, in, cand_budget, cand_expected, cand);
        struct lod_result r;
        lod_choice_start(&p, s->previous_level, s->choice);
        lod_optimize_fs(&p, s->opt_limit_us, s->scratch, s->choice, &r);
        opt_us += r.elapsed_us;
        iterations += r.iterations;
        /* The setting's budget raised for its kept objects past the expected frame means it runs
         * late by that much; within it, it spends the margin. */
        struct frm_layer_outcome outcome = {fmax(0.0, p.budget_ms - cand_expected),
                                            dropped_pixels(s, &p, s->choice),
                                            fmin(p.budget_ms, cand_expected) - cand_budget, r.benefit,
                                            r.cost_ms + cand->overhead_ms,
                                            frm_layers_visible_loss_px(l, cand, s->pixels_px, in->count)};
        if (!have || frm_layers_outcome_better(&outcome, &best_outcome)) {
            have = 1;
            best_outcome = outcome;
            *best = r;
            l->chosen = c;
            margin = r.margin_value;
            lod_level_of_choice(&p, s->choice, lod_out);
            rec->underused_drop = lod_choice_underused_drop(&p, s->choice, FRM_UNDERUSED_FRACTION);
            rec->optimizer_budget_ms = p.budget_ms;
        }
        int64_t lp_start = hl_clock_now_ns(); /* measurement only, as below */
        lp = fmax(lp, lod_lp_bound(&p, NULL));
        lp_us += (double)(hl_clock_now_ns() - lp_start) * 1e-3;
        l->evaluated = c + 1;
    }
    s->fs_margin_value = margin;
    best->elapsed_us = opt_us;
    best->iterations = iterations;
    rec->lp_bound = lp; /* the largest of the solved settings' bounds bounds their union (lod.h "layer choice") */
    rec->lp_us = lp_us;
}

/* Popping: levels that changed for objects drawn in both frames; then this frame becomes "last". */
static uint32_t remember_levels(struct frm_select *s, const struct frm_view_inputs *in, const uint8_t *lod)
{
    uint32_t changes = 0;
    for (size_t k = 0; k < in->count; ++k) {
        uint8_t prev = s->level_of_instance[in->visible[k]];
        changes += prev != LOD_UNSEEN && prev != lod[k];
    }
    for (uint32_t k = 0; k < s->last_visible_count; ++k)
        s->level_of_instance[s->last_visible[k]] = LOD_UNSEEN;
    for (size_t k = 0; k < in->count; ++k) {
        s->level_of_instance[in->visible[k]] = lod[k];
        s->last_visible[k] = in->visible[k];
    }
    s->last_visible_count = (uint32_t)in->count;
    return changes;
}

/* The perceptual ceilings of the visible objects under the frame's criterion (docs/visibility.md),
 * lowered while a saccade suppresses vision; returns the model evaluations. */
static uint64_t compute_ceilings(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in)
{
    struct lod_select_stats stats = {0};
    if (in->contrast)
        lod_select_contrast(in->contrast, in->limits, in->chains, scene->chain_of_instance, in->visible, in->count,
                            in->eccentricity_deg, in->velocity_degps, in->diameter_deg, s->ceiling_level, &stats);
    else
        lod_select_reddy(in->limits, in->chains, scene->chain_of_instance, in->visible, in->count, in->eccentricity_deg,
                         in->velocity_degps, in->diameter_deg, s->ceiling_level, NULL, &stats);
    /* The perceptual benefit's visible loss per level, on the same limits (docs/optimizer.md). */
    s->visible_loss_valid = s->visible_loss && in->contrast;
    if (s->visible_loss_valid)
        lod_visible_loss_contrast(in->contrast, in->chains, scene->chain_of_instance, in->visible, in->count,
                                  in->eccentricity_deg, in->velocity_degps, in->diameter_deg, s->visible_loss, &stats);
    frm_saccade_lower_ceilings(s, scene, in); /* suppressed: nothing above the coarsest is seen */
    return stats.model_evaluations;
}

int frm_selector_uses_ceiling(enum frm_selector selector)
{
    return selector == FRM_SELECT_REDDY || selector == FRM_SELECT_FS || selector == FRM_SELECT_MB;
}

void frm_select_frame(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                      uint8_t *lod_out, uint32_t *extra_index, uint8_t *extra_level, size_t *extra_count,
                      struct frm_select_record *rec)
{
    memset(rec, 0, sizeof *rec);
    rec->layer_scale = 1.0;
    *extra_count = 0;
    rec->budget_ms = s->budget_ms;
    rec->lp_bound = NAN;
    frm_coverage_compute(scene, in->eyes, 2, in->visible, in->count, s->pixels_px, s->boxed);
    if (frm_selector_uses_ceiling(s->selector))
        rec->acuity_evaluations = compute_ceilings(s, scene, in);
    if (s->layers && s->layers->mode != FRM_FOVEATION_OFF) {
        if (!frm_selector_uses_ceiling(s->selector)) /* the periphery's levels follow the ceilings */
            (void)compute_ceilings(s, scene, in);
        frm_layers_periphery_ceilings(s->layers, in->contrast, in->limits, in->chains, scene->chain_of_instance,
                                      in->visible, in->count, in->eccentricity_deg, in->velocity_degps,
                                      in->diameter_deg, s->ceiling_level);
    }

    switch (s->selector) {
    case FRM_SELECT_NONE:
        lod_select_finest(in->count, lod_out);
        break;
    case FRM_SELECT_REDDY:
        memcpy(lod_out, s->ceiling_level, in->count);
        break;
    case FRM_SELECT_STATIC:
    case FRM_SELECT_FEEDBACK: {
        double px = s->selector == FRM_SELECT_STATIC ? s->static_px : s->feedback.min_px_per_triangle;
        lod_select_static(px, s->chain_triangles, s->chain_lod_count, scene->chain_of_instance, in->visible, in->count,
                          s->pixels_px, lod_out);
        break;
    }
    case FRM_SELECT_FS:
    case FRM_SELECT_MB: {
        /* What the optimizer may spend: the budget less the frame's own CPU work (smoothed), scaled
         * by the measured/predicted ratio when correcting, less the per-frame constant c0 — or, with
         * the affine correction, what the fitted a + b·x leaves for the objects. */
        double budget = s->budget_ms - s->overhead_ms, expected = 0.0;
        if (s->correct == FRM_CORRECTION_AFFINE) {
            expected = lod_cost_rls_objects_expected_ms(&s->rls, budget);
            budget = lod_cost_rls_objects_budget_ms(&s->rls, budget);
        } else {
            if (s->correct == FRM_CORRECTION_RATIO)
                budget = lod_cost_correction_budget_ms(&s->correction, budget);
            budget = fmax(0.0, budget - s->cost.c0_ms);
        }
        struct lod_result r;
        if (s->selector == FRM_SELECT_FS && s->layers && s->layers->mode != FRM_FOVEATION_OFF) {
            solve_fs_layers(s, scene, in, budget, expected, lod_out, rec, &r);
            record_result(rec, &r);
            break;
        }
        struct lod_problem p = build_problem(s, scene, in, budget, expected, NULL);
        rec->optimizer_budget_ms = p.budget_ms; /* raised to hold the kept objects, if they need it */
        if (s->selector == FRM_SELECT_MB) { /* Mason & Blake on the visible part of the hierarchy */
            frm_mb_select(s->mb, scene, &p, &s->cost, &s->benefit, in->eyes, s->opt_limit_us, lod_out, extra_index,
                          extra_level, extra_count, &r);
            rec->underused_drop = frm_mb_underused_drop(s->mb, FRM_UNDERUSED_FRACTION);
        } else {
            lod_choice_start(&p, s->previous_level, s->choice);
            lod_optimize_fs(&p, s->opt_limit_us, s->scratch, s->choice, &r);
            s->fs_margin_value = r.margin_value; /* centres next frame's filters: one pass (lod.h) */
            lod_level_of_choice(&p, s->choice, lod_out);
            rec->underused_drop = lod_choice_underused_drop(&p, s->choice, FRM_UNDERUSED_FRACTION);
        }
        record_result(rec, &r);
        /* Measurement only, and not part of the frame: its time is taken out of the frame's. The
         * flat problem's bound does not bound mb's (group impostors are choices it lacks): none. */
        int64_t lp_start = hl_clock_now_ns();
        rec->lp_bound = s->selector == FRM_SELECT_MB ? NAN : lod_lp_bound(&p, NULL);
        rec->lp_us = (double)(hl_clock_now_ns() - lp_start) * 1e-3;
        break;
    }
    }
    const struct frm_layer_candidate *layer = NULL;
    if (s->layers && s->layers->mode != FRM_FOVEATION_OFF) {
        if (!(s->selector == FRM_SELECT_FS))
            choose_layers_lossless(s, scene, in, lod_out);
        layer = &s->layers->cand[s->layers->chosen];
        rec->layer_scale = layer->scale;
        rec->inset_radius_deg = layer->inset_radius_deg;
        rec->layer_loses = layer->loses;
        rec->layer_candidates = s->selector == FRM_SELECT_FS ? s->layers->evaluated : s->layers->cand_count;
    }
    layer_prepare(s, scene, in, layer);
    if (!rec->truncated) /* the time limit bounds the boost too: a stopped frame leaves it to the next */
        (void)frm_saccade_refine(s, scene, in, lod_out, layer, rec->optimizer_budget_ms);
    rec->predicted_ms = predicted_ms(s, scene, in, lod_out, layer);
    double visible_px = 0.0, dropped_px = 0.0;
    for (size_t k = 0; k < in->count; ++k) {
        visible_px += s->pixels_px[k];
        dropped_px += lod_out[k] == LOD_DROP ? s->pixels_px[k] : 0.0;
    }
    rec->dropped_px_share = visible_px > 0.0 ? dropped_px / visible_px : 0.0;
    for (size_t k = 0; k < *extra_count; ++k) {
        const struct scn_chain *ch = &scene->chains[scene->instances[extra_index[k]].chain];
        double px = 0.0;
        acu_compute_pixels(in->eyes, 2, scene->center_m, scene->radius_m, &extra_index[k], 1, &px);
        rec->predicted_ms += frm_level_cost_ms(&s->cost, ch, extra_level[k], px, 0);
    }
    frm_saccade_account(s, scene, in, lod_out, layer, rec);
    rec->lod_changes = remember_levels(s, in, lod_out);
}

double frm_select_visible_error(struct frm_select *s, const struct scn_scene *scene, const struct frm_view_inputs *in,
                                const uint8_t *lod)
{
    if (!frm_selector_uses_ceiling(s->selector)) /* the same ceilings reddy, fs and mb would have seen */
        (void)compute_ceilings(s, scene, in);
    double total_px = 0.0, coarse_px = 0.0;
    for (size_t k = 0; k < in->count; ++k) {
        uint8_t ceiling = s->ceiling_level[k];
        int coarser = lod[k] == LOD_DROP ? ceiling != LOD_DROP : ceiling != LOD_DROP && lod[k] > ceiling;
        total_px += s->pixels_px[k];
        coarse_px += coarser ? s->pixels_px[k] : 0.0;
    }
    return total_px > 0.0 ? coarse_px / total_px : 0.0;
}

void frm_select_measured(struct frm_select *s, const struct frm_select_record *rec, double draw_ms, double frame_ms)
{
    if (s->frames_measured++ < FRM_CORRECTION_WARMUP_FRAMES)
        return; /* first-use costs: frame 0 here pays ~40 % more than steady frames, frame 1 ~10 % */
    double overhead = fmax(0.0, frame_ms - draw_ms);
    s->overhead_ms = s->overhead_ms > 0.0 ? s->overhead_ms + 0.1 * (overhead - s->overhead_ms) : overhead;
    if (s->correct == FRM_CORRECTION_RATIO) /* only the correction in use learns */
        lod_cost_correction_update(&s->correction, draw_ms, rec->predicted_ms);
    else if (s->correct == FRM_CORRECTION_AFFINE)
        lod_cost_rls_update(&s->rls, draw_ms, rec->predicted_ms - s->cost.c0_ms);
    if (s->selector == FRM_SELECT_FEEDBACK)
        lod_feedback_update(&s->feedback, frame_ms, s->budget_ms);
}
