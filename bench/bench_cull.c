/* hmdlod bench cull: per-frame culling time, flat (every instance tested) against hierarchical
 * (scene/cull.c), on generated scenes of 1k / 10k / 100k instances under the real head motion of
 * one trace, in one run so that the ratios are measured under the same load. The scene is a ground
 * grid of objects around the viewer grouped as a quadtree (4 × 4 objects a leaf, 4 × 4 groups a
 * parent): Clark's (1976) hierarchy in its plainest form. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "hmd/hmd.h"
#include "replay/replay.h"
#include "scene/scene.h"

#define CULL_TRACE "data/traces/corbillon-mmsys18/user1_quaternion.txt"

enum { N_SIZES = 3, FANOUT = 4 };
static const uint32_t sizes[N_SIZES] = {1000, 10000, 100000};
static const double pitch_m = 2.0; /* one object per 2 m × 2 m of ground */

/* splitmix64: the scene is the same for a seed everywhere */
static uint64_t mix_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static double mix_uniform(uint64_t *s) { return (double)(mix_next(s) >> 11) * 0x1.0p-53; }

/* The generated scene: n objects on a W × W grid of slots (W = ⌈√n⌉, row-major slots < n filled),
 * 2 m apart around the origin, heights from 1.5 m below to 3 m above the eyes, radii 0.3–0.8 m.
 * Groups top-down, breadth first (parents before children, siblings consecutive): level 0 are the
 * slots, a node of level l covers FANOUT × FANOUT nodes of level l − 1; the roots are the level whose
 * side is ≤ FANOUT. Objects are numbered leaf by leaf. */
int bch_cull_make_grid(uint32_t n, uint64_t seed, struct scn_scene *s, struct hl_error *err)
{
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "grid%u", n);
    uint32_t w = (uint32_t)ceil(sqrt((double)n)), side[16], levels = 0;
    side[0] = w;
    while (side[levels] > FANOUT && levels < 14) {
        side[levels + 1] = (side[levels] + FANOUT - 1) / FANOUT;
        ++levels;
    }
    /* upper bound on groups: every node of levels 1…levels */
    uint64_t cap = 0;
    for (uint32_t l = 1; l <= levels; ++l)
        cap += (uint64_t)side[l] * side[l];
    s->instance_count = n;
    s->center_m = malloc(3 * (size_t)n * sizeof(double));
    s->radius_m = malloc((size_t)n * sizeof(double));
    s->group_instances = malloc((size_t)n * sizeof(uint32_t));
    s->groups = calloc(cap ? cap : 1, sizeof *s->groups);
    s->group_children = malloc((cap ? cap : 1) * sizeof(uint32_t));
    uint32_t *node_level = malloc((cap ? cap : 1) * sizeof(uint32_t)), *node_x = malloc((cap ? cap : 1) * sizeof(uint32_t)),
             *node_z = malloc((cap ? cap : 1) * sizeof(uint32_t));
    int rc = -1;
    if (!s->center_m || !s->radius_m || !s->group_instances || !s->groups || !s->group_children || !node_level ||
        !node_x || !node_z) {
        hl_fail(err, "bench cull: out of memory for %u objects", n);
        goto done;
    }
    uint32_t tail = 0, inst = 0;
    if (levels == 0) { /* too small for groups: flat */
        for (uint32_t i = 0; i < n; ++i)
            s->group_instances[i] = i;
    }
    for (uint32_t z = 0; levels > 0 && z < side[levels]; ++z)
        for (uint32_t x = 0; x < side[levels]; ++x) {
            node_level[tail] = levels, node_x[tail] = x, node_z[tail] = z;
            s->groups[tail].parent = SCN_NONE;
            ++tail;
        }
    uint64_t rng = seed;
    for (uint32_t head = 0; head < tail; ++head) {
        struct scn_group *g = &s->groups[head];
        uint32_t l = node_level[head], child_side = side[l - 1];
        snprintf(g->name, sizeof g->name, "l%u_%u_%u", l, node_x[head], node_z[head]);
        g->impostor_chain = SCN_NONE;
        g->impostor_instance = SCN_NONE;
        g->importance = 1.0;
        g->first_child = tail;
        g->first_instance = inst;
        /* a node's slot span: FANOUT^l slots on a side */
        for (uint32_t dz = 0; dz < FANOUT; ++dz)
            for (uint32_t dx = 0; dx < FANOUT; ++dx) {
                uint32_t cx = node_x[head] * FANOUT + dx, cz = node_z[head] * FANOUT + dz;
                if (cx >= child_side || cz >= child_side)
                    continue;
                uint64_t span = 1;
                for (uint32_t k = 1; k < l; ++k)
                    span *= FANOUT;
                uint64_t first_slot = (uint64_t)cz * span * w + (uint64_t)cx * span; /* its top-left slot */
                if (cz * span >= w || cx * span >= w || first_slot >= n)
                    continue; /* nothing in it */
                if (l == 1) { /* the child is a slot: an object */
                    uint32_t i = inst++;
                    s->group_instances[i] = i;
                    s->center_m[3 * (size_t)i] = ((double)cx - 0.5 * w + 0.25 + 0.5 * mix_uniform(&rng)) * pitch_m;
                    s->center_m[3 * (size_t)i + 1] = -1.5 + 4.5 * mix_uniform(&rng);
                    s->center_m[3 * (size_t)i + 2] = ((double)cz - 0.5 * w + 0.25 + 0.5 * mix_uniform(&rng)) * pitch_m;
                    s->radius_m[i] = 0.3 + 0.5 * mix_uniform(&rng);
                } else {
                    node_level[tail] = l - 1, node_x[tail] = cx, node_z[tail] = cz;
                    s->groups[tail].parent = head;
                    s->group_children[tail] = tail;
                    ++tail;
                }
            }
        g->child_count = tail - g->first_child;
        g->instance_count = inst - g->first_instance;
    }
    if (levels == 0) {
        for (uint32_t i = 0; i < n; ++i) {
            s->center_m[3 * (size_t)i] = ((double)(i % w) - 0.5 * w + 0.5) * pitch_m;
            s->center_m[3 * (size_t)i + 1] = 0.0;
            s->center_m[3 * (size_t)i + 2] = ((double)(i / w) - 0.5 * w + 0.5) * pitch_m;
            s->radius_m[i] = 0.5;
        }
    }
    if (inst != n && levels > 0) {
        hl_fail(err, "bench cull: placed %u of %u objects", inst, n);
        goto done;
    }
    s->group_count = tail;
    scn_scene_group_bounds(s);
    rc = scn_scene_check_groups(s, err);
