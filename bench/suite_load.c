/* Reading a run back from its folder: summary.json for the error figures and the renderer,
 * frames.csv by column name (docs/replay-output.md) so that columns added later do not shift it.
 * Absent numbers (null in JSON, an empty CSV field, a missing column) read as NaN. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "bench/suite_internal.h"

/* cJSON allocates through base's counting hooks, so a parse that fails for want of memory is told from
 * bad text (base.h, "allocation in libraries"). */
__attribute__((constructor)) static void bench_load_json_hooks(void)
{
    cJSON_Hooks hooks = {hl_lib_malloc, hl_lib_free};
    cJSON_InitHooks(&hooks);
}

static char *slurp(const char *path, struct hl_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        hl_fail(err, "%s: cannot read: %s", path, strerror(errno));
        return NULL;
    }
    size_t cap = 1 << 16, len = 0;
    char *buf = malloc(cap);
    size_t got;
    while (buf && (got = fread(buf + len, 1, cap - len - 1, f)) > 0) {
        len += got;
        if (len + 1 == cap) {
            char *bigger = realloc(buf, cap *= 2);
            if (!bigger) {
                free(buf);
                buf = NULL;
            }
            buf = bigger;
        }
    }
    fclose(f);
    if (!buf) {
        hl_fail(err, "%s: out of memory", path);
        return NULL;
    }
    buf[len] = '\0';
    return buf;
}

static double json_num(const cJSON *o, const char *name)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, name);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static double json_stat(const cJSON *o, const char *name, const char *field)
{
    return json_num(cJSON_GetObjectItemCaseSensitive(o, name), field);
}

static int load_summary(const char *dir, struct bch_result *r, struct hl_error *err)
{
    char path[4400];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    char *text = slurp(path, err);
    if (!text)
        return -1;
    uint64_t failed_before = hl_lib_alloc_failures();
    cJSON *root = cJSON_Parse(text);
    free(text);
    if (!root && hl_lib_alloc_failures() != failed_before)
        return hl_fail(err, "%s: out of memory parsing the JSON", path);
    if (!cJSON_IsObject(root)) {
        cJSON_Delete(root);
        return hl_fail(err, "%s: not a JSON object", path);
    }
    const cJSON *renderer = cJSON_GetObjectItemCaseSensitive(root, "renderer");
    snprintf(r->renderer, sizeof r->renderer, "%s", cJSON_IsString(renderer) ? renderer->valuestring : "unknown");
    r->budget_ms = json_num(root, "budget_ms");
    const cJSON *wall = cJSON_GetObjectItemCaseSensitive(root, "wall_clock");
    const cJSON *host = cJSON_GetObjectItemCaseSensitive(wall, "host");
    snprintf(r->host, sizeof r->host, "%s", cJSON_IsString(host) ? host->valuestring : "");
    r->wall_start_unix_s = json_num(wall, "start_unix_s");
    r->wall_end_unix_s = json_num(wall, "end_unix_s");
    r->visible_error_mean = json_stat(root, "visible_error", "mean");
    r->visible_error_max = json_stat(root, "visible_error", "max");
    const cJSON *e = cJSON_GetObjectItemCaseSensitive(root, "image_error"); /* null without --reference */
    r->ref_frames = json_num(e, "frames");
    r->identical_frames = json_num(e, "identical_frames");
    r->psnr_db_mean = json_stat(e, "psnr_db", "mean");
    r->psnr_db_min = json_stat(e, "psnr_db", "min");
    r->ssim_mean = json_stat(e, "ssim", "mean");
    r->ssim_min = json_stat(e, "ssim", "min");
    r->ssim_rgb_mean = json_num(e, "ssim_rgb_mean");
    r->fssim_mean = json_stat(e, "fssim", "mean");
    r->fssim_min = json_stat(e, "fssim", "min");
    r->fssim_p5 = json_stat(e, "fssim", "p5");
    r->px_over_32 = json_num(e, "px_over_32_share_mean");
    r->flip_mean = json_stat(e, "flip", "mean");
    const cJSON *kept = cJSON_GetObjectItemCaseSensitive(root, "triangles_by_band");
    const cJSON *kept_e = cJSON_GetObjectItemCaseSensitive(kept, "eccentricity");
    const cJSON *kept_r = cJSON_GetObjectItemCaseSensitive(kept, "retinal_speed");
    for (int b = 0; b < 4; ++b) {
        r->kept_ecc[b] = json_num(cJSON_GetArrayItem(kept_e, b), "triangle_share");
        r->kept_retinal[b] = json_num(cJSON_GetArrayItem(kept_r, b), "triangle_share");
    }
    const cJSON *bands = cJSON_GetObjectItemCaseSensitive(e, "fssim_bands");
    for (int b = 0; b < 4; ++b)
        r->fssim_band[b] = json_num(cJSON_GetArrayItem(bands, b), "ssim_mean");
    cJSON_Delete(root);
    return 0;
}

