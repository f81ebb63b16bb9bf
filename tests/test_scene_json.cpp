// test_scene_json.cpp — wavepath JSON scene files (scene/json_scene.h) against hand-computed
// answers: every shape and key, transforms in the documented order, the shipped scenes
// (scenes/*.json; cornell-box.json must be the built-in box, triangle for triangle and pixel
// for pixel), and one clear message for every kind of bad input.
//
// Everything but the last test only parses: [parser] (run again under ASan + UBSan).
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "image/image.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "scene/json_scene.h"
#include "scene/load.h"
#include "scene/validate.h"
#include "support.h"
#include "util/error.h"
#include "util/splitmix.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using wp::Scene;

namespace {

using wp::test::TempDir;

Scene parse(const std::string& text) { return wp::parse_json_scene(text, "dir/t.json"); }

// The message of the wp::Error that parsing `text` throws ("" and a failed check if none).
std::string error_of(const std::string& text) {
    try {
        parse(text);
    } catch (const wp::Error& e) {
        return e.what();
    }
    FAIL_CHECK("no error for: " << text);
    return {};
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::string read_file(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// A scene around `shapes` with an emitting material "lamp" and a white "white".
std::string with_shapes(const std::string& shapes, const std::string& extra_materials = "") {
    return R"({"materials": {"white": {"type": "diffuse", "reflectance": 0.5},
                             "lamp": {"type": "diffuse", "emission": 1})" +
           extra_materials + R"(}, "shapes": [)" + shapes + "]}";
}

glm::dvec3 normal_of(const Scene& s, const glm::uvec3& t) {
    glm::dvec3 a(s.positions[t.x]), b(s.positions[t.y]), c(s.positions[t.z]);
    return glm::cross(b - a, c - a);
}

double total_area(const Scene& s) {
    double a = 0.0;
    for (const auto& t : s.triangles) a += 0.5 * glm::length(normal_of(s, t));
    return a;
}

// The distinct vertex positions used by triangles, rounded to 1e-4 for set comparison.
std::set<std::array<long, 3>> corners(const Scene& s) {
    std::set<std::array<long, 3>> out;
    for (const auto& t : s.triangles)
        for (int k = 0; k < 3; ++k) {
            glm::vec3 p = s.positions[t[k]];
            out.insert({std::lround(p.x * 1e4), std::lround(p.y * 1e4), std::lround(p.z * 1e4)});
        }
    return out;
}
std::set<std::array<long, 3>> points(std::initializer_list<glm::dvec3> ps) {
    std::set<std::array<long, 3>> out;
    for (auto p : ps) out.insert({std::lround(p.x * 1e4), std::lround(p.y * 1e4), std::lround(p.z * 1e4)});
    return out;
}

std::uint32_t material_named(const Scene& s, const std::string& name) {
    for (std::uint32_t i = 0; i < s.materials.size(); ++i)
        if (s.materials[i].name == name) return i;
    FAIL("no material " << name);
    return 0;
}

fs::path repo_scene(const char* name) { return fs::path(WP_SOURCE_DIR) / "scenes" / name; }

}  // namespace

TEST_CASE("json scene: a quad from corner and edges, camera, background, render, material",
          "[scene][json][parser]") {
    Scene s = parse(R"({
      "version": 1,
      "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov": 30,
                 "width": 64, "height": 48},
      "background": [0.1, 0.2, 0.3],
      "render": {"spp": 7, "depth": 2, "seed": 99},
      "materials": {"white": {"type": "diffuse", "reflectance": 0.5, "emission": [1, 2, 3]}},
      "shapes": [{"type": "quad", "corner": [1, 2, 3], "edge_u": [2, 0, 0], "edge_v": [0, 0, -4],
                  "material": "white"}]
    })");
    CHECK(s.name == "t.json");
    REQUIRE(s.triangle_count() == 2);
    CHECK(corners(s) == points({{1, 2, 3}, {3, 2, 3}, {1, 2, -1}, {3, 2, -1}}));
    // cross((2,0,0), (0,0,-4)) = (0, 8, 0): both triangles face +y; area |u x v| = 8
    for (const auto& t : s.triangles) {
        glm::dvec3 n = glm::normalize(normal_of(s, t));
        CHECK(n.y == Approx(1.0));
    }
    CHECK(total_area(s) == Approx(8.0));
    REQUIRE(s.materials.size() == 1);
    CHECK(s.materials[0].name == "white");
    CHECK(s.materials[0].kind == wp::MaterialKind::Diffuse);
    CHECK(s.materials[0].albedo == glm::vec3(0.5f));
    CHECK(s.materials[0].emission == glm::vec3(1.0f, 2.0f, 3.0f));
    CHECK(s.material_ids == std::vector<std::uint32_t>{0, 0});
    CHECK(s.camera.position == glm::vec3(0, 0, 5));
    CHECK(s.camera.target == glm::vec3(0, 0, 0));
    CHECK(s.camera.up == glm::vec3(0, 1, 0));
    CHECK(s.camera.vfov_deg == 30.0f);
    CHECK(s.camera.width == 64);
    CHECK(s.camera.height == 48);
    CHECK(s.background == glm::vec3(0.1f, 0.2f, 0.3f));
    CHECK(s.render.spp == 7);
    CHECK(s.render.depth == 2);
    CHECK(s.render.seed == 99u);
    CHECK(s.warnings.empty());
}

TEST_CASE("json scene: quad size and subdivisions", "[scene][json][parser]") {
    Scene s = parse(with_shapes(
        R"({"type": "quad", "size": [2, 1], "subdivisions": [3, 2], "material": "lamp"})"));
    CHECK(s.triangle_count() == 12);  // 3 x 2 cells, 2 triangles each
    CHECK(s.positions.size() == 12);  // 4 x 3 grid points
    wp::Aabb b = s.bounds();
    CHECK(b.lo == glm::vec3(-1.0f, -0.5f, 0.0f));
    CHECK(b.hi == glm::vec3(1.0f, 0.5f, 0.0f));
    for (const auto& t : s.triangles) CHECK(glm::normalize(normal_of(s, t)).z == Approx(1.0));
    CHECK(total_area(s) == Approx(2.0));

    Scene sq = parse(with_shapes(R"({"type": "quad", "size": 3, "subdivisions": 4, "material": "lamp"})"));
    CHECK(sq.triangle_count() == 32);
    CHECK(corners(sq).size() == 25);
    CHECK(total_area(sq) == Approx(9.0));
}

TEST_CASE("json scene: boxes from min/max and from size/center", "[scene][json][parser]") {
    Scene a = parse(with_shapes(
        R"({"type": "box", "min": [0, 0, 0], "max": [1, 2, 3], "material": "lamp"})"));
    CHECK(a.triangle_count() == 12);
    CHECK(a.positions.size() == 8);
    CHECK(corners(a) == points({{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}, {1, 2, 0}, {1, 0, 3},
                                {0, 2, 3}, {1, 2, 3}}));
    CHECK(total_area(a) == Approx(2.0 * (1 * 2 + 2 * 3 + 3 * 1)));
    // Outward: every triangle's normal points away from the centre (0.5, 1, 1.5)
    for (const auto& t : a.triangles) {
        glm::dvec3 c = (glm::dvec3(a.positions[t.x]) + glm::dvec3(a.positions[t.y]) +
                        glm::dvec3(a.positions[t.z])) / 3.0;
        CHECK(glm::dot(normal_of(a, t), c - glm::dvec3(0.5, 1, 1.5)) > 0.0);
    }

    Scene b = parse(with_shapes(
        R"({"type": "box", "size": [2, 4, 6], "center": [1, 1, 1], "subdivisions": 2, "material": "lamp"})"));
    CHECK(b.triangle_count() == 48);    // 12 n^2
    CHECK(b.positions.size() == 26);    // 6 n^2 + 2
    CHECK(b.bounds().lo == glm::vec3(0, -1, -2));
    CHECK(b.bounds().hi == glm::vec3(2, 3, 4));

    Scene c = parse(with_shapes(R"({"type": "box", "size": 1, "material": "lamp"})"));
    CHECK(c.bounds().lo == glm::vec3(-0.5f));
    CHECK(c.bounds().hi == glm::vec3(0.5f));
}

TEST_CASE("json scene: spheres: counts, radius, area against 4 pi r^2", "[scene][json][parser]") {
    const double pi = 3.14159265358979323846;
    Scene s = parse(with_shapes(R"({"type": "sphere", "center": [1, 2, 3], "radius": 2,
                                    "rings": 16, "segments": 32, "material": "lamp"})"));
    CHECK(s.triangle_count() == 2 * 32 * 15);
    for (const auto& p : s.positions)
        CHECK(glm::length(glm::dvec3(p) - glm::dvec3(1, 2, 3)) == Approx(2.0).epsilon(1e-6));
    // An inscribed polyhedron: a little less area than the sphere, the error falling as the
    // square of the cell size (16 x 32 cells: under 2%; 64 x 128: under 0.2%)
    const double exact = 4.0 * pi * 4.0;
    const double coarse = total_area(s) / exact;
    CHECK(coarse < 1.0);
    CHECK(coarse > 0.98);
    Scene fine = parse(with_shapes(R"({"type": "sphere", "center": [1, 2, 3], "radius": 2,
                                       "rings": 64, "segments": 128, "material": "lamp"})"));
    const double f = total_area(fine) / exact;
    CHECK(f < 1.0);
    CHECK(f > 0.998);
    CHECK(1.0 - f < (1.0 - coarse) / 8.0);  // 4x finer: about 16x less error
    // Defaults: centre 0, radius 1, 32 rings, 64 segments
    Scene d = parse(with_shapes(R"({"type": "sphere", "material": "lamp"})"));
    CHECK(d.triangle_count() == 2 * 64 * 31);
    CHECK(d.bounds().hi.y == Approx(1.0f));
    CHECK(d.bounds().lo.y == Approx(-1.0f));
}

