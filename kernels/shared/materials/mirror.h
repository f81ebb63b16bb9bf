// mirror.h — perfect specular reflection tinted by albedo (material_kinds.h: MIRROR).
// The contract of wp_<name>_sample / wp_<name>_eval is in bsdf.h.
#ifndef WP_MATERIAL_MIRROR_H
#define WP_MATERIAL_MIRROR_H

#include "../sampling.h"
#include "../types.h"

// Compiled in unless KernelConfig says the scene has no mirror material.
#ifndef WP_HAVE_MIRROR
#define WP_HAVE_MIRROR 1
#endif

WP_NAMESPACE_BEGIN

WP_FN int wp_mirror_sample(MaterialData m, WP_GLOBAL const float* tables, float3 d, float3 ns,
                           int front, float4 u, float3* wo, float3* weight, float* pdf, int* specular) {
    (void)tables, (void)front, (void)u;
    *wo = wp_reflect(d, ns);
    *weight = wp_xyz(m.albedo);
    *pdf = 0.0f;
    *specular = 1;
    return 1;
}

// A Dirac lobe: no finite f for any given direction.
WP_FN float3 wp_mirror_eval(MaterialData m, WP_GLOBAL const float* tables, float3 d, float3 ns,
                            int front, float3 wi, float cos_i, float* pdf) {
    (void)m, (void)tables, (void)d, (void)ns, (void)front, (void)wi, (void)cos_i;
    *pdf = 0.0f;
    return make_float3(0.0f, 0.0f, 0.0f);
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_MIRROR_H
