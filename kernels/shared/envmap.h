// envmap.h — the environment light: an equirectangular (latitude-longitude) radiance map
// infinitely far away, its lookup and its importance sampling.
//
// Mapping: exactly Mitsuba 3's `envmap` emitter (mitsuba3 src/emitters/envmap.cpp,
// EnvironmentMapEmitter::direction_to_uv / uv_to_direction / eval_spectrum), read at commit
// 0179ad9f28b580b15c75032afdef8036bfac7f09:
//   * d = to_local · dir, to_local the inverse of the map's rotation to_world (Mitsuba's
//     eval: m_to_world.inverse() * (-si.wi), -wi being the escaped ray's direction);
//   * u = atan2(d.x, -d.z) / (2π), v = acos(d.y) / π (d.y clamped to [-1, 1]): v = 0 at
//     +y (up; image row 0), v = 1 at -y; u = 0 at -z and grows towards +x (u = 1/4 at +x,
//     1/2 at +z, 3/4 at -x). Inverse: θ = π v, φ = 2π u,
//     d = (sin φ sin θ, cos θ, -cos φ sin θ).
//   * Filtering, bilinear on Mitsuba's grid: the W x H image is a grid of samples whose
//     column i sits at u = (i + 1/2) / W (u wraps: between the last column and the first,
//     Mitsuba's extra periodic column) and whose row j sits at v = j / (H - 1): rows 0 and
//     H - 1 lie on the poles themselves, not half a texel inside (Mitsuba: uv.x -= 0.5 / W,
//     uv -= floor(uv), uv *= (W, H - 1), pos = min(floor(uv), (W - 1, H - 2))). So
//       x = frac(u - 0.5 / W) · W, i0 = min(floor x, W - 1), i1 = (i0 + 1) mod W
//       y = v · (H - 1),         j0 = min(floor y, H - 2), j1 = j0 + 1
//     and L = lerp_y(lerp_x(T[j0][i0], T[j0][i1]), lerp_x(T[j1][i0], T[j1][i1])) · scale.
//     v needs no wrap or clamp on this grid; it is clamped to [0, 1] against rounding
//     (Mitsuba's `uv -= floor(uv)` would send exactly v = 1, the -y pole, to row 0; here
//     it reads row H - 1). A map of one row (H = 1, which Mitsuba refuses) is constant in
//     v. Mitsuba blends with fmadd; here a·(1 - f) + b·f rounds twice (no contraction).
//
// Sampling: a piecewise-constant 2D distribution (pbrt-v4 PiecewiseConstant2D; Pharr,
// Jakob & Humphreys, "Physically Based Rendering", 4th ed., 12.5.2 and A.5.6) over the
// CELLS of the grid above: cell (r, c), r in [0, R), R = max(H - 1, 1), c in [0, W), spans
// v in [r / R, (r + 1) / R) and u in [(c + 1/2) / W, (c + 3/2) / W) (mod 1); its corners
// are the four texels the bilinear lookup blends there. Its weight (scene/envmap.cpp) is
// the largest Rec. 709 luminance of those four corners times sin θ at the cell's centre
// row, so every direction with non-zero bilinear radiance has non-zero density (the
// bilinear value inside a cell never exceeds its largest corner, and is zero only where
// all four corners are). Tables (floats):
//   marginal[r]            inclusive CDF over the R cell rows, last entry exactly 1
//   conditional[r * W + c] inclusive CDF over the W cells of row r, last entry exactly 1
//                          (all 0 for a row of zero weight)
// A black map has all-zero tables: wp_env_sample returns *pdf = 0 and wp_env_pdf 0.
// Row and cell probabilities are the float differences of consecutive CDF entries, the
// widths the binary search draws from, so sample and pdf agree to float rounding. The
// density per unit (u, v) area of cell (r, c) is P(r) P(c | r) · W · R, and per unit solid
// angle p(ω) = p(u, v) / (2π² sin θ) (dω = 2π du · π dv · sin θ); directions with
// sin θ = 0 (the poles, a null set) get density 0.
#ifndef WP_ENVMAP_H
#define WP_ENVMAP_H

#include "sampling.h"
#include "types.h"

WP_NAMESPACE_BEGIN

// The environment as the kernels see it: its EnvData and three device arrays (the texels,
// row 0 = top = +y, row-major, xyz linear RGB; the two CDF tables described above).
typedef struct EnvLight {
    EnvData data;
    WP_GLOBAL const float4* texels;
    WP_GLOBAL const float* marginal;
    WP_GLOBAL const float* conditional;
} EnvLight;

#define WP_ENV_PI 3.14159265358979323846f
#define WP_ENV_INV_PI 0.31830988618379067154f
#define WP_ENV_INV_2PI 0.15915494309189533577f
#define WP_ENV_INV_2PI2 0.05066059182116888572f  // 1 / (2π²)
#define WP_ENV_ONE_MINUS_EPS 0.99999994f        // the largest float below 1

// Rows of the sampling cells: H - 1, or 1 for a map of one row.
WP_FN int wp_env_cell_rows(int height) { return height > 1 ? height - 1 : 1; }

// World direction -> map frame (rows of to_local) and back (its transpose: a rotation).
WP_FN float3 wp_env_to_local(EnvData d, float3 w) {
    return make_float3(dot(wp_xyz(d.to_local0), w), dot(wp_xyz(d.to_local1), w),
                       dot(wp_xyz(d.to_local2), w));
}
WP_FN float3 wp_env_to_world(EnvData d, float3 l) {
    return wp_xyz(d.to_local0) * l.x + wp_xyz(d.to_local1) * l.y + wp_xyz(d.to_local2) * l.z;
}

