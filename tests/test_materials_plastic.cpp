// test_materials_plastic.cpp — smooth and rough plastic (kernels/shared/materials/plastic.h,
// roughplastic.h) through bsdf.h's dispatch compiled as host C++, with the host's tables
// (scene/material_tables) and specular sampling weight (scene/upload): eval() and pdf()
// against Mitsuba 3's own values (scripts/mitsuba_bsdf_values.py), the tables against the
// ones Mitsuba computes, the polynomial diffuse Fresnel reflectance against its integral,
// sampling against eval()'s density (χ²; the smooth coat's Dirac event as one bin of known
// probability), the weight f cos / pdf, reciprocity, and the white furnace against closed
// forms.
//
// χ² tests: 1e6 samples, bins with < 5 expected pooled, family-wise α = 0.01 Šidák-
// corrected over the kChi2Tests tests of this file.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "materials_support.h"
#include "scene/material_tables.h"
#include "scene/upload.h"

using namespace wp;
using test::polar;

namespace {

constexpr int kChi2Tests = 4;
const double kAlpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / kChi2Tests);

// A plastic as scene/upload makes it (the sampling weight from the host).
MaterialData plastic(MaterialKind kind, float diffuse, float ior, float alpha = 0.0f,
                     bool beckmann = false, bool nonlinear = false) {
    Material h;
    h.kind = kind;
    h.albedo = glm::vec3(diffuse);
    h.ior = ior;
    h.alpha = alpha;
    h.distribution = beckmann ? MicrofacetModel::Beckmann : MicrofacetModel::GGX;
    h.separable_g = true;  // Mitsuba's
    h.nonlinear = nonlinear;
    Scene s;
    s.add_material(h);
    s.add_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, 0);
    return upload_scene(s).materials[0];
}

// The tables of m (a rough plastic) as the renderer uploads them.
std::vector<float> tables_of(MaterialKind kind, float diffuse, float ior, float alpha, bool beckmann) {
    Material h;
    h.kind = kind;
    h.albedo = glm::vec3(diffuse);
    h.ior = ior;
    h.alpha = alpha;
    h.distribution = beckmann ? MicrofacetModel::Beckmann : MicrofacetModel::GGX;
    h.separable_g = true;
    Scene s;
    s.add_material(h);
    s.add_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, 0);
    return upload_scene(s).material_tables;
}

struct MitsubaValue {
    float to, po, ti, pi, f, pdf;
};
// Mitsuba 3.9.1 (scripts/mitsuba_bsdf_values.py), reflections only: {θo, φo, θi, φi, eval, pdf}.
// plastic η 1.5 diffuse 0.5 (Mitsuba's numbers)
const MitsubaValue kMitsubaPlastic[] = {
    {0, 0, 0, 0, 0.1616856f, 0.2938245f},       {0, 0, 30, 0, 0.1398018f, 0.2544595f},
    {30, 0, 30, 180, 0.13958f, 0.2536845f},     {30, 0, 45, 120, 0.1129301f, 0.2071325f},
    {60, 20, 50, 200, 0.09679037f, 0.1710979f}, {75, 0, 80, 180, 0.01393304f, 0.03294835f},
};
// plastic η 1.9 diffuse 0.8 nonlinear (Mitsuba's numbers)
const MitsubaValue kMitsubaPlasticNonlinear[] = {
    {0, 0, 0, 0, 0.1480746f, 0.2808889f},        {0, 0, 30, 0, 0.1279709f, 0.2432569f},
    {30, 0, 30, 180, 0.127706f, 0.2426425f},     {30, 0, 45, 120, 0.1031216f, 0.1981168f},
    {60, 20, 50, 200, 0.08773644f, 0.1680349f},  {75, 0, 80, 180, 0.01267471f, 0.03590764f},
};
// roughplastic ggx α 0.3 η 1.5 diffuse 0.5 (Mitsuba's numbers)
const MitsubaValue kMitsubaRough[] = {
    {0, 0, 0, 0, 0.1451949f, 0.3689507f},       {0, 0, 30, 0, 0.1068308f, 0.2791202f},
    {30, 0, 30, 180, 0.1353174f, 0.3522119f},   {30, 0, 45, 120, 0.08224011f, 0.2200402f},
    {60, 20, 50, 200, 0.1601989f, 0.4553557f},  {75, 0, 80, 180, 0.5644777f, 0.9149679f},
};
// roughplastic beckmann α 0.1 η 1.5 diffuse 0.8 nonlinear (Mitsuba's numbers)
const MitsubaValue kMitsubaRoughBeckmann[] = {
    {0, 0, 0, 0, 0.513186f, 0.6965201f},        {0, 0, 30, 0, 0.1687344f, 0.2623617f},
    {30, 0, 30, 180, 0.5496872f, 0.7363334f},   {30, 0, 45, 120, 0.1359625f, 0.2134461f},
    {60, 20, 50, 200, 0.6403989f, 1.017493f},   {75, 0, 80, 180, 7.975044f, 7.46787f},
};

