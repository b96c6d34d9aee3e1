/* hmdlod lodgen: a user's mesh file → an LOD chain in a .lod file (scene/lodgen.h, docs/lod-format.md).
 * Import (OpenMesh IO or assimp), decimation (OpenMesh or meshoptimizer), each level's Hausdorff
 * error, written atomically: a failed run leaves no .lod behind. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/commands.h"
#include "scene/scene.h"

static void print_lodgen_usage(FILE *f)
{
    fprintf(f,
            "usage: hmdlod lodgen MESH [--levels N | --ratios LIST | --max-error-px E@DIST]\n"
            "                     [--simplifier openmesh|meshopt] [--feature-angle DEG] [--samples N]\n"
            "                     [--fov DEG] [--width PX] --out FILE.lod\n\n"
            "Imports MESH (.obj .ply .off .stl through OpenMesh, .gltf .glb through assimp), welds it,\n"
            "decimates it into a chain of levels, measures each level's two-sided Hausdorff distance to\n"
            "the full mesh and writes the chain with its bounds, errors and geometric frequencies.\n"
            "  --levels N          N levels at triangle ratios 1, 1/2, 1/4, … (default 4; 1…8)\n"
            "  --ratios LIST       explicit triangle ratios, e.g. 1,0.5,0.25,0.1 (first 1, decreasing)\n"
            "  --max-error-px E@DIST  levels chosen so that level k's error spans ≤ E pixels seen from\n"
            "                      DIST·2^(k−1) metres on the reference display (see --fov, --width)\n"
            "  --fov DEG, --width PX  reference display for --max-error-px: PX pixels across DEG degrees\n"
            "                      (default 1080 px over 100°, about one HTC Vive eye)\n"
            "  --simplifier S      openmesh (quadric + normal-flip guard + feature lines; default) or\n"
            "                      meshopt (meshoptimizer, 20–30× faster)\n"
            "  --feature-angle DEG OpenMesh: edges sharper than DEG are kept as lines (default 60;\n"
            "                      'off' for none)\n"
            "  --samples N         Hausdorff surface samples per mesh (default: scn_mesh_hausdorff's)\n"
            "  --out FILE.lod      the chain (written atomically)\n"
            "Non-manifold edges are a warning (the mesh is imported as the file has it); NaN coordinates,\n"
            "no faces or only degenerate faces are errors naming the file and the vertex or face.\n");
}

static int parse_ratios(const char *text, struct scn_lodgen_params *p)
{
    p->ratio_count = 0;
    const char *s = text;
    while (*s) {
        if (p->ratio_count == SCN_LODSET_MAX_LEVELS) {
            fprintf(stderr, "hmdlod lodgen: --ratios %s: more than %d levels\n", text, SCN_LODSET_MAX_LEVELS);
            return -1;
        }
        char *end = NULL;
        double v = strtod(s, &end);
        if (end == s || (*end != ',' && *end != '\0') || !isfinite(v)) {
            fprintf(stderr, "hmdlod lodgen: --ratios %s: '%.*s' is not a number\n", text, (int)strcspn(s, ","), s);
            return -1;
        }
        int k = p->ratio_count;
        if (k == 0 && v != 1.0) {
            fprintf(stderr, "hmdlod lodgen: --ratios %s: the first ratio must be 1 (the mesh itself)\n", text);
            return -1;
        }
        if (k > 0 && !(v > 0 && v < p->ratios[k - 1])) {
            fprintf(stderr, "hmdlod lodgen: --ratios %s: ratio %d (%g) must be > 0 and below %g\n", text, k + 1, v,
                    p->ratios[k - 1]);
            return -1;
        }
        p->ratios[p->ratio_count++] = v;
        s = *end == ',' ? end + 1 : end;
        if (*end == ',' && !*s) {
            fprintf(stderr, "hmdlod lodgen: --ratios %s: trailing comma\n", text);
            return -1;
        }
    }
    if (p->ratio_count == 0) {
        fprintf(stderr, "hmdlod lodgen: --ratios needs a list such as 1,0.5,0.25\n");
        return -1;
    }
    return 0;
}

static int parse_error_at(const char *text, struct scn_lodgen_params *p)
{
    const char *at = text ? strchr(text, '@') : NULL;
    if (!at) {
        fprintf(stderr, "hmdlod lodgen: --max-error-px needs E@DIST, e.g. 1@2 (1 px at 2 m)\n");
        return -1;
    }
    char e[64];
    snprintf(e, sizeof e, "%.*s", (int)(at - text), text);
    if (app_parse_double("--max-error-px (pixels)", e, &p->max_error_px) != 0 ||
        app_parse_double("--max-error-px (distance)", at + 1, &p->at_distance_m) != 0)
        return -1;
    if (!(p->max_error_px > 0 && isfinite(p->max_error_px)) || !(p->at_distance_m > 0 && isfinite(p->at_distance_m))) {
        fprintf(stderr, "hmdlod lodgen: --max-error-px %s: error and distance must both be > 0\n", text);
        return -1;
    }
    return 0;
}

static void lodgen_progress(void *user, double fraction)
{
    hl_progress_update(user, (uint64_t)(fraction * 1000.0));
}

static void print_report(const char *path, const struct scn_import_report *r, const struct scn_mesh *m, double s)
{
    printf("%s: %u faces read, %u polygons triangulated, %u vertices welded, %u degenerate faces dropped → "
           "%u triangles, %u vertices (%.3f s)\n",
           path, r->faces_read, r->polygons_triangulated, r->vertices_welded, r->degenerate_dropped,
           m->index_count / 3, m->vertex_count, s);
    if (r->nonmanifold_edges)
        fprintf(stderr,
                "hmdlod lodgen: warning: %s: %u non-manifold edges (shared by more than two faces); imported as "
                "they are, the simplifier works around them and may stop above its targets\n",
                path, r->nonmanifold_edges);
}

int cmd_lodgen(int argc, char **argv)
{
    /* A group's impostor is built from a scene, not from a mesh file: its own command file. */
    for (int i = 1; i < argc; ++i)
        if (!strcmp(argv[i], "--group"))
            return cmd_lodgen_group(argc, argv);
    if (app_wants_help(argc, argv)) {
        print_lodgen_usage(stdout);
        return 0;
    }
    struct scn_lodgen_params p;
    memset(&p, 0, sizeof p);
    const char *mesh_path = NULL, *out_path = NULL;
    int modes = 0;
    long levels = 4;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--levels")) {
            if (app_parse_long("--levels", v, 1, SCN_LODSET_MAX_LEVELS, &levels) != 0)
                return 1;
            ++modes, ++i;
        } else if (!strcmp(a, "--ratios")) {
            if (!v) {
                fprintf(stderr, "hmdlod lodgen: --ratios needs a value\n");
                return 1;
            }
            if (parse_ratios(v, &p) != 0)
                return 1;
            ++modes, ++i;
        } else if (!strcmp(a, "--max-error-px")) {
            if (parse_error_at(v, &p) != 0)
                return 1;
            ++modes, ++i;
        } else if (!strcmp(a, "--simplifier")) {
            if (v && !strcmp(v, "openmesh"))
                p.simplifier = SCN_SIMPLIFIER_OPENMESH;
            else if (v && !strcmp(v, "meshopt"))
                p.simplifier = SCN_SIMPLIFIER_MESHOPT;
            else {
                fprintf(stderr, "hmdlod lodgen: --simplifier '%s': use openmesh or meshopt\n", v ? v : "");
                return 1;
            }
            ++i;
        } else if (!strcmp(a, "--feature-angle")) {
            if (v && !strcmp(v, "off")) {
                p.feature_angle_deg = -1;
            } else {
                if (app_parse_double("--feature-angle", v, &p.feature_angle_deg) != 0)
                    return 1;
                if (!(p.feature_angle_deg > 0 && p.feature_angle_deg <= 180)) {
                    fprintf(stderr, "hmdlod lodgen: --feature-angle %g: need (0, 180] degrees, or off\n",
                            p.feature_angle_deg);
                    return 1;
                }
            }
            ++i;
        } else if (!strcmp(a, "--samples")) {
            long n = 0;
            if (app_parse_long("--samples", v, 1000, 1L << 30, &n) != 0)
                return 1;
            p.hausdorff_samples = (uint32_t)n;
            ++i;
        } else if (!strcmp(a, "--fov") || !strcmp(a, "--width")) {
            double *dst = !strcmp(a, "--fov") ? &p.fov_deg : &p.width_px;
            if (app_parse_double(a, v, dst) != 0)
                return 1;
            if (!(*dst > 0) || (dst == &p.fov_deg && *dst >= 180) || *dst > 1e6) {
                fprintf(stderr, "hmdlod lodgen: %s %g: out of range\n", a, *dst);
                return 1;
            }
            ++i;
        } else if (!strcmp(a, "--out")) {
            if (!v) {
                fprintf(stderr, "hmdlod lodgen: --out needs a value\n");
                return 1;
            }
            out_path = v, ++i;
        } else if (a[0] == '-' && a[1]) {
            fprintf(stderr, "hmdlod lodgen: unknown option '%s' (try --help)\n", a);
            return 1;
        } else if (!mesh_path) {
            mesh_path = a;
        } else {
            fprintf(stderr, "hmdlod lodgen: one mesh at a time ('%s' and '%s')\n", mesh_path, a);
            return 1;
        }
    }
    if (!mesh_path) {
        fprintf(stderr, "hmdlod lodgen: no mesh file given (try --help)\n");
        return 1;
    }
    if (!out_path) {
        fprintf(stderr, "hmdlod lodgen: --out FILE.lod is required\n");
        return 1;
    }
    if (modes > 1) {
        fprintf(stderr, "hmdlod lodgen: choose one of --levels, --ratios, --max-error-px\n");
        return 1;
    }
    if (p.ratio_count == 0 && !(p.max_error_px > 0)) {
        p.ratio_count = (int)levels;
        for (int k = 0; k < p.ratio_count; ++k)
            p.ratios[k] = ldexp(1.0, -k);
    }

    struct hl_error err = {{0}};
    struct scn_mesh mesh;
    struct scn_import_report rep;
    double t0 = hl_clock_now_s();
    if (scn_mesh_import(mesh_path, &mesh, &rep, &err) != 0) {
        fprintf(stderr, "hmdlod lodgen: %s\n", err.msg);
        return 1;
    }
    print_report(mesh_path, &rep, &mesh, hl_clock_now_s() - t0);

    struct hl_progress bar;
    hl_progress_begin(&bar, "lodgen", 1000);
    p.progress = lodgen_progress, p.progress_user = &bar;
    struct scn_lodset set;
    struct scn_lodgen_stats st;
    double t1 = hl_clock_now_s();
    int rc = scn_lodgen_build_timed(&mesh, &p, &set, &st, &err);
    double build_s = hl_clock_now_s() - t1;
    hl_progress_end(&bar);
    scn_mesh_free(&mesh);
    if (rc != 0) {
        fprintf(stderr, "hmdlod lodgen: %s: %s\n", mesh_path, err.msg);
        return 1;
    }
    printf("simplifier %s, bounding sphere centre (%.6g, %.6g, %.6g) m, radius %.6g m\n", set.simplifier,
           set.center_m[0], set.center_m[1], set.center_m[2], set.radius_m);
    if (p.max_error_px > 0)
        printf("levels for ≤ %g px at %g m·2^(k−1), reference %g px over %g°: %d of %d candidates\n",
               p.max_error_px, p.at_distance_m, p.width_px > 0 ? p.width_px : 1080.0, p.fov_deg > 0 ? p.fov_deg : 100.0,
               set.level_count - 1, st.candidates);
    printf("\n| level | triangles | target | vertices | Hausdorff m | %% of radius | R/ε cpd | decimate s | error s |\n");
    printf("|---|---|---|---|---|---|---|---|---|\n");
    for (int l = 0; l < set.level_count; ++l) {
        const struct scn_mesh *m = &set.levels[l];
        printf("| %d | %u | %u | %u | %.4g | %.3f | %.4g | %.3f | %.3f |\n", l, m->index_count / 3,
               st.target_triangles[l], m->vertex_count, set.error_m[l], 100.0 * set.error_rel[l],
               set.freq[l].geometric_cpdiam, st.decimate_s[l], st.error_s[l]);
    }
    if (st.stopped_early)
        printf("\nnote: the simplifier could not reach every target; the chain ends at the last level it made "
               "coarser.\n");
    int level_count = set.level_count;
    rc = scn_lodfile_write(out_path, &set, &err);
    scn_lodset_free(&set);
    if (rc != 0) {
        fprintf(stderr, "hmdlod lodgen: %s\n", err.msg);
        return 1;
    }
    printf("\nwrote %s (%d levels, %.2f s)\n", out_path, level_count, build_s);
    return 0;
}
