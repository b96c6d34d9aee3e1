/* render/distortion.c against the undistorted render, headless (EGL): a profile without lens
 * coefficients passes the image through unchanged; with the DK2's PanoTools coefficients the lens
 * centre stays put, pixels away from it move where the model says, and each colour channel follows
 * its own aberration scale, so red and blue separate radially in the direction the coefficients
 * say (and swap when the coefficients are swapped). */
#include "render/render.h"
#include "test_util.h"

#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { EW = 240, EH = 270 }; /* a quarter of the DK2's 960×1080 per eye: same aspect, quick */

static const uint8_t *px(const uint8_t *img, int x, int row) { return img + 4 * ((size_t)row * 2 * EW + (size_t)x); }

/* Channel c of the undistorted image at eye-uv (x right, y up) by bilinear interpolation, as the
 * GPU's linear filter samples; −1 outside the eye. */
static double sample(const uint8_t *img, int eye, double u, double v, int c)
{
    if (u < 0 || u > 1 || v < 0 || v > 1)
        return -1;
    double x = u * EW - 0.5, y = v * EH - 0.5;
    int x0 = (int)floor(x), y0 = (int)floor(y);
    double fx = x - x0, fy = y - y0, sum = 0;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            int xi = x0 + i < 0 ? 0 : x0 + i >= EW ? EW - 1 : x0 + i;
            int yi = y0 + j < 0 ? 0 : y0 + j >= EH ? EH - 1 : y0 + j;
            double w = (i ? fx : 1 - fx) * (j ? fy : 1 - fy);
            sum += w * px(img, eye * EW + xi, EH - 1 - yi)[c];
        }
    return sum;
}

/* Mean |D_c(x) − U_c(model(x))| over the left eye's pixels between radius r0 and r1 (1 = half the
 * width) from the lens centre, where `model` is the source point of `model_channel` under profile
 * `p` (NULL: the identity, i.e. "nothing moved"). */
static double mismatch(const struct hmd_profile *lens, const struct hmd_profile *p, const uint8_t *U, const uint8_t *D,
                       int c, int model_channel, double r0, double r1)
{
    double sum = 0;
    long n = 0;
    double cu, cv;
    {
        struct hmd_eye e = hmd_eye_frustum(lens, HMD_EYE_LEFT);
        cu = e.tan_left / (e.tan_left + e.tan_right), cv = e.tan_down / (e.tan_down + e.tan_up);
    }
    for (int row = 0; row < EH; ++row)
        for (int x = 0; x < EW; ++x) {
            double uv[2] = {(x + 0.5) / EW, (EH - 1 - row + 0.5) / EH}, src[2] = {uv[0], uv[1]};
            double r = hypot((uv[0] - cu) * EW, (uv[1] - cv) * EH) / (0.5 * EW);
            if (r < r0 || r > r1)
                continue;
            if (p)
                rnd_distortion_source_uv(p, HMD_EYE_LEFT, model_channel, EW, EH, uv, src);
            double s = sample(U, 0, src[0], src[1], c);
            if (s < 0)
                continue;
            sum += fabs(px(D, x, row)[c] - s);
            ++n;
        }
    return n ? sum / n : 1e9;
}

static int render_field(struct rnd_renderer *r, const struct hmd_profile *p, struct scn_scene *scene, uint8_t *U)
{
    struct hl_error err = {""};
    struct scn_scene_params sp = {0, 0};
    if (scn_scene_build("field", &sp, scene, &err) != 0 || rnd_renderer_upload_scene(r, scene, &err) != 0) {
        fprintf(stderr, "scene: %s\n", err.msg);
        return -1;
    }
    uint32_t n = scene->instance_count;
    uint32_t *index = malloc(n * sizeof *index);
    uint8_t *lod = calloc(n, 1);
    for (uint32_t i = 0; i < n; ++i)
        index[i] = i;
    struct rnd_eye_view views[2];
    for (int e = 0; e < 2; ++e) {
        struct hmd_eye eye = hmd_eye_frustum(p, e);
        views[e] = (struct rnd_eye_view){{eye.offset_x_m, 1.6, 0}, hl_q_identity(), {0}};
        hmd_eye_projection(&eye, 0.05, 200.0, views[e].projection);
    }
    struct rnd_draw_stats st;
    int rc = rnd_renderer_draw_stereo(r, scene, views, index, lod, n, &st) == 0 &&
                     rnd_renderer_read_rgba(r, U, &err) == 0
                 ? 0
                 : -1;
    free(index);
    free(lod);
    return rc;
}

static int distort(struct rnd_renderer *r, const struct hmd_profile *p, uint8_t *D, int *has_lens)
{
    struct hl_error err = {""};
    struct rnd_distortion *d = NULL;
    if (rnd_distortion_create(r, p, 2 * EW, EH, 1, &d, &err) != 0 || rnd_distortion_draw(d, 1, &err) != 0 ||
        rnd_distortion_read_rgba(d, D, &err) != 0) {
        fprintf(stderr, "distortion: %s\n", err.msg);
        rnd_distortion_destroy(d);
        return -1;
    }
    *has_lens = rnd_distortion_has_lens(d);
    rnd_distortion_destroy(d);
    return 0;
}