done:
    free(node_level);
    free(node_x);
    free(node_z);
    return rc;
}

static double percentile(double *v, long n, double p) /* nearest rank; sorts v */
{
    hl_sort_doubles(v, (size_t)n);
    return hl_percentile_sorted(v, (size_t)n, p);
}

struct size_result {
    uint32_t instances, groups;
    double flat_us_median, flat_us_p95, hier_us_median, hier_us_p95;
    double visible_instances, visible_groups, groups_tested, instances_tested, plane_tests_hier, plane_tests_flat;
};

static int run_size(uint32_t n, const struct bch_cull_options *o, struct trk_pose_source *src,
                    const struct frm_cull_frustum *frustum, double rate_hz, struct size_result *r)
{
    struct scn_scene s;
    struct hl_error err = {{0}};
    struct scn_culler c = {0};
    uint32_t *vis = malloc(n * sizeof *vis);
    double *flat_us = malloc((size_t)o->frames * sizeof(double)), *hier_us = malloc((size_t)o->frames * sizeof(double));
    int rc = 1;
    memset(r, 0, sizeof *r);
    if (!vis || !flat_us || !hier_us) {
        fprintf(stderr, "hmdlod bench cull: out of memory\n");
        goto done;
    }
    if (bch_cull_make_grid(n, (uint64_t)o->seed, &s, &err) != 0 || scn_culler_init(&c, &s, &err) != 0) {
        fprintf(stderr, "hmdlod bench cull: %s\n", err.msg);
        scn_scene_free(&s);
        goto done;
    }
    r->instances = n;
    r->groups = s.group_count;
    double span_s = src->end_time_s - src->start_time_s;
    for (long f = 0; f < o->frames; ++f) {
        /* the trace loops when it is shorter than the frames asked for */
        double t = src->start_time_s + fmod((double)f / rate_hz, span_s > 0 ? span_s : 1.0);
        struct trk_pose pose;
        if (trk_source_pose_at(src, t, &pose, &err) != 0) {
            fprintf(stderr, "hmdlod bench cull: %s\n", err.msg);
            goto free_scene;
        }
        if (!pose.has_position)
            pose.position_m = hl_v3(0, 0, 0);
        struct scn_plane planes[5];
        int np = frm_cull_frustum_planes(frustum, &pose, planes);
        struct scn_cull_stats hs, fs;
        uint32_t nh = 0, nf = 0;
        int64_t t0, t1, t2;
        /* alternate which goes first, so neither always finds the caches warm */
        if (f & 1) {
            t0 = hl_clock_now_ns();
            nh = scn_cull(&s, planes, np, &c, vis, &hs);
            t1 = hl_clock_now_ns();
            nf = scn_cull_flat(&s, planes, np, vis, &fs);
            t2 = hl_clock_now_ns();
            hier_us[f] = (double)(t1 - t0) * 1e-3, flat_us[f] = (double)(t2 - t1) * 1e-3;
        } else {
            t0 = hl_clock_now_ns();
            nf = scn_cull_flat(&s, planes, np, vis, &fs);
            t1 = hl_clock_now_ns();
            nh = scn_cull(&s, planes, np, &c, vis, &hs);
            t2 = hl_clock_now_ns();
            flat_us[f] = (double)(t1 - t0) * 1e-3, hier_us[f] = (double)(t2 - t1) * 1e-3;
        }
        if (nh != nf) {
            fprintf(stderr, "hmdlod bench cull: %u objects: frame %ld: hierarchical %u visible, flat %u\n", n, f, nh, nf);
            goto free_scene;
        }
        r->visible_instances += nh;
        r->visible_groups += hs.groups_visible;
        r->groups_tested += hs.groups_tested;
        r->instances_tested += hs.instances_tested;
        r->plane_tests_hier += (double)hs.plane_tests;
        r->plane_tests_flat += (double)fs.plane_tests;
    }
    double frames = (double)o->frames;
    r->visible_instances /= frames, r->visible_groups /= frames, r->groups_tested /= frames;
    r->instances_tested /= frames, r->plane_tests_hier /= frames, r->plane_tests_flat /= frames;
    r->flat_us_median = percentile(flat_us, o->frames, 0.5);
    r->flat_us_p95 = percentile(flat_us, o->frames, 0.95);
    r->hier_us_median = percentile(hier_us, o->frames, 0.5);
    r->hier_us_p95 = percentile(hier_us, o->frames, 0.95);
    rc = 0;
free_scene:
    scn_culler_free(&c);
    scn_scene_free(&s);
done:
    free(vis);
    free(flat_us);
    free(hier_us);
    return rc;
}

