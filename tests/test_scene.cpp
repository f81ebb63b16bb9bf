// test_scene.cpp — the host scene module: procedural meshes, built-in scenes, the OBJ loader
// and validate_scene. Every check compares with an answer found another way: edge
// counting, the divergence theorem, closed-form areas and volumes, hand-written files.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <unordered_map>

#include <unistd.h>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "scene/builtin.h"
#include "scene/obj_loader.h"
#include "scene/procedural.h"
#include "scene/validate.h"
#include "util/error.h"
#include "util/read_file.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

using wp::test::TempDir;

constexpr double kPi = std::numbers::pi;

// Directed-edge bookkeeping: a mesh is closed and consistently wound when every directed
// edge appears exactly once and its reverse appears exactly once too.
struct EdgeReport {
    std::size_t directed = 0;   // distinct directed edges
    std::size_t duplicated = 0; // directed edges used by more than one triangle
    std::size_t unpaired = 0;   // directed edges whose reverse is missing (border edges)
    bool closed() const { return directed > 0 && duplicated == 0 && unpaired == 0; }
};

EdgeReport edges_of(const std::vector<glm::uvec3>& tris) {
    std::unordered_map<std::uint64_t, int> count;
    auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
    for (const auto& t : tris)
        for (int k = 0; k < 3; ++k)
            ++count[key(t[k], t[(k + 1) % 3])];
    EdgeReport r;
    r.directed = count.size();
    for (const auto& [e, n] : count) {
        if (n > 1) ++r.duplicated;
        if (!count.count(key(std::uint32_t(e & 0xffffffffu), std::uint32_t(e >> 32)))) ++r.unpaired;
    }
    return r;
}

// Divergence theorem: V = sum over triangles of dot(a, cross(b, c)) / 6 (positive when
// the winding is outward).
double signed_volume(const std::vector<glm::vec3>& p, const std::vector<glm::uvec3>& tris) {
    double v = 0.0;
    for (const auto& t : tris) {
        glm::dvec3 a(p[t.x]), b(p[t.y]), c(p[t.z]);
        v += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return v;
}
double signed_volume(const wp::Mesh& m) {
    return signed_volume(m.positions, m.triangles);
}

double area(const std::vector<glm::vec3>& p, const std::vector<glm::uvec3>& tris) {
    double s = 0.0;
    for (const auto& t : tris) {
        glm::dvec3 a(p[t.x]), b(p[t.y]), c(p[t.z]);
        s += 0.5 * glm::length(glm::cross(b - a, c - a));
    }
    return s;
}
double area(const wp::Mesh& m) {
    return area(m.positions, m.triangles);
}

// The largest |distance to c - r| over the mesh's vertices.
double max_radius_error(const wp::Mesh& m, glm::vec3 c, float r) {
    double e = 0.0;
    for (const auto& p : m.positions)
        e = std::max(e, std::abs(glm::length(glm::dvec3(p) - glm::dvec3(c)) - double(r)));
    return e;
}

glm::dvec3 normal_of(const std::vector<glm::vec3>& p, const glm::uvec3& t) {
    glm::dvec3 a(p[t.x]), b(p[t.y]), c(p[t.z]);
    return glm::cross(b - a, c - a);
}

// The part of a scene that uses one material, as a mesh over the scene's vertices.
std::vector<glm::uvec3> triangles_with(const wp::Scene& s, std::uint32_t material) {
    std::vector<glm::uvec3> out;
    for (std::size_t i = 0; i < s.triangles.size(); ++i)
        if (s.material_ids[i] == material) out.push_back(s.triangles[i]);
    return out;
}

std::uint32_t material_named(const wp::Scene& s, const std::string& name) {
    for (std::size_t i = 0; i < s.materials.size(); ++i)
        if (s.materials[i].name == name) return std::uint32_t(i);
    FAIL("no material named " << name);
    return 0;
}

// The message of the wp::Error that f throws ("<no error>" when it throws none).
template <typename F> std::string error_of(F&& f) {
    try {
        f();
    } catch (const wp::Error& e) {
        return e.what();
    }
    return "<no error>";
}

// A fresh folder under the system temp directory, removed at the end of the test.
const char* kCubeQuads = R"(# unit cube, quads, outward counter-clockwise
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 4 8 7 3
f 1 5 8 4
f 2 3 7 6
)";

} // namespace

// --- Procedural meshes ---------------------------------------------------------------------

