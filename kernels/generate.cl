// generate.cl — the generate stage: camera rays and fresh paths for one wave of samples.
//
// The samples of a render are the sequence s = sample * pixel_count + pixel (every pixel's
// sample 0, then every pixel's sample 1, ...). A wave is `count` consecutive samples
// starting at pixel first_pixel of sample first_sample: whole passes (first_pixel = 0,
// count = k * pixel_count) or a part of one pass (first_pixel + count <= pixel_count).
// reads   camera (CameraData), seed, first_pixel, first_sample, count
// writes  rays[i], paths[i] for every item i < count of the wave (queue slot i; the path
//         keeps its pixel, sample and item), radiance[i] = 0 (the sample's radiance, filled
//         by shade and shadow), counters on NaN/Inf
// pushes  all `count` paths: queue_count[0] = count
// Launched over count items (padded); items past it return at once. The pixel jitter comes
// from the sample key (rng.h: seed, pixel, sample), so the rays do not depend on the wave.
// WP_HAVE_LENS (KernelConfig: the camera has a thin lens) compiles the lens sample (group
// WP_RNG_LENS); without it, or with lens radius 0, the rays are the pinhole's bit for bit.
#include "shared/camera.h"
#include "shared/film.h"
#include "shared/rng.h"

#ifndef WP_HAVE_LENS
#define WP_HAVE_LENS 0
#endif

// The camera ray and fresh path of item i: sample `sample` of pixel p.
WP_FN void wp_generate_item(CameraData camera, uint seed, int i, int p, uint sample,
                            WP_GLOBAL Ray* rays, WP_GLOBAL PathState* paths,
                            WP_GLOBAL float4* radiance, WP_GLOBAL int* counters) {
    int y = p / camera.width, x = p - y * camera.width;

    // Position inside the pixel: random with jitter, else its centre.
    float4 u = wp_rng4(seed, (uint)p, sample, 0u, WP_RNG_CAMERA);
    float jx = camera.jitter ? u.x : 0.5f, jy = camera.jitter ? u.y : 0.5f;
    float px = (float)x + jx, py = (float)y + jy;
    float3 org = wp_xyz(camera.origin), d;
#if WP_HAVE_LENS
    if (camera.lens.x > 0.0f) {
        float4 ul = wp_rng4(seed, (uint)p, sample, 0u, WP_RNG_LENS);
        d = wp_camera_lens_ray(camera, px, py, ul.x, ul.y, &org);
    } else
#endif
        d = wp_camera_direction(camera, px, py);

#if WP_INJECT_NAN
    if (wp_inject_here(WP_INJECT_GENERATE, p)) d.x = wp_quiet_nan();
#endif
    // A NaN/Inf direction (degenerate camera) becomes a ray that misses everything.
    float tmax = FLT_MAX;
    if (!wp_all_finite3(d)) {
        wp_atomic_inc(&counters[WP_COUNTER_GENERATE_NONFINITE]);
        d = make_float3(0.0f, 0.0f, 1.0f);
        tmax = 0.0f;
    }
    Ray r;
    r.org = make_float4(org.x, org.y, org.z, 0.0f);
    r.dir = make_float4(d.x, d.y, d.z, tmax);
    rays[i] = r;
    PathState ps;
    ps.throughput = make_float4(1.0f, 1.0f, 1.0f, 0.0f);
    ps.pixel = p;
    ps.sample = sample;
    ps.item = i;
    ps.cone = 0.0f;
    paths[i] = ps;
    radiance[i] = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
}

WP_KERNEL void generate_camera(CameraData camera, uint seed, int first_pixel, uint first_sample,
                               int count, WP_GLOBAL Ray* rays, WP_GLOBAL PathState* paths,
                               WP_GLOBAL float4* radiance, WP_GLOBAL int* queue_count,
                               WP_GLOBAL int* counters) {
    int i = wp_global_id();
    if (i >= count) return;
    if (i == 0) queue_count[0] = count;
    int n = camera.width * camera.height;
    // Pixel and sample of item i (no div/rem pair: LLVM fuses it behind a `freeze`, which
    // Oclgrind cannot check).
    int s = first_pixel + i;
    int pass = s / n;
    int p = s - pass * n;
    wp_generate_item(camera, seed, i, p, first_sample + (uint)pass, rays, paths, radiance, counters);
}

// generate_camera_active — the same for adaptive sampling (render/adaptive.h): the wave's
// samples run over the list of active pixels, active[0..active_count), instead of every
// pixel: item i is list entry L = first + i mod active_count of pass (first + i) /
// active_count, i.e. sample first_sample + pass of pixel active[L]. Every active pixel has
// had the same number of samples (a pixel never restarts once stopped), so its sample
// index, and with it its random numbers, are those of the render without adaptive sampling.
WP_KERNEL void generate_camera_active(CameraData camera, uint seed, WP_GLOBAL const int* active,
                                      int first, int active_count, uint first_sample, int count,
                                      WP_GLOBAL Ray* rays, WP_GLOBAL PathState* paths,
                                      WP_GLOBAL float4* radiance, WP_GLOBAL int* queue_count,
                                      WP_GLOBAL int* counters) {
    int i = wp_global_id();
    if (i >= count) return;
    if (i == 0) queue_count[0] = count;
    int s = first + i;
    int pass = s / active_count;
    int l = s - pass * active_count;
    wp_generate_item(camera, seed, i, active[l], first_sample + (uint)pass, rays, paths, radiance,
                     counters);
}
