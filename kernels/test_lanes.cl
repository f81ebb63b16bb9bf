// test_lanes.cl — probe kernels for tests/test_lanes.cpp: each work-item runs a lane
// function of shared/lanes.h on eight lanes of inputs and the scalar function it mirrors
// on each lane, and writes both results as raw bits for the host to compare.
// Built with -D WP_GLOSSY_MODEL=0 or 1 (estimator.h) and -D WP_HAVE_GLOSSY=1
// -D WP_HAVE_MIRROR=1. The lane functions are OpenCL-only; under CUDA and the host C++
// build the probes copy the scalar results into lane[].
#include "shared/bsdf.h"
#include "shared/lights.h"
#include "shared/offset.h"
#include "shared/lanes.h"

// Lane l of item i reads in[(8 i + l) * NIN + k] into a[k][l].
#define WP_PROBE_READ(a, nin)                                   \
    for (int l = 0; l < 8; ++l)                                 \
        for (int k = 0; k < (nin); ++k) a[k][l] = in[(8 * i + l) * (nin) + k];

// An isotropic material of `kind` with albedo a[0..2][l] and width a[3][l] for lane l, every
// other field neutral (η 0, k 0, no flags, no table).
WP_FN MaterialData wp_probe_material(int kind, float a[][8], int l) {
    MaterialData m;
    m.albedo = make_float4(a[0][l], a[1][l], a[2][l], 0.0f);
    m.emission = make_float4(0.0f, 0.0f, 0.0f, 0.0f);
    m.kind = kind;
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
    return m;
}

// Lane l's scalar sample (wp_bsdf_sample_pdf) and eval (wp_bsdf_eval, at the sample's wo
// where use_wo > 0 and it scattered, else at wi) of m: r[0] the sample mask (-1 / 0 as
// bits), r[1..7] wo, weight, pdf, r[8..11] f cos and the eval's pdf; *wi_out the eval's
// direction. a[4..15][l]: d, ns, u1, u2, wi, use_wo as probe_glossy8 reads them.
WP_FN void wp_probe_scalar_bsdf(MaterialData m, float a[][8], int l, uint* r, float3* wi_out) {
    float3 d = make_float3(a[4][l], a[5][l], a[6][l]);
    float3 ns = make_float3(a[7][l], a[8][l], a[9][l]);
    float4 u = make_float4(a[10][l], a[11][l], 0.5f, 0.5f);
    float3 wo = make_float3(0.0f, 0.0f, 0.0f), weight = wo;
    float pdf = 0.0f;
    int specular;
    int ok = wp_bsdf_sample_pdf(m, 0, d, ns, 1, u, &wo, &weight, &pdf, &specular);
    float3 wi = make_float3(a[12][l], a[13][l], a[14][l]);
    if (ok && a[15][l] > 0.0f) wi = wo;
    *wi_out = wi;
    float epdf;
    float3 f = wp_bsdf_eval(m, 0, d, ns, 1, wi, &epdf);
    float v[12] = {0.0f, wo.x, wo.y, wo.z, weight.x, weight.y, weight.z, pdf, f.x, f.y, f.z, epdf};
    for (int k = 0; k < 12; ++k) r[k] = as_uint(v[k]);
    r[0] = ok ? 0xffffffffu : 0u;
}

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
        MaterialData m = wp_probe_material(WP_MATERIAL_GLOSSY, a, l);
        float3 wi;
        wp_probe_scalar_bsdf(m, a, l, sres[l], &wi);
        wix[l] = wi.x, wiy[l] = wi.y, wiz[l] = wi.z;
        float3 d = make_float3(a[4][l], a[5][l], a[6][l]);
        float3 ns = make_float3(a[7][l], a[8][l], a[9][l]);
        float4 u = make_float4(a[10][l], a[11][l], 0.5f, 0.5f);
        int specular;
        MaterialData mm = m;
        mm.kind = WP_MATERIAL_MIRROR;
        float3 mwo, mweight;
        float mpdf;
        wp_bsdf_sample_pdf(mm, 0, d, ns, 1, u, &mwo, &mweight, &mpdf, &specular);
        float r[4] = {mwo.x, mwo.y, mwo.z, 0.0f};  // words 12..15 after the scalar BSDF's 12
        for (int k = 0; k < 4; ++k) sres[l][12 + k] = as_uint(r[k]);
    }
