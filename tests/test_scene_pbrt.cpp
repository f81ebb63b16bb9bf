// test_scene_pbrt.cpp — the pbrt-v4 scene reader (scene/pbrt_loader.h).
//
// Expected values come from elsewhere than the reader: transforms and fields of view
// computed by hand from pbrt-v4's definitions, areas of the shapes, the RGB metal values of
// Tungsten's table typed in here, pbrt's texture lookup rules re-implemented here (the
// checkerboard's parity rule, the image lookup at (s, 1 - t), the equal-area square-to-sphere
// map), the Mitsuba file of the same scene, and the triangle counts the shared scenes' README
// states. Tests tagged [parser] parse only (no OpenCL), so they also run under the sanitizers.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "image/image.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/load.h"
#include "scene/pbrt_loader.h"
#include "support.h"
#include "temp_dir.h"
#include "util/error.h"
#include "util/splitmix.h"

using namespace wp;
namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using wp::test::TempDir;

namespace {

constexpr double kPi = std::numbers::pi;

// A scene body after WorldBegin, with a camera and one quad unless the body brings shapes.
const char* kHead = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n";
const char* kQuad =
    "Shape \"trianglemesh\" \"point3 P\" [ -1 -1 0  1 -1 0  1 1 0  -1 1 0 ] "
    "\"integer indices\" [ 0 1 2  0 2 3 ]\n";

Scene parse(const std::string& text, const fs::path& origin = "test.pbrt") {
    return parse_pbrt(text, origin);
}

Scene parse_world(const std::string& body) {
    return parse(std::string(kHead) + "WorldBegin\n" + body);
}

std::string error_of(const std::string& text, const fs::path& origin = "test.pbrt") {
    try {
        parse_pbrt(text, origin);
    } catch (const Error& e) {
        return e.what();
    }
    FAIL("no error for:\n" << text);
    return "";
}

std::string error_of_world(const std::string& body) {
    return error_of(std::string(kHead) + "WorldBegin\n" + body);
}

bool has_warning(const Scene& s, const std::string& text) {
    for (const auto& w : s.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

int count_warnings(const Scene& s, const std::string& text) {
    int n = 0;
    for (const auto& w : s.warnings) n += w.find(text) != std::string::npos;
    return n;
}

std::string all_warnings(const Scene& s) {
    std::string out;
    for (const auto& w : s.warnings) out += w + "\n";
    return out;
}

using test::Measure;
using test::measure;
using test::texel_at;
using test::write_exr;

void check_vec(glm::dvec3 got, glm::dvec3 want, double tol = 1e-5) {
    INFO("got (" << got.x << ", " << got.y << ", " << got.z << "), want (" << want.x << ", "
                 << want.y << ", " << want.z << ")");
    CHECK(glm::length(got - want) <= tol * std::max(1.0, glm::length(want)));
}

// The one material the scene's triangles use (fails when there are several)
const Material& only_material(const Scene& s) {
    std::set<std::uint32_t> ids(s.material_ids.begin(), s.material_ids.end());
    REQUIRE(ids.size() == 1);
    return s.materials.at(*ids.begin());
}

// pbrt-v4's EqualAreaSquareToSphere (src/pbrt/util/math.cpp), written out here as the
// independent inverse of the reader's sphere-to-square map.
glm::dvec3 square_to_sphere(double px, double py) {
    const double u = 2 * px - 1, v = 2 * py - 1;
    const double up = std::abs(u), vp = std::abs(v);
    const double sd = 1 - (up + vp);
    const double r = 1 - std::abs(sd);
    const double phi = (r == 0 ? 1 : (vp - up) / r + 1) * kPi / 4;
    const double z = std::copysign(1 - r * r, sd);
    const double c = std::copysign(std::cos(phi), u), s = std::copysign(std::sin(phi), v);
    const double k = r * std::sqrt(std::max(0.0, 2 - r * r));
    return {c * k, s * k, z};
}

double frac(double x) { return x - std::floor(x); }

}  // namespace

// --- Syntax and errors ------------------------------------------------------------------------

TEST_CASE("pbrt: a minimal scene: comments, strings, brackets, numbers in every form",
          "[scene][pbrt][parser]") {
    Scene s = parse(R"(# a comment
LookAt 0 0 5   0 0 0   0 1 0 # trailing comment
Camera "perspective" "float fov" [ 40 ]
Film "rgb" "integer xresolution" 64 "integer yresolution" [ 48 ] "string filename" "out.exr"
WorldBegin
Material "diffuse" "rgb reflectance" [ .25 +0.5 7.5e-1 ]
Shape "trianglemesh" "point3 P" [ -1 -1 0 1 -1 0 1. 1 0 ] "integer indices" [0 1 2]
)");
    CHECK(s.triangle_count() == 1);
    CHECK(s.camera.width == 64);
    CHECK(s.camera.height == 48);
    CHECK(only_material(s).albedo == glm::vec3(0.25f, 0.5f, 0.75f));
    CHECK(has_warning(s, "test.pbrt:4:1"));  // the Film filename note, at its place
    CHECK(has_warning(s, "Film \"filename\" is ignored"));
}

TEST_CASE("pbrt: bad input fails with file:line:column and the problem", "[scene][pbrt][parser]") {
    CHECK_THAT(error_of("WorldBegin\nFoo 1 2\n"),
               Contains("test.pbrt:2:1: unknown directive 'Foo'"));
    CHECK_THAT(error_of("WorldBegin\n  Shape \"sphere\" \"float radius\" [ 1\n"),
               Contains("test.pbrt:2:33: '[' is never closed"));
    CHECK_THAT(error_of("WorldBegin\nShape \"sph\n"),
               Contains("test.pbrt:2:7: the string does not end on its line"));
    CHECK_THAT(error_of("WorldBegin\nShape \"a\\qb\"\n"), Contains("test.pbrt:2:7: unknown escape"));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"real radius\" 1\n"),
               Contains("test.pbrt:4:16: unknown parameter type 'real'"));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"radius\" 1\n"),
               Contains("expected a parameter \"TYPE NAME\""));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"float radius\" 1x\n"),
               Contains("test.pbrt:4:31: parameter \"float radius\": '1x' is not a number"));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"float radius\" nan\n"),
               Contains("'nan' is not a finite number"));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"float radius\" 1e999\n"),
               Contains("'1e999' is not a finite number"));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"float radius\" inf\n"),
               Contains("not a finite number"));
    CHECK_THAT(error_of_world("Translate 1 nan 0\n"), Contains("test.pbrt:4:13: Translate: 'nan' is not a finite number"));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"float radius\" [ 1 \"two\" ]\n"),
               Contains("mixes numbers, strings and booleans"));
    CHECK_THAT(error_of_world("Material \"diffuse\" \"rgb reflectance\" [ 1 2 ]\n"),
               Contains("parameter \"rgb reflectance\" takes 3 numbers"));
    CHECK_THAT(error_of("Film \"rgb\" \"integer xresolution\" 1.5\n"),
               Contains("1.5 is not a 32-bit integer"));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"float radius\" \"one\"\n"),
               Contains("parameter \"float radius\" takes numbers"));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"string radius\" \"one\"\n"),
               Contains("Shape \"sphere\": parameter \"string radius\" must be \"float radius\""));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"float radius\" 1 \"float radius\" 2\n"),
               Contains("parameter 'radius' is given twice (first at test.pbrt:4:16)"));
    CHECK_THAT(error_of_world("Shape \"sphere\" \"float radius\" -1\n"),
               Contains("test.pbrt:4:1: Shape \"sphere\": radius -1 must be > 0"));
    // Sampled spectra: one value or whole (wavelength, value) pairs (the fuzzer found an
    // empty light spectrum read past its end).
    CHECK_THAT(error_of_world("AreaLightSource \"diffuse\" \"spectrum L\" [ ]\n" + std::string(kQuad)),
               Contains("parameter \"spectrum L\" takes one value or (wavelength, value) pairs; got none"));
    CHECK_THAT(error_of_world("Material \"diffuse\" \"spectrum reflectance\" [ ]\n" + std::string(kQuad)),
               Contains("got none"));
    // Block structure
    CHECK_THAT(error_of_world("AttributeEnd\n"), Contains("test.pbrt:4:1: AttributeEnd without"));
    CHECK_THAT(error_of_world("AttributeBegin\n" + std::string(kQuad)),
               Contains("test.pbrt:4:1: AttributeBegin is never closed"));
    CHECK_THAT(error_of_world("AttributeBegin\nTransformEnd\n"),
               Contains("test.pbrt:5:1: TransformEnd closes the AttributeBegin at test.pbrt:4:1"));
    CHECK_THAT(error_of(std::string(kQuad)), Contains("test.pbrt:1:1: Shape is only allowed after "
                                                      "WorldBegin"));
    CHECK_THAT(error_of("WorldBegin\nCamera \"perspective\"\n"),
               Contains("test.pbrt:2:1: Camera is only allowed before WorldBegin"));
    CHECK_THAT(error_of(std::string(kHead)), Contains("test.pbrt: no WorldBegin"));
    CHECK_THAT(error_of("WorldBegin\nWorldBegin\n"), Contains("test.pbrt:2:1: a second WorldBegin"));
    CHECK_THAT(error_of_world("Shape \"cylinder\"\n"),
               Contains("test.pbrt: no shape that wavepath can render (1 skipped)"));
    // Meshes
    CHECK_THAT(error_of_world("Shape \"trianglemesh\" \"integer indices\" [ 0 1 2 ]\n"),
               Contains("Shape \"trianglemesh\": missing \"point3 P\""));
    CHECK_THAT(error_of_world("Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] "
                              "\"integer indices\" [ 0 1 3 ]\n"),
               Contains("index 3 is out of range (there are 3 vertices)"));
    CHECK_THAT(error_of_world("Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] "
                              "\"integer indices\" [ 0 1 ]\n"),
               Contains("2 indices is not a multiple of 3"));
    CHECK_THAT(error_of_world("Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] "
                              "\"normal N\" [ 0 0 1 ]\n"),
               Contains("1 normals for 3 positions"));
    CHECK_THAT(error_of_world("Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 ]\n"),
               Contains("parameter \"point3 P\" takes triples of numbers"));
    CHECK_THAT(error_of_world("Shape \"plymesh\" \"string filename\" \"nowhere.ply\"\n"),
               Contains("test.pbrt:4:1: Shape \"plymesh\": mesh file") && Contains("not found"));
    // Materials and textures (resolved at the end, reported where they were named)
    CHECK_THAT(error_of_world("NamedMaterial \"nope\"\n" + std::string(kQuad)),
               Contains("test.pbrt:4:1: no MakeNamedMaterial \"nope\" in the scene"));
    CHECK_THAT(error_of_world("MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
                              "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"),
               Contains("test.pbrt:5:1: MakeNamedMaterial \"a\": redefined (first at test.pbrt:4:1)"));
    CHECK_THAT(error_of_world("MakeNamedMaterial \"a\" \"rgb reflectance\" [ 1 1 1 ]\n"),
               Contains("missing \"string type\""));
    CHECK_THAT(error_of_world("Material \"diffuse\" \"texture reflectance\" \"tx\"\n" +
                              std::string(kQuad)),
               Contains("test.pbrt:4:20: no spectrum texture \"tx\" is defined"));
    CHECK_THAT(error_of_world("Texture \"t\" \"colour\" \"constant\"\n"),
               Contains("must be \"spectrum\" or \"float\""));
    CHECK_THAT(error_of_world("Material \"conductor\" \"rgb reflectance\" [ .5 .5 .5 ] \"rgb k\" "
                              "[ 1 1 1 ]\n" + std::string(kQuad)),
               Contains("give either \"reflectance\" or \"eta\" and \"k\""));
    CHECK_THAT(error_of_world("Material \"dielectric\" \"float eta\" 1000\n" + std::string(kQuad)),
               Contains("index of refraction 1000 is out of range"));
    // Lights
    CHECK_THAT(error_of_world("AreaLightSource \"diffuse\" \"rgb L\" [ -1 1 1 ]\n"),
               Contains("radiance (-1, 1, 1) must be finite and >= 0"));
    CHECK_THAT(error_of_world("LightSource \"infinite\" \"rgb L\" [ 1 1 1 ] \"string filename\" "
                              "\"a.exr\"\n"),
               Contains("give either \"L\" or \"filename\""));
    // Instances
    CHECK_THAT(error_of_world("ObjectInstance \"ghost\"\n" + std::string(kQuad)),
               Contains("test.pbrt:4:1: ObjectInstance \"ghost\": no ObjectBegin \"ghost\""));
    CHECK_THAT(error_of_world("ObjectBegin \"a\"\nObjectBegin \"b\"\n"),
               Contains("ObjectBegin \"b\" inside ObjectBegin \"a\""));
    CHECK_THAT(error_of_world("ObjectEnd\n"), Contains("ObjectEnd without ObjectBegin"));
    // Camera
    CHECK_THAT(error_of("Camera \"perspective\" \"float fov\" 180\nWorldBegin\n" + std::string(kQuad)),
               Contains("fov 180 is out of range"));
    CHECK_THAT(error_of("LookAt 0 0 0  0 0 0  0 1 0\n"), Contains("LookAt: the eye and the point"));
    CHECK_THAT(error_of("LookAt 0 0 0  0 1 0  0 1 0\n"),
               Contains("LookAt: the up vector is parallel"));
    CHECK_THAT(error_of("Rotate 10 0 0 0\n"), Contains("Rotate: the axis is zero"));
    CHECK_THAT(error_of("Transform [ 1 0 0 ]\n"), Contains("Transform: expected 16 numbers, found 3"));
    CHECK_THAT(error_of("Film \"rgb\" \"integer xresolution\" 0\nWorldBegin\n" + std::string(kQuad)),
               Contains("Film: size 0 x 720 is out of range"));
    CHECK_THAT(error_of("Sampler \"sobol\" \"integer pixelsamples\" 0\nWorldBegin\n" +
                        std::string(kQuad)),
               Contains("pixelsamples 0 is out of range"));
    // Encodings
    CHECK_THAT(error_of(std::string("\xFF\xFE") + "W\0o"), Contains("UTF-16"));
}

