// test_probes.cl — kernels that only tests launch: they run shared device functions on the
// device with inputs a test chooses.
//
// film_add_repeat: reads value; adds it `repeat` times to film[0] with wp_film_add (the
//   function accumulate_film uses); writes film[0]. One work-item. Lets a test do 10^6
//   accumulations in one launch.
#include "shared/film.h"

WP_KERNEL void film_add_repeat(float4 value, int repeat, WP_GLOBAL FilmPixel* film) {
    if (wp_global_id() != 0) return;
    FilmPixel f = film[0];
    float3 x = wp_xyz(value);
    for (int k = 0; k < repeat; ++k) f = wp_film_add(f, x);
    film[0] = f;
}
