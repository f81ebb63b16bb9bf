// rng.h — counter-based random numbers: every value is a pure function of its key.
//
// A sample's random numbers are keyed by (seed, pixel, sample index, bounce, dimension
// group), so any path can be reproduced alone and the image does not depend on the order
// in which work-items run or paths sit in a queue. The hash is pcg4d from Jarzynski &
// Olano, "Hash Functions for GPU Rendering", JCGT 9(3), 2020 (their best quality/speed
// trade-off for 4D input): one call turns a 4D key into four well-mixed 32-bit words.
// Unsigned arithmetic wraps modulo 2^32 on every backend, so host and device agree bit for
// bit and tests can reproduce a kernel's random numbers on the host.
#ifndef WP_RNG_H
#define WP_RNG_H

#include "compat.h"
#include "sobol.h"

// The sampler (WP_SAMPLER, estimator.h): the counter-based pcg4d numbers below, or
// Owen-scrambled Sobol points (sobol.h) indexed by the sample, scrambled per (seed, pixel,
// bounce, group); the default is the shipped one.
#include "estimator.h"
#ifndef WP_SAMPLER
#define WP_SAMPLER WP_DEFAULT_SAMPLER
#endif

WP_NAMESPACE_BEGIN

// Dimension groups (4 numbers each) within one bounce. New consumers take new groups.
#define WP_RNG_CAMERA 0    // bounce 0 only: (pixel jitter x, y, unused, unused)
#define WP_RNG_BSDF 1      // direction sampling at a surface: (u1, u2, lobe choice, unused)
#define WP_RNG_LIGHT 2     // next-event estimation: (point u1, point u2, light choice, unused)
#define WP_RNG_RR 3        // Russian roulette: (survival, unused, unused, unused)
#define WP_RNG_LENS 4      // bounce 0 only, thin-lens cameras: (lens u1, u2, unused, unused)
#define WP_RNG_GROUPS 16   // groups per bounce (the key packs bounce * 16 + group)

typedef struct Rng4 {
    uint x, y, z, w;
} Rng4;

// pcg4d (Jarzynski & Olano 2020, listing in section 4): an LCG step per lane, then two
// rounds of cross-lane multiply-adds around an xorshift.
WP_FN Rng4 wp_pcg4d(uint a, uint b, uint c, uint d) {
    Rng4 v;
    v.x = a * 1664525u + 1013904223u;
    v.y = b * 1664525u + 1013904223u;
    v.z = c * 1664525u + 1013904223u;
    v.w = d * 1664525u + 1013904223u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    v.x ^= v.x >> 16;
    v.y ^= v.y >> 16;
    v.z ^= v.z >> 16;
    v.w ^= v.w >> 16;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    return v;
}

// A uniform float in [0, 1) from the top 24 bits of a word (exactly representable).
WP_FN float wp_uint_to_unit(uint x) { return (float)(x >> 8) * (1.0f / 16777216.0f); }

// RQMC replicates (WP_SOBOL_REPLICATES = K, a power of two; only defined when K > 1, so
// K = 1 compiles to the sampler of before): sample s of a pixel belongs to replicate
// r = s mod K and is point s / K of replicate r's own Owen-scrambled Sobol sequence, its
// scramble seed hashed from (the pixel's seed, r). Each replicate's samples of a pixel are
// then a prefix 0, 1, 2, ... of an independently scrambled (0,2)-sequence: K independent
// RQMC estimates of the pixel, whose spread estimates the variance of their mean
// (kernels/shared/adaptive.h). With K = 1 the index is s and the seed the pixel's seed.
#ifndef WP_SOBOL_REPLICATES
#define WP_SOBOL_REPLICATES 1
#endif

// The scramble seed of replicate r of a dimension group whose K = 1 seed is `base`.
WP_FN uint wp_replicate_scramble(uint base, uint r) {
    return wp_pcg4d(base, r, 0x7e91cu, 0x50b02u).x;
}

// Four Owen-scrambled Sobol numbers (32-bit words) for (seed, pixel, sample, bounce, group)
// with `replicates` RQMC replicates (a power of two; 1: none). A function of its own so the
// host can reproduce any K (tests/test_adaptive.cpp); the kernels pass the constant.
WP_FN uint4 wp_sobol_rng4(uint seed, uint pixel, uint sample, uint bounce, uint group,
                          uint replicates) {
    Rng4 h = wp_pcg4d(pixel, bounce * (uint)WP_RNG_GROUPS + group, seed, 0x50b01u);
    uint scramble = h.x;
    uint index = sample;
    if (replicates > 1u) {
        scramble = wp_replicate_scramble(h.x, sample & (replicates - 1u));
        index = sample / replicates;
    }
    return wp_sobol_owen4(index, scramble);
}

// Four uniform numbers in [0, 1) for (seed, pixel, sample, bounce, group).
// With WP_SAMPLER_SOBOL: the sample-th Owen-scrambled Sobol point, its scramble seed
// hashed from (pixel, bounce, group, seed), so every pixel and dimension group gets an
// independent scramble of the same low-discrepancy sequence (with replicates: above).
WP_FN float4 wp_rng4(uint seed, uint pixel, uint sample, uint bounce, uint group) {
#if WP_SAMPLER == WP_SAMPLER_SOBOL
    uint4 q = wp_sobol_rng4(seed, pixel, sample, bounce, group, (uint)WP_SOBOL_REPLICATES);
    Rng4 r;
    r.x = q.x;
    r.y = q.y;
    r.z = q.z;
    r.w = q.w;
#else
    Rng4 r = wp_pcg4d(pixel, sample, bounce * (uint)WP_RNG_GROUPS + group, seed);
#endif
    return make_float4(wp_uint_to_unit(r.x), wp_uint_to_unit(r.y), wp_uint_to_unit(r.z),
                       wp_uint_to_unit(r.w));
}

WP_NAMESPACE_END

#endif  // WP_RNG_H
