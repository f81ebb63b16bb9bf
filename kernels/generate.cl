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
// Launched over count items (padded; ceil(count / 8) with WP_GENERATE_LANES); items past it
// return at once. The pixel jitter comes
// from the sample key (rng.h: seed, pixel, sample), so the rays do not depend on the wave.
// WP_HAVE_LENS (KernelConfig: the camera has a thin lens) compiles the lens sample (group
// WP_RNG_LENS); without it, or with lens radius 0, the rays are the pinhole's bit for bit.
// WP_GENERATE_LANES (KernelConfig::generate_lanes(): CPU devices; OpenCL only) makes each
// work-item generate eight consecutive items, their jitter (rng_lanes.h, wp_rng2_lanes) and
// pinhole directions computed in vector lanes, their pixels' (x, y) stepped from the first
// one's (one division a work-item), and the host launch ceil(count / 8) work-items: the same
// rays bit for bit (tests/test_generate.cpp).
#include "shared/camera.h"
#include "shared/film.h"
#include "shared/queue_store.h"
#include "shared/rng.h"

#ifndef WP_HAVE_LENS
#define WP_HAVE_LENS 0
#endif
#ifndef WP_GENERATE_LANES
#define WP_GENERATE_LANES 0
#endif
#if WP_GENERATE_LANES
#include "shared/rng_lanes.h"
#endif

// The path state of a camera ray: unit throughput, no BSDF density yet, its pixel, sample
// and item (its radiance slot), a cone of width 0 (a pinhole).
WP_FN PathState wp_fresh_path(int p, uint sample, int i) {
    PathState ps;
    ps.throughput = make_float4(1.0f, 1.0f, 1.0f, 0.0f);
    ps.pixel = p;
    ps.sample = sample;
    ps.item = i;
    ps.cone = 0.0f;
    return ps;
}

// The camera ray and fresh path of item i: sample `sample` of pixel p, (ux, uy) the first
// two numbers of wp_rng4(seed, p, sample, 0, WP_RNG_CAMERA).
WP_FN void wp_generate_item(CameraData camera, uint seed, int i, int p, uint sample, float ux,
                            float uy, WP_GLOBAL Ray* rays, WP_GLOBAL PathState* paths,
                            WP_GLOBAL float4* radiance, WP_GLOBAL int* counters) {
    int y = p / camera.width, x = p - y * camera.width;

    // Position inside the pixel: random with jitter, else its centre.
    float jx = camera.jitter ? ux : 0.5f, jy = camera.jitter ? uy : 0.5f;
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
    wp_store_path(rays + i, paths + i, r, wp_fresh_path(p, sample, i));
    WP_STORE_STREAM(&radiance[i], make_float4(0.0f, 0.0f, 0.0f, 0.0f));
}

#if WP_GENERATE_LANES
// The items i0 .. i0 + 7 (those below count) of pixels p[l] = (x[l], y[l]) and samples
// sample[l], as eight lanes: the jitter (wp_rng2_lanes), the pinhole direction and its finite
// check in vectors, each the scalar item's operations in its order (wp_camera_direction:
// (forward + right sx) + up sy, normalize as v * (1 / sqrt(dot(v, v))), which is PoCL's
// normalize bit for bit: lanes.h), then the stores item by item. Lanes past count hold valid
// keys (their numbers are drawn and dropped). A thin lens and NaN injection take the item
// path (wp_generate_item) per lane.
WP_FN void wp_generate_items8(CameraData camera, uint seed, int i0, int count, const int* p,
                              const int* x, const int* y, const uint* sample, WP_GLOBAL Ray* rays,
                              WP_GLOBAL PathState* paths, WP_GLOBAL float4* radiance,
                              WP_GLOBAL int* counters) {
    float8 ux, uy;
    wp_rng2_lanes(seed, vload8(0, (const uint*)p), vload8(0, sample), 0u, WP_RNG_CAMERA, &ux, &uy);
    const int m = min(8, count - i0);
#if WP_HAVE_LENS || WP_INJECT_NAN
    if (WP_INJECT_NAN || camera.lens.x > 0.0f) {
        float uxa[8], uya[8];
        vstore8(ux, 0, uxa), vstore8(uy, 0, uya);
        for (int l = 0; l < m; ++l)
            wp_generate_item(camera, seed, i0 + l, p[l], sample[l], uxa[l], uya[l], rays, paths, radiance,
                             counters);
        return;
    }
#endif
    // wp_camera_image_point, then normalize.
    const float8 jx = camera.jitter ? ux : (float8)(0.5f), jy = camera.jitter ? uy : (float8)(0.5f);
    const float8 px = convert_float8(vload8(0, x)) + jx, py = convert_float8(vload8(0, y)) + jy;
    const float8 sx = 2.0f * px / (float)camera.width - 1.0f;
    const float8 sy = 1.0f - 2.0f * py / (float)camera.height;
    const float8 ix = camera.forward.x + camera.right.x * sx + camera.up.x * sy;
    const float8 iy = camera.forward.y + camera.right.y * sx + camera.up.y * sy;
    const float8 iz = camera.forward.z + camera.right.z * sx + camera.up.z * sy;
    const float8 inv = 1.0f / sqrt(ix * ix + iy * iy + iz * iz);
    float8 dx = ix * inv, dy = iy * inv, dz = iz * inv;
    // A NaN/Inf direction (degenerate camera) becomes a ray that misses everything.
    const int8 finite = isfinite(dx) & isfinite(dy) & isfinite(dz);
    dx = select((float8)(0.0f), dx, finite);
    dy = select((float8)(0.0f), dy, finite);
    dz = select((float8)(1.0f), dz, finite);
    const float8 tmax = select((float8)(0.0f), (float8)(FLT_MAX), finite);
    float dxa[8], dya[8], dza[8], tma[8];
    int fa[8];
    vstore8(dx, 0, dxa), vstore8(dy, 0, dya), vstore8(dz, 0, dza), vstore8(tmax, 0, tma);
    vstore8(finite, 0, fa);
    const float4 org = make_float4(camera.origin.x, camera.origin.y, camera.origin.z, 0.0f);
    int nonfinite = 0;
    for (int l = 0; l < m; ++l) {
        const int i = i0 + l;
        nonfinite += fa[l] == 0;
        Ray r;
        r.org = org;
        r.dir = make_float4(dxa[l], dya[l], dza[l], tma[l]);
        wp_store_path(rays + i, paths + i, r, wp_fresh_path(p[l], sample[l], i));
        WP_STORE_STREAM(&radiance[i], make_float4(0.0f, 0.0f, 0.0f, 0.0f));
    }
    if (nonfinite > 0) wp_atomic_add(&counters[WP_COUNTER_GENERATE_NONFINITE], nonfinite);
}
#endif

