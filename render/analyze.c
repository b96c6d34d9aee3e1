/* The rendering half of Reddy's offline analysis (1998 §3.2–3.3): every level of a chain drawn by
 * the stereo pass's own shader from 6 or 18 points of the view sphere, read back, and successive
 * levels compared (analyze_image.c). docs/analysis.md explains each choice. */
#include "render/analyze_internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The default albedo: grey near the brightest of the field palette's luminances: a light object
 * makes shading and silhouette changes largest in ΔE, so the analysis errs towards seeing a
 * difference. (The lost contrast does not depend on it away from silhouettes: test_analyze.) */
static const double rnd_analyze_grey = 0.8;

void rnd_analyze_params_defaults(struct rnd_analyze_params *p)
{
    memset(p, 0, sizeof *p);
    p->views = 18;
    p->size_px = 256;
    p->threshold_de = 2.3;
    p->min_component_px = 3;
    p->contrast_percentile = 99.0;
    p->contrast_silhouette_reach = -1;
    p->albedo_rgb[0] = p->albedo_rgb[1] = p->albedo_rgb[2] = rnd_analyze_grey;
}

int rnd_analyze_params_check(const struct rnd_analyze_params *p, struct hl_error *err)
{
    if (!p)
        return hl_fail(err, "analyze: no parameters");
    if (p->views != 6 && p->views != 18)
        return hl_fail(err, "analyze: views: %d (6 or 18)", p->views);
    if (p->size_px < 16 || p->size_px > 2048)
        return hl_fail(err, "analyze: size: %d px outside [16, 2048]", p->size_px);
    if (!(p->threshold_de > 0.0) || !(p->threshold_de <= 100.0))
        return hl_fail(err, "analyze: threshold: ΔE %g outside (0, 100]", p->threshold_de);
    if (p->min_component_px < 1 || p->min_component_px > 1000)
        return hl_fail(err, "analyze: min component: %d px outside [1, 1000]", p->min_component_px);
    if (!(p->contrast_percentile > 0.0) || !(p->contrast_percentile <= 100.0))
        return hl_fail(err, "analyze: contrast percentile: %g outside (0, 100]", p->contrast_percentile);
    if (p->contrast_silhouette_reach < -1 || p->contrast_silhouette_reach > 64)
        return hl_fail(err, "analyze: contrast silhouette reach: %d outside −1…64", p->contrast_silhouette_reach);
    for (int k = 0; k < 3; ++k)
        if (!(p->albedo_rgb[k] >= 0.0) || !(p->albedo_rgb[k] <= 1.0))
            return hl_fail(err, "analyze: albedo: channel %d is %g, outside [0, 1]", k, p->albedo_rgb[k]);
    return 0;
}

int rnd_analyze_view_dirs(int views, double dirs[18][3])
{
    if (views != 6 && views != 18)
        return 0;
    /* Reddy's Figure 1: the vertices of a tessellated view sphere. 6 = the octahedron (±X, ±Y, ±Z);
     * 18 adds the 12 cube-edge midpoints (two non-zero coordinates of ±1/√2). */
    int n = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (int s = -1; s <= 1; s += 2) {
            dirs[n][0] = dirs[n][1] = dirs[n][2] = 0.0;
            dirs[n++][axis] = s;
        }
    if (views == 18) {
        const double h = 0.70710678118654752;
        for (int a = 0; a < 3; ++a)
            for (int sa = -1; sa <= 1; sa += 2)
                for (int sb = -1; sb <= 1; sb += 2) {
                    int b = (a + 1) % 3;
                    dirs[n][0] = dirs[n][1] = dirs[n][2] = 0.0;
                    dirs[n][a] = sa * h;
                    dirs[n++][b] = sb * h;
                }
    }
    return n;
}

/* Rotation taking unit d to +Z (the camera sits on +Z looking down −Z): shortest arc, atan2 angle. */
static hl_quatd rnd_rotation_to_z(const double d[3])
{
    hl_vec3d from = hl_v3(d[0], d[1], d[2]), z = hl_v3(0, 0, 1);
    hl_vec3d axis = hl_v3_cross(from, z);
    double s = hl_v3_length(axis), c = hl_v3_dot(from, z);
    if (s < 1e-12)
        return c > 0 ? hl_q_identity() : hl_q_from_axis_angle(hl_v3(0, 1, 0), HL_PI);
    return hl_q_from_axis_angle(hl_v3_scale(axis, 1.0 / s), atan2(s, c));
}

