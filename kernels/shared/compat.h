// compat.h — the only file that knows which language the shared code is compiled as.
//
// The headers in kernels/shared/ are compiled three ways:
//   * as OpenCL C 1.2 (the kernels), where vector types and math builtins are native;
//   * as C++20 on the host (tests, oracles, the upload code), where this file supplies
//     float3/float4/int4 and the OpenCL builtins the shared code uses;
//   * later as CUDA C++ (same host definitions, marked __host__ __device__).
// Shared code writes make_float3(...) instead of (float3)(...) and never uses swizzles
// other than .x .y .z .w, so the same text compiles everywhere.
//
// FP contraction is off on every side (the pragma below, -ffp-contract=off on the host,
// --fmad=false for CUDA): a*b+c rounds twice everywhere, so host oracles and every
// device agree bit for bit. Where a fused multiply-add is wanted, write fma().
#ifndef WP_COMPAT_H
#define WP_COMPAT_H

#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
// ---------------------------------------------------------------- OpenCL C ----------
#define WP_OPENCL 1
#pragma OPENCL FP_CONTRACT OFF

#define WP_KERNEL __kernel
#define WP_GLOBAL __global
#define WP_LOCAL __local
#define WP_CONSTANT __constant
#define WP_FN static inline
#define WP_NAMESPACE_BEGIN
#define WP_NAMESPACE_END

#define make_float3(a, b, c) ((float3)((a), (b), (c)))
#define make_float4(a, b, c, d) ((float4)((a), (b), (c), (d)))
#define make_int4(a, b, c, d) ((int4)((a), (b), (c), (d)))
#define make_uint4(a, b, c, d) ((uint4)((a), (b), (c), (d)))
#define make_float2(a, b) ((float2)((a), (b)))

#define wp_global_id() ((int)get_global_id(0))
#define wp_local_id() ((int)get_local_id(0))
// Work-group barrier over local memory (the only kind the stages use).
#define wp_barrier() barrier(CLK_LOCAL_MEM_FENCE)
// (a.z, a.w, a.x, a.y): swaps the two halves of a float4.
#define wp_swap_halves(a) ((a).zwxy)
// Permutes the lanes of a float4 by a per-ray index vector (vpermilps on AVX).
#define wp_permute(a, idx) shuffle((a), (idx))
#define wp_atomic_add(p, v) atomic_add((p), (v))
#define wp_atomic_inc(p) atomic_inc((p))

#else
// ---------------------------------------------------------------- C++ host ----------
#include <cmath>
#include <cstdint>
#include <cstring>
#include <algorithm>
#include <cfloat>

#define WP_HOST 1
#define WP_KERNEL
#define WP_GLOBAL
#define WP_CONSTANT
#define WP_FN inline
#define WP_NAMESPACE_BEGIN namespace wp {
#define WP_NAMESPACE_END }

