/* From one imported mesh to an LOD chain asset: the levels (ratios or a screen-space error budget),
 * each level's two-sided Hausdorff error against level 0, a tight bounding sphere and the geometric
 * spatial frequency R/ε the acuity model compares (Reddy 1998 §3.2). */
#include "scene/lodgen_internal.h"
#include "scene/scene_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { LODGEN_MIN_TRIANGLES = 16, LODGEN_MAX_CANDIDATES = 24 };
#define LODGEN_DEFAULT_FEATURE_DEG 60.0
#define LODGEN_DEFAULT_WIDTH_PX 1080.0 /* one HTC Vive eye's horizontal pixels */
#define LODGEN_DEFAULT_FOV_DEG 100.0   /* about its horizontal field of view per eye */

const char *scn_simplifier_name(enum scn_simplifier s)
{
    return s == SCN_SIMPLIFIER_OPENMESH ? "openmesh" : s == SCN_SIMPLIFIER_MESHOPT ? "meshopt" : NULL;
}

int scn_decimate_chain(const struct scn_mesh *in, const uint32_t *target_tris, int count,
                       enum scn_simplifier simplifier, double feature_angle_deg, struct scn_mesh *outs,
                       struct scn_decimate_timing *timing, const struct scn_chain_observer *obs,
                       struct hl_error *err)
{
    struct hl_error why;
    if (scn_mesh_check(in, "mesh to decimate", &why) != 0)
        return hl_fail(err, "%s", why.msg);
    for (int k = 0; k < count; ++k)
        if (target_tris[k] < 1 || (k > 0 && target_tris[k] >= target_tris[k - 1]))
            return hl_fail(err, "decimate: level %d: target %u triangles (need ≥ 1, fewer than the level before)",
                           k, target_tris[k]);
    if (simplifier == SCN_SIMPLIFIER_OPENMESH) {
        double angle = feature_angle_deg == 0 ? LODGEN_DEFAULT_FEATURE_DEG : feature_angle_deg;
        if (!(angle < 0 || (angle > 0 && angle <= 180)))
            return hl_fail(err, "decimate: feature angle %g° (need 0…180, or negative for none)", feature_angle_deg);
        return scn_om_decimate_chain(in, target_tris, count, angle, outs, timing, obs, err);
    }
    if (simplifier == SCN_SIMPLIFIER_MESHOPT) {
        double t = hl_clock_now_s();
        int rc = scn_meshopt_decimate_chain(in, target_tris, count, outs, obs, err);
        if (rc == 0 && timing)
            *timing = (struct scn_decimate_timing){0, 0, 0, hl_clock_now_s() - t, 0, 0};
        return rc;
    }
    return hl_fail(err, "decimate: unknown simplifier %d", (int)simplifier);
}

int scn_mesh_decimate_chain(const struct scn_mesh *in, const uint32_t *target_tris, int count,
                            enum scn_simplifier simplifier, double feature_angle_deg, struct scn_mesh *outs,
                            struct scn_decimate_timing *timing, struct hl_error *err)
{
    for (int k = 0; k < count; ++k)
        memset(&outs[k], 0, sizeof outs[k]);
    if (count < 1 || count > 64)
        return hl_fail(err, "decimate: %d levels (1…64)", count);
    return scn_decimate_chain(in, target_tris, count, simplifier, feature_angle_deg, outs, timing, NULL, err);
}

static int copy_mesh(const struct scn_mesh *in, struct scn_mesh *out)
{
    memset(out, 0, sizeof *out);
    size_t nv = (size_t)in->vertex_count * 3, ni = in->index_count;
    out->positions = malloc((nv + 1) * sizeof(float));
    out->normals = malloc((nv + 1) * sizeof(float));
    out->indices = malloc((ni + 1) * sizeof(uint32_t));
    if (!out->positions || !out->normals || !out->indices) {
        scn_mesh_free(out);
        return -1;
    }
    memcpy(out->positions, in->positions, nv * sizeof(float));
    if (in->normals)
        memcpy(out->normals, in->normals, nv * sizeof(float));
    memcpy(out->indices, in->indices, ni * sizeof(uint32_t));
    out->vertex_count = out->vertex_cap = in->vertex_count;
    out->index_count = out->index_cap = in->index_count;
    if (!in->normals)
        scn_mesh_smooth_normals(out);
    return 0;
}

