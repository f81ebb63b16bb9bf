// test_materials_conductor.cpp — issue 14, item 1: conductors and the microfacet
// distributions (kernels/shared/microfacet.h, materials/conductor.h, materials/roughconductor.h).
// The shared code is compiled here as host C++ and checked against independent answers:
//   - D: ∫ D(h) h_z dω = 1 by quadrature in double (GGX, Beckmann; isotropic, anisotropic);
//   - Smith: G1 against the projected-area identity ∫ max(0, w·h) D(h) dω = w_z (1 + Λ(w))
//     integrated by brute force, and ∫ D_w(h) dω = 1 for the code's own VNDF density;
//   - visible-normal sampling: χ² of wp_mf_sample_vndf against D_w written here in double;
//   - the conductor Fresnel term against the textbook complex r_s / r_p (std::complex);
//   - roughconductor through bsdf.h: eval against a double implementation, sample weight =
//     f cos / pdf, reciprocity, χ² of the sampled directions against eval's density, the white
//     furnace (F ≡ 1) against a quadrature, its energy loss printed per α;
//   - conductor (smooth): weight = albedo × F;
//   - Mitsuba 3.9.1's roughconductor and conductor at fixed directions (an independent
//     implementation; scripts/mitsuba_conductor_values.py generated the tables);
//   - the OpenCL build (PoCL) draws the directions the host draws.
//
// χ² tests: bins with < 5 expected pooled; family-wise α = 0.01, Šidák-corrected over the
// kChi2Tests tests of this file (pbrt-v4 bsdfs_test.cpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/glm.hpp>

// The host copy of the shared code, compiled exactly as tests/test_sampling.cpp compiles it
// (the same switches, so the inline definitions agree across translation units).
#define WP_SAMPLING 3
#define WP_GLOSSY_MODEL 1
#include "shared/bsdf.h"
#include "shared/rng.h"

#include "cl/kernel.h"
#include "cl/program.h"
#include "chi2.h"
#include "support.h"

using namespace wp;
using glm::dvec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
// VNDF: 2 distributions × 4 roughnesses × 7 directions; roughconductor: 2 × 3 × 4; turned axes: 2 × 3.
constexpr int kChi2Tests = 56 + 24 + 6;
const double kAlpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / kChi2Tests);

// --- Independent double-precision formulas ----------------------------------------------
// Written from the textbook (θ, φ) forms (Walter et al. 2007 eqs. 25, 33; Heitz 2014,
// "Understanding the Masking-Shadowing Function", eqs. 72, 86 and section 5.3 for the
// anisotropic α(φ)), not from microfacet.h's Cartesian ones.
struct Dist {
    double ax, ay;
    bool beckmann;
};

double tan2_theta(dvec3 w) { return (w.x * w.x + w.y * w.y) / (w.z * w.z); }
// α² along w's azimuth: cos²φ α_x² + sin²φ α_y².
double alpha2_phi(const Dist& m, dvec3 w) {
    double r2 = w.x * w.x + w.y * w.y;
    if (r2 == 0.0) return m.ax * m.ay;  // any: multiplied by tan θ = 0
    return (w.x * w.x * m.ax * m.ax + w.y * w.y * m.ay * m.ay) / r2;
}
// ∑ over the azimuth of slope² / α²: tan²θ (cos²φ / α_x² + sin²φ / α_y²).
double e_phi(const Dist& m, dvec3 h) {
    double r2 = h.x * h.x + h.y * h.y;
    if (r2 == 0.0) return 0.0;
    double c2 = h.x * h.x / r2, s2 = h.y * h.y / r2;
    return tan2_theta(h) * (c2 / (m.ax * m.ax) + s2 / (m.ay * m.ay));
}

double ref_d(const Dist& m, dvec3 h) {
    if (h.z <= 0) return 0;
    double cos4 = h.z * h.z * h.z * h.z, e = e_phi(m, h);
    if (m.beckmann) return std::exp(-e) / (kPi * m.ax * m.ay * cos4);
    return 1.0 / (kPi * m.ax * m.ay * cos4 * (1 + e) * (1 + e));
}

double ref_lambda(const Dist& m, dvec3 w) {
    double t2 = tan2_theta(w) * alpha2_phi(m, w);  // (α tan θ)²
    if (!m.beckmann) return 0.5 * (-1 + std::sqrt(1 + t2));
    if (t2 == 0) return 0;
    double a = 1 / std::sqrt(t2);
    return 0.5 * (std::erf(a) - 1) + std::exp(-a * a) / (2 * a * std::sqrt(kPi));
}
double ref_g1(const Dist& m, dvec3 w) { return w.z > 0 ? 1 / (1 + ref_lambda(m, w)) : 0; }
double ref_g(const Dist& m, bool separable, dvec3 o, dvec3 i) {
    if (separable) return ref_g1(m, o) * ref_g1(m, i);
    return 1 / (1 + ref_lambda(m, o) + ref_lambda(m, i));
}
// D_w(h) = G1(w) max(0, w·h) D(h) / w_z.
double ref_vndf(const Dist& m, dvec3 w, dvec3 h) {
    return ref_g1(m, w) * std::max(0.0, glm::dot(w, h)) * ref_d(m, h) / w.z;
}

// Fresnel reflectance of the interface to a medium of relative index n = η + i k for
// unpolarised light (Born & Wolf; Hecht 4.6): Snell's law with a complex angle, r_s and r_p.
double ref_fresnel(double cos_i, double eta, double k) {
    using C = std::complex<double>;
    C n(eta, k);
    double sin_i2 = 1 - cos_i * cos_i;
    C cos_t = std::sqrt(C(1.0) - sin_i2 / (n * n));
    C rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    C rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    return 0.5 * (std::norm(rs) + std::norm(rp));
}

// --- Quadrature and bins over the upper hemisphere ----------------------------------------
// θ = atan(s tan(π u / 2)) for u in [0, 1): a lobe of width ~s gets resolved at any s.
double theta_of(double u, double s) { return std::atan(s * std::tan(0.5 * kPi * u)); }
double u_of(double theta, double s) { return 2 / kPi * std::atan(std::tan(theta) / s); }
double dtheta_du(double u, double s) {
    double t = std::tan(0.5 * kPi * u);
    return s * 0.5 * kPi * (1 + t * t) / (1 + s * s * t * t);
}
dvec3 dir(double theta, double phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// ∫ f(ω) dω over z > 0, midpoint rule in (u, φ).
template <typename F>
double hemisphere(F f, double s, int nu = 1000, int nphi = 1000) {
    double sum = 0, du = 1.0 / nu, dp = 2 * kPi / nphi;
    for (int i = 0; i < nu; ++i) {
        double u = (i + 0.5) * du, th = theta_of(u, s), jac = std::sin(th) * dtheta_du(u, s);
        double row = 0;
        for (int j = 0; j < nphi; ++j) row += f(dir(th, (j + 0.5) * dp));
        sum += row * jac;
    }
    return sum * du * dp;
}

// Bin probabilities of a density over (u, φ) bins of the hemisphere.
template <typename F>
std::vector<double> hemisphere_bins(F pdf, double s, int nu, int nphi, int sub) {
    std::vector<double> p(std::size_t(nu) * nphi, 0.0);
    double du = 1.0 / nu / sub, dp = 2 * kPi / nphi / sub;
    for (int i = 0; i < nu; ++i)
        for (int a = 0; a < sub; ++a) {
            double u = (i * sub + a + 0.5) * du, th = theta_of(u, s);
            double jac = std::sin(th) * dtheta_du(u, s) * du * dp;
            for (int j = 0; j < nphi; ++j)
                for (int b = 0; b < sub; ++b) p[i * nphi + j] += pdf(dir(th, (j * sub + b + 0.5) * dp)) * jac;
        }
    return p;
}
int hemisphere_bin(dvec3 w, double s, int nu, int nphi) {
    double th = std::acos(std::clamp(w.z, -1.0, 1.0));
    double ph = std::atan2(w.y, w.x);
    if (ph < 0) ph += 2 * kPi;
    int i = std::clamp(int(u_of(th, s) * nu), 0, nu - 1);
    int j = std::clamp(int(ph / (2 * kPi) * nphi), 0, nphi - 1);
    return i * nphi + j;
}

float3 f3(dvec3 v) { return make_float3(float(v.x), float(v.y), float(v.z)); }
dvec3 d3(float3 v) { return {v.x, v.y, v.z}; }

Microfacet microfacet(const Dist& m, bool separable = false) {
    Microfacet mf;
    mf.ax = float(m.ax);
    mf.ay = float(m.ay);
    mf.beckmann = m.beckmann ? 1 : 0;
    mf.separable = separable ? 1 : 0;
    mf.c = 1.0f;  // axes along the local frame's x and y
    mf.s = 0.0f;
    return mf;
}

MaterialData conductor(int kind, glm::vec3 albedo, glm::vec3 eta, glm::vec3 k, float ax = 0, float ay = 0,
                       int flags = 0) {
    MaterialData m{};
    m.albedo = make_float4(albedo.x, albedo.y, albedo.z, 0);
    m.kind = kind;
    m.alpha = ax;
    m.alpha_v = ay;
    m.eta = make_float4(eta.x, eta.y, eta.z, 0);
    m.k = make_float4(k.x, k.y, k.z, 0);
    m.flags = flags;
    m.table = -1;
    return m;
}

// Named metals: mitsuba_loader.cpp's RGB table (Tungsten's fits), a few of them.
struct Metal {
    const char* name;
    glm::vec3 eta, k;
};
const Metal kMetals[] = {
    {"Ag", {0.1552646f, 0.1167233f, 0.1383807f}, {4.8283433f, 3.1222459f, 2.1469504f}},
    {"Al", {1.6574600f, 0.8803690f, 0.5212287f}, {9.2238692f, 6.2695232f, 4.8370012f}},
    {"Au", {0.1431190f, 0.3749570f, 1.4424786f}, {3.9831604f, 2.3857207f, 1.6032153f}},
    {"Cr", {4.3696829f, 2.9167025f, 1.6547005f}, {5.2064338f, 4.2313645f, 3.7549468f}},
    {"Cu", {0.2004377f, 0.9240334f, 1.1022120f}, {3.9129485f, 2.4528477f, 2.1421880f}},
    {"K", {0.0640493f, 0.0464101f, 0.0381842f}, {2.1042156f, 1.3489364f, 0.9132114f}},
    {"W", {4.3707030f, 3.3002972f, 2.9982667f}, {3.5006779f, 2.6048653f, 2.2731931f}},
};

const Dist kDists[] = {
    {0.05, 0.05, false}, {0.3, 0.3, false}, {1.0, 1.0, false}, {1.8, 1.8, false}, {0.1, 0.5, false},
    {0.05, 0.05, true},  {0.3, 0.3, true},  {1.0, 1.0, true},  {1.8, 1.8, true},  {0.1, 0.5, true},
};

std::string name(const Dist& m) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s (%.2f, %.2f)", m.beckmann ? "Beckmann" : "GGX", m.ax, m.ay);
    return buf;
}

}  // namespace

