// test_scene_attributes_gltf.cpp — glTF 2.0 NORMAL / TEXCOORD_0 / TANGENT (node transforms:
// normals by the inverse transpose, tangents as vectors with the bitangent sign flipped by a
// mirror), material textures (a file beside the .gltf, a data: URI, a GLB buffer view),
// samplers, alphaMode MASK / BLEND, and KHR_texture_transform against the extension's own
// examples worked out by hand. Images are written here with OpenImageIO.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include "scene/gltf_loader.h"
#include "scene/texture.h"
#include "util/error.h"
#include "support.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using json = nlohmann::json;
using wp::test::TempDir;

namespace {

using wp::test::base64;
using wp::test::put;

// A small glTF: one buffer, one view per accessor or image; one mesh of primitives under
// root nodes; materials, textures, images, samplers as given.
struct Gltf {
    std::string bin;
    json j = {{"asset", {{"version", "2.0"}}}, {"accessors", json::array()},
              {"bufferViews", json::array()}, {"meshes", json::array()},
              {"nodes", json::array()}, {"materials", json::array()},
              {"textures", json::array()}, {"images", json::array()},
              {"samplers", json::array()},
              {"scenes", json::array({json{{"nodes", json::array()}}})}, {"scene", 0}};

    int view(const std::string& bytes) {
        while (bin.size() % 4) bin.push_back('\0');
        j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes.size()}});
        bin += bytes;
        return int(j["bufferViews"].size()) - 1;
    }
    int floats(const std::vector<float>& v, int comps, const char* type) {
        std::string b;
        for (float f : v) put(b, f);
        j["accessors"].push_back({{"bufferView", view(b)}, {"componentType", 5126},
                                  {"count", v.size() / std::size_t(comps)}, {"type", type}});
        return int(j["accessors"].size()) - 1;
    }
    int bytes_normalized(const std::vector<std::uint8_t>& v, const char* type, int comps) {
        std::string b(v.begin(), v.end());
        j["accessors"].push_back({{"bufferView", view(b)}, {"componentType", 5121},
                                  {"normalized", true}, {"count", v.size() / std::size_t(comps)},
                                  {"type", type}});
        return int(j["accessors"].size()) - 1;
    }
    int mesh(json primitives) {
        j["meshes"].push_back({{"primitives", primitives}});
        return int(j["meshes"].size()) - 1;
    }
    void root(json n) {
        j["nodes"].push_back(n);
        j["scenes"][0]["nodes"].push_back(int(j["nodes"].size()) - 1);
    }
    int add(const char* what, json v) {
        j[what].push_back(v);
        return int(j[what].size()) - 1;
    }
    std::string gltf() const {
        json k = j;
        k["buffers"] = json::array({{{"byteLength", bin.size()},
                                     {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
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

// Writes an 8-bit image (row 0 at the top) and returns its bytes.
std::string write_png(const fs::path& path, int w, int h, int channels,
                      const std::vector<std::uint8_t>& px) {
    fs::create_directories(path.parent_path());
    auto out = OIIO::ImageOutput::create(path.string());
    REQUIRE(out);
    REQUIRE(out->open(path.string(), OIIO::ImageSpec(w, h, channels, OIIO::TypeDesc::UINT8)));
    REQUIRE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

glm::vec4 texel(const wp::Texture& t, int x, int y) {
    const std::size_t i = (std::size_t(y) * std::size_t(t.width) + std::size_t(x)) * 4;
    if (t.is_float()) return {t.texelsf[i], t.texelsf[i + 1], t.texelsf[i + 2], t.texelsf[i + 3]};
    return glm::vec4(t.texels8[i], t.texels8[i + 1], t.texels8[i + 2], t.texels8[i + 3]) / 255.0f;
}

bool has_warning(const wp::Scene& s, const std::string& text) {
    for (const auto& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

bool near(glm::vec3 a, glm::vec3 b, float eps = 1e-6f) { return glm::length(a - b) <= eps; }
bool near2(glm::vec2 a, glm::vec2 b, float eps = 1e-6f) { return glm::length(a - b) <= eps; }

// RGBA 2x2: opaque red, transparent green / opaque blue, half-covered white.
const std::vector<std::uint8_t> kRgba2x2 = {255, 0, 0, 255, 0, 255, 0, 0,
                                            0, 0, 255, 255, 255, 255, 255, 128};

// One triangle (positions, normals, uvs, tangents) in a primitive with material `mat`.
json textured_triangle(Gltf& g, int mat) {
    int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, 3, "VEC3");
    int uv = g.floats({0, 0, 1, 0, 0, 1}, 2, "VEC2");
    json p = {{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}};
    if (mat >= 0) p["material"] = mat;
    return p;
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

TEST_CASE("gltf attributes: NORMAL, TEXCOORD_0 and TANGENT through node transforms",
          "[scene][gltf][parser][attributes]") {
    Gltf g;
    const float r = 1.0f / std::sqrt(2.0f);
    int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, 3, "VEC3");
    int nrm = g.floats({r, 0, r, 0, r, r, 0, 0, 1}, 3, "VEC3");
    int uv = g.floats({0.25f, 0.75f, 1, 0, 0.5f, 0.125f}, 2, "VEC2");
    int tan = g.floats({1, 0, 0, 1, 0, 1, 0, -1, r, r, 0, 1}, 4, "VEC4");
    int m = g.mesh(json::array(
        {{{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}, {"TANGENT", tan}}}}}));
    g.root({{"mesh", m}, {"scale", {2, 1, 1}}});                                       // S
    g.root({{"mesh", m}, {"matrix", {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}}}); // mirror x
    wp::Scene s = wp::parse_gltf(g.gltf(), "attr.gltf");
    REQUIRE(s.positions.size() == 6);
    REQUIRE(s.normals.size() == 6);
    REQUIRE(s.uvs.size() == 6);
    REQUIRE(s.tangents.size() == 6);
    CHECK(s.warnings.empty());
    // uvs as in the file (glTF's origin is already the image's top-left)
    for (int inst = 0; inst < 2; ++inst) {
        CHECK(s.uvs[3 * inst + 0] == glm::vec2(0.25f, 0.75f));
        CHECK(s.uvs[3 * inst + 1] == glm::vec2(1.0f, 0.0f));
        CHECK(s.uvs[3 * inst + 2] == glm::vec2(0.5f, 0.125f));
    }
    // Scale (2, 1, 1): normals by diag(1/2, 1, 1), tangents by diag(2, 1, 1), w kept
    CHECK(near(s.normals[0], {0.5f * r, 0, r}));
    CHECK(near(s.normals[1], {0, r, r}));
    CHECK(near(s.normals[2], {0, 0, 1}));
    CHECK(s.tangents[0] == glm::vec4(2, 0, 0, 1));
    CHECK(s.tangents[1] == glm::vec4(0, 1, 0, -1));
    CHECK(near(glm::vec3(s.tangents[2]), {2 * r, r, 0}));
    CHECK(s.tangents[2].w == 1.0f);
    // Mirror x: winding reversed, normals (-x, y, z), tangents (-x, y, z) with w negated so
    // that w' cross(n', t') is the mirrored bitangent M (w cross(n, t))
    CHECK(s.triangles[1] == glm::uvec3(3, 5, 4));
    const glm::mat3 M(glm::vec3(-1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1));
    const glm::vec3 n_file[3] = {{r, 0, r}, {0, r, r}, {0, 0, 1}};
    const glm::vec4 t_file[3] = {{1, 0, 0, 1}, {0, 1, 0, -1}, {r, r, 0, 1}};
    for (int i = 0; i < 3; ++i) {
        CHECK(near(s.normals[3 + i], M * n_file[i]));
        CHECK(near(glm::vec3(s.tangents[3 + i]), M * glm::vec3(t_file[i])));
        CHECK(s.tangents[3 + i].w == -t_file[i].w);
        const glm::vec3 b_file = t_file[i].w * glm::cross(n_file[i], glm::vec3(t_file[i]));
        const glm::vec3 b = s.tangents[3 + i].w *
                            glm::cross(s.normals[3 + i], glm::vec3(s.tangents[3 + i]));
        CHECK(near(b, M * b_file));
    }
}

TEST_CASE("gltf attributes: normalized u8 texcoords; a primitive without attributes gets zeros",
          "[scene][gltf][parser][attributes]") {
    Gltf g;
    int pos = g.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, 3, "VEC3");
    int uv8 = g.bytes_normalized({0, 255, 255, 0, 51, 102}, "VEC2", 2);
    int m = g.mesh(json::array({{{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv8}}}},
                                {{"attributes", {{"POSITION", pos}}}}}));
    g.root({{"mesh", m}});
    wp::Scene s = wp::parse_gltf(g.gltf(), "u8.gltf");
    REQUIRE(s.uvs.size() == 6);
    CHECK(s.uvs[0] == glm::vec2(0, 1));
    CHECK(s.uvs[1] == glm::vec2(1, 0));
    CHECK(near2(s.uvs[2], {0.2f, 0.4f}));
    for (int i = 3; i < 6; ++i) CHECK(s.uvs[i] == glm::vec2(0, 0));
    CHECK(s.normals.empty());
    CHECK(s.tangents.empty());
    // A NORMAL accessor with another count than POSITION is an error naming it
    Gltf b;
    int p2 = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, 3, "VEC3");
    int n2 = b.floats({0, 0, 1, 0, 0, 1}, 3, "VEC3");
    b.root({{"mesh", b.mesh(json::array({{{"attributes", {{"POSITION", p2}, {"NORMAL", n2}}}}}))}});
    CHECK_THAT(error_of([&] { wp::parse_gltf(b.gltf(), "n.gltf"); }),
               Contains("n.gltf") && Contains("NORMAL (accessors[1]) has 2 elements, but POSITION has 3"));
}

TEST_CASE("gltf textures: base colour from a file beside the .gltf, x factor; sampler",
          "[scene][gltf][parser][attributes]") {
    TempDir dir;
    write_png(dir.path / "tex" / "my tex.png", 2, 2, 4, kRgba2x2);
    Gltf g;
    int img = g.add("images", {{"uri", "tex/my%20tex.png"}});
    int smp = g.add("samplers", {{"magFilter", 9728}, {"wrapS", 33071}});  // NEAREST, CLAMP
    int tex = g.add("textures", {{"source", img}, {"sampler", smp}});
    int mat = g.add("materials", {{"pbrMetallicRoughness",
                                   {{"baseColorFactor", {0.5, 0.25, 1, 1}}, {"metallicFactor", 0},
                                    {"baseColorTexture", {{"index", tex}}}}}});
    g.root({{"mesh", g.mesh(json::array({textured_triangle(g, mat)}))}});
    wp::Scene s = wp::load_gltf(dir.write("a.gltf", g.gltf()));
    REQUIRE(s.materials.size() == 1);
    const wp::Material& m = s.materials[0];
    CHECK(m.kind == wp::MaterialKind::Diffuse);
    CHECK(m.albedo == glm::vec3(0.5f, 0.25f, 1.0f));
    REQUIRE(m.albedo_map.used());
    CHECK(m.albedo_map.uv_transform == glm::mat3(1.0f));
    CHECK(!m.alpha_map.used());  // OPAQUE: alpha ignored, as the spec says
    REQUIRE(s.textures.size() == 1);
    const wp::Texture& t = s.textures[0];
    REQUIRE(t.width == 2);
    REQUIRE(t.height == 2);
    CHECK(t.nearest);
    CHECK(texel(t, 0, 0) == glm::vec4(1, 0, 0, 1));
    CHECK(texel(t, 0, 1) == glm::vec4(0, 0, 1, 1));
    // (colour where A < 1 is not compared: a PNG reader may premultiply it)
    CHECK(texel(t, 1, 0).w == 0.0f);
    CHECK(texel(t, 1, 1).w == 128 / 255.0f);
    CHECK(has_warning(s, "a.gltf: 1 texture use(s) have a sampler wrap mode other than REPEAT"));
    CHECK(s.warnings.size() == 1);
}

TEST_CASE("gltf textures: data: URI and GLB buffer view images go to load_texture_from_memory",
          "[scene][gltf][parser][attributes]") {
    TempDir dir;
    const std::string png = write_png(dir.path / "t.png", 2, 2, 4, kRgba2x2);
    // Whether the texture module decodes images from memory yet (it may be provisional)
    std::vector<std::string> w;
    const wp::Texture direct = wp::load_texture_from_memory(png, "direct", wp::TextureUse::Colour, w);
    const bool decodes = direct.width == 2 && direct.height == 2;
    if (!decodes) WARN("load_texture_from_memory does not decode yet: texel checks skipped");

    for (bool glb : {false, true}) {
        Gltf g;
        json image = glb ? json{{"bufferView", g.view(png)}, {"mimeType", "image/png"}}
                         : json{{"uri", "data:image/png;base64," + base64(png)}};
        int img = g.add("images", image);
        int tex = g.add("textures", {{"source", img}});
        int mat = g.add("materials", {{"pbrMetallicRoughness",
                                       {{"metallicFactor", 0}, {"baseColorTexture", {{"index", tex}}}}}});
        g.root({{"mesh", g.mesh(json::array({textured_triangle(g, mat)}))}});
        wp::Scene s = glb ? wp::parse_gltf(g.glb(), "m.glb") : wp::parse_gltf(g.gltf(), "m.gltf");
        REQUIRE(s.textures.size() == 1);
        REQUIRE(s.materials.at(0).albedo_map.image == 0);
        CHECK_THAT(s.textures[0].source, Contains("images[0]"));
        if (decodes) {
            CHECK(s.textures[0].width == 2);
            CHECK(texel(s.textures[0], 1, 1).w == 128 / 255.0f);
            CHECK(texel(s.textures[0], 0, 1) == glm::vec4(0, 0, 1, 1));
        }
    }
    // An image buffer view outside its buffer is an error naming the image
    Gltf g;
    int img = g.add("images", {{"bufferView", g.view(png)}, {"mimeType", "image/png"}});
    g.j["bufferViews"][0]["byteLength"] = png.size() + 100;
    int tex = g.add("textures", {{"source", img}});
    int mat = g.add("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", tex}}}}}});
    g.root({{"mesh", g.mesh(json::array({textured_triangle(g, mat)}))}});
    CHECK_THAT(error_of([&] { wp::parse_gltf(g.glb(), "bad.glb"); }),
               Contains("bad.glb") && Contains("images[0]") && Contains("lies outside"));
}

