/* hmdlod lodgen --group: a group's impostor (Mason & Blake 1997 §2–3) as a .lod file, with the
 * paper's requirement checked and printed. Called by `hmdlod lodgen` when its arguments hold --group. */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "app/commands.h"
#include "scene/scene.h"

static const char group_usage[] =
    "usage: hmdlod lodgen --group SCENE GROUP [--simplifier openmesh|meshopt] [--triangles N]\n"
    "                     [--objects N] [--seed S] [--samples N] --out FILE.lod\n"
    "  Builds GROUP's impostor: the finest levels of every instance below the group merged in the\n"
    "  group's frame (origin at its centre at rest), welded and decimated to about N triangles, then\n"
    "  checked against Mason & Blake's requirement (it must cost less than the children at their\n"
    "  coarsest — triangles and vertices — and be worth less: a Hausdorff error > 0 and a lower\n"
    "  Funkhouser accuracy 1 - 0.5/vertices^2). A refused impostor writes nothing.\n"
    "  SCENE          a built-in scene (domes: groups dome0, dome1, ...) or a scene file (.json)\n"
    "  --simplifier   meshopt (default here: OpenMesh's normal-flip guard stops each closed part at\n"
    "                 a few dozen triangles, too many for many-part groups such as domes) or openmesh\n"
    "  --triangles N  target triangle count (default: half the children's coarsest total)\n"
    "  --objects N    built-in scenes: object count (domes: number of domes); --seed S: placement seed\n"
    "  --samples N    Hausdorff surface samples per mesh (default 2^20; fewer: faster, wider bound)\n"
    "  --out FILE     the .lod to write (atomically)\n";

static int is_scene_file(const char *scene)
{
    size_t len = strlen(scene);
    struct stat st;
    return (len > 5 && strcmp(scene + len - 5, ".json") == 0) || (stat(scene, &st) == 0 && S_ISREG(st.st_mode));
}

static int need_value(int argc, char **argv, int i)
{
    if (i + 1 < argc)
        return 0;
    fprintf(stderr, "hmdlod: %s needs a value\n", argv[i]);
    return -1;
}

