// test_hard.cpp — numerical hard cases of issue 5 through the real intersect kernels, each
// against an independent answer: geometry (a ray that crosses a closed surface must hit
// it; a ray leaving a flat triangle cannot meet it again), an analytic value (the plane
// distance in double precision, the furnace's Le (1 + rho + rho^2)) or the brute-force
// oracle (tests/support.h). The criteria and the last measured results are in
// docs/hard-cases.md; `wavepath bench hard` runs the large versions.
//
// Cases covered elsewhere (not duplicated here):
//   * NaN/Inf vertices refused at load: tests/test_scene.cpp ("validate_scene names each
//     defect", "load_obj: bad files give one clear error ...": nan.obj:2: ... non-finite);
//   * 10^6 samples of a constant exact to 1e-6: tests/test_accumulate.cpp ("the
//     compensated sum keeps 6+ digits over 10^6 samples"), NaN/Inf samples counted and
//     dropped by accumulate: same file;
//   * duplicated / zero-area / all-identical triangles against brute force:
//     tests/test_intersect.cpp ("degenerate scenes").
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "bvh/build.h"
#include "bvh/device_bvh.h"
#include "bvh/flatten.h"
#include "bvh/hard_cases.h"
#include "image/stats.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "scene/procedural.h"
#include "shared/offset.h"
#include "support.h"

using namespace wp;

namespace {

bvh::BatchTracer& tracer() {
    static bvh::BatchTracer t(test::device());
    return t;
}

bvh::DeviceBvh upload(const Mesh& m, bvh::BuildOptions opt = {}, bvh::FlatBvh* keep = nullptr) {
    auto flat = bvh::flatten(bvh::build(bvh::triangle_boxes(m.positions, m.triangles), opt), m.positions,
                             m.triangles);
    auto d = bvh::DeviceBvh::upload(test::device(), flat);
    if (keep) *keep = std::move(flat);
    return d;
}

// Hits equal to the oracle's: same triangle and, for a hit, bit-identical t (the oracle
// runs the same triangle test on the same inputs). Misses must report t = tmax.
int mismatches(const std::vector<Hit>& got, const std::vector<Hit>& want, const std::vector<Ray>& rays,
               const char* what) {
    int bad = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        bool ok = got[i].prim == want[i].prim;
        if (ok && want[i].prim >= 0) ok = got[i].t == want[i].t && std::isfinite(got[i].t);
        if (ok && want[i].prim < 0) ok = got[i].t == rays[i].dir.w;
        if (!ok && ++bad <= 5)
            UNSCOPED_INFO(what << " ray " << i << " org (" << rays[i].org.x << ", " << rays[i].org.y << ", "
                               << rays[i].org.z << ") dir (" << rays[i].dir.x << ", " << rays[i].dir.y << ", "
                               << rays[i].dir.z << "): got prim " << got[i].prim << " t " << got[i].t
                               << ", want prim " << want[i].prim << " t " << want[i].t);
    }
    return bad;
}

}  // namespace

// Case 1. Criterion: 0 misses (and no NaN/Inf or non-positive t) over >= 10^7 rays aimed at
// shared edges and vertices from inside and outside; the other two traversals on 2^18 each.
TEST_CASE("hard: watertight meshes have no cracks at shared edges and vertices", "[hard][kernel]") {
    bvh::HardProbe probe(test::device(), tracer());
    std::uint64_t total = 0;
    for (const auto& c : bvh::watertight_cases()) {
        for (auto v : {bvh::TraceVariant::Stackless, bvh::TraceVariant::Stack, bvh::TraceVariant::Any}) {
            std::uint64_t n = v == bvh::TraceVariant::Stackless ? 2600000 : (1u << 18);
            auto r = probe.watertight(c, n, v, 11);
            INFO(c.name << " (" << c.mesh.triangles.size() << " triangles, " << c.segments.size() / 2
                        << " targets), " << bvh::to_string(v) << ": " << r.misses << " misses of " << r.rays
                        << " rays in " << r.seconds << " s");
            CHECK(r.rays == n);
            CHECK(r.misses == 0);
            CHECK(r.nonfinite == 0);
            CHECK(r.nonpositive == 0);
            if (v == bvh::TraceVariant::Stackless) total += r.rays;
        }
    }
    CHECK(total >= 10000000);
}

