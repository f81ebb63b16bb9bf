#include "render/stages/shade.h"

namespace wp::render {

ShadeStage::ShadeStage(const ocl::Device& dev, const KernelConfig& config, ocl::Profiler* profiler)
    : target_{&dev.queue, profiler},
      program_(ocl::Program::build(dev, "shade.cl", config.shade_options())),
      kernel_(program_, "shade_surface", "shade") {}

::cl::Event ShadeStage::enqueue(std::size_t launch, const PathQueue& in, const ocl::Array<Hit>& hits,
                                const ShadingScene& scene, std::uint32_t seed, int bounce,
                                int max_depth, const ocl::Array<float4>& radiance,
                                const ocl::Array<int>& counters, const PathQueue& out,
                                const ShadowQueue& shadow) {
    return kernel_.launch(target_, launch, in.rays, in.paths, in.count, hits, scene.tris,
                          scene.material_ids, scene.materials, scene.background, scene.light_cdf,
                          scene.light_prims, scene.light_pdf_area, cl_int(scene.light_count),
                          cl_uint(seed), cl_int(bounce), cl_int(max_depth), radiance, counters,
                          out.rays, out.paths, out.count, shadow.rays, shadow.items,
                          shadow.contrib, shadow.count);
}

}  // namespace wp::render
