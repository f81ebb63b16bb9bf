// test_sampling.cl — probe kernels for the statistical tests of tests/test_sampling.cpp:
// they call the shared sampling code exactly as shade.cl does and write what it drew.
// Built with the options of the strategy under test (e.g. -D WP_SAMPLING=3
// -D WP_GLOSSY_MODEL=1). Random numbers: wp_rng4(seed, i, 0, 0, group) for item i.
#include "shared/bsdf.h"
#include "shared/lights.h"
#include "shared/rng.h"
#include "shared/rng_lanes.h"

// probe_bsdf_sample
// reads   m, the arriving direction d and normal ns (xyz, unit), front (glass: from
//         outside), seed
// writes  out[i] = (wo, pdf) for i < n, or (0, 0, 0, -1) when the sample is absorbed
WP_KERNEL void probe_bsdf_sample(MaterialData m, float4 d, float4 ns, int front, uint seed,
                                int n, WP_GLOBAL float4* out) {
    int i = wp_global_id();
    if (i >= n) return;
    float4 u = wp_rng4(seed, (uint)i, 0u, 0u, WP_RNG_BSDF);
    float3 wo, weight;
    float pdf;
    int specular;
    if (wp_bsdf_sample_pdf(m, 0, wp_xyz(d), wp_xyz(ns), front, u, &wo, &weight, &pdf,
                           &specular))
        out[i] = wp_float4(wo, pdf);
    else
        out[i] = make_float4(0.0f, 0.0f, 0.0f, -1.0f);
}

// probe_light_sample
// reads   tris (scene order), the light table (lights.h), seed
// writes  light[i] = the chosen light index k, point[i] = (b1, b2, pdf_area, 0): the
//         barycentrics of the point on triangle light_prims[k], for i < n
WP_KERNEL void probe_light_sample(WP_GLOBAL const float* light_cdf, int light_count,
                                 WP_GLOBAL const int* light_guide,
                                 int light_guide_size, WP_GLOBAL const int* light_prims,
                                 WP_GLOBAL const float* light_pdf_area, uint seed, int n,
                                 WP_GLOBAL int* light, WP_GLOBAL float4* point) {
    int i = wp_global_id();
    if (i >= n) return;
    float4 ul = wp_rng4(seed, (uint)i, 0u, 0u, WP_RNG_LIGHT);
    int k = wp_light_pick(light_cdf, light_count, light_guide, light_guide_size, ul.z);
    float2 b = wp_sample_triangle_barycentric(ul.x, ul.y);
    light[i] = k;
    point[i] = make_float4(b.x, b.y, light_pdf_area[light_prims[k]], 0.0f);
}

// wp_rng4 of (seed, pixel i, sample 3 i + 1, bounce i % 7, group i % 5) as raw bits: the
// device's vector Sobol path against the host's scalar one (tests/test_sampling.cpp).
WP_KERNEL void probe_rng4(uint seed, int n, WP_GLOBAL uint4* out) {
    int i = wp_global_id();
    if (i >= n) return;
    float4 u = wp_rng4(seed, (uint)i, 3u * (uint)i + 1u, (uint)(i % 7), (uint)(i % 5));
    out[i] = make_uint4(as_uint(u.x), as_uint(u.y), as_uint(u.z), as_uint(u.w));
}

// wp_rng4_lanes for eight keys per item, as raw bits: lane l of item i has the key (seed,
// pixel[8 i + l], sample[8 i + l], bounce[i], group[i]) and writes component c to
// out[32 i + 8 c + l]; wp_rng2_lanes' two numbers go to narrow[24 i + l] and
// narrow[24 i + 8 + l], wp_rng1_lanes' one to narrow[24 i + 16 + l]
// (tests/test_sampling.cpp compares them with the host's wp_rng4).
// The functions are OpenCL-only; CUDA and the host run the scalar function per lane.
WP_KERNEL void probe_rng4_lanes(uint seed, int n, WP_GLOBAL const uint* pixel,
                                WP_GLOBAL const uint* sample, WP_GLOBAL const uint* bounce,
                                WP_GLOBAL const uint* group, WP_GLOBAL uint* out,
                                WP_GLOBAL uint* narrow) {
    int i = wp_global_id();
    if (i >= n) return;
#if defined(WP_OPENCL)
    float8 x, y, z, w;
    const uint8 p = vload8(i, pixel), s = vload8(i, sample);
    wp_rng4_lanes(seed, p, s, bounce[i], group[i], &x, &y, &z, &w);
    vstore8(as_uint8(x), 4 * i + 0, out);
    vstore8(as_uint8(y), 4 * i + 1, out);
    vstore8(as_uint8(z), 4 * i + 2, out);
    vstore8(as_uint8(w), 4 * i + 3, out);
    wp_rng2_lanes(seed, p, s, bounce[i], group[i], &x, &y);
    vstore8(as_uint8(x), 3 * i + 0, narrow);
    vstore8(as_uint8(y), 3 * i + 1, narrow);
    vstore8(as_uint8(wp_rng1_lanes(seed, p, s, bounce[i], group[i])), 3 * i + 2, narrow);
#else
    for (int l = 0; l < 8; ++l) {
        float4 u = wp_rng4(seed, pixel[8 * i + l], sample[8 * i + l], bounce[i], group[i]);
        out[32 * i + l] = as_uint(u.x);
        out[32 * i + 8 + l] = as_uint(u.y);
        out[32 * i + 16 + l] = as_uint(u.z);
        out[32 * i + 24 + l] = as_uint(u.w);
        narrow[24 * i + l] = narrow[24 * i + 16 + l] = as_uint(u.x);
        narrow[24 * i + 8 + l] = as_uint(u.y);
    }
#endif
}

// wp_sincos_2pi(i / n) as raw bits (tests/test_sampling.cpp: the same bits as the host's).
WP_KERNEL void probe_sincos(int n, WP_GLOBAL uint2* out) {
    int i = wp_global_id();
    if (i > n) return;
    float s, c;
    wp_sincos_2pi((float)i / (float)n, &s, &c);
    out[i] = make_uint2(as_uint(s), as_uint(c));
}