int scn_mesh_decimate(const struct scn_mesh *in, uint32_t target_triangles, enum scn_simplifier simplifier,
                      double feature_angle_deg, struct scn_mesh *out, struct hl_error *err)
{
    memset(out, 0, sizeof *out);
    if (target_triangles < 1)
        return hl_fail(err, "decimate: target 0 triangles (need ≥ 1)");
    if (target_triangles >= in->index_count / 3) { /* nothing to remove: the mesh as it is */
        struct hl_error why;
        if (scn_mesh_check(in, "mesh to decimate", &why) != 0)
            return hl_fail(err, "%s", why.msg);
        return copy_mesh(in, out) == 0 ? 0 : hl_fail(err, "decimate: out of memory");
    }
    return scn_decimate_chain(in, &target_triangles, 1, simplifier, feature_angle_deg, out, NULL, NULL, err);
}

/* ---- bounds ------------------------------------------------------------------------------------ */

static hl_vec3d vpos(const struct scn_mesh *m, uint32_t i)
{
    const float *p = m->positions + 3 * (size_t)i;
    return hl_v3(p[0], p[1], p[2]);
}

static double max_dist(const struct scn_mesh *m, hl_vec3d c)
{
    double r = 0;
    for (uint32_t i = 0; i < m->vertex_count; ++i) {
        double d = hl_v3_length(hl_v3_sub(vpos(m, i), c));
        r = d > r ? d : r;
    }
    return r;
}

/* Ritter (1990), "An efficient bounding sphere": a far pair's midpoint, then grow towards every
 * point outside; within ~5–20 % of the optimum. Two passes so the second only confirms. */
static void ritter_sphere(const struct scn_mesh *m, hl_vec3d *center, double *radius)
{
    uint32_t y = 0, z = 0;
    double best = -1;
    for (uint32_t i = 0; i < m->vertex_count; ++i) {
        double d = hl_v3_length(hl_v3_sub(vpos(m, i), vpos(m, 0)));
        if (d > best)
            best = d, y = i;
    }
    best = -1;
    for (uint32_t i = 0; i < m->vertex_count; ++i) {
        double d = hl_v3_length(hl_v3_sub(vpos(m, i), vpos(m, y)));
        if (d > best)
            best = d, z = i;
    }
    hl_vec3d c = hl_v3_scale(hl_v3_add(vpos(m, y), vpos(m, z)), 0.5);
    double r = 0.5 * best;
    for (int pass = 0; pass < 2; ++pass)
        for (uint32_t i = 0; i < m->vertex_count; ++i) {
            hl_vec3d p = vpos(m, i);
            double d = hl_v3_length(hl_v3_sub(p, c));
            if (d > r) { /* new sphere: from the far side of the old one to p */
                double nr = 0.5 * (r + d);
                c = hl_v3_add(c, hl_v3_scale(hl_v3_sub(p, c), (nr - r) / d));
                r = nr;
            }
        }
    *center = c;
    *radius = max_dist(m, c); /* exact for this centre (guards the incremental rounding) */
}

