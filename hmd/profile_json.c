/* JSON display profiles (docs/display-profile.md): strict reading with cJSON. Every error names the
 * file and the field: "path: field 'eye_pixels': expected two positive integers". Unknown and
 * duplicate keys are errors; numbers must be finite; pixels must be integers. */
#include "hmd/hmd.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define HMD_FORMAT_TAG "hmdlod-display-1"

enum field_id {
    F_FORMAT, F_NAME, F_DESCRIPTION, F_EYE_PIXELS, F_FOV_DEG, F_FOV_TANGENTS, F_REFRESH, F_IPD,
    F_DISTORTION, F_ABERRATION, F_XI, F_NECK, F_PEAK_LUMINANCE, F_COUNT
};
/* cJSON allocates through base's counting hooks, so a parse that fails for want of memory is told from
 * bad text (base.h, "allocation in libraries"). */
__attribute__((constructor)) static void profile_json_hooks(void)
{
    cJSON_Hooks hooks = {hl_lib_malloc, hl_lib_free};
    cJSON_InitHooks(&hooks);
}

static const char *const g_keys[F_COUNT] = {
    "format", "name", "description", "eye_pixels", "fov_deg", "fov_tangents", "refresh_hz", "ipd_m",
    "distortion_k", "aberration", "xi_cpd", "neck_to_eye_m", "peak_luminance_cdm2",
};

/* Reads the whole file (at most HMD_PROFILE_MAX_BYTES) into a NUL-terminated buffer; base/file.c
 * refuses FIFOs and devices before they can block. */
static char *read_file(const char *path, size_t *len_out, struct hl_error *err)
{
    char *buf = NULL;
    size_t len = 0;
    if (hl_file_read_all(path, HMD_PROFILE_MAX_BYTES, &buf, &len, err) != 0)
        return NULL;
    if (strlen(buf) != len) {
        hl_fail(err, "%s: not valid JSON near byte %zu (NUL byte)", path, strlen(buf));
        free(buf);
        return NULL;
    }
    *len_out = len;
    return buf;
}

/* A finite JSON number. */
static int get_finite(const cJSON *item, double *out)
{
    if (!cJSON_IsNumber(item) || !isfinite(item->valuedouble))
        return 0;
    *out = item->valuedouble;
    return 1;
}

/* A JSON array of exactly n finite numbers. */
static int get_number_array(const cJSON *item, int n, double *out)
{
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != n)
        return 0;
    int i = 0;
    for (const cJSON *c = item->child; c; c = c->next, ++i)
        if (!get_finite(c, &out[i]))
            return 0;
    return i == n;
}

static int copy_string(const cJSON *item, char *dst, size_t cap, int allow_empty)
{
    if (!cJSON_IsString(item) || !item->valuestring)
        return 0;
    size_t n = strlen(item->valuestring);
    if (n >= cap || (!allow_empty && n == 0))
        return 0;
    memcpy(dst, item->valuestring, n + 1);
    return 1;
}

static int parse_tangents(const cJSON *obj, const char *path, struct hmd_profile *p, struct hl_error *err)
{
    static const char *const names[4] = {"left", "right", "up", "down"};
    double *dst[4] = {&p->tan_left, &p->tan_right, &p->tan_up, &p->tan_down};
    int seen[4] = {0, 0, 0, 0};
    if (!cJSON_IsObject(obj))
        return hl_fail(err, "%s: field 'fov_tangents': expected an object {\"left\", \"right\", \"up\", \"down\"}",
                       path);
    for (const cJSON *c = obj->child; c; c = c->next) {
        int k = -1;
        for (int i = 0; i < 4; ++i)
            if (c->string && strcmp(c->string, names[i]) == 0)
                k = i;
        if (k < 0)
            return hl_fail(err, "%s: field 'fov_tangents': unknown key '%.40s' (expected left, right, up, down)",
                           path, c->string ? c->string : "");
        if (seen[k])
            return hl_fail(err, "%s: field 'fov_tangents': duplicate key '%s'", path, names[k]);
        seen[k] = 1;
        double v;
        if (!get_finite(c, &v) || !(v > 0))
            return hl_fail(err, "%s: field 'fov_tangents': '%s' must be a finite number > 0", path, names[k]);
        *dst[k] = v;
    }
    for (int i = 0; i < 4; ++i)
        if (!seen[i])
            return hl_fail(err, "%s: field 'fov_tangents': missing '%s'", path, names[i]);
    return 0;
}

