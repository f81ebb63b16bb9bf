#include "render/stages/shadow.h"

#include "util/error.h"

namespace wp::render {

ShadowStage::ShadowStage(const ocl::Device& dev, const KernelConfig& config, ocl::Profiler* profiler)
    : target_{&dev.queue, profiler},
      program_(ocl::Program::build(dev, "shadow.cl", config.trace_options())),
      kernel_(program_, "shadow_trace", "shadow"), alpha_(config.alpha_mask) {}

::cl::Event ShadowStage::enqueue(std::size_t launch, const ShadowQueue& shadow,
                                 const bvh::DeviceBvh& bvh, const ocl::Array<float4>& radiance,
                                 const TextureArrays* alpha) {
    if (alpha_) {
        if (!alpha) fail("shadow: built with alpha cut-outs but launched without their textures");
        return kernel_.launch(target_, launch, shadow.rays, shadow.items, shadow.contrib, shadow.count,
                              bvh.nodes, bvh.links, bvh.triangles, bvh.prim_ids, radiance,
                              alpha->material_ids, alpha->material_textures, alpha->tri_uvs,
                              alpha->textures, alpha->views, alpha->texels8, alpha->texelsf);
    }
    return kernel_.launch(target_, launch, shadow.rays, shadow.items, shadow.contrib, shadow.count,
                          bvh.nodes, bvh.links, bvh.triangles, bvh.prim_ids, radiance);
}

}  // namespace wp::render
