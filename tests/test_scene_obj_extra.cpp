// test_scene_obj_extra.cpp — parse_obj (OBJ text in memory): polygon triangulation against
// shoelace areas, winding, materials missing from the MTL, where `mtllib` is looked up and
// what it refuses to read. Every expected value is worked out by hand or by an independent
// formula (the polygon's own area), never taken from the loader's output.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <numbers>
#include <string>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>

#include "scene/obj_loader.h"
#include "util/error.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

struct ObjTempDir {
    fs::path path;
    ObjTempDir() {
        path = fs::temp_directory_path() / fmt::format("wp-objx-{}-{}", ::getpid(),
                                                       std::chrono::steady_clock::now()
                                                           .time_since_epoch()
                                                           .count());
        fs::create_directories(path);
    }
    ~ObjTempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    fs::path write(const fs::path& name, const std::string& text) const {
        fs::path p = path / name;
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
};

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const wp::Error& e) {
        return e.what();
    }
    return "(no error)";
}

// A planar polygon in the z = 0 plane as OBJ text: vertices in order, one face over them
// (starting at corner `start`, reversed when asked).
std::string polygon_obj(const std::vector<glm::dvec2>& p, std::size_t start = 0,
                        bool reversed = false) {
    std::string s;
    for (const auto& v : p)
        s += fmt::format("v {} {} 0\n", v.x, v.y);
    s += "f";
    const std::size_t n = p.size();
    for (std::size_t k = 0; k < n; ++k) {
        std::size_t i = (start + (reversed ? n - k : k)) % n;
        s += fmt::format(" {}", i + 1);
    }
    return s + "\n";
}

// Shoelace formula: the polygon's signed area (positive when counter-clockwise).
double shoelace(const std::vector<glm::dvec2>& p) {
    double a = 0.0;
    for (std::size_t k = 0; k < p.size(); ++k) {
        const glm::dvec2 u = p[k], v = p[(k + 1) % p.size()];
        a += u.x * v.y - v.x * u.y;
    }
    return 0.5 * a;
}

// Signed areas of the triangles' projections on z (positive = counter-clockwise from +z).
std::vector<double> z_areas(const wp::Scene& s) {
    std::vector<double> out;
    for (const auto& t : s.triangles) {
        glm::dvec3 a(s.positions[t.x]), b(s.positions[t.y]), c(s.positions[t.z]);
        out.push_back(0.5 * glm::cross(b - a, c - a).z);
    }
    return out;
}

// A star with `tips` tips (radius 1) and inner corners (radius 0.4): concave, 2 * tips corners.
std::vector<glm::dvec2> star(int tips) {
    std::vector<glm::dvec2> p;
    for (int k = 0; k < 2 * tips; ++k) {
        const double a = std::numbers::pi * k / tips;
        const double r = k % 2 == 0 ? 1.0 : 0.4;
        p.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    return p;
}

bool has_warning(const wp::Scene& s, const std::string& part) {
    for (const auto& w : s.warnings)
        if (w.find(part) != std::string::npos) return true;
    return false;
}

} // namespace

TEST_CASE("parse_obj: text in memory, origin names the file in errors", "[scene][obj][parser]") {
    wp::Scene s = wp::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "some/dir/mem.obj");
    CHECK(s.name == "mem.obj");
    REQUIRE(s.triangle_count() == 1);
    CHECK(s.triangles[0] == glm::uvec3(0, 1, 2));
    CHECK(s.positions[1] == glm::vec3(1, 0, 0));

    CHECK_THAT(error_of([] { wp::parse_obj("v 0 0 0\nv 1 0 0\n\nf 1 2 x\n", "some/dir/mem.obj"); }),
               Contains("some/dir/mem.obj:4:") && Contains("'x'"));
    CHECK_THAT(error_of([] { wp::parse_obj("", "e.obj"); }),
               Contains("e.obj") && Contains("no triangles"));
    // Bytes that are not text at all: an error, not a crash
    const std::string junk("\0\xff\x01v\0f", 6);
    CHECK_THAT(error_of([&] { wp::parse_obj(junk, "junk.obj"); }), Contains("junk.obj"));
}

