// roughconductor.h — a rough conductor (material_kinds.h: ROUGH_CONDUCTOR): the microfacet
// BRDF f = albedo F(wo·h) D(h) G(wo, wi) / (4 cos θo cos θi) (Walter et al. 2007) with the
// conductor Fresnel term of η + i k (microfacet.h), distribution GGX or Beckmann, isotropic or
// anisotropic, G separable (Mitsuba 3) or height-correlated (pbrt-v4) per material. Sampled
// from the visible normals: weight albedo F G / G1(wo), density D_wo(h) / (4 wo·h).
// The contract of wp_<name>_sample / wp_<name>_eval is in bsdf.h.
#ifndef WP_MATERIAL_ROUGHCONDUCTOR_H
#define WP_MATERIAL_ROUGHCONDUCTOR_H

#include "../microfacet.h"
#include "../sampling.h"
#include "../types.h"

// Compiled in unless KernelConfig says the scene has no rough conductor.
#ifndef WP_HAVE_ROUGH_CONDUCTOR
#define WP_HAVE_ROUGH_CONDUCTOR 1
#endif

WP_NAMESPACE_BEGIN

WP_FN int wp_roughconductor_sample(MaterialData m, WP_GLOBAL const float* tables, float3 d, float3 ns,
                                   int front, float4 u, float3* wo, float3* weight, float* pdf, int* specular) {
    (void)tables, (void)front, (void)specular;
    Microfacet mf = wp_microfacet(m);
    float3 vo = wp_to_local(-d, ns);
    if (!(vo.z > 0.0f)) return 0;  // below the surface
    // Λ(wo), G1(wo) and D(h) once each (the weight and the density share them).
    float lo = wp_mf_lambda(mf, vo);
    float g1o = 1.0f / (1.0f + lo);
    if (!(g1o > 0.0f)) return 0;  // below the surface, or so grazing that Λ overflows: no visible normal
    float3 h = wp_mf_sample_vndf(mf, vo, u.x, u.y);
    float oh = dot(vo, h);
    if (!(oh > 0.0f)) return 0;
    float3 vi = h * (2.0f * oh) - vo;
    if (!(vi.z > 0.0f)) return 0;  // reflected below the surface: absorbed
    *wo = wp_to_world(vi, ns);
    float3 f = wp_fresnel_conductor(oh, wp_xyz(m.eta), wp_xyz(m.k));
    *weight = wp_xyz(m.albedo) * f * (wp_mf_g_lo(mf, lo, vi) / g1o);
    *pdf = wp_mf_pdf_vndf_gd(g1o, vo, h, wp_mf_d(mf, h)) / (4.0f * oh);
    return 1;
}

WP_FN float3 wp_roughconductor_eval(MaterialData m, WP_GLOBAL const float* tables, float3 d, float3 ns,
                                    int front, float3 wi, float cos_i, float* pdf) {
    (void)tables, (void)front, (void)cos_i;
    float3 zero = make_float3(0.0f, 0.0f, 0.0f);
    Microfacet mf = wp_microfacet(m);
    float3 vo = wp_to_local(-d, ns);
    float3 vi = wp_to_local(wi, ns);
    if (!(vo.z > 0.0f) || !(vi.z > 0.0f)) return zero;
    float3 h = normalize(vo + vi);
    float oh = dot(vo, h);
    float lo = wp_mf_lambda(mf, vo), d_h = wp_mf_d(mf, h);
    *pdf = wp_mf_pdf_vndf_gd(1.0f / (1.0f + lo), vo, h, d_h) / (4.0f * oh);
    float s = d_h * wp_mf_g_lo(mf, lo, vi) / (4.0f * vo.z);
    return wp_xyz(m.albedo) * wp_fresnel_conductor(oh, wp_xyz(m.eta), wp_xyz(m.k)) * s;
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_ROUGHCONDUCTOR_H
