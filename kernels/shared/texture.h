// texture.h — image texture lookups on the device: repeat-wrapped, bilinear per mip level,
// trilinear between levels, the level chosen from a ray footprint.
//
// The textures live in two pools (built on the host by scene/texture.h upload_textures):
// 8-bit RGBA texels packed one per uint (R in the low byte) and float4 texels. Each
// TextureData (types.h) names its pool by format, its first texel and its mip chain: level
// l is max(1, w >> l) x max(1, h >> l) texels, rows from the top, right after level l - 1.
// Buffers, not OpenCL image objects, so the same code runs on CUDA and on the host.
//
// Conventions: uv (0, 0) is the image's top-left corner, u right, v down (scene.h
// TextureRef); both directions repeat; texel (i, j) of a w x h level has its centre at
// ((i + 0.5) / w, (j + 0.5) / h). Results are linear RGBA: sRGB8 texels are decoded
// (RGB by the exact IEC 61966-2-1 curve, alpha as stored) before any filtering.
//
// Level selection (wp_texture_view): ray cones (Akenine-Möller et al., "Texture Level of
// Detail Strategies for Real-Time Ray Tracing", Ray Tracing Gems 2019, ch. 20, and
// "Improved Shader and Texture Level of Detail Using Ray Cones", JCGT 10(1), 2021): the
// caller gives the footprint's width in uv units as lod_uv = log2(width); the level is
// lod_uv + 0.5 log2(W H |det A|), A the 2x2 part of the view's uv map, W x H level 0.
#ifndef WP_TEXTURE_H
#define WP_TEXTURE_H

#include "types.h"

WP_NAMESPACE_BEGIN

#if defined(WP_HOST)
using std::log2;
#endif

// The device buffers of every texture of a scene (render/device_scene binds them).
typedef struct TexturePool {
    WP_GLOBAL const TextureData* textures;  // one per image, scene order
    WP_GLOBAL const TextureView* views;     // one per material slot that uses an image
    WP_GLOBAL const uint* texels8;          // WP_TEXEL_SRGB8 / _LINEAR8 texels
    WP_GLOBAL const float4* texelsf;        // WP_TEXEL_FLOAT texels
} TexturePool;

