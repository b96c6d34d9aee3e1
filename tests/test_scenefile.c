/* Scene files (scene/scenefile*.c, docs/scene-format.md): a valid file with nested groups loads with
 * the right counts, order, bounds, impostor, importance and motion; every kind of bad input is
 * refused with a message naming the file and the JSON path; the shipped real-meshes scene loads
 * through a caller's resolver (the hook replay and analyze use) and a small real mesh through the
 * default one. */
#define _XOPEN_SOURCE 700 /* mkdtemp */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene/scene.h"
#include "test_util.h"

static char tmp_dir[] = "/tmp/hmdlod-test-scenefile-XXXXXX";

static const char *write_temp(const char *name, const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", tmp_dir, name);
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (f) {
        fputs(text, f);
        fclose(f);
    }
    return path;
}

static double dist3(const double *a, const double *b)
{
    return hl_v3_length(hl_v3(a[0] - b[0], a[1] - b[1], a[2] - b[2]));
}

/* Each group's sphere holds its instances' and its child groups' spheres (from the definitions). */
static int bounds_contain(const struct scn_scene *s)
{
    for (uint32_t g = 0; g < s->group_count; ++g) {
        const struct scn_group *gr = &s->groups[g];
        for (uint32_t k = 0; k < gr->instance_count; ++k) {
            uint32_t i = s->group_instances[gr->first_instance + k];
            if (dist3(&s->center_m[3 * i], gr->center_m) + s->radius_m[i] > gr->radius_m)
                return 0;
        }
        for (uint32_t k = 0; k < gr->child_count; ++k) {
            const struct scn_group *c = &s->groups[s->group_children[gr->first_child + k]];
            if (c->parent != g || dist3(c->center_m, gr->center_m) + c->radius_m > gr->radius_m)
                return 0;
        }
    }
    return 1;
}

static uint32_t group_named(const struct scn_scene *s, const char *name)
{
    for (uint32_t g = 0; g < s->group_count; ++g)
        if (!strcmp(s->groups[g].name, name))
            return g;
    return SCN_NONE;
}

