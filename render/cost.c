/* Measuring the machine's cost (PAPERS.md §2: Funkhouser & Séquin time sample objects over many
 * sizes and LODs; §5: llvmpipe bins geometry on the calling thread and rasterises at flush, so only
 * a timer around draw + glFinish sees the raster, and shaders compile on first use). Renders copies
 * of the field's bumpy sphere in stereo with the real renderer over a grid of triangles per object ×
 * total screen coverage × object count, and records per frame what the replay will predict from. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/render.h"

static const double cost_distance_m = 10.0; /* the grid's plane, far enough that the IPD barely matters */
static const double cost_near_m = 0.05, cost_far_m = 2000.0; /* the replay's clip planes */

void rnd_cost_grid_default(struct rnd_cost_grid *g, int quick)
{
    memset(g, 0, sizeof *g);
    g->render_scale = 1.0;
    if (quick) {
        /* Seconds for tests: the finest and coarsest level, two coverages, three counts. */
        static const uint32_t objects[] = {1, 8, 32};
        g->levels = 2, g->level[0] = 0, g->level[1] = 3;
        g->coverages = 2, g->coverage[0] = 0.02, g->coverage[1] = 0.3;
        g->counts = 3, memcpy(g->objects, objects, sizeof objects);
        g->repeats = 3;
        return;
    }
    /* Triangles per frame span 78 … 2·10⁶ (both eyes), coverage 0.2 % … 60 % of each eye, draws
     * 2 … 512: the range the field (10–1000 objects) and the auditorium put on this machine. */
    static const double coverage[] = {0.002, 0.02, 0.08, 0.25, 0.6};
    static const uint32_t objects[] = {1, 4, 16, 64, 256};
    g->levels = 4;
    for (int l = 0; l < 4; ++l)
        g->level[l] = (uint32_t)l;
    g->coverages = 5, memcpy(g->coverage, coverage, sizeof coverage);
    g->counts = 5, memcpy(g->objects, objects, sizeof objects);
    g->repeats = 7;
}

void rnd_calibration_free(struct rnd_calibration *c)
{
    if (!c)
        return;
    free(c->frames);
    free(c->objects);
    memset(c, 0, sizeof *c);
}