/* Column-major glOrtho(−r, r, −r, r, near, far). */
static void rnd_ortho(double r, double near_m, double far_m, double m[16])
{
    memset(m, 0, 16 * sizeof *m);
    m[0] = 1.0 / r;
    m[5] = 1.0 / r;
    m[10] = -2.0 / (far_m - near_m);
    m[14] = -(far_m + near_m) / (far_m - near_m);
    m[15] = 1.0;
}

/* One chain (the set's levels), one instance: the smallest scene the stereo pass can draw. */
static int rnd_analyze_scene(const struct scn_lodset *set, const double albedo_rgb[3], struct scn_scene *s,
                             struct hl_error *err)
{
    memset(s, 0, sizeof *s);
    uint64_t nv = 0, ni = 0;
    for (int l = 0; l < set->level_count; ++l)
        nv += set->levels[l].vertex_count, ni += set->levels[l].index_count;
    if (nv > UINT32_MAX || ni > UINT32_MAX)
        return hl_fail(err, "analyze: more than 2^32 vertices or indices");
    snprintf(s->name, sizeof s->name, "analysis");
    s->positions = malloc(3 * sizeof(float) * (nv ? nv : 1));
    s->normals = malloc(3 * sizeof(float) * (nv ? nv : 1));
    s->indices = malloc(sizeof(uint32_t) * (ni ? ni : 1));
    s->chains = calloc(1, sizeof *s->chains);
    s->instances = calloc(1, sizeof *s->instances);
    if (!s->positions || !s->normals || !s->indices || !s->chains || !s->instances) {
        scn_scene_free(s);
        return hl_fail(err, "analyze: out of memory for %llu vertices", (unsigned long long)nv);
    }
    struct scn_chain *c = &s->chains[0];
    c->lod_count = set->level_count;
    c->bound_radius_m = set->radius_m;
    for (int l = 0; l < set->level_count; ++l) {
        const struct scn_mesh *m = &set->levels[l];
        c->lods[l] = (struct scn_lod){.first_index = s->index_count, .index_count = m->index_count,
                                      .triangle_count = m->index_count / 3, .vertex_count = m->vertex_count};
        memcpy(s->positions + 3 * (size_t)s->vertex_count, m->positions, 3 * sizeof(float) * m->vertex_count);
        memcpy(s->normals + 3 * (size_t)s->vertex_count, m->normals, 3 * sizeof(float) * m->vertex_count);
        for (uint32_t k = 0; k < m->index_count; ++k)
            s->indices[s->index_count + k] = m->indices[k] + s->vertex_count;
        s->vertex_count += m->vertex_count;
        s->index_count += m->index_count;
    }
    s->chain_count = 1;
    s->instance_count = 1;
    s->instances[0].rotation = hl_q_identity();
    s->instances[0].scale = 1.0;
    for (int k = 0; k < 3; ++k)
        s->instances[0].color[k] = (float)albedo_rgb[k];
    return 0;
}

static int rnd_analyze_check_set(const struct scn_lodset *set, struct hl_error *err)
{
    if (!set || set->level_count < 1 || set->level_count > SCN_LODSET_MAX_LEVELS)
        return hl_fail(err, "analyze: level count %d outside [1, %d]", set ? set->level_count : 0,
                       SCN_LODSET_MAX_LEVELS);
    for (int l = 0; l < set->level_count; ++l) {
        const struct scn_mesh *m = &set->levels[l];
        if (m->index_count == 0 || m->index_count % 3 || !m->positions || !m->normals || !m->indices)
            return hl_fail(err, "analyze: level %d: no triangles", l);
        for (uint32_t k = 0; k < m->index_count; ++k)
            if (m->indices[k] >= m->vertex_count)
                return hl_fail(err, "analyze: level %d: index %u refers to vertex %u of %u", l, k, m->indices[k],
                               m->vertex_count);
        for (size_t k = 0; k < 3 * (size_t)m->vertex_count; ++k)
            if (!isfinite(m->positions[k]))
                return hl_fail(err, "analyze: level %d: vertex %zu is not finite", l, k / 3);
    }
    return 0;
}

