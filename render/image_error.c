/* Image error against a full-detail reference: PSNR, SSIM (Wang et al. 2004) and a foveated SSIM.
 * SSIM follows scikit-image's structural_similarity(gaussian_weights=True, sigma=1.5,
 * use_sample_covariance=False, data_range=255) exactly, so that it can be checked against it: a
 * separable Gaussian of radius 5 (truncate 3.5), the map averaged over the pixels whose window lies
 * inside the image. The window is applied row by row through a ring of 11 filtered rows, so a
 * comparison touches each pixel a constant number of times and allocates nothing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/image_error.h"

const double rnd_ecc_band_lower_deg[RND_ECC_BANDS] = {0.0, 5.79, 15.0, 30.0};

enum { WINDOW = 2 * RND_SSIM_RADIUS_PX + 1, MOMENTS = 5 }; /* μx, μy, E[x²], E[y²], E[xy] */

struct rnd_image_error_work {
    int width_px, height_px;
    double kernel[WINDOW];
    double *row[MOMENTS];          /* one row of x, y, x², y², xy, an eye wide */
    double *ring[WINDOW][MOMENTS]; /* horizontally filtered rows, indexed by row % WINDOW */
    double *moment[MOMENTS];       /* the window's moments along one output row */
    double *weight;                /* one output row's foveation weights (or bands) */
    unsigned char *band;
};

/* Which quantity a plane is: the luminance (with the map's foveated sums) or one colour channel. */
enum plane { PLANE_LUMA = 0, PLANE_R, PLANE_G, PLANE_B, PLANES };

/* The sums one plane of one eye contributes. */
struct plane_sums {
    double ssim_sum;
    long count;
    double weighted_sum, weight_sum;
    double band_sum[RND_ECC_BANDS];
    long band_count[RND_ECC_BANDS];
};

void rnd_image_error_work_destroy(struct rnd_image_error_work *w)
{
    if (!w)
        return;
    for (int m = 0; m < MOMENTS; ++m)
        free(w->row[m]), free(w->moment[m]);
    free(w->weight);
    free(w->band);
    for (int r = 0; r < WINDOW; ++r)
        for (int m = 0; m < MOMENTS; ++m)
            free(w->ring[r][m]);
    free(w);
}

int rnd_image_error_work_create(int width_px, int height_px, struct rnd_image_error_work **out, struct hl_error *err)
{
    *out = NULL;
    if (width_px < WINDOW || height_px < WINDOW || width_px > 65536 || height_px > 65536)
        return hl_fail(err, "image error: %d x %d px is outside [%d, 65536] per side", width_px, height_px, WINDOW);
    struct rnd_image_error_work *w = calloc(1, sizeof *w);
    if (!w)
        return hl_fail(err, "image error: out of memory");
    w->width_px = width_px;
    w->height_px = height_px;
    size_t row = (size_t)width_px * sizeof(double);
    int ok = (w->weight = malloc(row)) != NULL && (w->band = malloc((size_t)width_px)) != NULL;
    for (int m = 0; m < MOMENTS && ok; ++m)
        ok = (w->row[m] = malloc(row)) != NULL && (w->moment[m] = malloc(row)) != NULL;
    for (int r = 0; r < WINDOW && ok; ++r)
        for (int m = 0; m < MOMENTS && ok; ++m)
            ok = (w->ring[r][m] = malloc(row)) != NULL;
    if (!ok) {
        rnd_image_error_work_destroy(w);
        return hl_fail(err, "image error: out of memory for %d px rows", width_px);
    }
    /* scipy.ndimage.gaussian_filter1d's weights: exp(−x²/2σ²) over |x| ≤ radius, normalised. */
    double sum = 0.0;
    for (int i = 0; i < WINDOW; ++i) {
        double d = (double)(i - RND_SSIM_RADIUS_PX);
        w->kernel[i] = exp(-0.5 * d * d / (RND_SSIM_SIGMA_PX * RND_SSIM_SIGMA_PX));
        sum += w->kernel[i];
    }
    for (int i = 0; i < WINDOW; ++i)
        w->kernel[i] /= sum;
    *out = w;
    return 0;
}

static double plane_value(const uint8_t *px, enum plane p)
{
    if (p == PLANE_LUMA) /* ITU-R BT.601 luma, on the stored (sRGB-encoded) levels as SSIM is usually run */
        return 0.299 * px[0] + 0.587 * px[1] + 0.114 * px[2];
    return (double)px[p - PLANE_R];
}

/* Row `row` of one eye's plane, filtered horizontally into the ring (columns [r, eye_w − r) only).
 * The kernel is symmetric: each tap pair is added once, in loops over x the compiler vectorises. */
