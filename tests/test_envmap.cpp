// test_envmap.cpp — the environment light (kernels/shared/envmap.h compiled as host C++,
// scene/envmap.cpp): the direction <-> texel mapping against Mitsuba 3's envmap formula
// written here from scratch in double precision, bilinear filtering, the sampling tables
// against weights computed here, χ² goodness of fit of wp_env_sample against wp_env_pdf,
// normalisation by quadrature, closed-form irradiance by Monte Carlo, and bad input.
//
// χ² tests: bins with < 5 expected pooled (tests/chi2.h), family-wise α = 0.01 Šidák-
// corrected over the kChi2Tests tests of this file.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "shared/envmap.h"

#include "scene/envmap.h"
#include "util/error.h"
#include "chi2.h"
#include "support.h"

using namespace wp;

namespace {

constexpr int kChi2Tests = 2;
const double kAlpha = 1.0 - std::pow(1.0 - 0.01, 1.0 / kChi2Tests);

// A float RGBA map from a function of the texel (column i, row j).
Texture make_map(int w, int h, const std::function<glm::dvec3(int, int)>& f,
                 const std::string& name = "test.exr") {
    Texture t;
    t.source = name;
    t.width = w;
    t.height = h;
    t.texelsf.resize(std::size_t(w) * h * 4);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            glm::dvec3 c = f(i, j);
            float* p = &t.texelsf[(std::size_t(j) * w + i) * 4];
            p[0] = float(c.x), p[1] = float(c.y), p[2] = float(c.z), p[3] = 1.0f;
        }
    return t;
}

// The device's view of an upload (pointers into its vectors).
EnvLight view(const EnvUpload& up) {
    return EnvLight{up.data, up.texels.data(), up.marginal.data(), up.conditional.data()};
}

EnvUpload upload(const Texture& t, glm::dmat3 to_world = glm::dmat3(1.0), float scale = 1.0f) {
    Environment env;
    env.image = 0;
    env.scale = scale;
    env.to_world = glm::mat3(to_world);
    std::vector<std::string> warnings;
    return upload_environment(env, t, warnings);
}

glm::dmat3 rot(double deg, glm::dvec3 axis) {
    return glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(deg), glm::normalize(axis)));
}

float3 f3(glm::dvec3 v) { return make_float3(float(v.x), float(v.y), float(v.z)); }
glm::dvec3 d3(float3 v) { return {v.x, v.y, v.z}; }

// Mitsuba 3's envmap eval (src/emitters/envmap.cpp: direction_to_uv, eval_spectrum), from
// scratch in double: the image gets an extra column equal to its first, u is shifted by
// half a texel and wrapped, uv scaled by (W, H - 1), bilinear between the four samples.
glm::dvec3 mitsuba_eval(const Texture& t, const glm::dmat3& to_world, double scale, glm::dvec3 dir) {
    const int w = t.width, h = t.height, wp1 = w + 1;
    auto sample = [&](int x, int y) {  // the padded (w + 1) x h image
        int xs = x == w ? 0 : x;
        const float* p = &t.texelsf[(std::size_t(y) * w + xs) * 4];
        return glm::dvec3(p[0], p[1], p[2]);
    };
    glm::dvec3 d = glm::inverse(to_world) * dir;
    double u = std::atan2(d.x, -d.z) / (2 * M_PI);
    double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / M_PI;
    u -= 0.5 / (wp1 - 1);
    u -= std::floor(u);
    v -= std::floor(v);
    double x = u * (wp1 - 1), y = v * (h - 1);
    int px = std::min(int(x), wp1 - 2), py = std::min(int(y), h - 2);
    double fx = x - px, fy = y - py;
    glm::dvec3 v0 = (1 - fx) * sample(px, py) + fx * sample(px + 1, py);
    glm::dvec3 v1 = (1 - fx) * sample(px, py + 1) + fx * sample(px + 1, py + 1);
    return ((1 - fy) * v0 + fy * v1) * scale;
}

// Map-frame direction of Mitsuba's uv (uv_to_direction).
glm::dvec3 uv_direction(double u, double v) {
    double th = M_PI * v, ph = 2 * M_PI * u;
    return {std::sin(ph) * std::sin(th), std::cos(th), -std::cos(ph) * std::sin(th)};
}

