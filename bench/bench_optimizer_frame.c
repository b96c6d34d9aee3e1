/* One frame of `hmdlod bench optimizer`: from a head pose to a built lod_problem, on the embeddable
 * core's calls only (what an engine does per frame, DESIGN.md steps 3–6), over arrays sized once. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench_optimizer_frame.h"

/* Four synthetic chains (level 0 finest): triangle and vertex counts of typical scanned props and
 * Reddy's removed frequencies in cycles per object diameter (made up, in the range `hmdlod analyze`
 * measures on the shared meshes, docs/analysis.md). */
static const uint32_t chain_triangles[BCH_OPT_CHAINS][BCH_OPT_LEVELS] = {
    {3906, 840, 256, 78}, {8000, 2000, 500, 120}, {1200, 400, 120, 40}, {20000, 4800, 1100, 240}};
static const uint32_t chain_vertices[BCH_OPT_CHAINS][BCH_OPT_LEVELS] = {
    {2016, 465, 153, 56}, {4100, 1050, 270, 70}, {640, 220, 72, 26}, {10200, 2500, 600, 140}};
static const double chain_freq_cpdiam[BCH_OPT_CHAINS][BCH_OPT_LEVELS] = {
    {INFINITY, 40.0, 18.0, 7.0}, {INFINITY, 48.0, 20.0, 8.0}, {INFINITY, 30.0, 12.0, 5.0}, {INFINITY, 64.0, 28.0, 10.0}};

/* Lost-contrast spectra of the synthetic chains (7 bands, 1 … 64 c/diam): the field object's and the
 * chair's as `hmdlod analyze` measures them (docs/RESULTS.md, issue 31), rounded; chains 2 and 3
 * reuse them. Level 0 loses nothing. */
enum { BCH_OPT_BANDS = 7 };
static const double chain_lost_contrast[2][BCH_OPT_LEVELS - 1][BCH_OPT_BANDS] = {
    {{0.11, 0.26, 0.31, 0.30, 0.31, 0.42, 0.79}, {0.33, 0.68, 0.81, 0.76, 0.76, 0.75, 0.68},
     {0.81, 1.46, 1.38, 1.25, 0.95, 0.78, 0.64}},
    {{0.38, 0.48, 1.28, 1.38, 1.13, 1.44, 1.91}, {5.5, 6.4, 10.0, 18.5, 30.9, 20.8, 17.0},
     {6.2, 7.3, 13.9, 16.6, 15.7, 16.1, 8.9}}};

/* The CSF table of every view: 116 KB, so not in the struct the bench copies per variant. */
static struct acu_csf_table bch_opt_csf;

void bch_opt_view_init(struct bch_opt_view *v, const struct hmd_profile *display)
{
    memset(v, 0, sizeof *v);
    v->eye[0] = hmd_eye_frustum(display, HMD_EYE_LEFT);
    v->eye[1] = hmd_eye_frustum(display, HMD_EYE_RIGHT);
    v->width_px = display->eye_width_px;
    v->height_px = display->eye_height_px;
    acu_limits_init(&v->limits, hmd_compute_xi(display).used_cpd, 1.0);
    frm_cull_frustum_init(&v->frustum, display, 0.05);
    for (int c = 0; c < BCH_OPT_CHAINS; ++c) {
        v->chains[c].lod_count = BCH_OPT_LEVELS;
        for (int l = 0; l < BCH_OPT_LEVELS; ++l)
            v->chains[c].unique_freq_cpdiam[l] = chain_freq_cpdiam[c][l];
        v->chains[c].band_count = BCH_OPT_BANDS;
        for (int l = 1; l < BCH_OPT_LEVELS; ++l)
            for (int b = 0; b < BCH_OPT_BANDS; ++b)
                v->chains[c].lost_contrast[l][b] = chain_lost_contrast[c & 1][l - 1][b];
    }
    /* 20 cd/m²: a 100 cd/m² panel showing a scene of mean relative luminance 0.2. */
    acu_csf_table_fill_cycles(&bch_opt_csf, ACU_CSF_CASTLE, 20.0, ACU_CSF_GABOR_CYCLES);
    acu_contrast_limits_init(&v->contrast, &bch_opt_csf, hmd_compute_xi(display).used_cpd, 1.0, 2.0);
    /* The additive form with coefficients of the order llvmpipe shows on two cores (bench replay:
     * ~100k triangles per eye in ~10 ms): assumed, not calibrated; the optimizer's time does not
     * depend on their values, only on how many candidates the budget admits. */
    v->cost = (struct lod_cost_model){.form = LOD_COST_ADDITIVE, .c0_ms = 1.5, .c1_ms_per_triangle = 4.0e-5,
                                      .c2_ms_per_vertex = 1.0e-5, .c3_ms_per_pixel = 1.5e-6, .c4_ms_per_draw = 0.01};
    lod_benefit_params_default(&v->benefit);
}