static void lodset_bounds(struct scn_lodset *set)
{
    const struct scn_mesh *m0 = &set->levels[0];
    double lo[3], hi[3];
    scn_mesh_aabb(m0, lo, hi);
    memcpy(set->aabb_min_m, lo, sizeof lo);
    memcpy(set->aabb_max_m, hi, sizeof hi);
    hl_vec3d box_c = hl_v3(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2]));
    double box_r = max_dist(m0, box_c);
    hl_vec3d c;
    double r;
    ritter_sphere(m0, &c, &r);
    if (box_r < r)
        c = box_c, r = box_r;
    /* Coarser levels' vertices may sit a little outside (quadric-optimal placement): the sphere
     * must hold every level, as culling uses one sphere for whichever level is drawn. */
    for (int l = 1; l < set->level_count; ++l) {
        double d = max_dist(&set->levels[l], c);
        r = d > r ? d : r;
    }
    set->center_m[0] = c.x, set->center_m[1] = c.y, set->center_m[2] = c.z;
    set->radius_m = r;
}

/* ---- the chain -------------------------------------------------------------------------------------- */

struct lodgen_clock {
    const struct scn_lodgen_params *p;
    double *level_end_s; /* time each decimated level was done */
    int steps_done, steps_total;
};

static void lodgen_report(struct lodgen_clock *c)
{
    if (c->p->progress && c->steps_total > 0)
        c->p->progress(c->p->progress_user, (double)c->steps_done / c->steps_total);
}

static void lodgen_level_done(void *user, int level)
{
    struct lodgen_clock *c = user;
    c->level_end_s[level] = hl_clock_now_s();
    c->steps_done++;
    lodgen_report(c);
}

static int check_params(const struct scn_lodgen_params *p, struct hl_error *err)
{
    if (!scn_simplifier_name(p->simplifier))
        return hl_fail(err, "lodgen: unknown simplifier %d", (int)p->simplifier);
    if (p->max_error_px > 0) {
        if (!isfinite(p->max_error_px) || !(p->at_distance_m > 0) || !isfinite(p->at_distance_m))
            return hl_fail(err, "lodgen: max error %g px at %g m: need a finite error > 0 and distance > 0",
                           p->max_error_px, p->at_distance_m);
        if (p->fov_deg != 0 && !(p->fov_deg > 0 && p->fov_deg < 180))
            return hl_fail(err, "lodgen: reference field of view %g° (need 0…180, 0 = 100°)", p->fov_deg);
        if (p->width_px != 0 && !(p->width_px >= 1 && p->width_px <= 1e6))
            return hl_fail(err, "lodgen: reference width %g px (need 1…1e6, 0 = 1080)", p->width_px);
        return 0;
    }
    if (p->ratio_count < 1 || p->ratio_count > SCN_LODSET_MAX_LEVELS)
        return hl_fail(err, "lodgen: %d levels (need 1…%d)", p->ratio_count, SCN_LODSET_MAX_LEVELS);
    if (p->ratios[0] != 1.0)
        return hl_fail(err, "lodgen: ratio 1 is %g (the first level is the mesh itself: 1)", p->ratios[0]);
    for (int k = 1; k < p->ratio_count; ++k)
        if (!(p->ratios[k] > 0 && p->ratios[k] < p->ratios[k - 1]))
            return hl_fail(err, "lodgen: ratio %d is %g (need > 0 and below the one before, %g)", k + 1,
                           p->ratios[k], p->ratios[k - 1]);
    return 0;
}

/* Triangle targets from ratios, kept strictly decreasing and ≥ 1 (a tiny mesh can make two ratios
 * round to the same count: the later one is then dropped). */
static int ratio_targets(const struct scn_lodgen_params *p, uint32_t t0, uint32_t *targets)
{
    int n = 0;
    uint32_t prev = t0;
    for (int k = 1; k < p->ratio_count; ++k) {
        double want = floor(p->ratios[k] * t0 + 0.5);
        uint32_t t = want < 1 ? 1 : (uint32_t)want;
        if (t < prev)
            targets[n++] = prev = t;
    }
    return n;
}