/* The bounding sphere: the set's own when it has one, else level 0's box centre and the farthest
 * vertex. *reach_m: the farthest vertex of any level from the centre (the depth range). */
static void rnd_analyze_sphere(const struct scn_lodset *set, double c[3], double *radius_m, double *reach_m)
{
    const struct scn_mesh *m0 = &set->levels[0];
    int own = set->radius_m > 0 && isfinite(set->radius_m) && isfinite(set->center_m[0]) &&
              isfinite(set->center_m[1]) && isfinite(set->center_m[2]);
    if (own) {
        memcpy(c, set->center_m, 3 * sizeof *c);
    } else {
        double lo[3], hi[3];
        scn_mesh_aabb(m0, lo, hi);
        for (int a = 0; a < 3; ++a)
            c[a] = 0.5 * (lo[a] + hi[a]);
    }
    double r0 = 0, reach = 0;
    for (int l = 0; l < set->level_count; ++l) {
        const struct scn_mesh *m = &set->levels[l];
        for (uint32_t v = 0; v < m->vertex_count; ++v) {
            const float *p = m->positions + 3 * (size_t)v;
            double d = hl_v3_length(hl_v3(p[0] - c[0], p[1] - c[1], p[2] - c[2]));
            reach = d > reach ? d : reach;
            if (l == 0)
                r0 = d > r0 ? d : r0;
        }
    }
    *radius_m = own ? set->radius_m : r0;
    *reach_m = reach > *radius_m ? reach : *radius_m;
    if (!(*radius_m > 0)) /* a mesh collapsed to a point: any scale shows it as one pixel */
        *radius_m = *reach_m = 1.0;
}

/* Per-level readings from the views' comparisons, made strictly decreasing (lod/select.c steps
 * to level l+1 while f[l+1] > limit, so f must fall with l). A level that loses nothing visible gets
 * the largest double below the previous level's value: whenever the selector takes the previous
 * level it takes this one too (after level 0, +∞, that is DBL_MAX). */
static void rnd_analyze_tables(const struct rnd_analyze_report *rep, int levels, int size_px, double narrow[],
                               double longr[], int clamped[])
{
    narrow[0] = longr[0] = INFINITY;
    for (int l = 1; l < levels; ++l) {
        const struct rnd_analyze_level *L = &rep->levels[l];
        double fn, fl;
        if (L->invisible) {
            fn = nextafter(narrow[l - 1], 0.0);
            fl = nextafter(longr[l - 1], 0.0);
        } else {
            /* A feature L px across is half a cycle: 1/(2L) cycles/px, × size_px px per diameter. */
            fn = size_px / (2.0 * L->narrow_extent_px);
            fl = size_px / (2.0 * L->long_extent_px);
        }
        clamped[l] = 0;
        if (!(fn < narrow[l - 1]))
            fn = nextafter(narrow[l - 1], 0.0), clamped[l] = 1;
        if (!(fl < longr[l - 1]))
            fl = nextafter(longr[l - 1], 0.0), clamped[l] = 1;
        narrow[l] = fn;
        longr[l] = fl;
    }
}

/* Debug output (--dump): level l−1 and l as rendered, and the differing pixels in white over a
 * darkened copy of level l. Reuses `prev` for the mask once compared (it is rendered again next). */
static int rnd_analyze_dump(const char *dir, int view, int level, uint8_t *prev, const uint8_t *cur,
                            const struct rnd_diff_work *w, struct hl_error *err)
{
    char path[4096];
    int size = w->width_px;
    if (level == 1) {
        snprintf(path, sizeof path, "%s/view%02d_level0.png", dir, view);
        if (rnd_png_write(path, prev, size, size, err) != 0)
            return -1;
    }
    snprintf(path, sizeof path, "%s/view%02d_level%d.png", dir, view, level);
    if (rnd_png_write(path, cur, size, size, err) != 0)
        return -1;
    for (size_t i = 0; i < (size_t)size * (size_t)size; ++i)
        for (int k = 0; k < 3; ++k)
            prev[4 * i + k] = w->label[i] ? 255 : (uint8_t)(cur[4 * i + k] / 3);
    snprintf(path, sizeof path, "%s/view%02d_diff%d.png", dir, view, level);
    if (rnd_png_write(path, prev, size, size, err) != 0)
        return -1;
    /* prev now holds the mask; the next level compares against cur, so nothing is lost. */
    return 0;
}

