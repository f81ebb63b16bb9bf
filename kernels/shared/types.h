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
#include "material_kinds.h"

WP_NAMESPACE_BEGIN

// The one local size of every launch (the host's ocl::kLocalSize is this): kernels that
// share work within a group (shade.cl's queue reservation) size their local arrays by it.
#define WP_GROUP_SIZE 64

// Queue entries per work-item of the lane shade kernel (shade.cl shade_surface8; the host
// launches ceil(n / this) work-items): its surface hits are packed and shaded eight lanes at
// a time, so more entries than lanes let an open scene's misses drop out of the lanes.
// 64 against 32 (a work-group of 128 entries either way; docs/performance.md, "Nineteenth
// round"): shade 0.917 on Bitterli's box, 0.965 on the built-in box, 0.939 on veach-mis (half
// the queue atomics and per-work-item set-ups).
#define WP_SHADE_LANE_ENTRIES 64
// Its local size (it shares nothing within a group): 2 work-items, 128 queue entries, so the
// short queues of late bounces still spread over every core.
#define WP_SHADE_LANE_GROUP 2

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

// Up to four triangles of one BVH leaf as the traversal reads them: their vertices as SoA
// rows, row[3 * v + axis] = coordinate `axis` of vertex v, lane i = the leaf's triangle
// 4b + i of block b. The ray's permuted axes pick rows by index, and one four-lane test
// (triangle.h, wp_intersect_block) covers the block. Lanes past the leaf's count hold
// zeros: a degenerate triangle that no ray hits. 144 bytes.
#define WP_TRI_BLOCK 4
typedef struct TriBlock {
    float4 row[9];
} TriBlock;

// --- Stackless wide BVH (see src/bvh/flatten.h for how it is built) -----------------
// A binary SAH tree collapsed to up to WP_BVH_WIDTH (8, or 4) children per interior node.
// Each node stores the boxes of its children as SoA rows, one WpLanes vector (float8, or
// float4) per bound and axis, lane i = child slot i, so one node visit tests all children
// with six vector slab computations (one AVX/SSE instruction each); the row order lets a
// ray pick its near/far plane per axis by index (row 2*axis + sign). The child references
// follow in integer fields of the same node, so the fetch that feeds the box test also
// yields the next node's index (no dependent load on the descent path).
// WP_BVH_WIDTH is the one switch (host and kernels both read it here); tests/test_layout
// checks that both sides agree.
#define WP_BVH_WIDTH 8
#if WP_BVH_WIDTH == 8
typedef float8 WpLanes;
// 256 bytes (four cache lines).
typedef struct BvhNode {
    float8 lo_x;  // lane i: child i's box lower x (world units)
    float8 hi_x;  // lane i: child i's box upper x
    float8 lo_y;  // same for y
    float8 hi_y;
    float8 lo_z;  // same for z
    float8 hi_z;
    int child0;   // child reference of slot 0 (below); the eight are read as int[8]
    int child1;
    int child2;
    int child3;
    int child4;
    int child5;
    int child6;
    int child7;   // slot 7
    int pad0;     // 0 (pads the node to 256 bytes)
    int pad1;     // 0
    int pad2;     // 0
    int pad3;     // 0
    int pad4;     // 0
    int pad5;     // 0
    int pad6;     // 0
    int pad7;     // 0
} BvhNode;
#else
typedef float4 WpLanes;
// 128 bytes (two cache lines).
typedef struct BvhNode {
    float4 lo_x;  // lane i: child i's box lower x (world units)
    float4 hi_x;  // lane i: child i's box upper x
    float4 lo_y;  // same for y
    float4 hi_y;
    float4 lo_z;  // same for z
    float4 hi_z;
    int child0;   // child reference of slot 0 (below); the four are read as int[4]
    int child1;
    int child2;
    int child3;   // slot 3
    int pad0;     // 0 (pads the node to 128 bytes)
    int pad1;     // 0
    int pad2;     // 0
    int pad3;     // 0
} BvhNode;
#endif
// A child reference c is an interior node index when c >= 0, else a leaf:
//   ~c = (first << WP_LEAF_COUNT_BITS) | count: `count` triangles in the blocks [first,
//   first + ceil(count / WP_TRI_BLOCK)) of the leaf-ordered TriBlock array; triangle i of
//   the leaf is lane i % 4 of block first + i / 4, its original index prim_ids[4 * first +
//   i] (-1 in the padding lanes). count 0 (c = -1) is the empty leaf of unused slots.
// An unused slot (a node with fewer than WP_BVH_WIDTH children) holds the inverted box
// lo = +FLT_MAX, hi = -FLT_MAX in every axis, which no ray enters (its entry distance lies
// beyond its exit whatever the direction's sign, zero components included), and child
// reference -1. Used slots come first.

