// test_scene_gltf.cpp — the glTF 2.0 loader against hand-built files: node transforms
// composed (positions computed by hand), index types, each material rule, the camera, GLB
// and JSON agreeing, and bad input (truncated .glb, NaN, out-of-bounds accessors) failing
// with the file named — also through the CLI (exit status, message, no image).
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "scene/gltf_loader.h"
#include "scene/load.h"
#include "util/error.h"
#include "support.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using json = nlohmann::json;
using namespace wp;

namespace {

using wp::test::TempDir;
using Run = wp::test::CliRun;

Run run_cli(const TempDir& dir, const std::string& args) { return wp::test::run_render(dir.path, args); }


using wp::test::base64;
using wp::test::put;

// A small glTF builder: one buffer, one buffer view per accessor.
struct Builder {
    std::string bin;
    json j = {{"asset", {{"version", "2.0"}}}, {"accessors", json::array()},
              {"bufferViews", json::array()}, {"meshes", json::array()}, {"nodes", json::array()},
              {"materials", json::array()}, {"scenes", json::array({json{{"nodes", json::array()}}})},
              {"scene", 0}};

    int view(const std::string& bytes) {
        while (bin.size() % 4) bin.push_back('\0');
        j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}});
        bin += bytes;
        return int(j["bufferViews"].size()) - 1;
    }
    int positions(const std::vector<glm::vec3>& p) {
        std::string b;
        for (auto& v : p) put(b, v.x), put(b, v.y), put(b, v.z);
        int bv = view(b);
        j["accessors"].push_back({{"bufferView", bv}, {"componentType", 5126}, {"count", p.size()}, {"type", "VEC3"}});
        return int(j["accessors"].size()) - 1;
    }
    int indices(const std::vector<std::uint32_t>& idx, int component) {
        std::string b;
        for (auto i : idx) {
            if (component == 5121) put(b, std::uint8_t(i));
            if (component == 5123) put(b, std::uint16_t(i));
            if (component == 5125) put(b, std::uint32_t(i));
        }
        int bv = view(b);
        j["accessors"].push_back({{"bufferView", bv}, {"componentType", component}, {"count", idx.size()}, {"type", "SCALAR"}});
        return int(j["accessors"].size()) - 1;
    }
    int mesh(json primitives) {
        j["meshes"].push_back({{"primitives", primitives}});
        return int(j["meshes"].size()) - 1;
    }
    int node(json n, bool root) {
        j["nodes"].push_back(n);
        int id = int(j["nodes"].size()) - 1;
        if (root) j["scenes"][0]["nodes"].push_back(id);
        return id;
    }
    int material(json m) {
        j["materials"].push_back(m);
        return int(j["materials"].size()) - 1;
    }
    // JSON with the buffer as a data URI
    std::string gltf() const {
        json k = j;
        k["buffers"] = json::array({{{"byteLength", bin.size()},
                                     {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
        return k.dump();
    }
    // JSON with an external buffer file
    std::string gltf_external(const std::string& uri) const {
        json k = j;
        k["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", uri}}});
        return k.dump();
    }
    std::string glb() const {
        json k = j;
        k["buffers"] = json::array({{{"byteLength", bin.size()}}});
        std::string js = k.dump();
        while (js.size() % 4) js.push_back(' ');
        std::string b = bin;
        while (b.size() % 4) b.push_back('\0');
        std::string out = "glTF";
        put(out, std::uint32_t(2));
        put(out, std::uint32_t(12 + 8 + js.size() + 8 + b.size()));
        put(out, std::uint32_t(js.size()));
        put(out, std::uint32_t(0x4E4F534A));
        out += js;
        put(out, std::uint32_t(b.size()));
        put(out, std::uint32_t(0x004E4942));
        out += b;
        return out;
    }
};

const std::vector<glm::vec3> kTri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const wp::Error& e) {
        return e.what();
    }
    return "(no error)";
}

bool near(glm::vec3 a, glm::vec3 b, float eps = 1e-5f) { return glm::length(a - b) <= eps; }

