// test_aov.cpp — the feature buffers (render/aov.h, kernels/aov.cl) against analytic
// scenes: a constant-albedo plane facing the camera (albedo, normal, depth = distance to
// the plane along each pixel's ray, computed here in double from the camera model), a
// mirror in front of a diffuse wall (the AOVs look through the specular bounce), misses,
// the generic kernels, and --aov on the command line.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "image/image.h"
#include "render/aov.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "support.h"
#include "temp_dir.h"
#include "util/error.h"

using namespace wp;

namespace {

// A quad in the plane z = z0 of half-size s; facing +z when `up`, else -z.
void add_quad_z(Scene& sc, float z0, float s, std::uint32_t mat, bool up) {
    std::vector<glm::vec3> p = {{-s, -s, z0}, {s, -s, z0}, {s, s, z0}, {-s, s, z0}};
    std::vector<glm::uvec3> t = up ? std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}}
                                   : std::vector<glm::uvec3>{{0, 2, 1}, {0, 3, 2}};
    sc.add_mesh(p, t, mat);
}

Material diffuse(glm::vec3 albedo) {
    Material m;
    m.kind = MaterialKind::Diffuse;
    m.albedo = albedo;
    return m;
}

// Camera at (0, 0, 5) looking down -z, 40 degrees vertical field of view.
Scene base_scene(int w, int h) {
    Scene sc;
    sc.name = "aov-test";
    sc.camera.position = {0.0f, 0.0f, 5.0f};
    sc.camera.target = {0.0f, 0.0f, 0.0f};
    sc.camera.vfov_deg = 40.0f;
    sc.camera.width = w;
    sc.camera.height = h;
    return sc;
}

struct AovRender {
    Image color;
    render::AovImages aov;
};

AovRender render_aov(const Scene& sc, int w, int h, int spp, int depth = 3, bool jitter = false,
                     render::KernelSet kernels = render::KernelSet::Specialised) {
    render::RenderSettings s;
    s.width = w;
    s.height = h;
    s.depth = depth;
    s.seed = 3;
    s.jitter = jitter;
    s.aov = true;
    s.kernels = kernels;
    render::Wavefront wf(test::device(), sc, s);
    render::LoopOptions lo;
    lo.spp = spp;
    render::render_frames(wf, lo, nullptr);
    return {wf.resolve(), wf.aovs()};
}

// cos of the angle between pixel (x, y)'s centre ray and the view axis, in double, from
// the pinhole model of camera.h (image plane at distance 1, half-height tan(vfov / 2)).
double cos_to_axis(int x, int y, int w, int h, double vfov_deg) {
    const double th = std::tan(vfov_deg * M_PI / 360.0), aspect = double(w) / h;
    const double sx = (2.0 * (x + 0.5) / w - 1.0) * th * aspect;
    const double sy = (1.0 - 2.0 * (y + 0.5) / h) * th;
    return 1.0 / std::sqrt(1.0 + sx * sx + sy * sy);
}

} // namespace

TEST_CASE("aov: a plane facing the camera: albedo, normal and depth exactly", "[render][aov]") {
    const int w = 24, h = 18;
    Scene sc = base_scene(w, h);
    const glm::vec3 albedo(0.25f, 0.5f, 0.75f);
    add_quad_z(sc, 0.0f, 100.0f, sc.add_material(diffuse(albedo)), true);
    // Pixel centres (no jitter), so every sample of a pixel is the same ray.
    AovRender r = render_aov(sc, w, h, 4);
    double worst_depth = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float* a = r.aov.albedo.pixel(x, y);
            const float* n = r.aov.normal.pixel(x, y);
            INFO("pixel " << x << ", " << y);
            // The sums of 4 equal floats divided by 4: exact.
            CHECK(a[0] == albedo.x);
            CHECK(a[1] == albedo.y);
            CHECK(a[2] == albedo.z);
            CHECK(n[0] == 0.0f);
            CHECK(n[1] == 0.0f);
            CHECK(n[2] == 1.0f);
            const double expect = 5.0 / cos_to_axis(x, y, w, h, 40.0);
            const double d = r.aov.depth[std::size_t(y) * w + x];
            worst_depth = std::max(worst_depth, std::abs(d - expect) / expect);
        }
    // Float ray directions and hit distances: a few ulps.
    CHECK(worst_depth < 2e-6);

    // With pixel jitter the albedo and normal stay exact (every sample sees the plane).
    AovRender j = render_aov(sc, w, h, 8, 3, true);
    for (std::size_t i = 0; i < j.aov.albedo.rgb.size(); i += 3) {
        CHECK(j.aov.albedo.rgb[i + 1] == Approx(albedo.y).epsilon(1e-6));
        CHECK(j.aov.normal.rgb[i + 2] == Approx(1.0f).epsilon(1e-6));
    }
}

