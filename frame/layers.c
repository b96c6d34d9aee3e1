/* Resolution as a representation (frame/layers.h): the layer candidates of a frame, what an object
 * costs and keeps under each, and the chosen setting and masks for render. Arrays are sized when the
 * scene loads; a frame allocates nothing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "frame/frame.h"

const double frm_layer_scales[FRM_LAYER_SCALES] = {1.0, 0.75, 0.5, 0.35, 0.25};

static const char *const foveation_names[] = {"off", "fixed", "gaze", "adaptive"};
enum { FOVEATION_MODES = 4 };

int frm_foveation_parse(const char *name, enum frm_foveation_mode *out, struct hl_error *err)
{
    const char *n = name ? name : "off";
    for (int k = 0; k < FOVEATION_MODES; ++k)
        if (!strcmp(n, foveation_names[k])) {
            *out = (enum frm_foveation_mode)k;
            return 0;
        }
    return hl_fail(err, "--foveation: unknown mode '%s' (known: off, fixed, gaze, adaptive)", n);
}

const char *frm_foveation_name(enum frm_foveation_mode mode)
{
    return (int)mode >= 0 && (int)mode < (int)FOVEATION_MODES ? foveation_names[mode] : "?";
}

int frm_layers_init(struct frm_layers *l, enum frm_foveation_mode mode, double blend_deg, double forced_scale,
                    double forced_radius_deg, uint32_t instances, uint32_t groups, struct hl_error *err)
{
    memset(l, 0, sizeof *l);
    l->mode = mode;
    l->blend_deg = blend_deg > 0.0 ? blend_deg : FRM_LAYER_BLEND_DEG_DEFAULT;
    l->forced_scale = forced_scale;
    l->forced_radius_deg = forced_radius_deg;
    frm_adaptive_init(&l->adaptive);
    l->cand_count = 1;
    l->cand[0].scale = 1.0;
    if (mode == FRM_FOVEATION_OFF)
        return 0;
    size_t n = instances ? instances : 1;
    l->centre_angle_deg = calloc(n, sizeof(double));
    l->radius_deg = calloc(n, sizeof(double));
    l->mask = calloc((size_t)instances + groups + 1, 1);
    l->lod_scratch = calloc(n, 1);
    l->inset_px = calloc(n, sizeof(double));
    l->resolution_loss = calloc(n * FRM_LAYER_SCALES, sizeof(double));
    l->periphery_lod = calloc((size_t)instances + groups + 1, 1);
    l->periphery_ceiling = calloc(n * FRM_LAYER_SCALES, 1);
    if (!l->centre_angle_deg || !l->radius_deg || !l->mask || !l->lod_scratch || !l->inset_px || !l->resolution_loss ||
        !l->periphery_lod || !l->periphery_ceiling)
        return hl_fail(err, "out of memory for the layers of %u objects", instances);
    return 0;
}

void frm_layers_free(struct frm_layers *l)
{
    free(l->centre_angle_deg);
    free(l->radius_deg);
    free(l->mask);
    free(l->lod_scratch);
    free(l->inset_px);
    free(l->resolution_loss);
    free(l->periphery_lod);
    free(l->periphery_ceiling);
    memset(l, 0, sizeof *l);
}

static double angle_deg(hl_vec3d a, hl_vec3d b)
{
    return hl_v3_angle_rad(a, b) * HL_DEG_PER_RAD;
}

/* The grid scale a setting's per-scale tables are read at: its own, or for a scale between the grid's
 * (the adaptive mode's) the next finer one — its LOD ceiling and overhead are then conservative. */
static int scale_index(double scale)
{
    int i = 0;
    while (i + 1 < FRM_LAYER_SCALES && frm_layer_scales[i + 1] >= scale - 1e-9)
        ++i;
    return i;
}

/* The eccentricity beyond which content of contrast c loses nothing visible at scale s. */
static double needed_eccentricity_deg(const struct frm_layers *l, const struct acu_limits *acuity,
                                      const struct acu_contrast_limits *contrast, double xi_cpd, double scale, double c)
{
    double target = scale * xi_cpd;
    return contrast ? acu_contrast_resolution_eccentricity_deg(contrast, c, l->slowest_degps, target)
                    : acu_resolution_eccentricity_deg(acuity, l->slowest_degps, target);
}

