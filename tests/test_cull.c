/* Hierarchical culling (scene/cull.c): the same visible set as a brute-force test written here
 * independently, over random hierarchies and random plane sets; the cost claims (a far group culled
 * by one test, a group inside everything accepted untested); group bounds containing their
 * children; the auditorium's rows as groups with its instances unchanged. */
#define _XOPEN_SOURCE 700 /* mkdtemp */
#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "replay/replay.h"
#include "scene/scene.h"
#include "test_util.h"

/* splitmix64, independent of the scene's own generator */
static uint64_t rng_state;
static uint64_t rng_next(void)
{
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}
static double rng_uniform(void) { return (double)(rng_next() >> 11) * 0x1.0p-53; }

/* A random hierarchy by hand: groups in index order (each parent chosen among earlier groups or
 * none), instances held by a random group or by none, spheres clustered about their group so that
 * the bounds mean something. Arrays as scn_scene expects them; freed by scn_scene_free. */
static void random_scene(struct scn_scene *s, uint32_t ng, uint32_t ni)
{
    memset(s, 0, sizeof *s);
    snprintf(s->name, sizeof s->name, "random");
    s->instance_count = ni;
    s->group_count = ng;
    s->center_m = calloc(3 * (size_t)ni, sizeof(double));
    s->radius_m = calloc(ni, sizeof(double));
    s->groups = calloc(ng ? ng : 1, sizeof *s->groups);
    s->group_children = calloc(ng ? ng : 1, sizeof(uint32_t));
    s->group_instances = calloc(ni, sizeof(uint32_t));
    uint32_t *parent = malloc((ng ? ng : 1) * sizeof *parent), *owner = malloc(ni * sizeof *owner);
    double *anchor = malloc(3 * (size_t)(ng ? ng : 1) * sizeof *anchor);
    for (uint32_t g = 0; g < ng; ++g) {
        parent[g] = (g == 0 || rng_uniform() < 0.15) ? SCN_NONE : (uint32_t)(rng_next() % g);
        for (int a = 0; a < 3; ++a) /* children cluster near their parent */
            anchor[3 * g + a] = parent[g] == SCN_NONE ? 80.0 * (rng_uniform() - 0.5)
                                                      : anchor[3 * parent[g] + a] + 10.0 * (rng_uniform() - 0.5);
    }
    for (uint32_t i = 0; i < ni; ++i) {
        owner[i] = (ng == 0 || rng_uniform() < 0.1) ? SCN_NONE : (uint32_t)(rng_next() % ng);
        for (int a = 0; a < 3; ++a)
            s->center_m[3 * i + a] = (owner[i] == SCN_NONE ? 80.0 * (rng_uniform() - 0.5) : anchor[3 * owner[i] + a]) +
                                     4.0 * (rng_uniform() - 0.5);
        s->radius_m[i] = 0.05 + 1.5 * rng_uniform();
    }
    /* children lists: group g's children consecutive; since parents precede children, order them by parent */
    uint32_t k = 0;
    for (uint32_t g = 0; g < ng; ++g) {
        s->groups[g].parent = parent[g];
        s->groups[g].impostor_chain = SCN_NONE;
        s->groups[g].impostor_instance = SCN_NONE;
        s->groups[g].importance = 1.0;
        s->groups[g].first_child = k;
        for (uint32_t c = g + 1; c < ng; ++c)
            if (parent[c] == g)
                s->group_children[k++] = c;
        s->groups[g].child_count = k - s->groups[g].first_child;
    }
    k = 0;
    for (uint32_t g = 0; g < ng; ++g) {
        s->groups[g].first_instance = k;
        for (uint32_t i = 0; i < ni; ++i)
            if (owner[i] == g)
                s->group_instances[k++] = i;
        s->groups[g].instance_count = k - s->groups[g].first_instance;
    }
    free(parent);
    free(owner);
    free(anchor);
    scn_scene_group_bounds(s);
}

/* The reference: a sphere is kept unless some plane has it wholly on its negative side. */
static int brute_visible(const struct scn_scene *s, uint32_t i, const struct scn_plane *p, int np)
{
    for (int k = 0; k < np; ++k) {
        double d = 0;
        for (int a = 0; a < 3; ++a)
            d += p[k].normal[a] * s->center_m[3 * i + a];
        if (d + p[k].offset_m < -s->radius_m[i])
            return 0;
    }
    return 1;
}

