// test_scene_mitsuba.cpp — the Mitsuba 3 scene reader (scene/mitsuba_loader.h).
//
// Every expected value comes from somewhere else than the reader: hand-computed corners,
// areas and volumes of the shapes, the analytic fov conversions, hand-evaluated Fresnel
// reflectances, hand-written files, and the triangle counts that ../shared/scenes/README.md
// states. Tests tagged [parser] parse only (no OpenCL), so they also run under the sanitizers.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>

#include <glm/glm.hpp>

#include "image/image.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/load.h"
#include "scene/mitsuba_loader.h"
#include "support.h"
#include "util/limits.h"
#include "util/error.h"
#include "util/splitmix.h"
#include "temp_dir.h"

using namespace wp;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

using wp::test::TempDir;

constexpr double kPi = std::numbers::pi;

Scene parse(const std::string& body, const MitsubaParams& params = {}) {
    return parse_mitsuba("<scene version=\"3.0.0\">\n" + body + "\n</scene>\n", "test.xml", params);
}

// The message of the wp::Error that parsing `xml` (a whole file) throws.
std::string error_of(const std::string& xml, const MitsubaParams& params = {}) {
    try {
        parse_mitsuba(xml, "test.xml", params);
    } catch (const Error& e) {
        return e.what();
    }
    FAIL("no error for:\n" << xml);
    return "";
}

std::string error_of_body(const std::string& body) {
    return error_of("<scene version=\"3.0.0\">\n" + body + "\n</scene>\n");
}

using test::Measure;
using test::measure;
using test::texel_at;
using test::write_exr;

bool has_warning(const Scene& s, const std::string& text) {
    for (const auto& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

int count_warnings(const Scene& s, const std::string& text) {
    int n = 0;
    for (const auto& w : s.warnings)
        n += w.find(text) != std::string::npos;
    return n;
}

std::string all_warnings(const Scene& s) {
    std::string out;
    for (const auto& w : s.warnings)
        out += w + "\n";
    return out;
}

void check_vec(glm::dvec3 got, glm::dvec3 want, double tol = 1e-5) {
    INFO("got (" << got.x << ", " << got.y << ", " << got.z << "), want (" << want.x << ", "
                 << want.y << ", " << want.z << ")");
    CHECK(glm::length(got - want) <= tol * std::max(1.0, glm::length(want)));
}

const char* kRect = R"(<shape type="rectangle"/>)";

} // namespace

// --- Shapes ----------------------------------------------------------------------------------

TEST_CASE("mitsuba: rectangle is [-1,1]^2 in z = 0 facing +z, then to_world",
          "[scene][mitsuba][parser]") {
    Scene s = parse(R"(<shape type="rectangle">
      <transform name="to_world"><scale x="2" y="3"/><translate x="1" y="2" z="3"/></transform>
    </shape>)");
    REQUIRE(s.triangle_count() == 2);
    Measure m = measure(s);
    // Corners (-1,-1) (1,1) scaled by (2,3), moved by (1,2,3): (-1,-1,3) to (3,5,3)
    check_vec(m.lo, {-1, -1, 3});
    check_vec(m.hi, {3, 5, 3});
    CHECK(m.area == Approx(24.0));
    check_vec(glm::normalize(m.normal_sum), {0, 0, 1}); // front = +z
    CHECK(s.materials.size() == 1);
    CHECK(s.materials[0].kind == MaterialKind::Diffuse); // Mitsuba's default BSDF
    CHECK(s.materials[0].albedo == glm::vec3(0.5f));
}

TEST_CASE("mitsuba: cube is the closed [-1,1]^3 with outward winding", "[scene][mitsuba][parser]") {
    Scene s = parse(R"(<shape type="cube">
      <transform name="to_world"><scale value="0.5, 1, 2"/><translate value="0, 10, 0"/></transform>
    </shape>)");
    REQUIRE(s.triangle_count() == 12);
    Measure m = measure(s);
    check_vec(m.lo, {-0.5, 9, -2});
    check_vec(m.hi, {0.5, 11, 2});
    CHECK(m.volume == Approx(1.0 * 2.0 * 4.0)); // positive: outward
    CHECK(m.area == Approx(2 * (1.0 * 2.0 + 2.0 * 4.0 + 1.0 * 4.0)));
}

TEST_CASE("mitsuba: a mirroring to_world keeps the cube's winding outward",
          "[scene][mitsuba][parser]") {
    Scene s = parse(R"(<shape type="cube">
      <transform name="to_world"><scale x="-1"/></transform></shape>)");
    CHECK(measure(s).volume == Approx(8.0));
}

TEST_CASE("mitsuba: sphere keeps the area 4 pi r^2 and its centre, normals outward",
          "[scene][mitsuba][parser]") {
    Scene s = parse(R"(<shape type="sphere">
      <point name="center" x="1" y="2" z="3"/><float name="radius" value="0.5"/></shape>
    <shape type="sphere">
      <float name="radius" value="0.25"/>
      <transform name="to_world"><scale value="4"/><translate x="-10"/></transform>
    </shape>)");
    REQUIRE(s.materials.size() == 1);
    REQUIRE(s.triangle_count() == 2 * 5120);
    // Both spheres share the default material; split them by vertex position
    Scene a = s, b = s;
    a.triangles.resize(5120);
    a.material_ids.resize(5120);
    b.triangles.erase(b.triangles.begin(), b.triangles.begin() + 5120);
    b.material_ids.erase(b.material_ids.begin(), b.material_ids.begin() + 5120);
    Measure ma = measure(a), mb = measure(b);
    CHECK(ma.area == Approx(4 * kPi * 0.25).epsilon(1e-4));
    check_vec(0.5 * (ma.lo + ma.hi), {1, 2, 3});
    CHECK(ma.volume > 0.0);
    // to_world after center/radius: radius 0.25 * 4 = 1, centre moved to (-10, 0, 0)
    CHECK(mb.area == Approx(4 * kPi * 1.0).epsilon(1e-4));
    check_vec(0.5 * (mb.lo + mb.hi), {-10, 0, 0});
    // The inscribed polyhedron is scaled out slightly: vertices within 0.5% of the radius
    CHECK(mb.hi.x - mb.lo.x == Approx(2.0).epsilon(5e-3));
}

TEST_CASE("mitsuba: disk and cylinder keep their areas", "[scene][mitsuba][parser]") {
    Scene d = parse(
        R"(<shape type="disk"><transform name="to_world"><scale value="2"/></transform></shape>)");
    Measure md = measure(d);
    CHECK(md.area == Approx(kPi * 4).epsilon(1e-5));
    check_vec(glm::normalize(md.normal_sum), {0, 0, 1});
    Scene c = parse(R"(<shape type="cylinder">
      <point name="p0" x="0" y="0" z="0"/><point name="p1" x="0" y="3" z="0"/>
      <float name="radius" value="0.5"/></shape>)");
    Measure mc = measure(c);
    CHECK(mc.area == Approx(2 * kPi * 0.5 * 3).epsilon(1e-5));
    check_vec(mc.lo, {-0.5, 0, -0.5}, 1e-2);
    check_vec(mc.hi, {0.5, 3, 0.5}, 1e-2);
    // Outward: every triangle's normal points away from the axis (the y axis)
    int inward = 0;
    for (const auto& t : c.triangles) {
        glm::dvec3 a(c.positions[t.x]), b(c.positions[t.y]), e(c.positions[t.z]);
        glm::dvec3 n = glm::cross(b - a, e - a), mid = (a + b + e) / 3.0;
        inward += glm::dot(n, glm::dvec3(mid.x, 0, mid.z)) <= 0.0;
    }
    CHECK(inward == 0);
}

TEST_CASE("mitsuba: flip_normals reverses the winding", "[scene][mitsuba][parser]") {
    Scene s =
        parse(R"(<shape type="rectangle"><boolean name="flip_normals" value="true"/></shape>)");
    check_vec(glm::normalize(measure(s).normal_sum), {0, 0, -1});
}

// --- Transforms ------------------------------------------------------------------------------

TEST_CASE("mitsuba: transform steps apply in document order (M = new * M)",
          "[scene][mitsuba][parser]") {
    // translate then scale: x in [-1, 1] -> [0, 2] -> [0, 4]
    Scene a = parse(R"(<shape type="rectangle"><transform name="to_world">
      <translate x="1"/><scale value="2"/></transform></shape>)");
    check_vec(measure(a).lo, {0, -2, 0});
    check_vec(measure(a).hi, {4, 2, 0});
    // scale then translate: [-2, 2] -> [-1, 3]
    Scene b = parse(R"(<shape type="rectangle"><transform name="to_world">
      <scale value="2"/><translate x="1"/></transform></shape>)");
    check_vec(measure(b).lo, {-1, -2, 0});
    check_vec(measure(b).hi, {3, 2, 0});
}

TEST_CASE("mitsuba: rotate (axis and angle, right-handed), matrix (row by row), lookat",
          "[scene][mitsuba][parser]") {
    // 90 degrees about +y takes +z to +x: the rectangle then faces +x
    for (const char* rot :
         {R"(<rotate y="1" angle="90"/>)", R"(<rotate value="0, 1, 0" angle="90"/>)"}) {
        Scene s = parse(std::string(R"(<shape type="rectangle"><transform name="to_world">)") +
                        rot + "</transform></shape>");
        check_vec(glm::normalize(measure(s).normal_sum), {1, 0, 0});
        check_vec(measure(s).lo, {0, -1, -1});
        check_vec(measure(s).hi, {0, 1, 1});
    }
    // A 4 x 4 matrix is written row by row: the last column is the translation
    Scene m = parse(R"(<shape type="cube"><transform name="to_world">
      <matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/></transform></shape>)");
    check_vec(0.5 * (measure(m).lo + measure(m).hi), {5, 6, 7});
    // 3 x 3: a shear x += y
    Scene sh = parse(R"(<shape type="rectangle"><transform name="to_world">
      <matrix value="1 1 0  0 1 0  0 0 1"/></transform></shape>)");
    check_vec(measure(sh).lo, {-2, -1, 0});
    check_vec(measure(sh).hi, {2, 1, 0});
    // lookat: z -> target - origin = +x, y -> up, x -> left = up x dir = -z
    Scene l = parse(R"(<shape type="rectangle"><transform name="to_world">
      <lookat origin="1, 2, 3" target="2, 2, 3" up="0, 1, 0"/></transform></shape>)");
    check_vec(glm::normalize(measure(l).normal_sum), {1, 0, 0});
    check_vec(measure(l).lo, {1, 1, 2});
    check_vec(measure(l).hi, {1, 3, 4});
}

// --- Sensor ----------------------------------------------------------------------------------

TEST_CASE("mitsuba: sensor lookat gives the camera, film size and sample count",
          "[scene][mitsuba][parser]") {
    Scene s = parse(std::string(kRect) + R"(
    <sensor type="perspective">
      <transform name="to_world"><lookat origin="0, 1, 6.8" target="0, 1, 0" up="0, 1, 0"/></transform>
      <float name="fov" value="40"/>
      <sampler type="independent"><integer name="sample_count" value="37"/><integer name="seed" value="9"/></sampler>
      <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/></film>
    </sensor>)");
    const Camera& c = s.camera;
    check_vec(c.position, {0, 1, 6.8});
    check_vec(glm::normalize(glm::dvec3(c.target - c.position)), {0, 0, -1});
    check_vec(glm::normalize(glm::dvec3(c.up)), {0, 1, 0});
    CHECK(c.width == 200);
    CHECK(c.height == 100);
    // fov_axis x (the default): tan(v/2) = tan(20 deg) * 100 / 200
    CHECK(c.vfov_deg == Approx(2.0 * std::atan(std::tan(20.0 * kPi / 180.0) / 2.0) * 180.0 / kPi));
    CHECK(c.vfov_deg == Approx(20.628).epsilon(1e-4));
    CHECK(s.render.spp == 37);
    CHECK(s.render.seed == 9u);
    CHECK_FALSE(has_warning(s, "mirror"));
}

TEST_CASE("mitsuba: fov_axis x, y, smaller, larger, diagonal and focal_length",
          "[scene][mitsuba][parser]") {
    auto vfov = [](const std::string& fov, int w, int h) {
        Scene s = parse(std::string(kRect) + "<sensor type=\"perspective\">" + fov +
                        "<film type=\"hdrfilm\"><integer name=\"width\" value=\"" +
                        std::to_string(w) + "\"/><integer name=\"height\" value=\"" +
                        std::to_string(h) + "\"/></film></sensor>");
        return double(s.camera.vfov_deg);
    };
    auto deg = [](double rad) { return rad * 180.0 / kPi; };
    const std::string f90 = R"(<float name="fov" value="90"/>)";
    auto axis = [&](const char* a) {
        return f90 + "<string name=\"fov_axis\" value=\"" + a + "\"/>";
    };
    // Wide film 200 x 100, fov 90 (tan 45 = 1)
    CHECK(vfov(f90, 200, 100) == Approx(deg(2 * std::atan(0.5)))); // 53.130
    CHECK(vfov(axis("x"), 200, 100) == Approx(53.1301).epsilon(1e-5));
    CHECK(vfov(axis("y"), 200, 100) == Approx(90.0));
    CHECK(vfov(axis("smaller"), 200, 100) == Approx(90.0)); // smaller side = y
    CHECK(vfov(axis("larger"), 200, 100) == Approx(53.1301).epsilon(1e-5));
    CHECK(vfov(axis("diagonal"), 200, 100) == Approx(deg(2 * std::atan(1 / std::sqrt(5.0)))));
    // Tall film 100 x 200: the smaller side is x; tan(v/2) = 1 * 200 / 100
    CHECK(vfov(axis("smaller"), 100, 200) == Approx(deg(2 * std::atan(2.0))));
    CHECK(vfov(axis("larger"), 100, 200) == Approx(90.0));
    // 3:4 diagonal: tan(v/2) = 1 * 400 / 500
    CHECK(vfov(axis("diagonal"), 300, 400) == Approx(deg(2 * std::atan(0.8))));
    // 50 mm on a 36 x 24 mm film (a 300 x 200 image): vertical fov 2 atan(12 / 50)
    CHECK(vfov(R"(<string name="focal_length" value="50mm"/>)", 300, 200) ==
          Approx(deg(2 * std::atan(12.0 / 50.0))).epsilon(1e-5));
    CHECK_THAT(error_of_body(std::string(kRect) + "<sensor type=\"perspective\">" + axis("z") +
                             "</sensor>"),
               Contains("fov_axis 'z'"));
}

TEST_CASE("mitsuba: a sensor matrix whose column 0 points right is reported as mirrored",
          "[scene][mitsuba][parser]") {
    Scene s = parse(std::string(kRect) + R"(<sensor type="perspective"><transform name="to_world">
      <scale x="-1"/><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>)");
    CHECK(has_warning(s, "mirrors the image"));
    // Without a sensor the camera frames the scene from +z, with a warning
    Scene n = parse(kRect);
    CHECK(n.camera.position.z > 0.0f);
    CHECK(has_warning(n, "no <sensor>"));
}

// --- Parameters ------------------------------------------------------------------------------

TEST_CASE("mitsuba: $parameters take <default> values, overrides win, undefined ones fail",
          "[scene][mitsuba][parser]") {
    const std::string xml = R"(<scene version="3.0.0">
  <default name="res" value="64"/>
  <default name="kind" value="rectangle"/>
  <default name="spp" value="16"/>
  <default name="res" value="999"/>
  <shape type="$kind"/>
  <sensor type="perspective">
    <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
    <film type="hdrfilm"><integer name="width" value="$res"/><integer name="height" value="${res}"/></film>
  </sensor>
</scene>)";
    // "${res}" is not Mitsuba syntax: '$' must be followed by a name
    CHECK_THAT(error_of(xml),
               Contains("test.xml:9:") && Contains("'$' must be followed by a parameter name"));
    std::string ok = std::regex_replace(xml, std::regex(R"(\$\{res\})"), "$$res");
    Scene a = parse_mitsuba(ok, "test.xml");
    CHECK(a.camera.width == 64); // the first <default> wins
    CHECK(a.render.spp == 16);
    CHECK(a.triangle_count() == 2);
    Scene b = parse_mitsuba(ok, "test.xml", {{"res", "32"}, {"kind", "cube"}});
    CHECK(b.camera.width == 32);
    CHECK(b.camera.height == 32);
    CHECK(b.triangle_count() == 12);
    // The longest name after '$' is the parameter: $spp0 is not $spp
    std::string spp0 = std::regex_replace(ok, std::regex(R"(\$spp)"), "$$spp0");
    CHECK_THAT(error_of(spp0), Contains("test.xml:8:") && Contains("undefined parameter $spp0"));
    // Defaults count from where they stand
    CHECK_THAT(error_of(R"(<scene version="3.0.0">
  <shape type="$kind"/>
  <default name="kind" value="cube"/>
</scene>)"),
               Contains("test.xml:2:3") && Contains("undefined parameter $kind"));
    CHECK_THROWS_WITH(parse_mitsuba(ok, "test.xml", {{"bad name", "1"}}), Contains("bad name"));
}