TEST_CASE("make_quad: grid counts, area, normal along cross(u, v), one border", "[unit][scene]") {
    const glm::vec3 u(2.0f, 0.0f, 0.0f), v(0.0f, 0.0f, -3.0f);
    for (auto [nu, nv] : {std::pair{1, 1}, std::pair{3, 2}, std::pair{7, 5}}) {
        wp::Mesh m = wp::make_quad({1.0f, 2.0f, 3.0f}, u, v, nu, nv);
        CHECK(m.positions.size() == std::size_t((nu + 1) * (nv + 1)));
        CHECK(m.triangles.size() == std::size_t(2 * nu * nv));
        CHECK(area(m) == Approx(6.0).epsilon(1e-6));
        // Every triangle faces cross(u, v) = (0, 6, 0)
        for (const auto& t : m.triangles) {
            glm::dvec3 n = glm::normalize(normal_of(m.positions, t));
            CHECK(n.y == Approx(1.0).epsilon(1e-6));
        }
        // Open: the border has 2 (nu + nv) edges, no edge is duplicated
        EdgeReport e = edges_of(m.triangles);
        CHECK(e.duplicated == 0);
        CHECK(e.unpaired == std::size_t(2 * (nu + nv)));
    }
}

TEST_CASE("make_box: closed, outward, exact area and volume", "[unit][scene]") {
    const glm::vec3 lo(-1.0f, 0.5f, 2.0f), hi(2.0f, 2.5f, 6.0f);
    const double a = 3.0, b = 2.0, c = 4.0;
    for (int n : {1, 2, 3, 8}) {
        wp::Mesh m = wp::make_box(lo, hi, n);
        CHECK(m.triangles.size() == std::size_t(12 * n * n));
        CHECK(m.positions.size() == std::size_t(6 * n * n + 2)); // Euler: V - E + F = 2
        CHECK(edges_of(m.triangles).closed());
        CHECK(area(m) == Approx(2.0 * (a * b + b * c + c * a)).epsilon(1e-6));
        CHECK(signed_volume(m) == Approx(a * b * c).epsilon(1e-6));
        // Every vertex on the surface (one coordinate on a face) and inside the box
        std::size_t off_surface = 0;
        for (const auto& p : m.positions) {
            int on_face = 0;
            for (int k = 0; k < 3; ++k)
                on_face += (p[k] == lo[k] || p[k] == hi[k]);
            off_surface +=
                on_face == 0 || glm::any(glm::lessThan(p, lo)) || glm::any(glm::greaterThan(p, hi));
        }
        CHECK(off_surface == 0);
    }
    // n = 1 with small integer sizes: the area sums exactly
    CHECK(area(wp::make_box({0, 0, 0}, {1, 2, 3})) == 22.0);
}

TEST_CASE("make_uv_sphere: closed, outward, volume converges at second order", "[unit][scene]") {
    const glm::vec3 c(0.5f, -1.0f, 2.0f);
    const float r = 1.5f;
    const double exact = 4.0 / 3.0 * kPi * r * r * r;
    double previous_error = 0.0;
    for (int rings : {8, 16, 32, 64}) {
        wp::Mesh m = wp::make_uv_sphere(c, r, rings, 2 * rings);
        CHECK(m.triangles.size() == std::size_t(2 * (2 * rings) * (rings - 1)));
        CHECK(m.positions.size() == std::size_t((rings - 1) * 2 * rings + 2));
        CHECK(edges_of(m.triangles).closed());
        CHECK(max_radius_error(m, c, r) < 1e-5 * r);
        // Inscribed polyhedron: slightly smaller than the sphere, error ~ 1/rings^2
        double v = signed_volume(m);
        double err = (exact - v) / exact;
        CHECK(err > 0.0);
        CHECK(err < 5.0 / (rings * rings));
        if (previous_error > 0.0) CHECK(previous_error / err == Approx(4.0).epsilon(0.1));
        previous_error = err;
    }
}

TEST_CASE("make_icosphere: Euler counts, closed, outward, volume converges", "[unit][scene]") {
    const glm::vec3 c(-2.0f, 0.0f, 1.0f);
    const float r = 0.75f;
    const double exact = 4.0 / 3.0 * kPi * r * r * r;
    double previous_error = 0.0;
    for (int s = 0; s <= 5; ++s) {
        wp::Mesh m = wp::make_icosphere(c, r, s);
        const std::size_t f = 20u << (2 * s);
        CHECK(m.triangles.size() == f);
        CHECK(m.positions.size() == f / 2 + 2); // V = E - F + 2, E = 3F / 2
        CHECK(edges_of(m.triangles).closed());
        CHECK(max_radius_error(m, c, r) < 1e-5 * r);
        double err = (exact - signed_volume(m)) / exact;
        CHECK(err > 0.0);
        if (s >= 2) CHECK(previous_error / err == Approx(4.0).epsilon(0.15));
        previous_error = err;
    }
    CHECK(previous_error < 2e-3);
}

