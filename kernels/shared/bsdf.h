// bsdf.h — scattering at a surface: sampling, evaluation and densities, dispatched over the
// material kinds of material_kinds.h.
//
// wp_bsdf_sample_pdf draws an outgoing direction and returns its weight f cos / pdf (the
// factor the path throughput is multiplied by), the density it was drawn with (solid angle)
// and whether the event is specular (a Dirac lobe, which light sampling cannot reach);
// wp_bsdf_eval returns f cos and that same density for a given direction, for next-event
// estimation and MIS weights (Veach & Guibas 1995).
//
// Each kind `name` of material_kinds.h has its file materials/<name>.h (included below)
// with the two functions this file calls:
//   int wp_<name>_sample(MaterialData m, float3 d, float3 ns, int front, float4 u,
//                        float3* wo, float3* weight, float* pdf, int* specular)
//     d: unit direction of the arriving ray (pointing at the surface); ns: unit geometric
//     normal on the side the ray arrives from (dot(d, ns) <= 0); front: the ray arrives at
//     the front face (for glass: from outside); u: uniform numbers in [0, 1); *specular is
//     0 on entry. Returns 1 and writes the unit outgoing direction, the weight, the density
//     (0 for specular events) and, for a Dirac event, *specular = 1; returns 0 when the
//     path is absorbed.
//   float3 wp_<name>_eval(MaterialData m, float3 d, float3 ns, float3 wi, float cos_i,
//                         float* pdf)
//     f cos θi for the unit direction wi with cos_i = dot(wi, ns) > 0, and in *pdf the
//     density with which wp_<name>_sample draws wi; zero and 0 for Dirac lobes.
// Which kinds are compiled is set by WP_HAVE_<KIND> (KernelConfig; each file defaults its
// own to 1); a material of a kind that is not compiled absorbs the path.
#ifndef WP_BSDF_H
#define WP_BSDF_H

#include "sampling.h"
#include "types.h"

// The strategy (WP_SAMPLING) and glossy model (WP_GLOSSY_MODEL): estimator.h, whose
// defaults are the shipped ones.
#include "estimator.h"
#ifndef WP_SAMPLING
#define WP_SAMPLING WP_DEFAULT_SAMPLING
#endif
#ifndef WP_GLOSSY_MODEL
#define WP_GLOSSY_MODEL WP_DEFAULT_GLOSSY_MODEL
#endif

#include "material_kinds.h"
#include "materials/diffuse.h"
#include "materials/mirror.h"
#include "materials/glossy.h"
#include "materials/glass.h"
#include "materials/conductor.h"
#include "materials/roughconductor.h"
#include "materials/roughdielectric.h"
#include "materials/thindielectric.h"
#include "materials/plastic.h"
#include "materials/roughplastic.h"

WP_NAMESPACE_BEGIN

// Whether every event of m's kind is a Dirac lobe (material_kinds.h SPECULAR): shade skips
// next-event estimation there. Unknown kinds: 0.
WP_FN int wp_material_is_specular(MaterialData m) {
#define WP_KIND_SPECULAR_(KIND, Kind, name, specular, alpha, ior, etak) \
    if (m.kind == WP_MATERIAL_##KIND) return specular;
    WP_MATERIAL_KINDS(WP_KIND_SPECULAR_)
#undef WP_KIND_SPECULAR_
    return 0;
}

// Draws an outgoing direction from m's kind (see the contract above); 0: absorbed.
WP_FN int wp_bsdf_sample_pdf(MaterialData m, float3 d, float3 ns, int front, float4 u,
                             float3* wo, float3* weight, float* pdf, int* specular) {
    *specular = 0;
#define WP_KIND_SAMPLE_(KIND, Kind, name, spec, alpha, ior, etak)                          \
    if (WP_HAVE_##KIND && m.kind == WP_MATERIAL_##KIND)                               \
        return wp_##name##_sample(m, d, ns, front, u, wo, weight, pdf, specular);
    WP_MATERIAL_KINDS(WP_KIND_SAMPLE_)
#undef WP_KIND_SAMPLE_
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
    float3 zero = make_float3(0.0f, 0.0f, 0.0f);
    float cos_i = dot(wi, ns);
    *pdf = 0.0f;
    if (!(cos_i > 0.0f)) return zero;
#define WP_KIND_EVAL_(KIND, Kind, name, spec, alpha, ior, etak) \
    if (WP_HAVE_##KIND && m.kind == WP_MATERIAL_##KIND) return wp_##name##_eval(m, d, ns, wi, cos_i, pdf);
    WP_MATERIAL_KINDS(WP_KIND_EVAL_)
#undef WP_KIND_EVAL_
    return zero;
}

WP_NAMESPACE_END

#endif  // WP_BSDF_H
