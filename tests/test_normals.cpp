// test_normals.cpp — computed shading normals (smooth_normals) and tangents
// (corner_tangents), and the built-in box's sphere normals. Every check compares with an
// answer found another way: the analytic normal of a sphere or a cube, the closed-form
// angle-weighted sum, a brute-force double-precision accumulation by vertex index, the
// analytic dP/du of a linear uv map.
#include <catch2/catch.hpp>

#include <chrono>
#include <ctime>
#include <cmath>
#include <numbers>
#include <set>

#include <fmt/format.h>
#include <glm/glm.hpp>

#include "scene/builtin.h"
#include "scene/normals.h"
#include "scene/procedural.h"
#include "util/error.h"

using namespace wp;

namespace {

constexpr double kPi = std::numbers::pi;

Scene scene_with(const std::vector<glm::vec3>& pos, const std::vector<glm::uvec3>& tris,
                 const std::vector<glm::vec3>& normals = {}, const std::vector<glm::vec2>& uvs = {}) {
    Scene s;
    s.add_material(Material{});
    s.add_mesh(pos, tris, 0, normals, uvs);
    return s;
}

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

double dist(glm::dvec3 a, glm::dvec3 b) { return glm::length(a - b); }

// The unit geometric normal of triangle t, in double.
glm::dvec3 face_normal(const Scene& s, std::size_t t) {
    const glm::uvec3& tri = s.triangles[t];
    glm::dvec3 a(s.positions[tri.x]), b(s.positions[tri.y]), c(s.positions[tri.z]);
    return glm::normalize(glm::cross(b - a, c - a));
}

// A latitude/longitude sphere as an OBJ loader makes one: the seam column (phi = 2 pi) is a
// second copy of the phi = 0 vertices (same positions, other uvs), poles single vertices.
Scene seam_sphere(glm::vec3 c, float r, int rings, int segments) {
    std::vector<glm::vec3> pos;
    std::vector<glm::vec2> uv;
    std::vector<glm::uvec3> tris;
    pos.push_back(c + glm::vec3(0, r, 0));
    uv.push_back({0.5f, 0.0f});
    for (int i = 1; i < rings; ++i) {
        double th = kPi * i / rings;
        for (int j = 0; j <= segments; ++j) {
            double ph = 2.0 * kPi * j / segments;
            if (j == segments) {
                pos.push_back(pos[pos.size() - segments]);  // the seam copy, bit-identical
            } else {
                pos.push_back(c + r * glm::vec3(glm::dvec3(std::sin(th) * std::sin(ph), std::cos(th),
                                                           std::sin(th) * std::cos(ph))));
            }
            uv.push_back({float(j) / segments, float(i) / rings});
        }
    }
    const auto south = std::uint32_t(pos.size());
    pos.push_back(c - glm::vec3(0, r, 0));
    uv.push_back({0.5f, 1.0f});
    auto id = [&](int i, int j) { return std::uint32_t(1 + (i - 1) * (segments + 1) + j); };
    for (int j = 0; j < segments; ++j) {
        tris.emplace_back(0u, id(1, j), id(1, j + 1));
        for (int i = 1; i + 1 < rings; ++i) {
            tris.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
            tris.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
        }
        tris.emplace_back(south, id(rings - 1, j + 1), id(rings - 1, j));
    }
    return scene_with(pos, tris, {}, uv);
}

// The unit cube [0, 1]^3 by hand: 8 vertices, 12 triangles, outward.
Scene hand_cube() {
    std::vector<glm::vec3> p;
    for (int i = 0; i < 8; ++i) p.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    // Faces as quads (counter-clockwise from outside), each split along a diagonal
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    std::vector<glm::uvec3> t;
    for (const auto& q : quads) {
        t.emplace_back(q[0], q[1], q[2]);
        t.emplace_back(q[0], q[2], q[3]);
    }
    std::vector<glm::vec2> uv;
    for (const auto& v : p) uv.emplace_back(v.x + 2 * v.z, v.y);
    return scene_with(p, t, {}, uv);
}

// Brute force: angle-weighted vertex normals by vertex index, in double (the crease-180
// answer for a mesh whose equal positions are equal indices).
std::vector<glm::dvec3> brute_force_normals(const Scene& s) {
    std::vector<glm::dvec3> acc(s.positions.size(), glm::dvec3(0.0));
    for (const auto& t : s.triangles) {
        glm::dvec3 p[3] = {glm::dvec3(s.positions[t.x]), glm::dvec3(s.positions[t.y]),
                           glm::dvec3(s.positions[t.z])};
        glm::dvec3 n = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
        for (int k = 0; k < 3; ++k) {
            glm::dvec3 a = glm::normalize(p[(k + 1) % 3] - p[k]), b = glm::normalize(p[(k + 2) % 3] - p[k]);
            acc[t[k]] += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * n;
        }
    }
    for (auto& a : acc) a = glm::normalize(a);
    return acc;
}

}  // namespace