TEST_CASE("make_random_soup: deterministic per seed, bounded edges and box", "[unit][scene]") {
    const glm::vec3 lo(-1.0f, 0.0f, 2.0f), hi(3.0f, 1.0f, 4.0f);
    const float max_edge = 0.3f;
    wp::Mesh a = wp::make_random_soup(2000, 42, lo, hi, max_edge);
    wp::Mesh b = wp::make_random_soup(2000, 42, lo, hi, max_edge);
    wp::Mesh c = wp::make_random_soup(2000, 43, lo, hi, max_edge);
    REQUIRE(a.triangles.size() == 2000);
    REQUIRE(a.positions.size() == 6000);
    CHECK(a.positions == b.positions);
    CHECK(a.triangles == b.triangles);
    std::size_t same = 0;
    for (std::size_t i = 0; i < a.positions.size(); ++i)
        same += a.positions[i] == c.positions[i];
    CHECK(same == 0);
    // Edges at most max_edge, vertices in the box, and the centres fill the box
    glm::dvec3 mean(0.0);
    float longest = 0.0f;
    std::size_t outside = 0;
    for (const auto& t : a.triangles) {
        for (int k = 0; k < 3; ++k) {
            glm::vec3 p = a.positions[t[k]];
            longest = std::max(longest, glm::length(p - a.positions[t[(k + 1) % 3]]));
            outside += glm::any(glm::lessThan(p, lo)) || glm::any(glm::greaterThan(p, hi));
            mean += glm::dvec3(p) / 6000.0;
        }
    }
    CHECK(longest <= max_edge);
    CHECK(longest > 0.5f * max_edge);
    CHECK(outside == 0);
    glm::dvec3 mid = 0.5 * (glm::dvec3(lo) + glm::dvec3(hi));
    CHECK(glm::length(mean - mid) < 0.1);
}

TEST_CASE("make_stress_mesh: 250k triangles, closed torus, outward, in bounds", "[unit][scene]") {
    wp::Mesh m = wp::make_stress_mesh(250000);
    CHECK(m.triangles.size() == 250000);
    EdgeReport e = edges_of(m.triangles);
    CHECK(e.closed());
    // A torus: V - E + F = 0, with E = directed / 2
    CHECK(long(m.positions.size()) - long(e.directed / 2) + long(m.triangles.size()) == 0);
    CHECK(signed_volume(m) > 0.0);
    wp::Aabb b;
    for (const auto& p : m.positions)
        b.grow(p);
    CHECK(wp::Aabb{{-3.5f, -3.5f, -1.5f}, {3.5f, 3.5f, 1.5f}}.contains(b));
    // Deterministic, and other sizes land near their target
    CHECK(wp::make_stress_mesh(250000).positions == m.positions);
    for (std::size_t target : {1000u, 60000u, 100000u}) {
        double n = double(wp::make_stress_mesh(target).triangles.size());
        CHECK(n == Approx(double(target)).epsilon(0.03));
    }
}

TEST_CASE("transform and append keep meshes closed and outward", "[unit][scene]") {
    wp::Mesh box = wp::make_box({0, 0, 0}, {1, 2, 3}, 2);
    // Rotation + translation: same area and volume
    glm::mat4 rt = glm::translate(glm::mat4(1.0f), glm::vec3(5, -2, 1)) *
                   glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(1, 2, 3)));
    wp::Mesh moved = wp::transform(box, rt);
    CHECK(area(moved) == Approx(22.0).epsilon(1e-5));
    CHECK(signed_volume(moved) == Approx(6.0).epsilon(1e-5));
    // Scale by 2: volume x 8; a mirror keeps the volume positive (winding reversed)
    CHECK(signed_volume(wp::transform(box, glm::scale(glm::mat4(1.0f), glm::vec3(2.0f)))) ==
          Approx(48.0).epsilon(1e-6));
    wp::Mesh mirrored = wp::transform(box, glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1)));
    CHECK(signed_volume(mirrored) == Approx(6.0).epsilon(1e-6));
    CHECK(edges_of(mirrored.triangles).closed());
    // Append: the union of two closed meshes is closed, volumes add
    wp::Mesh both = box;
    wp::append(both, wp::make_icosphere({10, 0, 0}, 1.0f, 2));
    CHECK(both.triangles.size() == 48 + 320);
    CHECK(edges_of(both.triangles).closed());
    CHECK(signed_volume(both) ==
          Approx(6.0 + signed_volume(wp::make_icosphere({0, 0, 0}, 1.0f, 2))).epsilon(1e-5));
    // Flip: inward
    wp::flip_winding(both);
    CHECK(signed_volume(both) < 0.0);
}

// --- Built-in scenes -----------------------------------------------------------------------

