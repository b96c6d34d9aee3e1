/* The lost-contrast spectrum (render/analyze.h; docs/analysis.md, "Lost contrast"): Peli's (1990)
 * band-limited contrast of the difference between two renders of one view, on Burt & Adelson's
 * (1983) Laplacian pyramid of relative luminance. Pure CPU, double precision; scratch allocated per
 * call (offline: 18 views × a few levels per analysis). */
#include "render/analyze_internal.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* Burt & Adelson's generating kernel with a = 0.375: [1 4 6 4 1]/16, separable. Its response to a
 * sinusoid of f cycles per sample is W(f) = cos^4(π f). */
static const double rnd_pyr_w[5] = {1.0 / 16, 4.0 / 16, 6.0 / 16, 4.0 / 16, 1.0 / 16};

/* Symmetric extension without repeating the edge sample (…, 2, 1 | 0, 1, 2, …). */
static int rnd_pyr_reflect(int i, int n)
{
    if (n == 1)
        return 0;
    while (i < 0 || i >= n)
        i = i < 0 ? -i : 2 * n - 2 - i;
    return i;
}

struct rnd_pyr_level {
    int w, h;
    double *g; /* Gaussian level of the reference */
    double *d; /* Gaussian level of ref − test (the pyramid is linear: Lap(ref) − Lap(test) = Lap(ref − test)) */
    uint8_t *obj, *sil; /* per level-j pixel: covers an object pixel; holds or touches background */
};

/* REDUCE: blur with the kernel, keep every other sample; src w × h → dst ⌈w/2⌉ × ⌈h/2⌉. */
static void rnd_pyr_reduce(const double *src, int w, int h, double *dst, double *tmp)
{
    int w2 = (w + 1) / 2, h2 = (h + 1) / 2;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w2; ++x) {
            double s = 0;
            for (int k = -2; k <= 2; ++k)
                s += rnd_pyr_w[k + 2] * src[(size_t)y * w + rnd_pyr_reflect(2 * x + k, w)];
            tmp[(size_t)y * w2 + x] = s;
        }
    for (int y = 0; y < h2; ++y)
        for (int x = 0; x < w2; ++x) {
            double s = 0;
            for (int k = -2; k <= 2; ++k)
                s += rnd_pyr_w[k + 2] * tmp[(size_t)rnd_pyr_reflect(2 * y + k, h) * w2 + x];
            dst[(size_t)y * w2 + x] = s;
        }
}

/* EXPAND: src (the coarser level, ⌈w/2⌉ × ⌈h/2⌉) interpolated to w × h — zeros inserted between
 * samples, then the kernel × 2 per axis (only the taps landing on a sample contribute). */
static void rnd_pyr_expand(const double *src, int w, int h, double *dst, double *tmp)
{
    int w2 = (w + 1) / 2, h2 = (h + 1) / 2;
    for (int y = 0; y < h2; ++y)
        for (int x = 0; x < w; ++x) {
            double s = 0;
            for (int k = -2; k <= 2; ++k)
                if (((x - k) & 1) == 0)
                    s += 2.0 * rnd_pyr_w[k + 2] * src[(size_t)y * w2 + rnd_pyr_reflect((x - k) / 2, w2)];
            tmp[(size_t)y * w + x] = s;
        }
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double s = 0;
            for (int k = -2; k <= 2; ++k)
                if (((y - k) & 1) == 0)
                    s += 2.0 * rnd_pyr_w[k + 2] * tmp[(size_t)rnd_pyr_reflect((y - k) / 2, h2) * w + x];
            dst[(size_t)y * w + x] = s;
        }
}

/* OR over 2 × 2 blocks: a coarser pixel is marked when any finer pixel it covers is. */
static void rnd_pyr_pool(const uint8_t *src, int w, int h, uint8_t *dst)
{
    int w2 = (w + 1) / 2, h2 = (h + 1) / 2;
    for (int y = 0; y < h2; ++y)
        for (int x = 0; x < w2; ++x) {
            uint8_t m = 0;
            for (int dy = 0; dy < 2 && 2 * y + dy < h; ++dy)
                for (int dx = 0; dx < 2 && 2 * x + dx < w; ++dx)
                    m |= src[(size_t)(2 * y + dy) * w + 2 * x + dx];
            dst[(size_t)y * w2 + x] = m;
        }
}

/* The level's gain for a sinusoid at its centre f0 = 2^−(j+2) cycles per level-0 pixel: each REDUCE
 * before it passes W(2^k f0); the band keeps 1 − W² of what reaches it (EXPAND∘REDUCE passes W²).
 * Aliasing ignored; tests/test_analyze.c measures the result on gratings (0.9375, 0.683, 0.632 …). */
static double rnd_pyr_gain(int j)
{
    double f0 = ldexp(1.0, -(j + 2)), g = 1.0;
    for (int k = 0; k < j; ++k)
        g *= pow(cos(HL_PI * ldexp(f0, k)), 4.0);
    double wj = pow(cos(HL_PI * ldexp(f0, j)), 4.0);
    return g * (1.0 - wj * wj);
}

