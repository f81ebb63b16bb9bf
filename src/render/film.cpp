#include "render/film.h"

#include <algorithm>

#include "util/error.h"

namespace wp::render {

namespace {

double value(const FilmPixel& p, int c) {
    const float* hi = &p.sum.x;
    const float* lo = &p.comp.x;
    return double(hi[c]) + double(lo[c]);
}

void check_film(const std::vector<FilmPixel>& film, int width, int height) {
    if (film.size() != static_cast<std::size_t>(width) * height)
        fail("film holds {} pixels, expected {}x{}", film.size(), width, height);
}

}  // namespace

void resolve_film_into(const FilmPixel* film, std::size_t count, std::size_t first, int samples,
                       Image& out) {
    double inv = samples > 0 ? 1.0 / samples : 0.0;
    for (std::size_t k = 0; k < count; ++k)
        for (int c = 0; c < 3; ++c)
            out.rgb[3 * (first + k) + c] = static_cast<float>(value(film[k], c) * inv);
}

void resolve_film_into(const FilmPixel* film, std::size_t count, std::size_t first,
                       const int* samples, Image& out) {
    for (std::size_t k = 0; k < count; ++k) resolve_film_into(film + k, 1, first + k, samples[k], out);
}

void resolve_moments_into(const FilmPixel* film, const FilmPixel* film_sq, std::size_t count,
                          std::size_t first, const int* samples, FilmMoments& m) {
    for (std::size_t k = 0; k < count; ++k)
        resolve_moments_into(film + k, film_sq + k, 1, first + k, samples[k], m);
}

Image resolve_film(const std::vector<FilmPixel>& film, int width, int height, int samples) {
    check_film(film, width, height);
    Image img(width, height);
    resolve_film_into(film.data(), film.size(), 0, samples, img);
    return img;
}

void resolve_moments_into(const FilmPixel* film, const FilmPixel* film_sq, std::size_t count,
                          std::size_t first, int samples, FilmMoments& m) {
    const double n = samples;
    for (std::size_t k = 0; k < count; ++k)
        for (int c = 0; c < 3; ++c) {
            const std::size_t i = first + k;
            double s1 = value(film[k], c), s2 = value(film_sq[k], c);
            double mean = samples > 0 ? s1 / n : 0.0;
            // Unbiased sample variance; rounding can push a zero variance slightly negative.
            double var = samples > 1 ? std::max(0.0, (s2 - s1 * mean) / (n - 1.0)) : 0.0;
            m.mean.rgb[3 * i + c] = static_cast<float>(mean);
            m.sample_variance.rgb[3 * i + c] = static_cast<float>(var);
            m.mean_variance.rgb[3 * i + c] = static_cast<float>(samples > 0 ? var / n : 0.0);
        }
}

FilmMoments resolve_moments(const std::vector<FilmPixel>& film,
                            const std::vector<FilmPixel>& film_sq, int width, int height,
                            int samples) {
    check_film(film, width, height);
    check_film(film_sq, width, height);
    FilmMoments m{Image(width, height), Image(width, height), Image(width, height)};
    resolve_moments_into(film.data(), film_sq.data(), film.size(), 0, samples, m);
    return m;
}

const FilmArray* FilmState::find(const std::string& name) const {
    for (const auto& a : arrays)
        if (a.name == name) return &a;
    return nullptr;
}

std::size_t FilmState::array_bytes() const {
    std::size_t b = 0;
    for (const auto& a : arrays) b += a.values.size() * sizeof(double);
    return b;
}

void film_pixels_to_doubles(const FilmPixel* film, std::size_t count, double* out) {
    for (std::size_t k = 0; k < count; ++k)
        for (int c = 0; c < 3; ++c) out[3 * k + c] = value(film[k], c);
}

void doubles_to_film_pixels(const double* in, std::size_t count, FilmPixel* film) {
    for (std::size_t k = 0; k < count; ++k) {
        float hi[3], lo[3];
        for (int c = 0; c < 3; ++c) {
            const double d = in[3 * k + c];
            hi[c] = static_cast<float>(d);
            lo[c] = static_cast<float>(d - double(hi[c]));
        }
        film[k].sum = float4{hi[0], hi[1], hi[2], 0.0f};
        film[k].comp = float4{lo[0], lo[1], lo[2], 0.0f};
    }
}

void add_film_state(FilmState& dst, const FilmState& src) {
    if (dst.width != src.width || dst.height != src.height || dst.arrays.size() != src.arrays.size())
        fail("film states differ: {}x{} with {} arrays and {}x{} with {}", dst.width, dst.height,
             dst.arrays.size(), src.width, src.height, src.arrays.size());
    for (std::size_t a = 0; a < dst.arrays.size(); ++a) {
        auto& d = dst.arrays[a];
        const auto& s = src.arrays[a];
        if (d.name != s.name || d.values.size() != s.values.size())
            fail("film states differ in array {} ('{}' vs '{}')", a, d.name, s.name);
        for (std::size_t i = 0; i < d.values.size(); ++i) d.values[i] += s.values[i];
    }
    dst.passes += src.passes;
    dst.rays += src.rays;
    dst.shadow_rays += src.shadow_rays;
    for (std::size_t i = 0; i < dst.counters.size(); ++i) dst.counters[i] += src.counters[i];
}

}  // namespace wp::render
