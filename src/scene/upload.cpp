#include "scene/upload.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "scene/light_pairs.h"
#include "scene/material_tables.h"
#include "scene/normals.h"
#include "shared/lights.h"
#include "util/error.h"

namespace wp {

namespace {

float4 row(const glm::vec3& v, float w = 0.0f) { return {v.x, v.y, v.z, w}; }

// The mean of a texture's linear RGB texels (8-bit sRGB texels decoded).
double texture_mean(const Texture& t) {
    std::size_t n = static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height);
    if (n == 0) return 1.0;
    auto linear = [&](std::uint8_t b) {
        double c = b / 255.0;
        if (!t.srgb) return c;
        return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    };
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            sum += t.is_float() ? double(t.texelsf[4 * i + k]) : linear(t.texels8[4 * i + k]);
    return sum / (3.0 * double(n));
}

}  // namespace

float plastic_specular_weight(const Material& m, const std::vector<Texture>& textures) {
    double d_mean = (double(m.albedo.x) + m.albedo.y + m.albedo.z) / 3.0;
    if (m.albedo_map.used() && m.albedo_map.image < static_cast<int>(textures.size()))
        d_mean *= texture_mean(textures[m.albedo_map.image]);
    double s_mean = (double(m.specular.x) + m.specular.y + m.specular.z) / 3.0;
    return d_mean + s_mean > 0.0 ? static_cast<float>(s_mean / (d_mean + s_mean)) : 0.5f;
}

SceneUpload upload_scene(const Scene& scene) {
    SceneUpload up;
    if (scene.material_ids.size() != scene.triangles.size())
        fail("scene '{}': {} material ids for {} triangles", scene.name, scene.material_ids.size(),
             scene.triangles.size());
    up.triangles.reserve(scene.triangles.size());
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
        const glm::uvec3& t = scene.triangles[i];
        for (int k = 0; k < 3; ++k)
            if (t[k] >= scene.positions.size())
                fail("scene '{}': triangle {} uses vertex {}, but there are {} vertices", scene.name,
                     i, t[k], scene.positions.size());
        up.triangles.push_back({row(scene.positions[t.x]), row(scene.positions[t.y]),
                                row(scene.positions[t.z])});
        if (scene.material_ids[i] >= scene.materials.size())
            fail("scene '{}': triangle {} uses material {}, but there are {} materials", scene.name,
                 i, scene.material_ids[i], scene.materials.size());
        up.material_ids.push_back(static_cast<int>(scene.material_ids[i]));
    }
    MaterialTables tables = build_material_tables(scene);
    for (const Material& m : scene.materials) {
        MaterialData d{};
        // Parameters the kind does not read (material_kinds.h) stay 0.
        d.albedo = row(m.albedo);
        d.emission = row(m.emission);
        d.kind = static_cast<int>(m.kind);
        d.ior = uses_ior(m.kind) ? m.ior : 0.0f;
        if (uses_alpha(m.kind)) {
            d.alpha = m.alpha;
            d.alpha_v = m.alpha_v.value_or(m.alpha);
            if (m.distribution == MicrofacetModel::Beckmann) d.flags |= WP_MF_BECKMANN;
            if (m.separable_g) d.flags |= WP_MF_SEPARABLE_G;
        }
        if (uses_ior(m.kind)) d.specular = row(m.specular);
        if (uses_eta_k(m.kind)) {
            d.eta = row(m.eta);
            d.k = row(m.k);
        }
        bool plastic = m.kind == MaterialKind::Plastic || m.kind == MaterialKind::RoughPlastic;
        if (m.nonlinear && plastic) d.flags |= WP_PLASTIC_NONLINEAR;
        if (plastic) d.specular.w = plastic_specular_weight(m, scene.textures);
        d.table = tables.table[up.materials.size()];
        up.materials.push_back(d);
    }
    up.material_tables = std::move(tables.data);
    up.background = row(scene.background);
    return up;
}