// Up-links of an interior node, in a separate dense integer array (8 bytes a node, so the
// climb of the stackless traversal touches little memory).
typedef struct BvhLinks {
    int parent;  // parent interior node index; -1 at the root (node 0)
    int slot;    // this node's slot in its parent (0..WP_BVH_WIDTH-1); 0 at the root
} BvhLinks;

#define WP_LEAF_COUNT_BITS 5
#define WP_LEAF_MAX_COUNT 31
// The stackless traversal keeps one bit per level in a 64-bit word: the builder caps the
// number of interior levels of the binary tree at this, and collapsing never adds levels.
#define WP_BVH_MAX_DEPTH 64
// Entries of the stackless traversal's ring of recent pending ancestors (bvh_traverse.h;
// a power of two).
#ifndef WP_BVH_SHORT_STACK
#define WP_BVH_SHORT_STACK 4
#endif
// The any-hit traversal's ring (node and children left, no distances: 8 bytes an entry;
// a power of two). Eight covers the built-in scenes' 8-wide trees (depth <= 8).
#ifndef WP_BVH_ANY_RING
#define WP_BVH_ANY_RING 8
#endif
// Entries of the small-stack (oracle) traversal: at most WIDTH - 1 pending children a level.
#define WP_BVH_STACK_SIZE ((WP_BVH_WIDTH - 1) * WP_BVH_MAX_DEPTH)

// Per-ray traversal statistics, written only by kernels compiled with WP_STATS. 8 bytes.
typedef struct TraceStats {
    int box_tests;  // child boxes tested (WP_BVH_WIDTH per node test, re-tests included)
    int tri_tests;  // ray/triangle tests
} TraceStats;

