// lanes.h — eight paths at a time: the shading arithmetic on float8 lanes (OpenCL only).
//
// PoCL turns a work-group into a loop over its work-items and vectorises that loop only when
// its body holds no vector-typed instruction; every float3 of the scalar shading code is one,
// so shade_surface runs one path at a time (docs/performance.md, "Third round"). The lane
// kernel (shade.cl, shade_surface8) spells the vector width out instead: a work-item shades
// its paths eight at a time, every per-path value a float8 (lane l = path l), every 3-vector an L3
// of three float8, decisions as int8 masks (-1 true, 0 false: OpenCL's vector relational
// results, which select() reads by their sign bit).
//
// Each function here is the lane form of a scalar one, with the same operations in the same
// order, so that a lane computes the scalar function's bits (FP_CONTRACT is off: compat.h);
// tests/test_lanes.cpp checks the functions against their scalar twins bit for bit, and
// tests/test_shade.cpp the lane kernel against shade_surface. Change both together.
#ifndef WP_LANES_H
#define WP_LANES_H

#include "compat.h"
#include "offset.h"
#include "shading.h"
#include "estimator.h"
#include "sampling.h"
#include "microfacet.h"

#ifndef WP_GLOSSY_MODEL
#define WP_GLOSSY_MODEL WP_DEFAULT_GLOSSY_MODEL
#endif

#if defined(WP_OPENCL)

WP_NAMESPACE_BEGIN

// Three float8: lane l of x, y, z is the 3-vector of path l.
typedef struct L3 {
    float8 x, y, z;
} L3;

WP_FN L3 l3(float8 x, float8 y, float8 z) {
    L3 r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}
