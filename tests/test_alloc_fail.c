/* Allocation failure (docs/HARD_CASES.md, "Faults"): the k-th allocation made by the scene loaders,
 * the trace loader and the display-profile loader fails, for k = 1, 2, ... until the load succeeds.
 * Every failed load must return an error that says "out of memory", must not crash, and must leave
 * nothing allocated behind (counted here; the ASan build's leak checker checks it again).
 *
 * The program is linked with -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc,--wrap=free, which sends
 * every allocation of the project's own code (all its static libraries) through the wrappers below;
 * cJSON, a shared library, allocates through base's hl_lib_malloc (its loaders install the hooks),
 * so its allocations come here too. A load with
 * more than all_up_to allocations is probed at its first all_up_to, its last `tail` and `spread` evenly in
 * between (HMDLOD_ALLOC_FAIL_ALL=1 probes every one). `small` (scripts/valgrind-tests.sh) probes fewer
 * of the late ones, which cost a nearly whole load each: the first 100, the last 16 and 50 between. */
#define _XOPEN_SOURCE 700 /* mkdtemp */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hmd/hmd.h"
#include "replay/replay.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"
#include "test_util.h"

void *__real_malloc(size_t n);
void *__real_calloc(size_t n, size_t size);
void *__real_realloc(void *p, size_t n);
void __real_free(void *p);

/* ---- counting allocator ------------------------------------------------------------------------ */
static int armed;          /* counting (and failing) only inside a probed load */
static long alloc_count;   /* allocations since armed */
static long fail_at;       /* 0: none fails */
static long live;          /* blocks allocated while armed and not yet freed */

/* The blocks allocated while armed: open addressing, deleted slots marked (never reused for probing
 * stops), sized for far more blocks than any probed load makes. */
enum { SLOTS = 1 << 22 };
#define TOMB ((void *)1)
static void **slots;

static size_t slot_of(const void *p) { return ((uintptr_t)p >> 4) * 0x9E3779B97F4A7C15ull >> 42 & (SLOTS - 1); }
static void track(void *p)
{
    if (!p || !slots)
        return;
    for (size_t i = slot_of(p);; i = (i + 1) & (SLOTS - 1))
        if (slots[i] == NULL || slots[i] == TOMB) {
            slots[i] = p;
            ++live;
            return;
        }
}
static int untrack(void *p)
{
    if (!p || !slots)
        return 0;
    for (size_t i = slot_of(p); slots[i] != NULL; i = (i + 1) & (SLOTS - 1))
        if (slots[i] == p) {
            slots[i] = TOMB;
            --live;
            return 1;
        }
    return 0;
}

static int should_fail(void) { return armed && ++alloc_count == fail_at; }

void *__wrap_malloc(size_t n)
{
    if (should_fail())
        return NULL;
    void *p = __real_malloc(n);
    if (armed)
        track(p);
    return p;
}
void *__wrap_calloc(size_t n, size_t size)
{
    if (should_fail())
        return NULL;
    void *p = __real_calloc(n, size);
    if (armed)
        track(p);
    return p;
}
void *__wrap_realloc(void *p, size_t n)
{
    if (should_fail())
        return NULL; /* the block stays as it was, as realloc promises */
    int was = untrack(p);
    void *q = __real_realloc(p, n);
    if (q && (armed || was))
        track(q);
    else if (!q && was)
        track(p);
    return q;
}
void __wrap_free(void *p)
{
    untrack(p);
    __real_free(p);
}

/* ---- the probes ---------------------------------------------------------------------------------- */
static long all_up_to = 400, tail = 64, spread = 200;

typedef int (*load_fn)(void *ctx, struct hl_error *err); /* 0, or −1 with err, having freed everything */
typedef void (*free_fn)(void *ctx);