TEST_CASE("mitsuba: parameter expansion is bounded", "[scene][mitsuba][parser]") {
    std::string xml = "<scene version=\"3.0.0\">\n<default name=\"a0\" value=\"" +
                      std::string(1000, 'x') + "\"/>\n";
    for (int i = 1; i < 20; ++i)
        xml += fmt::format("<default name=\"a{}\" value=\"$a{}$a{}$a{}$a{}\"/>\n", i, i - 1, i - 1,
                           i - 1, i - 1);
    xml += "<shape type=\"$a19\"/></scene>";
    CHECK_THAT(error_of(xml), Contains("expands to more than"));
}

// --- Materials -------------------------------------------------------------------------------

TEST_CASE("mitsuba: BSDFs map to wavepath's materials of the same model",
          "[scene][mitsuba][parser]") {
    Scene s = parse(R"(
  <bsdf type="twosided" id="white"><bsdf type="diffuse"><rgb name="reflectance" value="0.1, 0.2, 0.3"/></bsdf></bsdf>
  <bsdf type="twosided" id="metal"><bsdf type="conductor">
      <rgb name="eta" value="1.5, 2, 0"/><rgb name="k" value="0, 1, 1"/>
      <spectrum name="specular_reflectance" value="0.5"/></bsdf></bsdf>
  <bsdf type="twosided" id="gold"><bsdf type="conductor"><string name="material" value="Au"/></bsdf></bsdf>
  <bsdf type="twosided" id="mirror"><bsdf type="conductor"/></bsdf>
  <bsdf type="twosided" id="rough"><bsdf type="roughconductor">
      <float name="alpha" value="0.5"/><string name="distribution" value="ggx"/></bsdf></bsdf>
  <bsdf type="twosided" id="beck1"><bsdf type="roughconductor"><float name="alpha" value="0.1"/>
      <string name="material" value="Cu"/></bsdf></bsdf>
  <bsdf type="twosided" id="beck2"><bsdf type="roughconductor"/></bsdf>
  <bsdf type="dielectric" id="water"><string name="int_ior" value="water"/><string name="ext_ior" value="air"/></bsdf>
  <bsdf type="dielectric" id="glass"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/>
      <rgb name="specular_transmittance" value="0.9, 0.8, 0.7"/>
      <rgb name="specular_reflectance" value="0.6, 0.5, 0.4"/></bsdf>
  <bsdf type="plastic" id="p1"><rgb name="diffuse_reflectance" value="0.3, 0.4, 0.5"/>
      <rgb name="specular_reflectance" value="0.7"/><float name="int_ior" value="1.6"/>
      <boolean name="nonlinear" value="true"/></bsdf>
  <bsdf type="roughplastic" id="p2"/>
  <bsdf type="plastic" id="p3"/>
  <shape type="rectangle" id="r0"><ref id="white"/></shape>
  <shape type="rectangle" id="r1"><ref id="metal"/></shape>
  <shape type="rectangle" id="r2"><ref id="gold"/></shape>
  <shape type="rectangle" id="r3"><ref id="mirror"/></shape>
  <shape type="rectangle" id="r4"><ref id="rough"/></shape>
  <shape type="rectangle" id="r5"><ref id="beck1"/></shape>
  <shape type="rectangle" id="r6"><ref id="beck2"/></shape>
  <shape type="rectangle" id="r7"><ref id="water"/></shape>
  <shape type="rectangle" id="r8"><ref id="glass"/></shape>
  <shape type="rectangle" id="r9"><ref id="p1"/></shape>
  <shape type="rectangle" id="r10"><ref id="p2"/></shape>
  <shape type="rectangle" id="r11"><ref id="p3"/></shape>
  <shape type="rectangle" id="r12"><ref id="white"/></shape>)");
    INFO(all_warnings(s));
    REQUIRE(s.triangle_count() == 26);
    auto mat = [&](int shape) { return s.materials.at(s.material_ids.at(2 * shape)); };
    CHECK(mat(0).kind == MaterialKind::Diffuse);
    CHECK(mat(0).albedo == glm::vec3(0.1f, 0.2f, 0.3f));
    CHECK(s.material_ids[0] == s.material_ids[24]); // one material per referenced BSDF
    // Conductor: η and k as given, specular_reflectance the tint (it scales the Fresnel term)
    CHECK(mat(1).kind == MaterialKind::Conductor);
    CHECK(mat(1).eta == glm::vec3(1.5f, 2.0f, 0.0f));
    CHECK(mat(1).k == glm::vec3(0.0f, 1.0f, 1.0f));
    CHECK(mat(1).albedo == glm::vec3(0.5f));
    // Gold from the table (Tungsten's RGB fit; Mitsuba 3.9.1 scalar_rgb: 0.143036, 3.983)
    CHECK(mat(2).kind == MaterialKind::Conductor);
    CHECK(mat(2).eta.x == Approx(0.143036).epsilon(2e-3));
    CHECK(mat(2).k.x == Approx(3.983).epsilon(2e-3));
    CHECK(mat(2).albedo == glm::vec3(1.0f));
    // material "none" (the default): η 0, k 1, F = 1 at every angle
    CHECK(mat(3).kind == MaterialKind::Conductor);
    CHECK(mat(3).eta == glm::vec3(0.0f));
    CHECK(mat(3).k == glm::vec3(1.0f));
    // roughconductor: the distribution as given (default Beckmann), Mitsuba's separable G
    CHECK(mat(4).kind == MaterialKind::RoughConductor);
    CHECK(mat(4).alpha == 0.5f);
    CHECK_FALSE(mat(4).alpha_v.has_value());
    CHECK(mat(4).distribution == MicrofacetModel::GGX);
    CHECK(mat(4).separable_g);
    CHECK(mat(5).kind == MaterialKind::RoughConductor);
    CHECK(mat(5).distribution == MicrofacetModel::Beckmann);
    CHECK(mat(5).alpha == 0.1f);
    CHECK(mat(5).eta.y == Approx(0.92375).epsilon(2e-3));  // Cu, Mitsuba: 0.92375, 2.45305
    CHECK(mat(5).k.y == Approx(2.45305).epsilon(2e-3));
    CHECK(mat(6).distribution == MicrofacetModel::Beckmann);  // Mitsuba's defaults
    CHECK(mat(6).alpha == 0.1f);
    CHECK(mat(6).separable_g);
    // dielectric: η = int / ext, transmittance = albedo, reflection tint = specular
    CHECK(mat(7).kind == MaterialKind::Glass);
    CHECK(mat(7).ior == Approx(1.3330 / 1.000277));
    CHECK(mat(7).specular == glm::vec3(1.0f));
    CHECK(mat(7).albedo == glm::vec3(1.0f));
    CHECK(mat(8).ior == Approx(1.5));
    CHECK(mat(8).albedo == glm::vec3(0.9f, 0.8f, 0.7f));
    CHECK(mat(8).specular == glm::vec3(0.6f, 0.5f, 0.4f));
    // plastic: diffuse_reflectance = albedo, specular_reflectance = specular, η, nonlinear
    CHECK(mat(9).kind == MaterialKind::Plastic);
    CHECK(mat(9).albedo == glm::vec3(0.3f, 0.4f, 0.5f));
    CHECK(mat(9).specular == glm::vec3(0.7f));
    CHECK(mat(9).ior == Approx(1.6 / 1.000277));  // ext_ior defaults to air
    CHECK(mat(9).nonlinear);
    // roughplastic with Mitsuba's defaults: diffuse 0.5, polypropylene in air, Beckmann 0.1
    CHECK(mat(10).kind == MaterialKind::RoughPlastic);
    CHECK(mat(10).albedo == glm::vec3(0.5f));
    CHECK(mat(10).specular == glm::vec3(1.0f));
    CHECK(mat(10).ior == Approx(1.49 / 1.000277));
    CHECK(mat(10).distribution == MicrofacetModel::Beckmann);
    CHECK(mat(10).alpha == 0.1f);
    CHECK(mat(10).separable_g);
    CHECK_FALSE(mat(10).nonlinear);
    CHECK(mat(11).kind == MaterialKind::Plastic);
    // Nothing is approximated but the plastics' one-sidedness (not inside twosided)
    CHECK(count_warnings(s, "one-sided") == 1);
    CHECK(has_warning(s, "(3 times"));
    CHECK(s.warnings.size() == 2);  // and the missing sensor's
}

