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

// Unit direction with polar cosine cos_theta and azimuth 2π u around +z.
WP_FN float3 wp_spherical_local(float cos_theta, float u) {
    float sin_theta = sqrt(max(0.0f, 1.0f - cos_theta * cos_theta));
    float phi = 2.0f * WP_PI * u;
    return make_float3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
}

// Uniform over the hemisphere z > 0: density 1 / (2π) per steradian.
WP_FN float3 wp_sample_uniform_hemisphere(float u1, float u2) {
    return wp_spherical_local(1.0f - u1, u2);  // 1 - u1 in (0, 1]: never exactly grazing
}
WP_FN float wp_uniform_hemisphere_pdf(void) { return WP_INV_2PI; }

// Normalised Phong lobe around +z with exponent e: density (e + 1) / (2π) cos^e(α) over the
// hemisphere around the lobe axis (α = angle to the axis). cos α = u1^(1 / (e + 1)).
WP_FN float3 wp_sample_phong_lobe(float u1, float u2, float exponent) {
    float cos_alpha = pow(1.0f - u1, 1.0f / (exponent + 1.0f));
    return wp_spherical_local(cos_alpha, u2);
}
WP_FN float wp_phong_lobe_pdf(float cos_alpha, float exponent) {
    return cos_alpha > 0.0f ? (exponent + 1.0f) * WP_INV_2PI * pow(cos_alpha, exponent) : 0.0f;
}

// Mirror reflection of direction d about unit normal n (d points towards the surface).
WP_FN float3 wp_reflect(float3 d, float3 n) { return d - n * (2.0f * dot(d, n)); }

WP_NAMESPACE_END

#endif  // WP_SAMPLING_H
