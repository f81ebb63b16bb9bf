// adaptive.h — the per-pixel error estimate of adaptive sampling and of `render
// --target-error` (render/adaptive.h), from the film's sums (film.h).
//
// From n samples of a pixel, per channel c: the mean m = S1 / n, the unbiased sample
// variance s² = (S2 − S1 m) / (n − 1) and the variance of the mean v = s² / n. The pixel's
// estimated relMSE is
//     e = (1/3) Σ_c v_c / (m_c² + eps),   eps = WP_RELMSE_EPS = 1e-2,
// the expected contribution of the pixel to the image's relMSE (the project's relMSE:
// mean over pixels and channels of (x − r)² / (r² + eps), image/image.h), with the noisy
// mean in place of the unknown reference. eps guards dark pixels: below m ≈ 0.1 the error
// is absolute (v / eps) rather than relative, so a dark noisy pixel does not need
// unbounded samples. Adaptive sampling stops a pixel when e <= its threshold; the image's
// estimate is the mean of e over the pixels. n < 2 gives FLT_MAX (no variance yet).
// The sums are read in float (hi + lo rounded once): enough for a stopping rule (the
// cancellation in S2 − S1 m leaves an error of ~1e-7 m², far below any useful threshold).
#ifndef WP_ADAPTIVE_H
#define WP_ADAPTIVE_H

#include "types.h"

#define WP_RELMSE_EPS 1e-2f

WP_NAMESPACE_BEGIN

WP_FN float wp_pixel_channel_relmse(float s1, float s2, float n, float eps) {
    float m = s1 / n;
    float var = (s2 - s1 * m) / (n - 1.0f);
    var = var > 0.0f ? var : 0.0f;  // rounding can make a zero variance slightly negative
    return var / n / (m * m + eps);
}

// The pixel's estimated relMSE from its film sums after n samples (see above).
WP_FN float wp_pixel_relmse(FilmPixel sum, FilmPixel sq, int n, float eps) {
    if (n < 2) return FLT_MAX;
    float fn = (float)n;
    float e = wp_pixel_channel_relmse(sum.sum.x + sum.comp.x, sq.sum.x + sq.comp.x, fn, eps) +
              wp_pixel_channel_relmse(sum.sum.y + sum.comp.y, sq.sum.y + sq.comp.y, fn, eps) +
              wp_pixel_channel_relmse(sum.sum.z + sum.comp.z, sq.sum.z + sq.comp.z, fn, eps);
    return e / 3.0f;
}

// RQMC replicates (rng.h, render --replicates): with K replicates the pixel's samples are K
// independent randomised-QMC estimates, replicate r having n_r samples (n / K each when K
// divides n, the renderer's case; else the first n mod K replicates one more). With the
// replicate means m_r = S_r / n_r and their mean mbar, the variance of the pixel's mean is
// estimated by
//     v = Σ_r (m_r − mbar)² / (K (K − 1)),
// unbiased for independent equal-count replicates whatever the points' stratification
// (where s² / n overstates the variance of a stratified mean). The pixel's estimate is then
// (1/3) Σ_c v_c / (m_c² + eps), m the pixel's mean (S1 / n). `rep` points at the pixel's K
// replicate sums. Below 2K samples (fewer than two per replicate) it is s² / n
// (wp_pixel_relmse): each replicate mean is then one sample or two, the estimate that of
// so few samples.
WP_FN float wp_pixel_relmse_replicates(FilmPixel sum, FilmPixel sq, WP_GLOBAL const FilmPixel* rep,
                                       int replicates, int n, float eps) {
    if (n < 2 * replicates || replicates < 2) return wp_pixel_relmse(sum, sq, n, eps);
    int base = n / replicates, extra = n - base * replicates;
    float3 mbar = make_float3(0.0f, 0.0f, 0.0f);
    for (int r = 0; r < replicates; ++r) {
        FilmPixel p = rep[r];
        float nr = (float)(base + (r < extra ? 1 : 0));
        mbar.x += (p.sum.x + p.comp.x) / nr;
        mbar.y += (p.sum.y + p.comp.y) / nr;
        mbar.z += (p.sum.z + p.comp.z) / nr;
    }
    float fk = (float)replicates;
    mbar.x /= fk;
    mbar.y /= fk;
    mbar.z /= fk;
    float3 ss = make_float3(0.0f, 0.0f, 0.0f);
    for (int r = 0; r < replicates; ++r) {
        FilmPixel p = rep[r];
        float nr = (float)(base + (r < extra ? 1 : 0));
        float dx = (p.sum.x + p.comp.x) / nr - mbar.x;
        float dy = (p.sum.y + p.comp.y) / nr - mbar.y;
        float dz = (p.sum.z + p.comp.z) / nr - mbar.z;
        ss.x += dx * dx;
        ss.y += dy * dy;
        ss.z += dz * dz;
    }
    float norm = fk * (fk - 1.0f);
    float fn = (float)n;
    float mx = (sum.sum.x + sum.comp.x) / fn;
    float my = (sum.sum.y + sum.comp.y) / fn;
    float mz = (sum.sum.z + sum.comp.z) / fn;
    float e = ss.x / norm / (mx * mx + eps) + ss.y / norm / (my * my + eps) +
              ss.z / norm / (mz * mz + eps);
    return e / 3.0f;
}

WP_NAMESPACE_END

#endif  // WP_ADAPTIVE_H
