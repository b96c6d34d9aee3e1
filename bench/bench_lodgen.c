/* hmdlod bench lodgen: the LOD chain of the Stanford bunny with both simplifiers — how long each
 * takes (import apart), what each level keeps and how far it strays, and where OpenMesh's time goes.
 * Targets (docs/PLATFORM.md §7b): OpenMesh ≤ 1.5 s, meshopt ≤ 100 ms for the 4-level chain. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench/bench.h"
#include "scene/scene.h"

enum { BENCH_LEVELS = 4 }; /* decimated levels below the full mesh: 50, 25, 10, 2 % */
static const double bench_ratios[BENCH_LEVELS] = {0.5, 0.25, 0.1, 0.02};

static double median(double *v, int n)
{
    hl_sort_doubles(v, (size_t)n);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct lodgen_run {
    double chain_s[16];
    struct scn_decimate_timing split[16];
    uint32_t tris[BENCH_LEVELS], verts[BENCH_LEVELS];
    double error_m[BENCH_LEVELS], mean_m[BENCH_LEVELS];
};

static int bench_simplifier(const struct scn_mesh *mesh, enum scn_simplifier s, int repeats, uint64_t samples,
                            struct lodgen_run *run)
{
    uint32_t t0 = mesh->index_count / 3, targets[BENCH_LEVELS];
    for (int k = 0; k < BENCH_LEVELS; ++k)
        targets[k] = (uint32_t)(bench_ratios[k] * t0 + 0.5);
    struct hl_error err = {{0}};
    for (int r = 0; r < repeats; ++r) {
        struct scn_mesh out[BENCH_LEVELS];
        double a = hl_clock_now_s();
        if (scn_mesh_decimate_chain(mesh, targets, BENCH_LEVELS, s, 0, out, &run->split[r], &err) != 0) {
            fprintf(stderr, "hmdlod bench lodgen: %s: %s\n", scn_simplifier_name(s), err.msg);
            return -1;
        }
        run->chain_s[r] = hl_clock_now_s() - a;
        for (int k = 0; k < BENCH_LEVELS; ++k) {
            if (r == 0) { /* the levels are the same every repeat (deterministic): measure once */
                struct scn_hausdorff h;
                run->tris[k] = out[k].index_count / 3, run->verts[k] = out[k].vertex_count;
                if (scn_mesh_hausdorff(mesh, &out[k], samples, 1, &h, &err) != 0) {
                    fprintf(stderr, "hmdlod bench lodgen: %s\n", err.msg);
                    for (int j = k; j < BENCH_LEVELS; ++j)
                        scn_mesh_free(&out[j]);
                    return -1;
                }
                run->error_m[k] = h.max_m, run->mean_m[k] = h.mean_m;
            }
            scn_mesh_free(&out[k]);
        }
    }
    return 0;
}

int bch_lodgen(const struct bch_lodgen_options *o, int full_argc, char **full_argv)
{
    long repeats = o->repeats;
    uint64_t samples = o->hausdorff_samples;
    const char *results = o->results;
    char shared[4096], path[4200];
    if (bch_find_shared(shared, sizeof shared) != 0) {
        fprintf(stderr, "hmdlod bench lodgen: skip: the shared data folder is absent (%s); set HMDLOD_SHARED\n",
                shared);
        return 0;
    }
    snprintf(path, sizeof path, "%s/data/meshes/stanford-bunny.obj", shared);
    struct scn_mesh mesh;
    struct scn_import_report rep;
    struct hl_error err = {{0}};
    double import_s[16];
    for (int r = 0; r < repeats; ++r) {
        double a = hl_clock_now_s();
        if (scn_mesh_import(path, &mesh, &rep, &err) != 0) {
            fprintf(stderr, "hmdlod bench lodgen: %s\n", err.msg);
            return 1;
        }
        import_s[r] = hl_clock_now_s() - a;
        if (r + 1 < repeats)
            scn_mesh_free(&mesh);
    }
    /* The radius the errors are relative to: the chain's bounding sphere (scn_lodgen_build's). */
    struct scn_lodgen_params one = {.ratio_count = 1, .ratios = {1}};
    struct scn_lodset set;
    if (scn_lodgen_build(&mesh, &one, &set, &err) != 0) {
        fprintf(stderr, "hmdlod bench lodgen: %s\n", err.msg);
        scn_mesh_free(&mesh);
        return 1;
    }
    double radius_m = set.radius_m;
    scn_lodset_free(&set);

    static struct lodgen_run runs[2];
    memset(runs, 0, sizeof runs);
    int rc = 0;
    for (int s = 0; s < 2 && rc == 0; ++s)
        if (bench_simplifier(&mesh, (enum scn_simplifier)s, (int)repeats, samples, &runs[s]) != 0)
            rc = 1;
    uint32_t t0 = mesh.index_count / 3, v0 = mesh.vertex_count;
    scn_mesh_free(&mesh);
    if (rc != 0)
        return rc;

    if (results && bch_copy_begin() != 0) {
        fprintf(stderr, "hmdlod bench lodgen: out of memory\n");
        return 1;
    }
    bch_emit(BCH_LODGEN_HEADING "\n\n");
    bch_print_context(full_argc, full_argv, NULL);
    bch_emit("\nstanford-bunny.obj: %u triangles, %u vertices; import (OpenMesh OBJ reader + welding + normals) "
               "%.3f s median of %ld. Chain: 50 → 25 → 10 → 2 %% of the triangles, each level from the one before; "
               "time = the whole chain, median of %ld (min–max). Hausdorff: two-sided, %llu samples per mesh, "
               "relative to the bounding-sphere radius %.4g m.\n\n",
               t0, v0, median(import_s, (int)repeats), repeats, repeats, (unsigned long long)samples, radius_m);
    bch_emit("| simplifier | chain s | target |");
    for (int k = 0; k < BENCH_LEVELS; ++k)
        bch_emit(" %g %% |", 100 * bench_ratios[k]);
    bch_emit("\n|---|---|---|");
    for (int k = 0; k < BENCH_LEVELS; ++k)
        bch_emit("---|");
    bch_emit("\n");
    static const char *target_text[2] = {"≤ 1.5 s", "≤ 0.100 s"};
    for (int s = 0; s < 2; ++s) {
        double sorted[16];
        memcpy(sorted, runs[s].chain_s, sizeof sorted);
        double med = median(sorted, (int)repeats);
        bch_emit("| %s | **%.3f** (%.3f–%.3f) | %s |", scn_simplifier_name((enum scn_simplifier)s), med, sorted[0],
                   sorted[repeats - 1], target_text[s]);
        for (int k = 0; k < BENCH_LEVELS; ++k)
            bch_emit(" %u tris, %u verts: %.3g m (%.2f %%), mean %.2g m |", runs[s].tris[k], runs[s].verts[k],
                       runs[s].error_m[k], 100 * runs[s].error_m[k] / radius_m, runs[s].mean_m[k]);
        bch_emit("\n");
    }
    /* Where OpenMesh's time goes: medians of each phase over the repeats. */
    double ph[6][16];
    for (int r = 0; r < repeats; ++r) {
        const struct scn_decimate_timing *t = &runs[0].split[r];
        ph[0][r] = t->build_s, ph[1][r] = t->feature_s, ph[2][r] = t->init_s;
        ph[3][r] = t->decimate_s, ph[4][r] = t->gc_s, ph[5][r] = t->extract_s;
    }
    static const char *phase[6] = {"build half-edge mesh", "mark feature lines (> 60°)", "init modules (quadrics)",
                                   "decimate_to_faces (4 levels)", "garbage_collection", "copy out + weld + normals"};
    double total = 0, med6[6];
    for (int i = 0; i < 6; ++i)
        total += med6[i] = median(ph[i], (int)repeats);
    bch_emit("\nOpenMesh chain, where the time goes (monotonic clock, medians):\n\n| phase | s | share |\n|---|---|---|\n");
    for (int i = 0; i < 6; ++i)
        bch_emit("| %s | %.3f | %.0f %% |\n", phase[i], med6[i], total > 0 ? 100 * med6[i] / total : 0);
    bch_emit("\nOpenMesh: DecimaterT + ModQuadricT (priority only) + ModNormalFlippingT, feature edges > 60° "
               "(corners where three lines meet locked), open boundaries locked while the targets allow, shim built -O2 -DNDEBUG against Debian's assertion-enabled "
               "libOpenMeshCore (PLATFORM.md §7b). meshopt: meshopt_simplify 0.18 after meshopt_generateVertexRemap "
               "welding, target_error 1 (no limit), no border lock. Both weld and recompute area-weighted normals "
               "per level.\n");
    return bch_copy_finish(results, BCH_LODGEN_HEADING, "hmdlod bench lodgen", 0);
}
