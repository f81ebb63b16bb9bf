// test_render_cli.cpp — `wavepath render` as a user runs it: bad input fails cleanly.
//
// Each case runs the real binary (WP_CLI_PATH) in a fresh temporary folder, and checks the
// exit status, the message on stderr and that no image (render.exr / render.png / the -o
// file) is left behind.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "temp_dir.h"

using namespace std::string_literals;
namespace fs = std::filesystem;

namespace {

using wp::test::TempDir;
using Run = wp::test::CliRun;

Run run_cli(const TempDir& dir, const std::string& args) { return wp::test::run_render(dir.path, args); }

}  // namespace

TEST_CASE("render CLI: a missing scene file fails with a clear message", "[render][cli]") {
    TempDir d;
    Run r = run_cli(d, "no-such-scene.obj");
    INFO(r.err);
    CHECK(r.status != 0);
    CHECK(r.err.find("no-such-scene.obj") != std::string::npos);
    CHECK(r.err.find("not found") != std::string::npos);
    CHECK(d.empty_of_images());
}

TEST_CASE("render CLI: an OBJ with a bad face index fails and writes nothing", "[render][cli]") {
    TempDir d;
    std::ofstream(d.path / "bad.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
    Run r = run_cli(d, "bad.obj --spp 1");
    INFO(r.err);
    CHECK(r.status != 0);
    CHECK(r.err.find("bad.obj") != std::string::npos);
    CHECK(r.err.find("out of range") != std::string::npos);
    CHECK(d.empty_of_images());
}

TEST_CASE("render CLI: an unwritable output path fails before rendering", "[render][cli]") {
    TempDir d;
    Run r = run_cli(d, "-o /nonexistent-dir/x.png --size 16x12 --spp 1");
    INFO(r.err);
    CHECK(r.status != 0);
    CHECK(r.err.find("/nonexistent-dir") != std::string::npos);
    CHECK(r.err.find("does not exist") != std::string::npos);
    CHECK(d.empty_of_images());
    CHECK_FALSE(fs::exists("/nonexistent-dir/x.png"));
    Run e = run_cli(d, "-o out.tiff --size 16x12 --spp 1");
    CHECK(e.status != 0);
    CHECK(e.err.find("extension") != std::string::npos);
    CHECK(d.empty_of_images());
}

TEST_CASE("render CLI: invalid options are rejected with a message", "[render][cli]") {
    TempDir d;
    // Beyond util/limits.h: spp 2^24 + 1, depth 2^20 + 1, a side of 16385.
    for (const char* args : {"--spp 0", "--depth -1", "--size 0x10", "--size 64by48", "--time -2",
                             "--debug-nan shader", "--debug-nan-period 0", "--spp 16777217",
                             "--depth 1048577", "--size 16385x1", "--shadow-rays queue"}) {
        Run r = run_cli(d, args);
        INFO(args << ": " << r.err);
        CHECK(r.status != 0);
        CHECK(r.err.size() > 10);
        CHECK(d.empty_of_images());
    }
}

TEST_CASE("render CLI: a small render writes only the -o file and the profile", "[render][cli]") {
    TempDir d;
    Run r = run_cli(d, "--size 32x24 --spp 2 --depth 2 -q -o out.exr --profile prof.json");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(fs::exists(d.path / "out.exr"));
    CHECK_FALSE(fs::exists(d.path / "render.exr"));
    CHECK_FALSE(fs::exists(d.path / "render.png"));
    REQUIRE(fs::exists(d.path / "prof.json"));
    REQUIRE(fs::exists(d.path / "prof.trace.json"));
    auto j = nlohmann::json::parse(std::ifstream(d.path / "prof.json"));
    CHECK(j["spp"] == 2);
    // The loop takes 1, 1, 2, 4, ... passes per step: two waves of one pass each.
    CHECK(j["waves"] == 2);
    CHECK(j["wave_ms"].size() == 2);
    // The pool: 16 passes of the 32x24 image (smaller than the 2^20 default), 160 bytes a
    // path (NEE, its shadow rays traced in shade: no shadow queue); the film 32 bytes a pixel.
    CHECK(j["settings"]["shadow_rays"] == "shade");
    CHECK(j["settings"]["pool_paths"] == 16 * 32 * 24);
    CHECK(j["settings"]["pool_bytes"] == 16 * 32 * 24 * 160);
    CHECK(j["settings"]["film_bytes"] == 32 * 24 * 32);
    CHECK(j["scene"]["triangles"].get<int>() > 1000);
    CHECK(j.contains("device"));
    bool has_intersect = false;
    for (auto& s : j["stages"]) has_intersect |= s["name"] == "intersect.closest";
    CHECK(has_intersect);
    auto t = nlohmann::json::parse(std::ifstream(d.path / "prof.trace.json"));
    // 2 waves x (generate + 2 x (intersect, reset, shade) + the last bounce's (reset,
    // shade_final) + accumulate) complete events: paths of the open box survive to depth 2,
    // shade traces the shadow rays of the default --sampling mis itself (no shadow stage;
    // test_shadow.cpp runs it) and the last bounce's rays too (--final-rays emitters).
    int complete = 0;
    for (auto& e : t["traceEvents"]) complete += e["ph"] == "X" && e["tid"] == 1;
    CHECK(complete == 2 * (1 + 2 * 3 + 2 + 1));
    // Issue 12, item 7: host work on its own track (tid 2 "host"), on the device's clock, in
    // the order it ran.
    std::vector<std::string> host;
    std::vector<std::string> tracks;
    for (auto& e : t["traceEvents"]) {
        if (e["ph"] == "M" && e["name"] == "thread_name") tracks.push_back(e["args"]["name"]);
        if (e["ph"] != "X") continue;
        CHECK(e["ts"].get<double>() >= 0.0);
        CHECK(e["dur"].get<double>() >= 0.0);
        if (e["tid"] == 2) {
            CHECK(e["cat"] == "host");
            host.push_back(e["name"]);
        }
    }
    CHECK(tracks == std::vector<std::string>{"device queue", "host"});
    CHECK(host == std::vector<std::string>{"load", "device", "bvh", "upload", "programs", "resolve", "write"});
    bool has_shadow = false;
    for (auto& s : j["stages"]) has_shadow |= s["name"] == "shadow";
    CHECK_FALSE(has_shadow);
    CHECK(j["rays_shadow"].get<std::uint64_t>() > 0);
}

// Issue 5, case 8 through the CLI: --debug-nan injects NaN into every 7th pixel of the three
// stages; the run succeeds, writes a finite image and reports each stage's count: 2 frames x
// ceil(320 / 7) = 2 x 46 = 92 per stage, 276 in all.
TEST_CASE("render CLI: --debug-nan reports the count caught by each stage", "[render][cli]") {
    TempDir d;
    Run r = run_cli(d, "--size 20x16 --spp 2 --debug-nan generate,shade,accumulate "
                       "--debug-nan-period 7 -q -o out.exr --profile prof.json");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.find("276 NaN/Inf values caught and dropped (generate 92, shade 92, accumulate 92)") !=
          std::string::npos);
    auto j = nlohmann::json::parse(std::ifstream(d.path / "prof.json"));
    CHECK(j["nonfinite"]["generate"] == 92);
    CHECK(j["nonfinite"]["shade"] == 92);
    CHECK(j["nonfinite"]["accumulate"] == 92);
}

// Issue 7: loading reports what it found. A hand-written OBJ: 2 quads (4 triangles), one
// diffuse and one emissive material, known bounds.
TEST_CASE("render CLI: loading a scene file reports triangles, materials, emitters, bounds, time",
          "[render][cli][scene]") {
    TempDir d;
    d.write("two.mtl", "newmtl white\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0 0 0\nKe 4 4 4\n");
    d.write("two.obj",
            "mtllib two.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
            "v -0.5 2 -0.5\nv 0.5 2 -0.5\nv 0.5 2 0.5\nv -0.5 2 0.5\n"
            "usemtl white\nf 1 4 3 2\nusemtl lamp\nf 5 6 7 8\n");
    Run r = run_cli(d, "two.obj --size 8x6 --spp 1 -o out.png");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.find("two.obj: 4 triangles, materials 2 diffuse, 1 emissive material (2 triangles), "
                     "background (0, 0, 0), bounds (-1, 0, -1) to (1, 2, 1), loaded in ") != std::string::npos);
    CHECK(r.err.find(" ms\n") != std::string::npos);
}