// A parent with T = (10, 0, 0), a child with R = 90° about z and S = 2 holding the triangle,
// and a root mirror (matrix diag(-1, 1, 1)) holding it too.
Builder transform_scene() {
    Builder b;
    int pos = b.positions(kTri);
    int idx = b.indices({0, 1, 2}, 5123);
    int m = b.mesh(json::array({{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}));
    const float h = std::sqrt(0.5f);
    int child = b.node({{"mesh", m}, {"rotation", {0, 0, h, h}}, {"scale", {2, 2, 2}}}, false);
    b.node({{"translation", {10, 0, 0}}, {"children", {child}}}, true);
    b.node({{"mesh", m}, {"matrix", {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}}, true);
    return b;
}

}  // namespace

TEST_CASE("gltf: node transforms compose parent x child (TRS and matrix)", "[scene][gltf][parser]") {
    Builder b = transform_scene();
    for (const std::string& bytes : {b.gltf(), b.glb()}) {
        Scene s = parse_gltf(bytes, "t.gltf");
        REQUIRE(s.triangles.size() == 2);
        REQUIRE(s.positions.size() == 6);
        // T(10,0,0) R_z(90) S(2): (x, y) -> (10 - 2y, 2x)
        CHECK(near(s.positions[0], {10, 0, 0}));
        CHECK(near(s.positions[1], {10, 2, 0}));
        CHECK(near(s.positions[2], {8, 0, 0}));
        CHECK(s.triangles[0] == glm::uvec3(0, 1, 2));
        // Mirror in x: positions negated in x, winding reversed
        CHECK(near(s.positions[3], {0, 0, 0}));
        CHECK(near(s.positions[4], {-1, 0, 0}));
        CHECK(near(s.positions[5], {0, 1, 0}));
        CHECK(s.triangles[1] == glm::uvec3(3, 5, 4));
        // No material: the grey default, no warning; no camera: default framing from +z
        REQUIRE(s.materials.size() == 1);
        CHECK(s.materials[0].name == "default");
        CHECK(s.materials[0].albedo == glm::vec3(0.5f));
        CHECK(s.warnings.empty());
        CHECK(s.camera.width == 800);
        CHECK(s.camera.height == 600);
        CHECK(s.camera.position.z > s.camera.target.z);
    }
}

TEST_CASE("gltf: u8, u16, u32 and non-indexed primitives give the same triangles",
          "[scene][gltf][parser]") {
    Builder b;
    // A quad as two triangles, indexed three ways, and unrolled without indices
    std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    int pos = b.positions(quad);
    json prims = json::array();
    for (int c : {5121, 5123, 5125})
        prims.push_back({{"attributes", {{"POSITION", pos}}}, {"indices", b.indices({0, 1, 2, 0, 2, 3}, c)}});
    int flat = b.positions({quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]});
    prims.push_back({{"attributes", {{"POSITION", flat}}}});
    prims.push_back({{"attributes", {{"POSITION", pos}}}, {"mode", 0}});  // points: skipped
    b.node({{"mesh", b.mesh(prims)}}, true);
    Scene s = parse_gltf(b.gltf(), "idx.gltf");
    REQUIRE(s.triangles.size() == 8);
    for (int p = 0; p < 4; ++p)
        for (int t = 0; t < 2; ++t)
            for (int k = 0; k < 3; ++k) {
                const glm::vec3 want = t == 0 ? std::array{quad[0], quad[1], quad[2]}[k]
                                              : std::array{quad[0], quad[2], quad[3]}[k];
                CHECK(s.positions[s.triangles[2 * p + t][k]] == want);
            }
    REQUIRE(s.warnings.size() == 1);
    CHECK_THAT(s.warnings[0], Contains("idx.gltf") && Contains("not TRIANGLES"));
}

