// rng_lanes.h — wp_rng4 (rng.h) for eight independent keys at once, as eight-lane vectors,
// and its first one or two numbers alone (wp_rng1_lanes, wp_rng2_lanes).
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

// wp_sobol2_reversed (sobol.h) on eight indices: dimensions 0 and 1, bit-reversed, no table.
WP_FN void wp_sobol2_reversed_lanes(uint8 j, uint8* x0, uint8* x1) {
    uint8 a = j, b = j;
    WP_REVERSE_BITS_STEPS(a);
    WP_SOBOL_DIM1_STEPS(b);
    WP_REVERSE_BITS_STEPS(b);
    *x0 = a, *x1 = b;
}

// wp_uint_to_unit per lane: the top 24 bits, exactly representable, times 2^-24 (exact).
WP_FN float8 wp_uint_to_unit8(uint8 r) { return convert_float8(r >> 8) * (1.0f / 16777216.0f); }

#if WP_SAMPLER == WP_SAMPLER_SOBOL
// The first half of wp_sobol_rng4 on eight keys: the scramble seed hashed from (pixel,
// bounce and group, seed), with replicates the replicate's, and j, the Owen-shuffled index
// reversed (LK(reverse(index))), which the coordinates are read at.
WP_FN void wp_sobol_key_lanes(uint seed, uint8 pixel, uint8 sample, uint key, uint8* scramble, uint8* j) {
    uint8 s, h1, h2, h3;
    WP_PCG4D_LANES(pixel, key, seed, 0x50b01u, s, h1, h2, h3);
#if WP_SOBOL_REPLICATES > 1
    {
        // Replicate r = sample mod K: its own scramble (wp_replicate_scramble), point s / K.
        uint8 t1, t2, t3;
        WP_PCG4D_LANES(s, sample & ((uint)WP_SOBOL_REPLICATES - 1u), 0x7e91cu, 0x50b02u, s, t1, t2, t3);
    }
    uint8 index = sample / (uint)WP_SOBOL_REPLICATES;
#else
    uint8 index = sample;
#endif
    WP_REVERSE_BITS_STEPS(index);
    WP_LAINE_KARRAS_STEPS(index, s);
    *scramble = s;
    *j = index;
}

// Dimension d's number from its bit-reversed coordinate r: the scramble of
// wp_sobol_owen4 (seed wp_hash_combine(scramble, d), Laine-Karras, reversed back), then
// wp_uint_to_unit.
WP_FN float8 wp_sobol_finish_lanes(uint8 r, uint8 scramble, uint d) {
    uint8 s = scramble ^ (d + (scramble << 6) + (scramble >> 2));
    WP_LAINE_KARRAS_STEPS(r, s);
    WP_REVERSE_BITS_STEPS(r);
    return wp_uint_to_unit8(r);
}
#endif

// The four numbers wp_rng4(seed, pixel[l], sample[l], bounce, group) of lanes l = 0..7,
// as four float8 (x: first number of every lane, y: second, ...). Same bits as wp_rng4.
WP_FN void wp_rng4_lanes(uint seed, uint8 pixel, uint8 sample, uint bounce, uint group,
                         float8* x, float8* y, float8* z, float8* w) {
    uint key = bounce * (uint)WP_RNG_GROUPS + group;
#if WP_SAMPLER == WP_SAMPLER_SOBOL
    uint8 scramble, j, r0, r1, r2, r3;
    wp_sobol_key_lanes(seed, pixel, sample, key, &scramble, &j);
    wp_sobol4_reversed_lanes(j, &r0, &r1, &r2, &r3);
    *x = wp_sobol_finish_lanes(r0, scramble, 0u);
    *y = wp_sobol_finish_lanes(r1, scramble, 1u);
    *z = wp_sobol_finish_lanes(r2, scramble, 2u);
    *w = wp_sobol_finish_lanes(r3, scramble, 3u);
#else
    uint8 r0, r1, r2, r3;
    WP_PCG4D_LANES(pixel, sample, key, seed, r0, r1, r2, r3);
    *x = wp_uint_to_unit8(r0);
    *y = wp_uint_to_unit8(r1);
    *z = wp_uint_to_unit8(r2);
    *w = wp_uint_to_unit8(r3);
#endif
}

// The first two numbers of wp_rng4_lanes (the same bits) for draws that use no more: the
// camera's jitter, a BSDF sample of the lane kinds. With Sobol, dimensions 0 and 1 come
// from bit operations on j (wp_sobol2_reversed_lanes) instead of the nibble table, whose
// eight loads per lane are the table path's cost.
WP_FN void wp_rng2_lanes(uint seed, uint8 pixel, uint8 sample, uint bounce, uint group, float8* x,
                         float8* y) {
    uint key = bounce * (uint)WP_RNG_GROUPS + group;
#if WP_SAMPLER == WP_SAMPLER_SOBOL
    uint8 scramble, j, r0, r1;
    wp_sobol_key_lanes(seed, pixel, sample, key, &scramble, &j);
    wp_sobol2_reversed_lanes(j, &r0, &r1);
    *x = wp_sobol_finish_lanes(r0, scramble, 0u);
    *y = wp_sobol_finish_lanes(r1, scramble, 1u);
#else
    uint8 r0, r1, r2, r3;
    WP_PCG4D_LANES(pixel, sample, key, seed, r0, r1, r2, r3);
    *x = wp_uint_to_unit8(r0);
    *y = wp_uint_to_unit8(r1);
#endif
}

// The first number of wp_rng4_lanes (the same bits): Russian roulette.
WP_FN float8 wp_rng1_lanes(uint seed, uint8 pixel, uint8 sample, uint bounce, uint group) {
    uint key = bounce * (uint)WP_RNG_GROUPS + group;
#if WP_SAMPLER == WP_SAMPLER_SOBOL
    uint8 scramble, j;
    wp_sobol_key_lanes(seed, pixel, sample, key, &scramble, &j);
    WP_REVERSE_BITS_STEPS(j);  // dimension 0, bit-reversed (wp_sobol2_reversed_lanes' first)
    return wp_sobol_finish_lanes(j, scramble, 0u);
#else
    uint8 r0, r1, r2, r3;
    WP_PCG4D_LANES(pixel, sample, key, seed, r0, r1, r2, r3);
    return wp_uint_to_unit8(r0);
#endif
}

#undef WP_PCG4D_LANES

#endif  // WP_OPENCL

#endif  // WP_RNG_LANES_H