template <std::size_t N>
double max_mitsuba_diff(const MaterialData& m, const float* tables, const MitsubaValue (&vals)[N],
                        bool pdf) {
    double worst = 0.0;
    for (const MitsubaValue& v : vals) {
        float p = 0.0f;
        float3 f = test::eval_bsdf(m, tables, polar(v.to, v.po), polar(v.ti, v.pi), 1, &p);
        double a = pdf ? p : f.x, b = pdf ? v.pdf : v.f;
        INFO("θo " << v.to << " θi " << v.ti << ": wavepath " << a << ", Mitsuba " << b);
        CHECK(std::abs(a - b) < 0.02 * b);
        worst = std::max(worst, std::abs(a - b) / b);
    }
    return worst;
}

// Dielectric Fresnel reflectance from scratch (Born & Wolf), eta = η_t / η_i.
double fresnel(double c, double eta) {
    double s2 = (1 - c * c) / (eta * eta);
    if (s2 >= 1) return 1.0;
    double t = std::sqrt(1 - s2);
    double rs = (c - eta * t) / (c + eta * t), rp = (eta * c - t) / (eta * c + t);
    return 0.5 * (rs * rs + rp * rp);
}

// ∫ F(c) 2c dc, midpoint rule in c² (smooth but for the critical angle's square root).
double diffuse_fresnel_exact(double eta) {
    const int n = 400000;
    double s = 0;
    for (int i = 0; i < n; ++i) s += fresnel(std::sqrt((i + 0.5) / n), eta);
    return s / n;
}

}  // namespace

TEST_CASE("plastic: the diffuse Fresnel reflectance fits against the integral", "[unit][plastic]") {
    for (double eta : {1.0 / 2.0, 1.0 / 1.5, 1.0 / 1.33, 1.33, 1.5, 1.9, 2.5}) {
        double exact = diffuse_fresnel_exact(eta), fit = wp_fresnel_diffuse_reflectance(float(eta));
        std::printf("diffuse Fresnel reflectance η %.3f: fit %.5f, integral %.5f (%+.2f %%)\n", eta, fit,
                    exact, 100.0 * (fit - exact) / exact);
        // Mitsuba's fits (Egan & Hilgeman below 1, d'Eon & Irving above): < 0.6 % in [0.5, 2.5].
        CHECK(std::abs(fit - exact) < 6e-3 * exact);
    }
}

TEST_CASE("plastic: eval and pdf match Mitsuba 3's", "[unit][plastic]") {
    MaterialData a = plastic(MaterialKind::Plastic, 0.5f, 1.5f);
    MaterialData b = plastic(MaterialKind::Plastic, 0.8f, 1.9f, 0.0f, false, true);
    CHECK(a.specular.w == Approx(1.0 / 1.5).epsilon(1e-6));  // Mitsuba: 1 / (0.5 + 1)
    double fa = max_mitsuba_diff(a, nullptr, kMitsubaPlastic, false);
    double pa = max_mitsuba_diff(a, nullptr, kMitsubaPlastic, true);
    double fb = max_mitsuba_diff(b, nullptr, kMitsubaPlasticNonlinear, false);
    double pb = max_mitsuba_diff(b, nullptr, kMitsubaPlasticNonlinear, true);
    std::printf("plastic vs Mitsuba 3 (max relative difference of eval / pdf): %.1e / %.1e, "
                "nonlinear η 1.9: %.1e / %.1e\n", fa, pa, fb, pb);
    CHECK(std::max({fa, pa, fb, pb}) < 1e-5);
}

