// test_appearance.cpp — issue 13 in the stages: shading normals and their failure modes,
// textures, alpha cut-outs and the environment light, each against an independent answer
// (closed forms, geometric facts, or a second scene that must give the same bits).
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "render/kernel_config.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "scene/procedural.h"
#include "scene/texture.h"
#include "shared/shading.h"
#include "support.h"

using namespace wp;

namespace {

struct Rendered {
    Image image;
    std::array<int, WP_COUNTER_COUNT> counters;
    std::string options;
};

Rendered render_image(const Scene& scene, int w, int h, int spp, int depth, std::uint32_t seed = 7,
                render::Sampling sampling = render::Sampling::Mis) {
    render::RenderSettings s;
    s.width = w;
    s.height = h;
    s.depth = depth;
    s.seed = seed;
    s.estimator.sampling = sampling;
    render::Wavefront wf(test::device(), scene, s);
    render::LoopOptions lo;
    lo.spp = spp;
    render::render_frames(wf, lo, nullptr);
    return {wf.resolve(), wf.counters(), wf.options()};
}

// A float texture of w x h texels of one colour.
Texture constant_texture(int w, int h, glm::vec3 c) {
    Texture t;
    t.source = "constant";
    t.width = w;
    t.height = h;
    for (int i = 0; i < w * h; ++i) t.texelsf.insert(t.texelsf.end(), {c.x, c.y, c.z, 1.0f});
    return t;
}

// A scene with a camera looking down -z at the origin and a constant environment of
// radiance L (through an environment map, not the background).
Scene env_scene(float L) {
    Scene s;
    s.name = "env-test";
    s.camera.position = {0.0f, 0.0f, 4.0f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.vfov_deg = 40.0f;
    s.textures.push_back(constant_texture(8, 4, glm::vec3(L)));
    Environment e;
    e.image = 0;
    s.environment = e;
    return s;
}

void add(Scene& s, const Mesh& m, std::uint32_t mat, bool normals_from_center = false,
         glm::vec3 c = glm::vec3(0.0f)) {
    std::vector<glm::vec3> n;
    if (normals_from_center)
        for (const glm::vec3& p : m.positions) n.push_back(glm::normalize(p - c));
    s.add_mesh(m.positions, m.triangles, mat, n);
}

std::array<double, 2> mean_se(const std::vector<double>& v) {
    double sum = 0, sum2 = 0;
    for (double x : v) sum += x, sum2 += x * x;
    double n = double(v.size()), mean = sum / n;
    double var = std::max(0.0, (sum2 - n * mean * mean) / (n - 1));
    return {mean, std::sqrt(var / n)};
}

float3 f3(glm::vec3 v) { return make_float3(v.x, v.y, v.z); }
glm::vec3 g3(float3 v) { return {v.x, v.y, v.z}; }

}  // namespace

TEST_CASE("shading: a bent normal mirrors the viewer above the geometric surface",
          "[unit][appearance]") {
    test::Rng rng(11);
    int bent = 0;
    for (int i = 0; i < 20000; ++i) {
        glm::vec3 ng = rng.unit_vector();
        glm::vec3 wo = rng.unit_vector();
        if (glm::dot(wo, ng) < 1e-3f) wo = glm::reflect(wo, ng);  // viewer on ng's side
        if (glm::dot(wo, ng) < 1e-3f) continue;
        glm::vec3 ns = glm::normalize(ng + 1.5f * rng.unit_vector());
        if (glm::dot(ns, ng) <= 0.05f) continue;
        glm::vec3 b = g3(wp_bend_normal(f3(ns), f3(ng), f3(wo)));
        glm::vec3 r = 2.0f * glm::dot(wo, b) * b - wo;  // mirror direction about the result
        INFO("ng " << ng.x << " " << ng.y << " " << ng.z << " wo " << wo.x << " " << wo.y << " " << wo.z);
        CHECK(std::abs(glm::length(b) - 1.0f) < 1e-5f);
        CHECK(glm::dot(wo, b) > 0.0f);             // the viewer sees its front
        CHECK(glm::dot(r, ng) > 0.9f * WP_BEND_EPS);  // failure mode 1 fixed
        glm::vec3 r0 = 2.0f * glm::dot(wo, ns) * ns - wo;
        if (glm::dot(wo, ns) > 0.0f && glm::dot(r0, ng) >= WP_BEND_EPS) {
            CHECK(b == ns);  // already fine: unchanged
        } else {
            ++bent;
            // Bent just enough: the new mirror direction sits at the minimum elevation.
            CHECK(glm::dot(r, ng) == Approx(WP_BEND_EPS).margin(2e-4));
        }
    }
    CHECK(bent > 1000);  // the case was exercised
}

TEST_CASE("shading: the terminator factor is Chiang et al.'s polynomial and 1 without bending",
          "[unit][appearance]") {
    glm::vec3 ng(0, 0, 1);
    // ns = ng: G = 1 -> factor 1 for every light direction above.
    for (float th : {0.1f, 0.7f, 1.4f}) {
        glm::vec3 wi(std::sin(th), 0.0f, std::cos(th));
        CHECK(wp_terminator_factor(f3(ng), f3(ng), f3(wi)) == Approx(1.0f).epsilon(1e-6));
    }
    // A shading normal tilted by 30 degrees towards +x, light at 80 degrees from ng on the
    // +x side: G = cos80 / (cos(80 - 30) cos30), factor = -G³ + G² + G.
    const double a = 30 * M_PI / 180, t = 80 * M_PI / 180;
    glm::vec3 ns(std::sin(a), 0, std::cos(a)), wi(std::sin(t), 0, std::cos(t));
    double g = std::cos(t) / (std::cos(t - a) * std::cos(a));
    double expect = -g * g * g + g * g + g;
    CHECK(wp_terminator_factor(f3(ng), f3(glm::normalize(ns)), f3(wi)) == Approx(expect).epsilon(1e-5));
    CHECK(expect < 0.6);  // a real attenuation at the terminator
}

TEST_CASE("shading: a direction must stay on the geometric side its lobe meant",
          "[unit][appearance]") {
    glm::vec3 ng(0, 0, 1), ns = glm::normalize(glm::vec3(0.5f, 0, 1));
    CHECK(wp_same_side(f3({0, 0, 1}), f3(ns), f3(ng)));        // reflection above: kept
    CHECK(!wp_same_side(f3(glm::normalize(glm::vec3(1, 0, -0.2f))), f3(ns), f3(ng)));  // below ng, above ns
    CHECK(wp_same_side(f3({0, 0, -1}), f3(ns), f3(ng)));       // transmission below: kept
}

TEST_CASE("render: features a scene lacks are not compiled", "[render][appearance]") {
    Scene plain = make_closed_box_furnace(0.5f, 0.5f);
    auto c = render::KernelConfig::from_scene(plain);
    std::string o = c.shade_options() + c.trace_options();
    CHECK(o.find("WP_HAVE_NORMALS") == std::string::npos);
    CHECK(o.find("WP_HAVE_TEXTURES") == std::string::npos);
    CHECK(o.find("WP_HAVE_ENV") == std::string::npos);
    CHECK(o.find("WP_HAVE_ALPHA_MASK") == std::string::npos);
    Scene e = env_scene(1.0f);
    std::uint32_t m = e.add_material(Material{});
    add(e, make_icosphere({0, 0, 0}, 1.0f, 1), m, true);
    auto ce = render::KernelConfig::from_scene(e);
    CHECK(ce.env);
    CHECK(ce.normals);
    CHECK(ce.nee());  // the environment is a light
    CHECK(!ce.textures);
}

// A convex object under a constant environment L: every point sees only the environment,
// so a diffuse surface of albedo ρ returns exactly ρ L, whatever the depth (>= 1). The
// background pixels are L. Flat-shaded, this is the closed form; with smooth normals the
// guards may only lose energy (failure modes 1-3), never add it.
TEST_CASE("render: a diffuse sphere under a constant environment map returns rho L",
          "[render][appearance][env]") {
    const float L = 0.8f, rho = 0.6f;
    for (bool smooth : {false, true})
        for (render::Sampling sampling : {render::Sampling::Mis, render::Sampling::Nee, render::Sampling::Cosine}) {
            Scene s = env_scene(L);
            Material mat;
            mat.albedo = glm::vec3(rho);
            std::uint32_t m = s.add_material(mat);
            add(s, make_icosphere({0, 0, 0}, 1.0f, 3), m, smooth);
            const int w = 48, h = 48;
            Rendered r = render_image(s, w, h, 32, 3, 7, sampling);
            // Classify pixels by a primary ray test against the exact sphere (radius 1):
            // the icosphere lies inside it, so pixels well inside its disc are surface.
            std::vector<double> inside, outside;
            const float tan_half = std::tan(glm::radians(20.0f));
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    float sx = (2.0f * (x + 0.5f) / w - 1.0f) * tan_half;
                    float sy = (1.0f - 2.0f * (y + 0.5f) / h) * tan_half;
                    glm::vec3 d = glm::normalize(glm::vec3(sx, sy, -1.0f));
                    glm::vec3 o(0, 0, 4);
                    float b = glm::dot(o, d), cc = glm::dot(o, o) - 1.0f;
                    float disc = b * b - cc;  // > 0: the ray meets the unit sphere
                    double v = r.image.pixel(x, y)[1];
                    if (disc > 0.12f) inside.push_back(v);
                    if (disc < -0.05f) outside.push_back(v);
                }
            INFO("smooth " << smooth << " sampling " << render::sampling_name(sampling));
            REQUIRE(inside.size() > 300);
            REQUIRE(outside.size() > 300);
            for (double v : outside) REQUIRE(v == Approx(L).epsilon(1e-5));
            auto [mean, se] = mean_se(inside);
            INFO("mean " << mean << " se " << se << " expected " << rho * L);
            if (!smooth) {
                CHECK(std::abs(mean - rho * L) < 4.0 * se + 1e-5);
            } else {
                CHECK(mean < rho * L + 4.0 * se + 1e-5);  // no energy appears
                CHECK(mean > 0.9 * rho * L);              // and little is lost
            }
            CHECK(se < 0.01 * rho * L);
            CHECK(r.counters[WP_COUNTER_SHADE_NONFINITE] == 0);
        }
}

