// microfacet.h — the microfacet distributions of the rough material kinds (roughconductor,
// roughdielectric, roughplastic) and the conductor Fresnel term.
//
// Local frame: +z is the (shading) normal, x is wp_onb(n)'s t (sampling.h). Anisotropic
// roughness runs along the surface's dp/du projected onto the shading plane (Mitsuba 3's and
// pbrt-v4's shading frame: dp/du from the uvs, p1 − p0 on meshes without uvs), which the
// shade stage gives as (cos, sin) in the local frame (MaterialData.aniso_cos/_sin).
// Distributions, anisotropic with widths α_x, α_y:
//   GGX (Trowbridge-Reitz): D(h) = 1 / (π α_x α_y (h_x²/α_x² + h_y²/α_y² + h_z²)²),
//     Λ(w) = (−1 + sqrt(1 + (α_x² w_x² + α_y² w_y²) / w_z²)) / 2 (Walter et al. 2007; Heitz 2014);
//   Beckmann: D(h) = exp(−(h_x²/α_x² + h_y²/α_y²) / h_z²) / (π α_x α_y h_z⁴),
//     Λ(w) = (erf(a) − 1) / 2 + exp(−a²) / (2 a sqrt(π)), a = w_z / sqrt(α_x² w_x² + α_y² w_y²).
// Masking-shadowing G(wo, wi): height-correlated 1 / (1 + Λ(wo) + Λ(wi)) (Heitz 2014; pbrt-v4)
// or separable G1(wo) G1(wi) (Mitsuba 3), per material (WP_MF_SEPARABLE_G).
// Visible normals (density D_w(h) = G1(w) max(0, w·h) D(h) / w_z): GGX by Heitz 2018
// ("Sampling the GGX Distribution of Visible Normals", JCGT 7(4)), Beckmann by the
// stretch-and-sample-slopes method (Heitz & d'Eon 2014) with Jakob's 2014 slope sampler (the
// bisection-safeguarded Newton inversion of Mitsuba 0.5; Mitsuba 3 runs three plain Newton
// steps from another first guess: the same density). Tests: tests/test_materials_conductor.cpp;
// models, energy and the comparison with Mitsuba 3: docs/materials.md.
#ifndef WP_MICROFACET_H
#define WP_MICROFACET_H

#include "sampling.h"
#include "types.h"

WP_NAMESPACE_BEGIN

// A material's distribution: widths along x and y, Beckmann or GGX, separable G or not.
// An anisotropic distribution's axes: α_x runs along (c, s) of the local frame (shade sets
// MaterialData.aniso_cos/_sin per hit to the surface's dp/du; (1, 0) otherwise).
typedef struct Microfacet {
    float ax, ay;
    int beckmann;
    int separable;
    float c, s;
} Microfacet;

WP_FN Microfacet wp_microfacet(MaterialData m) {
    Microfacet mf;
    mf.ax = m.alpha;
    mf.ay = m.alpha_v;
    mf.beckmann = (m.flags & WP_MF_BECKMANN) != 0;
    mf.separable = (m.flags & WP_MF_SEPARABLE_G) != 0;
    int axes = m.alpha != m.alpha_v && (m.aniso_cos != 0.0f || m.aniso_sin != 0.0f);
    mf.c = axes ? m.aniso_cos : 1.0f;
    mf.s = axes ? m.aniso_sin : 0.0f;
    return mf;
}

// A local direction in the distribution's axes, and back (rotations about z; isotropic
// distributions skip them, their D and Λ do not depend on the azimuth).
WP_FN float3 wp_mf_to_axes(Microfacet mf, float3 v) {
    if (mf.ax == mf.ay) return v;
    return make_float3(mf.c * v.x + mf.s * v.y, mf.c * v.y - mf.s * v.x, v.z);
}
WP_FN float3 wp_mf_from_axes(Microfacet mf, float3 v) {
    if (mf.ax == mf.ay) return v;
    return make_float3(mf.c * v.x - mf.s * v.y, mf.s * v.x + mf.c * v.y, v.z);
}

// D(h): microfacet normals per steradian per unit projected area; 0 for h_z <= 0.
WP_FN float wp_mf_d(Microfacet mf, float3 h) {
    if (!(h.z > 0.0f)) return 0.0f;
    h = wp_mf_to_axes(mf, h);
    float x = h.x / mf.ax, y = h.y / mf.ay;
    float z2 = h.z * h.z;
    if (mf.beckmann) {
        // exp(−e) = 0 near the horizon, where z2² may underflow too (0/0): 0.
        float ex = wp_exp(-(x * x + y * y) / z2);
        return ex > 0.0f ? ex / (WP_PI * mf.ax * mf.ay * z2 * z2) : 0.0f;
    }
    float t = x * x + y * y + z2;
    return 1.0f / (WP_PI * mf.ax * mf.ay * t * t);
}