TEST_CASE("smooth_normals: a tessellated sphere gets (p - c) / r, across its uv seam too",
          "[unit][normals]") {
    // Angle-weighted normals of a sphere converge at second order in the cell size; the
    // worst vertex is on the first ring around a pole (the skinniest fan).
    const glm::vec3 c(0.3f, -1.2f, 2.0f);
    const float r = 1.7f;
    for (float crease : {30.0f, 180.0f}) {
        INFO("crease " << crease);
        double worst[2] = {0.0, 0.0};
        for (int level = 0; level < 2; ++level) {
            const int rings = 32 << level;
            Scene s = seam_sphere(c, r, rings, 2 * rings);
            const std::size_t vertices = s.positions.size();
            const auto uvs = s.uvs;
            smooth_normals(s, crease);
            // No face pair differs by 30 degrees: nothing splits, uvs stay
            CHECK(s.positions.size() == vertices);
            CHECK(s.normals.size() == vertices);
            CHECK(s.uvs == uvs);
            for (std::size_t v = 0; v < vertices; ++v) {
                glm::dvec3 exact = (glm::dvec3(s.positions[v]) - glm::dvec3(c)) / double(r);
                worst[level] = std::max(worst[level], dist(glm::dvec3(s.normals[v]), exact));
                REQUIRE(std::abs(glm::length(glm::dvec3(s.normals[v])) - 1.0) < 1e-6);
            }
        }
        CHECK(worst[1] < 1e-3);                 // 64 rings x 128 segments: 3.8e-4
        CHECK(worst[0] / worst[1] > 3.5);       // second order: 4x per halving
    }
}

TEST_CASE("smooth_normals: a cube keeps its faces at crease 30, corners get the diagonal at 180",
          "[unit][normals]") {
    SECTION("crease 30: 24 vertices, each corner its face's normal exactly, uvs copied") {
        Scene s = hand_cube();
        smooth_normals(s, 30.0f);
        REQUIRE(s.positions.size() == 24);
        REQUIRE(s.normals.size() == 24);
        REQUIRE(s.uvs.size() == 24);
        std::set<std::tuple<float, float, float>> distinct;
        for (std::size_t t = 0; t < s.triangles.size(); ++t) {
            const glm::vec3 exact(face_normal(s, t));  // axis-aligned: exact in float
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t v = s.triangles[t][k];
                CHECK(s.normals[v] == exact);
                CHECK(s.uvs[v] == glm::vec2(s.positions[v].x + 2 * s.positions[v].z, s.positions[v].y));
                distinct.insert({s.normals[v].x, s.normals[v].y, s.normals[v].z});
            }
        }
        CHECK(distinct.size() == 6);
        // Each of the 24 vertices is one (corner, face) pair
        std::set<std::tuple<float, float, float, float, float, float>> pairs;
        for (std::size_t v = 0; v < 24; ++v)
            pairs.insert({s.positions[v].x, s.positions[v].y, s.positions[v].z, s.normals[v].x,
                          s.normals[v].y, s.normals[v].z});
        CHECK(pairs.size() == 24);
    }
    SECTION("crease 180 (and any triangulation): corners point along (+-1, +-1, +-1) / sqrt 3") {
        for (int n : {1, 3}) {
            Scene s = n == 1 ? hand_cube() : scene_with(make_box({0, 0, 0}, {1, 1, 1}, 3).positions,
                                                         make_box({0, 0, 0}, {1, 1, 1}, 3).triangles);
            const std::size_t vertices = s.positions.size();
            smooth_normals(s, 180.0f);
            CHECK(s.positions.size() == vertices);
            int corners = 0;
            for (std::size_t v = 0; v < vertices; ++v) {
                glm::dvec3 p(s.positions[v]);
                bool corner = (p.x == 0 || p.x == 1) && (p.y == 0 || p.y == 1) && (p.z == 0 || p.z == 1);
                if (!corner) continue;
                ++corners;
                glm::dvec3 exact = glm::normalize(2.0 * p - glm::dvec3(1.0));
                CHECK(dist(glm::dvec3(s.normals[v]), exact) < 1e-6);
            }
            CHECK(corners == 8);
        }
    }
}