// The ray through the shared diagonal of the two-triangle square, and rays that
// differ from it by one ulp in each direction component: every one hits, in every variant
// and in the oracle.
TEST_CASE("hard: the issue's ray through the diagonal of the two-triangle square", "[hard][kernel]") {
    Mesh m;
    m.positions = {{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    auto gpu = upload(m);
    std::vector<Ray> rays;
    glm::vec3 d0{0.30458447f, 0.30458447f, -0.9024725f};
    auto step = [](float x, int k) {
        for (int j = 0; j < std::abs(k); ++j) x = std::nextafter(x, k < 0 ? -INFINITY : INFINITY);
        return x;
    };
    for (int dx = -4; dx <= 4; ++dx)
        for (int dy = -4; dy <= 4; ++dy)
            rays.push_back(test::make_ray({0, 0, 10}, {step(d0.x, dx), step(d0.y, dy), d0.z}));
    auto want = test::brute_force(m.positions, m.triangles, rays);
    for (auto v : {bvh::TraceVariant::Stackless, bvh::TraceVariant::Stack, bvh::TraceVariant::Any}) {
        auto got = tracer().trace(gpu, rays, v);
        int miss = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) miss += got[i].prim < 0 || want[i].prim < 0;
        INFO(bvh::to_string(v));
        CHECK(miss == 0);
        if (v != bvh::TraceVariant::Any) CHECK(mismatches(got, want, rays, bvh::to_string(v)) == 0);
    }
    // The exact ray: t = 10 / 0.9024725 to float precision, on the diagonal x = y.
    auto h = tracer().trace(gpu, {rays[40]}, bvh::TraceVariant::Stackless)[0];
    REQUIRE(h.prim >= 0);
    CHECK(h.t == Approx(10.0 / 0.9024725).epsilon(1e-6));
}

// Case 2. Criterion: the same hits as brute force (triangle and bit-identical t), no NaN,
// for directions with +0 / -0 components, rays in the plane of a flat (zero-thickness)
// box, and origins exactly on box faces; any-hit agrees on occlusion.
TEST_CASE("hard: zero and negative-zero directions, flat boxes, origins on box faces", "[hard][kernel]") {
    Mesh m = make_quad({-2, -2, 0}, {4, 0, 0}, {0, 4, 0}, 8, 8);      // flat in z (a flat subtree)
    append(m, make_quad({-1.5f, -2, -1}, {0, 4, 0}, {0, 0, 2}, 2, 2));  // flat in x, crosses z = 0
    append(m, make_box({0.5f, 0.5f, 0.25f}, {1.5f, 1.5f, 1.25f}, 2));
    append(m, make_quad({-2, 1.75f, -1}, {4, 0, 0}, {0, 0, 2}, 3, 1));  // flat in y
    auto gpu = upload(m);
    test::Rng rng(5);
    const float zeros[2] = {0.0f, -0.0f};
    // Planes that are faces of triangle boxes (and so of BVH boxes).
    const float face_x[] = {-2.0f, -1.5f, 0.5f, 1.5f, 2.0f};
    const float face_y[] = {-2.0f, 0.5f, 1.5f, 1.75f, 2.0f};
    const float face_z[] = {0.0f, 0.25f, 1.25f, -1.0f, 1.0f};
    std::vector<Ray> rays;
    for (int i = 0; i < 60000; ++i) {
        glm::vec3 o{rng.uniform(-2.5f, 2.5f), rng.uniform(-2.5f, 2.5f), rng.uniform(-1.5f, 1.5f)};
        glm::vec3 d = rng.unit_vector();
        switch (i % 6) {
        case 0:  // in the plane z = 0 of the flat quad grid, dir.z = +-0
            o.z = zeros[i / 6 % 2];
            d.z = zeros[i / 12 % 2];
            break;
        case 1:  // origin on a face plane of some box, one zero component
            o.x = face_x[i / 6 % 5];
            d[i / 30 % 3] = zeros[i / 90 % 2];
            break;
        case 2:
            o.y = face_y[i / 6 % 5];
            o.z = face_z[i / 30 % 5];
            d[i / 150 % 3] = zeros[i / 450 % 2];
            break;
        case 3:  // axis-parallel: two zero components of either sign
        {
            int a = i / 6 % 3;
            d = glm::vec3(zeros[i / 18 % 2], zeros[i / 36 % 2], zeros[i / 72 % 2]);
            d[a] = (i / 144 % 2) ? 1.0f : -1.0f;
            o.z = face_z[i / 288 % 5];
            break;
        }
        case 4:  // in the plane x = -1.5 of the wall, dir.x = +-0
            o.x = -1.5f;
            d.x = zeros[i / 6 % 2];
            break;
        default:  // aimed at a vertex of the grid along a zero component
            o = glm::vec3(-2.0f + 0.5f * (i / 6 % 9), -2.0f + 0.5f * (i / 54 % 9), 1.0f);
            d = glm::vec3(zeros[i / 6 % 2], zeros[i / 12 % 2], -1.0f);
            break;
        }
        if (glm::length(d) == 0.0f) d.z = 1.0f;
        rays.push_back(test::make_ray(o, d));
    }
    auto want = test::brute_force(m.positions, m.triangles, rays);
    auto stackless = tracer().trace(gpu, rays, bvh::TraceVariant::Stackless);
    auto stack = tracer().trace(gpu, rays, bvh::TraceVariant::Stack);
    auto any = tracer().trace(gpu, rays, bvh::TraceVariant::Any);
    CHECK(mismatches(stackless, want, rays, "stackless") == 0);
    CHECK(mismatches(stack, want, rays, "stack") == 0);
    int occl = 0, hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += want[i].prim >= 0;
        occl += (any[i].prim >= 0) != (want[i].prim >= 0);
        if (any[i].prim >= 0 && !std::isfinite(any[i].t)) ++occl;
    }
    CHECK(occl == 0);
    CHECK(hits > 10000);  // the test has power
}