// erf(x) in single precision, inline (no library call: Sleef's erff was 8 % of a veach-mis
// render). Chebyshev interpolants of degree 6 in x² on |x| < 1 (erf(x)/x) and of degree 14 on
// 1 <= |x| < 4, 1 beyond (1 − erf(4) = 1.5e-8 rounds away); evaluated in float: max absolute
// error 1.2e-7, max relative 1.5e-7 (~2 ulp near 1; tests/test_materials_conductor.cpp checks
// both against double over a dense sweep). NaN stays NaN.
WP_FN float wp_erf(float x) {
    float ax = fabs(x), r;
    if (ax < 1.0f) {
        float u = 2.0f * ax * ax - 1.0f;
        float p = 1.23060545e-06f;
        p = -1.76690683e-05f + p * u;
        p = 0.000217513545f + p * u;
        p = -0.0022854195f + p * u;
        p = 0.0198524967f + p * u;
        p = -0.1405361f + p * u;
        p = 0.965468764f + p * u;
        r = ax * p;
    } else if (ax < 4.0f) {
        float u = (ax - 2.5f) * (2.0f / 3.0f);
        float p = 0.000258006097f;
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
        r = p;
    } else {
        r = ax >= 4.0f ? 1.0f : ax;  // NaN: NaN
    }
    return copysign(r, x);
}

// Smith Λ(w); FLT_MAX at or below the horizon.
WP_FN float wp_mf_lambda(Microfacet mf, float3 w) {
    if (!(w.z != 0.0f)) return FLT_MAX;
    w = wp_mf_to_axes(mf, w);
    float ax = mf.ax * w.x, ay = mf.ay * w.y;
    float t2 = (ax * ax + ay * ay) / (w.z * w.z);  // (α tan θ)² along w's azimuth
    if (!mf.beckmann) return 0.5f * (-1.0f + sqrt(1.0f + t2));
    // a = 1 / sqrt(t2) > 4: Λ < 8e-9 (erf(a) rounds to 1, exp(−a²) / (2 a sqrt(π)) < 8e-9), so
    // 1 + Λ rounds to 1 and G1, G come out the same bits with Λ = 0; skips the erf and the exp
    // for most directions of smooth surfaces (α tan θ < 1/4).
    if (!(t2 >= 0.0625f)) return 0.0f;
    float a = 1.0f / sqrt(t2);
    return 0.5f * (wp_erf(a) - 1.0f) + wp_exp(-a * a) / (2.0f * a * 1.7724538509055160f);
}

WP_FN float wp_mf_g1(Microfacet mf, float3 w) {
    if (!(w.z > 0.0f)) return 0.0f;
    return 1.0f / (1.0f + wp_mf_lambda(mf, w));
}

// G(wo, wi) and the visible-normal density (wp_mf_pdf_vndf, below) with Λ(wo), G1(w) and
// D(h) passed in, for callers that need them more than once at one vertex (each is an erf and
// exps for Beckmann): equal bit for bit to wp_mf_g and wp_mf_pdf_vndf given lambda_o =
// wp_mf_lambda(mf, wo), g1 = wp_mf_g1(mf, w), d = wp_mf_d(mf, h), for wo_z > 0 and w_z > 0.
// Those two are written with these, so the formulas live here once.
WP_FN float wp_mf_g_lo(Microfacet mf, float lambda_o, float3 wi) {
    if (mf.separable) return (1.0f / (1.0f + lambda_o)) * wp_mf_g1(mf, wi);
    return 1.0f / (1.0f + lambda_o + wp_mf_lambda(mf, wi));
}

WP_FN float wp_mf_pdf_vndf_gd(float g1, float3 w, float3 h, float d) {
    return g1 * max(0.0f, dot(w, h)) * d / w.z;
}

// G(wo, wi) for directions on the normal's side (callers flip transmitted directions).
// Separable: G1(wo) G1(wi), which is 0 for wo_z <= 0 (wp_mf_g1's test, not in wp_mf_g_lo).
WP_FN float wp_mf_g(Microfacet mf, float3 wo, float3 wi) {
    if (mf.separable) return wp_mf_g1(mf, wo) * wp_mf_g1(mf, wi);
    return wp_mf_g_lo(mf, wp_mf_lambda(mf, wo), wi);
}