TEST_CASE("smooth_normals: faces weigh by their angle at the vertex, not by area",
          "[unit][normals]") {
    // Vertex O at the origin; face A in the plane z = 0 with angle alpha at O (normal +z);
    // face B across the shared edge O-X with angle beta at O, tilted by phi about the x axis
    // (normal (0, sin phi, cos phi)). Edge lengths differ so that area weights would not.
    const double alpha = 1.2, beta = 0.4;
    auto build = [&](double phi) {
        std::vector<glm::vec3> p = {
            {0, 0, 0},
            {1, 0, 0},
            glm::vec3(3.0 * glm::dvec3(std::cos(alpha), std::sin(alpha), 0)),
            glm::vec3(0.5 * glm::dvec3(std::cos(beta), -std::sin(beta) * std::cos(phi),
                                       std::sin(beta) * std::sin(phi)))};
        return scene_with(p, {{0, 1, 2}, {0, 3, 1}});
    };
    SECTION("within the crease: one normal, the weighted sum") {
        const double phi = 20.0 * kPi / 180.0;
        for (float crease : {30.0f, 180.0f}) {
            Scene s = build(phi);
            smooth_normals(s, crease);
            REQUIRE(s.positions.size() == 4);
            glm::dvec3 exact = glm::normalize(alpha * glm::dvec3(0, 0, 1) +
                                              beta * glm::dvec3(0, std::sin(phi), std::cos(phi)));
            CHECK(dist(glm::dvec3(s.normals[0]), exact) < 1e-6);
            // The far vertices have one face each: its normal
            CHECK(dist(glm::dvec3(s.normals[2]), glm::dvec3(0, 0, 1)) < 1e-6);
            CHECK(dist(glm::dvec3(s.normals[3]), glm::dvec3(0, std::sin(phi), std::cos(phi))) < 1e-6);
        }
    }
    SECTION("beyond the crease: O and X split, each face keeps its own normal") {
        const double phi = 40.0 * kPi / 180.0;
        Scene s = build(phi);
        smooth_normals(s, 30.0f);
        CHECK(s.positions.size() == 6);  // O and X split in two
        const glm::dvec3 na(0, 0, 1), nb(0, std::sin(phi), std::cos(phi));
        for (int k = 0; k < 3; ++k) {
            CHECK(dist(glm::dvec3(s.normals[s.triangles[0][k]]), na) < 1e-6);
            CHECK(dist(glm::dvec3(s.normals[s.triangles[1][k]]), nb) < 1e-6);
        }
        // Crease 50 joins them again
        Scene j = build(phi);
        smooth_normals(j, 50.0f);
        CHECK(j.positions.size() == 4);
        CHECK(dist(glm::dvec3(j.normals[0]), glm::normalize(alpha * na + beta * nb)) < 1e-6);
    }
}

