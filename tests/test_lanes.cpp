// test_lanes.cpp — the lane functions of kernels/shared/lanes.h (eight paths per work-item
// as float8 code) against the scalar functions they mirror, bit for bit, on the device:
// the probe kernels of kernels/test_lanes.cl run both on the same inputs and write raw bits.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "shared/sampling.h"

#include "cl/kernel.h"
#include "cl/program.h"
#include "support.h"

using namespace wp;

namespace {

template <typename T>
cl::Buffer upload(const std::vector<T>& v) {
    auto& dev = wp::test::device();
    return cl::Buffer(dev.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                      std::max<std::size_t>(1, v.size()) * sizeof(T), const_cast<T*>(v.data()));
}

std::vector<std::uint32_t> download(const cl::Buffer& b, std::size_t n) {
    std::vector<std::uint32_t> v(n);
    wp::test::device().queue.enqueueReadBuffer(b, CL_TRUE, 0, n * sizeof(std::uint32_t), v.data());
    return v;
}

float bits_to_float(std::uint32_t b) {
    float f;
    std::memcpy(&f, &b, 4);
    return f;
}

// A unit vector perpendicular to unit n.
glm::vec3 perpendicular(glm::vec3 n, wp::test::Rng& rng) {
    glm::vec3 t = glm::cross(n, rng.unit_vector());
    if (glm::dot(t, t) < 1e-6f) t = glm::cross(n, glm::vec3(1.0f, 0.0f, 0.0f));
    if (glm::dot(t, t) < 1e-6f) t = glm::cross(n, glm::vec3(0.0f, 1.0f, 0.0f));
    return glm::normalize(t);
}

// u in [0, 1): mostly uniform, with 0 and 1 - 2^-24 mixed in.
float random_u(wp::test::Rng& rng) {
    std::uint64_t k = rng.next() % 16;
    if (k == 0) return 0.0f;
    if (k == 1) return 1.0f - 0x1p-24f;
    return rng.uniform();
}

// Inputs of probe_glossy8 (16 floats per lane), n_items * 8 lanes.
std::vector<float> glossy_inputs(int n_items, std::uint64_t seed) {
    wp::test::Rng rng(seed);
    std::vector<float> in;
    in.reserve(std::size_t(n_items) * 8 * 16);
    for (int q = 0; q < 8 * n_items; ++q) {
        float albedo[3] = {rng.uniform(), rng.uniform(), rng.uniform()};
        if (q % 17 == 0) albedo[0] = albedo[1] = albedo[2] = 1.0f;
        float alpha;
        switch (q % 7) {
            case 0: alpha = 1.0f; break;
            case 1: alpha = 1e-3f; break;
            default: alpha = std::pow(10.0f, rng.uniform(-3.0f, 0.0f));
        }
        glm::vec3 ns = rng.unit_vector();
        ns = ns / std::sqrt(glm::dot(ns, ns));
        if (q % 29 == 3) ns = glm::vec3(0.0f, 0.0f, (q & 1) ? 1.0f : -1.0f);
        // cos of the arriving ray to the normal: straight on to grazing (1e-6), both sides.
        float c;
        switch (q % 5) {
            case 0: c = 1.0f; break;
            case 1: c = std::pow(10.0f, rng.uniform(-6.0f, -2.0f)); break;
            case 2: c = 1e-6f; break;
            default: c = rng.uniform(); break;
        }
        if (q % 4 == 3) c = -c;  // from behind the normal
        glm::vec3 t = perpendicular(ns, rng);
        float s = std::sqrt(std::max(0.0f, 1.0f - c * c));
        glm::vec3 d = -(c * ns + s * t);
        d = d / std::sqrt(glm::dot(d, d));
        glm::vec3 wi = rng.unit_vector();
        float use_wo = (q % 3 != 0) ? 1.0f : 0.0f;
        float v[16] = {albedo[0], albedo[1], albedo[2], alpha, d.x, d.y, d.z, ns.x, ns.y, ns.z,
                       random_u(rng), random_u(rng), wi.x, wi.y, wi.z, use_wo};
        in.insert(in.end(), v, v + 16);
    }
    return in;
}

}  // namespace

