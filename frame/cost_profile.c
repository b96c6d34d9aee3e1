/* The machine cost profile JSON (docs/cost-model.md): strict reading with cJSON — every error names
 * the file and the field — atomic writing, and the built-in llvmpipe reference. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "frame/frame.h"

/* Version 2 adds c5 (the edge term, lod.h); version 3, the same keys, fits c3 and c5 on fragments (the
 * projected bound × the level's fill, scn_lod_fill) where 1 and 2 fitted them on the bound's pixels.
 * Versions 1 (five coefficients, c5 0) and 2 still read, their label saying what they predate. */
#define COST_FORMAT_TAG "hmdlod-cost-profile-3"
#define COST_FORMAT_TAG_V2 "hmdlod-cost-profile-2"
#define COST_FORMAT_TAG_V1 "hmdlod-cost-profile-1"
enum { COST_PROFILE_MAX_BYTES = 1 << 20 };

/* cJSON allocates through base's counting hooks, so a parse that fails for want of memory is told from
 * bad text (base.h, "allocation in libraries"). */
__attribute__((constructor)) static void cost_profile_json_hooks(void)
{
    cJSON_Hooks hooks = {hl_lib_malloc, hl_lib_free};
    cJSON_InitHooks(&hooks);
}

static const char *const coefficient_keys[6] = {"c0_ms", "c1_ms_per_triangle", "c2_ms_per_vertex",
                                                 "c3_ms_per_pixel", "c4_ms_per_draw", "c5_ms_per_edge_px"};

const char *frm_cost_form_name(enum lod_cost_form form)
{
    return form == LOD_COST_MAX ? "max" : form == LOD_COST_ADDITIVE ? "additive" : NULL;
}

int frm_cost_form_parse(const char *name, enum lod_cost_form *form)
{
    if (name && !strcmp(name, "max"))
        return *form = LOD_COST_MAX, 0;
    if (name && !strcmp(name, "additive"))
        return *form = LOD_COST_ADDITIVE, 0;
    return -1;
}

static double *coefficient(struct lod_cost_model *m, int i)
{
    double *c[6] = {&m->c0_ms,           &m->c1_ms_per_triangle, &m->c2_ms_per_vertex,
                    &m->c3_ms_per_pixel, &m->c4_ms_per_draw,     &m->c5_ms_per_edge_px};
    return c[i];
}

/* ---- reading --------------------------------------------------------------------------------- */

static char *read_text(const char *path, struct hl_error *err)
{
    char *buf = NULL;
    return hl_file_read_all(path, COST_PROFILE_MAX_BYTES, &buf, NULL, err) == 0 ? buf : NULL;
}

/* Unknown keys are errors: a misspelt coefficient must not silently fall back to nothing. */
static int check_keys(const cJSON *obj, const char *const *keys, int n, const char *path, const char *where,
                      struct hl_error *err)
{
    for (const cJSON *it = obj->child; it; it = it->next) {
        int known = 0;
        for (int i = 0; i < n && !known; ++i)
            known = it->string && !strcmp(it->string, keys[i]);
        if (!known)
            return hl_fail(err, "%s: %s'%s': unknown key", path, where, it->string ? it->string : "?");
    }
    return 0;
}

static int read_number(const cJSON *obj, const char *key, int required, double min, double *out, const char *path,
                       const char *where, struct hl_error *err)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!it)
        return required ? hl_fail(err, "%s: %s'%s': missing", path, where, key) : 0;
    if (!cJSON_IsNumber(it))
        return hl_fail(err, "%s: %s'%s': not a number", path, where, key);
    if (!isfinite(it->valuedouble))
        return hl_fail(err, "%s: %s'%s': not finite", path, where, key);
    if (it->valuedouble < min)
        return hl_fail(err, "%s: %s'%s': %g is negative (must be ≥ %g)", path, where, key, it->valuedouble, min);
    *out = it->valuedouble;
    return 0;
}

static int read_string(const cJSON *obj, const char *key, int required, char *out, size_t size, const char *path,
                       struct hl_error *err)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!it)
        return required ? hl_fail(err, "%s: '%s': missing", path, key) : 0;
    if (!cJSON_IsString(it))
        return hl_fail(err, "%s: '%s': not a string", path, key);
    if (strlen(it->valuestring) >= size)
        return hl_fail(err, "%s: '%s': longer than %zu characters", path, key, size - 1);
    snprintf(out, size, "%s", it->valuestring);
    return 0;
}