static void filter_row(struct rnd_image_error_work *w, const uint8_t *test, const uint8_t *ref, int stride_px,
                       int x0, int eye_w, int row, enum plane p)
{
    const uint8_t *a = test + ((size_t)row * (size_t)stride_px + (size_t)x0) * 4;
    const uint8_t *b = ref + ((size_t)row * (size_t)stride_px + (size_t)x0) * 4;
    double *restrict vx = w->row[0], *restrict vy = w->row[1];
    for (int x = 0; x < eye_w; ++x) {
        double u = plane_value(a + 4 * x, p), v = plane_value(b + 4 * x, p);
        vx[x] = u, vy[x] = v;
        w->row[2][x] = u * u, w->row[3][x] = v * v, w->row[4][x] = u * v;
    }
    const int r = RND_SSIM_RADIUS_PX;
    for (int m = 0; m < MOMENTS; ++m) {
        const double *restrict in = w->row[m];
        double *restrict out = w->ring[row % WINDOW][m];
        double g0 = w->kernel[r];
        for (int x = r; x < eye_w - r; ++x)
            out[x] = g0 * in[x];
        for (int j = 1; j <= r; ++j) {
            double g = w->kernel[r + j];
            for (int x = r; x < eye_w - r; ++x)
                out[x] += g * (in[x - j] + in[x + j]);
        }
    }
}

/* The window's moments along output row y from the ring's 11 rows around it (vertical pass). */
static void filter_column(struct rnd_image_error_work *w, int y, int eye_w)
{
    const int r = RND_SSIM_RADIUS_PX;
    for (int m = 0; m < MOMENTS; ++m) {
        double *restrict out = w->moment[m];
        const double *restrict mid = w->ring[y % WINDOW][m];
        double g0 = w->kernel[r];
        for (int x = r; x < eye_w - r; ++x)
            out[x] = g0 * mid[x];
        for (int j = 1; j <= r; ++j) {
            const double *restrict up = w->ring[(y - j) % WINDOW][m], *restrict down = w->ring[(y + j) % WINDOW][m];
            double g = w->kernel[r + j];
            for (int x = r; x < eye_w - r; ++x)
                out[x] += g * (up[x] + down[x]);
        }
    }
}

/* Eccentricity of pixel (x, y) of an eye image: the angle between its ray and the gaze, by atan2. */
static double pixel_eccentricity_deg(const struct rnd_eye_gaze *g, int x, int y, int eye_w, int eye_h)
{
    double tx = -g->tan_left + ((double)x + 0.5) / eye_w * (g->tan_left + g->tan_right);
    double ty = g->tan_up - ((double)y + 0.5) / eye_h * (g->tan_up + g->tan_down);
    double d[3] = {tx, ty, -1.0};
    const double *q = g->gaze_eye;
    double cx = d[1] * q[2] - d[2] * q[1], cy = d[2] * q[0] - d[0] * q[2], cz = d[0] * q[1] - d[1] * q[0];
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * HL_DEG_PER_RAD;
}

static int band_of(double ecc_deg)
{
    int b = RND_ECC_BANDS - 1;
    while (b > 0 && ecc_deg < rnd_ecc_band_lower_deg[b])
        --b;
    return b;
}

/* One output row's foveation weights and bands (the eccentricity of each pixel, by atan2). */
static void row_weights(struct rnd_image_error_work *w, const struct rnd_eye_gaze *gaze, int y, int eye_w, int eye_h,
                        double (*weight)(double, void *), void *user)
{
    for (int x = RND_SSIM_RADIUS_PX; x < eye_w - RND_SSIM_RADIUS_PX; ++x) {
        double e = pixel_eccentricity_deg(gaze, x, y, eye_w, eye_h);
        w->weight[x] = weight ? weight(e, user) : 1.0;
        w->band[x] = (unsigned char)band_of(e);
    }
}

