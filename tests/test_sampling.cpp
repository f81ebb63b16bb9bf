// test_sampling.cpp — importance sampling (issue 6): χ² goodness of fit of the sampling
// routines run on the device through kernels/test_sampling.cl, normalisation of their
// densities by quadrature on the host (the shared headers compiled as C++), MIS weights,
// and the unbiasedness of the MIS estimator against the original uniform one.
//
// χ² tests: 1e6 samples, bins with < 5 expected pooled, family-wise α = 0.01 Šidák-
// corrected over the kChi2Tests tests of this file (pbrt-v4 bsdfs_test.cpp). Expected bin
// probabilities come from densities written here from scratch in double precision.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include <cstring>

#include <glm/glm.hpp>

// The host copy of the shared code, compiled with the default estimator (MIS, GGX). The
// only other host translation unit that includes bsdf.h, test_materials_conductor.cpp, uses
// the same switches (inline definitions must agree across translation units).
#define WP_SAMPLING 3
#define WP_GLOSSY_MODEL 1
#include "shared/bsdf.h"
#include "shared/lights.h"
#include "shared/rng.h"
#include "shared/sobol.h"

#include "cl/profiler.h"
#include "cl/kernel.h"
#include "cl/program.h"
#include "image/stats.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "scene/obj_loader.h"
#include "scene/upload.h"
#include "chi2.h"
#include "support.h"

using namespace wp;
using test::bin_of;
using test::bin_probabilities;
using test::chi2_pvalue;

namespace {

constexpr int kChi2Tests = 6;  // cosine, GGX VNDF, light choice, light point, glass (2)
const double kAlpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / kChi2Tests);



template <typename T>
cl::Buffer upload(const std::vector<T>& v) {
    auto& dev = test::device();
    return cl::Buffer(dev.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                      std::max<std::size_t>(1, v.size()) * sizeof(T), const_cast<T*>(v.data()));
}

ocl::Program& probe_program() {
    static ocl::Program prog = ocl::Program::build(
        test::device(), "test_sampling.cl", "-D WP_SAMPLING=3 -D WP_GLOSSY_MODEL=1 -D WP_SAMPLER=0");
    return prog;
}

MaterialData material(int kind, float albedo, float alpha = 0) {
    MaterialData m{};
    m.albedo = {albedo, albedo, albedo, 0};
    m.alpha = alpha;
    m.kind = kind;
    return m;
}

// n BSDF samples on the device for arriving direction d and normal +z.
std::vector<float4> sample_bsdf(MaterialData m, glm::vec3 d, int n, cl_uint seed, int front = 1) {
    auto& dev = test::device();
    ocl::Kernel k(probe_program(), "probe_bsdf_sample", "probe.bsdf");
    cl::Buffer out(dev.context, CL_MEM_READ_WRITE, n * sizeof(float4));
    glm::vec3 dn = glm::normalize(d);
    k.launch({&dev.queue}, n, m, float4{dn.x, dn.y, dn.z, 0}, float4{0, 0, 1, 0}, front, seed, n,
             out);
    std::vector<float4> r(n);
    dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, n * sizeof(float4), r.data());
    return r;
}

// GGX from scratch (double): D, Λ, and the VNDF reflection density G1(wo) D(h) / (4 wo.z).
double ggx_d(glm::dvec3 h, double a) {
    if (h.z <= 0) return 0;
    double t = h.z * h.z * (a * a - 1) + 1;
    return a * a / (M_PI * t * t);
}
double ggx_lambda(glm::dvec3 w, double a) {
    double t2 = (1 - w.z * w.z) / (w.z * w.z);
    return 0.5 * (-1 + std::sqrt(1 + a * a * t2));
}
double ggx_pdf(glm::dvec3 wo, glm::dvec3 wi, double a) {
    if (wo.z <= 0 || wi.z <= 0) return 0;
    glm::dvec3 h = glm::normalize(wo + wi);
    return ggx_d(h, a) / (1 + ggx_lambda(wo, a)) / (4 * wo.z);
}

}  // namespace

TEST_CASE("sampling: cosine-weighted diffuse directions (chi2)", "[kernel][stat][sampling]") {
    const int n = 1000000, nt = 20, np = 40;
    auto s = sample_bsdf(material(WP_MATERIAL_DIFFUSE, 0.5f), {0.3f, -0.2f, -1}, n, 3);
    std::vector<double> obs(nt * np, 0.0);
    int bad_pdf = 0;
    for (const float4& w : s) {
        obs[bin_of({w.x, w.y, w.z}, nt, np)] += 1;
        bad_pdf += std::abs(w.w - w.z / M_PI) > 1e-5;
    }
    CHECK(bad_pdf == 0);  // the reported density is cos θ / π
    auto prob = bin_probabilities(nt, np, [](glm::dvec3 w) { return w.z > 0 ? w.z / M_PI : 0.0; });
    std::vector<double> expct(prob.size());
    for (std::size_t i = 0; i < prob.size(); ++i) expct[i] = prob[i] * n;
    int dof = 0;
    double p = chi2_pvalue(obs, expct, &dof);
    INFO("chi2 p-value " << p << " with " << dof << " degrees of freedom, alpha " << kAlpha);
    CHECK(dof > 300);
    CHECK(p > kAlpha);
}

TEST_CASE("sampling: GGX visible-normal reflections (chi2)", "[kernel][stat][sampling]") {
    const int n = 1000000, nt = 40, np = 40;
    const double alpha = 0.3;
    glm::dvec3 din = glm::normalize(glm::dvec3(1.0, 0.4, -0.7));
    glm::dvec3 wo = -din;
    auto s = sample_bsdf(material(WP_MATERIAL_GLOSSY, 0.9f, float(alpha)), glm::vec3(din), n, 5);
    auto prob = bin_probabilities(nt, np, [&](glm::dvec3 w) { return ggx_pdf(wo, w, alpha); });
    // Samples reflected below the surface are absorbed: one extra bin.
    std::vector<double> obs(nt * np + 1, 0.0), expct(nt * np + 1, 0.0);
    double above = 0;
    for (int i = 0; i < nt * np; ++i) {
        expct[i] = prob[i] * n;
        above += prob[i];
    }
    expct[nt * np] = std::max(0.0, 1.0 - above) * n;
    int bad_pdf = 0;
    for (const float4& w : s) {
        if (w.w < 0) {
            obs[nt * np] += 1;
            continue;
        }
        glm::dvec3 wi(w.x, w.y, w.z);
        obs[bin_of(wi, nt, np)] += 1;
        double ref = ggx_pdf(wo, wi, alpha);
        bad_pdf += std::abs(w.w - ref) > 1e-3 * ref + 1e-5;
    }
    CHECK(bad_pdf == 0);  // the reported density matches G1 D / (4 cos θo)
    int dof = 0;
    double p = chi2_pvalue(obs, expct, &dof);
    INFO("absorbed " << obs[nt * np] << " expected " << expct[nt * np] << "; chi2 p-value " << p
                     << " with " << dof << " degrees of freedom, alpha " << kAlpha);
    CHECK(dof > 100);
    CHECK(p > kAlpha);
}

