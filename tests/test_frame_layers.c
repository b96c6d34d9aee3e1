/* frame/layers: the layer candidates of a frame and what an object costs and keeps under each, on
 * synthetic objects in front of a Vive's eyes (no GL): the resolution ceiling grows as the scale
 * falls and shrinks with the content's contrast; lossless candidates come first, the fallback
 * insets after them and under their scale's ceiling; a forced scale gives one candidate; a lossless
 * setting keeps all of an object's benefit and a lossy one less where the object lies in the
 * periphery (the more so the coarser the scale); a fill-bound object costs less in layers than in
 * the plain frame; the periphery draws no finer than the object's own level or its ceiling at s·ξ;
 * masks put an object in the layers it reaches. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "frame/frame.h"
#include "test_util.h"

enum { N = 4 };

struct fixture {
    const struct hmd_profile *vive;
    struct hmd_eye eyes[2];
    struct acu_limits acuity;
    struct acu_csf_table *table;
    struct acu_contrast_limits contrast;
    struct acu_viewer viewer;
    double center_m[3 * N], radius_m[N];
    uint32_t visible[N];
    double eccentricity_deg[N], velocity_degps[N], diameter_deg[N];
};

/* Four objects 3 m ahead of the eye: at the gaze, 12°, 30° and 45° to the right; a 0.3 m sphere each. */
static void fixture_init(struct fixture *f)
{
    memset(f, 0, sizeof *f);
    f->vive = hmd_builtin_find("vive");
    for (int e = 0; e < 2; ++e)
        f->eyes[e] = hmd_eye_frustum(f->vive, e);
    double xi = hmd_compute_xi(f->vive).used_cpd;
    acu_limits_init(&f->acuity, xi, 1.0);
    f->table = malloc(sizeof *f->table);
    acu_csf_table_fill_cycles(f->table, ACU_CSF_CASTLE, 20.0, ACU_CSF_GABOR_CYCLES);
    acu_contrast_limits_init(&f->contrast, f->table, xi, 1.0, 2.0);
    f->viewer.eye_position_m = hl_v3(0, 0, 0);
    f->viewer.gaze_dir = hl_v3(0, 0, -1);
    const double angle_deg[N] = {0.0, 12.0, 30.0, 45.0};
    for (int k = 0; k < N; ++k) {
        double a = angle_deg[k] * HL_RAD_PER_DEG;
        f->center_m[3 * k] = 3.0 * sin(a), f->center_m[3 * k + 1] = 0.0, f->center_m[3 * k + 2] = -3.0 * cos(a);
        f->radius_m[k] = 0.3;
        f->visible[k] = (uint32_t)k;
    }
    acu_compute_geometry(&f->viewer, f->center_m, f->radius_m, NULL, f->visible, N, f->eccentricity_deg,
                         f->velocity_degps, f->diameter_deg);
}

static void plan_held(struct frm_layers *l, struct fixture *f, const double *velocity_degps, int fovea_held)
{
    struct frm_layers_view view = {&f->viewer, hl_q_identity(), f->eyes, f->vive->eye_width_px,
                                   f->vive->eye_height_px, 0.5 * f->vive->ipd_m, fovea_held};
    frm_layers_plan(l, &view, &f->acuity, &f->contrast, f->acuity.xi_cpd, f->center_m, f->radius_m, f->visible, N,
                    f->eccentricity_deg, velocity_degps);
}

static void plan(struct frm_layers *l, struct fixture *f)
{
    plan_held(l, f, f->velocity_degps, 0);
}

/* The 0.25 scale's ceiling radius of the last plan. */
static double quarter_ceiling_deg(const struct frm_layers *l)
{
    for (int c = 1; c < l->cand_count; ++c)
        if (l->cand[c].scale == 0.25)
            return l->cand[c].ceiling_radius_deg;
    return NAN;
}

/* A measured gaze's noise (EDVAM: 25–45 deg/s between fixations) gives every object a retinal speed
 * that lowers what the inset must show; with the fovea held (a measured gaze outside a saccade) the
 * inset is planned as for still objects. */