// ∫ D(h) cos θ_h dω = 1: the projected microfacet area is the macro-surface's (Walter et al.
// 2007, eq. 4), for the code's D and for the double formulas above.
TEST_CASE("conductor: microfacet D is normalised (quadrature)", "[unit][conductor]") {
    for (const Dist& m : kDists) {
        INFO(name(m));
        Microfacet mf = microfacet(m);
        const double s = std::min(m.ax, m.ay);
        double code = hemisphere([&](dvec3 h) { return double(wp_mf_d(mf, f3(h))) * h.z; }, s);
        double refd = hemisphere([&](dvec3 h) { return ref_d(m, h) * h.z; }, s);
        CHECK(code == Approx(1.0).epsilon(2e-5));
        CHECK(refd == Approx(1.0).epsilon(1e-5));
        // And pointwise: the code's D is the textbook formula.
        test::Rng rng(7);
        double worst = 0;
        for (int i = 0; i < 2000; ++i) {
            dvec3 h = glm::normalize(dvec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.05f, 1)));
            h = d3(f3(h));
            double r = ref_d(m, h), c = wp_mf_d(mf, f3(h));
            if (r < 1e-30) {  // below float's range: Beckmann's far tail
                CHECK(c < 1e-30);
                continue;
            }
            worst = std::max(worst, std::abs(c - r) / r);
        }
        INFO("largest relative difference " << worst);
        CHECK(worst < 2e-5);
    }
}

// Smith: G1(w) = w_z / ∫ max(0, w·h) D(h) dω (the projected-area identity,
// Heitz 2014 eq. 24, with Smith's Λ: ∫ max(0, w·h) D = w_z (1 + Λ(w))), brute force in
// double; and the code's visible-normal density integrates to 1 (which ties its G1 to its D).
TEST_CASE("conductor: Smith G1 and the visible-normal density (quadrature)", "[unit][conductor]") {
    for (const Dist& m : kDists) {
        Microfacet mf = microfacet(m);
        const double s = std::min(m.ax, m.ay);
        for (double theta_deg : {0.0, 30.0, 60.0, 80.0, 85.0, 89.0}) {
            for (double phi_deg : {0.0, 35.0, 90.0}) {
                if (m.ax == m.ay && phi_deg != 35.0) continue;
                dvec3 w = d3(f3(dir(theta_deg * kPi / 180, phi_deg * kPi / 180)));
                INFO(name(m) << " theta " << theta_deg << " phi " << phi_deg);
                double proj = hemisphere([&](dvec3 h) { return std::max(0.0, glm::dot(w, h)) * ref_d(m, h); }, s, 600, 600);
                double g1_brute = w.z / proj;
                CHECK(ref_g1(m, w) == Approx(g1_brute).epsilon(1e-5));
                CHECK(double(wp_mf_g1(mf, f3(w))) == Approx(g1_brute).epsilon(2e-5));
                CHECK(double(wp_mf_lambda(mf, f3(w))) == Approx(ref_lambda(m, w)).epsilon(2e-5).margin(1e-6));
                double vndf = hemisphere([&](dvec3 h) { return double(wp_mf_pdf_vndf(mf, f3(w), f3(h))); }, s, 600, 600);
                CHECK(vndf == Approx(1.0).epsilon(3e-5));
            }
        }
    }
}

// wp_mf_sample_vndf draws h with density D_w(h) = G1(w) max(0, w·h) D(h) / w_z: χ² against
// that density written in double, normal to grazing incidence (θ up to 89°).
TEST_CASE("conductor: visible-normal sampling of GGX and Beckmann (chi2)", "[unit][stat][conductor]") {
    const int n = 500000, nu = 32, nphi = 48;
    int tests = 0;
    double p_min = 1;
    for (const Dist& m : {Dist{0.05, 0.05, false}, Dist{0.3, 0.3, false}, Dist{1.8, 1.8, false},
                          Dist{0.1, 0.5, false}, Dist{0.05, 0.05, true}, Dist{0.3, 0.3, true},
                          Dist{1.8, 1.8, true}, Dist{0.1, 0.5, true}}) {
        Microfacet mf = microfacet(m);
        const double s = std::min(m.ax, m.ay);
        for (double theta_deg : {0.0, 0.5, 3.0, 45.0, 75.0, 85.0, 89.0}) {
            // Azimuth 34°: the edge w·h = 0 (near φ = 124° and 304° at grazing) runs through the
            // middle of the 7.5° bins, so no bin holds only a sliver that its quadrature misses.
            dvec3 w = d3(f3(dir(theta_deg * kPi / 180, 34 * kPi / 180)));
            auto prob = hemisphere_bins([&](dvec3 h) { return ref_vndf(m, w, h); }, s, nu, nphi, 12);
            std::vector<double> obs(prob.size(), 0.0), expct(prob.size());
            for (std::size_t i = 0; i < prob.size(); ++i) expct[i] = prob[i] * n;
            test::Rng rng(1000 + tests);
            int bad = 0;
            for (int i = 0; i < n; ++i) {
                float3 h = wp_mf_sample_vndf(mf, f3(w), rng.uniform(), rng.uniform());
                if (!(std::abs(dot(h, h) - 1.0f) < 1e-5f) || !(h.z > 0.0f)) {
                    ++bad;
                    continue;
                }
                obs[hemisphere_bin(d3(h), s, nu, nphi)] += 1;
            }
            int dof = 0;
            double p = test::chi2_pvalue(obs, expct, &dof);
            INFO(name(m) << " theta " << theta_deg << ": chi2 p-value " << p << " with " << dof
                         << " degrees of freedom, alpha " << kAlpha << "; " << bad << " bad");
            CHECK(bad == 0);
            CHECK(dof > 20);
            CHECK(p > kAlpha);
            p_min = std::min(p_min, p);
            ++tests;
        }
    }
    CHECK(tests == 56);
    std::printf("VNDF chi2: %d tests, smallest p-value %.3g (alpha %.3g)\n", tests, p_min, kAlpha);
}

