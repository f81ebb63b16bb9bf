// denoise.h — the denoise stage (kernels/denoise.cl): an edge-avoiding à-trous wavelet
// filter (Dammertz et al. 2010) guided by the feature buffers (render/aov.h) and the
// film's per-pixel variance (SVGF, Schied et al. 2017). docs/denoise.md.
//
// The input is a finished render on the host (its mean, its variance of the mean, its
// AOVs); the output is the denoised mean. The result is biased (it borrows neighbours'
// samples): error figures of a denoised image are not Monte Carlo errors, and the z-tests
// (image/stats.h, `compare --variance`) are for unbiased images only.
#pragma once

#include "cl/device.h"
#include "cl/kernel.h"
#include "image/image.h"
#include "render/aov.h"
#include "util/limits.h"

namespace wp::render {

struct DenoiseSettings {
    int iterations = limits::kDenoiseIterations; // à-trous steps 1, 2, 4, ..., 2^(iterations-1)
    float sigma_luminance = limits::kDenoiseSigmaLuminance;
    int normal_power = limits::kDenoiseNormalPower; // a power of two, 1..2^30
    float sigma_depth = limits::kDenoiseSigmaDepth;
    float sigma_albedo = limits::kDenoiseSigmaAlbedo;
    float min_albedo = limits::kDenoiseMinAlbedo;
    // Energy restore (kernels/denoise.cl, denoise_combine): à-trous iterations over the
    // filter's residual with the guides alone; 0: none.
    int restore_iterations = limits::kDenoiseRestoreIterations;
};

class Denoiser {
  public:
    Denoiser() = default;
    // Builds denoise.cl. Launches are profiled as denoise.prepare, denoise.atrous,
    // denoise.combine and denoise.finish when a profiler is given.
    explicit Denoiser(ocl::Device& dev, ocl::Profiler* profiler = nullptr);

    // The denoised image of `color` (the noisy mean), `variance` (its variance of the
    // mean per channel: FilmMoments::mean_variance) and `aov` (all three AOVs), all of one
    // size. Throws wp::Error when the sizes differ or a setting is out of range. Blocking;
    // allocates its device buffers (8 float4 per pixel) for the call only.
    Image run(const Image& color, const Image& variance, const AovImages& aov,
              const DenoiseSettings& settings = {});
    const ocl::Program& program() const { return program_; }
    // Device time of the last run's launches (prepare, iterations, finish), from their
    // OpenCL profiling events; the host's packing, upload and read-back are not in it.
    double last_device_ms() const { return device_ms_; }

  private:
    ocl::Device* dev_ = nullptr;
    ocl::LaunchTarget target_;
    ocl::Program program_;
    ocl::Kernel prepare_, atrous_, combine_, finish_;
    double device_ms_ = 0.0;
};

}  // namespace wp::render
