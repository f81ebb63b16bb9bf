// test_hard.cl — probe kernels of the hard-case suite (tests/test_hard*.cpp, `wavepath bench
// hard`). They only make rays and count results; the tracing itself is done by the real
// intersect kernels (intersect.cl, launched in between), so what is tested is what renders.
//
//   hard_edge_rays   reads segments[2 * n_seg] (float4 pairs a, b; a == b for a vertex)
//                    and writes rays[0..count): ray g = first_round * n_seg + first_seg + i
//                    (batches continue the numbering) aims at a point of segment g % n_seg
//                    (a + s (b - a), s uniform in [smin, smax], exactly a for a vertex).
//                    Origins (mode):
//                      WP_HARD_CONVEX: a closed convex mesh around `center`. Odd rounds
//                        (g / n_seg odd) start inside, within inner of the centre (every
//                        line from inside leaves the mesh); even rounds start outside at
//                        center + k (p - center), k in [1.5, 4], moved by at most a quarter
//                        of (k - 1) |p - center| (so they reach p well away from grazing).
//                      WP_HARD_SHEET: an open surface with normal near +z: from above and
//                        below alternately, at distance `radius` from p, within 30 degrees
//                        of the z axis.
//                    Every such ray crosses the surface at p in exact arithmetic: any miss
//                    is a crack.
//   hard_count       reads hits[0..count) and adds to out[0] the misses (prim < 0), to
//                    out[1] the hits whose t is not finite, to out[2] hits with t <= 0.
#include "shared/types.h"

#define WP_HARD_CONVEX 0
#define WP_HARD_SHEET 1

// A counter-based hash (splitmix-like, 32-bit) for reproducible per-item numbers.
WP_FN uint wp_hard_hash(uint x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// Uniform in [0, 1) from 24 bits.
WP_FN float wp_hard_u01(uint* state) {
    *state = wp_hard_hash(*state + 0x9e3779b9u);
    return (float)(*state >> 8) * 0x1p-24f;
}

// Uniform in the unit ball (rejection).
WP_FN float3 wp_hard_ball(uint* state) {
    for (int k = 0; k < 64; ++k) {
        float3 p = make_float3(2.0f * wp_hard_u01(state) - 1.0f, 2.0f * wp_hard_u01(state) - 1.0f,
                               2.0f * wp_hard_u01(state) - 1.0f);
        if (dot(p, p) <= 1.0f) return p;
    }
    return make_float3(0.0f, 0.0f, 0.0f);
}

WP_KERNEL void hard_edge_rays(WP_GLOBAL const float4* segments, int n_seg, float cx, float cy, float cz, float inner,
                             float radius, float smin, float smax, int mode, uint seed,
                             int first_seg, uint first_round, int count, WP_GLOBAL Ray* rays) {
    int i = wp_global_id();
    if (i >= count) return;
    // Global ray number first_round * n_seg + first_seg + i (batches continue the
    // sequence), split into (round, segment) in 32-bit arithmetic without a % (a 64-bit
    // or div/rem pair compiles to LLVM `freeze`, which Oclgrind's checker cannot run).
    uint idx = (uint)first_seg + (uint)i;
    uint q = idx / (uint)n_seg;
    int k = (int)(idx - q * (uint)n_seg);
    uint round = first_round + q;
    uint st = wp_hard_hash((uint)k ^ wp_hard_hash(round + seed));
    float3 a = wp_xyz(segments[2 * k]), b = wp_xyz(segments[2 * k + 1]);
    float3 p = a;
    if (a.x != b.x || a.y != b.y || a.z != b.z) {
        float s = smin + (smax - smin) * wp_hard_u01(&st);
        p = a + (b - a) * s;
    }
    float3 c = make_float3(cx, cy, cz);
    float3 o;
    if (mode == WP_HARD_CONVEX) {
        if (round & 1u) {
            o = c + wp_hard_ball(&st) * inner;
        } else {
            float kk = 1.5f + 2.5f * wp_hard_u01(&st);
            float3 r = p - c;
            o = c + r * kk + wp_hard_ball(&st) * (0.25f * (kk - 1.0f) * length(r));
        }
    } else {
        float3 w = wp_hard_ball(&st) * 0.5f;
        w.z += (round & 1u) ? -1.0f : 1.0f;
        o = p + normalize(w) * radius;
    }
    float3 d = p - o;
    Ray ray;
    ray.org = make_float4(o.x, o.y, o.z, 0.0f);
    ray.dir = make_float4(d.x, d.y, d.z, FLT_MAX);
    rays[i] = ray;
}

WP_KERNEL void hard_count(WP_GLOBAL const Hit* hits, int count, WP_GLOBAL int* out) {
    int i = wp_global_id();
    if (i >= count) return;
    Hit h = hits[i];
    if (h.prim < 0) {
        wp_atomic_add(&out[0], 1);
        return;
    }
    if (!isfinite(h.t)) wp_atomic_add(&out[1], 1);
    if (!(h.t > 0.0f)) wp_atomic_add(&out[2], 1);
}
