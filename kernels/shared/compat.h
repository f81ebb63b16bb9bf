// compat.h — the only file that knows which language the shared code is compiled as.
//
// The headers in kernels/shared/ are compiled three ways:
//   * as OpenCL C 1.2 (the kernels), where vector types and math builtins are native;
//   * as C++20 on the host (tests, oracles, the upload code), where this file supplies
//     float3/float4/int4 and the OpenCL builtins the shared code uses;
//   * as CUDA C++ (nvcc -x cu, detected by __CUDACC__), where CUDA's own vector types
//     are used and this file supplies their operators and the OpenCL builtins.
// Shared code writes make_float3(...) instead of (float3)(...) and never uses swizzles
// other than .x .y .z .w, so the same text compiles everywhere. Stage files (kernels/*.cl)
// write the vocabulary below instead of OpenCL's keywords and work-item functions:
//   WP_KERNEL (an entry point), WP_GLOBAL / WP_LOCAL / WP_CONSTANT (address spaces; WP_LOCAL
//   only for a variable declared inside a kernel), WP_FN (a device function),
//   wp_global_id(), wp_local_id(), wp_barrier(), wp_atomic_inc(p), wp_atomic_add(p, v).
// tests/cuda/cuda_compile.cpp (ctest -L cuda-compile) compiles every kernels/*.cl with
// nvcc and as host C++, and compares the struct layouts of types.h with CUDA's.
//
// FP contraction is off on every side (the pragma below, -ffp-contract=off on the host,
// --fmad=false for CUDA, which nvcc does not default to: it fuses a*b+c unless told not
// to): a*b+c rounds twice everywhere, so host oracles and every device agree bit for bit.
// Where a fused multiply-add is wanted, write fma(). No fast math anywhere (no
// -cl-fast-relaxed-math, no --use_fast_math, no native_*/__fdividef).
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
#define make_uint2(a, b) ((uint2)((a), (b)))
#define make_float2(a, b) ((float2)((a), (b)))

#define wp_global_id() ((int)get_global_id(0))
#define wp_local_id() ((int)get_local_id(0))
// Work-group barrier over local memory (the only kind the stages use).
#define wp_barrier() barrier(CLK_LOCAL_MEM_FENCE)
// (a.z, a.w, a.x, a.y): swaps the two halves of a float4.
#define wp_swap_halves(a) ((a).zwxy)
// Permutes the lanes of a float4 by a per-ray index vector. On AVX one vpermilps: LLVM 15
// lowers shuffle() with a run-time mask through memory (a store, then one load per lane
// at a variable offset), three times per triangle test (perf on bench intersect).
// Both forms move the same bits.
#if defined(__AVX__) && defined(__x86_64__)
#define wp_permute(a, idx) __builtin_ia32_vpermilvarps((a), as_int4(idx))
#else
#define wp_permute(a, idx) shuffle((a), (idx))
#endif
#define wp_atomic_add(p, v) atomic_add((p), (v))
#define wp_atomic_inc(p) atomic_inc((p))
// A read-only table at file scope (e.g. sobol.h's direction numbers).
#define WP_CONSTANT_TABLE __constant

#elif defined(__CUDACC__)
// ---------------------------------------------------------------- CUDA C++ ----------
// Built with nvcc -x cu --fmad=false (see the top of this file). CUDA supplies float2,
// float3, float4, int2, int4, uint2, uint4 and make_*; float3 is 12 bytes here (16 in
// OpenCL C), which is why no shared struct holds one (types.h).
#include <cfloat>

#define WP_CUDA 1
#define WP_KERNEL extern "C" __global__
#define WP_GLOBAL
#define WP_LOCAL __shared__
#define WP_CONSTANT
#define WP_FN __device__ inline
#define WP_HD __host__ __device__ inline
#define WP_NAMESPACE_BEGIN
#define WP_NAMESPACE_END
#define WP_CONSTANT_TABLE static __constant__ const