// ln(x) for normal, finite x > 0 (no zero, denormal, infinity or NaN handling), inline: Cephes'
// logf (x = m 2^e, m in [√½, √2), a degree-8 polynomial in m − 1, e ln 2 in two parts); max
// relative error 8.2e-8 over [2^-24, 4] (tests/test_materials_conductor.cpp sweeps it).
WP_FN float wp_log_normal(float x) {
    int i = as_int(x);
    int e = ((i >> 23) & 0xff) - 126;
    float m = as_float((i & 0x007fffff) | 0x3f000000);  // [0.5, 1)
    if (m < 0.70710678f) {
        e -= 1;
        m = m + m - 1.0f;
    } else {
        m = m - 1.0f;
    }
    float z = m * m;
    float y = 7.0376836292e-2f;
    y = -1.1514610310e-1f + y * m;
    y = 1.1676998740e-1f + y * m;
    y = -1.2420140846e-1f + y * m;
    y = 1.4249322787e-1f + y * m;
    y = -1.6668057665e-1f + y * m;
    y = 2.0000714765e-1f + y * m;
    y = -2.4999993993e-1f + y * m;
    y = 3.3333331174e-1f + y * m;
    y = y * m * z;
    float fe = (float)e;
    y += -2.12194440e-4f * fe;
    y += -0.5f * z;
    return (m + y) + 0.693359375f * fe;
}

