// intersect.h — the intersect stage (kernels/intersect.cl): closest hits of a queue.
#pragma once

#include "bvh/device_bvh.h"
#include "render/device_scene.h"
#include "render/frame_state.h"
#include "render/kernel_config.h"

namespace wp::render {

// Closest-hit traversal for the intersect stage (kernels/intersect.cl entry points).
enum class Traversal {
    Stackless,  // intersect_closest: the ordered stackless traversal (the default)
    Stack,      // intersect_closest_stack: the small-stack traversal (speed reference)
};

// "stackless" / "stack".
const char* traversal_name(Traversal t);

class IntersectStage {
  public:
    IntersectStage() = default;
    // Built with the config's trace slice (alpha cut-outs, KernelConfig::trace_options()).
    IntersectStage(const ocl::Device& dev, Traversal traversal, const KernelConfig& config,
                   ocl::Profiler* profiler = nullptr);

    // intersect_closest(_stack): hits[i] for every queued ray i < queue.count[0]. `launch`
    // bounds the queue length (the count itself is read on the device).
    // `alpha`: the texture arrays of the alpha test, when built with it (else ignored).
    ::cl::Event enqueue(std::size_t launch, const PathQueue& queue, const bvh::DeviceBvh& bvh,
                        const ocl::Array<Hit>& hits, const TextureArrays* alpha = nullptr);
    // intersect_final (stackless), the last bounce's rays where escaped rays carry no
    // radiance (final_rays_through_emitters): each ray first through `emitters` (the
    // emitting triangles' BVH, DeviceScene::emitter_bvh); a miss there is written as a miss,
    // a hit as the closest hit in `bvh` (bit for bit intersect_closest's). Profiled as
    // "intersect.final".
    ::cl::Event enqueue_final(std::size_t launch, const PathQueue& queue, const bvh::DeviceBvh& bvh,
                              const bvh::DeviceBvh& emitters, const ocl::Array<Hit>& hits,
                              const TextureArrays* alpha = nullptr);
    const ocl::Program& program() const { return program_; }

  private:
    ocl::LaunchTarget target_;
    ocl::Program program_;
    ocl::Kernel kernel_, final_;
    bool alpha_ = false;
};

}  // namespace wp::render
