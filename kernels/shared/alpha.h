// alpha.h — alpha cut-outs (glTF alphaMode MASK, MTL map_d): the test every traversal
// applies to a candidate hit when the scene has masked materials (WP_HAVE_ALPHA_MASK).
//
// A hit on a masked material counts only where its coverage, the alpha channel of its
// alpha texture (level 0, bilinear) times alpha_factor, is at least alpha_cutoff (glTF 2.0,
// "alpha coverage": fully opaque at or above the cutoff, fully transparent below). Camera,
// bounce and shadow rays apply the same test, so a leaf is see-through for all of them and
// the image does not depend on which traversal found the hit.
#ifndef WP_ALPHA_H
#define WP_ALPHA_H

#include "shading.h"
#include "texture.h"

WP_NAMESPACE_BEGIN

// What the alpha test reads (built inside the kernels from their arguments).
typedef struct AlphaScene {
    WP_GLOBAL const int* material_ids;                  // per triangle, scene order
    WP_GLOBAL const MaterialTextures* material_textures;  // per material
    WP_GLOBAL const TriUVs* uvs;                        // per triangle, scene order
    TexturePool pool;
} AlphaScene;

// 1 when the surface of triangle `prim` is there at barycentrics (u, v).
WP_FN int wp_alpha_pass(const AlphaScene* a, int prim, float u, float v) {
    MaterialTextures mt = a->material_textures[a->material_ids[prim]];
    if (!(mt.alpha_cutoff > 0.0f)) return 1;  // not masked
    float coverage = mt.alpha_factor;
    if (mt.alpha >= 0)
        coverage *= wp_texture_view(a->pool, mt.alpha, wp_interpolate_uv(a->uvs[prim], u, v), -FLT_MAX).w;
    return coverage >= mt.alpha_cutoff;
}

WP_NAMESPACE_END

#endif  // WP_ALPHA_H
