// test_render.cpp — the whole wavefront loop, end to end, against analytic answers.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <vector>

#include "render/frame_state.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "support.h"

using namespace wp;

namespace {

struct Rendered {
    Image image;
    std::vector<FilmPixel> film;
    std::array<int, WP_COUNTER_COUNT> counters;
    std::uint64_t rays = 0;
};

Rendered render_scene(const Scene& scene, int w, int h, int spp, int depth, std::uint32_t seed,
                      render::Traversal traversal = render::Traversal::Stackless,
                      render::Sampling sampling = render::Sampling::Mis, int rr_depth = 3,
                      bool sobol = true, std::size_t pool = 0, std::size_t film_segment = 0) {
    render::RenderSettings s;
    s.pool = pool;
    s.film_segment = film_segment;
    s.estimator.sobol = sobol;
    s.estimator.sampling = sampling;
    s.estimator.rr_depth = rr_depth;
    s.traversal = traversal;
    s.width = w;
    s.height = h;
    s.depth = depth;
    s.seed = seed;
    render::Wavefront wf(test::device(), scene, s);
    render::LoopOptions lo;
    lo.spp = spp;
    render::render_frames(wf, lo, nullptr);
    return {wf.resolve(), wf.film(), wf.counters(), wf.rays_traced()};
}

}  // namespace

// Inside a closed box whose walls all emit Le (towards the inside) and reflect diffusely
// with albedo ρ, every path sees Le at each of its 1 + D surface hits, weighted by the
// product of its BSDF weights, whose expectation is ρ per bounce. So every pixel's
// expected value is Le (1 + ρ + ... + ρ^D), whatever the geometry and camera.
TEST_CASE("render: closed furnace box converges to Le (1 + rho + ... + rho^D)", "[render]") {
    const float le = 0.5f, rho = 0.6f;
    Scene scene = make_closed_box_furnace(le, rho);
    const int w = 64, h = 48;
    using render::Sampling;
    // Every strategy; (depth, rr_depth): without roulette, and depth 6 with Russian
    // roulette from bounce 1 on, which must leave the expectation unchanged.
    struct Case {
        int depth, rr_depth;
    };
    // Both samplers (Owen-scrambled Sobol and the counter-based random numbers).
    for (bool sobol : {true, false})
    for (Sampling sampling : {Sampling::Uniform, Sampling::Cosine, Sampling::Nee, Sampling::Mis})
        for (Case cs : {Case{0, -1}, Case{1, -1}, Case{3, -1}, Case{6, 1}}) {
            const int depth = cs.depth;
            Rendered r = render_scene(scene, w, h, 8, depth, 42, render::Traversal::Stackless,
                                      sampling, cs.rr_depth, sobol);
            double expected = 0, term = le;
            for (int k = 0; k <= depth; ++k, term *= rho) expected += term;
            // Standard error from the image itself: every pixel has the same expectation, so
            // the spread of the pixel means across the image estimates the error of their
            // average.
            const int n = w * h;
            for (int ch = 0; ch < 3; ++ch) {
                double sum = 0, sum2 = 0;
                for (int i = 0; i < n; ++i) {
                    double v = r.image.rgb[3 * i + ch];
                    sum += v;
                    sum2 += v * v;
                }
                double mean = sum / n;
                double var = std::max(0.0, (sum2 - n * mean * mean) / (n - 1));
                double se = std::sqrt(var / n);
                INFO("sampler " << (sobol ? "sobol" : "random") << " sampling "
                                << render::sampling_name(sampling) << " depth " << depth
                                 << " rr_depth " << cs.rr_depth << " channel " << ch << ": mean "
                                 << mean << " expected " << expected << " standard error " << se);
                if (depth == 0) {
                    CHECK(mean == Approx(expected).epsilon(1e-6));  // no randomness at depth 0
                    CHECK(se < 1e-7);
                } else {
                    // (cosine sampling is exact here: every path weighs ρ per bounce, so
                    // se is rounding only; hence the small absolute allowance)
                    CHECK(std::abs(mean - expected) < 4.0 * se + 1e-5 * expected);
                    // The test has power; NEE alone is noisier in a box of emitting walls
                    // (light points next to the receiver: 1 / distance²).
                    CHECK(se < (sampling == Sampling::Nee ? 0.02 : 0.01) * expected);
                }
            }
            CHECK(r.counters[WP_COUNTER_SHADE_NONFINITE] == 0);
            CHECK(r.counters[WP_COUNTER_ACCUMULATE_NONFINITE] == 0);
            // Nothing escapes and every diffuse bounce survives (weight > 0): without light
            // sampling and roulette every queue is full, so the ray count is exact; shadow
            // rays add to it, roulette takes from it.
            const std::uint64_t full = std::uint64_t(n) * 8 * (depth + 1);
            bool nee = sampling == Sampling::Nee || sampling == Sampling::Mis;
            if (cs.rr_depth < 0 && !nee) CHECK(r.rays == full);
            if (cs.rr_depth < 0 && nee && depth > 0) CHECK(r.rays > full);
            if (cs.rr_depth >= 0 && !nee) CHECK(r.rays < full);
        }
}