TEST_CASE("Cornell box: budget, materials, light, objects, camera", "[unit][scene]") {
    wp::Scene s = wp::make_cornell_box();
    REQUIRE_NOTHROW(wp::validate_scene(s));
    CHECK(s.name == "cornell-box");
    CHECK(s.triangle_count() >= 15900);
    CHECK(s.triangle_count() <= 16100);
    CHECK(s.triangle_count() == 16020); // the count documented in builtin.h
    CHECK(s.warnings.empty());

    // The three material kinds and one emitter, with the classic box's values
    std::map<wp::MaterialKind, int> kinds;
    int emitters = 0;
    for (const auto& m : s.materials) {
        ++kinds[m.kind];
        emitters += m.emissive();
    }
    CHECK(kinds[wp::MaterialKind::Diffuse] >= 1);
    CHECK(kinds[wp::MaterialKind::Mirror] == 1);
    CHECK(kinds[wp::MaterialKind::Glossy] == 1);
    CHECK(emitters == 1);
    CHECK(s.materials[material_named(s, "red")].albedo == glm::vec3(0.63f, 0.065f, 0.05f));
    CHECK(s.materials[material_named(s, "green")].albedo == glm::vec3(0.14f, 0.45f, 0.091f));
    CHECK(s.materials[material_named(s, "white")].albedo == glm::vec3(0.725f, 0.71f, 0.68f));
    const auto& glossy = s.materials[material_named(s, "glossy")];
    CHECK(glossy.alpha == wp::phong_exponent_to_alpha(100.0f));  // the original exponent 100

    // Light: under the ceiling, facing down, Bitterli's area and radiance
    const std::uint32_t light = material_named(s, "light");
    CHECK(s.materials[light].emission == glm::vec3(17.0f, 12.0f, 4.0f));
    auto lt = triangles_with(s, light);
    REQUIRE(lt.size() == 2);
    CHECK(area(s.positions, lt) == Approx(0.47 * 0.38).epsilon(1e-5));
    for (const auto& t : lt) {
        CHECK(glm::normalize(normal_of(s.positions, t)).y == Approx(-1.0));
        for (int k = 0; k < 3; ++k) {
            CHECK(s.positions[t[k]].y < 2.0f);
            CHECK(s.positions[t[k]].y > 1.9f);
        }
    }

    // Walls: face the box's inside; red at x = -1, green at x = +1
    for (const char* wall : {"white", "red", "green"}) {
        for (const auto& t : triangles_with(s, material_named(s, wall))) {
            glm::dvec3 centroid = (glm::dvec3(s.positions[t.x]) + glm::dvec3(s.positions[t.y]) +
                                   glm::dvec3(s.positions[t.z])) /
                                  3.0;
            CHECK(glm::dot(normal_of(s.positions, t), glm::dvec3(0, 1, 0) - centroid) > 0.0);
            if (std::string(wall) == "red") CHECK(centroid.x == Approx(-1.0));
            if (std::string(wall) == "green") CHECK(centroid.x == Approx(1.0));
        }
    }
    // Mirror and glossy objects: closed, outward, inside the box, above the floor
    for (const char* object : {"mirror", "glossy"}) {
        auto tris = triangles_with(s, material_named(s, object));
        CHECK(tris.size() > 1000);
        CHECK(edges_of(tris).closed());
        CHECK(signed_volume(s.positions, tris) > 0.0);
        wp::Aabb b;
        for (const auto& t : tris)
            for (int k = 0; k < 3; ++k)
                b.grow(s.positions[t[k]]);
        CHECK(b.lo.y >= 0.0f);
        CHECK(b.hi.y < 1.9f); // below the light
        CHECK(wp::Aabb{{-1, 0, -1}, {1, 2, 1}}.contains(b));
        CHECK(b.lo.x > -1.0f); // clear of the side walls
        CHECK(b.hi.x < 1.0f);
    }
    // Camera: 800 x 600, outside the open front, looking into the box, the whole
    // front opening (y in [0, 2] at z = 1) inside the vertical fov
    const wp::Camera& c = s.camera;
    CHECK(c.width == 800);
    CHECK(c.height == 600);
    CHECK(c.vfov_deg == Approx(40.0f).margin(5.0f));
    CHECK(c.position.z > 1.0f);
    CHECK(c.target.z < c.position.z);
    float half = (c.position.z - 1.0f) * std::tan(glm::radians(0.5f * c.vfov_deg));
    CHECK(c.position.y - half <= 0.0f);
    CHECK(c.position.y + half >= 2.0f);
    CHECK(s.background == glm::vec3(0.0f));

    // The budget follows object_triangles
    for (int budget : {500, 4000, 50000}) {
        double n = double(wp::make_cornell_box(budget).triangle_count());
        CHECK(n == Approx(budget + 12.0).epsilon(0.02));
    }
}