int rnd_analyze_lodset(struct rnd_renderer *r, struct scn_lodset *set, const struct rnd_analyze_params *p,
                       struct rnd_analyze_report *report, struct hl_error *err)
{
    double t_start = hl_clock_now_s();
    if (rnd_analyze_params_check(p, err) != 0 || rnd_analyze_check_set(set, err) != 0)
        return -1;
    const int size = p->size_px;
    struct rnd_renderer *own = NULL;
    if (r) {
        int w, h;
        rnd_renderer_size(r, &w, &h);
        if (w / 2 < size || h < size)
            return hl_fail(err, "analyze: the renderer's eyes (%d×%d) are smaller than %d px", w / 2, h, size);
    } else if (rnd_renderer_create(size, size, &own, err) != 0) {
        return -1;
    } else {
        r = own;
    }

    struct rnd_analyze_report rep;
    memset(&rep, 0, sizeof rep);
    rep.level_count = set->level_count;
    struct scn_scene scene;
    struct rnd_diff_work work;
    memset(&work, 0, sizeof work);
    uint8_t *img = NULL;
    int rc = -1;
    if (rnd_analyze_scene(set, p->albedo_rgb, &scene, err) != 0)
        goto done_noscene;
    /* Three images (the previous level's, this one's and level 0's, which every level's spectrum is
     * taken against), allocated once for every view. */
    img = malloc(3 * (size_t)size * (size_t)size * 4);
    if (!img || rnd_diff_work_init(&work, size, size) != 0) {
        hl_fail(err, "analyze: out of memory for %d×%d images", size, size);
        goto done;
    }
    if (rnd_renderer_upload_scene(r, &scene, err) != 0)
        goto done;

