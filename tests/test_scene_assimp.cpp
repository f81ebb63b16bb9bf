// test_scene_assimp.cpp — PLY and STL through the Assimp loader (OFF refused), against hand-written
// files with known vertices and faces; bad input (truncated, NaN, out-of-range indices) must
// fail with the file name and the place; every prefix of a file loads or fails cleanly.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <functional>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "scene/assimp_loader.h"
#include "scene/load.h"
#include "util/error.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using namespace wp;

namespace {

using wp::test::TempDir;

// A square pyramid: apex (0, 2, 0) over the base square [-1, 1] x {0} x [-1, 1]; 4 side
// triangles and a quad base (2 triangles): 6 triangles, total area 4 + 4 * sqrt(5).
const float kPyramid[5][3] = {{-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, {0, 2, 0}};
const int kSides[4][3] = {{0, 4, 1}, {1, 4, 2}, {2, 4, 3}, {3, 4, 0}};
const int kBase[4] = {0, 1, 2, 3};
const double kPyramidArea = 4.0 + 4.0 * std::sqrt(5.0);

std::string pyramid_header(const char* format) {
    return std::string("ply\nformat ") + format +
           " 1.0\ncomment hand-written square pyramid\nelement vertex 5\nproperty float x\nproperty "
           "float y\nproperty float z\nelement face 5\nproperty list uchar int vertex_indices\n"
           "end_header\n";
}

std::string pyramid_ascii() {
    std::string s = pyramid_header("ascii");
    for (auto& v : kPyramid) s += fmt::format("{} {} {}\n", v[0], v[1], v[2]);
    for (auto& f : kSides) s += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]);
    s += "4 0 1 2 3\n";
    return s;
}

template <typename T>
void put(std::string& s, T v, bool big_endian) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    s.append(reinterpret_cast<const char*>(b), sizeof(T));
}

std::string pyramid_binary(bool big_endian, float poison = 0.0f, int poison_vertex = -1) {
    std::string s = pyramid_header(big_endian ? "binary_big_endian" : "binary_little_endian");
    for (int i = 0; i < 5; ++i)
        for (int k = 0; k < 3; ++k)
            put<float>(s, i == poison_vertex && k == 1 ? poison : kPyramid[i][k], big_endian);
    for (auto& f : kSides) {
        put<std::uint8_t>(s, 3, big_endian);
        for (int k = 0; k < 3; ++k) put<std::int32_t>(s, f[k], big_endian);
    }
    put<std::uint8_t>(s, 4, big_endian);
    for (int k : kBase) put<std::int32_t>(s, k, big_endian);
    return s;
}

double area(const Scene& s) {
    double a = 0.0;
    for (auto& t : s.triangles)
        a += 0.5 * glm::length(glm::cross(s.positions[t.y] - s.positions[t.x],
                                          s.positions[t.z] - s.positions[t.x]));
    return a;
}

