// conductor.h — a smooth conductor (material_kinds.h: CONDUCTOR): mirror reflection weighted
// by the exact Fresnel reflectance of the complex index of refraction η + i k per channel
// (microfacet.h wp_fresnel_conductor), times albedo (Mitsuba's / pbrt's specular_reflectance).
// Specular. The contract of wp_<name>_sample / wp_<name>_eval is in bsdf.h.
#ifndef WP_MATERIAL_CONDUCTOR_H
#define WP_MATERIAL_CONDUCTOR_H

#include "../microfacet.h"
#include "../sampling.h"
#include "../types.h"

// Compiled in unless KernelConfig says the scene has no conductor material.
#ifndef WP_HAVE_CONDUCTOR
#define WP_HAVE_CONDUCTOR 1
#endif

WP_NAMESPACE_BEGIN

WP_FN int wp_conductor_sample(MaterialData m, float3 d, float3 ns, int front, float4 u,
                              float3* wo, float3* weight, float* pdf, int* specular) {
    (void)front, (void)u;
    float cos_i = -dot(d, ns);
    if (!(cos_i > 0.0f)) return 0;
    *wo = wp_reflect(d, ns);
    *weight = wp_xyz(m.albedo) * wp_fresnel_conductor(cos_i, wp_xyz(m.eta), wp_xyz(m.k));
    *pdf = 0.0f;
    *specular = 1;
    return 1;
}

// A Dirac lobe: no finite f for any given direction.
WP_FN float3 wp_conductor_eval(MaterialData m, float3 d, float3 ns, float3 wi, float cos_i,
                               float* pdf) {
    (void)m, (void)d, (void)ns, (void)wi, (void)cos_i;
    *pdf = 0.0f;
    return make_float3(0.0f, 0.0f, 0.0f);
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_CONDUCTOR_H
