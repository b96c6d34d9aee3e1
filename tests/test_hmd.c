/* hmd: built-in table vs DEVICES.md §1c (Reddy's ξ, eq. 4), FOV from tangents, frusta mirroring,
 * projection corners, and strict JSON profile loading (valid and invalid fixtures, truncation). */
#include "hmd/hmd.h"
#include "test_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char g_data_dir[4096];

static const char *fixture(const char *name)
{
    static char path[4352];
    snprintf(path, sizeof path, "%s/%s", g_data_dir, name);
    return path;
}

/* ---- ξ table, DEVICES.md §1c ----------------------------------------------------------------- */
struct xi_row {
    const char *name;
    double h_cpd, v_cpd, used_cpd; /* as tabulated in DEVICES.md §1c */
    double tangent_h_cpd, tangent_v_cpd; /* > 0: the §1a tangents give another FOV; see below */
};

/* For vive, index, quest3, varjo-aero and reverb-g2 the FOV of DEVICES.md §1a/§1c is hmdgdb's
 * "head FOV", clipped by the hidden-area mesh (e.g. Vive right 46.75° where atan(1.2505) = 51.35°),
 * so it differs from atan(L)+atan(R) of the raw tangents in the same row (Vive 101.16° vs 105.76°).
 * hmdlod projects with the tangents (the render frustum) and hmd_fov_*_deg is defined on them, so
 * ξ follows them: where the row gives a tangent value it is checked to 0.01 c/deg, and the used ξ
 * loosely (0.35 c/deg) against §1c. */
static const struct xi_row g_xi[] = {
    {"i-glasses", 4.38, 4.79, 4.79, 0, 0},
    {"desktop", 12.05, 12.46, 12.46, 0, 0},
    {"dk1", 3.80, 4.10, 4.10, 0, 0}, /* pinhole FOV */
    {"dk2", 5.10, 5.09, 5.10, 0, 0},
    {"cv1", 6.79, 6.69, 6.79, 0, 0},
    {"vive", 5.34, 5.38, 5.38, 5.106, 0},
    {"index", 7.42, 7.32, 7.42, 6.955, 7.315},
    {"quest2", 9.44, 9.80, 9.80, 0, 0},
    {"quest3", 10.98, 11.24, 11.24, 0, 11.152},
    {"psvr", 5.65, 6.05, 6.05, 0, 0}, /* MO geometry */
    {"psvr2", 9.53, 9.62, 9.62, 0, 0},
    {"varjo-aero", 15.92, 15.87, 15.92, 15.485, 15.643},
    {"varjo-focus", 35.56, 35.56, 35.56, 0, 0},
    {"reverb-g2", 11.80, 11.88, 11.88, 11.466, 11.593},
    {"pimax-crystal", 15.43, 13.88, 15.43, 0, 0},
    {"hdk", 5.33, 5.58, 5.58, 0, 0},
    {"hdk2", 5.87, 5.87, 5.87, 0, 0},
};