int bch_opt_work_alloc(struct bch_opt_work *w, size_t cap, size_t scene_count)
{
    memset(w, 0, sizeof *w);
    w->cap = cap;
    w->scene_count = scene_count;
    size_t cand = cap * BCH_OPT_LEVELS;
    w->visible = malloc(scene_count * sizeof *w->visible); /* scn_cull may list every object */
    w->object_id = malloc(cap * sizeof *w->object_id);
    w->first = malloc(cap * sizeof *w->first);
    w->samples = malloc(cand * sizeof *w->samples);
    w->chain_of_object = malloc(scene_count * sizeof *w->chain_of_object);
    w->pixels_px = malloc(cap * sizeof(double));
    w->ecc_deg = malloc(cap * sizeof(double));
    w->vel_degps = malloc(cap * sizeof(double));
    w->diam_deg = malloc(cap * sizeof(double));
    w->cost_ms = malloc(cand * sizeof(double));
    w->benefit = malloc(cand * sizeof(double));
    w->ceiling = malloc(cap);
    w->previous = malloc(cap);
    w->count = malloc(cap);
    w->level = malloc(cand);
    w->choice = malloc(cap);
    w->choice_ref = malloc(cap);
    w->level_out = malloc(cap);
    w->last_level = malloc(scene_count);
    w->hull_scratch = malloc(cap * sizeof *w->hull_scratch);
    w->scratch = malloc(lod_scratch_bytes(cap, cand));
    if (!w->visible || !w->object_id || !w->first || !w->samples || !w->chain_of_object || !w->pixels_px ||
        !w->ecc_deg || !w->vel_degps || !w->diam_deg || !w->cost_ms || !w->benefit || !w->ceiling || !w->previous ||
        !w->count || !w->level || !w->choice || !w->choice_ref || !w->level_out || !w->last_level || !w->hull_scratch ||
        !w->scratch) {
        bch_opt_work_free(w);
        return -1;
    }
    for (size_t i = 0; i < scene_count; ++i)
        w->chain_of_object[i] = bch_opt_chain_of((uint32_t)i);
    bch_opt_work_forget(w);
    return 0;
}

void bch_opt_work_free(struct bch_opt_work *w)
{
    void *all[] = {w->visible, w->object_id, w->first, w->samples, w->chain_of_object, w->pixels_px, w->ecc_deg,
                   w->vel_degps, w->diam_deg, w->cost_ms, w->benefit, w->ceiling, w->previous, w->count, w->level,
                   w->choice, w->choice_ref, w->level_out, w->last_level, w->hull_scratch, w->scratch};
    for (size_t k = 0; k < sizeof all / sizeof all[0]; ++k)
        free(all[k]);
    memset(w, 0, sizeof *w);
}

void bch_opt_work_forget(struct bch_opt_work *w)
{
    memset(w->last_level, LOD_UNSEEN, w->scene_count);
    w->margin_value = 0.0; /* a cold start has no margin to centre fs's filters on */
}

size_t bch_opt_cull(const struct bch_opt_view *v, const struct scn_scene *s, struct scn_culler *c,
                 const struct trk_pose *pose, struct bch_opt_work *w)
{
    struct scn_plane planes[6];
    int np = frm_cull_frustum_planes(&v->frustum, pose, planes);
    if (v->far_m > 0) { /* inside when closer than far_m along the view direction */
        hl_vec3d n = hl_q_rotate(pose->orientation, hl_v3(0, 0, 1));
        planes[np].normal[0] = n.x, planes[np].normal[1] = n.y, planes[np].normal[2] = n.z;
        planes[np].offset_m = v->far_m - hl_v3_dot(n, pose->position_m);
        ++np;
    }
    /* scn_cull may list every object (w->visible has room); a problem holds at most cap of them. */
    uint32_t n = c ? scn_cull(s, planes, np, c, w->visible, NULL) : scn_cull_flat(s, planes, np, w->visible, NULL);
    w->n = n < w->cap ? n : w->cap;
    return n;
}