double lum(glm::dvec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// Uniform floats in [0, 1) with 24 random bits.
struct Uniform {
    std::mt19937_64 rng;
    explicit Uniform(std::uint64_t seed) : rng(seed) {}
    float operator()() { return float(rng() >> 40) * 0x1p-24f; }
};

// The χ² test's map: a horizontal gradient, a bright spot, a black block; 24 x 10 (not 2:1).
Texture spot_map() {
    return make_map(24, 10, [](int i, int j) {
        if (i >= 15 && i < 20 && j >= 6) return glm::dvec3(0.0);
        double g = 0.2 + 0.8 * i / 24.0;
        double s = 50.0 * std::exp(-((i - 6) * (i - 6) + (j - 3) * (j - 3)) / 2.0);
        return glm::dvec3(g + s, 0.5 * g + s, 0.3 + 0.2 * s);
    }, "spot.exr");
}
// A 2:1 map whose top three rows are black and whose left half is dim.
Texture half_black_map() {
    return make_map(32, 16, [](int i, int j) {
        if (j < 3) return glm::dvec3(0.0);
        double b = i < 16 ? 0.05 : 2.0 + std::sin(0.7 * i) + 0.1 * j;
        return glm::dvec3(b, 0.8 * b, 1.2 * b);
    }, "half.exr");
}

// ∫ pdf dω over the sphere: midpoint rule on an n x 2n (θ, φ) grid around world +z.
double integrate_pdf(const EnvLight& env, int n) {
    double sum = 0.0, dt = M_PI / n, dp = M_PI / n;
    for (int a = 0; a < n; ++a) {
        double th = (a + 0.5) * dt, st = std::sin(th), ct = std::cos(th);
        for (int b = 0; b < 2 * n; ++b) {
            double ph = (b + 0.5) * dp;
            glm::dvec3 w(st * std::cos(ph), st * std::sin(ph), ct);
            sum += wp_env_pdf(env, f3(w)) * st;
        }
    }
    return sum * dt * dp;
}

// χ² of n samples of wp_env_sample in nt x np world bins against wp_env_pdf integrated
// over each bin (sub x sub midpoint quadrature). Also: every sample has a positive density
// that wp_env_pdf reproduces (to float rounding, except rarely at cell edges).
void chi2_test(const EnvLight& env, int n, int nt, int np, int sub, std::uint64_t seed) {
    std::vector<double> obs(nt * np, 0.0);
    Uniform rnd(seed);
    int mismatched = 0, bad = 0;
    for (int k = 0; k < n; ++k) {
        float pdf = -1;
        float u1 = rnd(), u2 = rnd();
        float3 d = wp_env_sample(env, u1, u2, &pdf);
        glm::dvec3 w = d3(d);
        if (!(pdf > 0) || !(std::abs(glm::length(w) - 1.0) < 1e-5)) {
            ++bad;
            continue;
        }
        obs[test::bin_of(w, nt, np)] += 1;
        float q = wp_env_pdf(env, d);
        if (std::abs(q - pdf) > 1e-3 * pdf) ++mismatched;
    }
    CHECK(bad == 0);
    CHECK(mismatched <= n / 10000);
    std::vector<double> expct(nt * np, 0.0);
    double dt = M_PI / nt, dp = 2 * M_PI / np, total = 0.0;
    for (int i = 0; i < nt; ++i)
        for (int j = 0; j < np; ++j) {
            double s = 0.0;
            for (int a = 0; a < sub; ++a) {
                double th = (i + (a + 0.5) / sub) * dt, st = std::sin(th);
                for (int b = 0; b < sub; ++b) {
                    double ph = (j + (b + 0.5) / sub) * dp;
                    glm::dvec3 w(st * std::cos(ph), st * std::sin(ph), std::cos(th));
                    s += wp_env_pdf(env, f3(w)) * st;
                }
            }
            expct[i * np + j] = s * (dt / sub) * (dp / sub) * n;
            total += expct[i * np + j];
        }
    CHECK(total / n == Approx(1.0).epsilon(2e-3));
    int dof = 0;
    double p = test::chi2_pvalue(obs, expct, &dof);
    INFO("chi2 p-value " << p << " with " << dof << " degrees of freedom, alpha " << kAlpha);
    CHECK(dof > nt * np / 2);
    CHECK(p > kAlpha);
}

}  // namespace