/* prefix: where the object sits ("" at the top, "'periphery'[1]: " in a layer's model). */
static int read_accuracy(const cJSON *root, const char *key, struct frm_cost_accuracy *acc, const char *path,
                         const char *prefix, struct hl_error *err)
{
    static const char *const keys[] = {"frames", "median_rel", "p95_rel", "under5_share"};
    const cJSON *o = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!o)
        return 0;
    char where[96];
    snprintf(where, sizeof where, "%s'%s': ", prefix, key);
    if (!cJSON_IsObject(o))
        return hl_fail(err, "%s: %snot an object", path, where);
    double frames = 0;
    if (check_keys(o, keys, 4, path, where, err) != 0 ||
        read_number(o, "frames", 1, 0, &frames, path, where, err) != 0 ||
        read_number(o, "median_rel", 1, 0, &acc->median_rel, path, where, err) != 0 ||
        read_number(o, "p95_rel", 1, 0, &acc->p95_rel, path, where, err) != 0 ||
        read_number(o, "under5_share", 1, 0, &acc->under5_share, path, where, err) != 0)
        return -1;
    if (frames > 1e9 || frames != floor(frames))
        return hl_fail(err, "%s: %s'frames': not a whole number of frames", path, where);
    acc->frames = (uint32_t)frames;
    return 0;
}

static int read_fixed(const cJSON *root, struct frm_cost_fixed *fx, const char *path, const char *prefix,
                      struct hl_error *err)
{
    static const char *const keys[] = {"frames", "median_ms", "p25_ms", "p75_ms"};
    const cJSON *o = cJSON_GetObjectItemCaseSensitive(root, "fixed_cost");
    if (!o)
        return 0;
    char where[96];
    snprintf(where, sizeof where, "%s'fixed_cost': ", prefix);
    if (!cJSON_IsObject(o))
        return hl_fail(err, "%s: %snot an object", path, where);
    double frames = 0;
    if (check_keys(o, keys, 4, path, where, err) != 0 || read_number(o, "frames", 1, 1, &frames, path, where, err) != 0 ||
        read_number(o, "median_ms", 1, 0, &fx->median_ms, path, where, err) != 0 ||
        read_number(o, "p25_ms", 1, 0, &fx->p25_ms, path, where, err) != 0 ||
        read_number(o, "p75_ms", 1, 0, &fx->p75_ms, path, where, err) != 0)
        return -1;
    if (frames > 1e9 || frames != floor(frames))
        return hl_fail(err, "%s: %s'frames': not a whole number of frames", path, where);
    if (!(fx->p25_ms <= fx->median_ms && fx->median_ms <= fx->p75_ms))
        return hl_fail(err, "%s: %sexpected p25_ms ≤ median_ms ≤ p75_ms", path, where);
    fx->frames = (uint32_t)frames;
    return 0;
}

/* A JSON array of at most RND_COST_GRID_MAX finite non-negative numbers. */
static int read_list(const cJSON *grid, const char *key, double *out, int *count, const char *path,
                     struct hl_error *err)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(grid, key);
    int n = cJSON_IsArray(a) ? cJSON_GetArraySize(a) : -1;
    if (n < 1 || n > RND_COST_GRID_MAX)
        return hl_fail(err, "%s: 'grid': '%s': expected an array of 1…%d numbers", path, key, RND_COST_GRID_MAX);
    for (int i = 0; i < n; ++i) {
        const cJSON *it = cJSON_GetArrayItem(a, i);
        if (!cJSON_IsNumber(it) || !isfinite(it->valuedouble) || it->valuedouble < 0)
            return hl_fail(err, "%s: 'grid': '%s'[%d]: not a finite number ≥ 0", path, key, i);
        out[i] = it->valuedouble;
    }
    *count = n;
    return 0;
}

