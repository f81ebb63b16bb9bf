// roughplastic.h — rough plastic (material_kinds.h: ROUGH_PLASTIC), Mitsuba 3's
// `roughplastic`: a rough dielectric coat (index η = m.ior, the material's microfacet
// distribution) over a Lambertian base of reflectance albedo. In the local frame of ns with
// vo = −d and vi (both above the surface), h = normalize(vo + vi):
//   coat: f cos θi = specular F(vo·h) D(h) G(vo, vi) / (4 cos θo)   (microfacet.h, glass.h)
//   base: f cos θi = diffuse T(cos θo) T(cos θi) cos θi / (π η²),
//         diffuse = albedo / (1 − R) (or albedo / (1 − albedo R) with WP_PLASTIC_NONLINEAR)
// where T(μ) is the coat's external transmittance at cos θ = μ and R its internal diffuse
// reflectance: tables the host integrates numerically per material (scene/material_tables.h)
// and this file reads at tables[m.table] (WP_ROUGH_PLASTIC_RES values of T at
// μ = k / (RES − 1), linearly interpolated as Mitsuba's lerp_gather does, then R).
// Sampling (Mitsuba's): the coat's visible normals with probability
// P = (1 − T(cos θo)) w / ((1 − T(cos θo)) w + T(cos θo) (1 − w)), w = m.specular.w (the
// host's specular sampling weight), else a cosine-weighted direction; the weight is the
// whole f cos / pdf of both lobes, the density P D_vo(h) / (4 vo·h) + (1 − P) cos θi / π.
// Two-sided like every wavepath kind (Mitsuba's is black from behind outside a `twosided`).
// A material without tables (m.table < 0 or no buffer) absorbs.
// The contract of wp_<name>_sample / wp_<name>_eval is in bsdf.h.
#ifndef WP_MATERIAL_ROUGHPLASTIC_H
#define WP_MATERIAL_ROUGHPLASTIC_H

#include "../microfacet.h"
#include "../sampling.h"
#include "../types.h"
#include "glass.h"

// Compiled in unless KernelConfig says the scene has no rough plastic.
#ifndef WP_HAVE_ROUGH_PLASTIC
#define WP_HAVE_ROUGH_PLASTIC 1
#endif

WP_NAMESPACE_BEGIN

// The external transmittance T(μ) of the table t (WP_ROUGH_PLASTIC_RES values over
// μ = 0 .. 1), linearly interpolated.
WP_FN float wp_roughplastic_transmittance(WP_GLOBAL const float* t, float mu) {
    const int n = WP_ROUGH_PLASTIC_RES;
    float x = clamp(mu, 0.0f, 1.0f) * (float)(n - 1);
    int i = min((int)x, n - 2);
    float w = x - (float)i;
    return t[i] * (1.0f - w) + t[i + 1] * w;
}

// f cos θi of both lobes and the density of wp_roughplastic_sample for vo, vi (local, both
// above the surface); t: the material's tables.
WP_FN float3 wp_roughplastic_eval_local(MaterialData m, WP_GLOBAL const float* t, float3 vo,
                                        float3 vi, float* pdf) {
    Microfacet mf = wp_microfacet(m);
    float to = wp_roughplastic_transmittance(t, vo.z);
    float ti = wp_roughplastic_transmittance(t, vi.z);
    float r_int = t[WP_ROUGH_PLASTIC_RES];
    // The lobe probabilities.
    float w = m.specular.w;
    float ps = (1.0f - to) * w, pd = (1.0f - w) * to;
    ps = ps + pd > 0.0f ? ps / (ps + pd) : 0.0f;
    // Coat.
    float3 h = normalize(vo + vi);
    float oh = dot(vo, h);
    float cos_t;
    float f = wp_fresnel_dielectric(oh, 1.0f / m.ior, &cos_t);
    float3 coat = wp_xyz(m.specular) * (f * wp_mf_d(mf, h) * wp_mf_g(mf, vo, vi) / (4.0f * vo.z));
    float pdf_coat = oh > 0.0f ? wp_mf_pdf_vndf(mf, vo, h) / (4.0f * oh) : 0.0f;
    // Base.
    float3 albedo = wp_xyz(m.albedo);
    float3 one = make_float3(1.0f, 1.0f, 1.0f);
    float3 den = (m.flags & WP_PLASTIC_NONLINEAR) ? one - albedo * r_int : one * (1.0f - r_int);
    float s = to * ti * vi.z * WP_INV_PI / (m.ior * m.ior);
    float3 base = make_float3(albedo.x / den.x, albedo.y / den.y, albedo.z / den.z) * s;
    *pdf = ps * pdf_coat + (1.0f - ps) * wp_cosine_hemisphere_pdf(vi.z);
    return coat + base;
}

WP_FN int wp_roughplastic_sample(MaterialData m, WP_GLOBAL const float* tables, float3 d,
                                 float3 ns, int front, float4 u, float3* wo, float3* weight,
                                 float* pdf, int* specular) {
    (void)front, (void)specular;
    if (m.table < 0 || !tables) return 0;
    WP_GLOBAL const float* t = tables + m.table;
    float3 vo = wp_to_local(-d, ns);
    if (!(vo.z > 0.0f)) return 0;
    float to = wp_roughplastic_transmittance(t, vo.z);
    float w = m.specular.w;
    float ps = (1.0f - to) * w, pd = (1.0f - w) * to;
    ps = ps + pd > 0.0f ? ps / (ps + pd) : 0.0f;
    float3 vi;
    if (u.z < ps) {
        Microfacet mf = wp_microfacet(m);
        float3 h = wp_mf_sample_vndf(mf, vo, u.x, u.y);
        vi = h * (2.0f * dot(vo, h)) - vo;
    } else {
        vi = wp_sample_cosine_hemisphere(u.x, u.y);
    }
    if (!(vi.z > 0.0f)) return 0;  // the coat reflected below the surface: absorbed
    float p;
    float3 fcos = wp_roughplastic_eval_local(m, t, vo, vi, &p);
    if (!(p > 0.0f)) return 0;
    *wo = wp_to_world(vi, ns);
    *weight = fcos * (1.0f / p);
    *pdf = p;
    return 1;
}

WP_FN float3 wp_roughplastic_eval(MaterialData m, WP_GLOBAL const float* tables, float3 d,
                                  float3 ns, int front, float3 wi, float cos_i, float* pdf) {
    (void)front;
    float3 zero = make_float3(0.0f, 0.0f, 0.0f);
    if (m.table < 0 || !tables || !(cos_i > 0.0f)) return zero;
    float3 vo = wp_to_local(-d, ns);
    float3 vi = wp_to_local(wi, ns);
    if (!(vo.z > 0.0f) || !(vi.z > 0.0f)) return zero;
    return wp_roughplastic_eval_local(m, tables + m.table, vo, vi, pdf);
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_ROUGHPLASTIC_H
