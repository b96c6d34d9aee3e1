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
    g->periphery_scale = 1.0;
    g->families = 2;
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
     * 2 … 512 (the chair: 24 … 180 000 triangles, 150 copies at most): the range the field (10–1000 objects) and the auditorium put on this machine. */
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

/* Places k instances (0 … k−1) of the scene's one chain on a grid at cost_distance_m straight ahead,
 * each with the tangent-plane radius that makes k discs cover `coverage` of one eye's image, and
 * records each object's both-eye counts at `level` and its bounding sphere (replay estimates its
 * pixels from it, as it does in a frame). */
static void place_objects(struct scn_scene *s, const struct rnd_cost_eye eyes[2], uint32_t k, double coverage,
                          int level, struct rnd_cost_object *objects)
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
        objects[i].pixels_px = 0.0;
        objects[i].fill = scn_lod_fill(chain, level, 0);
        objects[i].inside_share = 1.0;
        for (int a = 0; a < 3; ++a)
            objects[i].center_m[a] = s->center_m[3 * i + a];
        objects[i].radius_m = radius_m;
    }
}

/* The families: a built-in scene whose chain 0 is the object and whose first instances are its
 * copies. The chair has 1–2 vertices per triangle against the sphere's 0.5, so with both the fit
 * can tell the triangle and the vertex coefficients apart; with one they are collinear. */
static const char *const cost_family_scene[2] = {"field", "auditorium"};

/* Decomposes grid point p: count fastest, then coverage, level, family. */
static void grid_point(const struct rnd_cost_grid *g, size_t p, int *family, int *level, int *coverage, int *count)
{
    *count = (int)(p % (size_t)g->counts);
    p /= (size_t)g->counts;
    *coverage = (int)(p % (size_t)g->coverages);
    p /= (size_t)g->coverages;
    *level = (int)(p % (size_t)g->levels);
    *family = (int)(p / (size_t)g->levels);
}

/* Draws grid point p once, plainly, as the periphery `layers` describes (inset radius 0) or as its
 * inset alone (radius > 0; NULL: plainly); *ms gets the time of draw + glFinish. The periphery's
 * composite is not timed: it is the compositor's, and a replay frame does not count it either
 * (docs/foveation.md "What a frame pays"). */
static int draw_point(struct rnd_renderer *r, struct scn_scene *scene, const struct rnd_eye_view views[2],
                      const struct rnd_layers *layers, const uint32_t *index, uint8_t *lod, uint32_t count,
                      int level, double *ms)
{
    memset(lod, level, count);
    int64_t t0 = hl_clock_now_ns();
    int rc = !layers                           ? rnd_renderer_draw_stereo(r, scene, views, index, lod, count, NULL)
             : layers->inset_radius_deg > 0.0 ? rnd_renderer_draw_inset(r, scene, views, layers, index, lod, count, NULL)
                                               : rnd_renderer_draw_layers(r, scene, views, layers, index, lod, NULL,
                                                                          NULL, count, NULL);
    *ms = (double)(hl_clock_now_ns() - t0) * 1e-6;
    return rc;
}