TEST_CASE("mitsuba: a bare diffuse warns once that it is treated as two-sided; area emitters "
          "get their own material",
          "[scene][mitsuba][parser]") {
    Scene s = parse(R"(
  <bsdf type="diffuse" id="d"><rgb name="reflectance" value="0.4"/></bsdf>
  <shape type="rectangle"><ref id="d"/></shape>
  <shape type="rectangle"><ref id="d"/>
    <emitter type="area"><rgb name="radiance" value="1, 2, 3"/></emitter></shape>
  <shape type="rectangle"><bsdf type="diffuse"/></shape>
  <emitter type="constant"><rgb name="radiance" value="0.25"/></emitter>
  <emitter type="constant"><spectrum name="radiance" value="0.5"/></emitter>
  <emitter type="point"/>)");
    INFO(all_warnings(s));
    CHECK(count_warnings(s, "treats it as two-sided") == 1);
    CHECK(has_warning(s, "(2 times; the first here)"));
    REQUIRE(s.materials.size() == 3);
    const Material& plain = s.materials[s.material_ids[0]];
    const Material& lit = s.materials[s.material_ids[2]];
    CHECK(plain.albedo == glm::vec3(0.4f));
    CHECK_FALSE(plain.emissive());
    CHECK(lit.albedo == glm::vec3(0.4f));
    CHECK(lit.emission == glm::vec3(1, 2, 3));
    CHECK(s.background == glm::vec3(0.75f));
    CHECK(has_warning(s, "emitter 'point' is not supported"));
}

TEST_CASE("mitsuba: unsupported kinds and properties warn, never silently",
          "[scene][mitsuba][parser]") {
    Scene s = parse(R"(
  <integrator type="bdpt"><integer name="max_depth" value="5"/></integrator>
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="diffuse"><float name="frobnicate" value="1"/></bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="hair"/></shape>
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="diffuse">
    <texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_color"/></texture></bsdf></bsdf></shape>
  <shape type="serialized"><string name="filename" value="x.serialized"/></shape>
  <emitter type="spot"/>
  <medium type="homogeneous" id="fog"/>
  <include filename="more.xml"/>)");
    INFO(all_warnings(s));
    CHECK(s.render.depth == 4);
    CHECK(has_warning(s, "integrator 'bdpt' is not supported"));
    CHECK(has_warning(s, "test.xml:3:"));
    CHECK(has_warning(s, "property 'frobnicate' of <bsdf type=\"diffuse\"> is not supported"));
    CHECK(has_warning(s, "bsdf 'hair' is not supported; rendered as diffuse 0.5"));
    CHECK(has_warning(s, "textures of type 'mesh_attribute' are not supported"));
    CHECK(has_warning(s, "shape 'serialized' is not supported; skipped"));
    CHECK(has_warning(s, "emitter 'spot' is not supported"));
    CHECK(has_warning(s, "<medium> at the top level is not supported"));
    CHECK(has_warning(s, "<include> is not supported"));
    CHECK(s.triangle_count() == 6);
}

TEST_CASE("mitsuba: sampled spectra become their mean; rough and thin dielectrics, anisotropic "
          "roughness",
          "[scene][mitsuba][parser]") {
    Scene s = parse(R"(
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="diffuse">
    <spectrum name="reflectance" value="400:0.2, 500:0.4, 600:0.6"/></bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="roughdielectric"><float name="alpha" value="0.3"/>
    <float name="int_ior" value="1.33"/><string name="distribution" value="ggx"/>
    <rgb name="specular_transmittance" value="0.5, 0.6, 0.7"/>
    <boolean name="sample_visible" value="false"/></bsdf></shape>
  <shape type="rectangle"><bsdf type="thindielectric">
    <rgb name="specular_reflectance" value="0.25"/></bsdf></shape>
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="roughconductor">
    <float name="alpha_u" value="0.1"/><float name="alpha_v" value="0.4"/>
    <string name="distribution" value="ggx"/></bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="roughdielectric">
    <float name="alpha_u" value="0.05"/><float name="alpha_v" value="0.2"/></bsdf></shape>
  <shape type="rectangle"><bsdf type="roughdielectric"/></shape>)");
    INFO(all_warnings(s));
    auto mat = [&](int shape) { return s.materials.at(s.material_ids.at(2 * shape)); };
    CHECK(mat(0).albedo.x == Approx(0.4f));
    CHECK(mat(0).albedo.z == Approx(0.4f));
    CHECK(has_warning(s, "mean of their values"));
    CHECK(mat(1).kind == MaterialKind::RoughDielectric);
    CHECK(mat(1).ior == Approx(1.33 / 1.000277)); // ext_ior defaults to air
    CHECK(mat(1).alpha == 0.3f);
    CHECK(mat(1).distribution == MicrofacetModel::GGX);
    CHECK(mat(1).separable_g);
    CHECK(mat(1).albedo == glm::vec3(0.5f, 0.6f, 0.7f));
    CHECK(mat(2).kind == MaterialKind::ThinDielectric);
    CHECK(mat(2).ior == Approx(1.5046 / 1.000277)); // bk7 in air, Mitsuba's defaults
    CHECK(mat(2).specular == glm::vec3(0.25f));
    CHECK(mat(2).albedo == glm::vec3(1.0f));
    // Anisotropic: alpha = α_u (along the frame's x), alpha_v = α_v
    CHECK(mat(3).kind == MaterialKind::RoughConductor);
    CHECK(mat(3).alpha == 0.1f);
    REQUIRE(mat(3).alpha_v.has_value());
    CHECK(*mat(3).alpha_v == 0.4f);
    CHECK(mat(4).kind == MaterialKind::RoughDielectric);
    CHECK(mat(4).alpha == 0.05f);
    CHECK(mat(4).alpha_v == std::optional<float>(0.2f));
    CHECK(mat(4).distribution == MicrofacetModel::Beckmann);
    CHECK(mat(5).kind == MaterialKind::RoughDielectric);  // defaults: Beckmann 0.1, bk7 / air
    CHECK(mat(5).alpha == 0.1f);
    CHECK(mat(5).ior == Approx(1.5046 / 1.000277));
    CHECK(s.warnings.size() == 2);  // the spectrum's and the missing sensor's only
}

