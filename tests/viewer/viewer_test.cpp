// viewer_test.cpp — the ctest tests of `wavepath view` (CMakeLists.txt, docs/viewer.md).
//
//   viewer_test screenshot WAVEPATH XVFB_RUN DIR
//     Renders the built-in Cornell box with `render` (PNG and EXR) and shows the same scene,
//     size, seed and spp with `view --frames N --screenshot` under Xvfb (Mesa's software
//     OpenGL); the screenshot is read back from the real window's framebuffer. Checks:
//       1. clamp, exposure 0, sRGB: the window's pixels equal render's PNG, code for code;
//       2. reinhard, exposure +1: each code is within 1 of round(255 srgb(y)) with
//          y = 2x / (1 + 2x) computed here in double from render's EXR (the sRGB formula is
//          written out here again, not taken from the program);
//       3. --views --view denoised: equal to `render --denoise`'s PNG.
//     XVFB_RUN "" (viewer component not built) or "-" (no xvfb-run): skipped, exit 77.
//   viewer_test no-display WAVEPATH XVFB_RUN DIR
//     `view` with $DISPLAY and $WAYLAND_DISPLAY unset exits 1, its message suggests
//     `render`, and it writes nothing.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

namespace fs = std::filesystem;

namespace {

int failures = 0;

void check(bool ok, const std::string& what) {
    std::printf("%s: %s\n", ok ? "ok" : "FAIL", what.c_str());
    if (!ok) ++failures;
}

int run(const std::string& cmd) {
    std::printf("$ %s\n", cmd.c_str());
    std::fflush(stdout);
    int st = std::system(cmd.c_str());
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

struct Pixels {
    int w = 0, h = 0;
    std::vector<unsigned char> rgb;  // codes or
    std::vector<float> lin;          // linear floats
};

Pixels read(const fs::path& p, bool codes) {
    Pixels px;
    auto in = OIIO::ImageInput::open(p.string());
    if (!in) {
        std::printf("cannot read %s\n", p.string().c_str());
        return px;
    }
    const auto& spec = in->spec();
    px.w = spec.width;
    px.h = spec.height;
    const std::size_t n = std::size_t(px.w) * px.h * 3;
    if (codes) {
        px.rgb.resize(n);
        in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.rgb.data());
    } else {
        px.lin.resize(n);
        in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.lin.data());
    }
    return px;
}