TEST_CASE("json scene: the stress shape", "[scene][json][parser]") {
    Scene s = parse(with_shapes(R"({"type": "stress", "triangles": 2000, "material": "lamp"})"));
    CHECK(s.triangle_count() >= 1900);
    CHECK(s.triangle_count() <= 2100);
    CHECK(wp::Aabb{{-3.5f, -3.5f, -1.5f}, {3.5f, 3.5f, 1.5f}}.contains(s.bounds()));
}

TEST_CASE("json scene: transforms in the documented order", "[scene][json][parser]") {
    // The quad's corners (1,0,0), (1,1,0), (1,0,1), (1,1,1), normal cross(y, z) = +x
    const std::string quad =
        R"({"type": "quad", "corner": [1, 0, 0], "edge_u": [0, 1, 0], "edge_v": [0, 0, 1],
            "material": "lamp", "transform": )";
    auto with = [&](const std::string& t) { return parse(with_shapes(quad + t + "}")); };

    // A list acts in order: scale 2, then rotate 90 about z ((x,y,z) -> (-y,x,z)), then
    // translate (1,0,0): (1,0,0) -> (2,0,0) -> (0,2,0) -> (1,2,0)
    const auto srt = points({{1, 2, 0}, {-1, 2, 0}, {1, 2, 2}, {-1, 2, 2}});
    Scene a = with(R"([{"scale": 2}, {"rotate": {"axis": [0, 0, 1], "degrees": 90}},
                       {"translate": [1, 0, 0]}])");
    CHECK(corners(a) == srt);
    // The normal +x turned 90 about z is +y
    for (const auto& t : a.triangles) CHECK(glm::normalize(normal_of(a, t)).y == Approx(1.0));

    // Reversed list: translate first: (1,0,0) -> (2,0,0) -> (0,2,0) -> (0,4,0)
    Scene b = with(R"([{"translate": [1, 0, 0]}, {"rotate": {"axis": [0, 0, 1], "degrees": 90}},
                       {"scale": 2}])");
    CHECK(corners(b) == points({{0, 4, 0}, {-2, 4, 0}, {0, 4, 2}, {-2, 4, 2}}));

    // The object form is scale, then rotate, then translate, whatever the key order
    Scene c = with(R"({"translate": [1, 0, 0], "rotate": {"axis": [0, 0, 1], "degrees": 90},
                       "scale": [2, 2, 2]})");
    CHECK(corners(c) == srt);

    // Matrices, row-major: the translation is the last column
    const auto shifted = points({{6, 6, 7}, {6, 7, 7}, {6, 6, 8}, {6, 7, 8}});
    Scene d = with(R"({"matrix": [1, 0, 0, 5,  0, 1, 0, 6,  0, 0, 1, 7,  0, 0, 0, 1]})");
    CHECK(corners(d) == shifted);
    Scene e = with(R"({"matrix": [[1, 0, 0, 5], [0, 1, 0, 6], [0, 0, 1, 7], [0, 0, 0, 1]]})");
    CHECK(corners(e) == shifted);
    // A matrix step among others: rotate 90 about y ((x,y,z) -> (z,y,-x)), then the matrix
    Scene f = with(R"([{"rotate": {"axis": [0, 1, 0], "degrees": 90}},
                       {"matrix": [1, 0, 0, 5,  0, 1, 0, 6,  0, 0, 1, 7,  0, 0, 0, 1]}])");
    CHECK(corners(f) == points({{5, 6, 6}, {5, 7, 6}, {6, 6, 6}, {6, 7, 6}}));

    // A mirror keeps the front in front: x -> -x maps the +x normal to -x
    Scene m = with(R"({"scale": [-1, 1, 1]})");
    CHECK(corners(m) == points({{-1, 0, 0}, {-1, 1, 0}, {-1, 0, 1}, {-1, 1, 1}}));
    for (const auto& t : m.triangles) CHECK(glm::normalize(normal_of(m, t)).x == Approx(-1.0));
}

TEST_CASE("json scene: materials of every kind, defaults, file order, unused ones",
          "[scene][json][parser]") {
    Scene s = parse(R"({
      "materials": {
        "z-diffuse": {"type": "diffuse"},
        "mirror": {"type": "mirror"},
        "rough": {"type": "glossy", "roughness": 0.2, "reflectance": [0.1, 0.2, 0.3]},
        "phong": {"type": "glossy", "exponent": 10},
        "plain-glossy": {"type": "glossy"},
        "water": {"type": "glass", "ior": 1.33, "reflectance": [1, 0.9, 0.8]},
        "glass": {"type": "glass"},
        "lamp": {"type": "mirror", "reflectance": 0.25, "emission": 5},
        "unused": {"type": "diffuse"}
      },
      "shapes": [
        {"type": "quad", "size": 1, "material": "lamp"},
        {"type": "quad", "size": 1, "material": "glass"},
        {"type": "quad", "size": 1, "material": "water"},
        {"type": "quad", "size": 1, "material": "plain-glossy"},
        {"type": "quad", "size": 1, "material": "phong"},
        {"type": "quad", "size": 1, "material": "rough"},
        {"type": "quad", "size": 1, "material": "mirror"},
        {"type": "quad", "size": 1, "material": "z-diffuse"}
      ]
    })");
    // File order, not use order or name order; the unused one dropped with a warning
    std::vector<std::string> names;
    for (const auto& m : s.materials) names.push_back(m.name);
    CHECK(names == std::vector<std::string>{"z-diffuse", "mirror", "rough", "phong",
                                            "plain-glossy", "water", "glass", "lamp"});
    REQUIRE(s.warnings.size() == 1);
    CHECK(has(s.warnings[0], "dir/t.json"));
    CHECK(has(s.warnings[0], "'unused'"));
    CHECK(has(s.warnings[0], "/materials/unused"));
    // Shapes use their materials
    CHECK(s.material_ids[0] == material_named(s, "lamp"));
    CHECK(s.material_ids[14] == material_named(s, "z-diffuse"));

    auto m = [&](const char* n) { return s.materials[material_named(s, n)]; };
    CHECK(m("z-diffuse").kind == wp::MaterialKind::Diffuse);
    CHECK(m("z-diffuse").albedo == glm::vec3(0.8f));
    CHECK(m("mirror").kind == wp::MaterialKind::Mirror);
    CHECK(m("mirror").albedo == glm::vec3(1.0f));
    CHECK(m("rough").kind == wp::MaterialKind::Glossy);
    CHECK(m("rough").alpha == 0.2f);  // as given
    CHECK(m("rough").albedo == glm::vec3(0.1f, 0.2f, 0.3f));
    CHECK(m("phong").alpha == wp::phong_exponent_to_alpha(10.0f));
    CHECK(m("phong").albedo == glm::vec3(0.8f));
    CHECK(m("plain-glossy").alpha == wp::phong_exponent_to_alpha(100.0f));
    CHECK(m("water").kind == wp::MaterialKind::Glass);
    CHECK(m("water").ior == 1.33f);
    CHECK(m("water").albedo == glm::vec3(1.0f, 0.9f, 0.8f));
    CHECK(m("glass").ior == 1.5f);
    CHECK(m("glass").albedo == glm::vec3(1.0f));
    CHECK(m("lamp").kind == wp::MaterialKind::Mirror);
    CHECK(m("lamp").albedo == glm::vec3(0.25f));
    CHECK(m("lamp").emission == glm::vec3(5.0f));
}