TEST_CASE("sampling: light triangles by power, points uniform on them (chi2)",
          "[kernel][stat][sampling]") {
    // Three emitters of different areas and radiances, and a non-emitting triangle.
    Scene s;
    s.name = "lights";
    Material dark;
    dark.name = "dark";
    std::uint32_t mdark = s.add_material(dark);
    auto light = [&](glm::vec3 le) {
        Material m;
        m.name = "light";
        m.emission = le;
        return s.add_material(m);
    };
    s.add_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, light({1, 1, 1}));
    s.add_mesh({{0, 0, 1}, {3, 0, 1}, {0, 1, 1}}, {{0, 1, 2}}, light({0.5f, 0.2f, 0.1f}));
    s.add_mesh({{0, 0, 2}, {1, 0, 2}, {0, 1, 2}}, {{0, 1, 2}}, mdark);
    s.add_mesh({{0, 0, 3}, {0.5f, 0, 3}, {0, 2, 3}}, {{0, 1, 2}}, light({2, 4, 1}));
    LightTable lt = build_light_table(s);
    REQUIRE(lt.size() == 3);
    CHECK(lt.pdf_area[2] == 0.0f);
    // Power = area × luminance, from scratch.
    auto lum = [](glm::dvec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
    std::vector<double> power = {0.5 * lum({1, 1, 1}), 1.5 * lum({0.5, 0.2, 0.1}),
                                 0.5 * lum({2, 4, 1})};
    double total = power[0] + power[1] + power[2];

    const int n = 1000000, g = 10;
    auto& dev = test::device();
    ocl::Kernel k(probe_program(), "probe_light_sample", "probe.light");
    // Three lights: below WP_LIGHT_GUIDE_MIN the renderer builds no guide table and picks by
    // the search; with a table (built here) the picks must be the same, light for light.
    REQUIRE(lt.guide.empty());
    const std::vector<int> guide = build_cdf_guide(lt.cdf);
    REQUIRE(guide.size() == 5);  // m = 4 buckets and the end
    cl::Buffer b_cdf = upload(lt.cdf), b_guide = upload(guide), b_prims = upload(lt.prims),
               b_pdf = upload(lt.pdf_area);
    cl::Buffer b_light(dev.context, CL_MEM_READ_WRITE, n * sizeof(int));
    cl::Buffer b_point(dev.context, CL_MEM_READ_WRITE, n * sizeof(float4));
    std::vector<int> li(n), li_plain(n);
    std::vector<float4> pt(n);
    k.launch({&dev.queue}, n, b_cdf, cl_int(3), b_guide, cl_int(0), b_prims, b_pdf, cl_uint(9), n,
             b_light, b_point);
    dev.queue.enqueueReadBuffer(b_light, CL_TRUE, 0, n * sizeof(int), li_plain.data());
    k.launch({&dev.queue}, n, b_cdf, cl_int(3), b_guide, static_cast<int>(guide.size() - 1), b_prims,
             b_pdf, cl_uint(9), n, b_light, b_point);
    dev.queue.enqueueReadBuffer(b_light, CL_TRUE, 0, n * sizeof(int), li.data());
    dev.queue.enqueueReadBuffer(b_point, CL_TRUE, 0, n * sizeof(float4), pt.data());
    CHECK(li == li_plain);

    // Choice frequencies against power fractions.
    std::vector<double> obs(3, 0.0), expct(3);
    for (int i = 0; i < 3; ++i) expct[i] = power[i] / total * n;
    // Points: a g x g grid over the barycentric square (b1, b2); cells below the diagonal
    // b1 + b2 = 1 hold 2 / g² of the triangle, cells on it 1 / g², cells above none.
    std::vector<double> pobs(g * g, 0.0), pexp(g * g, 0.0);
    for (int i = 0; i < g; ++i)
        for (int j = 0; j < g; ++j) pexp[i * g + j] = (i + j < g - 1 ? 2.0 : i + j == g - 1 ? 1.0 : 0.0) / (g * g) * n;
    int bad_pdf = 0;
    for (int i = 0; i < n; ++i) {
        REQUIRE((li[i] >= 0 && li[i] < 3));
        obs[li[i]] += 1;
        int a = std::min(g - 1, int(pt[i].x * g)), b = std::min(g - 1, int(pt[i].y * g));
        pobs[a * g + b] += 1;
        bad_pdf += pt[i].z != lt.pdf_area[lt.prims[li[i]]];
    }
    CHECK(bad_pdf == 0);
    // The area density integrates to 1 over all lights: Σ pdf_area × area.
    std::vector<double> area = {0.5, 1.5, 0.5};
    double integral = 0;
    for (int i = 0; i < 3; ++i) integral += lt.pdf_area[lt.prims[i]] * area[i];
    CHECK(integral == Approx(1.0).epsilon(1e-5));
    int dof = 0;
    double p = chi2_pvalue(obs, expct, &dof);
    INFO("light choice: counts " << obs[0] << " " << obs[1] << " " << obs[2] << " expected "
                                 << expct[0] << " " << expct[1] << " " << expct[2] << "; p " << p);
    CHECK(dof == 2);
    CHECK(p > kAlpha);
    double pp = chi2_pvalue(pobs, pexp, &dof);
    INFO("light point: p " << pp << " with " << dof << " degrees of freedom");
    CHECK(dof > 40);
    CHECK(pp > kAlpha);
}

// Each density the kernels sample with integrates to 1 over the sphere (minus what is
// absorbed below the surface for GGX, which the weight accounts for), by midpoint
// quadrature of the shared code compiled as C++.
// wp_cdf_pick is branch-free (a select per halving step); it must pick the entry the classic
// binary search picks (the first k with u < cdf[k], n − 1 if none) on every CDF the renderer
// builds: prefix sums, with runs of equal entries (zero-weight lights), every size from 1.
TEST_CASE("sampling: branch-free CDF pick equals the classic binary search", "[unit][sampling]") {
    auto classic = [](const std::vector<float>& cdf, float u) {
        int lo = 0, hi = int(cdf.size()) - 1;
        while (lo < hi) {
            int mid = (lo + hi) / 2;
            if (u < cdf[mid])
                hi = mid;
            else
                lo = mid + 1;
        }
        return lo;
    };
    test::Rng rng(15);
    long mismatches = 0, picks = 0;
    for (int n = 1; n <= 300; ++n) {
        for (int trial = 0; trial < 4; ++trial) {
            std::vector<float> w(n), cdf(n);
            for (float& x : w) x = rng.uniform() < 0.2f ? 0.0f : rng.uniform();
            double sum = 0, acc = 0;
            for (float x : w) sum += x;
            for (int k = 0; k < n; ++k) {
                acc += w[k];
                cdf[k] = sum > 0 ? float(acc / sum) : float(k + 1) / float(n);
            }
            cdf[n - 1] = 1.0f;
            std::vector<float> us = {0.0f, 0x1.fffffep-1f};
            for (int k = 0; k < n; ++k) us.insert(us.end(), {cdf[k], std::nextafter(cdf[k], 0.0f)});
            for (int i = 0; i < 200; ++i) us.push_back(rng.uniform());
            for (float u : us) {
                ++picks;
                if (wp_cdf_pick(cdf.data(), n, u) != classic(cdf, u)) ++mismatches;
            }
        }
    }
    INFO(mismatches << " of " << picks << " picks differ");
    CHECK(mismatches == 0);
}