// Mitsuba's direction_to_uv of a unit map-frame direction: u in [-1/2, 1/2], v in [0, 1].
WP_FN float2 wp_env_direction_to_uv(float3 d) {
    float u = atan2(d.x, -d.z) * WP_ENV_INV_2PI;
    float v = acos(clamp(d.y, -1.0f, 1.0f)) * WP_ENV_INV_PI;
    return make_float2(u, min(v, 1.0f));
}

// The continuous column coordinate of u on the grid: frac(u - 1/(2W)) · W, in [0, W].
WP_FN float wp_env_column_coord(float u, int width) {
    float x = u - 0.5f / (float)width;
    x = x - floor(x);
    return x * (float)width;
}

// Bilinear radiance at (u, v) (u any real, v in [0, 1]), before the scale.
WP_FN float3 wp_env_lookup(EnvLight env, float u, float v) {
    int w = env.data.width, h = env.data.height;
    float x = wp_env_column_coord(u, w);
    int i0 = min((int)x, w - 1);
    int i1 = i0 + 1 < w ? i0 + 1 : 0;
    float fx = x - (float)i0;
    float y = clamp(v, 0.0f, 1.0f) * (float)(h - 1);
    int j0 = max(min((int)y, h - 2), 0);
    int j1 = min(j0 + 1, h - 1);
    float fy = min(y - (float)j0, 1.0f);
    float4 t00 = env.texels[j0 * w + i0], t10 = env.texels[j0 * w + i1];
    float4 t01 = env.texels[j1 * w + i0], t11 = env.texels[j1 * w + i1];
    float4 top = t00 * (1.0f - fx) + t10 * fx;
    float4 bottom = t01 * (1.0f - fx) + t11 * fx;
    return wp_xyz(top * (1.0f - fy) + bottom * fy);
}

// Radiance arriving from unit world direction dir (the direction of a ray that left the
// scene): bilinear, times scale.
WP_FN float3 wp_env_radiance(EnvLight env, float3 dir) {
    float2 uv = wp_env_direction_to_uv(wp_env_to_local(env.data, dir));
    return wp_env_lookup(env, uv.x, uv.y) * wp_xyz(env.data.scale);
}


// The probability of entry k of an inclusive CDF: cdf[k] - cdf[k - 1].
WP_FN float wp_env_pmf(WP_GLOBAL const float* cdf, int k) {
    return k > 0 ? cdf[k] - cdf[k - 1] : cdf[0];
}

// A unit world direction drawn with density *pdf per unit solid angle from u1, u2 in
// [0, 1); *pdf = 0 means no sample (a black map, or a direction exactly on a pole).
WP_FN float3 wp_env_sample(EnvLight env, float u1, float u2, float* pdf) {
    int w = env.data.width, rows = wp_env_cell_rows(env.data.height);
    *pdf = 0.0f;
    if (!(env.marginal[rows - 1] > 0.0f)) return wp_env_to_world(env.data, make_float3(0.0f, 1.0f, 0.0f));
    u1 = clamp(u1, 0.0f, WP_ENV_ONE_MINUS_EPS);
    u2 = clamp(u2, 0.0f, WP_ENV_ONE_MINUS_EPS);
    // Row, then the cell within it; the remainder of each u, rescaled, places the
    // direction inside the cell.
    int r = wp_cdf_pick(env.marginal, rows, u1);
    float row_lo = r > 0 ? env.marginal[r - 1] : 0.0f;
    float p_row = env.marginal[r] - row_lo;
    float dv = min((u1 - row_lo) / p_row, WP_ENV_ONE_MINUS_EPS);
    WP_GLOBAL const float* cond = env.conditional + r * w;
    int c = wp_cdf_pick(cond, w, u2);
    float cell_lo = c > 0 ? cond[c - 1] : 0.0f;
    float p_cell = cond[c] - cell_lo;
    float du = min((u2 - cell_lo) / p_cell, WP_ENV_ONE_MINUS_EPS);
    float u = ((float)c + du + 0.5f) / (float)w;
    if (u >= 1.0f) u -= 1.0f;
    float v = ((float)r + dv) / (float)rows;
    float theta = WP_ENV_PI * v, phi = 2.0f * WP_ENV_PI * u;
    float sin_theta = sin(theta), cos_theta = cos(theta);
    float3 d = make_float3(sin(phi) * sin_theta, cos_theta, -cos(phi) * sin_theta);
    if (sin_theta > 0.0f)
        *pdf = p_row * p_cell * (float)(w * rows) * WP_ENV_INV_2PI2 / sin_theta;
    return wp_env_to_world(env.data, d);
}

// The density per unit solid angle with which wp_env_sample draws unit world direction dir.
WP_FN float wp_env_pdf(EnvLight env, float3 dir) {
    int w = env.data.width, rows = wp_env_cell_rows(env.data.height);
    if (!(env.marginal[rows - 1] > 0.0f)) return 0.0f;
    float3 d = wp_env_to_local(env.data, dir);
    float sin2 = d.x * d.x + d.z * d.z;
    if (!(sin2 > 0.0f)) return 0.0f;
    float2 uv = wp_env_direction_to_uv(d);
    int c = min((int)wp_env_column_coord(uv.x, w), w - 1);
    int r = min((int)(uv.y * (float)rows), rows - 1);
    float p = wp_env_pmf(env.marginal, r) * wp_env_pmf(env.conditional + r * w, c);
    return p * (float)(w * rows) * WP_ENV_INV_2PI2 / sqrt(sin2);
}

WP_NAMESPACE_END

#endif  // WP_ENVMAP_H
