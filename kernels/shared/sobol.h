// sobol.h — Owen-scrambled Sobol points, per (pixel, sample, dimension group).
//
// Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020: the first four Sobol
// dimensions (generator matrices from the direction numbers of Joe & Kuo, "Constructing
// Sobol sequences with better two-dimensional projections", SIAM J. Sci. Comput. 30(5),
// 2008: dimension 0 is van der Corput, then the polynomials x + 1, x² + x + 1,
// x³ + x + 1), the sample index shuffled by a nested uniform (Owen) scramble, and each
// dimension Owen-scrambled with the hash-based Laine-Karras permutation (Burley's
// listings 1-3). Higher dimensions are "padded": every dimension group (4 numbers) of every
// bounce gets its own scramble seed, hashed from (seed, pixel, bounce, group) with pcg4d
// (rng.h), as Burley section 4 recommends. Selected with -D WP_SAMPLER=1 (--sampler sobol).
#ifndef WP_SOBOL_H
#define WP_SOBOL_H

#include "compat.h"

WP_NAMESPACE_BEGIN

// Column j of the four generator matrices, row j: (d0, d1, d2, d3) as 32-bit words (bit 31 =
// first digit); laid out by column so one row is one 128-bit load.
WP_CONSTANT_TABLE uint wp_sobol_columns[32][4] = {
    {0x80000000u, 0x80000000u, 0x80000000u, 0x80000000u},
    {0x40000000u, 0xc0000000u, 0xc0000000u, 0xc0000000u},
    {0x20000000u, 0xa0000000u, 0x60000000u, 0x20000000u},
    {0x10000000u, 0xf0000000u, 0x90000000u, 0x50000000u},
    {0x08000000u, 0x88000000u, 0xe8000000u, 0xf8000000u},
    {0x04000000u, 0xcc000000u, 0x5c000000u, 0x74000000u},
    {0x02000000u, 0xaa000000u, 0x8e000000u, 0xa2000000u},
    {0x01000000u, 0xff000000u, 0xc5000000u, 0x93000000u},
    {0x00800000u, 0x80800000u, 0x68800000u, 0xd8800000u},
    {0x00400000u, 0xc0c00000u, 0x9cc00000u, 0x25400000u},
    {0x00200000u, 0xa0a00000u, 0xee600000u, 0x59e00000u},
    {0x00100000u, 0xf0f00000u, 0x55900000u, 0xe6d00000u},
    {0x00080000u, 0x88880000u, 0x80680000u, 0x78080000u},
    {0x00040000u, 0xcccc0000u, 0xc09c0000u, 0xb40c0000u},
    {0x00020000u, 0xaaaa0000u, 0x60ee0000u, 0x82020000u},
    {0x00010000u, 0xffff0000u, 0x90550000u, 0xc3050000u},
    {0x00008000u, 0x80008000u, 0xe8808000u, 0x208f8000u},
    {0x00004000u, 0xc000c000u, 0x5cc0c000u, 0x51474000u},
    {0x00002000u, 0xa000a000u, 0x8e606000u, 0xfbea2000u},
    {0x00001000u, 0xf000f000u, 0xc5909000u, 0x75d93000u},
    {0x00000800u, 0x88008800u, 0x6868e800u, 0xa0858800u},
    {0x00000400u, 0xcc00cc00u, 0x9c9c5c00u, 0x914e5400u},
    {0x00000200u, 0xaa00aa00u, 0xeeee8e00u, 0xdbe79e00u},
    {0x00000100u, 0xff00ff00u, 0x5555c500u, 0x25db6d00u},
    {0x00000080u, 0x80808080u, 0x8000e880u, 0x58800080u},
    {0x00000040u, 0xc0c0c0c0u, 0xc0005cc0u, 0xe54000c0u},
    {0x00000020u, 0xa0a0a0a0u, 0x60008e60u, 0x79e00020u},
    {0x00000010u, 0xf0f0f0f0u, 0x9000c590u, 0xb6d00050u},
    {0x00000008u, 0x88888888u, 0xe8006868u, 0x800800f8u},
    {0x00000004u, 0xccccccccu, 0x5c009c9cu, 0xc00c0074u},
    {0x00000002u, 0xaaaaaaaau, 0x8e00eeeeu, 0x200200a2u},
    {0x00000001u, 0xffffffffu, 0xc5005555u, 0x50050093u}};

WP_FN uint wp_reverse_bits(uint x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    return (x >> 16) | (x << 16);
}

// Sobol point `index` in the four dimensions: XOR of the columns of the set index bits.
// Branchless (a mask per bit) and all four dimensions per row, so the 32 steps are 32
// vector AND/XORs rather than 128 data-dependent branches (the index is Owen-scrambled,
// so all 32 bits are in play).
WP_FN uint4 wp_sobol4(uint index) {
    uint x0 = 0u, x1 = 0u, x2 = 0u, x3 = 0u;
    for (int bit = 0; bit < 32; ++bit) {
        uint take = 0u - ((index >> bit) & 1u);
        x0 ^= wp_sobol_columns[bit][0] & take;
        x1 ^= wp_sobol_columns[bit][1] & take;
        x2 ^= wp_sobol_columns[bit][2] & take;
        x3 ^= wp_sobol_columns[bit][3] & take;
    }
    return make_uint4(x0, x1, x2, x3);
}

WP_FN uint wp_laine_karras_permutation(uint x, uint seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}
WP_FN uint wp_nested_uniform_scramble(uint x, uint seed) {
    return wp_reverse_bits(wp_laine_karras_permutation(wp_reverse_bits(x), seed));
}

// A small integer hash to derive the per-dimension seeds (Burley's hash_combine).
WP_FN uint wp_hash_combine(uint seed, uint v) {
    return seed ^ (v + (seed << 6) + (seed >> 2));
}

// Four Owen-scrambled Sobol numbers (32-bit words) of point `index` under scramble `seed`
// (Burley 2020, listing 3: shuffled index, then a scramble per dimension).
WP_FN uint4 wp_sobol_owen4(uint index, uint seed) {
    uint i = wp_nested_uniform_scramble(index, seed);
    uint4 x = wp_sobol4(i);
    return make_uint4(wp_nested_uniform_scramble(x.x, wp_hash_combine(seed, 0u)),
                      wp_nested_uniform_scramble(x.y, wp_hash_combine(seed, 1u)),
                      wp_nested_uniform_scramble(x.z, wp_hash_combine(seed, 2u)),
                      wp_nested_uniform_scramble(x.w, wp_hash_combine(seed, 3u)));
}

WP_NAMESPACE_END

#endif  // WP_SOBOL_H
