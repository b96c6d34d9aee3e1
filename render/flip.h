/* render/flip.h: LDR-FLIP (Andersson et al., "FLIP: A Difference Evaluator for Alternating Images",
 * HPG 2020), the error a viewer sees flipping between a frame and its reference at a given number
 * of pixels per degree: per pixel in [0, 1], pooled as NVIDIA's FLIP tool pools it (its -txt output).
 * Our own C, in double, checked against that tool (tests/test_flip.c). Stereo images are compared per
 * eye: no filter straddles the seam between the eyes. Included by render/render.h. */
#ifndef HMDLOD_RENDER_FLIP_H
#define HMDLOD_RENDER_FLIP_H

#include <stdint.h>

#include "base/base.h"

/* The metric's constants (the paper's §4 and NVIDIA's FLIP.h): colour error exponent qc and the
 * breakpoints pc, pt of its remapping to [0, 1]; feature detector width w (degrees: the standard
 * deviation of its Gaussian is w/2) and exponent qf. The spatial CSF filters' Gaussians are in flip.c. */
#define RND_FLIP_QC 0.7
#define RND_FLIP_PC 0.4
#define RND_FLIP_PT 0.95
#define RND_FLIP_FEATURE_WIDTH_DEG 0.082
#define RND_FLIP_QF 0.5
/* The tool's default observer: 0.7 m from a 0.7 m wide 3840-pixel screen, ≈ 67.02 px per degree. */
#define RND_FLIP_DEFAULT_PPD (0.7 * 3840.0 / 0.7 * 3.14159265358979323846 / 180.0)

/* The pooled error over every pixel of the image (both eyes together), as the tool pools its map:
 * the mean; the weighted percentiles (each pixel weighted by its own error: the smallest error e
 * such that the pixels with error ≤ e hold more than the share p of the summed error; 0 when the
 * summed error is 0); the smallest and largest pixel error. */
struct rnd_flip_result {
    double mean;
    double weighted_median;    /* p = 0.5 */
    double weighted_q1;        /* 1st weighted quartile, p = 0.25 */
    double weighted_q3;        /* 3rd weighted quartile, p = 0.75 */
    double min, max;
};

/* Compares `test` against `reference` (FLIP is symmetric in the two), both RGBA8 sRGB of width ×
 * height, rows top to bottom, alpha ignored (as image_error.h), holding `eyes` eye images side by side
 * (1 or 2, width divisible by eyes); each eye is filtered on its own, its edges repeated outward.
 * pixels_per_degree: the observer's, finite and > 0 (RND_FLIP_DEFAULT_PPD is the tool's default).
 * error_map: NULL, or width × height floats that receive each pixel's error in the same order.
 * Allocates its scratch per call (a few filtered rows per eye and one double per pixel for the
 * weighted percentiles) and frees it before returning. Returns 0, or −1 with err on bad arguments
 * or no memory. */
int rnd_flip_compute(const uint8_t *test, const uint8_t *reference, int width_px, int height_px, int eyes,
                     double pixels_per_degree, struct rnd_flip_result *out, float *error_map, struct hl_error *err);

#endif