TEST_CASE("mitsuba: roughness limits: alpha < 1e-4 is the smooth kind, alpha > 2 is 2; "
          "roughplastic is isotropic",
          "[scene][mitsuba][parser]") {
    Scene s = parse(R"(
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="roughconductor">
    <float name="alpha" value="0"/><rgb name="eta" value="0.2"/><rgb name="k" value="3"/></bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="roughdielectric"><float name="alpha" value="5e-5"/></bsdf></shape>
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="roughplastic"><float name="alpha" value="0"/>
    <rgb name="diffuse_reflectance" value="0.2"/></bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="roughconductor"><float name="alpha" value="3"/></bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="roughconductor">
    <float name="alpha_u" value="0"/><float name="alpha_v" value="0.3"/></bsdf></bsdf></shape>)");
    INFO(all_warnings(s));
    auto mat = [&](int shape) { return s.materials.at(s.material_ids.at(2 * shape)); };
    CHECK(mat(0).kind == MaterialKind::Conductor);
    CHECK(mat(0).eta == glm::vec3(0.2f));
    CHECK(mat(0).k == glm::vec3(3.0f));
    CHECK(has_warning(s, "roughconductor with alpha < 1e-4 is rendered as a smooth conductor"));
    CHECK(mat(1).kind == MaterialKind::Glass);
    CHECK(has_warning(s, "roughdielectric with alpha < 1e-4 is rendered as a smooth dielectric"));
    CHECK(mat(2).kind == MaterialKind::Plastic);
    CHECK(mat(2).albedo == glm::vec3(0.2f));
    CHECK(has_warning(s, "roughplastic with alpha < 1e-4 is rendered as a smooth plastic"));
    CHECK(mat(3).kind == MaterialKind::RoughConductor);
    CHECK(mat(3).alpha == 2.0f);
    CHECK(has_warning(s, "alpha above 2 is clamped to 2"));
    CHECK(mat(4).alpha == Approx(1e-4f));
    CHECK(mat(4).alpha_v == std::optional<float>(0.3f));
    CHECK(has_warning(s, "alpha_u or alpha_v below 0.0001 is raised to 0.0001"));
    // What Mitsuba 3 refuses, wavepath refuses: anisotropic or textured roughplastic
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"roughplastic\">\n"
                             "  <float name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" "
                             "value=\"0.2\"/></bsdf></shape>"),
               Contains("test.xml:3:3: <float name=\"alpha_u\">: roughplastic is isotropic"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"roughplastic\">\n"
                             "  <texture name=\"alpha\" type=\"checkerboard\"/></bsdf></shape>"),
               Contains("test.xml:3:3:") && Contains("roughplastic takes alpha as a number only"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"roughdielectric\">\n"
                             "  <string name=\"distribution\" value=\"phong\"/></bsdf></shape>"),
               Contains("test.xml:2:20:") && Contains("distribution 'phong' is not beckmann or ggx"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"roughconductor\">\n"
                             "  <float name=\"alpha\" value=\"-1\"/></bsdf></shape>"),
               Contains("alpha -1 must be >= 0"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"roughconductor\">\n"
                             "  <float name=\"alpha_u\" value=\"0.1\"/></bsdf></shape>"),
               Contains("alpha_u and alpha_v must be given together"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"plastic\">\n"
                             "  <float name=\"int_ior\" value=\"1000\"/></bsdf></shape>"),
               Contains("int_ior / ext_ior = ") && Contains("is out of range [0.01, 100]"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"conductor\">\n"
                             "  <rgb name=\"eta\" value=\"-1\"/></bsdf></shape>"),
               Contains("eta and k must be >= 0"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"conductor\">\n"
                             "  <rgb name=\"eta\" value=\"1\"/><string name=\"material\" value=\"Cu\"/></bsdf></shape>"),
               Contains("give either eta/k or material, not both"));
    // An unknown metal: a warning, and Mitsuba's "none"
    Scene unknown = parse(R"(<shape type="rectangle"><bsdf type="twosided"><bsdf type="conductor">
      <string name="material" value="Unobtainium"/></bsdf></bsdf></shape>)");
    CHECK(has_warning(unknown, "conductor material 'Unobtainium' is not in wavepath's table"));
    CHECK(unknown.materials.at(unknown.material_ids.at(0)).eta == glm::vec3(0.0f));
    CHECK(unknown.materials.at(unknown.material_ids.at(0)).k == glm::vec3(1.0f));
}

TEST_CASE("mitsuba: integrator max_depth N is N - 1 bounces", "[scene][mitsuba][parser]") {
    auto depth = [](const std::string& integrator) {
        return parse(std::string(kRect) + integrator).render.depth;
    };
    auto with = [](const char* v) {
        return std::string(R"(<integrator type="path"><integer name="max_depth" value=")") + v +
               "\"/></integrator>";
    };
    CHECK(depth(with("65")) == 64);
    CHECK(depth(with("3")) == 2);
    CHECK(depth(with("1")) == 0);
    // Unbounded (-1, Mitsuba's default) is the renderer's depth cap (util/limits.h):
    // Russian roulette ends the paths and the path pool stops when its queue is empty.
    CHECK(depth(with("-1")) == limits::kMaxDepth);
    CHECK(depth("<integrator type=\"path\"/>") == limits::kMaxDepth);
    CHECK(depth("") == limits::kMaxDepth);  // no integrator: path, max_depth -1
    CHECK(depth(with("1000")) == 999);
    CHECK_FALSE(has_warning(parse(std::string(kRect) + with("1000")), "capped"));
    Scene capped = parse(std::string(kRect) + with("2000000"));
    CHECK(capped.render.depth == limits::kMaxDepth);
    CHECK(has_warning(capped, "capped"));
    CHECK_THAT(error_of_body(std::string(kRect) + with("-2")),
               Contains("max_depth -2 is out of range"));
    CHECK_FALSE(parse(kRect).render.spp.has_value()); // no sampler: the program's default
}

// --- Mesh files ------------------------------------------------------------------------------

TEST_CASE("mitsuba: obj shapes load relative to the XML file, with to_world; the MTL is ignored",
          "[scene][mitsuba][parser]") {
    TempDir d;
    fs::create_directories(d.path / "meshes");
    std::ofstream(d.path / "meshes" / "quad.obj")
        << "mtllib quad.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    std::ofstream(d.path / "meshes" / "quad.mtl") << "newmtl red\nKd 1 0 0\n";
    // Without any material: the OBJ reader's note about that does not apply to Mitsuba shapes
    std::ofstream(d.path / "meshes" / "plain.obj")
        << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    std::ofstream(d.path / "scene.xml") << R"(<scene version="3.0.0">
  <shape type="obj">
    <string name="filename" value="meshes/quad.obj"/>
    <transform name="to_world"><translate x="10"/></transform>
    <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.25"/></bsdf></bsdf>
  </shape>
  <shape type="obj"><string name="filename" value="meshes/plain.obj"/></shape>
  <shape type="obj">
    <string name="filename" value="meshes/missing.obj"/>
  </shape>
</scene>
)";
    CHECK_THROWS_WITH(load_scene_file(d.path / "scene.xml"),
                      Contains("scene.xml:8:3: <shape type=\"obj\">: mesh file '") &&
                          Contains("missing.obj' not found"));
    // Without the broken shape
    std::ifstream in(d.path / "scene.xml");
    std::stringstream ss;
    ss << in.rdbuf();
    std::string xml = std::regex_replace(
        ss.str(),
        std::regex(
            R"(<shape type="obj">\s*<string name="filename" value="meshes/missing.obj"/>\s*</shape>)"),
        "");
    std::ofstream(d.path / "scene.xml") << xml;
    Scene s = load_scene_file(d.path / "scene.xml");
    INFO(all_warnings(s));
    REQUIRE(s.triangle_count() == 4);
    check_vec(measure(s).lo, {0, 0, 0});
    check_vec(measure(s).hi, {11, 1, 0});
    CHECK(s.materials[s.material_ids[0]].albedo == glm::vec3(0.25f)); // not the MTL's red
    CHECK(s.materials[s.material_ids[2]].albedo == glm::vec3(0.5f));  // Mitsuba's default
    check_vec(glm::normalize(measure(s).normal_sum), {0, 0, 1});
    CHECK_FALSE(has_warning(s, "have no material"));
}

// --- Errors ----------------------------------------------------------------------------------