TEST_CASE("envmap: directions land on the texels of Mitsuba 3's mapping", "[unit][envmap]") {
    // R: (i + 1)² + 100 j identifies the column and the row; G: the row alone.
    Texture t = make_map(8, 5, [](int i, int j) { return glm::dvec3((i + 1) * (i + 1) + 100.0 * j, j + 1, 1); });
    auto r = [](const EnvLight& env, glm::dvec3 d) { return d3(wp_env_radiance(env, f3(glm::normalize(d)))); };

    EnvUpload up = upload(t);
    EnvLight env = view(up);
    // Columns sit at u = (i + 1/2) / 8, u = 0 at -z growing towards +x; the horizon is row 2
    // of rows at v = j / 4.
    CHECK(r(env, {0, 0, -1}).x == Approx(0.5 * (64 + 1) + 200));   // u = 0: columns 7 and 0
    CHECK(r(env, {1, 0, 0}).x == Approx(0.5 * (4 + 9) + 200));     // u = 1/4: columns 1, 2
    CHECK(r(env, {0, 0, 1}).x == Approx(0.5 * (16 + 25) + 200));   // u = 1/2: columns 3, 4
    CHECK(r(env, {-1, 0, 0}).x == Approx(0.5 * (36 + 49) + 200));  // u = 3/4: columns 5, 6
    CHECK(r(env, {0, 1, 0}).y == Approx(1));   // +y: row 0 (v = 0)
    CHECK(r(env, {0, -1, 0}).y == Approx(5));  // -y: the last row (v = 1)
    // A texel's own position: column 3, row 1 (θ = 45°).
    CHECK(r(env, uv_direction(3.5 / 8, 0.25)).x == Approx(16 + 100));
    // Row 1 and 2 mixed 1:2 at v = 1/3 + 1/12 (θ = 75°), column 5.
    CHECK(r(env, uv_direction(5.5 / 8, 5.0 / 12)).x == Approx(36 + 100 * (1 + 2.0 / 3)));
    // Across the seam u wraps: just either side of -z, columns 7 and 0 blend.
    CHECK(r(env, uv_direction(0.01, 0.5)).x == Approx((1 - 0.58) * 64 + 0.58 * 1 + 200));
    CHECK(r(env, uv_direction(-0.01, 0.5)).x == Approx(0.58 * 64 + 0.42 * 1 + 200));
    CHECK(r(env, uv_direction(0.5 / 8, 0.5)).x == Approx(1 + 200));  // column 0 itself

    // to_world: a quarter turn about +y takes the map's +z to world +x, +x to world -z.
    glm::dmat3 turn = rot(90, {0, 1, 0});
    REQUIRE(glm::length(turn * glm::dvec3(0, 0, 1) - glm::dvec3(1, 0, 0)) < 1e-12);
    EnvUpload upr = upload(t, turn, 2.0f);
    EnvLight envr = view(upr);
    CHECK(r(envr, {1, 0, 0}).x == Approx(2 * (0.5 * (16 + 25) + 200)));   // map +z: u = 1/2
    CHECK(r(envr, {0, 0, -1}).x == Approx(2 * (0.5 * (4 + 9) + 200)));    // map +x: u = 1/4
    CHECK(r(envr, {0, 0, 1}).x == Approx(2 * (0.5 * (36 + 49) + 200)));   // map -x: u = 3/4
    CHECK(r(envr, {-1, 0, 0}).x == Approx(2 * (0.5 * (64 + 1) + 200)));  // map -z: u = 0

    // Everywhere: Mitsuba's formula in double, under an arbitrary rotation.
    glm::dmat3 any = rot(70, {0.3, -1, 0.5});
    EnvUpload upa = upload(t, any, 0.5f);
    EnvLight enva = view(upa);
    test::Rng rng(7);
    for (int k = 0; k < 2000; ++k) {
        glm::dvec3 d = glm::dvec3(rng.unit_vector());
        glm::dvec3 want = mitsuba_eval(t, any, 0.5, d), got = r(enva, d);
        INFO("direction " << d.x << " " << d.y << " " << d.z);
        CHECK(got.x == Approx(want.x).epsilon(1e-4).margin(1e-3));
        CHECK(got.y == Approx(want.y).epsilon(1e-4).margin(1e-4));
        CHECK(got.z == Approx(want.z).epsilon(1e-4).margin(1e-4));
    }
}