static void test_nested_groups(void)
{
    const char *path = tu_source_path("tests/scenes/nested-groups.json");
    struct scn_scene s;
    struct hl_error err = {{0}};
    int rc = scn_scenefile_load(path, NULL, &s, &err);
    if (rc != 0)
        fprintf(stderr, "%s\n", err.msg);
    CHECK(rc == 0);
    if (rc != 0)
        return;
    CHECK(!strcmp(s.name, "nested-groups"));
    CHECK(s.chain_count == 4);
    CHECK(s.chains[0].lod_count == 4 && s.chains[1].lod_count == 4 && s.chains[2].lod_count == 1);
    CHECK(s.chains[2].lods[0].triangle_count == 12);
    CHECK(s.instance_count == 8);
    CHECK(s.group_count == 5);
    /* parents first, breadth first from the root: world, front, back, west, east */
    static const char *const order[] = {"world", "front", "back", "west", "east"};
    for (uint32_t g = 0; g < 5 && g < s.group_count; ++g)
        CHECK(!strcmp(s.groups[g].name, order[g]));
    CHECK(scn_scene_check_groups(&s, &err) == 0);
    CHECK(bounds_contain(&s));
    uint32_t west = group_named(&s, "west"), east = group_named(&s, "east"), back = group_named(&s, "back");
    uint32_t front = group_named(&s, "front");
    CHECK(west != SCN_NONE && east != SCN_NONE && back != SCN_NONE && front != SCN_NONE);
    if (west == SCN_NONE || east == SCN_NONE || back == SCN_NONE || front == SCN_NONE)
        goto done;
    CHECK(s.groups[0].parent == SCN_NONE && s.groups[front].parent == 0 && s.groups[back].parent == 0);
    CHECK(s.groups[west].parent == front && s.groups[east].parent == front);
    /* instances in the order each group listed them; by name and by index */
    CHECK(s.groups[east].instance_count == 2 && s.group_instances[s.groups[east].first_instance] == 3 &&
          s.group_instances[s.groups[east].first_instance + 1] == 2);
    CHECK(s.groups[back].instance_count == 2 && s.group_instances[s.groups[back].first_instance] == 4);
    CHECK(s.groups[west].impostor_chain == 2); /* "crate", the third mesh */
    CHECK(s.groups[0].impostor_chain == SCN_NONE && s.groups[0].impostor_instance == SCN_NONE);
    /* west's impostor is drawable: one instance after the objects, at west's centre */
    CHECK(s.impostor_instance_count == 1 && s.groups[west].impostor_instance == s.instance_count);
    if (s.groups[west].impostor_instance == s.instance_count) {
        uint32_t k = s.instance_count;
        CHECK(s.instances[k].chain == 2);
        for (int a = 0; a < 3; ++a)
            CHECK_NEAR(s.instances[k].position_m[a], s.groups[west].center_m[a], 1e-12);
        if (s.importance)
            CHECK_NEAR(s.importance[k], s.groups[west].importance, 0);
    }
    CHECK_NEAR(s.groups[east].importance, 0.5, 0);
    CHECK(s.importance != NULL);
    if (s.importance)
        CHECK_NEAR(s.importance[1], 2.0, 0), CHECK_NEAR(s.importance[0], 1.0, 0);
    /* scale and sphere: a2 is the field object at 1.5 × */
    CHECK_NEAR(s.radius_m[1], 1.5 * s.chains[0].bound_radius_m, 1e-12);
    CHECK_NEAR(s.center_m[3 * 1 + 0], -5.0, 1e-12);
    CHECK_NEAR(s.center_m[3 * 1 + 1], 1.0, 1e-12);
    /* yaw 90°: the model's −Z (forward) turns to −X */
    hl_vec3d fwd = hl_q_rotate(s.instances[2].rotation, hl_v3(0, 0, -1));
    CHECK_NEAR(fwd.x, -1.0, 1e-12);
    CHECK_NEAR(fwd.z, 0.0, 1e-12);
    CHECK(fabs(s.instances[3].color[2] - 0.9f) < 1e-6);
    /* motion: the spinner spins, everything else is still */
    CHECK(s.motion != NULL);
    if (s.motion) {
        CHECK(s.motion->instance_motion[6].flags == SCN_MOTION_SPIN);
        CHECK_NEAR(s.motion->instance_motion[6].spin_rate_degps, 30.0, 0);
        CHECK(s.motion->instance_motion[0].flags == 0);
    }
    /* the loose instance is in no group; a culler finds it */
    struct scn_culler c;
    CHECK(scn_culler_init(&c, &s, &err) == 0);
    CHECK(c.loose_count == 1 && c.loose[0] == 7);
    CHECK(c.root_count == 1);
    scn_culler_free(&c);
done:
    scn_scene_free(&s);
}

/* A minimal scene around one instance: "%s" slots for the meshes, instance and groups members. */
#define MESHES "\"meshes\": {\"o\": {\"builtin\": \"box\", \"size_m\": [1, 1, 1]}}"
#define ONE "\"instances\": [{\"name\": \"i0\", \"mesh\": \"o\", \"position_m\": [0, 0, -3]}]"
#define TWO                                                                                                            \
    "\"instances\": [{\"name\": \"i0\", \"mesh\": \"o\", \"position_m\": [0, 0, -3]}, {\"name\": \"i1\", \"mesh\": " \
    "\"o\", \"position_m\": [1, 0, -3]}]"

struct bad_case {
    const char *what, *text, *where; /* where: the JSON path (or position) the message must name */
};