static void random_planes(struct scn_plane *p, int np)
{
    for (int k = 0; k < np; ++k) {
        double z = 2 * rng_uniform() - 1, az = 2 * HL_PI * rng_uniform(), r = sqrt(1 - z * z);
        p[k].normal[0] = r * cos(az), p[k].normal[1] = r * sin(az), p[k].normal[2] = z;
        p[k].offset_m = 30.0 * (rng_uniform() - 0.3); /* mostly through the scene, some far out */
    }
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Every group's sphere contains each child's sphere and each instance's sphere (checked here from
 * the definitions, not from the code that computed them). */
static int bounds_contain(const struct scn_scene *s)
{
    for (uint32_t g = 0; g < s->group_count; ++g) {
        const struct scn_group *gr = &s->groups[g];
        for (uint32_t k = 0; k < gr->instance_count; ++k) {
            uint32_t i = s->group_instances[gr->first_instance + k];
            double d = hl_v3_length(hl_v3(s->center_m[3 * i] - gr->center_m[0], s->center_m[3 * i + 1] - gr->center_m[1],
                                          s->center_m[3 * i + 2] - gr->center_m[2]));
            if (d + s->radius_m[i] > gr->radius_m)
                return 0;
        }
        for (uint32_t k = 0; k < gr->child_count; ++k) {
            const struct scn_group *c = &s->groups[s->group_children[gr->first_child + k]];
            if (c->radius_m < 0)
                continue;
            double d = hl_v3_length(hl_v3(c->center_m[0] - gr->center_m[0], c->center_m[1] - gr->center_m[1],
                                          c->center_m[2] - gr->center_m[2]));
            if (d + c->radius_m > gr->radius_m)
                return 0;
        }
    }
    return 1;
}

static void test_random_against_brute_force(void)
{
    rng_state = 12345;
    int mismatches = 0, trials = 0, bounds_ok = 1, order_ok = 1;
    uint64_t hier_tests = 0, flat_tests = 0;
    for (int scene = 0; scene < 40; ++scene) {
        uint32_t ng = (uint32_t)(rng_next() % 60), ni = 1 + (uint32_t)(rng_next() % 400);
        struct scn_scene s;
        random_scene(&s, ng, ni);
        CHECK(scn_scene_check_groups(&s, NULL) == 0);
        bounds_ok &= bounds_contain(&s);
        struct scn_culler c;
        CHECK(scn_culler_init(&c, &s, NULL) == 0);
        uint32_t *vis = malloc(ni * sizeof *vis), *ref = malloc(ni * sizeof *ref), *flat = malloc(ni * sizeof *flat);
        for (int f = 0; f < 50; ++f, ++trials) {
            struct scn_plane planes[SCN_CULL_MAX_PLANES];
            int np = 1 + (int)(rng_next() % SCN_CULL_MAX_PLANES);
            random_planes(planes, np);
            struct scn_cull_stats st, fst;
            uint32_t n = scn_cull(&s, planes, np, &c, vis, &st);
            uint32_t nf = scn_cull_flat(&s, planes, np, flat, &fst);
            uint32_t nr = 0;
            for (uint32_t i = 0; i < ni; ++i)
                if (brute_visible(&s, i, planes, np))
                    ref[nr++] = i;
            /* flat keeps index order, so it must equal the reference exactly */
            if (nf != nr || memcmp(flat, ref, nr * sizeof *ref) != 0)
                order_ok = 0;
            qsort(vis, n, sizeof *vis, cmp_u32);
            int same = n == nr && memcmp(vis, ref, n * sizeof *vis) == 0 && st.instances_visible == n;
            for (uint32_t k = 1; k < n; ++k)
                same &= vis[k] != vis[k - 1]; /* no instance twice */
            mismatches += !same;
            hier_tests += st.instances_tested + st.groups_tested;
            flat_tests += fst.instances_tested;
        }
        free(vis);
        free(ref);
        free(flat);
        scn_culler_free(&c);
        scn_scene_free(&s);
    }
    CHECK(bounds_ok);
    CHECK(order_ok);
    if (mismatches)
        fprintf(stderr, "hierarchical cull differs from brute force in %d of %d trials\n", mismatches, trials);
    CHECK(mismatches == 0);
    printf("random: %d trials, sphere tests hierarchical %llu vs flat %llu\n", trials, (unsigned long long)hier_tests,
           (unsigned long long)flat_tests);
}

