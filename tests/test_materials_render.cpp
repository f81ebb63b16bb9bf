// test_materials_render.cpp — the dielectric and plastic kinds on the device, through the
// whole renderer: a white furnace of each (a plane under a constant sky of radiance 1, one
// bounce, so a pixel's expectation is the material's albedo E(θ) in radiance) against the
// closed forms of the host (the roughplastic's tables go through the material-table buffer),
// and next-event estimation of light transmitted by a rough dielectric (the contract of
// bsdf.h's signed cosine and shade's shadow ray from below the surface) against BSDF
// sampling alone.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>

#include <glm/glm.hpp>

#include "image/stats.h"
#include "materials_support.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/material_tables.h"
#include "scene/upload.h"
#include "support.h"

using namespace wp;

namespace {

constexpr double kPi = 3.14159265358979323846;

void add_quad(Scene& s, glm::vec2 lo, glm::vec2 hi, float z, std::uint32_t material, bool normals = false) {
    std::vector<glm::vec3> n;
    if (normals) n.assign(4, glm::vec3(0, 0, 1));
    s.add_mesh({{lo.x, lo.y, z}, {hi.x, lo.y, z}, {hi.x, hi.y, z}, {lo.x, hi.y, z}}, {{0, 1, 2}, {0, 2, 3}},
               material, n);
}

render::FilmMoments render_moments(const Scene& scene, int w, int h, int spp, int depth,
                                   render::Sampling sampling, std::uint32_t seed) {
    render::RenderSettings s;
    s.width = w;
    s.height = h;
    s.depth = depth;
    s.seed = seed;
    s.variance = true;
    s.estimator.sampling = sampling;
    render::Wavefront wf(test::device(), scene, s);
    render::LoopOptions lo;
    lo.spp = spp;
    render::render_frames(wf, lo, nullptr);
    for (int c : wf.counters()) CHECK(c == 0);
    return wf.moments();
}

double fresnel(double c, double eta) {  // Born & Wolf, eta = η_t / η_i
    double s2 = (1 - c * c) / (eta * eta);
    if (s2 >= 1) return 1.0;
    double t = std::sqrt(1 - s2);
    double rs = (c - eta * t) / (c + eta * t), rp = (eta * c - t) / (eta * c + t);
    return 0.5 * (rs * rs + rp * rp);
}

}  // namespace

TEST_CASE("materials: white furnace of roughdielectric, thindielectric, plastic, roughplastic on the device",
          "[render][stat][materials]") {
    // Four strips of the plane z = 0 side by side along y, seen at 60° from the normal by a
    // narrow camera whose image x runs along +y: strip k fills image columns 8k .. 8k + 7.
    const int w = 32, h = 8, spp = 1024;
    const double theta = 60.0, dist = 10.0;
    const float ior = 1.5f, alpha = 0.3f;
    Scene scene;
    scene.name = "furnace strips";
    scene.background = glm::vec3(1.0f);
    scene.camera.position = glm::vec3(float(dist * std::sin(theta * kPi / 180)), 0.0f,
                                      float(dist * std::cos(theta * kPi / 180)));
    scene.camera.target = glm::vec3(0.0f);
    scene.camera.up = glm::vec3(0, 0, 1);
    scene.camera.vfov_deg = 4.0f;
    Material base;
    base.albedo = glm::vec3(1.0f);
    base.specular = glm::vec3(1.0f);
    base.ior = ior;
    base.alpha = alpha;
    base.separable_g = true;
    const MaterialKind kinds[4] = {MaterialKind::RoughDielectric, MaterialKind::ThinDielectric,
                                   MaterialKind::Plastic, MaterialKind::RoughPlastic};
    CameraData cam = upload_camera(scene.camera, w, h, false);
    double y_edge = dist * 0.5 * double(cam.right.y);  // the column-8 and column-24 boundaries
    const float ys[5] = {-50.0f, float(-y_edge), 0.0f, float(y_edge), 50.0f};
    for (int k = 0; k < 4; ++k) {
        Material m = base;
        m.name = to_string(kinds[k]);
        m.kind = kinds[k];
        add_quad(scene, {-50.0f, ys[k]}, {50.0f, ys[k + 1]}, 0.0f, scene.add_material(m));
    }
    render::FilmMoments mo = render_moments(scene, w, h, spp, 1, render::Sampling::Mis, 9);

    // The closed forms at each pixel's centre direction.
    MaterialTables tables = build_material_tables(scene);
    const float* t = tables.data.data();
    RoughCoat coat = rough_coat(scene.materials[3]);
    double hemi = 0;  // 2 ∫ T(μ) μ dμ of the roughplastic's table
    for (int i = 0; i < 20000; ++i) {
        double mu = (i + 0.5) / 20000;
        double x = mu * (WP_ROUGH_PLASTIC_RES - 1);
        int j = std::min(int(x), WP_ROUGH_PLASTIC_RES - 2);
        hemi += 2 * mu * (t[j] * (1 - (x - j)) + t[j + 1] * (x - j)) / 20000;
    }
    auto lerp_t = [&](double mu) {
        double x = mu * (WP_ROUGH_PLASTIC_RES - 1);
        int j = std::min(int(x), WP_ROUGH_PLASTIC_RES - 2);
        return t[j] * (1 - (x - j)) + t[j + 1] * (x - j);
    };
    double fdr_out = 0;
    for (int i = 0; i < 200000; ++i) fdr_out += fresnel(std::sqrt((i + 0.5) / 200000), ior) / 200000;
    double fdr_in = wp_fresnel_diffuse_reflectance(1.0f / ior);  // the model's own (Mitsuba's fit)
    for (int k = 0; k < 4; ++k) {
        double sum = 0, expect = 0, var = 0;
        int count = 0;
        for (int py = 0; py < h; ++py)
            for (int px = 8 * k + 2; px < 8 * k + 6; ++px) {
                double sx = 2.0 * (px + 0.5) / w - 1.0, sy = 1.0 - 2.0 * (py + 0.5) / h;
                glm::dvec3 dir = glm::dvec3(cam.forward.x, cam.forward.y, cam.forward.z) +
                                 sx * glm::dvec3(cam.right.x, cam.right.y, cam.right.z) +
                                 sy * glm::dvec3(cam.up.x, cam.up.y, cam.up.z);
                dir = glm::normalize(dir);
                glm::dvec3 o(cam.origin.x, cam.origin.y, cam.origin.z);
                glm::dvec3 hit = o + dir * (-o.z / dir.z);
                REQUIRE(hit.y > ys[k] + 0.05);
                REQUIRE(hit.y < ys[k + 1] - 0.05);
                double mu = -dir.z, e = 0;
                switch (k) {
                    case 0:
                        e = rough_interface_reflectance(coat, mu, ior) +
                            rough_interface_transmittance(coat, mu, ior) / (double(ior) * ior);
                        break;
                    case 1: e = 1.0; break;
                    case 2: {
                        double f = fresnel(mu, ior);
                        e = f + (1 - f) * (1 - fdr_out) / (double(ior) * ior * (1 - fdr_in));
                        break;
                    }
                    case 3:
                        e = rough_interface_reflectance(coat, mu, ior) +
                            lerp_t(mu) * hemi / (double(ior) * ior * (1 - t[WP_ROUGH_PLASTIC_RES]));
                        break;
                }
                sum += mo.mean.pixel(px, py)[1];
                var += mo.mean_variance.pixel(px, py)[1];
                expect += e;
                ++count;
            }
        double mean = sum / count, ex = expect / count, se = std::sqrt(var) / count;
        INFO(to_string(kinds[k]) << ": rendered " << mean << " ± " << se << ", expected " << ex);
        std::printf("device white furnace at 60°: %s rendered %.4f ± %.4f, expected %.4f\n",
                    to_string(kinds[k]), mean, se, ex);
        if (k == 1)
            CHECK(std::abs(mean - 1.0) < 1e-5);  // every weight is exactly 1
        else
            CHECK(std::abs(mean - ex) < 5 * se + 1e-3);
    }
}