static void test_builtins(void)
{
    int n = hmd_builtin_count();
    CHECK(n >= (int)(sizeof g_xi / sizeof g_xi[0]));
    for (int i = 0; i < n; ++i) {
        const struct hmd_profile *p = hmd_builtin_at(i);
        struct hl_error err = {{0}};
        CHECK(p != NULL);
        int ok = hmd_profile_validate(p, p->name, &err) == 0;
        CHECK(ok);
        if (!ok)
            fprintf(stderr, "  %s\n", err.msg);
        CHECK(hmd_builtin_find(p->name) == p);
        CHECK(strlen(p->description) > 0);
        for (const char *c = p->name; *c; ++c)
            CHECK(!(*c >= 'A' && *c <= 'Z'));
    }
    CHECK(hmd_builtin_at(-1) == NULL);
    CHECK(hmd_builtin_at(n) == NULL);
    CHECK(hmd_builtin_find("VIVE") == hmd_builtin_find("vive"));
    CHECK(hmd_builtin_find("I-Glasses") != NULL);
    CHECK(hmd_builtin_find("viv") == NULL);
    CHECK(hmd_builtin_find("vivex") == NULL);
    CHECK(hmd_builtin_find(NULL) == NULL);

    for (size_t i = 0; i < sizeof g_xi / sizeof g_xi[0]; ++i) {
        const struct xi_row *r = &g_xi[i];
        const struct hmd_profile *p = hmd_builtin_find(r->name);
        CHECK(p != NULL);
        if (!p) {
            fprintf(stderr, "  missing built-in %s\n", r->name);
            continue;
        }
        struct hmd_xi xi = hmd_compute_xi(p);
        double want_h = r->tangent_h_cpd > 0 ? r->tangent_h_cpd : r->h_cpd;
        double want_v = r->tangent_v_cpd > 0 ? r->tangent_v_cpd : r->v_cpd;
        CHECK_NEAR(xi.horizontal_cpd, want_h, 0.015);
        CHECK_NEAR(xi.vertical_cpd, want_v, 0.015);
        if (r->tangent_h_cpd > 0 || r->tangent_v_cpd > 0)
            CHECK_NEAR(xi.used_cpd, r->used_cpd, 0.35);
        else
            CHECK_NEAR(xi.used_cpd, r->used_cpd, 0.015);
        CHECK(xi.used_cpd == fmax(xi.horizontal_cpd, xi.vertical_cpd));
    }

    /* The i-glasses row: eq. 4 with 263×230 px over 30×24°. */
    const struct hmd_profile *ig = hmd_builtin_find("i-glasses");
    CHECK_NEAR(hmd_fov_horizontal_deg(ig), 30.0, 1e-9);
    CHECK_NEAR(hmd_fov_vertical_deg(ig), 24.0, 1e-9);
    CHECK_NEAR(hmd_compute_xi(ig).vertical_cpd, 230.0 / 48.0, 1e-12);
    CHECK_NEAR(ig->refresh_hz, 60.0, 0);
    CHECK_NEAR(hmd_builtin_find("desktop")->refresh_hz, 60.0, 0);
    CHECK_NEAR(hmd_builtin_find("varjo-focus")->eye_width_px, 1920, 0);
}

static void test_fov_and_override(void)
{
    /* Vive: atan(1.3973) + atan(1.2505) = 54.41° + 51.35°. DEVICES.md's 101.2° is hmdgdb's
     * hidden-area-clipped head FOV (nasal 46.75°); the vertical 111.6° matches the tangents. */
    const struct hmd_profile *vive = hmd_builtin_find("vive");
    CHECK_NEAR(hmd_fov_horizontal_deg(vive), 105.76, 0.1);
    CHECK_NEAR(hmd_fov_vertical_deg(vive), 111.6, 0.1);
    CHECK_NEAR(atan(vive->tan_left) * HL_DEG_PER_RAD, 54.41, 0.01);

    struct hmd_profile p = *vive;
    p.xi_override_cpd = 20.0;
    struct hmd_xi xi = hmd_compute_xi(&p);
    CHECK_NEAR(xi.used_cpd, 20.0, 0);
    CHECK_NEAR(xi.vertical_cpd, 5.38, 0.015);

    /* Symmetric helper and defaults. */
    hmd_profile_defaults(&p);
    CHECK_NEAR(p.ipd_m, 0.063, 0);
    CHECK_NEAR(p.aberration[1], 1.0, 0);
    hmd_set_symmetric_fov_deg(&p, 90.0, 60.0);
    CHECK_NEAR(p.tan_left, 1.0, 1e-12);
    CHECK_NEAR(p.tan_down, tan(30.0 * HL_RAD_PER_DEG), 1e-12);

    /* Validation catches what a hand-built profile can get wrong. */
    struct hl_error err = {{0}};
    strcpy(p.name, "t");
    p.eye_width_px = p.eye_height_px = 100;
    p.refresh_hz = 60;
    CHECK(hmd_profile_validate(&p, "here", &err) == 0);
    p.tan_up = NAN;
    CHECK(hmd_profile_validate(&p, "here", &err) != 0 && strstr(err.msg, "here: field 'fov_tangents'"));
    p.tan_up = 1e300;
    p.tan_down = 1e300;
    CHECK(hmd_profile_validate(&p, "here", &err) != 0 && strstr(err.msg, "180"));
    p.tan_up = p.tan_down = 1;
    p.refresh_hz = 0;
    CHECK(hmd_profile_validate(&p, "here", &err) != 0 && strstr(err.msg, "refresh_hz"));
}