// Inside a closed box no light from outside may arrive, whatever its shading normals say:
// geometric normals decide sides (failure mode 2). The walls' normals are random, many
// pointing out of the box; the environment outside is bright.
TEST_CASE("render: shading normals do not leak light into a closed box", "[render][appearance][env]") {
    Scene s = env_scene(100.0f);
    s.camera.position = {0.0f, 0.0f, 0.5f};
    s.camera.target = {0.0f, 0.0f, -1.0f};
    s.camera.vfov_deg = 90.0f;
    for (MaterialKind k : {MaterialKind::Diffuse, MaterialKind::Glossy, MaterialKind::Mirror}) {
        Scene b = s;
        Material mat;
        mat.kind = k;
        mat.albedo = glm::vec3(0.9f);
        mat.alpha = 0.4f;
        std::uint32_t m = b.add_material(mat);
        Mesh box = make_box({-1, -1, -1}, {1, 1, 1}, 4);
        flip_winding(box);  // fronts face inwards, where the camera is
        std::vector<glm::vec3> n;
        test::Rng rng(5);
        for (std::size_t i = 0; i < box.positions.size(); ++i) n.push_back(rng.unit_vector());
        b.add_mesh(box.positions, box.triangles, m, n);
        Rendered r = render_image(b, 32, 32, 16, 6);
        double maxv = 0;
        for (float v : r.image.rgb) maxv = std::max(maxv, double(v));
        INFO("kind " << to_string(k));
        CHECK(maxv == 0.0);
        CHECK(r.counters[WP_COUNTER_SHADE_NONFINITE] == 0);
    }
}