TEST_CASE("mitsuba: bad input fails with file:line:column and the problem",
          "[scene][mitsuba][parser]") {
    // Malformed XML: pugixml's message at its place
    CHECK_THAT(
        error_of("<scene version=\"3.0.0\">\n  <shape type=\"cube\">\n  </shap>\n</scene>\n"),
        Contains("test.xml:3:") && Contains("malformed XML"));
    CHECK_THAT(error_of("<scene version=\"3.0.0\">\n  <shape type=\"cube\"\n"),
               Contains("test.xml:") && Contains("malformed XML"));
    CHECK_THAT(error_of(""), Contains("test.xml:1:1: malformed XML: No document element found"));
    CHECK_THAT(error_of("<scen version=\"3.0.0\"/>"), Contains("root element must be <scene>"));
    CHECK_THAT(error_of("<scene>\n  <shape type=\"cube\"/>\n</scene>"),
               Contains("test.xml:1:1: <scene>: missing attribute 'version'"));
    // Unknown element, unknown attribute, misplaced elements
    CHECK_THAT(error_of("<scene version=\"3.0.0\">\n  <shape type=\"cube\">\n    <colour "
                        "name=\"x\"/>\n  </shape>\n</scene>"),
               Contains("test.xml:3:5: <colour name=\"x\">: unknown element <colour>"));
    CHECK_THAT(error_of("<scene version=\"3.0.0\">\n\t<shape type=\"sphere\"><float nme=\"radius\" "
                        "value=\"1\"/></shape>\n</scene>"),
               Contains("test.xml:2:23") && Contains("unknown attribute 'nme'") &&
                   Contains("takes: name, value"));
    CHECK_THAT(error_of_body("<translate x=\"1\"/>"), Contains("belongs inside a <transform>"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><default name=\"a\" value=\"1\"/></shape>"),
               Contains("must be a child of <scene>"));
    // Bad numbers and values out of range
    CHECK_THAT(
        error_of_body("<shape type=\"sphere\"><float name=\"radius\" value=\"1.0x\"/></shape>"),
        Contains("'1.0x' is not a number"));
    CHECK_THAT(
        error_of_body("<shape type=\"sphere\"><float name=\"radius\" value=\"nan\"/></shape>"),
        Contains("not a finite float"));
    CHECK_THAT(
        error_of_body("<shape type=\"sphere\"><float name=\"radius\" value=\"-1\"/></shape>"),
        Contains("radius -1 must be > 0"));
    CHECK_THAT(
        error_of_body("<shape type=\"sphere\"><string name=\"radius\" value=\"1\"/></shape>"),
        Contains("property 'radius' must be a number"));
    CHECK_THAT(
        error_of_body(std::string(kRect) +
                      "<sensor type=\"perspective\"><float name=\"fov\" value=\"190\"/></sensor>"),
        Contains("fov 190 is out of range"));
    CHECK_THAT(error_of_body(std::string(kRect) +
                             "<sensor type=\"perspective\"><film type=\"hdrfilm\"><integer "
                             "name=\"width\" value=\"0\"/></film></sensor>"),
               Contains("film size 0 x 576 is out of range"));
    CHECK_THAT(error_of_body(std::string(kRect) +
                             "<sensor type=\"perspective\"><film type=\"hdrfilm\"><integer "
                             "name=\"width\" value=\"99999999999\"/></film></sensor>"),
               Contains("out of the integer range"));
    CHECK_THAT(error_of_body(std::string(kRect) +
                             "<sensor type=\"perspective\"><sampler type=\"independent\"><integer "
                             "name=\"sample_count\" value=\"0\"/></sampler></sensor>"),
               Contains("sample_count 0 is out of range"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"diffuse\"><rgb "
                             "name=\"reflectance\" value=\"1.5, 0, 0\"/></bsdf></shape>"),
               Contains("reflectance (1.5, 0, 0) is outside [0, 1]"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><emitter type=\"area\"><rgb name=\"radiance\" "
                             "value=\"-1\"/></emitter></shape>"),
               Contains("radiance (-1, -1, -1) must be >= 0"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"dielectric\"><string "
                             "name=\"int_ior\" value=\"unobtainium\"/></bsdf></shape>"),
               Contains("unknown index of refraction 'unobtainium'"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"dielectric\"><float "
                             "name=\"int_ior\" value=\"1e6\"/></bsdf></shape>"),
               Contains("int_ior / ext_ior = ") && Contains("out of range [0.01, 100]"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><transform name=\"to_world\"><matrix value=\"1 "
                             "2 3\"/></transform></shape>"),
               Contains("expected 16 (4 x 4) or 9 (3 x 3) numbers"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><transform name=\"to_world\"><rotate "
                             "angle=\"3\"/></transform></shape>"),
               Contains("rotation axis is zero"));
    // References and ids
    CHECK_THAT(error_of("<scene version=\"3.0.0\">\n  <shape type=\"cube\"><ref "
                        "id=\"nope\"/></shape>\n</scene>"),
               Contains("test.xml:2:22: <ref id=\"nope\">: no <bsdf id=\"nope\"> is defined"));
    CHECK_THAT(error_of_body("<bsdf type=\"diffuse\" id=\"a\"/><bsdf type=\"diffuse\" id=\"a\"/>"),
               Contains("id 'a' is already used at test.xml:2:1"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><float name=\"x\" value=\"1\"/><float "
                             "name=\"x\" value=\"2\"/></shape>"),
               Contains("property 'x' is given twice"));
    CHECK_THAT(error_of_body("<shape type=\"obj\"/>"),
               Contains("missing <string name=\"filename\""));
    CHECK_THAT(error_of_body("<shape type=\"serialized\"/>"),
               Contains("no shape that wavepath can render (1 skipped)"));
    // Nesting
    std::string deep;
    for (int i = 0; i < 70; ++i)
        deep += "<bsdf type=\"twosided\">";
    for (int i = 0; i < 70; ++i)
        deep += "</bsdf>";
    CHECK_THAT(error_of_body("<shape type=\"cube\">" + deep + "</shape>"),
               Contains("nested more than 64 deep"));
    std::string bsdfs;
    for (int i = 0; i < 20; ++i)
        bsdfs += "<bsdf type=\"twosided\">";
    bsdfs += "<bsdf type=\"diffuse\"/>";
    for (int i = 0; i < 20; ++i)
        bsdfs += "</bsdf>";
    CHECK_THAT(error_of_body("<shape type=\"cube\">" + bsdfs + "</shape>"),
               Contains("BSDFs are nested more than 16 deep"));
}

TEST_CASE("mitsuba: load_mitsuba refuses missing files and folders", "[scene][mitsuba][parser]") {
    CHECK_THROWS_WITH(load_mitsuba("/nonexistent/scene.xml"),
                      Contains("/nonexistent/scene.xml") && Contains("no such file"));
    CHECK_THROWS_WITH(load_mitsuba(fs::temp_directory_path()), Contains("not a regular file"));
}

// Damaged files (bytes changed, inserted, removed, truncated) must give a Scene or a
// wp::Error, nothing else: a small deterministic fuzz run (more under the sanitizers).
TEST_CASE("mitsuba: damaged input gives a scene or a wp::Error, never a crash",
          "[scene][mitsuba][parser]") {
    const std::string base = R"(<scene version="3.0.0">
  <default name="spp" value="8"/>
  <integrator type="path"><integer name="max_depth" value="4"/></integrator>
  <sensor type="perspective"><float name="fov" value="30"/><string name="fov_axis" value="smaller"/>
    <transform name="to_world"><lookat origin="0, 1, 5" target="0, 1, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
    <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="48"/></film></sensor>
  <bsdf type="twosided" id="w"><bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.7, 0.7"/></bsdf></bsdf>
  <bsdf type="roughconductor" id="m"><float name="alpha" value="0.2"/><string name="material" value="Cu"/></bsdf>
  <shape type="cube"><transform name="to_world"><scale value="0.5"/><rotate y="1" angle="30"/></transform><ref id="m"/></shape>
  <shape type="rectangle"><transform name="to_world"><matrix value="1 0 0 0 0 1 0 2 0 0 1 0 0 0 0 1"/></transform>
    <ref id="w"/><emitter type="area"><rgb name="radiance" value="5, 5, 5"/></emitter></shape>
  <shape type="sphere"><point name="center" x="1" y="0.5" z="0"/><float name="radius" value="0.3"/>
    <bsdf type="dielectric"><string name="int_ior" value="bk7"/></bsdf></shape>
  <emitter type="constant"><rgb name="radiance" value="0.1"/></emitter>
</scene>
)";
    Scene ok = parse_mitsuba(base, "fuzz.xml");
    REQUIRE(ok.triangle_count() == 12 + 2 + 5120);
    SplitMix64 rng(12345);
    const char alphabet[] = "<>/=\"' $-.,0123456789eE+abcxyz\n\t&;!?";
    int scenes = 0, errors = 0;
    for (int iter = 0; iter < 400; ++iter) {
        std::string s = base;
        int edits = 1 + int(rng.next() % 4);
        for (int e = 0; e < edits && !s.empty(); ++e) {
            std::size_t pos = rng.next() % s.size();
            char c = alphabet[rng.next() % (sizeof(alphabet) - 1)];
            switch (rng.next() % 5) {
            case 0:
                s[pos] = c;
                break;
            case 1:
                s.insert(pos, 1, c);
                break;
            case 2:
                s.erase(pos, 1 + rng.next() % 8);
                break;
            case 3:
                s.resize(pos);
                break;
            default:
                s.insert(pos, s.substr(rng.next() % s.size(), rng.next() % 64));
                break;
            }
        }
        try {
            Scene sc = parse_mitsuba(s, "fuzz.xml");
            ++scenes;
            CHECK(sc.triangle_count() > 0);
        } catch (const Error& e) {
            ++errors;
            CHECK(std::string(e.what()).find("fuzz.xml") != std::string::npos);
        }
    }
    INFO("scenes " << scenes << ", errors " << errors);
    CHECK(scenes + errors == 400);
    CHECK(errors > 100);
}

// --- The shared test scenes -------------------------------------------------------------------

namespace {

// Triangle count of a scene from the table in ../shared/scenes/README.md ("| [name](...) | 15,412
// (...) |").
long readme_triangles(const fs::path& readme, const std::string& name) {
    std::ifstream in(readme);
    std::string line;
    const std::string key = "| [" + name + "]";
    while (std::getline(in, line)) {
        if (line.rfind(key, 0) != 0) continue;
        std::size_t a = line.find('|', 1);
        if (a == std::string::npos) return -1;
        std::string digits;
        for (std::size_t i = a + 1; i < line.size(); ++i) {
            char c = line[i];
            if (c == ' ' && digits.empty()) continue;
            if (c >= '0' && c <= '9')
                digits += c;
            else if (c != ',')
                break;
        }
        return digits.empty() ? -1 : std::stol(digits);
    }
    return -1;
}

} // namespace

TEST_CASE("mitsuba: every shared scene_v3.xml loads with the README's triangle count",
          "[scene][mitsuba][parser]") {
    const fs::path root = WP_SHARED_SCENES;
    if (!fs::exists(root)) {
        WARN("SKIP: " << root << " does not exist (the shared test scenes are not checked out)");
        return;
    }
    auto files = test::shared_scene_files(root, "scene_v3.xml");
    REQUIRE(files.size() >= 3); // cornell-box, veach-bidir, veach-mis
    for (const fs::path& f : files) {
        const std::string name = f.parent_path().filename().string();
        INFO(name);
        Scene s = load_scene_file(f);
        INFO(all_warnings(s));
        // veach-mis: the README counts its spheres as 3 x 5,120 icosphere triangles, the
        // tessellation this reader uses too, so all counts compare exactly.
        long want = readme_triangles(root / "README.md", name);
        REQUIRE(want > 0);
        CHECK(long(s.triangle_count()) == want);
        CHECK(s.render.spp == 64);
    }
}