static long count_allocations(load_fn load, free_fn release, void *ctx)
{
    struct hl_error err = {""};
    armed = 1, alloc_count = 0, fail_at = 0, live = 0;
    int rc = load(ctx, &err);
    long n = alloc_count;
    armed = 0;
    if (rc != 0)
        fprintf(stderr, "  the load fails without any failed allocation: %s\n", err.msg);
    CHECK(rc == 0);
    if (rc == 0)
        release(ctx);
    CHECK(live == 0); /* the loaded thing frees all it allocated */
    return rc == 0 ? n : -1;
}

static void probe(const char *what, load_fn load, free_fn release, void *ctx)
{
    long n = count_allocations(load, release, ctx);
    if (n < 0)
        return;
    int all = getenv("HMDLOD_ALLOC_FAIL_ALL") != NULL || n <= all_up_to + tail + spread;
    long probed = 0, bad = 0;
    for (long k = 1; k <= n; ++k) {
        if (!all && k > all_up_to && k <= n - tail && (k - all_up_to) % ((n - all_up_to - tail) / spread + 1) != 0)
            continue;
        struct hl_error err = {""};
        armed = 1, alloc_count = 0, fail_at = k, live = 0;
        int rc = load(ctx, &err);
        armed = 0;
        ++probed;
        int ok = 1;
        if (rc == 0) { /* an allocation whose failure the code survives (a cache, a fallback) is fine */
            release(ctx);
        } else if (!strstr(err.msg, "out of memory")) {
            fprintf(stderr, "  %s: allocation %ld of %ld failed: the error does not say out of memory: %s\n", what,
                    k, n, err.msg);
            ok = 0;
        }
        if (live != 0) {
            fprintf(stderr, "  %s: allocation %ld of %ld failed: %ld blocks leaked (%s)\n", what, k, n, live,
                    err.msg);
            ok = 0;
        }
        bad += !ok;
        CHECK(ok);
        if (bad > 5) {
            fprintf(stderr, "  %s: more failures not shown\n", what);
            break;
        }
    }
    printf("  %s: %ld allocations, %ld probed, %ld mishandled\n", what, n, probed, bad);
}

/* scenes */
struct scene_ctx {
    const char *name, *path;
    int objects;
    struct scn_scene scene;
};
static int load_scene(void *c, struct hl_error *err)
{
    struct scene_ctx *s = c;
    memset(&s->scene, 0, sizeof s->scene);
    if (s->path)
        return scn_scenefile_load(s->path, NULL, &s->scene, err);
    struct scn_scene_params p = {s->objects, 1};
    return scn_scene_build(s->name, &p, &s->scene, err);
}
static void free_scene(void *c) { scn_scene_free(&((struct scene_ctx *)c)->scene); }

/* traces */
struct trace_ctx {
    const char *path;
    struct rpl_trace trace;
};
static int load_trace(void *c, struct hl_error *err)
{
    struct trace_ctx *t = c;
    return rpl_trace_load(t->path, &t->trace, err);
}
static void free_trace(void *c) { rpl_trace_free(&((struct trace_ctx *)c)->trace); }

/* display profiles */
struct display_ctx {
    const char *path;
    struct hmd_profile profile;
};
static int load_display(void *c, struct hl_error *err)
{
    struct display_ctx *d = c;
    return hmd_profile_load(d->path, &d->profile, err);
}
static void free_display(void *c) { (void)c; }

static char dir[] = "/tmp/hmdlod-alloc-fail-XXXXXX";

static const char *write_file(const char *name, const char *text)
{
    static char path[2][300];
    static int k;
    k ^= 1;
    snprintf(path[k], sizeof path[k], "%s/%s", dir, name);
    FILE *f = fopen(path[k], "wb");
    CHECK(f != NULL);
    if (f) {
        fputs(text, f);
        fclose(f);
    }
    return path[k];
}

static double bumpy(hl_vec3d d) { return 1.0 + 0.2 * d.x * d.y; }