static const struct bad_case bad_cases[] = {
    {"empty file", "", "empty file"},
    {"only spaces", "  \n\t ", "empty file"},
    {"truncated JSON", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"posi", ":1:"},
    {"not an object", "[1, 2]", "top level"},
    {"NaN literal", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": [0,0,0], \"scale\": NaN}]}",
     "not valid JSON"},
    {"unknown top-level key", "{\"version\": 1, " MESHES ", " ONE ", \"colour\": [1, 0, 0]}", "colour: unknown key"},
    {"unknown instance key", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"posiiton_m\": [0, 0, 0]}]}",
     "instances[0].posiiton_m: unknown key"},
    {"unknown mesh key", "{\"version\": 1, \"meshes\": {\"o\": {\"builtin\": \"box\", \"size\": [1, 1, 1]}}, " ONE "}",
     "meshes.o.size: unknown key"},
    {"duplicate key", "{\"version\": 1, \"version\": 1, " MESHES ", " ONE "}", "version: duplicate key"},
    {"missing version", "{" MESHES ", " ONE "}", "version: missing"},
    {"unknown version", "{\"version\": 2, " MESHES ", " ONE "}", "version: 2 is not a version"},
    {"wrong type position", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": \"here\"}]}",
     "instances[0].position_m: expected an array of 3 numbers"},
    {"wrong type meshes", "{\"version\": 1, \"meshes\": [1], " ONE "}", "meshes: expected an object"},
    {"wrong type mesh name", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": 3, \"position_m\": [0, 0, 0]}]}",
     "instances[0].mesh: expected a mesh name"},
    {"position of two", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": [0, 0]}]}",
     "instances[0].position_m: expected an array of 3"},
    {"missing position", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\"}]}", "instances[0].position_m: missing"},
    {"unknown mesh name",
     "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": [0, 0, 0]}, {\"mesh\": \"chair\", "
     "\"position_m\": [0, 0, 0]}]}",
     "instances[1].mesh: no mesh named \"chair\""},
    {"missing mesh file", "{\"version\": 1, \"meshes\": {\"bunny\": {\"path\": \"no-such-bunny.obj\"}}, \"instances\": "
                          "[{\"mesh\": \"bunny\", \"position_m\": [0, 0, 0]}]}",
     "meshes.bunny.path: mesh \"bunny\": cannot open \"no-such-bunny.obj\""},
    {"missing .lod file", "{\"version\": 1, \"meshes\": {\"b\": {\"path\": \"sub/b.lod\"}}, \"instances\": "
                          "[{\"mesh\": \"b\", \"position_m\": [0, 0, 0]}]}",
     "meshes.b.path: mesh \"b\": cannot open \"sub/b.lod\""},
    {"unreadable mesh file", "{\"version\": 1, \"meshes\": {\"junk\": {\"path\": \"junk.obj\"}}, \"instances\": "
                             "[{\"mesh\": \"junk\", \"position_m\": [0, 0, 0]}]}",
     "meshes.junk.path: mesh \"junk\": "},
    {"path and builtin", "{\"version\": 1, \"meshes\": {\"o\": {\"path\": \"a.obj\", \"builtin\": \"box\"}}, " ONE "}",
     "meshes.o: give exactly one"},
    {"unknown builtin", "{\"version\": 1, \"meshes\": {\"o\": {\"builtin\": \"teapot\"}}, " ONE "}", "meshes.o.builtin: expected one of"},
    {"box without size", "{\"version\": 1, \"meshes\": {\"o\": {\"builtin\": \"box\"}}, " ONE "}", "meshes.o.size_m: missing"},
    {"negative scale", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": [0, 0, 0], \"scale\": -1}]}",
     "instances[0].scale: -1 is not in (0, 1e6]"},
    {"zero scale", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": [0, 0, 0], \"scale\": 0}]}",
     "instances[0].scale"},
    {"infinite scale", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": [0, 0, 0], \"scale\": 1e999}]}",
     "instances[0].scale: inf is not a finite number"},
    {"infinite position", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": [0, -1e400, 0]}]}",
     "instances[0].position_m[1]"},
    {"colour out of range", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": [0, 0, 0], \"color\": [1, 2, 0]}]}",
     "instances[0].color[1]"},
    {"negative importance", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": [0, 0, 0], \"importance\": -2}]}",
     "instances[0].importance"},
    {"bad motion", "{\"version\": 1, " MESHES ", \"instances\": [{\"mesh\": \"o\", \"position_m\": [0, 0, 0], \"motion\": {\"wobble\": 1}}]}",
     "instances[0].motion"},
    {"duplicate instance name",
     "{\"version\": 1, " MESHES ", \"instances\": [{\"name\": \"x\", \"mesh\": \"o\", \"position_m\": [0, 0, 0]}, {\"name\": \"x\", "
     "\"mesh\": \"o\", \"position_m\": [0, 0, 0]}]}",
     "instances[1].name: \"x\" is also the name of instances[0]"},
    {"group cycle", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"parent\": \"c\"}, {\"name\": \"b\", "
                    "\"parent\": \"a\"}, {\"name\": \"c\", \"parent\": \"b\", \"instances\": [\"i0\"]}]}",
     "cycle: a -> c -> b -> a"},
    {"group its own parent", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"parent\": \"a\"}]}",
     "groups[0].parent: group \"a\" cannot contain itself"},
    {"group its own child", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"children\": [\"a\"]}]}",
     "groups[0].children[0]: group \"a\" cannot contain itself"},
    {"group with two parents",
     "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"children\": [\"c\"]}, {\"name\": \"b\", \"children\": "
     "[\"c\"]}, {\"name\": \"c\"}]}",
     "groups[1].children[0]: group \"c\" already has the parent \"a\""},
    {"parent and children disagree",
     "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"children\": [\"c\"]}, {\"name\": \"b\"}, "
     "{\"name\": \"c\", \"parent\": \"b\"}]}",
     "groups[2].parent: group \"c\" already has the parent \"a\""},
    {"instance in two groups",
     "{\"version\": 1, " MESHES ", " TWO ", \"groups\": [{\"name\": \"a\", \"instances\": [\"i0\", \"i1\"]}, {\"name\": \"b\", "
     "\"instances\": [\"i0\"]}]}",
     "groups[1].instances[0]: instances[0] is already in group \"a\""},
    {"instance twice in one group",
     "{\"version\": 1, " MESHES ", " TWO ", \"groups\": [{\"name\": \"a\", \"instances\": [1, \"i1\"]}]}",
     "groups[0].instances[1]: instances[1] is already in group \"a\""},
    {"unknown instance name", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"instances\": [\"i9\"]}]}",
     "groups[0].instances[0]: no instance named \"i9\""},
    {"instance index out of range", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"instances\": [1]}]}",
     "groups[0].instances[0]: 1 is not an instance index"},
    {"fractional instance index", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"instances\": [0.5]}]}",
     "groups[0].instances[0]"},
    {"unknown parent", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"parent\": \"nobody\"}]}",
     "groups[0].parent: no group named \"nobody\""},
    {"duplicate group name", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\"}, {\"name\": \"a\"}]}",
     "groups[1].name: \"a\" is also the name"},
    {"group without name", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"instances\": [0]}]}", "groups[0].name: missing"},
    {"unknown group key", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"kids\": []}]}",
     "groups[0].kids: unknown key"},
    {"unknown impostor mesh", "{\"version\": 1, " MESHES ", " ONE ", \"groups\": [{\"name\": \"a\", \"impostor\": \"sphere\"}]}",
     "groups[0].impostor: no mesh named \"sphere\""},
    {"name too long", "{\"version\": 1, \"meshes\": {\"a_mesh_name_that_is_far_too_long_for_a_chain\": {\"builtin\": \"box\", "
                      "\"size_m\": [1, 1, 1]}}, " ONE "}",
     "meshes.a_mesh_name_that_is_far_too_long_for_a_chain: a mesh name must have"},
    {"no instances", "{\"version\": 1, " MESHES ", \"instances\": []}", "instances: expected 1 to"},
};