TEST_CASE(
    "aov: misses give albedo 0, normal 0 and depth +inf; the back face's normal faces the camera",
    "[render][aov]") {
    const int w = 20, h = 16;
    Scene sc = base_scene(w, h);
    // A small quad seen from its back (it faces -z, away from the camera): the normal AOV
    // turns to the side the ray arrived from, +z.
    add_quad_z(sc, 0.0f, 0.5f, sc.add_material(diffuse({0.6f, 0.6f, 0.6f})), false);
    AovRender r = render_aov(sc, w, h, 2);
    // The corner pixel sees nothing, the centre pixel the quad.
    CHECK(r.aov.albedo.pixel(0, 0)[0] == 0.0f);
    CHECK(r.aov.normal.pixel(0, 0)[2] == 0.0f);
    CHECK(std::isinf(r.aov.depth[0]));
    CHECK(r.aov.depth[0] > 0.0f);
    const std::size_t c = std::size_t(h / 2) * w + w / 2;
    CHECK(r.aov.albedo.rgb[3 * c] == 0.6f);
    CHECK(r.aov.normal.rgb[3 * c + 2] == 1.0f);
    CHECK(r.aov.depth[c] == Approx(5.0 / cos_to_axis(w / 2, h / 2, w, h, 40.0)).epsilon(2e-6));
}

TEST_CASE("aov: through a mirror, the AOVs are the diffuse wall's, at the path's length",
          "[render][aov]") {
    const int w = 16, h = 12;
    Scene sc = base_scene(w, h);
    Material mirror;
    mirror.kind = MaterialKind::Mirror;
    mirror.albedo = {0.9f, 0.9f, 0.9f};
    add_quad_z(sc, 0.0f, 100.0f, sc.add_material(mirror), true);
    // The wall behind the camera at z = 10, facing -z (towards the mirror).
    const glm::vec3 wall(0.2f, 0.4f, 0.1f);
    add_quad_z(sc, 10.0f, 100.0f, sc.add_material(diffuse(wall)), false);
    AovRender r = render_aov(sc, w, h, 2);
    double worst = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            INFO("pixel " << x << ", " << y);
            CHECK(r.aov.albedo.pixel(x, y)[1] == wall.y);
            CHECK(r.aov.normal.pixel(x, y)[2] == -1.0f); // the wall's normal, facing the ray
            // 5 / cos to the mirror, then 10 / cos to the wall.
            const double expect = 15.0 / cos_to_axis(x, y, w, h, 40.0);
            worst =
                std::max(worst, std::abs(r.aov.depth[std::size_t(y) * w + x] - expect) / expect);
        }
    // The reflected ray starts off the mirror by its scale-free offset (offset.h: it grows
    // with the 200-unit quad's coordinates), about 1e-4 here.
    CHECK(worst < 2e-5 * 15.0);

    // Depth 0: the path ends at the mirror, whose values stay.
    AovRender r0 = render_aov(sc, w, h, 1, 0);
    CHECK(r0.aov.albedo.pixel(3, 3)[0] == 0.9f);
    CHECK(r0.aov.normal.pixel(3, 3)[2] == 1.0f);
}

TEST_CASE("aov: the generic kernels give the same AOVs", "[render][aov]") {
    const int w = 16, h = 12;
    Scene sc = base_scene(w, h);
    add_quad_z(sc, 0.0f, 1.0f, sc.add_material(diffuse({0.3f, 0.2f, 0.1f})), true);
    AovRender a = render_aov(sc, w, h, 2, 3, true);
    AovRender b = render_aov(sc, w, h, 2, 3, true, render::KernelSet::Generic);
    CHECK(a.aov.albedo.rgb == b.aov.albedo.rgb);
    CHECK(a.aov.normal.rgb == b.aov.normal.rgb);
    for (std::size_t i = 0; i < a.aov.depth.size(); ++i)
        CHECK((a.aov.depth[i] == b.aov.depth[i] ||
               (std::isinf(a.aov.depth[i]) && std::isinf(b.aov.depth[i]))));
}