TEST_CASE("render: the same seed gives a bit-identical image, another seed another one",
          "[render]") {
    Scene scene = make_cornell_box(2000);
    Rendered a = render_scene(scene, 64, 48, 4, 3, 7);
    Rendered b = render_scene(scene, 64, 48, 4, 3, 7);
    Rendered c = render_scene(scene, 64, 48, 4, 3, 8);
    REQUIRE(a.film.size() == b.film.size());
    CHECK(std::memcmp(a.film.data(), b.film.data(), a.film.size() * sizeof(FilmPixel)) == 0);
    CHECK(a.rays == b.rays);
    int differ = 0;
    for (std::size_t i = 0; i < a.image.rgb.size(); ++i) differ += a.image.rgb[i] != c.image.rgb[i];
    CHECK(differ > 100);
    // The Cornell box has light: the image is not black.
    double sum = 0;
    for (float v : a.image.rgb) sum += v;
    CHECK(sum > 0.0);
}

// The two closest-hit traversals return bit-identical hits (test_intersect.cpp), so whole
// renders through them must agree bit for bit too: a check of the wavefront entry points.
TEST_CASE("render: the stack and stackless traversals give bit-identical images", "[render]") {
    Scene scene = make_cornell_box(2000);
    Rendered a = render_scene(scene, 64, 48, 4, 3, 11, render::Traversal::Stackless);
    Rendered b = render_scene(scene, 64, 48, 4, 3, 11, render::Traversal::Stack);
    REQUIRE(a.film.size() == b.film.size());
    CHECK(std::memcmp(a.film.data(), b.film.data(), a.film.size() * sizeof(FilmPixel)) == 0);
    CHECK(a.rays == b.rays);
}

TEST_CASE("render: kernel options follow the scene's materials", "[render]") {
    Scene furnace = make_closed_box_furnace(1.0f, 0.5f);
    auto cfg = render::KernelConfig::from_scene(furnace);
    CHECK(cfg.has(MaterialKind::Diffuse));
    CHECK_FALSE(cfg.has(MaterialKind::Mirror));
    CHECK_FALSE(cfg.has(MaterialKind::Glossy));
    CHECK(cfg.emission);
    CHECK(cfg.options().find("-D WP_HAVE_MIRROR=0") != std::string::npos);
    // Every kind of material_kinds.h: a name that parses back, and its own switch.
#define WP_KIND_SWITCH_(KIND, Kind, name, specular, alpha, ior, etak) "WP_HAVE_" #KIND,
    const char* switches[] = {WP_MATERIAL_KINDS(WP_KIND_SWITCH_)};
#undef WP_KIND_SWITCH_
    for (int i = 0; i < kMaterialKindCount; ++i) {
        const auto k = static_cast<MaterialKind>(i);
        CHECK(material_kind_from_string(to_string(k)) == k);
        CHECK(cfg.options().find(std::string("-D ") + switches[i] + "=") != std::string::npos);
    }
    auto box = render::KernelConfig::from_scene(make_cornell_box(200));
    CHECK((box.has(MaterialKind::Diffuse) && box.has(MaterialKind::Mirror) &&
           box.has(MaterialKind::Glossy) && box.emission));
    // Light sampling only for strategies that use it and scenes that emit.
    box.estimator.sampling = render::Sampling::Mis;
    CHECK(box.options().find("-D WP_HAVE_NEE=1") != std::string::npos);
    box.estimator.sampling = render::Sampling::Cosine;
    CHECK(box.options().find("-D WP_HAVE_NEE=0") != std::string::npos);
    box.estimator.sampling = render::Sampling::Mis;
    box.emission = false;
    CHECK(box.options().find("-D WP_HAVE_NEE=0") != std::string::npos);
}

