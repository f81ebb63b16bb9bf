// test_triangle.cpp — the watertight ray/triangle test against an independent
// double-precision Möller–Trumbore, and its watertightness on shared edges and vertices.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>

#include "shared/triangle.h"
#include "support.h"

using namespace wp;

namespace {

// Möller & Trumbore (1997) in double precision: the independent answer.
struct MtHit {
    bool hit;
    double t, u, v;
};
MtHit moller_trumbore(glm::dvec3 o, glm::dvec3 d, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
    glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(d, e2);
    double det = glm::dot(e1, p);
    if (det == 0.0) return {false, 0, 0, 0};
    glm::dvec3 s = o - a;
    double u = glm::dot(s, p) / det;
    glm::dvec3 q = glm::cross(s, e1);
    double v = glm::dot(d, q) / det;
    double t = glm::dot(e2, q) / det;
    return {u >= 0 && v >= 0 && u + v <= 1 && t > 0, t, u, v};
}

float4 f4(glm::vec3 p) { return {p.x, p.y, p.z, 0.0f}; }

}  // namespace

TEST_CASE("watertight triangle test agrees with double-precision Moller-Trumbore", "[unit][triangle]") {
    test::Rng rng(7);
    int compared = 0, hits = 0;
    for (int i = 0; i < 200000; ++i) {
        glm::vec3 a = rng.unit_vector() * 2.0f, b = rng.unit_vector() * 2.0f, c = rng.unit_vector() * 2.0f;
        glm::vec3 o = rng.unit_vector() * 5.0f;
        glm::vec3 target = a + rng.uniform(-0.2f, 1.2f) * (b - a) + rng.uniform(-0.2f, 1.2f) * (c - a);
        glm::vec3 d = target - o;
        MtHit ref = moller_trumbore(o, d, a, b, c);
        // Skip cases within rounding distance of an edge or of grazing: the answer there is
        // legitimately either (watertightness is tested separately below).
        double w = 1.0 - ref.u - ref.v;
        double margin = std::min({std::fabs(ref.u), std::fabs(ref.v), std::fabs(w)});
        glm::dvec3 n = glm::cross(glm::dvec3(b - a), glm::dvec3(c - a));
        double cosang = std::fabs(glm::dot(glm::normalize(n), glm::normalize(glm::dvec3(d))));
        if (margin < 1e-4 || cosang < 1e-3) continue;
        TriRay tr = wp_tri_ray(test::make_ray(o, d));
        float t, u, v;
        bool hit = wp_intersect_triangle(&tr, f4(a), f4(b), f4(c), &t, &u, &v) != 0;
        ++compared;
        INFO("case " << i);
        REQUIRE(hit == ref.hit);
        if (hit) {
            ++hits;
            // Float error grows with distance/size and as the ray grazes the plane.
            // Float error in t grows as the ray grazes the plane: a few ulps / cos(angle).
            REQUIRE(t == Approx(ref.t).epsilon(1e-6 + 4e-7 / cosang));
            REQUIRE(u == Approx(ref.u).margin(2e-5 + 1e-6 / cosang));
            REQUIRE(v == Approx(ref.v).margin(2e-5 + 1e-6 / cosang));
        }
    }
    CHECK(compared > 150000);
    CHECK(hits > 20000);
}

TEST_CASE("rays through shared edges and vertices never slip through", "[unit][triangle][hard]") {
    SECTION("the two-triangle square of issue 5") {
        glm::vec3 p[4] = {{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}};
        TriRay tr = wp_tri_ray(test::make_ray({0, 0, 10}, {0.30458447f, 0.30458447f, -0.9024725f}));
        float t, u, v;
        int h = wp_intersect_triangle(&tr, f4(p[0]), f4(p[1]), f4(p[2]), &t, &u, &v) +
                wp_intersect_triangle(&tr, f4(p[0]), f4(p[2]), f4(p[3]), &t, &u, &v);
        CHECK(h >= 1);
    }
    SECTION("a fan around a vertex, rays aimed exactly at the vertex and along the spokes") {
        test::Rng rng(11);
        const int k = 7;
        glm::vec3 centre{0.3f, -0.2f, 0.1f};
        std::vector<glm::vec3> rim;
        for (int i = 0; i < k; ++i) {
            float a = 6.2831853f * i / k;
            rim.push_back(centre + glm::vec3(std::cos(a), std::sin(a), 0.05f * std::sin(3.0f * a)));
        }
        int misses = 0;
        for (int r = 0; r < 20000; ++r) {
            glm::vec3 o = centre + glm::vec3(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(0.5f, 4.0f));
            // Target: the centre vertex, or a point exactly on a spoke edge.
            glm::vec3 target = centre;
            if (r % 2) {
                int s = static_cast<int>(rng.next() % k);
                target = centre + rng.uniform() * (rim[s] - centre);
            }
            TriRay tr = wp_tri_ray(test::make_ray(o, target - o));
            int hits = 0;
            for (int i = 0; i < k; ++i) {
                float t, u, v;
                hits += wp_intersect_triangle(&tr, f4(centre), f4(rim[i]), f4(rim[(i + 1) % k]), &t, &u, &v);
            }
            if (hits == 0) ++misses;
        }
        CHECK(misses == 0);
    }
}