    double c[3], radius, reach;
    rnd_analyze_sphere(set, c, &radius, &reach);
    /* Orthographic: every level, every view and every depth at the same scale, so "the diameter spans
     * size_px" holds exactly (a perspective camera would enlarge the near half). Depth covers the
     * farthest vertex of any level, so a coarse level that bulges out is not clipped. */
    struct rnd_eye_view view = {.position_m = {0, 0, 3.0 * reach}, .orientation = hl_q_identity()};
    rnd_ortho(radius, 1.9 * reach, 4.1 * reach, view.projection);
    double dirs[18][3];
    int views = rnd_analyze_view_dirs(p->views, dirs);
    const int rect[4] = {0, 0, size, size};
    uint32_t total = (uint32_t)(views * set->level_count);
    uint8_t *img0 = img + 2 * (size_t)size * size * 4;
    struct rnd_contrast_params cp;
    rnd_contrast_params_defaults(&cp, size);
    cp.percentile = p->contrast_percentile;
    cp.silhouette_reach = p->contrast_silhouette_reach;
    for (int l = 0; l < set->level_count; ++l) {
        struct rnd_analyze_level *L = &rep.levels[l];
        L->narrow_view = L->long_view = l ? -1 : 0;
        for (int b = 0; b < RND_CONTRAST_MAX_BANDS; ++b) /* level 0 loses nothing; NaN: no view yet */
            L->lost_contrast[b] = l ? NAN : 0.0, L->lost_contrast_view[b] = -1;
    }
    for (int v = 0; v < views; ++v) {
        /* The object turns, not the camera, so the renderer's light stays fixed in the view. */
        struct scn_instance *in = &scene.instances[0];
        in->rotation = rnd_rotation_to_z(dirs[v]);
        hl_vec3d pc = hl_q_rotate(in->rotation, hl_v3(c[0], c[1], c[2]));
        in->position_m[0] = -pc.x, in->position_m[1] = -pc.y, in->position_m[2] = -pc.z;
        for (int l = 0; l < set->level_count; ++l) {
            uint8_t *cur = img + (size_t)(l % 2) * size * size * 4, *prev = img + (size_t)((l + 1) % 2) * size * size * 4;
            double t0 = hl_clock_now_s();
            if (rnd_renderer_draw_rect(r, &scene, &view, 0, (uint8_t)l, rect) != 0) {
                hl_fail(err, "analyze: drawing level %d from view %d failed", l, v);
                goto done;
            }
            if (rnd_renderer_read_rect(r, rect, cur, err) != 0)
                goto done;
            double t1 = hl_clock_now_s();
            rep.render_s += t1 - t0;
            rep.renders++;
            if (l == 0) {
                memcpy(img0, cur, (size_t)size * size * 4);
                /* The background: a corner, outside the inscribed bounding circle in every view. */
                memcpy(cp.background_rgb, cur, 3);
            }
            if (l > 0) {
                struct rnd_contrast_spectrum cs;
                if (rnd_contrast_spectrum(img0, cur, size, size, &cp, &cs, err) != 0)
                    goto done;
                struct rnd_analyze_level *C = &rep.levels[l];
                C->band_count = cs.band_count;
                /* The most visible loss over views governs, band by band (as the extents do). */
                for (int b = 0; b < cs.band_count; ++b)
                    if (!isnan(cs.contrast[b]) && !(cs.contrast[b] <= C->lost_contrast[b]))
                        C->lost_contrast[b] = cs.contrast[b], C->lost_contrast_view[b] = v;
                double t2 = hl_clock_now_s();
                rep.contrast_s += t2 - t1;
                struct rnd_image_diff d;
                rnd_diff_images(&work, prev, cur, p->threshold_de, p->min_component_px, &d);
                struct rnd_analyze_level *L = &rep.levels[l];
                L->differing_px += d.differing_px;
                L->components += d.components;
                L->noise_components += d.noise_components;
                /* The largest lost feature over all views governs (analyze.h, Reddy 1998 §3.2). */
                if (d.components && d.narrow_extent_px > L->narrow_extent_px)
                    L->narrow_extent_px = d.narrow_extent_px, L->narrow_view = v;
                if (d.components && d.long_extent_px > L->long_extent_px)
                    L->long_extent_px = d.long_extent_px, L->long_view = v;
                rep.compare_s += hl_clock_now_s() - t1;
                if (p->dump_dir && rnd_analyze_dump(p->dump_dir, v, l, prev, cur, &work, err) != 0)
                    goto done;
            }
            if (p->progress)
                p->progress(p->progress_user, (double)rep.renders / total);
        }
    }
    double narrow[SCN_LODSET_MAX_LEVELS], longr[SCN_LODSET_MAX_LEVELS];
    int clamped[SCN_LODSET_MAX_LEVELS] = {0};
    for (int l = 1; l < set->level_count; ++l)
        rep.levels[l].invisible = rep.levels[l].components == 0;
    rnd_analyze_tables(&rep, set->level_count, size, narrow, longr, clamped);
    for (int l = 0; l < set->level_count; ++l) {
        set->freq[l].narrow_cpdiam = narrow[l];
        set->freq[l].long_cpdiam = longr[l];
        rep.levels[l].clamped = clamped[l];
    }
    set->analysis_views = p->views;
    set->analysis_size_px = size;
    /* The spectrum (every level l ≥ 1 has the same band count: it depends on size_px only). */
    rep.levels[0].band_count = set->level_count > 1 ? rep.levels[1].band_count : 0;
    set->contrast_band_count = rep.levels[0].band_count;
    set->contrast_percentile = set->contrast_band_count ? p->contrast_percentile : 0.0;
    for (int l = 0; l < set->level_count; ++l)
        for (int b = 0; b < SCN_LODSET_MAX_BANDS; ++b)
            set->lost_contrast[l][b] = b < set->contrast_band_count ? rep.levels[l].lost_contrast[b] : 0.0;
    rc = 0;
done:
    scn_scene_free(&scene);
done_noscene:
    free(img);
    rnd_diff_work_free(&work);
    if (own)
        rnd_renderer_destroy(own);
    rep.total_s = hl_clock_now_s() - t_start;
    if (report)
        *report = rep;
    return rc;
}