static void test_bad_inputs(void)
{
    write_temp("junk.obj", "this is not an OBJ file\nv x y z\nf 1 2\n");
    int failures_before = tu_failures;
    for (size_t k = 0; k < sizeof bad_cases / sizeof bad_cases[0]; ++k) {
        const struct bad_case *b = &bad_cases[k];
        const char *path = write_temp("scene.json", b->text);
        char file[256];
        snprintf(file, sizeof file, "%s", path);
        struct scn_scene s;
        struct hl_error err = {{0}};
        int rc = scn_scenefile_load(file, NULL, &s, &err);
        int names_file = strncmp(err.msg, file, strlen(file)) == 0;
        int names_where = strstr(err.msg, b->where) != NULL;
        if (rc == 0 || !names_file || !names_where)
            fprintf(stderr, "bad input \"%s\": rc %d, message \"%s\" (wanted the file and \"%s\")\n", b->what, rc,
                    err.msg, b->where);
        CHECK(rc != 0);
        CHECK(names_file);
        CHECK(names_where);
        CHECK(s.instance_count == 0 && s.chains == NULL && s.groups == NULL); /* nothing half-built */
        if (rc == 0)
            scn_scene_free(&s);
    }
    if (tu_failures == failures_before)
        printf("bad inputs: %zu cases refused with file and JSON path\n", sizeof bad_cases / sizeof bad_cases[0]);
    struct scn_scene s;
    struct hl_error err = {{0}};
    char missing[300];
    snprintf(missing, sizeof missing, "%s/absent.json", tmp_dir);
    CHECK(scn_scenefile_load(missing, NULL, &s, &err) != 0 && strstr(err.msg, "absent.json: cannot open"));
    CHECK(scn_scenefile_load(tmp_dir, NULL, &s, &err) != 0 && strstr(err.msg, "not a regular file"));
}

