/* The image half of Reddy's offline analysis (1998 §3.3): colour difference in CIELUV, the regions
 * where two renders differ (8-connected components, two-pass union-find) and their sizes "along
 * several orientations" (run lengths through each pixel at 0, 45, 90 and 135 degrees). Pure CPU;
 * analyze.c renders the images. */
#include "render/analyze_internal.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* ---- colour ---------------------------------------------------------------------------------- */

/* IEC 61966-2-1 decoding: linear segment below 0.04045, then the 2.4 power. */
double rnd_srgb_decode(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

/* sRGB primaries and D65 white to XYZ (IEC 61966-2-1 matrix, 4 decimals widened as in Lindbloom's
 * tables); white (1,1,1) maps to Xn = 0.95047, Yn = 1, Zn = 1.08883. */
static const double rnd_rgb_to_xyz[3][3] = {
    {0.4124564, 0.3575761, 0.1804375},
    {0.2126729, 0.7151522, 0.0721750},
    {0.0193339, 0.1191920, 0.9503041},
};

static void rnd_linear_to_luv(const double lin[3], double luv[3])
{
    double xyz[3];
    for (int i = 0; i < 3; ++i)
        xyz[i] = rnd_rgb_to_xyz[i][0] * lin[0] + rnd_rgb_to_xyz[i][1] * lin[1] + rnd_rgb_to_xyz[i][2] * lin[2];
    const double xn = 0.4124564 + 0.3575761 + 0.1804375, zn = 0.0193339 + 0.1191920 + 0.9503041;
    const double dn = xn + 15.0 + 3.0 * zn, un = 4.0 * xn / dn, vn = 9.0 / dn;
    /* CIE 1976: L* = 116 (Y/Yn)^(1/3) − 16 above (6/29)^3, (29/3)^3 Y/Yn below. */
    double y = xyz[1];
    double l = y > 216.0 / 24389.0 ? 116.0 * cbrt(y) - 16.0 : 24389.0 / 27.0 * y;
    double d = xyz[0] + 15.0 * xyz[1] + 3.0 * xyz[2];
    if (!(d > 0)) { /* black: u*, v* are 0 by continuity (L* = 0) */
        luv[0] = l, luv[1] = 0, luv[2] = 0;
        return;
    }
    luv[0] = l;
    luv[1] = 13.0 * l * (4.0 * xyz[0] / d - un);
    luv[2] = 13.0 * l * (9.0 * xyz[1] / d - vn);
}

/* The 256 decoded values, computed once (pure function of the byte, so any thread may fill it). */
static double rnd_srgb_lut[256];
static int rnd_srgb_lut_ready;

const double *rnd_srgb_decode_table(void)
{
    if (!rnd_srgb_lut_ready) {
        for (int i = 0; i < 256; ++i)
            rnd_srgb_lut[i] = rnd_srgb_decode(i / 255.0);
        rnd_srgb_lut_ready = 1;
    }
    return rnd_srgb_lut;
}

void rnd_srgb8_to_luv(const uint8_t rgb[3], double luv_out[3])
{
    const double *t = rnd_srgb_decode_table();
    double lin[3] = {t[rgb[0]], t[rgb[1]], t[rgb[2]]};
    rnd_linear_to_luv(lin, luv_out);
}

double rnd_delta_e_uv(const double a[3], const double b[3])
{
    double dl = a[0] - b[0], du = a[1] - b[1], dv = a[2] - b[2];
    return sqrt(dl * dl + du * du + dv * dv);
}

/* ---- components ------------------------------------------------------------------------------ */

int rnd_diff_work_init(struct rnd_diff_work *w, int width_px, int height_px)
{
    memset(w, 0, sizeof *w);
    size_t n = (size_t)width_px * (size_t)height_px;
    /* With 8-connectivity a new provisional label needs an unmarked pixel to its left, so at most
     * ceil(w/2)·h labels, plus label 0 (background). */
    size_t labels = ((size_t)width_px + 1) / 2 * (size_t)height_px + 1;
    w->label = malloc(n * sizeof *w->label);
    w->parent = malloc(labels * sizeof *w->parent);
    w->comp = malloc(labels * sizeof *w->comp);
    w->min_run_px = malloc(n * sizeof *w->min_run_px);
    if (!w->label || !w->parent || !w->comp || !w->min_run_px) {
        rnd_diff_work_free(w);
        return -1;
    }
    w->width_px = width_px;
    w->height_px = height_px;
    w->label_cap = (uint32_t)labels;
    return 0;
}

void rnd_diff_work_free(struct rnd_diff_work *w)
{
    free(w->label);
    free(w->parent);
    free(w->comp);
    free(w->min_run_px);
    memset(w, 0, sizeof *w);
}

static uint32_t rnd_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]]; /* path halving: iterative, no recursion */
        x = parent[x];
    }
    return x;
}