// Case 3. Criterion: no secondary ray (cosine, uniform and mirror directions from offset
// origins, offset.h) re-hits the triangle it left, at every scale; no NaN.
TEST_CASE("hard: no self-intersection at scales 1e-4, 1 and 1e5 and translated by 1e5", "[hard][kernel]") {
    Scene s = make_cornell_box();
    Mesh mesh{s.positions, s.triangles};
    auto primary = bvh::camera_rays(s.camera.position, s.camera.target, s.camera.up, s.camera.vfov_deg, 400, 300);
    struct Scale {
        float scale;
        glm::vec3 shift;
    };
    for (Scale sc : {Scale{1.0f, {0, 0, 0}}, Scale{1e-4f, {0, 0, 0}}, Scale{1e5f, {0, 0, 0}},
                     Scale{1.0f, {1e5f, 1e5f, 1e5f}}}) {
        auto r = bvh::self_intersections(test::device(), tracer(), mesh, primary, sc.scale, sc.shift);
        INFO("scale " << sc.scale << " shift " << sc.shift.x << ": " << r.same_triangle << " self-hits of "
                      << r.rays << " secondary rays (" << r.primary_hits << " primary hits)");
        CHECK(r.primary_hits > 60000);
        CHECK(r.same_triangle == 0);
        CHECK(r.nonfinite == 0);
        // Scale-free: the largest offset is a few millionths of the scene's largest
        // coordinate at every scale (Wachter & Binder's fixed 256 ulps = 1.5e-5, or 2^-16
        // absolute near 0, fail this; measured 3.0e-6 at every scale, 5.9e-7 translated).
        double coord = 0.0;
        for (const auto& p : mesh.positions) {
            glm::vec3 q = p * sc.scale + sc.shift;
            coord = std::max({coord, double(std::fabs(q.x)), double(std::fabs(q.y)), double(std::fabs(q.z))});
        }
        INFO("largest offset " << r.max_offset << " = " << r.max_offset / coord << " x the largest coordinate");
        CHECK(r.max_offset <= 1e-5 * coord);
    }
}