namespace {

// The device view of a material slot: -1 without a texture, else the index of a new view.
int add_view(const TextureRef& r, const std::vector<int>& texture_slot, std::vector<TextureView>& views) {
    if (!r.used()) return -1;
    if (r.image >= static_cast<int>(texture_slot.size())) fail("texture {} does not exist", r.image);
    TextureView v{};
    const glm::mat3& m = r.uv_transform;  // column-major: m[col][row]
    v.u_row = {m[0][0], m[1][0], m[2][0], 0.0f};
    v.v_row = {m[0][1], m[1][1], m[2][1], 0.0f};
    v.texture = texture_slot[r.image];
    views.push_back(v);
    return static_cast<int>(views.size() - 1);
}

}  // namespace

AppearanceUpload upload_appearance(const Scene& scene, const AppearanceNeeds& needs) {
    AppearanceUpload up;
    const std::size_t n = scene.triangles.size();
    auto vertex4 = [](const std::vector<glm::vec3>& a, std::uint32_t i) {
        return i < a.size() ? row(a[i]) : float4{0.0f, 0.0f, 0.0f, 0.0f};
    };
    if (needs.normals) {
        up.normals.reserve(n);
        for (const glm::uvec3& t : scene.triangles)
            up.normals.push_back({vertex4(scene.normals, t.x), vertex4(scene.normals, t.y),
                                  vertex4(scene.normals, t.z)});
    }
    if (needs.uvs) {
        up.uvs.reserve(n);
        auto uv = [&](std::uint32_t i) { return i < scene.uvs.size() ? scene.uvs[i] : glm::vec2(0.0f); };
        for (const glm::uvec3& t : scene.triangles) {
            glm::vec2 a = uv(t.x), b = uv(t.y), c = uv(t.z);
            up.uvs.push_back({{a.x, a.y, b.x, b.y}, {c.x, c.y, 0.0f, 0.0f}});
        }
        // Upload only the images some material uses, each once.
        std::vector<int> slot(scene.textures.size(), -1);
        std::vector<const Texture*> used;
        for (const Material& m : scene.materials)
            for (const TextureRef* r : m.maps())
                if (r->used() && r->image < static_cast<int>(slot.size()) && slot[r->image] < 0) {
                    slot[r->image] = static_cast<int>(used.size());
                    used.push_back(&scene.textures[r->image]);
                }
        up.textures = upload_textures(used);
        for (const Material& m : scene.materials) {
            MaterialTextures mt{};
            mt.albedo = add_view(m.albedo_map, slot, up.views);
            mt.roughness = uses_alpha(m.kind) ? add_view(m.roughness_map, slot, up.views) : -1;
            mt.emission = add_view(m.emission_map, slot, up.views);
            mt.normal = needs.tangents ? add_view(m.normal_map, slot, up.views) : -1;
            mt.alpha = add_view(m.alpha_map, slot, up.views);
            mt.alpha_cutoff = m.alpha_masked() ? m.alpha_cutoff : 0.0f;
            mt.alpha_factor = m.alpha_factor;
            mt.normal_scale = m.normal_scale;
            up.material_textures.push_back(mt);
        }
    }
    if (needs.tangents) {
        std::vector<glm::vec4> ct = corner_tangents(scene);  // MikkTSpace-like, scene/normals.h
        up.tangents.reserve(n);
        for (std::size_t i = 0; i < n; ++i) {
            auto r4 = [](glm::vec4 v) { return float4{v.x, v.y, v.z, v.w}; };
            up.tangents.push_back({r4(ct[3 * i]), r4(ct[3 * i + 1]), r4(ct[3 * i + 2])});
        }
    }
    if (needs.env && scene.environment) {
        const Environment& e = *scene.environment;
        if (e.image < 0 || e.image >= static_cast<int>(scene.textures.size()))
            fail("scene '{}': the environment's image {} does not exist", scene.name, e.image);
        up.env = upload_environment(e, scene.textures[e.image], up.warnings);
    }
    return up;
}

std::vector<int> build_cdf_guide(const std::vector<float>& cdf) {
    const std::size_t n = cdf.size();
    if (n == 0) return {};
    std::size_t m = 1;
    while (m < n && m < (std::size_t{1} << 24)) m <<= 1;
    std::vector<int> guide(m + 1);
    std::size_t k = 0;
    for (std::size_t j = 0; j <= m; ++j) {
        // j / m is exact in double and in float (m <= 2^24), and so is each comparison.
        const double edge = static_cast<double>(j) / static_cast<double>(m);
        while (k < n && !(static_cast<double>(cdf[k]) > edge)) ++k;
        guide[j] = static_cast<int>(k < n ? k : n - 1);
    }
    guide[0] = 0;  // u < 0 (never drawn) picks 0 as the binary search does
    return guide;
}

