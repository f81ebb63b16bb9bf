// thindielectric.h — a thin dielectric slab (material_kinds.h: THIN_DIELECTRIC), Mitsuba 3's
// `thindielectric` and pbrt-v4's ThinDielectricBxDF: two parallel smooth interfaces of index
// η = m.ior with every internal reflection summed, so with F the dielectric Fresnel
// reflectance at |cos θ| (from outside, the same seen from either side),
//   R = F + T² F / (1 − F²)  (= 2F / (1 + F), T = 1 − F),   and the rest T_slab = 1 − R
// passes straight through (the two refractions cancel). Reflection is chosen with
// probability R, so the weight is m.specular (specular_reflectance) for the mirror
// direction and albedo (specular_transmittance) for the straight-through one; no η² factor:
// the ray leaves into the medium it came from. Both events are Dirac lobes.
// The contract of wp_<name>_sample / wp_<name>_eval is in bsdf.h.
#ifndef WP_MATERIAL_THINDIELECTRIC_H
#define WP_MATERIAL_THINDIELECTRIC_H

#include "../sampling.h"
#include "../types.h"
#include "glass.h"

// Compiled in unless KernelConfig says the scene has no thin dielectric.
#ifndef WP_HAVE_THIN_DIELECTRIC
#define WP_HAVE_THIN_DIELECTRIC 1
#endif

WP_NAMESPACE_BEGIN

// The slab's total reflectance R = 2F / (1 + F) at |cos θ| = cos_abs.
WP_FN float wp_thindielectric_reflectance(float cos_abs, float ior) {
    float cos_t;
    float f = wp_fresnel_dielectric(cos_abs, 1.0f / ior, &cos_t);
    return 2.0f * f / (1.0f + f);
}

WP_FN int wp_thindielectric_sample(MaterialData m, WP_GLOBAL const float* tables, float3 d,
                                   float3 ns, int front, float4 u, float3* wo, float3* weight,
                                   float* pdf, int* specular) {
    (void)tables, (void)front;
    float r = wp_thindielectric_reflectance(fabs(dot(d, ns)), m.ior);
    *specular = 1;
    *pdf = 0.0f;
    if (u.z < r) {
        *wo = wp_reflect(d, ns);
        *weight = wp_xyz(m.specular);
    } else {
        *wo = d;
        *weight = wp_xyz(m.albedo);
    }
    return 1;
}

// Dirac lobes only: no finite f for any given direction.
WP_FN float3 wp_thindielectric_eval(MaterialData m, WP_GLOBAL const float* tables, float3 d,
                                    float3 ns, int front, float3 wi, float cos_i, float* pdf) {
    (void)m, (void)tables, (void)d, (void)ns, (void)front, (void)wi, (void)cos_i;
    *pdf = 0.0f;
    return make_float3(0.0f, 0.0f, 0.0f);
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_THINDIELECTRIC_H