// Case 3, the bound itself: for random triangles at scales 1e-30 ... 1e30 and far from the
// origin, the float hit point of shared/offset.h lies within its error bound of the exact
// point (double arithmetic on the same float vertices and barycentrics; the exact point is
// in the triangle's plane), and the offset origin lies strictly on the side it leaves
// (signed distance to the plane in double > 0), for both sides.
TEST_CASE("hard: hit-point error bounds hold and offset origins leave the plane", "[hard][unit]") {
    test::Rng rng(77);
    int below = 0, outside = 0, n = 0;
    for (double scale : {1e-30, 1e-4, 1.0, 1e5, 1e30})
        for (double shift : {0.0, 1.0, 1e5})
            for (int i = 0; i < 20000; ++i) {
                auto rnd = [&] { return glm::dvec3(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0 - 1.0; };
                glm::dvec3 c = rnd() * shift * scale;  // some triangles far from the origin
                glm::vec3 v[3];
                for (auto& x : v) x = glm::vec3(c + rnd() * scale);
                float u = rng.uniform(), w = rng.uniform();
                if (u + w > 1.0f) { u = 1.0f - u; w = 1.0f - w; }
                if (i % 10 == 0) u = 0.0f;  // on edges and vertices too
                if (i % 15 == 0) w = 0.0f;
                glm::dvec3 d0(v[0]), d1(v[1]), d2(v[2]);
                glm::dvec3 nd = glm::cross(d1 - d0, d2 - d0);
                if (!(glm::length(nd) > 0.0)) continue;
                nd = glm::normalize(nd);
                glm::dvec3 exact = d0 + double(u) * (d1 - d0) + double(w) * (d2 - d0);
                auto f3 = [](glm::vec3 a) { return make_float3(a.x, a.y, a.z); };
                float3 err;
                float3 p = wp_hit_point(f3(v[0]), f3(v[1]), f3(v[2]), u, w, &err);
                if (std::fabs(p.x - exact.x) > err.x || std::fabs(p.y - exact.y) > err.y ||
                    std::fabs(p.z - exact.z) > err.z)
                    ++outside;
                for (double side : {1.0, -1.0}) {
                    glm::vec3 nf = glm::vec3(nd * side);
                    float3 o = wp_offset_ray_origin(p, err, f3(nf), 0.0f);
                    double dist = glm::dot(glm::dvec3(o.x, o.y, o.z) - exact, nd * side);
                    if (!(dist > 0.0)) ++below;
                }
                ++n;
            }
    INFO(n << " triangles: " << outside << " hit points outside their bound, " << below
           << " origins not strictly in front");
    CHECK(n > 250000);
    CHECK(outside == 0);
    CHECK(below == 0);
}

// Case 4. Rays at 89.99 degrees to the normal of a plane (0.01 degrees above it): no NaN,
// every ray that reaches the plane inside the grid hits, at the analytic distance (double
// precision) within 1e-4 relative, and the same triangle as brute force.
TEST_CASE("hard: grazing rays at 89.99 degrees hit at the analytic distance", "[hard][kernel]") {
    Mesh m = make_quad({-10, -10, 0}, {20, 0, 0}, {0, 20, 0}, 16, 16);
    auto gpu = upload(m);
    test::Rng rng(3);
    const double theta = (90.0 - 0.01) * 3.14159265358979323846 / 180.0;
    std::vector<Ray> rays;
    std::vector<double> t_exact;
    for (int i = 0; i < 50000; ++i) {
        double phi = 6.283185307179586 * rng.uniform();
        glm::vec3 d(static_cast<float>(std::sin(theta) * std::cos(phi)),
                    static_cast<float>(std::sin(theta) * std::sin(phi)), static_cast<float>(-std::cos(theta)));
        float h = rng.uniform(1e-4f, 1e-3f);
        glm::vec3 o{rng.uniform(-3.0f, 3.0f), rng.uniform(-3.0f, 3.0f), (i % 2) ? h : -h};
        if (i % 2) {
            rays.push_back(test::make_ray(o, d));
        } else {
            d.z = -d.z;  // from below, upwards
            rays.push_back(test::make_ray(o, d));
        }
        t_exact.push_back(-static_cast<double>(o.z) / static_cast<double>(d.z));
    }
    auto want = test::brute_force(m.positions, m.triangles, rays);
    int bad = 0, nan = 0, wrong_t = 0;
    for (auto v : {bvh::TraceVariant::Stackless, bvh::TraceVariant::Stack}) {
        auto got = tracer().trace(gpu, rays, v);
        bad += mismatches(got, want, rays, bvh::to_string(v));
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (got[i].prim < 0 || std::isnan(got[i].t)) {
                ++nan;
                continue;
            }
            if (std::fabs(got[i].t - t_exact[i]) > 1e-4 * t_exact[i] && ++wrong_t <= 5)
                UNSCOPED_INFO("ray " << i << ": t " << got[i].t << ", analytic " << t_exact[i]);
        }
    }
    CHECK(bad == 0);
    CHECK(nan == 0);
    CHECK(wrong_t == 0);
}