LightTable build_light_table(const Scene& scene, bool pairs, const std::vector<int>* partners) {
    LightTable lt;
    lt.pdf_area.assign(scene.triangles.size(), 0.0f);
    std::vector<double> power, area;
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
        const LightTriangle l = light_triangle(scene, i);
        if (l.power <= 0.0) continue;
        lt.prims.push_back(static_cast<int>(i));
        power.push_back(l.power);
        area.push_back(l.area);
        lt.total_power += l.power;
    }
    double run = 0.0;
    for (std::size_t k = 0; k < power.size(); ++k) {
        run += power[k];
        lt.cdf.push_back(k + 1 == power.size() ? 1.0f : static_cast<float>(run / lt.total_power));
    }
    if (lt.cdf.size() >= WP_LIGHT_GUIDE_MIN) lt.guide = build_cdf_guide(lt.cdf);
    for (std::size_t k = 0; k < lt.prims.size(); ++k) {
        float p = lt.cdf[k] - (k > 0 ? lt.cdf[k - 1] : 0.0f);
        lt.pdf_area[lt.prims[k]] = static_cast<float>(p / area[k]);
    }
    if (pairs) {
        const std::vector<int> found = partners ? std::vector<int>() : find_light_partners(scene);
        const std::vector<int>& partner = partners ? *partners : found;
        if (partner.size() != scene.triangles.size())
            fail("scene '{}': {} light partners for {} triangles", scene.name, partner.size(), scene.triangles.size());
        std::vector<double> chance(scene.triangles.size(), 0.0), tri_area(scene.triangles.size(), 0.0);
        for (std::size_t k = 0; k < lt.prims.size(); ++k) {
            chance[lt.prims[k]] = lt.cdf[k] - (k > 0 ? lt.cdf[k - 1] : 0.0f);
            tri_area[lt.prims[k]] = area[k];
        }
        for (std::size_t i = 0; i < partner.size(); ++i) {
            if (partner[i] < 0) continue;
            if (lt.pairs.empty()) lt.pairs.assign(scene.triangles.size(), LightPair{-1, 0.0f});
            lt.pairs[i] = {partner[i], static_cast<float>(chance[partner[i]] / tri_area[i])};
        }
    }
    return lt;
}

CameraData upload_camera(const Camera& camera, int width, int height, bool jitter) {
    if (width <= 0 || height <= 0) fail("image size {}x{} must be positive", width, height);
    glm::vec3 view = camera.target - camera.position;
    if (glm::length(view) == 0.0f) fail("camera: position and target coincide");
    glm::vec3 forward = glm::normalize(view);
    glm::vec3 right = glm::cross(forward, camera.up);
    if (glm::length(right) < 1e-6f) fail("camera: the up vector is parallel to the view direction");
    right = glm::normalize(right);
    glm::vec3 up = glm::cross(right, forward);
    if (!(camera.vfov_deg > 0.0f && camera.vfov_deg < 180.0f))
        fail("camera: vertical field of view {} degrees is outside (0, 180)", camera.vfov_deg);
    if (!(std::isfinite(camera.lens_radius) && camera.lens_radius >= 0.0f))
        fail("camera: lens radius {} must be finite and >= 0", camera.lens_radius);
    if (camera.lens_radius > 0.0f &&
        !(std::isfinite(camera.focus_distance) && camera.focus_distance > 0.0f))
        fail("camera: focus distance {} must be finite and > 0", camera.focus_distance);
    float tan_half = std::tan(glm::radians(camera.vfov_deg) * 0.5f);
    float aspect = static_cast<float>(width) / static_cast<float>(height);
    CameraData c{};
    c.origin = row(camera.position);
    c.forward = row(forward);
    c.right = row(right * (tan_half * aspect));
    c.up = row(up * tan_half);
    c.width = width;
    c.height = height;
    c.jitter = jitter ? 1 : 0;
    // Thin lens; radius 0 is the pinhole (the generate stage then ignores the focus distance).
    c.lens = {camera.lens_radius, camera.focus_distance, 0.0f, 0.0f};
    return c;
}

}  // namespace wp