TEST_CASE("gltf textures: metallic-roughness, emissive and normal textures; occlusion noted",
          "[scene][gltf][parser][attributes]") {
    TempDir dir;
    write_png(dir.path / "c.png", 1, 1, 3, {10, 20, 30});
    Gltf g;
    int img = g.add("images", {{"uri", "c.png"}});
    int tex = g.add("textures", {{"source", img}});
    int metal = g.add("materials", {{"pbrMetallicRoughness",
                                     {{"metallicFactor", 1}, {"roughnessFactor", 0.5},
                                      {"metallicRoughnessTexture", {{"index", tex}}}}},
                                    {"normalTexture", {{"index", tex}, {"scale", 0.25}}},
                                    {"occlusionTexture", {{"index", tex}}}});
    int lamp = g.add("materials", {{"pbrMetallicRoughness", {{"metallicFactor", 0}}},
                                   {"emissiveFactor", {1, 2, 3}},
                                   {"emissiveTexture", {{"index", tex}}}});
    int dark = g.add("materials", {{"pbrMetallicRoughness", {{"metallicFactor", 0}}},
                                   {"emissiveTexture", {{"index", tex}}}});  // factor 0
    g.root({{"mesh", g.mesh(json::array({textured_triangle(g, metal), textured_triangle(g, lamp),
                                         textured_triangle(g, dark)}))}});
    wp::Scene s = wp::load_gltf(dir.write("m.gltf", g.gltf()));
    REQUIRE(s.materials.size() == 3);
    const wp::Material &a = s.materials[0], &b = s.materials[1], &c = s.materials[2];
    CHECK(a.kind == wp::MaterialKind::Glossy);
    CHECK(a.alpha == Approx(0.25f));  // roughnessFactor², the texture's G multiplies on the device
    CHECK(a.roughness_map.used());
    CHECK(a.normal_map.used());
    CHECK(a.normal_scale == 0.25f);
    CHECK(!a.albedo_map.used());
    CHECK(b.emission == glm::vec3(1, 2, 3));
    CHECK(b.emission_map.used());
    CHECK(!c.emission_map.used());  // emissiveFactor 0 (the default): the map changes nothing
    CHECK(has_warning(s, "m.gltf: 1 material(s) have a metallicRoughnessTexture"));
    CHECK(has_warning(s, "m.gltf: 1 material(s) have an occlusionTexture; ignored"));
    // Colour and data uses of one image are loaded once each
    CHECK(s.textures.size() <= 2);
    // A texture index out of range is an error naming the material slot
    Gltf bad;
    int bm = bad.add("materials", {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 3}}}}}});
    bad.root({{"mesh", bad.mesh(json::array({textured_triangle(bad, bm)}))}});
    CHECK_THAT(error_of([&] { wp::parse_gltf(bad.gltf(), "bad.gltf"); }),
               Contains("bad.gltf: materials[0].pbrMetallicRoughness.baseColorTexture refers to "
                        "textures[3], but there are 0"));
}