// The guided pick (a guide table, then wp_cdf_pick inside one bucket) must pick what the
// plain definition picks, the first k with u < cdf[k] (n − 1 if none; a linear scan here),
// for every u the bucket arithmetic could get wrong: on bucket edges j / m and their float
// neighbours, on every cdf value and its neighbours, 0, just below 1, and out of [0, 1).
// The CDFs are adversarial: runs of zero weights (equal entries, leading zeros), weights
// over 60 decades, all weight on one entry, entries exactly on bucket edges, subnormal
// entries, sizes around powers of two and veach-mis's 15,360.
TEST_CASE("sampling: guided CDF pick equals a linear scan", "[unit][sampling]") {
    auto scan = [](const std::vector<float>& cdf, float u) {
        int n = int(cdf.size());
        for (int k = 0; k < n; ++k)
            if (u < cdf[k]) return k;
        return n - 1;
    };
    auto prefix = [](const std::vector<double>& w) {
        std::vector<float> cdf(w.size());
        double sum = 0, acc = 0;
        for (double x : w) sum += x;
        for (std::size_t k = 0; k < w.size(); ++k) {
            acc += w[k];
            cdf[k] = sum > 0 ? float(acc / sum) : float(k + 1) / float(w.size());
        }
        cdf.back() = 1.0f;
        return cdf;
    };
    test::Rng rng(1974);
    std::vector<std::vector<float>> cdfs;
    std::vector<int> sizes;
    for (int n = 1; n <= 70; ++n) sizes.push_back(n);
    for (int n : {127, 128, 129, 255, 256, 257, 1000, 1023, 1024, 1025, 4096, 15360})
        sizes.push_back(n);
    for (int n : sizes) {
        std::vector<double> w(n);
        for (double& x : w) x = rng.uniform() < 0.2f ? 0.0 : rng.uniform();  // zero runs
        cdfs.push_back(prefix(w));
        for (double& x : w) x = std::pow(10.0, 60.0 * rng.uniform() - 30.0);  // huge ratios
        cdfs.push_back(prefix(w));
        std::fill(w.begin(), w.end(), 0.0);  // one entry holds everything
        w[std::size_t(rng.uniform() * n) % n] = 1.0;
        cdfs.push_back(prefix(w));
        for (int k = 0; k < n; ++k) w[k] = k < n / 2 ? 0.0 : 1.0;  // leading zeros
        cdfs.push_back(prefix(w));
        std::fill(w.begin(), w.end(), 1.0);  // uniform: on bucket edges when n is 2^i
        cdfs.push_back(prefix(w));
        for (int k = 0; k < n; ++k) w[k] = k + 1 < n ? 1e-45 * (k % 3) : 1.0;  // subnormals
        cdfs.push_back(prefix(w));
        // Long zero runs between weights.
        for (int k = 0; k < n; ++k) w[k] = (k % 17 == 0 || rng.uniform() < 0.02f) ? rng.uniform() : 0.0;
        cdfs.push_back(prefix(w));
        // Entries one float above or below the bucket edges (k + 1) / m.
        int m = 1;
        while (m < n) m <<= 1;
        for (float dir : {2.0f, 0.0f}) {
            std::vector<float> cdf(n);
            for (int k = 0; k < n; ++k) cdf[k] = std::nextafter(float(k + 1) / float(m), dir);
            cdf.back() = 1.0f;
            cdfs.push_back(cdf);
        }
    }
    long mismatches = 0, picks = 0, bad_tables = 0;
    for (const std::vector<float>& cdf : cdfs) {
        const int n = int(cdf.size());
        std::vector<int> guide = build_cdf_guide(cdf);
        const int m = int(guide.size()) - 1;
        // m: the least power of two >= n; entries in [0, n) and non-decreasing (in-bounds reads).
        bool ok = m >= n && (m & (m - 1)) == 0 && (m == 1 || m / 2 < n) && guide[0] == 0 &&
                  guide[m] == n - 1;
        for (int j = 0; j < m; ++j) ok = ok && guide[j] >= 0 && guide[j] <= guide[j + 1];
        bad_tables += !ok;
        if (!ok) continue;
        std::vector<float> us = {0.0f, -0.0f, 0x1.fffffep-1f, 1.0f, 1.5f, -0.25f, -1e-30f,
                                 INFINITY, -INFINITY, 1e-45f};
        for (int j = 0; j <= m; ++j) {
            float e = float(j) / float(m);
            us.insert(us.end(), {e, std::nextafter(e, 0.0f), std::nextafter(e, 2.0f)});
        }
        for (int k = 0; k < n; ++k)
            us.insert(us.end(), {cdf[k], std::nextafter(cdf[k], 0.0f), std::nextafter(cdf[k], 2.0f)});
        for (int i = 0; i < 200; ++i) us.push_back(rng.uniform());
        for (float u : us) {
            ++picks;
            if (wp_cdf_pick_guided(cdf.data(), guide.data(), m, u) != scan(cdf, u)) ++mismatches;
        }
        int nan_pick = wp_cdf_pick_guided(cdf.data(), guide.data(), m, NAN);
        bad_tables += nan_pick < 0 || nan_pick >= n;  // NaN: any light, but a light
    }
    INFO(mismatches << " of " << picks << " picks differ; " << bad_tables << " bad tables of "
                    << cdfs.size());
    CHECK(bad_tables == 0);
    CHECK(mismatches == 0);
    CHECK(build_cdf_guide({}).empty());
}