TEST_CASE("parse_obj: a concave quad keeps its area and winding", "[scene][obj][parser]") {
    // Dart with the reflex corner at (0, 1): the shorter diagonal (1-3) lies outside it.
    // Shoelace area: (10 + 1 + 1 + 10) / 2 = 11.
    const std::vector<glm::dvec2> dart{{0, -10}, {1, 3}, {0, 1}, {-1, 3}};
    REQUIRE(shoelace(dart) == Approx(11.0));
    for (std::size_t start = 0; start < 4; ++start) {
        for (bool reversed : {false, true}) {
            CAPTURE(start, reversed);
            wp::Scene s = wp::parse_obj(polygon_obj(dart, start, reversed), "dart.obj");
            REQUIRE(s.triangle_count() == 2);
            double total = 0.0;
            for (double a : z_areas(s)) {
                CHECK((reversed ? -a : a) > 0.0); // every triangle faces like the polygon
                total += std::abs(a);
            }
            CHECK(total == Approx(11.0)); // and together they cover it exactly once
        }
    }
}

TEST_CASE("parse_obj: concave n-gons are ear-clipped from any starting corner",
          "[scene][obj][parser]") {
    // A U: the 3x3 square minus the 1x2 notch at the top: area 7
    const std::vector<glm::dvec2> u{{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
    REQUIRE(shoelace(u) == Approx(7.0));
    const auto st = star(12); // 24 corners, below the ear-clipping limit
    const double star_area = shoelace(st);
    REQUIRE(star_area > 0.0);
    for (const auto* poly : {&u, &st}) {
        const double expected = shoelace(*poly);
        for (std::size_t start = 0; start < poly->size(); start += 3) {
            for (bool reversed : {false, true}) {
                CAPTURE(poly->size(), start, reversed);
                wp::Scene s = wp::parse_obj(polygon_obj(*poly, start, reversed), "poly.obj");
                REQUIRE(s.triangle_count() == poly->size() - 2);
                double total = 0.0;
                bool all_facing = true;
                for (double a : z_areas(s)) {
                    all_facing = all_facing && (reversed ? -a : a) >= 0.0;
                    total += std::abs(a);
                }
                CHECK(all_facing);
                CHECK(total == Approx(expected).epsilon(1e-6));
                CHECK(s.warnings.size() == 1); // only "no material"
            }
        }
    }
}

TEST_CASE("parse_obj: a concave polygon in a tilted plane", "[scene][obj][parser]") {
    // The U rotated by 90 degrees about x (y -> z) and then moved: it lies in the plane
    // y = 2 and faces -y (its +z normal turned by the rotation). Area still 7.
    const std::vector<glm::dvec2> u{{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
    std::string text;
    for (const auto& p : u)
        text += fmt::format("v {} 2 {}\n", p.x + 5.0, p.y);
    text += "f 4 5 6 7 8 1 2 3\n";
    wp::Scene s = wp::parse_obj(text, "tilted.obj");
    REQUIRE(s.triangle_count() == 6);
    double total = 0.0;
    for (const auto& t : s.triangles) {
        glm::dvec3 a(s.positions[t.x]), b(s.positions[t.y]), c(s.positions[t.z]);
        const glm::dvec3 n = 0.5 * glm::cross(b - a, c - a);
        CHECK(n.y <= 0.0); // (x, z) counter-clockwise seen from -y
        CHECK(n.x == 0.0);
        CHECK(n.z == 0.0);
        total += glm::length(n);
    }
    CHECK(total == Approx(7.0));
}

TEST_CASE("parse_obj: large concave polygons are fanned with a warning",
          "[scene][obj][parser]") {
    // 200 corners: over the ear-clipping limit of 128, so a fan from corner 1 (a tip), which
    // overlaps itself: the warning says so; the triangle count is still n - 2
    const auto st = star(100);
    wp::Scene s = wp::parse_obj(polygon_obj(st), "star.obj");
    CHECK(s.triangle_count() == 198);
    CHECK(has_warning(s, "star.obj: 1 polygon(s)"));
    CHECK(has_warning(s, "128 corners"));
    // A convex polygon of the same size is fanned exactly, without that warning
    std::vector<glm::dvec2> circle;
    for (int k = 0; k < 200; ++k)
        circle.emplace_back(std::cos(std::numbers::pi * k / 100), std::sin(std::numbers::pi * k / 100));
    wp::Scene c = wp::parse_obj(polygon_obj(circle), "circle.obj");
    CHECK(c.triangle_count() == 198);
    CHECK_FALSE(has_warning(c, "polygon(s)"));
    double total = 0.0;
    for (double a : z_areas(c)) {
        CHECK(a > 0.0);
        total += a;
    }
    CHECK(total == Approx(shoelace(circle)).epsilon(1e-5));
}

TEST_CASE("parse_obj: vertex normals and texture coordinates do not change the winding",
          "[scene][obj][parser]") {
    // The normal says -z, the winding says +z: the winding (geometric normal) stays as written,
    // the normal is kept as the shading normal
    wp::Scene s = wp::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -1\nvt 0 0\n"
                                "f 1/1/1 2/1/1 3/1/1\nf 3//1 2//1 1//1\n",
                                "n.obj");
    REQUIRE(s.triangle_count() == 2);
    const glm::vec3 p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    for (int k = 0; k < 3; ++k) {
        CHECK(s.positions[s.triangles[0][k]] == p[k]);
        CHECK(s.positions[s.triangles[1][k]] == p[2 - k]);
    }
    REQUIRE(s.normals.size() == s.positions.size());
    for (const auto& n : s.normals) CHECK(n == glm::vec3(0, 0, -1));
    // A normal index that does not exist is ignored, with a warning: no normals at all here
    wp::Scene t = wp::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//7 2//7 3//7\n", "n.obj");
    CHECK(t.triangle_count() == 1);
    CHECK(t.normals.empty());
    CHECK(t.triangles[0] == glm::uvec3(0, 1, 2));
    bool named = false;  // (tinyobjloader warns as well)
    for (const auto& w : t.warnings)
        named = named || (w.find("n.obj: 3 face corner(s)") != std::string::npos);
    CHECK(named);
}

TEST_CASE("parse_obj: materials missing from the MTL get the visible default, with warnings",
          "[scene][obj][parser]") {
    const std::string obj = "mtllib lib.mtl\n"
                            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                            "usemtl red\nf 1 2 3\n"
                            "usemtl blue\nf 1 2 3 4\n"; // a quad: 2 triangles
    const wp::MtlSource lib = [](const std::string& name) -> std::optional<std::string> {
        if (name == "lib.mtl") return "newmtl red\nKd 0.9 0.1 0.1\n";
        return std::nullopt;
    };
    wp::Scene s = wp::parse_obj(obj, "dir/m.obj", lib);
    REQUIRE(s.triangle_count() == 3);
    REQUIRE(s.materials.size() == 2);
    const wp::Material& red = s.materials[s.material_ids[0]];
    CHECK(red.name == "red");
    CHECK(red.albedo == glm::vec3(0.9f, 0.1f, 0.1f));
    for (int t : {1, 2}) {
        const wp::Material& d = s.materials[s.material_ids[t]];
        CHECK(d.name == "default");
        CHECK(d.kind == wp::MaterialKind::Diffuse);
        CHECK(d.albedo == glm::vec3(0.5f));
    }
    CHECK(has_warning(s, "'blue'"));
    CHECK(has_warning(s, "dir/m.obj: 2 of 3 triangles have no material"));

    // The library itself missing: every triangle uses the default, the library is named
    wp::Scene none = wp::parse_obj(obj, "dir/m.obj", [](const std::string&) {
        return std::optional<std::string>();
    });
    REQUIRE(none.materials.size() == 1);
    CHECK(none.materials[0].name == "default");
    CHECK(has_warning(none, "material library 'lib.mtl' not found"));
    CHECK(has_warning(none, "3 of 3 triangles have no material"));
}

TEST_CASE("parse_obj: MTL glass: Tf is the transmittance, Ni outside [0.01, 100] is 1.5",
          "[scene][obj][parser]") {
    std::string obj = "mtllib lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
    for (const char* m : {"water", "huge", "tiny", "metal"})
        obj += std::string("usemtl ") + m + "\nf 1 2 3\n";
    const wp::MtlSource lib = [](const std::string&) -> std::optional<std::string> {
        return "newmtl water\nillum 7\nNi 1.33\nTf 0.9 0.8 0.7\n"
               "newmtl huge\nillum 7\nNi 1000\n"
               "newmtl tiny\nillum 4\nNi 0.001\n"
               // A metal as ../shared/scenes writes one: Pm/Pr are not read, Ns gives α
               "newmtl metal\nKd 0 0 0\nKs 0.9 0.6 0.5\nNs 198\nPm 1\nPr 0.1\nillum 3\n";
    };
    wp::Scene s = wp::parse_obj(obj, "dir/g.obj", lib);
    REQUIRE(s.materials.size() == 4);
    auto m = [&](int t) { return s.materials[s.material_ids[std::size_t(t)]]; };
    CHECK(m(0).kind == wp::MaterialKind::Glass);
    CHECK(m(0).ior == 1.33f);
    CHECK(m(0).albedo == glm::vec3(0.9f, 0.8f, 0.7f));
    CHECK(m(0).specular == glm::vec3(1.0f));  // reflection untinted
    CHECK(m(1).ior == 1.5f);
    CHECK(m(2).ior == 1.5f);
    CHECK(has_warning(s, "material 'huge': glass without a usable Ni (1000)"));
    CHECK(has_warning(s, "material 'tiny': glass without a usable Ni (0.001)"));
    CHECK(m(3).kind == wp::MaterialKind::Glossy);
    CHECK(m(3).albedo == glm::vec3(0.9f, 0.6f, 0.5f));
    CHECK(m(3).alpha == Approx(0.1f).epsilon(1e-6));  // sqrt(2 / (198 + 2))
}

TEST_CASE("parse_obj: mtllib is read beside the origin and only from regular files",
          "[scene][obj][parser]") {
    ObjTempDir dir;
    dir.write("sub/m.mtl", "newmtl lamp\nKd 0 0 0\nKe 4 5 6\n");
    const std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n";
    for (bool from_file : {false, true}) {
        CAPTURE(from_file);
        wp::Scene s = from_file ? wp::load_obj(dir.write("sub/a.obj", obj))
                                : wp::parse_obj(obj, dir.path / "sub" / "a.obj");
        REQUIRE(s.materials.size() == 1);
        CHECK(s.materials[0].name == "lamp");
        CHECK(s.materials[0].emission == glm::vec3(4, 5, 6));
    }
    // The same text with its origin elsewhere: the library is not found
    wp::Scene elsewhere = wp::parse_obj(obj, dir.path / "a.obj");
    CHECK(elsewhere.materials[0].name == "default");
    CHECK(has_warning(elsewhere, "'m.mtl' not found"));

    // A device, a folder: refused with a warning instead of read (/dev/zero never ends)
    for (const char* lib : {"/dev/zero", "sub", ".."}) {
        CAPTURE(lib);
        wp::Scene s = wp::parse_obj(
            fmt::format("mtllib {}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n", lib),
            dir.path / "a.obj");
        CHECK(s.materials[0].name == "default");
        CHECK(has_warning(s, fmt::format("material library '{}' not found", lib)));
    }
}

// Found by fuzz_obj: tinyobjloader's number parser overflows a signed int (undefined
// behaviour) on a 10-digit exponent. Such numbers are refused with the file and line, in the
// OBJ and in its MTL, before tinyobjloader reads them; ordinary exponents still load.
TEST_CASE("obj: numbers with huge exponents are refused before tinyobjloader sees them", "[scene][obj][parser]") {
    CHECK_THAT(error_of([] { wp::parse_obj("v 0 0 0\nv 1 0 0\nvt 1e2147483648 0\nv 0 1 0\nf 1 2 3\n", "big.obj"); }),
               Contains("big.obj:3: number '1e2147483648' is out of range"));
    wp::MtlSource mtl = [](const std::string& name) -> std::optional<std::string> {
        if (name == "m.mtl") return std::string("newmtl a\nKd 0.5 0.5 1e-2147483648\n");
        return std::nullopt;
    };
    CHECK_THAT(error_of([&] {
                   wp::parse_obj("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n", "m.obj", mtl);
               }),
               Contains("m.mtl:2: number '1e-2147483648' is out of range"));
    wp::Scene s = wp::parse_obj("v 0 0 0\nv 1e0 0 0\nv 0 1.0E+000 0\nf 1 2 3\n", "ok.obj");
    CHECK(s.triangle_count() == 1);
}

TEST_CASE("obj: skin weights (`vw`) are skipped, line numbers still match the file",
          "[scene][obj][parser]") {
    // tinyobjloader casts a vw joint id to int unchecked: "21e39" was undefined behaviour
    // (fuzz/regressions/obj/tinyobj-vw-joint-id-int-overflow). The triangle is unchanged.
    wp::Scene s = wp::parse_obj("v 0 0 0\nvw 1 21e39 0 0.5\nv 1 0 0\nvw 0 0 0.5\nv 0 1 0\nf 1 2 3\n",
                                "skin.obj");
    REQUIRE(s.triangle_count() == 1);
    CHECK(s.positions[s.triangles[0][1]] == glm::vec3(1, 0, 0));
    CHECK(s.positions[s.triangles[0][2]] == glm::vec3(0, 1, 0));
    // An error after a dropped line names the file's own line (5)
    CHECK_THAT(error_of([] { wp::parse_obj("v 0 0 0\nvw 1 2\nv 1 0 0\nv 0 1 0\nf 1 2 q\n", "skin.obj"); }),
               Contains("skin.obj:5:"));
}

// tinyobjloader ends a line at "\n", "\r\n" or a lone "\r". The checks before it split at
// "\n" only, so "o a\r vw 1 21e39" passed as one `o` line while tinyobjloader read the `vw`
// line and cast 21e39 to int (fuzz/regressions/obj/tinyobj-cr-line-end-vw), and a "\r" file
// was one line to the vertex and index checks. The checks now read tinyobjloader's lines.
TEST_CASE("obj: a lone carriage return ends a line, as in tinyobjloader", "[scene][obj][parser]") {
    wp::Scene s = wp::parse_obj("v 0 0 0\rv 1 0 0\rvw 1 21e39 0 0.5\rv 0 1 0\rf 1 2 3\r", "mac.obj");
    REQUIRE(s.triangle_count() == 1);
    CHECK(s.positions[s.triangles[0][1]] == glm::vec3(1, 0, 0));
    CHECK(s.positions[s.triangles[0][2]] == glm::vec3(0, 1, 0));
    // Indices are checked per "\r" line; "\r\n" is one line ending, not two
    CHECK_THAT(error_of([] { wp::parse_obj("v 0 0 0\rv 1 0 0\rf 1 2 3\n", "mac.obj"); }),
               Contains("mac.obj:3: face vertex index 3 is out of range"));
    CHECK_THAT(error_of([] { wp::parse_obj("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 q\r\n", "dos.obj"); }),
               Contains("dos.obj:4:"));
    // The MTL's lines too
    wp::MtlSource mtl = [](const std::string& name) -> std::optional<std::string> {
        if (name == "m.mtl") return std::string("newmtl a\rKd 0.5 0.5 1e-2147483648\r");
        return std::nullopt;
    };
    CHECK_THAT(error_of([&] {
                   wp::parse_obj("mtllib m.mtl\rv 0 0 0\rv 1 0 0\rv 0 1 0\rusemtl a\rf 1 2 3\r", "m.obj", mtl);
               }),
               Contains("m.mtl:2: number '1e-2147483648' is out of range"));
}