// wp_srgb8_to_linear[c] = srgb_decode(c / 255) (image.h, IEC 61966-2-1) evaluated in double
// and rounded to float: exact, and no pow() per texel. A program-scope constant (like
// sobol.h's table), so it needs no buffer of its own. tests/test_texture.cpp checks every
// entry against srgb_decode.
WP_CONSTANT_TABLE float wp_srgb8_to_linear[256] = {
    0.000000000e+00f, 3.035269910e-04f, 6.070539821e-04f, 9.105809731e-04f,
    1.214107964e-03f, 1.517634955e-03f, 1.821161946e-03f, 2.124688821e-03f,
    2.428215928e-03f, 2.731742803e-03f, 3.035269910e-03f, 3.346535843e-03f,
    3.676507389e-03f, 4.024717025e-03f, 4.391442053e-03f, 4.776953254e-03f,
    5.181516521e-03f, 5.605391692e-03f, 6.048833020e-03f, 6.512090564e-03f,
    6.995410193e-03f, 7.499032188e-03f, 8.023193106e-03f, 8.568125777e-03f,
    9.134058841e-03f, 9.721217677e-03f, 1.032982301e-02f, 1.096009370e-02f,
    1.161224488e-02f, 1.228648797e-02f, 1.298303250e-02f, 1.370208338e-02f,
    1.444384363e-02f, 1.520851441e-02f, 1.599629410e-02f, 1.680737548e-02f,
    1.764195412e-02f, 1.850022003e-02f, 1.938236132e-02f, 2.028856240e-02f,
    2.121900953e-02f, 2.217388526e-02f, 2.315336652e-02f, 2.415763214e-02f,
    2.518685907e-02f, 2.624122240e-02f, 2.732089162e-02f, 2.842603996e-02f,
    2.955683507e-02f, 3.071344458e-02f, 3.189603239e-02f, 3.310476616e-02f,
    3.433980793e-02f, 3.560131416e-02f, 3.688944876e-02f, 3.820437193e-02f,
    3.954623640e-02f, 4.091519862e-02f, 4.231141135e-02f, 4.373503104e-02f,
    4.518620297e-02f, 4.666508734e-02f, 4.817182571e-02f, 4.970656708e-02f,
    5.126945674e-02f, 5.286064744e-02f, 5.448027700e-02f, 5.612849072e-02f,
    5.780543014e-02f, 5.951123685e-02f, 6.124605238e-02f, 6.301001459e-02f,
    6.480326504e-02f, 6.662593782e-02f, 6.847816706e-02f, 7.036009431e-02f,
    7.227185369e-02f, 7.421357185e-02f, 7.618538290e-02f, 7.818742096e-02f,
    8.021982014e-02f, 8.228270710e-02f, 8.437620848e-02f, 8.650045842e-02f,
    8.865558356e-02f, 9.084171057e-02f, 9.305896610e-02f, 9.530746937e-02f,
    9.758734703e-02f, 9.989872575e-02f, 1.022417322e-01f, 1.046164855e-01f,
    1.070231050e-01f, 1.094617099e-01f, 1.119324267e-01f, 1.144353747e-01f,
    1.169706658e-01f, 1.195384264e-01f, 1.221387759e-01f, 1.247718185e-01f,
    1.274376810e-01f, 1.301364750e-01f, 1.328683197e-01f, 1.356333345e-01f,
    1.384316087e-01f, 1.412632912e-01f, 1.441284716e-01f, 1.470272690e-01f,
    1.499597877e-01f, 1.529261470e-01f, 1.559264660e-01f, 1.589608341e-01f,
    1.620293707e-01f, 1.651321948e-01f, 1.682693958e-01f, 1.714411080e-01f,
    1.746474057e-01f, 1.778884232e-01f, 1.811642498e-01f, 1.844749898e-01f,
    1.878207773e-01f, 1.912016869e-01f, 1.946178377e-01f, 1.980693191e-01f,
    2.015562505e-01f, 2.050787359e-01f, 2.086368650e-01f, 2.122307569e-01f,
    2.158605009e-01f, 2.195262015e-01f, 2.232279629e-01f, 2.269658744e-01f,
    2.307400554e-01f, 2.345505804e-01f, 2.383975685e-01f, 2.422811240e-01f,
    2.462013215e-01f, 2.501582801e-01f, 2.541520894e-01f, 2.581828535e-01f,
    2.622506618e-01f, 2.663556039e-01f, 2.704977989e-01f, 2.746773064e-01f,
    2.788942754e-01f, 2.831487358e-01f, 2.874408364e-01f, 2.917706370e-01f,
    2.961382568e-01f, 3.005437851e-01f, 3.049873114e-01f, 3.094689250e-01f,
    3.139887154e-01f, 3.185467720e-01f, 3.231432140e-01f, 3.277781010e-01f,
    3.324515224e-01f, 3.371636271e-01f, 3.419144154e-01f, 3.467040658e-01f,
    3.515326083e-01f, 3.564001322e-01f, 3.613067865e-01f, 3.662526011e-01f,
    3.712376952e-01f, 3.762621284e-01f, 3.813260198e-01f, 3.864294291e-01f,
    3.915724754e-01f, 3.967552185e-01f, 4.019777775e-01f, 4.072402120e-01f,
    4.125426114e-01f, 4.178850651e-01f, 4.232676625e-01f, 4.286904931e-01f,
    4.341536462e-01f, 4.396571815e-01f, 4.452011883e-01f, 4.507857859e-01f,
    4.564110339e-01f, 4.620769918e-01f, 4.677838087e-01f, 4.735314846e-01f,
    4.793201685e-01f, 4.851499498e-01f, 4.910208583e-01f, 4.969329834e-01f,
    5.028864741e-01f, 5.088813305e-01f, 5.149176717e-01f, 5.209955573e-01f,
    5.271151066e-01f, 5.332763791e-01f, 5.394794941e-01f, 5.457244515e-01f,
    5.520114303e-01f, 5.583403707e-01f, 5.647115111e-01f, 5.711248517e-01f,
    5.775804520e-01f, 5.840784311e-01f, 5.906188488e-01f, 5.972017646e-01f,
    6.038273573e-01f, 6.104955673e-01f, 6.172065735e-01f, 6.239603758e-01f,
    6.307571530e-01f, 6.375968456e-01f, 6.444796920e-01f, 6.514056325e-01f,
    6.583748460e-01f, 6.653872728e-01f, 6.724431515e-01f, 6.795424819e-01f,
    6.866853237e-01f, 6.938717365e-01f, 7.011018991e-01f, 7.083757520e-01f,
    7.156934738e-01f, 7.230551243e-01f, 7.304607630e-01f, 7.379103899e-01f,
    7.454041839e-01f, 7.529422045e-01f, 7.605245113e-01f, 7.681511641e-01f,
    7.758222222e-01f, 7.835378051e-01f, 7.912979126e-01f, 7.991027236e-01f,
    8.069522381e-01f, 8.148465753e-01f, 8.227857351e-01f, 8.307698965e-01f,
    8.387989998e-01f, 8.468732238e-01f, 8.549926281e-01f, 8.631572127e-01f,
    8.713670969e-01f, 8.796223998e-01f, 8.879231215e-01f, 8.962693810e-01f,
    9.046611786e-01f, 9.130986333e-01f, 9.215818644e-01f, 9.301108718e-01f,
    9.386857152e-01f, 9.473065138e-01f, 9.559733272e-01f, 9.646862745e-01f,
    9.734452963e-01f, 9.822505713e-01f, 9.911020994e-01f, 1.000000000e+00f,
};

