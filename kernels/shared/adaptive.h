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

WP_NAMESPACE_END

#endif  // WP_ADAPTIVE_H
