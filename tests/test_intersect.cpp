// test_intersect.cpp — the intersect kernels on PoCL against a brute-force host loop over
// every triangle (same watertight test, same tie rule: smallest index at equal t).
#include <catch2/catch.hpp>

#include <cstring>
#include <string>

#include "bvh/build.h"
#include "bvh/device_bvh.h"
#include "scene/builtin.h"
#include "scene/procedural.h"
#include "shared/bvh_traverse.h"
#include "support.h"

using namespace wp;

namespace {

struct Fixture {
    Mesh mesh;
    bvh::FlatBvh flat;
    bvh::DeviceBvh gpu;
    glm::vec3 lo, hi;
};

Fixture make_fixture(Mesh mesh) {
    Fixture f;
    f.mesh = std::move(mesh);
    auto boxes = bvh::triangle_boxes(f.mesh.positions, f.mesh.triangles);
    f.flat = bvh::flatten(bvh::build(boxes), f.mesh.positions, f.mesh.triangles);
    f.gpu = bvh::DeviceBvh::upload(test::device(), f.flat);
    Aabb b;
    for (const auto& p : f.mesh.positions) b.grow(p);
    if (b.empty()) b.lo = b.hi = glm::vec3(0.0f);
    // A little margin so some origins lie outside every triangle's box.
    glm::vec3 m = 0.05f * (b.extent() + glm::vec3(0.1f));
    f.lo = b.lo - m;
    f.hi = b.hi + m;
    return f;
}

bvh::BatchTracer& tracer() {
    static bvh::BatchTracer t(test::device());
    return t;
}

// Compares kernel hits with the oracle: exact primitive, t within 1e-5 relative.
int count_mismatches(const std::vector<Hit>& got, const std::vector<Hit>& want, std::size_t n,
                     const char* what) {
    int bad = 0;
    for (std::size_t i = 0; i < n; ++i) {
        bool ok = got[i].prim == want[i].prim;
        if (ok && want[i].prim >= 0) ok = std::fabs(got[i].t - want[i].t) <= 1e-5f * std::fabs(want[i].t);
        if (!ok && ++bad <= 5)
            UNSCOPED_INFO(what << " ray " << i << ": got prim " << got[i].prim << " t " << got[i].t
                               << ", want prim " << want[i].prim << " t " << want[i].t);
    }
    return bad;
}

void check_scene(Mesh mesh, std::size_t rays_n, std::size_t brute_n) {
    Fixture f = make_fixture(std::move(mesh));
    auto rays = test::random_rays(rays_n, 42, f.lo, f.hi);
    auto stackless = tracer().trace(f.gpu, rays, bvh::TraceVariant::Stackless);
    auto stack = tracer().trace(f.gpu, rays, bvh::TraceVariant::Stack);
    auto any = tracer().trace(f.gpu, rays, bvh::TraceVariant::Any);

    // Brute force on the first brute_n rays (all of them for small scenes).
    std::vector<Ray> sub(rays.begin(), rays.begin() + brute_n);
    auto want = test::brute_force(f.mesh.positions, f.mesh.triangles, sub);
    CHECK(count_mismatches(stackless, want, brute_n, "stackless") == 0);

    // The stack variant returns identical hits (bit for bit) on every ray.
    int differ = 0;
    for (std::size_t i = 0; i < rays_n; ++i)
        if (std::memcmp(&stack[i], &stackless[i], sizeof(Hit)) != 0) ++differ;
    CHECK(differ == 0);

    // Any hit agrees on occlusion with the closest hit, on every ray.
    int occl = 0, hits = 0;
    for (std::size_t i = 0; i < rays_n; ++i) {
        hits += stackless[i].prim >= 0;
        if ((any[i].prim >= 0) != (stackless[i].prim >= 0)) ++occl;
        // An any-hit answer must be a real hit within (tmin, tmax).
        if (any[i].prim >= 0 && !(any[i].t > 0.0f && any[i].t < FLT_MAX)) ++occl;
    }
    CHECK(occl == 0);

    // Shadow-ray form: tmax just before the closest hit. Brute force decides occlusion.
    std::vector<Ray> shadow;
    for (std::size_t i = 0; i < brute_n; ++i) {
        if (stackless[i].prim < 0) continue;
        Ray r = rays[i];
        r.dir.w = stackless[i].t * 0.999f;
        shadow.push_back(r);
    }
    auto any_short = tracer().trace(f.gpu, shadow, bvh::TraceVariant::Any);
    auto want_short = test::brute_force(f.mesh.positions, f.mesh.triangles, shadow, true);
    int shadow_bad = 0;
    for (std::size_t i = 0; i < shadow.size(); ++i)
        if ((any_short[i].prim >= 0) != (want_short[i].prim >= 0)) ++shadow_bad;
    CHECK(shadow_bad == 0);
    INFO(hits << " of " << rays_n << " rays hit");
    if (!f.mesh.triangles.empty()) CHECK(hits > 0);
}

}  // namespace