TEST_CASE("json scene: conductors, rough kinds, dielectrics and plastics parse to their Material",
          "[scene][json][parser]") {
    using wp::MaterialKind;
    using wp::MicrofacetModel;
    // Every material on one quad each, so every one is kept
    const std::vector<std::pair<std::string, std::string>> mats = {
        {"chrome", R"({"type": "conductor"})"},
        {"copper", R"({"type": "conductor", "metal": "Cu", "reflectance": [0.9, 0.8, 0.7]})"},
        {"custom", R"({"type": "conductor", "eta": [0.2, 0.9, 1.1], "k": 3.5})"},
        {"none", R"({"type": "conductor", "metal": "none"})"},
        {"rough-gold", R"({"type": "roughconductor", "metal": "Au", "roughness": 0.3,
                           "distribution": "beckmann", "g": "separable"})"},
        {"brushed", R"({"type": "roughconductor", "roughness_u": 0.05, "roughness_v": 1.5,
                        "distribution": "ggx", "g": "height-correlated"})"},
        {"rough-default", R"({"type": "roughconductor"})"},
        {"rough-tex", R"({"type": "roughconductor", "roughness_texture": {"checkerboard": [0.5, 1]}})"},
        {"tinted-glass", R"({"type": "glass", "reflectance": [0.9, 0.8, 0.7]})"},
        {"split-glass", R"({"type": "glass", "ior": 1.33, "specular": 0.5, "transmittance": [1, 0.9, 0.8]})"},
        {"frosted", R"({"type": "roughdielectric", "ior": 2.0, "roughness": 2, "transmittance": 0.75})"},
        {"pane", R"({"type": "thindielectric", "ior": 100, "specular": [0.1, 0.2, 0.3]})"},
        {"low-ior", R"({"type": "glass", "ior": 0.01})"},
        {"plastic", R"({"type": "plastic", "reflectance": [0.1, 0.2, 0.3], "specular": 0.9,
                        "ior": 1.49, "nonlinear": true})"},
        {"plastic-default", R"({"type": "plastic"})"},
        {"rough-plastic", R"({"type": "roughplastic", "roughness": 0.0001, "distribution": "beckmann",
                              "nonlinear": false})"},
    };
    std::string materials, shapes;
    for (const auto& [name, body] : mats) {
        materials += (materials.empty() ? "" : ", ") + ("\"" + name + "\": " + body);
        shapes += (shapes.empty() ? "" : ", ") +
                  (R"({"type": "quad", "size": 1, "material": ")" + name + "\"}");
    }
    materials += R"(, "lamp": {"type": "diffuse", "emission": 1})";
    shapes += R"(, {"type": "quad", "size": 1, "material": "lamp"})";
    Scene s = parse(R"({"materials": {)" + materials + R"(}, "shapes": [)" + shapes + "]}");
    CHECK(s.warnings.empty());
    auto m = [&](const char* n) { return s.materials[material_named(s, n)]; };
    const wp::Material def;  // the host defaults, for the fields a kind does not set

    // Conductors: η 0, k 1 without a metal (reflects everything); a metal from the table
    // (Tungsten's RGB fits, as the Mitsuba loader's: Cu, Au below); the tint is "reflectance"
    CHECK(m("chrome").kind == MaterialKind::Conductor);
    CHECK(m("chrome").albedo == glm::vec3(1.0f));
    CHECK(m("chrome").eta == glm::vec3(0.0f));
    CHECK(m("chrome").k == glm::vec3(1.0f));
    CHECK(m("copper").eta == glm::vec3(0.2004377f, 0.9240334f, 1.1022120f));
    CHECK(m("copper").k == glm::vec3(3.9129485f, 2.4528477f, 2.1421880f));
    CHECK(m("copper").albedo == glm::vec3(0.9f, 0.8f, 0.7f));
    CHECK(m("custom").eta == glm::vec3(0.2f, 0.9f, 1.1f));
    CHECK(m("custom").k == glm::vec3(3.5f));
    CHECK(m("none").eta == glm::vec3(0.0f));
    CHECK(m("none").k == glm::vec3(1.0f));
    // Rough conductors: α as given, the model's switches; Mitsuba's default α 0.1; α 1 under
    // a roughness texture (α × G²)
    CHECK(m("rough-gold").kind == MaterialKind::RoughConductor);
    CHECK(m("rough-gold").eta == glm::vec3(0.1431190f, 0.3749570f, 1.4424786f));
    CHECK(m("rough-gold").k == glm::vec3(3.9831604f, 2.3857207f, 1.6032153f));
    CHECK(m("rough-gold").alpha == 0.3f);
    CHECK(!m("rough-gold").alpha_v);
    CHECK(m("rough-gold").distribution == MicrofacetModel::Beckmann);
    CHECK(m("rough-gold").separable_g);
    CHECK(m("brushed").alpha == 0.05f);
    CHECK(m("brushed").alpha_v == 1.5f);
    CHECK(m("brushed").distribution == MicrofacetModel::GGX);
    CHECK(!m("brushed").separable_g);
    CHECK(m("rough-default").alpha == 0.1f);
    CHECK(m("rough-default").distribution == MicrofacetModel::GGX);
    CHECK(!m("rough-default").separable_g);
    CHECK(m("rough-default").albedo == glm::vec3(1.0f));
    CHECK(m("rough-tex").alpha == 1.0f);
    CHECK(m("rough-tex").roughness_map.used());

    // Dielectrics: "reflectance" tints both lobes (the glass kind's old meaning), "specular"
    // and "transmittance" one each
    CHECK(m("tinted-glass").kind == MaterialKind::Glass);
    CHECK(m("tinted-glass").albedo == glm::vec3(0.9f, 0.8f, 0.7f));
    CHECK(m("tinted-glass").specular == glm::vec3(0.9f, 0.8f, 0.7f));
    CHECK(m("tinted-glass").ior == 1.5f);
    CHECK(m("split-glass").ior == 1.33f);
    CHECK(m("split-glass").specular == glm::vec3(0.5f));
    CHECK(m("split-glass").albedo == glm::vec3(1.0f, 0.9f, 0.8f));
    CHECK(m("frosted").kind == MaterialKind::RoughDielectric);
    CHECK(m("frosted").ior == 2.0f);
    CHECK(m("frosted").alpha == 2.0f);
    CHECK(m("frosted").albedo == glm::vec3(0.75f));
    CHECK(m("frosted").specular == glm::vec3(1.0f));
    CHECK(m("pane").kind == MaterialKind::ThinDielectric);
    CHECK(m("pane").ior == 100.0f);
    CHECK(m("pane").specular == glm::vec3(0.1f, 0.2f, 0.3f));
    CHECK(m("pane").albedo == glm::vec3(1.0f));
    CHECK(m("low-ior").ior == 0.01f);

    // Plastics: diffuse "reflectance" (0.8 as diffuse), the coat's tint, η, nonlinear
    CHECK(m("plastic").kind == MaterialKind::Plastic);
    CHECK(m("plastic").albedo == glm::vec3(0.1f, 0.2f, 0.3f));
    CHECK(m("plastic").specular == glm::vec3(0.9f));
    CHECK(m("plastic").ior == 1.49f);
    CHECK(m("plastic").nonlinear);
    CHECK(m("plastic-default").albedo == glm::vec3(0.8f));
    CHECK(m("plastic-default").specular == glm::vec3(1.0f));
    CHECK(m("plastic-default").ior == 1.5f);
    CHECK(!m("plastic-default").nonlinear);
    CHECK(m("rough-plastic").kind == MaterialKind::RoughPlastic);
    CHECK(m("rough-plastic").alpha == 1e-4f);
    CHECK(m("rough-plastic").distribution == MicrofacetModel::Beckmann);
    CHECK(!m("rough-plastic").nonlinear);

    // Fields a kind does not read keep the host defaults
    CHECK(m("chrome").ior == def.ior);
    CHECK(m("chrome").specular == def.specular);
    CHECK(m("plastic").eta == def.eta);
    CHECK(m("split-glass").alpha == def.alpha);
    CHECK(!m("split-glass").alpha_v);
}

TEST_CASE("json scene: cameras: horizontal fov, matrix, framing", "[scene][json][parser]") {
    const std::string shapes = R"(, "materials": {"lamp": {"type": "diffuse", "emission": 1}},
        "shapes": [{"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1], "material": "lamp"}]})";
    // hfov 90 on 200 x 100: vfov = 2 atan(tan(45 deg) * 100 / 200) = 2 atan(0.5)
    Scene h = parse(R"({"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 90,
                                   "fov_axis": "x", "width": 200, "height": 100})" + shapes);
    CHECK(h.camera.vfov_deg == Approx(53.13010235).epsilon(1e-6));
    CHECK(h.camera.width == 200);

    // Row-major camera-to-world: position = last column, view = column 2, up = column 1
    Scene m = parse(R"({"camera": {"matrix": [-1, 0, 0, 1,  0, 1, 0, 2,  0, 0, -1, 3,  0, 0, 0, 1],
                                   "fov": 25})" + shapes);
    CHECK(m.camera.position == glm::vec3(1, 2, 3));
    CHECK(m.camera.target == glm::vec3(1, 2, 2));
    CHECK(m.camera.up == glm::vec3(0, 1, 0));
    CHECK(m.camera.vfov_deg == 25.0f);
    CHECK(m.camera.width == 800);
    CHECK(m.camera.height == 600);

    // No camera: looks at the centre from +z with the bounding sphere (radius sqrt 3) inside
    // the vertical fov (the narrower one on 800 x 600)
    Scene f = parse(R"({"camera": {"fov": 40})" + shapes);
    CHECK(f.camera.target == glm::vec3(0.0f));
    CHECK(f.camera.position.x == 0.0f);
    CHECK(f.camera.position.y == 0.0f);
    CHECK(f.camera.position.z * std::sin(glm::radians(20.0)) >= std::sqrt(3.0) * 0.9999);
    CHECK(f.camera.position.z * std::sin(glm::radians(20.0)) <= std::sqrt(3.0) * 1.01);
    Scene g = parse(R"({"background": 0)" + shapes);
    CHECK(g.camera.position == f.camera.position);
}

