// glass.h — a smooth dielectric (material_kinds.h: GLASS) with index of refraction
// η = m.ior (inside / outside; the front face is the outside): reflection with the exact
// Fresnel reflectance F (unpolarised, Born & Wolf; pbrt-v4 FrDielectric), else refraction
// by Snell's law, chosen with probability F / 1 − F, so the weight is m.specular for
// reflection (Mitsuba's specular_reflectance) and albedo / η_rel² for refraction (albedo:
// the transmittance, specular_transmittance) (radiance is compressed entering a denser medium;
// pbrt-v4 DielectricBxDF, TransportMode::Radiance); total internal reflection reflects
// always. Specular. The contract of wp_<name>_sample / wp_<name>_eval is in bsdf.h.
#ifndef WP_MATERIAL_GLASS_H
#define WP_MATERIAL_GLASS_H

#include "../sampling.h"
#include "../types.h"

// Compiled in unless KernelConfig says the scene has no glass material.
#ifndef WP_HAVE_GLASS
#define WP_HAVE_GLASS 1
#endif

WP_NAMESPACE_BEGIN

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

WP_FN int wp_glass_sample(MaterialData m, float3 d, float3 ns, int front, float4 u,
                          float3* wo, float3* weight, float* pdf, int* specular) {
    float eta = front ? 1.0f / m.ior : m.ior;  // η_i / η_t
    float cos_i = -dot(d, ns);
    float cos_t;
    float f = wp_fresnel_dielectric(cos_i, eta, &cos_t);
    *specular = 1;
    *pdf = 0.0f;
    if (u.z < f) {
        *wo = wp_reflect(d, ns);
        *weight = wp_xyz(m.specular);
    } else {
        *wo = normalize(d * eta + ns * (eta * cos_i - cos_t));
        *weight = wp_xyz(m.albedo) * (eta * eta);
    }
    return 1;
}

// A Dirac lobe: no finite f for any given direction.
WP_FN float3 wp_glass_eval(MaterialData m, float3 d, float3 ns, float3 wi, float cos_i,
                           float* pdf) {
    (void)m, (void)d, (void)ns, (void)wi, (void)cos_i;
    *pdf = 0.0f;
    return make_float3(0.0f, 0.0f, 0.0f);
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_GLASS_H
