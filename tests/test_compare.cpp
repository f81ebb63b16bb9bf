// test_compare.cpp — error metrics, the per-pixel z-test, film moments and `wavepath compare`.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "image/image.h"
#include "image/stats.h"
#include "render/film.h"
#include "support.h"

using namespace wp;
namespace fs = std::filesystem;

namespace {

// Standard normal by Box-Muller from the test generator.
double normal(test::Rng& rng) {
    double u1 = (rng.next() >> 11) * 0x1p-53 + 0x1p-54, u2 = (rng.next() >> 11) * 0x1p-53;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

// A smooth "true" image and its per-pixel variance of the mean.
void make_truth(int w, int h, Image& mean, Image& var) {
    mean = Image(w, h);
    var = Image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                mean.pixel(x, y)[c] = 0.5f + 0.3f * std::sin(0.2f * x + c) * std::cos(0.3f * y);
                var.pixel(x, y)[c] = 1e-4f * (1.0f + 0.5f * c + 0.01f * x);
            }
}

}  // namespace

TEST_CASE("compare: metrics of hand-made images", "[unit]") {
    Image a(2, 1), r(2, 1);
    float av[6] = {1, 2, 3, 0, 0, 0}, rv[6] = {1, 1, 1, 0, 0, 1};
    std::copy(av, av + 6, a.rgb.begin());
    std::copy(rv, rv + 6, r.rgb.begin());
    // Differences 0, 1, 2, 0, 0, -1: squares sum to 6 over 6 values.
    ErrorMetrics m = compare_images(a, r);
    CHECK(m.rmse == Approx(1.0));
    CHECK(m.relmse == Approx((1.0 / 1.01 + 4.0 / 1.01 + 1.0 / 1.01) / 6.0));
    CHECK(m.mae == Approx(4.0 / 6.0));
    CHECK(m.max_abs == Approx(2.0));
    CHECK(m.max_x == 0);
    CHECK(m.max_y == 0);
    CHECK_THROWS_WITH(compare_images(a, Image(1, 2)), Catch::Contains("sizes differ"));
}

TEST_CASE("compare: normal quantile and the Sidak threshold", "[unit]") {
    CHECK(normal_two_sided_quantile(0.05) == Approx(1.959964).epsilon(1e-6));
    CHECK(normal_two_sided_quantile(0.01) == Approx(2.575829).epsilon(1e-6));
    Image a(4, 2), b(4, 2);
    ZTest t = z_test(a, b, &a, nullptr, 0.01);
    // alpha_channel = 1 - 0.99^(1/24)
    CHECK(t.alpha_channel == Approx(1.0 - std::pow(0.99, 1.0 / 24.0)).epsilon(1e-9));
    CHECK(t.z_crit == Approx(normal_two_sided_quantile(t.alpha_channel)));
    CHECK(t.pass_fraction == 1.0);  // equal images with zero variance pass
}

TEST_CASE("compare: the z-test passes a draw from the stated mean and variance and rejects a "
          "shifted image",
          "[stat]") {
    const int w = 64, h = 48;
    Image mean, var;
    make_truth(w, h, mean, var);
    test::Rng rng(20240601);
    Image draw(w, h), shifted(w, h);
    for (std::size_t i = 0; i < draw.rgb.size(); ++i) {
        double sd = std::sqrt(double(var.rgb[i]));
        draw.rgb[i] = static_cast<float>(mean.rgb[i] + sd * normal(rng));
        // Shifted by 8 standard deviations (z_crit is about 4.8 here).
        shifted.rgb[i] = static_cast<float>(mean.rgb[i] + sd * (8.0 + normal(rng)));
    }
    ZTest good = z_test(draw, mean, &var, nullptr);
    INFO("draw: " << good.passed << "/" << good.pixels << ", max |z| " << good.max_abs_z
                  << ", z_crit " << good.z_crit);
    CHECK(good.pass_fraction >= 0.9975);
    CHECK(good.max_abs_z < 6.0);
    ZTest bad = z_test(shifted, mean, &var, nullptr);
    INFO("shifted: " << bad.passed << "/" << bad.pixels);
    CHECK(bad.pass_fraction < 0.05);
    // Both variances count: the same draw against itself shifted by its own noise passes.
    ZTest two = z_test(draw, mean, &var, &var);
    CHECK(two.passed >= good.passed);
}

TEST_CASE("film: moments from the sum and the sum of squares", "[unit]") {
    // One pixel, samples 1, 2, 3, 4 in every channel: S1 = 10, S2 = 30.
    std::vector<FilmPixel> s1(1), s2(1);
    s1[0].sum = {10.0f, 10.0f, 10.0f, 0.0f};
    s2[0].sum = {30.0f, 30.0f, 30.0f, 0.0f};
    render::FilmMoments m = render::resolve_moments(s1, s2, 1, 1, 4);
    CHECK(m.mean.rgb[0] == Approx(2.5));
    CHECK(m.sample_variance.rgb[1] == Approx(5.0 / 3.0));
    CHECK(m.mean_variance.rgb[2] == Approx(5.0 / 12.0));
    CHECK(variance_path_for("out/render.exr") == fs::path("out/render.var.exr"));
    CHECK(variance_path_for("a.png") == fs::path("a.var.exr"));
}

namespace {

int run_compare(const fs::path& dir, const std::string& args) {
    std::string cmd = "cd '" + dir.string() + "' && '" WP_CLI_PATH "' compare " + args +
                      " > out.txt 2> err.txt";
    int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace

TEST_CASE("compare CLI: exit codes 0/1 on the thresholds, 2 on usage errors", "[unit][cli]") {
    fs::path dir = fs::temp_directory_path() / ("wp-compare-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    Image mean, var;
    make_truth(16, 12, mean, var);
    Image off = mean;
    for (float& v : off.rgb) v += 0.1f;  // relMSE about 0.01 / (r^2 + 0.01)
    write_image(dir / "ref.exr", mean);
    write_image(dir / "var.exr", var);
    write_image(dir / "same.exr", mean);
    write_image(dir / "off.exr", off);
    double relmse = compare_images(off, mean).relmse;

    CHECK(run_compare(dir, "same.exr ref.exr --max-relmse 0") == 0);
    CHECK(run_compare(dir, "off.exr ref.exr --max-relmse " + std::to_string(relmse * 1.01)) == 0);
    CHECK(run_compare(dir, "off.exr ref.exr --max-relmse " + std::to_string(relmse * 0.99)) == 1);
    CHECK(run_compare(dir, "same.exr ref.exr --variance var.exr --min-pass 0.9975") == 0);
    CHECK(run_compare(dir, "off.exr ref.exr --variance var.exr --min-pass 0.9975 "
                           "--error-image e.png") == 1);
    CHECK(fs::exists(dir / "e.png"));
    // Usage errors and unreadable input: 2, and no error image.
    CHECK(run_compare(dir, "off.exr missing.exr") == 2);
    CHECK(run_compare(dir, "off.exr") == 2);
    CHECK(run_compare(dir, "off.exr ref.exr --min-pass 0.99") == 2);  // needs a variance
    CHECK(run_compare(dir, "off.exr ref.exr --bogus") == 2);
    CHECK(run_compare(dir, "off.exr ref.exr --error-image /nonexistent-dir/e.png") == 2);
    fs::remove_all(dir);
}
