// test_materials_dielectric.cpp — the rough and the thin dielectric (kernels/shared/materials/
// roughdielectric.h, thindielectric.h), through bsdf.h's dispatch compiled as host C++:
// eval() and pdf() against Mitsuba 3's own values (scripts/mitsuba_bsdf_values.py), sampling
// against eval()'s density (χ², over the whole sphere: reflection and transmission), the
// weight f |cos| / pdf, reciprocity and the η² relation of transmission, and the white
// furnace against the double-precision single-scattering integrals of
// scene/material_tables (written independently of the device code). And bsdf.h's contract:
// kinds without transmission evaluate zero below the surface.
//
// χ² tests: 1e6 samples, bins with < 5 expected pooled, family-wise α = 0.01 Šidák-
// corrected over the kChi2Tests tests of this file.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

#include "materials_support.h"
#include "scene/material_tables.h"

using namespace wp;
using test::polar;

namespace {

constexpr int kChi2Tests = 3;
const double kAlpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / kChi2Tests);

MaterialData rough_dielectric(float alpha, float ior, bool beckmann = false, bool separable = true,
                              float alpha_v = -1.0f) {
    MaterialData m{};
    m.kind = WP_MATERIAL_ROUGH_DIELECTRIC;
    m.albedo = make_float4(1.0f, 1.0f, 1.0f, 0.0f);
    m.specular = make_float4(1.0f, 1.0f, 1.0f, 0.0f);
    m.ior = ior;
    m.alpha = alpha;
    m.alpha_v = alpha_v > 0.0f ? alpha_v : alpha;
    m.flags = (beckmann ? WP_MF_BECKMANN : 0) | (separable ? WP_MF_SEPARABLE_G : 0);
    m.table = -1;
    return m;
}

