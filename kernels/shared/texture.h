// texture.h — PROVISIONAL (nearest texel of level 0) until the texture branch lands with the
// same functions: TexturePool, wp_texture_lookup, wp_texture_view.
#ifndef WP_TEXTURE_H
#define WP_TEXTURE_H

#include "types.h"

WP_NAMESPACE_BEGIN

typedef struct TexturePool {
    WP_GLOBAL const TextureData* textures;
    WP_GLOBAL const TextureView* views;
    WP_GLOBAL const uint* texels8;
    WP_GLOBAL const float4* texelsf;
} TexturePool;

WP_FN float4 wp_texture_lookup(TexturePool p, int t, float2 uv, float level) {
    (void)level;
    TextureData d = p.textures[t];
    float fu = uv.x - floor(uv.x), fv = uv.y - floor(uv.y);
    if (!isfinite(fu)) fu = 0.0f;
    if (!isfinite(fv)) fv = 0.0f;
    int x = min((int)(fu * (float)d.width), d.width - 1);
    int y = min((int)(fv * (float)d.height), d.height - 1);
    int i = d.offset + y * d.width + x;
    if (d.format == WP_TEXEL_FLOAT) return p.texelsf[i];
    uint c = p.texels8[i];
    float4 r = make_float4((float)(c & 255u) / 255.0f, (float)((c >> 8) & 255u) / 255.0f,
                           (float)((c >> 16) & 255u) / 255.0f, (float)(c >> 24) / 255.0f);
    if (d.format == WP_TEXEL_SRGB8) {
        r.x = pow(r.x, 2.2f);
        r.y = pow(r.y, 2.2f);
        r.z = pow(r.z, 2.2f);
    }
    return r;
}

WP_FN float4 wp_texture_view(TexturePool p, int view, float2 uv, float lod_uv) {
    TextureView v = p.views[view];
    float2 t = make_float2(v.u_row.x * uv.x + v.u_row.y * uv.y + v.u_row.z,
                           v.v_row.x * uv.x + v.v_row.y * uv.y + v.v_row.z);
    return wp_texture_lookup(p, v.texture, t, lod_uv);
}

WP_NAMESPACE_END

#endif  // WP_TEXTURE_H
