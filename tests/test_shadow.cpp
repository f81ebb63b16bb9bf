// test_shadow.cpp — the shadow stage and the queue upkeep, each alone on the test device.
//
// shadow_trace against a brute-force any-hit oracle over every triangle (support.h), and
// queue_reset against the counts it is given; at the CLI, the shadow rays that shade traces
// itself against the shadow stage's.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <numeric>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bvh/build.h"
#include "bvh/device_bvh.h"
#include "bvh/flatten.h"
#include "image/image.h"
#include "render/frame_state.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "render/stages/shadow.h"
#include "scene/builtin.h"
#include "support.h"
#include "temp_dir.h"

using namespace wp;

TEST_CASE("shadow: unoccluded segments add their contribution to their sample, occluded ones "
          "nothing", "[kernel][shadow]") {
    auto& dev = test::device();
    Scene scene = make_cornell_box(200);
    auto flat = bvh::flatten(bvh::build(bvh::triangle_boxes(scene.positions, scene.triangles)),
                             scene.positions, scene.triangles);
    auto bvh = bvh::DeviceBvh::upload(dev, flat);

    // Segments between random points of the box (hits need 0 < t < 1), each for its own
    // sample item in a shuffled order, with random contributions.
    const int n = 20000, items = n + 500;
    test::Rng rng(5);
    std::vector<Ray> rays(n);
    std::vector<int> item(items);
    std::iota(item.begin(), item.end(), 0);
    for (int i = items - 1; i > 0; --i) std::swap(item[i], item[rng.next() % (i + 1)]);
    item.resize(n);
    std::vector<float4> contrib(n), radiance(items);
    for (int i = 0; i < n; ++i) {
        glm::vec3 a(rng.uniform(-1, 1), rng.uniform(0, 2), rng.uniform(-1, 1));
        glm::vec3 b(rng.uniform(-1, 1), rng.uniform(0, 2), rng.uniform(-1, 1));
        rays[i] = test::make_ray(a, b - a, 0.0f, 1.0f);
        contrib[i] = {rng.uniform(), rng.uniform(), rng.uniform(), 0};
    }
    for (auto& r : radiance) r = {rng.uniform(), rng.uniform(), rng.uniform(), 0};

    render::ShadowQueue q;
    q.rays = ocl::Array<Ray>::upload(dev, rays, "shadow rays");
    q.items = ocl::Array<int>::upload(dev, item, "shadow items");
    q.contrib = ocl::Array<float4>::upload(dev, contrib, "shadow contrib");
    q.count = ocl::Array<int>::upload(dev, {n}, "shadow count");
    auto rad = ocl::Array<float4>::upload(dev, radiance, "radiance");
    render::ShadowStage stage(dev, render::KernelConfig{});  // no alpha cut-outs
    // Launched past the queue length: the stage reads the length on the device.
    stage.enqueue(n + 100, q, bvh, rad);
    auto out = rad.read(dev);

    auto oracle = test::brute_force(scene.positions, scene.triangles, rays, /*any_hit=*/true);
    int occluded = 0;
    std::vector<float4> expect = radiance;
    for (int i = 0; i < n; ++i) {
        if (oracle[i].prim >= 0) {
            ++occluded;
            continue;
        }
        float4& e = expect[item[i]];
        e = e + contrib[i];
    }
    INFO(occluded << " of " << n << " segments occluded");
    CHECK(occluded > n / 10);        // both cases are exercised
    CHECK(occluded < n - n / 10);
    int wrong = 0;
    for (int k = 0; k < items; ++k)
        wrong += out[k].x != expect[k].x || out[k].y != expect[k].y || out[k].z != expect[k].z;
    CHECK(wrong == 0);
}

TEST_CASE("queue upkeep: reset counts the bounce's rays and the last bounce's shadow rays, and empties the queues",
          "[kernel][queue]") {
    auto& dev = test::device();
    render::QueueUpkeep up(dev, nullptr);
    auto in = ocl::Array<int>::upload(dev, {12345}, "count in");
    auto out = ocl::Array<int>::upload(dev, {77}, "count out");
    auto shadow = ocl::Array<int>::upload(dev, {99}, "shadow count");
    auto total = ocl::Array<cl_ulong>::upload(dev, {cl_ulong(1) << 33}, "ray total");
    auto shadow_total = ocl::Array<cl_ulong>::upload(dev, {(cl_ulong(1) << 34) + 5}, "shadow ray total");
    up.enqueue_reset(in, out, shadow, total, shadow_total);
    CHECK(shadow_total.read(dev)[0] == (cl_ulong(1) << 34) + 5 + 99);  // the previous bounce's 99
    up.enqueue_reset(in, out, shadow, total, shadow_total);
    CHECK(in.read(dev)[0] == 12345);
    CHECK(out.read(dev)[0] == 0);
    CHECK(shadow.read(dev)[0] == 0);
    // 64-bit: starts above 2^32.
    CHECK(total.read(dev)[0] == (cl_ulong(1) << 33) + 2 * 12345u);
    CHECK(shadow_total.read(dev)[0] == (cl_ulong(1) << 34) + 5 + 99);  // nothing new
}