TEST_CASE("gltf alpha: MASK with its cutoff and factor; BLEND as MASK at 0.5; cut-out primitives",
          "[scene][gltf][parser][attributes]") {
    TempDir dir;
    write_png(dir.path / "a.png", 2, 2, 4, kRgba2x2);
    write_png(dir.path / "o.png", 1, 1, 4, {255, 255, 255, 255});
    Gltf g;
    int ta = g.add("textures", {{"source", g.add("images", {{"uri", "a.png"}})}});
    int to = g.add("textures", {{"source", g.add("images", {{"uri", "o.png"}})}});
    auto mat = [&](const char* mode, double a, int tex, double cutoff) {
        json pbr = {{"baseColorFactor", {1, 1, 1, a}}, {"metallicFactor", 0}};
        if (tex >= 0) pbr["baseColorTexture"] = {{"index", tex}};
        json m = {{"alphaMode", mode}, {"pbrMetallicRoughness", pbr}};
        if (cutoff >= 0) m["alphaCutoff"] = cutoff;
        return g.add("materials", m);
    };
    std::vector<int> mats = {
        mat("MASK", 0.8, ta, 0.3),   // 0: texture A x 0.8 against 0.3
        mat("MASK", 0.2, -1, -1),    // 1: no texture, 0.2 < 0.5: nothing left
        mat("MASK", 0.9, -1, -1),    // 2: no texture, 0.9 >= 0.5: opaque
        mat("BLEND", 1.0, ta, 0.9),  // 3: as MASK, cutoff 0.5 (alphaCutoff is MASK's only)
        mat("OPAQUE", 0.5, ta, -1),  // 4: alpha ignored
        mat("MASK", 1.0, to, -1),    // 5: a texture opaque everywhere: nothing to test
    };
    json prims = json::array();
    for (int m : mats) prims.push_back(textured_triangle(g, m));
    g.root({{"mesh", g.mesh(prims)}});
    wp::Scene s = wp::load_gltf(dir.write("alpha.gltf", g.gltf()));
    CHECK(s.triangle_count() == 5);  // primitive 1 is gone
    REQUIRE(s.materials.size() == 5);
    const wp::Material& mask = s.materials[0];
    REQUIRE(mask.alpha_map.used());
    CHECK(mask.alpha_map.image == mask.albedo_map.image);  // the base colour texture's A
    CHECK(mask.alpha_factor == Approx(0.8f));
    CHECK(mask.alpha_cutoff == Approx(0.3f));
    CHECK(!s.materials[1].alpha_map.used());  // (material 2 of the file)
    const wp::Material& blend = s.materials[2];
    REQUIRE(blend.alpha_map.used());
    CHECK(blend.alpha_cutoff == 0.5f);
    CHECK(blend.alpha_factor == 1.0f);
    CHECK(!s.materials[3].alpha_map.used());
    CHECK(!s.materials[4].alpha_map.used());
    CHECK(s.materials[4].albedo_map.used());
    CHECK(has_warning(s, "alpha.gltf: 1 material(s) use alphaMode BLEND; approximated as MASK with cutoff 0.5"));
    CHECK(has_warning(s, "alpha.gltf: 1 primitive(s) have alphaMode MASK/BLEND with base colour alpha below"));
    CHECK(s.warnings.size() == 2);
}

