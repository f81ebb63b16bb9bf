// device_scene.h — the scene as the stages read it: BVH, shading triangles, materials,
// light table, background and camera, in device arrays.
//
// Built once per render from a host Scene (scene/upload and bvh/flatten convert the
// types); the light table is uploaded only when the kernels sample lights (KernelConfig::
// nee()), else its arrays are 4-byte placeholders.
#pragma once

#include <cstddef>

#include "bvh/device_bvh.h"
#include "cl/kernel.h"
#include "render/kernel_config.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace wp::render {

// What the shade stage reads of the scene, in the order its kernel takes them.
struct ShadingScene {
    ocl::Array<Triangle> tris;        // original triangle order (hits name them by prim)
    ocl::Array<int> material_ids;     // one per triangle
    ocl::Array<MaterialData> materials;
    float4 background{0, 0, 0, 0};    // xyz: radiance of escaped rays
    // NEE light table (kernels/shared/lights.h); placeholders without NEE.
    ocl::Array<float> light_cdf;
    ocl::Array<int> light_prims;
    ocl::Array<float> light_pdf_area;
    int light_count = 0;
};

struct SceneStats {
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    std::size_t materials = 0;
    std::size_t emissive_materials = 0;
    std::size_t light_triangles = 0;  // entries of the NEE light table (0 without NEE)
    std::size_t bvh_nodes = 0;        // interior nodes of the flattened BVH
    int bvh_depth = 0;
    double bvh_build_ms = 0.0;
    double upload_ms = 0.0;   // flatten + upload
    double program_ms = 0.0;  // all program builds (or cache loads)
    std::size_t scene_bytes = 0;  // device memory of the scene (BVH, shading data, lights)
};

struct DeviceScene {
    bvh::DeviceBvh bvh;
    ShadingScene shading;
    CameraData camera{};
    SceneStats stats;

    // Builds the BVH and uploads; throws wp::Error for bad scenes or too little memory.
    static DeviceScene upload(const ocl::Device& dev, const Scene& scene, const KernelConfig& config,
                              int width, int height, bool jitter);
};

}  // namespace wp::render