void bch_opt_build(const struct bch_opt_view *v, const struct scn_scene *s, const struct trk_pose *pose, double budget_ms,
                struct bch_opt_work *w)
{
    size_t n = w->n;
    struct acu_viewer viewer = {
        .eye_position_m = pose->position_m,
        .gaze_dir = hl_v3_normalize(hl_q_rotate(pose->orientation, hl_v3(0, 0, -1))), /* no eye tracker */
        .angular_velocity_radps = pose->angular_velocity_radps,
        .linear_velocity_mps = hl_v3(0, 0, 0),
    };
    struct acu_eye eyes[2];
    for (int e = 0; e < 2; ++e) {
        eyes[e].position_m = hl_v3_add(pose->position_m, hl_q_rotate(pose->orientation, hl_v3(v->eye[e].offset_x_m, 0, 0)));
        eyes[e].orientation = pose->orientation;
        eyes[e].tan_left = v->eye[e].tan_left, eyes[e].tan_right = v->eye[e].tan_right;
        eyes[e].tan_up = v->eye[e].tan_up, eyes[e].tan_down = v->eye[e].tan_down;
        eyes[e].width_px = v->width_px, eyes[e].height_px = v->height_px;
    }
    acu_compute_geometry(&viewer, s->center_m, s->radius_m, NULL, w->visible, n, w->ecc_deg, w->vel_degps,
                         w->diam_deg);
    acu_compute_pixels(eyes, 2, s->center_m, s->radius_m, w->visible, n, w->pixels_px);
    lod_select_reddy(&v->limits, v->chains, w->chain_of_object, w->visible, n, w->ecc_deg, w->vel_degps,
                     w->diam_deg, w->ceiling, NULL, NULL);
    /* Candidates cheapest first: candidate j draws level BCH_OPT_LEVELS − 1 − j. Triangles, vertices
     * and draws count both eyes (lod.h's cost model); pixels are already summed over the eyes. */
    for (size_t k = 0; k < n; ++k) {
        uint32_t obj = w->visible[k], ch = w->chain_of_object[obj];
        w->object_id[k] = obj;
        w->first[k] = (uint32_t)(k * BCH_OPT_LEVELS);
        w->count[k] = BCH_OPT_LEVELS;
        w->previous[k] = w->last_level[obj];
        for (int j = 0; j < BCH_OPT_LEVELS; ++j) {
            size_t c = k * BCH_OPT_LEVELS + (size_t)j;
            int l = BCH_OPT_LEVELS - 1 - j;
            w->level[c] = (uint8_t)l;
            w->samples[c] = chain_vertices[ch][l];
            w->cost_ms[c] = lod_cost_object_ms(&v->cost, 2.0 * chain_triangles[ch][l], 2.0 * chain_vertices[ch][l],
                                               w->pixels_px[k], 2.0);
        }
    }
    lod_benefit_fill(&v->benefit, n, w->first, w->count, w->level, w->samples, w->pixels_px, NULL, w->ceiling,
                     w->previous, NULL, w->benefit);
    lod_hull_reduce(n, w->first, w->count, w->cost_ms, w->benefit, w->level, budget_ms, w->hull_scratch);
    w->p = (struct lod_problem){.object_count = n, .object_id = w->object_id, .first = w->first, .count = w->count,
                                .cost_ms = w->cost_ms, .benefit = w->benefit, .level = w->level, .budget_ms = budget_ms,
                                .value_hint = w->margin_value};
    lod_choice_start(&w->p, w->previous, w->choice);
}

void bch_opt_cost_range(const struct bch_opt_work *w, double *coarsest_ms, double *ceiling_ms)
{
    double lo = 0, hi = 0;
    for (size_t k = 0; k < w->n; ++k) {
        if (w->count[k] == 0)
            continue;
        lo += w->cost_ms[w->first[k]];
        hi += w->cost_ms[w->first[k] + w->count[k] - 1u];
    }
    *coarsest_ms = lo, *ceiling_ms = hi;
}

void bch_opt_remember(struct bch_opt_work *w, const uint8_t *choice)
{
    lod_level_of_choice(&w->p, choice, w->level_out);
    /* Objects that left the view become unseen. The whole scene array is cleared (a memset of
     * scene_count bytes), which is outside every timed section. */
    memset(w->last_level, LOD_UNSEEN, w->scene_count); /* not bch_opt_work_forget: fs's margin stays */
    for (size_t k = 0; k < w->n; ++k)
        w->last_level[w->visible[k]] = w->level_out[k] == LOD_DROP ? LOD_UNSEEN : w->level_out[k];
}

struct trk_pose bch_opt_pose_turned(const struct trk_pose *pose, double yaw_deg)
{
    struct trk_pose t = *pose;
    t.orientation = hl_q_normalize(hl_q_mul(hl_q_from_axis_angle(hl_v3(0, 1, 0), yaw_deg * HL_RAD_PER_DEG),
                                            pose->orientation));
    return t;
}