TEST_CASE("intersect kernels match brute force: random soup", "[kernel][intersect]") {
    check_scene(make_random_soup(2000, 5, {-1, -1, -1}, {1, 1, 1}, 0.25f), 100000, 100000);
}

TEST_CASE("intersect kernels match brute force: closed sphere", "[kernel][intersect]") {
    check_scene(make_uv_sphere({0.3f, -0.1f, 0.2f}, 1.0f, 32, 48), 100000, 100000);
}

TEST_CASE("intersect kernels match brute force: Cornell box (16k triangles)", "[kernel][intersect]") {
    Scene s = make_cornell_box();
    check_scene(Mesh{s.positions, s.triangles}, 100000, 12000);
}

TEST_CASE("intersect kernels match brute force: degenerate scenes", "[kernel][intersect][hard]") {
    SECTION("all coplanar, rays in and across the plane") {
        check_scene(make_random_soup(1500, 6, {-1, -1, 0}, {1, 1, 0}, 0.2f), 100000, 100000);
    }
    SECTION("all identical: the smallest index wins every tie") {
        Mesh m;
        m.positions = {{-1, -1, 0.2f}, {1, -1, 0.3f}, {0, 1, -0.1f}};
        for (int i = 0; i < 100; ++i) m.triangles.push_back({0, 1, 2});
        check_scene(m, 100000, 100000);
    }
    SECTION("single triangle") {
        Mesh m;
        m.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
        m.triangles = {{0, 1, 2}};
        check_scene(m, 100000, 100000);
    }
    SECTION("duplicated and zero-area triangles mixed with real ones") {
        Mesh m = make_random_soup(800, 8, {-1, -1, -1}, {1, 1, 1}, 0.3f);
        std::size_t n = m.triangles.size();
        for (std::size_t i = 0; i < n; i += 3) m.triangles.push_back(m.triangles[i]);  // duplicates
        for (std::size_t i = 0; i < n; i += 5) {
            auto t = m.triangles[i];
            m.triangles.push_back({t.x, t.y, t.y});  // zero area
        }
        check_scene(m, 100000, 100000);
    }
}

TEST_CASE("an empty scene is all misses", "[kernel][intersect]") {
    Fixture f = make_fixture(Mesh{});
    auto rays = test::random_rays(1000, 1, {-1, -1, -1}, {1, 1, 1});
    for (auto v : {bvh::TraceVariant::Stackless, bvh::TraceVariant::Stack, bvh::TraceVariant::Any}) {
        auto hits = tracer().trace(f.gpu, rays, v);
        int any_hit = 0;
        for (const auto& h : hits) any_hit += h.prim >= 0 || h.t != FLT_MAX;
        CHECK(any_hit == 0);
    }
}

// The shared traversal header also compiles as C++ (the host side of compat.h, later
// CUDA): the host build of every traversal must agree bit for bit with the kernels.
TEST_CASE("the traversals compiled for the host match the kernels", "[kernel][intersect]") {
    Scene s = make_cornell_box();
    Fixture f = make_fixture(Mesh{s.positions, s.triangles});
    auto rays = test::random_rays(20000, 7, f.lo, f.hi);
    auto dev_closest = tracer().trace(f.gpu, rays, bvh::TraceVariant::Stackless);
    auto dev_any = tracer().trace(f.gpu, rays, bvh::TraceVariant::Any);
    int differ = 0, any_differ = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        TraceStats st{0, 0};
        Hit a = wp::wp_trace_closest(rays[i], f.flat.nodes.data(), f.flat.links.data(), f.flat.triangles.data(),
                                     f.flat.prim_ids.data(), &st);
        Hit b = wp::wp_trace_closest_stack(rays[i], f.flat.nodes.data(), f.flat.links.data(),
                                           f.flat.triangles.data(), f.flat.prim_ids.data(), &st);
        Hit c = wp::wp_trace_any(rays[i], f.flat.nodes.data(), f.flat.links.data(), f.flat.triangles.data(),
                                 f.flat.prim_ids.data(), &st);
        if (std::memcmp(&a, &dev_closest[i], sizeof(Hit)) != 0 || std::memcmp(&b, &a, sizeof(Hit)) != 0) ++differ;
        if ((c.prim >= 0) != (dev_any[i].prim >= 0)) ++any_differ;
    }
    CHECK(differ == 0);
    CHECK(any_differ == 0);
}

