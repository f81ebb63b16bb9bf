#include "scene/scene.h"

#include "util/error.h"

namespace wp {

const char* to_string(MaterialKind k) {
    switch (k) {
    case MaterialKind::Diffuse: return "diffuse";
    case MaterialKind::Mirror: return "mirror";
    case MaterialKind::Glossy: return "glossy";
    case MaterialKind::Glass: return "glass";
    }
    return "unknown";
}

Aabb Scene::bounds() const {
    Aabb b;
    for (const auto& t : triangles)
        for (int k = 0; k < 3; ++k) b.grow(positions[t[k]]);
    return b;
}

std::size_t Scene::add_mesh(const std::vector<glm::vec3>& pos, const std::vector<glm::uvec3>& tris,
                            std::uint32_t material) {
    if (material >= materials.size()) fail("add_mesh: material {} does not exist", material);
    auto base = static_cast<std::uint32_t>(positions.size());
    std::size_t first = triangles.size();
    positions.insert(positions.end(), pos.begin(), pos.end());
    for (const auto& t : tris) {
        triangles.push_back(t + glm::uvec3(base));
        material_ids.push_back(material);
    }
    return first;
}

std::uint32_t Scene::add_material(const Material& m) {
    materials.push_back(m);
    return static_cast<std::uint32_t>(materials.size() - 1);
}

}  // namespace wp
