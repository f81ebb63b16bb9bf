#include "render/device_scene.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <fmt/format.h>

#include "bvh/build.h"
#include "bvh/flatten.h"
#include "render/memory.h"
#include "scene/light_clearance.h"
#include "scene/upload.h"
#include "util/error.h"
#include "util/host_trace.h"
#include "util/timer.h"

namespace wp::render {

std::string describe_appearance(const SceneStats& st) {
    auto mib = [](std::size_t b) { return fmt::format("{:.1f} MiB", double(b) / (1024.0 * 1024.0)); };
    std::vector<std::string> parts;
    if (st.texture_count > 0)
        parts.push_back(fmt::format("textures: {} image{}, {} (mip-mapped)", st.texture_count,
                                    st.texture_count == 1 ? "" : "s", mib(st.texture_bytes)));
    if (st.attribute_bytes > 0) parts.push_back(fmt::format("vertex attributes {}", mib(st.attribute_bytes)));
    if (st.env_bytes > 0)
        parts.push_back(fmt::format("environment {}x{}, {}", st.env_width, st.env_height, mib(st.env_bytes)));
    std::string s;
    for (const auto& p : parts) s += (s.empty() ? "" : "; ") + p;
    return s;
}

namespace {

// The stand-in of the generic build for a scene without an environment: radiance 0 in every
// direction and all-zero sampling tables, so wp_env_sample draws nothing (pdf 0) and
// wp_env_pdf is 0 (kernels/shared/envmap.h). Its scale is 0, so with emitting triangles
// next-event estimation never picks it (wp_env_choice in shade.cl): the same estimator as
// the specialised kernels.
EnvUpload black_environment() {
    Texture t;
    t.source = "(black environment of the generic kernels)";
    t.width = 2;
    t.height = 1;
    t.texelsf.assign(4 * 2, 0.0f);
    std::vector<std::string> warnings;
    Environment black;
    black.scale = 0.0f;  // light sampling never picks it while triangles emit (wp_env_choice)
    return upload_environment(black, t, warnings);
}

// The emitting triangles' BVH, prim_ids naming them in scene order (the tie rule at equal t
// and the alpha test read those).
bvh::FlatBvh emitter_flat_bvh(const Scene& scene) {
    std::vector<int> ids;
    for (std::size_t i = 0; i < scene.triangles.size(); ++i)
        if (scene.triangle_emits(i)) ids.push_back(static_cast<int>(i));
    return bvh::flatten_subset(scene.positions, scene.triangles, ids);
}

// Escaped rays carry no light: a black background and no environment map (or one of scale
// 0). The condition under which the emitters' BVH gives the last bounce's image exactly.
bool escaped_rays_black(const Scene& scene) {
    return scene.background == glm::vec3(0.0f) && (!scene.environment || scene.environment->scale == 0.0f);
}

}  // namespace

double emitter_area_share(const Scene& scene) {
    double all = 0.0, emitting = 0.0;
    for (std::size_t i = 0; i < scene.triangles.size(); ++i) {
        const double area = scene.triangle_area(i);
        if (!std::isfinite(area)) continue;
        all += area;
        if (scene.triangle_emits(i)) emitting += area;
    }
    return all > 0.0 ? emitting / all : 0.0;
}

bool final_rays_through_emitters(const Scene& scene) {
    // A share above 0: some emitter can be hit (a triangle of no area never is).
    const double share = escaped_rays_black(scene) ? emitter_area_share(scene) : 0.0;
    return share > 0.0 && share <= kFinalRaysMaxEmitterArea;
}

DeviceScene DeviceScene::upload(const ocl::Device& dev, const Scene& scene, const KernelConfig& config,
                                int width, int height, bool jitter, bool emitter_bvh) {
    DeviceScene d;
    Timer timer;
    std::optional<HostSpan> span(std::in_place, "bvh");
    auto boxes = bvh::triangle_boxes(scene.positions, scene.triangles);
    bvh::Bvh bvh = bvh::build(boxes);
    Timer flatten_timer;
    bvh::FlatBvh flat = bvh::flatten(bvh, scene.positions, scene.triangles);
    const double flatten_ms = flatten_timer.ms();
    span.emplace("upload");  // ends the BVH's span
    SceneUpload up = upload_scene(scene);
    d.camera = upload_camera(scene.camera, width, height, jitter);

    SceneStats& st = d.stats;
    st.triangles = scene.triangle_count();
    st.vertices = scene.positions.size();
    st.materials = scene.materials.size();
    st.emissive_materials = static_cast<std::size_t>(std::count_if(
        scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.emissive(); }));
    st.bvh_nodes = flat.nodes.size();
    st.bvh_depth = flat.depth;
    st.bvh_build_ms = bvh.build_ms;
    st.bvh_flatten_ms = flatten_ms;

