// sampling.h — direction sampling: lv frames, hemisphere and lobe warps, reflection.
//
// Directions are sampled in a lv frame whose +z axis is a chosen axis (the normal for
// diffuse, the mirror direction for the glossy lobe) and rotated to world space with an
// orthonormal basis from Duff et al., "Building an Orthonormal Basis, Revisited", JCGT
// 6(1), 2017. Each warp documents its density over solid angle, which the χ² tests in
// tests/test_shade.cpp integrate independently.
#ifndef WP_SAMPLING_H
#define WP_SAMPLING_H

#include "compat.h"

WP_NAMESPACE_BEGIN

// The entry k of an inclusive CDF of n >= 1 entries whose interval [cdf[k-1], cdf[k]) holds
// u in [0, 1): the first k with u < cdf[k], n − 1 if none (binary search). Light choice
// (lights.h) and the environment's rows and columns (envmap.h) draw with it.
// Branch-free: the answer lies in [base, base + len); each step halves len by a select
// (a conditional move), so the loop runs ceil(log2 n) times with no data-dependent branch.
// The taken/not-taken branch of the classic form mispredicted half the time: on veach-mis
// that search was the hottest spot of shade. Same index as the classic form for a
// non-decreasing cdf (every CDF here: prefix sums); reads cdf[0 .. n − 2] only.
WP_FN int wp_cdf_pick(WP_GLOBAL const float* cdf, int n, float u) {
    int base = 0, len = n;
    // Quarters first: three independent loads per step (the halving steps' loads form one
    // dependent chain, each waiting for the previous select). k = probes at or below u; the
    // answer is then in quarter k (the last one keeps the remainder). Reads <= base + len − 2.
    while (len > 3) {
        int q = len >> 2;
        int k = (u < cdf[base + q - 1] ? 0 : 1) + (u < cdf[base + 2 * q - 1] ? 0 : 1) +
                (u < cdf[base + 3 * q - 1] ? 0 : 1);
        base += k * q;
        len = k == 3 ? len - 3 * q : q;
    }
    while (len > 1) {
        int step = len >> 1;
        base += u < cdf[base + step - 1] ? 0 : step;
        len -= step;
    }
    return base;
}

// wp_cdf_pick in O(1) expected steps with a guide table (the cutpoint method: Chen & Asau,
// 1974; Devroye, "Non-Uniform Random Variate Generation", 1986, §III.2.4). m is a power of
// two <= 2^24 and guide[j] (j = 0 .. m) the first k with cdf[k] > j / m, n − 1 if none
// (guide[0] = 0; the host's wp::build_cdf_guide). Same index as wp_cdf_pick for every
// u that is not NaN: u m is exact (a power-of-two scale of a float), so j = floor(u m)
// puts u in [j / m, (j + 1) / m) exactly; cdf[k] <= j / m <= u for every k < guide[j], and
// u < (j + 1) / m < cdf[guide[j + 1]] unless guide[j + 1] = n − 1. The answer is thus in
// [guide[j], guide[j + 1]], where wp_cdf_pick on that bracket finds it. u < 0 takes j = 0
// (bracket from 0), u >= 1 j = m − 1 (bracket up to n − 1); NaN some index in [0, n).
// Prefix sums put about n / m entries in the bucket u falls in, on average over u.
WP_FN int wp_cdf_pick_guided(WP_GLOBAL const float* cdf, WP_GLOBAL const int* guide, int m,
                             float u) {
    int j = (int)fmin(fmax(u * (float)m, 0.0f), (float)(m - 1));
    int lo = guide[j], hi = guide[j + 1];
    return lo + wp_cdf_pick(cdf + lo, hi - lo + 1, u);
}

#define WP_PI 3.14159265358979323846f
#define WP_INV_PI 0.31830988618379067154f
#define WP_INV_2PI 0.15915494309189533577f

// Two unit vectors t, b with (t, b, n) a right-handed orthonormal basis (Duff et al. 2017,
// listing 3). n must be unit length.
WP_FN void wp_onb(float3 n, float3* t, float3* b) {
    float sign = copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float c = n.x * n.y * a;
    *t = make_float3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    *b = make_float3(c, sign + n.y * n.y * a, -n.y);
}