TEST_CASE("closed-box furnace: closed, inward, camera inside, one emissive material",
          "[unit][scene]") {
    wp::Scene s = wp::make_closed_box_furnace(0.5f, 0.8f);
    REQUIRE_NOTHROW(wp::validate_scene(s));
    REQUIRE(s.materials.size() == 1);
    CHECK(s.materials[0].kind == wp::MaterialKind::Diffuse);
    CHECK(s.materials[0].albedo == glm::vec3(0.8f));
    CHECK(s.materials[0].emission == glm::vec3(0.5f));
    CHECK(s.triangle_count() > 12);
    CHECK(edges_of(s.triangles).closed());
    CHECK(signed_volume(s.positions, s.triangles) == Approx(-8.0).epsilon(1e-6)); // inward
    wp::Aabb b = s.bounds();
    CHECK(glm::all(glm::greaterThan(s.camera.position, b.lo)));
    CHECK(glm::all(glm::lessThan(s.camera.position, b.hi)));
    CHECK(s.camera.width == 64);
    CHECK(s.camera.height == 48);
    CHECK_THROWS_AS(wp::make_closed_box_furnace(1.0f, 1.5f), wp::Error);
}

// --- validate_scene ------------------------------------------------------------------------

TEST_CASE("validate_scene names each defect", "[unit][scene][parser]") {
    auto good = [] {
        wp::Scene s;
        s.name = "t";
        wp::Mesh m = wp::make_box({0, 0, 0}, {1, 1, 1});
        s.add_mesh(m.positions, m.triangles, s.add_material(wp::Material{}));
        return s;
    };
    REQUIRE_NOTHROW(wp::validate_scene(good()));

    wp::Scene s = good();
    s.triangles[3].y = 99;
    CHECK_THAT(error_of([&] { wp::validate_scene(s); }), Contains("triangle 3 uses vertex 99"));
    s = good();
    s.positions[5].z = std::nanf("");
    CHECK_THAT(error_of([&] { wp::validate_scene(s); }), Contains("vertex 5 has a non-finite"));
    s = good();
    s.positions[2].x = INFINITY;
    CHECK_THAT(error_of([&] { wp::validate_scene(s); }), Contains("vertex 2"));
    s = good();
    s.material_ids[7] = 4;
    CHECK_THAT(error_of([&] { wp::validate_scene(s); }), Contains("triangle 7 uses material 4"));
    s = good();
    s.material_ids.pop_back();
    CHECK_THAT(error_of([&] { wp::validate_scene(s); }), Contains("material ids"));
    s = good();
    s.triangles.clear();
    s.material_ids.clear();
    CHECK_THAT(error_of([&] { wp::validate_scene(s); }), Contains("no triangles"));
    s = good();
    s.materials[0].albedo = glm::vec3(1.2f, 0.5f, 0.5f);
    CHECK_THAT(error_of([&] { wp::validate_scene(s); }), Contains("albedo"));
    s = good();
    s.materials[0].emission = glm::vec3(-1.0f);
    CHECK_THAT(error_of([&] { wp::validate_scene(s); }), Contains("emission"));
    s = good();
    s.camera.width = 0;
    CHECK_THAT(error_of([&] { wp::validate_scene(s); }), Contains("film"));
    s = good();
    s.camera.up = glm::vec3(0.0f, 0.0f, 1.0f); // parallel to the default view direction
    CHECK_THAT(error_of([&] { wp::validate_scene(s); }), Contains("up vector"));
}