TEST_CASE("gltf: metallic-roughness materials map by the documented rules", "[scene][gltf][parser]") {
    Builder b;
    int pos = b.positions(kTri);
    auto pbr = [](json base, double metal, double rough) {
        return json{{"baseColorFactor", base}, {"metallicFactor", metal}, {"roughnessFactor", rough}};
    };
    std::vector<int> mats = {
        b.material({{"name", "diffuse"}, {"pbrMetallicRoughness", pbr({0.2, 0.4, 0.6, 1}, 0, 0.8)}}),
        b.material({{"name", "mirror"}, {"pbrMetallicRoughness", pbr({0.9, 0.8, 0.7, 1}, 1, 0)}}),
        b.material({{"name", "glossy"}, {"pbrMetallicRoughness", pbr({1, 1, 1, 1}, 1, 0.5)}}),
        b.material({{"name", "glass"}, {"pbrMetallicRoughness", pbr({1, 1, 1, 1}, 0, 0)},
                    {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                                    {"KHR_materials_ior", {{"ior", 1.33}}}}}}),
        b.material({{"name", "lamp"}, {"pbrMetallicRoughness", pbr({0, 0, 0, 1}, 0, 1)},
                    {"emissiveFactor", {1, 0.5, 0.25}},
                    {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}}}}}),
        b.material({{"name", "defaults"}, {"pbrMetallicRoughness", json::object()}}),
    };
    json prims = json::array();
    for (int m : mats) prims.push_back({{"attributes", {{"POSITION", pos}}}, {"material", m}});
    b.node({{"mesh", b.mesh(prims)}}, true);
    Scene s = parse_gltf(b.gltf(), "mat.gltf");
    REQUIRE(s.materials.size() == 6);
    auto& m = s.materials;
    CHECK(m[0].kind == MaterialKind::Diffuse);
    CHECK(m[0].albedo == glm::vec3(0.2f, 0.4f, 0.6f));
    CHECK(m[1].kind == MaterialKind::Mirror);
    CHECK(m[1].albedo == glm::vec3(0.9f, 0.8f, 0.7f));
    CHECK(m[2].kind == MaterialKind::Glossy);
    // alpha = 0.5^2 = 0.25
    CHECK(m[2].alpha == Approx(0.25f));
    CHECK(m[3].kind == MaterialKind::Glass);
    CHECK(m[3].ior == Approx(1.33f));
    CHECK(m[4].kind == MaterialKind::Diffuse);
    CHECK(m[4].emission == glm::vec3(4.0f, 2.0f, 1.0f));
    CHECK(m[4].albedo == glm::vec3(0.0f));
    // defaults: spec defaults (base 1, metallic 1, roughness 1) → glossy, alpha 1
    CHECK(m[5].kind == MaterialKind::Glossy);
    CHECK(m[5].alpha == Approx(1.0f));
    CHECK(!m[5].textured());
    // Nothing approximated (textures: test_scene_attributes_gltf.cpp)
    CHECK(s.warnings.empty());
}