/* "form" and "coefficients" (the first `coefficients` keys) of obj into *m. */
static int read_model(const cJSON *obj, int coefficients, struct lod_cost_model *m, const char *path,
                      const char *prefix, struct hl_error *err)
{
    char where[96];
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(obj, "form");
    if (!f)
        return hl_fail(err, "%s: %s'form': missing", path, prefix);
    if (!cJSON_IsString(f) || frm_cost_form_parse(f->valuestring, &m->form) != 0)
        return hl_fail(err, "%s: %s'form': unknown form '%s' (max or additive)", path, prefix,
                       cJSON_IsString(f) ? f->valuestring : "?");
    const cJSON *co = cJSON_GetObjectItemCaseSensitive(obj, "coefficients");
    if (!co)
        return hl_fail(err, "%s: %s'coefficients': missing", path, prefix);
    if (!cJSON_IsObject(co))
        return hl_fail(err, "%s: %s'coefficients': not an object", path, prefix);
    snprintf(where, sizeof where, "%s'coefficients': ", prefix);
    if (check_keys(co, coefficient_keys, coefficients, path, where, err) != 0)
        return -1;
    for (int i = 0; i < coefficients; ++i)
        if (read_number(co, coefficient_keys[i], 1, 0.0, coefficient(m, i), path, where, err) != 0)
            return -1;
    return 0;
}

/* "periphery": the layer models (frm_cost_periphery), at most one per scale below 1 of the layers'
 * grid (frame/layers.h), each {"scale", "form", "coefficients", "held_out", "fixed_cost",
 * "composite_ms"}. */
static int read_periphery(const cJSON *root, struct frm_cost_profile *out, const char *path, struct hl_error *err)
{
    static const char *const keys[] = {"scale", "form", "coefficients", "held_out", "fixed_cost", "composite_ms"};
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(root, "periphery");
    if (!a)
        return 0;
    int n = cJSON_IsArray(a) ? cJSON_GetArraySize(a) : -1;
    if (n < 0 || n > FRM_COST_PERIPHERY_MAX)
        return hl_fail(err, "%s: 'periphery': expected an array of at most %d layer models", path,
                       FRM_COST_PERIPHERY_MAX);
    for (int i = 0; i < n; ++i) {
        const cJSON *o = cJSON_GetArrayItem(a, i);
        struct frm_cost_periphery *p = &out->periphery[i];
        char prefix[48];
        snprintf(prefix, sizeof prefix, "'periphery'[%d]: ", i);
        if (!cJSON_IsObject(o))
            return hl_fail(err, "%s: %snot an object", path, prefix);
        if (check_keys(o, keys, 6, path, prefix, err) != 0 || read_number(o, "scale", 1, 0.0, &p->scale, path, prefix, err) ||
            read_number(o, "composite_ms", 0, 0.0, &p->composite_ms, path, prefix, err) != 0 ||
            read_model(o, 6, &p->model, path, prefix, err) != 0 ||
            read_accuracy(o, "held_out", &p->held_out, path, prefix, err) != 0 ||
            read_fixed(o, &p->fixed, path, prefix, err) != 0)
            return -1;
        int known = 0;
        for (int k = 1; k < FRM_LAYER_SCALES; ++k)
            known |= fabs(p->scale - frm_layer_scales[k]) <= 1e-9;
        for (int k = 0; k < i; ++k)
            if (fabs(out->periphery[k].scale - p->scale) <= 1e-9)
                return hl_fail(err, "%s: %s'scale': %g appears twice", path, prefix, p->scale);
        if (!known)
            return hl_fail(err, "%s: %s'scale': %g is not a periphery scale (0.75, 0.5, 0.35, 0.25)", path, prefix,
                           p->scale);
    }
    out->periphery_count = n;
    return 0;
}

/* "inset": the inset's model (frm_cost_inset), {"radius_deg", "blend_deg", "form", "coefficients",
 * "outside_ms_per_triangle", "held_out", "fixed_cost"}. */
