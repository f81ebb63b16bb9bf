#include "scene/envmap.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include <fmt/format.h>

#include "util/error.h"

namespace wp {

namespace {

// The sRGB transfer function's inverse (IEC 61966-2-1), as image/image.cpp's srgb_decode.
double srgb_to_linear(double e) {
    if (e < 12.92 * 0.0031308) return e / 12.92;
    return std::pow((e + 0.055) / 1.055, 2.4);
}

double luminance(const float4& t) { return 0.2126 * t.x + 0.7152 * t.y + 0.0722 * t.z; }

// The map's rotation as orthonormal rows of its inverse (world -> map frame).
std::array<glm::dvec3, 3> rotation_rows(const glm::mat3& to_world, const std::string& source) {
    glm::dvec3 c[3] = {glm::dvec3(to_world[0]), glm::dvec3(to_world[1]), glm::dvec3(to_world[2])};
    double err = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) err = std::max(err, std::abs(glm::dot(c[i], c[j]) - (i == j ? 1.0 : 0.0)));
    if (!(err <= 1e-3))
        fail("environment map '{}': its to_world is not a rotation (columns off orthonormal by {:.3g})",
             source, err);
    double det = glm::dot(c[0], glm::cross(c[1], c[2]));
    glm::dvec3 e0 = glm::normalize(c[0]);
    glm::dvec3 e1 = glm::normalize(c[1] - glm::dot(e0, c[1]) * e0);
    glm::dvec3 e2 = glm::cross(e0, e1) * (det < 0.0 ? -1.0 : 1.0);
    return {e0, e1, e2};  // rows of the inverse = columns of the rotation
}

float4 to_float4(const glm::dvec3& v) {
    return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z), 0.0f};
}

// Inclusive CDF of non-negative weights as floats, last entry exactly 1; all 0 when the
// weights sum to 0.
void append_cdf(const double* w, std::size_t n, std::vector<float>& out) {
    double total = 0.0;
    for (std::size_t i = 0; i < n; ++i) total += w[i];
    double run = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        run += w[i];
        out.push_back(total > 0.0 ? (i + 1 == n ? 1.0f : static_cast<float>(run / total)) : 0.0f);
    }
}

}  // namespace