TEST_CASE("gltf: transmission maps to the dielectric kinds, rough by roughness²",
          "[scene][gltf][parser]") {
    Builder b;
    int pos = b.positions(kTri);
    auto glass = [&](const char* name, double rough, json ext) {
        ext["KHR_materials_transmission"] = {{"transmissionFactor", 1.0}};
        return b.material({{"name", name},
                           {"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.8, 0.7, 1}},
                                                     {"metallicFactor", 0},
                                                     {"roughnessFactor", rough}}},
                           {"extensions", ext}});
    };
    std::vector<int> mats = {
        glass("rough", 0.5, {{"KHR_materials_ior", {{"ior", 1.33}}}}),
        glass("smooth", 0.0, json::object()),
        glass("almost", 0.009, json::object()),          // α = 8.1e-5 < 1e-4: smooth, noted
        glass("edge", 0.01, {{"KHR_materials_ior", {{"ior", 1000.0}}}}),  // α = 1e-4: rough
        glass("spec", 1.0, {{"KHR_materials_specular", {{"specularFactor", 0.5}}}}),
    };
    json prims = json::array();
    for (int m : mats) prims.push_back({{"attributes", {{"POSITION", pos}}}, {"material", m}});
    b.node({{"mesh", b.mesh(prims)}}, true);
    Scene s = parse_gltf(b.gltf(), "glass.gltf");
    REQUIRE(s.materials.size() == 5);
    const auto& m = s.materials;
    // The base colour is the transmittance; reflection is untinted (specular 1)
    for (const auto& x : m) {
        CHECK(x.albedo == glm::vec3(0.9f, 0.8f, 0.7f));
        CHECK(x.specular == glm::vec3(1.0f));
        CHECK(x.distribution == wp::MicrofacetModel::GGX);
        CHECK(!x.separable_g);
        CHECK(!x.alpha_v);
    }
    CHECK(m[0].kind == MaterialKind::RoughDielectric);
    CHECK(m[0].alpha == 0.25f);  // 0.5²
    CHECK(m[0].ior == 1.33f);
    CHECK(m[1].kind == MaterialKind::Glass);
    CHECK(m[1].ior == 1.5f);
    CHECK(m[2].kind == MaterialKind::Glass);
    CHECK(m[3].kind == MaterialKind::RoughDielectric);
    CHECK(m[3].alpha == 0.01f * 0.01f);
    CHECK(m[3].ior == 1.5f);  // 1000 is outside [0.01, 100]
    CHECK(m[4].kind == MaterialKind::RoughDielectric);
    CHECK(m[4].alpha == 1.0f);
    // One note for the nearly smooth one, one for KHR_materials_specular
    REQUIRE(s.warnings.size() == 2);
    CHECK_THAT(s.warnings[0], Contains("glass.gltf") && Contains("1 transmissive") &&
                                  Contains("smooth glass"));
    CHECK_THAT(s.warnings[1], Contains("1 transmissive") && Contains("KHR_materials_specular"));
}

TEST_CASE("gltf: the first camera, looking down its node's -Z", "[scene][gltf][parser]") {
    Builder b;
    b.j["cameras"] = json::array({{{"type", "perspective"},
                                   {"perspective", {{"yfov", 0.5}, {"aspectRatio", 2.0}, {"znear", 0.1}}}},
                                  {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 0.1}}}}});
    int pos = b.positions(kTri);
    b.node({{"mesh", b.mesh(json::array({{{"attributes", {{"POSITION", pos}}}}}))}}, true);
    const float h = std::sqrt(0.5f);
    // Rotated 90° about +y: local -Z points to world -X
    b.node({{"camera", 0}, {"translation", {0, 1, 5}}, {"rotation", {0, h, 0, h}}}, true);
    b.node({{"camera", 1}, {"translation", {9, 9, 9}}}, true);
    Scene s = parse_gltf(b.glb(), "cam.glb");
    CHECK(s.camera.width == 800);
    CHECK(s.camera.height == 400);
    CHECK(s.camera.vfov_deg == Approx(0.5 * 180.0 / M_PI));
    CHECK(near(s.camera.position, {0, 1, 5}));
    CHECK(near(s.camera.target, {-1, 1, 5}));
    CHECK(near(s.camera.up, {0, 1, 0}));
}

TEST_CASE("gltf: external buffers resolve beside the file; GLB and JSON agree",
          "[scene][gltf][parser]") {
    TempDir d;
    Builder b = transform_scene();
    d.write("data.bin", b.bin);
    Scene ext = load_gltf(d.write("ext.gltf", b.gltf_external("data.bin")));
    Scene glb = load_mesh_file(d.write("same.glb", b.glb()));
    CHECK(ext.positions == glb.positions);
    CHECK(ext.triangles == glb.triangles);
    CHECK(glb.name == "same.glb");
    auto e = error_of([&] { load_gltf(d.write("missing.gltf", b.gltf_external("nope.bin"))); });
    CHECK_THAT(e, Contains("missing.gltf"));
}

