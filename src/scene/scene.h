// scene.h — the host's scene: triangles, materials, camera, background.
//
// Plain data (yocto-gl style): one indexed triangle mesh for the whole scene, a material
// id per triangle, and a pinhole camera. Loaders and procedural generators fill it;
// scene/upload converts it into the device layout. Nothing here knows about OpenCL.
#pragma once

#include <array>
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
#define WP_KIND_ENUM_(KIND, Kind, name, specular, alpha, ior, etak) Kind = WP_MATERIAL_##KIND,
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
bool uses_eta_k(MaterialKind k);  // reads Material::eta and ::k (conductors)

// The microfacet distribution of the rough kinds (kernels/shared/microfacet.h).
enum class MicrofacetModel : std::uint32_t { GGX, Beckmann };

// GGX roughness α of a Phong exponent e >= 0 given by a scene (OBJ Ns, JSON "exponent",
// the built-in scenes): α = sqrt(2 / (e + 2)) (Walter et al. 2007, section 5.2), in float
// exactly as the device computed it before materials stored α (so such scenes render the
// same bits). The one host conversion; the device's inverse is materials/glossy.h.
inline float phong_exponent_to_alpha(float e) { return std::sqrt(2.0f / (e + 2.0f)); }

// A texture image (also an environment map): RGBA texels, row 0 at the top.
// Loaders fill it through scene/texture.h (OpenImageIO) or procedurally; scene/upload turns
// it into mip levels on the device (kernels/shared/texture.h).
struct Texture {
    std::string source;  // the file (or procedural name) it came from, for messages
    int width = 0, height = 0;
    // Exactly one of the two is filled, width * height * 4 values:
    std::vector<std::uint8_t> texels8;  // 8-bit RGBA (PNG, JPEG, TGA, ...)
    std::vector<float> texelsf;         // float RGBA (EXR, HDR), linear, as in the file
    bool srgb = false;      // texels8 are sRGB-encoded (decoded to linear before filtering)
    bool nearest = false;   // nearest-texel lookups, no mip maps (Mitsuba filter_type
                            // "nearest", checkerboards); else bilinear with mip maps
    bool is_float() const { return !texelsf.empty(); }
};

// A texture as a material slot uses it: an image and an affine map of the surface's uv
// (KHR_texture_transform, Mitsuba to_uv) applied as uv' = uv_transform * (u, v, 1).
// uv convention everywhere in wavepath: (0, 0) is the image's top-left corner, u to the
// right, v down (glTF's and Mitsuba 3's); loaders of v-up formats (OBJ, PLY) store 1 - v.
// Repeat wrapping in both directions.
struct TextureRef {
    int image = -1;                  // index into Scene::textures; -1: no texture
    glm::mat3 uv_transform{1.0f};    // column-major, last row (0, 0, 1)
    bool used() const { return image >= 0; }
};