// Anisotropic axes turned by the shading frame (microfacet.h: α_x along (c, s) of the local
// frame, which shade sets from dp/du): D and Λ of the turned distribution at v equal the
// unturned one's at v turned back by φ (a rotation written here in double), a quarter turn
// swaps α_x and α_y, and visible normals drawn from the turned distribution follow the turned
// reference density (χ²).
TEST_CASE("conductor: anisotropic axes along the shading frame's tangent", "[unit][stat][conductor]") {
    for (bool beckmann : {false, true}) {
        const Dist m{0.1, 0.5, beckmann};
        for (double phi_deg : {90.0, 30.0, -117.0}) {
            const double phi = phi_deg * kPi / 180;
            Microfacet turned = microfacet(m);
            turned.c = float(std::cos(phi));
            turned.s = float(std::sin(phi));
            Microfacet plain = microfacet(m);
            Microfacet swapped = microfacet(Dist{m.ay, m.ax, beckmann});
            auto back = [&](dvec3 v) {  // v in the frame whose x runs along φ
                return dvec3(std::cos(phi) * v.x + std::sin(phi) * v.y,
                             -std::sin(phi) * v.x + std::cos(phi) * v.y, v.z);
            };
            test::Rng rng(77);
            double worst = 0;
            for (int i = 0; i < 2000; ++i) {
                dvec3 v = dir(std::acos(rng.uniform()) * 0.999, 2 * kPi * rng.uniform());
                double d_t = wp_mf_d(turned, f3(v)), d_p = wp_mf_d(plain, f3(back(v)));
                double l_t = wp_mf_lambda(turned, f3(v)), l_p = wp_mf_lambda(plain, f3(back(v)));
                worst = std::max({worst, std::abs(d_t - d_p) / std::max(d_p, 1e-12),
                                  std::abs(l_t - l_p) / std::max(l_p, 1e-6)});
                if (phi_deg == 90.0)
                    CHECK(wp_mf_d(turned, f3(v)) == Approx(wp_mf_d(swapped, f3(v))).epsilon(1e-5));
            }
            INFO((beckmann ? "Beckmann" : "GGX") << " turned " << phi_deg << " deg: worst " << worst);
            // The two sides see differently rounded float directions; Beckmann's exp(−e) turns
            // an input rounding into a relative error of about e · 2^-24 (e up to ~10^4 here).
            CHECK(worst < (beckmann ? 2e-3 : 1e-4));
            // χ² of the turned sampler against the reference density turned
            const int n = 300000, nu = 32, nphi = 48;
            dvec3 w = d3(f3(dir(60 * kPi / 180, 34 * kPi / 180)));
            auto prob = hemisphere_bins([&](dvec3 h) { return ref_vndf(m, back(w), back(h)); },
                                        std::min(m.ax, m.ay), nu, nphi, 12);
            std::vector<double> obs(prob.size(), 0.0), expct(prob.size());
            for (std::size_t i = 0; i < prob.size(); ++i) expct[i] = prob[i] * n;
            for (int i = 0; i < n; ++i) {
                float3 h = wp_mf_sample_vndf(turned, f3(w), rng.uniform(), rng.uniform());
                if (h.z > 0.0f) obs[hemisphere_bin(d3(h), std::min(m.ax, m.ay), nu, nphi)] += 1;
            }
            int dof = 0;
            double p = test::chi2_pvalue(obs, expct, &dof);
            INFO("chi2 p-value " << p << " with " << dof << " degrees of freedom");
            CHECK(dof > 20);
            CHECK(p > kAlpha);
        }
    }
}

// The conductor Fresnel term against the complex-arithmetic r_s / r_p in double, over angles
// and indices: the named metals, F ≡ 1 for (η, k) = (0, 1) (Mitsuba's "none"), a dielectric
// (k = 0, η > 1) and no interface (η = 1, k = 0: F(normal) = 0).
TEST_CASE("conductor: Fresnel of a complex index against std::complex", "[unit][conductor]") {
    std::vector<std::pair<double, double>> indices = {{0.0, 1.0}, {1.5, 0.0}, {1.0, 0.0}, {0.2, 3.0},  {3.0, 0.5},
                                                      {0.05, 10.0}, {1.0, 0.1}, {2.5, 0.0}, {0.5, 0.0}, {0.01, 0.01}};
    for (const Metal& metal : kMetals)
        for (int c = 0; c < 3; ++c) indices.push_back({metal.eta[c], metal.k[c]});
    double worst = 0;
    for (auto [eta, k] : indices) {
        for (int i = 0; i <= 400; ++i) {
            float cos_i = float(i / 400.0);
            double r = ref_fresnel(cos_i, eta, k);
            float3 f = wp_fresnel_conductor(cos_i, make_float3(float(eta), float(eta), float(eta)),
                                            make_float3(float(k), float(k), float(k)));
            INFO("eta " << eta << " k " << k << " cos " << cos_i << ": " << f.x << " vs " << r);
            CHECK(f.x == f.y);
            if (std::isnan(r)) {  // 0/0: no interface (η = 1, k = 0) at grazing
                CHECK((f.x >= 0.0f && f.x <= 1.0f));
                continue;
            }
            CHECK(std::abs(f.x - r) < 5e-6 * r + 2e-7);
            worst = std::max(worst, std::abs(f.x - r));
        }
    }
    // F ≡ 1 for (0, 1), exactly; F(1) = 0 for no interface.
    for (int i = 0; i <= 100; ++i)
        CHECK(wp_fresnel_conductor1(float(i / 100.0), 0.0f, 1.0f) == 1.0f);
    CHECK(wp_fresnel_conductor1(1.0f, 1.0f, 0.0f) == 0.0f);
    std::printf("conductor Fresnel: largest |F - F_complex| = %.2g over %zu indices\n", worst, indices.size());
}