// wp_glossy_sample8 / wp_glossy_eval8 / wp_reflect8 against wp_bsdf_sample_pdf and
// wp_bsdf_eval of a glossy material (and of a mirror for reflect), both glossy models:
// the sample mask in every lane, the sample's bits where the scalar function scattered,
// the eval's bits (f cos and pdf) everywhere.
TEST_CASE("lanes: glossy and mirror BSDFs on eight lanes equal the scalar functions bit for bit",
          "[kernel][lanes]") {
    auto& dev = wp::test::device();
    const int items = 1024;  // 8192 lanes per model
    std::vector<float> in = glossy_inputs(items, 0x9105517);
    cl::Buffer b_in = upload(in);
    const std::size_t words = std::size_t(items) * 8 * 16;
    const char* names[16] = {"mask", "wo.x", "wo.y", "wo.z", "weight.x", "weight.y", "weight.z",
                             "pdf", "f.x", "f.y", "f.z", "eval pdf", "reflect.x", "reflect.y",
                             "reflect.z", "pad"};
    for (int model : {0, 1}) {
        ocl::Program prog = ocl::Program::build(
            dev, "test_lanes.cl",
            "-D WP_GLOSSY_MODEL=" + std::to_string(model) + " -D WP_HAVE_GLOSSY=1 -D WP_HAVE_MIRROR=1");
        ocl::Kernel k(prog, "probe_glossy8", "probe.glossy8");
        cl::Buffer b_lane(dev.context, CL_MEM_READ_WRITE, words * 4),
            b_scalar(dev.context, CL_MEM_READ_WRITE, words * 4);
        k.launch({&dev.queue}, items, items, b_in, b_lane, b_scalar);
        std::vector<std::uint32_t> lane = download(b_lane, words), scalar = download(b_scalar, words);
        int bad[16] = {}, first[16], scattered = 0, evaluated = 0;
        std::fill(first, first + 16, -1);
        for (int q = 0; q < 8 * items; ++q) {
            const std::uint32_t* a = &lane[std::size_t(q) * 16];
            const std::uint32_t* b = &scalar[std::size_t(q) * 16];
            bool ok = b[0] != 0;
            scattered += ok;
            evaluated += bits_to_float(b[11]) > 0.0f;
            for (int w = 0; w < 16; ++w) {
                if (w >= 1 && w <= 7 && !ok) continue;  // sample outputs: only where it scattered
                if (a[w] != b[w]) {
                    bad[w] += 1;
                    if (first[w] < 0) first[w] = q;
                }
            }
        }
        INFO("glossy model " << model << ": " << scattered << " of " << 8 * items
                             << " lanes scattered, " << evaluated << " with eval pdf > 0");
        CHECK(scattered > 8 * items / 4);
        CHECK(evaluated > 8 * items / 4);
        for (int w = 0; w < 16; ++w) {
            INFO(names[w] << ": first differing lane " << first[w]);
            if (first[w] >= 0) {
                std::size_t o = std::size_t(first[w]) * 16 + w;
                INFO("lane " << bits_to_float(lane[o]) << " scalar " << bits_to_float(scalar[o])
                             << " alpha " << in[std::size_t(first[w]) * 16 + 3]);
                CHECK(bad[w] == 0);
            }
        }
    }
}