/* A view down −Z from the origin, 90° wide: four side planes through the origin and a near plane. */
static int view_planes(struct scn_plane *p)
{
    const double r = sqrt(0.5);
    const double n[5][3] = {{r, 0, -r}, {-r, 0, -r}, {0, r, -r}, {0, -r, -r}, {0, 0, -1}};
    for (int k = 0; k < 5; ++k) {
        memcpy(p[k].normal, n[k], sizeof n[k]);
        p[k].offset_m = k == 4 ? -0.05 : 0.0;
    }
    return 5;
}

/* One root group of 100 instances far behind the viewer: one sphere test and nothing else; then the
 * same group well inside the view: all visible with no instance tested. */
static void test_far_group_one_test(void)
{
    struct scn_scene s;
    rng_state = 7;
    random_scene(&s, 1, 100);
    for (int where = 0; where < 2; ++where) {
        for (uint32_t i = 0; i < 100; ++i) {
            s.groups[0].first_instance = 0, s.groups[0].instance_count = 100, s.group_instances[i] = i;
            s.center_m[3 * i] = 0.5 * (rng_uniform() - 0.5);
            s.center_m[3 * i + 1] = 0.5 * (rng_uniform() - 0.5);
            s.center_m[3 * i + 2] = (where == 0 ? 1000.0 : -100.0) + 0.5 * (rng_uniform() - 0.5);
            s.radius_m[i] = 0.1;
        }
        scn_scene_group_bounds(&s);
        struct scn_culler c;
        CHECK(scn_culler_init(&c, &s, NULL) == 0);
        CHECK(c.loose_count == 0);
        struct scn_plane p[5];
        int np = view_planes(p);
        uint32_t vis[100];
        struct scn_cull_stats st;
        uint32_t n = scn_cull(&s, p, np, &c, vis, &st);
        if (where == 0) {
            CHECK(n == 0);
            CHECK(st.groups_tested == 1);
            CHECK(st.instances_tested == 0);
            CHECK(st.groups_visible == 0);
        } else {
            CHECK(n == 100);
            CHECK(st.groups_tested == 1);
            CHECK(st.instances_tested == 0); /* wholly inside: accepted untested */
            CHECK(st.plane_tests == 5);
        }
        struct scn_cull_stats fst;
        CHECK(scn_cull_flat(&s, p, np, vis, &fst) == n);
        CHECK(fst.instances_tested == 100);
        scn_culler_free(&c);
    }
    scn_scene_free(&s);
}

/* Planes the group straddles are the only ones its children test (the mask): a group crossing only
 * the left plane makes its instances test that one plane each. */
static void test_plane_mask(void)
{
    struct scn_scene s;
    rng_state = 9;
    random_scene(&s, 1, 10);
    for (uint32_t i = 0; i < 10; ++i) {
        s.groups[0].first_instance = 0, s.groups[0].instance_count = 10, s.group_instances[i] = i;
        /* a row across the left edge (x = z) at 20 m */
        s.center_m[3 * i] = -20.0 - 4.5 + (double)i, s.center_m[3 * i + 1] = 0, s.center_m[3 * i + 2] = -20.0;
        s.radius_m[i] = 0.2;
    }
    scn_scene_group_bounds(&s);
    struct scn_culler c;
    CHECK(scn_culler_init(&c, &s, NULL) == 0);
    struct scn_plane p[5];
    int np = view_planes(p);
    uint32_t vis[10];
    struct scn_cull_stats st;
    uint32_t n = scn_cull(&s, p, np, &c, vis, &st);
    uint32_t expect = 0;
    for (uint32_t i = 0; i < 10; ++i)
        expect += brute_visible(&s, i, p, np);
    CHECK(n == expect && n > 0 && n < 10);
    CHECK(st.instances_tested == 10);
    CHECK(st.plane_tests == 5 + 10); /* the group against all five, each instance against the left plane only */
    scn_culler_free(&c);
    scn_scene_free(&s);
}