TEST_CASE("mitsuba: the shared Cornell box and veach-mis read as their SOURCE.md describes",
          "[scene][mitsuba][parser]") {
    const fs::path root = WP_SHARED_SCENES;
    if (!fs::exists(root)) {
        WARN("SKIP: " << root << " does not exist (the shared test scenes are not checked out)");
        return;
    }
    // Cornell box: camera (0, 1, 6.8) looking at -z, 19.5 degrees on a square film, depth
    // 65 segments = 64 bounces, one emitter of (17, 12, 4) on a 0.47 x 0.38 quad facing down
    Scene cb = load_scene_file(root / "cornell-box" / "scene_v3.xml");
    check_vec(cb.camera.position, {0, 1, 6.8});
    check_vec(glm::normalize(glm::dvec3(cb.camera.target - cb.camera.position)), {0, 0, -1});
    CHECK(cb.camera.vfov_deg == Approx(19.5));
    CHECK(cb.camera.width == 1024);
    CHECK(cb.render.depth == 64);
    int lights = 0;
    for (std::size_t m = 0; m < cb.materials.size(); ++m) {
        if (!cb.materials[m].emissive()) continue;
        ++lights;
        CHECK(cb.materials[m].emission == glm::vec3(17, 12, 4));
        Measure l = measure(cb, long(m));
        CHECK(l.area == Approx(0.47 * 0.38).epsilon(1e-3));
        check_vec(glm::normalize(l.normal_sum), {0, -1, 0});
        CHECK(l.lo.y == Approx(1.98));
    }
    CHECK(lights == 1);
    CHECK_FALSE(has_warning(cb, "one-sided"));

    // veach-mis: three sphere lights of equal power L * 4 pi r^2 (r = 1, 0.5, 0.05); the
    // Mitsuba file's depth 3 = 2 bounces; 1280 x 720 with a 35 degree horizontal fov
    Scene vm = load_scene_file(root / "veach-mis" / "scene_v3.xml");
    INFO(all_warnings(vm));
    CHECK(vm.render.depth == 2);
    CHECK(vm.camera.vfov_deg == Approx(20.1143).epsilon(1e-4)); // SOURCE.md
    std::vector<double> power;
    for (std::size_t m = 0; m < vm.materials.size(); ++m) {
        if (!vm.materials[m].emissive()) continue;
        Measure l = measure(vm, long(m));
        CHECK(l.triangles == 5120);
        const double r = 0.5 * (l.hi.x - l.lo.x);
        CHECK(l.area == Approx(4 * kPi * r * r).epsilon(1e-2)); // r from the bounds: ~0.5%
        power.push_back(vm.materials[m].emission.x * l.area);
    }
    REQUIRE(power.size() == 3);
    for (double p : power)
        CHECK(p == Approx(7.59909 * 4 * kPi).epsilon(1e-4));
    CHECK_FALSE(has_warning(vm, "beckmann"));
    // The plates: Beckmann rough conductors of copper's η, k as given, tint 0.3, alpha as given
    std::vector<float> alphas;
    for (const auto& m : vm.materials)
        if (m.kind == MaterialKind::RoughConductor) {
            alphas.push_back(m.alpha);
            CHECK(m.albedo == glm::vec3(0.3f));
            CHECK(m.distribution == MicrofacetModel::Beckmann);
            CHECK(m.separable_g);
            check_vec(m.eta, {0.200438, 0.924033, 1.10221});
            check_vec(m.k, {3.91295, 2.45285, 2.14219});
        }
    std::sort(alphas.begin(), alphas.end());
    CHECK(alphas == std::vector<float>{0.01f, 0.05f, 0.1f, 0.25f});
}

// --- Rendering -------------------------------------------------------------------------------

TEST_CASE("mitsuba: every shared scene_v3.xml renders without NaN or Inf",
          "[scene][mitsuba][render]") {
    const fs::path root = WP_SHARED_SCENES;
    if (!fs::exists(root)) {
        WARN("SKIP: " << root << " does not exist (the shared test scenes are not checked out)");
        return;
    }
    for (const fs::path& f : test::shared_scene_files(root, "scene_v3.xml")) {
        INFO(f);
        Scene s = load_scene_file(f);
        const test::SmokeRender r = test::smoke_render(s, 4, s.render.depth.value_or(3));
        CHECK(r.nonfinite == 0);
        CHECK(r.counters == 0);
        CHECK(r.sum > 0.0); // light reaches the camera
    }
}

// The CLI on a bad Mitsuba file: exit status 1, one message naming the place, no image.
TEST_CASE("mitsuba: wavepath render refuses a bad scene and writes nothing",
          "[scene][mitsuba][cli]") {
    TempDir d;
    std::ofstream(d.path / "bad.xml")
        << "<scene version=\"3.0.0\">\n  <shape type=\"obj\">\n"
           "    <string name=\"filename\" value=\"nowhere.obj\"/>\n  </shape>\n</scene>\n";
    fs::path err = d.path / "stderr.txt";
    std::string cmd = "cd '" + d.path.string() +
                      "' && '" WP_CLI_PATH "' render bad.xml --spp 1 -o out.exr > /dev/null 2> '" +
                      err.string() + "'";
    int rc = std::system(cmd.c_str());
    std::ifstream in(err);
    std::stringstream ss;
    ss << in.rdbuf();
    INFO(ss.str());
    CHECK(WIFEXITED(rc));
    CHECK(WEXITSTATUS(rc) == 1);
    CHECK_THAT(ss.str(), Contains("bad.xml:2:3") && Contains("nowhere.obj' not found"));
    CHECK_FALSE(fs::exists(d.path / "out.exr"));
}

// --- Appearance: textures, shading normals, uvs, normal maps, masks, envmap (issue 13) --------

namespace {

Scene parse_in(const TempDir& d, const std::string& body) {
    return parse_mitsuba("<scene version=\"3.0.0\">\n" + body + "\n</scene>\n", d.path / "test.xml");
}

glm::vec2 apply_uv(const glm::mat3& m, glm::vec2 uv) { return glm::vec2(m * glm::vec3(uv, 1.0f)); }

// u modulo 1 (seam copies of a vertex carry u + 1)
double wrap01(double u) { return u - std::floor(u); }

double angle_diff(double a, double b) {  // |a - b| modulo 1, for u values
    const double d = std::abs(wrap01(a) - wrap01(b));
    return std::min(d, 1.0 - d);
}

const Material& material_of(const Scene& s, std::size_t triangle) {
    return s.materials.at(s.material_ids.at(triangle));
}

}  // namespace

TEST_CASE("mitsuba: bitmap and checkerboard textures become albedo maps with their to_uv",
          "[scene][mitsuba][parser][texture]") {
    TempDir d;
    write_exr(d.path / "wood.exr", 4, 2, [](int x, int y) { return glm::vec3(0.1f * float(x + 4 * y)); });
    Scene s = parse_in(d, R"(
  <texture type="bitmap" id="wood">
    <string name="filename" value="wood.exr"/><string name="filter_type" value="nearest"/>
    <transform name="to_uv"><scale x="2" y="3"/><translate x="0.5" y="0.25"/></transform>
  </texture>
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="diffuse"><ref name="reflectance" id="wood"/></bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="roughplastic">
    <texture name="diffuse_reflectance" type="checkerboard">
      <rgb name="color0" value="0.1, 0.2, 0.3"/><rgb name="color1" value="0.9"/>
      <transform name="to_uv"><rotate z="1" angle="90"/></transform>
    </texture></bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="conductor">
    <texture name="specular_reflectance" type="bitmap"><string name="filename" value="wood.exr"/></texture>
  </bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.3"/></bsdf></bsdf></shape>)");
    INFO(all_warnings(s));
    REQUIRE(s.triangle_count() == 8);
    // Diffuse: the bitmap is the reflectance (albedo 1 times the map)
    const Material& wood = material_of(s, 0);
    CHECK(wood.kind == MaterialKind::Diffuse);
    CHECK(wood.albedo == glm::vec3(1.0f));
    REQUIRE(wood.albedo_map.used());
    const Texture& img = s.textures.at(std::size_t(wood.albedo_map.image));
    CHECK(img.source.find("wood.exr") != std::string::npos);
    CHECK(img.width == 4);
    CHECK(img.height == 2);
    CHECK(img.nearest);  // filter_type nearest
    // to_uv: scale, then translate: uv' = (2u + 0.5, 3v + 0.25)
    check_vec(glm::dvec3(apply_uv(wood.albedo_map.uv_transform, {0.1f, 0.2f}), 0.0), {0.7, 0.85, 0});
    // Checkerboard: 2 x 2 nearest, color0 at the top left and bottom right, color1 elsewhere
    const Material& plastic = material_of(s, 2);
    CHECK(plastic.albedo == glm::vec3(1.0f));
    REQUIRE(plastic.albedo_map.used());
    const Texture& cb = s.textures.at(std::size_t(plastic.albedo_map.image));
    REQUIRE(cb.width == 2);
    REQUIRE(cb.height == 2);
    CHECK(cb.nearest);
    for (int c = 0; c < 3; ++c) {
        const float c0 = glm::vec3(0.1f, 0.2f, 0.3f)[c];
        CHECK(texel_at(cb, 0, 0, c) == Approx(c0));
        CHECK(texel_at(cb, 1, 1, c) == Approx(c0));
        CHECK(texel_at(cb, 1, 0, c) == Approx(0.9f));
        CHECK(texel_at(cb, 0, 1, c) == Approx(0.9f));
    }
    // to_uv rotate 90 degrees about z: (u, v) -> (-v, u)
    check_vec(glm::dvec3(apply_uv(plastic.albedo_map.uv_transform, {0.1f, 0.2f}), 0.0), {-0.2, 0.1, 0});
    // Conductor: the map is the specular_reflectance tint (material "none": F = 1)
    const Material& metal = material_of(s, 4);
    CHECK(metal.kind == MaterialKind::Conductor);
    CHECK(metal.albedo == glm::vec3(1.0f));
    // The same file, but this bitmap filters bilinearly: its own copy, the wood's stays nearest
    REQUIRE(metal.albedo_map.used());
    const Texture& metal_img = s.textures.at(std::size_t(metal.albedo_map.image));
    CHECK(metal_img.source == img.source);
    CHECK(!metal_img.nearest);
    CHECK(img.nearest);
    CHECK(metal.albedo_map.uv_transform == glm::mat3(1.0f));
    // Textured shapes carry uvs; the rectangle's are ((x + 1) / 2, (y + 1) / 2)
    REQUIRE(s.uvs.size() == s.positions.size());
    for (std::size_t i = 0; i < s.positions.size(); ++i) {
        const glm::vec3 p = s.positions[i];
        if (!material_of(s, 0).textured()) continue;
        check_vec(glm::dvec3(s.uvs[i], 0.0), {(p.x + 1.0) / 2.0, (p.y + 1.0) / 2.0, 0.0});
        if (i == 3) break;  // the first rectangle's four vertices
    }
    CHECK_FALSE(material_of(s, 6).textured());
    CHECK_FALSE(has_warning(s, "texture"));
}

