// bsdf.h — scattering at a surface for the materials of the original design.
//
// Each material draws an outgoing direction and returns its weight f * cos / pdf, the
// factor the path throughput is multiplied by:
//   * diffuse (Lambertian, f = albedo / π): sampling strategy WP_DIFFUSE_SAMPLING, now
//     WP_SAMPLING_UNIFORM (uniform over the hemisphere, pdf 1 / (2π), weight
//     2 albedo cos θ), as in the original renderer. Cosine sampling slots in here later.
//   * mirror: the exact reflection, weight albedo.
//   * glossy: the original "weighted" lobe: a normalised Phong lobe with the material's
//     exponent e around the mirror direction r (density (e + 1) / (2π) cos^e α, sampling.h)
//     whose weight is albedo; directions that fall below the surface are absorbed (the
//     lobe's energy there is lost, as in the original).
// Which kinds are compiled is set by WP_HAVE_DIFFUSE / _MIRROR / _GLOSSY (KernelConfig);
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

// Diffuse sampling strategies (the switch for cosine / MIS variants to come).
#define WP_SAMPLING_UNIFORM 0
#ifndef WP_DIFFUSE_SAMPLING
#define WP_DIFFUSE_SAMPLING WP_SAMPLING_UNIFORM
#endif

WP_NAMESPACE_BEGIN

// d: unit direction of the arriving ray (pointing at the surface); ns: unit geometric
// normal on the side the ray arrives from (dot(d, ns) <= 0); u: uniform numbers in [0, 1).
// Returns 1 and writes the unit outgoing direction and the weight f cos / pdf, or returns
// 0 when the path is absorbed.
WP_FN int wp_bsdf_sample(MaterialData m, float3 d, float3 ns, float4 u, float3* wo,
                         float3* weight) {
    float3 albedo = wp_xyz(m.albedo);
#if WP_HAVE_DIFFUSE
    if (m.kind == WP_MATERIAL_DIFFUSE) {
#if WP_DIFFUSE_SAMPLING == WP_SAMPLING_UNIFORM
        float3 lv = wp_sample_uniform_hemisphere(u.x, u.y);
        *wo = wp_to_world(lv, ns);
        // (albedo / π) cos θ / (1 / 2π)
        *weight = albedo * (2.0f * lv.z);
        return 1;
#else
#error "unknown WP_DIFFUSE_SAMPLING"
#endif
    }
#endif
#if WP_HAVE_MIRROR
    if (m.kind == WP_MATERIAL_MIRROR) {
        *wo = wp_reflect(d, ns);
        *weight = albedo;
        return 1;
    }
#endif
#if WP_HAVE_GLOSSY
    if (m.kind == WP_MATERIAL_GLOSSY) {
        float3 r = wp_reflect(d, ns);
        float3 lv = wp_sample_phong_lobe(u.x, u.y, m.albedo.w);
        float3 w = wp_to_world(lv, r);
        if (!(dot(w, ns) > 0.0f)) return 0;  // below the surface: absorbed
        *wo = w;
        *weight = albedo;
        return 1;
    }
#endif
    return 0;
}

WP_NAMESPACE_END

#endif  // WP_BSDF_H
