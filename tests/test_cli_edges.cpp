// test_cli_edges.cpp — the edges of the command line a new user meets first (issue 12):
// every limit enforced alike with exit 2 and the allowed range, usage errors exit 2 and
// runtime failures 1, outputs checked before any work, and no silent black images.
//
// Each case runs the real binary (WP_CLI_PATH) in a fresh temporary folder, like
// test_render_cli.cpp.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "temp_dir.h"

namespace fs = std::filesystem;

namespace {

using wp::test::TempDir;
using Run = wp::test::CliRun;

Run run_cli(const TempDir& dir, const std::string& args) { return wp::test::run_render(dir.path, args); }

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::size_t count(const std::string& s, const std::string& part) {
    std::size_t n = 0;
    for (std::size_t at = s.find(part); at != std::string::npos; at = s.find(part, at + 1)) ++n;
    return n;
}

// `wavepath ARGS` (no subcommand added), stdout and stderr kept apart.
struct FullRun {
    int status = -1;
    std::string out, err;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

FullRun run_wavepath(const TempDir& dir, const std::string& args) {
    const fs::path out = dir.path / "stdout.txt", err = dir.path / "stderr.txt";
    std::string cmd = "cd '" + dir.path.string() + "' && '" WP_CLI_PATH "' " + args + " > '" +
                      out.string() + "' 2> '" + err.string() + "'";
    int rc = std::system(cmd.c_str());
    FullRun r;
    r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    fs::remove(out);
    fs::remove(err);
    return r;
}

// A small render of `scene` that must succeed; returns its stderr.
std::string render_ok(const TempDir& d, const std::string& scene) {
    Run r = run_cli(d, scene + " --spp 1 --size 8x6 -o out.exr");
    INFO(scene << ": " << r.err);
    CHECK(r.status == 0);
    return r.err;
}

}  // namespace

// --- 1. Every limit enforced alike -------------------------------------------------------

TEST_CASE("cli edges: every option out of range exits 2 with the allowed range", "[cli][render]") {
    TempDir d;
    struct Case {
        const char* args;
        const char* range;  // the allowed range, as the message gives it
    };
    for (const Case& c : {Case{"--spp 0", "1..16777216"}, Case{"--spp 16777217", "1..16777216"},
                          Case{"--depth -1", "0..1048576"}, Case{"--depth 1048577", "0..1048576"},
                          Case{"--size 0x10", "1..16384"}, Case{"--size 16385x1", "1..16384"},
                          Case{"--time -2", ">= 0"}, Case{"--time inf", ">= 0"},
                          Case{"--seed -1", "0..4294967295"},
                          Case{"--seed 4294967296", "0..4294967295"},
                          Case{"--pool 1099511627776", "0..1073741824"},
                          Case{"--pool -1", "0..1073741824"},
                          Case{"--rr-depth -2", "0..1048576"},
                          Case{"--rr-depth 1048577", "0..1048576"},
                          Case{"--debug-nan-period 0", "1..2147483647"},
                          Case{"--smooth -1", "0..180"}, Case{"--smooth 181", "0..180"},
                          Case{"--smooth nan", "0..180"},
                          Case{"--env-scale -1", "0..1000000"},
                          Case{"--env-scale 1e7", "0..1000000"},
                          Case{"--env-rotate 361", "-360..360"},
                          Case{"--env-rotate -400", "-360..360"},
                          Case{"--light-pairs maybe", "expected on or off"},
                          Case{"--final-rays maybe", "expected emitters or closest"}}) {
        Run r = run_cli(d, c.args);
        INFO(c.args << ": " << r.err);
        CHECK(r.status == 2);
        CHECK(has(r.err, "wavepath: error: "));
        CHECK(has(r.err, c.range));
        CHECK(d.empty_of_images());
    }
}

TEST_CASE("cli edges: CLI11's parse errors are usage errors with wavepath's prefix", "[cli][render]") {
    TempDir d;
    for (const char* args : {"--spp 1.5", "--no-such-option", "--depth three", "--spp"}) {
        Run r = run_cli(d, args);
        INFO(args << ": " << r.err);
        CHECK(r.status == 2);
        CHECK(r.err.rfind("wavepath: error: ", 0) == 0);
        CHECK(d.empty_of_images());
    }
    FullRun u = run_wavepath(d, "no-such-subcommand");
    CHECK(u.status == 2);
    CHECK(has(u.err, "wavepath: error: "));
}

TEST_CASE("cli edges: --help and --version still exit 0 with their text", "[cli]") {
    TempDir d;
    FullRun h = run_wavepath(d, "render --help");
    CHECK(h.status == 0);
    CHECK(has(h.out, "--spp"));
    for (const char* o : {"--env FILE", "--env-scale S", "--env-rotate DEG", "--smooth DEG"})
        CHECK(has(h.out, o));
    CHECK_FALSE(has(h.err, "error"));
    FullRun v = run_wavepath(d, "--version");
    CHECK(v.status == 0);
    CHECK(has(v.out, "wavepath "));
}

TEST_CASE("cli edges: a scene file's value out of range stays a file error (exit 1)",
          "[cli][scene]") {
    TempDir d;
    d.write("bad.json", "{\n  \"render\": {\"spp\": 0},\n"
                        "  \"materials\": {\"m\": {\"type\": \"diffuse\"}},\n"
                        "  \"shapes\": [{\"type\": \"quad\", \"size\": 1, \"material\": \"m\"}]}\n");
    Run r = run_cli(d, "bad.json");
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(has(r.err, "bad.json:2:"));
    CHECK(d.empty_of_images());
}

// --- 2. Outputs checked before the work ---------------------------------------------------

TEST_CASE("cli edges: -o /proc/out.png fails before loading or rendering", "[cli][render]") {
    TempDir d;
    // The scene does not exist: an output check after loading would name the scene instead.
    Run r = run_cli(d, "no-such-scene.obj -o /proc/out.png --spp 1");
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(has(r.err, "wavepath: error: "));
    CHECK(has(r.err, "/proc/out.png"));
    CHECK_FALSE(has(r.err, "no-such-scene"));
    CHECK_FALSE(has(r.err, "spp"));  // no progress line, no summary
    CHECK_FALSE(fs::exists("/proc/out.png"));
    // Also for a scene that renders, and for the profile
    Run p = run_cli(d, "--size 8x6 --spp 1 -o out.exr --profile /proc/prof.json");
    INFO(p.err);
    CHECK(p.status == 1);
    CHECK(has(p.err, "/proc/prof.json"));
    CHECK(d.empty_of_images());
}

// The image codec (OpenImageIO) is a module the binary loads on first use (image/codec.h):
// the binary itself does not link OpenImageIO, a command that writes no image never loads it,
// and a render whose module is missing fails before rendering, naming it.
TEST_CASE("cli edges: the image module is loaded on first use, and its absence is named before rendering",
          "[cli][render]") {
    // The binary's own libraries: no OpenImageIO among them.
    std::string libs;
    if (FILE* p = ::popen("ldd '" WP_CLI_PATH "' 2>/dev/null", "r")) {
        char buf[512];
        while (std::fgets(buf, sizeof buf, p)) libs += buf;
        ::pclose(p);
    }
    if (libs.empty()) {
        WARN("ldd gave nothing: the link check is skipped");
    } else {
        INFO(libs);
        CHECK(has(libs, "libOpenCL"));  // ldd did list the binary's libraries
        CHECK_FALSE(has(libs, "OpenImageIO"));
    }
    TempDir d;
    const std::string missing = (d.path / "no-such-dir" / "libwavepath_oiio.so").string();
    ::setenv("WP_IMAGE_MODULE", missing.c_str(), 1);
    FullRun v = run_wavepath(d, "--version");
    FullRun r = run_wavepath(d, "render --size 8x6 --spp 1 -o out.exr");
    ::unsetenv("WP_IMAGE_MODULE");
    CHECK(v.status == 0);  // never loads it
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(has(r.err, "wavepath: error: cannot load the image module libwavepath_oiio.so"));
    CHECK(has(r.err, missing + ": no such file"));
    CHECK_FALSE(has(r.err, "spp"));  // before rendering: no progress line, no summary
    CHECK(count(r.err, "wavepath: error:") == 1);
    CHECK(d.empty_of_images());
    // With the module found, the same render writes its image.
    Run ok = run_cli(d, "--size 8x6 --spp 1 -o out.exr");
    CHECK(ok.status == 0);
    CHECK(fs::exists(d.path / "out.exr"));
}

TEST_CASE("cli edges: a read-only folder fails before rendering, and leaves no probe",
          "[cli][render]") {
    if (::geteuid() == 0) {
        WARN("running as root, which ignores permissions: read-only folder case skipped");
        return;
    }
    TempDir d;
    fs::create_directories(d.path / "ro");
    REQUIRE(::chmod((d.path / "ro").c_str(), 0555) == 0);
    Run r = run_cli(d, "no-such-scene.obj -o ro/out.png --spp 1");
    ::chmod((d.path / "ro").c_str(), 0755);
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(has(r.err, "ro/out.png"));
    CHECK_FALSE(has(r.err, "no-such-scene"));
    CHECK(fs::is_empty(d.path / "ro"));
}

TEST_CASE("cli edges: a successful render leaves no probe file behind", "[cli][render]") {
    TempDir d;
    render_ok(d, "");
    for (const auto& name : d.entries()) CHECK(name.find("wavepath-probe") == std::string::npos);
}

// --- 4. No silent black images ------------------------------------------------------------

TEST_CASE("cli edges: a scene without light warns once, whatever its format", "[cli][scene]") {
    TempDir d;
    d.write("bunny.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    d.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");  // all degenerate
    d.write("dark.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                        "property float y\nproperty float z\nelement face 1\n"
                        "property list uchar int vertex_indices\nend_header\n"
                        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    d.write("dark.xml", R"(<scene version="3.0.0">
  <bsdf type="diffuse" id="grey"/>
  <shape type="rectangle"><ref id="grey"/></shape>
</scene>
)");
    d.write("dark.json", R"({"materials": {"m": {"type": "diffuse"}},
  "shapes": [{"type": "quad", "size": 1, "material": "m"}]})");
    // glTF: one triangle, no emissive material (positions in a data URI)
    d.write("dark.gltf", R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0}], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "buffers": [{"byteLength": 36, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})");
    for (const char* scene : {"bunny.obj", "flat.obj", "dark.ply", "dark.xml", "dark.json",
                              "dark.gltf"}) {
        std::string err = render_ok(d, scene);
        INFO(scene << ": " << err);
        CHECK(count(err, "no light") == 1);
        CHECK(has(err, std::string(scene) + ": no light"));
        fs::remove(d.path / "out.exr");
    }
    // A lit scene does not warn
    std::string lit = render_ok(d, "builtin:cornell-box");
    CHECK_FALSE(has(lit, "no light"));
}