/* Fills p from the parsed object; returns 0 or −1 with the message. */
static int parse_profile(const cJSON *root, const char *path, struct hmd_profile *p, struct hl_error *err)
{
    const cJSON *field[F_COUNT] = {0};
    if (!cJSON_IsObject(root))
        return hl_fail(err, "%s: expected a JSON object at the top level", path);
    for (const cJSON *c = root->child; c; c = c->next) {
        int k = -1;
        for (int i = 0; i < F_COUNT; ++i)
            if (c->string && strcmp(c->string, g_keys[i]) == 0)
                k = i;
        if (k < 0)
            return hl_fail(err,
                           "%s: field '%.40s': unknown key (known: format, name, description, eye_pixels, "
                           "fov_deg, fov_tangents, refresh_hz, ipd_m, distortion_k, aberration, xi_cpd, "
                           "neck_to_eye_m, peak_luminance_cdm2)",
                           path, c->string ? c->string : "");
        if (field[k])
            return hl_fail(err, "%s: field '%s': duplicate key", path, g_keys[k]);
        field[k] = c;
    }

    if (field[F_FORMAT] && !(cJSON_IsString(field[F_FORMAT]) &&
                             strcmp(field[F_FORMAT]->valuestring, HMD_FORMAT_TAG) == 0))
        return hl_fail(err, "%s: field 'format': expected \"%s\"", path, HMD_FORMAT_TAG);

    if (!field[F_NAME])
        return hl_fail(err, "%s: field 'name': missing (required)", path);
    if (!copy_string(field[F_NAME], p->name, sizeof p->name, 0))
        return hl_fail(err, "%s: field 'name': expected a non-empty string of at most %d bytes", path,
                       HMD_NAME_MAX - 1);
    if (field[F_DESCRIPTION] && !copy_string(field[F_DESCRIPTION], p->description, sizeof p->description, 1))
        return hl_fail(err, "%s: field 'description': expected a string of at most %zu bytes", path,
                       sizeof p->description - 1);

    if (!field[F_EYE_PIXELS])
        return hl_fail(err, "%s: field 'eye_pixels': missing (required)", path);
    double px[2];
    /* Integers that fit an int here; hmd_profile_validate then holds them to [HMD_PIXELS_MIN, _MAX]. */
    if (!get_number_array(field[F_EYE_PIXELS], 2, px) || !(px[0] >= 1 && px[0] <= 1 << 20) ||
        !(px[1] >= 1 && px[1] <= 1 << 20) || px[0] != floor(px[0]) || px[1] != floor(px[1]))
        return hl_fail(err, "%s: field 'eye_pixels': expected two positive integers", path);
    p->eye_width_px = (int)px[0];
    p->eye_height_px = (int)px[1];

    if (field[F_FOV_DEG] && field[F_FOV_TANGENTS])
        return hl_fail(err, "%s: field 'fov_deg': give either 'fov_deg' or 'fov_tangents', not both", path);
    if (!field[F_FOV_DEG] && !field[F_FOV_TANGENTS])
        return hl_fail(err, "%s: field 'fov_deg': missing (give 'fov_deg' [h, v] or 'fov_tangents')", path);
    if (field[F_FOV_DEG]) {
        double fov[2];
        if (!get_number_array(field[F_FOV_DEG], 2, fov) || !(fov[0] >= HMD_FOV_MIN_DEG && fov[0] < 180) ||
            !(fov[1] >= HMD_FOV_MIN_DEG && fov[1] < 180))
            return hl_fail(err, "%s: field 'fov_deg': expected [horizontal, vertical] degrees, each in [%g, 180)",
                           path, HMD_FOV_MIN_DEG);
        hmd_set_symmetric_fov_deg(p, fov[0], fov[1]);
    } else if (parse_tangents(field[F_FOV_TANGENTS], path, p, err) != 0) {
        return -1;
    }

    if (!field[F_REFRESH])
        return hl_fail(err, "%s: field 'refresh_hz': missing (required)", path);
    if (!get_finite(field[F_REFRESH], &p->refresh_hz) ||
        !(p->refresh_hz >= HMD_REFRESH_MIN_HZ && p->refresh_hz <= HMD_REFRESH_MAX_HZ))
        return hl_fail(err, "%s: field 'refresh_hz': expected a finite number of Hz in [%g, %g]", path,
                       HMD_REFRESH_MIN_HZ, HMD_REFRESH_MAX_HZ);

    if (field[F_IPD] && (!get_finite(field[F_IPD], &p->ipd_m) || !(p->ipd_m >= 0 && p->ipd_m < 0.1)))
        return hl_fail(err, "%s: field 'ipd_m': expected metres in [0, 0.1)", path);
    if (field[F_DISTORTION] && !get_number_array(field[F_DISTORTION], 4, p->distortion_k))
        return hl_fail(err, "%s: field 'distortion_k': expected four finite numbers [a, b, c, d]", path);
    if (field[F_ABERRATION] && (!get_number_array(field[F_ABERRATION], 3, p->aberration) ||
                                !(p->aberration[0] > 0 && p->aberration[1] > 0 && p->aberration[2] > 0)))
        return hl_fail(err, "%s: field 'aberration': expected three finite numbers > 0 [r, g, b]", path);
    if (field[F_XI] && (!get_finite(field[F_XI], &p->xi_override_cpd) || !(p->xi_override_cpd > 0)))
        return hl_fail(err, "%s: field 'xi_cpd': expected a finite number > 0 (cycles/degree)", path);
    if (field[F_NECK] && (!get_number_array(field[F_NECK], 2, p->neck_to_eye_m) ||
                          !(hypot(p->neck_to_eye_m[0], p->neck_to_eye_m[1]) < HMD_NECK_TO_EYE_MAX_M)))
        return hl_fail(err, "%s: field 'neck_to_eye_m': expected [forward, up] metres, length below %g", path,
                       HMD_NECK_TO_EYE_MAX_M);
    if (field[F_PEAK_LUMINANCE] &&
        (!get_finite(field[F_PEAK_LUMINANCE], &p->peak_luminance_cdm2) ||
         !(p->peak_luminance_cdm2 >= HMD_PEAK_LUMINANCE_MIN_CDM2 &&
           p->peak_luminance_cdm2 <= HMD_PEAK_LUMINANCE_MAX_CDM2)))
        return hl_fail(err, "%s: field 'peak_luminance_cdm2': expected a finite number of cd/m² in [%g, %g]", path,
                       HMD_PEAK_LUMINANCE_MIN_CDM2, HMD_PEAK_LUMINANCE_MAX_CDM2);

    /* The ranges of every field (the tangent form can still reach 180° per axis, or fall below 1°). */
    return hmd_profile_validate(p, path, err);
}

int hmd_profile_load_json(const char *path, struct hmd_profile *out, struct hl_error *err)
{
    size_t len = 0;
    char *buf = read_file(path, &len, err);
    if (!buf)
        return -1;
    const char *end = NULL;
    /* Length includes the terminating NUL: with require_null_terminated cJSON must see it in range. */
    uint64_t failed_before = hl_lib_alloc_failures();
    cJSON *root = cJSON_ParseWithLengthOpts(buf, len + 1, &end, 1);
    if (!root && hl_lib_alloc_failures() != failed_before) {
        free(buf);
        return hl_fail(err, "%s: out of memory parsing the JSON", path);
    }
    if (!root) {
        size_t at = (end && end >= buf && end <= buf + len) ? (size_t)(end - buf) : len;
        hl_fail(err, "%s: not valid JSON near byte %zu", path, at);
        free(buf);
        return -1;
    }
    struct hmd_profile p;
    hmd_profile_defaults(&p);
    int rc = parse_profile(root, path, &p, err);
    cJSON_Delete(root);
    free(buf);
    if (rc == 0)
        *out = p;
    return rc;
}
