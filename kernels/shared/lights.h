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
//   light_pairs[t]    LightPair per triangle (scene order), with WP_HAVE_LIGHT_PAIRS only:
//                     its back-to-back partner and the density the partner's samples add
//                     (below; scene/light_pairs.h)
// A point is uniform on the chosen triangle (Shirley & Chiu's square-root warp, in
// "A Low Distortion Map Between Disk and Square", JGT 2(3), 1997 / pbrt-v4
// SampleUniformTriangle), so its density per unit area is P(choose) / area; over solid
// angle at a receiver x it is pdf_area · |y − x|² / cos θ_light (Veach 1997, eq. 8.10).
#ifndef WP_LIGHTS_H
#define WP_LIGHTS_H

#include "sampling.h"
#include "types.h"

// Back-to-back light pairs (scene/light_pairs.h): compiled only for scenes whose light
// triangles have partners.
#ifndef WP_HAVE_LIGHT_PAIRS
#define WP_HAVE_LIGHT_PAIRS 0
#endif

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

// Light triangle t (frame normal from tri_frames, vertex v0) faces away from x: x is not
// strictly in front of its plane, so none of its points emits towards x (one-sided lights).
// The one facing test of the pairs, at both ends of MIS.
WP_FN int wp_light_faces_away(WP_GLOBAL const Triangle* tris, WP_GLOBAL const float4* tri_frames, int t, float3 x) {
    return !(dot(wp_xyz(tri_frames[t]), x - wp_xyz(tris[t].v0)) > 0.0f);
}

// The density per unit area with which light sampling from x draws a point of light
// triangle s that faces x: P(s) / A(s), plus P(partner) / A(s) where the partner faces
// away (its samples move to s). pdf_area: light_pdf_area.
WP_FN float wp_light_pdf_area(WP_GLOBAL const float* pdf_area, WP_GLOBAL const LightPair* pairs,
                              WP_GLOBAL const Triangle* tris, WP_GLOBAL const float4* tri_frames, int s,
                              float3 x) {
    float p = pdf_area[s];
#if WP_HAVE_LIGHT_PAIRS
    const LightPair q = pairs[s];
    if (q.partner >= 0 && wp_light_faces_away(tris, tri_frames, q.partner, x)) p += q.pdf;
#else
    (void)pairs, (void)tris, (void)tri_frames, (void)x;
#endif
    return p;
}

#if WP_HAVE_LIGHT_PAIRS
// wp_light_pair_choose's answer from its facing tests: pt = pairs[t]; q_away, whether t's
// partner faces away from x; t_away, whether t does (read only where q_away is 0).
WP_FN int wp_light_pair_decide(WP_GLOBAL const float* pdf_area, WP_GLOBAL const LightPair* pairs, int t,
                               LightPair pt, int q_away, int t_away, float* pdf) {
    if (pt.partner < 0) {
        *pdf = pdf_area[t];
        return t;
    }
    const int q = pt.partner;
    if (!q_away && t_away) {
        *pdf = pdf_area[q] + pairs[q].pdf;  // t, q's partner, faces away
        return q;
    }
    *pdf = q_away ? pdf_area[t] + pt.pdf : pdf_area[t];
    return t;
}

// The light triangle whose point light sampling from x uses, given the table's pick t: its
// partner, at the same barycentric coordinates, when t faces away from x and the partner
// does not; else t itself. *pdf: wp_light_pdf_area of that triangle, from the same two
// facing tests (pairs are mutual: the partner's partner is t). x: the origin of the rays
// that leave the receiver on its arrival side (reflections), the point the BSDF side of MIS
// sees too.
WP_FN int wp_light_pair_choose(WP_GLOBAL const float* pdf_area, WP_GLOBAL const LightPair* pairs,
                               WP_GLOBAL const Triangle* tris, WP_GLOBAL const float4* tri_frames, int t,
                               float3 x, float* pdf) {
    const LightPair pt = pairs[t];
    const int q_away = pt.partner >= 0 && wp_light_faces_away(tris, tri_frames, pt.partner, x);
    const int t_away = pt.partner >= 0 && !q_away && wp_light_faces_away(tris, tri_frames, t, x);
    return wp_light_pair_decide(pdf_area, pairs, t, pt, q_away, t_away, pdf);
}
#endif

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
