// test_denoise.cpp — the denoise stage (render/denoise.h, kernels/denoise.cl) alone on
// hand-made images with known answers (a constant stays constant, steps in the albedo,
// normal and depth buffers stay steps, the mean is kept), and on a noisy render of the
// built-in box against the stored 4096-spp reference (tests/references/cornell-box.exr).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/denoise.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "support.h"
#include "temp_dir.h"
#include "util/error.h"

using namespace wp;
namespace fs = std::filesystem;

namespace {

struct Inputs {
    Image color, variance;
    render::AovImages aov;
    Inputs(int w, int h)
        : color(w, h),
          variance(w, h), aov{Image(w, h), Image(w, h), std::vector<float>(std::size_t(w) * h)} {}
    void set(int x, int y, glm::vec3 c, float var, glm::vec3 albedo, glm::vec3 normal,
             float depth) {
        float* pc = color.pixel(x, y);
        float* pv = variance.pixel(x, y);
        float* pa = aov.albedo.pixel(x, y);
        float* pn = aov.normal.pixel(x, y);
        for (int k = 0; k < 3; ++k) {
            pc[k] = c[k];
            pv[k] = var;
            pa[k] = albedo[k];
            pn[k] = normal[k];
        }
        aov.depth[std::size_t(y) * color.width + x] = depth;
    }
};

// Standard normal numbers (Box-Muller on splitmix64).
struct Gauss {
    test::Rng rng;
    explicit Gauss(std::uint64_t seed) : rng(seed) {}
    double next() {
        double u1 = (double(rng.next() >> 11) + 0.5) * 0x1.0p-53,
               u2 = double(rng.next() >> 11) * 0x1.0p-53;
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
    }
};

render::Denoiser& denoiser() {
    static render::Denoiser d(test::device());
    return d;
}

// Mean of channel 0 over column x of rows [0, h).
double column_mean(const Image& img, int x) {
    double s = 0.0;
    for (int y = 0; y < img.height; ++y)
        s += img.pixel(x, y)[0];
    return s / img.height;
}

// A w x h step image: columns x < w/2 are side 0, the others side 1. Each side has its
// true value v[side] (grey) with Gaussian noise of relative deviation `rel` per pixel, and
// that noise's variance in the variance buffer.
struct Step {
    int w, h;
    float v[2];
    glm::vec3 albedo[2], normal[2];
    float depth[2];
    float rel = 0.3f;
};

Inputs make_step(const Step& s, std::uint64_t seed) {
    Inputs in(s.w, s.h);
    Gauss g(seed);
    for (int y = 0; y < s.h; ++y)
        for (int x = 0; x < s.w; ++x) {
            const int side = x < s.w / 2 ? 0 : 1;
            const float noisy = s.v[side] * float(1.0 + s.rel * g.next());
            const float var = (s.v[side] * s.rel) * (s.v[side] * s.rel);
            in.set(x, y, glm::vec3(noisy), var, s.albedo[side], s.normal[side], s.depth[side]);
        }
    return in;
}

// After denoising: every column at least 2 pixels from the edge has its side's true value
// within `tol` (relative); the columns next to the edge are reported.
void check_step(const Step& s, const Image& out, double tol) {
    const int edge = s.w / 2;
    for (int x = 0; x < s.w; ++x) {
        const int side = x < edge ? 0 : 1;
        const double m = column_mean(out, x);
        INFO("column " << x << " (edge at " << edge << "): mean " << m << ", true " << s.v[side]);
        if (x >= edge - 2 && x <= edge + 1) {
            // The two columns either side of the edge: no more than a third of the way over.
            CHECK(std::abs(m - s.v[side]) < std::abs(s.v[1] - s.v[0]) / 3.0);
        } else {
            CHECK(std::abs(m - s.v[side]) < tol * s.v[side]);
        }
    }
}

double image_mean(const Image& img) {
    double s = 0.0;
    for (float v : img.rgb)
        s += v;
    return s / img.rgb.size();
}

double image_sd(const Image& img, double mean) {
    double s = 0.0;
    for (float v : img.rgb)
        s += (v - mean) * (v - mean);
    return std::sqrt(s / img.rgb.size());
}

} // namespace