typedef unsigned int uint;
typedef unsigned long ulong;  // the same type as glibc's sys/types.h ulong (LP64)
static_assert(sizeof(ulong) == 8, "OpenCL's ulong is 64 bits");
static_assert(sizeof(float4) == 16 && alignof(float4) == 16, "float4 as in OpenCL");
static_assert(sizeof(int4) == 16 && alignof(int4) == 16 && sizeof(uint4) == 16, "int4 as in OpenCL");

// One-dimensional launches only, as in OpenCL (global id = group * size + local id).
#define wp_global_id() ((int)(blockIdx.x * blockDim.x + threadIdx.x))
#define wp_local_id() ((int)threadIdx.x)
#define wp_barrier() __syncthreads()
// OpenCL's atomic_inc/atomic_add return the old value, as atomicAdd does (CUDA's atomicInc
// wraps at a bound: not the same function).
#define wp_atomic_add(p, v) atomicAdd((p), (v))
#define wp_atomic_inc(p) atomicAdd((p), 1)

// Eight lanes; shared code reaches them only through the wp_*8 helpers below.
struct __align__(32) float8 { float s[8]; };
static_assert(sizeof(float8) == 32, "float8 as in OpenCL");

// Scalar builtins that CUDA names differently. min, max, fabs, sqrt, fmin, fmax, fma,
// floor, copysign, isfinite, isnan, isinf, sin, cos, tan, exp, log, pow, acos, asin, atan2, erf,
// log2, exp2, round, trunc are CUDA's
// own float overloads (IEEE, correctly rounded where OpenCL requires it; no fast math).
__device__ inline uint as_uint(float f) { return __float_as_uint(f); }
__device__ inline int as_int(float f) { return __float_as_int(f); }
__device__ inline float as_float(uint u) { return __uint_as_float(u); }
__device__ inline float as_float(int i) { return __int_as_float(i); }
__device__ inline uint popcount(uint x) { return (uint)__popc(x); }
__device__ inline ulong popcount(ulong x) { return (ulong)__popcll(x); }

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
#define WP_LOCAL
#define WP_CONSTANT
#define WP_FN inline
#define WP_HD inline
#define WP_NAMESPACE_BEGIN namespace wp {
#define WP_NAMESPACE_END }
#define WP_CONSTANT_TABLE static const

namespace wp {

using uint = std::uint32_t;
using ulong = std::uint64_t;

struct float2 { float x, y; };
struct float3 { float x, y, z; };
struct alignas(16) float4 { float x, y, z, w; };
struct alignas(16) int4 { int x, y, z, w; };
struct alignas(16) uint4 { uint x, y, z, w; };
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
inline uint4 make_uint4(uint a, uint b, uint c, uint d) { return {a, b, c, d}; }
inline uint2 make_uint2(uint a, uint b) { return {a, b}; }

// Work-item functions for kernels compiled as host C++: one work-item (id 0) unless a host
// driver sets wp::host_item (each thread its own).
struct HostItem { int global_id = 0, local_id = 0; };
inline thread_local HostItem host_item;
inline int wp_global_id() { return host_item.global_id; }
inline int wp_local_id() { return host_item.local_id; }
inline void wp_barrier() {}  // one work-item per group on the host
inline int wp_atomic_add(int* p, int v) { int old = *p; *p += v; return old; }
inline int wp_atomic_inc(int* p) { return wp_atomic_add(p, 1); }

// OpenCL C builtins used by the shared code. min/max follow OpenCL: for floats the result
// is unspecified with NaN operands (the shared code never feeds them NaN); fmin/fmax
// return the non-NaN operand.
inline float min(float a, float b) { return b < a ? b : a; }
inline float max(float a, float b) { return a < b ? b : a; }
inline int min(int a, int b) { return b < a ? b : a; }
inline int max(int a, int b) { return a < b ? b : a; }
inline uint min(uint a, uint b) { return b < a ? b : a; }
inline uint max(uint a, uint b) { return a < b ? b : a; }
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
using std::tan;
using std::exp;
using std::log;
using std::pow;
using std::acos;
using std::asin;
using std::atan2;
using std::erf;
using std::log2;
using std::exp2;
using std::round;
using std::trunc;
inline uint as_uint(float f) { uint u; std::memcpy(&u, &f, 4); return u; }
inline int as_int(float f) { int i; std::memcpy(&i, &f, 4); return i; }
inline float as_float(uint u) { float f; std::memcpy(&f, &u, 4); return f; }
inline float as_float(int i) { float f; std::memcpy(&f, &i, 4); return f; }
inline uint popcount(uint x) { return (uint)__builtin_popcount(x); }
inline ulong popcount(ulong x) { return (ulong)__builtin_popcountll(x); }

}  // namespace wp
#endif

