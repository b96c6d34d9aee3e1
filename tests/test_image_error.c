/* render/image_error: PSNR, SSIM and foveated SSIM — closed-form cases (identical images, a uniform
 * offset, a one-pixel change) and real renders of the built-in scenes (full detail against coarser
 * levels, a turned head) checked against scikit-image (tests/ssim_oracle.py, run with Debian's
 * /usr/bin/python3) to 1e-4. Skips the oracle part with a message only when python3-skimage is absent. */
#include "acuity/acuity.h"
#include "render/render.h"
#include "test_util.h"

#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define ORACLE_TOL 1e-4

static double reddy_weight(double ecc_deg, void *user)
{
    (void)user;
    return acu_eccentricity_factor(ecc_deg); /* Reddy 1998 eq. 3 */
}

static void fill(uint8_t *rgba, size_t pixels, uint8_t r, uint8_t g, uint8_t b)
{
    for (size_t i = 0; i < pixels; ++i)
        rgba[4 * i] = r, rgba[4 * i + 1] = g, rgba[4 * i + 2] = b, rgba[4 * i + 3] = 255;
}

static void test_closed_form(void)
{
    enum { W = 64, H = 40 };
    struct hl_error err = {""};
    struct rnd_image_error_work *w = NULL;
    CHECK(rnd_image_error_work_create(W, H, &w, &err) == 0);
    uint8_t *a = malloc(W * H * 4), *b = malloc(W * H * 4);
    for (int i = 0; i < W * H; ++i) /* a pattern, so SSIM's variances are not zero */
        a[4 * i] = (uint8_t)(i * 37 % 251), a[4 * i + 1] = (uint8_t)(i * 11 % 256), a[4 * i + 2] = (uint8_t)(i % 7 * 30),
        a[4 * i + 3] = 255;
    memcpy(b, a, W * H * 4);
    struct rnd_eye_gaze g[2] = {{1, 1, 1, 1, {0, 0, -1}}, {1, 1, 1, 1, {0, 0, -1}}};
    struct rnd_image_error e;
    CHECK(rnd_image_error_compute(w, a, b, W, H, 2, g, reddy_weight, NULL, &e, &err) == 0);
    CHECK(e.mse == 0.0 && isinf(e.psnr_db) && e.psnr_db > 0);
    CHECK_NEAR(e.ssim, 1.0, 1e-12);
    CHECK_NEAR(e.ssim_rgb, 1.0, 1e-12);
    CHECK_NEAR(e.fssim, 1.0, 1e-12);
    CHECK(e.px_over_32_share == 0.0);
    /* A 90° field of view (tangents 1): the eye's corners are 54.7° out, so every band has pixels. */
    for (int k = 0; k < RND_ECC_BANDS; ++k)
        CHECK_NEAR(e.fssim_band[k], 1.0, 1e-12);

    /* A uniform offset of d levels: MSE d², PSNR 10 log10(255²/d²); SSIM's structure term stays 1
     * and only the luminance term (2μxμy + C1)/(μx² + μy² + C1) falls. */
    fill(a, W * H, 100, 100, 100);
    fill(b, W * H, 140, 140, 140);
    CHECK(rnd_image_error_compute(w, a, b, W, H, 1, NULL, NULL, NULL, &e, &err) == 0);
    CHECK_NEAR(e.mse, 1600.0, 1e-9);
    CHECK_NEAR(e.psnr_db, 10.0 * log10(255.0 * 255.0 / 1600.0), 1e-9);
    double c1 = 0.01 * 255 * 0.01 * 255;
    CHECK_NEAR(e.ssim, (2 * 100.0 * 140.0 + c1) / (100.0 * 100.0 + 140.0 * 140.0 + c1), 1e-9);
    CHECK_NEAR(e.ssim_rgb, e.ssim, 1e-12);
    CHECK(e.px_over_32_share == 1.0);
    CHECK(isnan(e.fssim));

    /* Bad arguments: one eye narrower than the window, an odd split, too large for the work space. */
    CHECK(rnd_image_error_compute(w, a, b, 20, H, 2, NULL, NULL, NULL, &e, &err) != 0);
    CHECK(rnd_image_error_compute(w, a, b, 63, H, 2, NULL, NULL, NULL, &e, &err) != 0);
    CHECK(rnd_image_error_compute(w, a, b, W, H + 1, 1, NULL, NULL, NULL, &e, &err) != 0);
    struct rnd_image_error_work *bad = NULL;
    CHECK(rnd_image_error_work_create(10, 100, &bad, &err) != 0 && bad == NULL);
    free(a);
    free(b);
    rnd_image_error_work_destroy(w);
}

/* ---- real renders against scikit-image ------------------------------------------------------ */
struct capture {
    int eye_w, eye_h;
    struct rnd_eye_gaze gaze[2];
};