static void rnd_union(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = rnd_find(parent, a);
    b = rnd_find(parent, b);
    if (a < b)
        parent[b] = a;
    else if (b < a)
        parent[a] = b;
}

/* Whether the two pixels differ by more than the threshold: identical bytes skip the conversion,
 * which is most pixels of two renders of nearby levels. */
static int rnd_pixel_differs(const uint8_t *a, const uint8_t *b, double threshold_de)
{
    if (a[0] == b[0] && a[1] == b[1] && a[2] == b[2])
        return 0;
    double la[3], lb[3];
    rnd_srgb8_to_luv(a, la);
    rnd_srgb8_to_luv(b, lb);
    return rnd_delta_e_uv(la, lb) > threshold_de;
}

/* Run lengths (Reddy 1998 §3.3, "along several orientations"): for each of 0°, 45°, 90° and 135°
 * every pixel lies on one maximal run of its own component along that line; a run of n pixels is
 * n px long on the axes and n·√2 px on the diagonals (a pixel's diagonal). Per pixel the shortest
 * of its four runs is the component's thickness there (a 1-px sliver is 1 whether straight or
 * curved, which projections of a curved sliver are not); the component's narrow extent is the
 * largest such thickness (its thickest point) and its long extent its longest run (its longest
 * chord). Labels must already be roots. Each orientation is one pass: a run is walked from its
 * first pixel only (the pixel before it is off the image or another label), so every pixel is
 * visited at most three times per orientation; no recursion, no allocation. */
static void rnd_measure_runs(struct rnd_diff_work *w)
{
    static const int step[RND_ANALYZE_ORIENTATIONS][2] = {{1, 0}, {1, 1}, {0, 1}, {1, -1}}; /* (dx, dy), y down */
    static const float step_px[RND_ANALYZE_ORIENTATIONS] = {1.0f, 1.41421356f, 1.0f, 1.41421356f};
    const int W = w->width_px, H = w->height_px;
    const uint32_t *label = w->label;
    for (int o = 0; o < RND_ANALYZE_ORIENTATIONS; ++o) {
        const int dx = step[o][0], dy = step[o][1];
        const ptrdiff_t di = (ptrdiff_t)dy * W + dx;
        for (int y = 0; y < H; ++y) {
            for (int x = 0; x < W; ++x) {
                size_t i = (size_t)y * (size_t)W + (size_t)x;
                uint32_t lab = label[i];
                if (!lab)
                    continue;
                int px = x - dx, py = y - dy;
                if (px >= 0 && px < W && py >= 0 && py < H && label[(size_t)((ptrdiff_t)i - di)] == lab)
                    continue; /* not the run's first pixel */
                int n = 0, qx = x, qy = y;
                while (qx >= 0 && qx < W && qy >= 0 && qy < H && label[(size_t)qy * (size_t)W + (size_t)qx] == lab)
                    ++n, qx += dx, qy += dy;
                float len_px = (float)n * step_px[o];
                struct rnd_component *c = &w->comp[lab];
                if (len_px > c->long_px)
                    c->long_px = len_px;
                size_t k = i;
                for (int j = 0; j < n; ++j, k = (size_t)((ptrdiff_t)k + di))
                    if (len_px < w->min_run_px[k])
                        w->min_run_px[k] = len_px;
            }
        }
    }
    const size_t count = (size_t)W * (size_t)H;
    for (size_t i = 0; i < count; ++i) {
        uint32_t lab = label[i];
        if (lab && w->min_run_px[i] > w->comp[lab].narrow_px)
            w->comp[lab].narrow_px = w->min_run_px[i];
    }
}