#if !defined(WP_OPENCL)
// ------------------------------------------------- host and CUDA: vector operators ----------
// What OpenCL C has built in, written once for the C++ host and CUDA (WP_HD).
WP_NAMESPACE_BEGIN

// float3 arithmetic, component-wise as in OpenCL C.
WP_HD float3 operator+(float3 a, float3 b) { return make_float3(a.x + b.x, a.y + b.y, a.z + b.z); }
WP_HD float3 operator-(float3 a, float3 b) { return make_float3(a.x - b.x, a.y - b.y, a.z - b.z); }
WP_HD float3 operator*(float3 a, float3 b) { return make_float3(a.x * b.x, a.y * b.y, a.z * b.z); }
WP_HD float3 operator/(float3 a, float3 b) { return make_float3(a.x / b.x, a.y / b.y, a.z / b.z); }
WP_HD float3 operator*(float3 a, float s) { return make_float3(a.x * s, a.y * s, a.z * s); }
WP_HD float3 operator*(float s, float3 a) { return make_float3(a.x * s, a.y * s, a.z * s); }
WP_HD float3 operator/(float3 a, float s) { return make_float3(a.x / s, a.y / s, a.z / s); }
WP_HD float3 operator-(float3 a) { return make_float3(-a.x, -a.y, -a.z); }
WP_HD float3& operator+=(float3& a, float3 b) { a = a + b; return a; }
WP_HD float3& operator*=(float3& a, float3 b) { a = a * b; return a; }
WP_HD float3& operator*=(float3& a, float s) { a = a * s; return a; }

// float4 arithmetic.
WP_HD float4 operator+(float4 a, float4 b) { return make_float4(a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w); }
WP_HD float4 operator-(float4 a, float4 b) { return make_float4(a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w); }
WP_HD float4 operator*(float4 a, float4 b) { return make_float4(a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w); }
WP_HD float4 operator*(float4 a, float s) { return make_float4(a.x * s, a.y * s, a.z * s, a.w * s); }
WP_HD float4 operator/(float4 a, float4 b) { return make_float4(a.x / b.x, a.y / b.y, a.z / b.z, a.w / b.w); }
WP_HD float4 operator-(float4 a, float s) { return make_float4(a.x - s, a.y - s, a.z - s, a.w - s); }
WP_HD float4& operator+=(float4& a, float4 b) { a = a + b; return a; }

