// shade.cl — the shade stage: emission, scattering, next-event estimation, Russian roulette
// and compaction of the surviving paths.
//
// shade_surface
// reads   rays_in[i], paths_in[i], hits[i] for i < count_in[0] (the queue of this bounce);
//         the scene in original triangle order: tris (vertices), material_ids, materials;
//         background radiance, seed, bounce (this bounce's index, the same for every path
//         of the queue), max_depth; with WP_HAVE_NEE the light table (lights.h):
//         light_cdf, light_prims, light_pdf_area, light_count
// writes  radiance[item] += throughput * MIS weight * (emission of a front face hit), or
//         throughput * background on a miss (item: the path's sample in its wave);
//         counters[WP_COUNTER_SHADE_NONFINITE] on NaN/Inf
// pushes  every path that scatters (bounce < max_depth, not absorbed, throughput > 0, and
//         surviving Russian roulette) into rays_out / paths_out at a slot reserved from
//         count_out; with WP_HAVE_NEE a shadow ray per light sample into shadow_rays, with
//         its item and unoccluded contribution in shadow_items / shadow_contrib, at a slot
//         reserved from shadow_count (shadow.cl traces them). Both queues were emptied by
//         queue.reset; one global atomic per work-group and queue (see shade_surface).
// Each path owns its sample's radiance slot, so the radiance updates need no atomics and
// do not depend on the queue order.
//
// Compile options (KernelConfig): WP_HAVE_<KIND> (material_kinds.h) select the material
// code and WP_SAMPLING / WP_GLOSSY_MODEL the strategies (bsdf.h); WP_HAVE_EMISSION the
// emission term; WP_HAVE_NEE (scene has emitters and WP_SAMPLING is NEE or MIS) the light
// sampling; WP_RR_DEPTH the first bounce at which Russian roulette may end a path (< 0: off).
// Emission is one-sided: only the front face (counter-clockwise winding normal) emits.
#include "shared/bsdf.h"
#include "shared/film.h"
#include "shared/lights.h"
#include "shared/offset.h"
#include "shared/rng.h"

// Without options: the generic program of the shipped estimator (estimator.h).
#ifndef WP_HAVE_EMISSION
#define WP_HAVE_EMISSION 1
#endif
#ifndef WP_HAVE_NEE
#define WP_HAVE_NEE (WP_SAMPLING == WP_SAMPLING_NEE || WP_SAMPLING == WP_SAMPLING_MIS)
#endif
#ifndef WP_RR_DEPTH
#define WP_RR_DEPTH WP_DEFAULT_RR_DEPTH
#endif

// The light arrays of shade_surface, bundled for the helpers.
typedef struct LightTable {
    WP_GLOBAL const float* cdf;
    WP_GLOBAL const int* prims;
    WP_GLOBAL const float* pdf_area;
    int count;
} LightTable;

// Adds v to radiance[item] when finite; counts it otherwise.
WP_FN void wp_add_radiance(WP_GLOBAL float4* radiance, int item, float3 v, WP_GLOBAL int* counters) {
    if (wp_all_finite3(v))
        radiance[item] += wp_float4(v, 0.0f);
    else
        wp_atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
}