// Mitsuba 3.9.1's eval() and pdf() (scripts/mitsuba_bsdf_values.py): {θo, φo, θi, φi, eval, pdf}.
struct MitsubaValue {
    float to, po, ti, pi, f, pdf;
};
// roughdielectric ggx α 0.3 η 1.5 (Mitsuba's numbers)
const MitsubaValue kMitsubaGgx[] = {
    {0, 0, 0, 0, 0.03536776f, 0.03536776f},       {0, 0, 30, 0, 0.01250353f, 0.01259662f},
    {30, 0, 30, 180, 0.04176952f, 0.04208048f},   {30, 0, 45, 120, 0.007263912f, 0.007423829f},
    {60, 20, 50, 200, 0.09698702f, 0.09999315f},  {75, 0, 80, 180, 0.5517654f, 0.8203377f},
    {45, 0, 150, 180, 8.076707f, 18.30788f},      {0, 0, 180, 0, 13.58122f, 30.55775f},
    {30, 0, 160, 200, 2.282504f, 5.150896f},      {60, 0, 130, 180, 1.244083f, 2.885948f},
    {60, 30, 110, 250, 0.005669101f, 0.01464269f}, {80, 0, 120, 180, 1.359423f, 3.252841f},
    {20, 0, 95, 40, 0.0f, 0.0f},
};
// the same, arriving from inside (Mitsuba's numbers)
const MitsubaValue kMitsubaGgxBack[] = {
    {0, 0, 0, 0, 0.03536775f, 0.03536775f},        {0, 0, 30, 0, 0.01262393f, 0.01271791f},
    {30, 0, 30, 180, 0.05551835f, 0.05593166f},    {30, 0, 45, 120, 0.01101427f, 0.01125675f},
    {60, 20, 50, 200, 1.39098f, 1.434094f},        {75, 0, 80, 180, 1.768672f, 2.629575f},
    {45, 0, 150, 180, 0.2004802f, 0.08976562f},    {0, 0, 180, 0, 30.55775f, 13.58122f},
    {30, 0, 160, 200, 0.3913412f, 0.1744463f},     {60, 0, 130, 180, 0.3409325f, 0.1562222f},
    {60, 30, 110, 250, 0.01872285f, 0.009552429f}, {80, 0, 120, 180, 0.0f, 0.0f},
    {20, 0, 95, 40, 0.0f, 0.0f},
};
// roughdielectric beckmann α 0.2 η 1.33 (Mitsuba's numbers)
const MitsubaValue kMitsubaBeckmann[] = {
    {0, 0, 0, 0, 0.03990674f, 0.03990674f},      {0, 0, 30, 0, 0.007637003f, 0.007637004f},
    {30, 0, 30, 180, 0.04849964f, 0.04849964f},  {30, 0, 45, 120, 0.001211146f, 0.001211146f},
    {60, 20, 50, 200, 0.1431409f, 0.1431409f},   {75, 0, 80, 180, 1.90234f, 1.980549f},
    {45, 0, 150, 180, 23.02814f, 40.73447f},     {0, 0, 180, 0, 71.60807f, 126.6675f},
    {30, 0, 160, 200, 0.2914784f, 0.5155962f},   {60, 0, 130, 180, 1.017691f, 1.800194f},
    {60, 30, 110, 250, 0.0f, 0.0f},              {80, 0, 120, 180, 3.834767f, 6.78332f},
    {20, 0, 95, 40, 0.0f, 0.0f},
};
// roughdielectric ggx α_u 0.1 α_v 0.4 η 1.5, specular_reflectance 0.8, specular_transmittance
// 0.6 (Mitsuba's numbers)
const MitsubaValue kMitsubaAniso[] = {
    {0, 0, 0, 0, 0.06366199f, 0.07957748f},      {0, 0, 30, 0, 0.001094328f, 0.001369048f},
    {30, 0, 30, 180, 0.07618186f, 0.09530661f},  {30, 0, 45, 120, 0.01275146f, 0.01641337f},
    {60, 20, 50, 200, 0.07737255f, 0.09765258f}, {75, 0, 80, 180, 1.222679f, 1.642687f},
    {45, 0, 150, 180, 5.388466f, 20.22357f},     {0, 0, 180, 0, 18.33465f, 68.75493f},
    {30, 0, 160, 200, 4.7255f, 17.73677f},       {60, 0, 130, 180, 0.03289702f, 0.1238003f},
    {60, 30, 110, 250, 0.004652269f, 0.02128936f}, {80, 0, 120, 180, 0.05255489f, 0.198548f},
    {20, 0, 95, 40, 0.0f, 0.0f},
};

// Relative difference, with an absolute floor for values that are 0 in one program.
double rel_diff(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-6); }

template <std::size_t N>
double max_mitsuba_diff(const MaterialData& m, const MitsubaValue (&vals)[N], int front, bool pdf) {
    double worst = 0.0;
    for (const MitsubaValue& v : vals) {
        float3 o = polar(v.to, v.po), i = polar(v.ti, v.pi);
        float p = 0.0f;
        float3 f = test::eval_bsdf(m, nullptr, o, i, front, &p);
        double d = pdf ? rel_diff(p, v.pdf) : rel_diff(f.x, v.f);
        INFO("θo " << v.to << " φo " << v.po << " θi " << v.ti << " φi " << v.pi << ": wavepath "
                   << (pdf ? p : f.x) << ", Mitsuba " << (pdf ? v.pdf : v.f));
        CHECK(d < 0.02);  // catches gross errors here; the bounds below are the real test
        worst = std::max(worst, d);
    }
    return worst;
}

}  // namespace

