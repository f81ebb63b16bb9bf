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

struct FilmMoments {
    Image mean;             // m
    Image sample_variance;  // s², unbiased, clamped at 0
    Image mean_variance;    // s² / n: the variance of the mean m
};

// Running mean: (sum + comp) / samples per channel, evaluated in double. samples = 0 gives
// a black image. Throws wp::Error unless film.size() == width * height.
Image resolve_film(const std::vector<FilmPixel>& film, int width, int height, int samples);



// The same for `count` film pixels starting at pixel `first` of `out` (images already sized):
// lets the renderer resolve a large film chunk by chunk instead of copying it whole.
void resolve_film_into(const FilmPixel* film, std::size_t count, std::size_t first, int samples,
                       Image& out);
void resolve_moments_into(const FilmPixel* film, const FilmPixel* film_sq, std::size_t count,
                          std::size_t first, int samples, FilmMoments& out);

// The same with each pixel's own sample count, samples[k] for pixel first + k (adaptive
// sampling, render/adaptive.h): a pixel's mean is the mean of its own samples.
void resolve_film_into(const FilmPixel* film, std::size_t count, std::size_t first,
                       const int* samples, Image& out);
void resolve_moments_into(const FilmPixel* film, const FilmPixel* film_sq, std::size_t count,
                          std::size_t first, const int* samples, FilmMoments& out);

// Mean, sample variance and variance of the mean from the sum and the sum of squares.
// Throws wp::Error unless both films hold width * height pixels.
FilmMoments resolve_moments(const std::vector<FilmPixel>& film,
                            const std::vector<FilmPixel>& film_sq, int width, int height,
                            int samples);

}  // namespace wp::render