TEST_CASE("sampling: densities integrate to 1 (quadrature of the shared code)", "[unit][sampling]") {
    auto integrate = [](auto pdf) {
        const int nt = 400, np = 400;
        double s = 0, dt = M_PI / nt, dp = 2 * M_PI / np;
        for (int i = 0; i < nt; ++i)
            for (int j = 0; j < np; ++j) {
                double th = (i + 0.5) * dt, ph = (j + 0.5) * dp;
                float3 w = make_float3(float(std::sin(th) * std::cos(ph)),
                                       float(std::sin(th) * std::sin(ph)), float(std::cos(th)));
                s += pdf(w) * std::sin(th) * dt * dp;
            }
        return s;
    };
    CHECK(integrate([](float3 w) { return wp_cosine_hemisphere_pdf(w.z); }) == Approx(1.0).epsilon(1e-3));
    CHECK(integrate([](float3) { return wp_uniform_hemisphere_pdf() * 0.5f; }) == Approx(1.0).epsilon(1e-3));
    CHECK(integrate([](float3 w) { return wp_phong_lobe_pdf(w.z, 20.0f); }) == Approx(1.0).epsilon(1e-3));
    // GGX: the distribution of visible normals integrates to 1 for every wo (Heitz 2018,
    // eq. 3); the reflected directions' density integrates to 1 minus the part reflected
    // below the surface (absorbed), so to at most 1, and to ~1 for a smooth surface seen
    // head-on; ∫ D(h) (h·n) dh = 1 (Walter et al. 2007, eq. 4).
    for (float alpha : {0.1f, 0.3f, 0.7f}) {
        INFO("alpha " << alpha);
        const double tol = alpha < 0.2f ? 2e-2 : 3e-3;  // quadrature of a sharp lobe
        double proj = integrate([&](float3 h) { return wp_ggx_d(h, alpha) * h.z; });
        CHECK(proj == Approx(1.0).epsilon(tol));
        for (float3 wo : {make_float3(0, 0, 1), normalize(make_float3(0.8f, 0.1f, 0.4f))}) {
            double vndf = integrate([&](float3 h) {
                return wp_ggx_g1(wo, alpha) * max(0.0f, dot(wo, h)) * wp_ggx_d(h, alpha) / wo.z;
            });
            CHECK(vndf == Approx(1.0).epsilon(tol));
            double refl = integrate([&](float3 w) { return wp_ggx_reflect_pdf(wo, w, alpha); });
            CHECK(refl <= 1.0 + tol);
            CHECK(refl > 0.5);
        }
    }
    double head_on = integrate([](float3 w) { return wp_ggx_reflect_pdf(make_float3(0, 0, 1), w, 0.1f); });
    CHECK(head_on == Approx(1.0).epsilon(2e-2));
}