// Case 5. Coplanar overlapping, needle, zero-area and duplicated triangles: the winner is
// the documented one (smallest t, then smallest index: brute force in scene order) for
// every BVH build (leaf sizes 1, 2, 8; 4 and 16 bins) and every traversal, bit for bit.
TEST_CASE("hard: the tie rule picks the same winner under every BVH build and traversal", "[hard][kernel]") {
    Mesh m;
    test::Rng rng(9);
    // 300 overlapping triangles in the plane z = 0.5, 200 in the plane x + y + z = 1.
    for (int i = 0; i < 500; ++i) {
        glm::vec3 c{rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f), 0.0f};
        glm::vec3 p[3];
        for (auto& q : p) q = c + glm::vec3(rng.uniform(-0.6f, 0.6f), rng.uniform(-0.6f, 0.6f), 0.0f);
        if (i < 300) {
            for (auto& q : p) q.z = 0.5f;
        } else {
            for (auto& q : p) q.z = 1.0f - q.x - q.y;
        }
        unsigned b = static_cast<unsigned>(m.positions.size());
        m.positions.insert(m.positions.end(), p, p + 3);
        m.triangles.push_back({b, b + 1, b + 2});
    }
    // Needles (width 1e-6 over length 2), zero-area (collinear and repeated vertices).
    for (int i = 0; i < 50; ++i) {
        float y = rng.uniform(-0.5f, 0.5f);
        unsigned b = static_cast<unsigned>(m.positions.size());
        m.positions.push_back({-1.0f, y, 0.5f});
        m.positions.push_back({1.0f, y + 1e-6f, 0.5f});
        m.positions.push_back({0.0f, y, 0.5f});  // collinear with the first: zero area
        m.triangles.push_back({b, b + 1, b + 2 - (i % 2)});
        m.triangles.push_back({b, b + 2, b + 2});
    }
    // Duplicates of the first 100.
    for (int i = 0; i < 100; ++i) m.triangles.push_back(m.triangles[i]);

    std::vector<Ray> rays;
    for (int i = 0; i < 40000; ++i) {
        glm::vec3 o{rng.uniform(-1, 1), rng.uniform(-1, 1), (i % 2) ? 2.0f : -1.5f};
        glm::vec3 target{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.0f, 1.0f)};
        if (i % 4 == 3) target.z = 0.5f;
        rays.push_back(test::make_ray(o, target - o));
    }
    auto want = test::brute_force(m.positions, m.triangles, rays);
    std::vector<Hit> first;
    int builds = 0;
    for (int leaf : {1, 2, 8})
        for (int bins : {4, 16}) {
            bvh::BuildOptions opt;
            opt.max_leaf = leaf;
            opt.bins = bins;
            auto gpu = upload(m, opt);
            for (auto v : {bvh::TraceVariant::Stackless, bvh::TraceVariant::Stack}) {
                auto got = tracer().trace(gpu, rays, v);
                INFO("max_leaf " << leaf << " bins " << bins << " " << bvh::to_string(v));
                CHECK(mismatches(got, want, rays, bvh::to_string(v)) == 0);
                if (first.empty()) first = got;
                CHECK(std::memcmp(first.data(), got.data(), got.size() * sizeof(Hit)) == 0);
                ++builds;
            }
            auto any = tracer().trace(gpu, rays, bvh::TraceVariant::Any);
            int occl = 0;
            for (std::size_t i = 0; i < rays.size(); ++i) occl += (any[i].prim >= 0) != (want[i].prim >= 0);
            CHECK(occl == 0);
        }
    CHECK(builds == 12);
    int hits = 0;
    for (const auto& h : want) hits += h.prim >= 0;
    CHECK(hits > 10000);
}