static void test_fovea_held(struct fixture *f)
{
    struct frm_layers l;
    struct hl_error err = {""};
    CHECK(frm_layers_init(&l, FRM_FOVEATION_GAZE, 0.0, 0.0, -1.0, N, 0, &err) == 0);
    double fast[N];
    for (int k = 0; k < N; ++k)
        fast[k] = 40.0;
    plan_held(&l, f, f->velocity_degps, 0);
    double still = quarter_ceiling_deg(&l);
    plan_held(&l, f, fast, 0);
    double noisy = quarter_ceiling_deg(&l);
    CHECK(l.slowest_degps == 40.0);
    plan_held(&l, f, fast, 1);
    double held = quarter_ceiling_deg(&l);
    printf("scale 0.25 needs an inset of %.1f deg still, %.1f deg at 40 deg/s, %.1f deg at 40 deg/s held\n", still,
           noisy, held);
    CHECK(noisy < still && held == still && l.slowest_degps == 0.0);
    frm_layers_free(&l);
}

static void test_candidates(struct fixture *f)
{
    struct frm_layers l;
    struct hl_error err = {""};
    CHECK(frm_layers_init(&l, FRM_FOVEATION_FIXED, 0.0, 0.0, -1.0, N, 0, &err) == 0);
    CHECK(l.blend_deg == FRM_LAYER_BLEND_DEG_DEFAULT);
    plan(&l, f);
    CHECK(l.cand_count == FRM_LAYER_SCALES && l.cand[0].scale == 1.0 && l.cand[0].inset_radius_deg == 0.0);
    /* One candidate a scale: the ceiling's inset capped at the fovea's, lossless ones first;
     * ceilings grow as the scale falls. */
    double ceiling_of[FRM_LAYER_SCALES] = {0.0};
    for (int c = 1; c < l.cand_count; ++c) {
        const struct frm_layer_candidate *cand = &l.cand[c];
        CHECK(cand->inset_radius_deg == fmin(cand->ceiling_radius_deg, FRM_LAYER_FOVEA_DEG));
        CHECK(cand->loses == (c >= l.first_loss) && cand->loses == (cand->ceiling_radius_deg > FRM_LAYER_FOVEA_DEG));
        for (int i = 1; i < FRM_LAYER_SCALES; ++i)
            if (cand->scale == frm_layer_scales[i])
                ceiling_of[i] = cand->ceiling_radius_deg;
        printf("full contrast, still: scale %.2f needs an inset of %.1f deg (drawn %.1f)\n", cand->scale,
               cand->ceiling_radius_deg, cand->inset_radius_deg);
    }
    for (int i = 2; i < FRM_LAYER_SCALES; ++i)
        CHECK(ceiling_of[i] >= ceiling_of[i - 1] && ceiling_of[i] > 0.0);
    /* Benefit: lossless keeps all; a lossy setting keeps less of an object it leaves in the periphery. */
    for (int c = 0; c < l.cand_count; ++c)
        for (size_t k = 0; k < N; ++k) {
            double share = frm_layers_benefit_share(&l, &l.cand[c], k);
            CHECK(share > 0.0 && share <= 1.0);
            if (!l.cand[c].loses)
                CHECK(share == 1.0);
        }
    int quarter = -1;
    for (int c = l.first_loss; c < l.cand_count; ++c)
        if (l.cand[c].scale == 0.25)
            quarter = c;
    CHECK(quarter > 0);
    if (quarter > 0) {
        double at_gaze = frm_layers_benefit_share(&l, &l.cand[quarter], 0);
        double at_12 = frm_layers_benefit_share(&l, &l.cand[quarter], 1);
        printf("scale 0.25, inset 5 deg: the object at the gaze keeps %.3f, at 12 deg %.3f, at 45 deg %.3f\n",
               at_gaze, at_12, frm_layers_benefit_share(&l, &l.cand[quarter], 3));
        CHECK(at_gaze == 1.0 && at_12 < 1.0); /* inside the inset and its blend: whole; across its edge: less */
        /* Under Funkhouser's benefit the same loss is in accuracy units (§5, Samples ≤ pixels): a level
         * of 400 samples on 1 600 pixels has 100 at s 0.25 — 1 − 0.5/100² against 1 − 0.5/400²; one
         * of 50 samples loses nothing (50 < 100); the objects at the gaze and at 45° (D = 0 there) keep all. */
        struct lod_benefit_params bp;
        lod_benefit_params_default(&bp);
        double fine = frm_layers_level_share(&l, &l.cand[quarter], 1, &bp, 400.0, 1600.0);
        double coarse = frm_layers_level_share(&l, &l.cand[quarter], 1, &bp, 50.0, 1600.0);
        /* the periphery's share f of the object at 12°, from share = (1 − f) + f · a(D), a the
         * perceptual benefit's accuracy of D (lod_benefit_perceptual_accuracy) */
        double d_12 = l.resolution_loss[1 * FRM_LAYER_SCALES + FRM_LAYER_SCALES - 1];
        double f1 = (1.0 - at_12) / (1.0 - lod_benefit_perceptual_accuracy(d_12));
        double want = (1.0 - f1) + f1 * (1.0 - 0.5 / (100.0 * 100.0)) / (1.0 - 0.5 / (400.0 * 400.0));
        printf("Funkhouser units, scale 0.25, object at 12 deg: 400 samples keep %.8f (want %.8f), 50 keep %.8f\n",
               fine, want, coarse);
        CHECK(fabs(fine - want) < 1e-12 && fine < 1.0 && fine > 1.0 - 1e-4);
        CHECK(coarse == 1.0);
        CHECK(frm_layers_level_share(&l, &l.cand[quarter], 0, &bp, 400.0, 1600.0) == 1.0); /* in the inset */
        CHECK(frm_layers_level_share(&l, &l.cand[quarter], 3, &bp, 400.0, 1600.0) == 1.0); /* D = 0 at 45° */
        CHECK(frm_layers_level_share(&l, &l.cand[0], 1, &bp, 400.0, 1600.0) == 1.0);       /* the plain frame */
    }
    /* Lower content contrast: smaller insets for the same scale. */
    double full = ceiling_of[FRM_LAYER_SCALES - 1], low = INFINITY;
    l.rings.valid = 1;
    for (int k = 0; k < RND_CONTRAST_RINGS; ++k)
        l.rings.max_contrast[k] = 0.05, l.rings.pixels[k] = 100;
    plan(&l, f);
    for (int c = 1; c < l.cand_count; ++c)
        if (l.cand[c].scale == frm_layer_scales[FRM_LAYER_SCALES - 1])
            low = l.cand[c].ceiling_radius_deg;
    printf("content contrast 0.05: scale %.2f needs %.1f deg (full contrast %.1f)\n",
           frm_layer_scales[FRM_LAYER_SCALES - 1], low, full);
    CHECK(low < full);
    frm_layers_free(&l);

    /* --periphery-scale: one candidate, at that scale; off: the plain frame alone. */
    CHECK(frm_layers_init(&l, FRM_FOVEATION_FIXED, 5.0, 0.5, 12.0, N, 0, &err) == 0);
    plan(&l, f);
    CHECK(l.cand_count == 1 && l.cand[0].scale == 0.5 && l.cand[0].inset_radius_deg == 12.0);
    frm_layers_free(&l);
    CHECK(frm_layers_init(&l, FRM_FOVEATION_OFF, 0.0, 0.0, -1.0, N, 0, &err) == 0);
    plan(&l, f);
    CHECK(l.cand_count == 1 && l.cand[0].scale == 1.0);
    frm_layers_free(&l);
}