/* Wang et al. 2004 eq. 13 over one eye's plane, with the foveated sums when gaze is given. */
static void plane_ssim(struct rnd_image_error_work *w, const uint8_t *test, const uint8_t *ref, int stride_px, int x0,
                       int eye_w, int eye_h, enum plane p, const struct rnd_eye_gaze *gaze,
                       double (*weight)(double, void *), void *user, struct plane_sums *s)
{
    const double c1 = (RND_SSIM_K1 * 255.0) * (RND_SSIM_K1 * 255.0), c2 = (RND_SSIM_K2 * 255.0) * (RND_SSIM_K2 * 255.0);
    const int r = RND_SSIM_RADIUS_PX;
    memset(s, 0, sizeof *s);
    for (int row = 0; row < WINDOW - 1; ++row)
        filter_row(w, test, ref, stride_px, x0, eye_w, row, p);
    for (int y = r; y < eye_h - r; ++y) {
        filter_row(w, test, ref, stride_px, x0, eye_w, y + r, p);
        filter_column(w, y, eye_w);
        if (gaze)
            row_weights(w, gaze, y, eye_w, eye_h, weight, user);
        const double *mx = w->moment[0], *my = w->moment[1], *xx = w->moment[2], *yy = w->moment[3], *xy = w->moment[4];
        for (int x = r; x < eye_w - r; ++x) {
            double vx = xx[x] - mx[x] * mx[x], vy = yy[x] - my[x] * my[x], vxy = xy[x] - mx[x] * my[x];
            double ssim = ((2.0 * mx[x] * my[x] + c1) * (2.0 * vxy + c2)) /
                          ((mx[x] * mx[x] + my[x] * my[x] + c1) * (vx + vy + c2));
            s->ssim_sum += ssim;
            if (gaze) {
                s->weighted_sum += w->weight[x] * ssim;
                s->weight_sum += w->weight[x];
                s->band_sum[w->band[x]] += ssim;
                s->band_count[w->band[x]]++;
            }
        }
    }
    s->count = (long)(eye_w - 2 * r) * (long)(eye_h - 2 * r);
}

static void pixel_errors(const uint8_t *a, const uint8_t *b, size_t pixels, struct rnd_image_error *out)
{
    double sq = 0.0;
    size_t over = 0;
    for (size_t i = 0; i < pixels; ++i) {
        int worst = 0;
        for (int c = 0; c < 3; ++c) {
            int d = (int)a[4 * i + c] - (int)b[4 * i + c];
            sq += (double)(d * d);
            worst = abs(d) > worst ? abs(d) : worst;
        }
        over += worst > 32;
    }
    out->mse = sq / (3.0 * (double)pixels);
    out->psnr_db = out->mse > 0.0 ? 10.0 * log10(255.0 * 255.0 / out->mse) : INFINITY;
    out->px_over_32_share = (double)over / (double)pixels;
}

int rnd_image_error_compute(struct rnd_image_error_work *w, const uint8_t *test, const uint8_t *reference, int width_px,
                            int height_px, int eyes, const struct rnd_eye_gaze *gaze,
                            double (*weight)(double eccentricity_deg, void *user), void *user,
                            struct rnd_image_error *out, struct hl_error *err)
{
    if (!w || !test || !reference || !out || (eyes != 1 && eyes != 2))
        return hl_fail(err, "image error: bad arguments");
    if (width_px > w->width_px || height_px > w->height_px || width_px % eyes != 0 || width_px / eyes < WINDOW ||
        height_px < WINDOW)
        return hl_fail(err, "image error: %d x %d px in %d eye%s does not fit the work space (%d x %d) or is under %d px",
                       width_px, height_px, eyes, eyes == 1 ? "" : "s", w->width_px, w->height_px, WINDOW);
    pixel_errors(test, reference, (size_t)width_px * (size_t)height_px, out);
    int eye_w = width_px / eyes;
    double plane_mean[PLANES] = {0};
    double weighted = 0.0, weights = 0.0, band_sum[RND_ECC_BANDS] = {0};
    long band_count[RND_ECC_BANDS] = {0};
    for (int e = 0; e < eyes; ++e) {
        for (int p = 0; p < PLANES; ++p) {
            struct plane_sums s;
            const struct rnd_eye_gaze *g = p == PLANE_LUMA && gaze ? &gaze[e] : NULL;
            plane_ssim(w, test, reference, width_px, e * eye_w, eye_w, height_px, (enum plane)p, g, weight, user, &s);
            plane_mean[p] += s.ssim_sum / (double)s.count / eyes;
            weighted += s.weighted_sum;
            weights += s.weight_sum;
            for (int b = 0; b < RND_ECC_BANDS; ++b)
                band_sum[b] += s.band_sum[b], band_count[b] += s.band_count[b];
        }
    }
    out->ssim = plane_mean[PLANE_LUMA];
    out->ssim_rgb = (plane_mean[PLANE_R] + plane_mean[PLANE_G] + plane_mean[PLANE_B]) / 3.0;
    out->fssim = gaze && weights > 0.0 ? weighted / weights : NAN;
    for (int b = 0; b < RND_ECC_BANDS; ++b)
        out->fssim_band[b] = band_count[b] > 0 ? band_sum[b] / (double)band_count[b] : NAN;
    return 0;
}