TEST_CASE("pbrt: load_pbrt and load_scene_file refuse missing files", "[scene][pbrt][parser]") {
    CHECK_THROWS_WITH(load_pbrt("/nonexistent/scene.pbrt"),
                      Contains("/nonexistent/scene.pbrt") && Contains("no such file"));
    CHECK_THROWS_WITH(load_scene_file("/nonexistent/scene.pbrt"), Contains("not found"));
}

TEST_CASE("pbrt: unsupported things warn once per kind with their place and count",
          "[scene][pbrt][parser]") {
    Scene s = parse_world(std::string(kQuad) +
                          "Shape \"sphere\" \"float bogus\" 1\n"
                          "Shape \"sphere\" \"float bogus\" 2\n"
                          "LightSource \"point\" \"rgb I\" [ 1 1 1 ]\n"
                          "LightSource \"spot\"\n"
                          "Shape \"curve\"\n"
                          "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n"
                          "Material \"hair\"\n" + std::string(kQuad));
    INFO(all_warnings(s));
    CHECK(count_warnings(s, "parameter \"float bogus\" of Shape \"sphere\" is not supported") == 1);
    CHECK(has_warning(s, "test.pbrt:5:16: parameter \"float bogus\""));
    CHECK(has_warning(s, "(2 times; the first here)"));
    CHECK(has_warning(s, "test.pbrt:7:1: LightSource \"point\" is not supported"));
    CHECK(has_warning(s, "LightSource \"spot\" is not supported"));
    CHECK(has_warning(s, "Shape \"curve\" is not supported; skipped"));
    CHECK(has_warning(s, "participating media are not supported"));
    CHECK(has_warning(s, "material \"hair\" is not supported; rendered as diffuse 0.5"));
}

// --- Transforms and the graphics state ----------------------------------------------------------