/* A caller's resolver sees every mesh file once, by its path relative to the scene file; here it
 * answers with a small tetrahedron so the structure of real-meshes.json is checked without the
 * decimation (which the default-resolver test below runs on a small mesh). */
struct counting_resolver {
    int calls, missing;
};
static int tetra_resolve(void *user, const char *path, struct scn_lodset *out, struct hl_error *err)
{
    struct counting_resolver *r = user;
    r->calls++;
    if (access(path, R_OK) != 0)
        r->missing++;
    memset(out, 0, sizeof *out);
    struct scn_mesh *m = &out->levels[0];
    static const double p[4][3] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    for (int v = 0; v < 4; ++v)
        scn_mesh_add_vertex(m, hl_v3(0.1 * p[v][0] + 2, 0.1 * p[v][1], 0.1 * p[v][2]), hl_v3(p[v][0], p[v][1], p[v][2]));
    scn_mesh_add_triangle(m, 0, 1, 2);
    scn_mesh_add_triangle(m, 0, 3, 1);
    scn_mesh_add_triangle(m, 0, 2, 3);
    scn_mesh_add_triangle(m, 1, 3, 2);
    if (m->failed)
        return hl_fail(err, "out of memory");
    out->level_count = 1;
    out->center_m[0] = 2.0; /* off the origin, as an imported model would be: "recenter" moves it */
    out->radius_m = 0.1 * sqrt(3.0);
    for (int l = 0; l < 1; ++l)
        out->freq[l] = (struct scn_level_freq){NAN, NAN, NAN};
    snprintf(out->simplifier, sizeof out->simplifier, "procedural");
    return 0;
}