TEST_CASE("envmap: bilinear lookup of a two-value map", "[unit][envmap]") {
    const double a = 1.0, b = 3.0;
    Texture t = make_map(4, 3, [&](int i, int j) { return glm::dvec3((i + j) % 2 ? b : a); });
    EnvUpload up = upload(t);
    EnvLight env = view(up);
    auto texel = [&](int i, int j) { return (((i % 4) + j) % 2) ? b : a; };
    // Grid coordinates (x, y): column x at u = (x + 1/2) / 4, row y at v = y / 2.
    const double pts[][2] = {{0.25, 0.25}, {0.5, 0.5}, {1.0, 1.0}, {2.75, 0.1},
                             {3.5, 1.5},   {3.9, 0.6}, {0.0, 2.0}, {1.3, 1.99}};
    for (auto& p : pts) {
        double x = p[0], y = p[1];
        int i = int(x), j = std::min(int(y), 1);
        double fx = x - i, fy = y - j;
        double want = (1 - fx) * (1 - fy) * texel(i, j) + fx * (1 - fy) * texel(i + 1, j) +
                      (1 - fx) * fy * texel(i, j + 1) + fx * fy * texel(i + 1, j + 1);
        float3 got = wp_env_radiance(env, f3(uv_direction((x + 0.5) / 4, y / 2)));
        INFO("grid point " << x << ", " << y);
        CHECK(got.x == Approx(want).epsilon(1e-5));
        CHECK(got.y == got.x);
    }
}

TEST_CASE("envmap: sampling tables weigh cells by their brightest corner and sin θ",
          "[unit][envmap]") {
    Texture t = spot_map();
    glm::dmat3 to_world = rot(90, {1, 0, 0}) * rot(37, {0, 1, 0});
    EnvUpload up = upload(t, to_world);
    EnvLight env = view(up);
    const int w = t.width, rows = t.height - 1;
    REQUIRE(up.marginal.size() == std::size_t(rows));
    REQUIRE(up.conditional.size() == std::size_t(rows) * w);
    CHECK(up.marginal.back() == 1.0f);
    auto L = [&](int i, int j) {
        const float* p = &t.texelsf[(std::size_t(j) * w + (i % w)) * 4];
        return lum({p[0], p[1], p[2]});
    };
    std::vector<double> wt(rows * w);
    double total = 0.0;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < w; ++c) {
            double m = std::max({L(c, r), L(c + 1, r), L(c, r + 1), L(c + 1, r + 1)});
            wt[r * w + c] = m * std::sin(M_PI * (r + 0.5) / rows);
            total += wt[r * w + c];
        }
    int zero = 0;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < w; ++c) {
            // The cell's centre: u = (c + 1) / w, v = (r + 1/2) / rows.
            double v = (r + 0.5) / rows;
            glm::dvec3 d = to_world * uv_direction((c + 1.0) / w, v);
            double want = wt[r * w + c] / total * w * rows / (2 * M_PI * M_PI * std::sin(M_PI * v));
            float got = wp_env_pdf(env, f3(d));
            INFO("cell " << r << ", " << c);
            CHECK(got == Approx(want).epsilon(1e-4).margin(1e-6));
            zero += want == 0.0;
        }
    CHECK(zero > 0);  // the black block's inner cells
    // Non-zero radiance implies non-zero density (the brightest-corner bound).
    test::Rng rng(11);
    int violations = 0;
    for (int k = 0; k < 20000; ++k) {
        float3 d = f3(glm::dvec3(rng.unit_vector()));
        float3 l = wp_env_radiance(env, d);
        violations += (l.x > 0 || l.y > 0 || l.z > 0) && !(wp_env_pdf(env, d) > 0);
    }
    CHECK(violations == 0);
}