// Sizes and offsets that the device probe (utility.cl:probe_layout) and the host both
// evaluate, in this order; tests/test_layout.cpp compares the two lists.
#define WP_LAYOUT_FIELDS(X)                                                               \
    X(sizeof(Ray)) X(__builtin_offsetof(Ray, dir))                                        \
    X(sizeof(Hit)) X(__builtin_offsetof(Hit, prim)) X(__builtin_offsetof(Hit, u))          \
    X(__builtin_offsetof(Hit, v))                                                         \
    X(sizeof(Triangle)) X(__builtin_offsetof(Triangle, v1)) X(__builtin_offsetof(Triangle, v2)) \
    X(sizeof(TriBlock)) X(__builtin_offsetof(TriBlock, row[8]))                            \
    X(sizeof(BvhNode)) X(__builtin_offsetof(BvhNode, hi_x)) X(__builtin_offsetof(BvhNode, hi_z)) \
    X(__builtin_offsetof(BvhNode, child0)) X(__builtin_offsetof(BvhNode, pad0))           \
    X(sizeof(BvhLinks)) X(__builtin_offsetof(BvhLinks, slot))                             \
    X(sizeof(TraceStats))                                                                 \
    /* Render stage types */                                                              \
    X(sizeof(CameraData)) X(__builtin_offsetof(CameraData, forward))                      \
    X(__builtin_offsetof(CameraData, up)) X(__builtin_offsetof(CameraData, width))        \
    X(__builtin_offsetof(CameraData, jitter)) X(__builtin_offsetof(CameraData, lens))     \
    X(sizeof(MaterialData))                                                               \
    X(__builtin_offsetof(MaterialData, emission)) X(__builtin_offsetof(MaterialData, kind)) \
    X(__builtin_offsetof(MaterialData, ior)) X(__builtin_offsetof(MaterialData, alpha))   \
    X(__builtin_offsetof(MaterialData, specular)) X(__builtin_offsetof(MaterialData, k))  \
    X(__builtin_offsetof(MaterialData, flags)) X(__builtin_offsetof(MaterialData, table)) \
    X(sizeof(PathState)) X(__builtin_offsetof(PathState, pixel))                          \
    X(__builtin_offsetof(PathState, sample)) X(__builtin_offsetof(PathState, item))        \
    X(__builtin_offsetof(PathState, cone))                                               \
    X(sizeof(FilmPixel))                          \
    X(__builtin_offsetof(FilmPixel, comp))                                                \
    X(sizeof(LightPair)) X(__builtin_offsetof(LightPair, pdf))                            \
    /* Appearance types */                                                                \
    X(sizeof(TriNormals)) X(__builtin_offsetof(TriNormals, n2))                           \
    X(sizeof(TriUVs)) X(__builtin_offsetof(TriUVs, uv2))                                  \
    X(sizeof(TriTangents)) X(__builtin_offsetof(TriTangents, t2))                         \
    X(sizeof(TextureData)) X(__builtin_offsetof(TextureData, format))                     \
    X(__builtin_offsetof(TextureData, nearest))                                           \
    X(sizeof(TextureView)) X(__builtin_offsetof(TextureView, v_row))                      \
    X(__builtin_offsetof(TextureView, texture))                                           \
    X(sizeof(MaterialTextures)) X(__builtin_offsetof(MaterialTextures, alpha))            \
    X(__builtin_offsetof(MaterialTextures, normal_scale))                                 \
    X(sizeof(EnvData)) X(__builtin_offsetof(EnvData, scale))                              \
    X(__builtin_offsetof(EnvData, width)) X(__builtin_offsetof(EnvData, height))

// ===================================================================================
// Render stage types (generate / shade / accumulate; see kernels/*.cl and src/render/)
// ===================================================================================

// Flags of MaterialData.flags.
#define WP_MF_BECKMANN 1        // rough kinds: Beckmann distribution (else GGX)
#define WP_MF_SEPARABLE_G 2     // rough kinds: G = G1(wo) G1(wi) (else height-correlated)
#define WP_PLASTIC_NONLINEAR 4  // plastics: Mitsuba's nonlinear internal scattering

// The material tables of a roughplastic (scene/material_tables.h, materials/roughplastic.h):
// at MaterialData.table, WP_ROUGH_PLASTIC_RES values of the coat's external transmittance
// at cos θ = max(1e-6, k / (RES - 1)), then its internal diffuse reflectance (Mitsuba 3's
// MI_ROUGH_TRANSMITTANCE_RES tables).
#define WP_ROUGH_PLASTIC_RES 64
#define WP_ROUGH_PLASTIC_TABLE_SIZE (WP_ROUGH_PLASTIC_RES + 1)

// Camera as the generate stage reads it (built by scene/upload). 96 bytes.
// The pinhole ray through image position (px, py) in pixels (0,0 = top-left corner of the
// image) has direction forward + ((2 px / width) - 1) * right + (1 - (2 py / height)) * up.
// With a thin lens (lens.x > 0; camera.h) the ray starts on the lens disk and passes
// through the point where that pinhole ray meets the plane in focus.
typedef struct CameraData {
    float4 origin;   // xyz: eye position (world units); w: 0
    float4 forward;  // xyz: unit viewing direction (image centre); w: 0
    float4 right;    // xyz: unit right * tan(vfov / 2) * width / height; w: 0
    float4 up;       // xyz: unit up (orthogonal to forward) * tan(vfov / 2); w: 0
    int width;       // image width, pixels
    int height;      // image height, pixels
    int jitter;      // 1: uniform random position inside the pixel; 0: pixel centre
    int pad;         // 0
    float4 lens;     // x: thin lens radius (world units; 0: pinhole); y: focus distance along
                     // forward (world units, > 0); zw: 0
} CameraData;