int bch_cull(const struct bch_cull_options *options, int full_argc, char **full_argv)
{
    struct bch_cull_options o = *options;
    char trace_buf[4200];
    struct hl_error err = {{0}};
    struct hmd_profile display;
    if (hmd_profile_load(o.display, &display, &err) != 0) {
        fprintf(stderr, "hmdlod bench cull: %s\n", err.msg);
        return 1;
    }
    const char *trace_label = o.trace;
    if (!o.trace) {
        char shared[4096];
        if (bch_find_shared(shared, sizeof shared) == 0) {
            snprintf(trace_buf, sizeof trace_buf, "%s/" CULL_TRACE, shared);
            o.trace = trace_buf;
            trace_label = "Corbillon MMSys'18 user1";
        } else {
            fprintf(stderr, "hmdlod bench cull: note: the shared data folder is absent (%s); the built-in clip\n", shared);
            trace_label = "the built-in clip";
        }
    }
    struct rpl_trace trace;
    int rc = o.trace ? rpl_trace_load(o.trace, &trace, &err) : rpl_trace_builtin_clip(&trace, &err);
    struct trk_pose_source *src = NULL;
    if (rc != 0 || rpl_trace_source_create(&trace, &src, &err) != 0) {
        fprintf(stderr, "hmdlod bench cull: %s\n", err.msg);
        return 1;
    }
    struct frm_cull_frustum frustum;
    frm_cull_frustum_init(&frustum, &display, 0.05);
    double rate_hz = display.refresh_hz;
    struct size_result res[N_SIZES];
    for (int k = 0; k < N_SIZES && rc == 0; ++k) {
        fprintf(stderr, "hmdlod bench cull: %u objects, %ld frames\n", sizes[k], o.frames);
        rc = run_size(sizes[k], &o, src, &frustum, rate_hz, &res[k]);
    }
    trk_source_destroy(src);
    if (rc != 0)
        return 1;
    if (o.results && bch_copy_begin() != 0) {
        fprintf(stderr, "hmdlod bench cull: out of memory\n");
        return 1;
    }
    bch_emit(BCH_CULL_HEADING "\n\n");
    bch_print_context(full_argc, full_argv, NULL);
    bch_emit("- head motion: %s, %ld frames at %.0f Hz; frusta: %s (union of both eyes)\n\n", trace_label, o.frames,
               rate_hz, display.name);
    bch_emit("| objects | groups | flat µs median / p95 | hierarchical µs median / p95 | **flat / hier** (median) | "
               "visible objects | visible groups | groups tested | objects tested (hier / flat) | plane tests (hier / flat) |\n");
    bch_emit("|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int k = 0; k < N_SIZES; ++k) {
        const struct size_result *r = &res[k];
        bch_emit("| %u | %u | %.1f / %.1f | %.1f / %.1f | **×%.2f** | %.0f | %.0f | %.0f | %.0f / %u | %.0f / %.0f |\n",
                   r->instances, r->groups, r->flat_us_median, r->flat_us_p95, r->hier_us_median, r->hier_us_p95,
                   r->flat_us_median / r->hier_us_median, r->visible_instances, r->visible_groups, r->groups_tested,
                   r->instances_tested, r->instances, r->plane_tests_hier, r->plane_tests_flat);
    }
    /* What the time follows: each quantity's growth from the smallest scene to the largest. */
    const struct size_result *lo = &res[0], *hi = &res[N_SIZES - 1];
    bch_emit("| growth %uk → %uk | ×%.0f | ×%.1f | ×%.1f | | ×%.1f | ×%.1f | ×%.1f | ×%.1f / ×%.0f | ×%.1f / ×%.1f |\n",
               lo->instances / 1000, hi->instances / 1000, (double)hi->groups / lo->groups,
               hi->flat_us_median / lo->flat_us_median, hi->hier_us_median / lo->hier_us_median,
               hi->visible_instances / fmax(lo->visible_instances, 1e-9), hi->visible_groups / fmax(lo->visible_groups, 1e-9),
               hi->groups_tested / fmax(lo->groups_tested, 1e-9), hi->instances_tested / fmax(lo->instances_tested, 1e-9),
               (double)hi->instances / lo->instances, hi->plane_tests_hier / fmax(lo->plane_tests_hier, 1e-9),
               hi->plane_tests_flat / fmax(lo->plane_tests_flat, 1e-9));
    bch_emit("\nAt %uk objects: flat %.2f ns per object; hierarchical %.2f ns per sphere tested (groups and "
               "objects) if the copy of the visible objects were free, or %.2f ns per visible object if the tests "
               "were: the flat time follows the scene's objects, the hierarchical time the spheres tested (groups "
               "at the frustum's edges) plus a copy per visible object.\n",
               hi->instances / 1000, 1e3 * hi->flat_us_median / hi->instances,
               1e3 * hi->hier_us_median / (hi->groups_tested + hi->instances_tested),
               1e3 * hi->hier_us_median / fmax(hi->visible_instances, 1));
    bch_emit("\nHow measured (bench/bench_cull.c, scene/cull.c): each size is a ground grid of objects 2 m apart "
               "around the viewer (heights −1.5…3 m about the eyes, radii 0.3–0.8 m, seed %ld), grouped as a quadtree "
               "of 4 × 4 objects per leaf and 4 × 4 groups per parent. Each frame takes the trace's head pose on a "
               "virtual clock, builds the five world planes of the union of both eye frusta (frame's "
               "frm_cull_frustum_planes) and culls once flat (every object against the planes, scn_cull_flat) "
               "and once through the hierarchy (scn_cull, with plane masks), alternating which runs first; both "
               "must find the same number of objects. Times are CLOCK_MONOTONIC around each call on a machine shared "
               "with other work: compare the ratios within one run.\n",
               o.seed);
    return bch_copy_finish(o.results, BCH_CULL_HEADING, "hmdlod bench cull", 0);
}