/* The content's contrast in ring k: the last frame's, or full contrast where none is known. The
 * acuity criterion takes every loss at full contrast (Reddy's H). */
static double ring_contrast(const struct frm_layers *l, int k)
{
    return l->rings.valid && l->rings.pixels[k] > 0 ? l->rings.max_contrast[k] : 1.0;
}

/* The inset a scale needs, from the gaze: each ring whose content would show the loss at its inner
 * edge must be covered up to where it stops showing (or the ring's outer edge). */
static double ceiling_radius_deg(const struct frm_layers *l, const struct acu_limits *acuity,
                                 const struct acu_contrast_limits *contrast, double xi_cpd, double scale)
{
    double radius = 0.0;
    for (int k = 0; k < RND_CONTRAST_RINGS; ++k) {
        double inner = k * RND_CONTRAST_RING_DEG;
        double outer = k + 1 < RND_CONTRAST_RINGS ? inner + RND_CONTRAST_RING_DEG : INFINITY;
        double e = needed_eccentricity_deg(l, acuity, contrast, xi_cpd, scale, contrast ? ring_contrast(l, k) : 1.0);
        if (e > inner)
            radius = fmax(radius, fmin(e, outer));
    }
    return radius + l->centre_offset_deg;
}

/* Per ring, the coarsest scale that loses nothing visible there (1 when none does). */
static void fill_needed_scales(struct frm_layers *l, const struct acu_limits *acuity,
                               const struct acu_contrast_limits *contrast, double xi_cpd)
{
    for (int k = 0; k < RND_CONTRAST_RINGS; ++k) {
        double c = contrast ? ring_contrast(l, k) : 1.0;
        l->needed_scale[k] = 1.0;
        for (int i = FRM_LAYER_SCALES - 1; i >= 1; --i)
            if (needed_eccentricity_deg(l, acuity, contrast, xi_cpd, frm_layer_scales[i], c) <=
                k * RND_CONTRAST_RING_DEG) {
                l->needed_scale[k] = frm_layer_scales[i];
                break;
            }
    }
}

/* render's setting for a scale and radius around the frame's centre (frm_layers_setting's, per candidate). */
static void setting_of(const struct frm_layers *l, double scale, double radius_deg, const struct hmd_eye *eyes,
                       hl_quatd orientation, struct rnd_layers *out)
{
    memset(out, 0, sizeof *out);
    out->periphery_scale = scale;
    out->inset_radius_deg = radius_deg;
    out->blend_deg = l->blend_deg;
    for (int e = 0; e < 2; ++e) {
        out->centre_eye[e] = hl_q_rotate(hl_q_conj(orientation), l->centre_world);
        out->eyes[e] = eyes[e];
    }
}

static void add_candidate(struct frm_layers *l, const struct frm_layers_view *view, double scale, double radius_deg,
                          double ceiling_deg, int scale_index)
{
    struct rnd_layers setting;
    setting_of(l, scale, radius_deg, view->eyes, view->head_orientation, &setting);
    struct rnd_layer_plan plan;
    /* The insets' rectangles depend on the radius only: another scale's plan of the same radius
     * serves, with this scale's periphery. */
    int same = -1;
    for (int k = 1; k < l->cand_count && same < 0; ++k)
        if (l->cand[k].inset_radius_deg == radius_deg)
            same = k;
    if (same >= 0) {
        plan = l->cand[same].plan;
        plan.periphery_px[0] = (int)fmax(1.0, lround(scale * view->eye_w_px));
        plan.periphery_px[1] = (int)fmax(1.0, lround(scale * view->eye_h_px));
        plan.periphery_px_total = 2.0 * plan.periphery_px[0] * plan.periphery_px[1];
    } else if (rnd_layer_plan_make(&setting, view->eye_w_px, view->eye_h_px, &plan) != 0) {
        return;
    }
    if (plan.covers[0] || plan.covers[1])
        return; /* an inset covering an eye is no cheaper than the plain frame */
    struct frm_layer_candidate *c = &l->cand[l->cand_count++];
    c->plan = plan;
    c->scale = scale;
    c->inset_radius_deg = radius_deg;
    c->ceiling_radius_deg = ceiling_deg;
    c->overhead_ms = scale_index >= 0 ? l->overhead_ms[scale_index] : 0.0;
    c->loses = radius_deg < ceiling_deg;
}