TEST_CASE("denoise: a constant image stays constant", "[kernel][denoise]") {
    const int w = 40, h = 30;
    const glm::vec3 c(0.3f, 0.6f, 0.9f);
    for (float var : {0.0f, 0.01f, 10.0f})
        for (float depth : {3.0f, std::numeric_limits<float>::infinity()}) {
            Inputs in(w, h);
            const glm::vec3 albedo =
                std::isinf(depth) ? glm::vec3(0.0f) : glm::vec3(0.5f, 0.25f, 0.8f);
            const glm::vec3 normal =
                std::isinf(depth) ? glm::vec3(0.0f) : glm::vec3(0.0f, 0.6f, 0.8f);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    in.set(x, y, c, var, albedo, normal, depth);
            Image out = denoiser().run(in.color, in.variance, in.aov);
            REQUIRE(out.width == w);
            REQUIRE(out.height == h);
            double worst = 0.0;
            for (std::size_t i = 0; i < out.rgb.size(); ++i)
                worst = std::max(worst, std::abs(double(out.rgb[i]) - c[i % 3]) / c[i % 3]);
            INFO("variance " << var << ", depth " << depth);
            CHECK(worst < 1e-6); // a few float roundings
        }
}

TEST_CASE("denoise: an albedo step stays a step", "[kernel][denoise]") {
    Step s{64,
           32,
           {0.2f, 0.8f},
           {glm::vec3(0.2f), glm::vec3(0.8f)},
           {glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)},
           {5.0f, 5.0f}};
    Inputs in = make_step(s, 11);
    Image out = denoiser().run(in.color, in.variance, in.aov);
    check_step(s, out, 0.05);
}

TEST_CASE("denoise: a normal step and a depth step stay steps", "[kernel][denoise]") {
    // Same albedo on both sides: only the normals (90 degrees apart) tell the sides apart.
    Step n{64,
           32,
           {0.2f, 0.8f},
           {glm::vec3(0.5f), glm::vec3(0.5f)},
           {glm::vec3(0, 0, 1), glm::vec3(1, 0, 0)},
           {5.0f, 5.0f}};
    Inputs in = make_step(n, 12);
    check_step(n, denoiser().run(in.color, in.variance, in.aov), 0.05);
    // Only the depth: a near plane (2) beside a far one (20), both facing the camera.
    Step z{64,
           32,
           {0.8f, 0.2f},
           {glm::vec3(0.5f), glm::vec3(0.5f)},
           {glm::vec3(0, 0, 1), glm::vec3(0, 0, 1)},
           {2.0f, 20.0f}};
    in = make_step(z, 13);
    check_step(z, denoiser().run(in.color, in.variance, in.aov), 0.05);
    // A surface beside nothing (a miss: albedo, normal 0, depth +inf) and a bright
    // background.
    Step m{64,
           32,
           {0.3f, 2.0f},
           {glm::vec3(0.5f), glm::vec3(0.0f)},
           {glm::vec3(0, 0, 1), glm::vec3(0.0f)},
           {5.0f, std::numeric_limits<float>::infinity()}};
    in = make_step(m, 14);
    check_step(m, denoiser().run(in.color, in.variance, in.aov), 0.05);
}

TEST_CASE("denoise: the mean is kept and the noise falls", "[kernel][denoise]") {
    const int w = 96, h = 64;
    const float truth = 0.5f, sd = 0.1f;
    Inputs in(w, h);
    Gauss g(21);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            in.set(x, y, glm::vec3(truth + sd * float(g.next())), sd * sd, glm::vec3(0.7f),
                   glm::vec3(0, 0, 1), 4.0f);
    Image out = denoiser().run(in.color, in.variance, in.aov);
    const double mean_in = image_mean(in.color), mean_out = image_mean(out);
    // The input's mean is within noise of the truth: sd / sqrt(pixels) = 1.3e-3 (the
    // channels are equal, so the pixels count once).
    const double se = sd / std::sqrt(double(w) * h);
    CHECK(std::abs(mean_in - truth) < 4.0 * se);
    // The denoised mean stays within the same noise of the truth.
    CHECK(std::abs(mean_out - truth) < 4.0 * se);
    // And the noise per pixel falls a lot (a 5-iteration à-trous filter averages hundreds
    // of pixels where nothing stops it).
    CHECK(image_sd(out, mean_out) < 0.2 * image_sd(in.color, mean_in));
}

