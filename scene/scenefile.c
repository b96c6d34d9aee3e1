/* Scene files (docs/scene-format.md): strict reading with cJSON, like the display profiles. Every
 * error names the file and the JSON path of the offending value ("scene.json: instances[3].mesh: no
 * mesh named \"chair\""); unknown and duplicate keys are errors; numbers must be finite. This file
 * reads and checks; scenefile_build.c turns the result into a scene. */
#include "scene/scenefile_internal.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define SF_MAX_BYTES (256 * 1024 * 1024)
enum { SF_MAX_ITEMS = 10000000 };

/* cJSON allocates through base's counting hooks, so a parse that fails for want of memory is told from
 * bad text (base.h, "allocation in libraries"). */
__attribute__((constructor)) static void scenefile_json_hooks(void)
{
    cJSON_Hooks hooks = {hl_lib_malloc, hl_lib_free};
    cJSON_InitHooks(&hooks);
}

void sf_file_free(struct sf_file *f)
{
    free(f->meshes);
    free(f->instances);
    free(f->groups);
    free(f->owner);
    free(f->member_order);
    free(f->motions);
    memset(f, 0, sizeof *f);
}

static char *sf_read_all(const char *path, size_t *len_out, struct hl_error *err)
{
    char *buf = NULL;
    return hl_file_read_all(path, SF_MAX_BYTES, &buf, len_out, err) == 0 ? buf : NULL;
}

/* Line and column (1-based) of byte `offset` in text. */
static void sf_line_col(const char *text, size_t offset, int *line, int *col)
{
    *line = 1, *col = 1;
    for (size_t i = 0; i < offset && text[i]; ++i) {
        if (text[i] == '\n')
            ++*line, *col = 1;
        else
            ++*col;
    }
}

/* The members of object `obj` at `where`, by name: unknown keys and duplicates are errors. */
static int sf_members(const char *file, const char *where, const cJSON *obj, const char *const *keys, int n,
                      const cJSON **out, struct hl_error *err)
{
    if (!cJSON_IsObject(obj))
        return hl_fail(err, "%s: %s: expected an object", file, where);
    for (int i = 0; i < n; ++i)
        out[i] = NULL;
    for (const cJSON *c = obj->child; c; c = c->next) {
        int k = -1;
        for (int i = 0; i < n; ++i)
            if (c->string && strcmp(c->string, keys[i]) == 0)
                k = i;
        if (k < 0) {
            char known[256] = "";
            for (int i = 0; i < n; ++i)
                snprintf(known + strlen(known), sizeof known - strlen(known), "%s%s", i ? ", " : "", keys[i]);
            return hl_fail(err, "%s: %s%s%.40s: unknown key (known: %s)", file, where, *where ? "." : "",
                           c->string ? c->string : "", known);
        }
        if (out[k])
            return hl_fail(err, "%s: %s%s%s: duplicate key", file, where, *where ? "." : "", keys[k]);
        out[k] = c;
    }
    return 0;
}

static int sf_number(const char *file, const char *where, const cJSON *item, double lo, double hi, double *out,
                     struct hl_error *err)
{
    if (!cJSON_IsNumber(item))
        return hl_fail(err, "%s: %s: expected a number", file, where);
    double v = item->valuedouble;
    if (!isfinite(v) || !(v >= lo && v <= hi))
        return hl_fail(err, "%s: %s: %g is not a finite number in [%g, %g]", file, where, v, lo, hi);
    *out = v;
    return 0;
}

static int sf_vec(const char *file, const char *where, const cJSON *item, int n, double lo, double hi,
                  double *out, struct hl_error *err)
{
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != n)
        return hl_fail(err, "%s: %s: expected an array of %d numbers", file, where, n);
    int i = 0;
    for (const cJSON *c = item->child; c; c = c->next, ++i) {
        char w[SF_WHERE_MAX + 16];
        snprintf(w, sizeof w, "%s[%d]", where, i);
        if (sf_number(file, w, c, lo, hi, &out[i], err) != 0)
            return -1;
    }
    return 0;
}

static int sf_name(const char *file, const char *where, const cJSON *item, char *dst, struct hl_error *err)
{
    if (!cJSON_IsString(item) || !item->valuestring)
        return hl_fail(err, "%s: %s: expected a string", file, where);
    size_t n = strlen(item->valuestring);
    if (n == 0 || n >= SCN_NAME_MAX)
        return hl_fail(err, "%s: %s: a name must have 1 to %d bytes", file, where, SCN_NAME_MAX - 1);
    memcpy(dst, item->valuestring, n + 1);
    return 0;
}