// Local (x, y, z) in the frame around unit axis n to world space.
WP_FN float3 wp_to_world(float3 lv, float3 n) {
    float3 t, b;
    wp_onb(n, &t, &b);
    return t * lv.x + b * lv.y + n * lv.z;
}

// sin(2π u) and cos(2π u) for u in [0, 1]. The octant reduction is exact in float
// (t = 4u, f = t − nearest integer q, |f| ≤ 1/2), so only x = f π/2 ∈ [−π/4, π/4] is
// rounded, and Cephes' sinf/cosf polynomials on that interval give about 1 ulp; then the
// quadrant q picks the signs. The same bits on every device and the host (no library
// call, no argument reduction of a general sin/cos: PoCL's costs a call per sample).
WP_FN void wp_sincos_2pi(float u, float* s, float* c) {
    float t = 4.0f * u;
    int q = (int)(t + 0.5f);
    float x = (t - (float)q) * (0.5f * WP_PI);
    float z = x * x;
    float sx = x + x * z * (-1.6666654611e-1f + z * (8.3321608736e-3f + z * -1.9515295891e-4f));
    float cx = 1.0f - 0.5f * z + z * z * (4.166664568298827e-2f + z * (-1.388731625493765e-3f + z * 2.443315711809948e-5f));
    // Quadrant q (0..4; 4 is 0): sin = ±sx or ±cx, cos = ±cx or ∓sx. Selects, not a
    // switch on q & 3: under Oclgrind 21.10 the switch gave other bits for q = 4, while
    // PoCL and the host agreed (the render-level Oclgrind check compares bits).
    float a = (q & 1) ? cx : sx, b = (q & 1) ? sx : cx;
    *s = (q & 2) ? -a : a;
    *c = ((q + 1) & 2) ? -b : b;
}

// Unit direction with polar cosine cos_theta and azimuth 2π u around +z.
WP_FN float3 wp_spherical_local(float cos_theta, float u) {
    float sin_theta = sqrt(max(0.0f, 1.0f - cos_theta * cos_theta));
    float sp, cp;
    wp_sincos_2pi(u, &sp, &cp);
    return make_float3(sin_theta * cp, sin_theta * sp, cos_theta);
}

// Uniform over the hemisphere z > 0: density 1 / (2π) per steradian.
WP_FN float3 wp_sample_uniform_hemisphere(float u1, float u2) {
    return wp_spherical_local(1.0f - u1, u2);  // 1 - u1 in (0, 1]: never exactly grazing
}
WP_FN float wp_uniform_hemisphere_pdf(void) { return WP_INV_2PI; }

// e^(n ln 2 + r) for an integer n in [-150, 128] and |r| <= ln 2 / 2 (a little more is
// fine): the polynomial and scaling that wp_exp and wp_pow share. Cephes' expf: a degree-7
// polynomial in r; 2^n applied as two exact power-of-two factors, so that results in the
// denormal range round once.
WP_FN float wp_exp_reduced(float n, float r) {
    float p = 1.9875691500e-4f;
    p = 1.3981999507e-3f + p * r;
    p = 8.3334519073e-3f + p * r;
    p = 4.1665795894e-2f + p * r;
    p = 1.6666665459e-1f + p * r;
    p = 5.0000001201e-1f + p * r;
    float y = p * (r * r) + r + 1.0f;
    int ni = (int)n;  // [-150, 128]
    int n1 = ni >> 1, n2 = ni - n1;
    return y * as_float((n1 + 127) << 23) * as_float((n2 + 127) << 23);
}

