// film.h — the film on the host side: turning the device's compensated sums into images.
//
// The device keeps per pixel and channel the double-float sum S1 = Σ x_i and, when
// variance is requested, the sum of squares S2 = Σ x_i² (kernels/shared/film.h). From n
// samples the host derives, in double:
//   mean                       m  = S1 / n
//   sample variance            s² = (S2 − n m²) / (n − 1)   (unbiased; 0 when n < 2)
//   variance of the mean       s² / n                        (what a z-test needs)
#pragma once

#include <vector>

#include "image/image.h"
#include "shared/types.h"

namespace wp::render {

// Running mean: (sum + comp) / samples per channel, evaluated in double. samples = 0 gives
// a black image. Throws wp::Error unless film.size() == width * height.
Image resolve_film(const std::vector<FilmPixel>& film, int width, int height, int samples);

struct FilmMoments {
    Image mean;             // m
    Image sample_variance;  // s², unbiased, clamped at 0
    Image mean_variance;    // s² / n: the variance of the mean m
};

// Mean, sample variance and variance of the mean from the sum and the sum of squares.
// Throws wp::Error unless both films hold width * height pixels.
FilmMoments resolve_moments(const std::vector<FilmPixel>& film,
                            const std::vector<FilmPixel>& film_sq, int width, int height,
                            int samples);

}  // namespace wp::render