// The path pool cuts the samples into waves of its capacity: several passes of the image,
// one pass, or parts of one; the film must hold the same bits whatever the cut (each
// sample's random numbers depend only on its key, and accumulate adds a pixel's samples in
// sample order).
TEST_CASE("render: the same image, bit for bit, for every path pool size", "[render][pool]") {
    Scene scene = make_cornell_box(2000);
    const int w = 24, h = 18, spp = 7, depth = 6;  // roulette from bounce 3 ends some paths
    Rendered ref = render_scene(scene, w, h, spp, depth, 3, render::Traversal::Stackless,
                                render::Sampling::Mis, 3, true, 0);
    for (std::size_t pool : {std::size_t(37), std::size_t(w * h), std::size_t(3 * w * h + 5),
                             std::size_t(64 * w * h)}) {
        INFO("pool of " << pool << " paths");
        Rendered r = render_scene(scene, w, h, spp, depth, 3, render::Traversal::Stackless,
                                  render::Sampling::Mis, 3, true, pool);
        REQUIRE(r.film.size() == ref.film.size());
        CHECK(std::memcmp(r.film.data(), ref.film.data(), r.film.size() * sizeof(FilmPixel)) == 0);
        CHECK(r.rays == ref.rays);
    }
    // A film in segments of 100 pixels (as a 16384^2 film is on a device that caps one
    // buffer at 2 GiB): waves never straddle two, and the film is the same.
    Rendered seg = render_scene(scene, w, h, spp, depth, 3, render::Traversal::Stackless,
                                render::Sampling::Mis, 3, true, 37, 100);
    CHECK(std::memcmp(seg.film.data(), ref.film.data(), seg.film.size() * sizeof(FilmPixel)) == 0);
    CHECK(seg.image.rgb == ref.image.rgb);
}

// With no depth limit to speak of, Russian roulette ends every path, the pool's wave ends
// when its queue is empty, and the closed furnace converges to the full geometric series
// Le / (1 - rho). No launch runs for a bounce after the queues are empty.
TEST_CASE("render: a depth of 10^6 ends when the paths end (furnace Le / (1 - rho))",
          "[render][pool][stat]") {
    const float le = 0.5f, rho = 0.6f;
    Scene scene = make_closed_box_furnace(le, rho);
    render::RenderSettings s;
    s.width = 32;
    s.height = 24;
    s.depth = 1000000;
    s.seed = 21;
    s.estimator.sobol = false;  // independent samples: pixels are independent estimates
    render::Wavefront wf(test::device(), scene, s);
    render::LoopOptions lo;
    lo.spp = 16;
    render::render_frames(wf, lo, nullptr);
    Image img = wf.resolve();
    const double expected = le / (1.0 - rho);
    double sum = 0, sum2 = 0;
    const std::size_t m = img.rgb.size() / 3;
    for (std::size_t i = 0; i < m; ++i) {
        double v = img.rgb[3 * i];
        sum += v;
        sum2 += v * v;
    }
    double mean = sum / m, se = std::sqrt((sum2 / m - mean * mean) / (m - 1));
    INFO("mean " << mean << " +- " << se << ", expected " << expected);
    CHECK(std::abs(mean - expected) < 4 * se);
    for (int c : wf.counters()) CHECK(c == 0);
    int launches = 0;
    for (const auto& t : wf.profiler().totals())
        if (t.name == "intersect.closest") launches = t.launches;
    INFO(launches << " intersect launches for " << wf.profiler().wave_count() << " waves");
    // Paths of throughput <= 0.6 per bounce after roulette: a few hundred bounces at most.
    CHECK(launches > 16);
    CHECK(launches < 2000);
}

