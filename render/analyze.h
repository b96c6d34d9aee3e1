/* render/analyze.h: Reddy's offline spatial-frequency analysis (1998 §3.2–3.3; docs/analysis.md).
 * Each level of a chain is rendered headless from the view sphere; successive levels are compared
 * pixel by pixel in CIELUV; the regions that differ are the features the coarser level loses, and
 * their extents give the frequencies the acuity selector compares against the eye's limit.
 * Included by render/render.h. */
#ifndef HMDLOD_RENDER_ANALYZE_H
#define HMDLOD_RENDER_ANALYZE_H

#include "scene/scene.h"

struct rnd_renderer;

/* ---- colour ------------------------------------------------------------------------------------
 * 8-bit sRGB (IEC 61966-2-1, what the FBO's bytes mean on a display) → linear → CIE XYZ (D65,
 * Y of white = 1) → CIE 1976 L*u*v* (L* in 0…100). */
void rnd_srgb8_to_luv(const uint8_t rgb[3], double luv_out[3]);
/* CIE 1976 ΔE*uv: the Euclidean distance in L*u*v*. */
double rnd_delta_e_uv(const double luv_a[3], const double luv_b[3]);

/* ---- comparing two renders -------------------------------------------------------------------- */
enum { RND_ANALYZE_ORIENTATIONS = 4 }; /* extents measured at 0, 45, 90 and 135 degrees */

struct rnd_image_diff {
    uint64_t differing_px;     /* pixels whose ΔE*uv exceeds the threshold */
    uint32_t components;       /* 8-connected regions of them at least min_component_px large */
    uint32_t noise_components; /* smaller regions, dropped as rasterisation noise */
    /* Over the kept components, in pixels (0 when none). A component's narrow extent is its
     * thickness at its thickest point: the largest, over its pixels, of the shortest run of the
     * component through that pixel over the 4 orientations (a 1-px sliver, straight or curved, is
     * about 1). Its long extent is its longest chord: the longest such run. Diagonal runs count
     * √2 px a pixel. These are the MAXIMA over components: the largest lost feature is the most
     * visible one, the lowest frequency f = 1 / (2 L) cycles per pixel, and it governs (every lost
     * feature must be above the eye's limit, Reddy 1998 §3.2). */
    double narrow_extent_px, long_extent_px;
};

/* Compares two RGBA8 images of width × height (rows top to bottom; alpha ignored): marks pixels with
 * ΔE*uv > threshold_de, labels 8-connected components (two-pass union-find), drops those under
 * min_component_px pixels and measures the rest by run lengths at 0, 45, 90 and 135 degrees (one
 * linear pass per orientation). Allocates its own work space (use
 * rnd_analyze_lodset for many images). Returns 0, or −1 on bad arguments or no memory. */
int rnd_image_compare(const uint8_t *rgba_a, const uint8_t *rgba_b, int width_px, int height_px,
                      double threshold_de, int min_component_px, struct rnd_image_diff *out, struct hl_error *err);

/* ---- the lost-contrast spectrum (docs/analysis.md, "Lost contrast") ----------------------------
 * Peli's (1990) band-limited contrast of the difference between two renders of one view: Laplacian
 * pyramids (Burt & Adelson 1983, 5-tap binomial [1 4 6 4 1]/16) of both images' relative luminance
 * Y (sRGB EOTF, BT.709 weights, white = 1); in pyramid level j,
 *     c_j(x) = |Lap_j(ref)(x) − Lap_j(test)(x)| / max(expand(G_{j+1}(ref))(x), RND_CONTRAST_FLOOR_Y) / g_j,
 * where g_j is the level's gain for a sinusoid at its centre frequency (so a grating of Michelson
 * contrast c at the centre reads c, the unit a CSF threshold is in). Level j is centred on
 * 1/2^(j+2) cycles per pixel, i.e. diameter_px / 2^(j+2) cycles per object diameter; band b
 * (f_b = 2^b c/diam) takes the level nearest in log frequency, j = round(log2(diameter_px) − 2 − b). */
enum { RND_CONTRAST_MAX_BANDS = SCN_LODSET_MAX_BANDS };
/* Local means below this relative luminance count as this: a difference on a black field would
 * otherwise be an infinite contrast. 1e-3 of white (0.1 cd/m² on a 100 cd/m² display, about a
 * panel's black level); the analysis renders' background (0.1, 0.1, 0.12) is Y ≈ 0.010, above it. */
#define RND_CONTRAST_FLOOR_Y 1e-3

struct rnd_contrast_params {
    double diameter_px;        /* the object's diameter in the images, px, ≥ 4 (band 0 needs 4 px) */
    double percentile;         /* of each band's object pixels, (0, 100]; 100 = the maximum */
    uint8_t background_rgb[3]; /* a pixel with these bytes is background; object = not so in either image */
    /* −1: every object pixel counts. k ≥ 0: drop silhouette pixels — in level j, those whose 2^j-px
     * block holds or touches (8-neighbour) a background pixel of either image, dilated by k level-j
     * pixels (the 5-tap kernel reaches 2). */
    int silhouette_reach;
};
/* Defaults: the 99th percentile, the renderer's clear colour as background, silhouettes kept. */
void rnd_contrast_params_defaults(struct rnd_contrast_params *p, double diameter_px);

