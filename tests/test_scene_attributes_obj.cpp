// test_scene_attributes_obj.cpp — OBJ/MTL shading normals, texture coordinates and texture
// maps: uvs stored as (u, 1 - v), normals as written, one vertex per (v, vt, vn) triple,
// polygons triangulated with their attributes, map_Kd / map_Ks / map_Ke / norm / map_Bump /
// map_d read relative to the MTL file, and the -o / -s options as a uv transform checked
// against a lookup worked out by hand in MTL's own v-up coordinates. Images are written
// here with OpenImageIO; expected texel values are the bytes written.
#include <catch2/catch.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>

#include "scene/obj_loader.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using wp::test::TempDir;

namespace {

// Writes an 8-bit image of `channels` channels (row 0 at the top) to `path`.
void write_png(const fs::path& path, int w, int h, int channels, const std::vector<std::uint8_t>& px) {
    fs::create_directories(path.parent_path());
    auto out = OIIO::ImageOutput::create(path.string());
    REQUIRE(out);
    OIIO::ImageSpec spec(w, h, channels, OIIO::TypeDesc::UINT8);
    REQUIRE(out->open(path.string(), spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
}

// Texel (x, y) of a loaded texture as stored, channels in [0, 1] (8-bit: byte / 255).
glm::vec4 texel(const wp::Texture& t, int x, int y) {
    const std::size_t i = (std::size_t(y) * std::size_t(t.width) + std::size_t(x)) * 4;
    if (t.is_float()) return {t.texelsf[i], t.texelsf[i + 1], t.texelsf[i + 2], t.texelsf[i + 3]};
    return glm::vec4(t.texels8[i], t.texels8[i + 1], t.texels8[i + 2], t.texels8[i + 3]) / 255.0f;
}

bool near(glm::vec2 a, glm::vec2 b, float eps = 1e-6f) {
    return std::abs(a.x - b.x) <= eps && std::abs(a.y - b.y) <= eps;
}

bool has_warning(const wp::Scene& s, const std::string& text) {
    for (const auto& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

// The 2x2 test image: red, green / blue, white (RGB).
const std::vector<std::uint8_t> kRgb2x2 = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};

}  // namespace

TEST_CASE("obj attributes: vt stored as (u, 1 - v), vn as written, one vertex per triple",
          "[scene][obj][parser][attributes]") {
    // A unit quad in z = 0 (two vt sets) and a triangle sharing vertex 2 with another normal
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                            "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.25 0.75\n"
                            "vn 0 0 1\nvn 0 0.6 0.8\n"
                            "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
                            "f 2/5/2 3/3/1 1/1/1\n";
    wp::Scene s = wp::parse_obj(obj, "q.obj");
    REQUIRE(s.triangle_count() == 3);
    REQUIRE(s.uvs.size() == s.positions.size());
    REQUIRE(s.normals.size() == s.positions.size());
    // Distinct triples: (1,1,1) (2,2,1) (3,3,1) (4,4,1) (2,5,2); (3,3,1) and (1,1,1) reused
    CHECK(s.positions.size() == 5);
    // Every corner carries its own file attributes: position -> (u, 1 - v) by hand
    const std::map<std::tuple<float, float>, glm::vec2> uv_of_quad = {
        {{0, 0}, {0, 1}}, {{1, 0}, {1, 1}}, {{1, 1}, {1, 0}}, {{0, 1}, {0, 0}}};
    for (std::size_t t = 0; t < 2; ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = s.triangles[t][k];
            const glm::vec3 p = s.positions[v];
            CHECK(s.uvs[v] == uv_of_quad.at({p.x, p.y}));
            CHECK(s.normals[v] == glm::vec3(0, 0, 1));
        }
    // The third triangle: vertex 2 with vt 5 = (0.25, 0.75) -> (0.25, 0.25), normal 2
    const std::uint32_t a = s.triangles[2][0];
    CHECK(s.positions[a] == glm::vec3(1, 0, 0));
    CHECK(s.uvs[a] == glm::vec2(0.25f, 0.25f));
    CHECK(s.normals[a] == glm::vec3(0.0f, 0.6f, 0.8f));
    CHECK(s.triangles[2][1] == s.triangles[0][2]);  // (3, 3, 1) is the same vertex
    CHECK(s.triangles[2][2] == s.triangles[0][0]);  // (1, 1, 1) too
}

TEST_CASE("obj attributes: without vt and vn the vertices stay the file's, in order",
          "[scene][obj][parser][attributes]") {
    wp::Scene s = wp::parse_obj("v 0 0 0\nv 9 9 9\nv 1 0 0\nv 0 1 0\nf 1 3 4\n", "plain.obj");
    REQUIRE(s.positions.size() == 4);  // the unused vertex 2 included
    CHECK(s.positions[1] == glm::vec3(9, 9, 9));
    CHECK(s.triangles[0] == glm::uvec3(0, 2, 3));
    CHECK(s.uvs.empty());
    CHECK(s.normals.empty());
    CHECK(s.tangents.empty());
}

TEST_CASE("obj attributes: corners without vt or vn in a mesh that has some get zeros",
          "[scene][obj][parser][attributes]") {
    wp::Scene s = wp::parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0.5 0.25\n"
                                "f 1/1 2/1 3/1\nf 2 4 3\n",
                                "mixed.obj");
    REQUIRE(s.triangle_count() == 2);
    CHECK(s.normals.empty());  // no corner names a normal
    REQUIRE(s.uvs.size() == s.positions.size());
    for (int k = 0; k < 3; ++k) CHECK(s.uvs[s.triangles[0][k]] == glm::vec2(0.5f, 0.75f));
    for (int k = 0; k < 3; ++k) CHECK(s.uvs[s.triangles[1][k]] == glm::vec2(0.0f, 0.0f));
}

TEST_CASE("obj attributes: concave polygons are triangulated with their corners' attributes",
          "[scene][obj][parser][attributes]") {
    // A concave "arrow" hexagon; each corner's vt is (x / 4, y / 4) of its own position and its
    // vn is (x, y, 1), so every triangle corner can be checked against its position
    const std::vector<glm::vec2> p = {{0, 0}, {4, 0}, {4, 4}, {2, 1}, {0, 4}, {1, 2}};
    std::string obj;
    for (auto v : p) obj += fmt::format("v {} {} 0\n", v.x, v.y);
    for (auto v : p) obj += fmt::format("vt {} {}\n", v.x / 4, v.y / 4);
    for (auto v : p) obj += fmt::format("vn {} {} 1\n", v.x, v.y);
    obj += "f";
    for (std::size_t i = 1; i <= p.size(); ++i) obj += fmt::format(" {}/{}/{}", i, i, i);
    obj += "\n";
    wp::Scene s = wp::parse_obj(obj, "arrow.obj");
    REQUIRE(s.triangle_count() == 4);
    double area = 0.0;
    for (const auto& t : s.triangles) {
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 q = s.positions[t[k]];
            CHECK(s.uvs[t[k]] == glm::vec2(q.x / 4, 1.0f - q.y / 4));
            CHECK(s.normals[t[k]] == glm::vec3(q.x, q.y, 1.0f));
        }
        const glm::vec3 e = glm::cross(s.positions[t.y] - s.positions[t.x],
                                       s.positions[t.z] - s.positions[t.x]);
        CHECK(e.z > 0.0f);
        area += 0.5 * e.z;
    }
    // Shoelace area of the hexagon: 16 - 2 - 2 - ... computed: 0.5 * |sum x_i y_{i+1} - x_{i+1} y_i|
    double shoelace = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const auto u = p[i], v = p[(i + 1) % p.size()];
        shoelace += 0.5 * (double(u.x) * v.y - double(v.x) * u.y);
    }
    CHECK(area == Approx(shoelace));
}