/* The frames.csv columns the report reads, and where they go. */
struct column {
    const char *name;
    size_t offset;
};
#define COL(name)                                                                                                      \
    {                                                                                                                  \
#name, offsetof(struct bch_result, name)                                                                 \
    }
static const struct column columns[] = {
    COL(frame_ms),
    COL(draw_ms),
    COL(predicted_ms),
    {"head_speed_degps", offsetof(struct bch_result, head_speed)},
    COL(optimizer_us),
    {"triangles_per_eye", offsetof(struct bch_result, triangles)},
    {"triangles_finest", offsetof(struct bch_result, finest)},
    COL(dropped),
    COL(iterations),
    COL(truncated),
    COL(deadline_met),
    COL(visible),
    COL(visible_error),
    COL(layer_scale),
    COL(inset_radius_deg),
};
enum { N_COLUMNS = sizeof columns / sizeof columns[0] };

static double **column_ptr(struct bch_result *r, int k) { return (double **)((char *)r + columns[k].offset); }

static int load_frames(const char *dir, struct bch_result *r, struct hl_error *err)
{
    char path[4400];
    snprintf(path, sizeof path, "%s/frames.csv", dir);
    char *text = slurp(path, err);
    if (!text)
        return -1;
    long rows = 0;
    for (const char *p = text; *p; ++p)
        rows += *p == '\n';
    rows = rows > 0 ? rows - 1 : 0;
    int where[128]; /* CSV column → index into columns, or −1 */
    int n_fields = 0;
    char *line_end = strchr(text, '\n');
    if (!line_end) {
        free(text);
        return hl_fail(err, "%s: no header line", path);
    }
    *line_end = '\0';
    for (char *field = text; field && n_fields < 128; ++n_fields) {
        char *comma = strchr(field, ',');
        if (comma)
            *comma = '\0';
        where[n_fields] = -1;
        for (int k = 0; k < N_COLUMNS; ++k)
            if (!strcmp(field, columns[k].name)) {
                if (*column_ptr(r, k)) { /* which of the two would the report mean? */
                    free(text);
                    return hl_fail(err, "%s:1: column '%s' appears twice in the header", path, columns[k].name);
                }
                where[n_fields] = k;
                if (!(*column_ptr(r, k) = malloc((size_t)(rows > 0 ? rows : 1) * sizeof(double)))) {
                    free(text);
                    return hl_fail(err, "%s: out of memory", path);
                }
            }
        field = comma ? comma + 1 : NULL;
    }
    long n = 0;
    for (char *line = line_end + 1; *line && n < rows; ++n) {
        char *end = strchr(line, '\n');
        if (end)
            *end = '\0';
        int f = 0;
        for (char *field = line; field && f < n_fields; ++f) {
            char *comma = strchr(field, ',');
            if (comma)
                *comma = '\0';
            if (where[f] >= 0) {
                char *stop = NULL;
                double v = strtod(field, &stop);
                (*column_ptr(r, where[f]))[n] = stop == field ? NAN : v; /* empty: no value this frame */
            }
            field = comma ? comma + 1 : NULL;
        }
        if (f != n_fields) {
            free(text);
            return hl_fail(err, "%s:%ld: %d fields, the header has %d", path, n + 2, f, n_fields);
        }
        line = end ? end + 1 : line + strlen(line);
    }
    r->n = n;
    free(text);
    return 0;
}