// A material as the shade stage reads it. 112 bytes. Kinds and the meaning of the colours:
// material_kinds.h. Parameters a kind does not read are 0.
typedef struct MaterialData {
    float4 albedo;    // xyz: the kind's main colour in [0, 1] (material_kinds.h); w: 0
    float4 emission;  // xyz: emitted radiance (W sr^-1 m^-2), front side only; w: 0
    int kind;         // WP_MATERIAL_* (material_kinds.h)
    float ior;        // kinds with IOR: index of refraction, inside (behind the front face) /
                      // outside
    float alpha;      // kinds with ALPHA: microfacet roughness α (α_u when anisotropic)
    float alpha_v;    // kinds with ALPHA: α_v (= alpha when isotropic)
    float4 specular;  // xyz: reflection tint of dielectrics and plastics; w: plastics: the
                      // probability weight of the coat (Mitsuba's specular sampling weight)
    float4 eta;       // xyz: conductors: η per channel; w: 0
    float4 k;         // xyz: conductors: k per channel; w: 0
    int flags;        // WP_MF_BECKMANN | WP_MF_SEPARABLE_G | WP_PLASTIC_NONLINEAR
    int table;        // roughplastic: first float of its tables in the material-table buffer;
                      // -1 otherwise
    float aniso_cos;  // anisotropic rough kinds, per hit (shade, WP_HAVE_ANISOTROPY): the
    float aniso_sin;  // direction of α_u in the local frame of the shading normal
                      // (microfacet.h); 0, 0 in the material buffer
} MaterialData;

// ===================================================================================
// Appearance data (issue 13): uploaded only for scenes that have it (render/device_scene,
// KernelConfig WP_HAVE_NORMALS / _TEXTURES / _NORMAL_MAPS / _ALPHA_MASK / _ENV); absent
// features get 4-byte placeholders and their code is not compiled.
// ===================================================================================

// Shading normals of one triangle at its three vertices, scene order. 48 bytes.
typedef struct TriNormals {
    float4 n0;  // xyz: shading normal at vertex 0 (need not be unit; zero: none, the
                // triangle shades with its geometric normal); w: 0
    float4 n1;  // same at vertex 1
    float4 n2;  // same at vertex 2
} TriNormals;

// Texture coordinates of one triangle, scene order (convention: scene.h TextureRef). 32 bytes.
typedef struct TriUVs {
    float4 uv01;  // (u0, v0, u1, v1)
    float4 uv2;   // (u2, v2, 0, 0)
} TriUVs;

// Tangents of one triangle at its three vertices, scene order (normal maps). 48 bytes.
typedef struct TriTangents {
    float4 t0;  // xyz: tangent at vertex 0 (direction of +u); w: ±1, bitangent = w cross(n, t)
    float4 t1;
    float4 t2;
} TriTangents;

// Texel formats of TextureData.format.
#define WP_TEXEL_SRGB8 0    // texels8 pool: RGBA8 in one uint (R in the low byte), sRGB-encoded
#define WP_TEXEL_LINEAR8 1  // texels8 pool: RGBA8, linear (normal, roughness and alpha maps)
#define WP_TEXEL_FLOAT 2    // texelsf pool: float4 RGBA, linear

// One mip-mapped image in a texel pool. 32 bytes. Level l is max(1, width >> l) x
// max(1, height >> l) texels, row-major from the top row, and follows level l - 1.
typedef struct TextureData {
    int offset;   // first texel of level 0 in its pool
    int width;    // of level 0
    int height;   // of level 0
    int levels;   // mip levels, >= 1 (1 for nearest)
    int format;   // WP_TEXEL_*
    int nearest;  // 1: the nearest texel of level 0, no filtering
    int pad0;     // 0
    int pad1;     // 0
} TextureData;

// A material's use of an image: the image and an affine uv map. 48 bytes.
typedef struct TextureView {
    float4 u_row;  // xyz: u' = u_row.x u + u_row.y v + u_row.z; w: 0
    float4 v_row;  // xyz: v' = v_row.x u + v_row.y v + v_row.z; w: 0
    int texture;   // index into the TextureData array
    int pad0;      // 0
    int pad1;      // 0
    int pad2;      // 0
} TextureView;

