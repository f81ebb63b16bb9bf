// test_accumulate.cpp — the accumulate stage alone, and the film's compensated sum.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "cl/profiler.h"
#include "cl/program.h"
#include "render/film.h"
#include "shared/types.h"
#include "support.h"

using namespace wp;

namespace {

struct Accum {
    ocl::Program prog;
    cl::Kernel k;
    cl::Buffer radiance, film, counters;
    int n;

    explicit Accum(int pixels) : n(pixels) {
        auto& dev = test::device();
        prog = ocl::Program::build(dev, "accumulate.cl");
        k = prog.kernel("accumulate_film");
        radiance = cl::Buffer(dev.context, CL_MEM_READ_WRITE, n * sizeof(float4));
        film = cl::Buffer(dev.context, CL_MEM_READ_WRITE, n * sizeof(FilmPixel));
        counters = cl::Buffer(dev.context, CL_MEM_READ_WRITE, WP_COUNTER_COUNT * sizeof(int));
        dev.queue.enqueueFillBuffer(film, 0.0f, 0, n * sizeof(FilmPixel));
        dev.queue.enqueueFillBuffer(counters, 0, 0, WP_COUNTER_COUNT * sizeof(int));
        k.setArg(0, radiance);
        k.setArg(1, n);
        k.setArg(2, film);
        k.setArg(3, counters);
    }
    void set(const std::vector<float4>& r) {
        test::device().queue.enqueueWriteBuffer(radiance, CL_TRUE, 0, n * sizeof(float4), r.data());
    }
    void launch() { ocl::launch(test::device().queue, k, "accumulate", n); }
    std::vector<FilmPixel> read() {
        std::vector<FilmPixel> f(n);
        test::device().queue.enqueueReadBuffer(film, CL_TRUE, 0, n * sizeof(FilmPixel), f.data());
        return f;
    }
    std::vector<int> read_counters() {
        std::vector<int> c(WP_COUNTER_COUNT);
        test::device().queue.enqueueReadBuffer(counters, CL_TRUE, 0, c.size() * sizeof(int), c.data());
        return c;
    }
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
    auto k = prog.kernel("film_add_repeat");
    cl::Buffer film(dev.context, CL_MEM_READ_WRITE, sizeof(FilmPixel));
    dev.queue.enqueueFillBuffer(film, 0.0f, 0, sizeof(FilmPixel));
    k.setArg(0, float4{value, 2.0f * value, 3.0f * value, 0.0f});
    k.setArg(1, repeat);
    k.setArg(2, film);
    ocl::launch(dev.queue, k, "film_add_repeat", 1);
    FilmPixel f;
    dev.queue.enqueueReadBuffer(film, CL_TRUE, 0, sizeof(f), &f);
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