static int cmp_double(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* Places k instances (0 … k−1) of the scene's one chain on a grid at cost_distance_m straight ahead,
 * each with the tangent-plane radius that makes k discs cover `coverage` of one eye's image, and
 * records each object's both-eye counts at `level`; pixels from acu_compute_pixels, the estimate the
 * replay predicts with (pixels_px: k doubles of scratch). */
static void place_objects(struct scn_scene *s, const struct acu_eye eyes[2], uint32_t k, double coverage, int level,
                          const uint32_t *index, double *pixels_px, struct rnd_cost_object *objects)
{
    const struct scn_chain *chain = &s->chains[0];
    double wt = eyes[0].tan_left + eyes[0].tan_right, ht = eyes[0].tan_up + eyes[0].tan_down;
    double radius_px = sqrt(coverage * eyes[0].width_px * eyes[0].height_px / ((double)k * HL_PI));
    double rho = radius_px * wt / eyes[0].width_px; /* tangent units */
    double radius_m = cost_distance_m * rho / sqrt(1.0 + rho * rho);
    uint32_t cols = (uint32_t)ceil(sqrt((double)k * wt / ht));
    if (cols < 1)
        cols = 1;
    uint32_t rows = (k + cols - 1) / cols;
    double spacing = 2.05 * rho; /* a little apart: no overdraw, so pixels filled ≈ pixels estimated */
    for (uint32_t i = 0; i < k; ++i) {
        double u = ((double)(i % cols) - 0.5 * (double)(cols - 1)) * spacing;
        double v = ((double)(i / cols) - 0.5 * (double)(rows - 1)) * spacing;
        struct scn_instance *in = &s->instances[i];
        in->position_m[0] = u * cost_distance_m;
        in->position_m[1] = v * cost_distance_m;
        in->position_m[2] = -cost_distance_m;
        in->scale = radius_m / chain->bound_radius_m;
        hl_vec3d c = hl_q_rotate(in->rotation, hl_v3(chain->bound_center_m[0] * in->scale,
                                                     chain->bound_center_m[1] * in->scale,
                                                     chain->bound_center_m[2] * in->scale));
        for (int a = 0; a < 3; ++a)
            s->center_m[3 * i + a] = in->position_m[a] + (&c.x)[a];
        s->radius_m[i] = radius_m;
        const struct scn_lod *L = &chain->lods[level];
        objects[i].triangles = 2.0 * L->triangle_count;
        objects[i].vertices = 2.0 * L->vertex_count;
        objects[i].draws = 2.0;
    }
    acu_compute_pixels(eyes, 2, s->center_m, s->radius_m, index, k, pixels_px);
    for (uint32_t i = 0; i < k; ++i)
        objects[i].pixels_px = pixels_px[i];
}

int rnd_cost_measure(const struct hmd_profile *display, struct rnd_cost_grid *grid, uint64_t seed,
                     struct rnd_calibration *out, struct hl_error *err)
{
    memset(out, 0, sizeof *out);
    if (!display || !grid || grid->levels < 1 || grid->coverages < 1 || grid->counts < 1 || grid->repeats < 1 ||
        grid->levels > RND_COST_GRID_MAX || grid->coverages > RND_COST_GRID_MAX || grid->counts > RND_COST_GRID_MAX)
        return hl_fail(err, "calibrate: empty or oversized grid");
    if (!(grid->render_scale > 0.0 && grid->render_scale <= 4.0))
        return hl_fail(err, "calibrate: render scale %g is outside (0, 4]", grid->render_scale);
    grid->eye_width_px = (int)lround(display->eye_width_px * grid->render_scale);
    grid->eye_height_px = (int)lround(display->eye_height_px * grid->render_scale);
    snprintf(grid->display, sizeof grid->display, "%s", display->name);
    uint32_t max_objects = 0;
    for (int c = 0; c < grid->counts; ++c) {
        if (grid->objects[c] < 1 || grid->objects[c] > 100000)
            return hl_fail(err, "calibrate: object count %u outside 1…100000", grid->objects[c]);
        if (grid->objects[c] > max_objects)
            max_objects = grid->objects[c];
    }
    for (int c = 0; c < grid->coverages; ++c)
        if (!(grid->coverage[c] > 0.0 && grid->coverage[c] <= 1.0))
            return hl_fail(err, "calibrate: coverage %g outside (0, 1]", grid->coverage[c]);

    int64_t start_ns = hl_clock_now_ns();
    struct scn_scene scene = {0};
    struct rnd_renderer *r = NULL;
    struct scn_scene_params params = {.object_count = (int)max_objects, .seed = seed ? seed : 1};
    if (scn_scene_build("field", &params, &scene, err) != 0)
        return -1;
    for (int l = 0; l < grid->levels; ++l)
        if (grid->level[l] >= (uint32_t)scene.chains[0].lod_count) {
            scn_scene_free(&scene);
            return hl_fail(err, "calibrate: level %u: the field object has %d levels", grid->level[l],
                           scene.chains[0].lod_count);
        }
    size_t points = (size_t)grid->levels * (size_t)grid->coverages * (size_t)grid->counts;
    size_t object_total = 0;
    for (int l = 0; l < grid->levels; ++l)
        for (int c = 0; c < grid->coverages; ++c)
            for (int k = 0; k < grid->counts; ++k)
                object_total += grid->objects[k];
    out->frames = calloc(points, sizeof *out->frames);
    out->objects = calloc(object_total, sizeof *out->objects);
    uint32_t *index = malloc(max_objects * sizeof *index);
    uint8_t *lod = malloc(max_objects);
    double *pixels = malloc(max_objects * sizeof *pixels);
    uint32_t *order = malloc(points * sizeof *order);
    double *times = malloc(points * (size_t)grid->repeats * sizeof *times);
    int rc = -1;
    if (!out->frames || !out->objects || !index || !lod || !pixels || !order || !times) {
        hl_fail(err, "calibrate: out of memory (%zu grid points)", points);
        goto done;
    }
    if (rnd_renderer_create(grid->eye_width_px, grid->eye_height_px, &r, err) != 0 ||
        rnd_renderer_upload_scene(r, &scene, err) != 0)
        goto done;
    snprintf(out->renderer, sizeof out->renderer, "%s", rnd_renderer_name(r));

    struct rnd_eye_view views[2];
    struct acu_eye eyes[2];
    for (int e = 0; e < 2; ++e) {
        struct hmd_eye he = hmd_eye_frustum(display, e == 0 ? HMD_EYE_LEFT : HMD_EYE_RIGHT);
        views[e].position_m[0] = he.offset_x_m, views[e].position_m[1] = 0, views[e].position_m[2] = 0;
        views[e].orientation = hl_q_identity();
        hmd_eye_projection(&he, cost_near_m, cost_far_m, views[e].projection);
        eyes[e] = (struct acu_eye){hl_v3(he.offset_x_m, 0, 0), hl_q_identity(), he.tan_left, he.tan_right,
                                   he.tan_up, he.tan_down, grid->eye_width_px, grid->eye_height_px};
    }
    /* Frame records in grid order (level, coverage, count), each with its own object range. */
    size_t next_object = 0;
    for (size_t p = 0; p < points; ++p) {
        int k = (int)(p % (size_t)grid->counts);
        out->frames[p].first_object = (uint32_t)next_object;
        out->frames[p].object_count = grid->objects[k];
        next_object += grid->objects[k];
    }
    out->frame_count = points;
    out->object_count = object_total;
    for (uint32_t i = 0; i < max_objects; ++i)
        index[i] = i;

    /* Warm-up: the heaviest point a few times (shader JIT, first-touch of buffers, thread start). */
    place_objects(&scene, eyes, max_objects, grid->coverage[grid->coverages - 1], 0, index, pixels,
                  out->objects);
    memset(lod, 0, max_objects);
    for (int w = 0; w < 3; ++w)
        if (rnd_renderer_draw_stereo(r, &scene, views, index, lod, max_objects, NULL) != 0) {
            hl_fail(err, "calibrate: drawing the warm-up frame failed");
            goto done;
        }

    /* Repeats as passes over the whole grid, each in its own seeded random order, rather than back
     * to back: on a shared 2-core machine the load from other processes comes and goes over seconds,
     * and a median across passes spread over the whole run is far less hit by one busy moment. */
    struct hl_progress bar;
    hl_progress_begin(&bar, "calibrate", (uint64_t)points * (uint64_t)grid->repeats);
    for (int pass = 0; pass < grid->repeats; ++pass) {
        size_t ignored;
        rnd_cost_split(points, seed ^ (0xC0575EEDull + (uint64_t)pass), order, &ignored);
        for (size_t n = 0; n < points; ++n) {
            size_t p = order[n];
            int k = (int)(p % (size_t)grid->counts);
            int c = (int)(p / (size_t)grid->counts % (size_t)grid->coverages);
            int l = (int)(p / ((size_t)grid->counts * (size_t)grid->coverages));
            uint32_t count = grid->objects[k];
            int level = (int)grid->level[l];
            struct rnd_cost_frame *f = &out->frames[p];
            place_objects(&scene, eyes, count, grid->coverage[c], level, index, pixels,
                          out->objects + f->first_object);
            memset(lod, level, count);
            for (int rep = 0; rep < 2; ++rep) { /* rep 0: untimed, settles the new layout */
                int64_t t0 = hl_clock_now_ns();
                if (rnd_renderer_draw_stereo(r, &scene, views, index, lod, count, NULL) != 0) {
                    hl_fail(err, "calibrate: drawing grid point %zu failed", p);
                    goto done;
                }
                if (rep == 1)
                    times[p * (size_t)grid->repeats + (size_t)pass] = (double)(hl_clock_now_ns() - t0) * 1e-6;
            }
            hl_progress_update(&bar, (uint64_t)pass * points + n + 1);
        }
    }
    for (size_t p = 0; p < points; ++p) {
        double *t = times + p * (size_t)grid->repeats;
        size_t m = (size_t)grid->repeats;
        qsort(t, m, sizeof *t, cmp_double);
        out->frames[p].measured_ms = m % 2 ? t[m / 2] : 0.5 * (t[m / 2 - 1] + t[m / 2]);
    }
    hl_progress_end(&bar);
    out->seconds = (double)(hl_clock_now_ns() - start_ns) * 1e-9;
    rc = 0;
done:
    rnd_renderer_destroy(r);
    scn_scene_free(&scene);
    free(index);
    free(lod);
    free(pixels);
    free(order);
    free(times);
    if (rc != 0)
        rnd_calibration_free(out);
    return rc;
}