TEST_CASE("materials: light through a rough dielectric, NEE and MIS agree with BSDF sampling (z-test)",
          "[render][stat][materials]") {
    // A rough glass plane at z = 0 (front +z) and a small light at z = -1 facing up: the camera
    // above sees the light only through the glass, so next-event estimation evaluates the
    // transmission lobe and traces its shadow ray from below the surface.
    for (bool normals : {false, true}) {
        Scene scene;
        scene.name = "light under rough glass";
        scene.camera.position = glm::vec3(0.2f, 0.1f, 3.0f);
        scene.camera.target = glm::vec3(0.0f);
        scene.camera.up = glm::vec3(0, 1, 0);
        scene.camera.vfov_deg = 30.0f;
        Material glass;
        glass.name = "rough glass";
        glass.kind = MaterialKind::RoughDielectric;
        glass.albedo = glm::vec3(0.9f, 0.8f, 0.7f);
        glass.ior = 1.5f;
        glass.alpha = 0.3f;
        Material light;
        light.name = "light";
        light.albedo = glm::vec3(0.0f);
        light.emission = glm::vec3(2.0f);
        add_quad(scene, {-3, -3}, {3, 3}, 0.0f, scene.add_material(glass), normals);
        add_quad(scene, {-1.2f, -1.0f}, {1.0f, 1.3f}, -1.0f, scene.add_material(light));
        const int w = 24, h = 24;
        render::FilmMoments ref = render_moments(scene, w, h, 2048, 2, render::Sampling::Cosine, 1);
        for (render::Sampling s : {render::Sampling::Mis, render::Sampling::Nee}) {
            if (normals && s == render::Sampling::Nee) continue;
            // Light sampling alone is noisy where the transmission lobe is narrower than the
            // light: more samples.
            render::FilmMoments a = render_moments(scene, w, h, s == render::Sampling::Nee ? 4096 : 256, 2, s, 2);
            ZTest z = z_test(a.mean, ref.mean, &a.mean_variance, &ref.mean_variance);
            double sum_a = 0, sum_r = 0;
            for (std::size_t i = 0; i < a.mean.rgb.size(); ++i) {
                sum_a += a.mean.rgb[i];
                sum_r += ref.mean.rgb[i];
            }
            INFO((normals ? "with" : "without") << " shading normals, " << render::sampling_name(s) << ": "
                                                << z.passed << " of " << z.pixels << " pixels pass, max |z| "
                                                << z.max_abs_z << "; image sums " << sum_a << " / " << sum_r);
            CHECK(sum_r > 1.0);  // the light is seen through the glass
            CHECK(z.pass_fraction >= 0.9975);
            CHECK(std::abs(sum_a - sum_r) < 0.02 * sum_r);
        }
    }
}