/* Applies a column-major 4×4 to (x, y, z, 1) and returns NDC x, y, z. */
static void project(const double m[16], double x, double y, double z, double ndc[3])
{
    double c[4];
    for (int r = 0; r < 4; ++r)
        c[r] = m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r];
    for (int r = 0; r < 3; ++r)
        ndc[r] = c[r] / c[3];
}

static void test_frusta(void)
{
    const struct hmd_profile *q3 = hmd_builtin_find("quest3");
    struct hmd_eye l = hmd_eye_frustum(q3, HMD_EYE_LEFT), r = hmd_eye_frustum(q3, HMD_EYE_RIGHT);
    CHECK_NEAR(l.offset_x_m, -0.5 * q3->ipd_m, 0);
    CHECK_NEAR(r.offset_x_m, 0.5 * q3->ipd_m, 0);
    CHECK(l.tan_left == q3->tan_left && l.tan_right == q3->tan_right);
    CHECK(r.tan_left == q3->tan_right && r.tan_right == q3->tan_left);
    CHECK(r.tan_up == l.tan_up && r.tan_down == l.tan_down);

    const double n = 0.1, f = 1000.0;
    const struct hmd_eye *eyes[2] = {&l, &r};
    for (int e = 0; e < 2; ++e) {
        double m[16], ndc[3];
        hmd_eye_projection(eyes[e], n, f, m);
        const double depth[2] = {n, f}, want_z[2] = {-1, 1};
        for (int d = 0; d < 2; ++d) {
            double z = depth[d];
            /* Corners of the frustum at distance z: (−tanL·z … tanR·z) × (−tanD·z … tanU·z). */
            project(m, -eyes[e]->tan_left * z, -eyes[e]->tan_down * z, -z, ndc);
            CHECK_NEAR(ndc[0], -1, 1e-9);
            CHECK_NEAR(ndc[1], -1, 1e-9);
            CHECK_NEAR(ndc[2], want_z[d], 1e-9);
            project(m, eyes[e]->tan_right * z, eyes[e]->tan_up * z, -z, ndc);
            CHECK_NEAR(ndc[0], 1, 1e-9);
            CHECK_NEAR(ndc[1], 1, 1e-9);
            CHECK_NEAR(ndc[2], want_z[d], 1e-9);
            project(m, -eyes[e]->tan_left * z, eyes[e]->tan_up * z, -z, ndc);
            CHECK_NEAR(ndc[0], -1, 1e-9);
            CHECK_NEAR(ndc[1], 1, 1e-9);
        }
        /* Straight ahead lands off-centre by the asymmetry: x = (L − R)/(L + R) (more FOV on the left
         * puts the forward axis right of the image centre). */
        project(m, 0, 0, -1, ndc);
        CHECK_NEAR(ndc[0], (eyes[e]->tan_left - eyes[e]->tan_right) / (eyes[e]->tan_right + eyes[e]->tan_left),
                   1e-12);
    }
}