TEST_CASE("pbrt: transforms compose as pbrt's CTM (CTM = CTM * step), Transform is column by "
          "column", "[scene][pbrt][parser]") {
    auto one_point = [](const std::string& xf) {
        Scene s = parse_world(xf + "\nShape \"trianglemesh\" \"point3 P\" [ 1 0 0  0 1 0  0 0 1 ] "
                                   "\"integer indices\" [ 0 1 2 ]\n");
        return glm::dvec3(s.positions.at(0));
    };
    // Translate then Scale: the point is scaled first, then translated
    check_vec(one_point("Translate 1 0 0 Scale 2 2 2"), {3, 0, 0});
    check_vec(one_point("Scale 2 2 2 Translate 1 0 0"), {4, 0, 0});
    // Rotate 90 about z (right-handed): x -> y
    check_vec(one_point("Rotate 90 0 0 1"), {0, 1, 0});
    // Transform: the last four numbers are the translation (column 3)
    check_vec(one_point("Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 ]"), {6, 6, 7});
    check_vec(one_point("Translate 1 0 0 ConcatTransform [ 2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1 ]"),
              {3, 0, 0});
    check_vec(one_point("Translate 9 9 9 Identity"), {1, 0, 0});
    // Blocks: AttributeEnd and TransformEnd restore the transform
    check_vec(one_point("AttributeBegin Translate 1 0 0 AttributeEnd"), {1, 0, 0});
    check_vec(one_point("TransformBegin Translate 1 0 0 TransformEnd"), {1, 0, 0});
    // Named coordinate systems
    check_vec(one_point("Translate 0 5 0 CoordinateSystem \"up\" Identity CoordSysTransform \"up\""),
              {1, 5, 0});
    // ActiveTransform EndTime: ignored (the start time's transform is used)
    check_vec(one_point("ActiveTransform EndTime Translate 4 0 0 ActiveTransform All"), {1, 0, 0});
}

TEST_CASE("pbrt: the front (emitting side) follows pbrt: N, else winding, mirroring and "
          "ReverseOrientation", "[scene][pbrt][parser]") {
    const std::string tri = "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0 ] "
                            "\"integer indices\" [ 0 1 2 ]";
    auto z_of_front = [&](const std::string& pre, const std::string& extra = "") {
        Scene s = parse_world(pre + "\n" + tri + " " + extra + "\n");
        return glm::normalize(measure(s).normal_sum).z;
    };
    CHECK(z_of_front("") == Approx(1));                       // counter-clockwise from +z
    CHECK(z_of_front("ReverseOrientation") == Approx(-1));    // reversed
    // Mirrored: the plane z = 0 stays where it is, but its object-side +z maps to world -z
    // (pbrt's transformSwapsHandedness flips the normal), so the front faces -z
    CHECK(z_of_front("Scale 1 1 -1") == Approx(-1));
    // With N the front faces N whatever the winding and ReverseOrientation (pbrt's FaceForward)
    CHECK(z_of_front("", "\"normal N\" [ 0 0 -1  0 0 -1  0 0 -1 ]") == Approx(-1));
    CHECK(z_of_front("ReverseOrientation", "\"normal N\" [ 0 0 1  0 0 1  0 0 1 ]") == Approx(1));
    // A mirrored sphere stays outward (positive signed volume); ReverseOrientation turns it in
    Scene a = parse_world("Scale -1 1 1\nShape \"sphere\"\n");
    CHECK(measure(a).volume > 4.0);
    Scene b = parse_world("ReverseOrientation\nShape \"sphere\"\n");
    CHECK(measure(b).volume < -4.0);
    // ... and its shading normals with it
    const glm::vec3 p = b.positions[b.triangles[0].x], n = b.normals[b.triangles[0].x];
    CHECK(glm::dot(p, n) < 0.0f);
}

TEST_CASE("pbrt: Attribute sets defaults; Include and Import resolve against the main file's "
          "folder; Import keeps the state", "[scene][pbrt][parser]") {
    Scene s = parse_world("Attribute \"shape\" \"float radius\" 2\nShape \"sphere\"\n");
    CHECK(measure(s).hi.x == Approx(2.0).epsilon(2e-3));

    TempDir d;
    d.write("sub/inc.pbrt", "Translate 0 0 3\nInclude \"sub/inc2.pbrt\"\n");
    d.write("sub/inc2.pbrt", kQuad);
    d.write("sub/imp.pbrt", "Translate 0 0 7\nMaterial \"conductor\"\n" + std::string(kQuad));
    d.write("main.pbrt", std::string(kHead) + "WorldBegin\nInclude \"sub/inc.pbrt\"\n"
                                              "Import \"sub/imp.pbrt\"\n" + kQuad);
    Scene t = load_pbrt(d.path / "main.pbrt");
    INFO(all_warnings(t));
    REQUIRE(t.triangle_count() == 6);
    // Include shares the state: the third quad is translated by 3 too; Import does not leak
    // its transform or its material
    CHECK(t.positions[t.triangles[0].x].z == Approx(3));
    CHECK(t.positions[t.triangles[2].x].z == Approx(10));
    CHECK(t.positions[t.triangles[4].x].z == Approx(3));
    CHECK(t.materials[t.material_ids[2]].kind == MaterialKind::Conductor);
    CHECK(t.materials[t.material_ids[4]].kind == MaterialKind::Diffuse);

    // Errors: a missing file, a cycle, Import outside the world
    d.write("missing.pbrt", std::string(kHead) + "WorldBegin\n\nInclude \"nothere.pbrt\"\n");
    CHECK_THROWS_WITH(load_pbrt(d.path / "missing.pbrt"),
                      Contains("missing.pbrt:5:1: Include \"nothere.pbrt\":") &&
                          Contains("no such file"));
    d.write("a.pbrt", "WorldBegin\nInclude \"b.pbrt\"\n");
    d.write("b.pbrt", "Include \"a.pbrt\"\n");
    CHECK_THROWS_WITH(load_pbrt(d.path / "a.pbrt"),
                      Contains("b.pbrt:1:1: Include \"a.pbrt\": the file includes itself"));
    d.write("self.pbrt", "Include \"self.pbrt\"\n");
    CHECK_THROWS_WITH(load_pbrt(d.path / "self.pbrt"), Contains("includes itself"));
    d.write("imp.pbrt", "Import \"sub/inc2.pbrt\"\n");
    CHECK_THROWS_WITH(load_pbrt(d.path / "imp.pbrt"),
                      Contains("imp.pbrt:1:1: Import is only allowed after WorldBegin"));
    d.write("open.pbrt", "AttributeBegin\n");
    d.write("bad-import.pbrt", "WorldBegin\nImport \"open.pbrt\"\n");
    CHECK_THROWS_WITH(load_pbrt(d.path / "bad-import.pbrt"), Contains("still open at the end"));
    // A diamond of includes cannot blow up: the number of files is capped
    for (int i = 0; i < 14; ++i)
        d.write("d" + std::to_string(i) + ".pbrt",
                "Include \"d" + std::to_string(i + 1) + ".pbrt\"\nInclude \"d" +
                    std::to_string(i + 1) + ".pbrt\"\n");
    d.write("d14.pbrt", "# leaf\n");
    d.write("diamond.pbrt", "WorldBegin\nInclude \"d0.pbrt\"\n");
    CHECK_THROWS_WITH(load_pbrt(d.path / "diamond.pbrt"), Contains("files included in all"));
}

TEST_CASE("pbrt: ObjectBegin/ObjectInstance are flattened with the instance's transform",
          "[scene][pbrt][parser]") {
    Scene s = parse_world("ObjectBegin \"q\"\nTranslate 0 0 1\n" + std::string(kQuad) +
                          "ObjectEnd\n"
                          "ObjectInstance \"q\"\n"
                          "AttributeBegin Translate 10 0 0 ObjectInstance \"q\" AttributeEnd\n"
                          "AttributeBegin Scale -1 1 1 ObjectInstance \"q\" AttributeEnd\n");
    REQUIRE(s.triangle_count() == 6);
    Measure m = measure(s);
    CHECK(m.lo.x == Approx(-1));
    CHECK(m.hi.x == Approx(11));
    CHECK(m.lo.z == Approx(1));
    // Every copy keeps its front towards +z (the mirrored one too)
    for (std::size_t t = 0; t < 6; ++t) {
        const auto& tr = s.triangles[t];
        const glm::vec3 n = glm::cross(s.positions[tr.y] - s.positions[tr.x],
                                       s.positions[tr.z] - s.positions[tr.x]);
        CHECK(n.z > 0.0f);
    }
    // The flattened scene is capped (util/limits.h): 7,000 instances of a 5,120-triangle sphere
    // pass 2^25 at the 6,554th, which is named before anything is allocated
    std::string many = "ObjectBegin \"s\"\nShape \"sphere\"\nObjectEnd\n";
    for (int i = 0; i < 7000; ++i) many += "ObjectInstance \"s\"\n";
    CHECK_THAT(error_of_world(many),
               Contains("test.pbrt:6560:1: ObjectInstance \"s\": the flattened scene would have "
                        "more than 33554432 triangles"));
    // Area lights inside an object are not instanced as lights (as pbrt-v4)
    Scene l = parse_world("ObjectBegin \"l\"\nAreaLightSource \"diffuse\"\n" + std::string(kQuad) +
                          "ObjectEnd\nObjectInstance \"l\"\n");
    CHECK(has_warning(l, "area lights inside ObjectBegin are not supported"));
    CHECK_FALSE(only_material(l).emissive());
}