TEST_CASE("degenerate triangles and directions give no hit and no NaN", "[unit][triangle][hard]") {
    float t = -1, u = -1, v = -1;
    glm::vec3 a{0, 0, 0}, b{1, 0, 0}, c{2, 0, 0};  // collinear: zero area
    TriRay tr = wp_tri_ray(test::make_ray({0.5f, 1.0f, -1.0f}, {0.0f, -1.0f, 1.0f}));
    CHECK(wp_intersect_triangle(&tr, f4(a), f4(b), f4(c), &t, &u, &v) == 0);
    // A ray lying in the triangle's plane.
    TriRay tp = wp_tri_ray(test::make_ray({-1.0f, 0.25f, 0.0f}, {1.0f, 0.0f, 0.0f}));
    CHECK(wp_intersect_triangle(&tp, f4({0, 0, 0}), f4({1, 0, 0}), f4({0, 1, 0}), &t, &u, &v) == 0);
    // Axis-parallel with negative zeros: a hit with finite results.
    TriRay tz = wp_tri_ray(test::make_ray({0.25f, 0.25f, 1.0f}, {-0.0f, 0.0f, -1.0f}));
    REQUIRE(wp_intersect_triangle(&tz, f4({0, 0, 0}), f4({1, 0, 0}), f4({0, 1, 0}), &t, &u, &v) == 1);
    CHECK(t == 1.0f);
    CHECK(u == Approx(0.25f));
    CHECK(v == Approx(0.25f));
}

TEST_CASE("a leaf block's four lanes give the scalar test's verdict and t, u, v bit for bit",
          "[unit][triangle][hard]") {
    // wp_intersect_block (four triangles in SoA rows) against wp_intersect_triangle one by one:
    // random triangles with rays aimed across their edges, two triangles sharing an edge with
    // rays through it, zero-area and collinear triangles, rays with zero direction components,
    // a tmin in front of some hits, and blocks of 1..4 lanes (the rest zero padding).
    test::Rng rng(11);
    int lanes_compared = 0, hits = 0;
    auto bits = [](float x) {
        std::uint32_t b;
        std::memcpy(&b, &x, 4);
        return b;
    };
    for (int i = 0; i < 50000; ++i) {
        glm::vec3 tri[4][3];
        for (int l = 0; l < 4; ++l)
            for (int k = 0; k < 3; ++k) tri[l][k] = rng.unit_vector() * 2.0f;
        const int kind = i % 5;
        if (kind == 1) {  // lanes 0 and 1 share the edge (a, b), in opposite windings
            tri[1][0] = tri[0][1];
            tri[1][1] = tri[0][0];
        } else if (kind == 2) {  // lane 2 zero-area (a point), lane 3 collinear
            tri[2][1] = tri[2][2] = tri[2][0];
            tri[3][2] = tri[3][0] + 0.5f * (tri[3][1] - tri[3][0]);
        }
        const int lanes = 1 + i % 4;
        const int aim = static_cast<int>(rng.uniform(0.0f, 3.999f)) % lanes;
        glm::vec3 o = rng.unit_vector() * 5.0f;
        glm::vec3 target = kind == 1 ? tri[0][0] + rng.uniform(0.0f, 1.0f) * (tri[0][1] - tri[0][0])
                                     : tri[aim][0] + rng.uniform(-0.2f, 1.2f) * (tri[aim][1] - tri[aim][0]) +
                                           rng.uniform(-0.2f, 1.2f) * (tri[aim][2] - tri[aim][0]);
        glm::vec3 d = target - o;
        if (kind == 3) d.y = 0.0f, target.y = o.y;  // a zero direction component
        if (kind == 4) d = -d;                      // pointing away: no hit in front
        Ray ray = test::make_ray(o, d);
        if (i % 7 == 0) ray.org.w = rng.uniform(0.0f, 6.0f);  // tmin
        TriRay tr = wp_tri_ray(ray);
        TriBlock blk{};
        for (int l = 0; l < lanes; ++l)
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 3; ++a) reinterpret_cast<float*>(&blk.row[3 * k + a])[l] = tri[l][k][a];
        float4 t4, u4, v4;
        const int m = wp_intersect_block(&tr, &blk, lanes, &t4, &u4, &v4);
        INFO("case " << i << " lanes " << lanes);
        REQUIRE((m & ~((1 << lanes) - 1)) == 0);
        for (int l = 0; l < 4; ++l) {
            float t = 0.0f, u = 0.0f, v = 0.0f;
            // A padding lane is the zero triangle: the scalar test must miss it too.
            const glm::vec3 z(0.0f);
            const bool hit = l < lanes ? wp_intersect_triangle(&tr, f4(tri[l][0]), f4(tri[l][1]), f4(tri[l][2]), &t, &u, &v)
                                       : wp_intersect_triangle(&tr, f4(z), f4(z), f4(z), &t, &u, &v);
            INFO("lane " << l);
            REQUIRE(((m >> l) & 1) == (l < lanes && hit ? 1 : 0));
            ++lanes_compared;
            if (!hit || l >= lanes) continue;
            ++hits;
            CHECK(bits(wp_lane4(t4, l)) == bits(t));
            CHECK(bits(wp_lane4(u4, l)) == bits(u));
            CHECK(bits(wp_lane4(v4, l)) == bits(v));
        }
    }
    CHECK(lanes_compared == 200000);
    CHECK(hits > 10000);
}