/* ---- JSON ------------------------------------------------------------------------------------- */
static void test_json_valid(void)
{
    struct hmd_profile p;
    struct hl_error err = {{0}};
    int rc = hmd_profile_load_json(fixture("valid_symmetric.json"), &p, &err);
    CHECK(rc == 0);
    if (rc)
        fprintf(stderr, "  %s\n", err.msg);
    else {
        CHECK(strcmp(p.name, "test-iglasses") == 0);
        CHECK(p.eye_width_px == 263 && p.eye_height_px == 230);
        CHECK_NEAR(hmd_fov_horizontal_deg(&p), 30.0, 1e-9);
        CHECK_NEAR(hmd_compute_xi(&p).used_cpd, 4.79, 0.01);
        CHECK_NEAR(p.ipd_m, 0.063, 0);
        CHECK_NEAR(p.aberration[2], 1.0, 0);
        CHECK_NEAR(p.refresh_hz, 60, 0);
    }

    rc = hmd_profile_load_json(fixture("valid_tangents.json"), &p, &err);
    CHECK(rc == 0);
    if (rc)
        fprintf(stderr, "  %s\n", err.msg);
    else {
        CHECK_NEAR(hmd_fov_horizontal_deg(&p), 105.76, 0.1);
        CHECK_NEAR(p.tan_down, 1.4775, 0);
        CHECK_NEAR(p.ipd_m, 0.064, 0);
        CHECK_NEAR(p.distortion_k[3], 0.795, 0);
        CHECK_NEAR(p.aberration[0], 0.985, 0);
        CHECK_NEAR(hmd_compute_xi(&p).used_cpd, 6.5, 0);
        CHECK_NEAR(hmd_compute_xi(&p).vertical_cpd, 5.38, 0.015);
    }

    /* hmd_profile_load: built-in names first (any case), then files. */
    rc = hmd_profile_load("Vive", &p, &err);
    CHECK(rc == 0 && strcmp(p.name, "vive") == 0);
    rc = hmd_profile_load(fixture("valid_symmetric.json"), &p, &err);
    CHECK(rc == 0 && strcmp(p.name, "test-iglasses") == 0);
    rc = hmd_profile_load("no-such-display", &p, &err);
    CHECK(rc != 0 && strstr(err.msg, "unknown display 'no-such-display'") && strstr(err.msg, "Built-ins: ") &&
          strstr(err.msg, "i-glasses"));
    rc = hmd_profile_load_json(fixture("absent.json"), &p, &err);
    CHECK(rc != 0 && strstr(err.msg, "absent.json: cannot open: "));
    rc = hmd_profile_load_json(g_data_dir, &p, &err); /* a directory */
    CHECK(rc != 0 && strstr(err.msg, "displays"));
}

struct bad_case {
    const char *file, *field;
};

static const struct bad_case g_bad[] = {
    {"invalid_missing_pixels.json", "'eye_pixels'"},
    {"invalid_zero_pixels.json", "'eye_pixels'"},
    {"invalid_negative_pixels.json", "'eye_pixels'"},
    {"invalid_float_pixels.json", "'eye_pixels'"},
    {"invalid_string_pixels.json", "'eye_pixels'"},
    {"invalid_three_pixels.json", "'eye_pixels'"},
    {"invalid_fov_180.json", "'fov_deg'"},
    {"invalid_fov_zero.json", "'fov_deg'"},
    {"invalid_tangents_negative.json", "'fov_tangents'"},
    {"invalid_tangents_missing.json", "'fov_tangents'"},
    {"invalid_tangents_huge.json", "'fov_tangents'"},
    {"invalid_both_fov.json", "'fov_deg'"},
    {"invalid_no_fov.json", "'fov_deg'"},
    {"invalid_unknown_key.json", "'refresh_rate'"},
    {"invalid_wrong_type.json", "'refresh_hz'"},
    {"invalid_huge_number.json", "'refresh_hz'"},
    {"invalid_missing_refresh.json", "'refresh_hz'"},
    {"invalid_bad_format.json", "'format'"},
    {"invalid_missing_name.json", "'name'"},
    {"invalid_ipd.json", "'ipd_m'"},
    {"invalid_aberration.json", "'aberration'"},
    {"invalid_distortion.json", "'distortion_k'"},
    {"invalid_xi.json", "'xi_cpd'"},
    {"invalid_duplicate_key.json", "'name'"},
    {"invalid_json.json", "not valid JSON near byte"},
    {"invalid_truncated.json", "not valid JSON near byte"},
    {"invalid_neck_long.json", "'neck_to_eye_m'"},
    {"invalid_neck_shape.json", "'neck_to_eye_m'"},
    /* physically meaningless values (docs/display-profile.md "Ranges") */
    {"invalid_fov_tiny.json", "'fov_deg'"},
    {"invalid_tangents_tiny.json", "'fov_tangents'"},
    {"invalid_refresh_tiny.json", "'refresh_hz'"},
    {"invalid_refresh_huge.json", "'refresh_hz'"},
    {"invalid_pixels_huge.json", "'eye_pixels'"},
    {"invalid_pixels_tiny.json", "'eye_pixels'"},
    {"invalid_distortion_huge.json", "'distortion_k'"},
    {"invalid_aberration_huge.json", "'aberration'"},
    {"invalid_xi_huge.json", "'xi_cpd'"},
    {"invalid_ipd_negative.json", "'ipd_m'"},
    {"invalid_peak_luminance_string.json", "'peak_luminance_cdm2'"},
    {"invalid_peak_luminance_huge.json", "'peak_luminance_cdm2'"},
    {"invalid_peak_luminance_tiny.json", "'peak_luminance_cdm2'"},
    {"invalid_peak_luminance_infinite.json", "'peak_luminance_cdm2'"},
};