static int read_inset(const cJSON *root, struct frm_cost_profile *out, const char *path, struct hl_error *err)
{
    static const char *const keys[] = {"radius_deg",  "blend_deg", "form",      "coefficients",
                                       "outside_ms_per_triangle", "held_out",  "fixed_cost"};
    const cJSON *o = cJSON_GetObjectItemCaseSensitive(root, "inset");
    if (!o)
        return 0;
    const char *prefix = "'inset': ";
    struct frm_cost_inset *p = &out->inset;
    if (!cJSON_IsObject(o))
        return hl_fail(err, "%s: %snot an object", path, prefix);
    if (check_keys(o, keys, 7, path, prefix, err) != 0 ||
        read_number(o, "radius_deg", 1, 0.0, &p->radius_deg, path, prefix, err) != 0 ||
        read_number(o, "blend_deg", 1, 0.0, &p->blend_deg, path, prefix, err) != 0 ||
        read_model(o, 6, &p->cost.model, path, prefix, err) != 0 ||
        read_number(o, "outside_ms_per_triangle", 1, 0.0, &p->cost.outside_ms_per_triangle, path, prefix, err) != 0 ||
        read_accuracy(o, "held_out", &p->held_out, path, prefix, err) != 0 || read_fixed(o, &p->fixed, path, prefix, err) != 0)
        return -1;
    if (!(p->radius_deg > 0.0 && p->radius_deg <= 45.0 && p->blend_deg > 0.0 && p->blend_deg <= 45.0))
        return hl_fail(err, "%s: %sexpected radius_deg and blend_deg in (0, 45]", path, prefix);
    out->inset_measured = 1;
    return 0;
}

static int read_grid(const cJSON *root, struct rnd_cost_grid *g, const char *path, struct hl_error *err)
{
    static const char *const keys[] = {"families", "levels", "coverage", "objects", "repeats", "render_scale"};
    const cJSON *o = cJSON_GetObjectItemCaseSensitive(root, "grid");
    if (!o)
        return 0;
    if (!cJSON_IsObject(o))
        return hl_fail(err, "%s: 'grid': not an object", path);
    double levels[RND_COST_GRID_MAX], objects[RND_COST_GRID_MAX], repeats = 0, families = 1;
    if (check_keys(o, keys, 6, path, "'grid': ", err) != 0 ||
        read_number(o, "families", 0, 1, &families, path, "'grid': ", err) || read_list(o, "levels", levels, &g->levels, path, err) ||
        read_list(o, "coverage", g->coverage, &g->coverages, path, err) ||
        read_list(o, "objects", objects, &g->counts, path, err) ||
        read_number(o, "repeats", 1, 1, &repeats, path, "'grid': ", err) ||
        read_number(o, "render_scale", 1, 0, &g->render_scale, path, "'grid': ", err))
        return -1;
    for (int i = 0; i < g->levels; ++i)
        g->level[i] = (uint32_t)fmin(levels[i], 255);
    for (int i = 0; i < g->counts; ++i)
        g->objects[i] = (uint32_t)fmin(objects[i], 1e9);
    g->repeats = (int)fmin(repeats, 1e6);
    g->families = (int)fmin(families, 2);
    g->periphery_scale = 1.0; /* the main model's grid: plain frames */
    return 0;
}

