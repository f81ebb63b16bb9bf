// plastic.h — IN PROGRESS (issue 14): the model of material_kinds.h's PLASTIC line is being written;
// until then this kind absorbs every path. The contract is in bsdf.h.
#ifndef WP_MATERIAL_PLASTIC_H
#define WP_MATERIAL_PLASTIC_H

#include "../microfacet.h"
#include "../sampling.h"
#include "../types.h"

#ifndef WP_HAVE_PLASTIC
#define WP_HAVE_PLASTIC 1
#endif

WP_NAMESPACE_BEGIN

WP_FN int wp_plastic_sample(MaterialData m, float3 d, float3 ns, int front, float4 u,
                         float3* wo, float3* weight, float* pdf, int* specular) {
    (void)m, (void)d, (void)ns, (void)front, (void)u, (void)wo, (void)weight, (void)pdf, (void)specular;
    return 0;
}

WP_FN float3 wp_plastic_eval(MaterialData m, float3 d, float3 ns, float3 wi, float cos_i, float* pdf) {
    (void)m, (void)d, (void)ns, (void)wi, (void)cos_i;
    *pdf = 0.0f;
    return make_float3(0.0f, 0.0f, 0.0f);
}

WP_NAMESPACE_END

#endif  // WP_MATERIAL_PLASTIC_H
