// triangle.h — watertight ray/triangle intersection.
//
// Woop, Benthin, Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013.
// The ray is turned into the +z axis by a permutation (the largest direction component
// becomes z) and a shear, so each edge function is a 2D cross product of vertices that
// were transformed identically for every triangle. Two triangles sharing an edge compute
// the same products with opposite signs (FP contraction is off, see compat.h), so a ray
// cannot pass between them. Edge values of exactly 0 count as inside (a ray through a
// shared edge or vertex hits all triangles there; the tie rule below picks one). The
// paper's double-precision recomputation of zero edge values is not done: it changes
// only which triangle of several at one edge is reported, never whether one is hit.
//
// Tie rule (documented, the same on every device): among hits at equal t the smallest
// original triangle index wins.
#ifndef WP_TRIANGLE_H
#define WP_TRIANGLE_H

#include "types.h"

WP_NAMESPACE_BEGIN

#if defined(WP_PLAIN_TRIANGLES)
// Benchmark-only baseline (`wavepath bench hard`, the cost of robustness): the plain
// Möller-Trumbore test (Möller & Trumbore, "Fast, Minimum Storage Ray/Triangle
// Intersection", JGT 2(1), 1997). Not watertight: the edge tests of two triangles that
// share an edge are computed from different values, so rays can pass between them.
typedef struct TriRay {
    float4 org;  // ray origin (w = 0)
    float4 dir;  // ray direction (w = 0)
    float tmin;
} TriRay;

WP_FN TriRay wp_tri_ray(Ray ray) {
    TriRay r;
    r.org = make_float4(ray.org.x, ray.org.y, ray.org.z, 0.0f);
    r.dir = make_float4(ray.dir.x, ray.dir.y, ray.dir.z, 0.0f);
    r.tmin = ray.org.w;
    return r;
}

WP_FN int wp_intersect_triangle(const TriRay* r, float4 v0, float4 v1, float4 v2, float* t_out,
                                float* u_out, float* v_out) {
    float3 e1 = wp_xyz(v1 - v0), e2 = wp_xyz(v2 - v0);
    float3 d = wp_xyz(r->dir);
    float3 p = cross(d, e2);
    float det = dot(e1, p);
    if (det == 0.0f) return 0;
    float inv = 1.0f / det;
    float3 s = wp_xyz(r->org - v0);
    float u = dot(s, p) * inv;
    if (u < 0.0f || u > 1.0f) return 0;
    float3 q = cross(s, e1);
    float v = dot(d, q) * inv;
    if (v < 0.0f || u + v > 1.0f) return 0;
    float t = dot(e2, q) * inv;
    if (!(t > r->tmin)) return 0;
    *t_out = t;
    *u_out = u;
    *v_out = v;
    return 1;
}
#else

// Per-ray constants of the watertight test.
typedef struct TriRay {
    float4 org;  // ray origin (w = 0)
    uint4 perm;  // lane permutation (kx, ky, kz, 3)
    float sx;    // shear: -dir[kx] / dir[kz] is applied as x - sx * z
    float sy;
    float sz;    // 1 / dir[kz]
    float tmin;
} TriRay;

WP_FN TriRay wp_tri_ray(Ray ray) {
    TriRay r;
    float3 d = wp_xyz(ray.dir);
    float3 a = fabs(d);
    // kz: the dimension where the direction is largest; kx, ky the next two cyclically,
    // swapped when d[kz] < 0 to keep the winding (and so the edge-function signs).
    uint kz = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
    uint kx = kz == 2u ? 0u : kz + 1u;
    uint ky = kx == 2u ? 0u : kx + 1u;
    float dz = wp_component(d, (int)kz);
    if (dz < 0.0f) {
        uint t = kx;
        kx = ky;
        ky = t;
    }
    r.org = make_float4(ray.org.x, ray.org.y, ray.org.z, 0.0f);
    r.perm = make_uint4(kx, ky, kz, 3u);
#if defined(WP_OPENCL) && defined(__AVX__) && defined(__x86_64__)
    // One four-lane divide (each lane correctly rounded: the same bits as three scalar ones).
    // x86 OpenCL (PoCL) only: Oclgrind 21.10's uninitialized-value check crashes on it.
    float4 q = (float4)(wp_component(d, (int)kx), wp_component(d, (int)ky), 1.0f, 1.0f) / (float4)(dz);
    r.sx = q.x;
    r.sy = q.y;
    r.sz = q.z;
#else
    r.sx = wp_component(d, (int)kx) / dz;
    r.sy = wp_component(d, (int)ky) / dz;
    r.sz = 1.0f / dz;
#endif
    r.tmin = ray.org.w;
    return r;
}

// Tests one triangle. Returns 1 and writes t and the barycentrics of vertices 1 and 2
// when the ray hits it at t > tmin; the caller compares t with its current best.
WP_FN int wp_intersect_triangle(const TriRay* r, float4 v0, float4 v1, float4 v2, float* t_out,
                                float* u_out, float* v_out) {
    // Vertices relative to the origin, in the ray's permuted frame.
    float4 A = wp_permute(v0 - r->org, r->perm);
    float4 B = wp_permute(v1 - r->org, r->perm);
    float4 C = wp_permute(v2 - r->org, r->perm);
    // Shear so the ray is the +z axis.
    float ax = A.x - r->sx * A.z, ay = A.y - r->sy * A.z;
    float bx = B.x - r->sx * B.z, by = B.y - r->sy * B.z;
    float cx = C.x - r->sx * C.z, cy = C.y - r->sy * C.z;
    // Scaled barycentric coordinates (edge functions).
    float U = cx * by - cy * bx;
    float V = ax * cy - ay * cx;
    float W = bx * ay - by * ax;
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return 0;
    float det = U + V + W;
    if (det == 0.0f) return 0;  // ray in the triangle's plane, or a degenerate triangle
    // Scaled hit distance, then t.
    float T = U * (r->sz * A.z) + V * (r->sz * B.z) + W * (r->sz * C.z);
    float rcp = 1.0f / det;
    float t = T * rcp;
    if (!(t > r->tmin)) return 0;  // also rejects NaN
    *t_out = t;
    *u_out = V * rcp;
    *v_out = W * rcp;
    return 1;
}
#endif  // WP_PLAIN_TRIANGLES

WP_NAMESPACE_END

#endif  // WP_TRIANGLE_H