TEST_CASE("json scene: mesh files relative to the scene, own materials or a named one",
          "[scene][json][parser]") {
    TempDir d;
    d.write("meshes/tri.obj", "mtllib tri.mtl\nusemtl shiny\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    d.write("meshes/tri.mtl", "newmtl shiny\nKd 0.2 0.3 0.4\nKe 2 2 2\n");
    const fs::path scene = d.write("scenes/s.json", R"({
      "materials": {"white": {"type": "diffuse", "reflectance": 0.5}},
      "shapes": [
        {"type": "mesh", "file": "../meshes/tri.obj", "transform": {"translate": [0, 0, 1]}},
        {"type": "mesh", "file": "../meshes/tri.obj", "material": "white",
         "transform": {"scale": 2}}
      ]
    })");
    Scene s = wp::load_json_scene(scene);
    REQUIRE(s.triangle_count() == 2);
    auto tri = [&](int i) {
        std::vector<glm::vec3> v;
        for (int k = 0; k < 3; ++k) v.push_back(s.positions[s.triangles[i][k]]);
        return v;
    };
    CHECK(tri(0) == std::vector<glm::vec3>{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}});
    CHECK(tri(1) == std::vector<glm::vec3>{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}});
    const auto& own = s.materials[s.material_ids[0]];
    CHECK(own.name == "shiny");
    CHECK(own.albedo == glm::vec3(0.2f, 0.3f, 0.4f));
    CHECK(own.emission == glm::vec3(2.0f));
    CHECK(s.materials[s.material_ids[1]].name == "white");
    // The dispatcher routes .json here
    Scene t = wp::load_scene_file(scene);
    CHECK(t.triangle_count() == 2);
}

TEST_CASE("json scene: a PLY mesh file (Assimp)", "[scene][json][parser]") {
    TempDir d;
    d.write("quad.ply",
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
    const fs::path scene = d.write("s.json", R"({
      "materials": {"lamp": {"type": "diffuse", "emission": 1}},
      "shapes": [{"type": "mesh", "file": "quad.ply", "material": "lamp",
                  "transform": {"translate": [0, 0, 2]}}]})");
    Scene s = wp::load_json_scene(scene);
    CHECK(s.triangle_count() == 2);  // the unit square, triangulated
    CHECK(total_area(s) == Approx(1.0));
    CHECK(corners(s) == points({{0, 0, 2}, {1, 0, 2}, {1, 1, 2}, {0, 1, 2}}));
    for (const auto& t : s.triangles) CHECK(glm::normalize(normal_of(s, t)).z == Approx(1.0));
}

TEST_CASE("json scene: a glTF mesh file", "[scene][json][parser]") {
    TempDir d;
    // One triangle (0,0,0), (1,0,0), (0,1,0): 36 bytes of little-endian floats, base64
    d.write("tri.gltf", R"({"asset": {"version": "2.0"},
      "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
      "bufferViews": [{"buffer": 0, "byteLength": 36}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                     "min": [0, 0, 0], "max": [1, 1, 0]}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
      "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0})");
    const fs::path scene = d.write("s.json", R"({
      "materials": {"lamp": {"type": "diffuse", "emission": 1}},
      "shapes": [{"type": "mesh", "file": "tri.gltf", "material": "lamp",
                  "transform": [{"scale": 2}, {"translate": [0, 0, 2]}]}]})");
    Scene s = wp::load_json_scene(scene);
    REQUIRE(s.triangle_count() == 1);
    CHECK(corners(s) == points({{0, 0, 2}, {2, 0, 2}, {0, 2, 2}}));
    CHECK(s.materials[s.material_ids[0]].name == "lamp");
}

TEST_CASE("json scene: scenes/cornell-box.json is the built-in Cornell box",
          "[scene][json][parser]") {
    Scene j = wp::load_json_scene(repo_scene("cornell-box.json"));
    Scene b = wp::make_cornell_box();
    CHECK(j.name == "cornell-box.json");
    CHECK(j.warnings.empty());
    REQUIRE(j.triangle_count() == b.triangle_count());
    REQUIRE(j.positions.size() == b.positions.size());
    REQUIRE(j.materials.size() == b.materials.size());
    for (std::size_t i = 0; i < b.materials.size(); ++i) {
        const wp::Material &x = j.materials[i], &y = b.materials[i];
        INFO("material " << i << " " << y.name);
        CHECK(x.name == y.name);
        CHECK(x.kind == y.kind);
        CHECK(x.albedo == y.albedo);
        CHECK(x.emission == y.emission);
        CHECK(x.alpha == y.alpha);
        CHECK(x.ior == y.ior);
    }
    CHECK(j.triangles == b.triangles);
    CHECK(j.material_ids == b.material_ids);
    float worst = 0.0f;
    for (std::size_t i = 0; i < b.positions.size(); ++i)
        worst = std::max(worst, glm::length(j.positions[i] - b.positions[i]));
    CHECK(worst <= 1e-6f);
    CHECK(j.camera.position == b.camera.position);
    CHECK(j.camera.target == b.camera.target);
    CHECK(j.camera.up == b.camera.up);
    CHECK(j.camera.vfov_deg == b.camera.vfov_deg);
    CHECK(j.camera.width == b.camera.width);
    CHECK(j.camera.height == b.camera.height);
    CHECK(j.background == b.background);
}

TEST_CASE("json scene: scenes/showcase.json and scenes/stress.json", "[scene][json][parser]") {
    Scene s = wp::load_json_scene(repo_scene("showcase.json"));
    CHECK(s.warnings.empty());
    std::set<float> glossy_alphas;
    int mirrors = 0, glasses = 0, emitters = 0;
    for (const auto& m : s.materials) {
        if (m.kind == wp::MaterialKind::Glossy) glossy_alphas.insert(m.alpha);
        mirrors += m.kind == wp::MaterialKind::Mirror;
        glasses += m.kind == wp::MaterialKind::Glass;
        emitters += m.emissive();
        // The glass kind reflected with its albedo before it had a specular tint; a shipped
        // glass keeps its image when the two agree
        if (m.kind == wp::MaterialKind::Glass) CHECK(m.specular == m.albedo);
    }
    CHECK(glossy_alphas.size() >= 3);
    CHECK(mirrors >= 1);
    CHECK(glasses >= 1);
    CHECK(emitters >= 1);

    Scene t = wp::load_json_scene(repo_scene("stress.json"));
    CHECK(t.warnings.empty());
    CHECK(t.triangle_count() >= 245000);
    CHECK(t.triangle_count() <= 255000);
}