/* D of each scale on object k (frame/layers.h): the octave bands ξ, ξ/2, … above s·ξ that the
 * periphery cannot show, each adding max(0, c·S·k − 1) (contrast criterion) or 1 where Reddy's
 * min(H, ξ)·s resolves it (acuity criterion). */
static void fill_resolution_loss(struct frm_layers *l, const struct acu_limits *acuity,
                                 const struct acu_contrast_limits *contrast, double xi_cpd, size_t k,
                                 double eccentricity_deg, double velocity_degps)
{
    double *row = l->resolution_loss + k * FRM_LAYER_SCALES;
    double from_gaze = fmax(0.0, l->centre_angle_deg[k] - l->centre_offset_deg);
    int ring = (int)(from_gaze / RND_CONTRAST_RING_DEG);
    double c = contrast ? ring_contrast(l, ring < RND_CONTRAST_RINGS ? ring : RND_CONTRAST_RINGS - 1) : 1.0;
    double limit_cpd = contrast ? 0.0 : acu_limit_cpd(acuity, velocity_degps, eccentricity_deg, NULL);
    row[0] = 0.0;
    for (int i = 1; i < FRM_LAYER_SCALES; ++i) {
        double d = 0.0;
        for (double rho = xi_cpd; rho > frm_layer_scales[i] * xi_cpd * (1.0 + 1e-9); rho *= 0.5) {
            if (contrast) {
                double sens = acu_contrast_band_sensitivity(contrast, rho, velocity_degps, eccentricity_deg);
                d += fmax(0.0, c * sens * contrast->k_scale - 1.0);
            } else {
                d += rho <= limit_cpd ? 1.0 : 0.0;
            }
        }
        row[i] = d;
    }
}