/* ---- meshes ------------------------------------------------------------------------------------ */

static int sf_read_mesh(struct sf_file *f, const char *dir, const cJSON *entry, struct sf_mesh *m,
                        struct hl_error *err)
{
    static const char *const keys[] = {"path", "builtin", "size_m", "recenter"};
    const cJSON *v[4];
    if (sf_members(f->file, m->where, entry, keys, 4, v, err) != 0)
        return -1;
    if (v[3]) {
        if (!cJSON_IsBool(v[3]))
            return hl_fail(err, "%s: %s.recenter: expected true or false", f->file, m->where);
        if (!v[0])
            return hl_fail(err, "%s: %s.recenter: only a mesh file can be recentred", f->file, m->where);
        m->recenter = cJSON_IsTrue(v[3]);
    }
    char w[SF_WHERE_MAX + 16];
    if (!!v[0] == !!v[1])
        return hl_fail(err, "%s: %s: give exactly one of \"path\" (a mesh or .lod file) and \"builtin\"", f->file,
                       m->where);
    if (v[0]) {
        snprintf(w, sizeof w, "%s.path", m->where);
        if (!cJSON_IsString(v[0]) || !v[0]->valuestring || !v[0]->valuestring[0])
            return hl_fail(err, "%s: %s: expected a non-empty string", f->file, w);
        const char *given = v[0]->valuestring;
        size_t n = strlen(given);
        if (n >= sizeof m->given || strlen(dir) + n + 2 > sizeof m->path)
            return hl_fail(err, "%s: %s: path too long", f->file, w);
        memcpy(m->given, given, n + 1);
        /* Relative to the scene file's folder, so a scene and its meshes move together. */
        if (given[0] == '/' || !dir[0])
            snprintf(m->path, sizeof m->path, "%s", given);
        else
            snprintf(m->path, sizeof m->path, "%s/%s", dir, given);
        m->builtin = SF_FILE;
        if (v[2])
            return hl_fail(err, "%s: %s.size_m: only a builtin box has a size", f->file, m->where);
        return 0;
    }
    snprintf(w, sizeof w, "%s.builtin", m->where);
    static const char *const builtins[] = {"field-object", "chair", "box"};
    const char *b = cJSON_IsString(v[1]) ? v[1]->valuestring : NULL;
    m->builtin = SF_FILE;
    for (int i = 0; b && i < 3; ++i)
        if (strcmp(b, builtins[i]) == 0)
            m->builtin = (enum sf_builtin)(SF_FIELD_OBJECT + i);
    if (m->builtin == SF_FILE)
        return hl_fail(err, "%s: %s: expected one of \"field-object\", \"chair\", \"box\"", f->file, w);
    if (m->builtin == SF_BOX) {
        snprintf(w, sizeof w, "%s.size_m", m->where);
        if (!v[2])
            return hl_fail(err, "%s: %s: missing (a box needs its [x, y, z] size in metres)", f->file, w);
        if (sf_vec(f->file, w, v[2], 3, 1e-6, 1e6, m->size_m, err) != 0)
            return -1;
    } else if (v[2]) {
        return hl_fail(err, "%s: %s.size_m: only a builtin box has a size", f->file, m->where);
    }
    return 0;
}

static uint32_t sf_find_mesh(const struct sf_file *f, const char *name)
{
    for (uint32_t i = 0; i < f->mesh_count; ++i)
        if (strcmp(f->meshes[i].name, name) == 0)
            return i;
    return SCN_NONE;
}

static int sf_mesh_ref(const struct sf_file *f, const char *where, const cJSON *item, uint32_t *out,
                       struct hl_error *err)
{
    if (!cJSON_IsString(item) || !item->valuestring)
        return hl_fail(err, "%s: %s: expected a mesh name (a string)", f->file, where);
    *out = sf_find_mesh(f, item->valuestring);
    if (*out == SCN_NONE)
        return hl_fail(err, "%s: %s: no mesh named \"%.40s\"", f->file, where, item->valuestring);
    return 0;
}

/* ---- motion ------------------------------------------------------------------------------------ */