#if defined(WP_OPENCL)
    L3 albedo = l3(vload8(0, a[0]), vload8(0, a[1]), vload8(0, a[2]));
    float8 alpha = vload8(0, a[3]);
    L3 d = l3(vload8(0, a[4]), vload8(0, a[5]), vload8(0, a[6]));
    L3 ns = l3(vload8(0, a[7]), vload8(0, a[8]), vload8(0, a[9]));
    float8 u1 = vload8(0, a[10]), u2 = vload8(0, a[11]);
    L3 wo, weight;
    float8 pdf;
    int8 ok = wp_glossy_sample8(albedo, alpha, d, ns, u1, u2, &wo, &weight, &pdf);
    L3 wi = l3(vload8(0, wix), vload8(0, wiy), vload8(0, wiz));
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
#else
    for (int l = 0; l < 8; ++l)
        for (int k = 0; k < 16; ++k)
            lane[(8 * i + l) * 16 + k] = scalar[(8 * i + l) * 16 + k] = sres[l][k];
#endif
}

// probe_math8: the builtins the lane code spells out, against the scalar ones.
// reads   per lane 4 floats: v xyz, y
// writes  per lane 8 words to lane[] and scalar[]: normalize(v) xyz (lane: l3_normalize),
//         word 3 wp_pow(|v.x|, y) (lane: wp_pow8), word 4 the builtin pow(|v.x|, y) (lane:
//         the scalar wp_pow, to compare with the host's wp_pow and the builtin), cross(v, (y,
//         v.z, v.x)) xyz
WP_KERNEL void probe_math8(int n, WP_GLOBAL const float* in, WP_GLOBAL uint* lane,
                           WP_GLOBAL uint* scalar) {
    int i = wp_global_id();
    if (i >= n) return;
    float a[4][8];
    WP_PROBE_READ(a, 4)
    for (int l = 0; l < 8; ++l) {
        float3 v = make_float3(a[0][l], a[1][l], a[2][l]);
        float3 nv = normalize(v);
        float p = wp_pow(fabs(v.x), a[3][l]);
        float3 c = cross(v, make_float3(a[3][l], v.z, v.x));
        float r[8] = {nv.x, nv.y, nv.z, p, pow(fabs(v.x), a[3][l]), c.x, c.y, c.z};
        for (int k = 0; k < 8; ++k) scalar[(8 * i + l) * 8 + k] = as_uint(r[k]);
    }
#if defined(WP_OPENCL)
    L3 v = l3(vload8(0, a[0]), vload8(0, a[1]), vload8(0, a[2]));
    float8 y = vload8(0, a[3]);
    L3 nv = l3_normalize(v);
    L3 c = l3_cross(v, l3(y, v.z, v.x));
    float8 res[8] = {nv.x, nv.y, nv.z, wp_pow8(fabs(v.x), y), (float8)(0.0f), c.x, c.y, c.z};
    for (int k = 0; k < 8; ++k) {
        uint b[8];
        vstore8(as_uint8(res[k]), 0, b);
        for (int l = 0; l < 8; ++l) lane[(8 * i + l) * 8 + k] = b[l];
    }
    for (int l = 0; l < 8; ++l) lane[(8 * i + l) * 8 + 4] = as_uint(wp_pow(fabs(a[0][l]), a[3][l]));
#else
    for (int j = 8 * 8 * i; j < 8 * 8 * (i + 1); ++j) lane[j] = scalar[j];
#endif
}