TEST_CASE("roughdielectric: eval and pdf match Mitsuba 3's (GGX, Beckmann, anisotropic, inside)",
          "[unit][dielectric]") {
    MaterialData ggx = rough_dielectric(0.3f, 1.5f);
    MaterialData beck = rough_dielectric(0.2f, 1.33f, true);
    MaterialData aniso = rough_dielectric(0.1f, 1.5f, false, true, 0.4f);
    aniso.specular = make_float4(0.8f, 0.8f, 0.8f, 0.0f);
    aniso.albedo = make_float4(0.6f, 0.6f, 0.6f, 0.0f);
    double g_f = max_mitsuba_diff(ggx, kMitsubaGgx, 1, false), g_p = max_mitsuba_diff(ggx, kMitsubaGgx, 1, true);
    double b_f = max_mitsuba_diff(ggx, kMitsubaGgxBack, 0, false), b_p = max_mitsuba_diff(ggx, kMitsubaGgxBack, 0, true);
    double k_f = max_mitsuba_diff(beck, kMitsubaBeckmann, 1, false), k_p = max_mitsuba_diff(beck, kMitsubaBeckmann, 1, true);
    double a_f = max_mitsuba_diff(aniso, kMitsubaAniso, 1, false), a_p = max_mitsuba_diff(aniso, kMitsubaAniso, 1, true);
    std::printf("roughdielectric vs Mitsuba 3 (max relative difference of eval / pdf): GGX %.1e / %.1e, "
                "GGX inside %.1e / %.1e, Beckmann %.1e / %.1e, anisotropic GGX %.1e / %.1e\n",
                g_f, g_p, b_f, b_p, k_f, k_p, a_f, a_p);
    // GGX: float rounding only. Beckmann: Mitsuba's G1 is a rational fit (< 0.35 %), wavepath's exact.
    CHECK(std::max({g_f, g_p, b_f, b_p, a_f, a_p}) < 1e-4);
    CHECK(std::max(k_f, k_p) < 7e-3);
}

TEST_CASE("roughdielectric: sampling matches eval's density over the sphere (chi2), weight = f cos / pdf",
          "[unit][stat][dielectric]") {
    struct Case {
        const char* name;
        MaterialData m;
        double theta, phi;
        int front;
    };
    const Case cases[] = {
        {"GGX α 0.4 η 1.5 from outside, θ 40", rough_dielectric(0.4f, 1.5f), 40, 10, 1},
        {"GGX α 0.3 η 1.5 from inside, θ 35 (total internal reflection near)", rough_dielectric(0.3f, 1.5f, false, false), 35, 0, 0},
        {"Beckmann α 0.2 / 0.5 η 1.33 from outside, θ 65", rough_dielectric(0.2f, 1.33f, true, true, 0.5f), 65, 30, 1},
    };
    const int n = 1000000;
    std::uint64_t seed = 7;
    for (const Case& c : cases) {
        float3 o = polar(c.theta, c.phi);
        auto draws = test::draw_bsdf(c.m, nullptr, o, c.front, n, seed++);
        // The reported density and weight against eval().
        int bad_pdf = 0, bad_weight = 0, transmitted = 0;
        float worst = 0.0f;
        for (const auto& s : draws) {
            if (!s.ok) continue;
            float p = 0.0f;
            float3 f = test::eval_bsdf(c.m, nullptr, o, s.wo, c.front, &p);
            // Float rounding: the generalised half vector of a transmission near the
            // critical angle, normalize(vo + η vi), loses digits (1 draw in 1e6 here).
            bad_pdf += !(std::abs(p - s.pdf) <= 1e-3f * s.pdf);
            bad_weight += !(std::abs(s.weight.x - f.x / s.pdf) <= 1e-3f * s.weight.x + 1e-6f);
            worst = std::max({worst, std::abs(p - s.pdf) / s.pdf,
                              std::abs(s.weight.x - f.x / s.pdf) / (s.weight.x + 1e-6f)});
            transmitted += s.wo.z < 0.0f;
        }
        auto r = test::chi2_against_eval(draws, c.m, nullptr, o, c.front, 0.0);
        INFO(c.name << ": " << transmitted << " transmitted; " << bad_pdf << " / " << bad_weight
                    << " densities / weights off by > 1e-3 (worst " << worst << "); absorbed " << r.absorbed << " expected "
                    << r.absorbed_expected << "; chi2 p-value " << r.p << " with " << r.dof
                    << " degrees of freedom, alpha " << kAlpha);
        std::printf("chi2 %s: p-value %.3g, %d degrees of freedom\n", c.name, r.p, r.dof);
        CHECK(bad_pdf <= 5);
        CHECK(bad_weight <= 5);
        CHECK(worst < 1e-2f);
        CHECK(transmitted > n / 10);
        CHECK(r.dof > 200);
        CHECK(r.p > kAlpha);
    }
}