TEST_CASE("mitsuba: bitmap options and missing files", "[scene][mitsuba][parser][texture]") {
    TempDir d;
    Scene s = parse_in(d, R"(
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="diffuse">
    <texture name="reflectance" type="bitmap"><string name="filename" value="gone.png"/>
      <string name="wrap_mode" value="mirror"/></texture></bsdf></bsdf></shape>)");
    INFO(all_warnings(s));
    // A missing file is a warning naming it and a placeholder, never an error
    CHECK(has_warning(s, "gone.png"));
    CHECK(has_warning(s, "wrap_mode 'mirror' is rendered as 'repeat'"));
    CHECK(material_of(s, 0).albedo_map.used());
    // Anisotropic roughness textures: their means, with a warning
    Scene aniso = parse(R"(<shape type="rectangle"><bsdf type="twosided"><bsdf type="roughconductor">
      <texture name="alpha_u" type="checkerboard"><float name="color0" value="0.1"/><float name="color1" value="0.3"/></texture>
      <float name="alpha_v" value="0.2"/><string name="distribution" value="ggx"/></bsdf></bsdf></shape>)");
    CHECK(material_of(aniso, 0).alpha == Approx(0.2f));  // the mean of 0.1 and 0.3
    CHECK(material_of(aniso, 0).alpha_v.value_or(0.2f) == Approx(0.2f));
    CHECK(has_warning(aniso, "alpha_u/alpha_v textures are not supported; their mean values are used"));
    // Bad values: the element's place and the problem
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"diffuse\">\n"
                             "  <texture name=\"reflectance\" type=\"bitmap\">\n"
                             "    <integer name=\"filename\" value=\"3\"/></texture></bsdf></shape>"),
               Contains("test.xml:4:5: <integer name=\"filename\">: property 'filename' must be a string"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"diffuse\">\n"
                             "  <texture name=\"reflectance\" type=\"bitmap\"><string name=\"filename\" "
                             "value=\"a.png\"/>\n    <string name=\"filter_type\" value=\"cubic\"/>"
                             "</texture></bsdf></shape>"),
               Contains("test.xml:4:5: <string name=\"filter_type\">: filter_type 'cubic' is not "
                        "bilinear or nearest"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"diffuse\">\n"
                             "  <texture name=\"reflectance\" type=\"bitmap\"/></bsdf></shape>"),
               Contains("test.xml:3:3: <texture type=\"bitmap\" name=\"reflectance\">: missing "
                        "<string name=\"filename\""));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"diffuse\">\n"
                             "  <texture name=\"reflectance\" type=\"checkerboard\"><rgb "
                             "name=\"color1\" value=\"2\"/></texture></bsdf></shape>"),
               Contains("test.xml:3:3:") &&
                   Contains("reflectance: checkerboard colour (2, 2, 2) is outside [0, 1]"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"diffuse\">\n"
                             "  <ref name=\"reflectance\" id=\"nope\"/></bsdf></shape>"),
               Contains("test.xml:3:3:") && Contains("no <texture id=\"nope\">"));
    CHECK_THAT(error_of_body("<shape type=\"cube\"><bsdf type=\"normalmap\">\n"
                             "  <bsdf type=\"diffuse\"/></bsdf></shape>"),
               Contains("test.xml:2:20: <bsdf type=\"normalmap\">: needs <texture "
                        "name=\"normalmap\""));
}

TEST_CASE("mitsuba: spheres get normals (p - c) / |p - c| and, textured, Mitsuba's uvs",
          "[scene][mitsuba][parser][texture]") {
    const glm::dvec3 c(1, 2, 3);
    Scene s = parse(R"(
  <shape type="sphere"><point name="center" x="1" y="2" z="3"/><float name="radius" value="2"/>
    <bsdf type="diffuse"><texture name="reflectance" type="checkerboard"/></bsdf></shape>)");
    INFO(all_warnings(s));
    REQUIRE(s.triangle_count() == 5120);
    REQUIRE(s.normals.size() == s.positions.size());
    REQUIRE(s.uvs.size() == s.positions.size());
    int poles = 0;
    for (std::size_t i = 0; i < s.positions.size(); ++i) {
        const glm::dvec3 q = (glm::dvec3(s.positions[i]) - c) / glm::length(glm::dvec3(s.positions[i]) - c);
        check_vec(glm::dvec3(s.normals[i]), q);
        // v = theta / pi from +z; u = phi / 2 pi, phi = atan2(y, x) (any u at the poles)
        CHECK(s.uvs[i].y == Approx(std::acos(q.z) / kPi).margin(1e-5));
        if (std::hypot(q.x, q.y) < 1e-6) {
            ++poles;
            continue;
        }
        CHECK(angle_diff(s.uvs[i].x, std::atan2(q.y, q.x) / (2 * kPi)) < 1e-5);
    }
    CHECK(poles > 0);  // the icosphere has vertices at both poles: they get one copy per triangle
    // No triangle spans the seam: its uvs interpolate like the surface (the widest are the
    // six around each pole, 1/6 of a turn)
    float widest = 0.0f;
    for (const auto& t : s.triangles) {
        const float lo = std::min({s.uvs[t.x].x, s.uvs[t.y].x, s.uvs[t.z].x});
        const float hi = std::max({s.uvs[t.x].x, s.uvs[t.y].x, s.uvs[t.z].x});
        widest = std::max(widest, hi - lo);
    }
    CHECK(widest < 0.2f);
    // flip_normals: inward normals; no texture: no uvs (and no seam copies)
    Scene f = parse(R"(<shape type="sphere"><float name="radius" value="0.5"/>
      <boolean name="flip_normals" value="true"/></shape>)");
    REQUIRE(f.normals.size() == f.positions.size());
    CHECK(f.uvs.empty());
    CHECK(f.positions.size() == 2562);  // 10 * 4^4 + 2: the icosphere's own vertices
    for (std::size_t i = 0; i < f.positions.size(); ++i)
        check_vec(glm::dvec3(f.normals[i]), -glm::normalize(glm::dvec3(f.positions[i])));
    // to_world turns the parameterization with the sphere: after a rotation of 90 degrees
    // about x, the local +z pole (v = 0) is at world -y
    Scene r = parse(R"(<shape type="sphere"><transform name="to_world"><rotate x="1" angle="90"/></transform>
      <bsdf type="diffuse"><texture name="reflectance" type="checkerboard"/></bsdf></shape>)");
    std::size_t lowest = 0;
    for (std::size_t i = 0; i < r.positions.size(); ++i)
        if (r.positions[i].y < r.positions[lowest].y) lowest = i;
    CHECK(r.uvs[lowest].y == Approx(0.0).margin(1e-6));
    check_vec(glm::dvec3(r.normals[lowest]), {0, -1, 0});
}

TEST_CASE("mitsuba: rectangle, cube, disk and cylinder get Mitsuba's uvs",
          "[scene][mitsuba][parser][texture]") {
    const std::string bsdf = R"(<bsdf type="diffuse"><texture name="reflectance" type="checkerboard"/></bsdf>)";
    // Rectangle: uv = ((x + 1) / 2, (y + 1) / 2) in its own space, whatever to_world does
    Scene rect = parse(R"(<shape type="rectangle"><transform name="to_world"><scale value="3"/>
      <translate z="1"/></transform>)" + bsdf + "</shape>");
    REQUIRE(rect.uvs.size() == 4);
    CHECK(rect.normals.empty());  // flat: the geometric normal shades
    for (std::size_t i = 0; i < 4; ++i)
        check_vec(glm::dvec3(rect.uvs[i], 0),
                  {(rect.positions[i].x / 3.0 + 1) / 2, (rect.positions[i].y / 3.0 + 1) / 2, 0});
    // Cube: 24 vertices, each face the whole texture; on the +z face uv = ((y + 1) / 2, (x + 1) / 2)
    Scene cube = parse("<shape type=\"cube\">" + bsdf + "</shape>");
    REQUIRE(cube.positions.size() == 24);
    REQUIRE(cube.triangle_count() == 12);
    int on_top = 0;
    for (std::size_t i = 0; i < 24; ++i) {
        const glm::vec3 p = cube.positions[i];
        CHECK(glm::all(glm::greaterThanEqual(cube.uvs[i], glm::vec2(0.0f))));
        CHECK(glm::all(glm::lessThanEqual(cube.uvs[i], glm::vec2(1.0f))));
        if (p.z != 1.0f) continue;
        // the +z face is the 4th face of Mitsuba's table (vertices 12..15)
        if (i < 12 || i > 15) continue;
        ++on_top;
        check_vec(glm::dvec3(cube.uvs[i], 0), {(p.y + 1) / 2.0, (p.x + 1) / 2.0, 0});
    }
    CHECK(on_top == 4);
    // Disk: uv = (r, phi / 2 pi): the rim at u = 1, the centre at u = 0
    Scene disk = parse("<shape type=\"disk\">" + bsdf + "</shape>");
    REQUIRE(disk.uvs.size() == disk.positions.size());
    for (std::size_t i = 0; i < disk.positions.size(); ++i) {
        const glm::dvec3 p(disk.positions[i]);
        if (glm::length(p) == 0.0) {
            CHECK(disk.uvs[i].x == 0.0f);
            continue;
        }
        CHECK(disk.uvs[i].x == 1.0f);
        CHECK(angle_diff(disk.uvs[i].y, std::atan2(p.y, p.x) / (2 * kPi)) < 1e-6);
    }
    // Cylinder along +x: Mitsuba's frame for d = +x has s = (0, 0, -1), t = (0, 1, 0), so
    // u = atan2(y, -z) / 2 pi, v = x / length; normals point away from the axis
    Scene cyl = parse(R"(<shape type="cylinder"><point name="p0" value="0, 0, 0"/>
      <point name="p1" value="2, 0, 0"/><float name="radius" value="0.5"/>)" + bsdf + "</shape>");
    REQUIRE(cyl.uvs.size() == cyl.positions.size());
    REQUIRE(cyl.normals.size() == cyl.positions.size());
    for (std::size_t i = 0; i < cyl.positions.size(); ++i) {
        const glm::dvec3 p(cyl.positions[i]);
        check_vec(glm::dvec3(cyl.normals[i]), glm::normalize(glm::dvec3(0, p.y, p.z)));
        CHECK(angle_diff(cyl.uvs[i].x, std::atan2(p.y, -p.z) / (2 * kPi)) < 1e-6);
        CHECK(cyl.uvs[i].y == Approx(p.x / 2.0).margin(1e-6));
    }
    for (const auto& t : cyl.triangles)  // no triangle across the seam
        CHECK(std::abs(cyl.uvs[t.x].x - cyl.uvs[t.z].x) < 0.1f);
}