// Path-traced noise is skewed: a pixel's 16 samples are 0.1 each, or 10 with probability
// 0.04 (a rare bright path); expectation 0.496. The SVGF luminance weight alone darkens
// such an image (the bright pixels are averaged down, their neighbours reject them); the
// optional energy restore puts the residual back.
TEST_CASE("denoise: skewed noise keeps its mean (energy restore)", "[kernel][denoise]") {
    const int w = 96, h = 64, spp = 16;
    const double truth = 0.04 * 10.0 + 0.96 * 0.1;
    Inputs in(w, h);
    test::Rng rng(31);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double s1 = 0.0, s2 = 0.0;
            for (int k = 0; k < spp; ++k) {
                const double v = rng.uniform() < 0.04f ? 10.0 : 0.1;
                s1 += v;
                s2 += v * v;
            }
            const double mean = s1 / spp, var = (s2 - s1 * mean) / (spp - 1) / spp;
            in.set(x, y, glm::vec3(float(mean)), float(var), glm::vec3(0.7f), glm::vec3(0, 0, 1), 4.0f);
        }
    const double mean_in = image_mean(in.color);
    // The input: within 4 standard errors of the truth (per pixel sd 1.96/4 = 0.49).
    CHECK(std::abs(mean_in - truth) < 4.0 * 0.49 / std::sqrt(double(w) * h));
    render::DenoiseSettings off, on;
    off.restore_iterations = 0;
    on.restore_iterations = 5;  // opt-in (off by default: see the bright-emitter test below)
    const double mean_off = image_mean(denoiser().run(in.color, in.variance, in.aov, off));
    const Image out = denoiser().run(in.color, in.variance, in.aov, on);
    const double mean_out = image_mean(out);
    INFO("mean: truth " << truth << ", noisy " << mean_in << ", without restore " << mean_off
                        << ", denoised " << mean_out);
    CHECK(mean_off < 0.95 * mean_in);  // what the restore is for (measured: 9.5 % darker)
    CHECK(std::abs(mean_out - mean_in) < 0.01 * mean_in);  // within 1 % of the input's mean
    CHECK(image_sd(out, mean_out) < 0.5 * image_sd(in.color, mean_in));
}

// A small, very bright emitter (a 2x2 block at 500, albedo 0, a little nearer) on a dark,
// slightly noisy wall: the denoiser must not spread it. Every pixel 3 or more pixels from
// the block stays within 0.05 of its input. (The veach-mis leak that turned the energy
// restore off by default, docs/denoise.md, is not reproduced by this image.)
TEST_CASE("denoise: a small bright emitter does not leak into a dark neighbourhood", "[kernel][denoise]") {
    const int w = 48, h = 40, bx = 20, by = 18;
    Inputs in(w, h);
    test::Rng rng(5);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool light = x >= bx && x < bx + 2 && y >= by && y < by + 2;
            const float v = light ? 500.0f : 0.01f + 0.005f * (rng.uniform() - 0.5f);
            // The emitter: albedo 0 (an emitter's AOV), a little nearer than the wall.
            in.set(x, y, glm::vec3(v), light ? 1.0f : 1e-5f, glm::vec3(light ? 0.0f : 0.5f),
                   glm::vec3(0, 0, 1), light ? 3.9f : 4.0f);
        }
    const Image out = denoiser().run(in.color, in.variance, in.aov);
    int leaked = 0;
    float worst = 0.0f;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int dx = x < bx ? bx - x : (x >= bx + 2 ? x - bx - 1 : 0);
            const int dy = y < by ? by - y : (y >= by + 2 ? y - by - 1 : 0);
            if (std::max(dx, dy) < 3) continue;
            const float d = std::fabs(out.pixel(x, y)[0] - in.color.pixel(x, y)[0]);
            worst = std::max(worst, d);
            leaked += d > 0.05f;
        }
    INFO("largest change 3+ pixels away: " << worst);
    CHECK(leaked == 0);
}

TEST_CASE("denoise: mismatched inputs and bad settings are errors", "[kernel][denoise]") {
    Inputs in(8, 6);
    Inputs small(4, 6);
    CHECK_THROWS_WITH(denoiser().run(in.color, small.variance, in.aov),
                      Catch::Contains("variance"));
    render::AovImages bad = in.aov;
    bad.depth.pop_back();
    CHECK_THROWS_WITH(denoiser().run(in.color, in.variance, bad), Catch::Contains("depth"));
    render::DenoiseSettings s;
    s.normal_power = 100;
    CHECK_THROWS_WITH(denoiser().run(in.color, in.variance, in.aov, s),
                      Catch::Contains("power of two"));
}