TEST_CASE("envmap: samples follow wp_env_pdf (chi2), rotated 24x10 map with a spot",
          "[stat][envmap]") {
    Texture t = spot_map();
    // The map's +y to world +z (the bins' pole), turned 37° about it.
    EnvUpload up = upload(t, rot(90, {1, 0, 0}) * rot(37, {0, 1, 0}));
    chi2_test(view(up), 1000000, 12, 24, 64, 1);
}

TEST_CASE("envmap: samples follow wp_env_pdf (chi2), black rows and a dim half",
          "[stat][envmap]") {
    Texture t = half_black_map();
    EnvUpload up = upload(t, rot(-90, {1, 0, 0}));
    CHECK(up.marginal[0] == 0.0f);  // the black rows are never drawn
    CHECK(up.marginal[1] == 0.0f);
    chi2_test(view(up), 1000000, 12, 24, 64, 2);
}

TEST_CASE("envmap: densities integrate to 1 over the sphere", "[unit][envmap]") {
    SECTION("spot map, rotated") {
        EnvUpload up = upload(spot_map(), rot(50, {1, 1, 0}));
        CHECK(integrate_pdf(view(up), 600) == Approx(1.0).epsilon(3e-3));
    }
    SECTION("black rows, 2:1") {
        EnvUpload up = upload(half_black_map());
        CHECK(integrate_pdf(view(up), 600) == Approx(1.0).epsilon(3e-3));
    }
    SECTION("one row, one column") {
        EnvUpload up1 = upload(make_map(5, 1, [](int i, int) { return glm::dvec3(i + 1.0); }));
        CHECK(integrate_pdf(view(up1), 400) == Approx(1.0).epsilon(3e-3));
        EnvUpload up2 = upload(make_map(1, 4, [](int, int j) { return glm::dvec3(j + 1.0); }));
        CHECK(integrate_pdf(view(up2), 400) == Approx(1.0).epsilon(3e-3));
    }
}

TEST_CASE("envmap: irradiance under constant and two-value maps (Monte Carlo, closed form)",
          "[stat][envmap]") {
    // E(n) = ∫ L(ω) max(0, n·ω) dω, estimated with n_s env samples; z-test at 4 s.e.
    auto irradiance = [](const EnvLight& env, glm::dvec3 n, int ns, std::uint64_t seed,
                         glm::dvec3* se) {
        Uniform rnd(seed);
        glm::dvec3 sum(0.0), sum2(0.0);
        for (int k = 0; k < ns; ++k) {
            float pdf = 0;
            float3 d = wp_env_sample(env, rnd(), rnd(), &pdf);
            glm::dvec3 x(0.0);
            double c = glm::dot(n, d3(d));
            if (pdf > 0 && c > 0) x = d3(wp_env_radiance(env, d)) * c / double(pdf);
            sum += x;
            sum2 += x * x;
        }
        glm::dvec3 mean = sum / double(ns);
        *se = glm::sqrt((sum2 / double(ns) - mean * mean) / double(ns - 1));
        return mean;
    };
    const int ns = 100000;
    SECTION("constant map: π L") {
        const glm::dvec3 L(0.5, 1.0, 2.0);
        Texture t = make_map(16, 8, [&](int, int) { return L; });
        for (int k = 0; k < 2; ++k) {
            glm::dmat3 to_world = k == 0 ? glm::dmat3(1.0) : rot(90, {1, 0, 0});  // map +y -> world +z
            EnvUpload up = upload(t, to_world, 1.5f);
            glm::dvec3 n = to_world * glm::dvec3(0, 1, 0), se;
            glm::dvec3 e = irradiance(view(up), n, ns, 3 + k, &se);
            for (int c = 0; c < 3; ++c) {
                INFO("rotation " << k << " channel " << c << ": " << e[c] << " ± " << se[c]);
                CHECK(std::abs(e[c] - M_PI * 1.5 * L[c]) < 4 * se[c]);
                CHECK(se[c] < 0.05 * e[c]);
            }
            CHECK(up.mean_luminance == Approx(1.5 * lum(L)).epsilon(1e-9));
        }
    }
    SECTION("L1 above the horizon, L2 below: π L1 upwards") {
        // 9 rows at v = j / 8: rows 0..4 (v <= 1/2) are L1, so the bilinear radiance is L1
        // on the whole upper hemisphere; below, rows blend towards L2.
        const glm::dvec3 L1(1.0, 0.7, 0.4), L2(4.0, 5.0, 6.0);
        Texture t = make_map(18, 9, [&](int, int j) { return j <= 4 ? L1 : L2; });
        glm::dmat3 to_world = rot(25, {0, 0, 1});
        EnvUpload up = upload(t, to_world);
        glm::dvec3 n = to_world * glm::dvec3(0, 1, 0), se;
        glm::dvec3 e = irradiance(view(up), n, ns, 5, &se);
        for (int c = 0; c < 3; ++c) {
            INFO("channel " << c << ": " << e[c] << " ± " << se[c]);
            CHECK(std::abs(e[c] - M_PI * L1[c]) < 4 * se[c]);
            CHECK(se[c] < 0.05 * e[c]);
        }
    }
}

