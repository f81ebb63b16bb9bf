// test_camera_lens.cpp — the thin-lens camera (depth of field) against closed forms.
//
// The camera model (kernels/shared/camera.h, written again here in double precision):
// camera coordinates have the eye at 0, lateral axes right/up and depth z along forward.
// The image plane is z = 1; image position p (lateral, image-plane units) is at pixel
//   px = W/2 + p.right * K,  py = H/2 - p.up * K,   K = H / (2 tan(vfov / 2)) pixels per unit
// (right is scaled by tan(vfov/2) * W/H, so K is the same along both axes).
//
// Circle of confusion. The ray for image point p and lens point a (lateral, |a| <= ρ,
// z = 0) passes through d_f (p, 1), the pinhole ray's point on the plane in focus; at depth
// z its lateral position is
//   X(z) = a + (z / d_f) (d_f p - a) = a (1 - z / d_f) + z p.
// It meets a point q (lateral) at depth d_o when X(d_o) = q, i.e.
//   p = q / d_o + a (1/d_f - 1/d_o).
// With a uniform on the lens disk, the image points that see q fill the disk around the
// pinhole image q / d_o of radius ρ |1/d_f - 1/d_o|, uniformly (the map a -> p is linear
// with a constant Jacobian), so in pixels
//   R = ρ |1/d_f - 1/d_o| K.
// A small emitter (a square facing the camera at depth d_o, pinhole image of side s
// pixels, radiance L) is thus imaged as its pinhole image convolved with the uniform disk
// of radius R (the integral L s² is kept): the convolution of two independent
// distributions, whose variances add. Per image axis
//   E[x²] = R²/4 (uniform disk) + s²/12 (uniform square side).
// The test measures the second moment of the rendered image about the pinhole image's
// centre. Pixel values are box averages and the moment is taken at pixel centres: for a
// profile smooth on the pixel scale (the disk blurred by a 6-pixel square is) the grouped
// moment is the continuous one + 1/12 (Sheppard's correction); for the pinhole's square
// with its edges on pixel edges it is s²/12 - 1/12 exactly.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <vector>

#include <glm/glm.hpp>

#include "chi2.h"
#include "render/loop.h"
#include "render/stages/generate.h"
#include "render/wavefront.h"
#include "scene/json_scene.h"
#include "scene/mitsuba_loader.h"
#include "scene/upload.h"
#include "scene/validate.h"
#include "shared/types.h"
#include "support.h"
#include "util/error.h"

using namespace wp;

namespace {

std::vector<Ray> generate_rays(const CameraData& cam, bool lens_program, cl_uint seed,
                               cl_uint sample) {
    auto& dev = test::device();
    render::KernelConfig with_lens;
    with_lens.lens = true;
    static render::GenerateStage plain(dev, render::KernelConfig{});
    static render::GenerateStage lens(dev, with_lens);
    const int n = cam.width * cam.height;
    render::PathQueue q;
    q.rays = ocl::Array<Ray>::allocate(dev, std::size_t(n), "rays");
    q.paths = ocl::Array<PathState>::allocate(dev, std::size_t(n), "paths");
    q.count = ocl::Array<int>::zeros(dev, 1, "count");
    auto radiance = ocl::Array<float4>::zeros(dev, std::size_t(n), "radiance");
    auto counters = ocl::Array<int>::zeros(dev, WP_COUNTER_COUNT, "counters");
    (lens_program ? lens : plain).enqueue(cam, seed, 0, sample, n, q, radiance, counters);
    auto c = counters.read(dev);
    REQUIRE(c[WP_COUNTER_GENERATE_NONFINITE] == 0);
    return q.rays.read(dev);
}

Camera oblique_camera() {
    Camera c;
    c.position = {0.3f, 1.1f, 3.7f};
    c.target = {-0.2f, 0.9f, 0.1f};
    c.up = {0.05f, 1.0f, 0.0f}; // not orthogonal to the view direction on purpose
    c.vfov_deg = 47.0f;
    return c;
}

glm::dvec3 dv(float4 v) {
    return {v.x, v.y, v.z};
}

} // namespace