EnvUpload upload_environment(const Environment& env, const Texture& image,
                             std::vector<std::string>& warnings) {
    const std::string& src = image.source;
    const int w = image.width, h = image.height;
    if (w <= 0 || h <= 0) fail("environment map '{}' has no pixels ({}x{})", src, w, h);
    const std::int64_t n = std::int64_t(w) * h;
    if (n > std::numeric_limits<int>::max())
        fail("environment map '{}': {}x{} is more texels than the device indexes ({})", src, w, h,
             std::numeric_limits<int>::max());
    const std::size_t values = image.is_float() ? image.texelsf.size() : image.texels8.size();
    if (values != static_cast<std::size_t>(n) * 4)
        fail("environment map '{}': {}x{} RGBA needs {} values, the image holds {}", src, w, h, n * 4,
             values);
    if (!std::isfinite(env.scale) || env.scale < 0.0f)
        fail("environment map '{}': scale {} must be finite and >= 0", src, env.scale);
    if (w != 2 * h)
        warnings.push_back(fmt::format(
            "environment map '{}': {}x{} is not 2:1 (an equirectangular map is twice as wide as "
            "high); used as it is",
            src, w, h));

    EnvUpload up;
    auto rows = rotation_rows(env.to_world, src);
    up.data.to_local0 = to_float4(rows[0]);
    up.data.to_local1 = to_float4(rows[1]);
    up.data.to_local2 = to_float4(rows[2]);
    up.data.scale = {env.scale, env.scale, env.scale, 0.0f};
    up.data.width = w;
    up.data.height = h;

    // Texels, linear.
    up.texels.resize(static_cast<std::size_t>(n));
    std::array<float, 256> decode{};
    for (int c = 0; c < 256; ++c)
        decode[c] = static_cast<float>(image.srgb ? srgb_to_linear(c / 255.0) : c / 255.0);
    std::size_t negative = 0;
    for (std::size_t p = 0; p < up.texels.size(); ++p) {
        float rgb[3];
        for (int k = 0; k < 3; ++k) {
            float x = image.is_float() ? image.texelsf[4 * p + k] : decode[image.texels8[4 * p + k]];
            if (!std::isfinite(x))
                fail("environment map '{}': texel ({}, {}) is not finite ({})", src, p % w, p / w, x);
            if (x < 0.0f) {
                ++negative;
                x = 0.0f;
            }
            rgb[k] = x;
        }
        up.texels[p] = {rgb[0], rgb[1], rgb[2], 0.0f};
    }
    if (negative > 0)
        warnings.push_back(fmt::format("environment map '{}': {} negative texel values read as 0",
                                       src, negative));

    // Sampling cells (kernels/shared/envmap.h): row r between texel rows r and r + 1 (one
    // cell row for a one-row map), column c between texel columns c and c + 1 (mod w).
    const int cell_rows = h > 1 ? h - 1 : 1;
    std::vector<double> lum(static_cast<std::size_t>(n));
    for (std::size_t p = 0; p < lum.size(); ++p) lum[p] = luminance(up.texels[p]);
    std::vector<double> weight(static_cast<std::size_t>(cell_rows) * w), row_weight(cell_rows, 0.0);
    for (int r = 0; r < cell_rows; ++r) {
        const int r1 = std::min(r + 1, h - 1);
        const double sin_theta = std::sin(M_PI * (r + 0.5) / cell_rows);
        for (int c = 0; c < w; ++c) {
            const int c1 = c + 1 < w ? c + 1 : 0;
            double m = std::max(std::max(lum[std::size_t(r) * w + c], lum[std::size_t(r) * w + c1]),
                                std::max(lum[std::size_t(r1) * w + c], lum[std::size_t(r1) * w + c1]));
            weight[std::size_t(r) * w + c] = m * sin_theta;
            row_weight[r] += m * sin_theta;
        }
    }
    append_cdf(row_weight.data(), row_weight.size(), up.marginal);
    up.conditional.reserve(weight.size());
    for (int r = 0; r < cell_rows; ++r) append_cdf(&weight[std::size_t(r) * w], w, up.conditional);

    // Mean luminance: the bilinear radiance integrated exactly over the sphere. Over a full
    // turn in u the linear interpolation of a row averages its texels (sum S_j / w); between
    // rows j and j + 1 (t in [0, 1], θ = π (j + t) / (h - 1)) it is linear in t, so
    // ∫ L dω = (2π² / w) Δ Σ_j ∫ [(1 - t) S_j + t S_{j+1}] sin(α + β t) dt, Δ = 1 / (h - 1),
    // α = π j Δ, β = π Δ, with ∫ sin = I0 and ∫ t sin = I1 in closed form.
    std::vector<double> row_sum(h, 0.0);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) row_sum[j] += lum[std::size_t(j) * w + i];
    double integral = 0.0;
    if (h == 1) {
        integral = 4.0 * M_PI * row_sum[0] / w;
    } else {
        const double delta = 1.0 / (h - 1), beta = M_PI * delta;
        for (int j = 0; j + 1 < h; ++j) {
            const double a = M_PI * j * delta;
            const double i0 = (std::cos(a) - std::cos(a + beta)) / beta;
            const double i1 = (std::sin(a + beta) - std::sin(a)) / (beta * beta) - std::cos(a + beta) / beta;
            integral += row_sum[j] * (i0 - i1) + row_sum[j + 1] * i1;
        }
        integral *= 2.0 * M_PI * M_PI / w * delta;
    }
    up.mean_luminance = static_cast<double>(env.scale) * integral / (4.0 * M_PI);
    return up;
}

}  // namespace wp