TEST_CASE("aov: a render without AOVs allocates none and builds no aov program", "[render][aov]") {
    Scene sc = base_scene(8, 6);
    add_quad_z(sc, 0.0f, 1.0f, sc.add_material(diffuse({0.5f, 0.5f, 0.5f})), true);
    auto has_aov_buffer = [](const render::Wavefront& wf) {
        for (const auto& b : wf.memory().buffers)
            if (b.name.find("AOV") != std::string::npos) return true;
        return false;
    };
    auto has_aov_program = [](const render::Wavefront& wf) {
        for (const auto& p : wf.program_builds())
            if (p.file == "aov.cl") return true;
        return false;
    };
    render::RenderSettings s;
    s.width = 8;
    s.height = 6;
    {
        render::Wavefront wf(test::device(), sc, s);
        CHECK_FALSE(has_aov_buffer(wf));
        CHECK_FALSE(has_aov_program(wf));
        CHECK_THROWS_AS(wf.aovs(), Error);
    }
    s.aov = true;
    render::Wavefront wf(test::device(), sc, s);
    CHECK(has_aov_buffer(wf));
    CHECK(has_aov_program(wf));
    CHECK(wf.memory().bytes_per_pixel ==
          render::FilmBuffers::bytes_per_pixel(false) + render::AovBuffers::kBytesPerPixel);
}

TEST_CASE("aov: --aov lists: names, all, unknown and repeated names", "[unit][aov]") {
    render::AovSet s = render::parse_aov_list("normal,depth");
    CHECK_FALSE(s.albedo);
    CHECK(s.normal);
    CHECK(s.depth);
    s = render::parse_aov_list("all");
    CHECK((s.albedo && s.normal && s.depth));
    auto message = [](const std::string& list) {
        try {
            render::parse_aov_list(list);
        } catch (const UsageError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK(message("albedo,colour").find("unknown AOV 'colour'") != std::string::npos);
    CHECK(message("albedo,colour").find("albedo, normal, depth") != std::string::npos);
    CHECK(message("depth,depth").find("'depth' is listed twice") != std::string::npos);
    CHECK(message("albedo,").find("unknown AOV ''") != std::string::npos);
    CHECK(message("").find("empty") != std::string::npos);
}

TEST_CASE("render CLI: --aov writes named EXR channels and PNG previews; bad lists fail",
          "[render][cli][aov]") {
    test::TempDir d;
    auto r = test::run_render(
        d.path, "--size 32x24 --spp 2 --aov albedo,normal,depth --aov-png -o out.exr");
    INFO(r.err);
    REQUIRE(r.status == 0);
    ChannelImage img = read_image_channels(d.path / "out.exr");
    for (const char* c : {"R", "G", "B", "albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y",
                          "normal.Z", "depth.Z"})
        CHECK(img.has(c));
    CHECK(img.names.size() == 10);
    // read_image still reads the colour (R, G, B) of a file with AOV channels.
    Image rgb = read_image(d.path / "out.exr");
    CHECK(rgb.rgb[3 * 100 + 1] == img.channel("G")[100]);
    for (const char* p : {"out.albedo.png", "out.normal.png", "out.depth.png"})
        CHECK(std::filesystem::exists(d.path / p));
    // Depths are > 0, +inf only where the albedo is 0 (no sample hit), and the box fills
    // the centre of the view.
    const auto z = img.channel("depth.Z"), alb = img.channel("albedo.R");
    for (std::size_t i = 0; i < z.size(); ++i) {
        CHECK(z[i] > 0.0f);
        if (std::isinf(z[i])) CHECK(alb[i] == 0.0f);
    }
    CHECK(std::isfinite(z[12 * 32 + 16]));

    test::TempDir e;
    r = test::run_render(e.path, "--size 16x12 --spp 1 --aov albedo,colour -o x.exr");
    CHECK(r.status == 2);
    CHECK(r.err.find("unknown AOV 'colour'") != std::string::npos);
    CHECK(e.empty_of_images());
    r = test::run_render(e.path, "--size 16x12 --spp 1 --aov albedo -o x.png");
    CHECK(r.status == 2);
    CHECK(r.err.find("--aov-png") != std::string::npos);
    r = test::run_render(e.path, "--size 16x12 --spp 1 --aov-png -o x.exr");
    CHECK(r.status == 2);
    CHECK(r.err.find("needs --aov") != std::string::npos);
    CHECK(e.empty_of_images());
}