TEST_CASE("json scene: bad input gives one message with file, place and problem",
          "[scene][json][parser]") {
    const std::string lamp = R"("materials": {"white": {"type": "diffuse", "emission": 1}})";
    const std::string quad = R"({"type": "quad", "size": 1, "material": "white"})";
    auto scene = [&](const std::string& extra) {
        return "{" + lamp + ", \"shapes\": [" + quad + "]" + extra + "}";
    };
    struct Case {
        std::string text;
        std::vector<std::string> parts;  // every one must be in the message
    };
    const std::vector<Case> cases = {
        // Malformed JSON: line and column of the second comma
        {"{\n  \"camera\": {\n    \"fov\": 40,,\n  }\n}", {"dir/t.json:3:15:", "malformed JSON"}},
        {"", {"dir/t.json:1:1:", "malformed JSON"}},
        {"{\"shapes\": [\n  {\"type\": \"quad\", \"size\": NaN}]}",
         {"dir/t.json:2:28:", "malformed JSON", "NaN or Infinity"}},
        {"{\"shapes\": [\n  {\"type\": \"quad\", \"size\": 1e999}]}",
         {"dir/t.json:2:28:", "overflow", "finite"}},
        {"{\"a\": 1} x", {"dir/t.json:1:", "malformed JSON"}},
        // Unknown keys, with the JSON path, line:column of the key and a hint
        {"{\n  \"materials\": {\n    \"white\": {\"type\": \"diffuse\", \"materail\": 1}\n  },\n"
         "  \"shapes\": []\n}",
         {"dir/t.json:3:34:", "/materials/white/materail", "unknown key 'materail'",
          "known keys: type, reflectance, emission"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "size": 1, "materail": "white"}]})",
         {"/shapes/0/materail", "unknown key", "did you mean 'material'?"}},
        // (a byte order mark and CRLF line ends do not shift the position)
        {"\xEF\xBB\xBF{\r\n  \"shapez\": []\r\n}\r\n",
         {"dir/t.json:2:3:", "/shapez", "did you mean 'shapes'?"}},
        {"{\"materials\": {\"a\\u0062c\": {\"type\": \"diffuse\"}}, \"shapes\": [{\"type\": "
         "\"quad\", \"size\": 1, \"material\": \"abc\", \"x\\ty\": 1}]}",
         {"dir/t.json:1:108:", "/shapes/0/x\\x09y", "unknown key"}},
        {scene(R"(, "camrea": {})"), {"/camrea", "unknown key 'camrea'", "did you mean 'camera'?"}},
        {scene(R"(, "camera": {"target": [0, 0, 0]})"), {"/camera/target", "did you mean 'look_at'?"}},
        {"{\"materials\": {\"w\": {\"type\": \"diffuse\", \"albedo\": 0.5}}, \"shapes\": []}",
         {"/materials/w/albedo", "did you mean 'reflectance'?"}},
        {scene(R"(, "camera": {"fov": 40, "fov": 50})"), {"/camera/fov", "appears twice"}},
        {"{\"materials\": {\"w\": {\"type\": \"diffuse\", \"ior\": 1.5}}, \"shapes\": []}",
         {"/materials/w/ior", "does not apply to a diffuse material", "glass"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "radius": 1, "material": "white"}]})",
         {"/shapes/0/radius", "does not apply to a quad", "sphere"}},
        // Wrong types
        {scene(R"(, "camera": {"fov": "40"})"),
         {"/camera/fov", "expected a number, got the string \"40\""}},
        {scene(R"(, "camera": {"width": 64.5})"), {"/camera/width", "expected an integer"}},
        {scene(R"(, "camera": {"position": [0, 0], "look_at": [0, 0, 0]})"),
         {"/camera/position", "array of 3 numbers"}},
        {scene(R"(, "background": "black")"), {"/background", "expected a number or an array"}},
        {scene(R"(, "render": [64])"), {"/render", "expected render settings"}},
        {"[1, 2]", {"dir/t.json:1:1: /:", "expected a scene"}},
        {"{" + lamp + R"(, "shapes": {"type": "quad"}})", {"/shapes", "expected an array"}},
        // Out of range
        {scene(R"(, "camera": {"fov": -10})"), {"/camera/fov", "out of range", "(0, 180)"}},
        {scene(R"(, "camera": {"fov": 180})"), {"/camera/fov", "(0, 180)"}},
        {scene(R"(, "camera": {"width": 0})"), {"/camera/width", "out of range", "[1, 16384]"}},
        {scene(R"(, "render": {"depth": 1048577})"), {"/render/depth", "out of range", "1048576"}},
        {scene(R"(, "render": {"spp": 0})"), {"/render/spp", "out of range"}},
        {scene(R"(, "render": {"seed": -1})"), {"/render/seed", "out of range"}},
        {scene(R"(, "camera": {"position": [0, 0, 1], "look_at": [0, 0, 1]})"),
         {"/camera/look_at", "equals position"}},
        {scene(R"(, "camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "up": [0, 0, 2]})"),
         {"/camera/up", "parallel"}},
        {scene(R"(, "camera": {"position": [0, 0, 1]})"), {"/camera", "go together"}},
        {"{\"materials\": {\"w\": {\"type\": \"diffuse\", \"reflectance\": [0.5, 2, 0.5]}}, "
         "\"shapes\": []}",
         {"/materials/w/reflectance/1", "out of range", "[0, 1]"}},
        {"{\"materials\": {\"w\": {\"type\": \"glossy\", \"roughness\": 0}}, \"shapes\": []}",
         {"/materials/w/roughness", "out of range"}},
        {"{\"materials\": {\"w\": {\"type\": \"diffuse\", \"emission\": -1}}, \"shapes\": []}",
         {"/materials/w/emission", ">= 0"}},
        {"{\"materials\": {\"w\": {\"type\": \"principled\"}}, \"shapes\": []}",
         {"/materials/w/type", "unknown material type 'principled'", "roughplastic"}},
        {"{\"materials\": {\"w\": {\"type\": \"roughconductr\"}}, \"shapes\": []}",
         {"/materials/w/type", "did you mean 'roughconductor'?"}},
        {scene(R"(, "version": 2)"), {"/version", "unsupported version 2"}},
        // Shapes
        {"{" + lamp + R"(, "shapes": [{"type": "sphear", "material": "white"}]})",
         {"/shapes/0/type", "did you mean 'sphere'?"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "size": 1, "material": "whit"}]})",
         {"/shapes/0/material", "no material named 'whit'", "did you mean 'white'?"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "size": 1}]})",
         {"/shapes/0", "needs a \"material\""}},
        {"{" + lamp + R"(, "shapes": [{"type": "mesh", "file": "nowhere.obj"}]})",
         {"/shapes/0/file", "nowhere.obj", "not found"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "corner": [0, 0, 0], "edge_u": [1, 0, 0],
             "edge_v": [2, 0, 0], "material": "white"}]})",
         {"/shapes/0/edge_v", "parallel"}},
        {"{" + lamp + R"(, "shapes": [{"type": "box", "min": [0, 0, 0], "max": [1, 0, 1],
             "material": "white"}]})",
         {"/shapes/0/max", "must exceed min"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "size": 1, "subdivisions": 5000,
             "material": "white"}]})",
         {"/shapes/0/subdivisions", "out of range"}},
        {"{" + lamp + R"(, "shapes": [{"type": "sphere", "rings": 4096, "segments": 8192,
             "material": "white"}]})",
         {"/shapes/0", "limit of 16777216 triangles"}},
        {"{" + lamp + R"(, "shapes": [{"type": "stress", "triangles": 99999999,
             "material": "white"}]})",
         {"/shapes/0/triangles", "out of range"}},
        // Transforms
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "size": 1, "material": "white",
             "transform": {"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 1, 1]}}]})",
         {"/shapes/0/transform/matrix", "last row"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "size": 1, "material": "white",
             "transform": [{"scale": [1, 0, 1]}]}]})",
         {"/shapes/0/transform/0/scale", "scale of 0"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "size": 1, "material": "white",
             "transform": [{"translate": [1, 0, 0], "scale": 2}]}]})",
         {"/shapes/0/transform/0", "exactly one key"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "size": 1, "material": "white",
             "transform": {"rotate": {"axis": [0, 0, 0], "degrees": 10}}}]})",
         {"/shapes/0/transform/rotate/axis", "must not be zero"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "size": 1, "material": "white",
             "transform": {"rotate": {"axis": [0, 1, 0], "angle": 10}}}]})",
         {"/shapes/0/transform/rotate/angle", "did you mean 'degrees'?"}},
        {"{" + lamp + R"(, "shapes": [{"type": "sphere", "radius": 3e38, "center": [3e38, 0, 0],
             "material": "white"}]})",
         {"/shapes/0", "not finite", "overflows"}},
        {"{" + lamp + R"(, "shapes": [{"type": "quad", "size": 1, "material": "white",
             "transform": [{"scale": 1e30}, {"scale": 1e30}]}]})",
         {"/shapes/0/transform", "not finite"}},
        // No triangles
        {"{" + lamp + R"(, "shapes": []})", {"/shapes", "no triangles"}},
        {"{" + lamp + "}", {"dir/t.json:1:1: /:", "no triangles"}},
    };
    for (const Case& c : cases) {
        std::string msg = error_of(c.text);
        INFO("scene: " << c.text << "\nmessage: " << msg);
        CHECK(has(msg, "dir/t.json"));
        CHECK(msg.find('\n') == std::string::npos);  // one line
        for (const auto& part : c.parts) CHECK(has(msg, part));
    }
}