// Texel `index` of a pool as linear RGBA.
WP_FN float4 wp_texel_fetch(TexturePool p, int format, int index) {
    if (format == WP_TEXEL_FLOAT) return p.texelsf[index];
    uint c = p.texels8[index];
    uint r = c & 255u, g = (c >> 8) & 255u, b = (c >> 16) & 255u, a = c >> 24;
    float alpha = (float)a / 255.0f;  // alpha is linear in every 8-bit format
    if (format == WP_TEXEL_SRGB8)
        return make_float4(wp_srgb8_to_linear[r], wp_srgb8_to_linear[g], wp_srgb8_to_linear[b], alpha);
    return make_float4((float)r / 255.0f, (float)g / 255.0f, (float)b / 255.0f, alpha);
}

// Bilinear lookup in level `level` of d at wrapped (u, v) in [0, 1]: the four texels
// around (u w - 0.5, v h - 0.5), neighbours across the border taken from the other side.
WP_FN float4 wp_texture_bilinear(TexturePool p, TextureData d, int level, float u, float v) {
    int w = d.width, h = d.height, first = d.offset;
    for (int l = 0; l < level; ++l) {
        first += w * h;
        w = max(1, w >> 1);
        h = max(1, h >> 1);
    }
    float x = u * (float)w - 0.5f, y = v * (float)h - 0.5f;  // in [-0.5, side - 0.5]
    float x0f = floor(x), y0f = floor(y);
    float fx = x - x0f, fy = y - y0f;
    int x0 = (int)x0f, y0 = (int)y0f;  // in [-1, side - 1]
    int x1 = x0 + 1, y1 = y0 + 1;      // in [0, side]
    if (x0 < 0) x0 += w;
    if (y0 < 0) y0 += h;
    if (x1 >= w) x1 -= w;
    if (y1 >= h) y1 -= h;
    float4 t00 = wp_texel_fetch(p, d.format, first + y0 * w + x0);
    float4 t10 = wp_texel_fetch(p, d.format, first + y0 * w + x1);
    float4 t01 = wp_texel_fetch(p, d.format, first + y1 * w + x0);
    float4 t11 = wp_texel_fetch(p, d.format, first + y1 * w + x1);
    float4 top = t00 + (t10 - t00) * fx;
    float4 bottom = t01 + (t11 - t01) * fx;
    return top + (bottom - top) * fy;
}

// Linear RGBA of texture t at uv, filtered at mip level `level` (fractional: trilinear
// between floor(level) and the next; clamped to [0, levels - 1]; NaN: 0). uv repeats in
// both directions; NaN or infinite coordinates are taken as 0. Nearest textures return the
// texel of level 0 that contains uv, whatever the level.
WP_FN float4 wp_texture_lookup(TexturePool p, int t, float2 uv, float level) {
    TextureData d = p.textures[t];
    float u = uv.x, v = uv.y;
    if (!isfinite(u)) u = 0.0f;
    if (!isfinite(v)) v = 0.0f;
    u = u - floor(u);  // [0, 1]: 1 only when a tiny negative u rounds up
    v = v - floor(v);
    if (d.nearest) {
        int i = min((int)(u * (float)d.width), d.width - 1);
        int j = min((int)(v * (float)d.height), d.height - 1);
        return wp_texel_fetch(p, d.format, d.offset + j * d.width + i);
    }
    float top = (float)(d.levels - 1);
    if (!(level > 0.0f)) level = 0.0f;  // also NaN
    if (level > top) level = top;
    float l0f = floor(level);
    int l0 = (int)l0f;
    float f = level - l0f;
    float4 a = wp_texture_bilinear(p, d, l0, u, v);
    if (f > 0.0f && l0 + 1 < d.levels) {
        float4 b = wp_texture_bilinear(p, d, l0 + 1, u, v);
        a = a + (b - a) * f;
    }
    return a;
}

// The mip level a view's texture is read at for a footprint of width 2^lod_uv in the
// surface's uv units: lod_uv + 0.5 log2(W H |det|), det of the view's 2x2 uv map, W x H
// level 0. -FLT_MAX (or any very negative lod_uv) gives a negative level, i.e. level 0.
WP_FN float wp_texture_view_level(TexturePool p, int view, float lod_uv) {
    TextureView tv = p.views[view];
    TextureData d = p.textures[tv.texture];
    float det = tv.u_row.x * tv.v_row.y - tv.u_row.y * tv.v_row.x;
    float area = (float)d.width * (float)d.height * fabs(det);  // texels per unit uv area
    return lod_uv + 0.5f * log2(area);  // area 0: -inf, i.e. level 0
}

// A material's texture (TextureView `view`) at the surface's uv: the view's affine map
// uv' = (u_row . (u, v, 1), v_row . (u, v, 1)), then wp_texture_lookup at the level of
// wp_texture_view_level.
WP_FN float4 wp_texture_view(TexturePool p, int view, float2 uv, float lod_uv) {
    TextureView tv = p.views[view];
    float u = tv.u_row.x * uv.x + tv.u_row.y * uv.y + tv.u_row.z;
    float v = tv.v_row.x * uv.x + tv.v_row.y * uv.y + tv.v_row.z;
    return wp_texture_lookup(p, tv.texture, make_float2(u, v), wp_texture_view_level(p, view, lod_uv));
}

WP_NAMESPACE_END

#endif  // WP_TEXTURE_H
