// bsdf.h — scattering at a surface: sampling, evaluation and densities per material kind.
//
// wp_bsdf_sample draws an outgoing direction and returns its weight f cos / pdf (the factor
// the path throughput is multiplied by), the density it was drawn with (solid angle) and
// whether the event is specular (a Dirac lobe, which light sampling cannot reach);
// wp_bsdf_eval returns f cos and that same density for a given direction, for next-event
// estimation and MIS weights (Veach & Guibas 1995). Materials:
//   * diffuse (Lambertian, f = albedo / π). WP_SAMPLING selects the strategy: UNIFORM is the
//     original renderer's uniform hemisphere (pdf 1 / (2π), weight 2 albedo cos θ); every
//     other strategy samples cos θ / π (weight albedo).
//   * mirror: the exact reflection, weight albedo, specular.
//   * glossy, WP_GLOSSY_MODEL:
//       PHONG: the original "weighted" lobe: a normalised Phong lobe with the material's
//         exponent e around the mirror direction r (density (e + 1) / (2π) cos^e α) whose
//         weight is albedo, i.e. f cos = albedo (e + 1) / (2π) cos^e α above the surface;
//         directions below the surface are absorbed (as in the original).
//       GGX: a Trowbridge-Reitz microfacet BRDF f = F D G2 / (4 cos θo cos θi) (Walter et al.
//         2007) with height-correlated Smith G2 (Heitz 2014), Schlick's Fresnel with
//         F0 = albedo (Schlick, "An Inexpensive BRDF Model for Physically-based Rendering",
//         CGF 13(3), 1994), roughness α = sqrt(2 / (e + 2)) from the exponent e; sampled
//         from the visible normals (Heitz 2018): weight F G2 / G1(wo).
//   * glass: a smooth dielectric with index of refraction η = ior (inside / outside):
//     reflection with the exact Fresnel reflectance F (unpolarised, Born & Wolf; pbrt-v4
//     FrDielectric), else refraction by Snell's law, chosen with probability F / 1 − F, so
//     the weight is albedo for reflection and albedo / η_rel² for refraction (radiance is
//     compressed entering a denser medium; pbrt-v4 DielectricBxDF, TransportMode::Radiance);
//     total internal reflection reflects always. Specular; the front face is the outside.
// Which kinds are compiled is set by WP_HAVE_DIFFUSE / _MIRROR / _GLOSSY / _GLASS (KernelConfig);
// a material of a kind that is not compiled absorbs the path.
#ifndef WP_BSDF_H
#define WP_BSDF_H

#include "sampling.h"
#include "types.h"

#ifndef WP_HAVE_DIFFUSE
#define WP_HAVE_DIFFUSE 1
#endif
#ifndef WP_HAVE_MIRROR
#define WP_HAVE_MIRROR 1
#endif
#ifndef WP_HAVE_GLOSSY
#define WP_HAVE_GLOSSY 1
#endif
#ifndef WP_HAVE_GLASS
#define WP_HAVE_GLASS 1
#endif

// Sampling strategies (--sampling; render/kernel_config.h).
#define WP_SAMPLING_UNIFORM 0  // uniform hemisphere for diffuse, no light sampling (original)
#define WP_SAMPLING_COSINE 1   // BSDF sampling only: cosine diffuse, lobe sampling for glossy
#define WP_SAMPLING_NEE 2      // cosine + next-event estimation for diffuse/glossy surfaces
#define WP_SAMPLING_MIS 3      // NEE and BSDF sampling combined by the power heuristic
#ifndef WP_SAMPLING
#define WP_SAMPLING WP_SAMPLING_UNIFORM
#endif
// Glossy models (--glossy).
#define WP_GLOSSY_PHONG 0
#define WP_GLOSSY_GGX 1
#ifndef WP_GLOSSY_MODEL
#define WP_GLOSSY_MODEL WP_GLOSSY_PHONG
#endif

WP_NAMESPACE_BEGIN

// Schlick's Fresnel approximation with normal-incidence reflectance f0 (per channel).
WP_FN float3 wp_fresnel_schlick(float3 f0, float cos_theta) {
    float c = 1.0f - clamp(cos_theta, 0.0f, 1.0f);
    float c5 = c * c * c * c * c;
    return f0 + (make_float3(1.0f, 1.0f, 1.0f) - f0) * c5;
}

// Exact Fresnel reflectance of a smooth dielectric for unpolarised light; cos_i > 0 on the
// arriving side, eta = η_i / η_t. Returns 1 for total internal reflection; *cos_t is the
// cosine of the refracted direction.
WP_FN float wp_fresnel_dielectric(float cos_i, float eta, float* cos_t) {
    float sin2_t = eta * eta * max(0.0f, 1.0f - cos_i * cos_i);
    if (sin2_t >= 1.0f) {
        *cos_t = 0.0f;
        return 1.0f;
    }
    float ct = sqrt(1.0f - sin2_t);
    *cos_t = ct;
    float rs = (eta * cos_i - ct) / (eta * cos_i + ct);
    float rp = (cos_i - eta * ct) / (cos_i + eta * ct);
    return 0.5f * (rs * rs + rp * rp);
}

