// offset.h — hit points with an error bound, and robust origins for rays that leave them.
//
// The hit point is computed from the barycentrics as p = v0 + u e1 + v e2 with the edges
// e1 = v1 - v0, e2 = v2 - v0 (more accurate than o + t d; Wächter & Binder 2019). Its
// floating-point error against P = v0 + u (v1 - v0) + v (v2 - v0) — the exact point for
// these (u, v), which lies exactly in the triangle's plane — is bounded per component from
// the same numbers (the idea of pbrt-v4, section 6.8; this bound is our own, for this
// formula, in float without FMA, eps = 2^-24, g_n = n eps / (1 - n eps)):
//   edges rounded:      u eps |e1| + v eps |e2|
//   products rounded:   eps |u e1| + eps |v e2|
//   two sums rounded:   eps |v0 + u e1| + eps |p|  <=  eps (|v0| + |u e1|) + eps |p|
//   total              <=  g3 (|u e1| + |v e2|) + g2 (|v0| + |p|)   (g's absorb the slack)
// which is about one ulp of the point's own coordinates: 2 ulps of 1e5 when the scene sits
// at 1e5, 2 ulps of 1e-4 when it is scaled to 1e-4. No scene-size constant anywhere.
//
// A new ray starts at p moved along the geometric normal by
//   d = |n| . err  +  K eps L^3 / |e1 x e2|          (L: the longest edge)
// and then rounded one float further away. The first term puts the origin strictly on
// the side it leaves. The second covers the rounding of the ray/triangle test itself
// (shared/triangle.h): its error in t is about eps times the triangle's extent seen from
// the origin, divided by the projected area (pbrt-v4's deltaT, section 6.8.7), i.e. about
// eps L^3 / (2 area) along the normal for any ray direction. K = WP_OFFSET_TRI_K = 16:
// tests/test_hard.cpp counts 0 re-hits of the triangle left (of 967,872 secondary rays at
// four scales) already with K = 1, and 3% with K = 0; 16 is the margin for needles and
// coplanar neighbours of other sizes. It is capped at L / 1024 for needles. Both terms scale with the triangle's
// own coordinates: no scene-size constant. We do not reject close hits in the triangle
// test instead (pbrt's t > deltaT): at a concave corner that also rejects the legitimate
// hit on the adjacent wall, and the ray leaves a closed box (measured: 1 path in 98,304 of
// the furnace test).
//
// This replaces the fixed constants of Wächter & Binder (256 ulps, or 2^-16 absolute near
// the origin), which assume a scene of size ~1: they moved origins by 7.5% of a box scaled
// by 1e-4 and by its whole width at 1e5.
//
// Shadow segments (next-event estimation) run from an offset origin o to a light point y
// (from wp_hit_point, bound yerr) on a light triangle with unit normal n, as the ray
// o + t sd, sd = fl(y - o), 0 < t < tmax. Their far end needs a bound of its own: the
// triangle test works in coordinates relative to the ray's origin, so for a triangle near
// the far end its error is eps times the segment's length, not eps times the triangle's
// size as at the near end (the offset above). With S = max_i |sd_i|, L the size of the
// triangles near y, and |sx|, |sy| <= 1 (triangle.h), the errors measured along n are:
//   lateral  fl(v - o) (eps |v_i - o_i| <= eps (S + L)) and the shear x - sx z (three
//            roundings): each vertex moves sideways by <= ~5 eps (S + L) per sheared
//            coordinate, so the plane the test sees moves by <= ~7 eps (S + L);
//   depth    t = (three products summed) / det, with z rounded twice: <= ~8 eps in t,
//            which is 8 eps |sd . n| <= 14 eps S along n;
//   the end  o + sd misses y by the rounding of sd, eps |sd_i| per component: <= 3 eps S;
//   y itself |n| . yerr.
// That is <= 24 eps S, plus terms in L that wp_triangle_offset (>= 18 eps L) bounds, plus
// |n| . yerr. So the segment stops short of the light's plane by
//   h = |n| . yerr + wp_triangle_offset(light) + K_s eps S,   K_s = WP_OFFSET_SHADOW_K = 32,
// and since it nears that plane by |sd . n| per unit of t, tmax = 1 - h / |sd . n|: the
// bound scales with the segment's coordinates and, through 1 / |sd . n|, with the grazing
// angle, not with the light triangle. It holds for the light's neighbours too, whatever
// their size (a convex light's neighbours lie behind its plane, coplanar ones in it).
// Before, the segment ended at y offset by the last two terms only, which bound the error
// of a ray that starts on the light: seen from 20 radii away a 5,120-triangle sphere light
// occluded itself on 13 % of its samples (15 % of its light; docs/robustness.md). K_s
// measured, as the largest a false hit would have needed: 4.2 in tests/test_hard_lights.cpp
// (spheres of 48 and 5,120 triangles, a box of 768, at scales 1e-4 to 1e5 and translated
// by 1e5; receivers on a floor and 1.5 to 2,000 radii away), 5.3 in a longer run with
// spheres of up to 81,920 triangles; so 32 is the derivation's 24, 6 times the measurement.
// pbrt-v4 (SpawnRayTo: both ends offset, tmax = 1 - ShadowEpsilon = 1 - 1e-4) has no false
// occlusion in the same measurement either, but its end is 1e-4 |sd| short of the light
// whatever the angle, 50 to 90 times ours at normal incidence, so an occluder that close
// to the light (a shade on its bulb) casts no shadow; and it is too short where
// |sd . n| / |sd| < ~3e-3 (the error in t grows as 1 / cos), a loss of O(1e-5) of the
// light there. When h / |sd . n| exceeds 1/2 (the receiver lies in the light's
// plane to within the error) tmax stays 1/2: such a sample may be lost (its contribution
// is O(eps)), but light never leaks through an occluder in front of the receiver.
//
#ifndef WP_OFFSET_H
#define WP_OFFSET_H

