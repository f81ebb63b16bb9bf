// test_scene_attributes_assimp.cpp — per-vertex normals and the first uv set through the
// Assimp loader: PLY nx/ny/nz and u/v (ASCII, binary, and binary read by wavepath's own
// walker when Assimp would misread it) against the values written, uvs stored (u, 1 - v);
// a Collada file's diffuse texture; and the teapot of ../shared/scenes (normals read).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "scene/assimp_loader.h"
#include "scene/load.h"
#include "support.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using wp::test::TempDir;

namespace {

// A unit square in z = 0 as one quad face; per vertex a normal tilted differently and a uv.
const float kPos[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
const float kNrm[4][3] = {{0, 0, 1}, {0.6f, 0, 0.8f}, {0, 0.6f, 0.8f}, {-0.6f, 0, 0.8f}};
const float kUv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0.25f, 0.75f}};

std::string header(const char* format, const char* u = "u", const char* v = "v") {
    return fmt::format("ply\nformat {} 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                       "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
                       "property float {}\nproperty float {}\nelement face 1\n"
                       "property list uchar int vertex_indices\nend_header\n",
                       format, u, v);
}

using wp::test::put;

// Binary little-endian; x of vertex 0 replaced by `x0`.
std::string binary_square(float x0) {
    std::string s = header("binary_little_endian");
    for (int i = 0; i < 4; ++i) {
        put<float>(s, i == 0 ? x0 : kPos[i][0]);
        put<float>(s, kPos[i][1]);
        put<float>(s, kPos[i][2]);
        for (float n : kNrm[i]) put<float>(s, n);
        for (float t : kUv[i]) put<float>(s, t);
    }
    put<std::uint8_t>(s, 4);
    for (int k = 0; k < 4; ++k) put<std::int32_t>(s, k);
    return s;
}

// The square's attributes as written: normals as is, uvs (u, 1 - v); triangles cover it.
void check_square(const wp::Scene& s, float x0 = 0.0f) {
    REQUIRE(s.positions.size() == 4);
    REQUIRE(s.normals.size() == 4);
    REQUIRE(s.uvs.size() == 4);
    CHECK(s.tangents.empty());
    for (int i = 0; i < 4; ++i) {
        CHECK(s.positions[i] == glm::vec3(i == 0 ? x0 : kPos[i][0], kPos[i][1], kPos[i][2]));
        CHECK(s.normals[i] == glm::vec3(kNrm[i][0], kNrm[i][1], kNrm[i][2]));
        CHECK(s.uvs[i] == glm::vec2(kUv[i][0], 1.0f - kUv[i][1]));
    }
    REQUIRE(s.triangle_count() == 2);
    for (const auto& t : s.triangles) {
        const glm::vec3 e = glm::cross(s.positions[t.y] - s.positions[t.x],
                                       s.positions[t.z] - s.positions[t.x]);
        CHECK(e.z > 0.0f);  // the quad's winding, vertices not renumbered
    }
}

