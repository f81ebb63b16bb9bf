// materials_support.h — helpers of the material tests (test_materials_*.cpp): the shared
// BSDF code compiled as host C++ (with the shipped estimator, like test_sampling.cpp, so
// every translation unit sees the same inline definitions), local directions, and a χ² test
// of a kind's sampling against its own eval() density over the whole sphere.
#pragma once

#define WP_SAMPLING 3
#define WP_GLOSSY_MODEL 1
#include "shared/bsdf.h"

#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "chi2.h"
#include "support.h"

namespace wp::test {

constexpr double kPiD = 3.14159265358979323846;

// The unit direction (θ, φ) in degrees, local frame (normal +z).
inline float3 polar(double theta_deg, double phi_deg) {
    double t = theta_deg * kPiD / 180.0, p = phi_deg * kPiD / 180.0;
    return make_float3(float(std::sin(t) * std::cos(p)), float(std::sin(t) * std::sin(p)),
                       float(std::cos(t)));
}
inline glm::dvec3 dvec(float3 v) { return {v.x, v.y, v.z}; }
inline float3 fvec(glm::dvec3 v) { return make_float3(float(v.x), float(v.y), float(v.z)); }

// One BSDF sample: ok = 0 when absorbed.
struct BsdfDraw {
    int ok = 0;
    float3 wo{}, weight{};
    float pdf = 0.0f;
    int specular = 0;
};

// n samples of m for the viewer direction o (towards the viewer, local, o.z > 0) with the
// normal +z, through bsdf.h's dispatch.
inline std::vector<BsdfDraw> draw_bsdf(const MaterialData& m, const float* tables, float3 o,
                                       int front, int n, std::uint64_t seed) {
    Rng rng(seed);
    std::vector<BsdfDraw> out(n);
    float3 d = make_float3(-o.x, -o.y, -o.z), ns = make_float3(0.0f, 0.0f, 1.0f);
    for (int i = 0; i < n; ++i) {
        float4 u = make_float4(rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
        BsdfDraw& s = out[i];
        s.ok = wp_bsdf_sample_pdf(m, tables, d, ns, front, u, &s.wo, &s.weight, &s.pdf, &s.specular);
    }
    return out;
}

// eval() of m for viewer o and light direction i (local, normal +z): f |cos θi| and *pdf.
inline float3 eval_bsdf(const MaterialData& m, const float* tables, float3 o, float3 i, int front,
                        float* pdf) {
    return wp_bsdf_eval(m, tables, make_float3(-o.x, -o.y, -o.z), make_float3(0.0f, 0.0f, 1.0f),
                        front, i, pdf);
}

// Expected bin probabilities of a direction density over the (θ, φ) grid of chi2.h's
// bin_of, by the midpoint rule on sub × sub points per bin (finer than chi2.h's 8 × 8: the
// absorbed bin's expectation is 1 minus the sum of all bins, so their quadrature error adds
// up there).
template <typename Pdf>
std::vector<double> fine_bin_probabilities(int n_theta, int n_phi, Pdf pdf, int sub = 24) {
    std::vector<double> p(n_theta * n_phi, 0.0);
    double dt = kPiD / n_theta, dp = 2 * kPiD / n_phi;
    for (int i = 0; i < n_theta; ++i)
        for (int j = 0; j < n_phi; ++j) {
            double s = 0;
            for (int a = 0; a < sub; ++a) {
                double th = (i + (a + 0.5) / sub) * dt, st = std::sin(th), ct = std::cos(th);
                for (int b = 0; b < sub; ++b) {
                    double ph = (j + (b + 0.5) / sub) * dp;
                    s += pdf(glm::dvec3(st * std::cos(ph), st * std::sin(ph), ct)) * st;
                }
            }
            p[i * n_phi + j] = s * (dt / sub) * (dp / sub);
        }
    return p;
}

struct Chi2Result {
    double p = 0.0;
    int dof = 0;
    double absorbed = 0, absorbed_expected = 0;   // counts
    double dirac = 0, dirac_expected = 0;         // counts
};

// χ² of the non-Dirac draws against eval()'s density over an nt × np (θ over [0, π]) grid,
// with one bin for absorbed draws (expected: what the density does not cover, less the
// Dirac probability) and one for Dirac draws (expected: p_dirac).
inline Chi2Result chi2_against_eval(const std::vector<BsdfDraw>& draws, const MaterialData& m,
                                    const float* tables, float3 o, int front, double p_dirac,
                                    int nt = 40, int np = 40) {
    const double n = double(draws.size());
    auto prob = fine_bin_probabilities(nt, np, [&](glm::dvec3 w) {
        float pdf = 0.0f;
        eval_bsdf(m, tables, o, fvec(w), front, &pdf);
        return double(pdf);
    });
    std::vector<double> obs(nt * np + 2, 0.0), expct(nt * np + 2, 0.0);
    double covered = 0;
    for (int i = 0; i < nt * np; ++i) {
        expct[i] = prob[i] * n;
        covered += prob[i];
    }
    Chi2Result r;
    r.absorbed_expected = expct[nt * np] = std::max(0.0, 1.0 - covered - p_dirac) * n;
    r.dirac_expected = expct[nt * np + 1] = p_dirac * n;
    for (const BsdfDraw& s : draws) {
        if (!s.ok)
            obs[nt * np] += 1;
        else if (s.specular)
            obs[nt * np + 1] += 1;
        else
            obs[bin_of(dvec(s.wo), nt, np)] += 1;
    }
    r.absorbed = obs[nt * np];
    r.dirac = obs[nt * np + 1];
    r.p = chi2_pvalue(obs, expct, &r.dof);
    return r;
}

}  // namespace wp::test