TEST_CASE("obj textures: map_Kd relative to the MTL folder, texels as written, Kd multiplies",
          "[scene][obj][parser][attributes]") {
    TempDir dir;
    write_png(dir.path / "mat" / "tex" / "rgb.png", 2, 2, 3, kRgb2x2);
    dir.write("mat/lib.mtl",
              "newmtl Painted\nKd 0.5 0.25 1\nmap_Kd tex/rgb.png\n"
              "newmtl Bare\nmap_Kd tex\\rgb.png\n");  // no Kd line: the map alone; '\' as '/'
    dir.write("quad.obj", "mtllib mat/lib.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                          "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                          "usemtl Painted\nf 1/1 2/2 3/3 4/4\nusemtl Bare\nf 1/1 3/3 4/4\n");
    wp::Scene s = wp::load_obj(dir.path / "quad.obj");
    REQUIRE(s.materials.size() == 2);
    const wp::Material& m = s.materials[s.material_ids[0]];
    CHECK(m.name == "Painted");
    CHECK(m.kind == wp::MaterialKind::Diffuse);
    CHECK(m.albedo == glm::vec3(0.5f, 0.25f, 1.0f));
    REQUIRE(m.albedo_map.used());
    CHECK(m.albedo_map.uv_transform == glm::mat3(1.0f));
    const wp::Texture& t = s.textures.at(std::size_t(m.albedo_map.image));
    REQUIRE(t.width == 2);
    REQUIRE(t.height == 2);
    CHECK(texel(t, 0, 0) == glm::vec4(1, 0, 0, 1));  // row 0 = the image's top row
    CHECK(texel(t, 1, 0) == glm::vec4(0, 1, 0, 1));
    CHECK(texel(t, 0, 1) == glm::vec4(0, 0, 1, 1));
    CHECK(texel(t, 1, 1) == glm::vec4(1, 1, 1, 1));
    // The second material names the same file: same texture, albedo 1 (no Kd line)
    const wp::Material& b = s.materials[s.material_ids[2]];
    CHECK(b.name == "Bare");
    CHECK(b.albedo == glm::vec3(1.0f));
    CHECK(b.albedo_map.image == m.albedo_map.image);
    CHECK(s.textures.size() == 1);
    CHECK(!has_warning(s, "ignored"));
    // uv (0, 0) of the file is the image's bottom-left corner: stored (0, 1)
    for (const auto& tri : s.triangles)
        for (int k = 0; k < 3; ++k)
            if (s.positions[tri[k]] == glm::vec3(0, 0, 0)) CHECK(s.uvs[tri[k]] == glm::vec2(0, 1));
}

