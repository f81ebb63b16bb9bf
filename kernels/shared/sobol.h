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

// The four generator matrices (direction numbers of Joe & Kuo 2008, dimension 0 the van
// der Corput identity) as a nibble table for bit-reversed indices: row 16 k + v holds, for
// each dimension d, the XOR over the set bits t of v of reverse(column 31 - (4 k + t) of
// matrix d). XOR-ing the rows of the eight nibbles of j = reverse(i) gives the four
// coordinates of Sobol point i, each bit-reversed (wp_sobol4_reversed) — which is the form
// the Owen scramble takes them in (wp_nested_uniform_scramble reverses first). Generated
// from the direction numbers; tests/test_sampling.cpp checks the points against the
// numbers' recurrence.
WP_CONSTANT_TABLE uint wp_sobol_nibbles[128][4] = {
    {0x00000000u, 0x00000000u, 0x00000000u, 0x00000000u},
    {0x80000000u, 0xffffffffu, 0xaaaa00a3u, 0xc900a00au},
    {0x40000000u, 0x55555555u, 0x77770071u, 0x45004004u},
    {0xc0000000u, 0xaaaaaaaau, 0xdddd00d2u, 0x8c00e00eu},
    {0x20000000u, 0x33333333u, 0x3939003au, 0x2e003003u},
    {0xa0000000u, 0xccccccccu, 0x93930099u, 0xe7009009u},
    {0x60000000u, 0x66666666u, 0x4e4e004bu, 0x6b007007u},
    {0xe0000000u, 0x99999999u, 0xe4e400e8u, 0xa200d00du},
    {0x10000000u, 0x11111111u, 0x16160017u, 0x1f001001u},
    {0x90000000u, 0xeeeeeeeeu, 0xbcbc00b4u, 0xd600b00bu},
    {0x50000000u, 0x44444444u, 0x61610066u, 0x5a005005u},
    {0xd0000000u, 0xbbbbbbbbu, 0xcbcb00c5u, 0x9300f00fu},
    {0x30000000u, 0x22222222u, 0x2f2f002du, 0x31002002u},
    {0xb0000000u, 0xddddddddu, 0x8585008eu, 0xf8008008u},
    {0x70000000u, 0x77777777u, 0x5858005cu, 0x74006006u},
    {0xf0000000u, 0x88888888u, 0xf2f200ffu, 0xbd00c00cu},
    {0x00000000u, 0x00000000u, 0x00000000u, 0x00000000u},
    {0x08000000u, 0x0f0f0f0fu, 0x09a30009u, 0x0a000b6du},
    {0x04000000u, 0x05050505u, 0x06710006u, 0x0400079eu},
    {0x0c000000u, 0x0a0a0a0au, 0x0fd2000fu, 0x0e000cf3u},
    {0x02000000u, 0x03030303u, 0x033a0003u, 0x030002a7u},
    {0x0a000000u, 0x0c0c0c0cu, 0x0a99000au, 0x090009cau},
    {0x06000000u, 0x06060606u, 0x054b0005u, 0x07000539u},
    {0x0e000000u, 0x09090909u, 0x0ce8000cu, 0x0d000e54u},
    {0x01000000u, 0x01010101u, 0x01170001u, 0x0100011au},
    {0x09000000u, 0x0e0e0e0eu, 0x08b40008u, 0x0b000a77u},
    {0x05000000u, 0x04040404u, 0x07660007u, 0x05000684u},
    {0x0d000000u, 0x0b0b0b0bu, 0x0ec5000eu, 0x0f000de9u},
    {0x03000000u, 0x02020202u, 0x022d0002u, 0x020003bdu},
    {0x0b000000u, 0x0d0d0d0du, 0x0b8e000bu, 0x080008d0u},
    {0x07000000u, 0x07070707u, 0x045c0004u, 0x06000423u},
    {0x0f000000u, 0x08080808u, 0x0dff000du, 0x0c000f4eu},
    {0x00000000u, 0x00000000u, 0x00000000u, 0x00000000u},
    {0x00800000u, 0x00ff00ffu, 0x00a3aaaau, 0x00b6dba4u},
    {0x00400000u, 0x00550055u, 0x00717777u, 0x0079e7dbu},
    {0x00c00000u, 0x00aa00aau, 0x00d2ddddu, 0x00cf3c7fu},
    {0x00200000u, 0x00330033u, 0x003a3939u, 0x002a7289u},
    {0x00a00000u, 0x00cc00ccu, 0x00999393u, 0x009ca92du},
    {0x00600000u, 0x00660066u, 0x004b4e4eu, 0x00539552u},
    {0x00e00000u, 0x00990099u, 0x00e8e4e4u, 0x00e54ef6u},
    {0x00100000u, 0x00110011u, 0x00171616u, 0x0011a105u},
    {0x00900000u, 0x00ee00eeu, 0x00b4bcbcu, 0x00a77aa1u},
    {0x00500000u, 0x00440044u, 0x00666161u, 0x006846deu},
    {0x00d00000u, 0x00bb00bbu, 0x00c5cbcbu, 0x00de9d7au},
    {0x00300000u, 0x00220022u, 0x002d2f2fu, 0x003bd38cu},
    {0x00b00000u, 0x00dd00ddu, 0x008e8585u, 0x008d0828u},
    {0x00700000u, 0x00770077u, 0x005c5858u, 0x00423457u},
    {0x00f00000u, 0x00880088u, 0x00fff2f2u, 0x00f4eff3u},
    {0x00000000u, 0x00000000u, 0x00000000u, 0x00000000u},
    {0x00080000u, 0x000f000fu, 0x000909a3u, 0x000c9baeu},
    {0x00040000u, 0x00050005u, 0x00060671u, 0x000457dfu},
    {0x000c0000u, 0x000a000au, 0x000f0fd2u, 0x0008cc71u},
    {0x00020000u, 0x00030003u, 0x0003033au, 0x0002e28au},
    {0x000a0000u, 0x000c000cu, 0x000a0a99u, 0x000e7924u},
    {0x00060000u, 0x00060006u, 0x0005054bu, 0x0006b555u},
    {0x000e0000u, 0x00090009u, 0x000c0ce8u, 0x000a2efbu},
    {0x00010000u, 0x00010001u, 0x00010117u, 0x0001f104u},
    {0x00090000u, 0x000e000eu, 0x000808b4u, 0x000d6aaau},
    {0x00050000u, 0x00040004u, 0x00070766u, 0x0005a6dbu},
    {0x000d0000u, 0x000b000bu, 0x000e0ec5u, 0x00093d75u},
    {0x00030000u, 0x00020002u, 0x0002022du, 0x0003138eu},
    {0x000b0000u, 0x000d000du, 0x000b0b8eu, 0x000f8820u},
    {0x00070000u, 0x00070007u, 0x0004045cu, 0x00074451u},
    {0x000f0000u, 0x00080008u, 0x000d0dffu, 0x000bdfffu},
    {0x00000000u, 0x00000000u, 0x00000000u, 0x00000000u},
    {0x00008000u, 0x0000ffffu, 0x0000aa09u, 0x0000a0c3u},
    {0x00004000u, 0x00005555u, 0x00007706u, 0x00004041u},
    {0x0000c000u, 0x0000aaaau, 0x0000dd0fu, 0x0000e082u},
    {0x00002000u, 0x00003333u, 0x00003903u, 0x0000302du},
    {0x0000a000u, 0x0000ccccu, 0x0000930au, 0x000090eeu},
    {0x00006000u, 0x00006666u, 0x00004e05u, 0x0000706cu},
    {0x0000e000u, 0x00009999u, 0x0000e40cu, 0x0000d0afu},
    {0x00001000u, 0x00001111u, 0x00001601u, 0x0000101eu},
    {0x00009000u, 0x0000eeeeu, 0x0000bc08u, 0x0000b0ddu},
    {0x00005000u, 0x00004444u, 0x00006107u, 0x0000505fu},
    {0x0000d000u, 0x0000bbbbu, 0x0000cb0eu, 0x0000f09cu},
    {0x00003000u, 0x00002222u, 0x00002f02u, 0x00002033u},
    {0x0000b000u, 0x0000ddddu, 0x0000850bu, 0x000080f0u},
    {0x00007000u, 0x00007777u, 0x00005804u, 0x00006072u},
    {0x0000f000u, 0x00008888u, 0x0000f20du, 0x0000c0b1u},
    {0x00000000u, 0x00000000u, 0x00000000u, 0x00000000u},
    {0x00000800u, 0x00000f0fu, 0x000009aau, 0x00000b67u},
    {0x00000400u, 0x00000505u, 0x00000677u, 0x0000079au},
    {0x00000c00u, 0x00000a0au, 0x00000fddu, 0x00000cfdu},
    {0x00000200u, 0x00000303u, 0x00000339u, 0x000002a4u},
    {0x00000a00u, 0x00000c0cu, 0x00000a93u, 0x000009c3u},
    {0x00000600u, 0x00000606u, 0x0000054eu, 0x0000053eu},
    {0x00000e00u, 0x00000909u, 0x00000ce4u, 0x00000e59u},
    {0x00000100u, 0x00000101u, 0x00000116u, 0x0000011bu},
    {0x00000900u, 0x00000e0eu, 0x000008bcu, 0x00000a7cu},
    {0x00000500u, 0x00000404u, 0x00000761u, 0x00000681u},
    {0x00000d00u, 0x00000b0bu, 0x00000ecbu, 0x00000de6u},
    {0x00000300u, 0x00000202u, 0x0000022fu, 0x000003bfu},
    {0x00000b00u, 0x00000d0du, 0x00000b85u, 0x000008d8u},
    {0x00000700u, 0x00000707u, 0x00000458u, 0x00000425u},
    {0x00000f00u, 0x00000808u, 0x00000df2u, 0x00000f42u},
    {0x00000000u, 0x00000000u, 0x00000000u, 0x00000000u},
    {0x00000080u, 0x000000ffu, 0x000000a3u, 0x000000c9u},
    {0x00000040u, 0x00000055u, 0x00000071u, 0x00000045u},
    {0x000000c0u, 0x000000aau, 0x000000d2u, 0x0000008cu},
    {0x00000020u, 0x00000033u, 0x0000003au, 0x0000002eu},
    {0x000000a0u, 0x000000ccu, 0x00000099u, 0x000000e7u},
    {0x00000060u, 0x00000066u, 0x0000004bu, 0x0000006bu},
    {0x000000e0u, 0x00000099u, 0x000000e8u, 0x000000a2u},
    {0x00000010u, 0x00000011u, 0x00000017u, 0x0000001fu},
    {0x00000090u, 0x000000eeu, 0x000000b4u, 0x000000d6u},
    {0x00000050u, 0x00000044u, 0x00000066u, 0x0000005au},
    {0x000000d0u, 0x000000bbu, 0x000000c5u, 0x00000093u},
    {0x00000030u, 0x00000022u, 0x0000002du, 0x00000031u},
    {0x000000b0u, 0x000000ddu, 0x0000008eu, 0x000000f8u},
    {0x00000070u, 0x00000077u, 0x0000005cu, 0x00000074u},
    {0x000000f0u, 0x00000088u, 0x000000ffu, 0x000000bdu},
    {0x00000000u, 0x00000000u, 0x00000000u, 0x00000000u},
    {0x00000008u, 0x0000000fu, 0x00000009u, 0x0000000au},
    {0x00000004u, 0x00000005u, 0x00000006u, 0x00000004u},
    {0x0000000cu, 0x0000000au, 0x0000000fu, 0x0000000eu},
    {0x00000002u, 0x00000003u, 0x00000003u, 0x00000003u},
    {0x0000000au, 0x0000000cu, 0x0000000au, 0x00000009u},
    {0x00000006u, 0x00000006u, 0x00000005u, 0x00000007u},
    {0x0000000eu, 0x00000009u, 0x0000000cu, 0x0000000du},
    {0x00000001u, 0x00000001u, 0x00000001u, 0x00000001u},
    {0x00000009u, 0x0000000eu, 0x00000008u, 0x0000000bu},
    {0x00000005u, 0x00000004u, 0x00000007u, 0x00000005u},
    {0x0000000du, 0x0000000bu, 0x0000000eu, 0x0000000fu},
    {0x00000003u, 0x00000002u, 0x00000002u, 0x00000002u},
    {0x0000000bu, 0x0000000du, 0x0000000bu, 0x00000008u},
    {0x00000007u, 0x00000007u, 0x00000004u, 0x00000006u},
    {0x0000000fu, 0x00000008u, 0x0000000du, 0x0000000cu}};

