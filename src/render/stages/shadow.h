// shadow.h — the shadow stage (kernels/shadow.cl): traces the light samples shade pushed
// and adds the unoccluded ones to their samples' radiance.
#pragma once

#include "bvh/device_bvh.h"
#include "render/device_scene.h"
#include "render/frame_state.h"
#include "render/kernel_config.h"

namespace wp::render {

class ShadowStage {
  public:
    ShadowStage() = default;
    // Built with the config's trace slice (alpha cut-outs, KernelConfig::trace_options()).
    ShadowStage(const ocl::Device& dev, const KernelConfig& config, ocl::Profiler* profiler = nullptr);

    // shadow_trace: for every queued shadow ray without a hit, radiance[item] += contrib
    // (the next queue_reset counts the rays).
    ::cl::Event enqueue(std::size_t launch, const ShadowQueue& shadow, const bvh::DeviceBvh& bvh,
                        const ocl::Array<float4>& radiance, const TextureArrays* alpha = nullptr);
    const ocl::Program& program() const { return program_; }

  private:
    ocl::LaunchTarget target_;
    ocl::Program program_;
    ocl::Kernel kernel_;
    bool alpha_ = false;
};

}  // namespace wp::render
