/* LDR-FLIP (Andersson et al., HPG 2020) as NVIDIA's FLIP tool computes it (FLIP.h, LDR path), written
 * anew in double:
 *   1. sRGB → linear RGB → XYZ → YCxCz (opponent space, linear in XYZ; D65 white);
 *   2. the spatial CSF: each YCxCz channel convolved with a sum of Gaussians a·√(π/b)·exp(−π²x²/b)
 *      (x in degrees), each filter normalised to sum 1 (the Cz filter, a sum of two Gaussians, is
 *      applied as two separable passes normalised together), edges repeated;
 *   3. filtered YCxCz → linear RGB clamped to [0, 1] → CIELAB → Hunt-adjusted (a, b scaled by L/100);
 *      the colour error is the HyAB distance |ΔL| + ‖Δ(a, b)‖ to the power qc, remapped to [0, 1]
 *      with [0, pc·cmax) → [0, pt) and [pc·cmax, cmax] → [pt, 1], where cmax is the distance between
 *      pure green and pure blue;
 *   4. the features: luminance (Y + 16)/116 convolved with a Gaussian of σ = w/2 degrees and its first
 *      and second derivatives (radius ⌈3σ⌉ px; the Gaussian normalised to sum 1, the derivatives'
 *      positive and negative weights to +1 and −1); edge = ‖(∂x, ∂y)‖, point = ‖(∂xx, ∂yy)‖; the feature
 *      error is (max(|Δedge|, |Δpoint|)/√2)^qf;
 *   5. the pixel's error = colour error^(1 − feature error).
 * Both convolutions are separable. Each eye is swept row by row: a source row is converted and
 * filtered horizontally into a ring of the 2R + 1 rows the vertical pass needs (R the larger of the two
 * radii), so the scratch is a few rows per eye plus one double per pixel for the pooling. A pixel
 * whose filtered values are equal in both images has error exactly 0 and skips the conversions, and
 * only the nonzero errors are sorted for the weighted percentiles (zeros weigh nothing). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/flip.h"
#include "render/render_internal.h"

#define FLIP_PI 3.14159265358979323846

/* The spatial CSF's Gaussians per channel (Y, Cx, Cz): a1·g(b1) + a2·g(b2) (the paper's Table 1). */
static const double csf_a1[3] = {1.0, 1.0, 34.1};
static const double csf_b1[3] = {0.0047, 0.0053, 0.04};
static const double csf_a2[3] = {0.0, 0.0, 13.5};
static const double csf_b2[3] = {1.0e-5, 1.0e-5, 0.025};
static const double csf_b_max = 0.04; /* the widest of the b's sets the spatial filter's radius */

/* D65 white in XYZ (Y = 1) and its inverse, as the tool has them. */
static const double white_x = 0.950428545, white_z = 1.088900371;
static const double inv_white_x = 1.052156925, inv_white_z = 0.918357670;

/* Linear sRGB ↔ XYZ (D65). */
static const double rgb_to_xyz[3][3] = {
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0},
};
static const double xyz_to_rgb[3][3] = {
    {3.241003275, -1.537398934, -0.498615861},
    {-0.969224334, 1.875930071, 0.041554224},
    {0.055639423, -0.204011202, 1.057148933},
};

/* Channels of a converted source row (per image) and of the horizontally filtered rows in the ring. */
enum { SRC_Y, SRC_CX, SRC_CZ, SRC_YN, SRC_CHANNELS };
enum { H_Y, H_CX, H_CZ1, H_CZ2, H_DX, H_DDX, H_G, H_CHANNELS };
/* The vertical pass's sums along one output row, per image. */
enum { V_Y, V_CX, V_CZ, V_DX, V_DDX, V_DY, V_DDY, V_CHANNELS };

struct flip_scratch {
    int eye_w, radius_s, radius_f, pad, ring_rows;
    double *spatial; /* 4 × (2·radius_s + 1): Y, Cx, Cz's first and second Gaussian */
    double *feature; /* 3 × (2·radius_f + 1): Gaussian, first and second derivative */
    double *src;     /* [image][SRC_CHANNELS][pad + eye_w + pad] */
    double *ring;    /* [slot][image][H_CHANNELS][eye_w] */
    double *acc;     /* [image][V_CHANNELS][eye_w] */
    double *values;  /* every pixel's error, for the pooling */
};

static double clamp01(double v)
{
    return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
}

static double lab_f(double t)
{
    const double delta = 6.0 / 29.0;
    return t > delta * delta * delta ? cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
}