TEST_CASE("envmap: mean luminance is the sphere's average of the bilinear radiance",
          "[unit][envmap]") {
    for (int k = 0; k < 2; ++k) {
        Texture t = k == 0 ? spot_map() : make_map(6, 1, [](int i, int) { return glm::dvec3(i); });
        EnvUpload up = upload(t, rot(33, {1, 2, 3}), 2.0f);
        EnvLight env = view(up);
        // Quadrature in the map's own (u, v), fine enough for the bilinear pieces.
        const int nu = 960, nv = 900;
        double sum = 0.0;
        for (int b = 0; b < nv; ++b) {
            double v = (b + 0.5) / nv;
            for (int a = 0; a < nu; ++a) {
                glm::dvec3 d = rot(33, {1, 2, 3}) * uv_direction((a + 0.5) / nu, v);
                sum += lum(d3(wp_env_radiance(env, f3(d)))) * std::sin(M_PI * v);
            }
        }
        double mean = sum * 2 * M_PI * M_PI / (double(nu) * nv) / (4 * M_PI);
        CHECK(up.mean_luminance == Approx(mean).epsilon(1e-3));
    }
}

TEST_CASE("envmap: aspect warning, black maps, decoding and bad input", "[unit][envmap]") {
    Environment env;
    env.image = 0;
    std::vector<std::string> warnings;

    SECTION("a map that is not 2:1 is used with one warning naming it") {
        upload_environment(env, spot_map(), warnings);
        REQUIRE(warnings.size() == 1);
        CHECK(warnings[0].find("spot.exr") != std::string::npos);
        CHECK(warnings[0].find("24x10") != std::string::npos);
        warnings.clear();
        upload_environment(env, half_black_map(), warnings);
        CHECK(warnings.empty());
    }
    SECTION("a black map: no samples, density 0, no NaN") {
        EnvUpload up = upload_environment(env, make_map(16, 8, [](int, int) { return glm::dvec3(0); }), warnings);
        CHECK(warnings.empty());
        CHECK(std::all_of(up.marginal.begin(), up.marginal.end(), [](float x) { return x == 0.0f; }));
        CHECK(std::all_of(up.conditional.begin(), up.conditional.end(), [](float x) { return x == 0.0f; }));
        CHECK(up.mean_luminance == 0.0);
        EnvLight l = view(up);
        Uniform rnd(9);
        for (int k = 0; k < 100; ++k) {
            float pdf = -1;
            float3 d = wp_env_sample(l, rnd(), rnd(), &pdf);
            CHECK(pdf == 0.0f);
            CHECK(std::abs(glm::length(d3(d)) - 1.0) < 1e-6);
            CHECK(wp_env_pdf(l, d) == 0.0f);
            float3 rad = wp_env_radiance(l, d);
            CHECK((rad.x == 0 && rad.y == 0 && rad.z == 0));
        }
    }
    SECTION("the poles: density 0, never NaN") {
        EnvUpload up = upload_environment(env, make_map(8, 4, [](int, int) { return glm::dvec3(1); }), warnings);
        EnvLight l = view(up);
        CHECK(wp_env_pdf(l, make_float3(0, 1, 0)) == 0.0f);
        CHECK(wp_env_pdf(l, make_float3(0, -1, 0)) == 0.0f);
        float pdf = -1;
        float3 d = wp_env_sample(l, 0.0f, 0.0f, &pdf);  // v = 0 exactly: the north pole
        CHECK(pdf == 0.0f);
        CHECK(std::isfinite(d.x));
        CHECK(std::isfinite(d.y));
        CHECK(std::isfinite(d.z));
        d = wp_env_sample(l, 1.0f, 1.0f, &pdf);  // u = 1 is clamped below 1
        CHECK(pdf > 0.0f);
        CHECK(std::isfinite(pdf));
    }
    SECTION("8-bit texels are decoded; negative ones read as 0 with a warning") {
        Texture t;
        t.source = "ldr.png";
        t.width = 2;
        t.height = 1;
        t.texels8 = {128, 0, 255, 7, 10, 20, 30, 255};
        t.srgb = true;
        EnvUpload up = upload_environment(env, t, warnings);
        CHECK(up.texels[0].x == Approx(std::pow((128 / 255.0 + 0.055) / 1.055, 2.4)).epsilon(1e-6));
        CHECK(up.texels[0].y == 0.0f);
        CHECK(up.texels[0].z == 1.0f);
        CHECK(up.texels[1].x == Approx(10 / 255.0 / 12.92).epsilon(1e-6));
        t.srgb = false;
        up = upload_environment(env, t, warnings);
        CHECK(up.texels[0].x == Approx(128 / 255.0).epsilon(1e-6));
        CHECK(warnings.empty());  // 2x1 is 2:1
    }
    SECTION("errors name the file") {
        Texture empty;
        empty.source = "empty.hdr";
        CHECK_THROWS_WITH(upload_environment(env, empty, warnings), Catch::Contains("empty.hdr"));
        Texture t = make_map(4, 2, [](int, int) { return glm::dvec3(1); }, "short.exr");
        t.texelsf.pop_back();
        CHECK_THROWS_WITH(upload_environment(env, t, warnings), Catch::Contains("short.exr"));
        Texture nan = make_map(4, 2, [](int i, int) { return glm::dvec3(i == 3 ? NAN : 1.0); }, "nan.exr");
        CHECK_THROWS_WITH(upload_environment(env, nan, warnings), Catch::Contains("nan.exr") && Catch::Contains("(3, 0)"));
        Texture ok = make_map(4, 2, [](int, int) { return glm::dvec3(1); }, "ok.exr");
        Environment sheared = env;
        sheared.to_world[1] = glm::vec3(0.3f, 1.0f, 0.0f);
        CHECK_THROWS_WITH(upload_environment(sheared, ok, warnings), Catch::Contains("ok.exr") && Catch::Contains("rotation"));
        Environment neg = env;
        neg.scale = -1.0f;
        CHECK_THROWS_WITH(upload_environment(neg, ok, warnings), Catch::Contains("ok.exr"));
        // A rotation with float rounding is accepted and made orthonormal; a mirror too.
        Environment nearly = env;
        nearly.to_world = glm::mat3(rot(30, {0, 1, 0})) * 1.0000002f;
        EnvUpload up = upload_environment(nearly, ok, warnings);
        CHECK(glm::length(glm::vec3(up.data.to_local0.x, up.data.to_local0.y, up.data.to_local0.z)) == Approx(1.0f).epsilon(1e-7));
        Environment mirror = env;
        mirror.to_world[0] = glm::vec3(-1, 0, 0);
        up = upload_environment(mirror, ok, warnings);
        CHECK(up.data.to_local0.x == -1.0f);
    }
    SECTION("negative float texels") {
        Texture t = make_map(4, 2, [](int i, int) { return glm::dvec3(i == 1 ? -2.0 : 1.0); }, "neg.exr");
        EnvUpload up = upload_environment(env, t, warnings);
        REQUIRE(warnings.size() == 1);
        CHECK(warnings[0].find("neg.exr") != std::string::npos);
        CHECK(up.texels[1].x == 0.0f);
    }
}
