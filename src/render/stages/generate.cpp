#include "render/stages/generate.h"

namespace wp::render {

std::size_t GenerateStage::work_items(int count) const {
    const auto n = static_cast<std::size_t>(count);
    return lanes_ ? (n + 7) / 8 : n;  // WP_GENERATE_LANES: eight items per work-item
}

GenerateStage::GenerateStage(const ocl::Device& dev, const KernelConfig& config, ocl::Profiler* profiler)
    : target_{&dev.queue, profiler},
      lanes_(config.generate_lanes),
      program_(ocl::Program::build(dev, "generate.cl", config.generate_options())),
      kernel_(program_, "generate_camera", "generate"),
      active_(program_, "generate_camera_active", "generate") {}

::cl::Event GenerateStage::enqueue(const CameraData& camera, std::uint32_t seed, int first_pixel,
                                   std::uint32_t first_sample, int count, const PathQueue& queue,
                                   const ocl::Array<float4>& radiance, const ocl::Array<int>& counters) {
    return kernel_.launch(target_, work_items(count), camera, cl_uint(seed),
                          cl_int(first_pixel), cl_uint(first_sample), cl_int(count), queue.rays,
                          queue.paths, radiance, queue.count, counters);
}

::cl::Event GenerateStage::enqueue_active(const CameraData& camera, std::uint32_t seed,
                                          const ocl::Array<int>& active, int first, int active_count,
                                          std::uint32_t first_sample, int count, const PathQueue& queue,
                                          const ocl::Array<float4>& radiance,
                                          const ocl::Array<int>& counters) {
    return active_.launch(target_, work_items(count), camera, cl_uint(seed), active,
                          cl_int(first), cl_int(active_count), cl_uint(first_sample), cl_int(count),
                          queue.rays, queue.paths, radiance, queue.count, counters);
}

}  // namespace wp::render
