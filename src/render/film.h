// film.h — the film on the host side: turning the device's compensated sums into images.
//
// The device keeps per pixel and channel the double-float sum S1 = Σ x_i and, when
// variance is requested, the sum of squares S2 = Σ x_i² (kernels/shared/film.h). From n
// samples the host derives, in double:
//   mean                       m  = S1 / n
//   sample variance            s² = (S2 − n m²) / (n − 1)   (unbiased; 0 when n < 2)
//   variance of the mean       s² / n                        (what a z-test needs)
#pragma once

#include <array>
#include <cstdint>
#include <string>
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

// The film on the host, to move between processes (render/distributed.h): every per-pixel
// array of the film as 3 doubles a pixel (each channel's double-float pair hi + lo, which a
// double holds to within 2^-53 relative), with the sample count, the NaN/Inf counters and
// the ray totals. Generic over the arrays: a film array added later is one more entry in
// Wavefront::film_arrays(), and saving, loading, sending and reducing follow.
struct FilmArray {
    std::string name;            // "sum", "sum_sq", ...
    std::vector<double> values;  // 3 (RGB) per film pixel, pixel order (K film pixels per
                                 // image pixel for an array of K sums a pixel)
};

struct FilmState {
    int width = 0, height = 0;
    std::int64_t passes = 0;  // samples per pixel in the sums
    std::uint64_t rays = 0, shadow_rays = 0;
    std::array<std::int64_t, WP_COUNTER_COUNT> counters{};
    std::vector<FilmArray> arrays;

    std::size_t pixels() const { return std::size_t(width) * std::size_t(height); }
    // The array named `name`, or nullptr.
    const FilmArray* find(const std::string& name) const;
    // Bytes of the per-pixel arrays (what a reduction moves).
    std::size_t array_bytes() const;
};

// Film pixels <-> 3 doubles each: d = double(hi) + double(lo) per channel; back, hi =
// float(d), lo = float(d - hi) (a valid double-float pair: |lo| <= ulp(hi) / 2).
void film_pixels_to_doubles(const FilmPixel* film, std::size_t count, double* out);
void doubles_to_film_pixels(const double* in, std::size_t count, FilmPixel* film);

// dst += src: sums, counters and ray totals (in double and integers); passes add. Throws
// wp::Error unless both have the same size and the same arrays in the same order.
void add_film_state(FilmState& dst, const FilmState& src);

}  // namespace wp::render