static int sf_motion(struct sf_file *f, const char *where, const cJSON *item, uint32_t *out, struct hl_error *err)
{
    char path[SF_PATH_MAX + SF_WHERE_MAX];
    snprintf(path, sizeof path, "%s: %s", f->file, where);
    struct scn_motion m;
    if (scn_motion_parse(item, path, &m, err) != 0)
        return -1;
    void *grown = realloc(f->motions, (f->motion_count + 1) * sizeof *f->motions);
    if (!grown)
        return hl_fail(err, "%s: %s: out of memory", f->file, where);
    f->motions = grown;
    f->motions[f->motion_count] = m;
    *out = f->motion_count++;
    return 0;
}

/* ---- instances ----------------------------------------------------------------------------------- */

/* Yaw about +Y, then pitch about +X, then roll about −Z, intrinsic (the head convention of the
 * traces: yaw turns left, pitch looks up, roll tilts right): q = q_yaw ⊗ q_pitch ⊗ q_roll. */
static hl_quatd sf_yaw_pitch_roll(const double ypr_deg[3])
{
    hl_quatd yaw = hl_q_from_axis_angle(hl_v3(0, 1, 0), ypr_deg[0] * HL_RAD_PER_DEG);
    hl_quatd pitch = hl_q_from_axis_angle(hl_v3(1, 0, 0), ypr_deg[1] * HL_RAD_PER_DEG);
    hl_quatd roll = hl_q_from_axis_angle(hl_v3(0, 0, -1), ypr_deg[2] * HL_RAD_PER_DEG);
    return hl_q_normalize(hl_q_mul(yaw, hl_q_mul(pitch, roll)));
}

static int sf_read_instance(struct sf_file *f, const char *where, const cJSON *entry, struct sf_instance *in,
                            struct hl_error *err)
{
    static const char *const keys[] = {"name", "mesh", "position_m", "yaw_pitch_roll_deg", "scale",
                                       "color", "importance", "motion"};
    enum { K_NAME, K_MESH, K_POS, K_YPR, K_SCALE, K_COLOR, K_IMPORTANCE, K_MOTION, K_COUNT };
    const cJSON *v[K_COUNT];
    if (sf_members(f->file, where, entry, keys, K_COUNT, v, err) != 0)
        return -1;
    char w[SF_WHERE_MAX + 32];
    *in = (struct sf_instance){.rotation = hl_q_identity(), .scale = 1.0, .importance = 1.0,
                               .color = {0.7f, 0.7f, 0.7f}, .motion = SCN_NONE};
    if (v[K_NAME]) {
        snprintf(w, sizeof w, "%s.name", where);
        if (sf_name(f->file, w, v[K_NAME], in->name, err) != 0)
            return -1;
    }
    snprintf(w, sizeof w, "%s.mesh", where);
    if (!v[K_MESH])
        return hl_fail(err, "%s: %s: missing (required)", f->file, w);
    if (sf_mesh_ref(f, w, v[K_MESH], &in->mesh, err) != 0)
        return -1;
    snprintf(w, sizeof w, "%s.position_m", where);
    if (!v[K_POS])
        return hl_fail(err, "%s: %s: missing (required)", f->file, w);
    double p[3];
    if (sf_vec(f->file, w, v[K_POS], 3, -1e9, 1e9, p, err) != 0)
        return -1;
    in->position_m = hl_v3(p[0], p[1], p[2]);
    if (v[K_YPR]) {
        snprintf(w, sizeof w, "%s.yaw_pitch_roll_deg", where);
        double ypr[3];
        if (sf_vec(f->file, w, v[K_YPR], 3, -3600, 3600, ypr, err) != 0)
            return -1;
        in->rotation = sf_yaw_pitch_roll(ypr);
    }
    if (v[K_SCALE]) {
        snprintf(w, sizeof w, "%s.scale", where);
        if (sf_number(f->file, w, v[K_SCALE], -HUGE_VAL, HUGE_VAL, &in->scale, err) != 0)
            return -1;
        if (!(in->scale > 0.0 && in->scale <= 1e6))
            return hl_fail(err, "%s: %s: %g is not in (0, 1e6]", f->file, w, in->scale);
    }
    if (v[K_COLOR]) {
        snprintf(w, sizeof w, "%s.color", where);
        double c[3];
        if (sf_vec(f->file, w, v[K_COLOR], 3, 0.0, 1.0, c, err) != 0)
            return -1;
        for (int k = 0; k < 3; ++k)
            in->color[k] = (float)c[k];
    }
    if (v[K_IMPORTANCE]) {
        snprintf(w, sizeof w, "%s.importance", where);
        if (sf_number(f->file, w, v[K_IMPORTANCE], 0.0, 1e6, &in->importance, err) != 0)
            return -1;
    }
    if (v[K_MOTION]) {
        snprintf(w, sizeof w, "%s.motion", where);
        if (sf_motion(f, w, v[K_MOTION], &in->motion, err) != 0)
            return -1;
    }
    return 0;
}