TEST_CASE("json scene: bad values of the material kinds give their message",
          "[scene][json][parser]") {
    // One material "w" of the given body; its line is 2, so every message names "t.json:2:"
    auto mat = [](const std::string& body) {
        return "{\"materials\": {\n\"w\": " + body + "}, \"shapes\": []}";
    };
    struct Case {
        std::string body;
        std::vector<std::string> parts;  // every one must be in the message
    };
    const std::vector<Case> cases = {
        // Keys of other kinds, with the kinds that take them
        {R"({"type": "diffuse", "eta": 1, "k": 1})",
         {"/materials/w/eta", "does not apply to a diffuse material", "conductor, roughconductor"}},
        {R"({"type": "glass", "eta": 1.5})",
         {"/materials/w/eta", "does not apply to a glass", "did you mean 'ior'?"}},
        {R"({"type": "conductor", "roughness": 0.1})",
         {"/materials/w/roughness", "does not apply to a conductor material", "roughconductor"}},
        {R"({"type": "conductor", "specular": 0.5})",
         {"/materials/w/specular", "does not apply to a conductor", "did you mean 'reflectance'?"}},
        {R"({"type": "glossy", "distribution": "beckmann"})",
         {"/materials/w/distribution", "does not apply to a glossy material", "roughplastic"}},
        {R"({"type": "glossy", "roughness_u": 0.1, "roughness_v": 0.2})",
         {"/materials/w/roughness_u", "does not apply to a glossy material"}},
        {R"({"type": "roughdielectric", "exponent": 10})",
         {"/materials/w/exponent", "does not apply to a roughdielectric material", "glossy"}},
        {R"({"type": "plastic", "transmittance": 0.5})",
         {"/materials/w/transmittance", "does not apply to a plastic", "glass"}},
        {R"({"type": "glass", "nonlinear": true})",
         {"/materials/w/nonlinear", "does not apply to a glass", "plastic, roughplastic"}},
        {R"({"type": "plastic", "roughness": 0.2})",
         {"/materials/w/roughness", "does not apply to a plastic material", "roughplastic"}},
        {R"({"type": "roughconductor", "alpha_u": 0.1})",
         {"/materials/w/alpha_u", "unknown key", "did you mean 'roughness_u'?"}},
        {R"({"type": "conductor", "material": "Cu"})",
         {"/materials/w/material", "unknown key", "did you mean 'metal'?"}},
        // Conductors: metals, η and k
        {R"({"type": "conductor", "metal": "Cuu"})",
         {"/materials/w/metal", "unknown metal 'Cuu'", "did you mean 'Cu'?", "none, Ag, Al"}},
        {R"({"type": "conductor", "metal": 29})", {"/materials/w/metal", "expected a string"}},
        {R"({"type": "conductor", "metal": "Cu", "eta": 1, "k": 1})",
         {"/materials/w/eta", "either \"metal\" or \"eta\" and \"k\""}},
        {R"({"type": "conductor", "eta": 1})", {"/materials/w/eta", "go together"}},
        {R"({"type": "roughconductor", "k": 1})", {"/materials/w/k", "go together"}},
        {R"({"type": "conductor", "eta": [0.2, -0.1, 1], "k": 1})",
         {"/materials/w/eta/1", "out of range", ">= 0"}},
        {R"({"type": "conductor", "eta": 1, "k": -3})", {"/materials/w/k", "out of range", ">= 0"}},
        {R"({"type": "conductor", "eta": 1, "k": [1, 2]})",
         {"/materials/w/k", "expected a number or an array of 3 numbers"}},
        {R"({"type": "conductor", "reflectance": 1.5})",
         {"/materials/w/reflectance", "out of range", "[0, 1]"}},
        // Roughness of the rough kinds
        {R"({"type": "roughconductor", "roughness": 2.5})",
         {"/materials/w/roughness", "out of range", "[0.0001, 2]"}},
        {R"({"type": "roughdielectric", "roughness": 0.00005})",
         {"/materials/w/roughness", "out of range", "[0.0001, 2]"}},
        {R"({"type": "glossy", "roughness": 1.5})",
         {"/materials/w/roughness", "out of range", "[0.0001, 1]"}},
        {R"({"type": "roughplastic", "roughness_u": 0.1})",
         {"/materials/w/roughness_u", "go together"}},
        {R"({"type": "roughplastic", "roughness_v": 0.1})",
         {"/materials/w/roughness_v", "go together"}},
        {R"({"type": "roughconductor", "roughness": 0.1, "roughness_u": 0.1, "roughness_v": 0.2})",
         {"/materials/w/roughness_u", "either \"roughness\" (isotropic)"}},
        {R"({"type": "roughconductor", "roughness_u": 0.1, "roughness_v": 3})",
         {"/materials/w/roughness_v", "out of range", "[0.0001, 2]"}},
        {R"({"type": "roughconductor", "roughness_u": 0.1, "roughness_v": 0.2, "roughness_texture": {"checkerboard": [0, 1]}})",
         {"/materials/w/roughness_texture", "isotropic"}},
        {R"({"type": "roughconductor", "distribution": "phong"})",
         {"/materials/w/distribution", "unknown distribution 'phong'", "ggx, beckmann"}},
        {R"({"type": "roughconductor", "distribution": 1})",
         {"/materials/w/distribution", "expected a string"}},
        {R"({"type": "roughdielectric", "g": "smith"})",
         {"/materials/w/g", "unknown masking-shadowing 'smith'", "height-correlated, separable"}},
        // Dielectrics and plastics
        {R"({"type": "glass", "ior": 0})", {"/materials/w/ior", "out of range", "[0.01, 100]"}},
        {R"({"type": "thindielectric", "ior": 101})", {"/materials/w/ior", "out of range", "[0.01, 100]"}},
        {R"({"type": "roughplastic", "ior": -1.5})", {"/materials/w/ior", "out of range"}},
        {R"({"type": "glass", "reflectance": 0.9, "specular": 1})",
         {"/materials/w/specular", "either \"reflectance\"", "not both"}},
        {R"({"type": "roughdielectric", "transmittance": 0.9, "reflectance": 1})",
         {"/materials/w/transmittance", "either \"reflectance\""}},
        {R"({"type": "glass", "specular": [1, 1.2, 1]})",
         {"/materials/w/specular/1", "out of range", "[0, 1]"}},
        {R"({"type": "thindielectric", "transmittance": -0.5})",
         {"/materials/w/transmittance", "out of range", "[0, 1]"}},
        {R"({"type": "plastic", "specular": 2})", {"/materials/w/specular", "out of range"}},
        {R"({"type": "plastic", "nonlinear": 1})",
         {"/materials/w/nonlinear", "expected true or false, got the number 1"}},
        {R"({"type": "roughplastic", "nonlinear": "yes"})",
         {"/materials/w/nonlinear", "expected true or false"}},
    };
    for (const Case& c : cases) {
        const std::string msg = error_of(mat(c.body));
        INFO("material: " << c.body << "\nmessage: " << msg);
        CHECK(has(msg, "dir/t.json:2:"));
        CHECK(msg.find('\n') == std::string::npos);  // one line
        for (const auto& part : c.parts) CHECK(has(msg, part));
    }
}

TEST_CASE("json scene: errors inside mesh files name both files", "[scene][json][parser]") {
    TempDir d;
    d.write("bad.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    const fs::path scene = d.write("s.json", R"({
  "materials": {"lamp": {"type": "diffuse", "emission": 1}},
  "shapes": [{"type": "mesh", "file": "bad.obj", "material": "lamp"}]
})");
    try {
        wp::load_json_scene(scene);
        FAIL("no error");
    } catch (const wp::Error& e) {
        std::string msg = e.what();
        INFO(msg);
        CHECK(has(msg, "s.json:3:39: /shapes/0/file:"));
        CHECK(has(msg, "bad.obj:2"));
        CHECK(has(msg, "non-finite"));
    }
    // A folder instead of a file, and a missing scene file
    fs::create_directories(d.path / "dir.obj");
    d.write("s2.json", R"({"materials": {"lamp": {"type": "diffuse", "emission": 1}},
        "shapes": [{"type": "mesh", "file": "dir.obj"}]})");
    CHECK_THROWS_WITH(wp::load_json_scene(d.path / "s2.json"),
                      Catch::Contains("/shapes/0/file") && Catch::Contains("not a regular file"));
    CHECK_THROWS_WITH(wp::load_json_scene(d.path / "missing.json"),
                      Catch::Contains("missing.json") && Catch::Contains("no such file"));
}

TEST_CASE("json scene: a scene without light loads; has_light says so", "[scene][json][parser]") {
    // The warning itself is the command line's, one for every format (test_cli_edges.cpp).
    Scene s = parse(R"({"materials": {"grey": {"type": "diffuse"}},
                        "shapes": [{"type": "quad", "size": 1, "material": "grey"}]})");
    CHECK(s.warnings.empty());
    CHECK_FALSE(wp::has_light(s));
    // An emitter or a background is light enough
    Scene b = parse(R"({"background": [0, 0, 0.5], "materials": {"grey": {"type": "diffuse"}},
                        "shapes": [{"type": "quad", "size": 1, "material": "grey"}]})");
    CHECK(b.warnings.empty());
    CHECK(wp::has_light(b));
    // An emissive material that no triangle uses is no light
    Scene u = parse(R"({"materials": {"grey": {"type": "diffuse"}, "lamp": {"type": "diffuse", "emission": 3}},
                        "shapes": [{"type": "quad", "size": 1, "material": "grey"}]})");
    CHECK(u.warnings.size() == 1);  // the unused material
    CHECK_FALSE(wp::has_light(u));
}

TEST_CASE("json scene: arbitrary bytes give a Scene or a wp::Error, nothing else",
          "[scene][json][parser]") {
    // Every prefix of a real scene and random mutations of it (no file references, so
    // nothing is read): the contract the fuzzer checks, at test size.
    const std::string base = read_file(repo_scene("showcase.json"));
    REQUIRE(base.size() > 100);
    int scenes = 0, errors = 0;
    auto attempt = [&](const std::string& text) {
        try {
            Scene s = wp::parse_json_scene(text, "fuzz.json");
            CHECK(s.triangle_count() > 0);
            ++scenes;
        } catch (const wp::Error&) {
            ++errors;
        }
    };
    for (std::size_t n = 0; n < base.size(); n += 7) attempt(base.substr(0, n));
    wp::SplitMix64 rng(12345);
    const char alphabet[] = "{}[]\",:0123456789.-+eE tfn\\u\x01\xff";
    for (int i = 0; i < 1500; ++i) {
        std::string t = base;
        const int edits = 1 + int(rng.next() % 4);
        for (int e = 0; e < edits; ++e) {
            std::size_t at = std::size_t(rng.next() % t.size());
            char c = alphabet[rng.next() % (sizeof alphabet - 1)];
            switch (rng.next() % 3) {
            case 0: t[at] = c; break;
            case 1: t.insert(t.begin() + long(at), c); break;
            default: t.erase(at, 1 + rng.next() % 8); break;
            }
        }
        attempt(t);
    }
    CHECK(scenes > 0);
    CHECK(errors > 0);
}

