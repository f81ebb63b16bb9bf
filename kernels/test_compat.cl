// test_compat.cl — the compatibility layer's own test (tests/test_compat.cpp): each work-item
// runs the compat.h functions that differ between OpenCL C and the C++/CUDA definitions
// (lane permutes, masks and lane reads of four and eight lanes, min/max, bit casts, ctz,
// float3 algebra) on its inputs, and the host compares the results with the same calls compiled as C++. A lane in the wrong slot
// (LuxCore's vstore4 .w once was) fails here, not in a render.
//
// probe_compat
//   reads   a[i], b[i] (float4), idx[i] (uint4 of lanes 0..3), bits[i] (a non-zero ulong)
//   writes  f[WP_COMPAT_F * i + k] (float4 results) and n[WP_COMPAT_N * i + k] (int
//           results) for i < count, in the order listed in the kernel
#include "shared/compat.h"

#define WP_COMPAT_F 10
#define WP_COMPAT_N 12

WP_KERNEL void probe_compat(WP_GLOBAL const float4* a, WP_GLOBAL const float4* b,
                            WP_GLOBAL const uint4* idx, WP_GLOBAL const ulong* bits, int count,
                            WP_GLOBAL float4* f, WP_GLOBAL int* n) {
    int i = wp_global_id();
    if (i >= count) return;
    float4 x = a[i], y = b[i];
    float3 x3 = wp_xyz(x), y3 = wp_xyz(y);
    WP_GLOBAL float4* fo = f + WP_COMPAT_F * i;
    WP_GLOBAL int* no = n + WP_COMPAT_N * i;
    fo[0] = wp_permute(x, idx[i]);
    fo[1] = wp_swap_halves(x);
    fo[2] = min(x, y);
    fo[3] = max(x, y);
    fo[4] = x * y - y * 0.5f + x;
    fo[5] = wp_float4(cross(x3, y3), dot(x3, y3));
    fo[6] = wp_float4(fabs(x3) + copysign(y3, x3), wp_max_component(x3));
    fo[7] = wp_float4(normalize(x3), length(x3));
    // Eight lanes from two float4s, so that lane order is seen (a splat would hide it).
    float8 xy = wp_float8(x, y), yx = wp_float8(y, x), yy = wp_float8(y, y);
    fo[8] = make_float4(wp_lane4(x, (int)idx[i].x), wp_lane8(xy, (int)idx[i].y + 4 * (i & 1)),
                        clamp(x.x, -0.5f, 0.5f), as_float(as_uint(x.y) ^ 0x80000000u));
    fo[9] = make_float4(fmin(x.x, y.x), fmax(x.y, y.y), sqrt(fabs(x.z)), floor(x.w));
    no[0] = wp_mask4_le(x, y);
    no[1] = wp_mask4_lt(x, y);
    no[2] = wp_mask4_eq(x, y);
    no[3] = wp_mask8_le(xy, yx) | (wp_mask8_le(wp_splat8(x.x), wp_splat8(y.x)) << 8);
    no[4] = wp_mask8_lt(xy, yx) | (wp_mask8_lt(wp_splat8(x.y), wp_splat8(y.y)) << 8);
    no[5] = wp_mask8_eq(xy, yy) | (wp_mask8_eq(wp_splat8(x.z), wp_splat8(y.z)) << 8);
    no[6] = wp_ctz32((uint)bits[i] | 0x80000000u);
    no[7] = wp_ctz64(bits[i]);
    no[8] = as_int(x.x);
    no[9] = (int)as_uint(y.w);
    no[10] = isfinite(x.w) ? 1 : 0;
    no[11] = min(i, 7) + max((int)idx[i].z, 1);
}