static void views_for(const struct hmd_profile *p, double yaw_deg, double pitch_deg, struct rnd_eye_view v[2],
                      struct capture *c)
{
    hl_quatd q = hl_q_mul(hl_q_from_axis_angle(hl_v3(0, 1, 0), yaw_deg / HL_DEG_PER_RAD),
                          hl_q_from_axis_angle(hl_v3(1, 0, 0), pitch_deg / HL_DEG_PER_RAD));
    for (int e = 0; e < 2; ++e) {
        struct hmd_eye eye = hmd_eye_frustum(p, e == 0 ? HMD_EYE_LEFT : HMD_EYE_RIGHT);
        hl_vec3d off = hl_q_rotate(q, hl_v3(eye.offset_x_m, 0, 0));
        v[e].position_m[0] = off.x, v[e].position_m[1] = off.y, v[e].position_m[2] = off.z;
        v[e].orientation = q;
        hmd_eye_projection(&eye, 0.05, 2000.0, v[e].projection);
        /* A gaze off the centre: 8° right and 4° down in the eye's frame. */
        double gx = tan(8.0 / HL_DEG_PER_RAD), gy = -tan(4.0 / HL_DEG_PER_RAD), n = sqrt(gx * gx + gy * gy + 1.0);
        c->gaze[e] = (struct rnd_eye_gaze){eye.tan_left, eye.tan_right, eye.tan_up, eye.tan_down, {gx / n, gy / n, -1.0 / n}};
    }
}

/* Draws every instance of s at `level` (clamped to each chain's coarsest) into rgba. */
static int draw_all(struct rnd_renderer *r, const struct scn_scene *s, const struct rnd_eye_view v[2], int level,
                    uint8_t *rgba)
{
    struct hl_error err = {""};
    uint32_t n = s->instance_count;
    uint32_t *index = malloc(n * sizeof *index);
    uint8_t *lod = malloc(n);
    for (uint32_t i = 0; i < n; ++i) {
        int count = s->chains[s->chain_of_instance[i]].lod_count;
        index[i] = i;
        lod[i] = (uint8_t)(level < count ? level : count - 1);
    }
    struct rnd_draw_stats st;
    int rc = rnd_renderer_draw_stereo(r, s, v, index, lod, n, &st) || rnd_renderer_read_rgba(r, rgba, &err);
    free(index);
    free(lod);
    return rc;
}

static int oracle_available(void)
{
    if (access("/usr/bin/python3", X_OK) != 0 ||
        system("/usr/bin/python3 -c 'import skimage.metrics, PIL' >/dev/null 2>&1") != 0) {
        printf("skip: scikit-image oracle: /usr/bin/python3 with python3-skimage and python3-pil is absent "
               "(scripts/setup.sh installs them)\n");
        return 0;
    }
    return 1;
}

/* Runs the oracle on two PNGs; 0 and its ten figures, or −1. */
static int run_oracle(const char *test_png, const char *ref_png, const struct capture *c, double out[10])
{
    char cmd[8192];
    int n = snprintf(cmd, sizeof cmd, "/usr/bin/python3 '%s' '%s' '%s' 2", tu_source_path("tests/ssim_oracle.py"),
                     test_png, ref_png);
    for (int e = 0; e < 2; ++e) {
        const struct rnd_eye_gaze *g = &c->gaze[e];
        n += snprintf(cmd + n, sizeof cmd - (size_t)n, " %.17g %.17g %.17g %.17g %.17g %.17g %.17g", g->tan_left,
                      g->tan_right, g->tan_up, g->tan_down, g->gaze_eye[0], g->gaze_eye[1], g->gaze_eye[2]);
    }
    FILE *p = popen(cmd, "r");
    if (!p)
        return -1;
    int got = 0;
    for (int k = 0; k < 10; ++k)
        got += fscanf(p, "%lf", &out[k]) == 1;
    return pclose(p) == 0 && got == 10 ? 0 : -1;
}