TEST_CASE("validate_scene: the parameters each kind reads, with their ranges",
          "[unit][scene][parser]") {
    using wp::MaterialKind;
    auto with = [](wp::Material m) {
        wp::Scene s;
        s.name = "t";
        m.name = "m";
        wp::Mesh b = wp::make_box({0, 0, 0}, {1, 1, 1});
        s.add_mesh(b.positions, b.triangles, s.add_material(m));
        return s;
    };
    auto message = [&](const wp::Material& m) {
        const wp::Scene s = with(m);
        return error_of([&] { wp::validate_scene(s); });
    };
    auto ok = [&](const wp::Material& m) {
        const wp::Scene s = with(m);
        wp::validate_scene(s);
        return true;
    };
    auto kind = [](MaterialKind k) {
        wp::Material m;
        m.kind = k;
        return m;
    };
    const float nan = std::nanf("");

    // Roughness: glossy (0, 1]; the rough kinds [1e-4, 2], alpha_v too
    wp::Material g = kind(MaterialKind::Glossy);
    g.alpha = 1.5f;
    CHECK_THAT(message(g), Contains("'m', glossy") && Contains("roughness alpha 1.5") &&
                               Contains("(0, 1]"));
    for (MaterialKind k : {MaterialKind::RoughConductor, MaterialKind::RoughDielectric,
                           MaterialKind::RoughPlastic}) {
        wp::Material m = kind(k);
        m.alpha = 2.0f;
        CHECK(ok(m));
        m.alpha = 1e-4f;
        CHECK(ok(m));
        m.alpha = 2.5f;
        CHECK_THAT(message(m), Contains("roughness alpha 2.5") && Contains("[0.0001, 2]"));
        m.alpha = 5e-5f;
        CHECK_THAT(message(m), Contains("roughness alpha"));
        m.alpha = nan;
        CHECK_THAT(message(m), Contains("roughness alpha nan"));
        m.alpha = 0.3f;
        m.alpha_v = 3.0f;
        CHECK_THAT(message(m), Contains("alpha_v 3"));
        m.alpha_v = 0.01f;
        CHECK(ok(m));
    }
    // Kinds without ALPHA do not read it: any value passes
    wp::Material c = kind(MaterialKind::Conductor);
    c.alpha = 7.0f;
    CHECK(ok(c));

    // Index of refraction and specular tint of the IOR kinds
    for (MaterialKind k : {MaterialKind::Glass, MaterialKind::RoughDielectric,
                           MaterialKind::ThinDielectric, MaterialKind::Plastic,
                           MaterialKind::RoughPlastic}) {
        wp::Material m = kind(k);
        m.ior = 100.0f;
        CHECK(ok(m));
        m.ior = 0.01f;
        CHECK(ok(m));
        m.ior = 101.0f;
        CHECK_THAT(message(m), Contains("index of refraction 101") && Contains("[0.01, 100]"));
        m.ior = 0.0f;
        CHECK_THAT(message(m), Contains("index of refraction 0"));
        m.ior = nan;
        CHECK_THAT(message(m), Contains("index of refraction"));
        m.ior = 1.5f;
        m.specular = glm::vec3(0.5f, 1.5f, 0.5f);
        CHECK_THAT(message(m), Contains("specular tint (0.5, 1.5, 0.5)") && Contains("[0, 1]"));
        m.specular = glm::vec3(-0.1f);
        CHECK_THAT(message(m), Contains("specular tint"));
    }
    wp::Material d = kind(MaterialKind::Diffuse);
    d.ior = 0.0f;
    d.specular = glm::vec3(9.0f);
    d.eta = glm::vec3(-1.0f);
    CHECK(ok(d));  // not read by diffuse

    // Conductors' η and k: finite, >= 0 (0 allowed: η 0 k 1 is the default)
    for (MaterialKind k : {MaterialKind::Conductor, MaterialKind::RoughConductor}) {
        wp::Material m = kind(k);
        CHECK(ok(m));
        m.eta = glm::vec3(0.2f, -0.1f, 1.0f);
        CHECK_THAT(message(m), Contains("conductor eta (0.2, -0.1, 1)") && Contains(">= 0"));
        m.eta = glm::vec3(0.2f, INFINITY, 1.0f);
        CHECK_THAT(message(m), Contains("conductor eta") && Contains("finite"));
        m.eta = glm::vec3(0.2f);
        m.k = glm::vec3(nan);
        CHECK_THAT(message(m), Contains("conductor k"));
        m.k = glm::vec3(-2.0f);
        CHECK_THAT(message(m), Contains("conductor k (-2, -2, -2)"));
        m.k = glm::vec3(0.0f);
        CHECK(ok(m));
    }
}

// --- OBJ loader ----------------------------------------------------------------------------

TEST_CASE("load_obj: quads are triangulated into a closed cube", "[unit][scene][parser]") {
    TempDir dir;
    wp::Scene s = wp::load_obj(dir.write("cube.obj", kCubeQuads));
    CHECK(s.name == "cube.obj");
    CHECK(s.positions.size() == 8);
    CHECK(s.triangle_count() == 12);
    CHECK(edges_of(s.triangles).closed());
    CHECK(signed_volume(s.positions, s.triangles) == Approx(1.0));
    CHECK(area(s.positions, s.triangles) == Approx(6.0));
    // No material: the mid-grey default, and exactly one warning saying so
    REQUIRE(s.materials.size() == 1);
    CHECK(s.materials[0].kind == wp::MaterialKind::Diffuse);
    CHECK(s.materials[0].albedo == glm::vec3(0.5f));
    REQUIRE(s.warnings.size() == 1);
    CHECK_THAT(s.warnings[0], Contains("no material") && Contains("cube.obj"));
    // Camera: from +z at the box centre, bounding sphere (radius sqrt(3)/2) in the fov
    CHECK(s.camera.width == 800);
    CHECK(s.camera.height == 600);
    CHECK(s.camera.target == glm::vec3(0.5f));
    const float d = std::sqrt(3.0f) / 2.0f / std::sin(glm::radians(20.0f));
    CHECK(s.camera.position.x == Approx(0.5f));
    CHECK(s.camera.position.y == Approx(0.5f));
    CHECK(s.camera.position.z == Approx(0.5f + d));
}