void rnd_diff_images(struct rnd_diff_work *w, const uint8_t *rgba_a, const uint8_t *rgba_b, double threshold_de,
                     int min_component_px, struct rnd_image_diff *out)
{
    const int W = w->width_px, H = w->height_px;
    uint32_t *label = w->label, *parent = w->parent, next = 1;
    memset(out, 0, sizeof *out);
    parent[0] = 0;
    /* Pass 1: provisional labels from the already-visited neighbours W, NW, N, NE (8-connected). */
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x) {
            size_t i = (size_t)y * (size_t)W + (size_t)x;
            if (!rnd_pixel_differs(rgba_a + 4 * i, rgba_b + 4 * i, threshold_de)) {
                label[i] = 0;
                continue;
            }
            out->differing_px++;
            uint32_t nb[4], k = 0;
            if (x > 0 && label[i - 1])
                nb[k++] = label[i - 1];
            if (y > 0) {
                const uint32_t *up = label + i - (size_t)W;
                if (x > 0 && up[-1])
                    nb[k++] = up[-1];
                if (up[0])
                    nb[k++] = up[0];
                if (x + 1 < W && up[1])
                    nb[k++] = up[1];
            }
            if (k == 0) {
                parent[next] = next;
                label[i] = next++;
                continue;
            }
            label[i] = nb[0];
            for (uint32_t j = 1; j < k; ++j)
                rnd_union(parent, nb[0], nb[j]);
        }
    }
    if (out->differing_px == 0)
        return;
    /* Pass 2: every label replaced by its root, so a run below compares labels directly; count
     * each component's pixels. */
    struct rnd_component *comp = w->comp;
    for (uint32_t l = 1; l < next; ++l)
        comp[l] = (struct rnd_component){0, 0.0f, 0.0f};
    const size_t n = (size_t)W * (size_t)H;
    for (size_t i = 0; i < n; ++i)
        if (label[i]) {
            label[i] = rnd_find(parent, label[i]);
            comp[label[i]].count++;
            w->min_run_px[i] = INFINITY;
        }
    rnd_measure_runs(w);
    for (uint32_t l = 1; l < next; ++l) {
        if (parent[l] != l)
            continue;
        const struct rnd_component *c = &comp[l];
        if (c->count < (uint32_t)min_component_px) {
            out->noise_components++;
            continue;
        }
        out->components++;
        /* The governing feature is the most visible one, the largest (the lowest frequency): the
         * selector drops a level only when every lost feature is above the eye's limit (Reddy 1998
         * §3.2, "any change evoked will be below the user's threshold of vision"). */
        if (c->narrow_px > out->narrow_extent_px)
            out->narrow_extent_px = c->narrow_px;
        if (c->long_px > out->long_extent_px)
            out->long_extent_px = c->long_px;
    }
}

int rnd_image_compare(const uint8_t *rgba_a, const uint8_t *rgba_b, int width_px, int height_px,
                      double threshold_de, int min_component_px, struct rnd_image_diff *out, struct hl_error *err)
{
    if (!rgba_a || !rgba_b || !out)
        return hl_fail(err, "analyze: compare: no images or output");
    if (width_px < 1 || height_px < 1 || width_px > 16384 || height_px > 16384)
        return hl_fail(err, "analyze: compare: image size %d×%d out of range (1…16384 each)", width_px, height_px);
    if (!(threshold_de > 0) || !isfinite(threshold_de) || min_component_px < 1)
        return hl_fail(err, "analyze: compare: threshold %g must be > 0 and min component %d ≥ 1", threshold_de,
                       min_component_px);
    struct rnd_diff_work w;
    if (rnd_diff_work_init(&w, width_px, height_px) != 0)
        return hl_fail(err, "analyze: compare: out of memory for %d×%d", width_px, height_px);
    rnd_diff_images(&w, rgba_a, rgba_b, threshold_de, min_component_px, out);
    rnd_diff_work_free(&w);
    return 0;
}