// d: unit direction of the arriving ray (pointing at the surface); ns: unit geometric
// normal on the side the ray arrives from (dot(d, ns) <= 0); front: the ray arrives at the
// front face (for glass: from outside); u: uniform numbers in [0, 1).
// Returns 1 and writes the unit outgoing direction, the weight f cos / pdf, the density
// (solid angle; 0 for specular events) and whether the event is specular; returns 0 when
// the path is absorbed.
WP_FN int wp_bsdf_sample_pdf(MaterialData m, float3 d, float3 ns, int front, float4 u,
                             float3* wo, float3* weight, float* pdf, int* specular) {
    float3 albedo = wp_xyz(m.albedo);
    *specular = 0;
#if WP_HAVE_DIFFUSE
    if (m.kind == WP_MATERIAL_DIFFUSE) {
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
#endif
#if WP_HAVE_MIRROR
    if (m.kind == WP_MATERIAL_MIRROR) {
        *wo = wp_reflect(d, ns);
        *weight = albedo;
        *pdf = 0.0f;
        *specular = 1;
        return 1;
    }
#endif
#if WP_HAVE_GLOSSY
    if (m.kind == WP_MATERIAL_GLOSSY) {
#if WP_GLOSSY_MODEL == WP_GLOSSY_PHONG
        float3 r = wp_reflect(d, ns);
        float3 lv = wp_sample_phong_lobe(u.x, u.y, m.albedo.w);
        float3 w = wp_to_world(lv, r);
        if (!(dot(w, ns) > 0.0f)) return 0;  // below the surface: absorbed
        *wo = w;
        *weight = albedo;
        *pdf = wp_phong_lobe_pdf(lv.z, m.albedo.w);
        return 1;
#else
        float alpha = wp_phong_to_ggx_alpha(m.albedo.w);
        float3 vo = wp_to_local(-d, ns);
        if (!(vo.z > 0.0f)) return 0;
        float3 h = wp_ggx_sample_vndf(vo, alpha, u.x, u.y);
        float oh = dot(vo, h);
        float3 vi = h * (2.0f * oh) - vo;
        if (!(vi.z > 0.0f)) return 0;  // reflected below the surface: absorbed
        *wo = wp_to_world(vi, ns);
        *weight = wp_fresnel_schlick(albedo, oh) *
                  (wp_ggx_g2(vo, vi, alpha) / wp_ggx_g1(vo, alpha));
        *pdf = wp_ggx_reflect_pdf(vo, vi, alpha);
        return 1;
#endif
    }
#endif
#if WP_HAVE_GLASS
    if (m.kind == WP_MATERIAL_GLASS) {
        float eta = front ? 1.0f / m.ior : m.ior;  // η_i / η_t
        float cos_i = -dot(d, ns);
        float cos_t;
        float f = wp_fresnel_dielectric(cos_i, eta, &cos_t);
        *specular = 1;
        *pdf = 0.0f;
        if (u.z < f) {
            *wo = wp_reflect(d, ns);
            *weight = albedo;
        } else {
            *wo = normalize(d * eta + ns * (eta * cos_i - cos_t));
            *weight = albedo * (eta * eta);
        }
        return 1;
    }
#endif
    return 0;
}

// The original entry point: direction and weight only.
WP_FN int wp_bsdf_sample(MaterialData m, float3 d, float3 ns, float4 u, float3* wo,
                         float3* weight) {
    float pdf;
    int specular;
    return wp_bsdf_sample_pdf(m, d, ns, 1, u, wo, weight, &pdf, &specular);
}

// f cos θi for the unit direction wi (towards the light), and in *pdf the density with
// which wp_bsdf_sample_pdf draws wi. Zero for specular and uncompiled kinds and for wi
// below the surface.
WP_FN float3 wp_bsdf_eval(MaterialData m, float3 d, float3 ns, float3 wi, float* pdf) {
    float3 albedo = wp_xyz(m.albedo);
    float3 zero = make_float3(0.0f, 0.0f, 0.0f);
    float cos_i = dot(wi, ns);
    *pdf = 0.0f;
    if (!(cos_i > 0.0f)) return zero;
#if WP_HAVE_DIFFUSE
    if (m.kind == WP_MATERIAL_DIFFUSE) {
#if WP_SAMPLING == WP_SAMPLING_UNIFORM
        *pdf = wp_uniform_hemisphere_pdf();
#else
        *pdf = wp_cosine_hemisphere_pdf(cos_i);
#endif
        return albedo * (cos_i * WP_INV_PI);
    }
#endif
#if WP_HAVE_GLOSSY
    if (m.kind == WP_MATERIAL_GLOSSY) {
#if WP_GLOSSY_MODEL == WP_GLOSSY_PHONG
        float3 r = wp_reflect(d, ns);
        *pdf = wp_phong_lobe_pdf(dot(wi, r), m.albedo.w);
        return albedo * *pdf;
#else
        float alpha = wp_phong_to_ggx_alpha(m.albedo.w);
        float3 vo = wp_to_local(-d, ns);
        float3 vi = wp_to_local(wi, ns);
        if (!(vo.z > 0.0f) || !(vi.z > 0.0f)) return zero;
        float3 h = normalize(vo + vi);
        *pdf = wp_ggx_reflect_pdf(vo, vi, alpha);
        float s = wp_ggx_d(h, alpha) * wp_ggx_g2(vo, vi, alpha) / (4.0f * vo.z);
        return wp_fresnel_schlick(albedo, dot(vo, h)) * s;
#endif
    }
#endif
    return zero;
}

WP_NAMESPACE_END

#endif  // WP_BSDF_H