WP_HD float clamp(float x, float lo, float hi) { return min(max(x, lo), hi); }
WP_HD float4 min(float4 a, float4 b) { return make_float4(min(a.x, b.x), min(a.y, b.y), min(a.z, b.z), min(a.w, b.w)); }
WP_HD float4 max(float4 a, float4 b) { return make_float4(max(a.x, b.x), max(a.y, b.y), max(a.z, b.z), max(a.w, b.w)); }
WP_HD float3 min(float3 a, float3 b) { return make_float3(min(a.x, b.x), min(a.y, b.y), min(a.z, b.z)); }
WP_HD float3 max(float3 a, float3 b) { return make_float3(max(a.x, b.x), max(a.y, b.y), max(a.z, b.z)); }
WP_HD float3 fabs(float3 a) { return make_float3(fabs(a.x), fabs(a.y), fabs(a.z)); }
WP_HD float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
WP_HD float3 cross(float3 a, float3 b) {
    return make_float3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
// length/normalize: the plain formulas. OpenCL's builtins rescale when |v|^2 overflows or
// underflows; these do not (|v| must stay below 1.8e19): the shared code applies them to
// directions and edges of scenes far inside that range. Elsewhere they agree bit for bit
// with PoCL's (tests/test_compat.cpp).
WP_HD float length(float3 a) { return sqrt(dot(a, a)); }
WP_HD float3 normalize(float3 a) { return a * (1.0f / length(a)); }
WP_HD float3 copysign(float3 a, float3 b) {
    return make_float3(copysign(a.x, b.x), copysign(a.y, b.y), copysign(a.z, b.z));
}

// (a.z, a.w, a.x, a.y): swaps the two halves of a float4.
WP_HD float4 wp_swap_halves(float4 a) { return make_float4(a.z, a.w, a.x, a.y); }
WP_HD float wp_lane(float4 a, uint i) { return i == 0 ? a.x : i == 1 ? a.y : i == 2 ? a.z : a.w; }
// OpenCL's shuffle(a, idx): lane i of the result is lane idx[i] of a (idx in 0..3).
WP_HD float4 wp_permute(float4 a, uint4 idx) {
    return make_float4(wp_lane(a, idx.x), wp_lane(a, idx.y), wp_lane(a, idx.z), wp_lane(a, idx.w));
}

// float8: the few operations the wide BVH uses.
WP_HD float8 operator-(const float8& a, const float8& b) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = a.s[i] - b.s[i];
    return r;
}
WP_HD float8 operator*(const float8& a, const float8& b) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = a.s[i] * b.s[i];
    return r;
}
WP_HD float8 operator*(const float8& a, float b) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = a.s[i] * b;
    return r;
}
WP_HD float8 min(const float8& a, const float8& b) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = min(a.s[i], b.s[i]);
    return r;
}
WP_HD float8 max(const float8& a, const float8& b) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = max(a.s[i], b.s[i]);
    return r;
}

WP_NAMESPACE_END
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
    return (int)popcount((x & (0 - x)) - 1);
}