// The loaded pyramid is exactly the hand data: vertices in file order, the 4 side triangles
// as written, the base split into two triangles of the quad's vertices; grey default material.
void check_pyramid(const Scene& s) {
    REQUIRE(s.positions.size() == 5);
    for (int i = 0; i < 5; ++i)
        CHECK(s.positions[i] == glm::vec3(kPyramid[i][0], kPyramid[i][1], kPyramid[i][2]));
    REQUIRE(s.triangles.size() == 6);
    for (int f = 0; f < 4; ++f)
        CHECK(s.triangles[f] == glm::uvec3(kSides[f][0], kSides[f][1], kSides[f][2]));
    for (int f = 4; f < 6; ++f)
        for (int k = 0; k < 3; ++k) CHECK(s.triangles[f][k] < 4u);
    CHECK(area(s) == Approx(kPyramidArea).epsilon(1e-6));
    // Outward winding everywhere: the signed volume is +1/3 * base 4 * height 2
    double vol = 0.0;
    for (auto& t : s.triangles)
        vol += glm::dot(s.positions[t.x], glm::cross(s.positions[t.y], s.positions[t.z])) / 6.0;
    CHECK(std::abs(vol) == Approx(8.0 / 3.0));
    REQUIRE(s.materials.size() == 1);
    CHECK(s.materials[0].name == "default");
    CHECK(s.materials[0].kind == MaterialKind::Diffuse);
    CHECK(s.materials[0].albedo == glm::vec3(0.5f));
    CHECK(s.warnings.empty());
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const wp::Error& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST_CASE("assimp: ASCII and binary PLY give the hand-written pyramid", "[scene][assimp][parser]") {
    TempDir d;
    Scene a = load_assimp(d.write("pyr-ascii.ply", pyramid_ascii()));
    Scene le = load_assimp(d.write("pyr-le.ply", pyramid_binary(false)));
    Scene be = load_assimp(d.write("pyr-be.PLY", pyramid_binary(true)));
    check_pyramid(a);
    check_pyramid(le);
    check_pyramid(be);
    CHECK(a.triangles == le.triangles);
    CHECK(a.triangles == be.triangles);
    CHECK(a.name == "pyr-ascii.ply");
    // Through the dispatcher and from memory: the same scene
    Scene viaload = load_mesh_file(d.path / "pyr-le.ply");
    CHECK(viaload.positions == le.positions);
    CHECK(viaload.triangles == le.triangles);
    Scene mem = parse_assimp(pyramid_binary(false), ".ply", "memory.ply");
    CHECK(mem.triangles == le.triangles);
    CHECK(mem.name == "memory.ply");
}

TEST_CASE("assimp: degenerate triangles are kept, lines skipped with a warning",
          "[scene][assimp][parser]") {
    std::string s =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty "
        "double z\nproperty uchar red\nelement face 4\nproperty list uchar uint vertex_index\n"
        "end_header\n0 0 0 255\n1 0 0 0\n0 1 0 0\n2 2 2 0\n3 0 1 2\n3 3 3 3\n3 0 0 1\n2 0 1\n";
    Scene sc = parse_assimp(s, "ply", "degen.ply");
    REQUIRE(sc.triangles.size() == 3);
    CHECK(sc.triangles[1] == glm::uvec3(3, 3, 3));
    CHECK(sc.triangles[2] == glm::uvec3(0, 0, 1));
    REQUIRE(sc.warnings.size() == 1);
    CHECK_THAT(sc.warnings[0], Contains("degen.ply") && Contains("1 faces with fewer than 3"));
}

TEST_CASE("assimp: truncated PLY files fail with the file and the place", "[scene][assimp][parser]") {
    TempDir d;
    const std::string ascii = pyramid_ascii();
    const std::string bin = pyramid_binary(false);
    const std::size_t hdr = pyramid_header("ascii").size();
    const std::size_t bhdr = pyramid_header("binary_little_endian").size();

    // ASCII: cut inside the last face, inside the vertices, inside the header
    auto e1 = error_of([&] { load_assimp(d.write("cut-face.ply", ascii.substr(0, ascii.size() - 4))); });
    CHECK_THAT(e1, Contains("cut-face.ply:") && Contains("truncated") && Contains("5 faces") &&
                       Contains("after 4"));
    auto e2 = error_of([&] { load_assimp(d.write("cut-vert.ply", ascii.substr(0, hdr + 10))); });
    CHECK_THAT(e2, Contains("cut-vert.ply:") && Contains("truncated") && Contains("5 vertices"));
    auto e3 = error_of([&] { load_assimp(d.write("cut-head.ply", ascii.substr(0, 60))); });
    CHECK_THAT(e3, Contains("cut-head.ply") && Contains("truncated PLY header"));

    // Binary: cut in the last face's indices, in the vertices
    auto e4 = error_of([&] { load_assimp(d.write("bcut-face.ply", bin.substr(0, bin.size() - 3))); });
    CHECK_THAT(e4, Contains("bcut-face.ply") && Contains("truncated") && Contains("5 faces") &&
                       Contains("after 4"));
    auto e5 = error_of([&] { load_assimp(d.write("bcut-vert.ply", bin.substr(0, bhdr + 20))); });
    CHECK_THAT(e5, Contains("bcut-vert.ply") && Contains("truncated") && Contains("5 vertices") &&
                       Contains("after 1"));

    // A line with a missing value shifts the rest: more values than declared at the end
    std::string shifted = ascii;
    shifted.replace(shifted.find("0 2 0\n"), 6, "0 2\n");
    auto e6 = error_of([&] { parse_assimp(shifted, "ply", "shift.ply"); });
    CHECK_THAT(e6, Contains("shift.ply:") && Contains("more values than the header declares"));
}

TEST_CASE("assimp: NaN and Inf coordinates and bad indices fail with the vertex named",
          "[scene][assimp][parser]") {
    std::string ascii = pyramid_ascii();
    std::string nan_text = ascii;
    nan_text.replace(nan_text.find("0 2 0\n"), 6, "0 nan 0\n");
    // Vertex 4 is on line 15 (10 header lines), its y at column 3
    CHECK_THAT(error_of([&] { parse_assimp(nan_text, "ply", "nan.ply"); }),
               Contains("nan.ply:15:3:") && Contains("vertex 4") && Contains("non-finite"));
    std::string inf_text = ascii;
    inf_text.replace(inf_text.find("1 0 1\n"), 6, "1 0 -inf\n");
    CHECK_THAT(error_of([&] { parse_assimp(inf_text, "ply", "inf.ply"); }),
               Contains("inf.ply:13:5:") && Contains("vertex 2") && Contains("non-finite"));
    for (bool be : {false, true}) {
        CHECK_THAT(error_of([&] { parse_assimp(pyramid_binary(be, NAN, 3), "ply", "bnan.ply"); }),
                   Contains("bnan.ply") && Contains("vertex 3") && Contains("non-finite") &&
                       Contains("y = nan"));
        CHECK_THAT(error_of([&] { parse_assimp(pyramid_binary(be, INFINITY, 0), "ply", "binf.ply"); }),
                   Contains("binf.ply") && Contains("vertex 0") && Contains("y = inf"));
    }
    std::string oor = ascii;
    oor.replace(oor.find("3 2 4 3\n"), 8, "3 2 4 7\n");
    CHECK_THAT(error_of([&] { parse_assimp(oor, "ply", "oor.ply"); }),
               Contains("oor.ply") && Contains("face 2 uses vertex 7") && Contains("5 vertices"));
}

TEST_CASE("assimp: malformed PLY headers fail with the line", "[scene][assimp][parser]") {
    auto head = [](const std::string& body) { return "ply\nformat ascii 1.0\n" + body; };
    CHECK_THAT(error_of([&] { parse_assimp(head("element vertex 1\nproperty flot x\nend_header\n1\n"), "ply", "h.ply"); }),
               Contains("h.ply:4:") && Contains("unknown PLY type 'flot'"));
    CHECK_THAT(error_of([&] { parse_assimp(head("element vertex 99999999999\nproperty float x\nend_header\n"), "ply", "h.ply"); }),
               Contains("h.ply:3:") && Contains("exceeds the limit"));
    CHECK_THAT(error_of([&] { parse_assimp("ply\nformat binary_middle_endian 1.0\nend_header\n", "ply", "h.ply"); }),
               Contains("h.ply:2:") && Contains("unknown PLY format"));
    CHECK_THAT(error_of([&] { parse_assimp("solid x\n", "ply", "h.ply"); }),
               Contains("h.ply:1:") && Contains("not a PLY file"));
    // A binary file whose list length claims far more data than there is
    std::string huge = "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list uint int "
                       "vertex_indices\nend_header\n";
    put<std::uint32_t>(huge, 0xfffffff0u, false);
    CHECK_THAT(error_of([&] { parse_assimp(huge, "ply", "huge.ply"); }),
               Contains("huge.ply") && Contains("truncated"));
    CHECK_THAT(error_of([&] { parse_assimp("", "ply", "empty.ply"); }),
               Contains("empty.ply") && Contains("empty"));
}

TEST_CASE("assimp: every prefix of a PLY file loads or fails with wp::Error",
          "[scene][assimp][parser]") {
    for (const std::string& full : {pyramid_ascii(), pyramid_binary(false), pyramid_binary(true)}) {
        int loaded = 0;
        for (std::size_t n = 0; n < full.size(); ++n) {
            try {
                parse_assimp(std::string_view(full).substr(0, n), "ply", "prefix.ply");
                ++loaded;
            } catch (const wp::Error& e) {
                CHECK_THAT(std::string(e.what()), Contains("prefix.ply"));
            }
        }
        // Only the ASCII file minus its final newline is complete
        CHECK(loaded <= 1);
    }
}

TEST_CASE("assimp: STL files load with the default material; OFF is refused", "[scene][assimp][parser]") {
    const std::string stl =
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 2 0 0\nvertex 0 3 0\n"
        "endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 1\nvertex 1 0 1\nvertex 0 1 1\n"
        "endloop\nendfacet\nendsolid t\n";
    Scene s = parse_assimp(stl, ".stl", "two.stl");
    REQUIRE(s.triangles.size() == 2);
    CHECK(area(s) == Approx(3.0 + 0.5));
    CHECK(s.materials.size() == 1);
    CHECK(s.materials[0].albedo == glm::vec3(0.5f));
    CHECK(s.warnings.empty());
    CHECK(s.bounds().lo == glm::vec3(0, 0, 0));
    CHECK(s.bounds().hi == glm::vec3(2, 3, 1));

    // OFF: Assimp 5.2's importer reads out of bounds on a face with more corners than the
    // file has vertices (fuzz_assimp), so wavepath refuses .off with a message saying why.
    const std::string off = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    std::string e = error_of([&] { parse_assimp(off, "off", "quad.off"); });
    CHECK_THAT(e, Contains("quad.off"));
    CHECK_THAT(e, Contains(".off is refused"));
}

TEST_CASE("assimp: a truncated binary STL fails with the file name", "[scene][assimp][parser]") {
    std::string stl(80, ' ');
    put<std::uint32_t>(stl, 3, false);  // three triangles declared, one present
    for (int i = 0; i < 12; ++i) put<float>(stl, float(i % 3), false);
    put<std::uint16_t>(stl, 0, false);
    CHECK_THAT(error_of([&] { parse_assimp(stl, "stl", "short.stl"); }), Contains("short.stl"));
}

TEST_CASE("assimp: a binary PLY whose data starts with a whitespace byte is read exactly",
          "[scene][assimp][parser]") {
    // Assimp 5.2 skips whitespace after end_header and reads such files shifted; the loader
    // then uses its own checked decoding. -1.0000012f is 0xBF80000A: first byte 0x0a ('\n').
    std::uint32_t bits = 0xBF80000Au;
    float x0;
    std::memcpy(&x0, &bits, 4);
    std::string s = pyramid_header("binary_little_endian");
    for (int i = 0; i < 5; ++i)
        for (int k = 0; k < 3; ++k) put<float>(s, i == 0 && k == 0 ? x0 : kPyramid[i][k], false);
    for (auto& f : kSides) {
        put<std::uint8_t>(s, 3, false);
        for (int k = 0; k < 3; ++k) put<std::int32_t>(s, f[k], false);
    }
    put<std::uint8_t>(s, 4, false);
    for (int k : kBase) put<std::int32_t>(s, k, false);
    REQUIRE(s[pyramid_header("binary_little_endian").size()] == '\n');
    Scene sc = parse_assimp(s, "ply", "ws.ply");
    REQUIRE(sc.positions.size() == 5);
    CHECK(sc.positions[0] == glm::vec3(x0, 0.0f, -1.0f));
    for (int i = 1; i < 5; ++i)
        CHECK(sc.positions[i] == glm::vec3(kPyramid[i][0], kPyramid[i][1], kPyramid[i][2]));
    REQUIRE(sc.triangles.size() == 6);
    for (int f = 0; f < 4; ++f)
        CHECK(sc.triangles[f] == glm::uvec3(kSides[f][0], kSides[f][1], kSides[f][2]));
    CHECK(sc.triangles[4] == glm::uvec3(0, 1, 2));
    CHECK(sc.triangles[5] == glm::uvec3(0, 2, 3));
    CHECK(sc.warnings.empty());
}

// Found by fuzz_assimp: Assimp 5.2 reads an element name that starts with a digit as a count
// (a name of twenty 9s made it allocate 100 GB). Such names are refused with file and line.
TEST_CASE("assimp: a PLY element name that starts with a digit is refused", "[scene][assimp][parser]") {
    std::string ply = "ply\nformat ascii 1.0\nelement 99999999999999999999vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 0\n"
                      "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    CHECK_THAT(error_of([&] { parse_assimp(ply, "ply", "digits.ply"); }),
               Contains("digits.ply:3: PLY element name '99999999999999999999vertex' must start with a letter"));
}