#include "compat.h"

WP_NAMESPACE_BEGIN

// g_n for float (eps = 2^-24), rounded up.
#define WP_GAMMA2 1.1920930e-7f
#define WP_GAMMA3 1.7881396e-7f

// The next float towards +inf / -inf (finite inputs; -0 and +0 step to the smallest denormal).
WP_FN float wp_next_float_up(float x) {
    if (x == 0.0f) return as_float(1);
    int b = as_int(x);
    return as_float(x > 0.0f ? b + 1 : b - 1);
}

WP_FN float wp_next_float_down(float x) {
    if (x == 0.0f) return -as_float(1);
    int b = as_int(x);
    return as_float(x > 0.0f ? b - 1 : b + 1);
}

// The hit point at barycentrics (u, v) of triangle (v0, v1, v2) and its error bound *err.
WP_FN float3 wp_hit_point(float3 v0, float3 v1, float3 v2, float u, float v, float3* err) {
    float3 a = (v1 - v0) * u, b = (v2 - v0) * v;
    float3 p = (v0 + a) + b;
    *err = (fabs(a) + fabs(b)) * WP_GAMMA3 + (fabs(v0) + fabs(p)) * WP_GAMMA2;
    return p;
}

// The triangle's share of the offset (the second term above), >= 0.
#ifndef WP_OFFSET_TRI_K
#define WP_OFFSET_TRI_K 16.0f
#endif
WP_FN float wp_triangle_offset(float3 v0, float3 v1, float3 v2) {
    float3 e1 = v1 - v0, e2 = v2 - v0, e3 = v2 - v1;
    float l2 = fmax(dot(e1, e1), fmax(dot(e2, e2), dot(e3, e3)));
    float l = sqrt(l2);
    float twice_area = length(cross(e1, e2));
    float d = (WP_OFFSET_TRI_K * 5.9604645e-8f) * l * (l2 / twice_area);  // K eps L^3 / 2A
    return fmin(d, l * (1.0f / 1024.0f));  // also for zero area (d = inf or NaN)
}