/* A .lod for the scene file to reference, written by the project's writer: a sphere and a box. */
static int write_lod(const char *path)
{
    struct scn_lodset set;
    memset(&set, 0, sizeof set);
    scn_mesh_add_sphere(&set.levels[0], 0.5, 4, 6, bumpy);
    scn_mesh_add_box(&set.levels[1], hl_v3(0, 0, 0), hl_v3(0.45, 0.45, 0.45), hl_q_identity());
    set.level_count = 2;
    set.error_m[1] = 0.05, set.error_rel[1] = 0.1;
    set.freq[0] = (struct scn_level_freq){INFINITY, INFINITY, INFINITY};
    set.freq[1] = (struct scn_level_freq){12.0, 20.0, 10.0};
    set.radius_m = 0.6;
    for (int k = 0; k < 3; ++k)
        set.aabb_min_m[k] = -0.6, set.aabb_max_m[k] = 0.6;
    set.source_hash = scn_mesh_hash(&set.levels[0]);
    snprintf(set.simplifier, sizeof set.simplifier, "meshopt");
    struct hl_error err = {""};
    int rc = scn_lodfile_write(path, &set, &err);
    if (rc != 0)
        fprintf(stderr, "  cannot write the .lod: %s\n", err.msg);
    scn_lodset_free(&set);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "small") == 0)
        all_up_to = 100, tail = 16, spread = 50;
    slots = __real_calloc(SLOTS, sizeof *slots);
    if (!slots || !mkdtemp(dir))
        return 1;

    static const char *const builtins[] = {"field", "auditorium", "domes"};
    for (int b = 0; b < 3; ++b) {
        struct scene_ctx s = {.name = builtins[b], .objects = 10};
        char what[64];
        snprintf(what, sizeof what, "built-in scene %s", builtins[b]);
        probe(what, load_scene, free_scene, &s);
    }

    const char *groups = tu_source_path("tests/scenes/nested-groups.json");
    struct scene_ctx g = {.path = groups};
    probe("scene file nested-groups.json (groups, impostor, motion)", load_scene, free_scene, &g);

    char lod[300];
    snprintf(lod, sizeof lod, "%s/obj.lod", dir);
    if (write_lod(lod) == 0) {
        const char *file = write_file(
            "with-lod.json",
            "{\"version\": 1, \"name\": \"with-lod\", \"meshes\": {\"obj\": {\"path\": \"obj.lod\"},"
            " \"crate\": {\"builtin\": \"box\", \"size_m\": [1, 1, 1]}},"
            " \"instances\": [{\"name\": \"a\", \"mesh\": \"obj\", \"position_m\": [0, 0, -4]},"
            " {\"name\": \"b\", \"mesh\": \"obj\", \"position_m\": [1, 0, -4],"
            " \"motion\": {\"spin\": {\"axis\": [0, 1, 0], \"rate_degps\": 30}}},"
            " {\"name\": \"c\", \"mesh\": \"crate\", \"position_m\": [0, 2, -6]}],"
            " \"groups\": [{\"name\": \"all\", \"instances\": [\"a\", \"b\", \"c\"], \"impostor\": \"crate\"}]}");
        struct scene_ctx s = {.path = file};
        probe("scene file with a .lod asset, a motion and a group", load_scene, free_scene, &s);
    } else {
        CHECK(0);
    }

    const char *trace = write_file("trace.csv", "t_s,qw,qx,qy,qz\n0,1,0,0,0\n0.5,0.995004165,0,0.099833417,0\n1,0.980066578,0,0.198669331,0\n");
    struct trace_ctx t = {.path = trace};
    probe("trace", load_trace, free_trace, &t);
    const char *example = tu_source_path("tests/data/trace_example.csv");
    struct trace_ctx te = {.path = example};
    probe("trace tests/data/trace_example.csv", load_trace, free_trace, &te);

    const char *display = tu_source_path("tests/data/displays/valid_tangents.json");
    if (access(display, R_OK) == 0) {
        struct display_ctx d = {.path = display};
        probe("display profile", load_display, free_display, &d);
    }

    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "note: could not remove %s\n", dir);
    __real_free(slots);
    return tu_finish(tail == 16 ? "alloc_fail small" : "alloc_fail");
}
