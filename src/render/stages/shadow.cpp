#include "render/stages/shadow.h"

namespace wp::render {

ShadowStage::ShadowStage(const ocl::Device& dev, ocl::Profiler* profiler)
    : target_{&dev.queue, profiler}, program_(ocl::Program::build(dev, "shadow.cl")),
      kernel_(program_, "shadow_trace", "shadow") {}

::cl::Event ShadowStage::enqueue(std::size_t launch, const ShadowQueue& shadow,
                                 const bvh::DeviceBvh& bvh, const ocl::Array<float4>& radiance,
                                 const ocl::Array<cl_ulong>& ray_total) {
    return kernel_.launch(target_, launch, shadow.rays, shadow.items, shadow.contrib, shadow.count,
                          bvh.nodes, bvh.links, bvh.triangles, bvh.prim_ids, radiance, ray_total);
}

}  // namespace wp::render
