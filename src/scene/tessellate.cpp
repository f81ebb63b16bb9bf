#include "scene/tessellate.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "scene/procedural.h"
#include "scene/shape_uv.h"

namespace wp {

namespace {

constexpr double kPi = std::numbers::pi;

// The unit icosphere with the area-preserving radius, tessellated once.
const Mesh& unit_sphere() {
    static const Mesh sphere = [] {
        Mesh s = make_icosphere(glm::vec3(0.0f), 1.0f, kSphereSubdivisions);
        double area = 0.0;
        for (const auto& t : s.triangles) {
            glm::dvec3 a(s.positions[t.x]), b(s.positions[t.y]), c(s.positions[t.z]);
            area += 0.5 * glm::length(glm::cross(b - a, c - a));
        }
        const float k = float(std::sqrt(4.0 * kPi / area));  // area-preserving radius
        for (auto& p : s.positions) p *= k;
        return s;
    }();
    return sphere;
}

}  // namespace

TessellatedShape tessellated_sphere(bool with_uvs) {
    const Mesh& unit = unit_sphere();
    TessellatedShape g;
    g.positions = unit.positions;
    g.triangles = unit.triangles;
    for (const auto& p : g.positions) g.normals.push_back(glm::normalize(p));
    if (with_uvs)
        wrap_uvs(
            g.positions, g.triangles, g.normals, g.uvs,
            [](glm::vec3 p) {
                double phi = std::atan2(double(p.y), double(p.x));
                if (phi < 0.0) phi += 2.0 * kPi;
                const double theta =
                    std::acos(std::clamp(double(p.z) / glm::length(glm::dvec3(p)), -1.0, 1.0));
                return glm::vec2(float(phi / (2.0 * kPi)), float(theta / kPi));
            },
            [](glm::vec3 p) { return p.x == 0.0f && p.y == 0.0f; });
    return g;
}

}  // namespace wp
