#include "scene/material_tables.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/glm.hpp>

#include "shared/types.h"

namespace wp {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n from the Chebyshev guesses).
std::pair<std::vector<double>, std::vector<double>> gauss_legendre01(int n) {
    std::vector<double> x(n), w(n);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            double dz = p1 / dp;
            z -= dz;
            if (std::abs(dz) < 1e-15) break;
        }
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp);  // 2 / ((1 - z²) P'²) on [-1, 1], halved
    }
    return {x, w};
}

// The isotropic distribution in double precision (the same definitions as
// kernels/shared/microfacet.h, written independently of it).
struct Dist {
    double a;
    bool beckmann;
    bool separable;

    double lambda(const glm::dvec3& v) const {
        double t2 = a * a * (v.x * v.x + v.y * v.y) / (v.z * v.z);
        if (!beckmann) return 0.5 * (-1.0 + std::sqrt(1.0 + t2));
        if (!(t2 > 0.0)) return 0.0;
        double b = 1.0 / std::sqrt(t2);
        return 0.5 * (std::erf(b) - 1.0) + std::exp(-b * b) / (2.0 * b * std::sqrt(kPi));
    }
    double g1(const glm::dvec3& v) const { return 1.0 / (1.0 + lambda(v)); }
    // G(w, v) / G1(w), v mirrored to the upper side.
    double g_ratio(const glm::dvec3& w, glm::dvec3 v) const {
        v.z = std::abs(v.z);
        if (separable) return g1(v);
        return (1.0 + lambda(w)) / (1.0 + lambda(w) + lambda(v));
    }
    // tan² θ_h of the sampling coordinate u in [0, 1) (density D cos θ_h).
    double tan2(double u) const {
        return beckmann ? -a * a * std::log1p(-u) : a * a * u / (1.0 - u);
    }
};

// Fresnel reflectance at cos θ = c > 0 for relative index eta = η_t / η_i; *ct the cosine of
// the refracted direction (0 with total internal reflection).
double fresnel(double c, double eta, double* ct) {
    double s2 = (1.0 - c * c) / (eta * eta);
    if (s2 >= 1.0) {
        *ct = 0.0;
        return 1.0;
    }
    double t = std::sqrt(1.0 - s2);
    *ct = t;
    double rs = (c - eta * t) / (c + eta * t), rp = (eta * c - t) / (eta * c + t);
    return 0.5 * (rs * rs + rp * rp);
}

// ∫ D_w(h) X(h) dh for X = the reflected (reflect = true) or transmitted energy, by a
// product Gauss-Legendre rule: u = 1 − (1 − s)² (which removes the 1 / cos θ_h endpoint
// behaviour of D_w / (D cos θ_h)) and φ over [0, π] (the integrand is even in φ).
double interface_integral(const RoughCoat& c, double mu, double eta, bool reflect) {
    constexpr int kNu = 160, kNphi = 96;
    static const auto gu = gauss_legendre01(kNu);
    static const auto gp = gauss_legendre01(kNphi);
    Dist dist{c.alpha, c.distribution == MicrofacetModel::Beckmann, c.separable_g};
    mu = std::clamp(mu, 1e-6, 1.0);
    glm::dvec3 w(std::sqrt(std::max(0.0, 1.0 - mu * mu)), 0.0, mu);
    double g1w = dist.g1(w);
    double sum = 0.0;
    for (int i = 0; i < kNu; ++i) {
        double s = gu.first[i];
        double u = 1.0 - (1.0 - s) * (1.0 - s), du = 2.0 * (1.0 - s) * gu.second[i];
        double t2 = dist.tan2(u);
        double cos_h = 1.0 / std::sqrt(1.0 + t2), sin_h = std::sqrt(t2) * cos_h;
        if (!(cos_h > 0.0)) continue;
        for (int j = 0; j < kNphi; ++j) {
            double phi = kPi * gp.first[j];
            glm::dvec3 h(sin_h * std::cos(phi), sin_h * std::sin(phi), cos_h);
            double wh = glm::dot(w, h);
            if (!(wh > 0.0)) continue;
            // D_w(h) / (D(h) cos θ_h) and the measure du dφ / (2π), φ folded: dφ / π.
            double base = g1w * wh / (mu * cos_h) * du * gp.second[j];
            double ct;
            double f = fresnel(wh, eta, &ct);
            double x = 0.0;
            if (reflect) {
                glm::dvec3 r = 2.0 * wh * h - w;
                if (r.z > 0.0) x = f * dist.g_ratio(w, r);
            } else if (f < 1.0) {
                glm::dvec3 t = h * (wh / eta - ct) - w / eta;
                if (t.z < 0.0) x = (1.0 - f) * dist.g_ratio(w, t);
            }
            sum += base * x;
        }
    }
    return sum;
}

}  // namespace

RoughCoat rough_coat(const Material& m) {
    RoughCoat c;
    c.alpha = m.alpha_v ? std::sqrt(double(m.alpha) * double(*m.alpha_v)) : double(m.alpha);
    c.eta = m.ior;
    c.distribution = m.distribution;
    c.separable_g = m.separable_g;
    return c;
}

double rough_interface_reflectance(const RoughCoat& c, double mu, double eta) {
    return interface_integral(c, mu, eta, true);
}

double rough_interface_transmittance(const RoughCoat& c, double mu, double eta) {
    return interface_integral(c, mu, eta, false);
}

std::vector<float> rough_plastic_table(const RoughCoat& c) {
    const int n = WP_ROUGH_PLASTIC_RES;
    std::vector<float> t(WP_ROUGH_PLASTIC_TABLE_SIZE);
    double r_int = 0.0;
    for (int k = 0; k < n; ++k) {
        double mu = std::max(1e-6, double(k) / double(n - 1));
        t[k] = static_cast<float>(rough_interface_transmittance(c, mu, c.eta));
        r_int += rough_interface_reflectance(c, mu, 1.0 / c.eta) * mu;
    }
    t[n] = static_cast<float>(2.0 * r_int / n);
    return t;
}

MaterialTables build_material_tables(const Scene& scene) {
    MaterialTables mt;
    mt.table.assign(scene.materials.size(), -1);
    std::vector<std::pair<RoughCoat, int>> done;
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        if (m.kind != MaterialKind::RoughPlastic) continue;
        RoughCoat c = rough_coat(m);
        auto it = std::find_if(done.begin(), done.end(), [&](const auto& p) { return p.first == c; });
        if (it != done.end()) {
            mt.table[i] = it->second;
            continue;
        }
        int offset = static_cast<int>(mt.data.size());
        std::vector<float> t = rough_plastic_table(c);
        mt.data.insert(mt.data.end(), t.begin(), t.end());
        done.emplace_back(c, offset);
        mt.table[i] = offset;
    }
    return mt;
}

}  // namespace wp
