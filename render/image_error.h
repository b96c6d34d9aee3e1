/* render/image_error.h: how far a frame is from its full-detail reference — PSNR, SSIM (Wang et al.
 * 2004) on luminance and per channel, and a foveated SSIM that weights each pixel by how well the eye
 * sees it there (a weight of eccentricity, Reddy's M(E) in replay). Stereo images are compared per
 * eye: a window never straddles the seam between the eyes. Checked against scikit-image
 * (tests/ssim_oracle.py). Included by render/render.h. */
#ifndef HMDLOD_RENDER_IMAGE_ERROR_H
#define HMDLOD_RENDER_IMAGE_ERROR_H

#include <stdint.h>

#include "base/base.h"

/* SSIM's constants (Wang et al. 2004 §III-C; scikit-image's gaussian_weights=True, sigma=1.5,
 * use_sample_covariance=False): an 11×11 Gaussian window, K1 0.01, K2 0.03, range 255. The mean is
 * taken over the pixels whose window lies inside the eye's image (a 5-pixel border is left out). */
#define RND_SSIM_SIGMA_PX 1.5
#define RND_SSIM_RADIUS_PX 5
#define RND_SSIM_K1 0.01
#define RND_SSIM_K2 0.03

/* Eccentricity bands of the foveated SSIM, degrees from the gaze: [0, 5.79) where M(E) = 1 (Reddy 1998
 * eq. 3), [5.79, 15), [15, 30), [30, 180]. */
enum { RND_ECC_BANDS = 4 };
extern const double rnd_ecc_band_lower_deg[RND_ECC_BANDS];

/* Where one eye looks, for the foveated SSIM: the eye's frustum (tangents of its half-angles, all > 0,
 * as hmd_eye) and the gaze as a unit vector in the eye's frame (−Z forward, +Y up, +X right). */
struct rnd_eye_gaze {
    double tan_left, tan_right, tan_up, tan_down;
    double gaze_eye[3];
};

struct rnd_image_error {
    double mse;               /* mean squared error over R, G, B, levels² */
    double psnr_db;           /* 10·log10(255² / mse); +INFINITY for identical images */
    double ssim;              /* luminance Y = 0.299 R + 0.587 G + 0.114 B (BT.601), mean of the eyes */
    double ssim_rgb;          /* the mean of the R, G and B SSIMs (scikit-image's channel_axis) */
    double fssim;             /* luminance SSIM map weighted by weight(E); NaN without gaze */
    double fssim_band[RND_ECC_BANDS]; /* unweighted mean of the map per band; NaN for an empty band */
    double px_over_32_share;  /* share of pixels with some channel off by more than 32 levels */
};

/* Work space for images up to width × height (the whole stereo image); allocated once, so comparing
 * a frame allocates nothing. */
struct rnd_image_error_work;
int rnd_image_error_work_create(int width_px, int height_px, struct rnd_image_error_work **out, struct hl_error *err);
void rnd_image_error_work_destroy(struct rnd_image_error_work *w);

/* Compares `test` against `reference`, both RGBA8 of width × height, rows top to bottom, alpha ignored,
 * holding `eyes` eye images side by side (1 or 2; width divisible by eyes, each eye at least 11 × 11).
 * gaze: one per eye, or NULL (fssim and its bands NaN); weight(E, user) ≥ 0 is the weight of a pixel
 * at eccentricity E degrees (NULL: 1 everywhere). Returns 0, or −1 with err on bad arguments. */
int rnd_image_error_compute(struct rnd_image_error_work *w, const uint8_t *test, const uint8_t *reference, int width_px,
                            int height_px, int eyes, const struct rnd_eye_gaze *gaze,
                            double (*weight)(double eccentricity_deg, void *user), void *user,
                            struct rnd_image_error *out, struct hl_error *err);

#endif