/* Linear RGB (already in [0, 1]) → CIELAB with the Hunt adjustment. */
static void rgb_to_hunt_lab(const double rgb[3], double lab[3])
{
    double xyz[3];
    for (int i = 0; i < 3; ++i)
        xyz[i] = rgb_to_xyz[i][0] * rgb[0] + rgb_to_xyz[i][1] * rgb[1] + rgb_to_xyz[i][2] * rgb[2];
    double fx = lab_f(xyz[0] * inv_white_x), fy = lab_f(xyz[1]), fz = lab_f(xyz[2] * inv_white_z);
    double l = 116.0 * fy - 16.0;
    lab[0] = l;
    lab[1] = 0.01 * l * 500.0 * (fx - fy);
    lab[2] = 0.01 * l * 200.0 * (fy - fz);
}

/* Filtered YCxCz → linear RGB clamped to [0, 1] → Hunt-adjusted CIELAB. */
static void ycxcz_to_hunt_lab(double y, double cx, double cz, double lab[3])
{
    double fy = (y + 16.0) / 116.0;
    double xyz[3] = {(fy + cx / 500.0) * white_x, fy, (fy - cz / 200.0) * white_z};
    double rgb[3];
    for (int i = 0; i < 3; ++i)
        rgb[i] = clamp01(xyz_to_rgb[i][0] * xyz[0] + xyz_to_rgb[i][1] * xyz[1] + xyz_to_rgb[i][2] * xyz[2]);
    rgb_to_hunt_lab(rgb, lab);
}

static double hyab(const double a[3], const double b[3])
{
    double da = a[1] - b[1], db = a[2] - b[2];
    return fabs(a[0] - b[0]) + sqrt(da * da + db * db);
}

/* Fills the normalised 1-D filters (the header comment's steps 2 and 4). A weight set whose sum
 * underflows to 0 (a feature σ of a few hundredths of a pixel) is left at 0 rather than divided. */
static void make_filters(struct flip_scratch *s, double ppd)
{
    int ns = 2 * s->radius_s + 1, nf = 2 * s->radius_f + 1;
    double sum[4] = {0, 0, 0, 0};
    for (int k = 0; k < ns; ++k) {
        double x_deg = (k - s->radius_s) / ppd, x2 = x_deg * x_deg;
        double *w = s->spatial;
        for (int c = 0; c < 2; ++c) /* Y and Cx: one Gaussian each (a2 = 0) */
            w[c * ns + k] = csf_a1[c] * sqrt(FLIP_PI / csf_b1[c]) * exp(-FLIP_PI * FLIP_PI * x2 / csf_b1[c]);
        /* Cz: a1·g(b1) + a2·g(b2) in 2-D is the sum of two separable products, each of whose 1-D
         * factors carries the square root of its Gaussian's 2-D amplitude a·π/b. */
        w[2 * ns + k] = sqrt(csf_a1[2] * sqrt(FLIP_PI / csf_b1[2])) * exp(-FLIP_PI * FLIP_PI * x2 / csf_b1[2]);
        w[3 * ns + k] = sqrt(csf_a2[2] * sqrt(FLIP_PI / csf_b2[2])) * exp(-FLIP_PI * FLIP_PI * x2 / csf_b2[2]);
        for (int c = 0; c < 4; ++c)
            sum[c] += w[c * ns + k];
    }
    double norm_cz = sqrt(sum[2] * sum[2] + sum[3] * sum[3]); /* the 2-D Cz filter sums to 1 */
    for (int k = 0; k < ns; ++k) {
        s->spatial[0 * ns + k] /= sum[0];
        s->spatial[1 * ns + k] /= sum[1];
        s->spatial[2 * ns + k] /= norm_cz;
        s->spatial[3 * ns + k] /= norm_cz;
    }

    double sigma_px = 0.5 * RND_FLIP_FEATURE_WIDTH_DEG * ppd;
    double g_sum = 0, d_pos = 0, d_neg = 0, dd_pos = 0, dd_neg = 0;
    double *g = s->feature, *dg = s->feature + nf, *ddg = s->feature + 2 * nf;
    for (int k = 0; k < nf; ++k) {
        double x = k - s->radius_f;
        g[k] = exp(-x * x / (2.0 * sigma_px * sigma_px));
        dg[k] = -x * g[k];
        ddg[k] = (x * x / (sigma_px * sigma_px) - 1.0) * g[k];
        g_sum += g[k];
        if (dg[k] > 0)
            d_pos += dg[k];
        else
            d_neg -= dg[k];
        if (ddg[k] > 0)
            dd_pos += ddg[k];
        else
            dd_neg -= ddg[k];
    }
    for (int k = 0; k < nf; ++k) {
        double dn = dg[k] > 0 ? d_pos : d_neg, ddn = ddg[k] > 0 ? dd_pos : dd_neg;
        g[k] = g_sum > 0 ? g[k] / g_sum : 0.0;
        dg[k] = dn > 0 ? dg[k] / dn : 0.0;
        ddg[k] = ddn > 0 ? ddg[k] / ddn : 0.0;
    }
}

