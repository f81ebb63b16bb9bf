// film.h — the film on the host side: turning the device's compensated sums into an image.
#pragma once

#include <vector>

#include "image/image.h"
#include "shared/types.h"

namespace wp::render {

// Running mean: (sum + comp) / samples per channel, evaluated in double. samples = 0 gives
// a black image. Throws wp::Error unless film.size() == width * height.
Image resolve_film(const std::vector<FilmPixel>& film, int width, int height, int samples);

}  // namespace wp::render