TEST_CASE("smooth_normals: a mesh agrees with a brute-force double accumulation",
          "[unit][normals]") {
    // The stress mesh: closed, bumpy, no repeated positions, so by-index accumulation is
    // the crease-180 answer
    Mesh m = make_stress_mesh(20000);
    Scene s = scene_with(m.positions, m.triangles);
    const auto exact = brute_force_normals(s);
    smooth_normals(s, 180.0f);
    REQUIRE(s.positions.size() == m.positions.size());
    REQUIRE(s.triangles == m.triangles);
    double worst = 0.0;
    for (std::size_t v = 0; v < exact.size(); ++v) worst = std::max(worst, dist(glm::dvec3(s.normals[v]), exact[v]));
    CHECK(worst < 1e-6);
    // Each corner's normal is on the front of its face
    for (std::size_t t = 0; t < s.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) REQUIRE(glm::dot(glm::dvec3(s.normals[s.triangles[t][k]]), face_normal(s, t)) > 0.0);
}

TEST_CASE("smooth_normals: degenerate faces add nothing, output has no NaN", "[unit][normals]") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},  // a good face, +z
                                {2, 0, 0}, {3, 0, 0},             // collinear with 0 and 1
                                {5, 5, 5}, {6, 6, 6}, {7, 7, 7},  // only in degenerate faces
                                {nan, 0, 0}};
    std::vector<glm::uvec3> t = {{0, 1, 2}, {0, 1, 3}, {1, 4, 3}, {5, 6, 7}, {5, 5, 6},
                                 {2, 8, 0}};
    Scene s = scene_with(p, t);
    smooth_normals(s, 30.0f);
    REQUIRE(s.normals.size() == s.positions.size());
    for (const auto& n : s.normals) REQUIRE(finite(n));
    // Good face's vertices: +z; degenerate corners share those vertices (no split)
    CHECK(s.positions.size() == p.size());
    for (std::uint32_t v : {0u, 1u, 2u}) CHECK(s.normals[v] == glm::vec3(0, 0, 1));
    for (std::uint32_t v : {3u, 4u, 5u, 6u, 7u, 8u}) CHECK(s.normals[v] == glm::vec3(0.0f));
    CHECK(s.triangles == t);

    // Only degenerate faces: nothing to smooth, the scene stays as it was
    Scene d = scene_with({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, {{0, 1, 2}});
    smooth_normals(d, 180.0f);
    CHECK(d.normals.empty());
}

TEST_CASE("smooth_normals: first_triangle and given normals are respected", "[unit][normals]") {
    // Two cubes; the first has given normals on one face (kept), the second none
    Scene s = hand_cube();
    const std::size_t first = s.triangle_count();
    Scene b = hand_cube();
    s.add_mesh(b.positions, b.triangles, 0, {}, b.uvs);
    const auto before = s.triangles;
    SECTION("triangles before first_triangle keep their indices and zero normals") {
        smooth_normals(s, 30.0f, first);
        for (std::size_t t = 0; t < first; ++t) {
            CHECK(s.triangles[t] == before[t]);
            for (int k = 0; k < 3; ++k) CHECK(s.normals[s.triangles[t][k]] == glm::vec3(0.0f));
        }
        for (std::size_t t = first; t < s.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k)
                CHECK(glm::dvec3(s.normals[s.triangles[t][k]]) == face_normal(s, t));
        CHECK(s.positions.size() == 8 + 24);
    }
    SECTION("a vertex shared with a triangle outside the range is copied, not changed") {
        Scene m = scene_with({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 2, 1}, {0, 1, 3}});
        smooth_normals(m, 180.0f, 1);
        CHECK(m.triangles[0] == glm::uvec3(0, 2, 1));
        for (std::uint32_t v : {0u, 1u, 2u}) CHECK(m.normals[v] == glm::vec3(0.0f));
        CHECK(m.positions.size() == 6);  // 0 and 1 copied for triangle 1; 3 is its own
        for (int k = 0; k < 3; ++k)
            CHECK(m.normals[m.triangles[1][k]] == glm::vec3(0, -1, 0));
    }
    SECTION("triangles with normals inside the range are left alone") {
        s.normals.assign(s.positions.size(), glm::vec3(0.0f));
        const glm::uvec3 given = s.triangles[first];
        for (int k = 0; k < 3; ++k) s.normals[given[k]] = glm::vec3(0.0f, 0.0f, 7.0f);
        smooth_normals(s, 30.0f, first);
        CHECK(s.triangles[first] == given);
        for (int k = 0; k < 3; ++k) CHECK(s.normals[given[k]] == glm::vec3(0.0f, 0.0f, 7.0f));
    }
    SECTION("bad arguments name the problem") {
        CHECK_THROWS_AS(smooth_normals(s, -1.0f), Error);
        CHECK_THROWS_AS(smooth_normals(s, std::numeric_limits<float>::quiet_NaN()), Error);
        s.triangles.back().x = 1000;
        CHECK_THROWS_WITH(smooth_normals(s, 30.0f), Catch::Matchers::Contains("vertex 1000"));
    }
}