// The smooth conductor reflects in the mirror direction with weight albedo × F(cos θ).
TEST_CASE("conductor: smooth conductor weight is albedo times F", "[unit][conductor]") {
    test::Rng rng(11);
    float3 ns = make_float3(0, 0, 1);
    for (const Metal& metal : kMetals) {
        MaterialData m = conductor(WP_MATERIAL_CONDUCTOR, {0.9f, 0.7f, 0.5f}, metal.eta, metal.k);
        for (int i = 0; i < 200; ++i) {
            glm::vec3 o = test::Rng(i).unit_vector();
            o.z = std::abs(o.z);
            float3 d = make_float3(-o.x, -o.y, -o.z);
            float4 u = make_float4(rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
            float3 wo, weight = make_float3(0, 0, 0);
            float pdf = -1;
            int spec = 0;
            REQUIRE(wp_bsdf_sample_pdf(m, nullptr, d, ns, 1, u, &wo, &weight, &pdf, &spec) == 1);
            CHECK(spec == 1);
            CHECK(pdf == 0.0f);
            CHECK(wo.x == Approx(-o.x).margin(1e-6));  // the mirror direction of d = -o
            CHECK(wo.y == Approx(-o.y).margin(1e-6));
            CHECK(wo.z == Approx(o.z).margin(1e-6));
            const float tint[3] = {0.9f, 0.7f, 0.5f};
            const float got[3] = {weight.x, weight.y, weight.z};
            for (int c = 0; c < 3; ++c) {
                double r = tint[c] * ref_fresnel(o.z, metal.eta[c], metal.k[c]);
                INFO(metal.name << " channel " << c << " cos " << o.z);
                CHECK(std::abs(got[c] - r) < 2e-6);
            }
            float epdf = -1;
            float3 f = wp_bsdf_eval(m, nullptr, d, ns, 1, wo, &epdf);
            CHECK(f.x == 0.0f);
            CHECK(epdf == 0.0f);
        }
    }
}

namespace {

// The rough conductor's f cos θ_i in double: albedo F(o·h) D(h) G(o, i) / (4 cos θ_o).
glm::dvec3 ref_rough_fcos(const Dist& m, bool separable, glm::vec3 albedo, glm::vec3 eta, glm::vec3 k,
                          dvec3 o, dvec3 i) {
    if (o.z <= 0 || i.z <= 0) return {};
    dvec3 h = glm::normalize(o + i);
    double s = ref_d(m, h) * ref_g(m, separable, o, i) / (4 * o.z);
    glm::dvec3 r;
    for (int c = 0; c < 3; ++c) r[c] = albedo[c] * ref_fresnel(glm::dot(o, h), eta[c], k[c]) * s;
    return r;
}

int flags_of(const Dist& m, bool separable) {
    return (m.beckmann ? WP_MF_BECKMANN : 0) | (separable ? WP_MF_SEPARABLE_G : 0);
}

}  // namespace

// Through bsdf.h: eval = the double formula; the density eval reports is G1(o) D(h) / (4 cos θ_o);
// a sample's weight is f cos / pdf at its direction and its pdf is eval's; f is reciprocal.
TEST_CASE("conductor: rough conductor eval and sample weight and reciprocity", "[unit][conductor]") {
    const Metal& cu = kMetals[4];
    float3 ns = make_float3(0, 0, 1);
    const glm::vec3 tint{0.9f, 0.7f, 0.5f};
    for (const Dist& m : kDists)
        for (bool separable : {false, true}) {
            INFO(name(m) << (separable ? " separable" : " height-correlated"));
            MaterialData mat = conductor(WP_MATERIAL_ROUGH_CONDUCTOR, tint, cu.eta, cu.k, float(m.ax),
                                         float(m.ay), flags_of(m, separable));
            test::Rng rng(99);
            int bad_eval = 0, bad_pdf = 0, bad_weight = 0, bad_recip = 0, samples = 0;
            for (int t = 0; t < 4000; ++t) {
                glm::vec3 og = rng.unit_vector(), ig = rng.unit_vector();
                og.z = std::max(std::abs(og.z), 0.02f);
                ig.z = std::max(std::abs(ig.z), 0.02f);
                float3 o = normalize(make_float3(og.x, og.y, og.z)), i = normalize(make_float3(ig.x, ig.y, ig.z));
                float3 d = make_float3(-o.x, -o.y, -o.z);
                // eval against the double formula and the reference density.
                float pdf = 0;
                float3 f = wp_bsdf_eval(mat, nullptr, d, ns, 1, i, &pdf);
                dvec3 r = ref_rough_fcos(m, separable, tint, cu.eta, cu.k, d3(o), d3(i));
                double rp = ref_g1(m, d3(o)) * ref_d(m, glm::normalize(d3(o) + d3(i))) / (4 * o.z);
                bad_eval += std::abs(f.x - r.x) > 1e-4 * r.x + 1e-30 || std::abs(f.z - r.z) > 1e-4 * r.z + 1e-30;
                bad_pdf += std::abs(pdf - rp) > 1e-4 * rp + 1e-30;
                // reciprocity: f(o, i) = f(i, o), f = f cos / cos θ_i.
                float pdf2 = 0;
                float3 fr = wp_bsdf_eval(mat, nullptr, make_float3(-i.x, -i.y, -i.z), ns, 1, o, &pdf2);
                bad_recip += std::abs(f.x / i.z - fr.x / o.z) > 1e-4 * (f.x / i.z) + 1e-30;
                // a sample from o: weight = f cos / pdf, pdf = eval's.
                float4 u = make_float4(rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
                float3 wo, weight = make_float3(0, 0, 0);
                float spdf = 0;
                int spec = 0;
                if (wp_bsdf_sample_pdf(mat, nullptr, d, ns, 1, u, &wo, &weight, &spdf, &spec)) {
                    ++samples;
                    float epdf = 0;
                    float3 ef = wp_bsdf_eval(mat, nullptr, d, ns, 1, wo, &epdf);
                    bad_weight += spec != 0 || !(spdf > 0.0f) || std::abs(spdf - epdf) > 1e-3f * epdf ||
                                  std::abs(weight.x - ef.x / epdf) > 1e-3f * weight.x + 1e-7f ||
                                  std::abs(weight.z - ef.z / epdf) > 1e-3f * weight.z + 1e-7f;
                }
            }
            INFO(bad_eval << " eval, " << bad_pdf << " pdf, " << bad_weight << " weight, " << bad_recip
                          << " reciprocity mismatches; " << samples << " samples");
            CHECK(bad_eval == 0);
            CHECK(bad_pdf == 0);
            CHECK(bad_weight == 0);
            CHECK(bad_recip == 0);
            CHECK(samples > 1500);  // the rest reflected below the surface (α up to 1.8)
        }
}

// The directions wp_bsdf_sample_pdf draws for a rough conductor follow the density
// wp_bsdf_eval reports (whose formula the test above checks), plus the absorbed part
// (reflections below the surface) in one extra bin.
TEST_CASE("conductor: rough conductor samples follow eval's density (chi2)", "[unit][stat][conductor]") {
    const int n = 500000, nt = 45, np = 90, sub = 6;
    const Metal& au = kMetals[2];
    float3 ns = make_float3(0, 0, 1);
    int tests = 0;
    double p_min = 1;
    for (const Dist& m : {Dist{0.2, 0.2, false}, Dist{0.1, 0.4, false}, Dist{0.8, 0.8, false},
                          Dist{0.2, 0.2, true}, Dist{0.1, 0.4, true}, Dist{0.8, 0.8, true}}) {
        MaterialData mat = conductor(WP_MATERIAL_ROUGH_CONDUCTOR, {1, 1, 1}, au.eta, au.k, float(m.ax),
                                     float(m.ay), flags_of(m, tests % 2 == 1));
        for (double theta_deg : {0.0, 50.0, 80.0, 88.0}) {
            dvec3 o = d3(f3(dir(theta_deg * kPi / 180, 20 * kPi / 180)));
            float3 d = f3(-o);
            // Expected: eval's density over (θ, φ) bins of the upper hemisphere.
            std::vector<double> expct(nt * np + 1, 0.0), obs(nt * np + 1, 0.0);
            double dt = 0.5 * kPi / nt / sub, dp = 2 * kPi / np / sub, above = 0;
            for (int a = 0; a < nt * sub; ++a) {
                double th = (a + 0.5) * dt;
                for (int b = 0; b < np * sub; ++b) {
                    float pdf = 0;
                    wp_bsdf_eval(mat, nullptr, d, ns, 1, f3(dir(th, (b + 0.5) * dp)), &pdf);
                    double p = pdf * std::sin(th) * dt * dp;
                    expct[(a / sub) * np + b / sub] += p * n;
                    above += p;
                }
            }
            expct[nt * np] = std::max(0.0, 1.0 - above) * n;
            test::Rng rng(500 + tests);
            for (int i = 0; i < n; ++i) {
                float4 u = make_float4(rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
                float3 wo, weight = make_float3(0, 0, 0);
                float pdf;
                int spec;
                if (!wp_bsdf_sample_pdf(mat, nullptr, d, ns, 1, u, &wo, &weight, &pdf, &spec)) {
                    obs[nt * np] += 1;
                    continue;
                }
                double th = std::acos(std::clamp(double(wo.z), -1.0, 1.0)), ph = std::atan2(wo.y, wo.x);
                if (ph < 0) ph += 2 * kPi;
                int bi = std::min(nt - 1, int(th / (0.5 * kPi) * nt)), bj = std::min(np - 1, int(ph / (2 * kPi) * np));
                obs[bi * np + bj] += 1;
            }
            int dof = 0;
            double p = test::chi2_pvalue(obs, expct, &dof);
            INFO(name(m) << " theta " << theta_deg << ": absorbed " << obs[nt * np] << " expected "
                         << expct[nt * np] << "; chi2 p-value " << p << " with " << dof
                         << " degrees of freedom, alpha " << kAlpha);
            CHECK(dof > 20);
            CHECK(p > kAlpha);
            p_min = std::min(p_min, p);
            ++tests;
        }
    }
    CHECK(tests == 24);
    std::printf("rough conductor chi2: %d tests, smallest p-value %.3g (alpha %.3g)\n", tests, p_min, kAlpha);
}

// White furnace with F ≡ 1 (η = 0, k = 1, albedo 1): the directional albedo E(θ_o) = ∫ f cos dω
// by sampling (mean weight) agrees with a deterministic quadrature of the double formulas,
//   E = ∫ D(h) G(o, i(h)) (o·h) / cos θ_o dω_h   (i = reflect(o, h), i_z > 0),
// never exceeds 1 (no sample gains energy), and separable G loses more than height-correlated
// G. 1 − E is single scattering's missing multiple scattering: printed per α (docs/materials.md).
TEST_CASE("conductor: white furnace of the rough conductor (F = 1) and its energy loss per alpha",
          "[unit][conductor]") {
    float3 ns = make_float3(0, 0, 1);
    for (bool beckmann : {false, true})
        for (double alpha : {0.05, 0.1, 0.3, 0.6, 1.0, 1.5, 2.0}) {
            Dist m{alpha, alpha, beckmann};
            std::string line;
            for (double theta_deg : {0.0, 30.0, 60.0, 75.0, 85.0, 89.0}) {
                dvec3 o = d3(f3(dir(theta_deg * kPi / 180, 0.0)));
                double e[2];
                for (bool separable : {false, true}) {
                    INFO(name(m) << (separable ? " separable" : " height-correlated") << " theta " << theta_deg);
                    MaterialData mat = conductor(WP_MATERIAL_ROUGH_CONDUCTOR, {1, 1, 1}, {0, 0, 0}, {1, 1, 1},
                                                 float(alpha), float(alpha), flags_of(m, separable));
                    test::Rng rng(77);
                    const int n = 50000;
                    double sum = 0, sum2 = 0;
                    int bad = 0, gain = 0;
                    for (int i = 0; i < n; ++i) {
                        float4 u = make_float4(rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
                        float3 wo, weight = make_float3(0, 0, 0);
                        float pdf;
                        int spec;
                        double w = 0;
                        if (wp_bsdf_sample_pdf(mat, nullptr, f3(-o), ns, 1, u, &wo, &weight, &pdf, &spec)) {
                            if (!std::isfinite(weight.x) || !(weight.x >= 0.0f) || !(wo.z > 0.0f) ||
                                weight.x != weight.y || weight.x != weight.z)
                                ++bad;
                            gain += weight.x > 1.0f + 1e-5f;
                            w = weight.x;
                        }
                        sum += w;
                        sum2 += w * w;
                    }
                    double e_s = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - e_s * e_s) / n);
                    double e_q = hemisphere(
                        [&](dvec3 h) {
                            double oh = glm::dot(o, h);
                            if (!(oh > 0)) return 0.0;
                            dvec3 i = 2 * oh * h - o;
                            if (!(i.z > 0)) return 0.0;
                            return ref_d(m, h) * ref_g(m, separable, o, i) * oh / o.z;
                        },
                        alpha, 800, 400);
                    INFO("E sampled " << e_s << " +- " << se << ", quadrature " << e_q << "; " << bad << " bad, "
                                      << gain << " gains");
                    CHECK(bad == 0);
                    CHECK(gain == 0);
                    CHECK(e_q <= 1.0 + 1e-4);
                    CHECK(std::abs(e_s - e_q) < 5 * se + 2e-3);
                    e[separable] = e_q;
                }
                CHECK(e[1] <= e[0] + 1e-6);
                char buf[64];
                std::snprintf(buf, sizeof buf, " %2.0f°: %.4f/%.4f", theta_deg, e[0], e[1]);
                line += buf;
            }
            std::printf("rough conductor white furnace %-8s alpha %.2f E(theta) height-correlated/separable:%s\n",
                        beckmann ? "Beckmann" : "GGX", alpha, line.c_str());
        }
}

// Extreme inputs (α from 1e-4 to 2, directions down to cos θ = 1e-30, random numbers 0 and
// 1 − 2^-24): every sample, weight, density and f cos is finite and non-negative, sampled
// directions are unit and above the surface, and the microfacet functions give no NaN.
// The inline replacements for library calls on the Beckmann path (microfacet.h; wp_exp in
// sampling.h) against double precision (std::erf, std::log, std::atan2) over dense sweeps;
// the bounds are the ones the comments in those headers state.
TEST_CASE("conductor: inline erf log exp atan2 erfinv against double", "[unit][conductor]") {
    double erf_abs = 0, erf_rel = 0;
    for (long i = -2000000; i <= 2000000; ++i) {  // [-6, 6] in steps of 3e-6
        float x = float(6.0 * double(i) / 2000000.0);
        double r = std::erf(double(x)), e = std::abs(double(wp_erf(x)) - r);
        erf_abs = std::max(erf_abs, e);
        if (r != 0.0) erf_rel = std::max(erf_rel, e / std::abs(r));
    }
    bool odd = true;
    for (float x = 1e-37f; x < 1.0f; x *= 1.0001f) {  // small arguments: relative error
        double r = std::erf(double(x));
        erf_rel = std::max(erf_rel, std::abs(double(wp_erf(x)) - r) / r);
        odd = odd && wp_erf(-x) == -wp_erf(x);
    }
    CHECK(odd);
    INFO("wp_erf: max abs " << erf_abs << ", max rel " << erf_rel);
    CHECK(erf_abs < 1.3e-7);
    CHECK(erf_rel < 1.6e-7);
    CHECK(wp_erf(0.0f) == 0.0f);
    CHECK(wp_erf(INFINITY) == 1.0f);
    CHECK(wp_erf(-INFINITY) == -1.0f);
    CHECK(std::isnan(wp_erf(NAN)));

    double log_rel = 0;  // every 61st float in [2^-24, 4], and 1 ± a few ulp
    const uint32_t lo = as_uint(std::ldexp(1.0f, -24)), hi = as_uint(4.0f);
    for (uint64_t b = lo; b <= hi; b += 61) {
        float x = as_float(uint32_t(b));
        double r = std::log(double(x));
        double e = std::abs(double(wp_log_normal(x)) - r);
        log_rel = std::max(log_rel, r == 0.0 ? e : e / std::abs(r));
    }
    for (float x = 0.999f; x < 1.001f; x = std::nextafter(x, 2.0f)) {
        double r = std::log(double(x));
        double e = std::abs(double(wp_log_normal(x)) - r);
        log_rel = std::max(log_rel, r == 0.0 ? e : e / std::abs(r));
    }
    INFO("wp_log_normal: max rel " << log_rel);
    CHECK(log_rel < 1e-7);
    CHECK(wp_log_normal(1.0f) == 0.0f);

    // e^x: every 17th float in [-87.3, 88.7] (normal results), relative error; the denormal
    // range to 1 ulp of the smallest denormal; the ends.
    double exp_rel = 0, exp_denormal = 0;
    for (float x = -87.3f; x <= 88.7f; x = std::nextafter(x, 100.0f)) {
        double r = std::exp(double(x));
        exp_rel = std::max(exp_rel, std::abs(double(wp_exp(x)) - r) / r);
        for (int k = 0; k < 16 && x <= 88.7f; ++k) x = std::nextafter(x, 100.0f);
    }
    for (float x = -104.0f; x < -87.3f; x += 1e-4f) {
        // Below the normal range: the polynomial's error plus one rounding to a denormal
        // (half of 2^-149), in units of 2^-149.
        double r = std::exp(double(x));
        double e = (std::abs(double(wp_exp(x)) - r) - 2e-7 * r) / std::ldexp(1.0, -149);
        exp_denormal = std::max(exp_denormal, e);
    }
    INFO("wp_exp: max rel " << exp_rel << ", denormal range: max error beyond the polynomial's "
                            << exp_denormal << " x 2^-149");
    CHECK(exp_rel < 2e-7);
    CHECK(exp_denormal <= 0.5);
    CHECK(wp_exp(0.0f) == 1.0f);
    CHECK(wp_exp(-104.5f) == 0.0f);
    CHECK(wp_exp(-INFINITY) == 0.0f);
    CHECK(std::isinf(wp_exp(88.8f)));
    CHECK(std::isinf(wp_exp(INFINITY)));
    CHECK(std::isnan(wp_exp(NAN)));

    double atan_abs = 0;  // the first quadrant, (y, x) = (sin t, cos t) and scaled
    for (int i = 0; i <= 1000000; ++i) {
        double t = 0.5 * kPi * i / 1000000.0;
        for (float scale : {1.0f, 1e-20f, 3e20f}) {
            float y = float(std::sin(t)) * scale, x = float(std::cos(t)) * scale;
            atan_abs = std::max(atan_abs, std::abs(double(wp_atan2_guess(y, x)) - std::atan2(double(y), double(x))));
        }
    }
    INFO("wp_atan2_guess: max abs " << atan_abs);
    CHECK(atan_abs < 2e-6);
    CHECK(wp_atan2_guess(0.0f, 0.0f) == 0.0f);

    // erf⁻¹ (Giles' polynomial, now on wp_log_normal): one Newton step in double from the
    // code's answer gives the reference; relative error as Giles states (~4e-7).
    double erfinv_rel = 0;
    for (long i = -999999; i <= 999999; ++i) {
        float x = float(double(i) / 1000000.0);
        double y = wp_erfinv(x);
        double ref = y;
        for (int k = 0; k < 3; ++k) ref -= (std::erf(ref) - double(x)) / (2.0 / std::sqrt(kPi) * std::exp(-ref * ref));
        if (ref != 0.0) erfinv_rel = std::max(erfinv_rel, std::abs(y - ref) / std::abs(ref));
    }
    INFO("wp_erfinv: max rel " << erfinv_rel);
    CHECK(erfinv_rel < 1e-6);
}

TEST_CASE("conductor: no NaN or negative value at extreme inputs", "[unit][conductor]") {
    const float alphas[] = {1e-4f, 1e-3f, 0.05f, 0.5f, 1.0f, 2.0f};
    const float zs[] = {1.0f, 0.9999999f, 0.99999f, 0.5f, 1e-2f, 1e-4f, 1e-6f, 1e-8f, 1e-20f, 1e-30f};
    const float us[] = {0.0f, 1e-7f, 1e-3f, 0.5f, 0.999f, 0.99999994f};
    const Metal& cu = kMetals[4];
    float3 ns = make_float3(0, 0, 1);
    int bad = 0, total = 0;
    for (int flags = 0; flags < 4; ++flags)
        for (float ax : alphas)
            for (float ay : alphas)
                for (float z : zs) {
                    float s = std::sqrt(std::max(0.0f, 1 - z * z));
                    float3 o = make_float3(s * 0.6f, s * 0.8f, z), d = make_float3(-o.x, -o.y, -o.z);
                    float3 wi = normalize(make_float3(0.3f, -0.2f, z));
                    MaterialData m = conductor(WP_MATERIAL_ROUGH_CONDUCTOR, {1, 1, 1}, cu.eta, cu.k, ax, ay, flags);
                    Microfacet mf = wp_microfacet(m);
                    for (float u1 : us)
                        for (float u2 : us) {
                            ++total;
                            float3 h = wp_mf_sample_vndf(mf, o, u1, u2);
                            float hp = wp_mf_pdf_vndf(mf, o, h);
                            bool ok = std::isfinite(h.x) && std::isfinite(h.y) && h.z >= 0.0f &&
                                      std::abs(dot(h, h) - 1.0f) < 1e-5f && std::isfinite(hp) && hp >= 0.0f;
                            ok = ok && !std::isnan(wp_mf_lambda(mf, o)) && std::isfinite(wp_mf_g1(mf, o)) &&
                                 std::isfinite(wp_mf_g(mf, o, wi)) && std::isfinite(wp_mf_d(mf, h));
                            float3 w, weight = make_float3(0, 0, 0);
                            float pdf = 0;
                            int spec = 0;
                            if (wp_bsdf_sample_pdf(m, nullptr, d, ns, 1, make_float4(u1, u2, 0.5f, 0.5f), &w, &weight, &pdf, &spec))
                                ok = ok && std::isfinite(weight.x) && weight.x >= 0.0f && std::isfinite(pdf) &&
                                     pdf >= 0.0f && w.z > 0.0f && std::abs(dot(w, w) - 1.0f) < 1e-5f;
                            float epdf = 0;
                            float3 f = wp_bsdf_eval(m, nullptr, d, ns, 1, wi, &epdf);
                            ok = ok && std::isfinite(f.x) && f.x >= 0.0f && std::isfinite(epdf) && epdf >= 0.0f;
                            if (!ok) {
                                if (bad < 10)
                                    UNSCOPED_INFO("flags " << flags << " alpha " << ax << ", " << ay << " cos " << z
                                                           << " u " << u1 << ", " << u2);
                                ++bad;
                            }
                        }
                }
    CHECK(bad == 0);
    CHECK(total == 4 * 6 * 6 * 10 * 36);
}

namespace {

// --- Mitsuba 3's values (scripts/mitsuba_conductor_values.py; paste its output here) -----
struct MitsubaRough {
    int beckmann;
    float au, av;
    int copper;
    float wi[3], wo[3], value[3];
};
struct MitsubaSmooth {
    int copper;
    float theta;
    float weight[3];
};
// MITSUBA TABLES BEGIN
// Generated by scripts/mitsuba_conductor_values.py with Mitsuba 3.9.1 (scalar_rgb).
// specular_reflectance (TINT) = (0.9, 0.7, 0.5) throughout.
// {beckmann, alpha_u, alpha_v, copper (else eta 0, k 1), wi, wo, Mitsuba's eval}
const MitsubaRough kMitsubaRough[] = {
    {1, 0.3f, 0.3f, 1, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.706608057f, 0.357682139f, 0.210507229f}},
    {1, 0.3f, 0.3f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {0.874570668f, 0.442714274f, 0.260947049f}},
    {1, 0.3f, 0.3f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {0.606460869f, 0.307023108f, 0.181136116f}},
    {1, 0.3f, 0.3f, 1, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {0.464360118f, 0.235065252f, 0.1385739f}},
    {1, 0.3f, 0.3f, 1, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {0.74933672f, 0.382922083f, 0.230538636f}},
    {1, 0.3f, 0.3f, 1, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {1.34797788f, 0.734628081f, 0.46521458f}},
    {1, 0.3f, 0.3f, 1, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.0060429438f, 0.00306672021f, 0.0018246501f}},
    {1, 0.3f, 0.3f, 1, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {3.68315196f, 2.49270177f, 1.71241057f}},
    {1, 0.3f, 0.3f, 1, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.135853738f, 0.0688292608f, 0.0407605581f}},
    {1, 0.3f, 0.3f, 0, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.742125928f, 0.577209055f, 0.412292182f}},
    {1, 0.3f, 0.3f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {0.918881655f, 0.714685738f, 0.510489821f}},
    {1, 0.3f, 0.3f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {0.63733393f, 0.495704174f, 0.354074419f}},
    {1, 0.3f, 0.3f, 0, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {0.487905174f, 0.379481822f, 0.27105844f}},
    {1, 0.3f, 0.3f, 0, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {0.790906489f, 0.615149498f, 0.439392507f}},
    {1, 0.3f, 0.3f, 0, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {1.43081105f, 1.11285305f, 0.794895053f}},
    {1, 0.3f, 0.3f, 0, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.00636295136f, 0.00494896248f, 0.00353497313f}},
    {1, 0.3f, 0.3f, 0, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {3.81051087f, 2.96373057f, 2.11695051f}},
    {1, 0.3f, 0.3f, 0, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.142897218f, 0.111142278f, 0.0793873444f}},
    {1, 0.1f, 0.5f, 1, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.774011075f, 0.391801298f, 0.230587423f}},
    {1, 0.1f, 0.5f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {1.57422745f, 0.796885729f, 0.469704717f}},
    {1, 0.1f, 0.5f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {1.29209077f, 0.65412581f, 0.38591823f}},
    {1, 0.1f, 0.5f, 1, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {1.53773105f, 0.778419912f, 0.458888263f}},
    {1, 0.1f, 0.5f, 1, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {1.94101214f, 0.991885722f, 0.597165823f}},
    {1, 0.1f, 0.5f, 1, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.00295354356f, 0.00160963775f, 0.0010193279f}},
    {1, 0.1f, 0.5f, 1, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.0f, 0.0f, 0.0f}},
    {1, 0.1f, 0.5f, 1, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {5.32080364f, 3.60104012f, 2.47380543f}},
    {1, 0.1f, 0.5f, 1, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.918498456f, 0.4653503f, 0.275579542f}},
    {1, 0.1f, 0.5f, 0, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.812916994f, 0.632268786f, 0.451620549f}},
    {1, 0.1f, 0.5f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {1.65398717f, 1.28643441f, 0.918881774f}},
    {1, 0.1f, 0.5f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {1.35786712f, 1.05611885f, 0.75437063f}},
    {1, 0.1f, 0.5f, 0, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {1.61570072f, 1.25665617f, 0.897611558f}},
    {1, 0.1f, 0.5f, 0, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {2.04869056f, 1.59342599f, 1.13816142f}},
    {1, 0.1f, 0.5f, 0, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.00313503854f, 0.00243836339f, 0.00174168812f}},
    {1, 0.1f, 0.5f, 0, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.0f, 0.0f, 0.0f}},
    {1, 0.1f, 0.5f, 0, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {5.50479078f, 4.28150415f, 3.05821729f}},
    {1, 0.1f, 0.5f, 0, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.966118991f, 0.751425922f, 0.536732793f}},
    {1, 0.05f, 0.05f, 1, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {1.29638636f, 0.656225562f, 0.386209458f}},
    {1, 0.05f, 0.05f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {31.4845428f, 15.9377136f, 9.39409256f}},
    {1, 0.05f, 0.05f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {3.85465228e-06f, 1.9514323e-06f, 1.15129728e-06f}},
    {1, 0.05f, 0.05f, 1, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {7.49809913e-15f, 3.79563765e-15f, 2.2375756e-15f}},
    {1, 0.05f, 0.05f, 1, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {3.721334e-12f, 1.90165635e-12f, 1.14489418e-12f}},
    {1, 0.05f, 0.05f, 1, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {3.02935173e-12f, 1.65095205e-12f, 1.04549084e-12f}},
    {1, 0.05f, 0.05f, 1, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.0f, 0.0f, 0.0f}},
    {1, 0.05f, 0.05f, 1, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {317.711578f, 215.022415f, 147.713882f}},
    {1, 0.05f, 0.05f, 1, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.0f, 0.0f, 0.0f}},
    {1, 0.05f, 0.05f, 0, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {1.36154962f, 1.05898309f, 0.7564165f}},
    {1, 0.05f, 0.05f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {33.0797386f, 25.7286854f, 18.3776321f}},
    {1, 0.05f, 0.05f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {4.05088076e-06f, 3.15068519e-06f, 2.25048939e-06f}},
    {1, 0.05f, 0.05f, 0, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {7.87828563e-15f, 6.12755577e-15f, 4.37682549e-15f}},
    {1, 0.05f, 0.05f, 0, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {3.92777651e-12f, 3.05493716e-12f, 2.18209804e-12f}},
    {1, 0.05f, 0.05f, 0, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {3.21550512e-12f, 2.50094845e-12f, 1.78639178e-12f}},
    {1, 0.05f, 0.05f, 0, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.0f, 0.0f, 0.0f}},
    {1, 0.05f, 0.05f, 0, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {328.697662f, 255.653748f, 182.609818f}},
    {1, 0.05f, 0.05f, 0, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.0f, 0.0f, 0.0f}},
    {1, 1.0f, 1.0f, 1, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.0687119886f, 0.0347817354f, 0.0204701498f}},
    {1, 1.0f, 1.0f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {0.0787113681f, 0.0398442857f, 0.0234852359f}},
    {1, 1.0f, 1.0f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {0.0810882747f, 0.0410512462f, 0.0242192317f}},
    {1, 1.0f, 1.0f, 1, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {0.102297373f, 0.0517842881f, 0.0305274837f}},
    {1, 1.0f, 1.0f, 1, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {0.116751082f, 0.0596615188f, 0.0359192789f}},
    {1, 1.0f, 1.0f, 1, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.125165045f, 0.0682131052f, 0.0431970023f}},
    {1, 1.0f, 1.0f, 1, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.260936677f, 0.132422164f, 0.0787891075f}},
    {1, 1.0f, 1.0f, 1, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {0.0568092018f, 0.038447611f, 0.0264123455f}},
    {1, 1.0f, 1.0f, 1, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.068782635f, 0.034848202f, 0.0206370372f}},
    {1, 1.0f, 1.0f, 0, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.0721658245f, 0.056128975f, 0.0400921255f}},
    {1, 1.0f, 1.0f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {0.0826993585f, 0.0643217191f, 0.0459440872f}},
    {1, 1.0f, 1.0f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {0.0852162316f, 0.0662792921f, 0.0473423526f}},
    {1, 1.0f, 1.0f, 0, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {0.107484296f, 0.0835988969f, 0.0597134978f}},
    {1, 1.0f, 1.0f, 0, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {0.123227894f, 0.0958439186f, 0.0684599429f}},
    {1, 1.0f, 1.0f, 0, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.132856429f, 0.10333278f, 0.073809132f}},
    {1, 1.0f, 1.0f, 0, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.274754733f, 0.213698119f, 0.15264152f}},
    {1, 1.0f, 1.0f, 0, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {0.0587735958f, 0.0457127951f, 0.0326519981f}},
    {1, 1.0f, 1.0f, 0, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.0723487437f, 0.0562712476f, 0.0401937477f}},
    {0, 0.3f, 0.3f, 1, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.653000295f, 0.330546111f, 0.19453682f}},
    {0, 0.3f, 0.3f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {0.861692905f, 0.436195463f, 0.257104665f}},
    {0, 0.3f, 0.3f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {0.443104208f, 0.224323183f, 0.132345185f}},
    {0, 0.3f, 0.3f, 1, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {0.307860136f, 0.15584287f, 0.0918713287f}},
    {0, 0.3f, 0.3f, 1, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {0.461546719f, 0.235857174f, 0.141998038f}},
    {0, 0.3f, 0.3f, 1, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.670881271f, 0.365620404f, 0.231534764f}},
    {0, 0.3f, 0.3f, 1, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.113158844f, 0.0574267283f, 0.0341679975f}},
    {0, 0.3f, 0.3f, 1, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {1.68890655f, 1.14302659f, 0.785224617f}},
    {0, 0.3f, 0.3f, 1, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.106300376f, 0.053856276f, 0.0318935849f}},
    {0, 0.3f, 0.3f, 0, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.68582356f, 0.533418298f, 0.381013095f}},
    {0, 0.3f, 0.3f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {0.9053514f, 0.70416224f, 0.50297302f}},
    {0, 0.3f, 0.3f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {0.465661287f, 0.362181008f, 0.258700728f}},
    {0, 0.3f, 0.3f, 0, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {0.323469967f, 0.251587749f, 0.179705545f}},
    {0, 0.3f, 0.3f, 0, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {0.487151206f, 0.378895402f, 0.270639569f}},
    {0, 0.3f, 0.3f, 0, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.712106884f, 0.553860903f, 0.395614952f}},
    {0, 0.3f, 0.3f, 0, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.119151235f, 0.0926731825f, 0.0661951303f}},
    {0, 0.3f, 0.3f, 0, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {1.74730694f, 1.35901654f, 0.970726073f}},
    {0, 0.3f, 0.3f, 0, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.11181163f, 0.0869645998f, 0.0621175729f}},
    {0, 0.1f, 0.5f, 1, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.553208828f, 0.280032098f, 0.164807737f}},
    {0, 0.1f, 0.5f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {1.5716095f, 0.795560598f, 0.468923599f}},
    {0, 0.1f, 0.5f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {1.03256691f, 0.522740841f, 0.308404297f}},
    {0, 0.1f, 0.5f, 1, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {1.11809087f, 0.565992415f, 0.333659589f}},
    {0, 0.1f, 0.5f, 1, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {1.40079892f, 0.715828896f, 0.430965483f}},
    {0, 0.1f, 0.5f, 1, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.0411550961f, 0.0224289224f, 0.01420346f}},
    {0, 0.1f, 0.5f, 1, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.00753083266f, 0.00382180559f, 0.00227391394f}},
    {0, 0.1f, 0.5f, 1, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {2.31353164f, 1.56576347f, 1.0756321f}},
    {0, 0.1f, 0.5f, 1, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.528025925f, 0.267520308f, 0.158425033f}},
    {0, 0.1f, 0.5f, 0, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.581016064f, 0.451901406f, 0.322786719f}},
    {0, 0.1f, 0.5f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {1.65123665f, 1.2842952f, 0.91735369f}},
    {0, 0.1f, 0.5f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {1.08513165f, 0.84399128f, 0.602850914f}},
    {0, 0.1f, 0.5f, 0, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {1.17478287f, 0.913720012f, 0.652657151f}},
    {0, 0.1f, 0.5f, 0, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {1.47850883f, 1.14995134f, 0.821393788f}},
    {0, 0.1f, 0.5f, 0, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.0436840728f, 0.0339765027f, 0.0242689308f}},
    {0, 0.1f, 0.5f, 0, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.00792963244f, 0.0061674919f, 0.00440535136f}},
    {0, 0.1f, 0.5f, 0, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {2.39353085f, 1.86163521f, 1.32973945f}},
    {0, 0.1f, 0.5f, 0, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.555401981f, 0.431979328f, 0.308556676f}},
    {0, 0.05f, 0.05f, 1, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {1.67876983f, 0.84978652f, 0.500126243f}},
    {0, 0.05f, 0.05f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {31.4714298f, 15.9310741f, 9.39017963f}},
    {0, 0.05f, 0.05f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {0.117810376f, 0.0596419424f, 0.0351872891f}},
    {0, 0.05f, 0.05f, 1, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {0.0328687131f, 0.0166385788f, 0.00980865024f}},
    {0, 0.05f, 0.05f, 1, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {0.0633272678f, 0.0323611647f, 0.0194830727f}},
    {0, 0.05f, 0.05f, 1, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.114539109f, 0.0624221303f, 0.0395297743f}},
    {0, 0.05f, 0.05f, 1, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.00588948699f, 0.00298884278f, 0.00177831424f}},
    {0, 0.05f, 0.05f, 1, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {274.469543f, 185.756836f, 127.609322f}},
    {0, 0.05f, 0.05f, 1, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.00680021849f, 0.00344527909f, 0.00204028771f}},
    {0, 0.05f, 0.05f, 0, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {1.76315379f, 1.37134182f, 0.979529917f}},
    {0, 0.05f, 0.05f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {33.0659599f, 25.717968f, 18.369978f}},
    {0, 0.05f, 0.05f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {0.123807736f, 0.0962949023f, 0.0687820762f}},
    {0, 0.05f, 0.05f, 0, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {0.0345353f, 0.0268607903f, 0.0191862788f}},
    {0, 0.05f, 0.05f, 0, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {0.066840373f, 0.0519869551f, 0.037133541f}},
    {0, 0.05f, 0.05f, 0, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.121577531f, 0.0945603028f, 0.0675430745f}},
    {0, 0.05f, 0.05f, 0, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.00620136829f, 0.00482328655f, 0.00344520458f}},
    {0, 0.05f, 0.05f, 0, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {283.960358f, 220.858047f, 157.755753f}},
    {0, 0.05f, 0.05f, 0, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.00715278322f, 0.00556327589f, 0.00397376856f}},
    {0, 1.0f, 1.0f, 1, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.0676700771f, 0.03425432f, 0.0201597493f}},
    {0, 1.0f, 1.0f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {0.0678146631f, 0.0343282931f, 0.0202339683f}},
    {0, 1.0f, 1.0f, 1, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {0.0633669943f, 0.0320797786f, 0.0189262852f}},
    {0, 1.0f, 1.0f, 1, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {0.0773756281f, 0.0391685739f, 0.0230903625f}},
    {0, 1.0f, 1.0f, 1, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {0.0659563765f, 0.0337046795f, 0.0202919357f}},
    {0, 1.0f, 1.0f, 1, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.0546415001f, 0.0297788121f, 0.0188578907f}},
    {0, 1.0f, 1.0f, 1, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.107586518f, 0.0545988381f, 0.0324854478f}},
    {0, 1.0f, 1.0f, 1, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {0.0204193294f, 0.0138194952f, 0.0094935745f}},
    {0, 1.0f, 1.0f, 1, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.0417126268f, 0.0211333856f, 0.0125151509f}},
    {0, 1.0f, 1.0f, 0, {0.0f, 0.0f, 1.0f}, {0.150383733f, 0.0868240888f, 0.984807753f}, {0.0710715353f, 0.0552778617f, 0.039484188f}},
    {0, 1.0f, 1.0f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.5f, 6.123234e-17f, 0.866025404f}, {0.0712505579f, 0.0554171018f, 0.0395836458f}},
    {0, 1.0f, 1.0f, 0, {0.5f, 0.0f, 0.866025404f}, {-0.556670399f, 0.321393805f, 0.766044443f}, {0.0665928125f, 0.0517944098f, 0.036996007f}},
    {0, 1.0f, 1.0f, 0, {0.353553391f, 0.612372436f, 0.707106781f}, {-0.321393805f, -0.116977778f, 0.939692621f}, {0.0812989101f, 0.0632324889f, 0.0451660641f}},
    {0, 1.0f, 1.0f, 0, {0.852868532f, 0.150383733f, 0.5f}, {-0.806707284f, 0.14224426f, 0.573576436f}, {0.0696153343f, 0.0541452579f, 0.0386751853f}},
    {0, 1.0f, 1.0f, 0, {5.91458986e-17f, 0.965925826f, 0.258819045f}, {0.163175911f, -0.925416578f, 0.342020143f}, {0.057999216f, 0.0451105013f, 0.0322217867f}},
    {0, 1.0f, 1.0f, 0, {0.984807753f, 0.0f, 0.173648178f}, {-0.25f, 0.433012702f, 0.866025404f}, {0.11328382f, 0.0881096348f, 0.0629354566f}},
    {0, 1.0f, 1.0f, 0, {0.704416026f, 0.704416026f, 0.0871557427f}, {-0.704416026f, -0.704416026f, 0.0871557427f}, {0.021125406f, 0.0164308716f, 0.0117363371f}},
    {0, 1.0f, 1.0f, 0, {0.171010072f, -0.296198133f, 0.939692621f}, {-0.157378696f, 0.892538935f, 0.422618262f}, {0.0438752621f, 0.0341252051f, 0.0243751463f}},
};
// {copper (else eta 0, k 1), theta_i (degrees), Mitsuba's sample weight}
const MitsubaSmooth kMitsubaSmooth[] = {
    {1, 0.0f, {0.856926441f, 0.433772802f, 0.25528875f}},
    {1, 30.0f, {0.85659951f, 0.433617234f, 0.255584925f}},
    {1, 60.0f, {0.851458073f, 0.438079953f, 0.265925974f}},
    {1, 80.0f, {0.853584647f, 0.518309653f, 0.344006538f}},
    {1, 89.0f, {0.893226862f, 0.674255729f, 0.477619946f}},
    {0, 0.0f, {0.899999976f, 0.699999988f, 0.5f}},
    {0, 30.0f, {0.899999976f, 0.699999988f, 0.5f}},
    {0, 60.0f, {0.899999976f, 0.699999988f, 0.5f}},
    {0, 80.0f, {0.899999976f, 0.699999988f, 0.5f}},
    {0, 89.0f, {0.899999976f, 0.699999988f, 0.5f}},
};
// MITSUBA TABLES END