#ifdef WP_CLI_PATH
TEST_CASE("render CLI: shadow rays traced in shade give the shadow stage's image bit for bit",
          "[render][cli][shadow]") {
    // Two implementations of the same light samples: the lane kernel tracing its shadow rays
    // itself (the default on a CPU) and the queue plus shadow stage. The built-in box (a
    // quad light, occluders) and a scene with a sphere light (pairs) and glossy plates.
    test::TempDir d;
    struct Case {
        const char* scene;
        const char* size;
    };
    for (const Case& c : {Case{"", "48x36"}, Case{"builtin:veach-plates", "40x30"}}) {
        std::string args = std::string(c.scene) + " --size " + c.size + " --spp 3 --depth 4";
        Image img[2];
        std::uint64_t shadow_rays[2] = {0, 0};
        const char* modes[2] = {"shade", "stage"};
        for (int m = 0; m < 2; ++m) {
            auto r = test::run_render(d.path, args + " --shadow-rays " + modes[m] + " -o " + modes[m] +
                                                  ".exr --profile " + modes[m] + ".json");
            INFO(args << " --shadow-rays " << modes[m] << ": " << r.err);
            REQUIRE(r.status == 0);
            auto j = nlohmann::json::parse(std::ifstream(d.path / (std::string(modes[m]) + ".json")));
            // The device is a CPU (PoCL): the lane kernel runs, so "shade" takes effect.
            CHECK(j["settings"]["shadow_rays"].get<std::string>() == modes[m]);
            shadow_rays[m] = j["rays_shadow"].get<std::uint64_t>();
            bool shadow_stage = false;
            for (auto& st : j["stages"]) shadow_stage |= st["name"] == "shadow";
            CHECK(shadow_stage == (m == 1));
            img[m] = read_image(d.path / (std::string(modes[m]) + ".exr"));
        }
        INFO(args);
        CHECK(shadow_rays[0] > 0);
        CHECK(shadow_rays[0] == shadow_rays[1]);
        REQUIRE(img[0].rgb.size() == img[1].rgb.size());
        std::size_t differ = 0;
        double sum = 0.0;
        for (std::size_t k = 0; k < img[0].rgb.size(); ++k) {
            differ += img[0].rgb[k] != img[1].rgb[k];
            sum += img[0].rgb[k];
        }
        CHECK(sum > 0.0);
        CHECK(differ == 0);
    }
    // Without light sampling there are no shadow rays to place.
    auto r = test::run_render(d.path, "--size 16x12 --spp 1 --sampling cosine -o c.exr --profile c.json");
    REQUIRE(r.status == 0);
    auto j = nlohmann::json::parse(std::ifstream(d.path / "c.json"));
    CHECK(j["settings"]["shadow_rays"].get<std::string>() == "none");
    CHECK(j["rays_shadow"].get<std::uint64_t>() == 0);
}
#endif

TEST_CASE("render: shadow rays of a scene with cut-outs go through the shadow stage's alpha test",
          "[render][shadow]") {
    // A constant alpha below its cutoff cuts a material out without any texture, so the lane
    // kernel (no textures) shades the scene; its own traversal has no alpha test, so it must
    // not trace the shadow rays. The built-in box with its tall glossy box cut out: the
    // light that box would block reaches the floor. Independent answer: the same render
    // without cut-outs differs (the box casts its shadow), and the render asking for shadows
    // in shade equals the one asking for the stage, bit for bit.
    Scene box = make_cornell_box(2000);
    Scene cut = box;
    int cut_materials = 0;
    for (Material& m : cut.materials)
        if (m.kind == MaterialKind::Glossy) {
            m.alpha_factor = 0.0f;
            ++cut_materials;
        }
    REQUIRE(cut_materials == 1);
    auto render = [](const Scene& scene, bool in_shade, std::string* mode) {
        render::RenderSettings s;
        s.width = 40;
        s.height = 30;
        s.depth = 3;
        s.shadows_in_shade = in_shade;
        render::Wavefront wf(test::device(), scene, s);
        *mode = wf.shadow_rays();
        render::LoopOptions lo;
        lo.spp = 4;
        render::render_frames(wf, lo, nullptr);
        return wf.resolve();
    };
    std::string mode_shade, mode_stage, mode_plain;
    const Image a = render(cut, true, &mode_shade), b = render(cut, false, &mode_stage);
    const Image plain = render(box, true, &mode_plain);
    CHECK(mode_shade == "stage");  // cut-outs keep the stage even when shade could trace
    CHECK(mode_stage == "stage");
    CHECK(mode_plain == "shade");
    REQUIRE(a.rgb.size() == b.rgb.size());
    std::size_t differ = 0, differ_plain = 0;
    for (std::size_t k = 0; k < a.rgb.size(); ++k) {
        differ += a.rgb[k] != b.rgb[k];
        differ_plain += a.rgb[k] != plain.rgb[k];
    }
    CHECK(differ == 0);
    CHECK(differ_plain > a.rgb.size() / 10);
}