int bch_result_load(const char *run_dir, struct bch_result *r, struct hl_error *err)
{
    memset(r, 0, sizeof *r);
    if (load_summary(run_dir, r, err) != 0 || load_frames(run_dir, r, err) != 0) {
        bch_result_free(r);
        return -1;
    }
    r->present = 1;
    return 0;
}

void bch_result_free(struct bch_result *r)
{
    for (int k = 0; k < N_COLUMNS; ++k) {
        free(*column_ptr(r, k));
        *column_ptr(r, k) = NULL;
    }
    for (int k = 0; r->more && k < r->rounds - 1; ++k)
        bch_result_free(&r->more[k]);
    free(r->more);
    r->more = NULL;
    r->rounds = 0;
    r->present = 0;
}

double bch_mean(const struct bch_result *r, const double *col) { return bch_mean_from(r, col, 0); }
double bch_max(const struct bch_result *r, const double *col) { return bch_max_from(r, col, 0); }
double bch_stddev(const struct bch_result *r, const double *col)
{
    return bch_stddev_from(r, col, 0);
}

double bch_mean_from(const struct bch_result *r, const double *col, long first)
{
    if (!r || !col)
        return NAN;
    double sum = 0.0;
    long n = 0;
    for (long i = first; i < r->n; ++i)
        if (isfinite(col[i]))
            sum += col[i], ++n;
    return n ? sum / (double)n : NAN;
}

double bch_max_from(const struct bch_result *r, const double *col, long first)
{
    if (!r || !col)
        return NAN;
    double m = NAN;
    for (long i = first; i < r->n; ++i)
        if (isfinite(col[i]) && !(col[i] <= m))
            m = col[i];
    return m;
}

double bch_stddev_from(const struct bch_result *r, const double *col, long first)
{
    double mean = bch_mean_from(r, col, first);
    if (!isfinite(mean))
        return NAN;
    double ss = 0.0;
    long n = 0;
    for (long i = first; i < r->n; ++i)
        if (isfinite(col[i]))
            ss += (col[i] - mean) * (col[i] - mean), ++n;
    return n > 1 ? sqrt(ss / (double)(n - 1)) : 0.0;
}

int bch_result_rounds(const struct bch_result *r)
{
    if (!r || r->rounds < 1)
        return 1;
    return r->rounds > BCH_SUITE_MAX_REPEATS ? BCH_SUITE_MAX_REPEATS : r->rounds;
}

const struct bch_result *bch_round(const struct bch_result *r, int k)
{
    const struct bch_result *x = k == 0 ? r : k < r->rounds && r->more ? &r->more[k - 1] : NULL;
    return x && x->present ? x : NULL;
}

static double stat_of(const struct bch_result *x, enum bch_stat stat, size_t column)
{
    const double *col = *(double *const *)((const char *)x + column);
    /* frame 0 left out: the GL driver compiles its shaders there */
    return stat == BCH_STAT_MAX ? bch_max_from(x, col, 1) : stat == BCH_STAT_SD ? bch_stddev_from(x, col, 1)
                                                                                : bch_mean_from(x, col, 1);
}

double bch_timing(const struct bch_result *r, enum bch_stat stat, size_t column)
{
    if (!r)
        return NAN;
    int rounds = bch_result_rounds(r);
    double v[BCH_SUITE_MAX_REPEATS];
    for (int k = 0; k < rounds; ++k) {
        const struct bch_result *x = bch_round(r, k);
        v[k] = x ? stat_of(x, stat, column) : NAN;
    }
    struct bch_spread sp;
    bch_spread_of(v, rounds, &sp);
    return sp.median;
}

void bch_timing_ratio(const struct bch_result *num, const struct bch_result *den, enum bch_stat stat, size_t column,
                      struct bch_spread *out)
{
    double v[BCH_SUITE_MAX_REPEATS];
    int n = 0;
    if (num && den) {
        int a_rounds = bch_result_rounds(num), b_rounds = bch_result_rounds(den);
        int rounds = a_rounds > b_rounds ? a_rounds : b_rounds;
        for (int k = 0; k < rounds; ++k) {
            const struct bch_result *a = bch_round(num, k), *b = bch_round(den, k);
            v[n++] = a && b ? stat_of(a, stat, column) / stat_of(b, stat, column) : NAN;
        }
    }
    bch_spread_of(v, n, out);
}
