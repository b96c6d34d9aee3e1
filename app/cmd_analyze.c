/* hmdlod analyze: Reddy's offline spatial-frequency analysis of a .lod file, written back into it. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "app/commands.h"
#include "render/render.h"

static const char analyze_usage[] =
    "usage: hmdlod analyze FILE.lod [--views 6|18] [--size PX] [--threshold DE] [--min-region PX]\n"
    "                      [--dump DIR]\n"
    "  Renders every level headless from the view sphere, compares successive levels in CIELUV\n"
    "  and stores each level's image-based frequencies (narrow and long readings, cycles per object\n"
    "  diameter) and its lost-contrast spectrum against level 0 in the file, which is rewritten\n"
    "  atomically (as format version 2). Prints them beside the geometric estimate.\n"
    "  docs/analysis.md describes the method.\n"
    "  --views N        6 (+-X, +-Y, +-Z) or 18 (plus the cube-edge midpoints; default 18)\n"
    "  --size PX        pixels across the bounding diameter, 16..2048 (default 256)\n"
    "  --threshold DE   CIE 1976 Delta E*uv above which a pixel differs, (0, 100] (default 2.3)\n"
    "  --min-region PX  differing regions smaller than this are rasterisation noise (default 3)\n"
    "  --dump DIR       also write every render and difference mask as PNG into DIR (existing)\n";

static void analyze_progress(void *user, double fraction)
{
    struct hl_progress *p = user;
    hl_progress_update(p, (uint64_t)llround(fraction * (double)p->total));
}

static void print_freq(double f)
{
    if (isinf(f))
        printf(" %13s", "inf");
    else if (isnan(f))
        printf(" %13s", "-");
    else if (f > 1e300)
        printf(" %13s", "max"); /* DBL_MAX: nothing visible lost, always taken */
    else
        printf(" %13.4g", f);
}

static void print_table(const char *path, const struct scn_lodset *set, const struct rnd_analyze_params *p,
                        const struct rnd_analyze_report *rep)
{
    printf("%s: %d levels, bounding radius %.4g m; %d views, %d px across the diameter, dE*uv > %g, regions >= %d px\n",
           path, set->level_count, set->radius_m, p->views, p->size_px, p->threshold_de, p->min_component_px);
    printf("%5s %10s %11s %8s %13s %13s %13s  %s\n", "level", "triangles", "error m", "% R", "narrow c/diam",
           "long c/diam", "geom c/diam", "differing px, regions, thickest / longest lost feature");
    for (int l = 0; l < set->level_count; ++l) {
        const struct rnd_analyze_level *L = &rep->levels[l];
        printf("%5d %10u %11.5g %8.3g", l, set->levels[l].index_count / 3, set->error_m[l], 100.0 * set->error_rel[l]);
        print_freq(set->freq[l].narrow_cpdiam);
        print_freq(set->freq[l].long_cpdiam);
        print_freq(set->freq[l].geometric_cpdiam);
        if (l == 0)
            printf("  (finest)\n");
        else if (L->invisible)
            printf("  %llu px, no region: loses nothing visible at this size\n", (unsigned long long)L->differing_px);
        else
            printf("  %llu px, %u regions (+%u noise), %.1f / %.1f px (views %d / %d)%s\n",
                   (unsigned long long)L->differing_px, L->components, L->noise_components, L->narrow_extent_px,
                   L->long_extent_px, L->narrow_view, L->long_view, L->clamped ? "; clamped below the finer level" : "");
    }
    if (set->contrast_band_count < 1)
        return;
    printf("lost contrast against level 0 (band-limited, Peli 1990; percentile %g of each view's object pixels, "
           "the largest over views), band centres in c/diam:\n%5s", set->contrast_percentile, "level");
    for (int b = 0; b < set->contrast_band_count; ++b)
        printf(" %7g", ldexp(1.0, b));
    printf("\n");
    for (int l = 1; l < set->level_count; ++l) {
        printf("%5d", l);
        for (int b = 0; b < set->contrast_band_count; ++b)
            printf(" %7.4f", set->lost_contrast[l][b]);
        printf("\n");
    }
}