// Case 7 (the part that is not the render's debug option): NaN and Inf in rays fed straight
// to the intersect kernels. Criterion: the kernels finish, and a reported hit never has a
// NaN/Inf t; a ray with a NaN origin or direction component, or a zero direction, misses.
TEST_CASE("hard: NaN and Inf rays through the intersect kernels", "[hard][kernel]") {
    Scene s = make_cornell_box(2000);
    Mesh mesh{s.positions, s.triangles};
    auto gpu = upload(mesh);
    const float nan = std::nanf(""), inf = INFINITY;
    std::vector<Ray> rays;
    test::Rng rng(4);
    for (int i = 0; i < 4000; ++i) {
        glm::vec3 o{rng.uniform(-0.9f, 0.9f), rng.uniform(0.1f, 1.9f), rng.uniform(-0.9f, 0.9f)};
        glm::vec3 d = rng.unit_vector();
        Ray r = test::make_ray(o, d);
        float* f = &r.org.x;
        int k = i % 8;
        if (i % 3 == 0) f[k] = nan;
        else if (i % 3 == 1) f[k] = (i & 8) ? inf : -inf;
        else if (k < 4) r.dir = float4{0.0f, -0.0f, 0.0f, FLT_MAX};  // zero direction
        rays.push_back(r);
    }
    for (auto v : {bvh::TraceVariant::Stackless, bvh::TraceVariant::Stack, bvh::TraceVariant::Any}) {
        auto got = tracer().trace(gpu, rays, v);
        int bad_t = 0, nan_hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const Ray& r = rays[i];
            bool has_nan = std::isnan(r.org.x) || std::isnan(r.org.y) || std::isnan(r.org.z) || std::isnan(r.dir.x) ||
                           std::isnan(r.dir.y) || std::isnan(r.dir.z);
            bool zero_dir = r.dir.x == 0.0f && r.dir.y == 0.0f && r.dir.z == 0.0f;
            if (got[i].prim >= 0 && !std::isfinite(got[i].t)) ++bad_t;
            if ((has_nan || zero_dir) && got[i].prim >= 0) ++nan_hits;
        }
        INFO(bvh::to_string(v));
        CHECK(bad_t == 0);
        CHECK(nan_hits == 0);
    }
}

// Case 6 (second half). A 4096-spp render of the closed furnace box (16 x 12, depth 2):
// the image mean matches Le (1 + rho + rho^2) within 4 standard errors, per channel.
TEST_CASE("hard: a 4096-spp furnace render matches the analytic value", "[hard][render]") {
    const float le = 0.5f, rho = 0.6f;
    Scene scene = make_closed_box_furnace(le, rho);
    render::RenderSettings st;
    st.width = 16;
    st.height = 12;
    st.depth = 2;
    st.seed = 2024;
    render::Wavefront wf(test::device(), scene, st);
    render::LoopOptions lo;
    lo.spp = 4096;
    render::render_frames(wf, lo, nullptr);
    Image img = wf.resolve();
    const double expected = le * (1.0 + rho + rho * rho);
    const int n = st.width * st.height;
    for (int ch = 0; ch < 3; ++ch) {
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) {
            double v = img.rgb[3 * i + ch];
            sum += v;
            sum2 += v * v;
        }
        double mean = sum / n, var = std::max(0.0, (sum2 - n * mean * mean) / (n - 1)), se = std::sqrt(var / n);
        INFO("channel " << ch << ": mean " << mean << " expected " << expected << " standard error " << se);
        CHECK(std::abs(mean - expected) < 4.0 * se);
        CHECK(se < 1e-3 * expected);
    }
    auto counters = wf.counters();
    for (int c : counters) CHECK(c == 0);
}

// Case 3, image level: the Cornell box scaled by 1e-4 and 1e5 and translated by 1e5 (camera
// transformed alike) renders the same image as the unscaled box: per-pixel z-test with
// the variances of both means (src/image/stats.h), >= 99.75% of pixels passing at
// alpha = 0.01 as in the image regression tests. Independent seeds.
//
// "The same scene" is the scene the floats describe: translated by 1e5, coordinates are
// rounded to 1/128 (the ulp there), which moves the light's edges by up to 0.4% of its
// width — a real change of the input that no renderer can undo (it failed one pixel at
// |z| = 5.7 when compared with the exact box). So the reference is the transformed scene
// mapped back exactly, (fl(s p + t) - t) / s in double, rounded to float: for a
// translation that is exact (Sterbenz), for a pure scale it is the box itself to 1 ulp.
namespace {

struct Transformed {
    float scale;
    glm::vec3 shift;
};

glm::vec3 forward(glm::vec3 p, Transformed x) { return p * x.scale + x.shift; }
glm::vec3 back(glm::vec3 q, Transformed x) {
    return glm::vec3((glm::dvec3(q) - glm::dvec3(x.shift)) / double(x.scale));
}

render::FilmMoments render_moments(const Scene& s, std::uint32_t seed) {
    render::RenderSettings st;
    st.width = 32;
    st.height = 24;
    st.depth = 3;
    st.seed = seed;
    st.variance = true;
    render::Wavefront wf(test::device(), s, st);
    render::LoopOptions lo;
    lo.spp = 64;
    render::render_frames(wf, lo, nullptr);
    int nonfinite = 0;
    for (int v : wf.counters()) nonfinite += v;
    CHECK(nonfinite == 0);
    return wf.moments();
}

void check_transformed_render(float scale, glm::vec3 shift, std::uint32_t seed) {
    Transformed x{scale, shift};
    Scene moved = make_cornell_box(2000);
    for (auto& p : moved.positions) p = forward(p, x);
    moved.camera.position = forward(moved.camera.position, x);
    moved.camera.target = forward(moved.camera.target, x);
    Scene ref_scene = moved;  // the same floats, mapped back to the unit box
    for (auto& p : ref_scene.positions) p = back(p, x);
    ref_scene.camera.position = back(moved.camera.position, x);
    ref_scene.camera.target = back(moved.camera.target, x);
    const render::FilmMoments ref = render_moments(ref_scene, 1);
    const render::FilmMoments m = render_moments(moved, seed);
    ZTest z = z_test(m.mean, ref.mean, &m.mean_variance, &ref.mean_variance);
    INFO("scale " << scale << " shift " << shift.x << ": " << z.passed << " of " << z.pixels
                  << " pixels pass, max |z| " << z.max_abs_z << " at (" << z.max_x << ", " << z.max_y << ")");
    CHECK(z.pass_fraction >= 0.9975);
}

}  // namespace