int cmd_lodgen_group(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(group_usage, stdout);
        return 0;
    }
    const char *scene_name = NULL, *group_name = NULL, *out = NULL;
    enum scn_simplifier simplifier = SCN_SIMPLIFIER_MESHOPT;
    long triangles = 0, objects = 0, seed = 1, samples = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--group")) {
            continue;
        } else if (!strcmp(a, "--out")) {
            if (need_value(argc, argv, i))
                return 1;
            out = argv[++i];
        } else if (!strcmp(a, "--simplifier")) {
            if (need_value(argc, argv, i))
                return 1;
            const char *v = argv[++i];
            if (!strcmp(v, "openmesh"))
                simplifier = SCN_SIMPLIFIER_OPENMESH;
            else if (!strcmp(v, "meshopt"))
                simplifier = SCN_SIMPLIFIER_MESHOPT;
            else {
                fprintf(stderr, "hmdlod: --simplifier: unknown simplifier '%s' (known: openmesh, meshopt)\n", v);
                return 1;
            }
        } else if (!strcmp(a, "--triangles")) {
            if (app_parse_long(a, i + 1 < argc ? argv[++i] : NULL, 1, 100000000, &triangles) != 0)
                return 1;
        } else if (!strcmp(a, "--objects")) {
            if (app_parse_long(a, i + 1 < argc ? argv[++i] : NULL, 1, 100000, &objects) != 0)
                return 1;
        } else if (!strcmp(a, "--samples")) {
            if (app_parse_long(a, i + 1 < argc ? argv[++i] : NULL, 1000, 1L << 30, &samples) != 0)
                return 1;
        } else if (!strcmp(a, "--seed")) {
            if (app_parse_long(a, i + 1 < argc ? argv[++i] : NULL, 1, 2147483647L, &seed) != 0)
                return 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "hmdlod: lodgen --group: unknown option '%s'\n%s", a, group_usage);
            return 1;
        } else if (!scene_name) {
            scene_name = a;
        } else if (!group_name) {
            group_name = a;
        } else {
            fprintf(stderr, "hmdlod: lodgen --group: '%s' is extra (SCENE and GROUP already given)\n", a);
            return 1;
        }
    }
    if (!scene_name || !group_name || !out) {
        fprintf(stderr, "hmdlod: lodgen --group: %s is required\n%s",
                !scene_name ? "SCENE" : !group_name ? "GROUP" : "--out FILE.lod", group_usage);
        return 1;
    }

    struct hl_error err;
    struct scn_scene scene;
    int rc;
    if (is_scene_file(scene_name)) {
        rc = scn_scenefile_load(scene_name, NULL, &scene, &err);
    } else {
        struct scn_scene_params params = {.object_count = (int)objects, .seed = (uint64_t)seed};
        rc = scn_scene_build(scene_name, &params, &scene, &err);
    }
    if (rc != 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        return 1;
    }
    uint32_t g = scn_scene_find_group(&scene, group_name);
    if (g == SCN_NONE) {
        fprintf(stderr, "hmdlod: scene %s: no group named '%s' (%u groups%s%s%s)\n", scene_name, group_name,
                scene.group_count, scene.group_count ? ", e.g. '" : "", scene.group_count ? scene.groups[0].name : "",
                scene.group_count ? "'" : "");
        scn_scene_free(&scene);
        return 1;
    }
    struct scn_impostor_report r;
    struct scn_lodset set;
    uint32_t target = (uint32_t)triangles;
    if (target == 0) { /* default: half the cheapest implicit representation */
        struct scn_impostor_report probe;
        struct scn_lodset none;
        struct hl_error ignored;
        /* An unreachable target is refused by the cost check (before any Hausdorff sampling), and
         * the report's children counts come back either way. */
        if (scn_impostor_build_report(&scene, g, simplifier, UINT32_MAX, 0, &none, &probe, &ignored) == 0)
            scn_lodset_free(&none);
        target = (uint32_t)(probe.children_triangles_coarsest / 2 > 0 ? probe.children_triangles_coarsest / 2 : 1);
    }
    rc = scn_impostor_build_report(&scene, g, simplifier, target, (uint64_t)samples, &set, &r, &err);
    printf("group %s: %u instances; children finest %llu triangles / %llu vertices, coarsest %llu / %llu\n",
           scene.groups[g].name, r.instances, (unsigned long long)r.children_triangles_finest,
           (unsigned long long)r.children_vertices_finest, (unsigned long long)r.children_triangles_coarsest,
           (unsigned long long)r.children_vertices_coarsest);
    if (r.impostor_triangles > 0) {
        printf("impostor (%s, target %u): %u triangles / %u vertices (merged children: %u / %u welded)\n",
               simplifier == SCN_SIMPLIFIER_MESHOPT ? "meshopt" : "openmesh", target, r.impostor_triangles,
               r.impostor_vertices, r.merged_triangles, r.merged_vertices);
        if (r.error.samples > 0) {
            printf("Hausdorff error vs the children: max %.6g m, mean %.6g m (sampling bound %.3g m, %llu samples)\n",
                   r.error.max_m, r.error.mean_m, r.error.bound_m, (unsigned long long)r.error.samples);
            printf("Funkhouser accuracy 1 - 0.5/V^2: impostor %.12f, children coarsest %.12f, finest %.12f\n",
                   r.accuracy_impostor, r.accuracy_children_coarsest, r.accuracy_children_finest);
        }
        printf("Mason & Blake requirement: costs less %s, worth less %s\n", r.cheaper ? "yes" : "NO",
               !r.cheaper ? "(not measured)" : r.worse ? "yes" : "NO");
    }
    if (rc != 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        scn_scene_free(&scene);
        return 1;
    }
    rc = scn_lodfile_write(out, &set, &err);
    if (rc != 0)
        fprintf(stderr, "hmdlod: %s\n", err.msg);
    else
        printf("wrote %s\n", out);
    scn_lodset_free(&set);
    scn_scene_free(&scene);
    return rc != 0;
}