int cmd_analyze(int argc, char **argv)
{
    if (app_wants_help(argc, argv)) {
        fputs(analyze_usage, stdout);
        return 0;
    }
    struct rnd_analyze_params p;
    rnd_analyze_params_defaults(&p);
    const char *path = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *opt = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        long n = 0;
        if (opt[0] != '-' || opt[1] != '-') {
            if (path) {
                fprintf(stderr, "hmdlod analyze: one .lod file at a time ('%s' and '%s')\n", path, opt);
                return 1;
            }
            path = opt;
            continue;
        }
        if (!strcmp(opt, "--views")) {
            if (app_parse_long(opt, val, 6, 18, &n))
                return 1;
            if (n != 6 && n != 18) {
                fprintf(stderr, "hmdlod: --views: %ld (6 or 18)\n", n);
                return 1;
            }
            p.views = (int)n;
        } else if (!strcmp(opt, "--size")) {
            if (app_parse_long(opt, val, 16, 2048, &n))
                return 1;
            p.size_px = (int)n;
        } else if (!strcmp(opt, "--threshold")) {
            if (app_parse_double(opt, val, &p.threshold_de))
                return 1;
            if (!(p.threshold_de > 0 && p.threshold_de <= 100)) {
                fprintf(stderr, "hmdlod: --threshold: %g is outside (0, 100]\n", p.threshold_de);
                return 1;
            }
        } else if (!strcmp(opt, "--min-region")) {
            if (app_parse_long(opt, val, 1, 1000, &n))
                return 1;
            p.min_component_px = (int)n;
        } else if (!strcmp(opt, "--dump")) {
            if (!val) {
                fprintf(stderr, "hmdlod: --dump needs a value\n");
                return 1;
            }
            p.dump_dir = val;
        } else {
            fprintf(stderr, "hmdlod analyze: unknown option '%s'\n%s", opt, analyze_usage);
            return 1;
        }
        ++i;
    }
    if (!path) {
        fprintf(stderr, "hmdlod analyze: a .lod file is required\n%s", analyze_usage);
        return 1;
    }

    struct hl_error err;
    struct scn_lodset set;
    if (scn_lodfile_read(path, &set, &err) != 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        return 1;
    }
    double t0 = hl_clock_now_s();
    struct rnd_renderer *r = NULL;
    if (rnd_renderer_create(p.size_px, p.size_px, &r, &err) != 0) {
        fprintf(stderr, "hmdlod: %s\n", err.msg);
        scn_lodset_free(&set);
        return 1;
    }
    double t_egl = hl_clock_now_s() - t0;
    struct hl_progress progress;
    hl_progress_begin(&progress, "analyze", (uint64_t)(p.views * set.level_count));
    p.progress = analyze_progress;
    p.progress_user = &progress;
    struct rnd_analyze_report rep;
    int rc = rnd_analyze_lodset(r, &set, &p, &rep, &err);
    hl_progress_end(&progress);
    rnd_renderer_destroy(r);
    if (rc != 0 || scn_lodfile_write(path, &set, &err) != 0) {
        fprintf(stderr, "hmdlod: %s: %s\n", path, err.msg);
        scn_lodset_free(&set);
        return 1;
    }
    print_table(path, &set, &p, &rep);
    printf("time: %.3f s analysis (%u renders %.3f s, comparisons %.3f s of which contrast spectra %.3f s) + %.3f s "
           "EGL context = %.3f s; wrote %s\n",
           rep.total_s, rep.renders, rep.render_s, rep.compare_s, rep.contrast_s, t_egl, rep.total_s + t_egl, path);
    scn_lodset_free(&set);
    return 0;
}