TEST_CASE("roughdielectric: reciprocity of reflection, η² relation of transmission",
          "[unit][dielectric]") {
    // Direction pairs drawn from the material itself (so f is not negligible).
    for (MaterialData m : {rough_dielectric(0.3f, 1.5f), rough_dielectric(0.15f, 1.33f, true, false),
                           rough_dielectric(0.2f, 1.7f, false, true, 0.6f)}) {
        int checked_r = 0, checked_t = 0;
        double worst_r = 0, worst_t = 0;
        std::uint64_t seed = 40;
        for (double theta : {10.0, 40.0, 70.0})
            for (int front : {1, 0})
                for (const auto& s : test::draw_bsdf(m, nullptr, polar(theta, 30.0), front, 500, seed++)) {
                    if (!s.ok) continue;
                    float3 a = polar(theta, 30.0), b = s.wo;
                    float p;
                    if (b.z > 0.0f) {
                        // Reflection: f(a, b) = f(b, a) (eval gives f |cos| of its light direction).
                        double x = test::eval_bsdf(m, nullptr, a, b, front, &p).x / b.z;
                        double y = test::eval_bsdf(m, nullptr, b, a, front, &p).x / a.z;
                        worst_r = std::max(worst_r, std::abs(x - y) / x);
                        ++checked_r;
                    } else {
                        // Transmission from a (viewer on the `front` side) to b below: the viewer at
                        // b, on the other side (front flipped, its side up: both directions
                        // mirrored) sees f_b; radiance transport: f_b / η_b² = f_a / η_a².
                        double eta_a = front ? 1.0 : m.ior, eta_b = front ? m.ior : 1.0;
                        double x = test::eval_bsdf(m, nullptr, a, b, front, &p).x / -b.z;
                        double y = test::eval_bsdf(m, nullptr, make_float3(b.x, b.y, -b.z),
                                                   make_float3(a.x, a.y, -a.z), !front, &p).x / a.z;
                        worst_t = std::max(worst_t, std::abs(x / (eta_a * eta_a) - y / (eta_b * eta_b)) /
                                                        (x / (eta_a * eta_a)));
                        ++checked_t;
                    }
                }
        INFO("reflections " << checked_r << " worst " << worst_r << "; transmissions " << checked_t
                            << " worst " << worst_t);
        CHECK(checked_r > 200);
        CHECK(checked_t > 500);
        CHECK(worst_r < 1e-3);
        CHECK(worst_t < 1e-3);
    }
}