static void scratch_free(struct flip_scratch *s)
{
    free(s->spatial);
    free(s->feature);
    free(s->src);
    free(s->ring);
    free(s->acc);
    free(s->values);
}

/* Converts source row y of one eye (both images) to YCxCz plus normalised luminance, its edges
 * repeated into the padding, then filters it horizontally into its ring slot. */
static void fill_row(struct flip_scratch *s, const uint8_t *const img[2], int width_px, int x0, int y,
                     const double srgb_to_linear[256])
{
    int ew = s->eye_w, pad = s->pad, span = pad + ew + pad;
    int ns = 2 * s->radius_s + 1, nf = 2 * s->radius_f + 1;
    double *slot = s->ring + (size_t)(y % s->ring_rows) * 2 * H_CHANNELS * (size_t)ew;
    for (int m = 0; m < 2; ++m) {
        const uint8_t *row = img[m] + ((size_t)y * (size_t)width_px + (size_t)x0) * 4;
        double *src = s->src + (size_t)m * SRC_CHANNELS * (size_t)span;
        for (int x = 0; x < ew; ++x) {
            double rgb[3] = {srgb_to_linear[row[4 * x]], srgb_to_linear[row[4 * x + 1]],
                             srgb_to_linear[row[4 * x + 2]]};
            double xyz[3];
            for (int i = 0; i < 3; ++i)
                xyz[i] = rgb_to_xyz[i][0] * rgb[0] + rgb_to_xyz[i][1] * rgb[1] + rgb_to_xyz[i][2] * rgb[2];
            double xw = xyz[0] * inv_white_x, yw = xyz[1], zw = xyz[2] * inv_white_z;
            double lum = 116.0 * yw - 16.0;
            src[SRC_Y * span + pad + x] = lum;
            src[SRC_CX * span + pad + x] = 500.0 * (xw - yw);
            src[SRC_CZ * span + pad + x] = 200.0 * (yw - zw);
            src[SRC_YN * span + pad + x] = lum / 116.0 + 16.0 / 116.0;
        }
        for (int c = 0; c < SRC_CHANNELS; ++c) {
            double *p = src + c * span;
            for (int k = 0; k < pad; ++k)
                p[k] = p[pad], p[pad + ew + k] = p[pad + ew - 1];
        }

        double *h = slot + (size_t)m * H_CHANNELS * (size_t)ew;
        for (int c = 0; c < H_CHANNELS; ++c)
            memset(h + (size_t)c * (size_t)ew, 0, (size_t)ew * sizeof *h);
        const double *py = src + SRC_Y * span + pad - s->radius_s, *pcx = src + SRC_CX * span + pad - s->radius_s;
        const double *pcz = src + SRC_CZ * span + pad - s->radius_s;
        for (int k = 0; k < ns; ++k) {
            double wy = s->spatial[k], wcx = s->spatial[ns + k], wz1 = s->spatial[2 * ns + k],
                   wz2 = s->spatial[3 * ns + k];
            for (int x = 0; x < ew; ++x) {
                h[H_Y * ew + x] += wy * py[x + k];
                h[H_CX * ew + x] += wcx * pcx[x + k];
                h[H_CZ1 * ew + x] += wz1 * pcz[x + k];
                h[H_CZ2 * ew + x] += wz2 * pcz[x + k];
            }
        }
        const double *pn = src + SRC_YN * span + pad - s->radius_f;
        for (int k = 0; k < nf; ++k) {
            double wg = s->feature[k], wd = s->feature[nf + k], wdd = s->feature[2 * nf + k];
            for (int x = 0; x < ew; ++x) {
                h[H_DX * ew + x] += wd * pn[x + k];
                h[H_DDX * ew + x] += wdd * pn[x + k];
                h[H_G * ew + x] += wg * pn[x + k];
            }
        }
    }
}

/* One eye: rows top to bottom, the vertical pass over the ring, each pixel's error into s->values
 * (and error_map) at its place in the whole image. */
