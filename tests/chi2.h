// chi2.h — χ² goodness-of-fit helpers shared by the sampling tests: the p-value of binned
// counts (bins with expected < 5 pooled, as pbrt-v4's tests do) and expected bin
// probabilities of a direction density over a (theta, phi) grid by midpoint quadrature.
#pragma once

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include <glm/glm.hpp>

namespace wp::test {

// Regularised upper incomplete gamma Q(a, x) (Numerical Recipes, 3rd ed., 6.2: series for
// x < a + 1, continued fraction otherwise); the χ² p-value is Q(dof / 2, χ² / 2).
inline double gamma_q(double a, double x) {
    if (x <= 0.0) return 1.0;
    double gln = std::lgamma(a);
    if (x < a + 1.0) {
        double ap = a, sum = 1.0 / a, del = sum;
        for (int n = 0; n < 10000; ++n) {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if (std::abs(del) < std::abs(sum) * 1e-15) break;
        }
        return 1.0 - sum * std::exp(-x + a * std::log(x) - gln);
    }
    double b = x + 1.0 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < 1e-300) d = 1e-300;
        c = b + an / c;
        if (std::abs(c) < 1e-300) c = 1e-300;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < 1e-15) break;
    }
    return std::exp(-x + a * std::log(x) - gln) * h;
}

// χ² test of observed against expected counts; bins with expected < 5 are pooled (pbrt).
// Returns the p-value.
inline double chi2_pvalue(const std::vector<double>& observed, const std::vector<double>& expected,
                   int* dof_out = nullptr) {
    std::vector<std::size_t> idx(observed.size());
    std::iota(idx.begin(), idx.end(), 0);
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return expected[a] < expected[b]; });
    double pooled_o = 0, pooled_e = 0, chi2 = 0;
    int bins = 0;
    for (std::size_t i : idx) {
        if (expected[i] == 0.0) {
            if (observed[i] > 0) return 0.0;  // a sample where the density is 0
            continue;
        }
        if (expected[i] < 5.0) {
            pooled_o += observed[i];
            pooled_e += expected[i];
            continue;
        }
        double d = observed[i] - expected[i];
        chi2 += d * d / expected[i];
        ++bins;
    }
    if (pooled_e > 0) {
        double d = pooled_o - pooled_e;
        chi2 += d * d / pooled_e;
        ++bins;
    }
    int dof = bins - 1;
    if (dof_out) *dof_out = dof;
    return gamma_q(dof / 2.0, chi2 / 2.0);
}

template <typename Pdf>
std::vector<double> bin_probabilities(int n_theta, int n_phi, Pdf pdf) {
    std::vector<double> p(n_theta * n_phi, 0.0);
    const int sub = 8;
    double dt = M_PI / n_theta, dp = 2 * M_PI / n_phi;
    for (int i = 0; i < n_theta; ++i)
        for (int j = 0; j < n_phi; ++j) {
            double s = 0;
            for (int a = 0; a < sub; ++a)
                for (int b = 0; b < sub; ++b) {
                    double th = (i + (a + 0.5) / sub) * dt, ph = (j + (b + 0.5) / sub) * dp;
                    glm::dvec3 w(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
                    s += pdf(w) * std::sin(th);
                }
            p[i * n_phi + j] = s * (dt / sub) * (dp / sub);
        }
    return p;
}

inline int bin_of(glm::dvec3 w, int n_theta, int n_phi) {
    double th = std::acos(std::clamp(w.z, -1.0, 1.0));
    double ph = std::atan2(w.y, w.x);
    if (ph < 0) ph += 2 * M_PI;
    int i = std::min(n_theta - 1, static_cast<int>(th / M_PI * n_theta));
    int j = std::min(n_phi - 1, static_cast<int>(ph / (2 * M_PI) * n_phi));
    return i * n_phi + j;
}

}  // namespace wp::test