// The last bounce's rays through the emitters' BVH first (render --final-rays, kernels/
// intersect.cl intersect_final, or shade.cl shade_final, which also shades the rays that
// meet an emitter) return the closest hit wherever it emits and a miss or that hit elsewhere
// (test_intersect.cpp); where escaped rays carry no light the image must then be the
// closest-hit render's, bit for bit, for every estimator and depth, with the lane shade
// kernel and the scalar one, shadow rays traced in shade or queued.
TEST_CASE("render: the last bounce through the emitters' BVH gives the same image bit for bit",
          "[render]") {
    struct Shade {
        bool lanes = true, shadows_in_shade = true;
    };
    auto render = [](const Scene& scene, render::Sampling sampling, int depth, bool final_rays,
                     bool* engaged, bool aov = false, Shade sh = {}) {
        render::RenderSettings s;
        s.aov = aov;  // feature buffers read the last bounce's hits: every bounce whole
        s.width = 40;
        s.height = 30;
        s.depth = depth;
        s.seed = 5;
        s.estimator.sampling = sampling;
        s.final_rays = final_rays;
        s.shade_lanes = sh.lanes;
        s.shadows_in_shade = sh.shadows_in_shade;
        render::Wavefront wf(test::device(), scene, s);
        *engaged = wf.final_rays_through_emitters();
        // Where it traces them so, shade does the last bounce in one launch (shade_final).
        CHECK(wf.config().shade_final() == *engaged);
        render::LoopOptions lo;
        lo.spp = 4;
        render::render_frames(wf, lo, nullptr);
        return wf.film();
    };
    Scene scene = make_cornell_box(2000);
    REQUIRE(render::final_rays_through_emitters(scene));
    for (auto sampling : {render::Sampling::Mis, render::Sampling::Nee, render::Sampling::Cosine,
                          render::Sampling::Uniform})
        for (int depth : {0, 1, 3}) {
            INFO("sampling " << render::sampling_name(sampling) << ", depth " << depth);
            bool on = false, off = true;
            auto a = render(scene, sampling, depth, true, &on);
            auto b = render(scene, sampling, depth, false, &off);
            CHECK(on);
            CHECK_FALSE(off);
            REQUIRE(a.size() == b.size());
            CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(FilmPixel)) == 0);
        }
    // The scalar shade kernel (and its shadow queue) on the box; the lane kernel with queued
    // shadow rays on veach-plates (light pairs: sphere lights; rough conductors); depths 1
    // and 2.
    struct Variant {
        Scene scene;
        Shade shade;
    };
    for (const Variant& v : {Variant{scene, Shade{false, false}}, Variant{make_veach_plates(), Shade{true, false}}})
        for (int depth : {1, 2}) {
            INFO("lanes " << v.shade.lanes << ", " << v.scene.triangles.size() << " triangles, depth " << depth);
            bool on = false, off = true;
            auto a = render(v.scene, render::Sampling::Mis, depth, true, &on, false, v.shade);
            auto b = render(v.scene, render::Sampling::Mis, depth, false, &off, false, v.shade);
            CHECK(on);
            CHECK_FALSE(off);
            REQUIRE(a.size() == b.size());
            CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(FilmPixel)) == 0);
        }
    // Where escaped rays shine, or most of the surface emits, every bounce is traced whole.
    Scene lit = scene;
    lit.background = glm::vec3(0.1f);
    CHECK_FALSE(render::final_rays_through_emitters(lit));
    CHECK_FALSE(render::final_rays_through_emitters(make_closed_box_furnace(1.0f, 0.5f)));
    CHECK(render::emitter_area_share(make_closed_box_furnace(1.0f, 0.5f)) == Approx(1.0));
    bool engaged = true;
    (void)render(lit, render::Sampling::Mis, 1, true, &engaged);
    CHECK_FALSE(engaged);
    engaged = true;
    (void)render(scene, render::Sampling::Mis, 1, true, &engaged, true);
    CHECK_FALSE(engaged);
    // The stack traversal, the oracle, traces every bounce itself.
    render::RenderSettings st;
    st.width = 8;
    st.height = 6;
    st.traversal = render::Traversal::Stack;
    CHECK_FALSE(render::Wavefront(test::device(), scene, st).final_rays_through_emitters());
}