// A cut-out is not there for any ray: an occluder whose coverage is below the cutoff
// everywhere gives the same image, bit for bit, as the scene without it (its triangles
// are never hit, so no random number changes); one at full coverage gives the same bits as
// the same occluder without a mask.
TEST_CASE("render: alpha cut-outs are invisible to camera, bounce and shadow rays",
          "[render][appearance][alpha]") {
    auto base = [] {
        Scene s;
        s.name = "alpha-test";
        s.camera.position = {0.0f, 2.0f, 3.0f};
        s.camera.target = {0.0f, 0.0f, 0.0f};
        Material floor;
        floor.albedo = glm::vec3(0.7f);
        std::uint32_t fm = s.add_material(floor);
        Mesh f = make_quad({-2, 0, 2}, {4, 0, 0}, {0, 0, -4});
        s.add_mesh(f.positions, f.triangles, fm);
        Material light;
        light.emission = glm::vec3(5.0f);
        std::uint32_t lm = s.add_material(light);
        Mesh l = make_quad({-0.5f, 2.0f, -0.5f}, {1, 0, 0}, {0, 0, 1});  // normal x cross z = -y: faces down
        s.add_mesh(l.positions, l.triangles, lm);
        return s;
    };
    auto with_blocker = [&](float coverage, bool masked) {
        Scene s = base();
        Material b;
        b.albedo = glm::vec3(0.5f, 0.2f, 0.1f);
        if (masked) {
            s.textures.push_back(constant_texture(4, 4, glm::vec3(1.0f)));
            for (std::size_t i = 3; i < s.textures.back().texelsf.size(); i += 4)
                s.textures.back().texelsf[i] = coverage;
            b.alpha_map.image = 0;
        }
        std::uint32_t bm = s.add_material(b);
        // Between the light and the floor, and in the camera's view; both sides hit.
        Mesh q = make_quad({-0.8f, 1.0f, -0.8f}, {1.6f, 0, 0}, {0, 0, 1.6f});
        std::vector<glm::vec2> uv;
        for (const glm::vec3& p : q.positions) uv.push_back({p.x, p.z});
        s.add_mesh(q.positions, q.triangles, bm, {}, uv);
        return s;
    };
    const int w = 40, h = 30, spp = 8, depth = 3;
    Rendered none = render_image(base(), w, h, spp, depth);
    Rendered cut = render_image(with_blocker(0.2f, true), w, h, spp, depth);
    Rendered opaque_masked = render_image(with_blocker(0.9f, true), w, h, spp, depth);
    Rendered opaque = render_image(with_blocker(0.0f, false), w, h, spp, depth);
    CHECK(cut.options.find("WP_HAVE_TEXTURES") != std::string::npos);
    CHECK(cut.image.rgb == none.image.rgb);
    CHECK(opaque_masked.image.rgb == opaque.image.rgb);
    CHECK(opaque.image.rgb != none.image.rgb);  // the occluder matters when it is there
}