double srgb(double x) {  // IEC 61966-2-1
    x = std::fmin(std::fmax(x, 0.0), 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

int screenshot(const std::string& wavepath, const std::string& xvfb, const fs::path& dir) {
    if (xvfb.empty()) {
        std::printf("SKIP: wavepath was built without the viewer component (GLFW 3 + OpenGL: "
                    "Debian libglfw3-dev libgl-dev; scripts/setup.sh)\n");
        return 77;
    }
    if (xvfb == "-") {
        std::printf("SKIP: xvfb-run not found (Debian package xvfb; scripts/setup.sh)\n");
        return 77;
    }
    fs::remove_all(dir / "shot");
    fs::create_directories(dir / "shot");
    const fs::path d = dir / "shot";
    // A deterministic seed; 64x48, 4 spp: identical images whatever the step sizes.
    const std::string common = " --size 64x48 --spp 4 --seed 7 --depth 4 -q";
    if (run(quote(wavepath) + " render" + common + " -o " + quote(d / "render.png")) != 0 ||
        run(quote(wavepath) + " render" + common + " -o " + quote(d / "render.exr")) != 0 ||
        run(quote(wavepath) + " render" + common + " --denoise -o " + quote(d / "denoised.png")) != 0) {
        std::printf("FAIL: render did not run\n");
        return 1;
    }
    const std::string view = quote(xvfb) + " -a -s '-screen 0 320x240x24' " + quote(wavepath) +
                             " view" + common + " --frames 4";
    check(run(view + " --screenshot " + quote(d / "view.png")) == 0, "view (clamp) exits 0");
    check(run(view + " --tonemap reinhard --exposure 1 --screenshot " + quote(d / "view_reinhard.png")) == 0,
          "view (reinhard, exposure +1) exits 0");
    check(run(view + " --views --view denoised --screenshot " + quote(d / "view_denoised.png")) == 0,
          "view (--views, denoised) exits 0");

    // 1. Clamp: the window's pixels are render's PNG.
    Pixels ref = read(d / "render.png", true), got = read(d / "view.png", true);
    check(got.w == 64 && got.h == 48, "screenshot is 64x48 (got " + std::to_string(got.w) + "x" +
                                          std::to_string(got.h) + ")");
    if (got.w == ref.w && got.h == ref.h && !got.rgb.empty()) {
        int differ = 0, maxd = 0;
        for (std::size_t i = 0; i < ref.rgb.size(); ++i) {
            int dd = std::abs(int(ref.rgb[i]) - int(got.rgb[i]));
            differ += dd != 0;
            maxd = std::max(maxd, dd);
        }
        long nonblack = 0;
        for (auto v : ref.rgb) nonblack += v > 0;
        check(nonblack > long(ref.rgb.size()) / 2, "render's image is not black");
        check(differ == 0, "clamp: screenshot equals render.png code for code (" +
                               std::to_string(differ) + " channels differ, largest by " +
                               std::to_string(maxd) + ")");
    }
    // 2. Reinhard with exposure +1, from render's EXR here in double.
    Pixels exr = read(d / "render.exr", false), rh = read(d / "view_reinhard.png", true);
    if (rh.w == exr.w && rh.h == exr.h && !rh.rgb.empty()) {
        int maxd = 0;
        for (std::size_t i = 0; i < exr.lin.size(); ++i) {
            double x = 2.0 * double(exr.lin[i]);
            int want = int(std::floor(srgb(x / (1.0 + x)) * 255.0 + 0.5));
            maxd = std::max(maxd, std::abs(want - int(rh.rgb[i])));
        }
        check(maxd <= 1, "reinhard +1 stop: within 1 code of the formula (largest difference " +
                             std::to_string(maxd) + ")");
    } else {
        check(false, "reinhard screenshot readable and 64x48");
    }
    // 3. The denoised view: render --denoise's PNG (the same denoise stage on the same film).
    Pixels dn = read(d / "denoised.png", true), vdn = read(d / "view_denoised.png", true);
    if (dn.w == vdn.w && dn.h == vdn.h && !dn.rgb.empty()) {
        int differ = 0, maxd = 0;
        for (std::size_t i = 0; i < dn.rgb.size(); ++i) {
            int dd = std::abs(int(dn.rgb[i]) - int(vdn.rgb[i]));
            differ += dd != 0;
            maxd = std::max(maxd, dd);
        }
        check(dn.rgb != ref.rgb, "the denoised image is not the noisy one");
        check(differ == 0, "denoised view equals render --denoise's PNG (" + std::to_string(differ) +
                               " channels differ, largest by " + std::to_string(maxd) + ")");
    } else {
        check(false, "denoised screenshot readable and 64x48");
    }
    return failures ? 1 : 0;
}

int no_display(const std::string& wavepath, const fs::path& dir) {
    const fs::path d = dir / "nodisplay";
    fs::remove_all(d);
    fs::create_directories(d / "out");
    const int rc = run("cd " + quote(d / "out") + " && env -u DISPLAY -u WAYLAND_DISPLAY " +
                       quote(wavepath) + " view --spp 1 -q 2> " + quote(d / "stderr.txt"));
    std::ifstream f(d / "stderr.txt");
    std::stringstream ss;
    ss << f.rdbuf();
    const std::string msg = ss.str();
    std::printf("stderr: %s", msg.c_str());
    check(rc == 1, "exit code 1 (got " + std::to_string(rc) + ")");
    check(msg.find("wavepath render") != std::string::npos, "the message suggests `wavepath render`");
    check(std::count(msg.begin(), msg.end(), '\n') == 1, "one line");
    check(fs::is_empty(d / "out"), "nothing written");
    return failures ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 5) {
        std::fprintf(stderr, "usage: viewer_test screenshot|no-display WAVEPATH XVFB_RUN DIR\n");
        return 2;
    }
    const std::string mode = argv[1];
    if (mode == "screenshot") return screenshot(argv[2], argv[3], argv[4]);
    if (mode == "no-display") return no_display(argv[2], argv[4]);
    std::fprintf(stderr, "viewer_test: unknown mode %s\n", argv[1]);
    return 2;
}
