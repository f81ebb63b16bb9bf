// rng_lanes.h — wp_rng4 (rng.h) for eight independent keys at once, as eight-lane vectors.
//
// PoCL vectorises only what a work-item spells out with vector types (NOTES-pocl.md, trap
// 3), so a work-item that handles eight paths gets their random numbers cheaply only when
// the hash, the bit reversals, the Laine-Karras permutations and the float conversion run
// on uint8 / float8 over the lanes. Every step is the scalar function's, lane by lane
// (integer arithmetic wraps mod 2^32, the conversion is exact), so lane l holds exactly the
// bits of wp_rng4(seed, pixel[l], sample[l], bounce, group) for both samplers and every
// WP_SOBOL_REPLICATES (tests/test_sampling.cpp checks it against the host's wp_rng4).
// OpenCL C only: the host and CUDA use the scalar function.
#ifndef WP_RNG_LANES_H
#define WP_RNG_LANES_H

#include "rng.h"

#if defined(WP_OPENCL)

// pcg4d (rng.h) on eight keys; each argument may be a uniform uint (broadcast) or a uint8.
#define WP_PCG4D_LANES(a, b, c, d, vx, vy, vz, vw) \
    do {                                           \
        vx = (a) * 1664525u + 1013904223u;         \
        vy = (b) * 1664525u + 1013904223u;         \
        vz = (c) * 1664525u + 1013904223u;         \
        vw = (d) * 1664525u + 1013904223u;         \
        vx += vy * vw;                             \
        vy += vz * vx;                             \
        vz += vx * vy;                             \
        vw += vy * vz;                             \
        vx ^= vx >> 16;                            \
        vy ^= vy >> 16;                            \
        vz ^= vz >> 16;                            \
        vw ^= vw >> 16;                            \
        vx += vy * vw;                             \
        vy += vz * vx;                             \
        vz += vx * vy;                             \
        vw += vy * vz;                             \
    } while (0)

// (wp_uint4_rows: sobol.h)

// The four bit-reversed Sobol coordinates (wp_sobol4_reversed) of eight indices j, as
// four uint8 (x0: dimension 0 of every lane, ...). The nibble table is read per lane: a
// lane's eight 128-bit rows XORed as one uint4, then the 8 x uint4 transposed into
// 4 x uint8. Row k of nibble v starts at byte 256 k + 16 v, so the byte offset is the
// nibble shifted to bits 4..7 (one shift and one mask; 256 k folds into the address) and
// the row is loaded as one vector (vload4 of the same row became two 64-bit scalar XORs).
// Measured on PoCL 3.1 (1M lanes, one thread): 5.1 ns per lane, against 6.4 with vload4
// and row indices, 6.8 with the 64 indices computed as uint8 vectors and stored for the
// per-lane loads, and 8.2 gathering each dimension with uint8 row indices (LLVM emits no
// gather: 32 scalar loads and inserts per nibble).
WP_FN void wp_sobol4_reversed_lanes(uint8 j, uint8* x0, uint8* x1, uint8* x2, uint8* x3) {
    uint jl[8];
    vstore8(j, 0, jl);
    __constant const uchar* table = (__constant const uchar*)wp_sobol_nibbles;
    uint4 row[8];
#pragma unroll
    for (int l = 0; l < 8; ++l) {
        uint4 acc = *(__constant const wp_uint4_rows*)(table + ((jl[l] << 4) & 0xf0u));
#pragma unroll
        for (int k = 1; k < 8; ++k)
            acc ^= *(__constant const wp_uint4_rows*)(table + 256 * k + ((jl[l] >> (4 * k - 4)) & 0xf0u));
        row[l] = acc;
    }
    *x0 = (uint8)(row[0].x, row[1].x, row[2].x, row[3].x, row[4].x, row[5].x, row[6].x, row[7].x);
    *x1 = (uint8)(row[0].y, row[1].y, row[2].y, row[3].y, row[4].y, row[5].y, row[6].y, row[7].y);
    *x2 = (uint8)(row[0].z, row[1].z, row[2].z, row[3].z, row[4].z, row[5].z, row[6].z, row[7].z);
    *x3 = (uint8)(row[0].w, row[1].w, row[2].w, row[3].w, row[4].w, row[5].w, row[6].w, row[7].w);
}

// The four numbers wp_rng4(seed, pixel[l], sample[l], bounce, group) of lanes l = 0..7,
// as four float8 (x: first number of every lane, y: second, ...). Same bits as wp_rng4.
WP_FN void wp_rng4_lanes(uint seed, uint8 pixel, uint8 sample, uint bounce, uint group,
                         float8* x, float8* y, float8* z, float8* w) {
    uint key = bounce * (uint)WP_RNG_GROUPS + group;
    uint8 r0, r1, r2, r3;
#if WP_SAMPLER == WP_SAMPLER_SOBOL
    // wp_sobol_rng4: the scramble seed hashed from (pixel, bounce and group, seed).
    uint8 scramble, h1, h2, h3;
    WP_PCG4D_LANES(pixel, key, seed, 0x50b01u, scramble, h1, h2, h3);
#if WP_SOBOL_REPLICATES > 1
    {
        // Replicate r = sample mod K: its own scramble (wp_replicate_scramble), point s / K.
        uint8 t1, t2, t3;
        WP_PCG4D_LANES(scramble, sample & ((uint)WP_SOBOL_REPLICATES - 1u), 0x7e91cu, 0x50b02u,
                       scramble, t1, t2, t3);
    }
    uint8 index = sample / (uint)WP_SOBOL_REPLICATES;
#else
    uint8 index = sample;
#endif
    // wp_sobol_owen4: the shuffled index reversed is LK(reverse(index)); the table gives
    // the coordinates reversed; each is scrambled with its own seed and reversed back.
    uint8 j = index;
    WP_REVERSE_BITS_STEPS(j);
    WP_LAINE_KARRAS_STEPS(j, scramble);
    wp_sobol4_reversed_lanes(j, &r0, &r1, &r2, &r3);
    // wp_hash_combine(scramble, d) for d = 0..3 (the seed terms shared).
    uint8 mix = (scramble << 6) + (scramble >> 2);
    uint8 s0 = scramble ^ mix, s1 = scramble ^ (mix + 1u), s2 = scramble ^ (mix + 2u),
          s3 = scramble ^ (mix + 3u);
    WP_LAINE_KARRAS_STEPS(r0, s0);
    WP_LAINE_KARRAS_STEPS(r1, s1);
    WP_LAINE_KARRAS_STEPS(r2, s2);
    WP_LAINE_KARRAS_STEPS(r3, s3);
    WP_REVERSE_BITS_STEPS(r0);
    WP_REVERSE_BITS_STEPS(r1);
    WP_REVERSE_BITS_STEPS(r2);
    WP_REVERSE_BITS_STEPS(r3);
#else
    WP_PCG4D_LANES(pixel, sample, key, seed, r0, r1, r2, r3);
#endif
    // wp_uint_to_unit: the top 24 bits, exactly representable, times 2^-24 (exact).
    *x = convert_float8(r0 >> 8) * (1.0f / 16777216.0f);
    *y = convert_float8(r1 >> 8) * (1.0f / 16777216.0f);
    *z = convert_float8(r2 >> 8) * (1.0f / 16777216.0f);
    *w = convert_float8(r3 >> 8) * (1.0f / 16777216.0f);
}

#undef WP_PCG4D_LANES

#endif  // WP_OPENCL

#endif  // WP_RNG_LANES_H