TEST_CASE("corner_tangents: a planar grid gets dP/du and the handedness of its uv map",
          "[unit][normals]") {
    // The plane z = 0.5 (normal +z), a 4 x 3 grid over [-1, 1] x [-1, 1]
    Mesh g = make_quad({-1, -1, 0.5f}, {2, 0, 0}, {0, 2, 0}, 4, 3);
    auto tangents_for = [&](auto uv_of) {
        std::vector<glm::vec2> uv;
        for (const auto& p : g.positions) uv.push_back(uv_of(p));
        return corner_tangents(scene_with(g.positions, g.triangles, {}, uv));
    };
    struct Case {
        const char* name;
        glm::vec2 (*uv)(glm::vec3);
        glm::dvec3 dpdu, dpdv;  // analytic, from inverting the linear map by hand
    };
    const Case cases[] = {
        // The usual picture: image top at +y, v down = -y. b = cross(n, t) = +y = -dP/dv.
        {"u = x, v = -y", [](glm::vec3 p) { return glm::vec2(0.5f * p.x + 0.5f, 0.5f - 0.5f * p.y); },
         {2, 0, 0}, {0, -2, 0}},
        // Mirrored in u: t = -x, w = -1
        {"u = -x, v = -y", [](glm::vec3 p) { return glm::vec2(-p.x, -p.y); }, {-1, 0, 0}, {0, -1, 0}},
        // Mirrored in v (image top at -y): t = +x, w = -1
        {"u = x, v = y", [](glm::vec3 p) { return glm::vec2(p.x, p.y); }, {1, 0, 0}, {0, 1, 0}},
        // Sheared: u = x, v = 0.3 x - y, so x = u, y = 0.3 u - v
        {"u = x, v = 0.3x - y", [](glm::vec3 p) { return glm::vec2(p.x, 0.3f * p.x - p.y); },
         {1, 0.3, 0}, {0, -1, 0}},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        const auto t = tangents_for(c.uv);
        REQUIRE(t.size() == 3 * g.triangles.size());
        const glm::dvec3 n(0, 0, 1), exact = glm::normalize(c.dpdu);
        const double w = glm::dot(glm::cross(n, exact), -c.dpdv) > 0 ? 1.0 : -1.0;
        for (const auto& tc : t) {
            REQUIRE(dist(glm::dvec3(glm::vec3(tc)), exact) < 1e-6);
            REQUIRE(tc.w == float(w));
        }
    }
}

TEST_CASE("corner_tangents: a mirrored seam splits by handedness at shared vertices",
          "[unit][normals]") {
    // u = |x|: the left half runs u towards -x, the right half towards +x; the column x = 0
    // is shared by both halves with the same uv
    Mesh g = make_quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}, 4, 2);
    std::vector<glm::vec2> uv;
    for (const auto& p : g.positions) uv.emplace_back(std::abs(p.x), -p.y);
    Scene s = scene_with(g.positions, g.triangles, {}, uv);
    const auto t = corner_tangents(s);
    int at_seam = 0;
    for (std::size_t f = 0; f < s.triangles.size(); ++f) {
        const glm::vec3 c = (s.positions[s.triangles[f].x] + s.positions[s.triangles[f].y] +
                             s.positions[s.triangles[f].z]) / 3.0f;
        const float side = c.x < 0 ? -1.0f : 1.0f;
        for (int k = 0; k < 3; ++k) {
            const glm::vec4& tc = t[3 * f + k];
            CHECK(glm::vec3(tc) == glm::vec3(side, 0, 0));
            CHECK(tc.w == side);
            at_seam += s.positions[s.triangles[f][k]].x == 0.0f;
        }
    }
    CHECK(at_seam > 0);
}

