// parity_cases.h — the inputs of the GPU parity check (tests/cuda/gpu_parity.cu, parity_check.cpp):
// one material per kind of material_kinds.h and N random scattering configurations, made
// by the host of both programs from the same integer hash, so both see the same bits.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

namespace parity {

struct Case {  // plain floats: no float3 (12 bytes in CUDA, 16 in OpenCL)
    float d[3], ns[3], wi[3], u[4];
    int front;
};

struct Result {
    float wo[3], weight[3], pdf, fcos[3], eval_pdf;
    int ok, specular;
};

inline std::uint32_t hash(std::uint32_t x) {  // lowbias32 (Wellons)
    x ^= x >> 16; x *= 0x7feb352dU; x ^= x >> 15; x *= 0x846ca68bU; x ^= x >> 16;
    return x;
}
inline float uniform(std::uint32_t i, std::uint32_t j) {
    return float(hash(i * 16u + j) >> 8) * (1.0f / 16777216.0f);
}
inline void unit(float* v, float a, float b) {  // uniform on the sphere
    float z = 1.0f - 2.0f * a, r = std::sqrt(std::fmax(0.0f, 1.0f - z * z)), p = 6.2831853f * b;
    v[0] = r * std::cos(p); v[1] = r * std::sin(p); v[2] = z;
}

// Case i: a normal, an arriving direction on its side (d·ns < 0), a light direction, numbers.
inline Case make_case(std::uint32_t i) {
    Case c{};
    unit(c.ns, uniform(i, 0), uniform(i, 1));
    unit(c.d, uniform(i, 2), uniform(i, 3));
    float dn = c.d[0] * c.ns[0] + c.d[1] * c.ns[1] + c.d[2] * c.ns[2];
    if (dn > 0.0f) for (float& x : c.d) x = -x;
    unit(c.wi, uniform(i, 4), uniform(i, 5));
    for (int k = 0; k < 4; ++k) c.u[k] = uniform(i, 6 + k);
    c.front = uniform(i, 10) < 0.5f;
    return c;
}

}  // namespace parity

namespace parity {

constexpr int kCasesPerKind = 1 << 16;

// The material of each kind (material_kinds.h numbering): roughness 0.3 (anisotropic 0.2 x 0.5
// for roughconductor), Beckmann for roughconductor/roughplastic, gold's η/k, η 1.5.
template <class MD, class F4>
MD material(int kind, F4 (*f4)(float, float, float, float)) {
    MD m{};
    m.kind = kind;
    m.albedo = f4(0.8f, 0.6f, 0.4f, 0.0f);
    m.specular = f4(1.0f, 0.9f, 0.8f, 0.0f);
    m.ior = 1.5f;
    m.alpha = 0.3f;
    m.alpha_v = 0.3f;
    m.eta = f4(0.1431190f, 0.3749570f, 1.4424786f, 0.0f);
    m.k = f4(3.9831604f, 2.3857207f, 1.6032153f, 0.0f);
    m.table = kind == 9 ? 0 : -1;  // roughplastic reads the table of table_value()
    if (kind == 5) m.alpha = 0.2f, m.alpha_v = 0.5f, m.flags = 1 | 2;  // roughconductor
    if (kind == 9) m.flags = 1 | 2;                                    // roughplastic
    if (kind == 8 || kind == 9) m.specular.w = 0.5f;
    return m;
}

}  // namespace parity

namespace parity {
// A smooth stand-in for a rough plastic's table (kernels/shared/types.h layout: 64 values of
// the coat's transmittance over cos θ, then its internal reflectance): the parity check
// compares arithmetic, not physics.
inline float table_value(int i) { return i < 64 ? 0.55f + 0.4f * float(i) / 63.0f : 0.42f; }
constexpr int kTableSize = 65;
}  // namespace parity
