#include "scene/builtin.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/procedural.h"
#include "util/error.h"
#include "util/limits.h"

namespace wp {

namespace {

// rings x segments of a UV sphere with 2 * segments * (rings - 1) as close to `budget` as
// possible, keeping segments about twice rings (cells roughly square).
void sphere_resolution(int budget, int& rings, int& segments) {
    const int r0 = std::max(3, int(std::lround(std::sqrt(budget / 4.0))));
    rings = 3;
    segments = 6;
    long best = -1;
    for (int r = std::max(3, r0 / 2); r <= 2 * r0; ++r) {
        int s = std::max(3, int(std::lround(budget / (2.0 * (r - 1)))));
        if (2 * s < 3 * r || 2 * s > 5 * r) continue; // keep s / r in [1.5, 2.5]
        long err = std::labs(long(2) * s * (r - 1) - budget) * 1000 + std::labs(s - 2 * r);
        if (best < 0 || err < best) {
            best = err;
            rings = r;
            segments = s;
        }
    }
}

} // namespace

Scene make_cornell_box(int object_triangles) {
    if (object_triangles < 0) fail("make_cornell_box: object_triangles must be >= 0");
    Scene s;
    s.name = "cornell-box";
    s.background = glm::vec3(0.0f);

    // Materials: the classic box's albedos and light
    auto diffuse = [&](const char* name, glm::vec3 albedo) {
        Material m;
        m.name = name;
        m.kind = MaterialKind::Diffuse;
        m.albedo = albedo;
        return s.add_material(m);
    };
    const std::uint32_t white = diffuse("white", {0.725f, 0.71f, 0.68f});
    const std::uint32_t red = diffuse("red", {0.63f, 0.065f, 0.05f});
    const std::uint32_t green = diffuse("green", {0.14f, 0.45f, 0.091f});
    Material light_m;
    light_m.name = "light";
    light_m.albedo = glm::vec3(0.0f);
    light_m.emission = glm::vec3(17.0f, 12.0f, 4.0f);
    const std::uint32_t light = s.add_material(light_m);
    Material mirror_m;
    mirror_m.name = "mirror";
    mirror_m.kind = MaterialKind::Mirror;
    mirror_m.albedo = glm::vec3(0.9f);
    const std::uint32_t mirror = s.add_material(mirror_m);
    Material glossy_m;
    glossy_m.name = "glossy";
    glossy_m.kind = MaterialKind::Glossy;
    glossy_m.albedo = glm::vec3(0.725f, 0.71f, 0.68f);
    glossy_m.alpha = phong_exponent_to_alpha(100.0f);  // the original scene's exponent 100
    const std::uint32_t glossy = s.add_material(glossy_m);

    // Walls, one quad each, normals (cross(u, v)) pointing into the box
    auto add = [&](const Mesh& m, std::uint32_t mat) { s.add_mesh(m.positions, m.triangles, mat); };
    const glm::vec3 ex(1, 0, 0), ey(0, 1, 0), ez(0, 0, 1);
    add(make_quad({-1, 0, -1}, 2.0f * ez, 2.0f * ex), white); // floor, +y
    add(make_quad({-1, 2, -1}, 2.0f * ex, 2.0f * ez), white); // ceiling, -y
    add(make_quad({-1, 0, -1}, 2.0f * ex, 2.0f * ey), white); // back wall, +z
    add(make_quad({-1, 0, -1}, 2.0f * ey, 2.0f * ez), red);   // left wall, +x
    add(make_quad({1, 0, -1}, 2.0f * ez, 2.0f * ey), green);  // right wall, -x

    // Light: Bitterli's quad, 2 cm under the ceiling, facing down (cross(x, z) = -y)
    add(make_quad({-0.24f, 1.98f, -0.22f}, 0.47f * ex, 0.38f * ez), light);

    // Objects: about a quarter of the budget to the glossy box, the rest to the sphere
    const int n = std::max(1, int(std::lround(std::sqrt(object_triangles / 48.0))));
    int rings = 0, segments = 0;
    sphere_resolution(std::max(12, object_triangles - 12 * n * n), rings, segments);

    // Glossy tall box: 0.6 x 1.2 x 0.6 on the floor at back left, turned 17 degrees
    glm::mat4 box_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(-0.33f, 0.0f, -0.32f)) *
                             glm::rotate(glm::mat4(1.0f), glm::radians(17.0f), ey);
    add(transform(make_box({-0.3f, 0.0f, -0.3f}, {0.3f, 1.2f, 0.3f}, n), box_to_world), glossy);

    // Mirror sphere: radius 0.4, resting 1 mm above the floor at front right, with its
    // analytic normals (the walls and the box get zero normals: they shade flat)
    const glm::vec3 sphere_center(0.42f, 0.401f, 0.3f);
    const Mesh sphere = make_uv_sphere(sphere_center, 0.4f, rings, segments);
    s.add_mesh(sphere.positions, sphere.triangles, mirror,
               sphere_normals(sphere.positions, sphere_center));

