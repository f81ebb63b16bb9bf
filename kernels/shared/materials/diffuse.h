// diffuse.h — Lambertian reflection, f = albedo / π (material_kinds.h: DIFFUSE).
// WP_SAMPLING selects the strategy: UNIFORM is the original renderer's uniform hemisphere
// (pdf 1 / (2π), weight 2 albedo cos θ); every other strategy samples cos θ / π (weight
// albedo). The contract of wp_<name>_sample / wp_<name>_eval is in bsdf.h.
#ifndef WP_MATERIAL_DIFFUSE_H
#define WP_MATERIAL_DIFFUSE_H

#include "../sampling.h"
#include "../types.h"

// Compiled in unless KernelConfig says the scene has no diffuse material.
#ifndef WP_HAVE_DIFFUSE
#define WP_HAVE_DIFFUSE 1
#endif

WP_NAMESPACE_BEGIN

WP_FN int wp_diffuse_sample(MaterialData m, WP_GLOBAL const float* tables, float3 d, float3 ns,
                            int front, float4 u, float3* wo, float3* weight, float* pdf, int* specular) {
    (void)tables, (void)d, (void)front, (void)specular;
    float3 albedo = wp_xyz(m.albedo);
#if WP_SAMPLING == WP_SAMPLING_UNIFORM
    float3 lv = wp_sample_uniform_hemisphere(u.x, u.y);
    *wo = wp_to_world(lv, ns);
    // (albedo / π) cos θ / (1 / 2π)
    *weight = albedo * (2.0f * lv.z);
    *pdf = wp_uniform_hemisphere_pdf();
#else
    float3 lv = wp_sample_cosine_hemisphere(u.x, u.y);
    *wo = wp_to_world(lv, ns);
    // (albedo / π) cos θ / (cos θ / π)
    *weight = albedo;
    *pdf = wp_cosine_hemisphere_pdf(lv.z);
#endif
    return 1;
}

WP_FN float3 wp_diffuse_eval(MaterialData m, WP_GLOBAL const float* tables, float3 d, float3 ns,
                             int front, float3 wi, float cos_i, float* pdf) {
    (void)tables, (void)d, (void)ns, (void)front, (void)wi;
    if (!(cos_i > 0.0f)) return make_float3(0.0f, 0.0f, 0.0f);  // reflection only
#if WP_SAMPLING == WP_SAMPLING_UNIFORM
    *pdf = wp_uniform_hemisphere_pdf();
#else
    *pdf = wp_cosine_hemisphere_pdf(cos_i);
#endif
    return wp_xyz(m.albedo) * (cos_i * WP_INV_PI);
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_DIFFUSE_H