int frm_cost_profile_read(const char *path, struct frm_cost_profile *out, struct hl_error *err)
{
    static const char *const keys[] = {"format", "label", "form", "coefficients", "renderer", "display", "eye_px",
                                       "held_out", "held_out_other_form", "grid", "date", "commit",
                                       "load_average_1min", "fixed_cost", "periphery", "inset"};
    memset(out, 0, sizeof *out);
    char *text = read_text(path, err);
    if (!text)
        return -1;
    const char *end = NULL;
    uint64_t failed_before = hl_lib_alloc_failures();
    cJSON *root = cJSON_ParseWithOpts(text, &end, 1);
    int rc = -1;
    if (!root && hl_lib_alloc_failures() != failed_before) {
        hl_fail(err, "%s: out of memory parsing the JSON", path);
        goto done;
    }
    if (!root) {
        hl_fail(err, "%s: not valid JSON near byte %td", path, end ? end - text : 0);
        goto done;
    }
    if (!cJSON_IsObject(root)) {
        hl_fail(err, "%s: expected a JSON object", path);
        goto done;
    }
    char format[64] = "";
    if (check_keys(root, keys, (int)(sizeof keys / sizeof keys[0]), path, "", err) != 0 ||
        read_string(root, "format", 1, format, sizeof format, path, err) != 0)
        goto done;
    int coefficients = !strcmp(format, COST_FORMAT_TAG) || !strcmp(format, COST_FORMAT_TAG_V2) ? 6
                       : !strcmp(format, COST_FORMAT_TAG_V1)                                    ? 5
                                                                                                : 0;
    if (!coefficients) {
        hl_fail(err, "%s: 'format': '%s' is not " COST_FORMAT_TAG " (or " COST_FORMAT_TAG_V2 ", " COST_FORMAT_TAG_V1 ")",
                path, format);
        goto done;
    }
    if (read_model(root, coefficients, &out->model, path, "", err) != 0)
        goto done;
    if (read_string(root, "renderer", 1, out->renderer, sizeof out->renderer, path, err) != 0 ||
        read_string(root, "label", 0, out->label, sizeof out->label, path, err) != 0 ||
        read_string(root, "display", 0, out->display, sizeof out->display, path, err) != 0 ||
        read_string(root, "date", 0, out->date, sizeof out->date, path, err) != 0 ||
        read_string(root, "commit", 0, out->commit, sizeof out->commit, path, err) != 0 ||
        read_accuracy(root, "held_out", &out->held_out, path, "", err) != 0 ||
        read_accuracy(root, "held_out_other_form", &out->held_out_other, path, "", err) != 0 ||
        read_fixed(root, &out->fixed, path, "", err) != 0 || read_grid(root, &out->grid, path, err) != 0 ||
        read_periphery(root, out, path, err) != 0 || read_inset(root, out, path, err) != 0)
        goto done;
    if (strcmp(format, COST_FORMAT_TAG) != 0) { /* said wherever the label is shown (summary, report) */
        size_t len = strlen(out->label);
        snprintf(out->label + len, sizeof out->label - len,
                 "%s[%s: pixel terms fitted per bounding-disc pixel, before fill factors; recalibrate]",
                 len ? " " : "", format);
    }
    out->load_before = out->load_after = -1;
    const cJSON *load = cJSON_GetObjectItemCaseSensitive(root, "load_average_1min");
    if (load) {
        const cJSON *l0 = cJSON_GetArrayItem(load, 0), *l1 = cJSON_GetArrayItem(load, 1);
        if (!cJSON_IsArray(load) || cJSON_GetArraySize(load) != 2 || !cJSON_IsNumber(l0) || !cJSON_IsNumber(l1) ||
            !(l0->valuedouble >= 0 && l0->valuedouble < 1e6) || !(l1->valuedouble >= 0 && l1->valuedouble < 1e6)) {
            hl_fail(err, "%s: 'load_average_1min': expected two load averages ≥ 0 (before, after)", path);
            goto done;
        }
        out->load_before = l0->valuedouble, out->load_after = l1->valuedouble;
    }
    const cJSON *px = cJSON_GetObjectItemCaseSensitive(root, "eye_px");
    if (px) {
        const cJSON *w = cJSON_GetArrayItem(px, 0), *h = cJSON_GetArrayItem(px, 1);
        if (!cJSON_IsArray(px) || cJSON_GetArraySize(px) != 2 || !cJSON_IsNumber(w) || !cJSON_IsNumber(h) ||
            !(w->valuedouble >= 1 && w->valuedouble <= 65536) || !(h->valuedouble >= 1 && h->valuedouble <= 65536)) {
            hl_fail(err, "%s: 'eye_px': expected two pixel counts in 1…65536", path);
            goto done;
        }
        out->eye_width_px = (int)w->valuedouble, out->eye_height_px = (int)h->valuedouble;
    }
    rc = 0;
done:
    cJSON_Delete(root);
    free(text);
    if (rc != 0)
        memset(out, 0, sizeof *out);
    return rc;
}

/* ---- writing --------------------------------------------------------------------------------- */

static cJSON *accuracy_json(const struct frm_cost_accuracy *a)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "frames", a->frames);
    cJSON_AddNumberToObject(o, "median_rel", a->median_rel);
    cJSON_AddNumberToObject(o, "p95_rel", a->p95_rel);
    cJSON_AddNumberToObject(o, "under5_share", a->under5_share);
    return o;
}

static int check_model(const struct lod_cost_model *model, const char *path, struct hl_error *err)
{
    if (!frm_cost_form_name(model->form))
        return hl_fail(err, "%s: unknown cost form %d", path, (int)model->form);
    struct lod_cost_model m = *model;
    for (int i = 0; i < 6; ++i)
        if (!isfinite(*coefficient(&m, i)) || *coefficient(&m, i) < 0)
            return hl_fail(err, "%s: coefficient %s = %g is not finite and ≥ 0", path, coefficient_keys[i],
                           *coefficient(&m, i));
    return 0;
}