// For directions sampled by either strategy, the two power-heuristic weights sum to 1.
TEST_CASE("sampling: MIS weights of BSDF and light sampling sum to 1", "[unit][sampling]") {
    MaterialData ggx{};
    ggx.albedo = make_float4(0.8f, 0.8f, 0.8f, 0.0f);
    ggx.alpha = 0.2f;
    ggx.kind = WP_MATERIAL_GLOSSY;
    MaterialData dif{};
    dif.albedo = make_float4(0.5f, 0.5f, 0.5f, 0.0f);
    dif.kind = WP_MATERIAL_DIFFUSE;
    float3 ns = make_float3(0, 0, 1), d = normalize(make_float3(0.5f, 0.2f, -1.0f));
    // A light triangle above, its density per unit area 1 / area.
    float3 l0 = make_float3(-1, -1, 2), l1 = make_float3(2, -1, 2), l2 = make_float3(-1, 2, 2);
    float3 ln = normalize(cross(l2 - l0, l1 - l0));  // facing down, towards the receiver
    float area = 0.5f * length(cross(l1 - l0, l2 - l0));
    test::Rng rng(17);
    int checked = 0;
    for (const MaterialData& m : {ggx, dif})
        for (int i = 0; i < 2000; ++i) {
            float4 u = make_float4(rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
            // A BSDF-sampled direction and a light-sampled one.
            float3 wo, weight;
            float pdf_b;
            int spec;
            if (!wp_bsdf_sample_pdf(m, nullptr, d, ns, 1, u, &wo, &weight, &pdf_b, &spec)) continue;
            float2 b = wp_sample_triangle_barycentric(u.z, u.w);
            float3 y = l0 * (1 - b.x - b.y) + l1 * b.x + l2 * b.y;
            float dist2 = dot(y, y);
            float3 wl = y * (1.0f / std::sqrt(dist2));
            float pdf_l = wp_light_pdf_solid_angle(1.0f / area, dist2, -dot(wl, ln));
            float pdf_bl;
            wp_bsdf_eval(m, nullptr, d, ns, 1, wl, &pdf_bl);
            for (auto pr : {std::pair<float, float>{pdf_b, pdf_l}, {pdf_l, pdf_bl}}) {
                float w1 = wp_power_heuristic(pr.first, pr.second);
                float w2 = wp_power_heuristic(pr.second, pr.first);
                if (pr.first > 0 || pr.second > 0) {
                    CHECK(w1 + w2 == Approx(1.0f).epsilon(1e-6));
                    ++checked;
                }
            }
            // eval agrees with sample on the density of the sampled direction
            float pdf_e;
            wp_bsdf_eval(m, nullptr, d, ns, 1, wo, &pdf_e);
            CHECK(pdf_e == Approx(pdf_b).epsilon(1e-3));
        }
    CHECK(checked > 3000);
}

// Same expectation, different variance: the MIS image and the original uniform image of a
// small scene pass the per-pixel z-test against each other (src/image/stats.h). The scene:
// the Cornell box (2,000 object triangles: mirror sphere and glossy box) whose ceiling is
// the light, so that the uniform estimator has no rare-event pixels whose variance it
// would underestimate.
TEST_CASE("sampling: mis and uniform images agree (per-pixel z-test)", "[render][stat][sampling]") {
    Scene scene = make_cornell_box(2000);
    Material ceiling;
    ceiling.name = "ceiling-light";
    ceiling.albedo = glm::vec3(0.5f);
    ceiling.emission = glm::vec3(1.0f, 0.9f, 0.8f);
    std::uint32_t mc = scene.add_material(ceiling);
    scene.material_ids[2] = scene.material_ids[3] = mc;  // the ceiling quad
    for (auto& m : scene.materials)
        if (m.name == "light") m.emission = glm::vec3(0.0f);
    auto render = [&](render::Sampling sampling, int spp, std::uint32_t seed) {
        render::RenderSettings s;
        s.width = 32;
        s.height = 24;
        s.depth = 3;
        s.seed = seed;
        s.variance = true;
        s.estimator.sampling = sampling;
        render::Wavefront wf(test::device(), scene, s);
        render::LoopOptions lo;
        lo.spp = spp;
        render::render_frames(wf, lo, nullptr);
        for (int c : wf.counters()) CHECK(c == 0);
        return wf.moments();
    };
    render::FilmMoments a = render(render::Sampling::Mis, 256, 1);
    render::FilmMoments b = render(render::Sampling::Uniform, 1024, 2);
    ZTest z = z_test(a.mean, b.mean, &a.mean_variance, &b.mean_variance);
    INFO(z.passed << " of " << z.pixels << " pixels pass, max |z| " << z.max_abs_z << " at ("
                  << z.max_x << ", " << z.max_y << ")");
    CHECK(z.pass_fraction >= 0.9975);
    // And MIS has the lower variance (mean over pixels of the variance of one sample).
    double va = 0, vb = 0;
    for (std::size_t i = 0; i < a.mean_variance.rgb.size(); ++i) {
        va += a.mean_variance.rgb[i] * 256;
        vb += b.mean_variance.rgb[i] * 1024;
    }
    INFO("per-sample variance: mis " << va << ", uniform " << vb);
    CHECK(va < vb);
}

// Glass: reflection with the exact Fresnel probability, refraction by Snell's law, total
// internal reflection past the critical angle. Fresnel from scratch (Born & Wolf).
TEST_CASE("sampling: glass reflects with the Fresnel probability and refracts by Snell (chi2)",
          "[kernel][stat][sampling]") {
    const int n = 1000000;
    const double ior = 1.5;
    auto fresnel = [](double cos_i, double eta) {  // eta = n_i / n_t
        double sin2_t = eta * eta * (1 - cos_i * cos_i);
        if (sin2_t >= 1) return 1.0;
        double ct = std::sqrt(1 - sin2_t);
        double rs = (eta * cos_i - ct) / (eta * cos_i + ct), rp = (cos_i - eta * ct) / (cos_i + eta * ct);
        return 0.5 * (rs * rs + rp * rp);
    };
    MaterialData m{};
    m.albedo = {1, 1, 1, 0};
    m.kind = WP_MATERIAL_GLASS;
    m.ior = float(ior);
    struct Case {
        double theta_deg;
        int front;
    };
    for (Case c : {Case{60.0, 1}, Case{30.0, 0}}) {
        double th = c.theta_deg * M_PI / 180;
        glm::dvec3 d(std::sin(th), 0.0, -std::cos(th));
        double eta = c.front ? 1 / ior : ior;
        double f = fresnel(std::cos(th), eta);
        auto s = sample_bsdf(m, glm::vec3(d), n, 21 + c.front, c.front);
        std::vector<double> obs(2, 0.0), expct = {f * n, (1 - f) * n};
        int bad_dir = 0;
        for (const float4& w : s) {
            bool refl = w.z > 0;
            obs[refl ? 0 : 1] += 1;
            // Reflection mirrors; refraction keeps the plane and sin θt = η sin θi.
            double sin_o = std::sqrt(w.x * w.x + w.y * w.y);
            double want = refl ? std::sin(th) : eta * std::sin(th);
            bad_dir += std::abs(sin_o - want) > 1e-5 || std::abs(w.y) > 1e-6 || w.x < 0;
        }
        int dof = 0;
        double p = chi2_pvalue(obs, expct, &dof);
        INFO("theta " << c.theta_deg << " front " << c.front << ": reflected " << obs[0]
                      << " expected " << expct[0] << "; p " << p);
        CHECK(bad_dir == 0);
        CHECK(dof == 1);
        CHECK(p > kAlpha);
    }
    // Past the critical angle (41.8 degrees from inside) everything reflects.
    double th = 60.0 * M_PI / 180;
    auto s = sample_bsdf(m, glm::vec3(std::sin(th), 0, -std::cos(th)), 10000, 3, 0);
    int refracted = 0;
    for (const float4& w : s) refracted += w.z <= 0;
    CHECK(refracted == 0);
}

// Owen-scrambled Sobol points (kernels/shared/sobol.h, compiled as C++): the first 2^k
// points of any scramble are stratified, one point in each of the 2^k intervals of every
// dimension, and dimensions (0, 1) form a (0, 2)-net: one point in every 2^a x 2^b box with
// a + b = k (the properties Owen scrambling preserves; Burley 2020, section 2).
TEST_CASE("sampling: Owen-scrambled Sobol points are stratified", "[unit][sampling]") {
    const int k = 8, n = 1 << k;
    for (uint seed : {0u, 1u, 0xdeadbeefu}) {
        std::vector<uint4> p(n);
        for (int i = 0; i < n; ++i) p[i] = wp_sobol_owen4(uint(i), seed);
        for (int dim = 0; dim < 4; ++dim) {
            std::vector<int> cnt(n, 0);
            for (const uint4& q : p) {
                uint v = dim == 0 ? q.x : dim == 1 ? q.y : dim == 2 ? q.z : q.w;
                cnt[v >> (32 - k)] += 1;
            }
            INFO("seed " << seed << " dim " << dim);
            CHECK(std::all_of(cnt.begin(), cnt.end(), [](int c) { return c == 1; }));
        }
        for (int a = 0; a <= k; ++a) {
            int b = k - a;
            std::vector<int> cnt(n, 0);
            for (const uint4& q : p) {
                uint cx = a > 0 ? q.x >> (32 - a) : 0u, cy = b > 0 ? q.y >> (32 - b) : 0u;
                cnt[(cx << b) | cy] += 1;
            }
            INFO("seed " << seed << " boxes 2^" << a << " x 2^" << b);
            CHECK(std::all_of(cnt.begin(), cnt.end(), [](int c) { return c == 1; }));
        }
    }
    // Different seeds scramble differently.
    CHECK(wp_sobol_owen4(5u, 1u).x != wp_sobol_owen4(5u, 2u).x);
}

// wp_sincos_2pi against sin/cos in double: every u = k / 2^20 of [0, 1] and the quarter
// turns exactly.
TEST_CASE("sampling: sincos of 2 pi u is within 2 ulp-scale error of double", "[unit][sampling]") {
    double worst = 0.0;
    const int n = 1 << 20;
    for (int k = 0; k <= n; ++k) {
        float u = float(k) / float(n), s, c;
        wp_sincos_2pi(u, &s, &c);
        double phi = 2.0 * 3.14159265358979323846 * double(u);
        worst = std::max({worst, std::abs(double(s) - std::sin(phi)), std::abs(double(c) - std::cos(phi))});
    }
    CHECK(worst < 2.4e-7);  // 2 ulp of 1 is 2.4e-7
    const float quarter[5][2] = {{0.0f, 1.0f}, {1.0f, 0.0f}, {0.0f, -1.0f}, {-1.0f, 0.0f}, {0.0f, 1.0f}};
    for (int q = 0; q <= 4; ++q) {
        float s, c;
        wp_sincos_2pi(0.25f * float(q), &s, &c);
        CHECK(std::abs(s - quarter[q][0]) == 0.0f);
        CHECK(c == quarter[q][1]);
    }
}

// wp_pow against pow in double: bases over every binade of the floats (denormals included)
// and densely near 1 (the Phong lobe's cosines), exponents from 1e-6 (1 / (e + 1) of the
// lobe sampler) to 1e6 (its pdf's e) and negative; relative error where the result is a
// normal float, the bound sampling.h states. Then the ends as pow has them.
TEST_CASE("sampling: inline pow is within its stated error of double pow", "[unit][sampling]") {
    test::Rng rng(0x90e);
    double worst = 0.0;
    float worst_x = 0.0f, worst_y = 0.0f;
    long compared = 0;
    auto check = [&](float x, float y) {
        const double r = std::pow(double(x), double(y));
        if (!(r >= 0x1p-126 && r <= 0x1.fffffep127)) return;
        const double e = std::abs(double(wp_pow(x, y)) - r) / r;
        ++compared;
        if (e > worst) worst = e, worst_x = x, worst_y = y;
    };
    const float ys[] = {0.5f, 1.0f, 2.0f, 3.0f, 1.0f / 3.0f, 100.0f, 1.0f / 101.0f, -1.0f, -2.5f, 20000.0f};
    for (int k = 0; k < 4000000; ++k) {
        float x, y;
        switch (k % 4) {
            case 0: x = std::ldexp(rng.uniform(1.0f, 2.0f), int(rng.next() % 276) - 149); break;  // any binade
            case 1: x = 1.0f - std::pow(10.0f, rng.uniform(-7.5f, 0.0f)); break;  // cosines near 1
            case 2: x = 1.0f + std::pow(10.0f, rng.uniform(-7.0f, 0.5f)); break;
            default: x = rng.uniform(); break;
        }
        switch (k % 3) {
            case 0: y = std::pow(10.0f, rng.uniform(-6.0f, 6.0f)); break;
            case 1: y = -std::pow(10.0f, rng.uniform(-3.0f, 2.0f)); break;
            default: y = ys[(k / 3) % 10]; break;
        }
        check(x, y);
    }
    for (float x = 0.999f; x < 1.001f; x = std::nextafter(x, 2.0f)) check(x, 1e5f);  // every float
    INFO("wp_pow: max rel " << worst << " at pow(" << worst_x << ", " << worst_y << ") over " << compared);
    CHECK(compared > 2000000);
    CHECK(worst < 2.5e-7);  // measured 2.38e-7
    for (float y : {0.5f, 3.0f, 1e6f}) {
        CHECK(wp_pow(0.0f, y) == 0.0f);
        CHECK(wp_pow(-0.0f, y) == 0.0f);
        CHECK(wp_pow(INFINITY, y) == INFINITY);
        CHECK(wp_pow(1.0f, y) == 1.0f);
        CHECK(wp_pow(0.5f, -y) > 1.0f);
        CHECK(std::isnan(wp_pow(-0.5f, y)));
        CHECK(std::isnan(wp_pow(NAN, y)));
    }
    CHECK(wp_pow(0.0f, 0.0f) == 1.0f);
    CHECK(wp_pow(0.0f, -1.0f) == INFINITY);
    CHECK(wp_pow(INFINITY, -1.0f) == 0.0f);
    CHECK(wp_pow(INFINITY, 0.0f) == 1.0f);
    CHECK(wp_pow(0.3f, 0.0f) == 1.0f);
    CHECK(wp_pow(2.0f, 10.0f) == 1024.0f);
    CHECK(wp_pow(2.0f, 128.0f) == INFINITY);
    CHECK(wp_pow(0.5f, 160.0f) == 0.0f);  // below e^-104: 0, as wp_exp
    CHECK(wp_pow(0x1p-149f, 1.0f) == 0x1p-149f);
    CHECK(std::isnan(wp_pow(0.5f, NAN)));
    CHECK(wp_pow(1.0f, INFINITY) == 1.0f);
    CHECK(wp_pow(1.0f, -INFINITY) == 1.0f);
    CHECK(wp_pow(0.5f, INFINITY) == 0.0f);
    CHECK(wp_pow(2.0f, INFINITY) == INFINITY);
    CHECK(wp_pow(0.5f, -INFINITY) == INFINITY);
    CHECK(wp_pow(0.0f, INFINITY) == 0.0f);
    CHECK(wp_pow(INFINITY, -INFINITY) == 0.0f);
}

// The device's Sobol numbers (128-bit vector code in OpenCL) equal the host's scalar
// spelling of the same steps, bit for bit.
TEST_CASE("sampling: Sobol numbers on the device equal the host's", "[kernel][sampling]") {
    auto& dev = test::device();
    static ocl::Program prog = ocl::Program::build(dev, "test_sampling.cl", "-D WP_SAMPLER=1");
    ocl::Kernel k(prog, "probe_rng4", "probe.rng4");
    const int n = 4096;
    for (cl_uint seed : {0u, 7u, 0xfeedbeefu}) {
        cl::Buffer out(dev.context, CL_MEM_READ_WRITE, n * sizeof(uint4));
        k.launch({&dev.queue}, n, seed, n, out);
        std::vector<uint4> got(n);
        dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, n * sizeof(uint4), got.data());
        int bad = 0;
        for (int i = 0; i < n; ++i) {
            float4 w = wp_rng4(seed, uint(i), 3u * uint(i) + 1u, uint(i % 7), uint(i % 5));
            uint4 b;
            std::memcpy(&b, &w, sizeof b);
            bad += got[i].x != b.x || got[i].y != b.y || got[i].z != b.z || got[i].w != b.w;
        }
        INFO("seed " << seed);
        CHECK(bad == 0);
    }
}