TEST_CASE("roughdielectric: white furnace E(θ) <= 1 and equals the single-scattering integrals",
          "[unit][stat][dielectric]") {
    // E(θ) = R + T in energy (transmitted weights times η², undoing the radiance factor):
    // what a single interface scatters; the rest is masked (no multiple scattering).
    const int n = 200000;
    std::uint64_t seed = 100;
    for (bool beckmann : {false, true})
        for (bool separable : {true, false})
            for (float alpha : {0.1f, 0.4f, 1.0f})
                for (int front : {1, 0})
                    for (double theta : {0.0, 45.0, 70.0, 85.0}) {
                        MaterialData m = rough_dielectric(alpha, 1.5f, beckmann, separable);
                        double eta = front ? 1.5 : 1.0 / 1.5;  // η_t / η_i
                        float3 o = polar(theta, 0.0);
                        auto draws = test::draw_bsdf(m, nullptr, o, front, n, seed++);
                        double sr = 0, st = 0, sr2 = 0, st2 = 0;
                        for (const auto& s : draws) {
                            if (!s.ok) continue;
                            if (s.wo.z > 0) {
                                sr += s.weight.x;
                                sr2 += double(s.weight.x) * s.weight.x;
                            } else {
                                double w = s.weight.x * eta * eta;
                                st += w;
                                st2 += w * w;
                            }
                        }
                        double r = sr / n, t = st / n;
                        double se_r = std::sqrt(std::max(0.0, sr2 / n - r * r) / n);
                        double se_t = std::sqrt(std::max(0.0, st2 / n - t * t) / n);
                        RoughCoat c;
                        c.alpha = alpha;
                        c.distribution = beckmann ? MicrofacetModel::Beckmann : MicrofacetModel::GGX;
                        c.separable_g = separable;
                        double mu = std::cos(theta * test::kPiD / 180.0);
                        double rq = rough_interface_reflectance(c, mu, eta);
                        double tq = rough_interface_transmittance(c, mu, eta);
                        INFO((beckmann ? "Beckmann" : "GGX") << (separable ? " separable" : " correlated")
                                                             << " α " << alpha << (front ? " outside" : " inside")
                                                             << " θ " << theta << ": R " << r << " ± " << se_r
                                                             << " (integral " << rq << "), T " << t << " ± " << se_t
                                                             << " (integral " << tq << ")");
                        CHECK(std::abs(r - rq) < 5 * se_r + 1e-4);
                        CHECK(std::abs(t - tq) < 5 * se_t + 1e-4);
                        CHECK(r + t <= 1.0 + 4 * (se_r + se_t));
                        CHECK(rq + tq <= 1.0 + 1e-6);
                        if (!beckmann && separable)
                            std::printf("roughdielectric white furnace (GGX, separable G, η 1.5, %s): α %.1f θ %4.1f: "
                                        "E = R + T = %.4f + %.4f = %.4f\n",
                                        front ? "outside" : "inside", alpha, theta, r, t, r + t);
                    }
}