// probe_misc8: the other lane functions of lanes.h against their scalar twins.
// reads   per lane 16 floats: a xyz, b xyz, c xyz, n xyz (unit), u, v, s, t
// writes  per lane 32 words to lane[] and scalar[]: sincos_2pi(u) (2), to_world(a, n) (3),
//         to_local(a, n) (3), cosine hemisphere(u, v) (3), uniform hemisphere(u, v) (3),
//         cosine pdf(n.z), hit point p of triangle (a, b, c) at (u, v) (3) and its err (3),
//         offset_ray_origin(p, err, n, s) (3), shadow_tmax(b - p, err, n, s),
//         power_heuristic(s, t), light_pdf_solid_angle(s, t, n.z),
//         shadow_end_clear(that tmax, b - p, c, err, t), 0 (3)
WP_KERNEL void probe_misc8(int n, WP_GLOBAL const float* in, WP_GLOBAL uint* lane,
                           WP_GLOBAL uint* scalar) {
    int i = wp_global_id();
    if (i >= n) return;
    float a[16][8];
    WP_PROBE_READ(a, 16)
    for (int l = 0; l < 8; ++l) {
        float3 va = make_float3(a[0][l], a[1][l], a[2][l]);
        float3 vb = make_float3(a[3][l], a[4][l], a[5][l]);
        float3 vc = make_float3(a[6][l], a[7][l], a[8][l]);
        float3 nn = make_float3(a[9][l], a[10][l], a[11][l]);
        float u = a[12][l], v = a[13][l], s = a[14][l], t = a[15][l];
        float r[32];
        wp_sincos_2pi(u, &r[0], &r[1]);
        float3 w = wp_to_world(va, nn), lo = wp_to_local(va, nn);
        float3 ch = wp_sample_cosine_hemisphere(u, v), uh = wp_sample_uniform_hemisphere(u, v);
        float3 err, p = wp_hit_point(va, vb, vc, u, v, &err);
        float3 o = wp_offset_ray_origin(p, err, nn, s);
        float f[] = {w.x, w.y, w.z, lo.x, lo.y, lo.z, ch.x, ch.y, ch.z, uh.x, uh.y, uh.z,
                     wp_cosine_hemisphere_pdf(nn.z), p.x, p.y, p.z, err.x, err.y, err.z,
                     o.x, o.y, o.z, wp_shadow_tmax(vb - p, err, nn, s),
                     wp_power_heuristic(s, t), wp_light_pdf_solid_angle(s, t, nn.z),
                     wp_shadow_end_clear(wp_shadow_tmax(vb - p, err, nn, s), vb - p, vc, err, nn, t),
                     0.0f, 0.0f, 0.0f, 0.0f};
        for (int k = 2; k < 32; ++k) r[k] = f[k - 2];
        for (int k = 0; k < 32; ++k) scalar[(8 * i + l) * 32 + k] = as_uint(r[k]);
    }
#if defined(WP_OPENCL)
    L3 va = l3(vload8(0, a[0]), vload8(0, a[1]), vload8(0, a[2]));
    L3 vb = l3(vload8(0, a[3]), vload8(0, a[4]), vload8(0, a[5]));
    L3 vc = l3(vload8(0, a[6]), vload8(0, a[7]), vload8(0, a[8]));
    L3 nn = l3(vload8(0, a[9]), vload8(0, a[10]), vload8(0, a[11]));
    float8 u = vload8(0, a[12]), v = vload8(0, a[13]), s = vload8(0, a[14]), t = vload8(0, a[15]);
    float8 r[32];
    wp_sincos_2pi8(u, &r[0], &r[1]);
    L3 w = wp_to_world8(va, nn), lo = wp_to_local8(va, nn);
    L3 ch = wp_sample_cosine_hemisphere8(u, v), uh = wp_sample_uniform_hemisphere8(u, v);
    L3 err, p = wp_hit_point8(va, vb, vc, u, v, &err);
    L3 o = wp_offset_ray_origin8(p, err, nn, s);
    float8 f[] = {w.x, w.y, w.z, lo.x, lo.y, lo.z, ch.x, ch.y, ch.z, uh.x, uh.y, uh.z,
                  wp_cosine_hemisphere_pdf8(nn.z), p.x, p.y, p.z, err.x, err.y, err.z,
                  o.x, o.y, o.z, wp_shadow_tmax8(l3_sub(vb, p), err, nn, s),
                  wp_power_heuristic8(s, t), wp_light_pdf_solid_angle8(s, t, nn.z),
                  wp_shadow_end_clear8(wp_shadow_tmax8(l3_sub(vb, p), err, nn, s), l3_sub(vb, p), vc, err, nn, t),
                  (float8)(0.0f), (float8)(0.0f), (float8)(0.0f), (float8)(0.0f)};
    for (int k = 2; k < 32; ++k) r[k] = f[k - 2];
    for (int k = 0; k < 32; ++k) {
        uint b[8];
        vstore8(as_uint8(r[k]), 0, b);
        for (int l = 0; l < 8; ++l) lane[(8 * i + l) * 32 + k] = b[l];
    }
#else
    for (int j = 8 * 32 * i; j < 8 * 32 * (i + 1); ++j) lane[j] = scalar[j];
#endif
}