WP_FN L3 l3_splat(float x, float y, float z) { return l3((float8)(x), (float8)(y), (float8)(z)); }
WP_FN L3 l3_add(L3 a, L3 b) { return l3(a.x + b.x, a.y + b.y, a.z + b.z); }
WP_FN L3 l3_sub(L3 a, L3 b) { return l3(a.x - b.x, a.y - b.y, a.z - b.z); }
WP_FN L3 l3_mul(L3 a, L3 b) { return l3(a.x * b.x, a.y * b.y, a.z * b.z); }
WP_FN L3 l3_scale(L3 a, float8 s) { return l3(a.x * s, a.y * s, a.z * s); }
WP_FN L3 l3_neg(L3 a) { return l3(-a.x, -a.y, -a.z); }
WP_FN L3 l3_abs(L3 a) { return l3(fabs(a.x), fabs(a.y), fabs(a.z)); }
// dot(a, b) of float3, as OpenCL's builtin rounds it: (x + y) + z.
WP_FN float8 l3_dot(L3 a, L3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
// c ? b : a per lane (c: a mask).
WP_FN L3 l3_select(L3 a, L3 b, int8 c) {
    return l3(select(a.x, b.x, c), select(a.y, b.y, c), select(a.z, b.z, c));
}
WP_FN float8 l3_max_component(L3 v) { return max(v.x, max(v.y, v.z)); }  // wp_max_component
WP_FN int8 l3_all_finite(L3 v) { return isfinite(v.x) & isfinite(v.y) & isfinite(v.z); }

// The lanes of mask m as bits (bit l: lane l true).
WP_FN int wp_lane_bits(int8 m) {
    int b[8];
    vstore8(m, 0, b);
    int r = 0;
#pragma unroll
    for (int l = 0; l < 8; ++l) r |= (b[l] < 0 ? 1 : 0) << l;
    return r;
}

// offset.h
WP_FN float8 wp_next_float_up8(float8 x) {
    int8 b = as_int8(x);
    float8 r = as_float8(select(b - 1, b + 1, x > 0.0f));
    return select(r, as_float8((int8)(1)), x == 0.0f);
}
WP_FN float8 wp_next_float_down8(float8 x) {
    int8 b = as_int8(x);
    float8 r = as_float8(select(b + 1, b - 1, x > 0.0f));
    return select(r, -as_float8((int8)(1)), x == 0.0f);
}
WP_FN L3 wp_hit_point8(L3 v0, L3 v1, L3 v2, float8 u, float8 v, L3* err) {
    L3 a = l3_scale(l3_sub(v1, v0), u), b = l3_scale(l3_sub(v2, v0), v);
    L3 p = l3_add(l3_add(v0, a), b);
    *err = l3_add(l3_scale(l3_add(l3_abs(a), l3_abs(b)), (float8)(WP_GAMMA3)),
                  l3_scale(l3_add(l3_abs(v0), l3_abs(p)), (float8)(WP_GAMMA2)));
    return p;
}
WP_FN float8 wp_offset_component8(float8 o, float8 off) {
    return select(select(o, wp_next_float_down8(o), off < 0.0f), wp_next_float_up8(o), off > 0.0f);
}
WP_FN L3 wp_offset_ray_origin8(L3 p, L3 err, L3 n, float8 extra) {
    float8 d = l3_dot(l3_abs(n), err) + extra;
    L3 off = l3_scale(n, d);
    L3 o = l3_add(p, off);
    return l3(wp_offset_component8(o.x, off.x), wp_offset_component8(o.y, off.y),
              wp_offset_component8(o.z, off.z));
}
WP_FN float8 wp_shadow_tmax8(L3 sd, L3 yerr, L3 ln, float8 tri_offset) {
    L3 a = l3_abs(sd);
    float8 s = fmax(a.x, fmax(a.y, a.z));
    float8 h = l3_dot(l3_abs(ln), yerr) + tri_offset + (WP_OFFSET_SHADOW_K * 5.9604645e-8f) * s;
    float8 dt = h / fabs(l3_dot(sd, ln));
    return select((float8)(0.5f), 1.0f - dt, dt < 0.5f);
}
WP_FN float8 wp_shadow_end_clear8(float8 tmax, L3 sd, L3 y, L3 yerr, L3 ln, float8 clearance) {
    L3 a = l3_abs(sd), b = l3_abs(y);
    float8 s = fmax(a.x, fmax(a.y, a.z)) + fmax(b.x, fmax(b.y, b.z));
    float8 reach = clearance - ((yerr.x + yerr.y) + yerr.z) - (64.0f * 5.9604645e-8f) * s;
    float8 t = fmax(1.0f - reach / sqrt(l3_dot(sd, sd)), 0.0f);
    return select(tmax, fmin(tmax, t), (reach > 0.0f) & (l3_dot(sd, ln) < 0.0f) & (tmax > 0.5f));
}

// sampling.h
WP_FN float8 wp_exp_reduced8(float8 n, float8 r) {
    float8 p = 1.9875691500e-4f;
    p = 1.3981999507e-3f + p * r;
    p = 8.3334519073e-3f + p * r;
    p = 4.1665795894e-2f + p * r;
    p = 1.6666665459e-1f + p * r;
    p = 5.0000001201e-1f + p * r;
    float8 y = p * (r * r) + r + 1.0f;
    int8 ni = convert_int8(n);
    int8 n1 = ni >> 1, n2 = ni - n1;
    return y * as_float8((n1 + 127) << 23) * as_float8((n2 + 127) << 23);
}
WP_FN float8 wp_exp8(float8 x) {
    float8 xc = clamp(x, -104.0f, 89.0f);
    float8 n = floor(xc * 1.44269504088896341f + 0.5f);
    float8 r = xc - n * 0.693359375f;
    r = r - n * -2.12194440e-4f;
    return select(wp_exp_reduced8(n, r), x, isnan(x));
}
// Lane masks are -1 where true: the scalar form's "+ big" is "- big" here.
WP_FN float8 wp_pow8(float8 x, float8 y) {
    const int8 denormal = x < 1.17549435e-38f;
    const float8 xs = select(x, x * 16777216.0f, denormal);
    const int8 i = as_int8(xs);
    float8 m = as_float8((i & 0x007fffff) | 0x3f800000);
    const int8 big = m >= 1.41421356f;
    m = select(m, 0.5f * m, big);
    const float8 fe = convert_float8(((i >> 23) & 0xff) - 127 - (denormal & 24) - big);
    const float8 a = m - 1.0f;
    const float8 b = m + 1.0f;
    const float8 be = m - (b - 1.0f);
    const float8 t = a / b;
    const float8 tl = (fma(-t, b, a) - t * be) / b;
    const float8 t2 = t * t;
    float8 q = 0.15384615384615385f;
    q = 0.18181818181818182f + q * t2;
    q = 0.22222222222222222f + q * t2;
    q = 0.28571428571428571f + q * t2;
    q = 0.4f + q * t2;
    q = 0.66666666666666667f + q * t2;
    const float8 s1 = fe * 0.693359375f, s2 = 2.0f * t;
    const float8 lh = s1 + s2;
    const float8 bv = lh - s1;
    const float8 l2 = ((s1 - (lh - bv)) + (s2 - bv)) + (fe * -2.12194440e-4f + (2.0f * tl + t2 * t * q));
    const float8 l1 = lh + l2;  // renormalised (|l2| <= |lh|): |ll| <= ulp(l1) / 2
    const float8 ll = l2 - (l1 - lh);
    const float8 zh = y * l1;
    const float8 zl = fma(y, l1, -zh) + y * ll;
    const float8 zc = select((float8)(0.0f), clamp(zh, -104.0f, 89.0f), zh == zh);
    const float8 n = floor(zc * 1.44269504088896341f + 0.5f);
    float8 r = zc - n * 0.693359375f;
    r = r - n * -2.12194440e-4f;
    r = r + select((float8)(0.0f), zl, zc == zh);
    float8 p = wp_exp_reduced8(n, r);
    const float8 lo = select(select((float8)(1.0f), (float8)(INFINITY), y < 0.0f), (float8)(0.0f), y > 0.0f);
    p = select(p, lo, x == 0.0f);
    p = select(p, 1.0f / lo, x == INFINITY);
    return select((float8)(NAN), p, (x >= 0.0f) & (y == y));
}
WP_FN void wp_sincos_2pi8(float8 u, float8* s, float8* c) {
    float8 t = 4.0f * u;
    int8 q = convert_int8(t + 0.5f);
    float8 x = (t - convert_float8(q)) * (0.5f * WP_PI);
    float8 z = x * x;
    float8 sx = x + x * z * (-1.6666654611e-1f + z * (8.3321608736e-3f + z * -1.9515295891e-4f));
    float8 cx = 1.0f - 0.5f * z + z * z * (4.166664568298827e-2f + z * (-1.388731625493765e-3f + z * 2.443315711809948e-5f));
    int8 odd = (q & 1) != 0;
    float8 a = select(sx, cx, odd), b = select(cx, sx, odd);
    *s = select(a, -a, (q & 2) != 0);
    *c = select(b, -b, ((q + 1) & 2) != 0);
}
// wp_onb: (t, b, n) right-handed and orthonormal for unit n.
WP_FN void wp_onb8(L3 n, L3* t, L3* b) {
    float8 sign = copysign((float8)(1.0f), n.z);
    float8 a = -1.0f / (sign + n.z);
    float8 c = n.x * n.y * a;
    *t = l3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    *b = l3(c, sign + n.y * n.y * a, -n.y);
}
WP_FN L3 wp_to_world8(L3 lv, L3 n) {
    L3 t, b;
    wp_onb8(n, &t, &b);
    return l3_add(l3_add(l3_scale(t, lv.x), l3_scale(b, lv.y)), l3_scale(n, lv.z));
}
WP_FN L3 wp_sample_cosine_hemisphere8(float8 u1, float8 u2) {
    float8 r = sqrt(u1);
    float8 sp, cp;
    wp_sincos_2pi8(u2, &sp, &cp);
    return l3(r * cp, r * sp, sqrt(1.0f - u1));
}
WP_FN L3 wp_sample_uniform_hemisphere8(float8 u1, float8 u2) {  // wp_spherical_local(1 - u1, u2)
    float8 cos_theta = 1.0f - u1;
    float8 sin_theta = sqrt(max(0.0f, 1.0f - cos_theta * cos_theta));
    float8 sp, cp;
    wp_sincos_2pi8(u2, &sp, &cp);
    return l3(sin_theta * cp, sin_theta * sp, cos_theta);
}
WP_FN float8 wp_cosine_hemisphere_pdf8(float8 cos_theta) {
    return select((float8)(0.0f), cos_theta * WP_INV_PI, cos_theta > 0.0f);
}

// lights.h
WP_FN float8 wp_light_pdf_solid_angle8(float8 pdf_area, float8 dist2, float8 cos_light) {
    return select((float8)(0.0f), pdf_area * dist2 / cos_light, cos_light > 0.0f);
}
WP_FN float8 wp_power_heuristic8(float8 pa, float8 pb) {
    float8 r = pb / pa;
    return select((float8)(0.0f), 1.0f / (1.0f + r * r), pa > 0.0f);
}

// shading.h (the failure modes of shading normals)
// wp_interpolated_normal: n0..n2 the vertex normals' lanes, ng_front the face normal.
WP_FN L3 wp_interpolated_normal8(L3 n0, L3 n1, L3 n2, float8 u, float8 v, L3 ng_front) {
    const float8 w = 1.0f - u - v;
    L3 n = l3_add(l3_add(l3_scale(n0, w), l3_scale(n1, u)), l3_scale(n2, v));
    const float8 l2 = l3_dot(n, n);
    const int8 none = ~(l2 > 1e-30f) | ~isfinite(l2);
    n = l3_scale(n, 1.0f / sqrt(l2));
    n = l3_select(n, l3_neg(n), l3_dot(n, ng_front) < 0.0f);
    return l3_select(n, ng_front, none);
}
WP_FN L3 wp_bend_normal8(L3 ns, L3 ng, L3 wo) {
    const float8 c = l3_dot(wo, ns);
    const L3 r = l3_sub(l3_scale(ns, 2.0f * c), wo);
    const int8 keep = (c > 0.0f) & (l3_dot(r, ng) >= WP_BEND_EPS);
    const L3 rt = l3_sub(r, l3_scale(ng, l3_dot(r, ng)));
    const float8 tl2 = l3_dot(rt, rt);
    const L3 r2 = l3_select(ng, l3_add(l3_scale(rt, sqrt(1.0f - WP_BEND_EPS * WP_BEND_EPS) / sqrt(tl2)),
                                        l3_scale(ng, (float8)(WP_BEND_EPS))),
                            tl2 > 1e-20f);
    const L3 h = l3_add(wo, r2);
    const float8 hl2 = l3_dot(h, h);
    const L3 bent = l3_select(ng, l3_scale(h, 1.0f / sqrt(hl2)), hl2 > 1e-30f);
    return l3_select(bent, ns, keep);
}
WP_FN int8 wp_same_side8(L3 w, L3 ns, L3 ng) { return (l3_dot(w, ns) > 0.0f) == (l3_dot(w, ng) > 0.0f); }
WP_FN float8 wp_terminator_factor8(L3 ng, L3 ns, L3 wi) {
    const float8 nsi = l3_dot(ns, wi), ngs = l3_dot(ng, ns);
    const float8 g = min(1.0f, l3_dot(ng, wi) / (nsi * ngs));
    const float8 f = select((float8)(0.0f), g * (1.0f + g * (1.0f - g)), g > 0.0f);
    return select((float8)(1.0f), f, (nsi > 0.0f) & (ngs > 0.0f));
}

// sampling.h: frames, reflection, GGX. normalize(v) of float3 is spelled
// v * (1 / sqrt(dot(v, v))): PoCL's scalar normalize gives those bits (tests/test_lanes.cpp,
// "normalize" case, over random, tiny and huge vectors).
WP_FN L3 l3_cross(L3 a, L3 b) {
    return l3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
WP_FN L3 l3_normalize(L3 v) { return l3_scale(v, 1.0f / sqrt(l3_dot(v, v))); }
WP_FN L3 wp_to_local8(L3 w, L3 n) {
    L3 t, b;
    wp_onb8(n, &t, &b);
    return l3(l3_dot(w, t), l3_dot(w, b), l3_dot(w, n));
}
WP_FN L3 wp_reflect8(L3 d, L3 n) { return l3_sub(d, l3_scale(n, 2.0f * l3_dot(d, n))); }
WP_FN L3 wp_spherical_local8(float8 cos_theta, float8 u) {
    float8 sin_theta = sqrt(max(0.0f, 1.0f - cos_theta * cos_theta));
    float8 sp, cp;
    wp_sincos_2pi8(u, &sp, &cp);
    return l3(sin_theta * cp, sin_theta * sp, cos_theta);
}
WP_FN float8 wp_phong_lobe_pdf8(float8 cos_alpha, float8 exponent) {
    return select((float8)(0.0f), (exponent + 1.0f) * WP_INV_2PI * wp_pow8(cos_alpha, exponent),
                  cos_alpha > 0.0f);
}
WP_FN float8 wp_ggx_d8(L3 h, float8 alpha) {
    float8 a2 = alpha * alpha;
    float8 t = h.z * h.z * (a2 - 1.0f) + 1.0f;
    return select((float8)(0.0f), a2 / (WP_PI * t * t), h.z > 0.0f);
}
WP_FN float8 wp_ggx_lambda8(L3 w, float8 alpha) {
    float8 c2 = w.z * w.z;
    float8 s2 = max(0.0f, 1.0f - c2);
    return select((float8)(FLT_MAX), 0.5f * (-1.0f + sqrt(1.0f + alpha * alpha * s2 / c2)), c2 > 0.0f);
}
WP_FN float8 wp_ggx_g1_8(L3 w, float8 alpha) { return 1.0f / (1.0f + wp_ggx_lambda8(w, alpha)); }
WP_FN float8 wp_ggx_g2_8(L3 wo, L3 wi, float8 alpha) {
    return 1.0f / (1.0f + wp_ggx_lambda8(wo, alpha) + wp_ggx_lambda8(wi, alpha));
}
WP_FN L3 wp_vndf_hemisphere8(L3 vh, float8 u1, float8 u2) {
    float8 lensq = vh.x * vh.x + vh.y * vh.y;
    L3 t1 = l3_select(l3_splat(1.0f, 0.0f, 0.0f),
                      l3_scale(l3(-vh.y, vh.x, (float8)(0.0f)), 1.0f / sqrt(lensq)), lensq > 0.0f);
    L3 t2 = l3_cross(vh, t1);
    float8 r = sqrt(u1);
    float8 sp, cp;
    wp_sincos_2pi8(u2, &sp, &cp);
    float8 p1 = r * cp;
    float8 p2 = r * sp;
    float8 s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * sqrt(max(0.0f, 1.0f - p1 * p1)) + s * p2;
    return l3_add(l3_add(l3_scale(t1, p1), l3_scale(t2, p2)),
                  l3_scale(vh, sqrt(max(0.0f, 1.0f - p1 * p1 - p2 * p2))));
}
WP_FN L3 wp_ggx_sample_vndf8(L3 wo, float8 alpha, float8 u1, float8 u2) {
    L3 vh = l3_normalize(l3(alpha * wo.x, alpha * wo.y, wo.z));
    L3 nh = wp_vndf_hemisphere8(vh, u1, u2);
    return l3_normalize(l3(alpha * nh.x, alpha * nh.y, max(1e-6f, nh.z)));
}
// wp_ggx_reflect_pdf for lanes with wo.z > 0 and wi.z > 0 (callers mask the others).
WP_FN float8 wp_ggx_reflect_pdf8(L3 wo, L3 wi, float8 alpha) {
    L3 h = l3_normalize(l3_add(wo, wi));
    return wp_ggx_g1_8(wo, alpha) * wp_ggx_d8(h, alpha) / (4.0f * wo.z);
}

// materials/glossy.h
WP_FN L3 wp_fresnel_schlick8(L3 f0, float8 cos_theta) {
    float8 c = 1.0f - clamp(cos_theta, 0.0f, 1.0f);
    float8 c5 = c * c * c * c * c;
    return l3_add(f0, l3_scale(l3_sub(l3_splat(1.0f, 1.0f, 1.0f), f0), c5));
}
WP_FN float8 wp_ggx_alpha_to_phong8(float8 alpha) { return 2.0f / (alpha * alpha) - 2.0f; }

// wp_glossy_sample per lane: the mask of the lanes where it returns 1; there *wo, *weight
// and *pdf hold its outputs (elsewhere: anything).
WP_FN int8 wp_glossy_sample8(L3 albedo, float8 alpha, L3 d, L3 ns, float8 u1, float8 u2,
                             L3* wo, L3* weight, float8* pdf) {
#if WP_GLOSSY_MODEL == WP_GLOSSY_PHONG
    float8 e = wp_ggx_alpha_to_phong8(alpha);
    L3 r = wp_reflect8(d, ns);
    float8 cos_alpha = wp_pow8(1.0f - u1, 1.0f / (e + 1.0f));
    L3 lv = wp_spherical_local8(cos_alpha, u2);
    L3 w = wp_to_world8(lv, r);
    *wo = w;
    *weight = albedo;
    *pdf = wp_phong_lobe_pdf8(lv.z, e);
    return l3_dot(w, ns) > 0.0f;
#else
    L3 vo = wp_to_local8(l3_neg(d), ns);
    L3 h = wp_ggx_sample_vndf8(vo, alpha, u1, u2);
    float8 oh = l3_dot(vo, h);
    L3 vi = l3_sub(l3_scale(h, 2.0f * oh), vo);
    *wo = wp_to_world8(vi, ns);
    *weight = l3_scale(wp_fresnel_schlick8(albedo, oh),
                       wp_ggx_g2_8(vo, vi, alpha) / wp_ggx_g1_8(vo, alpha));
    *pdf = wp_ggx_reflect_pdf8(vo, vi, alpha);
    return (vo.z > 0.0f) & (vi.z > 0.0f);
#endif
}

// wp_bsdf_eval of a glossy material per lane, given cos_i = dot(wi, ns): f cos and *pdf,
// zero and 0 where it returns zero.
WP_FN L3 wp_glossy_eval8(L3 albedo, float8 alpha, L3 d, L3 ns, L3 wi, float8 cos_i, float8* pdf) {
    const float8 zero = (float8)(0.0f);
    int8 live = cos_i > 0.0f;  // bsdf.h: cos_i != 0; glossy.h: reflection only
#if WP_GLOSSY_MODEL == WP_GLOSSY_PHONG
    L3 r = wp_reflect8(d, ns);
    float8 p = wp_phong_lobe_pdf8(l3_dot(wi, r), wp_ggx_alpha_to_phong8(alpha));
    L3 f = l3_scale(albedo, p);
#else
    L3 vo = wp_to_local8(l3_neg(d), ns);
    L3 vi = wp_to_local8(wi, ns);
    live = live & (vo.z > 0.0f) & (vi.z > 0.0f);
    L3 h = l3_normalize(l3_add(vo, vi));
    float8 p = wp_ggx_reflect_pdf8(vo, vi, alpha);
    float8 s = wp_ggx_d8(h, alpha) * wp_ggx_g2_8(vo, vi, alpha) / (4.0f * vo.z);
    L3 f = l3_scale(wp_fresnel_schlick8(albedo, l3_dot(vo, h)), s);
#endif
    *pdf = select(zero, p, live);
    return l3_select(l3(zero, zero, zero), f, live);
}


// microfacet.h per lane, for isotropic distributions (α_x = α_y = alpha: the lane kernel never
// runs with anisotropy, KernelConfig::shade_lanes), so the axes' rotation is the identity.
// bk: the lanes whose distribution is Beckmann (else GGX); sep: separable G (else
// height-correlated). Each is its scalar twin's operations in the same order, both branches
// computed and selected.
WP_FN float8 wp_erf8(float8 x) {
    float8 ax = fabs(x);
    float8 u = 2.0f * ax * ax - 1.0f;
    float8 p = 1.23060545e-06f;
    p = -1.76690683e-05f + p * u;
    p = 0.000217513545f + p * u;
    p = -0.0022854195f + p * u;
    p = 0.0198524967f + p * u;
    p = -0.1405361f + p * u;
    p = 0.965468764f + p * u;
    float8 near = ax * p;
    u = (ax - 2.5f) * (2.0f / 3.0f);
    p = 0.000258006097f;
    p = 9.49723835e-05f + p * u;
    p = -0.00203279871f + p * u;
    p = 0.00154291105f + p * u;
    p = 0.00466702878f + p * u;
    p = -0.0104118455f + p * u;
    p = 0.00663786428f + p * u;
    p = 0.00957930554f + p * u;
    p = -0.0318684503f + p * u;
    p = 0.0463895835f + p * u;
    p = -0.0436514802f + p * u;
    p = 0.0281874072f + p * u;
    p = -0.01225283f + p * u;
    p = 0.00326727028f + p * u;
    p = 0.999593019f + p * u;
    float8 far = select(ax, (float8)(1.0f), ax >= 4.0f);  // NaN: NaN
    float8 r = select(select(far, p, ax < 4.0f), near, ax < 1.0f);
    return copysign(r, x);
}
WP_FN float8 wp_log_normal8(float8 x) {
    int8 i = as_int8(x);
    int8 e = ((i >> 23) & 0xff) - 126;
    float8 m = as_float8((i & 0x007fffff) | 0x3f000000);
    int8 low = m < 0.70710678f;
    e = e + low;  // -1 where low
    m = select(m - 1.0f, m + m - 1.0f, low);
    float8 z = m * m;
    float8 y = 7.0376836292e-2f;
    y = -1.1514610310e-1f + y * m;
    y = 1.1676998740e-1f + y * m;
    y = -1.2420140846e-1f + y * m;
    y = 1.4249322787e-1f + y * m;
    y = -1.6668057665e-1f + y * m;
    y = 2.0000714765e-1f + y * m;
    y = -2.4999993993e-1f + y * m;
    y = 3.3333331174e-1f + y * m;
    y = y * m * z;
    float8 fe = convert_float8(e);
    y += -2.12194440e-4f * fe;
    y += -0.5f * z;
    return (m + y) + 0.693359375f * fe;
}
WP_FN float8 wp_erfinv8(float8 x) {
    float8 w = -wp_log_normal8(max((1.0f - x) * (1.0f + x), 0x1p-24f));
    float8 v = w - 2.5f;
    float8 p = 2.81022636e-08f;
    p = 3.43273939e-07f + p * v;
    p = -3.5233877e-06f + p * v;
    p = -4.39150654e-06f + p * v;
    p = 0.00021858087f + p * v;
    p = -0.00125372503f + p * v;
    p = -0.00417768164f + p * v;
    p = 0.246640727f + p * v;
    p = 1.50140941f + p * v;
    v = sqrt(w) - 3.0f;
    float8 q = -0.000200214257f;
    q = 0.000100950558f + q * v;
    q = 0.00134934322f + q * v;
    q = -0.00367342844f + q * v;
    q = 0.00573950773f + q * v;
    q = -0.0076224613f + q * v;
    q = 0.00943887047f + q * v;
    q = 1.00167406f + q * v;
    q = 2.83297682f + q * v;
    return select(q, p, w < 5.0f) * x;
}
WP_FN float8 wp_atan2_guess8(float8 y, float8 x) {
    float8 lo = min(x, y), hi = max(x, y);
    float8 z = select((float8)(0.0f), lo / hi, hi > 0.0f), z2 = z * z;
    float8 r = z * (0.99997726f + z2 * (-0.33262347f + z2 * (0.19354346f +
                    z2 * (-0.11643287f + z2 * (0.05265332f - 0.01172120f * z2)))));
    return select(r, 1.5707963267948966f - r, y > x);
}
// wp_beckmann_sample_slope11 for the lanes of `need` (the others: anything): the Newton
// iteration runs until every such lane has converged or made its ten steps, each lane
// freezing where its scalar loop would break.
WP_FN void wp_beckmann_sample_slope11_8(float8 cos_theta, float8 sin_theta, float8 u1, float8 u2,
                                       int8 need, float8* sx, float8* sy) {
    const float inv_sqrt_pi = 0.56418958354775628f;
    float8 tan_theta = sin_theta / cos_theta, cot_theta = cos_theta / sin_theta;
    float8 a = -1.0f, c = wp_erf8(cot_theta);
    float8 ux = max(u1, 1e-6f);
    float8 theta = wp_atan2_guess8(sin_theta, cos_theta);
    float8 fit = 1.0f + theta * (-0.876f + theta * (0.4265f - 0.0594f * theta));
    float8 b = c - (1.0f + c) * wp_exp8(fit * wp_log_normal8(1.0f - ux));
    float8 norm = 1.0f / (1.0f + c + inv_sqrt_pi * tan_theta * wp_exp8(-cot_theta * cot_theta));
    int8 active = need;
    for (int it = 0; it < 10 && wp_lane_bits(active); ++it) {
        b = select(b, 0.5f * (a + c), active & ~((b >= a) & (b <= c)));
        float8 x = wp_erfinv8(b);
        float8 value = norm * (1.0f + b + inv_sqrt_pi * tan_theta * wp_exp8(-x * x)) - ux;
        active &= ~(fabs(value) < 1e-5f);
        float8 derivative = norm * (1.0f - x * tan_theta);
        const int8 above = value > 0.0f;
        c = select(c, b, active & above);
        a = select(a, b, active & ~above);
        b = select(b, b - value / derivative, active);
    }
    *sx = wp_erfinv8(b);
    *sy = wp_erfinv8(2.0f * max(u2, 1e-6f) - 1.0f);
}
WP_FN float8 wp_mf_d8(L3 h, float8 alpha, int8 bk) {
    float8 x = h.x / alpha, y = h.y / alpha;
    float8 z2 = h.z * h.z;
    float8 ex = wp_exp8(-(x * x + y * y) / z2);
    float8 db = select((float8)(0.0f), ex / (WP_PI * alpha * alpha * z2 * z2), ex > 0.0f);
    float8 t = x * x + y * y + z2;
    float8 dg = 1.0f / (WP_PI * alpha * alpha * t * t);
    return select((float8)(0.0f), select(dg, db, bk), h.z > 0.0f);
}
WP_FN float8 wp_mf_lambda8(L3 w, float8 alpha, int8 bk) {
    float8 px = alpha * w.x, py = alpha * w.y;
    float8 t2 = (px * px + py * py) / (w.z * w.z);
    float8 r = 0.5f * (-1.0f + sqrt(1.0f + t2));
    if (wp_lane_bits(bk)) {
        float8 a = 1.0f / sqrt(t2);
        float8 lb = 0.5f * (wp_erf8(a) - 1.0f) + wp_exp8(-a * a) / (2.0f * a * 1.7724538509055160f);
        r = select(r, select((float8)(0.0f), lb, t2 >= 0.0625f), bk);
    }
    return select((float8)(FLT_MAX), r, w.z != 0.0f);
}
// wp_mf_g_lo: G(wo, wi) given Λ(wo).
WP_FN float8 wp_mf_g_lo8(float8 lambda_o, L3 wi, float8 alpha, int8 bk, int8 sep) {
    float8 li = wp_mf_lambda8(wi, alpha, bk);
    float8 separable = (1.0f / (1.0f + lambda_o)) * select((float8)(0.0f), 1.0f / (1.0f + li), wi.z > 0.0f);
    return select(1.0f / (1.0f + lambda_o + li), separable, sep);
}
WP_FN float8 wp_mf_pdf_vndf_gd8(float8 g1, L3 w, L3 h, float8 d) {
    return g1 * max(0.0f, l3_dot(w, h)) * d / w.z;
}
// wp_mf_sample_vndf for the lanes of `need`.
WP_FN L3 wp_mf_sample_vndf8(L3 w, float8 alpha, int8 bk, float8 u1, float8 u2, int8 need) {
    // Each distribution's sampler only where a needed lane has it (veach-mis: Beckmann only).
    L3 h = l3_splat(0.0f, 0.0f, 1.0f);
    if (wp_lane_bits(need & ~bk)) h = wp_ggx_sample_vndf8(w, alpha, u1, u2);  // Heitz 2018, as glossy
    if (wp_lane_bits(bk & need)) {
        L3 wh = l3_normalize(l3(alpha * w.x, alpha * w.y, w.z));
        float8 sin_t = sqrt(wh.x * wh.x + wh.y * wh.y);
        float8 cphi = select((float8)(1.0f), wh.x / sin_t, sin_t > 0.0f);
        float8 sphi = select((float8)(0.0f), wh.y / sin_t, sin_t > 0.0f);
        float8 s_x, s_y;
        wp_beckmann_sample_slope11_8(wh.z, sin_t, u1, u2, bk & need, &s_x, &s_y);
        float8 sx = (cphi * s_x - sphi * s_y) * alpha;
        float8 sy = (sphi * s_x + cphi * s_y) * alpha;
        h = l3_select(h, l3_normalize(l3(-sx, -sy, (float8)(1.0f))), bk);
    }
    return h;
}
WP_FN float8 wp_fresnel_conductor1_8(float8 cos_i, float8 eta, float8 k) {
    float8 c = clamp(cos_i, 0.0f, 1.0f);
    float8 c2 = c * c, s2 = 1.0f - c2;
    float8 eta2 = eta * eta, k2 = k * k;
    float8 t0 = eta2 - k2 - s2;
    float8 a2b2 = sqrt(t0 * t0 + 4.0f * eta2 * k2);
    float8 t1 = a2b2 + c2;
    float8 ek = fabs(eta * k);
    float8 a = select(select((float8)(0.0f), ek / sqrt(0.5f * (a2b2 - t0)), ek > 0.0f),
                      sqrt(0.5f * (a2b2 + t0)), t0 >= 0.0f);
    float8 t2 = 2.0f * c * a;
    float8 rs = select((float8)(1.0f), (t1 - t2) / (t1 + t2), t1 + t2 > 0.0f);
    float8 t3 = c2 * a2b2 + s2 * s2;
    float8 t4 = t2 * s2;
    float8 rp = rs * (t3 - t4) / (t3 + t4);
    return 0.5f * (rp + rs);
}
WP_FN L3 wp_fresnel_conductor8(float8 cos_i, L3 eta, L3 k) {
    return l3(wp_fresnel_conductor1_8(cos_i, eta.x, k.x), wp_fresnel_conductor1_8(cos_i, eta.y, k.y),
              wp_fresnel_conductor1_8(cos_i, eta.z, k.z));
}

// materials/roughconductor.h per lane (isotropic). A lane's parameters: albedo, η and k of
// its conductor, its width alpha, Beckmann (bk) and separable G (sep) masks.
typedef struct RoughConductor8 {
    L3 albedo, eta, k;
    float8 alpha;
    int8 bk, sep;
} RoughConductor8;

// wp_roughconductor_sample per lane: the mask of the lanes where it returns 1 (there *wo,
// *weight and *pdf hold its outputs); `need`: the lanes whose results are used.
WP_FN int8 wp_roughconductor_sample8(RoughConductor8 m, L3 d, L3 ns, float8 u1, float8 u2, L3* wo,
                                     L3* weight, float8* pdf, int8 need) {
    L3 vo = wp_to_local8(l3_neg(d), ns);
    float8 lo = wp_mf_lambda8(vo, m.alpha, m.bk);
    float8 g1o = 1.0f / (1.0f + lo);
    int8 ok = (vo.z > 0.0f) & (g1o > 0.0f);
    L3 h = wp_mf_sample_vndf8(vo, m.alpha, m.bk, u1, u2, need & ok);
    float8 oh = l3_dot(vo, h);
    ok &= oh > 0.0f;
    L3 vi = l3_sub(l3_scale(h, 2.0f * oh), vo);
    ok &= vi.z > 0.0f;
    *wo = wp_to_world8(vi, ns);
    L3 f = wp_fresnel_conductor8(oh, m.eta, m.k);
    *weight = l3_scale(l3_mul(m.albedo, f), wp_mf_g_lo8(lo, vi, m.alpha, m.bk, m.sep) / g1o);
    *pdf = wp_mf_pdf_vndf_gd8(g1o, vo, h, wp_mf_d8(h, m.alpha, m.bk)) / (4.0f * oh);
    return ok;
}

// wp_bsdf_eval of a rough conductor per lane: f cos and *pdf, zero and 0 where it returns
// zero.
WP_FN L3 wp_roughconductor_eval8(RoughConductor8 m, L3 d, L3 ns, L3 wi, float8* pdf) {
    const float8 zero = (float8)(0.0f);
    L3 vo = wp_to_local8(l3_neg(d), ns);
    L3 vi = wp_to_local8(wi, ns);
    int8 live = (vo.z > 0.0f) & (vi.z > 0.0f);
    L3 h = l3_normalize(l3_add(vo, vi));
    float8 oh = l3_dot(vo, h);
    float8 lo = wp_mf_lambda8(vo, m.alpha, m.bk), d_h = wp_mf_d8(h, m.alpha, m.bk);
    float8 p = wp_mf_pdf_vndf_gd8(1.0f / (1.0f + lo), vo, h, d_h) / (4.0f * oh);
    float8 s = d_h * wp_mf_g_lo8(lo, vi, m.alpha, m.bk, m.sep) / (4.0f * vo.z);
    L3 f = l3_scale(l3_mul(m.albedo, wp_fresnel_conductor8(oh, m.eta, m.k)), s);
    *pdf = select(zero, p, live);
    return l3_select(l3(zero, zero, zero), f, live);
}

WP_NAMESPACE_END

#endif  // WP_OPENCL
#endif  // WP_LANES_H