// The MTL's Kd lines are found by wavepath's own scan (a map without Kd is the map alone);
// that scan splits lines as tinyobjloader does, lone "\r" included: with "\n" alone it saw
// one line here, missed Painted's Kd and gave it albedo 1.
TEST_CASE("obj textures: an MTL with carriage-return line ends keeps its Kd with the map",
          "[scene][obj][parser][attributes]") {
    TempDir dir;
    write_png(dir.path / "rgb.png", 2, 2, 3, kRgb2x2);
    dir.write("m.mtl", "newmtl Painted\rKd 0.5 0.25 1\rmap_Kd rgb.png\rnewmtl Bare\rmap_Kd rgb.png\r");
    dir.write("t.obj", "mtllib m.mtl\rv 0 0 0\rv 1 0 0\rv 0 1 0\rvt 0 0\r"
                       "usemtl Painted\rf 1/1 2/1 3/1\rusemtl Bare\rf 1/1 3/1 2/1\r");
    wp::Scene s = wp::load_obj(dir.path / "t.obj");
    REQUIRE(s.triangle_count() == 2);
    const wp::Material& p = s.materials.at(s.material_ids[0]);
    const wp::Material& b = s.materials.at(s.material_ids[1]);
    CHECK(p.name == "Painted");
    CHECK(p.albedo == glm::vec3(0.5f, 0.25f, 1.0f));
    CHECK(p.albedo_map.used());
    CHECK(b.name == "Bare");
    CHECK(b.albedo == glm::vec3(1.0f));
    CHECK(b.albedo_map.used());
}