TEST_CASE("load_obj: pentagons, negative indices, comments and CRLF", "[unit][scene][parser]") {
    TempDir dir;
    const std::string text = "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\n"
                             "f -3 -2 -1 # the first triangle\r\n"
                             "v 0 1 0\r\nv -0.5 0.5 0\r\n"
                             "f -5/1 -4/1 -3/1\r\n" // vertices 1 2 3 again, with a texture index
                             "f 1//1 2//1 3//1 4//1 5//1\r\n"; // a convex pentagon, normals ignored
    wp::Scene s = wp::load_obj(dir.write("neg.obj", text));
    REQUIRE(s.triangle_count() == 1 + 1 + 3);
    CHECK(s.triangles[0] == glm::uvec3(0, 1, 2));
    CHECK(s.triangles[1] == glm::uvec3(0, 1, 2));
    // The pentagon as 3 triangles covering its area: the unit square plus the triangle
    // (1, 4, 5) of area 0.25, all facing +z like the polygon
    std::vector<glm::uvec3> poly(s.triangles.begin() + 2, s.triangles.end());
    CHECK(area(s.positions, poly) == Approx(1.25));
    for (const auto& t : poly)
        CHECK(normal_of(s.positions, t).z > 0.0);
}

TEST_CASE("load_obj: MTL material mapping of every kind", "[unit][scene][parser]") {
    TempDir dir;
    dir.write("m.mtl", R"(newmtl Matte
Kd 0.5 0.4 0.3
Ks 0.2 0.2 0.2
Ns 50
illum 2

newmtl Lamp
Kd 0 0 0
Ke 17 12 4
illum 1

newmtl Chrome
Kd 0 0 0
Ks 0.9 0.8 0.7
Ns 2000
illum 3

newmtl PerfectMirror
Kd 0 0 0
Ks 1 1 1
Ns 10
illum 5

newmtl Phong
Kd 0 0 0
Ks 0.8 0.7 0.6
Ns 120
illum 2

newmtl RoughMetal
Kd 0 0 0
Ks 0.3 0.2 0.1
Ns 198
illum 3

newmtl Layered
Kd 0.5 0.5 0.5
Ks 0.5 0.5 0.5
Ns 2000
illum 3

newmtl Unused
Kd 1 0 0
)");
    std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
    for (const char* m : {"Matte", "Lamp", "Chrome", "PerfectMirror", "Phong", "RoughMetal",
                          "Layered", "NotInTheMtl"})
        obj += fmt::format("usemtl {}\nf 1 2 3\n", m);
    wp::Scene s = wp::load_obj(dir.write("m.obj", obj));
    REQUIRE(s.triangle_count() == 8);
    REQUIRE(s.materials.size() == 8); // 7 used + default; "Unused" dropped
    auto mat = [&](int tri) { return s.materials[s.material_ids[tri]]; };
    using K = wp::MaterialKind;

    CHECK(mat(0).name == "Matte");
    CHECK(mat(0).kind == K::Diffuse);
    CHECK(mat(0).albedo == glm::vec3(0.5f, 0.4f, 0.3f));
    CHECK_FALSE(mat(0).emissive());

    CHECK(mat(1).kind == K::Diffuse);
    CHECK(mat(1).emission == glm::vec3(17.0f, 12.0f, 4.0f));
    CHECK(mat(1).albedo == glm::vec3(0.0f));

    CHECK(mat(2).kind == K::Mirror);
    CHECK(mat(2).albedo == glm::vec3(0.9f, 0.8f, 0.7f));
    CHECK(mat(3).kind == K::Mirror);
    CHECK(mat(3).albedo == glm::vec3(1.0f));

    CHECK(mat(4).kind == K::Glossy);
    CHECK(mat(4).albedo == glm::vec3(0.8f, 0.7f, 0.6f));
    CHECK(mat(4).alpha == wp::phong_exponent_to_alpha(120.0f));
    CHECK(mat(5).kind == K::Glossy);
    CHECK(mat(5).alpha == wp::phong_exponent_to_alpha(198.0f));

    CHECK(mat(6).kind == K::Diffuse); // Kd and Ks with illum 3: diffuse, with a warning
    CHECK(mat(6).albedo == glm::vec3(0.5f));

    CHECK(mat(7).name == "default");
    CHECK(mat(7).albedo == glm::vec3(0.5f));

    int layered = 0, no_material = 0;
    for (const auto& w : s.warnings) {
        layered += w.find("'Layered'") != std::string::npos;
        no_material += w.find("no material") != std::string::npos;
    }
    CHECK(layered == 1);
    CHECK(no_material == 1);
}

TEST_CASE("load_obj: the shipped Cornell box OBJ", "[unit][scene][parser]") {
    const fs::path p = fs::path(WP_SHARED_SCENES) / "cornell-box" / "cornell-box.obj";
    if (!fs::exists(p)) {
        WARN("skipped: " << p << " not found");
        return;
    }
    wp::Scene s = wp::load_obj(p);
    CHECK(s.triangle_count() == 36); // SOURCE.md: 36 triangles, 72 vertices
    CHECK(s.positions.size() == 72);
    CHECK(s.materials.size() == 8);
    CHECK(s.warnings.empty());
    int emitters = 0;
    for (const auto& m : s.materials) {
        CHECK(m.kind == wp::MaterialKind::Diffuse);
        if (m.emissive()) {
            ++emitters;
            CHECK(m.emission == glm::vec3(17.0f, 12.0f, 4.0f));
        }
    }
    CHECK(emitters == 1);
    CHECK(s.materials[material_named(s, "LeftWall")].albedo == glm::vec3(0.63f, 0.065f, 0.05f));
    wp::Aabb b = s.bounds();
    CHECK(b.hi.y == Approx(2.0f));
    CHECK(b.lo.x == Approx(-1.0f));
}

