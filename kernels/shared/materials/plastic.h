// plastic.h — smooth plastic (material_kinds.h: PLASTIC), Mitsuba 3's `plastic`: a smooth
// dielectric coat of index η = m.ior over a Lambertian base of reflectance albedo, with
// light that is reflected back and forth between the base and the underside of the coat
// summed in closed form (Weidlich & Wilkie 2007, as Mitsuba 3 models it). With
// F(c) = the dielectric Fresnel reflectance at cos θ = c from outside:
//   coat: a Dirac mirror lobe of weight specular F(cos θo);
//   base: f cos θi = diffuse (cos θi / π) (1 − F(cos θo)) (1 − F(cos θi)) / η²,
//         diffuse = albedo / (1 − F_dr) (linear, the default) or albedo / (1 − albedo F_dr)
//         (m.flags & WP_PLASTIC_NONLINEAR: internal scattering saturates the colour),
//   F_dr = the diffuse Fresnel reflectance of the coat's inside (wp_fresnel_diffuse_
//   reflectance(1 / η), Mitsuba's polynomial fits, so images match Mitsuba's).
// Sampling (Mitsuba's): the coat with probability P = F w / (F w + (1 − F)(1 − w)) with
// F = F(cos θo) and w = m.specular.w (the host's specular sampling weight: mean specular /
// (mean diffuse + mean specular)), else a cosine-weighted direction: weights specular F / P
// (Dirac, *specular = 1) and f cos / ((1 − P) cos θi / π). eval returns the base only, with
// density (1 − P) cos θi / π. Two-sided like every wavepath kind (Mitsuba's is black from
// behind outside a `twosided`), so `front` is not read.
// The contract of wp_<name>_sample / wp_<name>_eval is in bsdf.h.
#ifndef WP_MATERIAL_PLASTIC_H
#define WP_MATERIAL_PLASTIC_H

#include "../sampling.h"
#include "../types.h"
#include "glass.h"

// Compiled in unless KernelConfig says the scene has no plastic.
#ifndef WP_HAVE_PLASTIC
#define WP_HAVE_PLASTIC 1
#endif

WP_NAMESPACE_BEGIN

// The diffuse Fresnel reflectance F_dr(η) = ∫ F(cos θ; η) 2 cos θ dcos θ of an interface of
// relative index η (η < 1: seen from the denser side), by the polynomial fits Mitsuba 3's
// fresnel_diffuse_reflectance uses: Egan & Hilgeman 1973 for η < 1, d'Eon & Irving 2011
// ("A Quantized-Diffusion Model for Rendering Translucent Materials") for η >= 1. Their
// error against the integral is below 0.4 % for η in [1, 2] and 1 / η in [1, 2]
// (tests/test_materials_plastic.cpp measures it).
WP_FN float wp_fresnel_diffuse_reflectance(float eta) {
    float inv = 1.0f / eta;
    if (eta < 1.0f) return 0.0636f * inv + (eta * (eta * -1.4399f + 0.7099f) + 0.6681f);
    return 0.919317f +
           inv * (-3.4793f + inv * (6.75335f + inv * (-7.80989f + inv * (4.98554f + inv * -1.36881f))));
}

// The Fresnel reflectance of the coat at cos θ = c (from outside).
WP_FN float wp_plastic_fresnel(float c, float ior) {
    float cos_t;
    return wp_fresnel_dielectric(c, 1.0f / ior, &cos_t);
}

// The probability of sampling the coat at F(cos θo) = fo with sampling weight w.
WP_FN float wp_plastic_coat_prob(float fo, float w) {
    float ps = fo * w, pd = (1.0f - fo) * (1.0f - w);
    return ps + pd > 0.0f ? ps / (ps + pd) : 0.0f;
}

// The base's f cos θi / cos θi (no cosine), for F(cos θo) = fo, F(cos θi) = fi.
WP_FN float3 wp_plastic_base(MaterialData m, float fo, float fi) {
    float3 albedo = wp_xyz(m.albedo);
    float fdr = wp_fresnel_diffuse_reflectance(1.0f / m.ior);
    float3 one = make_float3(1.0f, 1.0f, 1.0f);
    float3 den = (m.flags & WP_PLASTIC_NONLINEAR) ? one - albedo * fdr : one * (1.0f - fdr);
    float s = (1.0f - fo) * (1.0f - fi) * WP_INV_PI / (m.ior * m.ior);
    return make_float3(albedo.x / den.x, albedo.y / den.y, albedo.z / den.z) * s;
}

WP_FN int wp_plastic_sample(MaterialData m, WP_GLOBAL const float* tables, float3 d, float3 ns,
                            int front, float4 u, float3* wo, float3* weight, float* pdf,
                            int* specular) {
    (void)tables, (void)front;
    float co = -dot(d, ns);
    if (!(co > 0.0f)) return 0;
    float fo = wp_plastic_fresnel(co, m.ior);
    float p_coat = wp_plastic_coat_prob(fo, m.specular.w);
    if (u.z < p_coat) {
        *wo = wp_reflect(d, ns);
        *weight = wp_xyz(m.specular) * (fo / p_coat);
        *pdf = 0.0f;
        *specular = 1;
        return 1;
    }
    float3 lv = wp_sample_cosine_hemisphere(u.x, u.y);
    if (!(lv.z > 0.0f)) return 0;
    *wo = wp_to_world(lv, ns);
    float fi = wp_plastic_fresnel(lv.z, m.ior);
    float p = (1.0f - p_coat) * wp_cosine_hemisphere_pdf(lv.z);
    *pdf = p;
    // f cos / p with f cos = base · cos θi and p = (1 − P) cos θi / π.
    *weight = wp_plastic_base(m, fo, fi) * (WP_PI / (1.0f - p_coat));
    return 1;
}

WP_FN float3 wp_plastic_eval(MaterialData m, WP_GLOBAL const float* tables, float3 d, float3 ns,
                             int front, float3 wi, float cos_i, float* pdf) {
    (void)tables, (void)front, (void)wi;
    float co = -dot(d, ns);
    if (!(co > 0.0f) || !(cos_i > 0.0f)) return make_float3(0.0f, 0.0f, 0.0f);
    float fo = wp_plastic_fresnel(co, m.ior);
    float fi = wp_plastic_fresnel(cos_i, m.ior);
    *pdf = (1.0f - wp_plastic_coat_prob(fo, m.specular.w)) * wp_cosine_hemisphere_pdf(cos_i);
    return wp_plastic_base(m, fo, fi) * cos_i;
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_PLASTIC_H
