// film.h — adding a sample (or its square) to a film pixel with a double-float running sum
// (FilmPixel).
//
// Each channel is an unevaluated pair (hi, lo) = (sum, comp) with |lo| <= ulp(hi) / 2, so
// the pair carries about 48 significant bits. Adding a float x is DWPlusFP, Algorithm 4
// of Joldes, Muller & Popescu, "Tight and Rigorous Error Bounds for Basic Building Blocks
// of Double-Word Arithmetic", ACM TOMS 44(2), 2017 (relative error <= 2u^2 per addition):
// Knuth's TwoSum gives the exact rounding error of hi + x, which is added to lo, then
// Fast2Sum renormalises the pair. Plain Kahan/Neumaier with a float compensation term is
// not enough here: after 10^6 equal samples Neumaier's comp itself drifts by ~6e-5
// relative (measured), while the renormalised pair stays within 1e-7.
// Needs strict IEEE evaluation: no fast-math, no FP contraction (compat.h).
#ifndef WP_FILM_H
#define WP_FILM_H

#include "types.h"

WP_NAMESPACE_BEGIN

// (*hi, *lo) += x.
WP_FN void wp_double_float_add(float* hi, float* lo, float x) {
    // TwoSum (Knuth): s + e == *hi + x exactly.
    float s = *hi + x;
    float bp = s - *hi;
    float e = (*hi - (s - bp)) + (x - bp);
    // Fold in the low word, then Fast2Sum to renormalise.
    float v = *lo + e;
    float h = s + v;
    *lo = v - (h - s);
    *hi = h;
}

WP_FN FilmPixel wp_film_add(FilmPixel p, float3 x) {
    float s0 = p.sum.x, s1 = p.sum.y, s2 = p.sum.z;
    float c0 = p.comp.x, c1 = p.comp.y, c2 = p.comp.z;
    wp_double_float_add(&s0, &c0, x.x);
    wp_double_float_add(&s1, &c1, x.y);
    wp_double_float_add(&s2, &c2, x.z);
    FilmPixel r;
    r.sum = make_float4(s0, s1, s2, 0.0f);
    r.comp = make_float4(c0, c1, c2, 0.0f);
    return r;
}

// Sum of squares: each x_c^2 is formed exactly as a float pair (TwoProd by Dekker's
// splitting; no FMA, so no contraction dependence) and both words are added, so the
// squares keep the same ~48-bit accuracy as the sum. Needed because the sample variance
// (sum_sq - sum^2 / n) / (n - 1) cancels when the variance is small against the mean.
WP_FN void wp_double_float_add_square(float* hi, float* lo, float x) {
    // Dekker's split of x into two 12-bit halves (factor 2^12 + 1; exact for |x| < 2^115).
    float c = 4097.0f * x;
    float xh = c - (c - x);
    float xl = x - xh;
    float p = x * x;
    float e = ((xh * xh - p) + 2.0f * xh * xl) + xl * xl;  // p + e == x * x exactly
    wp_double_float_add(hi, lo, p);
    wp_double_float_add(hi, lo, e);
}

WP_FN FilmPixel wp_film_add_square(FilmPixel p, float3 x) {
    float s0 = p.sum.x, s1 = p.sum.y, s2 = p.sum.z;
    float c0 = p.comp.x, c1 = p.comp.y, c2 = p.comp.z;
    wp_double_float_add_square(&s0, &c0, x.x);
    wp_double_float_add_square(&s1, &c1, x.y);
    wp_double_float_add_square(&s2, &c2, x.z);
    FilmPixel r;
    r.sum = make_float4(s0, s1, s2, 0.0f);
    r.comp = make_float4(c0, c1, c2, 0.0f);
    return r;
}

WP_FN int wp_all_finite3(float3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

// Debug NaN injection (types.h, WP_INJECT_*): compiled only when WP_INJECT_NAN is set.
#ifndef WP_INJECT_NAN
#define WP_INJECT_NAN 0
#endif
#ifndef WP_INJECT_PERIOD
#define WP_INJECT_PERIOD 97
#endif
WP_FN int wp_inject_here(int stage, int pixel) {
    return (WP_INJECT_NAN & stage) != 0 && (uint)pixel % (uint)WP_INJECT_PERIOD == 0u;
}
WP_FN float wp_quiet_nan(void) { return as_float(0x7fc00000u); }

WP_NAMESPACE_END

#endif  // WP_FILM_H