static void test_real_meshes_structure(void)
{
    const char *path = tu_source_path("tests/scenes/real-meshes.json");
    char file[4096];
    snprintf(file, sizeof file, "%s", path);
    struct counting_resolver count = {0, 0};
    struct scn_asset_resolver resolver = {tetra_resolve, &count};
    struct scn_scene s;
    struct hl_error err = {{0}};
    int rc = scn_scenefile_load(file, &resolver, &s, &err);
    if (rc != 0)
        fprintf(stderr, "%s\n", err.msg);
    CHECK(rc == 0);
    if (rc != 0)
        return;
    CHECK(count.calls == 5);
    if (tu_shared_path("data/meshes/stanford-bunny.obj"))
        CHECK(count.missing == 0); /* the paths reach ../shared from the scene file's folder */
    CHECK(s.chain_count == 8);
    CHECK(s.instance_count == 45);
    CHECK(s.group_count == 21);
    CHECK(scn_scene_check_groups(&s, &err) == 0);
    CHECK(bounds_contain(&s));
    uint32_t held = 0;
    for (uint32_t g = 0; g < s.group_count; ++g)
        held += s.groups[g].instance_count;
    CHECK(held == 45);
    /* recentred: the tetrahedron's centre is the instance's position */
    CHECK_NEAR(dist3(&s.center_m[0], s.instances[0].position_m), 0.0, 1e-6);
    CHECK_NEAR(s.radius_m[0], 4.0 * 0.1 * sqrt(3.0), 1e-6); /* the bunnies are at scale 4 */
    scn_scene_free(&s);
}

/* The default resolver on a small real mesh: imported and decimated to four levels; an off-origin
 * model without "recenter" keeps its sphere where the model is. */
static void test_default_resolver(void)
{
    const char *shared = tu_shared_path("data/meshes/suzanne.obj");
    char mesh[4096];
    if (!shared || !realpath(shared, mesh)) /* absolute: the scene file is in a temporary folder */
        return;
    char text[12288];
    snprintf(text, sizeof text,
             "{\"version\": 1, \"meshes\": {\"monkey\": {\"path\": \"%s\"}, \"centred\": {\"path\": \"%s\", \"recenter\": true}},"
             " \"instances\": [{\"mesh\": \"monkey\", \"position_m\": [0, 0, 0]}, {\"mesh\": \"centred\", \"position_m\": [1, 2, 3],"
             " \"scale\": 2}]}",
             mesh, mesh);
    char file[256];
    snprintf(file, sizeof file, "%s", write_temp("suzanne.json", text));
    struct scn_scene s;
    struct hl_error err = {{0}};
    int rc = scn_scenefile_load(file, NULL, &s, &err);
    if (rc != 0)
        fprintf(stderr, "%s\n", err.msg);
    CHECK(rc == 0);
    if (rc != 0)
        return;
    CHECK(s.chain_count == 2);
    CHECK(s.chains[0].lod_count == 4);
    for (int l = 1; l < s.chains[0].lod_count; ++l)
        CHECK(s.chains[0].lods[l].triangle_count < s.chains[0].lods[l - 1].triangle_count);
    /* suzanne.obj sits around x = −2.5, z = 4.1: the first sphere is there, the second at its position */
    CHECK(s.center_m[0] < -2.0 && s.center_m[2] > 3.5);
    CHECK_NEAR(dist3(&s.center_m[3], s.instances[1].position_m), 0.0, 1e-5);
    CHECK_NEAR(s.radius_m[1], 2.0 * s.radius_m[0], 1e-4 * s.radius_m[0]);
    scn_scene_free(&s);
}

int main(void)
{
    if (!mkdtemp(tmp_dir)) {
        fprintf(stderr, "cannot create a temporary folder\n");
        return 1;
    }
    test_nested_groups();
    test_bad_inputs();
    test_real_meshes_structure();
    test_default_resolver();
    static const char *const names[] = {"scene.json", "junk.obj", "suzanne.json"};
    for (size_t k = 0; k < 3; ++k) {
        char path[300];
        snprintf(path, sizeof path, "%s/%s", tmp_dir, names[k]);
        unlink(path);
    }
    rmdir(tmp_dir);
    return tu_finish("test_scenefile");
}