// Walter et al. 2007's rational approximation of Beckmann's G1 (Mitsuba 3's smith_g1).
double walter_g1(const Dist& m, dvec3 w) {
    double t2 = tan2_theta(w) * alpha2_phi(m, w);
    if (t2 == 0) return 1;
    double a = 1 / std::sqrt(t2);
    return a >= 1.6 ? 1.0 : (3.535 * a + 2.181 * a * a) / (1 + 2.276 * a + 2.577 * a * a);
}

}  // namespace

// Mitsuba 3 (separable G, as Mitsuba files get) evaluates the same f cos: GGX to float
// precision; Beckmann within Walter's G1 approximation, which Mitsuba uses and wavepath does not
// (exact erf form): with that approximation swapped into the double formula the two agree to
// float precision, so the whole difference is the approximation (printed).
TEST_CASE("conductor: rough and smooth conductor agree with Mitsuba 3", "[unit][conductor]") {
    const Metal& cu = kMetals[4];
    const glm::vec3 tint{0.9f, 0.7f, 0.5f};
    float3 ns = make_float3(0, 0, 1);
    double worst[2] = {0, 0}, worst_walter = 0;
    for (const MitsubaRough& r : kMitsubaRough) {
        Dist m{r.au, r.av, r.beckmann != 0};
        glm::vec3 eta = r.copper ? cu.eta : glm::vec3(0), k = r.copper ? cu.k : glm::vec3(1);
        MaterialData mat = conductor(WP_MATERIAL_ROUGH_CONDUCTOR, tint, eta, k, r.au, r.av, flags_of(m, true));
        float3 o = make_float3(r.wi[0], r.wi[1], r.wi[2]), i = make_float3(r.wo[0], r.wo[1], r.wo[2]);
        float pdf;
        float3 f = wp_bsdf_eval(mat, nullptr, make_float3(-o.x, -o.y, -o.z), ns, 1, i, &pdf);
        dvec3 od = d3(o), id = d3(i);
        // The double formula with Walter's G1 in place of the exact one.
        double walter_ratio = walter_g1(m, od) * walter_g1(m, id) / ref_g(m, true, od, id);
        dvec3 exact = ref_rough_fcos(m, true, tint, eta, k, od, id);
        const float got[3] = {f.x, f.y, f.z};
        for (int c = 0; c < 3; ++c) {
            double mv = r.value[c];
            INFO(name(m) << (r.copper ? " copper" : " F=1") << " channel " << c << ": wavepath " << got[c]
                         << ", Mitsuba " << mv << ", double " << exact[c]);
            if (mv < 1e-6) {
                CHECK(got[c] < 1e-6);
                continue;
            }
            double rel = std::abs(got[c] - mv) / mv;
            worst[r.beckmann] = std::max(worst[r.beckmann], rel);
            double rel_walter = std::abs(exact[c] * (r.beckmann ? walter_ratio : 1.0) - mv) / mv;
            worst_walter = std::max(worst_walter, rel_walter);
            CHECK(rel_walter < 2e-4);
            CHECK(rel < (r.beckmann ? 8e-3 : 2e-4));
        }
    }
    std::printf("Mitsuba 3 roughconductor: largest relative difference GGX %.2g, Beckmann %.2g "
                "(%.2g with Walter's G1 approximation in the double formula)\n",
                worst[0], worst[1], worst_walter);
    double worst_smooth = 0;
    for (const MitsubaSmooth& r : kMitsubaSmooth) {
        glm::vec3 eta = r.copper ? cu.eta : glm::vec3(0), k = r.copper ? cu.k : glm::vec3(1);
        MaterialData mat = conductor(WP_MATERIAL_CONDUCTOR, tint, eta, k);
        double th = r.theta * kPi / 180;
        float3 d = f3(-dir(th, 0));
        float3 wo, weight = make_float3(0, 0, 0);
        float pdf;
        int spec;
        REQUIRE(wp_bsdf_sample_pdf(mat, nullptr, d, ns, 1, make_float4(0.5f, 0.5f, 0.5f, 0.5f), &wo, &weight, &pdf, &spec));
        const float got[3] = {weight.x, weight.y, weight.z};
        for (int c = 0; c < 3; ++c) {
            INFO("theta " << r.theta << " channel " << c);
            double rel = std::abs(got[c] - r.weight[c]) / r.weight[c];
            worst_smooth = std::max(worst_smooth, rel);
            CHECK(rel < 2e-5);
        }
    }
    std::printf("Mitsuba 3 conductor: largest relative difference %.2g\n", worst_smooth);
}