// Four- and eight-lane comparisons as bit masks (bit i: lane i compares true), lane
// access by a run-time index, and broadcasts, for the wide BVH.
// On x86 OpenCL compilers that target AVX (PoCL's CPU devices define __AVX__ and
// __AVX2__ for the host CPU) the mask is one movmskps and the lane one vpermps: LLVM 15
// turned the portable forms into a masked constant load plus a seven-instruction OR
// reduction per node visit, and a compare-and-branch chain per lane read (perf on
// bench intersect). Other devices (GPUs, Oclgrind's SPIR) compile the portable forms;
// both give the same bits.
#if defined(WP_OPENCL) && defined(__AVX__) && defined(__x86_64__)
WP_FN int wp_mask4(int4 c) { return __builtin_ia32_movmskps(as_float4(c)); }
WP_FN int wp_mask8(int8 c) { return __builtin_ia32_movmskps256(as_float8(c)); }
#elif defined(WP_OPENCL)
WP_FN int wp_mask4(int4 c) { return (c.x & 1) | (c.y & 2) | (c.z & 4) | (c.w & 8); }
WP_FN int wp_mask8(int8 c) {
    return (c.s0 & 1) | (c.s1 & 2) | (c.s2 & 4) | (c.s3 & 8) | (c.s4 & 16) | (c.s5 & 32) | (c.s6 & 64) |
           (c.s7 & 128);
}
#endif
#if defined(WP_OPENCL)
WP_FN int wp_mask4_le(float4 a, float4 b) { return wp_mask4(a <= b); }
WP_FN int wp_mask4_lt(float4 a, float4 b) { return wp_mask4(a < b); }
WP_FN int wp_mask4_eq(float4 a, float4 b) { return wp_mask4(a == b); }
WP_FN int wp_mask8_le(float8 a, float8 b) { return wp_mask8(a <= b); }
WP_FN int wp_mask8_lt(float8 a, float8 b) { return wp_mask8(a < b); }
WP_FN int wp_mask8_eq(float8 a, float8 b) { return wp_mask8(a == b); }
WP_FN float8 wp_splat8(float s) { return (float8)(s); }
WP_FN float8 wp_float8(float4 lo, float4 hi) { return (float8)(lo, hi); }
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
WP_FN int wp_mask8_le(const float8& a, const float8& b) {
    int m = 0;
    for (int i = 0; i < 8; ++i) m |= a.s[i] <= b.s[i] ? 1 << i : 0;
    return m;
}
WP_FN int wp_mask8_lt(const float8& a, const float8& b) {
    int m = 0;
    for (int i = 0; i < 8; ++i) m |= a.s[i] < b.s[i] ? 1 << i : 0;
    return m;
}
WP_FN int wp_mask8_eq(const float8& a, const float8& b) {
    int m = 0;
    for (int i = 0; i < 8; ++i) m |= a.s[i] == b.s[i] ? 1 << i : 0;
    return m;
}
WP_FN float8 wp_splat8(float v) {
    float8 r;
    for (int i = 0; i < 8; ++i) r.s[i] = v;
    return r;
}
// Lanes 0..3 from lo, 4..7 from hi.
WP_FN float8 wp_float8(float4 lo, float4 hi) {
    float8 r = {{lo.x, lo.y, lo.z, lo.w, hi.x, hi.y, hi.z, hi.w}};
    return r;
}
#endif
// Lane i (0..3) of a float4, without going through memory.
WP_FN float wp_lane4(float4 v, int i) { return i == 0 ? v.x : (i == 1 ? v.y : (i == 2 ? v.z : v.w)); }
#if defined(WP_OPENCL) && defined(__AVX2__) && defined(__x86_64__)
WP_FN float wp_lane8(float8 v, int i) {
    float8 p = __builtin_ia32_permvarsf256(v, (int8)(i));
    return p.s0;
}
#elif defined(WP_OPENCL)
WP_FN float wp_lane8(float8 v, int i) { return i < 4 ? wp_lane4(v.lo, i) : wp_lane4(v.hi, i - 4); }
#else
WP_FN float wp_lane8(const float8& v, int i) { return v.s[i]; }
#endif
// Broadcast.
WP_FN float4 wp_splat4(float s) { return make_float4(s, s, s, s); }
// Number of trailing zero bits of a non-zero 32-bit word (see wp_ctz64).
WP_FN int wp_ctz32(uint x) {
    return (int)popcount((x & (0u - x)) - 1u);
}

WP_NAMESPACE_END


// A store of a scalar or vector that a later stage reads and this one does not (the
// queues shade pushes). With WP_STREAM_STORES (KernelConfig::stream_stores: CPU devices
// whose cache the pool's queues outgrow) a non-temporal store: the line is written without
// first being read for ownership, which halves the memory traffic of a write that misses
// the cache. Else a plain store. The same bits either way.
#ifndef WP_STREAM_STORES
#define WP_STREAM_STORES 0
#endif
#if WP_STREAM_STORES && defined(WP_OPENCL) && defined(__clang__)
#define WP_STORE_STREAM(ptr, value) __builtin_nontemporal_store((value), (ptr))
#else
#define WP_STORE_STREAM(ptr, value) (*(ptr) = (value))
#endif

#endif  // WP_COMPAT_H
