// scene.h — the host's scene: triangles, materials, camera, background.
//
// Plain data (yocto-gl style): one indexed triangle mesh for the whole scene, a material
// id per triangle, and a pinhole camera. Loaders and procedural generators fill it;
// scene/upload converts it into the device layout. Nothing here knows about OpenCL.
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "bvh/aabb.h"
#include "shared/material_kinds.h"
#include "util/limits.h"

namespace wp {

// One enumerator per line of kernels/shared/material_kinds.h, same numbering as the device.
enum class MaterialKind : std::uint32_t {
#define WP_KIND_ENUM_(KIND, Kind, name, specular, alpha, ior) Kind = WP_MATERIAL_##KIND,
    WP_MATERIAL_KINDS(WP_KIND_ENUM_)
#undef WP_KIND_ENUM_
};
constexpr int kMaterialKindCount = WP_MATERIAL_KIND_COUNT;

// The kind's name in scene files and reports ("diffuse", ...); "unknown" out of range.
const char* to_string(MaterialKind k);
// The kind named `name` (as to_string), if any.
std::optional<MaterialKind> material_kind_from_string(std::string_view name);
// The columns of material_kinds.h: Dirac lobes only; reads Material::alpha; reads ::ior.
bool is_specular(MaterialKind k);
bool uses_alpha(MaterialKind k);
bool uses_ior(MaterialKind k);

// GGX roughness α of a Phong exponent e >= 0 given by a scene (OBJ Ns, JSON "exponent",
// the built-in scenes): α = sqrt(2 / (e + 2)) (Walter et al. 2007, section 5.2), in float
// exactly as the device computed it before materials stored α (so such scenes render the
// same bits). The one host conversion; the device's inverse is materials/glossy.h.
inline float phong_exponent_to_alpha(float e) { return std::sqrt(2.0f / (e + 2.0f)); }

// A material as the user gave it; scene/upload turns it into MaterialData, keeping only
// the parameters its kind reads (material_kinds.h).
struct Material {
    std::string name;
    MaterialKind kind = MaterialKind::Diffuse;
    glm::vec3 albedo{0.8f};    // reflectance in [0, 1] per channel
    glm::vec3 emission{0.0f};  // emitted radiance (W sr^-1 m^-2), front side only
    // GGX roughness α in (0, 1] (kinds with ALPHA: glossy); default: Phong exponent 100.
    float alpha = phong_exponent_to_alpha(100.0f);
    float ior = 1.5f;          // index of refraction inside / outside (front side), Glass only
    bool emissive() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
};

struct Camera {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float vfov_deg = 40.0f;  // vertical field of view
    int width = limits::kDefaultWidth;
    int height = limits::kDefaultHeight;
};

// Render settings a scene file may carry (JSON "render", Mitsuba integrator/sampler);
// command-line options override them; unset ones fall back to the program's defaults.
struct RenderDefaults {
    std::optional<int> spp;
    std::optional<int> depth;  // bounces, as --depth
    std::optional<std::uint32_t> seed;
};

struct Scene {
    std::string name;                   // for reports: file name or "cornell-box"
    std::vector<glm::vec3> positions;   // vertex positions (world units)
    std::vector<glm::uvec3> triangles;  // vertex indices, counter-clockwise = front
    std::vector<std::uint32_t> material_ids;  // one per triangle
    std::vector<Material> materials;
    Camera camera;
    glm::vec3 background{0.0f};  // radiance of rays that leave the scene
    RenderDefaults render;       // settings from the scene file, if any
    // Non-fatal problems met while building or loading the scene (e.g. triangles without a
    // material), one line each, for the caller to print; empty when all went well.
    std::vector<std::string> warnings;

    std::size_t triangle_count() const { return triangles.size(); }
    Aabb bounds() const;
    // Appends a mesh with one material; returns the first new triangle's index.
    std::size_t add_mesh(const std::vector<glm::vec3>& pos, const std::vector<glm::uvec3>& tris,
                         std::uint32_t material);
    std::uint32_t add_material(const Material& m);
    // Appends every triangle of `src` with its positions transformed as points by
    // `to_world` (a mirroring transform also reverses the winding, so the front stays the
    // front). Materials: `material` when given, else src's own materials (appended, ids
    // remapped). src's warnings are appended too; its camera and background are ignored.
    void append(const Scene& src, const glm::mat4& to_world,
                std::optional<std::uint32_t> material = std::nullopt);
};

// Camera from a camera-to-world matrix whose columns are the camera's axes: column 2 the
// viewing direction, column 1 up, column 3 the position (wavepath's and Mitsuba's
// convention; Mitsuba's column 0 points to the image's left, which a look-at camera implies).
Camera camera_from_matrix(const glm::mat4& to_world, float vfov_deg, int width, int height);

// The default camera of files without one: 800 x 600, 40 degrees vertical fov, up +y,
// looking from +z at the centre of the box, far enough for its bounding sphere to fit.
// Throws wp::Error naming `source` (the file) when the bounds are too large to frame (the
// distance or the position overflows a float).
Camera frame_bounds(const Aabb& b, const std::string& source = {});

// The vertical field of view for a horizontal one on a width x height film.
float vfov_from_hfov(float hfov_deg, int width, int height);

}  // namespace wp