static void test_auditorium_groups(void)
{
    struct scn_scene s;
    struct hl_error err = {{0}};
    CHECK(scn_scene_build("auditorium", NULL, &s, &err) == 0);
    CHECK(s.instance_count == 157); /* 10 rows of 15 chairs, 7 room surfaces: unchanged */
    CHECK(s.chain_count == 8);
    CHECK(s.group_count == 32); /* seating, room, 10 rows, 20 half rows */
    CHECK(scn_scene_check_groups(&s, &err) == 0);
    CHECK(bounds_contain(&s));
    uint32_t held = 0;
    for (uint32_t g = 0; g < s.group_count; ++g)
        held += s.groups[g].instance_count;
    CHECK(held == s.instance_count); /* every instance in one group */
    CHECK(strcmp(s.groups[0].name, "seating") == 0 && s.groups[0].child_count == 10);
    CHECK(strcmp(s.groups[1].name, "room") == 0 && s.groups[1].instance_count == 7);
    CHECK(s.groups[2].child_count == 2 && s.groups[2].instance_count == 0);
    CHECK(s.groups[12].instance_count == 7 && s.groups[13].instance_count == 8 && s.groups[13].parent == 2);
    uint64_t tris = 0;
    for (uint32_t i = 0; i < s.instance_count; ++i)
        tris += s.chains[s.chain_of_instance[i]].lods[0].triangle_count;
    CHECK(tris == 150ull * 600 + 7 * 12); /* the finest triangles of the whole room */
    /* Looking at the stage from the back wall, outside the seating: the rows still all show, and the
     * visible set matches brute force. */
    struct scn_culler c;
    CHECK(scn_culler_init(&c, &s, &err) == 0);
    struct scn_plane p[5];
    int np = view_planes(p);
    for (int k = 0; k < np; ++k) /* the viewer moved to the origin of a frame 30 m behind the room */
        p[k].offset_m -= p[k].normal[2] * 30.0;
    uint32_t *vis = malloc(s.instance_count * sizeof *vis);
    struct scn_cull_stats st;
    uint32_t n = scn_cull(&s, p, np, &c, vis, &st), nr = 0;
    for (uint32_t i = 0; i < s.instance_count; ++i)
        nr += brute_visible(&s, i, p, np);
    CHECK(n == nr);
    free(vis);
    scn_culler_free(&c);
    scn_scene_free(&s);
}

/* The field scene is flat: scn_cull is the per-instance test in index order. */
static void test_field_flat(void)
{
    struct scn_scene s;
    struct scn_scene_params params = {.object_count = 500, .seed = 3};
    CHECK(scn_scene_build("field", &params, &s, NULL) == 0);
    CHECK(s.group_count == 0);
    struct scn_culler c;
    CHECK(scn_culler_init(&c, &s, NULL) == 0);
    struct scn_plane p[5];
    int np = view_planes(p);
    uint32_t *vis = malloc(500 * sizeof *vis);
    struct scn_cull_stats st;
    uint32_t n = scn_cull(&s, p, np, &c, vis, &st), k = 0;
    int same = 1;
    for (uint32_t i = 0; i < 500; ++i)
        if (brute_visible(&s, i, p, np))
            same &= k < n && vis[k++] == i;
    CHECK(same && k == n && n > 0);
    CHECK(st.groups_tested == 0 && st.instances_tested == 500);
    free(vis);
    scn_culler_free(&c);
    scn_scene_free(&s);
}

/* FNV-1a 64 of the deterministic columns of frames.csv: each line up to its 11th field (frame …
 * lod3, for 4-level chains); the wall-clock columns after them vary from run to run. */
static uint64_t deterministic_hash(const char *path, int *lines)
{
    size_t n = 0;
    char *text = tu_read_file(path, &n);
    uint64_t h = 0xcbf29ce484222325ull;
    *lines = 0;
    if (!text)
        return 0;
    int field = 0;
    for (size_t i = 0; i < n; ++i) {
        char ch = text[i];
        if (ch == '\n') {
            field = 0;
            ++*lines;
        } else if (ch == ',' && ++field >= 11) {
            continue;
        } else if (field >= 11) {
            continue;
        }
        h = (h ^ (uint8_t)ch) * 0x100000001b3ull;
    }
    free(text);
    return h;
}