TEST_CASE("corner_tangents: a smooth cylinder gets the analytic tangent, orthogonal to n",
          "[unit][normals]") {
    // P = (sin phi, y, cos phi), n = (sin phi, 0, cos phi), u = phi / 2pi, v = -y:
    // dP/du points along (cos phi, 0, -sin phi); b = cross(n, t) = +y = -dP/dv, w = +1.
    const int seg = 24, rows = 4;
    std::vector<glm::vec3> p, n;
    std::vector<glm::vec2> uv;
    std::vector<glm::uvec3> tris;
    for (int i = 0; i <= rows; ++i)
        for (int j = 0; j <= seg; ++j) {
            double ph = 2 * kPi * j / seg;
            p.emplace_back(std::sin(ph), float(i) / rows, std::cos(ph));
            n.emplace_back(std::sin(ph), 0.0, std::cos(ph));
            uv.emplace_back(float(j) / seg, -float(i) / rows);
        }
    auto id = [&](int i, int j) { return std::uint32_t(i * (seg + 1) + j); };
    for (int i = 0; i < rows; ++i)
        for (int j = 0; j < seg; ++j) {
            tris.emplace_back(id(i, j), id(i, j + 1), id(i + 1, j + 1));
            tris.emplace_back(id(i, j), id(i + 1, j + 1), id(i + 1, j));
        }
    Scene s = scene_with(p, tris, n, uv);
    const auto t = corner_tangents(s);
    for (std::size_t c = 0; c < t.size(); ++c) {
        const std::uint32_t v = s.triangles[c / 3][int(c % 3)];
        const glm::dvec3 nn = glm::normalize(glm::dvec3(s.normals[v]));
        const glm::dvec3 tc(glm::vec3(t[c]));
        REQUIRE(std::abs(glm::dot(tc, nn)) < 1e-6);
        REQUIRE(std::abs(glm::length(tc) - 1.0) < 1e-6);
        REQUIRE(dist(tc, glm::dvec3(nn.z, 0.0, -nn.x)) < 1e-5);
        REQUIRE(t[c].w == 1.0f);
    }
}