    {
        ocl::MemoryGroup group(dev, kMemoryBvh);
        d.bvh = bvh::DeviceBvh::upload(dev, flat);
        if (emitter_bvh) {
            // The area share is a matter of speed; this is one of exactness.
            if (!escaped_rays_black(scene))
                fail("scene upload: the emitters' BVH asked for a scene whose escaped rays carry light");
            d.emitter_bvh = bvh::DeviceBvh::upload(dev, emitter_flat_bvh(scene), "the emitters'");
            st.emitter_bvh_triangles = static_cast<std::size_t>(d.emitter_bvh.triangle_count);
        }
    }
    ocl::MemoryGroup group(dev, kMemoryScene);  // everything else this function uploads
    ShadingScene& s = d.shading;
    s.tris = ocl::Array<Triangle>::upload(dev, up.triangles, "the shading triangles");
    s.tri_frames = ocl::Array<float4>::allocate(dev, up.triangles.size(), "the triangle frames");
    s.material_ids = ocl::Array<int>::upload(dev, up.material_ids, "the material ids");
    s.materials = ocl::Array<MaterialData>::upload(dev, up.materials, "the materials");
    s.material_tables = ocl::Array<float>::upload(dev, up.material_tables, "the material tables");
    s.background = up.background;
    LightTable lights;
    if (config.nee()) lights = build_light_table(scene, config.sample_pairs(), config.light_partners.get());
    st.light_triangles = lights.size();
    s.light_count = static_cast<int>(lights.size());
    if (lights.size() > 0) {
        s.light_cdf = ocl::Array<float>::upload(dev, lights.cdf, "the light CDF");
        s.light_prims = ocl::Array<int>::upload(dev, lights.prims, "the light triangles");
        s.light_pdf_area = ocl::Array<float>::upload(dev, lights.pdf_area, "the light densities");
    } else {
        s.light_cdf = ocl::Array<float>::zeros(dev, 0, "a placeholder");
        s.light_prims = ocl::Array<int>::zeros(dev, 0, "a placeholder");
        s.light_pdf_area = ocl::Array<float>::zeros(dev, 0, "a placeholder");
    }
    // Back-to-back light pairs where the kernels read them (KernelConfig::sample_pairs()); the
    // generic build's neutral table for a scene without pairs: no partners.
    if (config.sample_pairs()) {
        if (lights.pairs.empty()) lights.pairs.assign(scene.triangles.size(), LightPair{-1, 0.0f});
        s.light_pairs = ocl::Array<LightPair>::upload(dev, lights.pairs, "the light pairs");
    } else {
        s.light_pairs = ocl::Array<LightPair>::zeros(dev, 0, "a placeholder");
    }
    // Where shadow segments may end: each light triangle's clearance, found through the
    // scene's BVH (its host tree, before flattening).
    if (config.clear_shadow_ends() && lights.size() > 0) {
        Timer clear_timer;
        const std::vector<float> clearance = light_clearances(scene, bvh, lights.prims);
        st.clearance_ms = clear_timer.ms();
        st.cleared_lights = static_cast<std::size_t>(
            std::count_if(clearance.begin(), clearance.end(), [](float c) { return c > 0.0f; }));
        // (Wavefront drops it again, and compiles shade without it, where no light has one
        // and the kernels are specialised.)
        s.light_clearance = ocl::Array<float>::upload(dev, clearance, "the light clearances");
    } else {
        s.light_clearance = ocl::Array<float>::zeros(dev, 0, "a placeholder");
    }
    // The light pick's guide table (below WP_LIGHT_GUIDE_MIN lights, or without lights, none:
    // size 0 tells the kernel to search the CDF directly).
    if (!lights.guide.empty()) {
        s.light_guide = ocl::Array<int>::upload(dev, lights.guide, "the light CDF's guide table");
        s.light_guide_size = static_cast<int>(lights.guide.size()) - 1;
    } else {
        s.light_guide = ocl::Array<int>::zeros(dev, 0, "a placeholder");
    }
    // Appearance: what the kernels were configured for. A switch on for a feature the
    // scene lacks (the generic build, KernelConfig::with_every_feature()) reads neutral data
    // that leaves every estimate as it was:
    //   normals      per triangle, zero where the scene has none: the kernels shade with the
    //                face normal (wp_interpolated_normal) and, seeing ns = ng, skip the
    //                bent-normal guard and the terminator factor (shade.cl);
    //   uvs          per triangle, (0, 0) without uvs; every material's texture slots -1 and
    //                alpha cut-off 0 (not masked): textures and the alpha test read nothing
    //                more, and anisotropy reads uvs only where α_u != α_v;
    //   tangents     read only where a material has a normal map (slot >= 0): uploaded only
    //                when one has;
    //   environment  a black one (black_environment()).
    const KernelConfig has = KernelConfig::from_scene(scene, config.estimator, false);  // no second pair search
    AppearanceNeeds needs;
    needs.normals = config.normals;
    needs.uvs = config.textures || config.alpha_mask || config.anisotropic;
    needs.tangents = config.normal_maps && has.normal_maps;
    needs.env = config.env && has.env;
    AppearanceUpload app = upload_appearance(scene, needs);
    if (config.env && !app.env) app.env = black_environment();
    s.tri_normals = ocl::Array<TriNormals>::upload(dev, app.normals, "the shading normals");
    s.tri_tangents = ocl::Array<TriTangents>::upload(dev, app.tangents, "the tangents");
    TextureArrays& t = s.tex;
    t.material_ids = s.material_ids;
    t.material_textures = ocl::Array<MaterialTextures>::upload(dev, app.material_textures, "the material textures");
    t.tri_uvs = ocl::Array<TriUVs>::upload(dev, app.uvs, "the texture coordinates");
    t.textures = ocl::Array<TextureData>::upload(dev, app.textures.textures, "the texture table");
    t.views = ocl::Array<TextureView>::upload(dev, app.views, "the texture views");
    t.texels8 = ocl::Array<cl_uint>::upload(dev, app.textures.texels8, "the 8-bit texels");
    t.texelsf = ocl::Array<float4>::upload(dev, app.textures.texelsf, "the float texels");
    st.texture_count = app.textures.textures.size();
    st.texture_bytes = t.material_textures.bytes() + t.textures.bytes() + t.views.bytes() +
                       t.texels8.bytes() + t.texelsf.bytes();
    st.attribute_bytes = s.tri_normals.bytes() + s.tri_tangents.bytes() + t.tri_uvs.bytes();
    std::vector<float4> no_texels;
    std::vector<float> no_table;
    const EnvUpload* env = app.env ? &*app.env : nullptr;
    if (env) {
        s.env = env->data;
        st.env_width = env->data.width;
        st.env_height = env->data.height;
    }
    s.env_texels = ocl::Array<float4>::upload(dev, env ? env->texels : no_texels, "the environment map");
    s.env_marginal = ocl::Array<float>::upload(dev, env ? env->marginal : no_table, "the environment's row CDF");
    s.env_conditional = ocl::Array<float>::upload(dev, env ? env->conditional : no_table,
                                                  "the environment's column CDFs");
    st.env_bytes = env ? s.env_texels.bytes() + s.env_marginal.bytes() + s.env_conditional.bytes() : 0;
    // A shadow ray towards the environment leaves the scene's bounds from any point in them.
    Aabb b = scene.bounds();
    // Twice the diagonal: no scene-size constant (a scene of one point gets 1).
    float diag = b.empty() ? 0.0f : glm::length(b.hi - b.lo);
    s.env_distance = diag > 0.0f && std::isfinite(diag) ? 2.0f * diag : 1.0f;
    // The spread of a pixel's cone: its angle at the image centre (Akenine-Möller et al.
    // 2021: atan(2 tan(vfov / 2) / height)).
    s.cone_spread = std::atan(2.0f * std::tan(glm::radians(scene.camera.vfov_deg) * 0.5f) /
                              static_cast<float>(height));
    d.warnings = std::move(app.warnings);

    st.scene_bytes = d.bvh.bytes + d.emitter_bvh.bytes + s.tris.bytes() + s.tri_frames.bytes() + s.material_ids.bytes() +
                     s.materials.bytes() + s.material_tables.bytes() + s.light_cdf.bytes() +
                     s.light_guide.bytes() + s.light_prims.bytes() + s.light_pdf_area.bytes() + s.light_pairs.bytes() + s.light_clearance.bytes() +
                     st.texture_bytes + st.attribute_bytes + st.env_bytes;
    st.upload_ms = timer.ms();
    return d;
}

}  // namespace wp::render