/* Wirth's selection (Algorithms + Data Structures = Programs, 1976): the k-th smallest (0-based) of
 * v[0 … n), reordering v; O(n) on average, no allocation. */
static double rnd_select_kth(double *v, size_t n, size_t k)
{
    ptrdiff_t l = 0, r = (ptrdiff_t)n - 1, kk = (ptrdiff_t)k;
    while (l < r) {
        double x = v[kk];
        ptrdiff_t i = l, j = r;
        do {
            while (v[i] < x)
                ++i;
            while (x < v[j])
                --j;
            if (i <= j) {
                double t = v[i];
                v[i] = v[j];
                v[j] = t;
                ++i;
                --j;
            }
        } while (i <= j);
        if (j < kk)
            l = i;
        if (kk < i)
            r = j;
    }
    return v[kk];
}

void rnd_contrast_params_defaults(struct rnd_contrast_params *p, double diameter_px)
{
    memset(p, 0, sizeof *p);
    p->diameter_px = diameter_px;
    p->percentile = 99.0;
    /* render/renderer.c's clear colour (0.1, 0.1, 0.12) as the FBO stores it. */
    p->background_rgb[0] = 26, p->background_rgb[1] = 26, p->background_rgb[2] = 31;
    p->silhouette_reach = -1;
}

int rnd_contrast_spectrum(const uint8_t *ref, const uint8_t *test, int w, int h, const struct rnd_contrast_params *p,
                          struct rnd_contrast_spectrum *out, struct hl_error *err)
{
    if (!ref || !test || !p || !out)
        return hl_fail(err, "contrast spectrum: no image, parameters or output");
    memset(out, 0, sizeof *out);
    if (w < 1 || h < 1 || w > 16384 || h > 16384)
        return hl_fail(err, "contrast spectrum: image %d×%d outside 1…16384 px a side", w, h);
    if (!(p->diameter_px >= 4.0) || !isfinite(p->diameter_px))
        return hl_fail(err, "contrast spectrum: diameter %g px (at least 4, finite)", p->diameter_px);
    if (!(p->percentile > 0.0) || !(p->percentile <= 100.0))
        return hl_fail(err, "contrast spectrum: percentile %g outside (0, 100]", p->percentile);
    if (p->silhouette_reach < -1 || p->silhouette_reach > 64)
        return hl_fail(err, "contrast spectrum: silhouette reach %d outside −1…64", p->silhouette_reach);

    /* Bands: b = 0, 1, … while its level j = round(log2 D − 2 − b) is ≥ 0 (finer than a quarter
     * cycle per pixel nothing is resolved). */
    double log2d = log2(p->diameter_px);
    int bands = 0, jmax = -1;
    for (int b = 0; b < RND_CONTRAST_MAX_BANDS; ++b) {
        long j = lround(log2d - 2.0 - b);
        if (j < 0)
            break;
        out->level[b] = (int)j;
        out->centre_cpdiam[b] = p->diameter_px / ldexp(1.0, (int)j + 2);
        jmax = (int)j > jmax ? (int)j : jmax;
        bands = b + 1;
    }
    out->band_count = bands;
    /* Pyramid depth: level j + 1 is needed for band j, and a level exists while the one before is at
     * least 2 × 2. */
    struct rnd_pyr_level L[32];
    memset(L, 0, sizeof L);
    int depth = 1;
    L[0].w = w, L[0].h = h;
    while (depth <= jmax + 1 && L[depth - 1].w >= 2 && L[depth - 1].h >= 2) {
        L[depth].w = (L[depth - 1].w + 1) / 2, L[depth].h = (L[depth - 1].h + 1) / 2;
        ++depth;
    }
    size_t n0 = (size_t)w * h, total = 0;
    for (int k = 0; k < depth; ++k)
        total += (size_t)L[k].w * L[k].h;
    double *dbuf = malloc(sizeof(double) * (2 * total + 3 * n0));
    uint8_t *mbuf = malloc(3 * total + n0);
    int rc = -1;
    if (!dbuf || !mbuf) {
        hl_fail(err, "contrast spectrum: out of memory for a %d×%d pyramid", w, h);
        goto done;
    }
    double *tmp = dbuf + 2 * total, *eg = tmp + n0, *ed = eg + n0, *vals = tmp; /* vals reuses tmp after the expands */
    size_t at = 0;
    for (int k = 0; k < depth; ++k) {
        L[k].g = dbuf + at;
        L[k].d = dbuf + total + at;
        L[k].obj = mbuf + at;
        L[k].sil = mbuf + total + at;
        at += (size_t)L[k].w * L[k].h;
    }
    uint8_t *dil = mbuf + 2 * total, *bgmask = mbuf + 3 * total;