static int measure_error(const struct scn_mesh *a, const struct scn_mesh *b, uint64_t samples, double *out_m,
                         struct hl_error *err)
{
    struct scn_hausdorff h;
    if (scn_mesh_hausdorff(a, b, samples, 1, &h, err) != 0)
        return -1;
    *out_m = h.max_m;
    return 0;
}

int scn_lodgen_build_timed(const struct scn_mesh *mesh, const struct scn_lodgen_params *p,
                           struct scn_lodset *out, struct scn_lodgen_stats *stats, struct hl_error *err)
{
    memset(out, 0, sizeof *out);
    struct scn_lodgen_stats st;
    memset(&st, 0, sizeof st);
    struct hl_error why;
    if (check_params(p, err) != 0)
        return -1;
    if (scn_mesh_check(mesh, "lodgen input", &why) != 0)
        return hl_fail(err, "%s", why.msg);
    uint32_t t0 = mesh->index_count / 3;
    int error_mode = p->max_error_px > 0;
    uint32_t targets[LODGEN_MAX_CANDIDATES];
    int n = 0;
    if (error_mode) {
        for (int j = 1; j <= LODGEN_MAX_CANDIDATES; ++j) {
            double want = floor(t0 * pow(2.0, -0.5 * j) + 0.5);
            if (want < LODGEN_MIN_TRIANGLES)
                break;
            if (n == 0 || (uint32_t)want < targets[n - 1])
                targets[n++] = (uint32_t)want;
        }
    } else {
        n = ratio_targets(p, t0, targets);
    }
    struct scn_mesh cand[LODGEN_MAX_CANDIDATES];
    double cand_end_s[LODGEN_MAX_CANDIDATES], cand_err_m[LODGEN_MAX_CANDIDATES];
    memset(cand, 0, sizeof cand);
    int levels_total = error_mode ? n + SCN_LODSET_MAX_LEVELS : 2 * n;
    struct lodgen_clock clk = {p, cand_end_s, 0, levels_total > 0 ? levels_total : 1};
    struct scn_chain_observer obs = {lodgen_level_done, &clk};
    lodgen_report(&clk);
    double start_s = hl_clock_now_s();
    if (n > 0 &&
        scn_decimate_chain(mesh, targets, n, p->simplifier, p->feature_angle_deg, cand, NULL, &obs, err) != 0)
        return -1;
    /* What the simplifier reached: a level no coarser than the one before ends the chain. */
    int reached = 0;
    for (uint32_t prev = t0; reached < n && cand[reached].index_count / 3 < prev; ++reached)
        prev = cand[reached].index_count / 3;
    st.stopped_early = reached < n;
    int rc = 0;
    int pick[SCN_LODSET_MAX_LEVELS], picks = 0;
    double budget[SCN_LODSET_MAX_LEVELS] = {0};
    uint64_t samples = p->hausdorff_samples;
    if (error_mode) {
        /* Screen-space error budget (see lodgen.h): px per radian at the centre of the reference
         * display; level k is for distances from at_distance_m·2^(k−1). Candidates are screened
         * with an eighth of the samples, the chosen ones measured again at full density; one that
         * then exceeds its budget gives way to the next finer candidate. */
        double fov = (p->fov_deg > 0 ? p->fov_deg : LODGEN_DEFAULT_FOV_DEG) * HL_RAD_PER_DEG;
        double px_per_rad = (p->width_px > 0 ? p->width_px : LODGEN_DEFAULT_WIDTH_PX) / fov;
        uint64_t screen = samples ? samples / 8 : ((uint64_t)1 << 17);
        for (int j = 0; j < reached && rc == 0; ++j) {
            rc = measure_error(mesh, &cand[j], screen > 1000 ? screen : 1000, &cand_err_m[j], err);
            clk.steps_done++;
            lodgen_report(&clk);
        }
        st.candidates = reached;
        int last = -1;
        for (int k = 1; rc == 0 && picks < SCN_LODSET_MAX_LEVELS - 1 && k <= 40 && last < reached - 1; ++k) {
            double dist = p->at_distance_m * pow(2.0, k - 1);
            double budget_m = p->max_error_px / px_per_rad * dist;
            int best = -1;
            for (int j = last + 1; j < reached; ++j)
                if (cand_err_m[j] <= budget_m)
                    best = j;
            if (best >= 0)
                budget[picks] = budget_m, pick[picks++] = last = best;
        }
    } else {
        for (int j = 0; j < reached; ++j)
            pick[picks++] = j;
    }
    if (rc == 0) {
        out->level_count = 1 + picks;
        if (copy_mesh(mesh, &out->levels[0]) != 0)
            rc = hl_fail(err, "lodgen: out of memory");
    }
    for (int k = 0; rc == 0 && k < picks; ++k) {
        int j = pick[k], finest = k > 0 ? pick[k - 1] + 1 : 0;
        double t = hl_clock_now_s();
        for (;;) {
            rc = measure_error(mesh, &cand[j], samples, &out->error_m[k + 1], err);
            if (rc != 0 || !error_mode || out->error_m[k + 1] <= budget[k] || j <= finest)
                break;
            --j;
        }
        if (rc != 0)
            break;
        pick[k] = j;
        out->levels[k + 1] = cand[j];
        memset(&cand[j], 0, sizeof cand[j]);
        st.target_triangles[k + 1] = targets[j];
        /* the chain's time from the previous kept level (or the start) to this one */
        st.decimate_s[k + 1] = cand_end_s[j] - (k == 0 ? start_s : cand_end_s[pick[k - 1]]);
        st.error_s[k + 1] = hl_clock_now_s() - t;
        clk.steps_done++;
        lodgen_report(&clk);
    }
    for (int j = 0; j < n; ++j)
        scn_mesh_free(&cand[j]);
    if (rc != 0) {
        scn_lodset_free(out);
        return -1;
    }
    st.target_triangles[0] = t0;
    lodset_bounds(out);
    out->source_hash = scn_mesh_hash(mesh);
    /* Shading: crease normals at the feature angle on every level, level 0 included (even when the
     * file had normals), so successive levels differ in geometry and not in how their normals were
     * made; the decimater keeps those same edges as feature lines. Done last: the errors, bounds and
     * hash above are of the welded meshes, and splitting only appends copies of existing positions. */
    double crease_deg = p->feature_angle_deg == 0 ? LODGEN_DEFAULT_FEATURE_DEG
                        : p->feature_angle_deg < 0 ? 180.0 : p->feature_angle_deg;
    for (int l = 0; l < out->level_count; ++l) {
        scn_mesh_crease_normals(&out->levels[l], crease_deg);
        if (out->levels[l].failed) {
            scn_lodset_free(out);
            return hl_fail(err, "lodgen: out of memory (normals)");
        }
    }
    snprintf(out->simplifier, sizeof out->simplifier, "%s", scn_simplifier_name(p->simplifier));
    for (int l = 0; l < out->level_count; ++l) {
        out->error_rel[l] = out->error_m[l] / out->radius_m;
        double f = scn_lod_unique_freq(out->error_m[l], out->radius_m);
        /* Strictly decreasing with the level, as scene.c clamps (docs/scenes.md). */
        if (l > 0 && !(f < out->freq[l - 1].geometric_cpdiam))
            f = out->freq[l - 1].geometric_cpdiam * (1.0 - 1e-6);
        out->freq[l] = (struct scn_level_freq){NAN, NAN, f};
    }
    if (p->progress)
        p->progress(p->progress_user, 1.0);
    if (stats)
        *stats = st;
    return 0;
}

int scn_lodgen_build(const struct scn_mesh *mesh, const struct scn_lodgen_params *p, struct scn_lodset *out,
                     struct hl_error *err)
{
    return scn_lodgen_build_timed(mesh, p, out, NULL, err);
}