// The stackless traversal's ring of recent pending ancestors only saves re-tests: with a
// ring of 1 (overrun at every second pending level, so the up-link climb and re-test run
// often), 2 or the default, every hit equals the stack oracle's bit for bit, and the
// smaller rings do more box tests (the fallback really ran).
TEST_CASE("stackless traversal: the ancestor ring's size never changes a hit", "[kernel][intersect]") {
    Mesh soup = make_random_soup(20000, 9, {-1, -1, -1}, {1, 1, 1}, 0.05f);
    Fixture f = make_fixture(std::move(soup));
    auto rays = test::random_rays(20000, 3, f.lo, f.hi);
    auto want = tracer().trace(f.gpu, rays, bvh::TraceVariant::Stack);
    // The any-hit traversal's own ring (WP_BVH_ANY_RING) the same way: the same first hit
    // (bit for bit) with every ring size, on full rays and on shadow segments that end
    // just before or just after the closest hit, and occlusion as the closest hit says.
    std::vector<Ray> shadow = rays;
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (want[i].prim >= 0) shadow[i].dir.w = want[i].t * (i % 2 ? 0.999f : 1.001f);
    auto want_any = tracer().trace(f.gpu, rays, bvh::TraceVariant::Any);
    auto want_any_short = tracer().trace(f.gpu, shadow, bvh::TraceVariant::Any);
    long tests_default = 0, any_tests_default = 0;
    for (int ring : {0, 1, 2}) {
        bvh::BatchTracer t(test::device(), true,
                           ring ? "-D WP_BVH_SHORT_STACK=" + std::to_string(ring) +
                                      " -D WP_BVH_ANY_RING=" + std::to_string(ring)
                                : "");
        std::vector<TraceStats> st, st_any;
        auto got = t.trace(f.gpu, rays, bvh::TraceVariant::Stackless, &st);
        auto any = t.trace(f.gpu, rays, bvh::TraceVariant::Any, &st_any);
        auto any_short = t.trace(f.gpu, shadow, bvh::TraceVariant::Any);
        int differ = 0, occl = 0, any_differ = 0, short_hits = 0;
        long box_tests = 0, any_box_tests = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (std::memcmp(&got[i], &want[i], sizeof(Hit)) != 0) ++differ;
            if ((any[i].prim >= 0) != (want[i].prim >= 0)) ++occl;
            if (std::memcmp(&any[i], &want_any[i], sizeof(Hit)) != 0) ++any_differ;
            if (std::memcmp(&any_short[i], &want_any_short[i], sizeof(Hit)) != 0) ++any_differ;
            short_hits += any_short[i].prim >= 0;
            box_tests += st[i].box_tests;
            any_box_tests += st_any[i].box_tests;
        }
        INFO("ring " << (ring ? ring : WP_BVH_SHORT_STACK) << ": " << box_tests << " box tests; any-hit ring "
                     << (ring ? ring : WP_BVH_ANY_RING) << ": " << any_box_tests);
        CHECK(differ == 0);
        CHECK(occl == 0);
        CHECK(any_differ == 0);
        CHECK(short_hits > 0);
        if (ring == 0) {
            tests_default = box_tests;
            any_tests_default = any_box_tests;
        } else {
            CHECK(box_tests > tests_default);
            CHECK(any_box_tests > any_tests_default);
        }
    }
}

