// aov.cl — the feature buffers (AOVs): albedo, shading normal and depth at the first
// non-specular hit of each sample's path, and their sums per film pixel. Built and
// launched only when a render asks for AOVs (render --aov, --denoise); layouts in
// shared/aov.h.
//
// aov_record
// reads   rays_in[i], paths_in[i], hits[i] for i < count_in[0] (the queue of bounce
//         `bounce`, after intersect); tri_frames (the face normals: shade.cl), material_ids,
//         materials; the appearance arrays
//         of the features the scene has (else one-element placeholders): tri_normals
//         (WP_HAVE_NORMALS), tri_uvs, material_textures and the texture pool
//         (WP_HAVE_TEXTURES), tri_tangents (WP_HAVE_NORMAL_MAPS); at bounce > 0 the item's
//         own aov rows
// writes  aov[2 item], aov[2 item + 1] (item = paths_in[i].item): at bounce 0 for every
//         path; at a later bounce only where the item's state is WP_AOV_SPECULAR (the
//         path came through specular surfaces only). Albedo: MaterialData.albedo times
//         its albedo texture (level 0: the average over the pixel's samples filters it);
//         normal: the interpolated (and normal-mapped) shading normal, unit, turned to the
//         side the ray arrived from (the geometric normal without vertex normals); depth:
//         the length of the path from the camera to the hit, through the specular bounces.
//         A miss: albedo 0, normal 0, state WP_AOV_MISS.
// pushes  nothing. The host launches it at bounce 0, and at later bounces only when the
//         scene has a specular kind (render/aov.h).
//
// aov_accumulate
// reads   aov[2 i], aov[2 i + 1] for i < count (a wave, laid out as in accumulate.cl)
// writes  film[2 (p - film_first)], film[2 (p - film_first) + 1] += the pixel's samples
//         of the wave, in sample order (the sums do not depend on the wave sizes)
// pushes  nothing. Launched over min(count, pixel_count) items.
//
// aov_accumulate_active
//   adaptive sampling: the same for a wave over the active-pixel list (generate_camera_active,
//   accumulate_film_active): work-item j takes list entry first + j, pixel active[first + j],
//   and adds its items j, j + active_count, ... in sample order.
//
// Compile options: WP_HAVE_NORMALS, WP_HAVE_TEXTURES, WP_HAVE_NORMAL_MAPS (KernelConfig
// aov_options(); all 0 without options).
#include "shared/aov.h"
#include "shared/film.h"
#include "shared/shading.h"
#include "shared/texture.h"

#ifndef WP_HAVE_NORMALS
#define WP_HAVE_NORMALS 0
#endif
#ifndef WP_HAVE_TEXTURES
#define WP_HAVE_TEXTURES 0
#endif
#ifndef WP_HAVE_NORMAL_MAPS
#define WP_HAVE_NORMAL_MAPS 0
#endif