/* Costs, periphery levels and masks on the scene's first chain (the field's bumpy sphere). */
static void test_costs_and_masks(struct fixture *f)
{
    struct scn_scene scene = {0};
    struct hl_error err = {""};
    struct scn_scene_params params = {.object_count = 1, .seed = 1};
    CHECK(scn_scene_build("field", &params, &scene, &err) == 0);
    const struct scn_chain *ch = &scene.chains[0];
    struct frm_layers l;
    CHECK(frm_layers_init(&l, FRM_FOVEATION_FIXED, 5.0, 0.0, 10.0, N, 0, &err) == 0); /* --inset-deg 10 */
    plan(&l, f);
    struct lod_cost_model m = {LOD_COST_ADDITIVE, 1.0, 1e-4, 0.0, 4e-6, 0.008, 0.0};
    int c = -1;
    for (int i = l.first_loss; i < l.cand_count; ++i)
        if (l.cand[i].scale == 0.25 && l.cand[i].inset_radius_deg == 10.0)
            c = i;
    CHECK(c > 0);
    if (c < 0)
        goto done;
    /* The object at 45°: wholly in the periphery, 1e5 pixels at full resolution. */
    for (size_t k = 0; k < N; ++k) {
        l.inset_px[k] = 0.0;
        for (int i = 0; i < FRM_LAYER_SCALES; ++i)
            l.periphery_ceiling[k * FRM_LAYER_SCALES + i] = (uint8_t)(i == 4 ? ch->lod_count - 1 : 0);
    }
    l.inset_px_of = c;
    double plain = frm_layers_level_cost_ms(&l, &l.cand[0], &m, ch, 0, 1e5, 0, 3);
    double layered = frm_layers_level_cost_ms(&l, &l.cand[c], &m, ch, 0, 1e5, 0, 3);
    printf("an object in the periphery, 1e5 px: %.3f ms plain, %.3f ms at scale 0.25 (drawn at its coarsest there)\n",
           plain, layered);
    CHECK(layered < plain);
    /* Periphery levels: no finer than the object's own level, nor than the ceiling at the scale. */
    l.chosen = c;
    uint8_t lod[N + 1] = {0, 1, 0, LOD_DROP, 0};
    frm_layers_periphery_levels(&l, lod, N, 1);
    for (size_t k = 0; k < N; ++k)
        CHECK(lod[k] == LOD_DROP ? l.periphery_lod[k] == LOD_DROP : l.periphery_lod[k] == ch->lod_count - 1);
    CHECK(l.periphery_lod[N] == lod[N]); /* a group impostor as it is */
    /* Masks: the object at the gaze in the inset only, at 45° in the periphery only, at 12° in both. */
    frm_layers_masks(&l, N, 1);
    printf("masks: %u %u %u %u\n", l.mask[0], l.mask[1], l.mask[2], l.mask[3]);
    CHECK(l.mask[0] == RND_LAYER_INSET);
    CHECK(l.mask[1] == RND_LAYER_BOTH);
    CHECK(l.mask[3] == RND_LAYER_PERIPHERY);
    CHECK(l.mask[N] == RND_LAYER_BOTH);
done:
    frm_layers_free(&l);
    scn_scene_free(&scene);
}