TEST_CASE("cli edges: bounds of +-1e38 name the automatic camera's overflow", "[cli][scene]") {
    TempDir d;
    d.write("huge.obj", "v -1e38 -1e38 -1e38\nv 1e38 -1e38 1e38\nv 0 1e38 0\nf 1 2 3\n");
    Run r = run_cli(d, "huge.obj --spp 1 --size 8x6 -o out.exr");
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(has(r.err, "huge.obj"));
    CHECK(has(r.err, "too large to frame"));
    CHECK_FALSE(has(r.err, "not finite"));
    CHECK(d.empty_of_images());
}

TEST_CASE("cli edges: glTF '{}' is named as not a glTF file, in wavepath's words",
          "[cli][scene]") {
    TempDir d;
    d.write("empty.gltf", "{}");
    Run r = run_cli(d, "empty.gltf --spp 1 -o out.exr");
    INFO(r.err);
    CHECK(r.status == 1);
    CHECK(has(r.err, "wavepath: error: empty.gltf: not a glTF 2.0 file: "));
    CHECK(d.empty_of_images());
}

// --- Appearance options (issue 13) -----------------------------------------------------------

TEST_CASE("cli edges: --env needs an existing file; --env-scale/--env-rotate need a map",
          "[cli][render]") {
    TempDir d;
    Run missing = run_cli(d, "--env nowhere.exr --spp 1 --size 8x6 -o out.exr");
    INFO(missing.err);
    CHECK(missing.status == 1);
    CHECK(has(missing.err, "wavepath: error: --env 'nowhere.exr': file not found"));
    CHECK(d.empty_of_images());
    // A file that is there but does not decode: an error too (no placeholder sky)
    d.write("bad.hdr", "not an image");
    Run garbage = run_cli(d, "--env bad.hdr --spp 1 --size 8x6 -o out.exr");
    INFO(garbage.err);
    CHECK(garbage.status == 1);
    CHECK(has(garbage.err, "wavepath: error:"));
    CHECK(has(garbage.err, "bad.hdr"));
    CHECK(!has(garbage.err, "placeholder"));
    CHECK(d.empty_of_images());
    // The built-in box has no environment map to scale or turn: a usage error
    Run scale = run_cli(d, "--env-scale 2 --spp 1 --size 8x6 -o out.exr");
    INFO(scale.err);
    CHECK(scale.status == 2);
    CHECK(has(scale.err, "--env-scale: the scene has no environment map; give one with --env FILE"));
    CHECK(d.empty_of_images());
}

TEST_CASE("cli edges: --env lights a scene without other light; --smooth applies to any scene",
          "[cli][render]") {
    TempDir d;
    d.write("dark.json", R"({"materials": {"m": {"type": "diffuse"}},
  "shapes": [{"type": "quad", "size": 1, "material": "m"}]})");
    // A 4 x 2 equirectangular map (a PPM: OpenImageIO reads it, and it needs no writer here)
    std::string ppm = "P3\n4 2\n255\n";
    for (int i = 0; i < 8; ++i) ppm += "200 200 255\n";
    d.write("sky.ppm", ppm);
    std::string err = render_ok(d, "dark.json --env sky.ppm --env-scale 2 --env-rotate 90 --smooth 30");
    CHECK_FALSE(has(err, "no light"));  // the environment lights it
    std::string dark = render_ok(d, "dark.json --smooth 180");
    CHECK(has(dark, "no light"));
}