static void compare_with_oracle(const char *label, const uint8_t *test, const uint8_t *ref, const struct capture *c,
                                struct rnd_image_error_work *w, const char *dir)
{
    struct hl_error err = {""};
    int width = 2 * c->eye_w, height = c->eye_h;
    char tp[4096], rp[4096];
    snprintf(tp, sizeof tp, "%s/%s_test.png", dir, label);
    snprintf(rp, sizeof rp, "%s/%s_ref.png", dir, label);
    CHECK(rnd_png_write(tp, test, width, height, &err) == 0);
    CHECK(rnd_png_write(rp, ref, width, height, &err) == 0);
    struct rnd_image_error e;
    CHECK(rnd_image_error_compute(w, test, ref, width, height, 2, c->gaze, reddy_weight, NULL, &e, &err) == 0);
    double o[10];
    CHECK(run_oracle(tp, rp, c, o) == 0);
    printf("%-22s ours: PSNR %.4f dB SSIM %.6f rgb %.6f fSSIM %.6f bands %.4f %.4f %.4f %.4f >32 %.4f\n", label,
           e.psnr_db, e.ssim, e.ssim_rgb, e.fssim, e.fssim_band[0], e.fssim_band[1], e.fssim_band[2], e.fssim_band[3],
           e.px_over_32_share);
    printf("%-22s skimage: PSNR %.4f dB SSIM %.6f rgb %.6f fSSIM %.6f bands %.4f %.4f %.4f %.4f >32 %.4f\n", label,
           o[1], o[2], o[3], o[4], o[5], o[6], o[7], o[8], o[9]);
    CHECK(e.mse > 0.0); /* the levels really differ: the comparison is not of equal images */
    CHECK_NEAR(e.mse, o[0], 1e-9 * o[0]);
    CHECK_NEAR(e.psnr_db, o[1], 1e-9 * o[1]);
    CHECK_NEAR(e.ssim, o[2], ORACLE_TOL);
    CHECK_NEAR(e.ssim_rgb, o[3], ORACLE_TOL);
    CHECK_NEAR(e.fssim, o[4], ORACLE_TOL);
    for (int k = 0; k < RND_ECC_BANDS; ++k)
        CHECK_NEAR(e.fssim_band[k], o[5 + k], ORACLE_TOL);
    CHECK_NEAR(e.px_over_32_share, o[9], 1e-12);
    /* Error far out counts less: the foveated SSIM is nearer 1 than the plain one whenever the
     * periphery is where the error is, and never outside [min band, max band]. */
    double lo = 1.0, hi = -1.0;
    for (int k = 0; k < RND_ECC_BANDS; ++k)
        if (isfinite(e.fssim_band[k]))
            lo = fmin(lo, e.fssim_band[k]), hi = fmax(hi, e.fssim_band[k]);
    CHECK(e.fssim >= lo - 1e-12 && e.fssim <= hi + 1e-12);
}

static void test_against_skimage(void)
{
    if (!oracle_available())
        return;
    struct hl_error err = {""};
    struct hmd_profile vive;
    CHECK(hmd_profile_load("vive", &vive, &err) == 0);
    struct capture c;
    memset(&c, 0, sizeof c);
    c.eye_w = vive.eye_width_px / 2, c.eye_h = vive.eye_height_px / 2;
    struct rnd_renderer *r = NULL;
    if (rnd_renderer_create(c.eye_w, c.eye_h, &r, &err) != 0) {
        printf("renderer: %s\n", err.msg);
        CHECK(0);
        return;
    }
    struct rnd_image_error_work *w = NULL;
    CHECK(rnd_image_error_work_create(2 * c.eye_w, c.eye_h, &w, &err) == 0);
    size_t bytes = (size_t)2 * c.eye_w * c.eye_h * 4;
    uint8_t *ref = malloc(bytes), *test = malloc(bytes);
    char dir[] = "/tmp/hmdlod-test-image-error-XXXXXX";
    CHECK(mkdtemp(dir) != NULL);

    static const struct { const char *scene; double yaw, pitch; int level; } cases[] = {
        {"field", 0.0, -5.0, 2},        /* the field from the start pose, level 2 everywhere */
        {"auditorium", 35.0, 0.0, 1},   /* the auditorium turned, one level coarser */
        {"auditorium", -20.0, 10.0, 3}, /* and much coarser */
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        struct scn_scene s = {0};
        struct scn_scene_params sp = {0, 0};
        CHECK(scn_scene_build(cases[k].scene, &sp, &s, &err) == 0);
        CHECK(rnd_renderer_upload_scene(r, &s, &err) == 0);
        struct rnd_eye_view v[2];
        views_for(&vive, cases[k].yaw, cases[k].pitch, v, &c);
        CHECK(draw_all(r, &s, v, 0, ref) == 0);
        CHECK(draw_all(r, &s, v, cases[k].level, test) == 0);
        char label[64];
        snprintf(label, sizeof label, "%s_yaw%+.0f_L%d", cases[k].scene, cases[k].yaw, cases[k].level);
        compare_with_oracle(label, test, ref, &c, w, dir);
        scn_scene_free(&s);
    }
    char cmd[4200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    CHECK(system(cmd) == 0);
    free(ref);
    free(test);
    rnd_image_error_work_destroy(w);
    rnd_renderer_destroy(r);
}

int main(void)
{
    /* Keep Mesa's driver loaded until exit so LeakSanitizer can see its globals (PLATFORM.md §4). */
    dlopen("/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so", RTLD_NOW | RTLD_NODELETE);
    test_closed_form();
    test_against_skimage();
    return tu_finish("image_error");
}