TEST_CASE("roughplastic: tables and eval and pdf match Mitsuba 3's", "[unit][plastic]") {
    // Mitsuba 3.9.1's tables, recovered from its eval() (scripts/mitsuba_bsdf_values.py):
    // T(μ) at μ = 0, 1/63, 32/63, 1 and the internal reflectance (Mitsuba's numbers).
    struct MitsubaTable {
        const char* dist;
        float alpha;
        float t[4];
        float r;
    };
    const MitsubaTable kTables[] = {
        {"ggx", 0.05f, {0.434737f, 0.416763f, 0.911855f, 0.959958f}, 0.576101f},
        {"ggx", 0.3f, {0.636519f, 0.651306f, 0.888562f, 0.953159f}, 0.414861f},
        {"ggx", 1.0f, {0.266381f, 0.282177f, 0.656170f, 0.880810f}, 0.117422f},
        {"beckmann", 0.05f, {0.215877f, 0.246666f, 0.912890f, 0.960001f}, 0.585944f},
        {"beckmann", 0.3f, {0.676578f, 0.685562f, 0.903617f, 0.959772f}, 0.529971f},
        {"beckmann", 1.0f, {0.596861f, 0.609900f, 0.868083f, 0.947428f}, 0.233775f},
    };
    double worst_t = 0, worst_r = 0;
    for (const MitsubaTable& mt : kTables) {
        bool beck = std::strcmp(mt.dist, "beckmann") == 0;
        std::vector<float> t = tables_of(MaterialKind::RoughPlastic, 0.5f, 1.5f, mt.alpha, beck);
        REQUIRE(t.size() == WP_ROUGH_PLASTIC_TABLE_SIZE);
        const int idx[4] = {0, 1, 32, 63};
        for (int k = 0; k < 4; ++k) {
            INFO(mt.dist << " α " << mt.alpha << " T[" << idx[k] << "] " << t[idx[k]] << " Mitsuba " << mt.t[k]);
            CHECK(std::abs(t[idx[k]] - mt.t[k]) < 1e-3);
            worst_t = std::max(worst_t, double(std::abs(t[idx[k]] - mt.t[k])));
        }
        INFO(mt.dist << " α " << mt.alpha << " R " << t[64] << " Mitsuba " << mt.r);
        CHECK(std::abs(t[64] - mt.r) < 1e-3);
        worst_r = std::max(worst_r, double(std::abs(t[64] - mt.r)));
    }
    MaterialData a = plastic(MaterialKind::RoughPlastic, 0.5f, 1.5f, 0.3f);
    std::vector<float> ta = tables_of(MaterialKind::RoughPlastic, 0.5f, 1.5f, 0.3f, false);
    a.table = 0;
    MaterialData b = plastic(MaterialKind::RoughPlastic, 0.8f, 1.5f, 0.1f, true, true);
    std::vector<float> tb = tables_of(MaterialKind::RoughPlastic, 0.8f, 1.5f, 0.1f, true);
    b.table = 0;
    double fa = max_mitsuba_diff(a, ta.data(), kMitsubaRough, false);
    double pa = max_mitsuba_diff(a, ta.data(), kMitsubaRough, true);
    double fb = max_mitsuba_diff(b, tb.data(), kMitsubaRoughBeckmann, false);
    double pb = max_mitsuba_diff(b, tb.data(), kMitsubaRoughBeckmann, true);
    std::printf("roughplastic vs Mitsuba 3: tables max |ΔT| %.1e, |ΔR| %.1e; eval / pdf max relative "
                "difference GGX %.1e / %.1e, Beckmann nonlinear %.1e / %.1e\n",
                worst_t, worst_r, fa, pa, fb, pb);
    // GGX: the two programs' quadratures of the same tables; Beckmann: and Mitsuba's G1 fit.
    CHECK(std::max(fa, pa) < 2e-3);
    CHECK(std::max(fb, pb) < 6e-3);
}

