// shade.cl — the shade stage: emission, scattering and compaction of surviving paths.
//
// reads   rays_in[i], paths_in[i], hits[i] for i < count_in[0] (the queue of this bounce);
//         the scene in original triangle order: tris (vertices), material_ids, materials;
//         background radiance, seed, sample, bounce (this bounce's index), max_depth
// writes  radiance[pixel] += throughput * (emission of a front face hit, or background on
//         a miss); counters[WP_COUNTER_SHADE_NONFINITE] on NaN/Inf
// pushes  every path that scatters (bounce < max_depth, not absorbed, throughput > 0) into
//         rays_out / paths_out at a slot reserved from count_out, which the host zeroed first
//         (queue.reset); one global atomic per work-group (see shade_surface). Dead
//         paths are not pushed, so they cost nothing later.
// Each path owns its pixel in this frame (one sample per pixel per frame), so the radiance
// update needs no atomics and does not depend on the queue order.
//
// Compile options (KernelConfig): WP_HAVE_DIFFUSE / _MIRROR / _GLOSSY select the material
// code (bsdf.h), WP_HAVE_EMISSION the emission term, WP_DIFFUSE_SAMPLING the strategy.
// Emission is one-sided: only the front face (counter-clockwise winding normal) emits.
#include "shared/bsdf.h"
#include "shared/film.h"
#include "shared/offset.h"
#include "shared/rng.h"

#ifndef WP_HAVE_EMISSION
#define WP_HAVE_EMISSION 1
#endif

// Shades one path. Returns 1 and fills *next_ray / *next_path when the path continues.
static int wp_shade_path(Ray ray, PathState path, Hit hit, __global const Triangle* tris,
                         __global const int* material_ids, __global const MaterialData* materials,
                         float4 background, uint seed, uint sample, int bounce, int max_depth,
                         __global float4* radiance, __global int* counters, Ray* next_ray,
                         PathState* next_path) {
    float3 beta = wp_xyz(path.throughput);
    float3 d = wp_xyz(ray.dir);

    // Escaped: the constant background.
    if (hit.prim < 0) {
        float3 le = beta * wp_xyz(background);
        if (wp_all_finite3(le))
            radiance[path.pixel] += wp_float4(le, 0.0f);
        else
            atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
        return 0;
    }

    // Surface: geometric normal (counter-clockwise front) and the barycentric hit point,
    // which is more accurate than o + t d (Wächter & Binder 2019).
    Triangle tri = tris[hit.prim];
    MaterialData m = materials[material_ids[hit.prim]];
    float3 v0 = wp_xyz(tri.v0), v1 = wp_xyz(tri.v1), v2 = wp_xyz(tri.v2);
    float3 n = normalize(cross(v1 - v0, v2 - v0));
    int front = dot(d, n) < 0.0f;

#if WP_HAVE_EMISSION
    // Emission of the front face.
    if (front) {
        float3 le = beta * wp_xyz(m.emission);
        if (wp_all_finite3(le))
            radiance[path.pixel] += wp_float4(le, 0.0f);
        else
            atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
    }
#endif
    if (bounce >= max_depth) return 0;

    // Scatter: sample the material on the side the ray came from.
    float3 ns = front ? n : -n;
    float4 u = wp_rng4(seed, (uint)path.pixel, sample, (uint)bounce, WP_RNG_BSDF);
    float3 wo, weight;
    if (!wp_bsdf_sample(m, normalize(d), ns, u, &wo, &weight)) return 0;
    beta = beta * weight;
    if (!wp_all_finite3(beta) || !wp_all_finite3(wo)) {
        atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
        return 0;
    }
    if (!(wp_max_component(beta) > 0.0f)) return 0;  // black: nothing more to gather

    // The continued path, from a robustly offset origin.
    float b0 = 1.0f - hit.u - hit.v;
    float3 p = v0 * b0 + v1 * hit.u + v2 * hit.v;
    float3 org = wp_offset_ray_origin(p, ns);
    next_ray->org = make_float4(org.x, org.y, org.z, 0.0f);
    next_ray->dir = make_float4(wo.x, wo.y, wo.z, FLT_MAX);
    next_path->throughput = wp_float4(beta, 0.0f);
    next_path->pixel = path.pixel;
    next_path->bounce = bounce + 1;
    next_path->flags = 0;
    next_path->pad = 0;
    return 1;
}

// The push is aggregated per work-group: survivors take slots from a local counter, and
// one work-item reserves the group's range with a single global atomic_add (so 1 global
// atomic per 64 paths instead of one per path). Every work-item reaches the barriers.
__kernel void shade_surface(__global const Ray* rays_in, __global const PathState* paths_in,
                            __global const Hit* hits, __global const int* count_in,
                            __global const Triangle* tris, __global const int* material_ids,
                            __global const MaterialData* materials, float4 background,
                            uint seed, uint sample, int bounce, int max_depth,
                            __global float4* radiance, __global Ray* rays_out,
                            __global PathState* paths_out, __global int* count_out,
                            __global int* counters) {
    __local int group_count;
    __local int group_base;
    int i = wp_global_id();
    int lid = (int)get_local_id(0);
    if (lid == 0) group_count = 0;
    barrier(CLK_LOCAL_MEM_FENCE);

    Ray next_ray;
    PathState next_path;
    int push = 0;
    if (i < count_in[0])
        push = wp_shade_path(rays_in[i], paths_in[i], hits[i], tris, material_ids, materials,
                             background, seed, sample, bounce, max_depth, radiance, counters,
                             &next_ray, &next_path);
    int local_slot = push ? atomic_inc(&group_count) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid == 0) group_base = group_count > 0 ? atomic_add(count_out, group_count) : 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (push) {
        int slot = group_base + local_slot;
        rays_out[slot] = next_ray;
        paths_out[slot] = next_path;
    }
}

// queue.reset — queue upkeep between intersect and shade, one work-item.
// reads   count_in[0] (rays traced by this bounce)   writes ray_total[0] += count_in[0]
//         (64-bit total of rays traced, for Mrays/s), count_out[0] = 0 (empty next queue)
__kernel void queue_reset(__global const int* count_in, __global int* count_out,
                          __global ulong* ray_total) {
    if (get_global_id(0) != 0) return;
    ray_total[0] += (ulong)count_in[0];
    count_out[0] = 0;
}