// The textures of one material, indices into the TextureView array, -1 for none. 32 bytes.
typedef struct MaterialTextures {
    int albedo;          // RGB × albedo
    int roughness;       // α × G²
    int emission;        // RGB × emission
    int normal;          // tangent-space normal map
    int alpha;           // coverage: A × alpha_factor < alpha_cutoff cuts the surface out
    float alpha_cutoff;  // glTF alphaCutoff (0.5 by default); 0 when there is no mask
    float alpha_factor;  // multiplies the coverage (glTF baseColorFactor.a)
    float normal_scale;  // scales the map's xy (glTF normalTexture.scale)
} MaterialTextures;

// The environment light (kernels/shared/envmap.h): its map has its own float4 texel
// array and sampling tables, not the texture pools. 80 bytes.
typedef struct EnvData {
    float4 to_local0;  // xyz: rows of the rotation world -> map frame; w: 0
    float4 to_local1;
    float4 to_local2;
    float4 scale;      // xyz: radiance multiplier per channel; w: 0
    int width;         // of the map, texels
    int height;
    int pad0;          // 0
    int pad1;          // 0
} EnvData;

// A light triangle's back-to-back partner (scene/light_pairs.h, kernels/shared/lights.h),
// per triangle in scene order; read only by kernels built with WP_HAVE_LIGHT_PAIRS. 8 bytes.
typedef struct LightPair {
    int partner;  // the paired light triangle (scene order); -1: none
    float pdf;    // P(choose partner) / area of this triangle: the density per unit area that
                  // the partner's samples add here when they move over (0 without a partner)
} LightPair;

// One path in flight, stored in a queue slot next to its ray. 32 bytes. Its results go to
// the radiance slot of its sample (`item`), never to the queue slot, so the image does not
// depend on the order in which paths were pushed. Every path of a queue is at the same
// bounce (the pool refills between waves), so the bounce is a kernel argument.
typedef struct PathState {
    float4 throughput;  // xyz: path throughput (product of BSDF * cos / pdf, unitless);
                        // w: density (per steradian) with which the last bounce drew this
                        // ray's direction, for MIS weights; 0 for camera rays and specular
                        // bounces (so a path at bounce > 0 with w == 0 arrived by a Dirac
                        // lobe: wp_path_specular)
    int pixel;          // pixel index y * width + x
    uint sample;        // the pixel's sample index (the sampler's sample number)
    int item;           // the sample's index within its wave: its radiance slot
    float cone;         // width of the ray cone at the ray's origin (world units, >= 0): the
                        // texture footprint (ray cones, Akenine-Möller et al. 2021); 0 at the
                        // camera (a pinhole), grown by the pixel's spread angle per unit length;
                        // tracked only when the scene has textures (else it stays 0)
} PathState;

// Accumulated sum of one film pixel: per channel a double-float pair (hi, lo) whose value
// is sum + comp, kept normalised (|comp| <= ulp(sum) / 2) by film.h (Joldes, Muller &
// Popescu 2017, DWPlusFP). 32 bytes.
typedef struct FilmPixel {
    float4 sum;   // xyz: high word of the running sum of radiance samples; w: 0
    float4 comp;  // xyz: low word (the rounding error of sum); w: 0
} FilmPixel;

// Slots of the counters buffer (int[WP_COUNTER_COUNT]): non-finite values caught per stage.
#define WP_COUNTER_GENERATE_NONFINITE 0  // camera rays with a NaN/Inf direction (dropped)
#define WP_COUNTER_SHADE_NONFINITE 1     // NaN/Inf emission or throughput (path ended)
#define WP_COUNTER_ACCUMULATE_NONFINITE 2  // NaN/Inf frame radiance (sample dropped)
#define WP_COUNTER_COUNT 8

