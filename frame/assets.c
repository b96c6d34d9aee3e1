/* The built-in chains' measured frequency tables and lost-contrast spectra: Reddy's offline
 * analysis (render/analyze.c) run once per chain and cached in small text files keyed by the meshes
 * and the parameters, and the reading the selectors use. docs/analysis.md describes the cache and
 * the choice of reading. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "frame/frame.h"

/* Bump when the analysis itself changes (shader, light, colour, orientations, extent rule) or the
 * cache file's content does: every cached table then misses (another key, another file name) and
 * is measured again. 2: the largest lost feature governs, sized by run lengths (was the smallest,
 * by projections). 3: the file holds the lost-contrast spectrum too ("hmdlod-freq 2"). 4: the renderer
 * shades in linear light (sRGB albedo decoded, shading applied, encoded), so readings moved.
 * FRM_CACHE_FILE_MAX: the largest file is about 3.1 KB — five header lines (≈ 145 bytes with a
 * 24-character %.17g percentile), per level (8) a "level" line of two %.17g values (≤ 58) and a
 * "contrast" line of 12 (≤ 11 + 12 × 25 = 311), and the check line (23); twice that leaves room
 * for a later field without a silent "cannot write" (frm_cache_format fails rather than cut). */
enum { FRM_ANALYSIS_VERSION = 4, FRM_CACHE_FILE_MAX = 8192 };

int frm_freq_reading_parse(const char *name, enum frm_freq_reading *out, struct hl_error *err)
{
    static const char *const names[] = {"long", "narrow", "geometric"};
    for (int i = 0; i < 3; ++i)
        if (name && !strcmp(name, names[i])) {
            *out = (enum frm_freq_reading)i;
            return 0;
        }
    return hl_fail(err, "--frequency-reading: unknown reading '%s' (known: long, narrow, geometric)",
                   name ? name : "(null)");
}

const char *frm_freq_reading_name(enum frm_freq_reading r)
{
    return r == FRM_READING_NARROW ? "narrow" : r == FRM_READING_GEOMETRIC ? "geometric" : "long";
}

void frm_assets_params(struct rnd_analyze_params *p) { rnd_analyze_params_defaults(p); }

int frm_cache_dir(char *out, size_t size, struct hl_error *err)
{
    const char *env = getenv("HMDLOD_CACHE_DIR");
    if (env && *env) {
        if (snprintf(out, size, "%s", env) >= (int)size)
            return hl_fail(err, "HMDLOD_CACHE_DIR: path too long");
        return 0;
    }
    char exe[4096];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0 || (size_t)n >= sizeof exe - 1)
        return hl_fail(err, "analysis cache: cannot find the executable (/proc/self/exe): %s", strerror(errno));
    exe[n] = '\0';
    char *slash = strrchr(exe, '/');
    if (slash)
        *slash = '\0';
    if (snprintf(out, size, "%s/lodcache", slash ? exe : ".") >= (int)size)
        return hl_fail(err, "analysis cache: path too long");
    return 0;
}