TEST_CASE("obj textures: -o and -s become the uv transform of the stored (u, 1 - v)",
          "[scene][obj][parser][attributes]") {
    TempDir dir;
    write_png(dir.path / "rgb.png", 2, 2, 3, kRgb2x2);
    dir.write("m.mtl", "newmtl T\nKd 1 1 1\nmap_Kd -o 0.25 0.5 0 -s 2 3 1 rgb.png\n");
    dir.write("t.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.3 0.2\nvt 0.9 0.6\n"
                       "usemtl T\nf 1/1 2/2 3/1\n");
    wp::Scene s = wp::load_obj(dir.path / "t.obj");
    const wp::Material& m = s.materials.at(0);
    REQUIRE(m.albedo_map.used());
    const glm::mat3 M = m.albedo_map.uv_transform;
    // MTL looks the map up at (su u + ou, sv v + ov) with v up; the image's top-down row
    // coordinate is 1 minus that. By hand for vt (0.3, 0.2): (2 * 0.3 + 0.25, 3 * 0.2 + 0.5) =
    // (0.85, 1.1) -> (0.85, 1 - 1.1) = (0.85, -0.1); for vt (0.9, 0.6): (2.05, 2.3) ->
    // (2.05, -1.3).
    const std::uint32_t a = s.triangles[0][0], b = s.triangles[0][1];
    REQUIRE(near(s.uvs[a], {0.3f, 0.8f}));
    REQUIRE(near(s.uvs[b], {0.9f, 0.4f}));
    CHECK(near(glm::vec2(M * glm::vec3(s.uvs[a], 1.0f)), {0.85f, -0.1f}, 1e-5f));
    CHECK(near(glm::vec2(M * glm::vec3(s.uvs[b], 1.0f)), {2.05f, -1.3f}, 1e-5f));
    CHECK(M[0][2] == 0.0f);
    CHECK(M[1][2] == 0.0f);
    CHECK(M[2][2] == 1.0f);
}

TEST_CASE("obj textures: map_Ks on glossy and mirror, map_Ke, norm with -bm",
          "[scene][obj][parser][attributes]") {
    TempDir dir;
    write_png(dir.path / "rgb.png", 2, 2, 3, kRgb2x2);
    write_png(dir.path / "n.png", 1, 1, 3, {128, 128, 255});
    dir.write("m.mtl", "newmtl Gloss\nKd 0 0 0\nKs 0.5 0.5 0.5\nNs 100\nillum 2\nmap_Ks rgb.png\n"
                       "newmtl Chrome\nKd 0 0 0\nKs 1 1 1\nNs 1000\nillum 3\nmap_Ks rgb.png\n"
                       "newmtl Lamp\nKd 0.5 0.5 0.5\nKe 2 2 2\nmap_Ke rgb.png\nnorm -bm 0.5 n.png\n"
                       "newmtl DiffuseKs\nKd 0.5 0.5 0.5\nmap_Ks rgb.png\n"
                       "newmtl KeZero\nKd 0.5 0.5 0.5\nKe 0 0 0\nmap_Ke rgb.png\n");
    std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n";
    for (const char* name : {"Gloss", "Chrome", "Lamp", "DiffuseKs", "KeZero"})
        obj += fmt::format("usemtl {}\nf 1/1 2/1 3/1\n", name);
    dir.write("t.obj", obj);
    wp::Scene s = wp::load_obj(dir.path / "t.obj");
    REQUIRE(s.materials.size() == 5);
    const wp::Material &gloss = s.materials[0], &chrome = s.materials[1], &lamp = s.materials[2],
                       &dks = s.materials[3], &kez = s.materials[4];
    CHECK(gloss.kind == wp::MaterialKind::Glossy);
    CHECK(gloss.albedo == glm::vec3(0.5f));
    CHECK(gloss.albedo_map.used());
    CHECK(chrome.kind == wp::MaterialKind::Mirror);
    CHECK(chrome.albedo_map.used());
    CHECK(chrome.albedo_map.image == gloss.albedo_map.image);
    CHECK(lamp.emission == glm::vec3(2.0f));
    CHECK(lamp.emission_map.used());
    REQUIRE(lamp.normal_map.used());
    CHECK(lamp.normal_scale == 0.5f);
    CHECK(texel(s.textures.at(std::size_t(lamp.normal_map.image)), 0, 0) ==
          glm::vec4(128 / 255.0f, 128 / 255.0f, 1.0f, 1.0f));
    CHECK(!dks.albedo_map.used());
    CHECK(has_warning(s, "material 'DiffuseKs': map_Ks 'rgb.png' ignored (the material is diffuse)"));
    CHECK(!kez.emission_map.used());
    CHECK(has_warning(s, "material 'KeZero': map_Ke 'rgb.png' ignored (Ke is 0)"));
}