// --- Camera and render settings ---------------------------------------------------------------

TEST_CASE("pbrt: the camera: LookAt, fov on the shorter axis, screenwindow, mirrored frames",
          "[scene][pbrt][parser]") {
    auto cam = [](const std::string& opts) {
        return parse(opts + "\nWorldBegin\n" + kQuad);
    };
    // Scale -1 1 1 + LookAt: pbrt's idiom for a right-handed view, not mirrored
    Scene a = cam("Scale -1 1 1 LookAt 1 2 3  1 2 0  0 1 0\nCamera \"perspective\" \"float fov\" "
                  "30\nFilm \"rgb\" \"integer xresolution\" 640 \"integer yresolution\" 480");
    check_vec(a.camera.position, {1, 2, 3});
    check_vec(glm::normalize(glm::dvec3(a.camera.target - a.camera.position)), {0, 0, -1});
    check_vec(a.camera.up, {0, 1, 0});
    CHECK(a.camera.vfov_deg == Approx(30));  // landscape: the fov is the vertical one
    CHECK_FALSE(has_warning(a, "mirrored"));
    // A plain LookAt: pbrt's image is mirrored relative to a right-handed view: a warning
    Scene b = cam("LookAt 1 2 3  1 2 0  0 1 0\nCamera \"perspective\" \"float fov\" 30");
    CHECK(has_warning(b, "renders this camera's image mirrored"));
    // Portrait: the fov is the horizontal one: tan(v/2) = tan(15°) * 640 / 480
    Scene c = cam("Scale -1 1 1 LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\" \"float fov\" 30\n"
                  "Film \"rgb\" \"integer xresolution\" 480 \"integer yresolution\" 640");
    CHECK(c.camera.vfov_deg ==
          Approx(2 * std::atan(std::tan(15 * kPi / 180) * 640.0 / 480.0) * 180 / kPi));
    // screenwindow scales the vertical extent
    Scene d = cam("Scale -1 1 1 LookAt 0 0 5 0 0 0 0 1 0\nCamera \"perspective\" \"float fov\" 30 "
                  "\"float screenwindow\" [ -0.5 0.5 -0.5 0.5 ]\nFilm \"rgb\" "
                  "\"integer xresolution\" 100 \"integer yresolution\" 100");
    CHECK(d.camera.vfov_deg == Approx(2 * std::atan(0.5 * std::tan(15 * kPi / 180)) * 180 / kPi));
    CHECK_FALSE(has_warning(d, "screenwindow"));
    // Defaults: pbrt-v4's fov 90, 1280 x 720, 16 spp, maxdepth 5
    Scene e = cam("");
    CHECK(e.camera.width == 1280);
    CHECK(e.camera.height == 720);
    CHECK(e.render.spp == 16);
    CHECK(e.render.depth == 5);
    CHECK(has_warning(e, "no Camera"));
    Scene f = cam("Camera \"perspective\"\nSampler \"halton\" \"integer pixelsamples\" 8\n"
                  "Integrator \"volpath\" \"integer maxdepth\" 7");
    CHECK(f.camera.vfov_deg == Approx(2 * std::atan(std::tan(45 * kPi / 180)) * 180 / kPi));
    CHECK(f.render.spp == 8);
    CHECK(f.render.depth == 7);  // pbrt's maxdepth counts bounces, as --depth does
    Scene g = cam("Camera \"perspective\" \"float lensradius\" 0.1 \"float focaldistance\" 4\n"
                  "Integrator \"bdpt\" \"integer maxdepth\" 3");
    CHECK(has_warning(g, "Integrator \"bdpt\" is not supported"));
    CHECK(g.render.depth == 3);
    CHECK(g.camera.lens_radius == 0.1f);  // thin lens: pbrt's plane in focus at camera z = 4
    CHECK(g.camera.focus_distance == 4.0f);
    CHECK(e.camera.lens_radius == 0.0f);
    // The camera's inverse transform: pbrt's camera space has +x right, +y up, +z forward
    Scene h = cam("Transform [ 1 0 0 0  0 1 0 0  0 0 -1 0  0 -1 6.8 1 ]\nCamera \"perspective\"");
    check_vec(h.camera.position, {0, 1, 6.8});
    check_vec(glm::normalize(glm::dvec3(h.camera.target - h.camera.position)), {0, 0, -1});
    CHECK_FALSE(has_warning(h, "mirrored"));
}

// --- Shapes ------------------------------------------------------------------------------------

TEST_CASE("pbrt: trianglemesh uvs become wavepath's (v down), normals are kept",
          "[scene][pbrt][parser]") {
    Scene s = parse_world(
        "Texture \"t\" \"spectrum\" \"checkerboard\"\n"
        "Material \"diffuse\" \"texture reflectance\" \"t\"\n"
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 0 ] \"integer indices\" [ 0 1 2 ] "
        "\"point2 uv\" [ 0 0  1 0.25  0 1 ] \"normal N\" [ 0 0 2  0 0 2  0 0 2 ]\n");
    REQUIRE(s.uvs.size() == 3);
    CHECK(s.uvs[0] == glm::vec2(0, 1));
    CHECK(s.uvs[1] == glm::vec2(1, 0.75f));
    CHECK(s.uvs[2] == glm::vec2(0, 0));
    CHECK(s.normals[0] == glm::vec3(0, 0, 1));
}

TEST_CASE("pbrt: bilinearmesh, sphere, disk and loopsubdiv", "[scene][pbrt][parser]") {
    // A bilinear patch p00 p10 p01 p11: two triangles facing dp/du x dp/dv = +z
    Scene b = parse_world("Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0  2 0 0  0 3 0  2 3 0 ]\n");
    Measure mb = measure(b);
    CHECK(mb.triangles == 2);
    CHECK(mb.area == Approx(6));
    check_vec(glm::normalize(mb.normal_sum), {0, 0, 1});
    // A non-planar one warns
    Scene nb = parse_world("Shape \"bilinearmesh\" \"point3 P\" [ 0 0 0  1 0 0  0 1 0  1 1 1 ] "
                           "\"integer indices\" [ 0 1 2 3 ]\n");
    CHECK(has_warning(nb, "non-planar bilinear patches"));
    // Sphere: 5,120 triangles, area 4 pi r^2, centred by the transform, normals outward
    Scene s = parse_world("Translate 1 2 3\nShape \"sphere\" \"float radius\" 0.5\n");
    Measure ms = measure(s);
    CHECK(ms.triangles == 5120);
    CHECK(ms.area == Approx(4 * kPi * 0.25).epsilon(1e-5));
    check_vec(0.5 * (ms.lo + ms.hi), {1, 2, 3}, 1e-3);
    CHECK(ms.volume > 0);
    for (std::size_t i = 0; i < s.positions.size(); i += 97)
        CHECK(glm::dot(s.normals[i], s.positions[i] - glm::vec3(1, 2, 3)) > 0.49f);
    Scene ps = parse_world("Shape \"sphere\" \"float zmin\" 0\n");
    CHECK(has_warning(ps, "partial spheres"));
    // Disk and annulus at z = height, front +z
    Scene d = parse_world("Shape \"disk\" \"float radius\" 2 \"float height\" 0.5\n");
    Measure md = measure(d);
    CHECK(md.area == Approx(kPi * 4).epsilon(1e-5));
    check_vec(glm::normalize(md.normal_sum), {0, 0, 1});
    CHECK(md.lo.z == Approx(0.5));
    Scene an = parse_world("Shape \"disk\" \"float radius\" 2 \"float innerradius\" 1\n");
    CHECK(measure(an).area == Approx(kPi * 3).epsilon(1e-5));
    // loopsubdiv: its control mesh, with a note
    Scene l = parse_world("Shape \"loopsubdiv\" \"integer levels\" 3 \"point3 P\" [ 0 0 0 1 0 0 "
                          "0 1 0 ] \"integer indices\" [ 0 1 2 ]\n");
    CHECK(l.triangle_count() == 1);
    CHECK(has_warning(l, "loopsubdiv is rendered as its control mesh"));
}