void frm_layers_plan(struct frm_layers *l, const struct frm_layers_view *view, const struct acu_limits *acuity,
                     const struct acu_contrast_limits *contrast, double xi_cpd, const double *center_m,
                     const double *radius_m, const uint32_t *visible, size_t count, const double *eccentricity_deg,
                     const double *velocity_degps)
{
    const struct acu_viewer *viewer = view->viewer;
    l->xi_cpd = xi_cpd;
    hl_vec3d head_forward = hl_q_rotate(view->head_orientation, hl_v3(0, 0, -1));
    double half_ipd_m = view->half_ipd_m;
    l->cand_count = 1;
    l->first_loss = 1;
    l->chosen = 0;
    l->evaluated = 0;
    l->inset_px_of = -1;
    memset(&l->cand[0], 0, sizeof l->cand[0]);
    l->cand[0].scale = 1.0;
    if (l->mode == FRM_FOVEATION_OFF)
        return;
    /* Gaze foveation follows the gaze model's gaze (the measured one under tracked); fixed stays on
     * the lens centre, and pays for the eye looking elsewhere with a wider inset. */
    l->centre_world = l->mode == FRM_FOVEATION_GAZE ? viewer->gaze_dir : head_forward;
    l->centre_offset_deg = angle_deg(l->centre_world, viewer->gaze_dir);
    double slowest = INFINITY;
    for (size_t k = 0; k < count; ++k) {
        const double *c = &center_m[3 * (size_t)visible[k]];
        hl_vec3d d = hl_v3(c[0] - viewer->eye_position_m.x, c[1] - viewer->eye_position_m.y,
                           c[2] - viewer->eye_position_m.z);
        double dist = hl_v3_length(d), r = radius_m[visible[k]];
        l->centre_angle_deg[k] = angle_deg(d, l->centre_world);
        /* The sphere's angular radius from the cyclopean eye, widened by what either eye sees more. */
        double reach = dist > r + half_ipd_m ? asin((r + half_ipd_m) / dist) * HL_DEG_PER_RAD : 180.0;
        l->radius_deg[k] = reach;
        slowest = fmin(slowest, velocity_degps[k]);
    }
    l->slowest_degps = isfinite(slowest) && !view->fovea_held ? slowest : 0.0;
    fill_needed_scales(l, acuity, contrast, xi_cpd);
    /* The resolution loss only lossy settings need: filled on first use (candidate_loss). */
    l->loss = (struct frm_layers_loss_inputs){acuity, contrast, eccentricity_deg, velocity_degps, count, 0};
    double ceilings[FRM_LAYER_SCALES] = {0.0};
    for (int i = 1; i < FRM_LAYER_SCALES; ++i)
        ceilings[i] = ceiling_radius_deg(l, acuity, contrast, xi_cpd, frm_layer_scales[i]);
    if (l->mode == FRM_FOVEATION_ADAPTIVE) { /* the controller's scale, the whole eye, no inset */
        double scale = frm_adaptive_scale(&l->adaptive);
        if (scale < 1.0) {
            int i = scale_index(scale);
            l->cand_count = 0;
            add_candidate(l, view, scale, 0.0, ceilings[i], i);
            if (l->cand_count == 0)
                l->cand_count = 1;
        }
        l->first_loss = l->cand_count;
        return;
    }
    if (l->forced_scale > 0.0) { /* --periphery-scale: this setting alone (the plain frame if it covers an eye) */
        for (int i = 1; i < FRM_LAYER_SCALES; ++i)
            if (fabs(frm_layer_scales[i] - l->forced_scale) <= 1e-9) {
                double radius = l->forced_radius_deg >= 0.0 ? l->forced_radius_deg : ceilings[i];
                l->cand_count = 0;
                add_candidate(l, view, frm_layer_scales[i], radius, ceilings[i], i);
                if (l->cand_count == 0)
                    l->cand_count = 1; /* cand[0] is still the plain frame */
            }
        l->first_loss = l->cand_count;
        return;
    }
    /* Each scale with its ceiling's inset where that is within the fovea's (it loses nothing), then
     * each other scale at the fovea's (or every scale at --inset-deg). */
    double cap_deg = l->forced_radius_deg >= 0.0 ? l->forced_radius_deg : FRM_LAYER_FOVEA_DEG + l->centre_offset_deg;
    for (int lossy = 0; lossy < 2; ++lossy) {
        for (int i = 1; i < FRM_LAYER_SCALES; ++i) {
            double radius = l->forced_radius_deg >= 0.0 ? cap_deg : fmin(ceilings[i], cap_deg);
            if ((radius < ceilings[i]) == lossy)
                add_candidate(l, view, frm_layer_scales[i], radius, ceilings[i], i);
        }
        if (!lossy)
            l->first_loss = l->cand_count;
    }
}

/* The share of an object's disc (by diameter) nearer the centre than radius_deg. */
static double share_within(double centre_deg, double half_deg, double radius_deg)
{
    if (half_deg <= 0.0)
        return centre_deg < radius_deg ? 1.0 : 0.0;
    double s = (radius_deg - (centre_deg - half_deg)) / (2.0 * half_deg);
    return s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
}

/* The level the periphery draws an object at under candidate c: its level, or its periphery ceiling
 * at c's scale where that is coarser. */

static int periphery_level(const struct frm_layers *l, const struct frm_layer_candidate *c, int level, size_t k)
{
    int ceiling = l->periphery_ceiling[k * FRM_LAYER_SCALES + scale_index(c->scale)];
    return ceiling > level ? ceiling : level;
}

