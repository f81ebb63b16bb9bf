// test_accumulate.cpp — the accumulate stage alone, and the film's compensated sum.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <vector>

#include "cl/kernel.h"
#include "cl/program.h"
#include "render/film.h"
#include "render/stages/accumulate.h"
#include "shared/types.h"
#include "support.h"

using namespace wp;

namespace {

// The accumulate stage through its launcher, over a film of `pixels` pixels.
struct Accum {
    render::AccumulateStage stage;
    render::FilmBuffers film;
    ocl::Array<float4> radiance;
    int n;

    explicit Accum(int pixels, int items = 0, bool variance = false) : n(pixels) {
        auto& dev = test::device();
        stage = render::AccumulateStage(dev, render::KernelConfig{}, variance);
        film = render::FilmBuffers(dev, n, variance);
        radiance = ocl::Array<float4>::allocate(dev, items > 0 ? items : n, "radiance");
    }
    void set(const std::vector<float4>& r) { radiance.write(test::device(), r); }
    // One whole pass (or a wave of `count` items from `first_pixel`).
    void launch(int first_pixel = 0, int count = 0) {
        stage.enqueue(radiance, first_pixel, count > 0 ? count : n, n, film.segments[0], film.counters);
    }
    std::vector<FilmPixel> read() { return film.segments[0].sum.read(test::device()); }
    std::vector<FilmPixel> read_sq() { return film.segments[0].sum_sq.read(test::device()); }
    std::vector<int> read_counters() { return film.counters.read(test::device()); }
};

double total(const FilmPixel& p, int ch) {
    const float s[3] = {p.sum.x, p.sum.y, p.sum.z}, c[3] = {p.comp.x, p.comp.y, p.comp.z};
    return double(s[ch]) + double(c[ch]);
}

}  // namespace

TEST_CASE("accumulate: known contributions give exact sums and the running mean",
          "[kernel][accumulate]") {
    Accum a(4);
    // Dyadic values: every partial sum is exact in float, so the expected sums are exact.
    std::vector<std::vector<float4>> frames = {
        {{0.5f, 1.0f, 2.0f, 0}, {0.25f, 0, 0, 0}, {3.0f, 3.0f, 3.0f, 0}, {0, 0, 0.125f, 0}},
        {{1.5f, 0.0f, 2.0f, 0}, {0.25f, 1, 0, 0}, {5.0f, 1.0f, 0.0f, 0}, {0, 0, 0.375f, 0}},
        {{1.0f, 2.0f, 5.0f, 0}, {0.50f, 2, 8, 0}, {1.0f, 2.0f, 0.0f, 0}, {0, 0, 0.000f, 0}},
    };
    for (auto& f : frames) {
        a.set(f);
        a.launch();
    }
    auto film = a.read();
    const double sums[4][3] = {{3, 3, 9}, {1, 3, 8}, {9, 6, 3}, {0, 0, 0.5}};
    for (int p = 0; p < 4; ++p)
        for (int ch = 0; ch < 3; ++ch) {
            INFO("pixel " << p << " channel " << ch);
            CHECK(total(film[p], ch) == sums[p][ch]);
        }
    Image mean = render::resolve_film(film, 2, 2, 3);
    for (int p = 0; p < 4; ++p)
        for (int ch = 0; ch < 3; ++ch) CHECK(mean.rgb[3 * p + ch] == Approx(sums[p][ch] / 3.0).epsilon(1e-7));
    CHECK(a.read_counters()[WP_COUNTER_ACCUMULATE_NONFINITE] == 0);
}

TEST_CASE("accumulate: NaN and Inf samples are counted and never reach the film",
          "[kernel][accumulate]") {
    Accum a(3);
    a.set({{1, 1, 1, 0}, {2, 2, 2, 0}, {4, 4, 4, 0}});
    a.launch();
    a.set({{NAN, 1, 1, 0}, {2, INFINITY, 2, 0}, {1, 1, 1, 0}});
    a.launch();
    auto film = a.read();
    CHECK(total(film[0], 0) == 1.0);
    CHECK(total(film[1], 1) == 2.0);
    CHECK(total(film[2], 2) == 5.0);
    CHECK(a.read_counters()[WP_COUNTER_ACCUMULATE_NONFINITE] == 2);
}