bool has_warning(const wp::Scene& s, const std::string& text) {
    for (const auto& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST_CASE("assimp attributes: PLY nx ny nz and u v, ASCII and binary, uvs stored (u, 1 - v)",
          "[scene][assimp][parser][attributes]") {
    SECTION("ascii, u v") {
        std::string ply = header("ascii");
        for (int i = 0; i < 4; ++i)
            ply += fmt::format("{} {} {} {} {} {} {} {}\n", kPos[i][0], kPos[i][1], kPos[i][2],
                               kNrm[i][0], kNrm[i][1], kNrm[i][2], kUv[i][0], kUv[i][1]);
        ply += "4 0 1 2 3\n";
        check_square(wp::parse_assimp(ply, "ply", "sq.ply"));
    }
    SECTION("ascii, s t") {
        std::string ply = header("ascii", "s", "t");
        for (int i = 0; i < 4; ++i)
            ply += fmt::format("{} {} {} {} {} {} {} {}\n", kPos[i][0], kPos[i][1], kPos[i][2],
                               kNrm[i][0], kNrm[i][1], kNrm[i][2], kUv[i][0], kUv[i][1]);
        ply += "4 0 1 2 3\n";
        check_square(wp::parse_assimp(ply, "ply", "st.ply"));
    }
    SECTION("binary, read by Assimp") { check_square(wp::parse_assimp(binary_square(0.0f), "ply", "b.ply")); }
    SECTION("binary whose data starts with a whitespace byte, read by wavepath's walker") {
        // -1.0000012f is 0xBF80000A: its first byte (little-endian) is 0x0a ('\n')
        std::uint32_t bits = 0xBF80000Au;
        float x0;
        std::memcpy(&x0, &bits, 4);
        const std::string ply = binary_square(x0);
        REQUIRE(ply[header("binary_little_endian").size()] == '\n');
        check_square(wp::parse_assimp(ply, "ply", "ws.ply"), x0);
    }
}

TEST_CASE("assimp attributes: a PLY without normals or uvs has none",
          "[scene][assimp][parser][attributes]") {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                            "property float y\nproperty float z\nelement face 1\n"
                            "property list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    wp::Scene s = wp::parse_assimp(ply, "ply", "plain.ply");
    CHECK(s.normals.empty());
    CHECK(s.uvs.empty());
    CHECK(s.triangle_count() == 1);
}

TEST_CASE("assimp attributes: a Collada diffuse texture beside the file, uvs flipped",
          "[scene][assimp][parser][attributes]") {
    TempDir dir;
    {
        fs::create_directories(dir.path / "tex");
        const std::string p = (dir.path / "tex" / "rgb.png").string();
        auto out = OIIO::ImageOutput::create(p);
        REQUIRE(out);
        REQUIRE(out->open(p, OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::UINT8)));
        const std::uint8_t px[6] = {255, 0, 0, 0, 0, 255};
        REQUIRE(out->write_image(OIIO::TypeDesc::UINT8, px));
        out->close();
    }
    const std::string dae = R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_images><image id="img"><init_from>tex/rgb.png</init_from></image></library_images>
  <library_effects><effect id="fx"><profile_COMMON>
    <newparam sid="surf"><surface type="2D"><init_from>img</init_from></surface></newparam>
    <newparam sid="samp"><sampler2D><source>surf</source></sampler2D></newparam>
    <technique sid="common"><lambert><diffuse><texture texture="samp" texcoord="UVSET0"/></diffuse></lambert></technique>
  </profile_COMMON></effect></library_effects>
  <library_materials><material id="mat" name="painted"><instance_effect url="#fx"/></material></library_materials>
  <library_geometries><geometry id="tri"><mesh>
    <source id="pos"><float_array id="pos-a" count="9">0 0 0 1 0 0 0 1 0</float_array>
      <technique_common><accessor source="#pos-a" count="3" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <source id="nrm"><float_array id="nrm-a" count="9">0 0 1 0 0.6 0.8 0.6 0 0.8</float_array>
      <technique_common><accessor source="#nrm-a" count="3" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <source id="uv"><float_array id="uv-a" count="6">0 0 1 0 0.25 0.75</float_array>
      <technique_common><accessor source="#uv-a" count="3" stride="2">
        <param name="S" type="float"/><param name="T" type="float"/>
      </accessor></technique_common></source>
    <vertices id="verts"><input semantic="POSITION" source="#pos"/></vertices>
    <triangles count="1" material="m">
      <input semantic="VERTEX" source="#verts" offset="0"/>
      <input semantic="NORMAL" source="#nrm" offset="0"/>
      <input semantic="TEXCOORD" source="#uv" offset="0" set="0"/>
      <p>0 1 2</p>
    </triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="n">
    <instance_geometry url="#tri"><bind_material><technique_common>
      <instance_material symbol="m" target="#mat">
        <bind_vertex_input semantic="UVSET0" input_semantic="TEXCOORD" input_set="0"/>
      </instance_material>
    </technique_common></bind_material></instance_geometry>
  </node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
    wp::Scene s = wp::load_mesh_file(dir.write("tri.dae", dae));
    REQUIRE(s.triangle_count() == 1);
    REQUIRE(s.uvs.size() == 3);
    REQUIRE(s.normals.size() == 3);
    // Per corner of the triangle (Assimp may renumber vertices): position -> file uv, normal
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = s.triangles[0][k];
        const glm::vec3 p = s.positions[v];
        const glm::vec2 want = p.x == 1 ? glm::vec2(1, 1) : p.y == 1 ? glm::vec2(0.25f, 0.25f)
                                                                     : glm::vec2(0, 1);
        const glm::vec3 n = p.x == 1 ? glm::vec3(0, 0.6f, 0.8f)
                            : p.y == 1 ? glm::vec3(0.6f, 0, 0.8f) : glm::vec3(0, 0, 1);
        CHECK(std::abs(s.uvs[v].x - want.x) < 1e-6f);
        CHECK(std::abs(s.uvs[v].y - want.y) < 1e-6f);
        CHECK(glm::length(s.normals[v] - n) < 1e-6f);
    }
    REQUIRE(s.materials.size() == 1);
    const wp::Material& m = s.materials[0];
    CHECK(m.name == "painted");
    REQUIRE(m.albedo_map.used());
    CHECK(m.albedo == glm::vec3(1.0f));
    const wp::Texture& t = s.textures.at(std::size_t(m.albedo_map.image));
    CHECK(t.width == 2);
    CHECK(t.height == 1);
    CHECK_THAT(t.source, Contains("rgb.png"));
    // (Assimp gives a lambert effect a specular colour: that warning is expected)
    CHECK(!has_warning(s, "texture"));
}

TEST_CASE("assimp attributes: the utah-teapot PLYs of ../shared/scenes have unit normals",
          "[scene][assimp][shared]") {
    const fs::path dir = fs::path(WP_SHARED_SCENES) / "utah-teapot" / "models";
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        WARN("SKIP: " << dir.string() << " does not exist (the shared public scenes are not here)");
        return;
    }
    for (const char* name : {"Mesh000.ply", "Mesh001.ply"}) {
        wp::Scene s = wp::load_mesh_file(dir / name);
        REQUIRE(s.normals.size() == s.positions.size());
        REQUIRE(s.uvs.size() == s.positions.size());
        std::size_t bad = 0, facing = 0;
        for (const auto& n : s.normals) bad += std::abs(glm::length(n) - 1.0f) > 1e-5f;
        // Every triangle's winding agrees with its vertex normals (SOURCE.md)
        for (const auto& t : s.triangles) {
            const glm::vec3 g = glm::cross(s.positions[t.y] - s.positions[t.x],
                                           s.positions[t.z] - s.positions[t.x]);
            facing += glm::dot(g, s.normals[t.x] + s.normals[t.y] + s.normals[t.z]) > 0.0f;
        }
        CHECK(bad == 0);
        CHECK(facing == s.triangle_count());
    }
}