void frm_layers_inset_pixels(struct frm_layers *l, int c, const struct scn_scene *scene, const struct acu_eye *eyes,
                             const uint32_t *visible, size_t count, const double *pixels_px)
{
    const struct frm_layer_candidate *cand = &l->cand[c];
    l->inset_px_of = c;
    if (cand->scale >= 1.0 || cand->inset_radius_deg <= 0.0) {
        memset(l->inset_px, 0, count * sizeof *l->inset_px);
        return;
    }
    /* Each eye's inset rectangle as an image of its own: the same eye, the window's tangents. */
    struct acu_eye inset[2];
    int n = 0;
    for (int e = 0; e < 2; ++e) {
        const int *rect = cand->plan.inset_rect_px[e];
        if (rect[2] < 1 || rect[3] < 1)
            continue;
        const struct acu_eye *y = &eyes[e];
        double t[4];
        rnd_layer_rect_tangents(y->tan_left, y->tan_right, y->tan_down, y->tan_up, y->width_px, y->height_px, rect, t);
        inset[n] = *y;
        inset[n].tan_left = t[0], inset[n].tan_right = t[1], inset[n].tan_down = t[2], inset[n].tan_up = t[3];
        inset[n].width_px = rect[2], inset[n].height_px = rect[3];
        ++n;
    }
    double outer = cand->inset_radius_deg + l->blend_deg;
    for (size_t k = 0; k < count; ++k) {
        double theta = l->centre_angle_deg[k], half = l->radius_deg[k];
        if (theta - half >= outer || n == 0)
            l->inset_px[k] = 0.0;
        else if (theta + half <= outer && half < 90.0)
            l->inset_px[k] = pixels_px[k]; /* wholly inside the disc, so inside the rectangles */
        else
            frm_coverage_compute(scene, inset, n, &visible[k], 1, &l->inset_px[k], NULL);
    }
}

double frm_layers_level_cost_ms(const struct frm_layers *l, const struct frm_layer_candidate *c,
                                const struct lod_cost_model *m, const struct scn_chain *ch, int level,
                                double pixels_px, int boxed, size_t k)
{
    if (c->scale >= 1.0)
        return frm_level_cost_ms(m, ch, level, pixels_px, boxed);
    double theta = l->centre_angle_deg[k], half = l->radius_deg[k];
    double outer = c->inset_radius_deg + l->blend_deg;
    double cost = 0.0;
    if (c->inset_radius_deg > 0.0 && theta - half < outer) /* the inset draws the band too */
        cost += l->costed && l->cost.inset_measured
                    ? frm_level_inset_cost_ms(&l->cost.inset, ch, level, l->inset_px[k],
                                              pixels_px > 0.0 ? l->inset_px[k] / pixels_px : 1.0, boxed)
                    : frm_level_cost_ms(m, ch, level, l->inset_px[k], boxed);
    int periphery = periphery_level(l, c, level, k);
    if (theta + half > c->inset_radius_deg && periphery != LOD_DROP) /* DROP: invisible at that scale */
        cost += frm_level_cost_ms(l->costed ? &l->cost.periphery[scale_index(c->scale)] : m, ch, periphery,
                                  pixels_px * c->scale * c->scale, boxed);
    return cost;
}

int frm_layers_outcome_better(const struct frm_layer_outcome *a, const struct frm_layer_outcome *b)
{
    if (fabs(a->late_ms - b->late_ms) > FRM_LAYER_LATE_TOLERANCE_MS)
        return a->late_ms < b->late_ms;
    if (fabs(a->dropped_px - b->dropped_px) > 0.5)
        return a->dropped_px < b->dropped_px;
    if (fabs(a->margin_ms - b->margin_ms) > FRM_LAYER_MARGIN_TIE_MS)
        return a->margin_ms < b->margin_ms;
    double tie = 1e-9 * fmax(1.0, fabs(b->benefit));
    if (fabs(a->benefit - b->benefit) > tie)
        return a->benefit > b->benefit;
    if (fabs(a->visible_loss_px - b->visible_loss_px) > 0.5)
        return a->visible_loss_px < b->visible_loss_px;
    return a->cost_ms < b->cost_ms;
}

/* Object k's resolution loss D under candidate c, and the share of its image the periphery draws
 * (*periphery). The first call for a lossy candidate in a frame fills every visible object's D. */
static double candidate_loss(struct frm_layers *l, const struct frm_layer_candidate *c, size_t k, double *periphery)
{
    if (!l->loss.ready) { /* once a frame, and only in frames that weigh a lossy setting */
        const struct frm_layers_loss_inputs *in = &l->loss;
        for (size_t j = 0; j < in->count; ++j)
            fill_resolution_loss(l, in->acuity, in->contrast, l->xi_cpd, j, in->eccentricity_deg[j],
                                 in->velocity_degps[j]);
        l->loss.ready = 1;
    }
    double theta = l->centre_angle_deg[k], half = l->radius_deg[k];
    *periphery = 1.0 - share_within(theta, half, c->inset_radius_deg + 0.5 * l->blend_deg);
    return l->resolution_loss[k * FRM_LAYER_SCALES + scale_index(c->scale)];
}