int rnd_cost_measure(const struct hmd_profile *display, struct rnd_cost_grid *grid, uint64_t seed,
                     struct rnd_calibration *out, struct hl_error *err)
{
    memset(out, 0, sizeof *out);
    if (!display || !grid || grid->levels < 1 || grid->coverages < 1 || grid->counts < 1 || grid->repeats < 1 ||
        grid->families < 1 || grid->families > 2 || grid->levels > RND_COST_GRID_MAX ||
        grid->coverages > RND_COST_GRID_MAX || grid->counts > RND_COST_GRID_MAX)
        return hl_fail(err, "calibrate: empty or oversized grid");
    if (!(grid->render_scale > 0.0 && grid->render_scale <= 4.0))
        return hl_fail(err, "calibrate: render scale %g is outside (0, 4]", grid->render_scale);
    if (!(grid->periphery_scale >= RND_LAYER_SCALE_MIN && grid->periphery_scale <= 1.0))
        return hl_fail(err, "calibrate: periphery scale %g is outside [%g, 1]", grid->periphery_scale,
                       RND_LAYER_SCALE_MIN);
    if (!(grid->inset_radius_deg >= 0.0 && grid->inset_radius_deg <= 45.0) ||
        (grid->inset_radius_deg > 0.0 && !(grid->inset_blend_deg > 0.0 && grid->inset_blend_deg <= 45.0)) ||
        (grid->inset_radius_deg > 0.0 && grid->periphery_scale < 1.0))
        return hl_fail(err, "calibrate: inset radius %g / blend %g: expected radius 0, or radius in (0, 45] and "
                       "blend in (0, 45] with plain frames' scale 1", grid->inset_radius_deg, grid->inset_blend_deg);
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
    struct scn_scene scenes[2];
    memset(scenes, 0, sizeof scenes);
    uint32_t copies[2] = {0, 0}; /* instances of chain 0 at the front of each scene: a count's cap */
    struct rnd_renderer *r = NULL;
    size_t points = (size_t)grid->families * (size_t)grid->levels * (size_t)grid->coverages * (size_t)grid->counts;
    uint32_t *index = malloc(max_objects * sizeof *index);
    uint8_t *lod = malloc(max_objects);
    struct rnd_cost_object *scratch = malloc(max_objects * sizeof *scratch); /* the warm-up's counts */
    uint32_t *order = malloc(points * sizeof *order);
    double *times = malloc(points * (size_t)grid->repeats * sizeof *times);
    /* One empty frame before each family's points and after every RND_COST_EMPTY_EVERY of them. */
    size_t empty_cap = ((points / RND_COST_EMPTY_EVERY) + 2 * (size_t)grid->families + 1) * (size_t)grid->repeats;
    double *empty = malloc(empty_cap * sizeof *empty), *composite = malloc(empty_cap * sizeof *composite);
    size_t empty_n = 0, composite_n = 0;
    int rc = -1;
    if (!index || !lod || !scratch || !order || !times || !empty || !composite) {
        hl_fail(err, "calibrate: out of memory (%zu grid points)", points);
        goto done;
    }
    for (int f = 0; f < grid->families; ++f) {
        struct scn_scene_params params = {.object_count = (int)max_objects, .seed = seed ? seed : 1};
        if (scn_scene_build(cost_family_scene[f], &params, &scenes[f], err) != 0)
            goto done;
        while (copies[f] < scenes[f].instance_count && scenes[f].chain_of_instance[copies[f]] == 0)
            copies[f]++;
        for (int l = 0; l < grid->levels; ++l)
            if (grid->level[l] >= (uint32_t)scenes[f].chains[0].lod_count) {
                hl_fail(err, "calibrate: level %u: the %s object has %d levels", grid->level[l], cost_family_scene[f],
                        scenes[f].chains[0].lod_count);
                goto done;
            }
    }
    /* Frame records in grid order, each with its own object range. */
    out->frames = calloc(points, sizeof *out->frames);
    if (!out->frames) {
        hl_fail(err, "calibrate: out of memory (%zu grid points)", points);
        goto done;
    }
    size_t next_object = 0;
    for (size_t p = 0; p < points; ++p) {
        int f, l, c, k;
        grid_point(grid, p, &f, &l, &c, &k);
        out->frames[p].first_object = (uint32_t)next_object;
        out->frames[p].object_count = grid->objects[k] < copies[f] ? grid->objects[k] : copies[f];
        next_object += out->frames[p].object_count;
    }
    out->frame_count = points;
    out->object_count = next_object;
    out->objects = calloc(next_object, sizeof *out->objects);
    if (!out->objects) {
        hl_fail(err, "calibrate: out of memory (%zu objects)", next_object);
        goto done;
    }
    if (rnd_renderer_create(grid->eye_width_px, grid->eye_height_px, &r, err) != 0)
        goto done;
    snprintf(out->renderer, sizeof out->renderer, "%s", rnd_renderer_name(r));