/* Valve's controller (frm_adaptive_*): two levels down after a frame over 0.90 of the budget, then a
 * hold; one down when the trend predicts crossing 0.90; up one after 6 cheap frames, two after 12;
 * clamped to its levels; the scale is √0.85 per level. */
static void test_adaptive(void)
{
    struct frm_adaptive a;
    frm_adaptive_init(&a);
    CHECK(a.level == 0 && frm_adaptive_scale(&a) == 1.0);
    frm_adaptive_update(&a, 10.5, 11.1); /* 0.95 of the budget */
    CHECK(a.level == 2);
    frm_adaptive_update(&a, 10.5, 11.1); /* held */
    CHECK(a.level == 2);
    frm_adaptive_update(&a, 10.5, 11.1);
    CHECK(a.level == 2);
    frm_adaptive_update(&a, 10.5, 11.1); /* the hold is over */
    CHECK(a.level == 4);
    CHECK(fabs(frm_adaptive_scale(&a) - sqrt(pow(0.85, 4))) < 1e-12);
    frm_adaptive_init(&a);
    frm_adaptive_update(&a, 8.0, 11.1);  /* 0.72: neither */
    frm_adaptive_update(&a, 9.5, 11.1);  /* 0.86, rising 1.5 ms a frame: 11.0 next, over 0.90 */
    CHECK(a.level == 1);
    frm_adaptive_init(&a);
    a.level = 5;
    for (int k = 0; k < 6; ++k)
        frm_adaptive_update(&a, 5.0, 11.1);
    CHECK(a.level == 4);
    for (int k = 0; k < 6; ++k)
        frm_adaptive_update(&a, 5.0, 11.1);
    CHECK(a.level == 2);
    for (int k = 0; k < 100; ++k)
        frm_adaptive_update(&a, 5.0, 11.1);
    CHECK(a.level == 0);
    for (int k = 0; k < 100; ++k)
        frm_adaptive_update(&a, 50.0, 11.1);
    CHECK(a.level == FRM_ADAPTIVE_LEVELS - 1 && frm_adaptive_scale(&a) >= 0.25);
    frm_adaptive_update(&a, NAN, 11.1); /* nothing measured: no change */
    CHECK(a.level == FRM_ADAPTIVE_LEVELS - 1);
}

/* Which candidate setting's outcome wins (frm_layers_outcome_better): the least late first, even
 * against one that drops nothing; then fewer dropped pixels; then less of the margin spent; then
 * benefit; then the scale's visible loss; then cost; each with its tolerance. */
