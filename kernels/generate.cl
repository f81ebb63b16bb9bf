// generate.cl — the generate stage: one camera ray and a fresh path per pixel.
//
// reads   camera (CameraData), seed, sample (the frame's sample index)
// writes  rays[p], paths[p] for every pixel p = y * width + x (queue slot p), radiance[p]
//         = 0 (the frame's per-pixel radiance, filled by shade), counters on NaN/Inf
// pushes  all width * height paths: queue_count[0] = width * height
// Launched over width * height items (padded); items past the pixel count return at once.
// The pixel jitter comes from the counter-based generator (rng.h) keyed by the pixel and
// sample, so the rays do not depend on scheduling.
#include "shared/camera.h"
#include "shared/film.h"
#include "shared/rng.h"

WP_KERNEL void generate_camera(CameraData camera, uint seed, uint sample,
                              WP_GLOBAL Ray* rays, WP_GLOBAL PathState* paths,
                              WP_GLOBAL float4* radiance, WP_GLOBAL int* queue_count,
                              WP_GLOBAL int* counters) {
    int p = wp_global_id();
    int n = camera.width * camera.height;
    if (p >= n) return;
    if (p == 0) queue_count[0] = n;
    // (no div/rem pair: LLVM fuses it behind a `freeze`, which Oclgrind cannot check)
    int y = p / camera.width, x = p - y * camera.width;

    // Position inside the pixel: random with jitter, else its centre.
    float4 u = wp_rng4(seed, (uint)p, sample, 0u, WP_RNG_CAMERA);
    float jx = camera.jitter ? u.x : 0.5f, jy = camera.jitter ? u.y : 0.5f;
    float3 d = wp_camera_direction(camera, (float)x + jx, (float)y + jy);

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
    r.org = make_float4(camera.origin.x, camera.origin.y, camera.origin.z, 0.0f);
    r.dir = make_float4(d.x, d.y, d.z, tmax);
    rays[p] = r;
    PathState s;
    s.throughput = make_float4(1.0f, 1.0f, 1.0f, 0.0f);
    s.pixel = p;
    s.bounce = 0;
    s.flags = 0;
    s.bsdf_pdf = 0.0f;
    paths[p] = s;
    radiance[p] = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
}
