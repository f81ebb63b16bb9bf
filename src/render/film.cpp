#include "render/film.h"

#include "util/error.h"

namespace wp::render {

Image resolve_film(const std::vector<FilmPixel>& film, int width, int height, int samples) {
    if (film.size() != static_cast<std::size_t>(width) * height)
        fail("film holds {} pixels, expected {}x{}", film.size(), width, height);
    Image img(width, height);
    double inv = samples > 0 ? 1.0 / samples : 0.0;
    for (std::size_t i = 0; i < film.size(); ++i) {
        const FilmPixel& p = film[i];
        img.rgb[3 * i + 0] = static_cast<float>((double(p.sum.x) + double(p.comp.x)) * inv);
        img.rgb[3 * i + 1] = static_cast<float>((double(p.sum.y) + double(p.comp.y)) * inv);
        img.rgb[3 * i + 2] = static_cast<float>((double(p.sum.z) + double(p.comp.z)) * inv);
    }
    return img;
}

}  // namespace wp::render
