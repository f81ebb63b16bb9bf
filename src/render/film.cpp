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

Image resolve_film(const std::vector<FilmPixel>& film, int width, int height, int samples) {
    check_film(film, width, height);
    Image img(width, height);
    double inv = samples > 0 ? 1.0 / samples : 0.0;
    for (std::size_t i = 0; i < film.size(); ++i)
        for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = static_cast<float>(value(film[i], c) * inv);
    return img;
}

FilmMoments resolve_moments(const std::vector<FilmPixel>& film,
                            const std::vector<FilmPixel>& film_sq, int width, int height,
                            int samples) {
    check_film(film, width, height);
    check_film(film_sq, width, height);
    FilmMoments m{Image(width, height), Image(width, height), Image(width, height)};
    const double n = samples;
    for (std::size_t i = 0; i < film.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            double s1 = value(film[i], c), s2 = value(film_sq[i], c);
            double mean = samples > 0 ? s1 / n : 0.0;
            // Unbiased sample variance; rounding can push a zero variance slightly negative.
            double var = samples > 1 ? std::max(0.0, (s2 - s1 * mean) / (n - 1.0)) : 0.0;
            m.mean.rgb[3 * i + c] = static_cast<float>(mean);
            m.sample_variance.rgb[3 * i + c] = static_cast<float>(var);
            m.mean_variance.rgb[3 * i + c] = static_cast<float>(samples > 0 ? var / n : 0.0);
        }
    return m;
}

}  // namespace wp::render