// e^x in single precision, inline (Cephes' expf: x = n ln 2 + r with ln 2 in two parts,
// then wp_exp_reduced): max relative error 1.9e-7 over [-87, 88]
// (tests/test_materials_conductor.cpp sweeps it against double). 0 below -104 (e^x < half the
// smallest denormal), +inf above ln(FLT_MAX), NaN stays NaN. Why not the builtin: the lane
// kernel (lanes.h, wp_exp8) must give these bits in every lane, and PoCL's exp(float8) differs
// from its scalar exp by an ulp in some lanes (tests/test_lanes.cpp).
WP_FN float wp_exp(float x) {
    if (x != x) return x;
    float xc = clamp(x, -104.0f, 89.0f);
    float n = floor(xc * 1.44269504088896341f + 0.5f);
    float r = xc - n * 0.693359375f;
    r = r - n * -2.12194440e-4f;
    return wp_exp_reduced(n, r);
}

// x^y for x >= 0, inline: e^(y ln x), with ln x and y ln x carried as float pairs (hi + lo)
// so that a large |y ln x| (the Phong lobe's cos^e, e up to 10^6) keeps its precision.
//   x = m 2^e, m in [sqrt(1/2), sqrt(2)) (a denormal x scaled by 2^24 first);
//   ln m = 2 atanh(t) = 2t + t^3 (2/3 + 2t^2/5 + ... + 2t^10/13), t = (m - 1) / (m + 1),
//     |t| <= 0.172, with t's rounding error tl from an fma (m - 1 and the error of m + 1 are
//     exact), so 2t + 2tl is good to about 2^-45 and the odd series' tail (<= 1 % of ln m)
//     needs only float precision;
//   ln x = e C1 + 2t (a two-sum: e C1 is exact) + the rest (ln 2 = C1 + C2 as in wp_exp),
//   renormalised to a pair l1 + ll with |ll| <= ulp(l1) / 2;
//   y ln x = zh + zl (zl from an fma), and e^(zh + zl) as wp_exp with zl added to the reduced
//   argument.
// Relative error at most 2.38e-7 (about 2 ulp; mostly wp_exp's polynomial) in a sweep against
// double pow where the result is a normal float (tests/test_sampling.cpp allows 2.5e-7).
// The ends as pow: x = 0 gives 0 for y > 0, 1 for y = 0, +inf for y < 0; x = +inf the
// reverse; results beyond the float range +inf or 0 (below e^-104, as wp_exp); y = +-inf as
// pow, 1^inf = 1 included. Unlike pow: NaN for any NaN argument (pow(1, NaN) is 1) and for
// every x < 0.
// Why not the builtin: PoCL's scalar pow is a library call (extended-precision log and exp:
// a third of the Phong model's shade time on the built-in box), and its pow(float8) differs
// from the scalar pow in some lanes; the lane form wp_pow8 (lanes.h) gives these bits.
WP_FN float wp_pow(float x, float y) {
    const int denormal = x < 1.17549435e-38f;
    const float xs = denormal ? x * 16777216.0f : x;
    const int i = as_int(xs);
    float m = as_float((i & 0x007fffff) | 0x3f800000);  // [1, 2)
    const int big = m >= 1.41421356f;
    m = big ? 0.5f * m : m;
    const float fe = (float)(((i >> 23) & 0xff) - 127 - (denormal ? 24 : 0) + big);
    const float a = m - 1.0f;            // exact (Sterbenz)
    const float b = m + 1.0f;
    const float be = m - (b - 1.0f);     // m + 1 - b: the rounding error of b, exact
    const float t = a / b;
    const float tl = (fma(-t, b, a) - t * be) / b;  // a / (m + 1) - t, to first order
    const float t2 = t * t;
    float q = 0.15384615384615385f;      // 2/13
    q = 0.18181818181818182f + q * t2;   // 2/11
    q = 0.22222222222222222f + q * t2;   // 2/9
    q = 0.28571428571428571f + q * t2;   // 2/7
    q = 0.4f + q * t2;                   // 2/5
    q = 0.66666666666666667f + q * t2;   // 2/3
    const float s1 = fe * 0.693359375f, s2 = 2.0f * t;
    const float lh = s1 + s2;
    const float bv = lh - s1;
    const float l2 = ((s1 - (lh - bv)) + (s2 - bv)) + (fe * -2.12194440e-4f + (2.0f * tl + t2 * t * q));
    const float l1 = lh + l2;  // renormalised (|l2| <= |lh|): |ll| <= ulp(l1) / 2
    const float ll = l2 - (l1 - lh);
    const float zh = y * l1;
    const float zl = fma(y, l1, -zh) + y * ll;
    const float zc = zh == zh ? clamp(zh, -104.0f, 89.0f) : 0.0f;  // NaN: 1^inf (0 inf)
    const float n = floor(zc * 1.44269504088896341f + 0.5f);
    float r = zc - n * 0.693359375f;
    r = r - n * -2.12194440e-4f;
    r = r + (zc == zh ? zl : 0.0f);
    float p = wp_exp_reduced(n, r);
    const float lo = y > 0.0f ? 0.0f : (y < 0.0f ? INFINITY : 1.0f);  // x = 0
    p = x == 0.0f ? lo : p;
    p = x == INFINITY ? 1.0f / lo : p;
    return (x >= 0.0f && y == y) ? p : NAN;
}