// wp_rng4_lanes (kernels/shared/rng_lanes.h: wp_rng4 for eight keys as uint8 / float8
// vector code) gives every lane the bits of the host's scalar wp_rng4, for both samplers and
// K = 1 and 4 RQMC replicates, on keys that include 0, 2^31 and 0xffffffff. The host's
// wp_rng4 is compiled for the default sampler (Sobol) and K = 1; the other cases take the
// same steps from its parts (wp_sobol_rng4 with `replicates`, wp_pcg4d).
TEST_CASE("sampling: eight-lane rng4 on the device equals the host's scalar rng4", "[kernel][sampling]") {
    // (and wp_rng2_lanes / wp_rng1_lanes its first two numbers and its first, from the
    // table-free dimensions 0 and 1)
    auto& dev = test::device();
    const int items = 512;  // 4096 lanes per seed
    // Keys: edge values mixed with pcg4d words; bounce and group uniform per item.
    const uint edges[] = {0u, 1u, 2u, 3u, 4u, 5u, 0x7fffffffu, 0x80000000u, 0x80000001u,
                          0xfffffffcu, 0xfffffffeu, 0xffffffffu};
    const int n_edges = int(sizeof edges / sizeof edges[0]);
    std::vector<uint> pixel(8 * items), sample(8 * items), bounce(items), group(items);
    for (int i = 0; i < items; ++i) {
        for (int l = 0; l < 8; ++l) {
            int q = 8 * i + l;
            Rng4 h = wp_pcg4d(uint(q), 0x1234u, 0x5678u, 0x9abcu);
            pixel[q] = (q % 3 == 0) ? edges[(q / 3) % n_edges] : (q % 3 == 1 ? h.x : h.x & 0xffffu);
            sample[q] = (q % 5 < 2) ? edges[(q / 5 + l) % n_edges] : (q % 5 == 2 ? h.y : h.y & 0x3ffu);
        }
        bounce[i] = (i % 11 == 10) ? 0xffffffffu : uint(i % 11);
        group[i] = uint(i % 16);
    }
    cl::Buffer pb = upload(pixel), sb = upload(sample), bb = upload(bounce), gb = upload(group);
    struct Config { int sampler; uint replicates; };
    for (Config c : {Config{1, 1u}, Config{1, 4u}, Config{0, 1u}, Config{0, 4u}}) {
        std::string options = "-D WP_SAMPLER=" + std::to_string(c.sampler) +
                               " -D WP_SOBOL_REPLICATES=" + std::to_string(c.replicates);
        ocl::Program prog = ocl::Program::build(dev, "test_sampling.cl", options);
        ocl::Kernel k(prog, "probe_rng4_lanes", "probe.rng4_lanes");
        for (cl_uint seed : {0u, 7u, 0xfeedbeefu, 0xffffffffu}) {
            cl::Buffer out(dev.context, CL_MEM_READ_WRITE, 32 * items * sizeof(uint));
            cl::Buffer out_narrow(dev.context, CL_MEM_READ_WRITE, 24 * items * sizeof(uint));
            k.launch({&dev.queue}, items, seed, items, pb, sb, bb, gb, out, out_narrow);
            std::vector<uint> got(32 * items), got_narrow(24 * items);
            dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, got.size() * sizeof(uint), got.data());
            dev.queue.enqueueReadBuffer(out_narrow, CL_TRUE, 0, got_narrow.size() * sizeof(uint),
                                        got_narrow.data());
            int bad = 0, first = -1, bad_narrow = 0;
            for (int q = 0; q < 8 * items; ++q) {
                int i = q / 8, l = q % 8;
                uint b[4];
                if (c.sampler == 1 && c.replicates == 1) {
                    float4 u = wp_rng4(seed, pixel[q], sample[q], bounce[i], group[i]);
                    std::memcpy(b, &u, sizeof b);
                } else {
                    uint r[4];
                    if (c.sampler == 1) {
                        uint4 v = wp_sobol_rng4(seed, pixel[q], sample[q], bounce[i], group[i], c.replicates);
                        r[0] = v.x, r[1] = v.y, r[2] = v.z, r[3] = v.w;
                    } else {
                        Rng4 v = wp_pcg4d(pixel[q], sample[q], bounce[i] * uint(WP_RNG_GROUPS) + group[i], seed);
                        r[0] = v.x, r[1] = v.y, r[2] = v.z, r[3] = v.w;
                    }
                    for (int d = 0; d < 4; ++d) b[d] = as_uint(wp_uint_to_unit(r[d]));
                }
                bool differs = false;
                for (int d = 0; d < 4; ++d) differs |= got[32 * i + 8 * d + l] != b[d];
                if (differs) {
                    bad += 1;
                    if (first < 0) first = q;
                }
                // wp_rng2_lanes: the first two numbers; wp_rng1_lanes: the first.
                bad_narrow += got_narrow[24 * i + l] != b[0] || got_narrow[24 * i + 8 + l] != b[1] ||
                              got_narrow[24 * i + 16 + l] != b[0];
            }
            INFO("sampler " << c.sampler << ", replicates " << c.replicates << ", seed " << seed
                            << ", first differing lane " << first);
            CHECK(bad == 0);
            CHECK(bad_narrow == 0);
        }
    }
}