TEST_CASE("plastic and roughplastic: sampling matches eval's density (chi2), weight = f cos / pdf",
          "[unit][stat][plastic]") {
    struct Case {
        const char* name;
        MaterialData m;
        std::vector<float> tables;
        double theta;
    };
    std::vector<Case> cases;
    cases.push_back({"plastic η 1.5 diffuse 0.5, θ 20", plastic(MaterialKind::Plastic, 0.5f, 1.5f), {}, 20});
    cases.push_back({"plastic η 1.9 diffuse 0.2 nonlinear, θ 75",
                     plastic(MaterialKind::Plastic, 0.2f, 1.9f, 0.0f, false, true), {}, 75});
    cases.push_back({"roughplastic GGX α 0.3 η 1.5 diffuse 0.5, θ 30",
                     plastic(MaterialKind::RoughPlastic, 0.5f, 1.5f, 0.3f),
                     tables_of(MaterialKind::RoughPlastic, 0.5f, 1.5f, 0.3f, false), 30});
    cases.push_back({"roughplastic Beckmann α 0.15 η 1.6 diffuse 0.3, θ 70",
                     plastic(MaterialKind::RoughPlastic, 0.3f, 1.6f, 0.15f, true),
                     tables_of(MaterialKind::RoughPlastic, 0.3f, 1.6f, 0.15f, true), 70});
    const int n = 1000000;
    std::uint64_t seed = 131;
    for (Case& c : cases) {
        const float* tables = c.tables.empty() ? nullptr : c.tables.data();
        if (tables) c.m.table = 0;
        float3 o = polar(c.theta, 40.0);
        // The smooth coat's Dirac probability F w / (F w + (1 − F)(1 − w)), F from scratch.
        double p_dirac = 0.0;
        if (c.m.kind == WP_MATERIAL_PLASTIC) {
            double f = fresnel(o.z, c.m.ior), w = c.m.specular.w;
            p_dirac = f * w / (f * w + (1 - f) * (1 - w));
        }
        auto draws = test::draw_bsdf(c.m, tables, o, 1, n, seed++);
        int bad_pdf = 0, bad_weight = 0, bad_dirac = 0;
        for (const auto& s : draws) {
            if (!s.ok) continue;
            if (s.specular) {
                double f = fresnel(o.z, c.m.ior);
                bad_dirac += std::abs(s.wo.x + o.x) > 1e-6f || std::abs(s.wo.z - o.z) > 1e-6f ||
                             std::abs(s.weight.x - f / p_dirac) > 1e-5 * (f / p_dirac);
                continue;
            }
            float p = 0.0f;
            float3 f = test::eval_bsdf(c.m, tables, o, s.wo, 1, &p);
            bad_pdf += !(std::abs(p - s.pdf) <= 1e-4f * s.pdf);
            bad_weight += !(std::abs(s.weight.x - f.x / s.pdf) <= 1e-4f * s.weight.x + 1e-7f);
        }
        auto r = test::chi2_against_eval(draws, c.m, tables, o, 1, p_dirac);
        INFO(c.name << ": Dirac " << r.dirac << " expected " << r.dirac_expected << "; absorbed "
                    << r.absorbed << " expected " << r.absorbed_expected << "; chi2 p-value " << r.p
                    << " with " << r.dof << " degrees of freedom, alpha " << kAlpha);
        std::printf("chi2 %s: p-value %.3g, %d degrees of freedom\n", c.name, r.p, r.dof);
        CHECK(bad_pdf == 0);
        CHECK(bad_weight == 0);
        CHECK(bad_dirac == 0);
        CHECK(r.dof > 200);
        CHECK(r.p > kAlpha);
    }
}

TEST_CASE("plastic and roughplastic: reciprocity", "[unit][plastic]") {
    std::vector<float> t = tables_of(MaterialKind::RoughPlastic, 0.6f, 1.5f, 0.25f, false);
    MaterialData rp = plastic(MaterialKind::RoughPlastic, 0.6f, 1.5f, 0.25f);
    rp.table = 0;
    MaterialData sp = plastic(MaterialKind::Plastic, 0.6f, 1.5f);
    test::Rng rng(5);
    int checked = 0;
    for (int k = 0; k < 2000; ++k) {
        glm::vec3 ua = rng.unit_vector(), ub = rng.unit_vector();
        float3 a = make_float3(ua.x, ua.y, std::abs(ua.z)), b = make_float3(ub.x, ub.y, std::abs(ub.z));
        for (const MaterialData& m : {rp, sp}) {
            float p;
            double x = test::eval_bsdf(m, t.data(), a, b, 1, &p).x / b.z;
            double y = test::eval_bsdf(m, t.data(), b, a, 1, &p).x / a.z;
            if (x > 1e-4 && x < 1e4) {
                CHECK(std::abs(x - y) <= 2e-4 * x);
                ++checked;
            }
        }
    }
    CHECK(checked > 3000);
}