TEST_CASE("pbrt: plymesh reads the PLY through the mesh loader, relative to the main file",
          "[scene][pbrt][parser]") {
    TempDir d;
    d.write("models/tri.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty float z\nelement face 1\n"
                              "property list uchar int vertex_indices\nend_header\n"
                              "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    d.write("scene.pbrt", std::string(kHead) + "WorldBegin\nTranslate 0 0 2\n"
                                               "Shape \"plymesh\" \"string filename\" "
                                               "\"models/tri.ply\" \"texture displacement\" \"x\"\n");
    Scene s = load_scene_file(d.path / "scene.pbrt");
    REQUIRE(s.triangle_count() == 1);
    CHECK(s.positions[s.triangles[0].y] == glm::vec3(1, 0, 2));
    CHECK(has_warning(s, "plymesh displacement is not supported"));
}

// --- Materials ----------------------------------------------------------------------------------

TEST_CASE("pbrt: materials map to wavepath's kinds (contract14's pbrt-v4 mapping)",
          "[scene][pbrt][parser]") {
    auto mat = [](const std::string& m) {
        Scene s = parse_world(m + "\n" + kQuad);
        INFO(all_warnings(s));
        return std::pair<Material, Scene>(only_material(s), s);
    };
    {
        auto [m, s] = mat("Material \"diffuse\" \"rgb reflectance\" [ 0.1 0.2 1.5 ]");
        CHECK(m.kind == MaterialKind::Diffuse);
        CHECK(m.albedo == glm::vec3(0.1f, 0.2f, 1.0f));  // clamped to [0, 1] as pbrt does
        CHECK(has_warning(s, "clamped to [0, 1]"));
    }
    {
        auto [m, s] = mat("Material \"diffuse\"");
        CHECK(m.albedo == glm::vec3(0.5f));  // pbrt-v4's default
    }
    {
        // Named metals: Tungsten's RGB fits (ComplexIorData.hpp, Au)
        auto [m, s] = mat("Material \"conductor\" \"spectrum eta\" \"metal-Au-eta\" "
                          "\"spectrum k\" \"metal-Au-k\"");
        CHECK(m.kind == MaterialKind::Conductor);  // roughness 0: smooth
        check_vec(m.eta, {0.1431189557, 0.3749570432, 1.4424785571}, 1e-6);
        check_vec(m.k, {3.9831604247, 2.3857207478, 1.6032152899}, 1e-6);
        CHECK(m.albedo == glm::vec3(1.0f));
    }
    {
        // Default: copper
        auto [m, s] = mat("Material \"conductor\" \"float roughness\" 0.01");
        check_vec(m.eta, {0.2004376970, 0.9240334304, 1.1022119527}, 1e-6);
        CHECK(m.kind == MaterialKind::RoughConductor);
        CHECK(m.alpha == Approx(0.1));  // remapped: sqrt(0.01)
        CHECK_FALSE(m.alpha_v.has_value());
        CHECK(m.distribution == MicrofacetModel::GGX);
        CHECK_FALSE(m.separable_g);  // pbrt-v4: height-correlated masking
    }
    {
        auto [m, s] = mat("Material \"conductor\" \"float uroughness\" 0.05 \"float vroughness\" "
                          "0.2 \"bool remaproughness\" false \"rgb eta\" [ 1 2 3 ] \"rgb k\" "
                          "[ 4 5 6 ]");
        CHECK(m.alpha == Approx(0.05));
        REQUIRE(m.alpha_v.has_value());
        CHECK(*m.alpha_v == Approx(0.2));
        CHECK(m.eta == glm::vec3(1, 2, 3));
        CHECK(m.k == glm::vec3(4, 5, 6));
        // α_u runs along dp/du as in pbrt-v4 (p1 − p0 without uvs, as pbrt's default uvs
        // give): nothing to warn about
        CHECK_FALSE(has_warning(s, "anisotropic"));
    }
    {
        // pbrt treats alpha < 1e-3 as smooth (EffectivelySmooth)
        auto [m, s] = mat("Material \"conductor\" \"float roughness\" 0.0009 \"bool "
                          "remaproughness\" false");
        CHECK(m.kind == MaterialKind::Conductor);
    }
    {
        // Artist mode: eta 1 and k such that the normal-incidence reflectance is r:
        // F0 = ((eta - 1)^2 + k^2) / ((eta + 1)^2 + k^2)
        auto [m, s] = mat("Material \"conductor\" \"rgb reflectance\" [ 0.9 0.5 0.1 ]");
        CHECK(m.eta == glm::vec3(1.0f));
        const glm::vec3 r(0.9f, 0.5f, 0.1f);
        for (int c = 0; c < 3; ++c) {
            const double k = m.k[c];
            CHECK(k * k / (4.0 + k * k) == Approx(r[c]).epsilon(1e-5));
        }
    }
    {
        auto [m, s] = mat("Material \"dielectric\" \"float eta\" 1.33");
        CHECK(m.kind == MaterialKind::Glass);
        CHECK(m.ior == Approx(1.33f));
        CHECK(m.albedo == glm::vec3(1.0f));
        CHECK(m.specular == glm::vec3(1.0f));
    }
    {
        auto [m, s] = mat("Material \"dielectric\" \"spectrum eta\" \"glass-BK7\" \"float "
                          "roughness\" 0.04");
        CHECK(m.kind == MaterialKind::RoughDielectric);
        CHECK(m.ior == Approx(1.5168f));  // Schott N-BK7 n_d
        CHECK(m.alpha == Approx(0.2));
        CHECK(has_warning(s, "named glass spectra become their index at 587.6 nm"));
    }
    {
        auto [m, s] = mat("Material \"dielectric\"");
        CHECK(m.ior == Approx(1.5f));  // pbrt-v4's default
    }
    {
        auto [m, s] = mat("Material \"thindielectric\" \"float eta\" 1.4");
        CHECK(m.kind == MaterialKind::ThinDielectric);
        CHECK(m.ior == Approx(1.4f));
    }
    {
        auto [m, s] = mat("Material \"coateddiffuse\" \"rgb reflectance\" [ 0.9 0.8 0.7 ] "
                          "\"float roughness\" 0.01 \"bool remaproughness\" false");
        CHECK(m.kind == MaterialKind::RoughPlastic);
        CHECK(m.albedo == glm::vec3(0.9f, 0.8f, 0.7f));
        CHECK(m.ior == Approx(1.5f));
        CHECK(m.alpha == Approx(0.01f));
        CHECK(m.nonlinear);
        CHECK(has_warning(s, "coateddiffuse is approximated by Mitsuba's plastic"));
    }
    {
        auto [m, s] = mat("Material \"coateddiffuse\"");
        CHECK(m.kind == MaterialKind::Plastic);
        CHECK(m.albedo == glm::vec3(0.5f));
    }
    {
        auto [m, s] = mat("Material \"coatedconductor\" \"spectrum conductor.eta\" "
                          "\"metal-Ag-eta\" \"spectrum conductor.k\" \"metal-Ag-k\" \"float "
                          "interface.roughness\" 0.1");
        CHECK(m.kind == MaterialKind::Conductor);
        check_vec(m.eta, {0.1552646489, 0.1167232965, 0.1383806959}, 1e-6);
        CHECK(has_warning(s, "the dielectric coat is dropped"));
        CHECK_FALSE(has_warning(s, "interface.roughness"));
    }
    {
        auto [m, s] = mat("Material \"diffusetransmission\"");
        CHECK(m.kind == MaterialKind::Diffuse);
        CHECK(m.albedo == glm::vec3(0.25f));
        CHECK(has_warning(s, "diffusetransmission is rendered as diffuse"));
    }
    {
        auto [m, s] = mat("Material \"conductor\" \"spectrum eta\" \"metal-CuZn-eta\" \"spectrum "
                          "k\" \"metal-CuZn-k\"");
        check_vec(m.eta, {0.2004376970, 0.9240334304, 1.1022119527}, 1e-6);
        CHECK(has_warning(s, "\"metal-CuZn-eta\" is not in wavepath's table of metals"));
    }
    {
        // Named materials, forward references and mix (the larger weight)
        Scene s = parse_world("NamedMaterial \"m\"\n" + std::string(kQuad) +
                              "MakeNamedMaterial \"a\" \"string type\" \"diffuse\" \"rgb "
                              "reflectance\" [ .1 .1 .1 ]\n"
                              "MakeNamedMaterial \"b\" \"string type\" \"conductor\"\n"
                              "MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string "
                              "materials\" [ \"a\" \"b\" ] \"float amount\" 0.7\n");
        CHECK(only_material(s).kind == MaterialKind::Conductor);
        CHECK(has_warning(s, "mix materials are rendered as the one with the larger weight"));
    }
    {
        // interface: the shapes are left out; an emitting one stays as a black emitter
        Scene s = parse_world("Material \"interface\"\n" + std::string(kQuad) +
                              "Material \"diffuse\"\nShape \"sphere\"\n");
        CHECK(s.triangle_count() == 5120);
        CHECK(has_warning(s, "they are left out"));
    }
    CHECK_THAT(error_of_world("MakeNamedMaterial \"m\" \"string type\" \"mix\" \"string "
                              "materials\" [ \"m\" \"m\" ]\nNamedMaterial \"m\"\n" +
                              std::string(kQuad)),
               Contains("contains itself"));
}