// A textured, diffuse quad filling the view under a constant white background, depth 1:
// each pixel's expectation is the filtered albedo texture times the background. The
// texture has a marker in its top-left texel (uv (0, 0) = the image's top-left), which must
// appear at the image's top-left.
TEST_CASE("render: an albedo texture multiplies the albedo, top-left at uv (0, 0)",
          "[render][appearance][texture]") {
    Scene s;
    s.name = "texture-test";
    s.camera.position = {0.0f, 0.0f, 1.0f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    s.camera.vfov_deg = 2.0f * glm::degrees(std::atan(0.5f));  // the view is the unit quad
    s.background = glm::vec3(1.0f);
    Texture t = constant_texture(4, 4, glm::vec3(0.5f));
    t.nearest = true;
    t.texelsf[0] = 1.0f, t.texelsf[1] = 0.0f, t.texelsf[2] = 0.0f;  // texel (0, 0): red
    s.textures.push_back(t);
    Material m;
    m.albedo = glm::vec3(1.0f);
    m.albedo_map.image = 0;
    std::uint32_t id = s.add_material(m);
    // Quad [-0.5, 0.5]^2 at z = 0 facing +z; uv (0, 0) at the top-left (-0.5, 0.5).
    std::vector<glm::vec3> p = {{-0.5f, 0.5f, 0}, {0.5f, 0.5f, 0}, {0.5f, -0.5f, 0}, {-0.5f, -0.5f, 0}};
    std::vector<glm::uvec3> tris = {{0, 3, 2}, {0, 2, 1}};
    std::vector<glm::vec2> uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    s.add_mesh(p, tris, id, {}, uv);
    Rendered r = render_image(s, 32, 32, 64, 1, 3, render::Sampling::Cosine);
    // Cosine sampling of a diffuse surface under a constant background: weight = albedo,
    // so every sample is exactly albedo x 1: the image is the texture, no noise.
    auto px = [&](int x, int y, int c) { return r.image.pixel(x, y)[c]; };
    CHECK(px(2, 2, 0) == Approx(1.0f).epsilon(1e-5));   // top-left quarter-texel: red
    CHECK(px(2, 2, 1) == Approx(0.0f).margin(1e-6));
    CHECK(px(29, 2, 0) == Approx(0.5f).epsilon(1e-5));  // top-right: grey
    CHECK(px(2, 29, 0) == Approx(0.5f).epsilon(1e-5));  // bottom-left: grey
    CHECK(px(29, 29, 1) == Approx(0.5f).epsilon(1e-5));
}

// One file used with two filters (Mitsuba bitmaps, JSON textures): the filter is the use's,
// so the second use gets its own copy and the first keeps its filter.
TEST_CASE("texture: one image used with both filters keeps each use's filter", "[unit][appearance]") {
    Scene s;
    s.textures.push_back(constant_texture(2, 2, glm::vec3(0.5f)));
    int nearest = texture_with_filter(s, 0, true);
    CHECK(nearest != 0);
    CHECK(s.textures[0].nearest == false);
    CHECK(s.textures[std::size_t(nearest)].nearest == true);
    CHECK(texture_with_filter(s, 0, true) == nearest);  // reused, not copied again
    CHECK(texture_with_filter(s, 0, false) == 0);
    CHECK(s.textures.size() == 2);
}
