#include "image/stats.h"

#include <algorithm>
#include <cmath>

#include "util/error.h"

namespace wp {

namespace fs = std::filesystem;

double normal_two_sided_quantile(double p) {
    if (!(p > 0.0 && p < 1.0)) fail("normal quantile: probability {} is not in (0, 1)", p);
    // P(|Z| > z) = erfc(z / sqrt 2) falls monotonically in z.
    double lo = 0.0, hi = 40.0;
    for (int i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        if (std::erfc(mid / std::sqrt(2.0)) > p)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

ZTest z_test(const Image& a, const Image& b, const Image* var_a, const Image* var_b,
             double alpha) {
    if (a.width != b.width || a.height != b.height)
        fail("z-test: image sizes differ ({}x{} vs {}x{})", a.width, a.height, b.width, b.height);
    for (const Image* v : {var_a, var_b})
        if (v && (v->width != a.width || v->height != a.height))
            fail("z-test: variance image is {}x{}, the images are {}x{}", v->width, v->height,
                 a.width, a.height);
    if (!(alpha > 0.0 && alpha < 1.0)) fail("z-test: alpha {} is not in (0, 1)", alpha);

    ZTest t;
    t.alpha = alpha;
    t.pixels = a.width * a.height;
    if (t.pixels == 0) return t;
    // Šidák over all 3N channel tests (see stats.h).
    t.alpha_channel = -std::expm1(std::log1p(-alpha) / (3.0 * t.pixels));
    t.z_crit = normal_two_sided_quantile(t.alpha_channel);
    t.pixel_z.assign(static_cast<std::size_t>(t.pixels), 0.0f);
    for (int p = 0; p < t.pixels; ++p) {
        double zmax = 0.0;
        for (int c = 0; c < 3; ++c) {
            std::size_t i = static_cast<std::size_t>(p) * 3 + c;
            double x = a.rgb[i], r = b.rgb[i];
            double scale = 1e-5 * std::max(std::abs(x), std::abs(r));
            double var = (var_a ? var_a->rgb[i] : 0.0) + (var_b ? var_b->rgb[i] : 0.0) +
                         scale * scale + 1e-24;
            double z = std::abs(x - r) / std::sqrt(var);
            if (!std::isfinite(z)) z = 1e30;  // NaN/Inf pixels always fail
            zmax = std::max(zmax, z);
        }
        t.pixel_z[static_cast<std::size_t>(p)] = static_cast<float>(std::min(zmax, 1e30));
        if (zmax <= t.z_crit) ++t.passed;
        if (zmax > t.max_abs_z) {
            t.max_abs_z = zmax;
            t.max_x = p % a.width;
            t.max_y = p / a.width;
        }
    }
    t.pass_fraction = static_cast<double>(t.passed) / t.pixels;
    return t;
}

double reference_relmse(const Image& r, const Image& var_r, double eps) {
    if (r.width != var_r.width || r.height != var_r.height)
        fail("reference is {}x{} but its variance image is {}x{}", r.width, r.height,
             var_r.width, var_r.height);
    if (r.rgb.empty()) return 0.0;
    double sum = 0.0;
    for (std::size_t i = 0; i < r.rgb.size(); ++i) {
        double v = r.rgb[i];
        sum += std::max(0.0, double(var_r.rgb[i])) / (v * v + eps);
    }
    return sum / static_cast<double>(r.rgb.size());
}

std::vector<float> abs_difference(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        fail("image sizes differ ({}x{} vs {}x{})", a.width, a.height, b.width, b.height);
    std::vector<float> d(static_cast<std::size_t>(a.width) * a.height);
    for (std::size_t p = 0; p < d.size(); ++p) {
        double s = 0.0;
        for (int c = 0; c < 3; ++c) s += std::abs(double(a.rgb[3 * p + c]) - b.rgb[3 * p + c]);
        d[p] = static_cast<float>(s / 3.0);
    }
    return d;
}

Image false_colour(const std::vector<float>& values, int w, int h, double scale) {
    if (values.size() != static_cast<std::size_t>(w) * h)
        fail("false colour: {} values for a {}x{} image", values.size(), w, h);
    // A few sRGB stops of viridis, interpolated linearly in t.
    static const float stops[5][3] = {{0.267f, 0.005f, 0.329f}, {0.229f, 0.322f, 0.546f},
                                      {0.128f, 0.567f, 0.551f}, {0.369f, 0.789f, 0.383f},
                                      {0.993f, 0.906f, 0.144f}};
    Image img(w, h);
    for (std::size_t p = 0; p < values.size(); ++p) {
        double v = values[p];
        double srgb[3];
        if (!(v <= scale) || scale <= 0.0) {  // above the scale (or NaN): pink
            srgb[0] = 1.0, srgb[1] = 0.6, srgb[2] = 0.8;
        } else {
            double t = std::clamp(v / scale, 0.0, 1.0) * 4.0;
            int k = std::min(3, static_cast<int>(t));
            double f = t - k;
            for (int c = 0; c < 3; ++c) srgb[c] = stops[k][c] * (1.0 - f) + stops[k + 1][c] * f;
        }
        for (int c = 0; c < 3; ++c) img.rgb[3 * p + c] = static_cast<float>(srgb_decode(srgb[c]));
    }
    return img;
}

fs::path variance_path_for(const fs::path& image_path) {
    fs::path p = image_path;
    p.replace_extension();
    return fs::path(p.string() + ".var.exr");
}

}  // namespace wp