// Shades one path. Returns 1 and fills *next_ray / *next_path when the path continues, and
// sets *shadow = 1 with *shadow_ray and its unoccluded contribution *contrib when it pushes
// a shadow ray.
WP_FN int wp_shade_path(Ray ray, PathState path, Hit hit, WP_GLOBAL const Triangle* tris,
                        WP_GLOBAL const int* material_ids, WP_GLOBAL const MaterialData* materials,
                        float4 background, uint seed, int bounce, int max_depth,
                        LightTable lights, WP_GLOBAL float4* radiance, WP_GLOBAL int* counters,
                        Ray* next_ray, PathState* next_path, int* shadow, Ray* shadow_ray,
                        float4* contrib) {
    float3 beta = wp_xyz(path.throughput);
    float3 d = wp_xyz(ray.dir);
    const uint pixel = (uint)path.pixel, sample = path.sample;
    *shadow = 0;
#if WP_INJECT_NAN
    if (bounce == 0 && wp_inject_here(WP_INJECT_SHADE, path.pixel)) beta.x = wp_quiet_nan();
#endif
    // Entry guard: a path whose throughput is not finite ends here, counted.
    if (!wp_all_finite3(beta)) {
        wp_atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
        return 0;
    }

    // Escaped: the constant background.
    if (hit.prim < 0) {
        wp_add_radiance(radiance, path.item, beta * wp_xyz(background), counters);
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
    // Emission of the front face, weighted against light sampling where that could have
    // found this point too (non-specular previous bounce of a path that continued).
    if (front && wp_max_component(wp_xyz(m.emission)) > 0.0f) {
        float w = 1.0f;
#if WP_HAVE_NEE
        float pdf_area = lights.pdf_area[hit.prim];
        if (bounce > 0 && !(path.flags & WP_PATH_SPECULAR) && pdf_area > 0.0f) {
#if WP_SAMPLING == WP_SAMPLING_MIS
            // Light density of this direction over solid angle at the previous vertex.
            float dist = hit.t * length(d);
            float p_light = wp_light_pdf_solid_angle(pdf_area, dist * dist, -dot(normalize(d), n));
            w = wp_power_heuristic(path.throughput.w, p_light);
#else
            w = 0.0f;  // NEE only: light sampling alone counts this light
#endif
        }
#endif
        if (w > 0.0f) wp_add_radiance(radiance, path.item, beta * wp_xyz(m.emission) * w, counters);
    }
#endif
    if (bounce >= max_depth) return 0;

    float3 ns = front ? n : -n;
    float3 dn = normalize(d);
    float3 perr;
    float3 p = wp_hit_point(v0, v1, v2, hit.u, hit.v, &perr);
    float tri_offset = wp_triangle_offset(v0, v1, v2);
    float3 org = wp_offset_ray_origin(p, perr, ns, tri_offset);

#if WP_HAVE_NEE
    // Next-event estimation: a point on a light chosen by power; the shadow ray is traced
    // by the shadow stage, which adds *contrib to the radiance when it is unoccluded.
    if (!wp_material_is_specular(m) && lights.count > 0) {
        float4 ul = wp_rng4(seed, pixel, sample, (uint)bounce, WP_RNG_LIGHT);
        int li = wp_light_pick(lights.cdf, lights.count, ul.z);
        int lp = lights.prims[li];
        Triangle lt = tris[lp];
        float3 l0 = wp_xyz(lt.v0), l1 = wp_xyz(lt.v1), l2 = wp_xyz(lt.v2);
        float3 ln = normalize(cross(l1 - l0, l2 - l0));
        float2 bl = wp_sample_triangle_barycentric(ul.x, ul.y);
        float3 yerr;
        float3 y = wp_hit_point(l0, l1, l2, bl.x, bl.y, &yerr);
        float3 to = y - p;
        float dist2 = dot(to, to);
        float3 wi = to * (1.0f / sqrt(dist2));
        float cos_light = -dot(wi, ln);
        float bsdf_pdf;
        float3 fcos = wp_bsdf_eval(m, dn, ns, wi, &bsdf_pdf);
        float p_light = wp_light_pdf_solid_angle(lights.pdf_area[lp], dist2, cos_light);
        if (p_light > 0.0f && wp_max_component(fcos) > 0.0f) {
            float w = 1.0f;
#if WP_SAMPLING == WP_SAMPLING_MIS
            w = wp_power_heuristic(p_light, bsdf_pdf);
#endif
            float3 le = wp_xyz(materials[material_ids[lp]].emission);
            float3 c = beta * fcos * le * (w / p_light);
            if (!wp_all_finite3(c)) {
                wp_atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
            } else if (wp_max_component(c) > 0.0f) {
                // Segment from the offset origin to the light point offset to its front:
                // hits need 0 < t < 1.
                float3 target = wp_offset_ray_origin(y, yerr, ln, wp_triangle_offset(l0, l1, l2));
                float3 sd = target - org;
                shadow_ray->org = make_float4(org.x, org.y, org.z, 0.0f);
                shadow_ray->dir = make_float4(sd.x, sd.y, sd.z, 1.0f);
                *contrib = wp_float4(c, 0.0f);
                *shadow = 1;
            }
        }
    }
#endif

    // Scatter: sample the material on the side the ray came from.
    float4 u = wp_rng4(seed, pixel, sample, (uint)bounce, WP_RNG_BSDF);
    float3 wo, weight;
    float pdf;
    int specular;
    if (!wp_bsdf_sample_pdf(m, dn, ns, front, u, &wo, &weight, &pdf, &specular)) return 0;
    beta = beta * weight;
    if (!wp_all_finite3(beta) || !wp_all_finite3(wo)) {
        wp_atomic_inc(&counters[WP_COUNTER_SHADE_NONFINITE]);
        return 0;
    }
    if (!(wp_max_component(beta) > 0.0f)) return 0;  // black: nothing more to gather

#if WP_RR_DEPTH >= 0
    // Russian roulette from bounce WP_RR_DEPTH on: survive with q = min(1, max component
    // of the throughput) and divide by q, so the estimate stays unbiased.
    if (bounce >= WP_RR_DEPTH) {
        float q = min(1.0f, wp_max_component(beta));
        float4 ur = wp_rng4(seed, pixel, sample, (uint)bounce, WP_RNG_RR);
        if (ur.x >= q) return 0;
        beta = beta * (1.0f / q);
    }
#endif

    // The continued path, from a robustly offset origin.
    float3 org_next = dot(wo, ns) > 0.0f ? org : wp_offset_ray_origin(p, perr, -ns, tri_offset);
    next_ray->org = make_float4(org_next.x, org_next.y, org_next.z, 0.0f);
    next_ray->dir = make_float4(wo.x, wo.y, wo.z, FLT_MAX);
    *next_path = path;
    next_path->throughput = wp_float4(beta, pdf);
    next_path->flags = specular ? WP_PATH_SPECULAR : 0;
    return 1;
}

// The pushes are aggregated per work-group: survivors take slots from a local counter, and
// one work-item reserves the group's range with a single global atomic add (so 1 global
// atomic per 64 paths instead of one per path), for each queue. Every work-item reaches
// the barriers.
WP_KERNEL void shade_surface(WP_GLOBAL const Ray* rays_in, WP_GLOBAL const PathState* paths_in,
                             WP_GLOBAL const int* count_in, WP_GLOBAL const Hit* hits,
                             WP_GLOBAL const Triangle* tris, WP_GLOBAL const int* material_ids,
                             WP_GLOBAL const MaterialData* materials, float4 background,
                             WP_GLOBAL const float* light_cdf, WP_GLOBAL const int* light_prims,
                             WP_GLOBAL const float* light_pdf_area, int light_count, uint seed,
                             int bounce, int max_depth, WP_GLOBAL float4* radiance,
                             WP_GLOBAL int* counters, WP_GLOBAL Ray* rays_out,
                             WP_GLOBAL PathState* paths_out, WP_GLOBAL int* count_out,
                             WP_GLOBAL Ray* shadow_rays, WP_GLOBAL int* shadow_items,
                             WP_GLOBAL float4* shadow_contrib, WP_GLOBAL int* shadow_count) {
    WP_LOCAL int group_count, group_base, shadow_group_count, shadow_group_base;
    int i = wp_global_id();
    int lid = wp_local_id();
    if (lid == 0) {
        group_count = 0;
        shadow_group_count = 0;
    }
    wp_barrier();

    LightTable lights;
    lights.cdf = light_cdf;
    lights.prims = light_prims;
    lights.pdf_area = light_pdf_area;
    lights.count = light_count;
    Ray next_ray, shadow_ray;
    PathState next_path;
    float4 contrib = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
    int push = 0, shadow = 0, item = 0;
    if (i < count_in[0]) {
        PathState path = paths_in[i];
        item = path.item;
        push = wp_shade_path(rays_in[i], path, hits[i], tris, material_ids, materials, background,
                             seed, bounce, max_depth, lights, radiance, counters, &next_ray,
                             &next_path, &shadow, &shadow_ray, &contrib);
    }
    int local_slot = push ? wp_atomic_inc(&group_count) : 0;
    int shadow_local_slot = shadow ? wp_atomic_inc(&shadow_group_count) : 0;
    wp_barrier();
    if (lid == 0) {
        group_base = group_count > 0 ? wp_atomic_add(count_out, group_count) : 0;
        shadow_group_base =
            shadow_group_count > 0 ? wp_atomic_add(shadow_count, shadow_group_count) : 0;
    }
    wp_barrier();
    if (push) {
        int slot = group_base + local_slot;
        rays_out[slot] = next_ray;
        paths_out[slot] = next_path;
    }
    if (shadow) {
        int slot = shadow_group_base + shadow_local_slot;
        shadow_rays[slot] = shadow_ray;
        shadow_items[slot] = item;
        shadow_contrib[slot] = contrib;
    }
}