int frm_lodset_from_chain(const struct scn_scene *s, uint32_t chain, struct scn_lodset *out, struct hl_error *err)
{
    memset(out, 0, sizeof *out);
    if (!s || chain >= s->chain_count)
        return hl_fail(err, "scene: chain %u of %u", chain, s ? s->chain_count : 0);
    const struct scn_chain *c = &s->chains[chain];
    out->level_count = c->lod_count;
    for (int l = 0; l < c->lod_count; ++l) {
        const struct scn_lod *L = &c->lods[l];
        /* A level's vertices are one contiguous run of the packed array (scene.c packs level by
         * level), so its index range's smallest and largest index bound it. */
        uint32_t lo = UINT32_MAX, hi = 0;
        for (uint32_t k = 0; k < L->index_count; ++k) {
            uint32_t v = s->indices[L->first_index + k];
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
        struct scn_mesh *m = &out->levels[l];
        for (uint32_t v = lo; L->index_count && v <= hi; ++v) {
            const float *p = s->positions + 3 * (size_t)v, *n = s->normals + 3 * (size_t)v;
            scn_mesh_add_vertex(m, hl_v3(p[0], p[1], p[2]), hl_v3(n[0], n[1], n[2]));
        }
        for (uint32_t k = 0; k + 2 < L->index_count; k += 3) {
            const uint32_t *t = s->indices + L->first_index + k;
            scn_mesh_add_triangle(m, t[0] - lo, t[1] - lo, t[2] - lo);
        }
        if (m->failed) {
            scn_lodset_free(out);
            return hl_fail(err, "scene: chain %s: out of memory copying level %d", c->name, l);
        }
        out->error_m[l] = L->geometric_error_m;
        out->error_rel[l] = c->bound_radius_m > 0 ? L->geometric_error_m / c->bound_radius_m : NAN;
        out->freq[l] = L->freq;
    }
    memcpy(out->center_m, c->bound_center_m, sizeof out->center_m);
    out->radius_m = c->bound_radius_m;
    out->contrast_band_count = c->contrast_band_count;
    out->contrast_percentile = c->contrast_percentile;
    for (int l = 0; l < c->lod_count; ++l)
        memcpy(out->lost_contrast[l], c->lods[l].lost_contrast, sizeof out->lost_contrast[l]);
    snprintf(out->simplifier, sizeof out->simplifier, "procedural");
    return 0;
}

/* ---- the cache ------------------------------------------------------------------------------- */

static uint64_t frm_fnv1a(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

/* Key: the analysis version, every parameter that changes a reading or the spectrum (the albedo
 * changes both: ΔE and contrast of a brighter object are larger) and every level's content hash
 * (scn_mesh_hash). */
static uint64_t frm_cache_key(const struct scn_lodset *set, const struct rnd_analyze_params *p)
{
    char text[512];
    int n = snprintf(text, sizeof text,
                     "v%d views %d size %d threshold %.17g min %d levels %d percentile %.17g reach %d "
                     "albedo %.17g %.17g %.17g",
                     FRM_ANALYSIS_VERSION, p->views, p->size_px, p->threshold_de, p->min_component_px,
                     set->level_count, p->contrast_percentile, p->contrast_silhouette_reach, p->albedo_rgb[0],
                     p->albedo_rgb[1], p->albedo_rgb[2]);
    if (n < 0 || (size_t)n >= sizeof text) /* cannot happen with these formats; never hash past the end */
        n = (int)strlen(text);
    uint64_t h = frm_fnv1a(0xcbf29ce484222325ull, text, (size_t)n);
    for (int l = 0; l < set->level_count; ++l) {
        uint64_t m = scn_mesh_hash(&set->levels[l]);
        h = frm_fnv1a(h, &m, sizeof m);
    }
    return h;
}

int frm_cache_file(char *out, size_t size, const char *dir, const char *label, uint64_t key, const char *suffix)
{
    /* A label is a chain's or a file's name: anything but letters, digits, '-' and '_' (a '/' in a
     * scene file's mesh name, say) becomes '_', so the file stays inside the cache folder. */
    char plain[64];
    size_t n = 0;
    for (; label[n] && n + 1 < sizeof plain; ++n) {
        char c = label[n];
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
        plain[n] = ok ? c : '_';
    }
    plain[n] = '\0';
    return snprintf(out, size, "%s/%s-%016llx%s", dir, plain, (unsigned long long)key, suffix) < (int)size ? 0 : -1;
}

/* What a cache file holds: the lodset's narrow and long readings and its lost-contrast spectrum. */
struct frm_cached {
    double narrow[SCN_LODSET_MAX_LEVELS], longr[SCN_LODSET_MAX_LEVELS];
    int band_count;
    double percentile;
    double lost_contrast[SCN_LODSET_MAX_LEVELS][SCN_LODSET_MAX_BANDS];
};

/* Appends to buf[*n …] like snprintf; −1 when it does not fit (the file is then not written). */
static int frm_append(char *buf, size_t size, size_t *n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(buf + *n, size - *n, fmt, ap);
    va_end(ap);
    if (k < 0 || (size_t)k >= size - *n)
        return -1;
    *n += (size_t)k;
    return 0;
}

/* Format (docs/analysis.md): "hmdlod-freq 2", "key HEX", "views N size_px N levels N",
 * "bands N percentile P", per level a "level L NARROW LONG" line and a "contrast L C0 … C(N−1)"
 * line (%.17g, exact through strtod; a NaN band as "nan", whatever its sign bit), then "check HEX",
 * the FNV-1a 64 of every byte before that line. */
static int frm_cache_format(char *buf, size_t size, uint64_t key, const struct scn_lodset *set)
{
    size_t n = 0;
    if (frm_append(buf, size, &n,
                   "hmdlod-freq 2\nkey %016llx\nviews %d size_px %d levels %d\nbands %d percentile %.17g\n",
                   (unsigned long long)key, set->analysis_views, set->analysis_size_px, set->level_count,
                   set->contrast_band_count, set->contrast_percentile) != 0)
        return -1;
    for (int l = 0; l < set->level_count; ++l) {
        if (frm_append(buf, size, &n, "level %d %.17g %.17g\ncontrast %d", l, set->freq[l].narrow_cpdiam,
                       set->freq[l].long_cpdiam, l) != 0)
            return -1;
        for (int b = 0; b < set->contrast_band_count; ++b) {
            double c = set->lost_contrast[l][b];
            if (isnan(c) ? frm_append(buf, size, &n, " nan") : frm_append(buf, size, &n, " %.17g", c))
                return -1;
        }
        if (frm_append(buf, size, &n, "\n") != 0)
            return -1;
    }
    return frm_append(buf, size, &n, "check %016llx\n", (unsigned long long)frm_fnv1a(0xcbf29ce484222325ull, buf, n))
               ? -1
               : (int)n;
}

/* One " VALUE" of a contrast line at *q: a space, then a number strtod reads ("nan" included, so
 * that a band no view saw survives); a negative or infinite value, or none, is corrupt. */
static int frm_read_contrast(const char **q, double *out)
{
    const char *s = *q;
    if (*s != ' ' || s[1] == '\0' || isspace((unsigned char)s[1])) /* strtod would skip on to the next line */
        return -1;
    char *end = NULL;
    double c = strtod(s + 1, &end);
    if (end == s + 1 || (*end != ' ' && *end != '\n'))
        return -1;
    if (isnan(c))
        c = NAN; /* one bit pattern, the analysis's (render/analyze.c starts every band at NAN) */
    else if (!(c >= 0) || isinf(c))
        return -1;
    *out = c;
    *q = end;
    return 0;
}

/* Reads a cache file into *out. 1 = absent, 0 = read, −1 = corrupt (why in *why). */
static int frm_cache_read(const char *path, uint64_t key, const struct scn_lodset *set,
                          const struct rnd_analyze_params *p, struct frm_cached *out, const char **why)
{
    struct hl_error open_err;
    FILE *f = hl_file_open_read(path, NULL, &open_err);
    *why = "not a regular file";
    if (!f)
        return errno == ENOENT ? 1 : -1;
    char buf[FRM_CACHE_FILE_MAX + 1];
    size_t len = fread(buf, 1, FRM_CACHE_FILE_MAX, f);
    int toolong = !feof(f);
    fclose(f);
    buf[len] = '\0';
    *why = "too long";
    if (toolong)
        return -1;
    *why = "no check line";
    char *check = strstr(buf, "check ");
    if (!check || (check != buf && check[-1] != '\n'))
        return -1;
    unsigned long long sum = 0;
    *why = "checksum mismatch";
    if (sscanf(check, "check %16llx", &sum) != 1 ||
        sum != frm_fnv1a(0xcbf29ce484222325ull, buf, (size_t)(check - buf)))
        return -1;
    unsigned long long k = 0;
    int views = 0, size = 0, levels = 0, bands = -1, used = 0;
    double percentile = NAN;
    *why = "bad header";
    if (sscanf(buf, "hmdlod-freq 2\nkey %16llx\nviews %d size_px %d levels %d\nbands %d percentile %lf\n%n", &k, &views,
               &size, &levels, &bands, &percentile, &used) != 6 ||
        used == 0)
        return -1;
    *why = "key or parameters differ";
    if (k != key || views != p->views || size != p->size_px || levels != set->level_count)
        return -1;
    *why = "bad band count or percentile";
    if (bands < 0 || bands > SCN_LODSET_MAX_BANDS || percentile != (bands ? p->contrast_percentile : 0.0))
        return -1;
    out->band_count = bands;
    out->percentile = percentile;
    const char *q = buf + used;
    for (int l = 0; l < levels; ++l) {
        int idx = -1, n = 0;
        *why = "bad level line";
        if (sscanf(q, "level %d %lf %lf\n%n", &idx, &out->narrow[l], &out->longr[l], &n) != 3 || idx != l || n == 0)
            return -1;
        q += n;
        *why = "table not strictly decreasing from +inf";
        if (l == 0 ? !(isinf(out->narrow[0]) && isinf(out->longr[0]))
                   : !(out->narrow[l] > 0 && out->narrow[l] < out->narrow[l - 1] && out->longr[l] > 0 &&
                       out->longr[l] < out->longr[l - 1]))
            return -1;
        n = 0;
        *why = "bad contrast line (a value missing, negative or infinite)";
        if (sscanf(q, "contrast %d%n", &idx, &n) != 1 || idx != l || n == 0)
            return -1;
        q += n;
        for (int b = 0; b < SCN_LODSET_MAX_BANDS; ++b)
            out->lost_contrast[l][b] = 0.0;
        for (int b = 0; b < bands; ++b)
            if (frm_read_contrast(&q, &out->lost_contrast[l][b]) != 0)
                return -1;
        if (*q++ != '\n')
            return -1;
        *why = "level 0 loses contrast";
        for (int b = 0; l == 0 && b < bands; ++b)
            if (out->lost_contrast[0][b] != 0.0)
                return -1;
    }
    *why = "text after the last level";
    if (q != check)
        return -1;
    return 0;
}

int frm_cache_make_dir(const char *dir)
{
    char path[4096];
    if (snprintf(path, sizeof path, "%s", dir) >= (int)sizeof path)
        return -1;
    for (char *s = path + 1;; ++s) {
        if (*s == '/' || *s == '\0') {
            char c = *s;
            *s = '\0';
            if (mkdir(path, 0777) != 0 && errno != EEXIST)
                return -1;
            *s = c;
            if (c == '\0')
                break;
        }
    }
    struct stat st;
    return stat(dir, &st) == 0 && S_ISDIR(st.st_mode) ? 0 : -1;
}

/* Temporary file + rename: a reader never sees half a table. 0, or −1 with errno's reason. */
static int frm_cache_write(const char *dir, const char *path, uint64_t key, const struct scn_lodset *set)
{
    char buf[FRM_CACHE_FILE_MAX];
    int len = frm_cache_format(buf, sizeof buf, key, set);
    if (len < 0) {
        errno = ENOSPC;
        return -1;
    }
    if (frm_cache_make_dir(dir) != 0)
        return -1;
    struct hl_error werr;
    if (hl_out_write_all(path, buf, (size_t)len, &werr) != 0)
        return -1; /* errno still says why (the caller names the file) */
    return 0;
}

/* ---- preparing a scene ----------------------------------------------------------------------- */

void frm_assets_apply_reading(struct scn_scene *scene, enum frm_freq_reading reading)
{
    for (uint32_t c = 0; c < scene->chain_count; ++c) {
        struct scn_chain *ch = &scene->chains[c];
        for (int l = 0; l < ch->lod_count; ++l) {
            struct scn_lod *L = &ch->lods[l];
            double f = reading == FRM_READING_NARROW ? L->freq.narrow_cpdiam
                       : reading == FRM_READING_LONG ? L->freq.long_cpdiam
                                                     : L->freq.geometric_cpdiam;
            if (isnan(f))
                f = L->freq.geometric_cpdiam;
            if (l == 0)
                f = INFINITY;
            else if (!(f < ch->lods[l - 1].unique_freq_cpdiam)) /* the selector needs it falling */
                f = nextafter(ch->lods[l - 1].unique_freq_cpdiam, 0.0);
            if (!isnan(f))
                L->unique_freq_cpdiam = f;
        }
    }
}

/* From the cache or by analysis (then stored): set->freq narrow and long readings and the
 * lost-contrast spectrum. *r is the analysis renderer, made on the first miss and reused for later
 * chains. */
static int frm_measure(struct scn_lodset *set, const char *name, const struct rnd_analyze_params *p,
                       struct rnd_renderer **r, struct frm_assets_report *rep, struct hl_error *err)
{
    static int frm_cache_warned; /* "cannot write" is said once per process */
    char dir[4096], path[4300] = "";
    struct hl_error dir_err;
    int have_dir = frm_cache_dir(dir, sizeof dir, &dir_err) == 0;
    uint64_t key = frm_cache_key(set, p);
    struct frm_cached fc;
    int cached = 1;
    const char *why = "";
    if (have_dir && frm_cache_file(path, sizeof path, dir, name, key, ".freq") == 0) {
        cached = frm_cache_read(path, key, set, p, &fc, &why);
        if (cached < 0)
            fprintf(stderr, "hmdlod: note: analysis cache %s is corrupt (%s); analysing %s again\n", path, why, name);
    }
    if (cached == 0) {
        for (int l = 0; l < set->level_count; ++l)
            set->freq[l].narrow_cpdiam = fc.narrow[l], set->freq[l].long_cpdiam = fc.longr[l];
        set->contrast_band_count = fc.band_count;
        set->contrast_percentile = fc.percentile;
        memcpy(set->lost_contrast, fc.lost_contrast, sizeof set->lost_contrast);
        set->analysis_views = p->views;
        set->analysis_size_px = p->size_px;
        rep->chains_cached++;
        return 0;
    }
    double t0 = hl_clock_now_s();
    if (!*r && rnd_renderer_create(p->size_px, p->size_px, r, err) != 0)
        return -1;
    if (rnd_analyze_lodset(*r, set, p, NULL, err) != 0)
        return -1;
    rep->analysis_s += hl_clock_now_s() - t0;
    rep->chains_analysed++;
    if (!have_dir || frm_cache_write(dir, path, key, set) != 0) {
        rep->cache_unwritable = 1;
        if (!frm_cache_warned++)
            fprintf(stderr, "hmdlod: note: cannot write the analysis cache %s (%s); analysing on every run\n",
                    have_dir ? dir : "", have_dir ? strerror(errno) : dir_err.msg);
    }
    return 0;
}

int frm_assets_measure(struct scn_lodset *set, const char *name, const struct rnd_analyze_params *p,
                       struct frm_assets_report *report, struct hl_error *err)
{
    struct frm_assets_report rep = {0};
    if (rnd_analyze_params_check(p, err) != 0)
        return -1;
    if (!set || set->level_count < 2) { /* one level loses nothing: nothing to measure */
        if (report)
            *report = rep;
        return set ? 0 : hl_fail(err, "analysis: no lodset");
    }
    struct rnd_renderer *r = NULL;
    int rc = frm_measure(set, name && *name ? name : "lodset", p, &r, &rep, err);
    rnd_renderer_destroy(r);
    if (report)
        *report = rep;
    return rc;
}

/* The chain's asset (a .lod written by `hmdlod analyze`) came with both image-based readings for
 * every coarser level (NaN = not measured). Readings an earlier frm_assets_prepare put there do not
 * count: they are the cache's, keyed by their parameters (prepare leaves analysis_views 0). */
static int frm_chain_has_readings(const struct scn_chain *ch)
{
    if (ch->analysis_views <= 0)
        return 0;
    for (int l = 1; l < ch->lod_count; ++l)
        if (isnan(ch->lods[l].freq.narrow_cpdiam) || isnan(ch->lods[l].freq.long_cpdiam))
            return 0;
    return 1;
}

/* Measured means readings and spectrum: a version 1 .lod (readings, no spectrum) is analysed like
 * a built-in chain so that the selectors find a spectrum in every chain of two or more levels. */
static int frm_chain_has_tables(const struct scn_chain *ch)
{
    return frm_chain_has_readings(ch) && ch->contrast_band_count > 0;
}

int frm_assets_prepare(struct scn_scene *scene, const struct rnd_analyze_params *p, enum frm_freq_reading reading,
                       struct frm_assets_report *report, struct hl_error *err)
{
    struct frm_assets_report rep = {0};
    if (rnd_analyze_params_check(p, err) != 0)
        return -1;
    struct rnd_renderer *r = NULL;
    int rc = 0;
    for (uint32_t c = 0; c < scene->chain_count && rc == 0; ++c) {
        struct scn_chain *ch = &scene->chains[c];
        if (ch->lod_count < 2)
            continue;
        if (frm_chain_has_tables(ch)) { /* a .lod that `hmdlod analyze` measured: its own tables */
            rep.chains_from_file++;
            continue;
        }
        struct scn_lodset set;
        if (frm_lodset_from_chain(scene, c, &set, err) != 0) {
            rc = -1;
            break;
        }
        rc = frm_measure(&set, ch->name, p, &r, &rep, err);
        /* A version 1 .lod keeps the readings its own `hmdlod analyze` measured (with the views and
         * size in analysis_views/size_px) and gains only the spectrum. */
        int own_readings = frm_chain_has_readings(ch);
        if (rc == 0) {
            ch->contrast_band_count = set.contrast_band_count;
            ch->contrast_percentile = set.contrast_percentile;
        }
        for (int l = 0; rc == 0 && l < ch->lod_count && l < SCN_LODSET_MAX_LEVELS; ++l) { /* bound for GCC */
            if (!own_readings) {
                ch->lods[l].freq.narrow_cpdiam = set.freq[l].narrow_cpdiam;
                ch->lods[l].freq.long_cpdiam = set.freq[l].long_cpdiam;
            }
            memcpy(ch->lods[l].lost_contrast, set.lost_contrast[l], sizeof ch->lods[l].lost_contrast);
        }
        scn_lodset_free(&set);
    }
    rnd_renderer_destroy(r);
    if (rc != 0)
        return -1;
    frm_assets_apply_reading(scene, reading);
    if (report)
        *report = rep;
    return 0;
}