double frm_layers_benefit_share(struct frm_layers *l, const struct frm_layer_candidate *c, size_t k)
{
    if (c->scale >= 1.0 || !c->loses)
        return 1.0;
    double periphery, d = candidate_loss(l, c, k, &periphery);
    /* The inset's part keeps its detail; the periphery's part is worth what a level losing D is. */
    return (1.0 - periphery) + periphery * lod_benefit_perceptual_accuracy(d);
}

double frm_layers_visible_loss_px(struct frm_layers *l, const struct frm_layer_candidate *c, const double *pixels_px,
                                  size_t count)
{
    if (c->scale >= 1.0 || !c->loses)
        return 0.0;
    double loss = 0.0;
    for (size_t k = 0; k < count; ++k)
        loss += pixels_px[k] * (1.0 - frm_layers_benefit_share(l, c, k));
    return loss;
}

double frm_layers_level_share(struct frm_layers *l, const struct frm_layer_candidate *c, size_t k,
                              const struct lod_benefit_params *p, double samples, double pixels_px)
{
    if (c->scale >= 1.0 || !c->loses)
        return 1.0;
    double periphery, d = candidate_loss(l, c, k, &periphery);
    if (!(d > 0.0) || !(periphery > 0.0))
        return 1.0; /* nothing visible lost on it: a finer scale would earn nothing */
    /* Funkhouser & Séquin §5: Samples never more than the pixels covered — the periphery covers the
     * object with s² of its pixels. */
    double full = lod_benefit_accuracy(p, samples, pixels_px);
    double coarse = lod_benefit_accuracy(p, samples, c->scale * c->scale * pixels_px);
    return full > 0.0 ? (1.0 - periphery) + periphery * coarse / full : 1.0;
}

void frm_layers_setting(const struct frm_layers *l, const struct hmd_eye eyes[2], const hl_quatd orientation[2],
                        struct rnd_layers *out)
{
    const struct frm_layer_candidate *c = &l->cand[l->chosen];
    setting_of(l, c->scale, c->inset_radius_deg, eyes, orientation[0], out);
    out->centre_eye[1] = hl_q_rotate(hl_q_conj(orientation[1]), l->centre_world);
}

void frm_layers_masks(struct frm_layers *l, size_t count, size_t extra)
{
    const struct frm_layer_candidate *c = &l->cand[l->chosen];
    double outer = c->inset_radius_deg + l->blend_deg;
    for (size_t k = 0; k < count; ++k) {
        double theta = l->centre_angle_deg[k], half = l->radius_deg[k];
        uint8_t m = 0;
        if (c->inset_radius_deg > 0.0 && theta - half < outer)
            m |= RND_LAYER_INSET;
        if (theta + half > c->inset_radius_deg)
            m |= RND_LAYER_PERIPHERY;
        l->mask[k] = m;
    }
    memset(l->mask + count, RND_LAYER_BOTH, extra); /* group impostors: not planned per layer */
}

uint8_t frm_layers_shown_ceiling(const struct frm_layers *l, const struct frm_layer_candidate *c, size_t k)
{
    uint8_t own = l->periphery_ceiling[k * FRM_LAYER_SCALES];
    if (c->scale >= 1.0 || (c->inset_radius_deg > 0.0 &&
                            l->centre_angle_deg[k] - l->radius_deg[k] < c->inset_radius_deg + l->blend_deg))
        return own;
    return (uint8_t)periphery_level(l, c, own, k);
}

void frm_layers_periphery_levels(struct frm_layers *l, const uint8_t *lod, size_t count, size_t extra)
{
    const struct frm_layer_candidate *c = &l->cand[l->chosen];
    for (size_t k = 0; k < count; ++k)
        l->periphery_lod[k] = lod[k] == LOD_DROP ? lod[k] : (uint8_t)periphery_level(l, c, lod[k], k);
    memcpy(l->periphery_lod + count, lod + count, extra);
}