static void test_json_invalid(void)
{
    for (size_t i = 0; i < sizeof g_bad / sizeof g_bad[0]; ++i) {
        struct hmd_profile p;
        struct hl_error err = {{0}};
        int rc = hmd_profile_load_json(fixture(g_bad[i].file), &p, &err);
        int ok = rc != 0 && strstr(err.msg, g_bad[i].file) && strstr(err.msg, g_bad[i].field);
        CHECK(ok);
        if (!ok)
            fprintf(stderr, "  %s: rc %d, message \"%s\" (want %s)\n", g_bad[i].file, rc, err.msg, g_bad[i].field);
    }
    /* The exact wording the docs promise. */
    struct hmd_profile p;
    struct hl_error err = {{0}};
    char want[4500];
    hmd_profile_load_json(fixture("invalid_float_pixels.json"), &p, &err);
    snprintf(want, sizeof want, "%s: field 'eye_pixels': expected two positive integers",
             fixture("invalid_float_pixels.json"));
    CHECK(strcmp(err.msg, want) == 0);
    hmd_profile_load_json(fixture("invalid_json.json"), &p, &err);
    CHECK(strstr(err.msg, "near byte 80") != NULL); /* the second ',' of ",," */
}

/* The eyes' offset from the neck (docs/display-profile.md): every built-in and a file without the
 * key get the Oculus SDK's 80.5 mm forward, 75 mm up; a file may set it; validation refuses NaN and
 * lengths of 0.3 m or more; the head-frame vector points forward (−Z) and up (+Y). */
static void test_neck_to_eye(void)
{
    for (int i = 0; i < hmd_builtin_count(); ++i) {
        const struct hmd_profile *b = hmd_builtin_at(i);
        CHECK_NEAR(b->neck_to_eye_m[0], 0.0805, 0);
        CHECK_NEAR(b->neck_to_eye_m[1], 0.075, 0);
    }
    struct hmd_profile p;
    struct hl_error err = {{0}};
    CHECK(hmd_profile_load_json(fixture("valid_tangents.json"), &p, &err) == 0);
    CHECK_NEAR(p.neck_to_eye_m[0], 0.0805, 0);
    CHECK(hmd_profile_load_json(fixture("valid_neck.json"), &p, &err) == 0);
    CHECK_NEAR(p.neck_to_eye_m[0], 0.09, 0);
    CHECK_NEAR(p.neck_to_eye_m[1], 0.06, 0);
    hl_vec3d v = hmd_neck_to_eye_head(&p);
    CHECK(v.x == 0.0 && v.y == 0.06 && v.z == -0.09);
    CHECK(hmd_profile_validate(&p, "t", &err) == 0);
    p.neck_to_eye_m[1] = NAN;
    CHECK(hmd_profile_validate(&p, "t", &err) != 0 && strstr(err.msg, "t: field 'neck_to_eye_m'"));
    p.neck_to_eye_m[1] = 0.0;
    p.neck_to_eye_m[0] = -0.3;
    CHECK(hmd_profile_validate(&p, "t", &err) != 0 && strstr(err.msg, "'neck_to_eye_m'"));
    p.neck_to_eye_m[0] = -0.29;
    CHECK(hmd_profile_validate(&p, "t", &err) == 0);
}

/* Peak luminance (DEVICES.md §1d): 100 cd/m² wherever a profile gives none — every built-in, since
 * the one device §1d measures (Vive Pro) has no row — a file may set it, and validation refuses NaN
 * and values outside [1, 10000] cd/m². */
