// test_lanes.cl — probe kernels for tests/test_lanes.cpp: each work-item runs a lane
// function of shared/lanes.h on eight lanes of inputs and the scalar function it mirrors
// on each lane, and writes both results as raw bits for the host to compare.
// Built with -D WP_GLOSSY_MODEL=0 or 1 (estimator.h) and -D WP_HAVE_GLOSSY=1
// -D WP_HAVE_MIRROR=1.
#include "shared/bsdf.h"
#include "shared/lights.h"
#include "shared/offset.h"
#include "shared/lanes.h"

// Lane l of item i reads in[(8 i + l) * NIN + k] into a[k][l].
#define WP_PROBE_READ(a, nin)                                   \
    for (int l = 0; l < 8; ++l)                                 \
        for (int k = 0; k < (nin); ++k) a[k][l] = in[(8 * i + l) * (nin) + k];

// probe_glossy8
// reads   per lane 16 floats: albedo xyz, alpha, d xyz (unit), ns xyz (unit), u1, u2,
//         wi xyz (unit), use_wo (> 0: evaluate at the scalar sample's wo where it scattered)
// writes  per lane 16 words to lane[] (lane functions) and scalar[] (scalar functions):
//         sample mask (-1 / 0), wo xyz, weight xyz, pdf, eval f xyz, eval pdf, reflect xyz,
//         0
WP_KERNEL void probe_glossy8(int n, WP_GLOBAL const float* in, WP_GLOBAL uint* lane,
                             WP_GLOBAL uint* scalar) {
    int i = wp_global_id();
    if (i >= n) return;
    float a[16][8];
    WP_PROBE_READ(a, 16)
    // Scalar functions per lane first (their wo may become the eval direction).
    uint sres[8][16];
    float wix[8], wiy[8], wiz[8];
    for (int l = 0; l < 8; ++l) {
        MaterialData m;
        m.albedo = make_float4(a[0][l], a[1][l], a[2][l], 0.0f);
        m.emission = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
        m.kind = WP_MATERIAL_GLOSSY;
        m.ior = 1.5f;
        m.alpha = a[3][l];
        m.alpha_v = a[3][l];
        m.specular = m.emission;
        m.eta = m.emission;
        m.k = m.emission;
        m.flags = 0;
        m.table = -1;
        m.aniso_cos = 0.0f;
        m.aniso_sin = 0.0f;
        float3 d = make_float3(a[4][l], a[5][l], a[6][l]);
        float3 ns = make_float3(a[7][l], a[8][l], a[9][l]);
        float4 u = make_float4(a[10][l], a[11][l], 0.5f, 0.5f);
        float3 wo = make_float3(0.0f, 0.0f, 0.0f), weight = wo;
        float pdf = 0.0f;
        int specular;
        int ok = wp_bsdf_sample_pdf(m, 0, d, ns, 1, u, &wo, &weight, &pdf, &specular);
        float3 wi = make_float3(a[12][l], a[13][l], a[14][l]);
        if (ok && a[15][l] > 0.0f) wi = wo;
        wix[l] = wi.x, wiy[l] = wi.y, wiz[l] = wi.z;
        float epdf;
        float3 f = wp_bsdf_eval(m, 0, d, ns, 1, wi, &epdf);
        MaterialData mm = m;
        mm.kind = WP_MATERIAL_MIRROR;
        float3 mwo, mweight;
        float mpdf;
        wp_bsdf_sample_pdf(mm, 0, d, ns, 1, u, &mwo, &mweight, &mpdf, &specular);
        float r[16] = {ok ? -1.0f : 0.0f, wo.x, wo.y, wo.z, weight.x, weight.y, weight.z, pdf,
                       f.x, f.y, f.z, epdf, mwo.x, mwo.y, mwo.z, 0.0f};
        for (int k = 0; k < 16; ++k) sres[l][k] = as_uint(r[k]);
        sres[l][0] = ok ? 0xffffffffu : 0u;
    }
    L3 albedo = l3(WP_LANES_F(a[0]), WP_LANES_F(a[1]), WP_LANES_F(a[2]));
    float8 alpha = WP_LANES_F(a[3]);
    L3 d = l3(WP_LANES_F(a[4]), WP_LANES_F(a[5]), WP_LANES_F(a[6]));
    L3 ns = l3(WP_LANES_F(a[7]), WP_LANES_F(a[8]), WP_LANES_F(a[9]));
    float8 u1 = WP_LANES_F(a[10]), u2 = WP_LANES_F(a[11]);
    L3 wo, weight;
    float8 pdf;
    int8 ok = wp_glossy_sample8(albedo, alpha, d, ns, u1, u2, &wo, &weight, &pdf);
    L3 wi = l3(WP_LANES_F(wix), WP_LANES_F(wiy), WP_LANES_F(wiz));
    float8 epdf;
    L3 f = wp_glossy_eval8(albedo, alpha, d, ns, wi, l3_dot(wi, ns), &epdf);
    L3 mwo = wp_reflect8(d, ns);
    float8 res[16] = {as_float8(ok), wo.x, wo.y, wo.z, weight.x, weight.y, weight.z, pdf,
                      f.x, f.y, f.z, epdf, mwo.x, mwo.y, mwo.z, (float8)(0.0f)};
    for (int k = 0; k < 16; ++k) {
        uint b[8];
        vstore8(as_uint8(res[k]), 0, b);
        for (int l = 0; l < 8; ++l) {
            lane[(8 * i + l) * 16 + k] = b[l];
            scalar[(8 * i + l) * 16 + k] = sres[l][k];
        }
    }
}

// probe_math8: the builtins the lane code spells out, against the scalar ones.
// reads   per lane 4 floats: v xyz, y
// writes  per lane 8 words to lane[] and scalar[]: normalize(v) xyz (lane: l3_normalize),
//         pow(|v.x|, y) (lane: pow(float8) in word 3, wp_pow8 in word 4), cross(v, (y, v.z,
//         v.x)) xyz
WP_KERNEL void probe_math8(int n, WP_GLOBAL const float* in, WP_GLOBAL uint* lane,
                           WP_GLOBAL uint* scalar) {
    int i = wp_global_id();
    if (i >= n) return;
    float a[4][8];
    WP_PROBE_READ(a, 4)
    for (int l = 0; l < 8; ++l) {
        float3 v = make_float3(a[0][l], a[1][l], a[2][l]);
        float3 nv = normalize(v);
        float p = pow(fabs(v.x), a[3][l]);
        float3 c = cross(v, make_float3(a[3][l], v.z, v.x));
        float r[8] = {nv.x, nv.y, nv.z, p, p, c.x, c.y, c.z};
        for (int k = 0; k < 8; ++k) scalar[(8 * i + l) * 8 + k] = as_uint(r[k]);
    }
    L3 v = l3(WP_LANES_F(a[0]), WP_LANES_F(a[1]), WP_LANES_F(a[2]));
    float8 y = WP_LANES_F(a[3]);
    L3 nv = l3_normalize(v);
    L3 c = l3_cross(v, l3(y, v.z, v.x));
    float8 res[8] = {nv.x, nv.y, nv.z, pow(fabs(v.x), y), wp_pow8(fabs(v.x), y), c.x, c.y, c.z};
    for (int k = 0; k < 8; ++k) {
        uint b[8];
        vstore8(as_uint8(res[k]), 0, b);
        for (int l = 0; l < 8; ++l) lane[(8 * i + l) * 8 + k] = b[l];
    }
}