TEST_CASE("thindielectric: R = 2F / (1 + F) (Mitsuba's numbers), straight through, R + T = 1",
          "[unit][stat][dielectric]") {
    // Mitsuba 3.9.1's reflection probability of thindielectric η 1.5 (scripts/mitsuba_bsdf_values.py).
    const double kMitsubaR[][2] = {{0, 0.07692309}, {30, 0.07973449}, {60, 0.1637675},
                                   {80, 0.5587709}, {89, 0.9496819}};
    auto fresnel = [](double c, double eta) {  // Born & Wolf, eta = η_t / η_i, from scratch
        double s2 = (1 - c * c) / (eta * eta);
        if (s2 >= 1) return 1.0;
        double t = std::sqrt(1 - s2);
        double rs = (c - eta * t) / (c + eta * t), rp = (eta * c - t) / (eta * c + t);
        return 0.5 * (rs * rs + rp * rp);
    };
    MaterialData m{};
    m.kind = WP_MATERIAL_THIN_DIELECTRIC;
    m.ior = 1.5f;
    m.specular = make_float4(0.9f, 0.8f, 0.7f, 0.0f);
    m.albedo = make_float4(0.3f, 0.4f, 0.5f, 0.0f);
    m.table = -1;
    const int n = 200000;
    for (const auto& mr : kMitsubaR) {
        double c = std::cos(mr[0] * test::kPiD / 180.0);
        double f = fresnel(c, 1.5), r_ref = 2 * f / (1 + f);
        CHECK(std::abs(r_ref - mr[1]) < 2e-6);  // the closed form is Mitsuba's
        CHECK(std::abs(wp_thindielectric_reflectance(float(c), 1.5f) - r_ref) < 1e-6);
        for (int front : {1, 0}) {
            float3 o = polar(mr[0], 25.0);
            auto draws = test::draw_bsdf(m, nullptr, o, front, n, 11 + front);
            int refl = 0, bad = 0;
            for (const auto& s : draws) {
                bad += !s.ok || !s.specular || s.pdf != 0.0f;
                if (s.wo.z > 0) {
                    ++refl;
                    bad += std::abs(s.wo.x + o.x) > 1e-6f || std::abs(s.wo.y + o.y) > 1e-6f ||
                           std::abs(s.wo.z - o.z) > 1e-6f || s.weight.x != 0.9f || s.weight.z != 0.7f;
                } else {
                    bad += s.wo.x != -o.x || s.wo.y != -o.y || s.wo.z != -o.z || s.weight.x != 0.3f ||
                           s.weight.z != 0.5f;
                }
            }
            double frac = double(refl) / n, se = std::sqrt(r_ref * (1 - r_ref) / n);
            INFO("θ " << mr[0] << (front ? " front" : " back") << ": reflected " << frac << ", R " << r_ref);
            CHECK(bad == 0);
            CHECK(std::abs(frac - r_ref) < 5 * se + 1e-6);
        }
        float p = 1.0f;
        CHECK(wp_max_component(test::eval_bsdf(m, nullptr, polar(mr[0], 0), polar(mr[0], 180), 1, &p)) == 0.0f);
        CHECK(p == 0.0f);
    }
    // White: every weight is 1 (reflection × 1, transmission × 1), so R + T = 1 exactly.
    m.specular = m.albedo = make_float4(1.0f, 1.0f, 1.0f, 0.0f);
    for (const auto& s : test::draw_bsdf(m, nullptr, polar(70, 0), 1, 10000, 5))
        CHECK((s.ok && s.weight.x == 1.0f && s.weight.y == 1.0f && s.weight.z == 1.0f));
}

TEST_CASE("bsdf: kinds without transmission evaluate zero below the surface", "[unit][dielectric]") {
    // bsdf.h passes the signed cosine; only roughdielectric has a transmission lobe.
    std::vector<float> tables(WP_ROUGH_PLASTIC_TABLE_SIZE, 0.5f);
    for (int kind = 0; kind < WP_MATERIAL_KIND_COUNT; ++kind) {
        MaterialData m{};
        m.kind = kind;
        m.albedo = m.specular = make_float4(0.8f, 0.8f, 0.8f, 0.5f);
        m.ior = 1.5f;
        m.alpha = m.alpha_v = 0.5f;
        m.eta = make_float4(0.2f, 0.9f, 1.1f, 0.0f);
        m.k = make_float4(3.9f, 2.4f, 2.2f, 0.0f);
        m.table = kind == WP_MATERIAL_ROUGH_PLASTIC ? 0 : -1;
        int below_nonzero = 0, above_nonzero = 0;
        for (int front : {0, 1})
            for (double ti : {100.0, 135.0, 170.0, 180.0}) {
                float p = 1.0f;
                float3 f = test::eval_bsdf(m, tables.data(), polar(30, 0), polar(ti, 180), front, &p);
                below_nonzero += wp_max_component(f) != 0.0f || p != 0.0f;
                float3 fa = test::eval_bsdf(m, tables.data(), polar(30, 0), polar(180 - ti, 180), front, &p);
                above_nonzero += wp_max_component(fa) > 0.0f;
            }
        INFO("kind " << kind);
        if (kind == WP_MATERIAL_ROUGH_DIELECTRIC)
            CHECK(below_nonzero > 4);
        else
            CHECK(below_nonzero == 0);
        bool reflects = !(kind == WP_MATERIAL_MIRROR || kind == WP_MATERIAL_GLASS ||
                          kind == WP_MATERIAL_CONDUCTOR || kind == WP_MATERIAL_THIN_DIELECTRIC);
        CHECK((above_nonzero > 0) == reflects);
    }
}