// The steps of a 32-bit reversal and of the Laine-Karras permutation, written once for a
// uint and, in OpenCL, a uint4 (wp_sobol_owen4 scrambles its four coordinates as one
// vector: PoCL does not combine the scalar chains by itself).
#define WP_REVERSE_BITS_STEPS(x)                                   \
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);      \
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);      \
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);      \
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);      \
    x = (x >> 16) | (x << 16)
#define WP_LAINE_KARRAS_STEPS(x, seed) \
    x += seed;                         \
    x ^= x * 0x6c50b47cu;              \
    x ^= x * 0xb82f1e52u;              \
    x ^= x * 0xc7afe638u;              \
    x ^= x * 0x8d22f6e6u

// Dimension 1 (polynomial x + 1: Pascal's matrix mod 2) of wp_sobol4_reversed without the
// table: its column for bit t of j has bit b set when b & t == 0, so bit b of the reversed
// coordinate is the XOR of j's bits t with t & b == 0. The five steps give bit m of x the
// XOR of j's bits t whose index is a subset of m's (a subset-XOR transform over the five
// index bits); reversed, bit b holds that of m = 31 - b = ~b, i.e. of every t & b == 0.
// Dimension 0 (van der Corput) is reverse(j) itself. wp_sobol2_reversed gives both;
// tests/test_sampling.cpp checks them against the direction numbers' recurrence, and the
// lane draws built on them against the table's wp_rng4.
#define WP_SOBOL_DIM1_STEPS(x)      \
    x ^= (x & 0x55555555u) << 1;    \
    x ^= (x & 0x33333333u) << 2;    \
    x ^= (x & 0x0f0f0f0fu) << 4;    \
    x ^= (x & 0x00ff00ffu) << 8;    \
    x ^= (x & 0x0000ffffu) << 16