// Normalised Phong lobe around +z with exponent e: density (e + 1) / (2π) cos^e(α) over the
// hemisphere around the lobe axis (α = angle to the axis). cos α = u1^(1 / (e + 1)).
WP_FN float3 wp_sample_phong_lobe(float u1, float u2, float exponent) {
    float cos_alpha = wp_pow(1.0f - u1, 1.0f / (exponent + 1.0f));
    return wp_spherical_local(cos_alpha, u2);
}
WP_FN float wp_phong_lobe_pdf(float cos_alpha, float exponent) {
    return cos_alpha > 0.0f ? (exponent + 1.0f) * WP_INV_2PI * wp_pow(cos_alpha, exponent) : 0.0f;
}

// Cosine-weighted over the hemisphere z > 0 (Malley's method: uniform on the unit disk,
// projected up): density cos θ / π per steradian. 1 - u1 in (0, 1]: never exactly grazing.
WP_FN float3 wp_sample_cosine_hemisphere(float u1, float u2) {
    float r = sqrt(u1);
    float sp, cp;
    wp_sincos_2pi(u2, &sp, &cp);
    return make_float3(r * cp, r * sp, sqrt(1.0f - u1));
}
WP_FN float wp_cosine_hemisphere_pdf(float cos_theta) {
    return cos_theta > 0.0f ? cos_theta * WP_INV_PI : 0.0f;
}

// Uniform on the unit disk (density 1 / π per unit area): Shirley & Chiu's concentric map,
// "A Low Distortion Map Between Disk and Square", JGT 2(3), 1997, which carries the
// square's strata to the disk with little distortion (the thin lens, camera.h).
WP_FN float2 wp_sample_concentric_disk(float u1, float u2) {
    float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
    if (a == 0.0f && b == 0.0f) return make_float2(0.0f, 0.0f);
    float r, phi;
    if (fabs(a) > fabs(b)) {
        r = a;
        phi = (0.25f * WP_PI) * (b / a);
    } else {
        r = b;
        phi = 0.5f * WP_PI - (0.25f * WP_PI) * (a / b);
    }
    return make_float2(r * cos(phi), r * sin(phi));
}

// --- GGX (Trowbridge-Reitz) microfacet distribution, local frame (+z = normal) --------
// Walter, Marschner, Li & Torrance, "Microfacet Models for Refraction through Rough
// Surfaces", EGSR 2007 (D, Smith Λ); Heitz, "Understanding the Masking-Shadowing Function
// in Microfacet-Based BRDFs", JCGT 3(2), 2014 (height-correlated G2); Heitz, "Sampling the
// GGX Distribution of Visible Normals", JCGT 7(4), 2018 (wp_ggx_sample_vndf, listing 1).
// α is the roughness (width) parameter (materials store it as given; a Phong exponent n
// maps to α = sqrt(2 / (n + 2)), Walter et al. 2007, section 5.2: wp::phong_exponent_to_alpha
// on the host, materials/glossy.h wp_ggx_alpha_to_phong on the device).

// D(h): microfacet normals per steradian per unit projected area; h.z > 0.
WP_FN float wp_ggx_d(float3 h, float alpha) {
    if (!(h.z > 0.0f)) return 0.0f;
    float a2 = alpha * alpha;
    float t = h.z * h.z * (a2 - 1.0f) + 1.0f;
    return a2 / (WP_PI * t * t);
}

