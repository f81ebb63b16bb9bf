#include "scene/scene.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "util/error.h"

namespace wp {

namespace {

// One row per kind, in list order (material_kinds.h): what the host asks of a kind.
struct KindInfo {
    MaterialKind kind;
    const char* name;
    bool specular, alpha, ior, etak;
};
constexpr KindInfo kKinds[] = {
#define WP_KIND_ROW_(KIND, Kind, name, specular, alpha, ior, etak) \
    {MaterialKind::Kind, #name, specular != 0, alpha != 0, ior != 0, etak != 0},
    WP_MATERIAL_KINDS(WP_KIND_ROW_)
#undef WP_KIND_ROW_
};

const KindInfo* info(MaterialKind k) {
    for (const KindInfo& i : kKinds)
        if (i.kind == k) return &i;
    return nullptr;
}

}  // namespace

const char* to_string(MaterialKind k) {
    const KindInfo* i = info(k);
    return i ? i->name : "unknown";
}

std::optional<MaterialKind> material_kind_from_string(std::string_view s) {
    for (const KindInfo& i : kKinds)
        if (s == i.name) return i.kind;
    return std::nullopt;
}

bool is_specular(MaterialKind k) {
    const KindInfo* i = info(k);
    return i && i->specular;
}

bool uses_alpha(MaterialKind k) {
    const KindInfo* i = info(k);
    return i && i->alpha;
}

bool uses_ior(MaterialKind k) {
    const KindInfo* i = info(k);
    return i && i->ior;
}

bool uses_eta_k(MaterialKind k) {
    const KindInfo* i = info(k);
    return i && i->etak;
}

bool Material::anisotropic() const {
    return uses_alpha(kind) && kind != MaterialKind::Glossy && alpha_v && *alpha_v != alpha;
}

Aabb Scene::bounds() const {
    Aabb b;
    for (const auto& t : triangles)
        for (int k = 0; k < 3; ++k) b.grow(positions[t[k]]);
    return b;
}

double Scene::triangle_area(std::size_t i) const {
    const glm::uvec3& t = triangles.at(i);
    const glm::dvec3 a(positions.at(t.x)), b(positions.at(t.y)), c(positions.at(t.z));
    return 0.5 * glm::length(glm::cross(b - a, c - a));
}

namespace {

// Brings an optional per-vertex attribute of a scene with `old_count` vertices to
// `old_count + added` entries: `src` when given (size `added`), else fill; when the scene
// had none and the new part has none, it stays empty.
template <class T>
void append_attribute(std::vector<T>& dst, std::size_t old_count, const std::vector<T>& src,
                      std::size_t added, const char* what) {
    if (!src.empty() && src.size() != added)
        fail("add_mesh: {} {} for {} vertices", src.size(), what, added);
    if (dst.empty() && src.empty()) return;
    dst.resize(old_count, T(0.0f));
    if (src.empty())
        dst.resize(old_count + added, T(0.0f));
    else
        dst.insert(dst.end(), src.begin(), src.end());
}

}  // namespace

std::size_t Scene::add_mesh(const std::vector<glm::vec3>& pos, const std::vector<glm::uvec3>& tris,
                            std::uint32_t material, const std::vector<glm::vec3>& nrm,
                            const std::vector<glm::vec2>& uv, const std::vector<glm::vec4>& tan) {
    if (material >= materials.size()) fail("add_mesh: material {} does not exist", material);
    auto base = static_cast<std::uint32_t>(positions.size());
    std::size_t first = triangles.size();
    append_attribute(normals, base, nrm, pos.size(), "normals");
    append_attribute(uvs, base, uv, pos.size(), "uvs");
    append_attribute(tangents, base, tan, pos.size(), "tangents");
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

void Scene::append(const Scene& src, const glm::mat4& to_world,
                   std::optional<std::uint32_t> material) {
    if (material && *material >= materials.size())
        fail("append: material {} does not exist", *material);
    std::vector<std::uint32_t> remap;
    if (!material) {
        const int image_base = static_cast<int>(textures.size());
        textures.insert(textures.end(), src.textures.begin(), src.textures.end());
        remap.reserve(src.materials.size());
        for (Material m : src.materials) {
            for (TextureRef* r : m.maps())
                if (r->used()) r->image += image_base;
            remap.push_back(add_material(m));
        }
    }
    auto base = static_cast<std::uint32_t>(positions.size());
    const glm::mat3 linear(to_world);
    const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
    std::vector<glm::vec3> pos, nrm;
    std::vector<glm::vec4> tan;
    pos.reserve(src.positions.size());
    for (const auto& p : src.positions) pos.push_back(glm::vec3(to_world * glm::vec4(p, 1.0f)));
    nrm.reserve(src.normals.size());
    for (const auto& n : src.normals) nrm.push_back(normal_matrix * n);
    tan.reserve(src.tangents.size());
    // A mirroring transform reverses the handedness: w keeps w cross(n, t) the bitangent.
    const float hand = glm::determinant(linear) < 0.0f ? -1.0f : 1.0f;
    for (const auto& t : src.tangents) tan.push_back(glm::vec4(linear * glm::vec3(t), t.w * hand));
    append_attribute(normals, base, nrm, pos.size(), "normals");
    append_attribute(uvs, base, src.uvs, pos.size(), "uvs");
    append_attribute(tangents, base, tan, pos.size(), "tangents");
    positions.insert(positions.end(), pos.begin(), pos.end());
    bool mirror = glm::determinant(linear) < 0.0f;
    triangles.reserve(triangles.size() + src.triangles.size());
    for (std::size_t i = 0; i < src.triangles.size(); ++i) {
        glm::uvec3 t = src.triangles[i] + glm::uvec3(base);
        if (mirror) std::swap(t.y, t.z);
        triangles.push_back(t);
        material_ids.push_back(material ? *material : remap.at(src.material_ids[i]));
    }
    warnings.insert(warnings.end(), src.warnings.begin(), src.warnings.end());
}

void Scene::prune_textures() {
    std::vector<TextureRef*> refs;
    for (Material& m : materials)
        for (TextureRef* r : m.maps())
            if (r->used() && std::size_t(r->image) < textures.size()) refs.push_back(r);
    const bool env = environment && environment->image >= 0 &&
                     std::size_t(environment->image) < textures.size();
    std::vector<int> index(textures.size(), -1);
    for (TextureRef* r : refs) index[std::size_t(r->image)] = 0;
    if (env) index[std::size_t(environment->image)] = 0;
    std::vector<Texture> kept;
    for (std::size_t i = 0; i < textures.size(); ++i)
        if (index[i] == 0) {
            index[i] = static_cast<int>(kept.size());
            kept.push_back(std::move(textures[i]));
        }
    for (TextureRef* r : refs) r->image = index[std::size_t(r->image)];
    if (env) environment->image = index[std::size_t(environment->image)];
    textures = std::move(kept);
}

Camera camera_from_matrix(const glm::mat4& m, float vfov_deg, int width, int height) {
    Camera c;
    glm::vec3 dir = glm::vec3(m[2]);
    glm::vec3 up = glm::vec3(m[1]);
    c.position = glm::vec3(m[3]);
    float len = glm::length(dir);
    if (!(len > 0.0f) || !std::isfinite(len)) fail("camera matrix has no viewing direction");
    c.target = c.position + dir / len;
    c.up = up;
    c.vfov_deg = vfov_deg;
    c.width = width;
    c.height = height;
    return c;
}

Camera frame_bounds(const Aabb& b, const std::string& source) {
    Camera c;  // limits::kDefaultWidth x kDefaultHeight
    c.vfov_deg = 40.0f;
    const float radius = std::max(0.5f * glm::length(b.extent()), 1e-3f);
    const float distance = radius / std::sin(glm::radians(0.5f * c.vfov_deg));
    c.target = b.center();
    c.position = c.target + glm::vec3(0.0f, 0.0f, distance);
    c.up = glm::vec3(0.0f, 1.0f, 0.0f);
    // Finite vertices can still overflow here (the extent of +-1e38 is 2e38 > FLT_MAX, or the
    // distance is): name that cause, not the camera that results from it.
    auto finite = [](glm::vec3 v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    if (!finite(b.lo) || !finite(b.hi) || !std::isfinite(radius) || !std::isfinite(distance) ||
        !finite(c.target) || !finite(c.position))
        fail("{}: scene bounds ({:g}, {:g}, {:g}) to ({:g}, {:g}, {:g}) are too large to frame "
             "with the automatic camera (its distance overflows a float); scale the scene down "
             "or give it a camera",
             source.empty() ? std::string("scene") : source, b.lo.x, b.lo.y, b.lo.z, b.hi.x,
             b.hi.y, b.hi.z);
    return c;
}

float vfov_from_hfov(float hfov_deg, int width, int height) {
    double t = std::tan(double(hfov_deg) * 0.5 * M_PI / 180.0) * double(height) / double(width);
    return static_cast<float>(2.0 * std::atan(t) * 180.0 / M_PI);
}

}  // namespace wp