TEST_CASE("plastic and roughplastic: white furnace E(θ) equals the closed form (<= 1 up to the fits)",
          "[unit][stat][plastic]") {
    const int n = 200000;
    std::uint64_t seed = 500;
    // Smooth: E = F(θ) + (1 − F(θ)) (1 − F_dr,out) / (η² (1 − F_dr,in)), F_dr,out the integral,
    // F_dr,in Mitsuba's fit (the model's), both at white albedo.
    for (float ior : {1.33f, 1.5f, 1.9f}) {
        MaterialData m = plastic(MaterialKind::Plastic, 1.0f, ior);
        double eta = ior, fdr_out = diffuse_fresnel_exact(eta);
        double fdr_in = wp_fresnel_diffuse_reflectance(float(1.0 / eta));
        for (double theta : {0.0, 45.0, 70.0, 85.0}) {
            float3 o = polar(theta, 0.0);
            double s = 0, s2 = 0;
            for (const auto& d : test::draw_bsdf(m, nullptr, o, 1, n, seed++)) {
                double w = d.ok ? d.weight.x : 0.0;
                s += w;
                s2 += w * w;
            }
            double e = s / n, se = std::sqrt(std::max(0.0, s2 / n - e * e) / n);
            double f = fresnel(o.z, eta);
            double closed = f + (1 - f) * (1 - fdr_out) / (eta * eta * (1 - fdr_in));
            INFO("plastic η " << ior << " θ " << theta << ": E " << e << " ± " << se << ", closed form " << closed);
            CHECK(std::abs(e - closed) < 5 * se + 1e-5);
            CHECK(closed <= 1.0 + 3e-3);  // 1 exactly with the integral for F_dr,in
            std::printf("plastic white furnace η %.2f θ %4.1f: E = %.4f (closed form %.4f)\n", ior, theta, e, closed);
        }
    }
    // Rough: E = R_coat(θ) + T(θ) 2 ∫ T(μ) μ dμ / (η² (1 − R_int)), R_coat the coat's
    // single-scattering reflectance (scene/material_tables, double), T the table as
    // interpolated.
    for (bool beckmann : {false, true})
        for (float alpha : {0.05f, 0.3f, 0.8f}) {
            const float ior = 1.5f;
            MaterialData m = plastic(MaterialKind::RoughPlastic, 1.0f, ior, alpha, beckmann);
            std::vector<float> t = tables_of(MaterialKind::RoughPlastic, 1.0f, ior, alpha, beckmann);
            m.table = 0;
            auto lerp_t = [&](double mu) { return double(wp_roughplastic_transmittance(t.data(), float(mu))); };
            double hemi = 0;  // 2 ∫ T(μ) μ dμ
            for (int i = 0; i < 20000; ++i) {
                double mu = (i + 0.5) / 20000;
                hemi += 2 * lerp_t(mu) * mu / 20000;
            }
            RoughCoat c;
            c.alpha = alpha;
            c.eta = ior;
            c.distribution = beckmann ? MicrofacetModel::Beckmann : MicrofacetModel::GGX;
            c.separable_g = true;
            for (double theta : {0.0, 45.0, 70.0, 85.0}) {
                float3 o = polar(theta, 0.0);
                double s = 0, s2 = 0;
                for (const auto& d : test::draw_bsdf(m, t.data(), o, 1, n, seed++)) {
                    double w = d.ok ? d.weight.x : 0.0;
                    s += w;
                    s2 += w * w;
                }
                double e = s / n, se = std::sqrt(std::max(0.0, s2 / n - e * e) / n);
                double closed = rough_interface_reflectance(c, o.z, ior) +
                                lerp_t(o.z) * hemi / (double(ior) * ior * (1 - t[WP_ROUGH_PLASTIC_RES]));
                INFO((beckmann ? "Beckmann" : "GGX") << " α " << alpha << " θ " << theta << ": E " << e << " ± "
                                                     << se << ", closed form " << closed);
                CHECK(std::abs(e - closed) < 5 * se + 2e-4);
                CHECK(closed <= 1.0 + 1e-2);
                std::printf("roughplastic white furnace %s α %.2f η 1.5 θ %4.1f: E = %.4f (closed form %.4f)\n",
                            beckmann ? "Beckmann" : "GGX", alpha, theta, e, closed);
            }
        }
}

TEST_CASE("plastic: Mitsuba's specular sampling weight from the means of both reflectances",
          "[unit][plastic]") {
    Material m;
    m.kind = MaterialKind::Plastic;
    m.albedo = glm::vec3(0.2f, 0.4f, 0.6f);
    m.specular = glm::vec3(1.0f, 0.5f, 0.0f);
    CHECK(plastic_specular_weight(m, {}) == Approx(0.5 / (0.4 + 0.5)).epsilon(1e-6));
    // An albedo texture scales the diffuse mean by the mean of its linear texels: 8-bit sRGB
    // 128 is (128/255 + 0.055)^2.4 / 1.055^2.4 = 0.21586 linear.
    Texture t;
    t.width = t.height = 2;
    t.srgb = true;
    t.texels8.assign(16, 128);
    m.albedo_map.image = 0;
    double lin = std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4);
    CHECK(plastic_specular_weight(m, {t}) == Approx(0.5 / (0.4 * lin + 0.5)).epsilon(1e-6));
    m.albedo = glm::vec3(0.0f);
    m.specular = glm::vec3(0.0f);
    CHECK(plastic_specular_weight(m, {}) == 0.5f);  // both black: either lobe
}