// Smith Λ(w) for GGX: (-1 + sqrt(1 + α² tan² θ)) / 2.
WP_FN float wp_ggx_lambda(float3 w, float alpha) {
    float c2 = w.z * w.z;
    float s2 = max(0.0f, 1.0f - c2);
    if (!(c2 > 0.0f)) return FLT_MAX;
    return 0.5f * (-1.0f + sqrt(1.0f + alpha * alpha * s2 / c2));
}
WP_FN float wp_ggx_g1(float3 w, float alpha) { return 1.0f / (1.0f + wp_ggx_lambda(w, alpha)); }
// Height-correlated masking-shadowing G2(wo, wi) = 1 / (1 + Λ(wo) + Λ(wi)).
WP_FN float wp_ggx_g2(float3 wo, float3 wi, float alpha) {
    return 1.0f / (1.0f + wp_ggx_lambda(wo, alpha) + wp_ggx_lambda(wi, alpha));
}

// A normal of the unit hemisphere visible from the unit direction vh (vh.z > 0), the
// stretched configuration of GGX visible-normal sampling (Heitz 2018, listing 1, lines 3-12);
// wp_ggx_sample_vndf and microfacet.h unstretch it with their widths.
WP_FN float3 wp_vndf_hemisphere(float3 vh, float u1, float u2) {
    // Orthonormal basis around vh (T1 = (1, 0, 0) when vh is +z).
    float lensq = vh.x * vh.x + vh.y * vh.y;
    float3 t1 = lensq > 0.0f ? make_float3(-vh.y, vh.x, 0.0f) * (1.0f / sqrt(lensq))
                             : make_float3(1.0f, 0.0f, 0.0f);
    float3 t2 = cross(vh, t1);
    // Uniform point on the disk, warped towards the visible half.
    float r = sqrt(u1);
    float sp, cp;
    wp_sincos_2pi(u2, &sp, &cp);
    float p1 = r * cp;
    float p2 = r * sp;
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * sqrt(max(0.0f, 1.0f - p1 * p1)) + s * p2;
    // Project onto the hemisphere.
    return t1 * p1 + t2 * p2 + vh * sqrt(max(0.0f, 1.0f - p1 * p1 - p2 * p2));
}

// A microfacet normal h from the distribution of normals visible from wo (wo.z > 0):
// density D_wo(h) = G1(wo) max(0, wo·h) D(h) / wo.z (Heitz 2018, listing 1).
WP_FN float3 wp_ggx_sample_vndf(float3 wo, float alpha, float u1, float u2) {
    // Stretch the view direction to the hemisphere configuration, sample, unstretch.
    float3 vh = normalize(make_float3(alpha * wo.x, alpha * wo.y, wo.z));
    float3 nh = wp_vndf_hemisphere(vh, u1, u2);
    return normalize(make_float3(alpha * nh.x, alpha * nh.y, max(1e-6f, nh.z)));
}

// Density over solid angle of wi = reflect(-wo, h) with h from wp_ggx_sample_vndf:
// D_wo(h) / (4 wo·h) = G1(wo) D(h) / (4 wo.z).
WP_FN float wp_ggx_reflect_pdf(float3 wo, float3 wi, float alpha) {
    if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return 0.0f;
    float3 h = normalize(wo + wi);
    return wp_ggx_g1(wo, alpha) * wp_ggx_d(h, alpha) / (4.0f * wo.z);
}

// World to the local frame around unit axis n (inverse of wp_to_world).
WP_FN float3 wp_to_local(float3 w, float3 n) {
    float3 t, b;
    wp_onb(n, &t, &b);
    return make_float3(dot(w, t), dot(w, b), dot(w, n));
}

// Mirror reflection of direction d about unit normal n (d points towards the surface).
WP_FN float3 wp_reflect(float3 d, float3 n) { return d - n * (2.0f * dot(d, n)); }

WP_NAMESPACE_END

#endif  // WP_SAMPLING_H