TEST_CASE("camera: thin-lens rays start on the lens disk, uniformly, and pass through the "
          "pinhole ray's point on the plane in focus",
          "[kernel][generate][lens]") {
    Camera c = oblique_camera();
    c.lens_radius = 0.25f;
    c.focus_distance = 2.3f;
    const int w = 64, h = 48;
    const CameraData cam = upload_camera(c, w, h, /*jitter=*/false);
    // The camera frame and the pinhole model in double precision (as in test_generate.cpp).
    const glm::dvec3 eye(c.position), f = glm::normalize(glm::dvec3(c.target) - eye);
    const glm::dvec3 r = glm::normalize(glm::cross(f, glm::dvec3(c.up))), u = glm::cross(r, f);
    const double th = std::tan(c.vfov_deg * 0.5 * M_PI / 180.0), aspect = double(w) / h;
    const double rho = c.lens_radius, df = c.focus_distance;

    // Lens points in 8 rings of equal area x 8 sectors: 64 cells of probability 1/64.
    std::vector<double> observed(64, 0.0);
    int total = 0;
    for (cl_uint sample = 0; sample < 4; ++sample) {
        const std::vector<Ray> rays = generate_rays(cam, true, 5, sample);
        for (int p = 0; p < w * h; ++p) {
            const int x = p % w, y = p / w;
            const glm::dvec3 o = dv(rays[p].org), d = dv(rays[p].dir);
            const glm::dvec3 a = o - eye;
            // On the lens: in the plane through the eye perpendicular to forward, |a| <= ρ.
            REQUIRE(std::abs(glm::dot(a, f)) < 1e-6);
            REQUIRE(glm::length(a) <= rho * (1.0 + 1e-6));
            REQUIRE(std::abs(glm::length(d) - 1.0) < 1e-6);
            // Through the pixel centre's pinhole ray at distance d_f along forward.
            const double sx = (2.0 * (x + 0.5) / w - 1.0) * th * aspect;
            const double sy = (1.0 - 2.0 * (y + 0.5) / h) * th;
            const glm::dvec3 focus = eye + df * (f + sx * r + sy * u);
            const glm::dvec3 to = focus - o;
            const glm::dvec3 off = to - glm::dot(to, d) * d;
            REQUIRE(glm::length(off) < 2e-6 * glm::length(to));
            // Cell of the lens point.
            const double ar = glm::dot(a, r) / rho, au = glm::dot(a, u) / rho;
            const double r2 = std::min(ar * ar + au * au, 1.0 - 1e-12);
            double phi = std::atan2(au, ar);
            if (phi < 0) phi += 2.0 * M_PI;
            const int ring = int(r2 * 8.0), sector = std::min(7, int(phi / (2.0 * M_PI) * 8.0));
            observed[std::size_t(ring * 8 + sector)] += 1.0;
            ++total;
        }
    }
    const std::vector<double> expected(64, total / 64.0);
    int dof = 0;
    const double pv = test::chi2_pvalue(observed, expected, &dof);
    INFO("chi2 p-value " << pv << " (" << dof << " dof, " << total << " lens points)");
    CHECK(pv > 1e-3);
}

TEST_CASE("camera: lens radius 0 gives the pinhole's rays bit for bit, with or without the "
          "lens program",
          "[kernel][generate][lens]") {
    Camera c = oblique_camera();
    c.focus_distance = 3.0f; // read by nothing without a lens
    const int w = 40, h = 30;
    const CameraData cam = upload_camera(c, w, h, /*jitter=*/true);
    CHECK(cam.lens.x == 0.0f);
    for (cl_uint sample : {0u, 7u}) {
        const std::vector<Ray> plain = generate_rays(cam, false, 3, sample);
        const std::vector<Ray> lens = generate_rays(cam, true, 3, sample);
        REQUIRE(plain.size() == lens.size());
        CHECK(std::memcmp(plain.data(), lens.data(), plain.size() * sizeof(Ray)) == 0);
        for (const Ray& ray : plain) {
            REQUIRE(ray.org.x == c.position.x);
            REQUIRE(ray.org.y == c.position.y);
            REQUIRE(ray.org.z == c.position.z);
        }
    }
    // The renderer compiles the lens only for a camera that has one.
    Scene s;
    s.camera = c;
    CHECK_FALSE(render::KernelConfig::from_scene(s).lens);
    CHECK(render::KernelConfig::from_scene(s).generate_options().find("WP_HAVE_LENS") ==
          std::string::npos);
    s.camera.lens_radius = 0.1f;
    CHECK(render::KernelConfig::from_scene(s).lens);
    CHECK(render::KernelConfig::from_scene(s).generate_options().find("-D WP_HAVE_LENS=1") !=
          std::string::npos);
}

