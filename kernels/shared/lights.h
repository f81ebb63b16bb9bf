// lights.h — next-event estimation to emissive triangles: light choice and point sampling.
//
// The host (scene/upload: build_light_table) lists every emissive triangle with positive
// area and builds a CDF over them by emitted power, area × luminance(Le) (one-sided
// emitters: the power is π · area · Le, the constant π cancels). The kernels get
//   light_cdf[k]      float, inclusive cumulative probability of lights 0..k (last = 1)
//   light_guide[j]    int, j = 0 .. guide_size: the guide table of light_cdf
//                     (sampling.h: wp_cdf_pick_guided); guide_size a power of two >= count,
//                     or 0 (no table) below WP_LIGHT_GUIDE_MIN lights
//   light_prims[k]    int, the triangle (scene order) of light k
//   light_pdf_area[t] float per triangle (scene order): P(choose t) / area(t), the density
//                     of the light point per unit area; 0 for triangles that are no light
// A point is uniform on the chosen triangle (Shirley & Chiu's square-root warp, in
// "A Low Distortion Map Between Disk and Square", JGT 2(3), 1997 / pbrt-v4
// SampleUniformTriangle), so its density per unit area is P(choose) / area; over solid
// angle at a receiver x it is pdf_area · |y − x|² / cos θ_light (Veach 1997, eq. 8.10).
#ifndef WP_LIGHTS_H
#define WP_LIGHTS_H

#include "sampling.h"

WP_NAMESPACE_BEGIN

// Light tables of at least this many lights get a guide table (scene/upload.cpp); below,
// the search alone is as quick (its steps are few, the guide's loads are extra).
#define WP_LIGHT_GUIDE_MIN 64

// The light whose CDF interval holds u in [0, 1) among n: the first k with u < cdf[k]
// (n − 1 if none). With a guide table (guide_size > 0: the host builds one from
// WP_LIGHT_GUIDE_MIN lights on) in O(1) expected steps, else by the search itself; the same
// index either way. On veach-mis (15,360 light triangles) the search's 14 dependent steps
// were 15 % of shade's samples; for the built-in box's 2 the guide's two extra dependent
// loads made shade 7 % slower (measured), hence the threshold.
WP_FN int wp_light_pick(WP_GLOBAL const float* cdf, int n, WP_GLOBAL const int* guide,
                        int guide_size, float u) {
    return guide_size > 0 ? wp_cdf_pick_guided(cdf, guide, guide_size, u) : wp_cdf_pick(cdf, n, u);
}

// Barycentric weights (b1, b2) of a uniform point on a triangle from u1, u2 in [0, 1);
// the point is (1 − b1 − b2) v0 + b1 v1 + b2 v2.
WP_FN float2 wp_sample_triangle_barycentric(float u1, float u2) {
    float s = sqrt(u1);
    return make_float2(u2 * s, 1.0f - s);
}

// Solid-angle density of a light point seen from a receiver at distance² dist2 under the
// light-side cosine cos_light (> 0 for the emitting side), from the area density.
WP_FN float wp_light_pdf_solid_angle(float pdf_area, float dist2, float cos_light) {
    return cos_light > 0.0f ? pdf_area * dist2 / cos_light : 0.0f;
}

// Power heuristic with β = 2 for one sample from each strategy (Veach & Guibas,
// "Optimally Combining Sampling Techniques for Monte Carlo Rendering", SIGGRAPH 1995):
// the weight of the strategy with density pa against the one with density pb.
WP_FN float wp_power_heuristic(float pa, float pb) {
    if (!(pa > 0.0f)) return 0.0f;
    float r = pb / pa;  // as 1 / (1 + r²): no overflow for large densities
    return 1.0f / (1.0f + r * r);
}

WP_NAMESPACE_END

#endif  // WP_LIGHTS_H