static void add_model(cJSON *obj, const struct lod_cost_model *model)
{
    struct lod_cost_model m = *model;
    cJSON_AddStringToObject(obj, "form", frm_cost_form_name(m.form));
    cJSON *co = cJSON_AddObjectToObject(obj, "coefficients");
    for (int i = 0; i < 6; ++i)
        cJSON_AddNumberToObject(co, coefficient_keys[i], *coefficient(&m, i));
}

static void add_fixed(cJSON *obj, const struct frm_cost_fixed *fx)
{
    if (!fx->frames)
        return;
    cJSON *fo = cJSON_AddObjectToObject(obj, "fixed_cost");
    cJSON_AddNumberToObject(fo, "frames", fx->frames);
    cJSON_AddNumberToObject(fo, "median_ms", fx->median_ms);
    cJSON_AddNumberToObject(fo, "p25_ms", fx->p25_ms);
    cJSON_AddNumberToObject(fo, "p75_ms", fx->p75_ms);
}

int frm_cost_profile_write(const char *path, const struct frm_cost_profile *p, struct hl_error *err)
{
    if (check_model(&p->model, path, err) != 0)
        return -1;
    if (p->periphery_count < 0 || p->periphery_count > FRM_COST_PERIPHERY_MAX)
        return hl_fail(err, "%s: %d periphery models (at most %d)", path, p->periphery_count, FRM_COST_PERIPHERY_MAX);
    for (int i = 0; i < p->periphery_count; ++i)
        if (check_model(&p->periphery[i].model, path, err) != 0)
            return -1;
    if (p->inset_measured && check_model(&p->inset.cost.model, path, err) != 0)
        return -1;
    if (p->inset_measured && !(p->inset.cost.outside_ms_per_triangle >= 0.0 &&
                               isfinite(p->inset.cost.outside_ms_per_triangle)))
        return hl_fail(err, "%s: 'inset': 'outside_ms_per_triangle': %g is negative or not finite", path,
                       p->inset.cost.outside_ms_per_triangle);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "format", COST_FORMAT_TAG);
    cJSON_AddStringToObject(root, "label", p->label);
    add_model(root, &p->model);
    cJSON_AddStringToObject(root, "renderer", p->renderer);
    if (p->display[0])
        cJSON_AddStringToObject(root, "display", p->display);
    if (p->eye_width_px > 0 && p->eye_height_px > 0) {
        int px[2] = {p->eye_width_px, p->eye_height_px};
        cJSON_AddItemToObject(root, "eye_px", cJSON_CreateIntArray(px, 2));
    }
    if (p->held_out.frames)
        cJSON_AddItemToObject(root, "held_out", accuracy_json(&p->held_out));
    if (p->held_out_other.frames)
        cJSON_AddItemToObject(root, "held_out_other_form", accuracy_json(&p->held_out_other));
    add_fixed(root, &p->fixed);
    if (p->periphery_count > 0) {
        cJSON *a = cJSON_AddArrayToObject(root, "periphery");
        for (int i = 0; i < p->periphery_count; ++i) {
            cJSON *o = cJSON_CreateObject();
            cJSON_AddNumberToObject(o, "scale", p->periphery[i].scale);
            add_model(o, &p->periphery[i].model);
            if (p->periphery[i].held_out.frames)
                cJSON_AddItemToObject(o, "held_out", accuracy_json(&p->periphery[i].held_out));
            add_fixed(o, &p->periphery[i].fixed);
            if (p->periphery[i].composite_ms > 0.0)
                cJSON_AddNumberToObject(o, "composite_ms", p->periphery[i].composite_ms);
            cJSON_AddItemToArray(a, o);
        }
    }
    if (p->inset_measured) {
        cJSON *o = cJSON_AddObjectToObject(root, "inset");
        cJSON_AddNumberToObject(o, "radius_deg", p->inset.radius_deg);
        cJSON_AddNumberToObject(o, "blend_deg", p->inset.blend_deg);
        add_model(o, &p->inset.cost.model);
        cJSON_AddNumberToObject(o, "outside_ms_per_triangle", p->inset.cost.outside_ms_per_triangle);
        if (p->inset.held_out.frames)
            cJSON_AddItemToObject(o, "held_out", accuracy_json(&p->inset.held_out));
        add_fixed(o, &p->inset.fixed);
    }
    if (p->grid.repeats > 0) {
        const struct rnd_cost_grid *g = &p->grid;
        cJSON *go = cJSON_AddObjectToObject(root, "grid");
        cJSON_AddNumberToObject(go, "families", g->families);
        double levels[RND_COST_GRID_MAX], objects[RND_COST_GRID_MAX];
        for (int i = 0; i < g->levels; ++i)
            levels[i] = g->level[i];
        for (int i = 0; i < g->counts; ++i)
            objects[i] = g->objects[i];
        cJSON_AddItemToObject(go, "levels", cJSON_CreateDoubleArray(levels, g->levels));
        cJSON_AddItemToObject(go, "coverage", cJSON_CreateDoubleArray(g->coverage, g->coverages));
        cJSON_AddItemToObject(go, "objects", cJSON_CreateDoubleArray(objects, g->counts));
        cJSON_AddNumberToObject(go, "repeats", g->repeats);
        cJSON_AddNumberToObject(go, "render_scale", g->render_scale);
    }
    if (p->load_before >= 0 && p->load_after >= 0) {
        double load[2] = {p->load_before, p->load_after};
        cJSON_AddItemToObject(root, "load_average_1min", cJSON_CreateDoubleArray(load, 2));
    }
    if (p->date[0])
        cJSON_AddStringToObject(root, "date", p->date);
    if (p->commit[0])
        cJSON_AddStringToObject(root, "commit", p->commit);
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    if (!text)
        return hl_fail(err, "%s: out of memory", path);
    size_t n = strlen(text);
    text[n] = '\n'; /* the NUL becomes the final newline: written by length */
    int rc = hl_out_write_all(path, text, n + 1, err);
    free(text);
    return rc;
}