WP_FN uint wp_reverse_bits(uint x) {
    WP_REVERSE_BITS_STEPS(x);
    return x;
}

// The four coordinates of Sobol point reverse(j), each bit-reversed: eight table rows, one
// per nibble of j (32 bits of any index cost the same: the Owen-scrambled index uses them all).
#if defined(__OPENCL_VERSION__)
// A uint4 that may sit at any 4-byte boundary: a row of wp_sobol_nibbles read as one vector.
typedef uint4 __attribute__((aligned(4))) wp_uint4_rows;
#endif
WP_FN uint4 wp_sobol4_reversed(uint j) {
#if defined(__OPENCL_VERSION__)
    // One 128-bit XOR per nibble (the host and CUDA spell the same four lanes out). Row
    // 16 k + v starts at byte 256 k + 16 v: the nibble shifted to bits 4..7 is the offset (a
    // vload4 of the row by index became two 64-bit scalar loads and XORs under LLVM 15).
    __constant const uchar* table = (__constant const uchar*)wp_sobol_nibbles;
    uint4 x = *(__constant const wp_uint4_rows*)(table + ((j << 4) & 0xf0u));
#pragma unroll
    for (int k = 1; k < 8; ++k)
        x ^= *(__constant const wp_uint4_rows*)(table + 256 * k + ((j >> (4 * k - 4)) & 0xf0u));
    return x;
#else
    uint x0 = 0u, x1 = 0u, x2 = 0u, x3 = 0u;
    for (int k = 0; k < 8; ++k) {
        uint r = 16u * (uint)k + ((j >> (4 * k)) & 15u);
        x0 ^= wp_sobol_nibbles[r][0];
        x1 ^= wp_sobol_nibbles[r][1];
        x2 ^= wp_sobol_nibbles[r][2];
        x3 ^= wp_sobol_nibbles[r][3];
    }
    return make_uint4(x0, x1, x2, x3);
#endif
}

