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

}  // namespace wp::render