// --- Textures ----------------------------------------------------------------------------------

TEST_CASE("pbrt: imagemap and checkerboard textures: pbrt's uv mapping in wavepath's uvs",
          "[scene][pbrt][parser][texture]") {
    TempDir d;
    write_exr(d.path / "img.exr", 4, 2, [](int x, int y) { return glm::vec3(0.1f * float(x + 4 * y)); });
    const std::string quad_uv =
        "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 1 1 0 0 1 0 ] \"integer indices\" "
        "[ 0 1 2 0 2 3 ] \"point2 uv\" [ 0 0 1 0 1 1 0 1 ]\n";
    d.write("s.pbrt", std::string(kHead) + "WorldBegin\n"
                      "Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"img.exr\" "
                      "\"float uscale\" 3 \"float vscale\" 2 \"float udelta\" 0.25 \"float "
                      "vdelta\" 0.1 \"float scale\" 0.5\n"
                      "Material \"diffuse\" \"texture reflectance\" \"img\"\n" + quad_uv);
    Scene s = load_pbrt(d.path / "s.pbrt");
    INFO(all_warnings(s));
    const Material& m = only_material(s);
    REQUIRE(m.albedo_map.used());
    CHECK(m.albedo == glm::vec3(0.5f));  // the texture's scale
    CHECK(s.textures.at(std::size_t(m.albedo_map.image)).width == 4);
    // pbrt looks the image up at (s, 1 - t), (s, t) = (su u + du, sv v + dv), image (0, 0) at
    // the top left; wavepath at uv_transform * (u, 1 - v) in the same image coordinates
    for (double u : {0.0, 0.3, 0.9})
        for (double v : {0.0, 0.45, 1.0}) {
            const glm::vec2 want(float(3 * u + 0.25), float(1 - (2 * v + 0.1)));
            const glm::vec2 got = glm::vec2(m.albedo_map.uv_transform * glm::vec3(float(u), float(1 - v), 1.0f));
            CHECK(got.x == Approx(want.x).margin(1e-6));
            CHECK(got.y == Approx(want.y).margin(1e-6));
        }
    // The stored uvs are (u, 1 - v)
    CHECK(s.uvs.at(s.triangles[0].x) == glm::vec2(0, 1));

    // Checkerboard: pbrt's tex1 where floor(s) + floor(t) is even
    d.write("c.pbrt", std::string(kHead) + "WorldBegin\n"
                      "Texture \"c\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [ 0.9 0.8 0.7 ] "
                      "\"rgb tex2\" [ 0.1 0.2 0.3 ] \"float uscale\" 5 \"float vscale\" 3 "
                      "\"float udelta\" 0.3\n"
                      "Material \"diffuse\" \"texture reflectance\" \"c\"\n" + quad_uv);
    Scene c = load_pbrt(d.path / "c.pbrt");
    const Material& mc = only_material(c);
    REQUIRE(mc.albedo_map.used());
    const Texture& tc = c.textures.at(std::size_t(mc.albedo_map.image));
    REQUIRE(tc.width == 2);
    CHECK(texel_at(tc, 0, 0, 0) == Approx(0.9f));
    int checked = 0;
    for (int i = 0; i < 37; ++i)
        for (int j = 0; j < 23; ++j) {
            const double u = (i + 0.5) / 37.0, v = (j + 0.5) / 23.0;
            const double ss = 5 * u + 0.3, tt = 3 * v;
            if (std::abs(ss - std::round(ss)) < 1e-3 || std::abs(tt - std::round(tt)) < 1e-3)
                continue;  // on a cell border
            const bool pbrt_tex1 = (int(std::floor(ss)) + int(std::floor(tt))) % 2 == 0;
            // wavepath's checker (texture.h): c0 where (u' mod 1 < 1/2) == (v' mod 1 < 1/2)
            const glm::vec3 w = mc.albedo_map.uv_transform * glm::vec3(float(u), float(1 - v), 1.0f);
            const bool wp_c0 = (frac(w.x) < 0.5) == (frac(w.y) < 0.5);
            CHECK(wp_c0 == pbrt_tex1);
            ++checked;
        }
    CHECK(checked > 700);
}

TEST_CASE("pbrt: a material's normalmap becomes its normal map (linear data, pbrt's lookup)",
          "[scene][pbrt][parser][texture]") {
    TempDir d;
    write_exr(d.path / "n.exr", 2, 2, [](int, int) { return glm::vec3(0.5f, 0.5f, 1.0f); });
    d.write("s.pbrt", std::string(kHead) + "WorldBegin\nMaterial \"diffuse\" \"string "
                                           "normalmap\" \"n.exr\"\n"
                                           "Shape \"trianglemesh\" \"point3 P\" [ 0 0 0 1 0 0 0 1 "
                                           "0 ] \"point2 uv\" [ 0 0 1 0 0 1 ]\n");
    Scene s = load_pbrt(d.path / "s.pbrt");
    const Material& m = only_material(s);
    REQUIRE(m.normal_map.used());
    CHECK(m.normal_scale == 1.0f);
    CHECK(m.normal_map.uv_transform == glm::mat3(1.0f));  // the stored (u, 1 - v) is pbrt's lookup
    CHECK(s.textures.at(std::size_t(m.normal_map.image)).width == 2);
    CHECK(s.uvs.size() == s.positions.size());
}

TEST_CASE("pbrt: scale, mix and constant textures; missing images warn with a placeholder",
          "[scene][pbrt][parser][texture]") {
    Scene s = parse_world("Texture \"k\" \"spectrum\" \"constant\" \"rgb value\" [ 0.2 0.4 0.6 ]\n"
                          "Texture \"h\" \"spectrum\" \"scale\" \"texture tex\" \"k\" \"float "
                          "scale\" 0.5\n"
                          "Texture \"m\" \"spectrum\" \"mix\" \"texture tex1\" \"h\" \"rgb tex2\" "
                          "[ 1 1 1 ] \"float amount\" 0.25\n"
                          "Material \"diffuse\" \"texture reflectance\" \"m\"\n" + std::string(kQuad));
    // mix: 0.75 * (0.1, 0.2, 0.3) + 0.25 * 1
    check_vec(only_material(s).albedo, {0.325, 0.4, 0.475}, 1e-6);
    CHECK_FALSE(only_material(s).albedo_map.used());

    TempDir d;
    d.write("s.pbrt", std::string(kHead) + "WorldBegin\nTexture \"t\" \"spectrum\" \"imagemap\" "
                                           "\"string filename\" \"nowhere.png\"\n"
                                           "Material \"diffuse\" \"texture reflectance\" \"t\"\n" +
                          kQuad);
    Scene m = load_pbrt(d.path / "s.pbrt");
    CHECK(has_warning(m, "texture not loaded"));
    CHECK(only_material(m).albedo_map.used());
    Scene f = parse_world("Texture \"w\" \"spectrum\" \"wrinkled\"\nMaterial \"diffuse\" "
                          "\"texture reflectance\" \"w\"\n" + std::string(kQuad));
    CHECK(has_warning(f, "textures of class \"wrinkled\" are not supported"));
}