    /* Level 0: relative luminance (IEC 61966-2-1 decoding, BT.709 / sRGB weights as in the CIELUV
     * path's XYZ matrix), background and silhouette masks. */
    const double *dec = rnd_srgb_decode_table();
    const double wr = 0.2126729, wg = 0.7151522, wb = 0.0721750;
    const uint8_t *bg = p->background_rgb;
    for (size_t i = 0; i < n0; ++i) {
        const uint8_t *a = ref + 4 * i, *t = test + 4 * i;
        double ya = wr * dec[a[0]] + wg * dec[a[1]] + wb * dec[a[2]];
        double yt = wr * dec[t[0]] + wg * dec[t[1]] + wb * dec[t[2]];
        L[0].g[i] = ya;
        L[0].d[i] = ya - yt;
        int bga = a[0] == bg[0] && a[1] == bg[1] && a[2] == bg[2];
        int bgt = t[0] == bg[0] && t[1] == bg[1] && t[2] == bg[2];
        L[0].obj[i] = !(bga && bgt);
        bgmask[i] = bga || bgt;
    }
    if (p->silhouette_reach >= 0)
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                uint8_t s = 0;
                for (int dy = -1; dy <= 1 && !s; ++dy)
                    for (int dx = -1; dx <= 1 && !s; ++dx) {
                        int yy = y + dy, xx = x + dx;
                        if (yy >= 0 && yy < h && xx >= 0 && xx < w)
                            s = bgmask[(size_t)yy * w + xx];
                    }
                L[0].sil[(size_t)y * w + x] = s;
            }
    else
        memset(L[0].sil, 0, n0);
    for (int k = 1; k < depth; ++k) {
        rnd_pyr_reduce(L[k - 1].g, L[k - 1].w, L[k - 1].h, L[k].g, tmp);
        rnd_pyr_reduce(L[k - 1].d, L[k - 1].w, L[k - 1].h, L[k].d, tmp);
        rnd_pyr_pool(L[k - 1].obj, L[k - 1].w, L[k - 1].h, L[k].obj);
        rnd_pyr_pool(L[k - 1].sil, L[k - 1].w, L[k - 1].h, L[k].sil);
    }

    for (int b = 0; b < bands; ++b) {
        int j = out->level[b];
        out->contrast[b] = out->max_contrast[b] = NAN;
        if (j + 1 >= depth)
            continue; /* the images are too small for this band */
        int lw = L[j].w, lh = L[j].h;
        size_t n = (size_t)lw * lh;
        rnd_pyr_expand(L[j + 1].g, lw, lh, eg, tmp);
        rnd_pyr_expand(L[j + 1].d, lw, lh, ed, tmp);
        /* Silhouette pixels of this level, dilated by the reach (Chebyshev, separable). */
        const uint8_t *excl = L[j].sil;
        if (p->silhouette_reach > 0) {
            int r = p->silhouette_reach;
            uint8_t *row = (uint8_t *)tmp; /* tmp is free again until the next band's expands */
            for (int y = 0; y < lh; ++y)
                for (int x = 0; x < lw; ++x) {
                    uint8_t m = 0;
                    for (int dx = -r; dx <= r && !m; ++dx)
                        if (x + dx >= 0 && x + dx < lw)
                            m = L[j].sil[(size_t)y * lw + x + dx];
                    row[(size_t)y * lw + x] = m;
                }
            for (int y = 0; y < lh; ++y)
                for (int x = 0; x < lw; ++x) {
                    uint8_t m = 0;
                    for (int dy = -r; dy <= r && !m; ++dy)
                        if (y + dy >= 0 && y + dy < lh)
                            m = row[(size_t)(y + dy) * lw + x];
                    dil[(size_t)y * lw + x] = m;
                }
            excl = dil;
        }
        /* Peli 1990: the band over the local mean of the next coarser Gaussian level (the
         * reference's: the loss is judged against what level 0 shows), floored; then over the
         * level's grating gain so that a grating at the centre reads its Michelson contrast. */
        double gain = rnd_pyr_gain(j), mx = 0.0;
        double *v = (p->silhouette_reach > 0) ? ed : vals; /* tmp holds the dilation; ed is read in place */
        size_t count = 0;
        for (size_t i = 0; i < n; ++i) {
            if (!L[j].obj[i] || excl[i])
                continue;
            double mean = eg[i] > RND_CONTRAST_FLOOR_Y ? eg[i] : RND_CONTRAST_FLOOR_Y;
            double c = fabs(L[j].d[i] - ed[i]) / mean / gain;
            v[count++] = c; /* count ≤ i: never overwrites an ed[] still to be read */
            mx = c > mx ? c : mx;
        }
        out->pixels[b] = (uint32_t)count;
        if (!count)
            continue;
        /* Nearest rank: the ⌈p/100 · n⌉-th smallest. */
        size_t rank = (size_t)ceil(p->percentile / 100.0 * (double)count);
        rank = rank < 1 ? 1 : rank > count ? count : rank;
        out->contrast[b] = rnd_select_kth(v, count, rank - 1);
        out->max_contrast[b] = mx;
    }
    rc = 0;
done:
    free(dbuf);
    free(mbuf);
    return rc;
}
