// aov.h — the feature buffers (AOVs: albedo, shading normal, depth) of a sample and of a
// film pixel, shared by kernels/aov.cl and the host (render/aov.h).
//
// Per sample (item of a wave), two float4 rows, written by aov_record:
//   aov[2 item]     = (albedo r, g, b, distance from the camera along the path so far)
//   aov[2 item + 1] = (shading normal x, y, z, state)
// state: WP_AOV_MISS (the path left the scene before a non-specular hit: albedo and normal
// 0), WP_AOV_HIT (the first non-specular hit is recorded: final), WP_AOV_SPECULAR (the
// latest hit is a specular surface — every event a Dirac lobe, wp_aov_specular_kind — and
// the path may go on: the next bounce overwrites the albedo and normal and adds its
// segment to the distance; a path that ends there keeps the specular surface's values).
// Per film pixel, two float4 rows of float sums over its samples, added in sample order by
// aov_accumulate:
//   film[2 p]     = (Σ albedo r, g, b, Σ depth over the samples that hit)
//   film[2 p + 1] = (Σ normal x, y, z, number of samples that hit)
// The host divides albedo and normal by the pixel's sample count (misses count as 0) and
// the depth by the number of hits (+inf where no sample hit): render/aov.cpp.
#ifndef WP_AOV_H
#define WP_AOV_H

#include "material_kinds.h"
#include "types.h"

WP_NAMESPACE_BEGIN

#define WP_AOV_MISS 0.0f
#define WP_AOV_HIT 1.0f
#define WP_AOV_SPECULAR 2.0f

// 1 when every event of the kind is a Dirac lobe (material_kinds.h SPECULAR): the AOVs
// look through it to the next surface, as the colour does.
WP_FN int wp_aov_specular_kind(int kind) {
#define WP_AOV_KIND_SPECULAR_(KIND, Kind, name, specular, alpha, ior, etak) \
    if (kind == WP_MATERIAL_##KIND) return specular;
    WP_MATERIAL_KINDS(WP_AOV_KIND_SPECULAR_)
#undef WP_AOV_KIND_SPECULAR_
    return 0;
}

WP_NAMESPACE_END

#endif  // WP_AOV_H
