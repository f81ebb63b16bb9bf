// scene.h — the host's scene: triangles, materials, camera, background.
//
// Plain data (yocto-gl style): one indexed triangle mesh for the whole scene, a material
// id per triangle, and a pinhole camera. Loaders and procedural generators fill it;
// scene/upload converts it into the device layout. Nothing here knows about OpenCL.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/aabb.h"

namespace wp {

enum class MaterialKind : std::uint32_t {
    Diffuse = 0,  // Lambertian, albedo
    Mirror = 1,   // perfect specular reflection, tinted by albedo
    Glossy = 2,   // the original "weighted" lobe around the mirror direction (Phong exponent)
    Glass = 3,    // smooth dielectric: exact Fresnel reflection and refraction, tinted by albedo
};

const char* to_string(MaterialKind k);

struct Material {
    std::string name;
    MaterialKind kind = MaterialKind::Diffuse;
    glm::vec3 albedo{0.8f};    // reflectance in [0, 1] per channel
    glm::vec3 emission{0.0f};  // emitted radiance (W sr^-1 m^-2), front side only
    float exponent = 100.0f;   // glossy lobe sharpness (Phong exponent), Glossy only
    float ior = 1.5f;          // index of refraction inside / outside (front side), Glass only
    bool emissive() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
};

struct Camera {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float vfov_deg = 40.0f;  // vertical field of view
    int width = 800;
    int height = 600;
};

struct Scene {
    std::string name;                   // for reports: file name or "cornell-box"
    std::vector<glm::vec3> positions;   // vertex positions (world units)
    std::vector<glm::uvec3> triangles;  // vertex indices, counter-clockwise = front
    std::vector<std::uint32_t> material_ids;  // one per triangle
    std::vector<Material> materials;
    Camera camera;
    glm::vec3 background{0.0f};  // radiance of rays that leave the scene
    // Non-fatal problems met while building or loading the scene (e.g. triangles without a
    // material), one line each, for the caller to print; empty when all went well.
    std::vector<std::string> warnings;

    std::size_t triangle_count() const { return triangles.size(); }
    Aabb bounds() const;
    // Appends a mesh with one material; returns the first new triangle's index.
    std::size_t add_mesh(const std::vector<glm::vec3>& pos, const std::vector<glm::uvec3>& tris,
                         std::uint32_t material);
    std::uint32_t add_material(const Material& m);
};

}  // namespace wp