namespace {

constexpr int kW = 96, kH = 64; // non-square: an aspect error would make the disk an ellipse
constexpr double kVfov = 30.0;  // degrees
constexpr double kSide = 6.0;   // the emitter's pinhole image: 6 x 6 pixels, edges on pixel edges
constexpr int kSpp = 1024;

double pixels_per_unit() {
    return kH / (2.0 * std::tan(kVfov * 0.5 * M_PI / 180.0));
}

// A square emitter (radiance 1, facing the camera) of pinhole image side kSide pixels,
// centred on the axis at depth d_o, seen by a camera at the origin looking down -z.
Scene emitter_scene(double d_o, double lens_radius, double focus_distance) {
    Scene s;
    s.name = "thin-lens test";
    Material m;
    m.name = "lamp";
    m.albedo = glm::vec3(0.0f);
    m.emission = glm::vec3(1.0f);
    const std::uint32_t id = s.add_material(m);
    const float hw = float(0.5 * kSide / pixels_per_unit() * d_o), z = float(-d_o);
    // Counter-clockwise seen from the camera: the emitting front faces it.
    s.add_mesh({{-hw, -hw, z}, {hw, -hw, z}, {hw, hw, z}, {-hw, hw, z}}, {{0, 1, 2}, {0, 2, 3}},
               id);
    s.camera.position = {0.0f, 0.0f, 0.0f};
    s.camera.target = {0.0f, 0.0f, -1.0f};
    s.camera.up = {0.0f, 1.0f, 0.0f};
    s.camera.vfov_deg = float(kVfov);
    s.camera.width = kW;
    s.camera.height = kH;
    s.camera.lens_radius = float(lens_radius);
    s.camera.focus_distance = float(focus_distance);
    validate_scene(s);
    return s;
}

Image render_emitter(const Scene& scene) {
    render::RenderSettings rs;
    rs.width = kW;
    rs.height = kH;
    rs.depth = 0; // the emitter seen directly, nothing else
    rs.seed = 1;
    render::Wavefront wf(test::device(), scene, rs);
    CHECK(wf.config().lens == (scene.camera.lens_radius > 0.0f));
    render::LoopOptions lo;
    lo.spp = kSpp;
    render::render_frames(wf, lo, nullptr);
    return wf.resolve();
}

// Moments of the image's red channel about the image centre (the pinhole image's centre),
// at pixel centres, and their standard errors: every sample sees radiance 1 or 0, so a
// pixel of mean v over n samples has variance at most v (1 - v) / n (independent
// samples; the stratified sampler does no worse).
struct Spot {
    double sum = 0;          // Σ v
    double mx = 0, my = 0;   // centroid (pixels)
    double sxx = 0, syy = 0; // Σ v x² / Σ v, Σ v y² / Σ v
    double se_mx = 0, se_my = 0, se_xx = 0, se_yy = 0;
    double outside = 0; // Σ v outside the box given to measure()
};

Spot measure(const Image& img, int box_lo_x = 0, int box_hi_x = kW, int box_lo_y = 0,
             int box_hi_y = kH) {
    Spot s;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double v = img.pixel(x, y)[0];
            const double px = x + 0.5 - kW / 2.0, py = y + 0.5 - kH / 2.0;
            s.sum += v;
            s.mx += v * px;
            s.my += v * py;
            s.sxx += v * px * px;
            s.syy += v * py * py;
            if (x < box_lo_x || x >= box_hi_x || y < box_lo_y || y >= box_hi_y) s.outside += v;
        }
    s.mx /= s.sum;
    s.my /= s.sum;
    s.sxx /= s.sum;
    s.syy /= s.sum;
    // Delta method: d(Σ v g / Σ v) / dv_i = (g_i - mean) / Σ v.
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const double v = img.pixel(x, y)[0];
            const double var = std::max(0.0, v * (1.0 - v)) / kSpp;
            const double px = x + 0.5 - kW / 2.0, py = y + 0.5 - kH / 2.0;
            auto add = [&](double& se, double g, double mean) {
                se += var * (g - mean) * (g - mean) / (s.sum * s.sum);
            };
            add(s.se_mx, px, s.mx);
            add(s.se_my, py, s.my);
            add(s.se_xx, px * px, s.sxx);
            add(s.se_yy, py * py, s.syy);
        }
    s.se_mx = std::sqrt(s.se_mx);
    s.se_my = std::sqrt(s.se_my);
    s.se_xx = std::sqrt(s.se_xx);
    s.se_yy = std::sqrt(s.se_yy);
    return s;
}

} // namespace