// wp_roughconductor_sample8 / wp_roughconductor_eval8 (lanes.h) against wp_bsdf_sample_pdf
// and wp_bsdf_eval of an isotropic rough conductor: GGX and Beckmann, separable and
// height-correlated G, widths 1e-3 to 1, arrival from straight on to grazing (cos 1e-6) and
// from behind, u = 0 and 1 - 2^-24, η and k of dielectric-like to metal-like conductors
// (t0 < 0 and > 0 in the Fresnel term). Same bits as in the glossy case.
TEST_CASE("lanes: rough conductor BSDF on eight lanes equals the scalar functions bit for bit",
          "[kernel][lanes]") {
    auto& dev = wp::test::device();
    const int items = 2048;  // 16384 lanes
    const std::vector<float> glossy = glossy_inputs(items, 0x70c0dd);
    wp::test::Rng rng(0xbec4a);
    std::vector<float> in;
    for (int q = 0; q < 8 * items; ++q) {
        in.insert(in.end(), glossy.begin() + std::ptrdiff_t(q) * 16, glossy.begin() + std::ptrdiff_t(q + 1) * 16);
        for (int c = 0; c < 3; ++c) in.push_back(q % 3 == 0 ? rng.uniform(0.05f, 0.3f) : rng.uniform(0.2f, 3.0f));  // eta
        for (int c = 0; c < 3; ++c) in.push_back(q % 11 == 0 ? 0.0f : rng.uniform(0.0f, 5.0f));  // k
        in.push_back((q / 2) % 2 ? 1.0f : 0.0f);  // Beckmann
        in.push_back((q / 4) % 2 ? 1.0f : 0.0f);  // separable G
    }
    cl::Buffer b_in = upload(in);
    const std::size_t words = std::size_t(items) * 8 * 12;
    const char* names[12] = {"mask", "wo.x", "wo.y", "wo.z", "weight.x", "weight.y", "weight.z",
                             "pdf", "f.x", "f.y", "f.z", "eval pdf"};
    ocl::Program prog = ocl::Program::build(dev, "test_lanes.cl", "-D WP_HAVE_ROUGH_CONDUCTOR=1");
    ocl::Kernel k(prog, "probe_roughconductor8", "probe.roughconductor8");
    cl::Buffer b_lane(dev.context, CL_MEM_READ_WRITE, words * 4), b_scalar(dev.context, CL_MEM_READ_WRITE, words * 4);
    k.launch({&dev.queue}, items, items, b_in, b_lane, b_scalar);
    std::vector<std::uint32_t> lane = download(b_lane, words), scalar = download(b_scalar, words);
    int bad[12] = {}, first[12], scattered[2] = {}, evaluated[2] = {};
    std::fill(first, first + 12, -1);
    for (int q = 0; q < 8 * items; ++q) {
        const std::uint32_t* a = &lane[std::size_t(q) * 12];
        const std::uint32_t* b = &scalar[std::size_t(q) * 12];
        const bool ok = b[0] != 0;
        const int beckmann = (q / 2) % 2;
        scattered[beckmann] += ok;
        evaluated[beckmann] += bits_to_float(b[11]) > 0.0f;
        for (int w = 0; w < 12; ++w) {
            if (w >= 1 && w <= 7 && !ok) continue;  // sample outputs: only where it scattered
            if (a[w] != b[w]) {
                bad[w] += 1;
                if (first[w] < 0) first[w] = q;
            }
        }
    }
    INFO("GGX / Beckmann lanes that scattered: " << scattered[0] << " / " << scattered[1] << ", eval pdf > 0: "
                                                 << evaluated[0] << " / " << evaluated[1] << " of " << 4 * items << " each");
    for (int m = 0; m < 2; ++m) {
        CHECK(scattered[m] > 4 * items / 4);
        CHECK(evaluated[m] > 4 * items / 4);
    }
    for (int w = 0; w < 12; ++w) {
        INFO(names[w] << ": " << bad[w] << " differing lanes, first " << first[w]);
        if (first[w] >= 0) {
            const std::size_t o = std::size_t(first[w]) * 12 + w;
            INFO("lane " << bits_to_float(lane[o]) << " scalar " << bits_to_float(scalar[o]) << " alpha "
                         << in[std::size_t(first[w]) * 24 + 3] << " beckmann " << (first[w] / 2) % 2);
            CHECK(bad[w] == 0);
        }
    }
}