TEST_CASE("json scene: cornell-box.json renders the built-in box's image", "[scene][json][render]") {
    Scene j = wp::load_json_scene(repo_scene("cornell-box.json"));
    Scene b = wp::make_cornell_box();
    auto render = [](const Scene& scene) {
        wp::render::RenderSettings s;
        s.width = 40;
        s.height = 30;
        s.depth = 3;
        s.seed = 17;
        wp::render::Wavefront wf(wp::test::device(), scene, s);
        wp::render::LoopOptions lo;
        lo.spp = 4;
        wp::render::render_frames(wf, lo, nullptr);
        return wf.film();
    };
    auto fj = render(j);
    auto fb = render(b);
    REQUIRE(fj.size() == fb.size());
    REQUIRE(fj.size() == 40u * 30u);
    // Same triangles, materials and camera, same seed: bit-identical films
    CHECK(std::memcmp(fj.data(), fb.data(), fj.size() * sizeof(fj[0])) == 0);
    double sum = 0.0;
    for (const auto& p : fb) sum += double(p.sum.x) + p.sum.y + p.sum.z;
    CHECK(sum > 0.0);  // not a black image compared with a black image
}

// --- Appearance: textures, environment, smooth normals, uvs (issue 13) -----------------------

namespace {

Scene parse_in(const TempDir& d, const std::string& text) {
    return wp::parse_json_scene(text, d.path / "t.json");
}

// A w x h linear float EXR of one colour.
void write_exr(const fs::path& p, int w, int h, glm::vec3 c) {
    wp::Image img(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* px = img.pixel(x, y);
            px[0] = c.x, px[1] = c.y, px[2] = c.z;
        }
    wp::write_image(p, img);
}

glm::dvec2 apply_uv(const glm::mat3& m, glm::vec2 uv) { return glm::dvec2(m * glm::vec3(uv, 1.0f)); }

void check_near(glm::dvec3 got, glm::dvec3 want, double tol = 1e-5) {
    INFO("got (" << got.x << ", " << got.y << ", " << got.z << "), want (" << want.x << ", "
                 << want.y << ", " << want.z << ")");
    CHECK(glm::length(got - want) <= tol);
}

const wp::Material& material_by_name(const Scene& s, const std::string& name) {
    for (const auto& m : s.materials)
        if (m.name == name) return m;
    FAIL("no material " << name);
    return s.materials.front();
}

double wrap_diff(double a, double b) {  // |a - b| modulo 1
    const double d = std::abs((a - std::floor(a)) - (b - std::floor(b)));
    return std::min(d, 1.0 - d);
}

}  // namespace

TEST_CASE("json scene: texture references on materials: files, transforms, checkerboards",
          "[scene][json][parser][texture]") {
    TempDir d;
    fs::create_directories(d.path / "tex");
    write_exr(d.path / "tex" / "wood.exr", 4, 2, glm::vec3(0.5f));
    Scene s = parse_in(d, R"({
  "materials": {
    "wood": {"type": "diffuse", "albedo_texture": "tex/wood.exr"},
    "tiles": {"type": "glossy", "reflectance": 0.5,
              "albedo_texture": {"file": "tex/wood.exr", "scale": [2, 4], "offset": [0.5, 0.25],
                                 "rotation": 90, "filter": "nearest"},
              "roughness_texture": {"checkerboard": [0.2, 1]},
              "normal_map": "tex/wood.exr", "normal_scale": 0.5},
    "sign": {"type": "diffuse", "reflectance": 0, "emission_texture": {"checkerboard": [[4, 0, 0], 2], "scale": 8}},
    "leaf": {"type": "diffuse", "alpha_texture": {"checkerboard": [0, 1]}, "alpha_cutoff": 0.3},
    "spare": {"type": "diffuse", "albedo_texture": "tex/other.exr"}
  },
  "shapes": [
    {"type": "quad", "size": 1, "material": "wood"},
    {"type": "quad", "size": 1, "material": "tiles"},
    {"type": "quad", "size": 1, "material": "sign"},
    {"type": "quad", "size": 1, "material": "leaf"}
  ]})");
    INFO(s.warnings.size());
    // wood: a file relative to the scene; the reflectance defaults to 1 with a texture
    const wp::Material& wood = material_by_name(s, "wood");
    CHECK(wood.albedo == glm::vec3(1.0f));
    REQUIRE(wood.albedo_map.used());
    const wp::Texture& img = s.textures.at(std::size_t(wood.albedo_map.image));
    CHECK(img.source == (d.path / "tex" / "wood.exr").string());
    CHECK(img.width == 4);
    CHECK(wood.albedo_map.uv_transform == glm::mat3(1.0f));
    // tiles: uv' = T(offset) R(rotation) S(scale) uv; rotation 90: (u, v) -> (v, -u), so
    // (0.1, 0.2) -> scale (0.2, 0.8) -> rotate (0.8, -0.2) -> offset (1.3, 0.05)
    const wp::Material& tiles = material_by_name(s, "tiles");
    CHECK(tiles.albedo == glm::vec3(0.5f));  // given: multiplies the texture
    REQUIRE(tiles.albedo_map.used());
    // the same file, but "filter": "nearest" is this use's: its own image, the wood's stays
    // bilinear
    const wp::Texture& tiles_img = s.textures.at(std::size_t(tiles.albedo_map.image));
    CHECK(tiles_img.source == img.source);
    CHECK(tiles_img.nearest);
    CHECK(!img.nearest);
    const glm::dvec2 t = apply_uv(tiles.albedo_map.uv_transform, {0.1f, 0.2f});
    CHECK(t.x == Approx(1.3).margin(1e-6));
    CHECK(t.y == Approx(0.05).margin(1e-6));
    // the roughness texture: alpha = 1 x G² when no roughness is given
    CHECK(tiles.alpha == 1.0f);
    REQUIRE(tiles.roughness_map.used());
    const wp::Texture& rough = s.textures.at(std::size_t(tiles.roughness_map.image));
    CHECK(rough.width == 2);
    CHECK(rough.nearest);
    REQUIRE(tiles.normal_map.used());
    CHECK(tiles.normal_scale == 0.5f);
    // sign: emission 1 times the checkerboard (radiance may exceed 1), scale 8
    const wp::Material& sign = material_by_name(s, "sign");
    CHECK(sign.emission == glm::vec3(1.0f));
    REQUIRE(sign.emission_map.used());
    const glm::dvec2 e = apply_uv(sign.emission_map.uv_transform, {0.25f, 0.5f});
    CHECK(e.x == Approx(2.0));
    CHECK(e.y == Approx(4.0));
    // leaf: coverage is the checkerboard's first component, in A
    const wp::Material& leaf = material_by_name(s, "leaf");
    CHECK(leaf.alpha_cutoff == 0.3f);
    REQUIRE(leaf.alpha_map.used());
    const wp::Texture& a = s.textures.at(std::size_t(leaf.alpha_map.image));
    REQUIRE(a.is_float());
    CHECK(a.texelsf[3] == 0.0f);       // texel (0, 0): color0
    CHECK(a.texelsf[4 + 3] == 1.0f);   // texel (1, 0): color1
    // The unused material's texture is never read; textured quads carry uvs (s, 1 - t)
    CHECK(s.textures.size() == 5);  // wood.exr twice (two filters) + three checkerboards
    for (const auto& w : s.warnings) CHECK_FALSE(has(w, "other.exr"));
    REQUIRE(s.uvs.size() == s.positions.size());
    for (std::size_t i = 0; i < 4; ++i)  // size 1: corner (-0.5, -0.5), edges +x, +y
        check_near(glm::dvec3(s.uvs[i], 0), {s.positions[i].x + 0.5, 0.5 - s.positions[i].y, 0});
}

TEST_CASE("json scene: a missing texture file warns and loads", "[scene][json][parser][texture]") {
    TempDir d;
    Scene s = parse_in(d, with_shapes(R"({"type": "quad", "size": 1, "material": "m"},
        {"type": "quad", "size": 1, "material": "lamp"})",
                                      R"(, "m": {"type": "diffuse", "albedo_texture": "gone.png"})"));
    bool warned = false;
    for (const auto& w : s.warnings) warned = warned || has(w, "gone.png");
    CHECK(warned);
    CHECK(material_by_name(s, "m").albedo_map.used());
}

