// accumulate.h — the accumulate stage (kernels/accumulate.cl): a wave's sample radiance
// into the film, in sample order per pixel.
#pragma once

#include <cstdint>

#include "render/frame_state.h"
#include "render/kernel_config.h"

namespace wp::render {

class AccumulateStage {
  public:
    AccumulateStage() = default;
    // With variance the film's sum of squares is kept too (accumulate_film_variance); with
    // replicates > 1 (which needs variance) also the replicate sums
    // (accumulate_film_replicates, accumulate_film_active_replicates).
    AccumulateStage(const ocl::Device& dev, const KernelConfig& config, bool variance,
                    ocl::Profiler* profiler = nullptr, int replicates = 1);

    // accumulate_film(_variance): adds radiance[0..count) of a wave that starts at pixel
    // first_pixel (generate.cl) to the film segment's sum (and sum of squares); the wave
    // lies inside the segment. first_sample: the wave's first sample index (the replicates').
    ::cl::Event enqueue(const ocl::Array<float4>& radiance, int first_pixel, int count,
                        int pixel_count, const FilmSegment& segment,
                        const ocl::Array<int>& counters, std::uint32_t first_sample = 0);
    // accumulate_film_active (adaptive sampling): the same for a wave over the active list
    // (GenerateStage::enqueue_active); every listed pixel of the wave lies inside the
    // segment, which must keep the sum of squares.
    ::cl::Event enqueue_active(const ocl::Array<float4>& radiance, const ocl::Array<int>& active,
                               int first, int count, int active_count, const FilmSegment& segment,
                               const ocl::Array<int>& counters, std::uint32_t first_sample = 0);
    const ocl::Program& program() const { return program_; }

  private:
    ocl::LaunchTarget target_;
    ocl::Program program_;
    ocl::Kernel kernel_;
    ocl::Kernel active_;
    bool variance_ = false;
    int replicates_ = 1;
};

}  // namespace wp::render