// The built-in box at 64x48, 16 spp (depth 3, as the stored reference): the denoised image
// has at most a quarter of the noisy relMSE against the 4096-spp reference.
TEST_CASE("denoise: a noisy render of the built-in box gets a lower relMSE", "[render][denoise]") {
    const fs::path ref_path = fs::path(WP_SOURCE_DIR) / "tests" / "references" / "cornell-box.exr";
    REQUIRE(fs::exists(ref_path));
    const Image ref = read_image(ref_path);
    render::RenderSettings s;
    s.width = 64;
    s.height = 48;
    s.depth = 3;
    s.seed = 5;
    s.variance = true;
    s.aov = true;
    render::Wavefront wf(test::device(), make_cornell_box(), s);
    render::LoopOptions lo;
    lo.spp = 16;
    render::render_frames(wf, lo, nullptr);
    render::FilmMoments m = wf.moments();
    const Image out = denoiser().run(m.mean, m.mean_variance, wf.aovs());
    const double noisy = compare_images(m.mean, ref).relmse,
                 denoised = compare_images(out, ref).relmse;
    INFO("relMSE noisy " << noisy << ", denoised " << denoised);
    CHECK(denoised < 0.25 * noisy); // issue 16: at most a quarter at 16 spp (measured: 0.1)
}

TEST_CASE("render CLI: --denoise writes OUT denoised and OUT.noisy.exr", "[render][cli][denoise]") {
    test::TempDir d;
    auto r = test::run_render(d.path, "--size 32x24 --spp 4 --denoise -o out.exr");
    INFO(r.err);
    REQUIRE(r.status == 0);
    REQUIRE(fs::exists(d.path / "out.exr"));
    REQUIRE(fs::exists(d.path / "out.noisy.exr"));
    CHECK(read_image_attribute(d.path / "out.exr", "wavepath:denoised") ==
          std::optional<std::string>("1"));
    CHECK_FALSE(read_image_attribute(d.path / "out.noisy.exr", "wavepath:denoised").has_value());
    // --denoise alone writes no AOV channels.
    CHECK(read_image_channels(d.path / "out.exr").names.size() == 3);
    // The default outputs: render.exr and render.png, each with a noisy sibling.
    test::TempDir e;
    r = test::run_render(e.path, "--size 16x12 --spp 2 --denoise");
    REQUIRE(r.status == 0);
    for (const char* f : {"render.exr", "render.png", "render.noisy.exr", "render.noisy.png"})
        CHECK(fs::exists(e.path / f));
}

// converge measures a "--denoise" configuration by its denoised image: at every checkpoint
// of the same seed the plain configuration's image is the noisy input, so at 4 and 8 spp
// the denoised error must be well below it (the 64x48 test above: about a tenth), and its
// seconds include the denoise. --denoise with --adaptive runs (the AOVs follow the active
// list), a configuration with a bad option is a usage error.
TEST_CASE("converge CLI: a --denoise configuration beside the plain one", "[cli][denoise]") {
    test::TempDir d;
    auto run = [&](const std::string& configs) {
        const std::string cmd = "cd '" + d.path.string() + "' && '" WP_CLI_PATH
                                "' converge --time 0.4 --runs 1 --reference-spp 256 --csv c.csv -q --max-spp 8 " +
                                configs + " > out.txt 2> err.txt";
        return std::system(cmd.c_str());
    };
    REQUIRE(run("--config 'plain=--size 48x36' --config 'den=--size 48x36 --denoise'") == 0);
    std::ifstream in(d.path / "c.csv");
    std::string line;
    std::getline(in, line);
    std::map<std::pair<std::string, int>, std::pair<double, double>> at;  // (config, spp) -> (relmse, s)
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
        REQUIRE(f.size() == 9);
        at[{f[0], std::stoi(f[3])}] = {std::stod(f[6]), std::stod(f[4])};
    }
    for (int spp : {4, 8}) {
        INFO("spp " << spp);
        REQUIRE(at.count({"plain", spp}));
        REQUIRE(at.count({"den", spp}));
        CHECK(at[{"den", spp}].first < 0.5 * at[{"plain", spp}].first);
        CHECK(at[{"den", spp}].second > 0.0);
    }
    std::ifstream out(d.path / "out.txt");
    std::string text((std::istreambuf_iterator<char>(out)), std::istreambuf_iterator<char>());
    CHECK(text.find("den (denoised: biased)") != std::string::npos);
    CHECK(run("--config 'x=--size 48x36 --denoise --adaptive --min-spp 4'") == 0);
    CHECK(run("--config 'x=--size 48x36 --denoise --replicates 3'") >> 8 == 2);
}
