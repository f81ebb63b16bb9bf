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

// The same test on the four lanes of a leaf block (types.h), for the traversal.
WP_FN int wp_intersect_block(const TriRay* r, WP_GLOBAL const TriBlock* blk, int lanes, float4* t_out,
                             float4* u_out, float4* v_out) {
    WP_GLOBAL const float4* row = blk->row;
    const float4 dx = wp_splat4(r->dir.x), dy = wp_splat4(r->dir.y), dz = wp_splat4(r->dir.z);
    const float4 e1x = row[3] - row[0], e1y = row[4] - row[1], e1z = row[5] - row[2];
    const float4 e2x = row[6] - row[0], e2y = row[7] - row[1], e2z = row[8] - row[2];
    const float4 px = dy * e2z - dz * e2y, py = dz * e2x - dx * e2z, pz = dx * e2y - dy * e2x;
    const float4 det = e1x * px + e1y * py + e1z * pz;
    const float4 zero = wp_splat4(0.0f), one = wp_splat4(1.0f);
    const float4 inv = one / det;
    const float4 sx = wp_splat4(r->org.x) - row[0], sy = wp_splat4(r->org.y) - row[1],
                 sz = wp_splat4(r->org.z) - row[2];
    const float4 u = (sx * px + sy * py + sz * pz) * inv;
    const float4 qx = sy * e1z - sz * e1y, qy = sz * e1x - sx * e1z, qz = sx * e1y - sy * e1x;
    const float4 v = (dx * qx + dy * qy + dz * qz) * inv;
    const float4 t = (e2x * qx + e2y * qy + e2z * qz) * inv;
    *t_out = t;
    *u_out = u;
    *v_out = v;
    return ~wp_mask4_eq(det, zero) & ~wp_mask4_lt(u, zero) & ~wp_mask4_lt(one, u) & ~wp_mask4_lt(v, zero) &
           ~wp_mask4_lt(one, u + v) & wp_mask4_lt(wp_splat4(r->tmin), t) & ((1 << lanes) - 1);
}
#else

// Per-ray constants of the watertight test.
typedef struct TriRay {
    float4 org;  // ray origin (w = 0)
    float4 porg; // the origin permuted: (org[kx], org[ky], org[kz], 0)
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
    r.porg = wp_permute(r.org, r.perm);
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

#if !defined(WP_PLAIN_TRIANGLES)
// The four triangles of a leaf block (types.h) at once: wp_intersect_triangle's arithmetic
// lane by lane, in the same order, so each lane's t, u, v and verdict are its bits (FP
// contraction is off everywhere, and a lane's divide rounds like a scalar one). Returns the
// lanes (bits 0..3, only those below `lanes`) that wp_intersect_triangle would report a hit
// for, their t, u and v in the lanes of *t_out, *u_out, *v_out.
WP_FN int wp_intersect_block(const TriRay* r, WP_GLOBAL const TriBlock* blk, int lanes, float4* t_out,
                             float4* u_out, float4* v_out) {
    WP_GLOBAL const float4* row = blk->row;
    const int kx = (int)r->perm.x, ky = (int)r->perm.y, kz = (int)r->perm.z;
    const float4 ox = wp_splat4(r->porg.x), oy = wp_splat4(r->porg.y), oz = wp_splat4(r->porg.z);
    // Vertices relative to the origin, in the ray's permuted frame (rows picked by axis).
    const float4 Az = row[kz] - oz, Bz = row[3 + kz] - oz, Cz = row[6 + kz] - oz;
    const float4 sx = wp_splat4(r->sx), sy = wp_splat4(r->sy), sz = wp_splat4(r->sz);
    // Shear so the ray is the +z axis.
    const float4 ax = (row[kx] - ox) - sx * Az, ay = (row[ky] - oy) - sy * Az;
    const float4 bx = (row[3 + kx] - ox) - sx * Bz, by = (row[3 + ky] - oy) - sy * Bz;
    const float4 cx = (row[6 + kx] - ox) - sx * Cz, cy = (row[6 + ky] - oy) - sy * Cz;
    // Scaled barycentric coordinates (edge functions).
    const float4 U = cx * by - cy * bx;
    const float4 V = ax * cy - ay * cx;
    const float4 W = bx * ay - by * ax;
    const float4 zero = wp_splat4(0.0f);
    const int neg = wp_mask4_lt(U, zero) | wp_mask4_lt(V, zero) | wp_mask4_lt(W, zero);
    const int pos = wp_mask4_lt(zero, U) | wp_mask4_lt(zero, V) | wp_mask4_lt(zero, W);
    const float4 det = U + V + W;
    // Scaled hit distance, then t.
    const float4 T = U * (sz * Az) + V * (sz * Bz) + W * (sz * Cz);
    const float4 rcp = wp_splat4(1.0f) / det;
    const float4 t = T * rcp;
    *t_out = t;
    *u_out = V * rcp;
    *v_out = W * rcp;
    // Inside (all edge values of one sign, zeros counting as either), not in the ray's plane
    // (det 0), in front of tmin (which also drops NaN), and a lane of the leaf.
    return ~(neg & pos) & ~wp_mask4_eq(det, zero) & wp_mask4_lt(wp_splat4(r->tmin), t) & ((1 << lanes) - 1);
}
#endif

WP_NAMESPACE_END

#endif  // WP_TRIANGLE_H
