#include "scene/validate.h"

#include <cmath>

#include <fmt/format.h>

#include "util/error.h"

namespace wp {

namespace {

bool finite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

} // namespace

void validate_scene(const Scene& scene) {
    const std::string& name = scene.name.empty() ? std::string("(unnamed)") : scene.name;

    // Geometry: at least one triangle, indices in range, finite positions
    if (scene.triangles.empty()) fail("scene '{}': no triangles", name);
    const std::size_t nv = scene.positions.size();
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
        const glm::uvec3& t = scene.triangles[i];
        for (int k = 0; k < 3; ++k)
            if (t[k] >= nv)
                fail("scene '{}': triangle {} uses vertex {}, but there are only {} vertices", name,
                     i, t[k], nv);
    }
    for (std::size_t i = 0; i < nv; ++i) {
        const glm::vec3& p = scene.positions[i];
        if (!finite(p))
            fail("scene '{}': vertex {} has a non-finite position ({}, {}, {})", name, i, p.x, p.y,
                 p.z);
    }

    // Materials: one id per triangle, each in range, each material physically sane
    if (scene.material_ids.size() != scene.triangles.size())
        fail("scene '{}': {} material ids for {} triangles", name, scene.material_ids.size(),
             scene.triangles.size());
    for (std::size_t i = 0; i < scene.material_ids.size(); ++i)
        if (scene.material_ids[i] >= scene.materials.size())
            fail("scene '{}': triangle {} uses material {}, but there are only {} materials", name,
                 i, scene.material_ids[i], scene.materials.size());
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        const glm::vec3 a = m.albedo, e = m.emission;
        if (!finite(a) || glm::any(glm::lessThan(a, glm::vec3(0.0f))) ||
            glm::any(glm::greaterThan(a, glm::vec3(1.0f))))
            fail("scene '{}': material {} ('{}') has albedo ({}, {}, {}) outside [0, 1]", name, i,
                 m.name, a.x, a.y, a.z);
        if (!finite(e) || glm::any(glm::lessThan(e, glm::vec3(0.0f))))
            fail("scene '{}': material {} ('{}') has emission ({}, {}, {}), which must be finite "
                 "and >= 0",
                 name, i, m.name, e.x, e.y, e.z);
        if (m.kind == MaterialKind::Glossy && !(m.alpha > 0.0f && m.alpha <= 1.0f))
            fail("scene '{}': material {} ('{}') has roughness alpha {}, which must be in (0, 1]",
                 name, i, m.name, m.alpha);
        // The rough kinds: α (α_u) and α_v in [1e-4, 2] (util/limits.h)
        if (uses_alpha(m.kind) && m.kind != MaterialKind::Glossy)
            for (float a : {m.alpha, m.alpha_v.value_or(m.alpha)})
                if (!(a >= limits::kMinMicrofacetAlpha && a <= limits::kMaxMicrofacetAlpha))
                    fail("scene '{}': material {} ('{}') has roughness alpha {}, which must be in "
                         "[{}, {}]",
                         name, i, m.name, a, limits::kMinMicrofacetAlpha,
                         limits::kMaxMicrofacetAlpha);
    }

    // Camera: a film, a direction, a field of view
    const Camera& c = scene.camera;
    if (c.width <= 0 || c.height <= 0)
        fail("scene '{}': camera film is {} x {} pixels", name, c.width, c.height);
    if (!(c.vfov_deg > 0.0f && c.vfov_deg < 180.0f))
        fail("scene '{}': camera vertical fov {} is not in (0, 180) degrees", name, c.vfov_deg);
    if (!finite(c.position) || !finite(c.target) || !finite(c.up))
        fail("scene '{}': camera position, target or up is not finite", name);
    const glm::vec3 dir = c.target - c.position;
    if (glm::dot(dir, dir) == 0.0f) fail("scene '{}': camera target equals its position", name);
    const glm::vec3 side = glm::cross(dir, c.up);
    if (glm::dot(side, side) == 0.0f)
        fail("scene '{}': camera up vector is zero or parallel to the view direction", name);
    if (!(std::isfinite(c.lens_radius) && c.lens_radius >= 0.0f))
        fail("scene '{}': camera lens radius {} must be finite and >= 0 (0: pinhole)", name,
             c.lens_radius);
    if (!(std::isfinite(c.focus_distance) && c.focus_distance > 0.0f))
        fail("scene '{}': camera focus distance {} must be finite and > 0", name, c.focus_distance);
}

bool has_light(const Scene& scene) {
    if (glm::any(glm::greaterThan(scene.background, glm::vec3(0.0f)))) return true;
    if (scene.environment && scene.environment->image >= 0 && scene.environment->scale > 0.0f) return true;
    for (std::uint32_t id : scene.material_ids)
        if (id < scene.materials.size() && scene.materials[id].emissive()) return true;
    return false;
}

std::string no_light_warning(const std::string& source) {
    return fmt::format(
        "{}: no light: no triangle emits (no material with emission is used), there is no "
        "environment map and the background is black, so the image will be black",
        source);
}

} // namespace wp