// wp_trace_any is the generic stackless walk (wp_trace_stackless with any_hit = 1)
// specialised for a constant cull distance and stopping at the first triangle hit inside
// a leaf: the same leaves in the same order, so the same occlusion on every ray, and its
// hit is a real one (the triangle test on that triangle gives the same t, below tmax) in
// the leaf where the generic walk stopped (so never before the generic walk's t). Here on
// the host build, on full rays and on segments that end just before or just after the
// closest hit (the kernels match the host build: above).
TEST_CASE("any hit: the specialised traversal agrees with the generic walk", "[kernel][intersect]") {
    for (int scene = 0; scene < 2; ++scene) {
        Scene s = make_cornell_box();
        Fixture f = scene == 0 ? make_fixture(Mesh{s.positions, s.triangles})
                               : make_fixture(make_random_soup(20000, 11, {-1, -1, -1}, {1, 1, 1}, 0.05f));
        auto rays = test::random_rays(20000, 13, f.lo, f.hi);
        int bad = 0, hits = 0, short_hits = 0, other_prim = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Ray& r = rays[i];
            TraceStats st{0, 0};
            Hit closest = wp::wp_trace_closest(r, f.flat.nodes.data(), f.flat.links.data(), f.flat.triangles.data(),
                                               f.flat.prim_ids.data(), &st);
            Ray seg = r;
            if (closest.prim >= 0) seg.dir.w = closest.t * (i % 2 ? 0.999f : 1.001f);
            for (const Ray& q : {r, seg}) {
                TraceStats sa{0, 0}, sb{0, 0};
                Hit a = wp::wp_trace_any(q, f.flat.nodes.data(), f.flat.links.data(), f.flat.triangles.data(),
                                         f.flat.prim_ids.data(), &sa);
                Hit b = wp::wp_trace_stackless(q, f.flat.nodes.data(), f.flat.links.data(),
                                               f.flat.triangles.data(), f.flat.prim_ids.data(), 1, &sb);
                bool ok = (a.prim >= 0) == (b.prim >= 0);
                if (a.prim < 0) {
                    ok = ok && std::memcmp(&a, &b, sizeof(Hit)) == 0;
                } else {
                    auto p = [&](int k) {
                        glm::vec3 v = f.mesh.positions[f.mesh.triangles[a.prim][k]];
                        return float4{v.x, v.y, v.z, 0.0f};
                    };
                    TriRay tr = wp::wp_tri_ray(q);
                    float t, u, v;
                    ok = ok && wp::wp_intersect_triangle(&tr, p(0), p(1), p(2), &t, &u, &v) && t == a.t &&
                         u == a.u && v == a.v && a.t < q.dir.w && a.t >= b.t;
                    other_prim += a.prim != b.prim;
                }
                if (!ok && ++bad <= 5)
                    UNSCOPED_INFO("ray " << i << ": any prim " << a.prim << " t " << a.t << ", generic prim "
                                         << b.prim << " t " << b.t);
            }
            hits += closest.prim >= 0;
            Hit a = wp::wp_trace_any(seg, f.flat.nodes.data(), f.flat.links.data(), f.flat.triangles.data(),
                                     f.flat.prim_ids.data(), &st);
            short_hits += a.prim >= 0;
        }
        INFO("scene " << scene << ": " << hits << " hits, " << short_hits << " occluded segments, " << other_prim
                      << " hits on another triangle of the leaf");
        CHECK(bad == 0);
        CHECK(hits > 1000);
        CHECK(short_hits > 0);
    }
}

// wp_trace_closest is the generic stackless walk (wp_trace_stackless with any_hit = 0)
// specialised (no any_hit branches, no "resumed" state, the cull distance kept between
// hits): the same nodes tested in the same order, so every hit is the same bit for bit,
// on full rays and on segments that end just before or just after the closest hit. Here
// on the host build (the kernels match the host build: above).
TEST_CASE("closest hit: the specialised traversal agrees with the generic walk", "[kernel][intersect]") {
    for (int scene = 0; scene < 2; ++scene) {
        Scene s = make_cornell_box();
        Fixture f = scene == 0 ? make_fixture(Mesh{s.positions, s.triangles})
                               : make_fixture(make_random_soup(20000, 17, {-1, -1, -1}, {1, 1, 1}, 0.05f));
        auto rays = test::random_rays(20000, 19, f.lo, f.hi);
        int differ = 0, hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            TraceStats sa{0, 0}, sb{0, 0};
            Hit a = wp::wp_trace_closest(rays[i], f.flat.nodes.data(), f.flat.links.data(),
                                         f.flat.triangles.data(), f.flat.prim_ids.data(), &sa);
            Hit b = wp::wp_trace_stackless(rays[i], f.flat.nodes.data(), f.flat.links.data(),
                                           f.flat.triangles.data(), f.flat.prim_ids.data(), 0, &sb);
            differ += std::memcmp(&a, &b, sizeof(Hit)) != 0;
            hits += a.prim >= 0;
            if (a.prim < 0) continue;
            Ray seg = rays[i];
            seg.dir.w = a.t * (i % 2 ? 0.999f : 1.001f);
            a = wp::wp_trace_closest(seg, f.flat.nodes.data(), f.flat.links.data(), f.flat.triangles.data(),
                                     f.flat.prim_ids.data(), &sa);
            b = wp::wp_trace_stackless(seg, f.flat.nodes.data(), f.flat.links.data(), f.flat.triangles.data(),
                                       f.flat.prim_ids.data(), 0, &sb);
            differ += std::memcmp(&a, &b, sizeof(Hit)) != 0;
        }
        INFO("scene " << scene << ": " << hits << " hits");
        CHECK(hits > 1000);
        CHECK(differ == 0);
    }
}