TEST_CASE("mitsuba: normalmap and mask wrap their BSDF with a normal map and an alpha cut-out",
          "[scene][mitsuba][parser][texture]") {
    TempDir d;
    write_exr(d.path / "bumps.exr", 2, 2, [](int, int) { return glm::vec3(0.5f, 0.5f, 1.0f); });
    // Opacity 0/1: a fence of columns; 0.3 everywhere: a stochastic mask
    write_exr(d.path / "fence.exr", 4, 1, [](int x, int) { return glm::vec3(x % 2 ? 1.0f : 0.0f); });
    write_exr(d.path / "haze.exr", 2, 1, [](int, int) { return glm::vec3(0.3f); });
    Scene s = parse_in(d, R"(
  <shape type="rectangle"><bsdf type="normalmap">
    <texture name="normalmap" type="bitmap"><boolean name="raw" value="true"/><string name="filename" value="bumps.exr"/></texture>
    <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.25"/></bsdf></bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="mask">
    <texture name="opacity" type="bitmap"><string name="filename" value="fence.exr"/>
      <transform name="to_uv"><scale value="4"/></transform></texture>
    <bsdf type="twosided"><bsdf type="diffuse"/></bsdf></bsdf></shape>
  <shape type="rectangle"><bsdf type="mask"><float name="opacity" value="0"/>
    <bsdf type="twosided"><bsdf type="diffuse"/></bsdf></bsdf></shape>)");
    INFO(all_warnings(s));
    const Material& nm = material_of(s, 0);
    CHECK(nm.kind == MaterialKind::Diffuse);
    CHECK(nm.albedo == glm::vec3(0.25f));
    REQUIRE(nm.normal_map.used());
    CHECK(s.textures.at(std::size_t(nm.normal_map.image)).source.find("bumps.exr") != std::string::npos);
    CHECK(nm.normal_scale == 1.0f);
    // Mitsuba's frame: x along dp/du, y = n x (x): on the rectangle dp/du = +x, and y = +y,
    // the direction of increasing v (v = (y + 1) / 2), so tangents (1, 0, 0) with w = +1
    REQUIRE(s.tangents.size() == s.positions.size());
    for (std::size_t i = 0; i < 4; ++i) {
        check_vec(glm::dvec3(s.tangents[i]), {1, 0, 0});
        CHECK(s.tangents[i].w == 1.0f);
    }
    for (std::size_t i = 4; i < s.positions.size(); ++i)  // no normal map: no tangents
        CHECK(s.tangents[i] == glm::vec4(0.0f));
    // Mask from a 0/1 bitmap: coverage (the alpha map's A) = the opacity, cutoff 0.5, exact
    const Material& fence = material_of(s, 2);
    REQUIRE(fence.alpha_map.used());
    CHECK(fence.alpha_cutoff == 0.5f);
    const Texture& a = s.textures.at(std::size_t(fence.alpha_map.image));
    REQUIRE(a.width == 4);
    for (int x = 0; x < 4; ++x) CHECK(texel_at(a, x, 0, 3) == (x % 2 ? 1.0f : 0.0f));
    check_vec(glm::dvec3(apply_uv(fence.alpha_map.uv_transform, {0.25f, 0.5f}), 0), {1, 2, 0});
    // Opacity 0: a 1 x 1 map of coverage 0 (nothing there)
    const Material& gone = material_of(s, 4);
    REQUIRE(gone.alpha_map.used());
    CHECK(texel_at(s.textures.at(std::size_t(gone.alpha_map.image)), 0, 0, 3) == 0.0f);
    CHECK_FALSE(has_warning(s, "stochastic"));
    // Opacity between 0 and 1 warns once; the default (0.5) is opaque with a cut-out
    Scene h = parse_in(d, R"(
  <shape type="rectangle"><bsdf type="mask"><texture name="opacity" type="bitmap">
    <string name="filename" value="haze.exr"/></texture><bsdf type="diffuse"/></bsdf></shape>
  <shape type="rectangle"><bsdf type="mask"><bsdf type="diffuse"/></bsdf></shape>
  <shape type="rectangle"><bsdf type="mask"><texture name="opacity" type="bitmap">
    <string name="filename" value="nothere.exr"/></texture><bsdf type="diffuse"/></bsdf></shape>)");
    INFO(all_warnings(h));
    CHECK(count_warnings(h, "stochastic") == 1);
    CHECK(has_warning(h, "is opaque (2 times; the first here)"));
    REQUIRE(material_of(h, 0).alpha_map.used());
    CHECK(texel_at(h.textures.at(std::size_t(material_of(h, 0).alpha_map.image)), 1, 0, 3) ==
          Approx(0.3f));
    CHECK_FALSE(material_of(h, 2).alpha_map.used());  // 0.5 >= the cutoff: opaque
    CHECK_FALSE(material_of(h, 4).alpha_map.used());  // a missing mask file leaves the surface
    CHECK(has_warning(h, "nothere.exr"));
}

TEST_CASE("mitsuba: roughconductor alpha as a texture is alpha_max times G squared",
          "[scene][mitsuba][parser][texture]") {
    Scene s = parse(R"(
  <shape type="rectangle"><bsdf type="twosided"><bsdf type="roughconductor"><string name="distribution" value="ggx"/>
    <texture name="alpha" type="checkerboard"><float name="color0" value="0.04"/><float name="color1" value="0.36"/></texture>
  </bsdf></bsdf></shape>)");
    INFO(all_warnings(s));
    const Material& m = material_of(s, 0);
    CHECK(m.kind == MaterialKind::RoughConductor);
    CHECK(m.distribution == MicrofacetModel::GGX);
    CHECK(m.alpha == Approx(0.36f));
    REQUIRE(m.roughness_map.used());
    const Texture& r = s.textures.at(std::size_t(m.roughness_map.image));
    // alpha = 0.36 G²: G = sqrt(0.04 / 0.36) = 1/3 where color0 is, 1 where color1 is
    CHECK(texel_at(r, 0, 0, 1) == Approx(1.0 / 3.0).epsilon(1e-5));
    CHECK(texel_at(r, 1, 1, 1) == Approx(1.0 / 3.0).epsilon(1e-5));
    CHECK(texel_at(r, 1, 0, 1) == Approx(1.0).epsilon(1e-5));
    CHECK(texel_at(r, 0, 1, 1) == Approx(1.0).epsilon(1e-5));
    CHECK(s.textures.size() == 1);  // the checkerboard it was made from is not kept
}

TEST_CASE("mitsuba: a textured area emitter's radiance is its emission map",
          "[scene][mitsuba][parser][texture]") {
    Scene s = parse(R"(<shape type="rectangle"><emitter type="area">
      <texture name="radiance" type="checkerboard"><float name="color0" value="4"/><float name="color1" value="0"/></texture>
    </emitter></shape>)");
    const Material& m = material_of(s, 0);
    CHECK(m.emission == glm::vec3(1.0f));
    REQUIRE(m.emission_map.used());
    CHECK(texel_at(s.textures.at(std::size_t(m.emission_map.image)), 0, 0, 0) == 4.0f);
    CHECK(s.uvs.size() == 4);
}

TEST_CASE("mitsuba: envmap is the environment (file, scale, rotation); a second is an error",
          "[scene][mitsuba][parser][texture]") {
    TempDir d;
    write_exr(d.path / "sky.exr", 8, 4, [](int, int) { return glm::vec3(1.0f); });
    Scene s = parse_in(d, std::string(kRect) + R"(
  <emitter type="envmap"><string name="filename" value="sky.exr"/><float name="scale" value="2.5"/>
    <transform name="to_world"><rotate y="1" angle="90"/></transform></emitter>
  <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>)");
    INFO(all_warnings(s));
    REQUIRE(s.environment);
    CHECK(s.environment->scale == 2.5f);
    const Texture& map = s.textures.at(std::size_t(s.environment->image));
    CHECK(map.source.find("sky.exr") != std::string::npos);
    CHECK(map.width == 8);
    // 90 degrees about +y: x -> -z, y -> y, z -> x (columns of to_world)
    const glm::mat3 r = s.environment->to_world;
    check_vec(glm::dvec3(r[0]), {0, 0, -1});
    check_vec(glm::dvec3(r[1]), {0, 1, 0});
    check_vec(glm::dvec3(r[2]), {1, 0, 0});
    CHECK(s.background == glm::vec3(0.5f));  // the constant emitter stays the background
    CHECK_FALSE(has_warning(s, "envmap"));
    // A to_world that scales keeps only its rotation, with a warning
    Scene sc = parse_in(d, std::string(kRect) + R"(
  <emitter type="envmap"><string name="filename" value="sky.exr"/>
    <transform name="to_world"><scale value="3"/></transform></emitter>)");
    CHECK(has_warning(sc, "not a rotation"));
    CHECK(sc.environment->to_world == glm::mat3(1.0f));
    // One environment only
    CHECK_THAT(error_of_body(std::string(kRect) + R"(
<emitter type="envmap"><string name="filename" value="a.exr"/></emitter>
<emitter type="envmap"><string name="filename" value="b.exr"/></emitter>)"),
               Contains("test.xml:4:1: <emitter type=\"envmap\">: a second environment map: "
                        "wavepath takes one (the first is at test.xml:3:1)"));
    CHECK_THAT(error_of_body(std::string(kRect) + "\n<emitter type=\"envmap\"/>"),
               Contains("test.xml:3:1: <emitter type=\"envmap\">: missing <string name=\"filename\""));
}

TEST_CASE("mitsuba: meshes without normals shade smooth unless face_normals",
          "[scene][mitsuba][parser]") {
    TempDir d;
    // An open square pyramid: apex (0, 0, 1), base corners (+-1, +-1, 0), no normals. At a
    // base corner two faces meet, with normals (1, 0, 1)/sqrt 2 and (0, 1, 1)/sqrt 2 and equal
    // angles, so the smooth normal there is (1, 1, 2)/sqrt 6; at the apex (0, 0, 1).
    d.write("pyramid.obj", "v 0 0 1\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nv -1 -1 0\n"
                           "f 2 3 1\nf 3 4 1\nf 4 5 1\nf 5 2 1\n");
    Scene s = parse_in(d, R"(<shape type="obj"><string name="filename" value="pyramid.obj"/></shape>
  <shape type="obj"><string name="filename" value="pyramid.obj"/><boolean name="face_normals" value="true"/>
    <transform name="to_world"><translate x="5"/></transform></shape>)");
    INFO(all_warnings(s));
    REQUIRE(s.triangle_count() == 8);
    REQUIRE(s.normals.size() == s.positions.size());
    for (std::size_t t = 0; t < 4; ++t)
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 p(s.positions[s.triangles[t][k]]);
            const glm::dvec3 n(s.normals[s.triangles[t][k]]);
            if (p.z == 1.0)
                check_vec(n, {0, 0, 1});
            else
                check_vec(n, glm::normalize(glm::dvec3(p.x, p.y, 2.0)));
        }
    // face_normals: the second pyramid has none (flat shading)
    for (std::size_t t = 4; t < 8; ++t)
        for (int k = 0; k < 3; ++k) CHECK(s.normals[s.triangles[t][k]] == glm::vec3(0.0f));
}