// probe_roughconductor8
// reads   per lane 24 floats: albedo xyz, alpha, d xyz (unit), ns xyz (unit), u1, u2, wi xyz
//         (unit), use_wo (> 0: evaluate at the scalar sample's wo where it scattered), eta
//         xyz, k xyz, beckmann (> 0), separable G (> 0)
// writes  per lane 12 words to lane[] (wp_roughconductor_sample8 / _eval8) and scalar[]
//         (wp_bsdf_sample_pdf / wp_bsdf_eval of an isotropic rough conductor): sample mask
//         (-1 / 0), wo xyz, weight xyz, pdf, eval f xyz, eval pdf
WP_KERNEL void probe_roughconductor8(int n, WP_GLOBAL const float* in, WP_GLOBAL uint* lane,
                                     WP_GLOBAL uint* scalar) {
    int i = wp_global_id();
    if (i >= n) return;
    float a[24][8];
    WP_PROBE_READ(a, 24)
    uint sres[8][12];
    float wix[8], wiy[8], wiz[8];
    int flags[8];
    for (int l = 0; l < 8; ++l) {
        MaterialData m = wp_probe_material(WP_MATERIAL_ROUGH_CONDUCTOR, a, l);
        m.eta = make_float4(a[16][l], a[17][l], a[18][l], 0.0f);
        m.k = make_float4(a[19][l], a[20][l], a[21][l], 0.0f);
        flags[l] = (a[22][l] > 0.0f ? WP_MF_BECKMANN : 0) | (a[23][l] > 0.0f ? WP_MF_SEPARABLE_G : 0);
        m.flags = flags[l];
        float3 wi;
        wp_probe_scalar_bsdf(m, a, l, sres[l], &wi);
        wix[l] = wi.x, wiy[l] = wi.y, wiz[l] = wi.z;
    }
#if defined(WP_OPENCL)
    RoughConductor8 m;
    m.albedo = l3(vload8(0, a[0]), vload8(0, a[1]), vload8(0, a[2]));
    m.alpha = vload8(0, a[3]);
    m.eta = l3(vload8(0, a[16]), vload8(0, a[17]), vload8(0, a[18]));
    m.k = l3(vload8(0, a[19]), vload8(0, a[20]), vload8(0, a[21]));
    const int8 fl = vload8(0, flags);
    m.bk = (fl & WP_MF_BECKMANN) != 0;
    m.sep = (fl & WP_MF_SEPARABLE_G) != 0;
    L3 d = l3(vload8(0, a[4]), vload8(0, a[5]), vload8(0, a[6]));
    L3 ns = l3(vload8(0, a[7]), vload8(0, a[8]), vload8(0, a[9]));
    L3 wo, weight;
    float8 pdf;
    int8 ok = wp_roughconductor_sample8(m, d, ns, vload8(0, a[10]), vload8(0, a[11]), &wo, &weight, &pdf,
                                        (int8)(-1));
    L3 wi = l3(vload8(0, wix), vload8(0, wiy), vload8(0, wiz));
    float8 epdf;
    L3 f = wp_roughconductor_eval8(m, d, ns, wi, &epdf);
    float8 res[12] = {as_float8(ok), wo.x, wo.y, wo.z, weight.x, weight.y, weight.z, pdf, f.x, f.y, f.z, epdf};
    for (int k = 0; k < 12; ++k) {
        uint b[8];
        vstore8(as_uint8(res[k]), 0, b);
        for (int l = 0; l < 8; ++l) {
            lane[(8 * i + l) * 12 + k] = b[l];
            scalar[(8 * i + l) * 12 + k] = sres[l][k];
        }
    }
#else
    for (int l = 0; l < 8; ++l)
        for (int k = 0; k < 12; ++k) lane[(8 * i + l) * 12 + k] = scalar[(8 * i + l) * 12 + k] = sres[l][k];
#endif
}

// probe_mf_math8: the inline functions of microfacet.h and sampling.h and their lane forms.
// reads   per lane 2 floats: x, y
// writes  per lane 6 words to lane[] and scalar[]: exp(x), erf(x), erfinv(y), log_normal(|x|),
//         atan2_guess(|x|, |y|), pow(x, y) (the host compares erfinv for |y| < 1 and log for
//         normal finite |x| only: their domains)
WP_KERNEL void probe_mf_math8(int n, WP_GLOBAL const float* in, WP_GLOBAL uint* lane,
                              WP_GLOBAL uint* scalar) {
    int i = wp_global_id();
    if (i >= n) return;
    float a[2][8];
    WP_PROBE_READ(a, 2)
    for (int l = 0; l < 8; ++l) {
        float x = a[0][l], y = a[1][l];
        float r[6] = {wp_exp(x), wp_erf(x), wp_erfinv(y), wp_log_normal(fabs(x)), wp_atan2_guess(fabs(x), fabs(y)),
                      wp_pow(x, y)};
        for (int k = 0; k < 6; ++k) scalar[(8 * i + l) * 6 + k] = as_uint(r[k]);
    }
#if defined(WP_OPENCL)
    float8 x = vload8(0, a[0]), y = vload8(0, a[1]);
    float8 res[6] = {wp_exp8(x), wp_erf8(x), wp_erfinv8(y), wp_log_normal8(fabs(x)), wp_atan2_guess8(fabs(x), fabs(y)),
                     wp_pow8(x, y)};
    for (int k = 0; k < 6; ++k) {
        uint b[8];
        vstore8(as_uint8(res[k]), 0, b);
        for (int l = 0; l < 8; ++l) lane[(8 * i + l) * 6 + k] = b[l];
    }
#else
    for (int l = 0; l < 8; ++l)
        for (int k = 0; k < 6; ++k) lane[(8 * i + l) * 6 + k] = scalar[(8 * i + l) * 6 + k];
#endif
}