TEST_CASE("gltf KHR_texture_transform: T x R x S by the extension's examples; texCoord noted",
          "[scene][gltf][parser][attributes]") {
    TempDir dir;
    write_png(dir.path / "c.png", 1, 1, 3, {10, 20, 30});
    Gltf g;
    int tex = g.add("textures", {{"source", g.add("images", {{"uri", "c.png"}})}});
    auto mat = [&](json transform) {
        return g.add("materials",
                     {{"pbrMetallicRoughness",
                       {{"metallicFactor", 0},
                        {"baseColorTexture",
                         {{"index", tex}, {"extensions", {{"KHR_texture_transform", transform}}}}}}}});
    };
    // The extension's first example: "the lower left quadrant of the source image, rotated
    // clockwise 90°"; second: "inverts the T axis"; third: a texCoord override
    int quadrant = mat({{"offset", {0, 1}}, {"rotation", 1.57079632679}, {"scale", {0.5, 0.5}}});
    int flip = mat({{"offset", {0, 1}}, {"scale", {1, -1}}});
    int other = mat({{"texCoord", 1}});
    g.root({{"mesh", g.mesh(json::array({textured_triangle(g, quadrant), textured_triangle(g, flip),
                                         textured_triangle(g, other)}))}});
    wp::Scene s = wp::load_gltf(dir.write("tt.gltf", g.gltf()));
    REQUIRE(s.materials.size() == 3);
    const glm::mat3 A = s.materials[0].albedo_map.uv_transform;
    // By hand: S (u, v) = (u/2, v/2); R by 90° (columns (cos, sin), (-sin, cos)) gives
    // (-v/2, u/2); T adds (0, 1): (u, v) -> (-v/2, u/2 + 1)
    auto apply = [](const glm::mat3& M, glm::vec2 uv) { return glm::vec2(M * glm::vec3(uv, 1.0f)); };
    CHECK(near2(apply(A, {0, 0}), {0, 1}));
    CHECK(near2(apply(A, {1, 0}), {0, 1.5f}));
    CHECK(near2(apply(A, {0, 1}), {-0.5f, 1}));
    CHECK(near2(apply(A, {0.5f, 0.5f}), {-0.25f, 1.25f}));
    CHECK(A[0][2] == 0.0f);
    CHECK(A[1][2] == 0.0f);
    CHECK(A[2][2] == 1.0f);
    // (u, v) -> (u, 1 - v)
    const glm::mat3 F = s.materials[1].albedo_map.uv_transform;
    CHECK(near2(apply(F, {0.25f, 0.0f}), {0.25f, 1.0f}));
    CHECK(near2(apply(F, {0.25f, 0.75f}), {0.25f, 0.25f}));
    CHECK(s.materials[2].albedo_map.used());
    CHECK(s.materials[2].albedo_map.uv_transform == glm::mat3(1.0f));
    CHECK(has_warning(s, "tt.gltf: 1 texture use(s) ask for a texCoord set other than 0"));
}