TEST_CASE("corner_tangents: degenerate uvs, no uvs and given tangents", "[unit][normals]") {
    Mesh g = make_quad({0, 0, 0}, {1, 0, 0}, {0, 0, -1}, 2, 2);  // normal +y
    auto check_fallback = [](const std::vector<glm::vec4>& t, glm::dvec3 n) {
        for (const auto& tc : t) {
            REQUIRE(finite(glm::vec3(tc)));
            REQUIRE(std::abs(glm::length(glm::dvec3(glm::vec3(tc))) - 1.0) < 1e-6);
            REQUIRE(std::abs(glm::dot(glm::dvec3(glm::vec3(tc)), n)) < 1e-6);
            REQUIRE(tc.w == 1.0f);
        }
    };
    SECTION("every uv the same") {
        std::vector<glm::vec2> uv(g.positions.size(), glm::vec2(0.25f));
        check_fallback(corner_tangents(scene_with(g.positions, g.triangles, {}, uv)), {0, 1, 0});
    }
    SECTION("no uvs at all") {
        check_fallback(corner_tangents(scene_with(g.positions, g.triangles)), {0, 1, 0});
    }
    SECTION("faces with zero uv area take the tangent of their vertex, or any") {
        // u = x, v = z, except that the column x = 1 has u = 0.5 like the middle one: the
        // cells between them have zero uv area. Their corners in the middle column share
        // the vertex (position, normal, uv) of the good cells; those at x = 1 have no good
        // face at all.
        std::vector<glm::vec2> uv;
        for (const auto& p : g.positions) uv.emplace_back(std::min(p.x, 0.5f), p.z);
        Scene s = scene_with(g.positions, g.triangles, {}, uv);
        const auto t = corner_tangents(s);
        int fallback = 0;
        for (std::size_t c = 0; c < t.size(); ++c) {
            const glm::vec3 p = s.positions[s.triangles[c / 3][int(c % 3)]];
            if (p.x < 1.0f) {
                // b = cross(+y, +x) = -z = -dP/dv: w = +1
                CHECK(t[c] == glm::vec4(1, 0, 0, 1));
            } else {
                ++fallback;
                check_fallback({t[c]}, {0, 1, 0});
            }
        }
        CHECK(fallback > 0);
    }
    SECTION("given tangents win where non-zero") {
        std::vector<glm::vec2> uv;
        for (const auto& p : g.positions) uv.emplace_back(p.x, p.z);
        Scene s = scene_with(g.positions, g.triangles, {}, uv);
        s.tangents.assign(s.positions.size(), glm::vec4(0.0f));
        s.tangents[0] = glm::vec4(0, 0, 2, -3);
        const auto t = corner_tangents(s);
        for (std::size_t c = 0; c < t.size(); ++c) {
            if (s.triangles[c / 3][int(c % 3)] == 0)
                CHECK(t[c] == glm::vec4(0, 0, 2, -1));
            else
                CHECK(t[c] == glm::vec4(1, 0, 0, 1));
        }
    }
}

TEST_CASE("make_cornell_box: the mirror sphere has unit normals (p - c) / r, the rest none",
          "[unit][normals]") {
    Scene s = make_cornell_box();
    CHECK(s.triangle_count() == 16020);
    REQUIRE(s.normals.size() == s.positions.size());
    const glm::dvec3 c(0.42f, 0.401f, 0.3f);
    const double r = 0.4f;
    std::uint32_t mirror = 0;
    while (s.materials[mirror].name != "mirror") ++mirror;
    std::size_t sphere = 0;
    for (std::size_t t = 0; t < s.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = s.triangles[t][k];
            const glm::dvec3 n(s.normals[v]);
            if (s.material_ids[t] == mirror) {
                ++sphere;
                REQUIRE(std::abs(glm::length(n) - 1.0) < 1e-6);
                REQUIRE(dist(n, (glm::dvec3(s.positions[v]) - c) / r) < 1e-5);
            } else {
                REQUIRE(n == glm::dvec3(0.0));
            }
        }
    CHECK(sphere == 3 * 12120);
}

TEST_CASE("smooth_normals: time on the 250k-triangle stress mesh", "[.][timing]") {
    // Wall and CPU time (the CPU time is the fairer figure on a shared machine)
    struct Clock {
        std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
        std::clock_t cpu = std::clock();
        std::string lap() const {
            double w = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall).count();
            double c = 1000.0 * double(std::clock() - cpu) / CLOCKS_PER_SEC;
            return fmt::format("{:.0f} ms wall, {:.0f} ms CPU", w, c);
        }
    };
    Mesh m = make_stress_mesh(250000);
    for (float crease : {30.0f, 180.0f}) {
        Scene s = scene_with(m.positions, m.triangles);
        Clock normals;
        smooth_normals(s, crease);
        const std::string normals_time = normals.lap();
        std::vector<glm::vec2> uv(s.positions.size());
        for (std::size_t v = 0; v < uv.size(); ++v) uv[v] = glm::vec2(s.positions[v].x, s.positions[v].y);
        s.uvs = uv;
        Clock tangents;
        auto t = corner_tangents(s);
        WARN("crease " << crease << ", " << s.triangle_count() << " triangles: smooth_normals "
                       << normals_time << "; corner_tangents " << tangents.lap());
        CHECK(t.size() == 3 * s.triangle_count());
    }
}