TEST_CASE("hard: the Cornell box scaled by 1e5 renders the same image (z-test)", "[hard][render]") {
    check_transformed_render(1e5f, {0, 0, 0}, 2);
}

TEST_CASE("hard: the Cornell box scaled by 1e-4 renders the same image (z-test)", "[hard][render]") {
    check_transformed_render(1e-4f, {0, 0, 0}, 3);
}

TEST_CASE("hard: the Cornell box translated by 1e5 renders the same image (z-test)",
          "[hard][render]") {
    check_transformed_render(1.0f, {1e5f, 1e5f, 1e5f}, 4);
}

// Case 8. NaN injection (render --debug-nan): each stage's guard catches every injected NaN
// before the film and counts it in its own counter. The expected count is arithmetic, not a
// recording: frames x ceil(pixels / period) for each injected stage, 0 for the others; the
// film stays finite. Every combination of the three stages.
TEST_CASE("hard: injected NaNs are caught and counted per stage, the image stays finite", "[hard][render]") {
    Scene scene = make_cornell_box(200);
    const int w = 20, h = 15, period = 7, frames = 3;
    const int per_frame = (w * h + period - 1) / period;
    for (int mask = 1; mask <= 7; ++mask) {
        render::RenderSettings st;
        st.width = w;
        st.height = h;
        st.depth = 3;
        st.seed = 5;
        st.inject_nan = mask;
        st.inject_period = period;
        st.variance = (mask & 1) != 0;  // both accumulate kernels
        render::Wavefront wf(test::device(), scene, st);
        render::LoopOptions lo;
        lo.spp = frames;
        render::render_frames(wf, lo, nullptr);
        auto c = wf.counters();
        INFO("stages mask " << mask << ": generate " << c[WP_COUNTER_GENERATE_NONFINITE] << ", shade "
                            << c[WP_COUNTER_SHADE_NONFINITE] << ", accumulate "
                            << c[WP_COUNTER_ACCUMULATE_NONFINITE] << " (expected " << frames * per_frame
                            << " per injected stage)");
        CHECK(c[WP_COUNTER_GENERATE_NONFINITE] == ((mask & WP_INJECT_GENERATE) ? frames * per_frame : 0));
        CHECK(c[WP_COUNTER_SHADE_NONFINITE] == ((mask & WP_INJECT_SHADE) ? frames * per_frame : 0));
        CHECK(c[WP_COUNTER_ACCUMULATE_NONFINITE] == ((mask & WP_INJECT_ACCUMULATE) ? frames * per_frame : 0));
        Image img = wf.resolve();
        int nonfinite = 0;
        for (float v : img.rgb) nonfinite += !std::isfinite(v);
        CHECK(nonfinite == 0);
    }
}