TEST_CASE("obj textures: map_Bump is a normal map unless the image is grey (a height map)",
          "[scene][obj][parser][attributes]") {
    TempDir dir;
    write_png(dir.path / "n.png", 2, 1, 3, {128, 128, 255, 200, 100, 230});
    write_png(dir.path / "h.png", 2, 1, 1, {10, 200});
    dir.write("m.mtl", "newmtl N\nKd 1 1 1\nmap_Bump -bm 2 n.png\n"
                       "newmtl H\nKd 1 1 1\nbump h.png\n");
    dir.write("t.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n"
                       "usemtl N\nf 1/1 2/1 3/1\nusemtl H\nf 1/1 2/1 3/1\n");
    wp::Scene s = wp::load_obj(dir.path / "t.obj");
    REQUIRE(s.materials.size() == 2);
    CHECK(s.materials[0].normal_map.used());
    CHECK(s.materials[0].normal_scale == 2.0f);
    CHECK(!s.materials[1].normal_map.used());
    CHECK(has_warning(s, "material 'H': map_Bump 'h.png' is a grey image"));
    CHECK(s.textures.size() == 1);  // the height map is not kept
}

TEST_CASE("obj textures: map_d coverage from alpha, else from the first channel; cutoff 0.5",
          "[scene][obj][parser][attributes]") {
    TempDir dir;
    // RGBA: coverage = A (0 and 255); RGB: coverage = R (0.2 and 0.8); all white: nothing cut
    write_png(dir.path / "a.png", 2, 1, 4, {255, 255, 255, 0, 0, 0, 0, 255});
    write_png(dir.path / "r.png", 2, 1, 3, {51, 255, 255, 204, 0, 0});
    write_png(dir.path / "w.png", 1, 1, 3, {255, 255, 255});
    dir.write("m.mtl", "newmtl A\nKd 1 1 1\nmap_d a.png\nnewmtl R\nKd 1 1 1\nmap_d r.png\n"
                       "newmtl W\nKd 1 1 1\nmap_d w.png\n");
    dir.write("t.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n"
                       "usemtl A\nf 1/1 2/1 3/1\nusemtl R\nf 1/1 2/1 3/1\nusemtl W\nf 1/1 2/1 3/1\n");
    wp::Scene s = wp::load_obj(dir.path / "t.obj");
    REQUIRE(s.materials.size() == 3);
    const wp::Material &a = s.materials[0], &r = s.materials[1], &w = s.materials[2];
    REQUIRE(a.alpha_map.used());
    CHECK(a.alpha_cutoff == 0.5f);
    CHECK(a.alpha_factor == 1.0f);
    const wp::Texture& ta = s.textures.at(std::size_t(a.alpha_map.image));
    CHECK(texel(ta, 0, 0).w == 0.0f);
    CHECK(texel(ta, 1, 0).w == 1.0f);
    REQUIRE(r.alpha_map.used());
    const wp::Texture& tr = s.textures.at(std::size_t(r.alpha_map.image));
    CHECK(texel(tr, 0, 0).w == Approx(0.2f));
    CHECK(texel(tr, 1, 0).w == Approx(0.8f));
    CHECK(!w.alpha_map.used());  // coverage 1 everywhere: no cut-out to test
    CHECK(s.textures.size() == 2);
}

TEST_CASE("obj textures: a missing map is a warning naming it with a placeholder; no uvs is fine",
          "[scene][obj][parser][attributes]") {
    TempDir dir;
    dir.write("m.mtl", "newmtl M\nKd 1 1 1\nmap_Kd nowhere.png\n");
    fs::create_directories(dir.path / "adir.png");
    dir.write("d.mtl", "newmtl D\nKd 1 1 1\nmap_Kd adir.png\n");
    dir.write("t.obj", "mtllib m.mtl\nmtllib d.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                       "usemtl M\nf 1 2 3\nusemtl D\nf 1 2 3\n");
    wp::Scene s;
    REQUIRE_NOTHROW(s = wp::load_obj(dir.path / "t.obj"));
    REQUIRE(s.materials.size() == 2);
    REQUIRE(s.materials[0].albedo_map.used());  // the placeholder
    CHECK(s.textures.size() == 1);
    CHECK(s.textures[0].width > 0);
    CHECK(has_warning(s, "nowhere.png"));
    CHECK(!s.materials[1].albedo_map.used());  // a folder is not read
    CHECK(has_warning(s, "adir.png' is not a regular file; ignored"));
}
