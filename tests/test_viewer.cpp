// test_viewer.cpp — the viewer's host parts (`wavepath view`, docs/viewer.md): the tone
// mapping's 8-bit codes against the formulas written out here in double, the camera
// navigation's geometry, and Wavefront::set_camera against a render made with that camera
// from the start (one camera definition). The window itself: tests/viewer/viewer_test.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <glm/geometric.hpp>

#include "image/tonemap.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "scene/camera_control.h"
#include "support.h"
#include "util/limits.h"

using namespace wp;

namespace {

// IEC 61966-2-1 in double, clamped, rounded to the nearest code.
int srgb_code_ref(double x) {
    if (std::isnan(x)) return 0;
    x = std::fmin(std::fmax(x, 0.0), 1.0);
    double e = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return int(std::floor(e * 255.0 + 0.5));
}

// Elevation of position above target, radians, against up.
float elevation(const Camera& c) {
    glm::vec3 b = glm::normalize(c.position - c.target);
    return std::asin(glm::dot(b, glm::normalize(c.up)));
}

Camera test_camera() {
    Camera c;
    c.position = {1.0f, 2.0f, 6.0f};
    c.target = {0.5f, 1.0f, -1.0f};
    c.up = {0.0f, 1.0f, 0.0f};
    return c;
}

}  // namespace

TEST_CASE("srgb_code8 equals the sRGB formula's code for every kind of float", "[unit][viewer]") {
    // Around every code boundary (found here by the formula's inverse), a ulp-by-ulp walk.
    for (int k = 1; k < 256; ++k) {
        double e = (k - 0.5) / 255.0;  // the encoded value where the code changes
        double x = e <= 12.92 * 0.0031308 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
        float f = float(x);
        for (int i = 0; i < 8; ++i) f = std::nextafter(f, 0.0f);
        for (int i = 0; i < 16; ++i, f = std::nextafter(f, 2.0f)) {
            INFO("k " << k << " x " << f);
            REQUIRE(int(srgb_code8(f)) == srgb_code_ref(f));
        }
    }
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-0.1f, 1.2f);
    for (int i = 0; i < 200000; ++i) {
        float x = u(rng);
        REQUIRE(int(srgb_code8(x)) == srgb_code_ref(x));
    }
    CHECK(srgb_code8(std::numeric_limits<float>::quiet_NaN()) == 0);
    CHECK(srgb_code8(std::numeric_limits<float>::infinity()) == 255);
    CHECK(srgb_code8(-std::numeric_limits<float>::infinity()) == 0);
    CHECK(srgb_code8(1.0f) == 255);
    CHECK(srgb_code8(std::numeric_limits<float>::denorm_min()) == 0);
}

TEST_CASE("tonemap_rgba8: exposure, curves and sRGB against the formulas", "[unit][viewer]") {
    Image img(64, 4);
    std::mt19937 rng(5);
    std::exponential_distribution<float> e(1.5f);
    for (float& v : img.rgb) v = e(rng);
    img.rgb[0] = std::numeric_limits<float>::quiet_NaN();
    struct Case {
        ToneCurve curve;
        double exposure;
        bool srgb;
    };
    for (Case c : {Case{ToneCurve::Clamp, 0.0, true}, Case{ToneCurve::Clamp, -1.5, false},
                   Case{ToneCurve::Reinhard, 1.0, true}, Case{ToneCurve::Filmic, 0.5, true}}) {
        ToneMapping t{c.exposure, c.curve, c.srgb};
        std::vector<std::uint8_t> out;
        tonemap_rgba8(img, t, out);
        REQUIRE(out.size() == img.rgb.size() / 3 * 4);
        int maxd = 0;
        for (std::size_t i = 0; i < img.rgb.size(); ++i) {
            double x = double(img.rgb[i]) * std::exp2(c.exposure);
            double y = std::isnan(x) ? 0.0
                       : c.curve == ToneCurve::Clamp ? x
                       : c.curve == ToneCurve::Reinhard
                           ? x / (1.0 + x)
                           : x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14);
            int want = c.srgb ? srgb_code_ref(y)
                              : int(std::floor(std::fmin(std::fmax(y, 0.0), 1.0) * 255.0 + 0.5));
            maxd = std::max(maxd, std::abs(want - int(out[i / 3 * 4 + i % 3])));
        }
        INFO(tone_curve_name(c.curve) << " exposure " << c.exposure);
        // Clamp at exposure 0 is exact (render's PNG); the others are float against double.
        CHECK(maxd <= (c.curve == ToneCurve::Clamp && c.exposure == 0.0 ? 0 : 1));
        for (std::size_t p = 0; p < out.size(); p += 4) REQUIRE(out[p + 3] == 255);
    }
    CHECK(parse_tone_curve("filmic") == ToneCurve::Filmic);
    CHECK(!parse_tone_curve("aces"));
    CHECK(next_tone_curve(next_tone_curve(next_tone_curve(ToneCurve::Clamp))) == ToneCurve::Clamp);
}