// The inline functions of microfacet.h and sampling.h (wp_exp, wp_erf, wp_erfinv,
// wp_log_normal, wp_atan2_guess, wp_pow) against their lane forms, bit for bit, over their
// whole ranges: every branch of each, the ends (infinities, NaN, signed zeros, denormal
// results of exp, erfinv next to ±1, pow of 0, 1, inf and negative x).
TEST_CASE("lanes: the inline math of microfacet.h and sampling.h on eight lanes equals the scalar forms",
          "[kernel][lanes]") {
    auto& dev = wp::test::device();
    std::vector<float> in;
    const float specials[] = {0.0f, -0.0f, INFINITY, -INFINITY, NAN, 1.0f, -1.0f, 4.0f, -4.0f,
                              0x1p-149f, 1e-30f, -104.5f, -104.0f, -103.9f, -87.5f, 88.7f, 88.72f,
                              88.8f, 89.5f, 0.70710678f, 1.0f - 0x1p-24f, -1.0f + 0x1p-24f, 0.9999f,
                              100.0f, 1e6f, -3.0f};
    for (float x : specials)
        for (float y : specials) in.insert(in.end(), {x, y});
    wp::test::Rng rng(0xe4f);
    while (in.size() < 2 * 8 * 8192) {
        float x;
        switch (rng.next() % 4) {
            case 0: x = rng.uniform(-110.0f, 95.0f); break;                              // exp
            case 1: x = rng.uniform(-6.0f, 6.0f); break;                                 // erf
            case 2: x = std::pow(2.0f, rng.uniform(-126.0f, 2.0f)); break;               // log
            default: x = std::copysign(std::pow(10.0f, rng.uniform(-8.0f, 0.0f)), rng.uniform(-1.0f, 1.0f));
        }
        float y = (rng.next() % 3 == 0) ? std::copysign(1.0f - std::pow(10.0f, rng.uniform(-7.5f, -1.0f)), rng.uniform(-1.0f, 1.0f))
                                        : rng.uniform(-1.0f, 1.0f);
        in.insert(in.end(), {x, y});
    }
    const int items = int(in.size() / 16);
    in.resize(std::size_t(items) * 16);
    cl::Buffer b_in = upload(in);
    ocl::Program prog = ocl::Program::build(dev, "test_lanes.cl", "-D WP_HAVE_ROUGH_CONDUCTOR=1");
    ocl::Kernel k(prog, "probe_mf_math8", "probe.mf_math8");
    const std::size_t words = std::size_t(items) * 8 * 6;
    cl::Buffer b_lane(dev.context, CL_MEM_READ_WRITE, words * 4), b_scalar(dev.context, CL_MEM_READ_WRITE, words * 4);
    k.launch({&dev.queue}, items, items, b_in, b_lane, b_scalar);
    std::vector<std::uint32_t> lane = download(b_lane, words), scalar = download(b_scalar, words);
    const char* names[6] = {"exp", "erf", "erfinv", "log_normal", "atan2_guess", "pow"};
    int bad[6] = {}, first[6] = {-1, -1, -1, -1, -1, -1}, compared[6] = {};
    for (int q = 0; q < 8 * items; ++q) {
        const float x = in[std::size_t(q) * 2], y = in[std::size_t(q) * 2 + 1];
        for (int w = 0; w < 6; ++w) {
            if (w == 2 && !(std::fabs(y) < 1.0f)) continue;                   // erfinv: (-1, 1)
            if (w == 3 && !std::isnormal(x)) continue;                         // log: normal x
            const std::uint32_t a = lane[std::size_t(q) * 6 + w], b = scalar[std::size_t(q) * 6 + w];
            ++compared[w];
            // NaN: any NaN (the payload is not part of the contract).
            if (a != b && !(std::isnan(bits_to_float(a)) && std::isnan(bits_to_float(b)))) {
                ++bad[w];
                if (first[w] < 0) first[w] = q;
            }
        }
    }
    for (int w = 0; w < 6; ++w) {
        INFO(names[w] << ": " << bad[w] << " of " << compared[w] << " differ, first at x = "
                      << (first[w] >= 0 ? in[std::size_t(first[w]) * 2] : 0.0f) << ", y = "
                      << (first[w] >= 0 ? in[std::size_t(first[w]) * 2 + 1] : 0.0f));
        CHECK(compared[w] > 10000);
        CHECK(bad[w] == 0);
    }
}