/* Instances by name, for the groups' lists: indices sorted by name, searched by bisection. */
static const struct sf_instance *sf_sort_base;
static int sf_cmp_instance(const void *a, const void *b)
{
    return strcmp(sf_sort_base[*(const uint32_t *)a].name, sf_sort_base[*(const uint32_t *)b].name);
}

static uint32_t sf_find_instance(const struct sf_file *f, const uint32_t *sorted, uint32_t named, const char *name)
{
    uint32_t lo = 0, hi = named;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        int c = strcmp(f->instances[sorted[mid]].name, name);
        if (c == 0)
            return sorted[mid];
        if (c < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return SCN_NONE;
}

/* ---- groups ------------------------------------------------------------------------------------ */

static uint32_t sf_find_group(const struct sf_file *f, const char *name)
{
    for (uint32_t i = 0; i < f->group_count; ++i)
        if (strcmp(f->groups[i].name, name) == 0)
            return i;
    return SCN_NONE;
}

static int sf_set_parent(struct sf_file *f, const char *where, uint32_t child, uint32_t parent, struct hl_error *err)
{
    struct sf_group *c = &f->groups[child];
    if (child == parent)
        return hl_fail(err, "%s: %s: group \"%s\" cannot contain itself (a cycle in the hierarchy)", f->file,
                       where, c->name);
    if (c->parent != SCN_NONE && c->parent != parent)
        return hl_fail(err, "%s: %s: group \"%s\" already has the parent \"%s\"; a group has one parent", f->file,
                       where, c->name, f->groups[c->parent].name);
    c->parent = parent;
    return 0;
}

static int sf_read_group(struct sf_file *f, uint32_t g, const char *where, const cJSON *entry,
                         const uint32_t *sorted, uint32_t named, struct hl_error *err)
{
    static const char *const keys[] = {"name", "parent", "children", "instances", "impostor", "importance",
                                       "motion"};
    enum { K_NAME, K_PARENT, K_CHILDREN, K_INSTANCES, K_IMPOSTOR, K_IMPORTANCE, K_MOTION, K_COUNT };
    const cJSON *v[K_COUNT];
    if (sf_members(f->file, where, entry, keys, K_COUNT, v, err) != 0)
        return -1;
    struct sf_group *gr = &f->groups[g];
    char w[SF_WHERE_MAX + 48];
    if (v[K_PARENT]) {
        snprintf(w, sizeof w, "%s.parent", where);
        if (!cJSON_IsString(v[K_PARENT]) || !v[K_PARENT]->valuestring)
            return hl_fail(err, "%s: %s: expected a group name (a string)", f->file, w);
        uint32_t p = sf_find_group(f, v[K_PARENT]->valuestring);
        if (p == SCN_NONE)
            return hl_fail(err, "%s: %s: no group named \"%.40s\"", f->file, w, v[K_PARENT]->valuestring);
        if (sf_set_parent(f, w, g, p, err) != 0)
            return -1;
    }
    if (v[K_CHILDREN]) {
        snprintf(w, sizeof w, "%s.children", where);
        if (!cJSON_IsArray(v[K_CHILDREN]))
            return hl_fail(err, "%s: %s: expected an array of group names", f->file, w);
        int k = 0;
        for (const cJSON *c = v[K_CHILDREN]->child; c; c = c->next, ++k) {
            snprintf(w, sizeof w, "%s.children[%d]", where, k);
            if (!cJSON_IsString(c) || !c->valuestring)
                return hl_fail(err, "%s: %s: expected a group name (a string)", f->file, w);
            uint32_t ch = sf_find_group(f, c->valuestring);
            if (ch == SCN_NONE)
                return hl_fail(err, "%s: %s: no group named \"%.40s\"", f->file, w, c->valuestring);
            if (sf_set_parent(f, w, ch, g, err) != 0)
                return -1;
        }
    }
    if (v[K_INSTANCES]) {
        snprintf(w, sizeof w, "%s.instances", where);
        if (!cJSON_IsArray(v[K_INSTANCES]))
            return hl_fail(err, "%s: %s: expected an array of instance names or indices", f->file, w);
        uint32_t k = 0;
        for (const cJSON *c = v[K_INSTANCES]->child; c; c = c->next, ++k) {
            snprintf(w, sizeof w, "%s.instances[%u]", where, k);
            uint32_t i = SCN_NONE;
            if (cJSON_IsString(c) && c->valuestring) {
                i = sf_find_instance(f, sorted, named, c->valuestring);
                if (i == SCN_NONE)
                    return hl_fail(err, "%s: %s: no instance named \"%.40s\"", f->file, w, c->valuestring);
            } else if (cJSON_IsNumber(c)) {
                double d = c->valuedouble;
                if (!(d >= 0 && d < f->instance_count && d == floor(d)))
                    return hl_fail(err, "%s: %s: %g is not an instance index (0…%u)", f->file, w, d,
                                   f->instance_count ? f->instance_count - 1 : 0);
                i = (uint32_t)d;
            } else {
                return hl_fail(err, "%s: %s: expected an instance name or index", f->file, w);
            }
            if (f->owner[i] != SCN_NONE)
                return hl_fail(err, "%s: %s: instances[%u] is already in group \"%s\"; an instance is in one group",
                               f->file, w, i, f->groups[f->owner[i]].name);
            f->owner[i] = g;
            f->member_order[i] = k;
        }
    }
    if (v[K_IMPOSTOR]) {
        snprintf(w, sizeof w, "%s.impostor", where);
        if (sf_mesh_ref(f, w, v[K_IMPOSTOR], &gr->impostor_mesh, err) != 0)
            return -1;
    }
    if (v[K_IMPORTANCE]) {
        snprintf(w, sizeof w, "%s.importance", where);
        if (sf_number(f->file, w, v[K_IMPORTANCE], 0.0, 1e6, &gr->importance, err) != 0)
            return -1;
    }
    if (v[K_MOTION]) {
        snprintf(w, sizeof w, "%s.motion", where);
        if (sf_motion(f, w, v[K_MOTION], &gr->motion, err) != 0)
            return -1;
    }
    return 0;
}

/* A parent chain that never reaches a root is a cycle: named in full so it can be broken. */
static int sf_check_cycles(const struct sf_file *f, struct hl_error *err)
{
    for (uint32_t g = 0; g < f->group_count; ++g) {
        uint32_t p = f->groups[g].parent, steps = 0;
        while (p != SCN_NONE && p != g && steps <= f->group_count)
            p = f->groups[p].parent, ++steps;
        if (p != g)
            continue;
        char chain[512];
        int len = snprintf(chain, sizeof chain, "%s", f->groups[g].name);
        for (p = f->groups[g].parent; len < (int)sizeof chain - 8; p = f->groups[p].parent) {
            len += snprintf(chain + len, sizeof chain - (size_t)len, " -> %s", f->groups[p].name);
            if (p == g)
                break;
        }
        return hl_fail(err, "%s: groups[%u].parent: the hierarchy has a cycle: %s (each is the parent of the one before)",
                       f->file, g, chain);
    }
    return 0;
}

/* ---- the file ---------------------------------------------------------------------------------- */

static int sf_read_root(struct sf_file *f, const char *dir, const cJSON *root, struct hl_error *err)
{
    static const char *const keys[] = {"version", "name", "description", "meshes", "instances", "groups"};
    enum { K_VERSION, K_NAME, K_DESCRIPTION, K_MESHES, K_INSTANCES, K_GROUPS, K_COUNT };
    const cJSON *v[K_COUNT];
    if (!cJSON_IsObject(root))
        return hl_fail(err, "%s: expected a JSON object at the top level", f->file);
    if (sf_members(f->file, "", root, keys, K_COUNT, v, err) != 0)
        return -1;
    double version;
    if (!v[K_VERSION])
        return hl_fail(err, "%s: version: missing (required; this reader knows version 1)", f->file);
    if (sf_number(f->file, "version", v[K_VERSION], -HUGE_VAL, HUGE_VAL, &version, err) != 0)
        return -1;
    if (version != 1.0)
        return hl_fail(err, "%s: version: %g is not a version this reader knows (1)", f->file, version);
    if (v[K_NAME] && sf_name(f->file, "name", v[K_NAME], f->name, err) != 0)
        return -1;
    if (v[K_DESCRIPTION] && !cJSON_IsString(v[K_DESCRIPTION]))
        return hl_fail(err, "%s: description: expected a string", f->file);

    /* meshes: an object, name → entry */
    if (!v[K_MESHES])
        return hl_fail(err, "%s: meshes: missing (required)", f->file);
    if (!cJSON_IsObject(v[K_MESHES]))
        return hl_fail(err, "%s: meshes: expected an object (name → mesh)", f->file);
    int nm = cJSON_GetArraySize(v[K_MESHES]);
    if (nm < 1 || nm > 65536)
        return hl_fail(err, "%s: meshes: expected 1 to 65536 meshes", f->file);
    f->meshes = calloc((size_t)nm, sizeof *f->meshes);
    if (!f->meshes)
        return hl_fail(err, "%s: out of memory", f->file);
    for (const cJSON *c = v[K_MESHES]->child; c; c = c->next) {
        struct sf_mesh *m = &f->meshes[f->mesh_count];
        snprintf(m->where, sizeof m->where, "meshes.%.100s", c->string ? c->string : "");
        size_t name_len = c->string ? strlen(c->string) : 0;
        if (name_len == 0 || name_len >= SCN_NAME_MAX)
            return hl_fail(err, "%s: %s: a mesh name must have 1 to %d bytes", f->file, m->where, SCN_NAME_MAX - 1);
        memcpy(m->name, c->string, name_len + 1);
        if (sf_find_mesh(f, m->name) != SCN_NONE)
            return hl_fail(err, "%s: %s: duplicate key", f->file, m->where);
        if (sf_read_mesh(f, dir, c, m, err) != 0)
            return -1;
        f->mesh_count++;
    }

    /* instances: an array */
    if (!v[K_INSTANCES])
        return hl_fail(err, "%s: instances: missing (required)", f->file);
    if (!cJSON_IsArray(v[K_INSTANCES]))
        return hl_fail(err, "%s: instances: expected an array", f->file);
    int ni = cJSON_GetArraySize(v[K_INSTANCES]);
    if (ni < 1 || ni > SF_MAX_ITEMS)
        return hl_fail(err, "%s: instances: expected 1 to %d instances", f->file, SF_MAX_ITEMS);
    f->instances = calloc((size_t)ni, sizeof *f->instances);
    f->owner = malloc((size_t)ni * sizeof *f->owner);
    f->member_order = calloc((size_t)ni, sizeof *f->member_order);
    uint32_t *sorted = malloc((size_t)ni * sizeof *sorted);
    if (!f->instances || !f->owner || !f->member_order || !sorted) {
        free(sorted);
        return hl_fail(err, "%s: out of memory for %d instances", f->file, ni);
    }
    uint32_t named = 0;
    for (const cJSON *c = v[K_INSTANCES]->child; c; c = c->next) {
        char where[64];
        snprintf(where, sizeof where, "instances[%u]", f->instance_count);
        if (sf_read_instance(f, where, c, &f->instances[f->instance_count], err) != 0) {
            free(sorted);
            return -1;
        }
        f->owner[f->instance_count] = SCN_NONE;
        if (f->instances[f->instance_count].name[0])
            sorted[named++] = f->instance_count;
        f->instance_count++;
    }
    sf_sort_base = f->instances;
    qsort(sorted, named, sizeof *sorted, sf_cmp_instance);
    for (uint32_t k = 1; k < named; ++k)
        if (strcmp(f->instances[sorted[k - 1]].name, f->instances[sorted[k]].name) == 0) {
            uint32_t a = sorted[k - 1] < sorted[k] ? sorted[k - 1] : sorted[k];
            uint32_t b = sorted[k - 1] < sorted[k] ? sorted[k] : sorted[k - 1];
            free(sorted);
            return hl_fail(err, "%s: instances[%u].name: \"%s\" is also the name of instances[%u]", f->file, b,
                           f->instances[b].name, a);
        }

    /* groups: an array; names first, so that parent and children may point forward */
    int rc = 0;
    if (v[K_GROUPS]) {
        if (!cJSON_IsArray(v[K_GROUPS])) {
            free(sorted);
            return hl_fail(err, "%s: groups: expected an array", f->file);
        }
        int ng = cJSON_GetArraySize(v[K_GROUPS]);
        f->groups = calloc(ng ? (size_t)ng : 1, sizeof *f->groups);
        if (!f->groups || ng > SF_MAX_ITEMS) {
            free(sorted);
            return hl_fail(err, "%s: groups: too many or out of memory", f->file);
        }
        uint32_t g = 0;
        for (const cJSON *c = v[K_GROUPS]->child; c && rc == 0; c = c->next, ++g) {
            char where[64];
            snprintf(where, sizeof where, "groups[%u]", g);
            const cJSON *name = cJSON_IsObject(c) ? cJSON_GetObjectItemCaseSensitive(c, "name") : NULL;
            char w[80];
            snprintf(w, sizeof w, "%s.name", where);
            if (!cJSON_IsObject(c))
                rc = hl_fail(err, "%s: %s: expected an object", f->file, where);
            else if (!name)
                rc = hl_fail(err, "%s: %s: missing (required)", f->file, w);
            else if (sf_name(f->file, w, name, f->groups[g].name, err) != 0)
                rc = -1;
            else if (sf_find_group(f, f->groups[g].name) != SCN_NONE)
                rc = hl_fail(err, "%s: %s: \"%s\" is also the name of an earlier group", f->file, w, f->groups[g].name);
            f->groups[g].parent = f->groups[g].impostor_mesh = f->groups[g].motion = SCN_NONE;
            f->groups[g].importance = 1.0;
            f->group_count = g + 1;
        }
        g = 0;
        for (const cJSON *c = v[K_GROUPS]->child; c && rc == 0; c = c->next, ++g) {
            char where[64];
            snprintf(where, sizeof where, "groups[%u]", g);
            rc = sf_read_group(f, g, where, c, sorted, named, err);
        }
        if (rc == 0)
            rc = sf_check_cycles(f, err);
    }
    free(sorted);
    return rc;
}

int sf_file_read(const char *path, struct sf_file *f, struct hl_error *err)
{
    memset(f, 0, sizeof *f);
    f->file = path;
    size_t len = 0;
    char *text = sf_read_all(path, &len, err);
    if (!text)
        return -1;
    size_t skip = strspn(text, " \t\r\n");
    if (skip == len) {
        free(text);
        return hl_fail(err, "%s: empty file (expected a JSON object, docs/scene-format.md)", path);
    }
    if (strlen(text) != len) {
        int line, col;
        sf_line_col(text, strlen(text), &line, &col);
        free(text);
        return hl_fail(err, "%s:%d:%d: a NUL byte; not a JSON text", path, line, col);
    }
    const char *end = NULL;
    /* The length counts the NUL: cJSON's require_null_terminated looks for it inside the buffer. */
    uint64_t failed_before = hl_lib_alloc_failures();
    cJSON *root = cJSON_ParseWithLengthOpts(text, len + 1, &end, 1);
    if (!root && hl_lib_alloc_failures() != failed_before) {
        free(text);
        return hl_fail(err, "%s: out of memory parsing the JSON", path);
    }
    if (!root) {
        size_t at = end && end >= text && end <= text + len ? (size_t)(end - text) : len;
        int line, col;
        sf_line_col(text, at, &line, &col);
        free(text);
        return hl_fail(err, "%s:%d:%d: not valid JSON (byte %zu%s)", path, line, col, at,
                       at >= len ? ", at the end: truncated?" : "");
    }
    /* Mesh paths are relative to the folder holding the scene file. */
    char dir[SF_PATH_MAX];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash)
        *(slash == dir ? slash + 1 : slash) = '\0';
    else
        dir[0] = '\0';
    if (!f->name[0]) { /* the file name without its folder and .json */
        const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
        size_t n = strcspn(base, ".");
        snprintf(f->name, sizeof f->name, "%.*s", (int)(n < SCN_NAME_MAX - 1 ? n : SCN_NAME_MAX - 1), base);
    }
    int rc = sf_read_root(f, dir, root, err);
    cJSON_Delete(root);
    free(text);
    if (rc != 0)
        sf_file_free(f);
    else
        f->file = path;
    return rc;
}

int scn_scenefile_load(const char *path, const struct scn_asset_resolver *resolver, struct scn_scene *out,
                       struct hl_error *err)
{
    if (!out)
        return hl_fail(err, "scene file: no output");
    memset(out, 0, sizeof *out);
    if (!path)
        return hl_fail(err, "scene file: no path");
    struct sf_file f;
    if (sf_file_read(path, &f, err) != 0)
        return -1;
    int rc = sf_file_build(&f, resolver, out, err);
    sf_file_free(&f);
    return rc;
}
