// adaptive.cl — the per-pixel error estimate of adaptive sampling and --target-error
// (render/adaptive.h; the estimate: shared/adaptive.h).
//
// adaptive_error
//   reads   active[first + k] for k < count (pixel ids of the active list, sorted), the
//           film segment that starts at pixel film_first (sum and sum of squares), and
//           samples: the sample count of every pixel of the list (the active pixels all
//           have the same count)
//   writes  error[first + k] = the pixel's estimated relMSE (wp_pixel_relmse, eps)
//   pushes  nothing. Launched over count items; the host compares with the threshold and
//           compacts the list.
// adaptive_error_replicates
//   the same, and also image_error[first + k] = the pixel's estimate from its RQMC
//   replicates (wp_pixel_relmse_replicates; film_rep: the segment's replicate sums, K per
//   pixel), which --target-error averages; adaptive stopping keeps reading `error`.
#include "shared/adaptive.h"

WP_KERNEL void adaptive_error(WP_GLOBAL const int* active, int first, int count, int film_first,
                              WP_GLOBAL const FilmPixel* film, WP_GLOBAL const FilmPixel* film_sq,
                              int samples, float eps, WP_GLOBAL float* error) {
    int k = wp_global_id();
    if (k >= count) return;
    int f = active[first + k] - film_first;  // the pixel's slot in this film segment
    error[first + k] = wp_pixel_relmse(film[f], film_sq[f], samples, eps);
}

WP_KERNEL void adaptive_error_replicates(WP_GLOBAL const int* active, int first, int count,
                                         int film_first, WP_GLOBAL const FilmPixel* film,
                                         WP_GLOBAL const FilmPixel* film_sq,
                                         WP_GLOBAL const FilmPixel* film_rep, int replicates,
                                         int samples, float eps, WP_GLOBAL float* error,
                                         WP_GLOBAL float* image_error) {
    int k = wp_global_id();
    if (k >= count) return;
    int f = active[first + k] - film_first;
    error[first + k] = wp_pixel_relmse(film[f], film_sq[f], samples, eps);
    image_error[first + k] = wp_pixel_relmse_replicates(film[f], film_sq[f], film_rep + f * replicates,
                                                        replicates, samples, eps);
}