    struct rnd_eye_view views[2];
    struct rnd_cost_eye *eyes = out->eyes;
    /* The periphery alone: inset radius 0 makes the whole eye one layer at the scale. The inset alone:
     * its rectangle around the lens centre (the placement's centre too), the periphery not drawn —
     * the scale only has to be below 1 for the plan to have an inset. */
    int inset = grid->inset_radius_deg > 0.0;
    struct rnd_layers layer = {.periphery_scale = inset ? 0.5 : grid->periphery_scale,
                               .inset_radius_deg = grid->inset_radius_deg,
                               .blend_deg = inset ? grid->inset_blend_deg : 1.0,
                               .centre_eye = {hl_v3(0, 0, -1), hl_v3(0, 0, -1)}};
    const struct rnd_layers *layers = inset || grid->periphery_scale < 1.0 ? &layer : NULL;
    for (int e = 0; e < 2; ++e) {
        struct hmd_eye he = hmd_eye_frustum(display, e == 0 ? HMD_EYE_LEFT : HMD_EYE_RIGHT);
        layer.eyes[e] = he;
        views[e].position_m[0] = he.offset_x_m, views[e].position_m[1] = 0, views[e].position_m[2] = 0;
        views[e].orientation = hl_q_identity();
        hmd_eye_projection(&he, cost_near_m, cost_far_m, views[e].projection);
        eyes[e] = (struct rnd_cost_eye){he.offset_x_m, he.tan_left, he.tan_right, he.tan_up, he.tan_down,
                                        grid->eye_width_px, grid->eye_height_px};
    }
    struct rnd_layer_plan plan;
    if (inset && (rnd_layer_plan_make(&layer, grid->eye_width_px, grid->eye_height_px, &plan) != 0 ||
                  plan.inset_rect_px[0][2] < 1 || plan.inset_rect_px[1][2] < 1 || plan.inset_rect_px[0][3] < 1 ||
                  plan.inset_rect_px[1][3] < 1)) {
        hl_fail(err, "calibrate: no inset of %g degrees on %s", grid->inset_radius_deg, display->name);
        goto done;
    }
    for (int e = 0; e < 2 && inset; ++e) {
        const int *rect = plan.inset_rect_px[e];
        double t[4];
        rnd_layer_rect_tangents(eyes[e].tan_left, eyes[e].tan_right, eyes[e].tan_down, eyes[e].tan_up,
                                eyes[e].width_px, eyes[e].height_px, rect, t);
        out->inset_eyes[e] = (struct rnd_cost_eye){eyes[e].offset_x_m, t[0], t[1], t[3], t[2], rect[2], rect[3]};
    }
    for (uint32_t i = 0; i < max_objects; ++i)
        index[i] = i;