/* ---- the built-in reference ------------------------------------------------------------------- */

void frm_cost_profile_builtin_llvmpipe(struct frm_cost_profile *out)
{
    memset(out, 0, sizeof *out);
    /* Measured by `hmdlod calibrate --out …` (default grid, seed 1, Vive, render scale 1) on the
     * 2-core development machine, nothing else running (load average 0.81 before, from this
     * session's previous command; 1.46 after), with the pixel terms on fragments (the bound's pixels
     * × the level's fill, scn_lod_fill) and every timed frame after a settling frame of the same
     * point: docs/RESULTS.md "Cost model". The host ran about twice as slow per triangle as on
     * 2026-12-04 (c1 0.075 against 0.039 µs), its empty frame scattered 0.90 … 1.79 ms (quartiles):
     * the online correction (frm_select) takes the day's machine from there. c0 is the measured median
     * of the empty frames; the objects' terms are the expectile fit (τ 0.98) on top of it. The
     * additive form was kept (held-out p95 49.7 % against the max form's 61.5 %). */
    out->model = (struct lod_cost_model){LOD_COST_ADDITIVE, 1.108178, 7.4831203272229766e-05, 0,
                                         3.9492098666021255e-06, 0.00818027805386367, 6.7372019070591763e-05};
    out->held_out = (struct frm_cost_accuracy){0.211515493051743, 0.49660506022009843, 0.04, 50};
    out->held_out_other = (struct frm_cost_accuracy){0.22588565092886848, 0.6149975419863728, 0.08, 50};
    out->fixed = (struct frm_cost_fixed){1.108178, 0.90462, 1.792979, 182};
    snprintf(out->label, sizeof out->label,
             "built-in llvmpipe reference (2-core, measured 2026-12-05, c0 measured, fragments, expectile 0.98)");
    snprintf(out->renderer, sizeof out->renderer, "llvmpipe (LLVM 15.0.6, 256 bits)");
    snprintf(out->display, sizeof out->display, "vive");
    out->eye_width_px = 1080, out->eye_height_px = 1200;
    snprintf(out->date, sizeof out->date, "2026-12-05 12:26 UTC");
    snprintf(out->commit, sizeof out->commit, "94331fa + fill factors");
    out->load_before = 0.81, out->load_after = 1.46;
    rnd_cost_grid_default(&out->grid, 0);
}