// A material as the user gave it; scene/upload turns it into MaterialData, keeping only
// the parameters its kind reads (material_kinds.h).
struct Material {
    std::string name;
    MaterialKind kind = MaterialKind::Diffuse;
    glm::vec3 albedo{0.8f};    // reflectance in [0, 1] per channel
    glm::vec3 emission{0.0f};  // emitted radiance (W sr^-1 m^-2), front side only
    // Microfacet roughness α of the kinds with ALPHA; default: Phong exponent 100. The glossy
    // kind takes α in (0, 1]; the rough kinds (roughconductor, roughdielectric, roughplastic)
    // take α in [1e-4, 2] and read it as α_u (along the frame's x) when alpha_v is set.
    float alpha = phong_exponent_to_alpha(100.0f);
    std::optional<float> alpha_v;  // anisotropic roughness along the frame's y; unset: isotropic
    MicrofacetModel distribution = MicrofacetModel::GGX;  // rough kinds
    // Masking-shadowing of the rough kinds: G1(wo) G1(wi) (Mitsuba 3) when true, else the
    // height-correlated 1 / (1 + Λ(wo) + Λ(wi)) (pbrt-v4, and the glossy kind).
    bool separable_g = false;
    float ior = 1.5f;          // index of refraction inside / outside (front side); kinds with
                               // IOR (glass, the dielectrics, the plastics' coat)
    glm::vec3 specular{1.0f};  // reflection tint of dielectrics and plastics (Mitsuba's
                               // specular_reflectance); albedo is their transmittance /
                               // diffuse reflectance (material_kinds.h)
    // Conductors: complex index of refraction η + i k per channel, relative to the outside;
    // the default (η 0, k 1) reflects everything at every angle (Mitsuba's material "none").
    glm::vec3 eta{0.0f};
    glm::vec3 k{1.0f};
    bool nonlinear = false;    // plastics: Mitsuba's `nonlinear` (internal scattering tints)
    // Textures (kernels/shared/texture.h); each multiplies the constant it names:
    TextureRef albedo_map;     // RGB × albedo (diffuse colour, glossy/mirror F0 or tint)
    TextureRef roughness_map;  // α × G² (glTF metallicRoughness: G is perceptual roughness;
                               // α = (factor · G)², with alpha = factor²); kinds with ALPHA
    TextureRef emission_map;   // RGB × emission (emissive only where emission > 0)
    TextureRef normal_map;     // tangent-space normal, RGB in [0, 1] -> [-1, 1]
                               // (glTF normalTexture, OBJ norm/map_Bump); xy × normal_scale
    float normal_scale = 1.0f;
    // Alpha cut-out (glTF alphaMode MASK, MTL map_d): where the coverage is below
    // alpha_cutoff the surface is not there for any ray. Coverage = A of alpha_map
    // (times alpha_factor), else 1.
    TextureRef alpha_map;
    float alpha_factor = 1.0f;
    float alpha_cutoff = 0.5f;
    // The material can be cut out: a coverage map, or a constant coverage below the cutoff.
    bool alpha_masked() const { return alpha_map.used() || alpha_factor < alpha_cutoff; }
    // Every texture slot, for code that treats them alike (remapping, uploading).
    std::array<const TextureRef*, 5> maps() const {
        return {&albedo_map, &roughness_map, &emission_map, &normal_map, &alpha_map};
    }
    std::array<TextureRef*, 5> maps() {
        return {&albedo_map, &roughness_map, &emission_map, &normal_map, &alpha_map};
    }
    bool textured() const {
        for (const TextureRef* r : maps())
            if (r->used()) return true;
        return false;
    }
    // Anisotropic roughness (a rough kind with α_v != α): its axes follow dp/du, so the
    // mesh's uvs matter even without textures (kernels/shared/microfacet.h).
    bool anisotropic() const;
    bool emissive() const { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
};

struct Camera {
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float vfov_deg = 40.0f;  // vertical field of view
    int width = limits::kDefaultWidth;
    int height = limits::kDefaultHeight;
    float lens_radius = 0.0f;      // thin lens aperture radius (world units); 0: pinhole
    float focus_distance = 1.0f;   // distance along the viewing direction to the plane in focus (world units)
};

// Render settings a scene file may carry (JSON "render", Mitsuba integrator/sampler);
// command-line options override them; unset ones fall back to the program's defaults.
struct RenderDefaults {
    std::optional<int> spp;
    std::optional<int> depth;  // bounces, as --depth
    std::optional<std::uint32_t> seed;
};

// Light from infinitely far away in every direction: an equirectangular (latitude-longitude)
// map, times scale, turned by to_world; the direction-to-texel mapping is Mitsuba 3's
// envmap (kernels/shared/envmap.h). Sampled by importance, combined with BSDF sampling by MIS.
struct Environment {
    int image = -1;                // index into Scene::textures (float or 8-bit)
    float scale = 1.0f;            // radiance multiplier
    glm::mat3 to_world{1.0f};      // rotation of the map (columns: its axes in the world)
};

struct Scene {
    std::string name;                   // for reports: file name or "cornell-box"
    std::vector<glm::vec3> positions;   // vertex positions (world units)
    // Per-vertex attributes, each either empty or one per position:
    std::vector<glm::vec3> normals;     // shading normals (need not be unit; a zero vector:
                                        // this vertex has none, the triangle shades flat)
    std::vector<glm::vec2> uvs;         // texture coordinates (convention at TextureRef)
    std::vector<glm::vec4> tangents;    // xyz: tangent (direction of +u), w: ±1 bitangent
                                        // sign (glTF/MikkTSpace: b = w · cross(n, t))
    std::vector<Texture> textures;      // texture images and environment maps
    std::optional<Environment> environment;
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
    // Triangle i's area, computed in double (the light table's weights, the emitters' share).
    double triangle_area(std::size_t i) const;
    // Triangle i's material emits (Material::emissive).
    bool triangle_emits(std::size_t i) const { return materials.at(material_ids.at(i)).emissive(); }
    // Appends a mesh with one material; returns the first new triangle's index. The
    // optional attributes are empty or one per entry of `pos`; where this scene or the mesh
    // lacks an attribute the other has, it is filled with zero normals / (0, 0) uvs /
    // zero tangents.
    std::size_t add_mesh(const std::vector<glm::vec3>& pos, const std::vector<glm::uvec3>& tris,
                         std::uint32_t material, const std::vector<glm::vec3>& normals = {},
                         const std::vector<glm::vec2>& uvs = {},
                         const std::vector<glm::vec4>& tangents = {});
    std::uint32_t add_material(const Material& m);
    // Appends every triangle of `src` with its positions transformed as points by
    // `to_world` (a mirroring transform also reverses the winding, so the front stays the
    // front). Materials: `material` when given, else src's own materials (appended, ids
    // remapped, with their textures appended too). Normals are transformed by the inverse
    // transpose, tangents as vectors; attributes one side lacks are filled as in add_mesh.
    // src's warnings are appended too; its camera, background and environment are ignored.
    void append(const Scene& src, const glm::mat4& to_world,
                std::optional<std::uint32_t> material = std::nullopt);
    // Drops the textures that no material slot and no environment refers to, renumbering
    // the references (e.g. a replaced environment map, the source of a derived map).
    void prune_textures();
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
