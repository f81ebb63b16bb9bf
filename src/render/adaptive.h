// adaptive.h — adaptive sampling and the image's error estimate (render --adaptive,
// --target-error): the list of pixels still sampled and each pixel's estimated relMSE.
//
// Per-pixel estimate (kernels/shared/adaptive.h): e_p = (1/3) Σ_c (s_c² / n_p) / (m_c² +
// eps), eps = 1e-2 (the relMSE tool's, image/image.h), from the film's sum and sum of
// squares. The image's estimated relMSE is the mean of e_p over all pixels: the expected
// relMSE of the image against the true one, with the noisy means in place of the reference
// and without a reference.
//
// Adaptive sampling (Dammertz-style stopping, with the relMSE criterion above): every pixel
// is sampled until it has AdaptiveSettings::min_spp samples; from then on the active list is
// checked at the passes min_spp, then every max(kAdaptiveMinInterval, spp /
// kAdaptiveIntervalDivisor) passes (limits.h), and a pixel leaves the list for good when the
// largest e over its 3x3 neighbourhood (itself included; stopped neighbours count with the
// estimate they stopped with) is <= threshold. The neighbourhood guards against the classic
// failure of per-pixel stopping: a pixel whose samples have not yet met a rare bright path
// (a caustic, a small light in a glossy plate) has a small variance estimate and would stop
// with a large error; its neighbours, which see the same light, usually have met it
// (measured in docs/adaptive.md: without it, equal-time relMSE on the veach plates got worse
// than without adaptive sampling). The wavefront generates paths only for the listed pixels
// (generate_camera_active, accumulate_film_active), so all listed pixels always have the same
// count (the passes so far), and a stopped pixel keeps the count it had when it stopped. The
// film is resolved with each pixel's own count: a pixel's estimate stays the mean of its own
// samples, which are exactly those of the render without adaptive sampling (same sample
// indices, same random numbers). The stopping rule reads the samples, so "unbiased" is per
// sample, not per stopping time: a pixel that happens to look converged early stops with that
// estimate (the usual caveat of sequential stopping; the min spp bounds it, and the z-tests
// of tests/test_adaptive.cpp find no bias at their level).
//
// RQMC replicates (RenderSettings::replicates = K > 1; kernels/shared/adaptive.h): the
// image's estimate is the mean of the pixels' replicate estimates instead (the variance of
// a pixel's mean from the spread of its K replicate means), which holds for Sobol points
// where s² / n overstates it; the per-pixel stopping rule of adaptive sampling keeps s² / n
// (with K - 1 degrees of freedom a pixel's replicate estimate is too noisy to stop on).
//
// Host side: the list is sorted by pixel id (the host compacts it), so the list entries of a
// film segment are one range.
#pragma once

#include <cstddef>
#include <vector>

#include "cl/kernel.h"
#include "render/frame_state.h"
#include "render/kernel_config.h"

namespace wp::render {

// The kernel adaptive_error (kernels/adaptive.cl).
class AdaptiveStage {
  public:
    AdaptiveStage() = default;
    AdaptiveStage(const ocl::Device& dev, ocl::Profiler* profiler = nullptr);
    // error[first + k] = the estimated relMSE of pixel active[first + k], k < count, of the
    // film segment (which must keep the sum of squares), after `samples` samples.
    ::cl::Event enqueue(const ocl::Array<int>& active, int first, int count,
                        const FilmSegment& segment, int samples, float eps,
                        const ocl::Array<float>& error);
    // adaptive_error_replicates: the same, and image_error[first + k] from the segment's
    // `replicates` replicate sums.
    ::cl::Event enqueue_replicates(const ocl::Array<int>& active, int first, int count,
                                   const FilmSegment& segment, int replicates, int samples,
                                   float eps, const ocl::Array<float>& error,
                                   const ocl::Array<float>& image_error);
    const ocl::Program& program() const { return program_; }

  private:
    ocl::LaunchTarget target_;
    ocl::Program program_;
    ocl::Kernel kernel_;
    ocl::Kernel replicates_;
};

// The active-pixel list, on the host and the device, and the per-pixel error estimates.
class ActivePixels {
  public:
    static constexpr std::size_t kBytesPerPixel = sizeof(int) + sizeof(float);  // list, error
    // With K > 1 replicates also the replicate estimate (a float per pixel).
    static std::size_t bytes_per_pixel(int replicates) {
        return kBytesPerPixel + (replicates > 1 ? sizeof(float) : 0);
    }

    ActivePixels() = default;
    // Every pixel active; the list and the error buffer on the device (film memory group);
    // with replicates > 1 also the buffer of the replicate estimates.
    ActivePixels(const ocl::Device& dev, int width, int height, ocl::Profiler* profiler,
                 int replicates = 1);

    std::size_t count() const { return list_.size(); }
    const std::vector<int>& list() const { return list_; }
    const ocl::Array<int>& device_list() const { return device_list_; }
    // List entries [begin, end) of the pixels of film segment `seg`.
    std::pair<std::size_t, std::size_t> range(const FilmSegment& seg) const;
    // Samples of pixel p when the listed pixels have `passes`.
    int samples(std::size_t p, int passes) const { return stopped_at_[p] ? stopped_at_[p] : passes; }
    // Every pixel's sample count.
    std::vector<int> sample_counts(int passes) const;
    // Recomputes the error of every listed pixel (they have `passes` samples) on the device
    // and reads it back; stopped pixels keep the error they stopped with.
    void refresh(const ocl::Device& dev, const FilmBuffers& film, int passes);
    // Drops the listed pixels whose 3x3 neighbourhood's largest error is <= threshold (they
    // keep `passes` samples) and uploads the shorter list. Call after refresh(). Returns the
    // pixels dropped.
    std::size_t drop_converged(const ocl::Device& dev, double threshold, int passes);
    // Mean of the per-pixel errors: the image's estimated relMSE (after refresh()); with
    // replicates, of the replicate estimates.
    double mean_error() const;
    // The per-pixel estimates adaptive stopping reads (s² / n).
    const std::vector<float>& errors() const { return error_; }
    // The per-pixel estimates the image's estimate averages (the replicates' with K > 1).
    const std::vector<float>& image_errors() const { return replicates_ > 1 ? image_error_ : error_; }
    const ocl::Program& program() const { return stage_.program(); }
    // Every pixel active again (Wavefront::reset).
    void reset(const ocl::Device& dev);

  private:
    AdaptiveStage stage_;
    int width_ = 0, height_ = 0;
    int replicates_ = 1;
    std::vector<int> list_;        // active pixel ids, ascending
    std::vector<int> stopped_at_;  // per pixel: samples when it stopped; 0 = active
    std::vector<float> error_;     // per pixel: the latest estimate
    ocl::Array<int> device_list_;  // the list (first count() entries valid)
    ocl::Array<float> device_error_;  // per list entry
    std::vector<float> image_error_;        // per pixel, replicates > 1: the replicate estimate
    ocl::Array<float> device_image_error_;  // per list entry, replicates > 1
};

}  // namespace wp::render