namespace {

// intersect_final (the last bounce's rays): through the emitters' BVH first, then the
// scene up to the emitter met. Against the brute-force closest hit over every triangle:
// where that hit emits, the same hit (and bit for bit the closest-hit kernel's); elsewhere
// a miss or, where an emitter lies behind, the closest-hit kernel's hit. Returns the rays
// whose closest hit emits and those whose emitter was hidden behind another triangle.
std::pair<int, int> check_final(const Mesh& mesh, const std::vector<int>& emitters, std::size_t rays_n) {
    Fixture f = make_fixture(mesh);
    bvh::DeviceBvh e = bvh::DeviceBvh::upload(test::device(), bvh::flatten_subset(f.mesh.positions, f.mesh.triangles, emitters), "the emitters'");
    std::vector<char> emits(f.mesh.triangles.size(), 0);
    for (int k : emitters) emits[static_cast<std::size_t>(k)] = 1;
    auto rays = test::random_rays(rays_n, 7, f.lo, f.hi);
    auto want = test::brute_force(f.mesh.positions, f.mesh.triangles, rays);
    auto closest = tracer().trace(f.gpu, rays, bvh::TraceVariant::Stackless);
    int direct = 0, hidden = 0;
    {
        auto got = tracer().trace_final(f.gpu, e, rays);
        int bad = 0;
        direct = hidden = 0;
        for (std::size_t i = 0; i < rays_n; ++i) {
            const bool same = std::memcmp(&got[i], &closest[i], sizeof(Hit)) == 0;
            const bool emitter = want[i].prim >= 0 && emits[static_cast<std::size_t>(want[i].prim)];
            bool ok;
            if (emitter) {
                ok = same && got[i].prim == want[i].prim;
                ++direct;
            } else {
                ok = got[i].prim < 0 || same;
                if (got[i].prim >= 0 && same) ++hidden;
                // A miss carries the ray's tmax, as every traversal's miss does.
                if (got[i].prim < 0) ok = ok && got[i].t == rays[i].dir.w;
            }
            if (!ok && ++bad <= 5)
                UNSCOPED_INFO("ray " << i << ": got prim " << got[i].prim
                              << " t " << got[i].t << ", closest prim " << closest[i].prim << " t "
                              << closest[i].t << (emitter ? " (emits)" : ""));
        }
        CHECK(bad == 0);
    }
    return {direct, hidden};
}

}  // namespace

TEST_CASE("last-bounce rays: the emitters' BVH first gives the closest hit wherever it emits",
          "[kernel][intersect]") {
    SECTION("random soup, every fifth triangle emits") {
        Mesh m = make_random_soup(2000, 5, {-1, -1, -1}, {1, 1, 1}, 0.25f);
        std::vector<int> em;
        for (int i = 0; i < 2000; i += 5) em.push_back(i);
        auto [direct, hidden] = check_final(m, em, 60000);
        INFO(direct << " rays end on an emitter, " << hidden << " meet one behind another triangle");
        CHECK(direct > 1000);
        CHECK(hidden > 1000);  // the second trace's work: the emitter is not the closest hit
    }
    SECTION("coplanar copies: an emitter and a non-emitter in the same place, ties by index") {
        // Every triangle twice; the closest hit of a tie is the smaller index (the original),
        // so where the copies emit, the closest hit is a non-emitter at the emitter's t: only
        // a second trace that keeps hits at t = t_e finds it.
        Mesh m = make_random_soup(600, 11, {-1, -1, -1}, {1, 1, 1}, 0.3f);
        const auto n = m.triangles.size();
        for (std::size_t i = 0; i < n; ++i) m.triangles.push_back(m.triangles[i]);
        std::vector<int> copies, originals;
        for (std::size_t i = 0; i < n; ++i) {
            copies.push_back(static_cast<int>(n + i));
            originals.push_back(static_cast<int>(i));
        }
        auto [d1, h1] = check_final(m, copies, 30000);
        CHECK(d1 == 0);
        CHECK(h1 > 1000);
        auto [d2, h2] = check_final(m, originals, 30000);
        CHECK(d2 > 1000);
        (void)h2;
    }
    SECTION("the built-in Cornell box's light") {
        Scene s = make_cornell_box();
        std::vector<int> em;
        for (std::size_t i = 0; i < s.triangles.size(); ++i)
            if (s.materials[static_cast<std::size_t>(s.material_ids[i])].emissive()) em.push_back(static_cast<int>(i));
        REQUIRE(!em.empty());
        auto [direct, hidden] = check_final(Mesh{s.positions, s.triangles}, em, 12000);
        CHECK(direct > 0);
        (void)hidden;
    }
}