    // Camera: the front opening (y in [0, 2] at z = 1) fills the frame height
    s.camera.position = glm::vec3(0.0f, 1.0f, 3.9f);
    s.camera.target = glm::vec3(0.0f, 1.0f, 0.0f);
    s.camera.up = ey;
    s.camera.vfov_deg = 40.0f;
    s.camera.width = limits::kDefaultWidth;  // the original program's 800 x 600
    s.camera.height = limits::kDefaultHeight;
    return s;
}

Scene make_closed_box_furnace(float emission, float albedo) {
    if (!(emission >= 0.0f) || !std::isfinite(emission))
        fail("make_closed_box_furnace: emission must be finite and >= 0, got {}", emission);
    if (!(albedo >= 0.0f && albedo <= 1.0f))
        fail("make_closed_box_furnace: albedo must be in [0, 1], got {}", albedo);
    Scene s;
    s.name = "closed-box-furnace";
    Material m;
    m.name = "furnace-wall";
    m.kind = MaterialKind::Diffuse;
    m.albedo = glm::vec3(albedo);
    m.emission = glm::vec3(emission);
    const std::uint32_t wall = s.add_material(m);

    // The cube seen from inside: outward winding flipped so every wall faces in
    Mesh box = make_box(glm::vec3(-1.0f), glm::vec3(1.0f), 4);
    flip_winding(box);
    s.add_mesh(box.positions, box.triangles, wall);

    // Camera inside, off-centre, looking at a corner
    s.camera.position = glm::vec3(0.1f, -0.05f, 0.2f);
    s.camera.target = glm::vec3(-1.0f, -1.0f, -1.0f);
    s.camera.up = glm::vec3(0.0f, 1.0f, 0.0f);
    s.camera.vfov_deg = 40.0f;
    s.camera.width = 64;
    s.camera.height = 48;
    s.background = glm::vec3(0.0f);
    return s;
}

Scene make_veach_plates() {
    Scene s;
    s.name = "veach-plates";
    s.background = glm::vec3(0.0f);
    const glm::vec3 ex(1, 0, 0), ey(0, 1, 0), ez(0, 0, 1);
    s.camera.position = glm::vec3(0.0f, 2.0f, 7.0f);
    s.camera.target = glm::vec3(0.0f, 0.6f, 0.0f);
    s.camera.up = ey;
    s.camera.vfov_deg = 35.0f;
    s.camera.width = 768;
    s.camera.height = 512;
    auto add = [&](const Mesh& m, std::uint32_t mat) { s.add_mesh(m.positions, m.triangles, mat); };

    // Floor: dark diffuse, facing up
    Material floor_m;
    floor_m.name = "floor";
    floor_m.albedo = glm::vec3(0.2f);
    add(make_quad({-10, -0.6f, -10}, 15.0f * ez, 20.0f * ex), s.add_material(floor_m));

    // Plates: each tilted to mirror the point `aim` towards the camera
    const glm::vec3 aim(0.0f, 3.0f, -3.0f);
    const float alphas[4] = {0.30f, 0.15f, 0.07f, 0.02f};
    for (int k = 0; k < 4; ++k) {
        glm::vec3 c(0.0f, 0.35f * k, 1.6f - 1.0f * k);
        glm::vec3 n = glm::normalize(glm::normalize(s.camera.position - c) + glm::normalize(aim - c));
        glm::vec3 eu = 6.0f * ex, ev = 0.8f * glm::normalize(glm::cross(n, ex));
        Material m;
        m.name = "plate-" + std::to_string(k);
        m.kind = MaterialKind::Glossy;
        m.albedo = glm::vec3(0.7f);
        m.alpha = alphas[k];
        add(make_quad(c - 0.5f * eu - 0.5f * ev, eu, ev), s.add_material(m));
    }

    // Lights: equal power, radiance ∝ 1 / r²
    const float radii[4] = {0.03f, 0.1f, 0.3f, 0.9f};
    const glm::vec3 tint[4] = {{1.0f, 0.85f, 0.7f}, {0.7f, 1.0f, 0.8f}, {0.7f, 0.8f, 1.0f}, {1.0f, 0.7f, 0.9f}};
    for (int k = 0; k < 4; ++k) {
        Material m;
        m.name = "light-" + std::to_string(k);
        m.albedo = glm::vec3(0.0f);
        m.emission = tint[k] * (0.2f / (radii[k] * radii[k]));
        add(make_uv_sphere({-2.25f + 1.5f * k, 3.0f, -3.0f}, radii[k], 12, 24), s.add_material(m));
    }
    return s;
}

} // namespace wp