namespace wp {

using uint = std::uint32_t;
using ulong = std::uint64_t;

struct float2 { float x, y; };
struct float3 { float x, y, z; };
struct alignas(16) float4 { float x, y, z, w; };
struct alignas(16) int4 { int x, y, z, w; };
// Eight lanes; shared code reaches them only through the wp_*8 helpers below.
struct alignas(32) float8 { float s[8]; };
static_assert(sizeof(float8) == 32);
struct alignas(8) int2 { int x, y; };
struct alignas(8) uint2 { uint x, y; };
static_assert(sizeof(float4) == 16 && alignof(float4) == 16);
static_assert(sizeof(int4) == 16 && sizeof(int2) == 8);

inline float2 make_float2(float a, float b) { return {a, b}; }
inline float3 make_float3(float a, float b, float c) { return {a, b, c}; }
inline float4 make_float4(float a, float b, float c, float d) { return {a, b, c, d}; }
inline int4 make_int4(int a, int b, int c, int d) { return {a, b, c, d}; }
struct uint4;
inline uint4 make_uint4(uint a, uint b, uint c, uint d);

// float3 arithmetic, component-wise as in OpenCL C.
inline float3 operator+(float3 a, float3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline float3 operator-(float3 a, float3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline float3 operator*(float3 a, float3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline float3 operator/(float3 a, float3 b) { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
inline float3 operator*(float3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline float3 operator*(float s, float3 a) { return {a.x * s, a.y * s, a.z * s}; }
inline float3 operator/(float3 a, float s) { return {a.x / s, a.y / s, a.z / s}; }
inline float3 operator-(float3 a) { return {-a.x, -a.y, -a.z}; }
inline float3& operator+=(float3& a, float3 b) { a = a + b; return a; }
inline float3& operator*=(float3& a, float3 b) { a = a * b; return a; }
inline float3& operator*=(float3& a, float s) { a = a * s; return a; }

// float4 arithmetic.
inline float4 operator+(float4 a, float4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
inline float4 operator-(float4 a, float4 b) { return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w}; }
inline float4 operator*(float4 a, float4 b) { return {a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w}; }
inline float4 operator*(float4 a, float s) { return {a.x * s, a.y * s, a.z * s, a.w * s}; }
inline float4 operator-(float4 a, float s) { return {a.x - s, a.y - s, a.z - s, a.w - s}; }
inline float4& operator+=(float4& a, float4 b) { a = a + b; return a; }

// OpenCL C builtins used by the shared code. min/max follow OpenCL: for floats the result
// is unspecified with NaN operands (the shared code never feeds them NaN); fmin/fmax
// return the non-NaN operand.
inline float min(float a, float b) { return b < a ? b : a; }
inline float max(float a, float b) { return a < b ? b : a; }
inline int min(int a, int b) { return b < a ? b : a; }
inline int max(int a, int b) { return a < b ? b : a; }
inline uint min(uint a, uint b) { return b < a ? b : a; }
inline uint max(uint a, uint b) { return a < b ? b : a; }
inline float clamp(float x, float lo, float hi) { return min(max(x, lo), hi); }
inline float4 min(float4 a, float4 b) { return {min(a.x, b.x), min(a.y, b.y), min(a.z, b.z), min(a.w, b.w)}; }
inline float4 max(float4 a, float4 b) { return {max(a.x, b.x), max(a.y, b.y), max(a.z, b.z), max(a.w, b.w)}; }
inline float3 min(float3 a, float3 b) { return {min(a.x, b.x), min(a.y, b.y), min(a.z, b.z)}; }
inline float3 max(float3 a, float3 b) { return {max(a.x, b.x), max(a.y, b.y), max(a.z, b.z)}; }
using std::fabs;
using std::sqrt;
using std::fmin;
using std::fmax;
using std::fma;
using std::floor;
using std::copysign;
using std::isnan;
using std::isinf;
using std::isfinite;
using std::sin;
using std::cos;
using std::exp;
using std::log;
using std::pow;
using std::acos;
inline float3 fabs(float3 a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
inline float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float3 cross(float3 a, float3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(float3 a) { return std::sqrt(dot(a, a)); }
inline float3 normalize(float3 a) { return a * (1.0f / length(a)); }
inline float3 copysign(float3 a, float3 b) {
    return {std::copysign(a.x, b.x), std::copysign(a.y, b.y), std::copysign(a.z, b.z)};
}
inline uint as_uint(float f) { uint u; std::memcpy(&u, &f, 4); return u; }
inline int as_int(float f) { int i; std::memcpy(&i, &f, 4); return i; }
inline float as_float(uint u) { float f; std::memcpy(&f, &u, 4); return f; }
inline float as_float(int i) { float f; std::memcpy(&f, &i, 4); return f; }

inline int wp_atomic_add(int* p, int v) { int old = *p; *p += v; return old; }
inline float4 wp_swap_halves(float4 a) { return {a.z, a.w, a.x, a.y}; }
struct alignas(16) uint4 { uint x, y, z, w; };
inline float wp_lane(float4 a, uint i) { return i == 0 ? a.x : i == 1 ? a.y : i == 2 ? a.z : a.w; }
inline uint4 make_uint4(uint a, uint b, uint c, uint d) { return {a, b, c, d}; }
inline float4 wp_permute(float4 a, uint4 idx) {
    return {wp_lane(a, idx.x), wp_lane(a, idx.y), wp_lane(a, idx.z), wp_lane(a, idx.w)};
}

}  // namespace wp
#endif

// ------------------------------------------------------------- both sides ----------
WP_NAMESPACE_BEGIN

// Component access helpers that need no swizzles.
WP_FN float3 wp_xyz(float4 v) { return make_float3(v.x, v.y, v.z); }
WP_FN float4 wp_float4(float3 v, float w) { return make_float4(v.x, v.y, v.z, w); }
WP_FN float wp_component(float3 v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }
WP_FN float wp_max_component(float3 v) { return max(v.x, max(v.y, v.z)); }

// Number of trailing zero bits of a non-zero 64-bit word. OpenCL C 1.2 has no ctz, so it
// is built from popcount of the bits below the lowest set bit (portable, branch-free).
WP_FN int wp_ctz64(ulong x) {
#if defined(WP_OPENCL)
    return (int)popcount((x & (0 - x)) - 1);
#else
    return __builtin_ctzll(x);
#endif
}

// Four- and eight-lane comparisons as bit masks (bit i: lane i compares true), lane
// access by a run-time index, and broadcasts, for the wide BVH.
#if defined(WP_OPENCL)
WP_FN int wp_mask4(int4 c) { return (c.x & 1) | (c.y & 2) | (c.z & 4) | (c.w & 8); }
WP_FN int wp_mask4_le(float4 a, float4 b) { return wp_mask4(a <= b); }
WP_FN int wp_mask4_lt(float4 a, float4 b) { return wp_mask4(a < b); }
WP_FN int wp_mask4_eq(float4 a, float4 b) { return wp_mask4(a == b); }
WP_FN int wp_mask8(int8 c) {
    return (c.s0 & 1) | (c.s1 & 2) | (c.s2 & 4) | (c.s3 & 8) | (c.s4 & 16) | (c.s5 & 32) | (c.s6 & 64) |
           (c.s7 & 128);
}
WP_FN int wp_mask8_le(float8 a, float8 b) { return wp_mask8(a <= b); }
WP_FN int wp_mask8_lt(float8 a, float8 b) { return wp_mask8(a < b); }
WP_FN int wp_mask8_eq(float8 a, float8 b) { return wp_mask8(a == b); }
WP_FN float8 wp_splat8(float s) { return (float8)(s); }
#else
WP_FN int wp_mask4_le(float4 a, float4 b) {
    return (a.x <= b.x ? 1 : 0) | (a.y <= b.y ? 2 : 0) | (a.z <= b.z ? 4 : 0) | (a.w <= b.w ? 8 : 0);
}
WP_FN int wp_mask4_lt(float4 a, float4 b) {
    return (a.x < b.x ? 1 : 0) | (a.y < b.y ? 2 : 0) | (a.z < b.z ? 4 : 0) | (a.w < b.w ? 8 : 0);
}
WP_FN int wp_mask4_eq(float4 a, float4 b) {
    return (a.x == b.x ? 1 : 0) | (a.y == b.y ? 2 : 0) | (a.z == b.z ? 4 : 0) | (a.w == b.w ? 8 : 0);
}
inline float8 operator-(const float8& a, const float8& b) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = a.s[i] - b.s[i];
    return r;
}
inline float8 operator*(const float8& a, const float8& b) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = a.s[i] * b.s[i];
    return r;
}
inline float8 operator*(const float8& a, float b) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = a.s[i] * b;
    return r;
}
inline float8 min(const float8& a, const float8& b) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = min(a.s[i], b.s[i]);
    return r;
}
inline float8 max(const float8& a, const float8& b) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = max(a.s[i], b.s[i]);
    return r;
}
inline int wp_mask8_le(const float8& a, const float8& b) {
    int m = 0;
    for (int i = 0; i < 8; ++i) m |= a.s[i] <= b.s[i] ? 1 << i : 0;
    return m;
}
inline int wp_mask8_lt(const float8& a, const float8& b) {
    int m = 0;
    for (int i = 0; i < 8; ++i) m |= a.s[i] < b.s[i] ? 1 << i : 0;
    return m;
}
inline int wp_mask8_eq(const float8& a, const float8& b) {
    int m = 0;
    for (int i = 0; i < 8; ++i) m |= a.s[i] == b.s[i] ? 1 << i : 0;
    return m;
}
inline float8 wp_splat8(float v) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = v;
    return r;
}
#endif
// Lane i (0..3) of a float4, without going through memory.
WP_FN float wp_lane4(float4 v, int i) { return i == 0 ? v.x : (i == 1 ? v.y : (i == 2 ? v.z : v.w)); }
#if defined(WP_OPENCL)
WP_FN float wp_lane8(float8 v, int i) { return i < 4 ? wp_lane4(v.lo, i) : wp_lane4(v.hi, i - 4); }
#else
inline float wp_lane8(const float8& v, int i) { return v.s[i]; }
#endif
// Broadcast.
WP_FN float4 wp_splat4(float s) { return make_float4(s, s, s, s); }
// Number of trailing zero bits of a non-zero 32-bit word (see wp_ctz64).
WP_FN int wp_ctz32(uint x) {
#if defined(WP_OPENCL)
    return (int)popcount((x & (0u - x)) - 1u);
#else
    return __builtin_ctz(x);
#endif
}

WP_NAMESPACE_END

#endif  // WP_COMPAT_H