// The builtins the lane code replaces: l3_normalize against normalize (random, tiny and
// huge vectors), l3_cross against cross, and wp_pow8 against the scalar wp_pow bit for bit;
// the device's wp_pow against the host's (so the host's sweep against double pow in
// test_materials_conductor.cpp holds for the kernels) and against the builtin pow.
TEST_CASE("lanes: normalize, cross and pow spelled per lane equal the scalar forms",
          "[kernel][lanes]") {
    auto& dev = wp::test::device();
    const int items = 4096;
    wp::test::Rng rng(0x1a9e5);
    std::vector<float> in;
    for (int q = 0; q < 8 * items; ++q) {
        glm::vec3 v = rng.unit_vector();
        float scale;
        switch (q % 6) {
            case 0: scale = std::pow(2.0f, rng.uniform(-80.0f, -40.0f)); break;   // tiny
            case 1: scale = std::pow(2.0f, rng.uniform(40.0f, 70.0f)); break;     // huge
            case 2: scale = std::pow(10.0f, rng.uniform(-6.0f, 6.0f)); break;
            default: scale = rng.uniform(0.5f, 2.0f); break;
        }
        v *= scale;
        if (q % 13 == 0) v.y = 0.0f;
        float y;
        switch (q % 4) {
            case 0: y = std::pow(10.0f, rng.uniform(-6.0f, 0.0f)); break;  // 1 / (e + 1)
            case 1: y = std::pow(10.0f, rng.uniform(0.0f, 6.3f)) - 1.0f; break;  // e
            case 2: y = rng.uniform(0.0f, 4.0f); break;
            default: y = float(q % 5); break;
        }
        // pow's base |x|: cosines near 1 (the Phong lobe's), 1 - u, or v.x.
        float x = (q % 3 == 0) ? 1.0f - std::pow(10.0f, rng.uniform(-7.0f, 0.0f))
                               : (q % 3 == 1 ? rng.uniform() : v.x);
        in.insert(in.end(), {x, v.y, v.z, y});
    }
    cl::Buffer b_in = upload(in);
    ocl::Program prog = ocl::Program::build(dev, "test_lanes.cl",
                                            "-D WP_GLOSSY_MODEL=1 -D WP_HAVE_GLOSSY=1 -D WP_HAVE_MIRROR=1");
    ocl::Kernel k(prog, "probe_math8", "probe.math8");
    const std::size_t words = std::size_t(items) * 8 * 8;
    cl::Buffer b_lane(dev.context, CL_MEM_READ_WRITE, words * 4),
        b_scalar(dev.context, CL_MEM_READ_WRITE, words * 4);
    k.launch({&dev.queue}, items, items, b_in, b_lane, b_scalar);
    std::vector<std::uint32_t> lane = download(b_lane, words), scalar = download(b_scalar, words);
    int bad[8] = {}, first[8], overflow = 0, overflow_bad = 0, pow_normal = 0;
    double pow_rel = 0;
    std::fill(first, first + 8, -1);
    for (int q = 0; q < 8 * items; ++q) {
        // normalize(v) where dot(v, v) overflows: PoCL's scalar normalize rescales there (and
        // returns about v / |v|², not a unit vector), the lane form gives 0. Shading only
        // normalizes vectors of length <= 2 or so; such lanes are counted, not compared.
        const float* x = &in[std::size_t(q) * 4];
        bool huge = !std::isfinite(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        overflow += huge;
        // Word 4: the device's scalar wp_pow (lane[]) and its builtin pow (scalar[]).
        const float device_wp = bits_to_float(lane[std::size_t(q) * 8 + 4]);
        const float host_wp = wp_pow(std::fabs(x[0]), x[3]);
        const float builtin = bits_to_float(scalar[std::size_t(q) * 8 + 4]);
        if (std::memcmp(&device_wp, &host_wp, 4) != 0 && !(std::isnan(device_wp) && std::isnan(host_wp))) {
            bad[4] += 1;
            if (first[4] < 0) first[4] = q;
        }
        if (std::isnormal(builtin)) {
            ++pow_normal;
            pow_rel = std::max(pow_rel, std::abs(double(device_wp) - double(builtin)) / double(builtin));
        }
        for (int w = 0; w < 8; ++w) {
            if (w == 4) continue;
            bool differs = lane[std::size_t(q) * 8 + w] != scalar[std::size_t(q) * 8 + w];
            if (huge && w < 3) {
                overflow_bad += differs && w == 0;
                continue;
            }
            if (differs) {
                bad[w] += 1;
                if (first[w] < 0) first[w] = q;
            }
        }
    }
    CHECK(overflow > 0);
    WARN("normalize: dot(v, v) overflows in " << overflow << " lanes, lane and scalar x differ in "
                                              << overflow_bad << " of them");
    const char* names[8] = {"normalize.x", "normalize.y", "normalize.z", "wp_pow8", "wp_pow device/host",
                            "cross.x", "cross.y", "cross.z"};
    // Both round the same real number: at most an ulp or two apart (wp_pow's own bound,
    // 2.4e-7, plus the builtin's).
    INFO("wp_pow against the device's pow: max rel " << pow_rel << " over " << pow_normal << " normal results");
    CHECK(pow_normal > 8 * items / 2);
    CHECK(pow_rel < 4e-7);
    for (int w = 0; w < 8; ++w) {
        INFO(names[w] << ": " << bad[w] << " differing lanes, first " << first[w]);
        CHECK(bad[w] == 0);
    }
}

// The lane functions shade_surface8 already used (sincos, frames, hemisphere warps, hit
// point and ray offsets, MIS weights) against their scalar twins, bit for bit.
TEST_CASE("lanes: frames, warps, offsets and MIS weights on eight lanes equal the scalar functions",
          "[kernel][lanes]") {
    auto& dev = wp::test::device();
    const int items = 2048;
    wp::test::Rng rng(0x3157c);
    std::vector<float> in;
    auto coord = [&] {
        float m = std::pow(10.0f, rng.uniform(-3.0f, 3.0f));
        return rng.uniform(-1.0f, 1.0f) * m;
    };
    auto density = [&](int q) {
        switch (q % 8) {
            case 0: return 0.0f;
            case 1: return -rng.uniform();
            default: return std::pow(10.0f, rng.uniform(-4.0f, 4.0f));
        }
    };
    for (int q = 0; q < 8 * items; ++q) {
        glm::vec3 base(coord(), coord(), coord());
        glm::vec3 v[3];
        for (auto& x : v) x = base + glm::vec3(coord(), coord(), coord()) * 1e-2f;
        glm::vec3 n = rng.unit_vector();
        n = n / std::sqrt(glm::dot(n, n));
        if (q % 23 == 0) n = glm::vec3(0.0f, 0.0f, (q & 1) ? 1.0f : -1.0f);
        if (q % 31 == 0) n = glm::vec3(1.0f, 0.0f, 0.0f);
        glm::vec3 lv = (q % 2) ? rng.unit_vector() : v[0];
        float s = density(q), t = density(q / 8 + 3);
        in.insert(in.end(), {lv.x, lv.y, lv.z, v[1].x, v[1].y, v[1].z, v[2].x, v[2].y, v[2].z,
                             n.x, n.y, n.z, random_u(rng), random_u(rng), s, t});
        if (q % 2 == 0) {  // a triangle (v0, v1, v2) for the hit point
            std::size_t o = std::size_t(q) * 16;
            in[o] = v[0].x, in[o + 1] = v[0].y, in[o + 2] = v[0].z;
        }
    }
    // u = k / 4 and k / 8 exactly (the quadrant edges of sincos) in some lanes.
    for (int q = 0; q < 8 * items; q += 37) in[std::size_t(q) * 16 + 12] = float(q % 9) / 8.0f;
    cl::Buffer b_in = upload(in);
    ocl::Program prog = ocl::Program::build(dev, "test_lanes.cl",
                                            "-D WP_GLOSSY_MODEL=1 -D WP_HAVE_GLOSSY=1 -D WP_HAVE_MIRROR=1");
    ocl::Kernel k(prog, "probe_misc8", "probe.misc8");
    const std::size_t words = std::size_t(items) * 8 * 32;
    cl::Buffer b_lane(dev.context, CL_MEM_READ_WRITE, words * 4),
        b_scalar(dev.context, CL_MEM_READ_WRITE, words * 4);
    k.launch({&dev.queue}, items, items, b_in, b_lane, b_scalar);
    std::vector<std::uint32_t> lane = download(b_lane, words), scalar = download(b_scalar, words);
    const char* names[32] = {"sin", "cos", "to_world.x", "to_world.y", "to_world.z", "to_local.x",
                             "to_local.y", "to_local.z", "cosine.x", "cosine.y", "cosine.z",
                             "uniform.x", "uniform.y", "uniform.z", "cosine pdf", "p.x", "p.y",
                             "p.z", "err.x", "err.y", "err.z", "origin.x", "origin.y", "origin.z",
                             "shadow tmax", "power heuristic", "solid-angle pdf", "pad", "pad",
                             "pad", "pad", "pad"};
    for (int w = 0; w < 32; ++w) {
        int bad = 0, first = -1;
        for (int q = 0; q < 8 * items; ++q)
            if (lane[std::size_t(q) * 32 + w] != scalar[std::size_t(q) * 32 + w]) {
                bad += 1;
                if (first < 0) first = q;
            }
        INFO(names[w] << ": " << bad << " differing lanes, first " << first);
        CHECK(bad == 0);
    }
}