static void flip_eye(struct flip_scratch *s, const uint8_t *const img[2], int width_px, int height_px, int x0,
                     const double srgb_to_linear[256], double cmax, float *error_map)
{
    int ew = s->eye_w, ns = 2 * s->radius_s + 1, nf = 2 * s->radius_f + 1;
    int reach = s->radius_s > s->radius_f ? s->radius_s : s->radius_f;
    double pc_cmax = RND_FLIP_PC * cmax;
    int next = 0; /* the next source row to convert and filter horizontally */
    for (int y = 0; y < height_px; ++y) {
        int last = y + reach < height_px - 1 ? y + reach : height_px - 1;
        for (; next <= last; ++next)
            fill_row(s, img, width_px, x0, next, srgb_to_linear);

        memset(s->acc, 0, (size_t)2 * V_CHANNELS * (size_t)ew * sizeof *s->acc);
        for (int m = 0; m < 2; ++m) {
            double *a = s->acc + (size_t)m * V_CHANNELS * (size_t)ew;
            for (int k = 0; k < ns; ++k) {
                int yy = y + k - s->radius_s;
                yy = yy < 0 ? 0 : yy > height_px - 1 ? height_px - 1 : yy;
                const double *h = s->ring + ((size_t)(yy % s->ring_rows) * 2 + (size_t)m) * H_CHANNELS * (size_t)ew;
                double wy = s->spatial[k], wcx = s->spatial[ns + k], wz1 = s->spatial[2 * ns + k],
                       wz2 = s->spatial[3 * ns + k];
                for (int x = 0; x < ew; ++x) {
                    a[V_Y * ew + x] += wy * h[H_Y * ew + x];
                    a[V_CX * ew + x] += wcx * h[H_CX * ew + x];
                    a[V_CZ * ew + x] += wz1 * h[H_CZ1 * ew + x] + wz2 * h[H_CZ2 * ew + x];
                }
            }
            for (int k = 0; k < nf; ++k) {
                int yy = y + k - s->radius_f;
                yy = yy < 0 ? 0 : yy > height_px - 1 ? height_px - 1 : yy;
                const double *h = s->ring + ((size_t)(yy % s->ring_rows) * 2 + (size_t)m) * H_CHANNELS * (size_t)ew;
                double wg = s->feature[k], wd = s->feature[nf + k], wdd = s->feature[2 * nf + k];
                for (int x = 0; x < ew; ++x) {
                    a[V_DX * ew + x] += wg * h[H_DX * ew + x];
                    a[V_DDX * ew + x] += wg * h[H_DDX * ew + x];
                    a[V_DY * ew + x] += wd * h[H_G * ew + x];
                    a[V_DDY * ew + x] += wdd * h[H_G * ew + x];
                }
            }
        }

        const double *a0 = s->acc, *a1 = s->acc + (size_t)V_CHANNELS * (size_t)ew;
        for (int x = 0; x < ew; ++x) {
            size_t i = (size_t)y * (size_t)width_px + (size_t)x0 + (size_t)x;
            int same = 1; /* equal filtered values: HyAB 0, features 0, error exactly 0 */
            for (int c = 0; c < V_CHANNELS && same; ++c)
                same = a0[c * ew + x] == a1[c * ew + x];
            if (same) {
                s->values[i] = 0.0;
                if (error_map)
                    error_map[i] = 0.0f;
                continue;
            }
            double lab0[3], lab1[3];
            ycxcz_to_hunt_lab(a0[V_Y * ew + x], a0[V_CX * ew + x], a0[V_CZ * ew + x], lab0);
            ycxcz_to_hunt_lab(a1[V_Y * ew + x], a1[V_CX * ew + x], a1[V_CZ * ew + x], lab1);
            double colour = pow(hyab(lab0, lab1), RND_FLIP_QC);
            colour = colour < pc_cmax ? colour * RND_FLIP_PT / pc_cmax
                                      : RND_FLIP_PT + (colour - pc_cmax) / (cmax - pc_cmax) * (1.0 - RND_FLIP_PT);

            double edge0 = hypot(a0[V_DX * ew + x], a0[V_DY * ew + x]);
            double edge1 = hypot(a1[V_DX * ew + x], a1[V_DY * ew + x]);
            double point0 = hypot(a0[V_DDX * ew + x], a0[V_DDY * ew + x]);
            double point1 = hypot(a1[V_DDX * ew + x], a1[V_DDY * ew + x]);
            double d = fmax(fabs(edge0 - edge1), fabs(point0 - point1));
            double feature = pow(d / sqrt(2.0), RND_FLIP_QF);

            double e = pow(colour, 1.0 - feature);
            s->values[i] = e;
            if (error_map)
                error_map[i] = (float)e;
        }
    }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The tool's weighted percentile over values sorted ascending, whose sum is total. */
static double weighted_percentile(const double *sorted, size_t n, double total, double p)
{
    double running = 0.0;
    for (size_t i = 0; i < n; ++i) {
        running += sorted[i];
        if (running > p * total)
            return sorted[i];
    }
    return 0.0;
}

int rnd_flip_compute(const uint8_t *test, const uint8_t *reference, int width_px, int height_px, int eyes,
                     double pixels_per_degree, struct rnd_flip_result *out, float *error_map, struct hl_error *err)
{
    if (!test || !reference || !out)
        return hl_fail(err, "flip: missing image or result");
    if (eyes != 1 && eyes != 2)
        return hl_fail(err, "flip: %d eyes (1 or 2)", eyes);
    if (width_px < 1 || height_px < 1 || width_px > 65536 || height_px > 65536)
        return hl_fail(err, "flip: %d x %d px is outside [1, 65536] per side", width_px, height_px);
    if (width_px % eyes != 0)
        return hl_fail(err, "flip: width %d px does not split into %d eyes", width_px, eyes);
    if (!isfinite(pixels_per_degree) || pixels_per_degree <= 0.0 || pixels_per_degree > 10000.0)
        return hl_fail(err, "flip: pixels per degree %g is not in (0, 10000]", pixels_per_degree);

    struct flip_scratch s;
    memset(&s, 0, sizeof s);
    s.eye_w = width_px / eyes;
    s.radius_s = (int)ceil(3.0 * sqrt(csf_b_max / (2.0 * FLIP_PI * FLIP_PI)) * pixels_per_degree);
    s.radius_f = (int)ceil(3.0 * 0.5 * RND_FLIP_FEATURE_WIDTH_DEG * pixels_per_degree);
    s.pad = s.radius_s > s.radius_f ? s.radius_s : s.radius_f;
    s.ring_rows = 2 * s.pad + 1;
    size_t ew = (size_t)s.eye_w, span = (size_t)(2 * s.pad) + ew, pixels = (size_t)width_px * (size_t)height_px;
    s.spatial = malloc((size_t)4 * (size_t)(2 * s.radius_s + 1) * sizeof *s.spatial);
    s.feature = malloc((size_t)3 * (size_t)(2 * s.radius_f + 1) * sizeof *s.feature);
    s.src = malloc((size_t)2 * SRC_CHANNELS * span * sizeof *s.src);
    s.ring = malloc((size_t)s.ring_rows * 2 * H_CHANNELS * ew * sizeof *s.ring);
    s.acc = malloc((size_t)2 * V_CHANNELS * ew * sizeof *s.acc);
    s.values = malloc(pixels * sizeof *s.values);
    if (!s.spatial || !s.feature || !s.src || !s.ring || !s.acc || !s.values) {
        scratch_free(&s);
        return hl_fail(err, "flip: out of memory for %d x %d px", width_px, height_px);
    }
    make_filters(&s, pixels_per_degree);

    const double *srgb_to_linear = rnd_srgb_decode_table();
    static const double green[3] = {0, 1, 0}, blue[3] = {0, 0, 1};
    double lab_green[3], lab_blue[3];
    rgb_to_hunt_lab(green, lab_green);
    rgb_to_hunt_lab(blue, lab_blue);
    double cmax = pow(hyab(lab_green, lab_blue), RND_FLIP_QC);

    const uint8_t *const img[2] = {reference, test};
    for (int e = 0; e < eyes; ++e)
        flip_eye(&s, img, width_px, height_px, e * s.eye_w, srgb_to_linear, cmax, error_map);

    /* Zeros add nothing to the weighted sums, so only the nonzero errors are sorted (a frame that
     * differs from its reference in a few objects sorts a few pixels). */
    double sum = 0.0, lo = INFINITY, hi = -INFINITY;
    size_t nonzero = 0;
    for (size_t i = 0; i < pixels; ++i) {
        double v = s.values[i];
        sum += v;
        lo = v < lo ? v : lo;
        hi = v > hi ? v : hi;
        if (v != 0.0)
            s.values[nonzero++] = v;
    }
    qsort(s.values, nonzero, sizeof *s.values, cmp_double);
    double total = 0.0; /* summed in the order the percentiles walk */
    for (size_t i = 0; i < nonzero; ++i)
        total += s.values[i];
    out->mean = sum / (double)pixels;
    out->weighted_median = weighted_percentile(s.values, nonzero, total, 0.5);
    out->weighted_q1 = weighted_percentile(s.values, nonzero, total, 0.25);
    out->weighted_q3 = weighted_percentile(s.values, nonzero, total, 0.75);
    out->min = lo;
    out->max = hi;
    scratch_free(&s);
    return 0;
}