TEST_CASE("camera navigation: orbit, pan, dolly and fly keep their invariants", "[unit][viewer]") {
    const Camera c = test_camera();
    const float dist = glm::length(c.target - c.position);
    const glm::vec3 f = glm::normalize(c.target - c.position);
    const glm::vec3 r = glm::normalize(glm::cross(f, c.up));

    // Orbit: the target and the distance stay; a yaw moves the camera to its right and leaves
    // the elevation; a whole turn comes back; the pitch changes the elevation by its angle and
    // stops short of the pole.
    Camera o = orbit_camera(c, 0.3f, 0.0f);
    CHECK(o.target == c.target);
    CHECK(glm::length(o.target - o.position) == Approx(dist).epsilon(1e-5));
    CHECK(glm::dot(o.position - c.position, r) > 0.0f);
    CHECK(elevation(o) == Approx(elevation(c)).margin(1e-5));
    Camera full = c;
    for (int i = 0; i < 8; ++i) full = orbit_camera(full, float(M_PI / 4.0), 0.0f);
    CHECK(glm::length(full.position - c.position) < 1e-4f * dist);
    Camera p = orbit_camera(c, 0.0f, 0.2f);
    CHECK(elevation(p) == Approx(elevation(c) + 0.2f).margin(1e-5));
    Camera pole = orbit_camera(c, 0.0f, 10.0f);
    CHECK(elevation(pole) == Approx(glm::radians(limits::kViewerMaxPitchDeg)).margin(1e-4));
    CHECK(glm::length(pole.target - pole.position) == Approx(dist).epsilon(1e-5));

    // Pan: position and target move by the same vector, across the view, scaled by distance.
    Camera pn = pan_camera(c, 0.1f, -0.05f);
    glm::vec3 m1 = pn.position - c.position, m2 = pn.target - c.target;
    CHECK(glm::length(m1 - m2) < 1e-5f);
    CHECK(std::fabs(glm::dot(m1, f)) < 1e-5f);
    CHECK(glm::length(m1) == Approx(dist * std::sqrt(0.1 * 0.1 + 0.05 * 0.05)).epsilon(1e-5));
    CHECK(glm::dot(m1, r) == Approx(0.1f * dist).epsilon(1e-5));

    // Dolly: the distance scales, the direction and target stay; never onto the target.
    Camera d = dolly_camera(c, 0.5f);
    CHECK(glm::length(d.target - d.position) == Approx(0.5f * dist).epsilon(1e-5));
    CHECK(glm::dot(glm::normalize(d.target - d.position), f) == Approx(1.0f).epsilon(1e-6));
    CHECK(glm::length(dolly_camera(c, 0.0f).target - c.target) == 0.0f);
    CHECK(glm::length(dolly_camera(c, 0.0f).target - dolly_camera(c, 0.0f).position) > 0.0f);

    // Fly: both points move along the frame.
    Camera fl = fly_camera(c, 0.0f, 0.0f, 2.0f);
    CHECK(glm::length(fl.position - (c.position + 2.0f * f)) < 1e-5f);
    CHECK(glm::length(fl.target - (c.target + 2.0f * f)) < 1e-5f);

    // The snippet names the JSON scene format's keys.
    std::string j = camera_json_snippet(c);
    for (const char* k : {"\"camera\"", "\"position\"", "\"look_at\"", "\"up\"", "\"fov\"", "\"width\""})
        CHECK(j.find(k) != std::string::npos);
}

TEST_CASE("Wavefront::set_camera renders what a render with that camera from the start does",
          "[kernel][viewer]") {
    Scene scene = make_cornell_box(200);
    const Camera original = scene.camera;
    const Camera moved = orbit_camera(pan_camera(original, 0.05f, 0.02f), 0.2f, 0.1f);
    render::RenderSettings s;
    s.width = 24;
    s.height = 18;
    s.depth = 3;
    s.seed = 3;
    render::LoopOptions lo;
    lo.spp = 2;

    scene.camera = moved;
    render::Wavefront direct(test::device(), scene, s);
    render::render_frames(direct, lo, nullptr);
    const std::vector<FilmPixel> want = direct.film();

    scene.camera = original;
    render::Wavefront viewer(test::device(), scene, s);
    render::render_frames(viewer, lo, nullptr);  // some samples with the old camera ...
    viewer.set_camera(moved);                     // ... are dropped with the move
    CHECK(viewer.frames() == 0);
    render::render_frames(viewer, lo, nullptr);
    const std::vector<FilmPixel> got = viewer.film();
    REQUIRE(got.size() == want.size());
    CHECK(std::memcmp(got.data(), want.data(), got.size() * sizeof(FilmPixel)) == 0);
    // The viewer's non-blocking read (and the ray totals read along) sees the same film.
    std::vector<FilmPixel> snap;
    cl_ulong rays[2] = {0, 0};
    viewer.enqueue_film_read(snap, rays).wait();
    REQUIRE(snap.size() == want.size());
    CHECK(std::memcmp(snap.data(), want.data(), snap.size() * sizeof(FilmPixel)) == 0);
    const auto totals = viewer.ray_totals();
    CHECK(rays[0] == totals.closest);
    CHECK(rays[1] == totals.shadow);
    // And the move changed the image.
    scene.camera = original;
    render::Wavefront still(test::device(), scene, s);
    render::render_frames(still, lo, nullptr);
    CHECK(std::memcmp(still.film().data(), want.data(), want.size() * sizeof(FilmPixel)) != 0);
}
