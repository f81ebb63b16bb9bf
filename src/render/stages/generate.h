// generate.h — the generate stage (kernels/generate.cl): camera rays and fresh paths for
// one wave of samples.
#pragma once

#include <cstdint>

#include "render/frame_state.h"
#include "render/kernel_config.h"

namespace wp::render {

class GenerateStage {
  public:
    GenerateStage() = default;
    // Builds generate.cl with the config's generate slice (sampler, NaN injection).
    GenerateStage(const ocl::Device& dev, const KernelConfig& config, ocl::Profiler* profiler = nullptr);

    // generate_camera: `count` samples from pixel first_pixel of sample first_sample on
    // (whole passes when first_pixel = 0, else part of one pass) into queue slots 0..count-1;
    // clears their radiance; sets queue.count to count.
    ::cl::Event enqueue(const CameraData& camera, std::uint32_t seed, int first_pixel,
                        std::uint32_t first_sample, int count, const PathQueue& queue,
                        const ocl::Array<float4>& radiance, const ocl::Array<int>& counters);
    // generate_camera_active (adaptive sampling): `count` samples over the active-pixel list
    // active[0..active_count) from list entry `first` of sample first_sample on.
    ::cl::Event enqueue_active(const CameraData& camera, std::uint32_t seed,
                               const ocl::Array<int>& active, int first, int active_count,
                               std::uint32_t first_sample, int count, const PathQueue& queue,
                               const ocl::Array<float4>& radiance, const ocl::Array<int>& counters);
    const ocl::Program& program() const { return program_; }

  private:
    std::size_t work_items(int count) const;  // the launch size for `count` items

    ocl::LaunchTarget target_;
    bool lanes_ = false;  // KernelConfig::generate_lanes
    ocl::Program program_;
    ocl::Kernel kernel_;
    ocl::Kernel active_;
};

}  // namespace wp::render