// Debug NaN injection (render --debug-nan): stage bits of WP_INJECT_NAN. A stage with its
// bit set replaces, for every pixel p with p % WP_INJECT_PERIOD == 0, the value its guard is
// about to check by NaN: generate the camera direction, shade the throughput of the path
// arriving at bounce 0, accumulate the frame radiance. Each guard must count every one.
#define WP_INJECT_GENERATE 1
#define WP_INJECT_SHADE 2
#define WP_INJECT_ACCUMULATE 4

WP_NAMESPACE_END

#if defined(WP_HOST)
#include <cstddef>
static_assert(sizeof(wp::Ray) == 32 && offsetof(wp::Ray, dir) == 16);
static_assert(sizeof(wp::Hit) == 16 && offsetof(wp::Hit, prim) == 4 && offsetof(wp::Hit, v) == 12);
static_assert(sizeof(wp::Triangle) == 48 && offsetof(wp::Triangle, v2) == 32);
#if WP_BVH_WIDTH == 8
static_assert(sizeof(wp::BvhNode) == 256 && offsetof(wp::BvhNode, hi_x) == 32 &&
              offsetof(wp::BvhNode, hi_z) == 160 && offsetof(wp::BvhNode, child0) == 192 &&
              offsetof(wp::BvhNode, pad0) == 224);
#else
static_assert(sizeof(wp::BvhNode) == 128 && offsetof(wp::BvhNode, hi_x) == 16 &&
              offsetof(wp::BvhNode, hi_z) == 80 && offsetof(wp::BvhNode, child0) == 96 &&
              offsetof(wp::BvhNode, pad0) == 112);
#endif
static_assert(sizeof(wp::BvhLinks) == 8 && offsetof(wp::BvhLinks, slot) == 4);
static_assert(sizeof(wp::TraceStats) == 8);
// Render stage types.
static_assert(sizeof(wp::CameraData) == 96 && offsetof(wp::CameraData, width) == 64 &&
              offsetof(wp::CameraData, jitter) == 72 && offsetof(wp::CameraData, lens) == 80);
static_assert(sizeof(wp::MaterialData) == 112 && offsetof(wp::MaterialData, kind) == 32 &&
              offsetof(wp::MaterialData, ior) == 36 && offsetof(wp::MaterialData, alpha) == 40 &&
              offsetof(wp::MaterialData, specular) == 48 && offsetof(wp::MaterialData, k) == 80 &&
              offsetof(wp::MaterialData, flags) == 96 && offsetof(wp::MaterialData, table) == 100);
static_assert(sizeof(wp::LightPair) == 8 && offsetof(wp::LightPair, pdf) == 4);
static_assert(sizeof(wp::PathState) == 32 && offsetof(wp::PathState, pixel) == 16 &&
              offsetof(wp::PathState, sample) == 20 && offsetof(wp::PathState, item) == 24 &&
              offsetof(wp::PathState, cone) == 28);
static_assert(sizeof(wp::FilmPixel) == 32 && offsetof(wp::FilmPixel, comp) == 16);
// Appearance types.
static_assert(sizeof(wp::TriNormals) == 48 && offsetof(wp::TriNormals, n2) == 32);
static_assert(sizeof(wp::TriUVs) == 32 && offsetof(wp::TriUVs, uv2) == 16);
static_assert(sizeof(wp::TriTangents) == 48 && offsetof(wp::TriTangents, t2) == 32);
static_assert(sizeof(wp::TextureData) == 32 && offsetof(wp::TextureData, format) == 16 &&
              offsetof(wp::TextureData, nearest) == 20);
static_assert(sizeof(wp::TextureView) == 48 && offsetof(wp::TextureView, v_row) == 16 &&
              offsetof(wp::TextureView, texture) == 32);
static_assert(sizeof(wp::MaterialTextures) == 32 && offsetof(wp::MaterialTextures, alpha) == 16 &&
              offsetof(wp::MaterialTextures, normal_scale) == 28);
static_assert(sizeof(wp::EnvData) == 80 && offsetof(wp::EnvData, scale) == 48 &&
              offsetof(wp::EnvData, width) == 64 && offsetof(wp::EnvData, height) == 68);
#endif

#endif  // WP_TYPES_H
