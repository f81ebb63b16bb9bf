// device_scene.h — the scene as the stages read it: BVH, shading triangles, materials,
// light table, background and camera, in device arrays.
//
// Built once per render from a host Scene (scene/upload and bvh/flatten convert the
// types); the light table is uploaded only when the kernels sample lights (KernelConfig::
// nee()), else its arrays are 4-byte placeholders. The appearance arrays follow the
// KernelConfig: where it models a feature the scene lacks (--kernels generic) they hold
// neutral data (zero normals, (0, 0) uvs, no texture slots, a black environment) that
// leaves the image's expectation unchanged (DeviceScene::upload).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bvh/device_bvh.h"
#include "cl/kernel.h"
#include "render/kernel_config.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace wp::render {

// The texture data the alpha test (intersect, shadow) and shade read; placeholders when
// no material has a texture or cut-out.
struct TextureArrays {
    ocl::Array<int> material_ids;                    // the shading scene's, shared
    ocl::Array<MaterialTextures> material_textures;  // per material
    ocl::Array<TriUVs> tri_uvs;                      // per triangle, scene order
    ocl::Array<TextureData> textures;
    ocl::Array<TextureView> views;
    ocl::Array<cl_uint> texels8;
    ocl::Array<float4> texelsf;
};

// What the shade stage reads of the scene, in the order its kernel takes them.
struct ShadingScene {
    ocl::Array<Triangle> tris;        // original triangle order (hits name them by prim)
    // Per triangle, the same order: xyz the unit face normal, w the ray-offset share
    // (kernels/shared/offset.h, wp_triangle_frame); written on the device by
    // ShadeStage::prepare, read by shade and the AOVs instead of recomputing them per hit.
    ocl::Array<float4> tri_frames;
    ocl::Array<int> material_ids;     // one per triangle
    ocl::Array<MaterialData> materials;
    // The tables some kinds read at MaterialData.table (scene/material_tables.h): a
    // one-float placeholder when no material has any (no rough plastic).
    ocl::Array<float> material_tables;
    float4 background{0, 0, 0, 0};    // xyz: radiance of escaped rays
    // NEE light table (kernels/shared/lights.h); placeholders without NEE.
    ocl::Array<float> light_cdf;
    ocl::Array<int> light_guide;  // guide table of light_cdf (scene/upload: build_cdf_guide)
    int light_guide_size = 0;     // its m: light_guide has m + 1 entries
    ocl::Array<int> light_prims;
    ocl::Array<float> light_pdf_area;
    ocl::Array<LightPair> light_pairs;  // per triangle with KernelConfig::sample_pairs(); else a placeholder
    // Per triangle (scene order) with KernelConfig::clear_shadow_ends(): a light triangle's
    // clearance (scene/light_clearance.h), 0 elsewhere; else a placeholder.
    ocl::Array<float> light_clearance;
    int light_count = 0;
    // Appearance (placeholders for features the scene lacks; KernelConfig).
    ocl::Array<TriNormals> tri_normals;
    ocl::Array<TriTangents> tri_tangents;
    TextureArrays tex;
    EnvData env{};
    ocl::Array<float4> env_texels;
    ocl::Array<float> env_marginal;
    ocl::Array<float> env_conditional;
    float env_distance = 0.0f;  // shadow rays towards the environment: beyond the scene
    float cone_spread = 0.0f;   // ray cones: the camera's spread angle per pixel
};

struct SceneStats {
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    std::size_t materials = 0;
    std::size_t emissive_materials = 0;
    std::size_t light_triangles = 0;  // entries of the NEE light table (0 without NEE)
    std::size_t cleared_lights = 0;   // light triangles with a clearance > 0 (light_clearance)
    double clearance_ms = 0.0;        // finding the clearances (light_clearances)
    std::size_t bvh_nodes = 0;        // interior nodes of the flattened BVH
    std::size_t emitter_bvh_triangles = 0;  // triangles of the emitters' BVH (0: none built)
    int bvh_depth = 0;
    double bvh_build_ms = 0.0;    // binned SAH build (bvh::build)
    double bvh_flatten_ms = 0.0;  // collapse to the 8-wide device layout (bvh::flatten)
    double upload_ms = 0.0;   // build + flatten + upload
    double program_ms = 0.0;  // all program builds (or cache loads)
    std::size_t scene_bytes = 0;  // device memory of the scene (BVH, shading data, lights,
                                  // appearance)
    std::size_t texture_count = 0;     // images uploaded for materials
    std::size_t texture_bytes = 0;     // their mip chains, views and material slots
    std::size_t attribute_bytes = 0;   // normals, uvs, tangents
    std::size_t env_bytes = 0;         // the environment map and its sampling tables
    int env_width = 0, env_height = 0;
};

// "textures: 3 images, 5.3 MiB (mip-mapped); vertex attributes 1.2 MiB; environment
// 2048x1024, 42.7 MiB" — the device memory of the appearance data; "" when the scene has none.
std::string describe_appearance(const SceneStats& stats);

// Whether the last bounce's rays can go through the emitting triangles' BVH first
// (IntersectStage::enqueue_final, kernels/intersect.cl intersect_final): where escaped rays
// carry no radiance (a black background, no environment map or one of scale 0), a last-bounce
// ray adds light only where its closest hit emits. The emitters' BVH is the cheaper first
// test where most rays miss the emitters: some triangle emits and the emitting triangles
// hold at most kFinalRaysMaxEmitterArea of the surface area (a furnace whose every wall
// emits traces its last bounce 1.24x slower this way; docs/performance.md, "Eighth round").
// The renderer also needs no hit of the last bounce for anything else (no feature buffers:
// Wavefront).
constexpr double kFinalRaysMaxEmitterArea = 0.25;
// The emitting triangles' share of the scene's surface area (0 for a scene without area).
double emitter_area_share(const Scene& scene);
bool final_rays_through_emitters(const Scene& scene);

struct DeviceScene {
    bvh::DeviceBvh bvh;
    // The emitting triangles' own BVH (prim_ids in scene order), uploaded only when asked
    // (upload's emitter_bvh); empty otherwise.
    bvh::DeviceBvh emitter_bvh;
    ShadingScene shading;
    CameraData camera{};
    SceneStats stats;
    std::vector<std::string> warnings;  // from the upload (e.g. an environment map not 2:1)

    // Builds the BVH and uploads; throws wp::Error for bad scenes or too little memory.
    // emitter_bvh: also the emitters' BVH (where final_rays_through_emitters holds; a scene
    // whose escaped rays carry light is refused).
    static DeviceScene upload(const ocl::Device& dev, const Scene& scene, const KernelConfig& config,
                              int width, int height, bool jitter, bool emitter_bvh = false);
};

}  // namespace wp::render