TEST_CASE("load_obj: bad files give one clear error with file and line", "[unit][scene][parser]") {
    TempDir dir;
    // Face index beyond the vertex count, at line 5
    std::string msg = error_of([&] {
        wp::load_obj(dir.write("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 9\n"));
    });
    CHECK_THAT(msg,
               Contains("bad_index.obj:5:") && Contains("index 9") && Contains("out of range"));
    // Negative index reaching before the first vertex, index 0
    msg = error_of([&] { wp::load_obj(dir.write("neg.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n")); });
    CHECK_THAT(msg, Contains("neg.obj:3:") && Contains("-3"));
    msg = error_of([&] { wp::load_obj(dir.write("zero.obj", "v 0 0 0\nv 1 0 0\nf 0 1 2\n")); });
    CHECK_THAT(msg, Contains("zero.obj:3:") && Contains("index 0"));
    // A forward reference that never gets defined is still out of range
    msg = error_of([&] { wp::load_obj(dir.write("fwd.obj", "f 1 2 3\nv 0 0 0\nv 1 0 0\n")); });
    CHECK_THAT(msg, Contains("fwd.obj:1:") && Contains("index 3"));
    // Faces with fewer than 3 vertices
    msg = error_of([&] { wp::load_obj(dir.write("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n")); });
    CHECK_THAT(msg, Contains("two.obj:3:") && Contains("at least 3"));
    // NaN and infinite coordinates, and garbage
    msg = error_of(
        [&] { wp::load_obj(dir.write("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n")); });
    CHECK_THAT(msg, Contains("nan.obj:2:") && Contains("vertex 2") && Contains("non-finite"));
    msg = error_of(
        [&] { wp::load_obj(dir.write("inf.obj", "v 0 0 -inf\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")); });
    CHECK_THAT(msg, Contains("inf.obj:1:") && Contains("non-finite"));
    msg = error_of(
        [&] { wp::load_obj(dir.write("big.obj", "v 0 0 1e39\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")); });
    CHECK_THAT(msg, Contains("big.obj:1:"));
    msg = error_of(
        [&] { wp::load_obj(dir.write("junk.obj", "v 0 0 0\nv 1 0 x\nv 0 1 0\nf 1 2 3\n")); });
    CHECK_THAT(msg, Contains("junk.obj:2:") && Contains("'x'"));
    msg = error_of(
        [&] { wp::load_obj(dir.write("short.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")); });
    CHECK_THAT(msg, Contains("short.obj:1:") && Contains("coordinates"));
    // Missing file, directory, empty file, vertices only
    msg = error_of([&] { wp::load_obj(dir.path / "missing.obj"); });
    CHECK_THAT(msg, Contains("cannot open") && Contains("missing.obj"));
    msg = error_of([&] { wp::load_obj(dir.path); });
    CHECK_THAT(msg, Contains("cannot open"));
    msg = error_of([&] { wp::load_obj(dir.write("empty.obj", "")); });
    CHECK_THAT(msg, Contains("empty.obj") && Contains("no triangles"));
    msg = error_of(
        [&] { wp::load_obj(dir.write("points.obj", "# only points\nv 0 0 0\nv 1 0 0\n")); });
    CHECK_THAT(msg, Contains("points.obj") && Contains("no triangles"));
}

// util/read_file: what every loader reads its file with (hand-made files, known sizes).
TEST_CASE("read_file: bytes, a size limit and one clear error", "[unit][scene][parser]") {
    TempDir d;
    fs::path ok = d.write("five.bin", std::string("ab\0cd", 5));
    CHECK(wp::read_file(ok, 5) == std::string("ab\0cd", 5));
    CHECK_THAT(error_of([&] { wp::read_file(ok, 4); }), Contains("five.bin") && Contains("more than the limit of 4"));
    CHECK_THAT(error_of([&] { wp::read_file(d.path / "none.obj", 100); }), Contains("none.obj': no such file"));
    CHECK_THAT(error_of([&] { wp::read_file(d.path, 100); }), Contains("not a regular file"));
    CHECK(wp::try_read_file(ok, 5) == std::string("ab\0cd", 5));
    CHECK_FALSE(wp::try_read_file(ok, 4).has_value());
    CHECK_FALSE(wp::try_read_file(d.path / "none.obj", 100).has_value());
    CHECK_FALSE(wp::try_read_file(d.path, 100).has_value());
}