// Case 6 (energy). A convex object of albedo 1 (an icosphere: a convex polyhedron, so a ray
// that leaves it never comes back) under a constant background of radiance 1, no emitter:
// every path sees the background after at most one bounce, so the expected pixel value is
// the material's directional albedo, 1 for a lossless material.
//  * mirror: every sample is exactly 1 (weight = albedo = 1), so every pixel is exactly 1;
//  * diffuse with cosine sampling (the default estimator without emitters): every sample is
//    exactly 1; with the original uniform sampling (weight 2 cos theta) 1 in expectation:
//    per-pixel z-test against 1;
//  * glossy GGX: single-scattering microfacets lose energy; every pixel lies between the
//    smallest directional albedo of the white-furnace table (test_sampling.cpp: 0.8458 at
//    alpha 0.3) and 1, within 4 standard errors; Phong (the original lobe) absorbs what points
//    below the surface: <= 1.
namespace {

Scene white_sphere(MaterialKind kind, float alpha) {
    Scene s;
    s.name = "white-sphere";
    Material m;
    m.kind = kind;
    m.albedo = glm::vec3(1.0f);
    m.alpha = alpha;
    std::uint32_t id = s.add_material(m);
    Mesh sphere = make_icosphere({0, 0, 0}, 1.0f, 3);
    s.add_mesh(sphere.positions, sphere.triangles, id);
    s.background = glm::vec3(1.0f);
    s.camera.position = {0.3f, 0.2f, 3.2f};
    s.camera.target = {0, 0, 0};
    s.camera.vfov_deg = 45.0f;
    return s;
}

render::FilmMoments render_white(const Scene& s, render::Sampling sampling, render::GlossyModel glossy, int spp) {
    render::RenderSettings st;
    st.width = 32;
    st.height = 24;
    st.depth = 4;
    st.seed = 11;
    st.variance = true;
    st.estimator.sampling = sampling;
    st.estimator.glossy = glossy;
    st.estimator.sobol = false;  // independent samples: s^2/n is the variance of the mean
    render::Wavefront wf(test::device(), s, st);
    render::LoopOptions lo;
    lo.spp = spp;
    render::render_frames(wf, lo, nullptr);
    for (int c : wf.counters()) CHECK(c == 0);
    return wf.moments();
}

}  // namespace

TEST_CASE("hard: albedo-1 convex objects under a constant background of 1 (energy)", "[hard][render]") {
    using render::GlossyModel;
    using render::Sampling;
    auto max_dev = [](const Image& img) {
        double m = 0;
        for (float v : img.rgb) m = std::max(m, std::abs(double(v) - 1.0));
        return m;
    };
    SECTION("mirror and cosine-sampled diffuse: every pixel exactly 1") {
        auto mirror = render_white(white_sphere(MaterialKind::Mirror, 0), Sampling::Mis, GlossyModel::Ggx, 16);
        CHECK(max_dev(mirror.mean) == 0.0);
        auto diffuse = render_white(white_sphere(MaterialKind::Diffuse, 0), Sampling::Mis, GlossyModel::Ggx, 16);
        CHECK(max_dev(diffuse.mean) == 0.0);
    }
    SECTION("uniformly sampled diffuse: 1 in expectation (per-pixel z-test)") {
        auto m = render_white(white_sphere(MaterialKind::Diffuse, 0), Sampling::Uniform, GlossyModel::Ggx, 256);
        Image ones(m.mean.width, m.mean.height);
        std::fill(ones.rgb.begin(), ones.rgb.end(), 1.0f);
        ZTest z = z_test(m.mean, ones, &m.mean_variance, nullptr);
        INFO(z.passed << " of " << z.pixels << " pixels pass, max |z| " << z.max_abs_z);
        CHECK(z.pass_fraction >= 0.9975);
        CHECK(max_dev(m.mean) > 0.0);  // the z-test has something to test
    }
    SECTION("glossy: bounded loss, never a gain") {
        const float alpha = 0.3f;
        Scene s = white_sphere(MaterialKind::Glossy, alpha);
        for (GlossyModel g : {GlossyModel::Ggx, GlossyModel::Phong}) {
            auto m = render_white(s, Sampling::Mis, g, 256);
            int above = 0, below = 0;
            double lo = 1.0, sum = 0;
            for (std::size_t i = 0; i < m.mean.rgb.size(); ++i) {
                double v = m.mean.rgb[i], se = std::sqrt(double(m.mean_variance.rgb[i]));
                if (v > 1.0 + 4 * se + 1e-6) ++above;
                if (g == GlossyModel::Ggx && v < 0.8458 - 4 * se - 1e-6) ++below;
                lo = std::min(lo, v);
                sum += v;
            }
            INFO(render::glossy_name(g) << ": smallest pixel " << lo << ", image mean "
                                        << sum / double(m.mean.rgb.size()));
            CHECK(above == 0);
            CHECK(below == 0);
            std::printf("white sphere, glossy alpha 0.3 (%s): smallest pixel %.4f, image mean %.4f\n",
                        render::glossy_name(g), lo, sum / double(m.mean.rgb.size()));
        }
    }
}