TEST_CASE("camera: a small emitter out of focus is imaged as the circle of confusion "
          "R = rho |1/d_f - 1/d_o| H / (2 tan(vfov/2))",
          "[render][lens]") {
    const double K = pixels_per_unit();
    const double s2 = kSide * kSide / 12.0; // the square's own variance per axis

    // The pinhole image: the emitter's 6 x 6 pixels (exact: its edges lie on pixel edges, so
    // only a sample within rounding error of a pixel edge may land on the other side),
    // grouped second moment s²/12 - 1/12 per axis. It checks the setup (size, position).
    const Image pin = render_emitter(emitter_scene(4.0, 0.0, 1.0));
    const Spot p = measure(pin, kW / 2 - 3, kW / 2 + 3, kH / 2 - 3, kH / 2 + 3);
    INFO("pinhole: sum " << p.sum << " centroid (" << p.mx << ", " << p.my << ") moments " << p.sxx
                         << ", " << p.syy << ", outside the 6 x 6 pixels " << p.outside);
    CHECK(p.outside < 1e-4 * p.sum);
    CHECK(measure(pin, kW / 2 - 4, kW / 2 + 4, kH / 2 - 4, kH / 2 + 4).outside == 0.0);
    CHECK(p.sum == Approx(kSide * kSide).epsilon(1e-3));
    CHECK(std::abs(p.mx) < 1e-3);
    CHECK(std::abs(p.my) < 1e-3);
    CHECK(p.sxx == Approx(s2 - 1.0 / 12.0).epsilon(1e-3));
    CHECK(p.syy == Approx(s2 - 1.0 / 12.0).epsilon(1e-3));

    struct Case {
        double d_o, d_f, rho;
    };
    // Behind the plane in focus and in front of it; R ≈ 11.9 and 4.0 pixels.
    for (Case cs : {Case{4.0, 2.0, 0.4}, Case{1.5, 3.0, 0.1}}) {
        const double R = cs.rho * std::abs(1.0 / cs.d_f - 1.0 / cs.d_o) * K;
        const Image img = render_emitter(emitter_scene(cs.d_o, cs.rho, cs.d_f));
        const Spot m = measure(img);
        // Grouped second moment per axis (Sheppard: + 1/12 for a smooth profile); allow 0.03
        // pixels² for the correction's residual (a Monte Carlo integration of the grouped
        // moment of this profile in double precision left 0.004) and 5 standard errors.
        const double expected = R * R / 4.0 + s2 + 1.0 / 12.0;
        INFO("d_o " << cs.d_o << ", d_f " << cs.d_f << ", rho " << cs.rho << ": R = " << R
                    << " px, expected moment " << expected << "; measured " << m.sxx << " +- "
                    << m.se_xx << ", " << m.syy << " +- " << m.se_yy << "; radius from them "
                    << 2.0 * std::sqrt(m.sxx - s2 - 1.0 / 12.0) << ", "
                    << 2.0 * std::sqrt(m.syy - s2 - 1.0 / 12.0) << "; centroid (" << m.mx << ", "
                    << m.my << ") sum " << m.sum);
        // Nothing lost or gained: the blur keeps the integral L s².
        CHECK(m.sum ==
              Approx(kSide * kSide)
                  .epsilon(5.0 * std::sqrt(kSide * kSide / kSpp) / (kSide * kSide) + 1e-3));
        CHECK(std::abs(m.mx) < 5.0 * m.se_mx + 1e-3);
        CHECK(std::abs(m.my) < 5.0 * m.se_my + 1e-3);
        const double tol_x = 5.0 * m.se_xx + 0.03, tol_y = 5.0 * m.se_yy + 0.03;
        CHECK(std::abs(m.sxx - expected) < tol_x);
        CHECK(std::abs(m.syy - expected) < tol_y);
        // The test is sharp: as a radius (dR / R = 2 dm / R²) the tolerance is a few percent.
        CHECK(2.0 * std::max(tol_x, tol_y) / (R * R) < 0.05);
    }

    // In focus (d_o = d_f): every lens point sees the emitter through the same image
    // point, so the spot is the pinhole's, to within a pixel (rays that graze the emitter's
    // edges may round the other way).
    const Image focused = render_emitter(emitter_scene(4.0, 0.4, 4.0));
    const Spot f = measure(focused, kW / 2 - 4, kW / 2 + 4, kH / 2 - 4, kH / 2 + 4);
    INFO("in focus: sum "
         << f.sum << " moments " << f.sxx << ", " << f.syy << ", outside " << f.outside
         << ", outside the 6 x 6 pixels "
         << measure(focused, kW / 2 - 3, kW / 2 + 3, kH / 2 - 3, kH / 2 + 3).outside);
    CHECK(f.outside == 0.0);
    CHECK(measure(focused, kW / 2 - 3, kW / 2 + 3, kH / 2 - 3, kH / 2 + 3).outside < 1e-3 * f.sum);
    CHECK(f.sum == Approx(p.sum).epsilon(1e-3));
    CHECK(std::abs(f.sxx - p.sxx) < 0.02);
    CHECK(std::abs(f.syy - p.syy) < 0.02);
}

