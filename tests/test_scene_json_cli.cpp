// test_scene_json_cli.cpp — `wavepath render SCENE.json` as a user runs it: every kind of bad
// scene file fails with one message (file, place, problem), a non-zero exit status and no
// image; the file's render settings apply unless --spp/--depth/--seed beat them; the shipped
// scene renders from the repository root.
//
// Each case runs the real binary (WP_CLI_PATH) in a fresh temporary folder.
#include <catch2/catch.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include "temp_dir.h"
#include "util/limits.h"

namespace fs = std::filesystem;

namespace {

using wp::test::TempDir;
using Run = wp::test::CliRun;

// `wavepath render ARGS` run in `cwd`; stderr captured.
Run run_cli(const fs::path& cwd, const fs::path& /*err_file*/, const std::string& args) {
    return wp::test::run_render(cwd, args);
}

Run run_cli(const TempDir& d, const std::string& args) {
    return run_cli(d.path, d.path / "stderr.txt", args);
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// A tiny lit scene (an emitting quad seen head-on) with the given extra top-level keys.
std::string tiny(const std::string& extra = "") {
    return R"({"camera": {"position": [0, 0, 2], "look_at": [0, 0, 0], "width": 8, "height": 6},
  "materials": {"lamp": {"type": "diffuse", "emission": 1}},
  "shapes": [{"type": "quad", "size": 1, "material": "lamp"}])" +
           extra + "}\n";
}

}  // namespace

TEST_CASE("json CLI: every bad scene file fails with file, place and problem, and no image",
          "[scene][json][cli]") {
    struct Case {
        const char* what;
        std::string text;                // "" : the file is not written at all
        std::vector<std::string> parts;  // all in stderr
    };
    const std::vector<Case> cases = {
        {"missing file", "", {"bad.json", "not found"}},
        {"malformed JSON", "{\n  \"camera\": {\n    \"fov\": 40,,\n  }\n}\n",
         {"bad.json:3:15:", "malformed JSON"}},
        {"unknown key",
         "{\n  \"materials\": {\n    \"white\": {\"type\": \"diffuse\", \"materail\": 1}\n  },\n"
         "  \"shapes\": []\n}\n",
         {"bad.json:3:34:", "/materials/white/materail", "unknown key 'materail'"}},
        {"unknown key with a hint",
         R"({"materials": {"w": {"type": "diffuse"}}, "shapes": [{"type": "quad", "size": 1, "materail": "w"}]})",
         {"bad.json:1:", "/shapes/0/materail", "did you mean 'material'?"}},
        {"wrong type", tiny(R"(, "render": {"spp": "many"})"),
         {"bad.json:3:82:", "/render/spp", "expected an integer"}},
        {"negative fov",
         R"({"camera": {"fov": -30}, "shapes": [{"type": "quad", "size": 1, "material": "m"}],
             "materials": {"m": {"type": "diffuse"}}})",
         {"bad.json:1:20:", "/camera/fov", "out of range", "(0, 180)"}},
        {"zero-size film",
         R"({"camera": {"width": 640, "height": 0}, "shapes": [{"type": "quad", "size": 1, "material": "m"}],
             "materials": {"m": {"type": "diffuse"}}})",
         {"bad.json:1:", "/camera/height", "out of range"}},
        {"mesh that does not exist",
         R"({"materials": {"m": {"type": "diffuse"}}, "shapes": [{"type": "mesh", "file": "gone.obj", "material": "m"}]})",
         {"bad.json:1:", "/shapes/0/file", "gone.obj", "not found"}},
        {"material that does not exist",
         R"({"materials": {"m": {"type": "diffuse"}}, "shapes": [{"type": "quad", "size": 1, "material": "n"}]})",
         {"bad.json:1:", "/shapes/0/material", "no material named 'n'"}},
        {"NaN coordinate", "{\"shapes\": [{\"type\": \"sphere\", \"center\": [0, NaN, 0]}]}",
         {"bad.json:1:", "malformed JSON", "NaN or Infinity"}},
        {"infinite coordinate", "{\"shapes\": [{\"type\": \"sphere\", \"center\": [0, 1e400, 0]}]}",
         {"bad.json:1:46:", "number overflow", "finite"}},
        {"coordinate beyond float",
         R"({"materials": {"m": {"type": "diffuse"}},
             "shapes": [{"type": "sphere", "center": [0, 1e300, 0], "material": "m"}]})",
         {"bad.json:2:58:", "/shapes/0/center/1", "32-bit float"}},
        {"no triangles", R"({"materials": {"m": {"type": "diffuse"}}, "shapes": []})",
         {"bad.json:1:", "/shapes", "no triangles"}},
        {"environment file of the wrong type", tiny(R"(, "environment": {"file": 3})"),
         {"bad.json:3:88:", "/environment/file", "expected a string, got the number 3"}},
        {"smooth out of range",
         R"({"materials": {"m": {"type": "diffuse"}}, "shapes": [{"type": "mesh", "file": "a.obj", "smooth": -5}]})",
         {"bad.json:1:", "/shapes/0/smooth", "expected a number in [0, 180] degrees"}},
    };
    for (const Case& c : cases) {
        TempDir d;
        if (!c.text.empty()) d.write("bad.json", c.text);
        Run r = run_cli(d, "bad.json --spp 1");
        INFO(c.what << ": " << r.err);
        CHECK(r.status != 0);
        for (const auto& part : c.parts) CHECK(has(r.err, part));
        CHECK(has(r.err, "error"));
        CHECK(d.empty_of_images());
    }
}