    /* Repeats as passes over the whole grid, each in its own seeded random order, rather than back
     * to back: on a shared 2-core machine the load from other processes comes and goes over seconds,
     * and a median across passes spread over the whole run is far less hit by one busy moment. Per
     * pass each family's scene is uploaded once and its points visited; the first pass starts each
     * family with a warm-up of its heaviest point (shader JIT, first touch of the buffers). */
    struct hl_progress bar;
    hl_progress_begin(&bar, "calibrate", (uint64_t)points * (uint64_t)grid->repeats);
    uint64_t done_points = 0;
    for (int pass = 0; pass < grid->repeats; ++pass) {
        size_t ignored;
        rnd_cost_split(points, seed ^ (0xC0575EEDull + (uint64_t)pass), order, &ignored);
        for (int fam = 0; fam < grid->families; ++fam) {
            struct scn_scene *scene = &scenes[fam];
            if (rnd_renderer_upload_scene(r, scene, err) != 0)
                goto done;
            uint32_t heavy = max_objects < copies[fam] ? max_objects : copies[fam];
            double ms;
            place_objects(scene, eyes, heavy, grid->coverage[grid->coverages - 1], 0, scratch);
            for (int w = 0; w < (pass == 0 ? 3 : 1); ++w)
                if (draw_point(r, scene, views, layers, index, lod, heavy, 0, &ms) != 0) {
                    hl_fail(err, "calibrate: drawing the warm-up frame failed");
                    goto done;
                }
            size_t since_empty = RND_COST_EMPTY_EVERY;
            for (size_t n = 0; n < points; ++n) {
                size_t p = order[n];
                int f, l, c, k;
                grid_point(grid, p, &f, &l, &c, &k);
                if (f != fam)
                    continue;
                /* The fixed cost, timed among the points it is part of: the same load, the same
                 * caches, the same position in the driver's buffer cycle. */
                if (since_empty >= RND_COST_EMPTY_EVERY && empty_n < empty_cap) {
                    double settle_ms;
                    if (draw_point(r, scene, views, layers, index, lod, 0, 0, &settle_ms) != 0 ||
                        draw_point(r, scene, views, layers, index, lod, 0, 0, &empty[empty_n++]) != 0) {
                        hl_fail(err, "calibrate: drawing an empty frame failed");
                        goto done;
                    }
                    if (layers && !inset) { /* a periphery: its composite, after its empty frame */
                        int64_t t0 = hl_clock_now_ns();
                        if (rnd_renderer_composite_layers(r, NULL) != 0) {
                            hl_fail(err, "calibrate: compositing the periphery failed");
                            goto done;
                        }
                        composite[composite_n++] = (double)(hl_clock_now_ns() - t0) * 1e-6;
                    }
                    since_empty = 0;
                }
                ++since_empty;
                struct rnd_cost_frame *fr = &out->frames[p];
                int level = (int)grid->level[l];
                place_objects(scene, eyes, fr->object_count, grid->coverage[c], level, out->objects + fr->first_object);
                /* One timed frame after one untimed frame of the same point: a frame pays part of
                 * the previous frame's work even after glFinish (llvmpipe resets the previous frame's
                 * binned scene when it starts the next: an empty frame measured 2.57 ms right after
                 * a sphere point, 1.83 after an empty one, 1.26 after two), and in a replay that
                 * previous frame is much like the current one. The median over passes discards the
                 * odd slow one. */
                double settle_ms;
                if (draw_point(r, scene, views, layers, index, lod, fr->object_count, level, &settle_ms) != 0 ||
                    draw_point(r, scene, views, layers, index, lod, fr->object_count, level,
                               &times[p * (size_t)grid->repeats + (size_t)pass]) != 0) {
                    hl_fail(err, "calibrate: drawing grid point %zu failed", p);
                    goto done;
                }
                hl_progress_update(&bar, ++done_points);
            }
        }
    }
    hl_progress_end(&bar);
    for (size_t p = 0; p < points; ++p) {
        double *t = times + p * (size_t)grid->repeats;
        size_t m = (size_t)grid->repeats;
        hl_sort_doubles(t, m);
        out->frames[p].measured_ms = m % 2 ? t[m / 2] : 0.5 * (t[m / 2 - 1] + t[m / 2]);
    }
    hl_sort_doubles(empty, empty_n);
    out->empty_frames = (uint32_t)empty_n;
    out->empty_ms = empty_n ? empty[empty_n / 2] : 0.0;
    out->empty_p25_ms = empty_n ? empty[empty_n / 4] : 0.0;
    out->empty_p75_ms = empty_n ? empty[(3 * empty_n) / 4] : 0.0;
    hl_sort_doubles(composite, composite_n);
    out->composite_frames = (uint32_t)composite_n;
    out->composite_ms = composite_n ? composite[composite_n / 2] : 0.0;
    out->seconds = (double)(hl_clock_now_ns() - start_ns) * 1e-9;
    rc = 0;
done:
    rnd_renderer_destroy(r);
    for (int f = 0; f < 2; ++f)
        scn_scene_free(&scenes[f]);
    free(index);
    free(lod);
    free(scratch);
    free(order);
    free(times);
    free(empty);
    free(composite);
    if (rc != 0)
        rnd_calibration_free(out);
    return rc;
}

void rnd_cost_split(size_t count, uint64_t seed, uint32_t *order, size_t *train_count)
{
    for (size_t i = 0; i < count; ++i)
        order[i] = (uint32_t)i;
    uint64_t state = seed;
    for (size_t i = count; i > 1; --i) { /* splitmix64 (as scene/'s generator) driving Fisher–Yates */
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        size_t j = (size_t)(z % i);
        uint32_t t = order[i - 1];
        order[i - 1] = order[j];
        order[j] = t;
    }
    size_t train = (size_t)llround(0.75 * (double)count);
    if (count >= 2 && train >= count)
        train = count - 1;
    if (count >= 2 && train < 1)
        train = 1;
    *train_count = train;
}
