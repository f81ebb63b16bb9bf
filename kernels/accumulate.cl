// accumulate.cl — the accumulate stage: adds the frame's radiance into the film.
//
// accumulate_film
//   reads   radiance[p] (this frame's sample of pixel p, written by generate and shade)
//   writes  film[p] (FilmPixel: double-float running sum, film.h), counters
//           [WP_COUNTER_ACCUMULATE_NONFINITE] when a sample is NaN/Inf (it is dropped, so
//           NaN/Inf never reach the film)
//   pushes  nothing. Launched over the pixel count; the host divides by the sample count.
// accumulate_film_variance
//   the same, and also film_sq[p] += x * x per channel (double-float running sum of
//   squares), from which the host derives the sample variance and the variance of the
//   mean. Used only when variance or a reference is requested (render/wavefront.h), so
//   plain renders neither square nor store the second buffer.
#include "shared/film.h"

WP_KERNEL void accumulate_film(WP_GLOBAL const float4* radiance, int pixel_count,
                              WP_GLOBAL FilmPixel* film, WP_GLOBAL int* counters) {
    int p = wp_global_id();
    if (p >= pixel_count) return;
    float3 x = wp_xyz(radiance[p]);
#if WP_INJECT_NAN
    if (wp_inject_here(WP_INJECT_ACCUMULATE, p)) x.x = wp_quiet_nan();
#endif
    if (!wp_all_finite3(x)) {
        wp_atomic_inc(&counters[WP_COUNTER_ACCUMULATE_NONFINITE]);
        return;
    }
    film[p] = wp_film_add(film[p], x);
}

WP_KERNEL void accumulate_film_variance(WP_GLOBAL const float4* radiance, int pixel_count,
                                       WP_GLOBAL FilmPixel* film, WP_GLOBAL int* counters,
                                       WP_GLOBAL FilmPixel* film_sq) {
    int p = wp_global_id();
    if (p >= pixel_count) return;
    float3 x = wp_xyz(radiance[p]);
#if WP_INJECT_NAN
    if (wp_inject_here(WP_INJECT_ACCUMULATE, p)) x.x = wp_quiet_nan();
#endif
    if (!wp_all_finite3(x)) {
        wp_atomic_inc(&counters[WP_COUNTER_ACCUMULATE_NONFINITE]);
        return;
    }
    film[p] = wp_film_add(film[p], x);
    film_sq[p] = wp_film_add_square(film_sq[p], x);
}