// The first two coordinates of wp_sobol4_reversed(j), without the table (above).
WP_FN uint2 wp_sobol2_reversed(uint j) {
    uint x0 = j, x1 = j;
    WP_REVERSE_BITS_STEPS(x0);
    WP_SOBOL_DIM1_STEPS(x1);
    WP_REVERSE_BITS_STEPS(x1);
    return make_uint2(x0, x1);
}

WP_FN uint wp_laine_karras_permutation(uint x, uint seed) {
    WP_LAINE_KARRAS_STEPS(x, seed);
    return x;
}
WP_FN uint wp_nested_uniform_scramble(uint x, uint seed) {
    return wp_reverse_bits(wp_laine_karras_permutation(wp_reverse_bits(x), seed));
}

// A small integer hash to derive the per-dimension seeds (Burley's hash_combine).
WP_FN uint wp_hash_combine(uint seed, uint v) {
    return seed ^ (v + (seed << 6) + (seed >> 2));
}

// Sobol point `index` in the four dimensions (unscrambled).
WP_FN uint4 wp_sobol4(uint index) {
    uint4 r = wp_sobol4_reversed(wp_reverse_bits(index));
    return make_uint4(wp_reverse_bits(r.x), wp_reverse_bits(r.y), wp_reverse_bits(r.z), wp_reverse_bits(r.w));
}

