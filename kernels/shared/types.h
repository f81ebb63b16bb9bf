// types.h — every plain-data layout shared by the host and the kernels.
//
// One definition per struct, compiled as OpenCL C and as C++ (see compat.h). Rules:
//   * rows of float4 or int4, or 4-byte scalars with explicit padding: never float3
//     (16 bytes in OpenCL, 12 in C and GLM) and never GLM types;
//   * integers live in integer fields, never as raw bits in a float lane: those bits
//     are denormal floats and slow every box test 2-2.5x on PoCL (NOTES-pocl.md, trap 1);
//   * unused lanes are 0.
// The host checks sizeof/offsetof below with static_assert, and the kernel
// utility.cl:probe_layout reports the device's numbers to tests/test_layout.cpp.
#ifndef WP_TYPES_H
#define WP_TYPES_H

#include "compat.h"

WP_NAMESPACE_BEGIN

// A ray: origin + [tmin, tmax) along an unnormalised direction. 32 bytes.
typedef struct Ray {
    float4 org;  // xyz: origin (world units); w: tmin, hits need t > tmin
    float4 dir;  // xyz: direction (need not be unit length); w: tmax, hits need t < tmax
} Ray;

// The closest (or any) hit of one ray. 16 bytes.
typedef struct Hit {
    float t;   // ray parameter of the hit; tmax of the ray when there is none
    int prim;  // original triangle index (scene order); -1 = miss
    float u;   // barycentric weight of vertex 1
    float v;   // barycentric weight of vertex 2 (vertex 0's weight is 1 - u - v)
} Hit;

// A triangle as the kernels read it: three vertices in BVH leaf order. 48 bytes.
typedef struct Triangle {
    float4 v0;  // xyz: vertex 0 (world units); w: 0
    float4 v1;  // xyz: vertex 1; w: 0
    float4 v2;  // xyz: vertex 2; w: 0
} Triangle;

// --- Stackless BVH2 (see src/bvh/flatten.h for how it is built) ----------------------
// Every interior node stores the boxes of its two children, one float4 row per axis, so
// one node visit tests both children with three float4 slab computations. 48 bytes.
typedef struct BvhNode {
    float4 x;  // (child0.lo.x, child1.lo.x, child0.hi.x, child1.hi.x), world units
    float4 y;  // same for y
    float4 z;  // same for z
} BvhNode;

// Links of an interior node, in a separate integer array (no integers in float lanes).
// A child reference c is an interior node index when c >= 0, else a leaf:
//   ~c = (first << WP_LEAF_COUNT_BITS) | count, triangles [first, first + count) of the
//   leaf-ordered triangle array. count may be 0 (the empty second child of a root that
//   is a single leaf; its box is the point (FLT_MAX, FLT_MAX, FLT_MAX)). 16 bytes.
typedef struct BvhLinks {
    int child0;  // child reference (see above)
    int child1;  // child reference
    int parent;  // parent interior node index; -1 at the root (node 0)
    int pad;     // 0
} BvhLinks;

#define WP_LEAF_COUNT_BITS 5
#define WP_LEAF_MAX_COUNT 31
// The stackless traversal keeps one bit per level in a 64-bit word: the builder caps the
// number of interior levels at this.
#define WP_BVH_MAX_DEPTH 64

// Per-ray traversal statistics, written only by kernels compiled with WP_STATS. 8 bytes.
typedef struct TraceStats {
    int box_tests;  // child boxes tested (2 per interior node visit, 1 per re-test)
    int tri_tests;  // ray/triangle tests
} TraceStats;

// Sizes and offsets that the device probe (utility.cl:probe_layout) and the host both
// evaluate, in this order; tests/test_layout.cpp compares the two lists.
#define WP_LAYOUT_FIELDS(X)                                                               \
    X(sizeof(Ray)) X(__builtin_offsetof(Ray, dir))                                        \
    X(sizeof(Hit)) X(__builtin_offsetof(Hit, prim)) X(__builtin_offsetof(Hit, u))          \
    X(__builtin_offsetof(Hit, v))                                                         \
    X(sizeof(Triangle)) X(__builtin_offsetof(Triangle, v1)) X(__builtin_offsetof(Triangle, v2)) \
    X(sizeof(BvhNode)) X(__builtin_offsetof(BvhNode, y)) X(__builtin_offsetof(BvhNode, z)) \
    X(sizeof(BvhLinks)) X(__builtin_offsetof(BvhLinks, child1))                           \
    X(__builtin_offsetof(BvhLinks, parent)) X(sizeof(TraceStats))

WP_NAMESPACE_END

#if defined(WP_HOST)
#include <cstddef>
static_assert(sizeof(wp::Ray) == 32 && offsetof(wp::Ray, dir) == 16);
static_assert(sizeof(wp::Hit) == 16 && offsetof(wp::Hit, prim) == 4 && offsetof(wp::Hit, v) == 12);
static_assert(sizeof(wp::Triangle) == 48 && offsetof(wp::Triangle, v2) == 32);
static_assert(sizeof(wp::BvhNode) == 48 && offsetof(wp::BvhNode, z) == 32);
static_assert(sizeof(wp::BvhLinks) == 16 && offsetof(wp::BvhLinks, parent) == 8);
static_assert(sizeof(wp::TraceStats) == 8);
#endif

#endif  // WP_TYPES_H