// --- Lights --------------------------------------------------------------------------------------

TEST_CASE("pbrt: area lights apply to the shapes of their attribute block", "[scene][pbrt][parser]") {
    Scene s = parse_world("AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [ 17 12 4 ] "
                          "\"float scale\" 2\nMaterial \"diffuse\" \"rgb reflectance\" [ 0 0 0 ]\n" +
                          std::string(kQuad) + "AttributeEnd\n" + kQuad);
    REQUIRE(s.triangle_count() == 4);
    const Material& l = s.materials[s.material_ids[0]];
    CHECK(l.emission == glm::vec3(34, 24, 8));  // rgb L is the rendered radiance, times scale
    CHECK(l.albedo == glm::vec3(0.0f));
    CHECK_FALSE(s.materials[s.material_ids[2]].emissive());
    // Spectral L: luminance 1 (pbrt-v4's normalisation), the illuminant's chromaticity
    auto radiance = [](const std::string& l) {
        Scene t = parse_world("AreaLightSource \"diffuse\" " + l + "\n" + kQuad);
        return glm::dvec3(only_material(t).emission);
    };
    auto luminance = [](glm::dvec3 c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
    check_vec(radiance("\"spectrum L\" \"stdillum-D65\""), {1, 1, 1}, 1e-6);
    const glm::dvec3 bb = radiance("\"blackbody L\" 6504");  // close to D65's chromaticity
    CHECK(luminance(bb) == Approx(1).epsilon(0.01));
    check_vec(bb, {1, 1, 1}, 0.06);
    const glm::dvec3 warm = radiance("\"blackbody L\" 2700");
    CHECK(luminance(warm) == Approx(1).epsilon(0.01));
    CHECK(warm.x > 1.2 * warm.z + 0.5);  // red > blue
    const glm::dvec3 a = radiance("\"spectrum L\" \"stdillum-A\"");
    CHECK(luminance(a) == Approx(1).epsilon(1e-3));
    CHECK(a.x > a.z);
    // A flat spectrum (equal energy, x = y = 1/3) is slightly pink in sRGB, luminance 1
    const glm::dvec3 e = radiance("\"spectrum L\" [ 300 2  900 2 ]");
    CHECK(luminance(e) == Approx(1).epsilon(0.01));
    CHECK(e.x > e.y);
    // Two-sided: emits from the front only, with a warning
    Scene t = parse_world("AreaLightSource \"diffuse\" \"bool twosided\" true\n" + std::string(kQuad));
    CHECK(has_warning(t, "two-sided area lights emit from the front only"));
}

TEST_CASE("pbrt: infinite lights: L is the background; a map is pbrt's equal-area square, "
          "resampled to wavepath's equirectangular map", "[scene][pbrt][parser][texture]") {
    Scene c = parse_world("LightSource \"infinite\" \"rgb L\" [ 0.5 0.25 1 ] \"float scale\" 2\n"
                          "LightSource \"infinite\" \"rgb L\" [ 1 1 1 ]\n" + std::string(kQuad));
    CHECK(c.background == glm::vec3(2.0f, 1.5f, 3.0f));
    CHECK_FALSE(c.environment.has_value());

    TempDir d;
    const int n = 32;
    // Each texel's colour is its direction (pbrt's EqualAreaSquareToSphere of its centre)
    write_exr(d.path / "sky.exr", n, n, [&](int x, int y) {
        const glm::dvec3 w = square_to_sphere((x + 0.5) / n, (y + 0.5) / n);
        return glm::vec3(0.5 * (w + 1.0));
    });
    d.write("s.pbrt", std::string(kHead) + "WorldBegin\nAttributeBegin\nRotate 90 0 1 0\n"
                                           "LightSource \"infinite\" \"string filename\" "
                                           "\"sky.exr\" \"float scale\" 3\nAttributeEnd\n" + kQuad);
    Scene s = load_pbrt(d.path / "s.pbrt");
    INFO(all_warnings(s));
    REQUIRE(s.environment.has_value());
    CHECK(s.environment->scale == 3.0f);
    const glm::mat3 r(glm::rotate(glm::mat4(1.0f), float(kPi / 2), glm::vec3(0, 1, 0)));
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) CHECK(s.environment->to_world[i][j] == Approx(r[i][j]).margin(1e-6));
    const Texture& t = s.textures.at(std::size_t(s.environment->image));
    REQUIRE(t.width == 2 * t.height);
    // Each equirectangular texel holds the colour of its own map-frame direction (the
    // mapping of kernels/shared/envmap.h), up to the bilinear interpolation's error
    double worst = 0.0, sum = 0.0;
    int count = 0;
    for (int j = 0; j < t.height; ++j)
        for (int i = 0; i < t.width; ++i) {
            const double th = kPi * j / (t.height - 1), ph = 2 * kPi * (i + 0.5) / t.width;
            const glm::dvec3 w(std::sin(ph) * std::sin(th), std::cos(th), -std::cos(ph) * std::sin(th));
            for (int ch = 0; ch < 3; ++ch) {
                const double err = std::abs(texel_at(t, i, j, ch) - 0.5 * (w[ch] + 1.0));
                worst = std::max(worst, err);
                sum += err;
                ++count;
            }
        }
    CHECK(worst < 0.08);
    CHECK(sum / count < 0.01);

    // A map that is not square is not pbrt-v4's: an error naming it
    write_exr(d.path / "latlong.exr", 8, 4, [](int, int) { return glm::vec3(1.0f); });
    d.write("ll.pbrt", std::string(kHead) + "WorldBegin\nLightSource \"infinite\" \"string "
                                            "filename\" \"latlong.exr\"\n" + kQuad);
    CHECK_THROWS_WITH(load_pbrt(d.path / "ll.pbrt"),
                      Contains("ll.pbrt:4:1: LightSource \"infinite\": '") &&
                          Contains("is 8 x 4; pbrt-v4's environment maps are square equal-area"));
    // A missing map: a warning and the magenta placeholder
    d.write("miss.pbrt", std::string(kHead) + "WorldBegin\nLightSource \"infinite\" \"string "
                                              "filename\" \"gone.pfm\"\n" + kQuad);
    Scene m = load_pbrt(d.path / "miss.pbrt");
    CHECK(has_warning(m, "texture not loaded"));
    CHECK(m.environment.has_value());
}

// --- Damaged input ----------------------------------------------------------------------------

TEST_CASE("pbrt: damaged input gives a scene or a wp::Error, never a crash", "[scene][pbrt][parser]") {
    const std::string base = R"(Integrator "path" "integer maxdepth" [ 4 ]
Transform [ 1 0 0 0 0 1 0 0 0 0 -1 0 0 -1 6.8 1 ]
Sampler "sobol" "integer pixelsamples" 8
Film "rgb" "integer xresolution" 32 "integer yresolution" 24
Camera "perspective" "float fov" [ 19.5 ]
WorldBegin
Texture "c" "spectrum" "checkerboard" "float uscale" 4 "rgb tex1" [ .8 .8 .8 ]
MakeNamedMaterial "w" "string type" [ "diffuse" ] "texture reflectance" "c"
MakeNamedMaterial "m" "string type" "conductor" "float roughness" .1 "spectrum eta" "metal-Au-eta"
NamedMaterial "w"
Shape "trianglemesh" "point2 uv" [ 0 0 1 0 1 1 0 1 ] "normal N" [ 0 1 0 0 1 0 0 1 0 0 1 0 ]
  "point3 P" [ -1 0 -1 -1 0 1 1 0 1 1 0 -1 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 17 12 4 ]
  NamedMaterial "m"
  Translate 0 1.5 0
  Shape "sphere" "float radius" 0.2
AttributeEnd
ObjectBegin "o" Shape "disk" ObjectEnd
ObjectInstance "o"
LightSource "infinite" "blackbody L" 5000
)";
    REQUIRE_NOTHROW(parse(base));
    SplitMix64 rng(14);
    int errors = 0, scenes = 0;
    for (int trial = 0; trial < 400; ++trial) {
        std::string t = base;
        const int edits = 1 + int(rng.next() % 4);
        for (int e = 0; e < edits && !t.empty(); ++e) {
            const std::size_t at = std::size_t(rng.next() % t.size());
            const char chars[] = "\"[]#\\ 0.-e\nabxAttributeEndShape";
            switch (rng.next() % 4) {
            case 0: t[at] = chars[rng.next() % (sizeof(chars) - 1)]; break;
            case 1: t.insert(at, 1, chars[rng.next() % (sizeof(chars) - 1)]); break;
            case 2: t.erase(at, 1 + rng.next() % 8); break;
            default: t.resize(at); break;
            }
        }
        try {
            Scene s = parse(t);
            ++scenes;
            CHECK(s.triangle_count() > 0);
        } catch (const Error&) {
            ++errors;
        }
    }
    CHECK(errors + scenes == 400);
    CHECK(errors > 20);
    CHECK(scenes > 20);
}