// --- Scene files: JSON camera keys, Mitsuba thinlens, validation (parse only) -------------

namespace {

bool contains(const std::string& s, const std::string& part) {
    return s.find(part) != std::string::npos;
}

Scene parse_json(const std::string& camera) {
    return parse_json_scene(R"({"camera": )" + camera + R"(,
        "materials": {"lamp": {"type": "diffuse", "emission": 1}},
        "shapes": [{"type": "quad", "size": 1, "material": "lamp"}]})",
                            "dir/lens.json");
}

template <typename F> std::string error_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    FAIL_CHECK("no error");
    return {};
}

Scene parse_xml(const std::string& sensor) {
    return parse_mitsuba("<scene version=\"3.0.0\">\n<shape type=\"rectangle\"/>\n" + sensor +
                             "\n</scene>\n",
                         "lens.xml");
}

} // namespace

TEST_CASE("json scene: camera lens_radius / aperture_radius and focus_distance",
          "[scene][json][parser][lens]") {
    const std::string at = R"("position": [0, 0, 5], "look_at": [0, 0, 1])";
    Scene a = parse_json("{" + at + R"(, "lens_radius": 0.05, "focus_distance": 3.5})");
    CHECK(a.camera.lens_radius == 0.05f);
    CHECK(a.camera.focus_distance == 3.5f);
    Scene b = parse_json("{" + at + R"(, "aperture_radius": 0.25})");
    CHECK(b.camera.lens_radius == 0.25f);
    CHECK(b.camera.focus_distance == 4.0f); // by default the distance to look_at
    Scene c = parse_json("{" + at + "}");
    CHECK(c.camera.lens_radius == 0.0f); // a pinhole
    CHECK(c.camera.focus_distance == 1.0f);
    Scene d = parse_json(
        R"({"matrix": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0, 0, 1], "lens_radius": 0.1})");
    CHECK(d.camera.focus_distance == Approx(1.0f)); // a matrix looks at distance 1
    Scene e = parse_json(R"({"lens_radius": 0})");
    CHECK(e.camera.lens_radius == 0.0f);

    struct Bad {
        std::string camera;
        std::vector<std::string> parts;
    };
    for (const Bad& bad : std::vector<Bad>{
             {"{" + at + R"(, "lens_radius": 0.1, "aperture_radius": 0.1})",
              {"dir/lens.json:1:", "/camera/aperture_radius", "not both"}},
             {R"({"lens_radius": -0.1})",
              {"dir/lens.json:1:", "/camera/lens_radius", "out of range", ">= 0"}},
             {R"({"aperture_radius": "wide"})", {"/camera/aperture_radius", "expected a number"}},
             {R"({"lens_radius": 0.1, "focus_distance": 0})",
              {"/camera/focus_distance", "out of range", "> 0"}},
             {R"({"focus_distance": -2})", {"/camera/focus_distance", "out of range"}},
             {R"({"focus_distanse": 2})",
              {"/camera/focus_distanse", "unknown key", "did you mean 'focus_distance'?"}},
         }) {
        const std::string msg = error_of([&] { parse_json(bad.camera); });
        INFO(bad.camera << "\n -> " << msg);
        for (const auto& part : bad.parts)
            CHECK(contains(msg, part));
    }
}