// wp_sincos_2pi on the device gives the host's bits (no contraction, no library call).
TEST_CASE("sampling: sincos of 2 pi u on the device equals the host's", "[kernel][sampling]") {
    auto& dev = test::device();
    ocl::Kernel k(probe_program(), "probe_sincos", "probe.sincos");
    const int n = 1 << 16;
    cl::Buffer out(dev.context, CL_MEM_READ_WRITE, (n + 1) * sizeof(uint2));
    k.launch({&dev.queue}, n + 1, n, out);
    std::vector<uint2> got(n + 1);
    dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, (n + 1) * sizeof(uint2), got.data());
    int bad = 0, first = -1;
    for (int i = 0; i <= n; ++i) {
        float s, c;
        wp_sincos_2pi(float(i) / float(n), &s, &c);
        uint bs, bc;
        std::memcpy(&bs, &s, 4);
        std::memcpy(&bc, &c, 4);
        if (got[i].x != bs || got[i].y != bc) {
            bad += 1;
            if (first < 0) first = i;
        }
    }
    INFO("first differing u = " << first << " / " << n);
    CHECK(bad == 0);
}

// The unscrambled points against direction numbers built here from their definition (Joe &
// Kuo 2008: primitive polynomial x^s + a_1 x^(s-1) + ... + 1 with initial m_1..m_s,
// m_j = 2a_1 m_(j-1) ^ 4a_2 m_(j-2) ^ ... ^ 2^s m_(j-s) ^ m_(j-s); v_j = m_j 2^(32-j)), and
// the point as the XOR of v_j over the set index bits in Gray-code-free (direct) form.
TEST_CASE("sampling: Sobol points match the direction numbers' recurrence", "[unit][sampling]") {
    struct Poly { int s; uint a; std::vector<uint> m; };
    const Poly polys[3] = {{1, 0u, {1u}}, {2, 1u, {1u, 3u}}, {3, 1u, {1u, 3u, 1u}}};
    uint v[4][32];
    for (int j = 0; j < 32; ++j) v[0][j] = 1u << (31 - j);  // van der Corput
    for (int d = 1; d < 4; ++d) {
        const Poly& p = polys[d - 1];
        std::vector<uint> m(32);
        for (int j = 0; j < 32; ++j) {
            if (j < p.s) {
                m[j] = p.m[j];
            } else {
                uint x = m[j - p.s] ^ (m[j - p.s] << p.s);
                for (int k = 1; k < p.s; ++k)
                    if ((p.a >> (p.s - 1 - k)) & 1u) x ^= m[j - k] << k;
                m[j] = x;
            }
            v[d][j] = m[j] << (31 - j);
        }
    }
    uint32_t state = 12345u;
    for (int t = 0; t < 2000; ++t) {
        state = state * 1664525u + 1013904223u;
        uint index = t < 64 ? uint(t) : state;
        uint4 got = wp_sobol4(index);
        uint want[4] = {0u, 0u, 0u, 0u};
        for (int d = 0; d < 4; ++d)
            for (int j = 0; j < 32; ++j)
                if ((index >> j) & 1u) want[d] ^= v[d][j];
        INFO("index " << index);
        CHECK(got.x == want[0]);
        CHECK(got.y == want[1]);
        CHECK(got.z == want[2]);
        CHECK(got.w == want[3]);
        // Dimensions 0 and 1 without the table (the lanes' wp_rng2_lanes / wp_rng1_lanes),
        // also at the extreme indices.
        for (uint idx : {index, ~index, index | 0x80000000u}) {
            uint2 r2 = wp_sobol2_reversed(wp_reverse_bits(idx));
            uint w0 = 0u, w1 = 0u;
            for (int j = 0; j < 32; ++j)
                if ((idx >> j) & 1u) w0 ^= v[0][j], w1 ^= v[1][j];
            CHECK(wp_reverse_bits(r2.x) == w0);
            CHECK(wp_reverse_bits(r2.y) == w1);
        }
        // The folded Owen scramble equals Burley's listing 3 written out: shuffle the index,
        // then scramble each coordinate, each scramble = reverse(LK(reverse(x))).
        uint seed = state ^ 0x9e3779b9u;
        uint i = wp_nested_uniform_scramble(index, seed);
        uint4 x = wp_sobol4(i);
        uint4 o = wp_sobol_owen4(index, seed);
        CHECK(o.x == wp_nested_uniform_scramble(x.x, wp_hash_combine(seed, 0u)));
        CHECK(o.y == wp_nested_uniform_scramble(x.y, wp_hash_combine(seed, 1u)));
        CHECK(o.z == wp_nested_uniform_scramble(x.z, wp_hash_combine(seed, 2u)));
        CHECK(o.w == wp_nested_uniform_scramble(x.w, wp_hash_combine(seed, 3u)));
    }
}