void frm_layers_periphery_ceilings(struct frm_layers *l, const struct acu_contrast_limits *contrast,
                                   const struct acu_limits *acuity, const struct lod_chain *chains,
                                   const uint32_t *chain_of_object, const uint32_t *visible, size_t count,
                                   const double *eccentricity_deg, const double *velocity_degps,
                                   const double *diameter_deg, const uint8_t *ceiling_level)
{
    double xi_cpd = l->xi_cpd;
    for (size_t k = 0; k < count; ++k)
        l->periphery_ceiling[k * FRM_LAYER_SCALES] = ceiling_level[k];
    for (int i = 1; i < FRM_LAYER_SCALES; ++i) {
        int used = 0; /* only the scales this frame's candidates draw at are read */
        for (int c = 0; c < l->cand_count && !used; ++c)
            used = l->cand[c].scale < 1.0 && scale_index(l->cand[c].scale) == i;
        if (!used)
            continue;
        uint8_t *out = l->lod_scratch;
        struct lod_select_stats stats = {0};
        if (contrast) {
            struct acu_contrast_limits at_scale = *contrast;
            at_scale.xi_cpd = frm_layer_scales[i] * xi_cpd;
            lod_select_contrast(&at_scale, acuity, chains, chain_of_object, visible, count, eccentricity_deg,
                                velocity_degps, diameter_deg, out, &stats);
        } else {
            struct acu_limits at_scale = *acuity;
            acu_limits_init(&at_scale, frm_layer_scales[i] * xi_cpd, acuity->scale);
            at_scale.use_velocity = acuity->use_velocity, at_scale.use_eccentricity = acuity->use_eccentricity;
            lod_select_reddy(&at_scale, chains, chain_of_object, visible, count, eccentricity_deg, velocity_degps,
                             diameter_deg, out, NULL, &stats);
        }
        for (size_t k = 0; k < count; ++k) {
            uint8_t coarser = out[k] > ceiling_level[k] ? out[k] : ceiling_level[k];
            l->periphery_ceiling[k * FRM_LAYER_SCALES + i] = coarser;
        }
    }
}

void frm_adaptive_init(struct frm_adaptive *a)
{
    a->level = 0, a->cheap_frames = 0, a->hold = 0;
    a->last_draw_ms = -1.0;
}

double frm_adaptive_scale(const struct frm_adaptive *a)
{
    return sqrt(pow(FRM_ADAPTIVE_FILL_STEP, a->level));
}

static void adaptive_step(struct frm_adaptive *a, int levels)
{
    a->level += levels;
    a->level = a->level < 0 ? 0 : a->level >= FRM_ADAPTIVE_LEVELS ? FRM_ADAPTIVE_LEVELS - 1 : a->level;
}

void frm_adaptive_update(struct frm_adaptive *a, double draw_ms, double budget_ms)
{
    if (!(draw_ms >= 0.0) || !(budget_ms > 0.0))
        return; /* nothing measured: no decision */
    double share = draw_ms / budget_ms;
    double next = a->last_draw_ms >= 0.0 ? (2.0 * draw_ms - a->last_draw_ms) / budget_ms : share;
    a->last_draw_ms = draw_ms;
    int held = a->hold > 0; /* a drop in one of the last FRM_ADAPTIVE_HOLD_FRAMES frames */
    if (held)
        --a->hold;
    if (share > FRM_ADAPTIVE_HIGH) {
        if (!held) {
            adaptive_step(a, 2);
            a->hold = FRM_ADAPTIVE_HOLD_FRAMES;
        }
        a->cheap_frames = 0;
    } else if (next > FRM_ADAPTIVE_HIGH) {
        if (!held) {
            adaptive_step(a, 1);
            a->hold = FRM_ADAPTIVE_HOLD_FRAMES;
        }
        a->cheap_frames = 0;
    } else if (share < FRM_ADAPTIVE_LOW) {
        ++a->cheap_frames;
        if (a->cheap_frames == 6 || a->cheap_frames == 12) {
            adaptive_step(a, a->cheap_frames == 6 ? -1 : -2);
            if (a->cheap_frames == 12)
                a->cheap_frames = 0;
        }
    } else {
        a->cheap_frames = 0;
    }
}
