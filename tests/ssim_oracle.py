#!/usr/bin/python3
"""Independent image error for test_image_error: scikit-image's PSNR and SSIM (Wang et al. 2004,
PLATFORM.md §10 flags) on two stereo PNGs, per eye, and the foveated SSIM from scikit-image's SSIM
map weighted by Reddy's M(E) (1998 eq. 3) computed here in numpy.

usage: ssim_oracle.py TEST.png REFERENCE.png EYES [tl tr tu td gx gy gz]×EYES
prints: mse psnr_db ssim ssim_rgb fssim band0 band1 band2 band3 px_over_32_share
"""
import sys

import numpy as np
from PIL import Image
from skimage.metrics import peak_signal_noise_ratio, structural_similarity

BANDS = (0.0, 5.79, 15.0, 30.0)
RADIUS = 5


def reddy_m(e_deg):
    return np.where(e_deg <= 5.79, 1.0, 7.49 / (0.3 * e_deg + 1.0) ** 2)


def ssim(a, b, **kw):
    return structural_similarity(a, b, gaussian_weights=True, sigma=1.5, use_sample_covariance=False,
                                 data_range=255, **kw)


def eccentricity_deg(shape, g):
    tl, tr, tu, td, gx, gy, gz = g
    h, w = shape
    tx = -tl + (np.arange(w) + 0.5) / w * (tl + tr)
    ty = tu - (np.arange(h) + 0.5) / h * (tu + td)
    dx, dy = np.meshgrid(tx, ty)
    d = np.stack([dx, dy, -np.ones_like(dx)], axis=-1)
    q = np.array([gx, gy, gz])
    cross = np.linalg.norm(np.cross(d, q), axis=-1)
    return np.degrees(np.arctan2(cross, d @ q))


def main():
    a = np.asarray(Image.open(sys.argv[1]).convert("RGB")).astype(np.float64)
    b = np.asarray(Image.open(sys.argv[2]).convert("RGB")).astype(np.float64)
    eyes = int(sys.argv[3])
    gaze = [float(v) for v in sys.argv[4:]]
    mse = np.mean((a - b) ** 2)
    psnr = peak_signal_noise_ratio(a.astype(np.uint8), b.astype(np.uint8), data_range=255) if mse > 0 else float("inf")
    over = np.mean(np.max(np.abs(a - b), axis=2) > 32)
    lum_w = np.array([0.299, 0.587, 0.114])
    w = a.shape[1] // eyes
    s_luma, s_rgb, wsum, wtot = [], [], 0.0, 0.0
    band_sum, band_n = np.zeros(4), np.zeros(4)
    for e in range(eyes):
        ea, eb = a[:, e * w:(e + 1) * w], b[:, e * w:(e + 1) * w]
        s_rgb.append(ssim(ea, eb, channel_axis=2))
        la, lb = ea @ lum_w, eb @ lum_w
        mean, smap = ssim(la, lb, full=True)
        s_luma.append(mean)
        if gaze:
            g = gaze[7 * e:7 * e + 7]
            ecc = eccentricity_deg(la.shape, g)[RADIUS:-RADIUS, RADIUS:-RADIUS]
            m = smap[RADIUS:-RADIUS, RADIUS:-RADIUS]
            wt = reddy_m(ecc)
            wsum += np.sum(wt * m)
            wtot += np.sum(wt)
            band = np.searchsorted(BANDS, ecc, side="right") - 1
            for k in range(4):
                band_sum[k] += np.sum(m[band == k])
                band_n[k] += np.sum(band == k)
    fssim = wsum / wtot if gaze else float("nan")
    bands = [band_sum[k] / band_n[k] if band_n[k] else float("nan") for k in range(4)]
    vals = [mse, psnr, np.mean(s_luma), np.mean(s_rgb), fssim] + bands + [over]
    print(" ".join("%.12g" % v for v in vals))


if __name__ == "__main__":
    main()
