// test_converge.cpp — the estimator converges like an unbiased Monte Carlo estimator, and
// the film's variance is right.
#include <catch2/catch.hpp>

#include <cmath>
#include <map>
#include <vector>

#include "image/stats.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "support.h"

using namespace wp;

namespace {

render::Wavefront make_wavefront(const Scene& scene, int w, int h, int depth, bool variance) {
    render::RenderSettings s;
    s.width = w;
    s.height = h;
    s.depth = depth;
    s.variance = variance;
    // Independent samples: the film's s² / n and the 1 / spp slope describe Monte Carlo
    // estimates; the default Owen-scrambled Sobol samples are correlated within a pixel
    // (their variance of the mean is below s² / n), so these tests use the random sampler.
    s.estimator.sobol = false;
    return render::Wavefront(test::device(), scene, s);
}

}  // namespace

// relMSE against an independent reference must fall as 1/spp (slope -1 in log-log) over a
// 64x range of spp. The reference (4096 spp, its own seed) must be much better than the
// errors fitted: its own relMSE, from its variance, is checked to be under a tenth of the
// smallest relMSE averaged (at 256 spp, 16x fewer samples, so about 1/16).
TEST_CASE("converge: relMSE on the Cornell box falls with log-log slope -1 +- 0.15", "[stat]") {
    Scene scene = make_cornell_box(2000);
    const int w = 32, h = 24, depth = 2, runs = 6;
    render::Wavefront wf = make_wavefront(scene, w, h, depth, true);

    // Reference.
    wf.reset(0xC0FFEE);
    render::LoopOptions ref_lo;
    ref_lo.spp = 4096;
    render::render_frames(wf, ref_lo, nullptr);
    render::FilmMoments ref = wf.moments();
    double ref_own = reference_relmse(ref.mean, ref.mean_variance);

    // Runs with other seeds, relMSE at every power of two.
    std::map<int, double> mean_relmse;
    for (int run = 0; run < runs; ++run) {
        wf.reset(static_cast<std::uint32_t>(run + 1));
        render::LoopOptions lo;
        lo.spp = 256;
        lo.checkpoint_due = [](int f, double) { return f >= 4 && (f & (f - 1)) == 0; };
        lo.checkpoint = [&](int f, double) {
            mean_relmse[f] += compare_images(wf.resolve(), ref.mean).relmse / runs;
        };
        render::render_frames(wf, lo, nullptr);
    }
    REQUIRE(mean_relmse.size() == 7);  // 4 .. 256: a 64x range

    // Least-squares slope of log relMSE against log spp.
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    for (auto [spp, rel] : mean_relmse) {
        double x = std::log(spp), y = std::log(rel);
        sx += x, sy += y, sxx += x * x, sxy += x * y, n += 1;
        UNSCOPED_INFO("spp " << spp << ": mean relMSE " << rel);
    }
    double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    INFO("slope " << slope << "; reference's own relMSE " << ref_own << " vs smallest fitted "
                  << mean_relmse[256]);
    CHECK(ref_own < 0.1 * mean_relmse[256]);
    CHECK(std::abs(slope + 1.0) <= 0.15);
}

// The furnace box gives every pixel the same expectation, so the spread of the pixel means
// across the image estimates the variance of one pixel's mean independently of the film's
// sum of squares: the two must agree.
TEST_CASE("film variance: the variance of the mean matches the spread across the furnace",
          "[stat]") {
    Scene scene = make_closed_box_furnace(0.5f, 0.6f);
    const int w = 64, h = 48, spp = 16;
    render::Wavefront wf = make_wavefront(scene, w, h, 2, true);
    render::LoopOptions lo;
    lo.spp = spp;
    render::render_frames(wf, lo, nullptr);
    render::FilmMoments m = wf.moments();
    const int n = w * h;
    for (int c = 0; c < 3; ++c) {
        double sum = 0, sum2 = 0, film_var = 0;
        for (int i = 0; i < n; ++i) {
            double v = m.mean.rgb[3 * i + c];
            sum += v, sum2 += v * v;
            film_var += m.mean_variance.rgb[3 * i + c] / n;
        }
        double spread = (sum2 - sum * sum / n) / (n - 1);
        INFO("channel " << c << ": spread of pixel means " << spread << ", film's variance of "
                        << "the mean " << film_var);
        CHECK(film_var > 0.0);
        CHECK(film_var == Approx(spread).epsilon(0.1));
    }
    // Depth 0 has no randomness: zero variance.
    render::Wavefront w0 = make_wavefront(scene, 16, 12, 0, true);
    render::render_frames(w0, lo, nullptr);
    render::FilmMoments m0 = w0.moments();
    for (float v : m0.mean_variance.rgb) CHECK(v < 1e-12f);
}