TEST_CASE("gltf: truncated GLB, NaN positions and bad accessors fail with the file and place",
          "[scene][gltf][parser]") {
    Builder b = transform_scene();
    const std::string glb = b.glb();
    CHECK_THAT(error_of([&] { parse_gltf(glb.substr(0, glb.size() - 10), "cut.glb"); }),
               Contains("cut.glb") && Contains("truncated"));
    CHECK_THAT(error_of([&] { parse_gltf(glb.substr(0, 8), "cut8.glb"); }),
               Contains("cut8.glb") && Contains("truncated"));
    // Consistent header length, but the BIN chunk declares more than remains
    std::string chunk = glb.substr(0, glb.size() - 4);
    std::uint32_t len = std::uint32_t(chunk.size());
    std::memcpy(chunk.data() + 8, &len, 4);
    CHECK_THAT(error_of([&] { parse_gltf(chunk, "chunk.glb"); }),
               Contains("chunk.glb") && Contains("chunk 1 (BIN)") && Contains("truncated"));

    Builder n;
    int pos = n.positions({{0, 0, 0}, {NAN, 0, 0}, {0, 1, 0}});
    n.node({{"mesh", n.mesh(json::array({{{"attributes", {{"POSITION", pos}}}}}))}}, true);
    CHECK_THAT(error_of([&] { parse_gltf(n.gltf(), "nan.gltf"); }),
               Contains("nan.gltf") && Contains("meshes[0].primitives[0] POSITION") &&
                   Contains("element 1 is not finite"));

    Builder o = transform_scene();
    o.j["accessors"][0]["count"] = 1000;
    CHECK_THAT(error_of([&] { parse_gltf(o.gltf(), "oob.gltf"); }),
               Contains("oob.gltf") && Contains("accessors[0]") && Contains("past the end"));

    Builder i = transform_scene();
    i.j["nodes"][0]["children"] = {1};  // node 1 is node 0's parent: a cycle
    CHECK_THAT(error_of([&] { parse_gltf(i.gltf(), "cycle.gltf"); }), Contains("cycle.gltf") && Contains("cycle"));

    CHECK_THAT(error_of([&] { parse_gltf("{ not json", "bad.gltf"); }), Contains("bad.gltf"));
    CHECK_THAT(error_of([&] { parse_gltf("", "empty.gltf"); }), Contains("empty.gltf"));
}

TEST_CASE("gltf: every prefix of a GLB loads or fails with wp::Error", "[scene][gltf][parser]") {
    const std::string glb = transform_scene().glb();
    int loaded = 0;
    for (std::size_t n = 0; n <= glb.size(); n += (n < 64 ? 1 : 7)) {
        try {
            parse_gltf(std::string_view(glb).substr(0, n), "prefix.glb");
            ++loaded;
        } catch (const wp::Error& e) {
            CHECK_THAT(std::string(e.what()), Contains("prefix.glb"));
        }
    }
    CHECK(loaded <= 1);
}

// ---------------------------------------------------------------------------------------
// Through the CLI: non-zero exit, the message on stderr, no image written

namespace {

bool no_images(const TempDir& d) { return d.empty_of_images(); }

}  // namespace

TEST_CASE("gltf/ply CLI: bad mesh files exit non-zero with the file named and no image",
          "[scene][gltf][cli]") {
    TempDir d;
    const std::string glb = transform_scene().glb();
    d.write("cut.glb", glb.substr(0, glb.size() - 10));
    d.write("cut.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                       "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n");
    d.write("nan.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                       "end_header\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
    d.write("mesh.xyz", "0 0 0\n");
    struct Case {
        const char* args;
        const char* file;
        const char* what;
    };
    for (const Case& c : {Case{"cut.glb -o out.png", "cut.glb", "truncated"},
                          Case{"cut.ply -o out.exr", "cut.ply", "truncated"},
                          Case{"nan.ply", "nan.ply:11:3", "non-finite"},
                          Case{"mesh.xyz", "mesh.xyz", "unsupported"},
                          Case{"missing.glb", "missing.glb", "not found"}}) {
        Run r = run_cli(d, std::string(c.args) + " --size 16x12 --spp 1");
        INFO(c.args << ": " << r.err);
        CHECK(r.status != 0);
        CHECK_THAT(r.err, Contains(c.file) && Contains(c.what));
        CHECK(no_images(d));
    }
    // And a good one renders
    d.write("ok.glb", glb);
    Run ok = run_cli(d, "ok.glb --size 16x12 --spp 1 -q -o ok.png");
    INFO(ok.err);
    CHECK(ok.status == 0);
    CHECK(fs::exists(d.path / "ok.png"));
}
