// glossy.h — glossy reflection with GGX roughness α = m.alpha (material_kinds.h: GLOSSY).
// WP_GLOSSY_MODEL:
//   PHONG: the original "weighted" lobe: a normalised Phong lobe with exponent
//     e = wp_ggx_alpha_to_phong(α) around the mirror direction r (density (e + 1) / (2π)
//     cos^e θr) whose weight is albedo, i.e. f cos = albedo (e + 1) / (2π) cos^e θr above
//     the surface; directions below the surface are absorbed (as in the original).
//   GGX: a Trowbridge-Reitz microfacet BRDF f = F D G2 / (4 cos θo cos θi) (Walter et al.
//     2007) with height-correlated Smith G2 (Heitz 2014), Schlick's Fresnel with
//     F0 = albedo (Schlick, "An Inexpensive BRDF Model for Physically-based Rendering",
//     CGF 13(3), 1994); sampled from the visible normals (Heitz 2018): weight F G2 / G1(wo).
// The contract of wp_<name>_sample / wp_<name>_eval is in bsdf.h.
#ifndef WP_MATERIAL_GLOSSY_H
#define WP_MATERIAL_GLOSSY_H

#include "../sampling.h"
#include "../types.h"

// Compiled in unless KernelConfig says the scene has no glossy material.
#ifndef WP_HAVE_GLOSSY
#define WP_HAVE_GLOSSY 1
#endif

WP_NAMESPACE_BEGIN

// Schlick's Fresnel approximation with normal-incidence reflectance f0 (per channel).
WP_FN float3 wp_fresnel_schlick(float3 f0, float cos_theta) {
    float c = 1.0f - clamp(cos_theta, 0.0f, 1.0f);
    float c5 = c * c * c * c * c;
    return f0 + (make_float3(1.0f, 1.0f, 1.0f) - f0) * c5;
}

// The Phong exponent of the PHONG model for the roughness α: e = 2 / α² − 2, the inverse
// of α = sqrt(2 / (e + 2)) (Walter et al. 2007, section 5.2; the host's
// wp::phong_exponent_to_alpha). The one place the device converts.
WP_FN float wp_ggx_alpha_to_phong(float alpha) { return 2.0f / (alpha * alpha) - 2.0f; }

WP_FN int wp_glossy_sample(MaterialData m, WP_GLOBAL const float* tables, float3 d, float3 ns,
                           int front, float4 u, float3* wo, float3* weight, float* pdf, int* specular) {
    (void)tables, (void)front, (void)specular;
    float3 albedo = wp_xyz(m.albedo);
#if WP_GLOSSY_MODEL == WP_GLOSSY_PHONG
    float e = wp_ggx_alpha_to_phong(m.alpha);
    float3 r = wp_reflect(d, ns);
    float3 lv = wp_sample_phong_lobe(u.x, u.y, e);
    float3 w = wp_to_world(lv, r);
    if (!(dot(w, ns) > 0.0f)) return 0;  // below the surface: absorbed
    *wo = w;
    *weight = albedo;
    *pdf = wp_phong_lobe_pdf(lv.z, e);
    return 1;
#else
    float alpha = m.alpha;
    float3 vo = wp_to_local(-d, ns);
    if (!(vo.z > 0.0f)) return 0;
    float3 h = wp_ggx_sample_vndf(vo, alpha, u.x, u.y);
    float oh = dot(vo, h);
    float3 vi = h * (2.0f * oh) - vo;
    if (!(vi.z > 0.0f)) return 0;  // reflected below the surface: absorbed
    *wo = wp_to_world(vi, ns);
    *weight = wp_fresnel_schlick(albedo, oh) * (wp_ggx_g2(vo, vi, alpha) / wp_ggx_g1(vo, alpha));
    *pdf = wp_ggx_reflect_pdf(vo, vi, alpha);
    return 1;
#endif
}

WP_FN float3 wp_glossy_eval(MaterialData m, WP_GLOBAL const float* tables, float3 d, float3 ns,
                            int front, float3 wi, float cos_i, float* pdf) {
    (void)tables, (void)front;
    float3 albedo = wp_xyz(m.albedo);
    if (!(cos_i > 0.0f)) return make_float3(0.0f, 0.0f, 0.0f);  // reflection only
#if WP_GLOSSY_MODEL == WP_GLOSSY_PHONG
    float3 r = wp_reflect(d, ns);
    *pdf = wp_phong_lobe_pdf(dot(wi, r), wp_ggx_alpha_to_phong(m.alpha));
    return albedo * *pdf;
#else
    float alpha = m.alpha;
    float3 zero = make_float3(0.0f, 0.0f, 0.0f);
    float3 vo = wp_to_local(-d, ns);
    float3 vi = wp_to_local(wi, ns);
    if (!(vo.z > 0.0f) || !(vi.z > 0.0f)) return zero;
    float3 h = normalize(vo + vi);
    *pdf = wp_ggx_reflect_pdf(vo, vi, alpha);
    float s = wp_ggx_d(h, alpha) * wp_ggx_g2(vo, vi, alpha) / (4.0f * vo.z);
    return wp_fresnel_schlick(albedo, dot(vo, h)) * s;
#endif
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_GLOSSY_H