namespace {

ocl::Program& probe_program() {
    static ocl::Program prog = ocl::Program::build(test::device(), "test_sampling.cl",
                                                   "-D WP_SAMPLING=3 -D WP_GLOSSY_MODEL=1 -D WP_SAMPLER=0");
    return prog;
}

}  // namespace

// The OpenCL build of the same code (PoCL) draws the directions and densities the host draws
// from the same random numbers (test_sampling.cl probe_bsdf_sample; pcg4d numbers), for
// Beckmann and GGX, anisotropic, and the smooth conductor.
TEST_CASE("conductor: the device samples what the host samples", "[kernel][conductor]") {
    auto& dev = test::device();
    const int n = 20000;
    const cl_uint seed = 4242;
    const Metal& cu = kMetals[4];
    std::vector<MaterialData> mats = {
        conductor(WP_MATERIAL_ROUGH_CONDUCTOR, {1, 1, 1}, cu.eta, cu.k, 0.1f, 0.5f, WP_MF_BECKMANN),
        conductor(WP_MATERIAL_ROUGH_CONDUCTOR, {1, 1, 1}, cu.eta, cu.k, 0.6f, 0.2f, WP_MF_SEPARABLE_G),
        conductor(WP_MATERIAL_ROUGH_CONDUCTOR, {1, 1, 1}, cu.eta, cu.k, 1.5f, 1.5f,
                  WP_MF_BECKMANN | WP_MF_SEPARABLE_G),
        conductor(WP_MATERIAL_CONDUCTOR, {1, 1, 1}, cu.eta, cu.k)};
    int differ_all = 0;
    for (const MaterialData& m : mats)
        for (glm::vec3 dv : {glm::vec3(0.3f, -0.2f, -1.0f), glm::vec3(1.0f, 0.4f, -0.05f)}) {
            glm::vec3 dn = glm::normalize(dv);
            ocl::Kernel k(probe_program(), "probe_bsdf_sample", "probe.bsdf");
            cl::Buffer out(dev.context, CL_MEM_READ_WRITE, n * sizeof(float4));
            k.launch({&dev.queue}, n, m, float4{dn.x, dn.y, dn.z, 0}, float4{0, 0, 1, 0}, 1, seed, n, out);
            std::vector<float4> got(n);
            dev.queue.enqueueReadBuffer(out, CL_TRUE, 0, n * sizeof(float4), got.data());
            int differ = 0;
            for (int i = 0; i < n; ++i) {
                Rng4 r = wp_pcg4d(uint(i), 0u, uint(WP_RNG_BSDF), seed);
                float4 u = make_float4(wp_uint_to_unit(r.x), wp_uint_to_unit(r.y), wp_uint_to_unit(r.z),
                                       wp_uint_to_unit(r.w));
                float3 wo, weight = make_float3(0, 0, 0);
                float pdf;
                int spec;
                float4 want = make_float4(0, 0, 0, -1);
                if (wp_bsdf_sample_pdf(m, nullptr, make_float3(dn.x, dn.y, dn.z), make_float3(0, 0, 1), 1, u, &wo, &weight,
                                       &pdf, &spec))
                    want = make_float4(wo.x, wo.y, wo.z, pdf);
                const float4& g = got[i];
                differ += std::abs(g.x - want.x) > 1e-4f || std::abs(g.y - want.y) > 1e-4f ||
                          std::abs(g.z - want.z) > 1e-4f || std::abs(g.w - want.w) > 1e-3f * std::abs(want.w) + 1e-6f;
            }
            INFO("kind " << m.kind << " flags " << m.flags << " d " << dn.x << " " << dn.y << " " << dn.z);
            CHECK(differ <= n / 10000);
            differ_all += differ;
        }
    std::printf("conductor device vs host: %d of %d samples differ\n", differ_all, int(mats.size()) * 2 * n);
}
