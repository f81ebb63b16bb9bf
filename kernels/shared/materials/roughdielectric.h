// roughdielectric.h — a rough dielectric interface (material_kinds.h: ROUGH_DIELECTRIC):
// the microfacet reflection and refraction of Walter et al. 2007 ("Microfacet Models for
// Refraction through Rough Surfaces", EGSR), as Mitsuba 3's `roughdielectric` and pbrt-v4's
// rough DielectricBxDF evaluate it in radiance mode. In the local frame of ns (+z, the
// arriving side) with vo = −d (towards the viewer), vi (towards the light) and
// η = η_t / η_i (m.ior arriving at the front, 1 / m.ior at the back):
//   reflection (vi.z > 0), h = normalize(vo + vi):
//     f cos θi = specular F(vo·h) D(h) G(vo, vi) / (4 cos θo)
//   transmission (vi.z < 0), h = ±normalize(vo + η vi) with h.z > 0:
//     f |cos θi| = albedo (1 − F(vo·h)) D(h) G(vo, vi) |vo·h| |vi·h| / (cos θo (vo·h + η vi·h)²)
//     (Walter's eq. 21 times the radiance factor 1 / η², which cancels its η²);
// F the exact dielectric Fresnel reflectance (glass.h), D, G the material's distribution
// (microfacet.h: GGX or Beckmann, anisotropic, G separable or height-correlated; a
// transmitted direction enters G mirrored to the upper side), both directions required to
// see the front of h (vo·h > 0, vi·h vi.z > 0). Sampling: h from the visible normals of vo
// (D_vo(h) = G1(vo) (vo·h) D(h) / cos θo), then reflection with probability F(vo·h), else
// refraction (total internal reflection: always reflection); weight = tint G / G1(vo)
// (/ η² for refraction); density D_vo(h) F / (4 vo·h) or D_vo(h) (1 − F) η² |vi·h| /
// (vo·h + η vi·h)². A reflection below or a refraction above the surface is absorbed.
// The contract of wp_<name>_sample / wp_<name>_eval is in bsdf.h.
#ifndef WP_MATERIAL_ROUGHDIELECTRIC_H
#define WP_MATERIAL_ROUGHDIELECTRIC_H

#include "../microfacet.h"
#include "../sampling.h"
#include "../types.h"
#include "glass.h"

// Compiled in unless KernelConfig says the scene has no rough dielectric.
#ifndef WP_HAVE_ROUGH_DIELECTRIC
#define WP_HAVE_ROUGH_DIELECTRIC 1
#endif

WP_NAMESPACE_BEGIN

WP_FN int wp_roughdielectric_sample(MaterialData m, WP_GLOBAL const float* tables, float3 d,
                                    float3 ns, int front, float4 u, float3* wo, float3* weight,
                                    float* pdf, int* specular) {
    (void)tables, (void)specular;
    Microfacet mf = wp_microfacet(m);
    float eta = front ? m.ior : 1.0f / m.ior;  // η_t / η_i
    float3 vo = wp_to_local(-d, ns);
    if (!(vo.z > 0.0f)) return 0;
    float3 h = wp_mf_sample_vndf(mf, vo, u.x, u.y);
    float oh = dot(vo, h);
    if (!(oh > 0.0f)) return 0;
    float pdf_h = wp_mf_pdf_vndf(mf, vo, h);
    float cos_t;
    float f = wp_fresnel_dielectric(oh, 1.0f / eta, &cos_t);
    float3 vi;
    if (u.z < f) {
        // Reflection about h.
        vi = h * (2.0f * oh) - vo;
        if (!(vi.z > 0.0f)) return 0;  // below the surface: absorbed
        *weight = wp_xyz(m.specular) * (wp_mf_g(mf, vo, vi) / wp_mf_g1(mf, vo));
        *pdf = f * pdf_h / (4.0f * oh);
    } else {
        // Refraction through h (Snell; cos_t > 0 is the cosine on the other side).
        float inv_eta = 1.0f / eta;
        vi = h * (inv_eta * oh - cos_t) - vo * inv_eta;
        float ih = dot(vi, h);
        if (!(vi.z < 0.0f) || !(ih < 0.0f)) return 0;  // stays above: absorbed
        float3 vt = make_float3(vi.x, vi.y, -vi.z);
        *weight = wp_xyz(m.albedo) * (inv_eta * inv_eta * wp_mf_g(mf, vo, vt) / wp_mf_g1(mf, vo));
        float den = oh + eta * ih;
        *pdf = (1.0f - f) * pdf_h * eta * eta * -ih / (den * den);
    }
    *wo = wp_to_world(vi, ns);
    return 1;
}

WP_FN float3 wp_roughdielectric_eval(MaterialData m, WP_GLOBAL const float* tables, float3 d,
                                     float3 ns, int front, float3 wi, float cos_i, float* pdf) {
    (void)tables, (void)cos_i;
    float3 zero = make_float3(0.0f, 0.0f, 0.0f);
    Microfacet mf = wp_microfacet(m);
    float eta = front ? m.ior : 1.0f / m.ior;  // η_t / η_i
    float3 vo = wp_to_local(-d, ns);
    float3 vi = wp_to_local(wi, ns);
    if (!(vo.z > 0.0f) || !(vi.z != 0.0f)) return zero;
    int reflect = vi.z > 0.0f;
    // The (generalised) half vector, on the normal's side.
    float3 h = normalize(vo + vi * (reflect ? 1.0f : eta));
    if (h.z < 0.0f) h = -h;
    float oh = dot(vo, h), ih = dot(vi, h);
    // Both directions see the front of the microfacet (Mitsuba's smith_g1 test).
    if (!(oh > 0.0f) || !(ih * vi.z > 0.0f)) return zero;
    float d_h = wp_mf_d(mf, h);
    float pdf_h = wp_mf_pdf_vndf(mf, vo, h);
    float cos_t;
    float f = wp_fresnel_dielectric(oh, 1.0f / eta, &cos_t);
    if (reflect) {
        *pdf = f * pdf_h / (4.0f * ih);
        return wp_xyz(m.specular) * (f * d_h * wp_mf_g(mf, vo, vi) / (4.0f * vo.z));
    }
    float3 vt = make_float3(vi.x, vi.y, -vi.z);
    float den = oh + eta * ih;
    *pdf = (1.0f - f) * pdf_h * eta * eta * -ih / (den * den);
    return wp_xyz(m.albedo) *
           ((1.0f - f) * d_h * wp_mf_g(mf, vo, vt) * oh * -ih / (vo.z * den * den));
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_ROUGHDIELECTRIC_H