// Shade pushes its queues with non-temporal stores on a CPU device only where the pool's
// queues exceed the device's cache (render/wavefront.cpp); the image is the same either way
// (tests/test_shade.cpp compares the outputs bit for bit).
TEST_CASE("render: shade streams its queues only where the pool outgrows the device's cache", "[render]") {
    // The rule, on devices as they may report themselves.
    ocl::DeviceInfo cpu;
    cpu.type = "CPU";
    cpu.cache_bytes = 32u << 20;
    CHECK(render::stream_queues(cpu, (32u << 20) + 1));
    CHECK_FALSE(render::stream_queues(cpu, 32u << 20));
    CHECK_FALSE(render::stream_queues(cpu, 1024));
    ocl::DeviceInfo gpu = cpu;
    gpu.type = "GPU";
    CHECK_FALSE(render::stream_queues(gpu, std::uint64_t(1) << 32));
    ocl::DeviceInfo unknown = cpu;
    unknown.cache_bytes = 0;  // no cache reported: nothing to outgrow
    CHECK_FALSE(render::stream_queues(unknown, std::uint64_t(1) << 32));
    // A virtual machine's two cores reporting their host's 480 MiB: they count on 2 x 12 MiB.
    ocl::DeviceInfo vm = cpu;
    vm.compute_units = 2;
    vm.cache_bytes = std::uint64_t(480) << 20;
    CHECK(render::usable_cache_bytes(vm) == (std::uint64_t(24) << 20));
    CHECK(render::stream_queues(vm, (std::uint64_t(24) << 20) + 1));
    CHECK_FALSE(render::stream_queues(vm, std::uint64_t(24) << 20));
    // Sixteen cores under 32 MiB: the report is the smaller.
    ocl::DeviceInfo desktop = cpu;
    desktop.compute_units = 16;
    CHECK(render::usable_cache_bytes(desktop) == (std::uint64_t(32) << 20));
    CHECK(render::stream_queues(desktop, (32u << 20) + 1));
    CHECK_FALSE(render::stream_queues(desktop, 32u << 20));

    // The renderer applies it to the pool it allocates: a small pool, and the automatic
    // limit of 2^20 paths (160-212 MiB: above the 8-32 MiB of L3 of some CI machines and above
    // the 24 MiB that two cores count on of another VM's reported 480 MiB).
    auto& dev = test::device();
    const Scene scene = make_cornell_box(200);
    render::RenderSettings s;
    s.width = 16;
    s.height = 12;
    for (std::size_t pool : {std::size_t(1024), render::PathPool::kDefaultCapacity}) {
        s.pool = pool;
        render::Wavefront w(dev, scene, s);
        const std::uint64_t queue_bytes = std::uint64_t(w.memory().pool_paths) * w.memory().bytes_per_path;
        INFO("pool " << pool << ", queues " << queue_bytes << " bytes, device cache " << dev.info.cache_bytes);
        CHECK(w.memory().pool_paths == pool);
        CHECK(w.config().stream_stores == render::stream_queues(dev.info, queue_bytes));
        if (pool == 1024) CHECK_FALSE(w.config().stream_stores);  // far below any cache
        if (pool == render::PathPool::kDefaultCapacity && dev.info.type == "CPU" && dev.info.cache_bytes > 0 &&
            dev.info.compute_units <= 8)
            CHECK(w.config().stream_stores);  // at most 96 MiB counted on
    }
}