// Glass from an OBJ/MTL file (illum 7, Ni), compiled only where used, renders without
// non-finite values; light inside a glass box still reaches the camera.
TEST_CASE("sampling: MTL illum 7 becomes glass (eta from Ni) and is compiled only when used",
          "[render][sampling]") {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("wp-glass-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    {
        std::ofstream mtl(dir / "g.mtl");
        mtl << "newmtl glass\nillum 7\nNi 1.33\nTf 0.9 0.95 1\n"
               "newmtl light\nKd 0 0 0\nKe 4 4 4\n"
               "newmtl floor\nKd 0.5 0.5 0.5\n";
        std::ofstream obj(dir / "g.obj");
        obj << "mtllib g.mtl\n"
               "v -5 -1 -5\nv 5 -1 -5\nv 5 -1 5\nv -5 -1 5\n"      // floor, facing up
               "v -1 3 -1\nv 1 3 -1\nv 1 3 1\nv -1 3 1\n"          // light, facing down
               "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"  // glass pane, +z
               "usemtl floor\nf 1 4 3 2\nusemtl light\nf 5 6 7 8\nusemtl glass\nf 9 10 11 12\n";
    }
    Scene scene = load_obj(dir / "g.obj");
    fs::remove_all(dir);
    bool found = false;
    for (const Material& m : scene.materials)
        if (m.name == "glass") {
            found = true;
            CHECK(m.kind == MaterialKind::Glass);
            CHECK(m.ior == Approx(1.33f));
            CHECK(m.albedo.x == Approx(0.9f));
        }
    CHECK(found);
    auto cfg = render::KernelConfig::from_scene(scene);
    CHECK(cfg.has(MaterialKind::Glass));
    CHECK(cfg.options().find("-D WP_HAVE_GLASS=1") != std::string::npos);
    CHECK(render::KernelConfig::from_scene(make_cornell_box(200)).options().find(
              "-D WP_HAVE_GLASS=0") != std::string::npos);
    render::RenderSettings s;
    s.width = 32;
    s.height = 24;
    s.depth = 4;
    render::Wavefront wf(test::device(), scene, s);
    render::LoopOptions lo;
    lo.spp = 8;
    render::render_frames(wf, lo, nullptr);
    for (int c : wf.counters()) CHECK(c == 0);
    Image img = wf.resolve();
    double sum = 0;
    for (float v : img.rgb) sum += v;
    CHECK(sum > 0.0);
}

// Issue 5, case 4: grazing light and lobes that point below the surface. A white GGX
// surface (F0 = 1, so Fresnel is 1) lit from incidence angles up to 89.99 degrees, at
// roughnesses 0.02 ... 1: every sampled weight is finite, >= 0 and <= 1 (G2 / G1 <= 1: no
// sample gains energy), directions reflected below the surface are absorbed (weight 0),
// and the mean weight — the directional albedo E(theta) — matches an independent
// deterministic quadrature of the BRDF's definition over microfacet normals,
//   E = integral D(h) G2(o, i(h)) (o.h) / (cos theta_o) dh   (i = reflect(o, h), i.z > 0),
// on a grid that inverts the CDF of D(h) cos theta_h. The loss 1 - E is single-scattering
// GGX's missing multiple scattering: bounded, and documented in docs/robustness.md (printed here).
TEST_CASE("sampling: white GGX furnace per direction, grazing to normal (no energy gain)", "[unit][sampling][hard]") {
    const double kPi = 3.14159265358979323846;
    float3 ns = make_float3(0, 0, 1);
    for (float alpha : {0.02f, 0.1f, 0.3f, 0.6f, 1.0f}) {
        MaterialData m{};
        m.albedo = make_float4(1.0f, 1.0f, 1.0f, 0.0f);
        m.alpha = alpha;
        m.kind = WP_MATERIAL_GLOSSY;
        for (double theta_deg : {0.0, 45.0, 80.0, 89.0, 89.99}) {
            double th = theta_deg * kPi / 180.0;
            float3 o = make_float3(float(std::sin(th)), 0.0f, float(std::cos(th)));  // towards the viewer
            float3 d = make_float3(-o.x, -o.y, -o.z);
            // Sampling.
            test::Rng rng(1234);
            const int n = 200000;
            double sum = 0, sum2 = 0;
            int bad = 0, gain = 0, below = 0;
            for (int i = 0; i < n; ++i) {
                float4 u = make_float4(rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
                float3 wo, weight;
                float pdf;
                int spec;
                double w = 0;
                if (wp_bsdf_sample_pdf(m, nullptr, d, ns, 1, u, &wo, &weight, &pdf, &spec)) {
                    if (!std::isfinite(weight.x) || !(weight.x >= 0.0f) || !std::isfinite(wo.z)) ++bad;
                    if (weight.x > 1.0f + 1e-5f) ++gain;
                    if (!(wo.z > 0.0f)) ++below;
                    w = weight.x;
                }
                sum += w;
                sum2 += w * w;
            }
            double e_s = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - e_s * e_s) / n);
            // Quadrature over h ~ D(h) cos(theta_h): tan^2 theta_h = a^2 t / (1 - t).
            // (at 89 degrees the cut-offs o.h > 0 and i.z > 0 cross the lobe: a finer grid;
            // at 89.99 degrees no grid resolves them: only the bounds are checked)
            const bool fine = theta_deg > 85.0;
            const int nt = fine ? 3000 : 1000, np = fine ? 3000 : 500;
            const bool compare = theta_deg < 89.5;
            double e_q = 0;
            for (int a = 0; compare && a < nt; ++a) {
                double t = (a + 0.5) / nt;
                double tan2 = double(alpha) * alpha * t / (1.0 - t);
                double ch = 1.0 / std::sqrt(1.0 + tan2), sh = std::sqrt(std::max(0.0, 1.0 - ch * ch));
                for (int b = 0; b < np; ++b) {
                    double phi = 2.0 * kPi * (b + 0.5) / np;
                    double hx = sh * std::cos(phi), hy = sh * std::sin(phi), hz = ch;
                    double oh = o.x * hx + o.y * hy + o.z * hz;
                    if (!(oh > 0.0)) continue;
                    double ix = 2 * oh * hx - o.x, iy = 2 * oh * hy - o.y, iz = 2 * oh * hz - o.z;
                    if (!(iz > 0.0)) continue;  // below the surface: absorbed
                    float g2 = wp_ggx_g2(o, make_float3(float(ix), float(iy), float(iz)), alpha);
                    // integrand / pdf = D G2 (o.h) / cos_o / (D cos_h)
                    e_q += g2 * oh / (o.z * ch);
                }
            }
            e_q /= double(nt) * np;
            INFO("alpha " << alpha << " theta " << theta_deg << ": E sampled " << e_s << " +- " << se
                          << ", quadrature " << e_q << "; " << below << " below, " << bad << " bad, " << gain
                          << " gains");
            CHECK(bad == 0);
            CHECK(gain == 0);
            CHECK(below == 0);
            CHECK(e_s <= 1.0 + 4 * se);
            if (compare) CHECK(std::abs(e_s - e_q) < 5 * se + 2e-3);
            std::printf("GGX white furnace: alpha %.2f theta %5.2f deg: E = %.4f (quadrature %s)\n", alpha,
                        theta_deg, e_s, compare ? std::to_string(e_q).c_str() : "-");
        }
    }
}
