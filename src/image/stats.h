// stats.h — statistical comparison of two images: per-pixel z-test with variances, the
// reference's own error, false-colour error images and the variance file naming rule.
//
// Z-test (after Mitsuba 3's image regression tests). Given images a and b with per-pixel
// variances of their means va and vb (either may be absent = 0), each pixel p and channel c
// gets z = (a − b) / sqrt(va + vb + floor), floor = (1e-5 · max(|a|, |b|))² + 1e-24, which
// keeps pixels whose estimated variance is zero (emitters at depth 0, the background)
// testable: they pass only when equal to about five digits. Under the hypothesis that both
// are unbiased estimates of the same image, z is about standard normal. The family-wise
// level α is split over all N pixels with Šidák's correction, and within a pixel over its
// three channels the same way:
//     α_pixel = 1 − (1 − α)^(1/N),   α_channel = 1 − (1 − α_pixel)^(1/3) = 1 − (1 − α)^(1/(3N)),
//     z_crit  = Φ⁻¹(1 − α_channel / 2)   (two-sided),
// and a pixel passes when all three |z| <= z_crit. (Šidák's inequality keeps this valid
// for correlated channels.) The image passes at level α when every pixel passes; the
// regression tests accept ≥ 99.75% passing pixels, as Mitsuba does.
#pragma once

#include <filesystem>
#include <vector>

#include "image/image.h"

namespace wp {

// z such that P(|Z| > z) = p for a standard normal Z (0 < p < 1), by bisection on erfc.
double normal_two_sided_quantile(double p);

struct ZTest {
    double alpha = 0.01;       // family-wise level over all pixels
    double alpha_channel = 0;  // per-channel level after the Šidák correction
    double z_crit = 0;         // |z| above this fails
    int pixels = 0;
    int passed = 0;
    double pass_fraction = 0;  // passed / pixels
    double max_abs_z = 0;      // largest |z| over pixels and channels
    int max_x = 0, max_y = 0;  // where it is
    std::vector<float> pixel_z;  // per pixel: the largest |z| of its channels
};

// Throws wp::Error when sizes differ. var_a / var_b: variance of the mean of a / b, or null.
ZTest z_test(const Image& a, const Image& b, const Image* var_a, const Image* var_b,
             double alpha = 0.01);

// The relMSE that the noise of a reference r (variance of its mean var_r) adds on its own:
// mean over pixels and channels of var_r / (r² + eps). A measured relMSE against r is, in
// expectation, the true relMSE plus this.
double reference_relmse(const Image& r, const Image& var_r, double eps = 1e-2);

// False-colour image of per-pixel values (row-major, w * h) on a dark-blue → yellow ramp
// (viridis-like), scaled so `scale` maps to the top of the ramp; values above it are shown
// in white-pink so out-of-range pixels stand out. Linear RGB (write_image sRGB-encodes
// PNGs, so the ramp is built in sRGB and decoded here).
Image false_colour(const std::vector<float>& values, int w, int h, double scale);

// Per pixel: the mean over channels of |a − b| (for error images without variance).
std::vector<float> abs_difference(const Image& a, const Image& b);

// "out/render.exr" -> "out/render.var.exr" (any extension becomes ".var.exr").
std::filesystem::path variance_path_for(const std::filesystem::path& image_path);

}  // namespace wp