WP_KERNEL void aov_record(WP_GLOBAL const Ray* rays_in, WP_GLOBAL const PathState* paths_in,
                          WP_GLOBAL const int* count_in, WP_GLOBAL const Hit* hits,
                          WP_GLOBAL const float4* tri_frames, WP_GLOBAL const int* material_ids,
                          WP_GLOBAL const MaterialData* materials,
                          WP_GLOBAL const TriNormals* tri_normals, WP_GLOBAL const TriUVs* tri_uvs,
                          WP_GLOBAL const TriTangents* tri_tangents,
                          WP_GLOBAL const MaterialTextures* material_textures,
                          WP_GLOBAL const TextureData* textures,
                          WP_GLOBAL const TextureView* texture_views,
                          WP_GLOBAL const uint* texels8, WP_GLOBAL const float4* texelsf, int bounce,
                          WP_GLOBAL float4* aov) {
    int i = wp_global_id();
    if (i >= count_in[0]) return;
    const int item = paths_in[i].item;
    // Later bounces only continue what a specular surface left open.
    float travelled = 0.0f;
    if (bounce > 0) {
        if (aov[2 * item + 1].w != WP_AOV_SPECULAR) return;
        travelled = aov[2 * item].w;
    }
    Hit hit = hits[i];
    Ray ray = rays_in[i];
    if (hit.prim < 0) {
        aov[2 * item] = make_float4(0.0f, 0.0f, 0.0f, travelled);
        aov[2 * item + 1] = make_float4(0.0f, 0.0f, 0.0f, WP_AOV_MISS);
        return;
    }
    float3 d = wp_xyz(ray.dir);
    MaterialData m = materials[material_ids[hit.prim]];
    float3 n = wp_xyz(tri_frames[hit.prim]);
    int front = dot(d, n) < 0.0f;
    float3 albedo = wp_xyz(m.albedo);
#if WP_HAVE_TEXTURES
    MaterialTextures mt = material_textures[material_ids[hit.prim]];
    TexturePool pool;
    pool.textures = textures;
    pool.views = texture_views;
    pool.texels8 = texels8;
    pool.texelsf = texelsf;
    float2 uv = wp_interpolate_uv(tri_uvs[hit.prim], hit.u, hit.v);
    if (mt.albedo >= 0) albedo = albedo * wp_xyz(wp_texture_view(pool, mt.albedo, uv, -FLT_MAX));
#else
    (void)tri_uvs, (void)material_textures, (void)textures, (void)texture_views;
    (void)texels8, (void)texelsf;
#endif
    float3 ns = n;
#if WP_HAVE_NORMALS
    ns = wp_interpolated_normal(tri_normals[hit.prim], hit.u, hit.v, n);
#if WP_HAVE_NORMAL_MAPS
    if (mt.normal >= 0) {
        TriTangents tt = tri_tangents[hit.prim];
        float3 t3 = wp_interpolate3(tt.t0, tt.t1, tt.t2, hit.u, hit.v);
        float4 c = wp_texture_view(pool, mt.normal, uv, -FLT_MAX);
        float3 mv = make_float3((2.0f * c.x - 1.0f) * mt.normal_scale,
                                (2.0f * c.y - 1.0f) * mt.normal_scale, 2.0f * c.z - 1.0f);
        ns = wp_apply_normal_map(ns, make_float4(t3.x, t3.y, t3.z, tt.t0.w), mv);
    }
#else
    (void)tri_tangents;
#endif
#else
    (void)tri_normals, (void)tri_tangents;
#endif
    if (!front) ns = -ns;
    const float depth = travelled + hit.t * length(d);
    const float state = wp_aov_specular_kind(m.kind) ? WP_AOV_SPECULAR : WP_AOV_HIT;
    aov[2 * item] = wp_float4(albedo, depth);
    aov[2 * item + 1] = wp_float4(ns, state);
}

// Adds items j, j + stride, ... < count to film slot f.
WP_FN void wp_aov_accumulate_pixel(WP_GLOBAL const float4* aov, int j, int f, int count, int stride,
                                   WP_GLOBAL float4* film) {
    float4 a = film[2 * f], b = film[2 * f + 1];
    for (int i = j; i < count; i += stride) {
        float4 x = aov[2 * i], y = aov[2 * i + 1];
        if (y.w == WP_AOV_MISS) continue;  // adds 0 to every sum
        a = a + x;                         // albedo and depth
        b = b + make_float4(y.x, y.y, y.z, 1.0f);
    }
    film[2 * f] = a;
    film[2 * f + 1] = b;
}

WP_KERNEL void aov_accumulate_active(WP_GLOBAL const float4* aov, WP_GLOBAL const int* active,
                                     int first, int count, int active_count, int film_first,
                                     WP_GLOBAL float4* film) {
    int j = wp_global_id();
    if (j >= min(count, active_count)) return;
    wp_aov_accumulate_pixel(aov, j, active[first + j] - film_first, count, active_count, film);
}

WP_KERNEL void aov_accumulate(WP_GLOBAL const float4* aov, int first_pixel, int count,
                              int pixel_count, int film_first, WP_GLOBAL float4* film) {
    int j = wp_global_id();
    if (j >= min(count, pixel_count)) return;
    // The pixel's slot in this film segment; its samples are j, j + pixel_count, ...
    wp_aov_accumulate_pixel(aov, j, first_pixel + j - film_first, count, pixel_count, film);
}