// Four Owen-scrambled Sobol numbers (32-bit words) of point `index` under scramble `seed`
// (Burley 2020, listing 3: shuffled index, then a scramble per dimension). With
// scramble(x) = reverse(LK(reverse(x))), the shuffled index i has reverse(i) = LK(reverse(
// index)), and the coordinates enter their scrambles reversed, so both inner reversals
// fold into the table (wp_sobol4_reversed): five bit reversals a call instead of ten.
WP_FN uint4 wp_sobol_owen4(uint index, uint seed) {
    uint4 r = wp_sobol4_reversed(wp_laine_karras_permutation(wp_reverse_bits(index), seed));
#if defined(__OPENCL_VERSION__)
    // The four scrambles as one 128-bit chain (the steps of wp_laine_karras_permutation
    // and wp_reverse_bits on a uint4).
    uint4 x = r;
    uint4 seeds = (uint4)(wp_hash_combine(seed, 0u), wp_hash_combine(seed, 1u),
                          wp_hash_combine(seed, 2u), wp_hash_combine(seed, 3u));
    WP_LAINE_KARRAS_STEPS(x, seeds);
    WP_REVERSE_BITS_STEPS(x);
    return x;
#else
    return make_uint4(wp_reverse_bits(wp_laine_karras_permutation(r.x, wp_hash_combine(seed, 0u))),
                      wp_reverse_bits(wp_laine_karras_permutation(r.y, wp_hash_combine(seed, 1u))),
                      wp_reverse_bits(wp_laine_karras_permutation(r.z, wp_hash_combine(seed, 2u))),
                      wp_reverse_bits(wp_laine_karras_permutation(r.w, wp_hash_combine(seed, 3u))));
#endif
}

WP_NAMESPACE_END

#endif  // WP_SOBOL_H