// erf⁻¹(x) for x in (−1, 1) in single precision (Giles 2010, "Approximating the erfinv
// function", the float version; relative error ~ 4e-7 inside the domain).
WP_FN float wp_erfinv(float x) {
    // In (−1, 1) the product is >= 2^-23; the floor only keeps wp_log_normal's domain at
    // x = ±1 (a sampler's bracket end), where it gives erfinv(1 − 2^-25) ≈ 3.9 instead of a
    // log(0) that wp_log_normal does not handle.
    float w = -wp_log_normal(max((1.0f - x) * (1.0f + x), 0x1p-24f));
    float p;
    if (w < 5.0f) {
        w = w - 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = sqrt(w) - 3.0f;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return p * x;
}

// atan2(y, x) for y >= 0, x >= 0 (θ in [0, π/2]; (0, 0) gives 0), inline: an odd polynomial of
// degree 11 in min/max (max error 1.9e-6 rad; tests/test_materials_conductor.cpp checks it).
// For first guesses only.
WP_FN float wp_atan2_guess(float y, float x) {
    float lo = min(x, y), hi = max(x, y);
    float z = hi > 0.0f ? lo / hi : 0.0f, z2 = z * z;
    float r = z * (0.99997726f + z2 * (-0.33262347f + z2 * (0.19354346f +
                   z2 * (-0.11643287f + z2 * (0.05265332f - 0.01172120f * z2)))));
    return y > x ? 1.5707963267948966f - r : r;
}

// A slope (x̃, ỹ) of the isotropic unit-width Beckmann distribution of slopes visible from a
// direction (sin θ, 0, cos θ) (Jakob 2014, "An Improved Visible Normal Sampling Routine for the
// Beckmann Distribution": the x̃ marginal's CDF inverted by a bisection-safeguarded Newton
// iteration in the erf domain; ỹ is independent, Gaussian). Exact down to θ = 0 (tan θ = 0:
// the CDF is linear in the erf domain and the first guess solves it), so normal incidence needs
// no special case; sin θ is passed in, since sqrt(1 − cos²θ) loses it near the normal.
WP_FN float2 wp_beckmann_sample_slope11(float cos_theta, float sin_theta, float u1, float u2) {
    const float inv_sqrt_pi = 0.56418958354775628f;
    float tan_theta = sin_theta / cos_theta, cot_theta = cos_theta / sin_theta;  // cot: inf at θ = 0
    float a = -1.0f, c = wp_erf(cot_theta);
    float ux = max(u1, 1e-6f);
    // Initial guess: Jakob's fit of the inverse CDF. Only a guess (the iteration below decides
    // the result), so θ and the power are computed cheaply: θ by wp_atan2_guess (error < 2e-6
    // rad), (1 − u)^fit as exp(fit log(1 − u)) (pow's extended-precision library path cost
    // more than the rest of the sampler's first guess together).
    float theta = wp_atan2_guess(sin_theta, cos_theta);
    float fit = 1.0f + theta * (-0.876f + theta * (0.4265f - 0.0594f * theta));
    float b = c - (1.0f + c) * wp_exp(fit * wp_log_normal(1.0f - ux));  // 1 − u >= 2^-24
    float norm = 1.0f / (1.0f + c + inv_sqrt_pi * tan_theta * wp_exp(-cot_theta * cot_theta));
    for (int it = 0; it < 10; ++it) {
        if (!(b >= a && b <= c)) b = 0.5f * (a + c);
        float x = wp_erfinv(b);
        float value = norm * (1.0f + b + inv_sqrt_pi * tan_theta * wp_exp(-x * x)) - ux;
        if (fabs(value) < 1e-5f) break;
        float derivative = norm * (1.0f - x * tan_theta);
        if (value > 0.0f)
            c = b;
        else
            a = b;
        b -= value / derivative;
    }
    return make_float2(wp_erfinv(b), wp_erfinv(2.0f * max(u2, 1e-6f) - 1.0f));
}

// A microfacet normal h with density D_w(h) = G1(w) max(0, w·h) D(h) / w_z (w_z > 0).
WP_FN float3 wp_mf_sample_vndf(Microfacet mf, float3 w, float u1, float u2) {
    w = wp_mf_to_axes(mf, w);
    // Stretch the direction to the unit-width configuration.
    float3 wh = normalize(make_float3(mf.ax * w.x, mf.ay * w.y, w.z));
    if (mf.beckmann) {
        // Slopes of the unit distribution seen from wh, rotated to wh's azimuth, unstretched.
        // sin θ and the azimuth from wh's x and y (exact near the normal, unlike 1 − cos²θ).
        float sin_t = sqrt(wh.x * wh.x + wh.y * wh.y);
        float cphi = sin_t > 0.0f ? wh.x / sin_t : 1.0f, sphi = sin_t > 0.0f ? wh.y / sin_t : 0.0f;
        float2 s = wp_beckmann_sample_slope11(wh.z, sin_t, u1, u2);
        float sx = (cphi * s.x - sphi * s.y) * mf.ax;
        float sy = (sphi * s.x + cphi * s.y) * mf.ay;
        return wp_mf_from_axes(mf, normalize(make_float3(-sx, -sy, 1.0f)));
    }
    // GGX: Heitz 2018, listing 1 (sampling.h).
    float3 nh = wp_vndf_hemisphere(wh, u1, u2);
    return wp_mf_from_axes(mf, normalize(make_float3(mf.ax * nh.x, mf.ay * nh.y, max(1e-6f, nh.z))));
}

// The density of wp_mf_sample_vndf: D_w(h) = G1(w) max(0, w·h) D(h) / w_z.
WP_FN float wp_mf_pdf_vndf(Microfacet mf, float3 w, float3 h) {
    if (!(w.z > 0.0f)) return 0.0f;
    return wp_mf_pdf_vndf_gd(wp_mf_g1(mf, w), w, h, wp_mf_d(mf, h));
}

// Fresnel reflectance of a conductor with complex index of refraction η + i k (per channel,
// relative to the outside) for unpolarised light at cos θ_i = cos_i (exact: pbrt-v3's
// FrConductor, equal to pbrt-v4's FrComplex and Mitsuba 3's fresnel_conductor).
// With a + i b = sqrt(η² − k² − sin²θ + 2iηk): a² = (|.| + t0) / 2 cancels when t0 < 0 (small η,
// large k: silver, copper, gold in red), so a = ηk / b there (a b = ηk); 0/0 in r_s (η = 1, k = 0
// at grazing) gives 1, the limit of every other index.
WP_FN float wp_fresnel_conductor1(float cos_i, float eta, float k) {
    float c = clamp(cos_i, 0.0f, 1.0f);
    float c2 = c * c, s2 = 1.0f - c2;
    float eta2 = eta * eta, k2 = k * k;
    float t0 = eta2 - k2 - s2;
    float a2b2 = sqrt(t0 * t0 + 4.0f * eta2 * k2);
    float t1 = a2b2 + c2;
    float ek = fabs(eta * k);
    float a = t0 >= 0.0f ? sqrt(0.5f * (a2b2 + t0)) : (ek > 0.0f ? ek / sqrt(0.5f * (a2b2 - t0)) : 0.0f);
    float t2 = 2.0f * c * a;
    float rs = t1 + t2 > 0.0f ? (t1 - t2) / (t1 + t2) : 1.0f;
    float t3 = c2 * a2b2 + s2 * s2;
    float t4 = t2 * s2;
    float rp = rs * (t3 - t4) / (t3 + t4);
    return 0.5f * (rp + rs);
}

WP_FN float3 wp_fresnel_conductor(float cos_i, float3 eta, float3 k) {
    return make_float3(wp_fresnel_conductor1(cos_i, eta.x, k.x),
                       wp_fresnel_conductor1(cos_i, eta.y, k.y),
                       wp_fresnel_conductor1(cos_i, eta.z, k.z));
}

WP_NAMESPACE_END

#endif  // WP_MICROFACET_H