static void test_outcome_order(void)
{
    /* The auditorium's case: the plain frame's kept objects 25 ms over a tight budget, dropping no
     * pixel, against a layered setting within it that drops a few chairs. */
    struct frm_layer_outcome plain = {25.3, 0.0, 0.0, 40.0, 29.9, 0.0}, layered = {0.0, 1800.0, 0.0, 31.0, 4.5, 0.0};
    CHECK(frm_layers_outcome_better(&layered, &plain) && !frm_layers_outcome_better(&plain, &layered));
    struct frm_layer_outcome less_late = {1.0, 5000.0, 0.0, 10.0, 6.0, 0.0};
    CHECK(frm_layers_outcome_better(&less_late, &plain));
    /* As late (within FRM_LAYER_LATE_TOLERANCE_MS): fewer dropped pixels, then the higher benefit,
     * then the cheaper — half a millisecond late does not outweigh a dropped chair. */
    struct frm_layer_outcome a = {0.5, 0.0, 0.0, 30.0, 7.0, 0.0}, b = {0.0, 100.0, 0.0, 35.0, 5.0, 0.0};
    CHECK(frm_layers_outcome_better(&a, &b) && !frm_layers_outcome_better(&b, &a));
    struct frm_layer_outcome c = {0.5, 0.3, 0.0, 31.0, 7.5, 0.0};
    CHECK(frm_layers_outcome_better(&c, &a) && !frm_layers_outcome_better(&a, &c)); /* 0.3 px is no drop */
    struct frm_layer_outcome d = {0.5, 0.0, 0.0, 31.0, 7.0, 0.0};
    CHECK(frm_layers_outcome_better(&d, &c) && !frm_layers_outcome_better(&c, &d));
    CHECK(!frm_layers_outcome_better(&d, &d)); /* a tie is not better: the first solved stays */
    /* Equally late, nothing dropped: the setting that spends less of the correction's margin wins
     * over a higher benefit — the margin keeps objects, it does not buy a larger inset. */
    struct frm_layer_outcome spends = {0.0, 0.0, 1.5, 40.0, 8.0, 0.0}, keeps = {0.0, 0.0, 0.0, 30.0, 6.5, 0.0};
    CHECK(frm_layers_outcome_better(&keeps, &spends) && !frm_layers_outcome_better(&spends, &keeps));
    struct frm_layer_outcome drops = {0.0, 900.0, 0.0, 45.0, 6.0, 0.0}; /* but spending it beats a drop */
    CHECK(frm_layers_outcome_better(&spends, &drops) && !frm_layers_outcome_better(&drops, &spends));
    /* Same levels, same benefit (Funkhouser's moves by 1e-9 with the scale): the setting whose
     * periphery loses less visible detail wins even at a higher cost; a higher benefit still comes
     * first; and half a pixel of loss is a tie, left to the cost. */
    struct frm_layer_outcome fine = {0.0, 0.0, 0.0, 6.0e6, 9.0, 1000.0}, coarse = {0.0, 0.0, 0.0, 6.0e6, 6.0, 80000.0};
    CHECK(frm_layers_outcome_better(&fine, &coarse) && !frm_layers_outcome_better(&coarse, &fine));
    struct frm_layer_outcome richer = {0.0, 0.0, 0.0, 6.0e6 + 1.0, 6.0, 80000.0};
    CHECK(frm_layers_outcome_better(&richer, &fine) && !frm_layers_outcome_better(&fine, &richer));
    struct frm_layer_outcome cheaper = {0.0, 0.0, 0.0, 6.0e6, 8.0, 1000.4};
    CHECK(frm_layers_outcome_better(&cheaper, &fine) && !frm_layers_outcome_better(&fine, &cheaper));
}

int main(void)
{
    struct fixture f;
    fixture_init(&f);
    CHECK(f.vive != NULL);
    if (!f.vive)
        return tu_finish("frame layers");
    test_candidates(&f);
    test_fovea_held(&f);
    test_costs_and_masks(&f);
    test_adaptive();
    test_outcome_order();
    enum frm_foveation_mode mode;
    struct hl_error err = {""};
    CHECK(frm_foveation_parse("gaze", &mode, &err) == 0 && mode == FRM_FOVEATION_GAZE);
    CHECK(frm_foveation_parse(NULL, &mode, &err) == 0 && mode == FRM_FOVEATION_OFF);
    CHECK(frm_foveation_parse("sideways", &mode, &err) != 0 && strstr(err.msg, "--foveation"));
    CHECK(frm_foveation_parse("adaptive", &mode, &err) == 0 && mode == FRM_FOVEATION_ADAPTIVE);
    CHECK(!strcmp(frm_foveation_name(FRM_FOVEATION_ADAPTIVE), "adaptive"));
    free(f.table);
    return tu_finish("frame layers");
}