static void test_peak_luminance(void)
{
    for (int i = 0; i < hmd_builtin_count(); ++i)
        CHECK_NEAR(hmd_builtin_at(i)->peak_luminance_cdm2, 100.0, 0);
    struct hmd_profile p;
    struct hl_error err = {{0}};
    hmd_profile_defaults(&p);
    CHECK_NEAR(p.peak_luminance_cdm2, 100.0, 0);
    CHECK(hmd_profile_load_json(fixture("valid_tangents.json"), &p, &err) == 0);
    CHECK_NEAR(p.peak_luminance_cdm2, 100.0, 0);
    CHECK(hmd_profile_load_json(fixture("valid_peak_luminance.json"), &p, &err) == 0);
    CHECK_NEAR(p.peak_luminance_cdm2, 133.3, 0);
    char want[4500];
    hmd_profile_load_json(fixture("invalid_peak_luminance_string.json"), &p, &err);
    snprintf(want, sizeof want, "%s: field 'peak_luminance_cdm2': expected a finite number of cd/m² in [1, 10000]",
             fixture("invalid_peak_luminance_string.json"));
    CHECK(strcmp(err.msg, want) == 0);
    CHECK(hmd_profile_load("vive", &p, &err) == 0);
    static const double bad[] = {NAN, INFINITY, 0.0, 0.999, 10000.5, -100.0};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        p.peak_luminance_cdm2 = bad[i];
        CHECK(hmd_profile_validate(&p, "t", &err) != 0 && strstr(err.msg, "t: field 'peak_luminance_cdm2'"));
    }
    static const double good[] = {1.0, 50.0, 200.0, 10000.0};
    for (size_t i = 0; i < sizeof good / sizeof good[0]; ++i) {
        p.peak_luminance_cdm2 = good[i];
        CHECK(hmd_profile_validate(&p, "t", &err) == 0);
    }
}

/* Every prefix of a valid profile fails cleanly or parses; a file over the size limit is refused. */
static void test_json_truncation_and_size(void)
{
    FILE *f = fopen(fixture("valid_tangents.json"), "rb");
    CHECK(f != NULL);
    if (!f)
        return;
    char text[4096];
    size_t len = fread(text, 1, sizeof text, f);
    fclose(f);
    char tmp[] = "/tmp/hmdlod_test_hmd_XXXXXX";
    int fd = mkstemp(tmp);
    CHECK(fd >= 0);
    if (fd < 0)
        return;
    close(fd);
    int parsed = 0, failed_cleanly = 0;
    for (size_t cut = 0; cut <= len; ++cut) {
        FILE *o = fopen(tmp, "wb");
        fwrite(text, 1, cut, o);
        fclose(o);
        struct hmd_profile p;
        struct hl_error err = {{0}};
        if (hmd_profile_load_json(tmp, &p, &err) == 0)
            ++parsed;
        else if (strstr(err.msg, tmp))
            ++failed_cleanly;
    }
    CHECK(parsed >= 1 && parsed <= 2); /* the whole file, with or without its final newline */
    CHECK(parsed + failed_cleanly == (int)len + 1);

    FILE *o = fopen(tmp, "wb");
    for (int i = 0; i < HMD_PROFILE_MAX_BYTES; ++i)
        fputc(' ', o);
    fputs("{}", o);
    fclose(o);
    struct hmd_profile p;
    struct hl_error err = {{0}};
    CHECK(hmd_profile_load_json(tmp, &p, &err) != 0 && strstr(err.msg, "too large"));
    o = fopen(tmp, "wb");
    fputs("[1, 2]", o);
    fclose(o);
    CHECK(hmd_profile_load_json(tmp, &p, &err) != 0 && strstr(err.msg, "JSON object"));
    o = fopen(tmp, "wb");
    fwrite("{\"name\"\0: 1}", 1, 12, o);
    fclose(o);
    CHECK(hmd_profile_load_json(tmp, &p, &err) != 0 && strstr(err.msg, "not valid JSON"));
    remove(tmp);
}

int main(void)
{
    /* ctest sets HMDLOD_SOURCE; run by hand, fall back to this file's folder (CMake passes full paths). */
    const char *src = getenv("HMDLOD_SOURCE");
    if (src && *src) {
        snprintf(g_data_dir, sizeof g_data_dir, "%s/tests/data/displays", src);
    } else {
        const char *slash = strrchr(__FILE__, '/');
        int dir_len = slash ? (int)(slash - __FILE__) : 1;
        snprintf(g_data_dir, sizeof g_data_dir, "%.*s/data/displays", dir_len, slash ? __FILE__ : ".");
    }
    test_builtins();
    test_fov_and_override();
    test_frusta();
    test_json_valid();
    test_json_invalid();
    test_json_truncation_and_size();
    test_neck_to_eye();
    test_peak_luminance();
    return tu_finish("test_hmd");
}