// A triangle's face frame, what shading reads of it at every hit and light sample: xyz its
// unit geometric normal (of (v1 - v0) x (v2 - v0): the counter-clockwise front; none for zero
// area: OpenCL's normalize gives 0, the plain formula of compat.h NaN), w its offset share (wp_triangle_offset). The shade stage computes it once per
// triangle (shade_triangle_frames) instead of at every path vertex: two sqrt and a divide
// for the normal, two sqrt and a divide for the share, for the hit and again for the light.
WP_FN float4 wp_triangle_frame(float3 v0, float3 v1, float3 v2) {
    float3 n = normalize(cross(v1 - v0, v2 - v0));
    return make_float4(n.x, n.y, n.z, wp_triangle_offset(v0, v1, v2));
}

// The origin of a ray leaving p (with error bound err) on the side of the unit normal n,
// moved by at least `extra` (wp_triangle_offset) beyond the error bound.
WP_FN float3 wp_offset_ray_origin(float3 p, float3 err, float3 n, float extra) {
    float d = dot(fabs(n), err) + extra;
    float3 off = n * d;
    float3 o = p + off;
    o.x = off.x > 0.0f ? wp_next_float_up(o.x) : (off.x < 0.0f ? wp_next_float_down(o.x) : o.x);
    o.y = off.y > 0.0f ? wp_next_float_up(o.y) : (off.y < 0.0f ? wp_next_float_down(o.y) : o.y);
    o.z = off.z > 0.0f ? wp_next_float_up(o.z) : (off.z < 0.0f ? wp_next_float_down(o.z) : o.z);
    return o;
}

// The end (tmax) of the shadow segment o + t sd, sd = y - o, towards a light point y with
// error bound yerr on a light triangle of unit normal ln and share tri_offset
// (wp_triangle_offset): 1 - h / |sd . ln| as derived above, at least 1/2 (also for NaN).
#ifndef WP_OFFSET_SHADOW_K
#define WP_OFFSET_SHADOW_K 32.0f
#endif
WP_FN float wp_shadow_tmax(float3 sd, float3 yerr, float3 ln, float tri_offset) {
    float3 a = fabs(sd);
    float s = fmax(a.x, fmax(a.y, a.z));
    float h = dot(fabs(ln), yerr) + tri_offset + (WP_OFFSET_SHADOW_K * 5.9604645e-8f) * s;
    float dt = h / fabs(dot(sd, ln));
    return dt < 0.5f ? 1.0f - dt : 0.5f;  // dt >= K_s eps / sqrt(3): 1 - dt < 1 after rounding
}

// The end moved back to where the segment comes within `clearance` of the light point y
// (error bound yerr) on a light triangle of unit normal ln: the triangle's clearance
// (scene/light_clearance.h), the distance from it to the nearest triangle that reaches in
// front of its plane; 0 for none. The stretch cut off lies within the clearance of the
// light, where only triangles in its plane or behind it are, and a segment from the front
// (sd . ln < 0) whose end keeps a full offset before the plane (tmax not at its floor of
// 1/2, wp_shadow_tmax) never reaches those: the same occlusion, without the light's own
// part of the BVH. Other segments keep tmax. The reach is the clearance less y's error and
// 64 eps of the coordinates (the hits' error in t, far below; the host already kept 1 % of
// the clearance back). At most tmax; 0 (no hits) where the whole segment lies within it.
WP_FN float wp_shadow_end_clear(float tmax, float3 sd, float3 y, float3 yerr, float3 ln, float clearance) {
    float3 a = fabs(sd), b = fabs(y);
    float s = fmax(a.x, fmax(a.y, a.z)) + fmax(b.x, fmax(b.y, b.z));
    float reach = clearance - ((yerr.x + yerr.y) + yerr.z) - (64.0f * 5.9604645e-8f) * s;
    float t = fmax(1.0f - reach / sqrt(dot(sd, sd)), 0.0f);
    return reach > 0.0f && dot(sd, ln) < 0.0f && tmax > 0.5f ? fmin(tmax, t) : tmax;
}

WP_NAMESPACE_END

#endif  // WP_OFFSET_H