TEST_CASE("mitsuba: sensor thinlens gives the lens; perspective ignores its parameters",
          "[scene][mitsuba][parser][lens]") {
    auto num = [](const char* name, const char* value) {
        return std::string("<float name=\"") + name + "\" value=\"" + value + "\"/>";
    };
    const std::string look = R"(<transform name="to_world">)"
                             R"(<lookat origin="0, 0, 6" target="0, 0, 0" up="0, 1, 0"/>)"
                             "</transform>";
    const std::string thin = R"(<sensor type="thinlens">)", end = "</sensor>";
    Scene a = parse_xml(thin + look + num("aperture_radius", "0.2") +
                        num("focus_distance", "4.5") + end);
    CHECK(a.camera.lens_radius == 0.2f);
    CHECK(a.camera.focus_distance == 4.5f);
    for (const auto& w : a.warnings)
        CHECK_FALSE(contains(w, "thinlens"));
    // Mitsuba 3's default focus distance is far_clip (1e4 unless given).
    Scene b = parse_xml(thin + look + num("aperture_radius", "0.1") + end);
    CHECK(b.camera.focus_distance == 1e4f);
    Scene c = parse_xml(thin + look + num("aperture_radius", "0.1") + num("far_clip", "50") + end);
    CHECK(c.camera.focus_distance == 50.0f);
    Scene d = parse_xml(R"(<sensor type="perspective">)" + look + num("aperture_radius", "0.1") +
                        num("focus_distance", "3") + end);
    CHECK(d.camera.lens_radius == 0.0f);
    // A scaled to_world (Mitsuba 3 refuses it): one warning, the lens stays in world units.
    Scene e = parse_xml(thin + R"(<transform name="to_world"><scale value="2"/></transform>)" +
                        num("aperture_radius", "0.1") + num("focus_distance", "3") + end);
    CHECK(e.camera.lens_radius == 0.1f);
    CHECK(e.camera.focus_distance == 3.0f);
    int scale_warnings = 0;
    for (const auto& w : e.warnings)
        scale_warnings += contains(w, "thinlens") && contains(w, "scale");
    CHECK(scale_warnings == 1);

    struct Bad {
        std::string sensor;
        std::vector<std::string> parts;
    };
    for (const Bad& bad : std::vector<Bad>{
             {thin + num("focus_distance", "3") + end, {"lens.xml:3:", "aperture_radius"}},
             {thin + num("aperture_radius", "-1") + end,
              {"lens.xml:3:", "aperture_radius -1", ">= 0"}},
             {thin + num("aperture_radius", "0.1") + num("focus_distance", "0") + end,
              {"lens.xml:3:", "focus_distance 0", "> 0"}},
             {thin + R"(<string name="aperture_radius" value="0.1"/>)" + end,
              {"lens.xml:3:", "aperture_radius", "must be a number"}},
         }) {
        const std::string msg = error_of([&] { parse_xml(bad.sensor); });
        INFO(bad.sensor << "\n -> " << msg);
        for (const auto& part : bad.parts)
            CHECK(contains(msg, part));
    }
}

TEST_CASE("validate: the lens radius is finite and >= 0, the focus distance finite and > 0",
          "[scene][parser][lens]") {
    Scene s;
    s.name = "lens.json";
    s.add_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, s.add_material(Material{}));
    s.camera.lens_radius = 0.1f;
    s.camera.focus_distance = 2.0f;
    CHECK_NOTHROW(validate_scene(s));
    struct Bad {
        float lens, focus;
        const char* part;
    };
    for (Bad bad :
         {Bad{-0.1f, 2.0f, "lens radius -0.1"}, Bad{NAN, 2.0f, "lens radius nan"},
          Bad{INFINITY, 2.0f, "lens radius inf"}, Bad{0.1f, 0.0f, "focus distance 0"},
          Bad{0.0f, -1.0f, "focus distance -1"}, Bad{0.1f, INFINITY, "focus distance inf"}}) {
        s.camera.lens_radius = bad.lens;
        s.camera.focus_distance = bad.focus;
        const std::string msg = error_of([&] { validate_scene(s); });
        INFO(msg);
        CHECK(contains(msg, "scene 'lens.json'"));
        CHECK(contains(msg, bad.part));
        // upload_camera refuses the same camera (it may be handed one directly).
        if (bad.lens != 0.0f) CHECK_THROWS_AS(upload_camera(s.camera, 8, 8, true), Error);
    }
}