TEST_CASE("json CLI: a NaN vertex in a referenced OBJ names both files", "[scene][json][cli]") {
    TempDir d;
    d.write("nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n");
    d.write("bad.json",
            R"({"materials": {"m": {"type": "diffuse", "emission": 1}},
  "shapes": [{"type": "mesh", "file": "nan.obj", "material": "m"}]})");
    Run r = run_cli(d, "bad.json --spp 1 -o out.png");
    INFO(r.err);
    CHECK(r.status != 0);
    CHECK(has(r.err, "bad.json:2:"));
    CHECK(has(r.err, "/shapes/0/file"));
    CHECK(has(r.err, "nan.obj:2"));
    CHECK(has(r.err, "non-finite"));
    CHECK(d.empty_of_images());
}

TEST_CASE("json CLI: no light and a black background warns and still renders",
          "[scene][json][cli]") {
    TempDir d;
    d.write("dark.json",
            R"({"camera": {"position": [0, 0, 2], "look_at": [0, 0, 0], "width": 8, "height": 6},
  "materials": {"m": {"type": "diffuse"}},
  "shapes": [{"type": "quad", "size": 1, "material": "m"}]})");
    Run r = run_cli(d, "dark.json --spp 1 -o out.exr");  // not -q: that hides warnings
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(has(r.err, "warning"));
    CHECK(has(r.err, "dark.json: no light"));
    CHECK(fs::exists(d.path / "out.exr"));
}

TEST_CASE("json CLI: the file's spp, depth and seed apply; the command line beats them",
          "[scene][json][cli]") {
    TempDir d;
    d.write("s.json", tiny(R"(, "render": {"spp": 3, "depth": 2, "seed": 9})"));
    auto settings = [&](const std::string& args) {
        Run r = run_cli(d, "s.json -q -o out.exr --profile p.json " + args);
        INFO(r.err);
        REQUIRE(r.status == 0);
        auto j = nlohmann::json::parse(std::ifstream(d.path / "p.json"));
        return j["settings"];
    };
    auto file = settings("");
    CHECK(file["spp"] == 3);
    CHECK(file["depth"] == 2);
    CHECK(file["seed"] == 9);
    CHECK(file["width"] == 8);
    CHECK(file["height"] == 6);
    auto cli = settings("--spp 2 --depth 1 --seed 4 --size 10x4");
    CHECK(cli["spp"] == 2);
    CHECK(cli["depth"] == 1);
    CHECK(cli["seed"] == 4);
    CHECK(cli["width"] == 10);
    CHECK(cli["height"] == 4);
}

TEST_CASE("json CLI: a scene file without a depth gets kDefaultSceneDepth, a built-in scene 3",
          "[scene][json][cli]") {
    TempDir d;
    d.write("s.json", tiny());
    // A one-triangle OBJ with an emitting material: a mesh file, no depth of its own.
    d.write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl lamp\nf 1 2 3\n");
    d.write("m.mtl", "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1 1 1\n");
    auto depth = [&](const std::string& args) {
        Run r = run_cli(d, args + " --size 8x6 --spp 1 -q -o out.exr --profile p.json");
        INFO(r.err);
        REQUIRE(r.status == 0);
        return nlohmann::json::parse(std::ifstream(d.path / "p.json"))["settings"]["depth"];
    };
    CHECK(depth("s.json") == wp::limits::kDefaultSceneDepth);
    CHECK(depth("m.obj") == wp::limits::kDefaultSceneDepth);
    CHECK(depth("builtin:cornell-box") == wp::limits::kDefaultDepth);
    CHECK(depth("s.json --depth 2") == 2);
    static_assert(wp::limits::kDefaultDepth == 3, "the benchmarks' workload stays depth 3");
}

TEST_CASE("json CLI: wavepath render scenes/cornell-box.json from the repository root",
          "[scene][json][cli]") {
    TempDir d;
    const fs::path out = d.path / "box.png";
    Run r = run_cli(WP_SOURCE_DIR, d.path / "stderr.txt",
                    "scenes/cornell-box.json --size 16x12 --spp 1 -q -o '" + out.string() + "'");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(fs::exists(out));
    CHECK_FALSE(has(r.err, "warning"));
}

TEST_CASE("json CLI: a missing texture or environment file warns, names it and renders",
          "[scene][json][cli]") {
    TempDir d;
    d.write("tex.json",
            R"({"camera": {"position": [0, 0, 2], "look_at": [0, 0, 0], "width": 8, "height": 6},
  "environment": {"file": "sky-gone.exr"},
  "materials": {"m": {"type": "diffuse", "albedo_texture": "wood-gone.png", "emission": 1}},
  "shapes": [{"type": "quad", "size": 1, "material": "m"}]})");
    Run r = run_cli(d, "tex.json --spp 1 -o out.exr");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(has(r.err, "warning"));
    CHECK(has(r.err, "wood-gone.png"));
    CHECK(has(r.err, "sky-gone.exr"));
    CHECK(fs::exists(d.path / "out.exr"));
}
