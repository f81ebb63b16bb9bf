// shading.h — the shading frame at a hit: interpolated and normal-mapped shading normals,
// and the guards that keep them from creating or leaking energy.
//
// Geometric normals decide sides (front/back, which side a ray leaves from, whether a
// direction is a reflection or a transmission); the shading normal only shapes the BSDF.
// Three known failure modes of shading normals and what wavepath does about each:
//   1. The viewer sees the back of the shading normal (dot(wo, ns) <= 0 while wo is on the
//      geometric front): the BSDF would be evaluated below its own horizon. And, milder,
//      the mirror direction of wo about ns points below the geometric surface, so specular
//      and glossy lobes would send most of their energy into the surface.
//      wp_bend_normal tilts ns towards ng, just enough that the mirror direction of wo lies
//      WP_BEND_EPS above the geometric tangent plane (the "bent normal" of Keller et al.,
//      "The Iray Light Transport Simulation and Rendering System", 2017, appendix A.3).
//      shade bends for every lobe where the viewer sees the back of ns, and for the kinds
//      whose lobes follow the mirror direction (mirror, glossy, glass) also where only that
//      direction falls below; a diffuse lobe does not depend on it, so where the viewer sees
//      the front its shading normal is left as the file gave it (as Mitsuba 3 renders it).
//   2. A sampled direction on the other geometric side than the BSDF meant (a reflection
//      below the surface or a transmission that stays above it): wp_same_side rejects it and
//      the path is absorbed: energy is lost, never leaked through the surface. Light
//      samples are likewise taken only on the geometric side the BSDF lobe is on.
//   3. The shadow terminator on coarse meshes: smooth normals light faces that the
//      geometry shadows, giving a hard, faceted terminator. wp_terminator_factor is the
//      smooth shadowing term of Chiang, Li & Burley, "Taming the Shadow Terminator"
//      (SIGGRAPH 2019 talks): G = min(1, dot(ng, wi) / (dot(ns, wi) dot(ng, ns))),
//      factor = -G³ + G² + G, applied to the non-specular reflection of light (light samples
//      and sampled bounces) where the shading normal is interpolated; not where a normal map
//      sets it, whose shading is kept as authored (Mitsuba 3 and pbrt-v4 apply no factor).
#ifndef WP_SHADING_H
#define WP_SHADING_H

#include "types.h"

WP_NAMESPACE_BEGIN

// The mirror direction of a bent normal is at least this far (cosine) above the geometric
// tangent plane.
#define WP_BEND_EPS 1e-3f

// The barycentric interpolation (1 - u - v) a + u b + v c of a per-vertex float4 row.
WP_FN float3 wp_interpolate3(float4 a, float4 b, float4 c, float u, float v) {
    return wp_xyz(a) * (1.0f - u - v) + wp_xyz(b) * u + wp_xyz(c) * v;
}

// The texture coordinates at barycentrics (u, v) of a triangle.
WP_FN float2 wp_interpolate_uv(TriUVs t, float u, float v) {
    float w = 1.0f - u - v;
    return make_float2(w * t.uv01.x + u * t.uv01.z + v * t.uv2.x,
                       w * t.uv01.y + u * t.uv01.w + v * t.uv2.y);
}

// The interpolated shading normal of a triangle (unit), turned to the hemisphere of the
// unit geometric normal ng_front (the front face's); ng_front itself where the triangle has
// none (zero normals) or they cancel.
WP_FN float3 wp_interpolated_normal(TriNormals tn, float u, float v, float3 ng_front) {
    float3 n = wp_interpolate3(tn.n0, tn.n1, tn.n2, u, v);
    float l2 = dot(n, n);
    if (!(l2 > 1e-30f) || !isfinite(l2)) return ng_front;
    n = n * (1.0f / sqrt(l2));
    return dot(n, ng_front) < 0.0f ? -n : n;
}

// The normal of a tangent-space normal map: m is the map's value in [-1, 1]^3 (xy already
// scaled), n the unit shading normal and t the tangent (xyz) with the bitangent sign in w
// (b = w cross(n, t), glTF / MikkTSpace). A degenerate tangent or map value leaves n.
WP_FN float3 wp_apply_normal_map(float3 n, float4 t, float3 m) {
    float3 tt = wp_xyz(t);
    tt = tt - n * dot(n, tt);  // Gram-Schmidt against the shading normal
    float tl2 = dot(tt, tt);
    if (!(tl2 > 1e-30f) || !isfinite(tl2)) return n;
    tt = tt * (1.0f / sqrt(tl2));
    float3 b = cross(n, tt) * (t.w < 0.0f ? -1.0f : 1.0f);
    float3 r = tt * m.x + b * m.y + n * m.z;
    float l2 = dot(r, r);
    if (!(l2 > 1e-30f) || !isfinite(l2)) return n;
    return r * (1.0f / sqrt(l2));
}

// Failure mode 1: ns (unit) turned so that the mirror direction of wo about it lies at
// least WP_BEND_EPS above the plane of ng. wo (unit, towards the viewer) and ng (unit) are
// on the same side: dot(wo, ng) > 0. Returns ns unchanged when it already is.
WP_FN float3 wp_bend_normal(float3 ns, float3 ng, float3 wo) {
    float c = dot(wo, ns);
    float3 r = ns * (2.0f * c) - wo;  // mirror direction of wo
    if (c > 0.0f && dot(r, ng) >= WP_BEND_EPS) return ns;
    // Lift the mirror direction to the minimum elevation, then the half vector of wo and it
    // is the normal that mirrors wo there.
    float3 rt = r - ng * dot(r, ng);  // tangential part
    float tl2 = dot(rt, rt);
    float3 r2;
    if (tl2 > 1e-20f) {
        r2 = rt * (sqrt(1.0f - WP_BEND_EPS * WP_BEND_EPS) / sqrt(tl2)) + ng * WP_BEND_EPS;
    } else {
        r2 = ng;
    }
    float3 h = wo + r2;
    float hl2 = dot(h, h);
    if (!(hl2 > 1e-30f)) return ng;
    return h * (1.0f / sqrt(hl2));
}

// Failure mode 2: a direction w leaving the surface is on the geometric side the BSDF
// lobe meant: reflections (dot(w, ns) > 0) above the geometric plane, transmissions below.
// ns and ng are on the same side (the side of arrival).
WP_FN int wp_same_side(float3 w, float3 ns, float3 ng) {
    return (dot(w, ns) > 0.0f) == (dot(w, ng) > 0.0f);
}

// Failure mode 3: Chiang et al.'s shadowing factor in [0, 1] for light arriving from wi
// (unit) at a point with geometric normal ng and shading normal ns (unit, same side, wi on
// their side). 1 when ns = ng.
WP_FN float wp_terminator_factor(float3 ng, float3 ns, float3 wi) {
    float nsi = dot(ns, wi), ngs = dot(ng, ns);
    if (!(nsi > 0.0f) || !(ngs > 0.0f)) return 1.0f;
    float g = min(1.0f, dot(ng, wi) / (nsi * ngs));
    if (!(g > 0.0f)) return 0.0f;
    return g * (1.0f + g * (1.0f - g));  // -g³ + g² + g
}

WP_NAMESPACE_END

#endif  // WP_SHADING_H
