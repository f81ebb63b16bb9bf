// accumulate.cl — the accumulate stage: adds a wave's sample radiance into the film.
//
// A wave (generate.cl) holds `count` samples from pixel first_pixel on: item i belongs to
// pixel first_pixel + (i mod pixel_count) when the wave is whole passes (first_pixel = 0),
// else to pixel first_pixel + i. Work-item j takes pixel first_pixel + j and adds its items
// j, j + pixel_count, j + 2 pixel_count, ... in that order, i.e. in sample order, so the
// film's sums are the same bits whatever the wave sizes were. `film` is the segment of the
// film that starts at pixel film_first (a device caps one buffer; the wave lies inside it).
// accumulate_film
//   reads   radiance[i] for i < count (written by generate, shade and shadow)
//   writes  film[p - film_first] (FilmPixel: double-float running sum, film.h), counters
//           [WP_COUNTER_ACCUMULATE_NONFINITE] when a sample is NaN/Inf (it is dropped, so
//           NaN/Inf never reach the film)
//   pushes  nothing. Launched over min(count, pixel_count) items; the host divides by the
//           sample count.
// accumulate_film_variance
//   the same, and also film_sq[p] += x * x per channel (double-float running sum of
//   squares), from which the host derives the sample variance and the variance of the
//   mean. Used only when variance or a reference is requested (render/wavefront.h), so
//   plain renders neither square nor store the second buffer.
// accumulate_film_active
//   adaptive sampling: the same over a wave of the active-pixel list (below).
// accumulate_film_replicates, accumulate_film_active_replicates
//   RQMC replicates (K = replicates > 1, kernels/shared/rng.h): the variance kernels, and
//   also film_rep[f * K + r] += x (double-float) for the replicate r = s mod K of the
//   item's sample s. Item j + t * pixel_count (or active_count) of a wave is sample
//   first_sample + t of its pixel (a wave is whole passes, or a part of one pass).
#include "shared/film.h"

// Adds the wave's samples of one pixel; with film_sq also their squares; with film_rep also
// to the sum of each sample's replicate (replicates > 1).
// Work-item j adds items j, j + pixel_count, ... < count to pixel p.
WP_FN void wp_accumulate_pixel(WP_GLOBAL const float4* radiance, int j, int p, int count,
                               int pixel_count, int film_first, WP_GLOBAL FilmPixel* film,
                               WP_GLOBAL int* counters, WP_GLOBAL FilmPixel* film_sq,
                               WP_GLOBAL FilmPixel* film_rep, uint first_sample, int replicates) {
    int f = p - film_first;  // the pixel's slot in this film segment
    FilmPixel sum = film[f];
    FilmPixel sq = sum;
    if (film_sq) sq = film_sq[f];
    // The replicate of the pixel's next sample (replicates is a power of two).
    int r = film_rep ? (int)(first_sample & (uint)(replicates - 1)) : 0;
    for (int i = j; i < count; i += pixel_count) {
        float3 x = wp_xyz(radiance[i]);
#if WP_INJECT_NAN
        if (wp_inject_here(WP_INJECT_ACCUMULATE, p)) x.x = wp_quiet_nan();
#endif
        int rep = r;
        if (film_rep) r = (r + 1) & (replicates - 1);
        if (!wp_all_finite3(x)) {
            wp_atomic_inc(&counters[WP_COUNTER_ACCUMULATE_NONFINITE]);
            continue;
        }
        sum = wp_film_add(sum, x);
        if (film_sq) sq = wp_film_add_square(sq, x);
        if (film_rep) {
            int k = f * replicates + rep;
            film_rep[k] = wp_film_add(film_rep[k], x);
        }
    }
    film[f] = sum;
    if (film_sq) film_sq[f] = sq;
}

WP_KERNEL void accumulate_film(WP_GLOBAL const float4* radiance, int first_pixel, int count,
                               int pixel_count, int film_first, WP_GLOBAL FilmPixel* film,
                               WP_GLOBAL int* counters) {
    int j = wp_global_id();
    if (j >= min(count, pixel_count)) return;
    wp_accumulate_pixel(radiance, j, first_pixel + j, count, pixel_count, film_first, film,
                        counters, 0, 0, 0u, 1);
}

WP_KERNEL void accumulate_film_variance(WP_GLOBAL const float4* radiance, int first_pixel,
                                        int count, int pixel_count, int film_first,
                                        WP_GLOBAL FilmPixel* film, WP_GLOBAL int* counters,
                                        WP_GLOBAL FilmPixel* film_sq) {
    int j = wp_global_id();
    if (j >= min(count, pixel_count)) return;
    wp_accumulate_pixel(radiance, j, first_pixel + j, count, pixel_count, film_first, film,
                        counters, film_sq, 0, 0u, 1);
}

WP_KERNEL void accumulate_film_replicates(WP_GLOBAL const float4* radiance, int first_pixel,
                                          int count, int pixel_count, int film_first,
                                          WP_GLOBAL FilmPixel* film, WP_GLOBAL int* counters,
                                          WP_GLOBAL FilmPixel* film_sq, WP_GLOBAL FilmPixel* film_rep,
                                          uint first_sample, int replicates) {
    int j = wp_global_id();
    if (j >= min(count, pixel_count)) return;
    wp_accumulate_pixel(radiance, j, first_pixel + j, count, pixel_count, film_first, film,
                        counters, film_sq, film_rep, first_sample, replicates);
}

// accumulate_film_active — adaptive sampling (generate_camera_active): the wave ran over
// the active list; work-item j takes list entry first + j, pixel active[first + j], and adds
// its items j, j + active_count, ... in sample order to the sum and the sum of squares
// (adaptive sampling always keeps the variance).
WP_KERNEL void accumulate_film_active(WP_GLOBAL const float4* radiance,
                                      WP_GLOBAL const int* active, int first, int count,
                                      int active_count, int film_first, WP_GLOBAL FilmPixel* film,
                                      WP_GLOBAL int* counters, WP_GLOBAL FilmPixel* film_sq) {
    int j = wp_global_id();
    if (j >= min(count, active_count)) return;
    wp_accumulate_pixel(radiance, j, active[first + j], count, active_count, film_first, film,
                        counters, film_sq, 0, 0u, 1);
}

WP_KERNEL void accumulate_film_active_replicates(WP_GLOBAL const float4* radiance,
                                                 WP_GLOBAL const int* active, int first, int count,
                                                 int active_count, int film_first,
                                                 WP_GLOBAL FilmPixel* film, WP_GLOBAL int* counters,
                                                 WP_GLOBAL FilmPixel* film_sq,
                                                 WP_GLOBAL FilmPixel* film_rep, uint first_sample,
                                                 int replicates) {
    int j = wp_global_id();
    if (j >= min(count, active_count)) return;
    wp_accumulate_pixel(radiance, j, active[first + j], count, active_count, film_first, film,
                        counters, film_sq, film_rep, first_sample, replicates);
}
