// test_hard_oclgrind.cpp — tiny kernel tests that also run on Oclgrind (issue 5 case 9).
//
// ctest's `oclgrind_kernels` entry runs the [oclgrind] tests and the layout probe under
// `oclgrind --check-api --data-races --uninitialized` (tests/run_oclgrind.sh) and fails on
// any report. They also run on PoCL with the rest of the suite. PoCL and Oclgrind are
// compared through a third party: every hit must equal, bit for bit, the same traversal
// compiled as C++ on the host (FP contraction is off everywhere), so the two devices agree
// with each other bit for bit.
#include <catch2/catch.hpp>

#include <cstring>
#include <vector>

#include "bvh/build.h"
#include "bvh/device_bvh.h"
#include "bvh/flatten.h"
#include "bvh/hard_cases.h"
#include "scene/procedural.h"
#include "shared/bvh_traverse.h"
#include "support.h"

using namespace wp;

TEST_CASE("oclgrind: intersect on a tiny scene equals the host traversal bit for bit", "[kernel][oclgrind]") {
    Mesh m = make_uv_sphere({0.1f, 0.0f, -0.1f}, 1.0f, 6, 8);
    append(m, make_random_soup(40, 3, {-1, -1, -1}, {1, 1, 1}, 0.5f));
    auto flat = bvh::flatten(bvh::build(bvh::triangle_boxes(m.positions, m.triangles)), m.positions, m.triangles);
    auto gpu = bvh::DeviceBvh::upload(test::device(), flat);
    bvh::BatchTracer tracer(test::device());
    auto rays = test::random_rays(200, 17, {-1.2f, -1.2f, -1.2f}, {1.2f, 1.2f, 1.2f});
    auto want = test::brute_force(m.positions, m.triangles, rays);
    auto closest = tracer.trace(gpu, rays, bvh::TraceVariant::Stackless);
    auto stack = tracer.trace(gpu, rays, bvh::TraceVariant::Stack);
    auto any = tracer.trace(gpu, rays, bvh::TraceVariant::Any);
    int differ = 0, oracle = 0, occl = 0, hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        TraceStats st{0, 0};
        Hit a = wp::wp_trace_closest(rays[i], flat.nodes.data(), flat.links.data(), flat.triangles.data(),
                                     flat.prim_ids.data(), &st);
        Hit c = wp::wp_trace_any(rays[i], flat.nodes.data(), flat.links.data(), flat.triangles.data(),
                                 flat.prim_ids.data(), &st);
        differ += std::memcmp(&a, &closest[i], sizeof(Hit)) != 0;
        differ += std::memcmp(&a, &stack[i], sizeof(Hit)) != 0;
        differ += std::memcmp(&c, &any[i], sizeof(Hit)) != 0;
        oracle += closest[i].prim != want[i].prim || (want[i].prim >= 0 && closest[i].t != want[i].t);
        occl += (any[i].prim >= 0) != (want[i].prim >= 0);
        hits += want[i].prim >= 0;
    }
    CHECK(differ == 0);
    CHECK(oracle == 0);
    CHECK(occl == 0);
    CHECK(hits > 50);
}

TEST_CASE("oclgrind: the watertight probe on tiny meshes", "[kernel][oclgrind]") {
    bvh::BatchTracer tracer(test::device());
    bvh::HardProbe probe(test::device(), tracer);
    for (const auto& c : bvh::watertight_cases(true)) {
        auto r = probe.watertight(c, 256, bvh::TraceVariant::Stackless, 3);
        INFO(c.name << ": " << r.misses << " misses of " << r.rays);
        CHECK(r.rays == 256);
        CHECK(r.misses == 0);
        CHECK(r.nonfinite == 0);
        CHECK(r.nonpositive == 0);
    }
}