WP_KERNEL void generate_camera(CameraData camera, uint seed, int first_pixel, uint first_sample,
                               int count, WP_GLOBAL Ray* rays, WP_GLOBAL PathState* paths,
                               WP_GLOBAL float4* radiance, WP_GLOBAL int* queue_count,
                               WP_GLOBAL int* counters) {
    int n = camera.width * camera.height;
#if WP_GENERATE_LANES
    const int i0 = wp_global_id() * 8;
    if (i0 >= count) return;
    if (i0 == 0) queue_count[0] = count;
    // Pixel and sample of item i0 (as below), then one pixel further per lane.
    int s = first_pixel + i0;
    int pass = s / n;
    int pl = s - pass * n;
    int yl = pl / camera.width, xl = pl - yl * camera.width;
    int p[8], x[8], y[8];
    uint sample[8];
    for (int l = 0; l < 8; ++l) {
        p[l] = pl, x[l] = xl, y[l] = yl;
        sample[l] = first_sample + (uint)pass;
        if (++pl == n)
            pl = 0, xl = 0, yl = 0, ++pass;
        else if (++xl == camera.width)
            xl = 0, ++yl;
    }
    wp_generate_items8(camera, seed, i0, count, p, x, y, sample, rays, paths, radiance, counters);
#else
    int i = wp_global_id();
    if (i >= count) return;
    if (i == 0) queue_count[0] = count;
    // Pixel and sample of item i (no div/rem pair: LLVM fuses it behind a `freeze`, which
    // Oclgrind cannot check).
    int s = first_pixel + i;
    int pass = s / n;
    int p = s - pass * n;
    uint sample = first_sample + (uint)pass;
    float4 u = wp_rng4(seed, (uint)p, sample, 0u, WP_RNG_CAMERA);
    wp_generate_item(camera, seed, i, p, sample, u.x, u.y, rays, paths, radiance, counters);
#endif
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
#if WP_GENERATE_LANES
    const int i0 = wp_global_id() * 8;
    if (i0 >= count) return;
    if (i0 == 0) queue_count[0] = count;
    int s = first + i0;
    int pass = s / active_count;
    int l0 = s - pass * active_count;
    int p[8], x[8], y[8];
    uint sample[8];
    for (int l = 0; l < 8; ++l) {
        p[l] = active[l0];
        y[l] = p[l] / camera.width, x[l] = p[l] - y[l] * camera.width;
        sample[l] = first_sample + (uint)pass;
        if (++l0 == active_count) l0 = 0, ++pass;
    }
    wp_generate_items8(camera, seed, i0, count, p, x, y, sample, rays, paths, radiance, counters);
#else
    int i = wp_global_id();
    if (i >= count) return;
    if (i == 0) queue_count[0] = count;
    int s = first + i;
    int pass = s / active_count;
    int l = s - pass * active_count;
    int p = active[l];
    uint sample = first_sample + (uint)pass;
    float4 u = wp_rng4(seed, (uint)p, sample, 0u, WP_RNG_CAMERA);
    wp_generate_item(camera, seed, i, p, sample, u.x, u.y, rays, paths, radiance, counters);
#endif
}