TEST_CASE("accumulate: the compensated sum keeps 6+ digits over 10^6 samples",
          "[kernel][accumulate]") {
    auto& dev = test::device();
    const float value = 0.1f;  // not dyadic: a plain float sum drifts
    const int repeat = 1000000;
    const double expected = double(value) * repeat;

    // The device's compensated add (the function accumulate_film calls), 10^6 times in one
    // launch of a probe kernel.
    auto prog = ocl::Program::build(dev, "test_probes.cl");
    ocl::Kernel k(prog, "film_add_repeat");
    auto film = ocl::Array<FilmPixel>::zeros(dev, 1, "film");
    k.launch({&dev.queue}, 1, float4{value, 2.0f * value, 3.0f * value, 0.0f}, repeat, film);
    FilmPixel f = film.read(dev)[0];
    for (int ch = 0; ch < 3; ++ch) {
        double e = expected * (ch + 1);
        INFO("channel " << ch << ": " << total(f, ch) << " vs " << e);
        CHECK(std::abs(total(f, ch) - e) / e < 5e-7);
    }
    // The test has teeth: a plain float sum misses by far more than that.
    float naive = 0.0f;
    for (int i = 0; i < repeat; ++i) naive += value;
    CHECK(std::abs(naive - expected) / expected > 1e-4);

    // And the real stage, launched many times over a tiny film.
    Accum a(2);
    a.set({{value, value, value, 0}, {1.0f / 3.0f, 0.7f, 0.01f, 0}});
    const int launches = 2000;
    for (int i = 0; i < launches; ++i) a.launch();
    auto film2 = a.read();
    CHECK(std::abs(total(film2[0], 0) - double(value) * launches) / (double(value) * launches) < 1e-7);
    CHECK(std::abs(total(film2[1], 0) - double(1.0f / 3.0f) * launches) /
              (double(1.0f / 3.0f) * launches) < 1e-7);
    CHECK(std::abs(total(film2[1], 2) - double(0.01f) * launches) / (double(0.01f) * launches) < 1e-7);
}

TEST_CASE("accumulate: waves of several passes or parts of one give the film of one pass at a "
          "time, bit for bit", "[kernel][accumulate]") {
    // The path pool hands accumulate a wave of k passes (items i, i + n, ... of pixel i) or a
    // chunk of one pass; the film must hold exactly the sums of adding each pixel's samples
    // one pass at a time, in sample order.
    const int n = 37, passes = 5;
    test::Rng rng(17);
    std::vector<std::vector<float4>> samples(passes, std::vector<float4>(n));
    for (auto& pass : samples)
        for (auto& x : pass) x = {float(rng.uniform()), float(rng.uniform()) * 0.1f, float(rng.uniform()) * 7.0f, 0};
    Accum one(n, 0, true);  // the reference: one pass per launch
    for (auto& pass : samples) {
        one.set(pass);
        one.launch();
    }
    Accum waves(n, 3 * n, true);  // passes 0-2 in one wave, 3-4 in chunks of 10 pixels
    std::vector<float4> w3;
    for (int p = 0; p < 3; ++p) w3.insert(w3.end(), samples[p].begin(), samples[p].end());
    waves.set(w3);
    waves.launch(0, 3 * n);
    for (int p = 3; p < passes; ++p)
        for (int first = 0; first < n; first += 10) {
            int c = std::min(10, n - first);
            waves.set(std::vector<float4>(samples[p].begin() + first, samples[p].begin() + first + c));
            waves.launch(first, c);
        }
    auto a = one.read(), b = waves.read();
    auto a2 = one.read_sq(), b2 = waves.read_sq();
    REQUIRE(std::memcmp(a.data(), b.data(), n * sizeof(FilmPixel)) == 0);
    REQUIRE(std::memcmp(a2.data(), b2.data(), n * sizeof(FilmPixel)) == 0);
    // Against an independent sum in double: the film's double-float pair is within 1e-7.
    for (int p = 0; p < n; ++p) {
        double e = 0.0;
        for (int k = 0; k < passes; ++k) e += double(samples[k][p].z);
        CHECK(std::abs(total(b[p], 2) - e) <= 1e-7 * e);
    }
}