TEST_CASE("json scene: bad texture references name the place and the problem",
          "[scene][json][parser][texture]") {
    auto mat = [](const std::string& m) {
        return "{\"materials\": {\"m\": " + m +
               "},\n \"shapes\": [{\"type\": \"quad\", \"size\": 1, \"material\": \"m\"}]}";
    };
    CHECK(has(error_of(mat(R"({"type": "diffuse", "albedo_texture": 3})")),
              "dir/t.json:1:59: /materials/m/albedo_texture: expected a texture: a file name, "
              "{\"file\": ...} or {\"checkerboard\": [c0, c1]}, got the number 3"));
    CHECK(has(error_of(mat(R"({"type": "diffuse", "albedo_texture": {"file": "a.png", "scael": 2}})")),
              "/materials/m/albedo_texture/scael: unknown key 'scael' in a texture (did you mean "
              "'scale'?)"));
    CHECK(has(error_of(mat(R"({"type": "diffuse", "albedo_texture": {"file": "a.png", "checkerboard": [0, 1]}})")),
              "/materials/m/albedo_texture/checkerboard: give either \"file\" or \"checkerboard\""));
    CHECK(has(error_of(mat(R"({"type": "diffuse", "albedo_texture": {"scale": 2}})")),
              "/materials/m/albedo_texture: a texture needs \"file\""));
    CHECK(has(error_of(mat(R"({"type": "diffuse", "albedo_texture": {"file": "a.png", "filter": "cubic"}})")),
              "/materials/m/albedo_texture/filter: expected \"bilinear\" or \"nearest\""));
    CHECK(has(error_of(mat(R"({"type": "diffuse", "albedo_texture": {"checkerboard": [0, 2]}})")),
              "/materials/m/albedo_texture/checkerboard/1: 2 is out of range: expected a number in [0, 1]"));
    CHECK(has(error_of(mat(R"({"type": "diffuse", "albedo_texture": {"file": "a.png", "scale": [1, 0]}})")),
              "/materials/m/albedo_texture/scale: a texture scale must not be 0"));
    CHECK(has(error_of(mat(R"({"type": "diffuse", "roughness_texture": "r.png"})")),
              "/materials/m/roughness_texture: 'roughness_texture' does not apply to a diffuse material"));
    CHECK(has(error_of(mat(R"({"type": "diffuse", "normal_scale": 2})")),
              "/materials/m/normal_scale: \"normal_scale\" needs a \"normal_map\""));
    CHECK(has(error_of(mat(R"({"type": "diffuse", "alpha_texture": "a.png", "alpha_cutoff": 2})")),
              "/materials/m/alpha_cutoff: 2 is out of range: expected a number in [0, 1]"));
    CHECK(has(error_of(mat(R"({"type": "diffuse", "albedo_texture": ""})")),
              "/materials/m/albedo_texture: expected a file name"));
}

TEST_CASE("json scene: the environment: file, scale, rotation", "[scene][json][parser][texture]") {
    TempDir d;
    write_exr(d.path / "sky.exr", 8, 4, glm::vec3(1.0f));
    const std::string shapes = R"(, "materials": {"m": {"type": "diffuse"}},
        "shapes": [{"type": "quad", "size": 1, "material": "m"}]})";
    Scene s = parse_in(d, R"({"environment": {"file": "sky.exr", "scale": 2, "rotate_y": 90})" + shapes);
    REQUIRE(s.environment);
    CHECK(s.environment->scale == 2.0f);
    CHECK(s.textures.at(std::size_t(s.environment->image)).source == (d.path / "sky.exr").string());
    // 90 degrees about +y: x -> -z, z -> x
    check_near(glm::dvec3(s.environment->to_world[0]), {0, 0, -1});
    check_near(glm::dvec3(s.environment->to_world[1]), {0, 1, 0});
    check_near(glm::dvec3(s.environment->to_world[2]), {1, 0, 0});
    CHECK(wp::has_light(s));  // the environment lights the scene
    // rotation [rx, ry, rz]: x first, then y, then z. [0, 90, 90]: x -> (0, 0, -1) -> (0, 0, -1);
    // y -> y -> (-1, 0, 0); z -> (1, 0, 0) -> (0, 1, 0)
    Scene r = parse_in(d, R"({"environment": {"file": "sky.exr", "rotation": [0, 90, 90]})" + shapes);
    check_near(glm::dvec3(r.environment->to_world[0]), {0, 0, -1});
    check_near(glm::dvec3(r.environment->to_world[1]), {-1, 0, 0});
    check_near(glm::dvec3(r.environment->to_world[2]), {0, 1, 0});
    CHECK(r.environment->scale == 1.0f);
    // Errors
    auto bad = [&](const std::string& env) {
        return error_of(R"({"environment": )" + env + shapes);
    };
    CHECK(has(bad(R"({"scale": 1})"), "dir/t.json:1:17: /environment: an environment needs a \"file\""));
    CHECK(has(bad(R"({"file": "a.exr", "rotation": [0, 1, 0], "rotate_y": 3})"),
              "/environment/rotate_y: give either \"rotation\" or \"rotate_y\", not both"));
    CHECK(has(bad(R"({"file": "a.exr", "scale": -1})"),
              "/environment/scale: -1 is out of range: expected a number >= 0"));
    CHECK(has(bad(R"({"file": "a.exr", "rotate": 3})"),
              "/environment/rotate: unknown key 'rotate' in the environment"));
    CHECK(has(bad(R"("sky.exr")"), "/environment: expected an environment"));
    CHECK(has(error_of(R"({"envmap": {"file": "sky.exr"})" + shapes),
              "/envmap: unknown key 'envmap' in the scene (did you mean 'environment'?)"));
}

TEST_CASE("json scene: \"smooth\" computes normals for a mesh without them",
          "[scene][json][parser]") {
    TempDir d;
    // An open square pyramid (see the Mitsuba test): smooth normals (1, 1, 2)/sqrt 6 at the base
    // corners, (0, 0, 1) at the apex
    d.write("pyramid.obj", "v 0 0 1\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv -1 -1 0\n"
                           "f 2 3 1\nf 3 4 1\nf 4 5 1\nf 5 2 1\n");
    const std::string mats = R"("materials": {"m": {"type": "diffuse", "emission": 1}})";
    Scene s = parse_in(d, "{" + mats + R"(, "shapes": [
        {"type": "mesh", "file": "pyramid.obj", "material": "m", "smooth": 180},
        {"type": "mesh", "file": "pyramid.obj", "material": "m", "transform": {"translate": [5, 0, 0]}}]})");
    REQUIRE(s.triangle_count() == 8);
    REQUIRE(s.normals.size() == s.positions.size());
    for (std::size_t t = 0; t < 4; ++t)
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 p(s.positions[s.triangles[t][k]]);
            const glm::dvec3 n(s.normals[s.triangles[t][k]]);
            check_near(n, p.z == 1.0 ? glm::dvec3(0, 0, 1) : glm::normalize(glm::dvec3(p.x, p.y, 2)));
        }
    for (std::size_t t = 4; t < 8; ++t)  // no "smooth": flat
        for (int k = 0; k < 3; ++k) CHECK(s.normals[s.triangles[t][k]] == glm::vec3(0.0f));
    CHECK(has(error_of("{" + mats + R"(, "shapes": [{"type": "mesh", "file": "p.obj", "smooth": 200}]})"),
              "/shapes/0/smooth: 200 is out of range: expected a number in [0, 180] degrees"));
    CHECK(has(error_of("{" + mats + R"(, "shapes": [{"type": "quad", "size": 1, "material": "m", "smooth": 30}]})"),
              "/shapes/0/smooth: 'smooth' does not apply to a quad shape (it is a key of mesh shapes)"));
}

TEST_CASE("json scene: spheres shade smooth; textured shapes get uvs", "[scene][json][parser][texture]") {
    const glm::dvec3 c(1, 2, 3);
    Scene s = parse(R"({"materials": {"m": {"type": "diffuse", "emission": 1},
        "t": {"type": "diffuse", "albedo_texture": {"checkerboard": [0, 1]}}},
      "shapes": [{"type": "sphere", "center": [1, 2, 3], "radius": 2, "rings": 8, "segments": 16, "material": "m"},
                 {"type": "sphere", "center": [1, 2, 3], "radius": 2, "rings": 8, "segments": 16, "material": "t",
                  "transform": {"translate": [10, 0, 0]}},
                 {"type": "box", "size": 2, "material": "t"}]})");
    // Untextured sphere: one vertex per lattice point, normals (p - c) / r
    const std::size_t first_sphere = 2 + 16 * 7;
    REQUIRE(s.normals.size() == s.positions.size());
    for (std::size_t i = 0; i < first_sphere; ++i)
        check_near(glm::dvec3(s.normals[i]), (glm::dvec3(s.positions[i]) - c) / 2.0);
    // Textured sphere: uv = (phi / 2 pi, theta / pi), phi around +y from +z, theta from +y
    const glm::dvec3 c2 = c + glm::dvec3(10, 0, 0);
    std::size_t checked = 0;
    for (std::size_t t = 2 * 16 * 7; t < 2 * 2 * 16 * 7; ++t)
        for (int k = 0; k < 3; ++k) {
            const std::size_t i = s.triangles[t][k];
            const glm::dvec3 q = (glm::dvec3(s.positions[i]) - c2) / 2.0;
            check_near(glm::dvec3(s.normals[i]), q, 1e-5);
            CHECK(s.uvs[i].y == Approx(std::acos(q.y) / M_PI).margin(1e-5));
            if (std::abs(q.y) < 0.999999)
                CHECK(wrap_diff(s.uvs[i].x, std::atan2(q.x, q.z) / (2 * M_PI)) < 1e-5);
            ++checked;
        }
    CHECK(checked == 3 * 2 * 16 * 7);
    // Box: each face has its own vertices and the whole texture: (n + 1)² = 4 per face
    const std::size_t box_first = s.triangle_count() - 12;
    std::set<std::uint32_t> box_vertices;
    for (std::size_t t = box_first; t < s.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) box_vertices.insert(s.triangles[t][k]);
    CHECK(box_vertices.size() == 24);
    for (std::uint32_t i : box_vertices) {
        CHECK((s.uvs[i].x == 0.0f || s.uvs[i].x == 1.0f));
        CHECK((s.uvs[i].y == 0.0f || s.uvs[i].y == 1.0f));
    }
}