struct rnd_contrast_spectrum {
    int band_count;                           /* bands 0 … band_count−1 resolved by the images */
    double contrast[RND_CONTRAST_MAX_BANDS];  /* the percentile; NaN when the band has no pixel */
    double max_contrast[RND_CONTRAST_MAX_BANDS]; /* the maximum over the same pixels (for comparison) */
    double centre_cpdiam[RND_CONTRAST_MAX_BANDS]; /* the level's own centre, diameter_px / 2^(j+2) */
    int level[RND_CONTRAST_MAX_BANDS];        /* pyramid level j of the band */
    uint32_t pixels[RND_CONTRAST_MAX_BANDS];  /* level-j pixels the percentile was taken over */
};
/* Lost-contrast spectrum of test against ref (RGBA8, width × height, rows top to bottom, alpha
 * ignored). Allocates its scratch (two pyramids in double, ~2.7 × 8 bytes a pixel) per call: it runs
 * offline. Returns 0, or −1 with a message on bad arguments or no memory. */
int rnd_contrast_spectrum(const uint8_t *rgba_ref, const uint8_t *rgba_test, int width_px, int height_px,
                          const struct rnd_contrast_params *p, struct rnd_contrast_spectrum *out,
                          struct hl_error *err);

/* ---- analysing a chain ------------------------------------------------------------------------ */
struct rnd_analyze_params {
    int views;               /* 6 (±X, ±Y, ±Z) or 18 (plus the 12 cube-edge midpoints) */
    int size_px;             /* the bounding-sphere diameter spans this many pixels, 16…2048 */
    double threshold_de;     /* ΔE*uv above which a pixel differs, > 0 (default 2.3, a JND) */
    int min_component_px;    /* regions smaller than this are noise, ≥ 1 (default 3) */
    void (*progress)(void *user, double fraction); /* optional, called after each render */
    void *progress_user;
    const char *dump_dir; /* optional, an existing folder: every render and difference mask as PNG */
    double contrast_percentile; /* of each view's object pixels for the lost-contrast spectrum, (0, 100] */
    int contrast_silhouette_reach; /* rnd_contrast_params.silhouette_reach: −1 keeps silhouette pixels */
    double albedo_rgb[3]; /* the object's colour, each in [0, 1] (what the shader multiplies by the shading) */
};
/* 18 views, 256 px, ΔE 2.3, 3 px, the 99th percentile with silhouettes, grey 0.8. */
void rnd_analyze_params_defaults(struct rnd_analyze_params *p);
/* Checks a parameter set; −1 with a message naming the parameter otherwise. */
int rnd_analyze_params_check(const struct rnd_analyze_params *p, struct hl_error *err);

/* What the analysis saw at one level (index l compares level l−1 with level l; index 0 unused). */
struct rnd_analyze_level {
    uint64_t differing_px;                  /* over all views */
    uint32_t components, noise_components;  /* over all views */
    /* The largest narrow extent (thickest lost feature) and the largest long extent (longest lost
     * chord) over all kept components and views, in pixels: they set the narrow and long readings
     * (the lowest frequencies lost, the most visible); 0 if none. */
    double narrow_extent_px, long_extent_px;
    int narrow_view, long_view;             /* the view they were seen from; −1 if none */
    int invisible;      /* no kept component from any view: nothing visible is lost at this size */
    int clamped;        /* a reading was lowered to keep the table strictly decreasing */
    /* The lost-contrast spectrum against level 0 (not l−1: skipping levels cannot hide a loss):
     * per band, the maximum over views of rnd_contrast_spectrum's percentile; NaN if no view had an
     * object pixel in the band. The view that gave each maximum (−1 if none). Level 0: all 0. */
    int band_count;
    double lost_contrast[RND_CONTRAST_MAX_BANDS];
    int lost_contrast_view[RND_CONTRAST_MAX_BANDS];
};
struct rnd_analyze_report {
    int level_count;
    struct rnd_analyze_level levels[SCN_LODSET_MAX_LEVELS];
    uint32_t renders;
    double render_s, compare_s, total_s; /* GPU draw + read-back, comparisons, whole call */
    double contrast_s;                   /* of compare_s, the lost-contrast spectra */
};

/* The view directions (unit, from the centre towards the camera) for 6 or 18 views; returns the
 * count written to dirs_out (0 for another count). */
int rnd_analyze_view_dirs(int views, double dirs_out[18][3]);

/* Renders every level of `set` from the params' views with an orthographic camera (the bounding
 * diameter spans size_px), compares successive levels and fills set->freq[l].narrow_cpdiam and
 * .long_cpdiam (l ≥ 1; level 0 gets +INFINITY) = size_px / (2 · the level's largest narrow or long
 * extent), cycles per object diameter, set->analysis_views and set->analysis_size_px; compares
 * every level with level 0 and fills the lost-contrast spectrum (set->lost_contrast,
 * contrast_band_count, contrast_percentile).
 * The tables come out strictly decreasing; a level that loses nothing visible gets the largest value
 * below the previous level's, so the selector always takes it when it takes the previous one.
 * r: a renderer whose eyes are at least size_px square, whose uploaded scene this replaces; NULL
 * makes (and destroys) one. set is unchanged on failure. report may be NULL. */
int rnd_analyze_lodset(struct rnd_renderer *r, struct scn_lodset *set, const struct rnd_analyze_params *p,
                       struct rnd_analyze_report *report, struct hl_error *err);

#endif