/* The replays of the built-in clip through field and auditorium (240 frames, Vive) write the same
 * deterministic columns as before culling went hierarchical: the hashes were taken from the build
 * of the commit before (75eea26, per-instance culling in the head frame). */
static void test_replay_unchanged(void)
{
    static const struct {
        const char *scene, *selector;
        uint64_t hash;
    } golden[] = {
        {"field", "reddy", 0x20de647cbe49d2e3ull},
        {"field", "none", 0x6f0b243ca5bfab9bull},
        {"auditorium", "reddy", 0x9b5d27d9f7f16399ull},
        {"auditorium", "none", 0xbebad0bea50b5f51ull},
    };
    char dir[] = "/tmp/hmdlod-test-cull-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp");
        return;
    }
    /* The goldens predate the gaze models: the head-locked eye at the neck pivot (the built-in Vive
     * with a zero neck-to-eye offset) is what every replay did then (docs/gaze.md). */
    char vive0[sizeof dir + 32];
    snprintf(vive0, sizeof vive0, "%s/vive0.json", dir);
    FILE *vf = fopen(vive0, "w");
    CHECK(vf != NULL);
    if (vf) {
        fputs("{\"name\": \"vive\", \"eye_pixels\": [1080, 1200], \"fov_tangents\": {\"left\": 1.3973, \"right\": 1.2505, "
              "\"up\": 1.4642, \"down\": 1.4775}, \"refresh_hz\": 90, \"ipd_m\": 0.063, \"neck_to_eye_m\": [0, 0]}\n", vf);
        fclose(vf);
    }
    for (size_t k = 0; k < sizeof golden / sizeof golden[0]; ++k) {
        struct rpl_options o;
        rpl_options_defaults(&o);
        o.frame.gaze = "head";
        o.frame.display = vive0;
        o.frame.scene = golden[k].scene;
        o.frame.selector = golden[k].selector;
        /* The goldens predate the measured tables: the geometric reading reproduces what the
         * selector saw then, so only the cull can make a difference here. */
        o.frame.frequency_reading = "geometric";
        o.frame.visibility = "acuity"; /* and the acuity criterion (docs/visibility.md) */
        o.frames = 240;
        o.frame.render_scale = 0.1;
        o.out_dir = dir;
        o.frame.quiet = 1;
        struct rpl_summary sum;
        struct hl_error err = {{0}};
        int rc = rpl_run(&o, &sum, &err);
        if (rc != 0)
            fprintf(stderr, "replay %s %s: %s\n", golden[k].scene, golden[k].selector, err.msg);
        CHECK(rc == 0);
        char path[sizeof dir + 32];
        snprintf(path, sizeof path, "%s/frames.csv", dir);
        int lines = 0;
        uint64_t h = deterministic_hash(path, &lines);
        if (h != golden[k].hash)
            fprintf(stderr, "replay %s %s: deterministic columns hash 0x%016llx, expected 0x%016llx\n",
                    golden[k].scene, golden[k].selector, (unsigned long long)h, (unsigned long long)golden[k].hash);
        CHECK(lines == 241);
        CHECK(h == golden[k].hash);
        CHECK(sum.vm_hwm_kib > 0 && sum.vm_rss_kib > 0 && sum.vm_rss_kib <= sum.vm_hwm_kib);
        unlink(path);
        snprintf(path, sizeof path, "%s/summary.json", dir);
        unlink(path);
    }
    unlink(vive0);
    rmdir(dir);
}

int main(void)
{
    /* Keep Mesa's driver loaded until exit so LeakSanitizer can see its globals (PLATFORM.md §4). */
    dlopen("/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so", RTLD_NOW | RTLD_NODELETE);
    test_replay_unchanged();
    test_random_against_brute_force();
    test_far_group_one_test();
    test_plane_mask();
    test_auditorium_groups();
    test_field_flat();
    return tu_finish("test_cull");
}