int main(void)
{
    dlopen("/usr/lib/x86_64-linux-gnu/dri/swrast_dri.so", RTLD_NOW | RTLD_NODELETE); /* PLATFORM.md §4 */
    struct hl_error err = {""};
    struct rnd_renderer *r = NULL;
    if (rnd_renderer_create(EW, EH, &r, &err) != 0) {
        printf("skip: no headless OpenGL 4.5: %s\n", err.msg);
        return 77;
    }
    struct hmd_profile dk2 = *hmd_builtin_find("dk2"), none = *hmd_builtin_find("vive");
    dk2.eye_width_px = none.eye_width_px = EW;
    dk2.eye_height_px = none.eye_height_px = EH;
    none.tan_left = dk2.tan_left, none.tan_right = dk2.tan_right; /* same frusta: one render serves both */
    none.tan_up = dk2.tan_up, none.tan_down = dk2.tan_down;
    size_t bytes = (size_t)2 * EW * EH * 4;
    uint8_t *U = malloc(bytes), *D = malloc(bytes);
    struct scn_scene scene = {0};
    CHECK(render_field(r, &dk2, &scene, U) == 0);

    /* No coefficients: the pass is the identity (pixel centres sample texel centres). */
    int has_lens = -1;
    CHECK(distort(r, &none, D, &has_lens) == 0);
    CHECK(has_lens == 0);
    int max_diff = 0;
    for (size_t i = 0; i < bytes; ++i)
        max_diff = abs(D[i] - U[i]) > max_diff ? abs(D[i] - U[i]) : max_diff;
    printf("no lens: largest channel difference %d\n", max_diff);
    CHECK(max_diff <= 1);

    CHECK(distort(r, &dk2, D, &has_lens) == 0);
    CHECK(has_lens == 1);
    /* The lens centre does not move (r → 0: the source point is the output point; nearby points
     * are pulled in by d = 0.795, so only the pixels within about one of the centre stay). */
    double centre = mismatch(&dk2, NULL, U, D, 1, 1, 0.0, 0.012);
    printf("dk2: centre mismatch %.2f\n", centre);
    CHECK(centre < 1.5);
    /* Away from it pixels move: the identity no longer explains the image, the model does. */
    for (int c = 0; c < 3; ++c) {
        double ident = mismatch(&dk2, NULL, U, D, c, c, 0.5, 0.95);
        double model = mismatch(&dk2, &dk2, U, D, c, c, 0.5, 0.95);
        printf("dk2 channel %d, radius 0.5-0.95: mismatch identity %.2f, model %.2f\n", c, ident, model);
        CHECK(ident > 1.0);
        CHECK(model < 0.2 * ident);
    }
    /* Fringes: red follows red's scale (0.985), not blue's (1.015), and blue the other way; with
     * red's factor smaller its image is magnified more: red lies radially outside blue. */
    double rr = mismatch(&dk2, &dk2, U, D, 0, 0, 0.5, 0.95), rb = mismatch(&dk2, &dk2, U, D, 0, 2, 0.5, 0.95);
    double bb = mismatch(&dk2, &dk2, U, D, 2, 2, 0.5, 0.95), br = mismatch(&dk2, &dk2, U, D, 2, 0, 0.5, 0.95);
    printf("dk2 fringes: red vs red model %.2f, vs blue model %.2f; blue vs blue %.2f, vs red %.2f\n", rr, rb, bb, br);
    CHECK(rr < 0.8 * rb);
    CHECK(bb < 0.8 * br);
    double out_uv[2] = {0.9, 0.5}, src_r[2], src_b[2];
    rnd_distortion_source_uv(&dk2, HMD_EYE_LEFT, 0, EW, EH, out_uv, src_r);
    rnd_distortion_source_uv(&dk2, HMD_EYE_LEFT, 2, EW, EH, out_uv, src_b);
    CHECK(src_r[0] < src_b[0]); /* red samples nearer the centre: its content lands further out */

    /* Swapped aberration: the channels swap sides. */
    struct hmd_profile swapped = dk2;
    swapped.aberration[0] = dk2.aberration[2], swapped.aberration[2] = dk2.aberration[0];
    CHECK(distort(r, &swapped, D, &has_lens) == 0);
    double srr = mismatch(&swapped, &swapped, U, D, 0, 0, 0.5, 0.95);
    double srd = mismatch(&swapped, &dk2, U, D, 0, 0, 0.5, 0.95);
    printf("swapped: red vs its model %.2f, vs the dk2 red model %.2f\n", srr, srd);
    CHECK(srr < 0.8 * srd);

    /* Bad sizes are refused. */
    struct rnd_distortion *bad = NULL;
    CHECK(rnd_distortion_create(r, &dk2, 0, EH, 1, &bad, &err) != 0 && bad == NULL);
    scn_scene_free(&scene);
    free(U);
    free(D);
    rnd_renderer_destroy(r);
    return tu_finish("distortion");
}