// --- The shared scenes ----------------------------------------------------------------------------

namespace {

}  // namespace

TEST_CASE("pbrt: every shared scene-v4.pbrt loads with the README's triangle count",
          "[scene][pbrt][parser][shared]") {
    const fs::path root = WP_SHARED_SCENES;
    if (!fs::exists(root)) {
        WARN("SKIP: " << root << " does not exist (the shared test scenes are not checked out)");
        return;
    }
    const auto counts = test::readme_counts(root / "README.md");
    const auto files = test::shared_scene_files(root, "scene-v4.pbrt");
    REQUIRE(files.size() == 6);  // every scene but the bunny has one
    for (const fs::path& f : files) {
        const std::string name = f.parent_path().filename().string();
        INFO(name);
        Scene s = load_scene_file(f);
        INFO(all_warnings(s));
        REQUIRE(counts.count(name));
        CHECK(long(s.triangle_count()) == counts.at(name));
        CHECK(s.render.spp.has_value());
        CHECK(s.render.depth.has_value());
    }
}

TEST_CASE("pbrt: the shared Cornell box's pbrt-v4 file gives the Mitsuba file's camera, "
          "geometry and materials; veach-mis reads as its SOURCE.md says",
          "[scene][pbrt][parser][shared]") {
    const fs::path root = WP_SHARED_SCENES;
    if (!fs::exists(root)) {
        WARN("SKIP: " << root << " does not exist (the shared test scenes are not checked out)");
        return;
    }
    Scene p = load_scene_file(root / "cornell-box" / "scene-v4.pbrt");
    Scene m = load_scene_file(root / "cornell-box" / "scene_v3.xml");
    INFO(all_warnings(p));
    // Camera
    check_vec(p.camera.position, m.camera.position);
    check_vec(glm::normalize(glm::dvec3(p.camera.target - p.camera.position)),
              glm::normalize(glm::dvec3(m.camera.target - m.camera.position)));
    check_vec(glm::normalize(glm::dvec3(p.camera.up)), glm::normalize(glm::dvec3(m.camera.up)));
    CHECK(p.camera.vfov_deg == Approx(m.camera.vfov_deg));
    CHECK(p.camera.width == m.camera.width);
    CHECK(p.camera.height == m.camera.height);
    CHECK_FALSE(has_warning(p, "mirrored"));
    // Settings: pbrt's maxdepth 65 bounces, Mitsuba's max_depth 65 segments (64 bounces)
    CHECK(p.render.spp == m.render.spp);
    CHECK(p.render.depth == 65);
    CHECK(m.render.depth == 64);
    // Geometry and materials: per distinct (albedo, emission) the same area, facing the
    // same way, in the same place
    auto groups = [](const Scene& s) {
        std::map<std::tuple<float, float, float, float, float, float>, Measure> g;
        for (std::size_t i = 0; i < s.materials.size(); ++i) {
            const Material& mat = s.materials[i];
            Measure x = measure(s, long(i));
            if (x.triangles == 0) continue;
            auto key = std::make_tuple(mat.albedo.x, mat.albedo.y, mat.albedo.z, mat.emission.x,
                                       mat.emission.y, mat.emission.z);
            Measure& acc = g[key];
            acc.area += x.area;
            acc.normal_sum += x.normal_sum;
            acc.triangles += x.triangles;
            acc.lo = glm::min(acc.lo, x.lo);
            acc.hi = glm::max(acc.hi, x.hi);
            CHECK(mat.kind == MaterialKind::Diffuse);
        }
        return g;
    };
    CHECK(p.triangle_count() == m.triangle_count());
    auto gp = groups(p), gm = groups(m);
    REQUIRE(gp.size() == gm.size());
    for (auto& [key, a] : gp) {
        REQUIRE(gm.count(key));
        const Measure& b = gm.at(key);
        CHECK(a.area == Approx(b.area).epsilon(1e-4));
        check_vec(a.normal_sum, b.normal_sum, 1e-4);
        check_vec(a.lo, b.lo, 1e-4);
        check_vec(a.hi, b.hi, 1e-4);
    }

    // veach-mis (pbrt-v4 file): four rough copper plates with pbrt's alphas, not remapped,
    // GGX; three sphere lights of equal power; depth 3 bounces; vertical fov 20.114292
    Scene v = load_scene_file(root / "veach-mis" / "scene-v4.pbrt");
    INFO(all_warnings(v));
    CHECK(v.render.depth == 3);
    CHECK(v.render.spp == 1);  // the mirror's edit (SOURCE.md)
    CHECK(v.camera.vfov_deg == Approx(20.114292));
    CHECK(v.camera.width == 1280);
    std::vector<float> alphas;
    for (const Material& mat : v.materials)
        if (mat.kind == MaterialKind::RoughConductor) {
            alphas.push_back(mat.alpha);
            check_vec(mat.eta, {0.200438, 0.924033, 1.102212}, 1e-6);
            check_vec(mat.k, {3.912949, 2.452848, 2.142188}, 1e-6);
        }
    std::sort(alphas.begin(), alphas.end());
    REQUIRE(alphas.size() == 4);
    CHECK(alphas[0] == Approx(0.01f));
    CHECK(alphas[3] == Approx(0.25f));
    std::vector<double> power;
    for (std::size_t i = 0; i < v.materials.size(); ++i) {
        if (!v.materials[i].emissive()) continue;
        Measure l = measure(v, long(i));
        CHECK(l.triangles == 5120);
        power.push_back(v.materials[i].emission.x * l.area);
    }
    REQUIRE(power.size() == 3);
    for (double pw : power) CHECK(pw == Approx(7.599088 * 4 * kPi).epsilon(1e-4));
}

TEST_CASE("pbrt: every shared scene-v4.pbrt renders without NaN or Inf",
          "[scene][pbrt][render][shared][slow]") {
    const fs::path root = WP_SHARED_SCENES;
    if (!fs::exists(root)) {
        WARN("SKIP: " << root << " does not exist (the shared test scenes are not checked out)");
        return;
    }
    for (const fs::path& f : test::shared_scene_files(root, "scene-v4.pbrt")) {
        INFO(f);
        Scene s = load_scene_file(f);
        const test::SmokeRender r = test::smoke_render(s, 2, std::min(*s.render.depth, 8));
        CHECK(r.nonfinite == 0);
        CHECK(r.counters == 0);
        CHECK(r.sum > 0.0);
    }
}

// The CLI on a pbrt file: a good one renders; a bad one exits 1 with FILE:LINE:COL, no image.
TEST_CASE("pbrt: wavepath render reads .pbrt files and refuses bad ones", "[scene][pbrt][cli]") {
    TempDir d;
    d.write("good.pbrt", std::string(kHead) + "WorldBegin\nAreaLightSource \"diffuse\"\n" + kQuad);
    auto ok = test::run_render(d.path, "good.pbrt --spp 1 --size 16x12 -o out.exr");
    INFO(ok.err);
    CHECK(ok.status == 0);
    CHECK(fs::exists(d.path / "out.exr"));
    d.write("bad.pbrt", std::string(kHead) + "WorldBegin\n  Shape \"plymesh\" \"string filename\" "
                                             "\"nowhere.ply\"\n");
    auto bad = test::run_render(d.path, "bad.pbrt --spp 1 -o bad.exr");
    INFO(bad.err);
    CHECK(bad.status == 1);
    CHECK_THAT(bad.err, Contains("bad.pbrt:4:3:") && Contains("nowhere.ply' not found"));
    CHECK_FALSE(fs::exists(d.path / "bad.exr"));
}
