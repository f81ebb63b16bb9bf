#include "render/stages/accumulate.h"

#include <algorithm>

#include "util/error.h"

namespace wp::render {

namespace {
const char* plain_kernel(bool variance, int replicates) {
    return replicates > 1 ? "accumulate_film_replicates"
           : variance     ? "accumulate_film_variance"
                          : "accumulate_film";
}
}  // namespace

AccumulateStage::AccumulateStage(const ocl::Device& dev, const KernelConfig& config, bool variance,
                                 ocl::Profiler* profiler, int replicates)
    : target_{&dev.queue, profiler},
      program_(ocl::Program::build(dev, "accumulate.cl", config.accumulate_options())),
      kernel_(program_, plain_kernel(variance, replicates), "accumulate"),
      active_(program_, replicates > 1 ? "accumulate_film_active_replicates" : "accumulate_film_active",
              "accumulate"),
      variance_(variance), replicates_(replicates) {
    if (replicates > 1 && !variance) fail("accumulate: replicates need the film's sum of squares");
}

::cl::Event AccumulateStage::enqueue(const ocl::Array<float4>& radiance, int first_pixel, int count,
                                     int pixel_count, const FilmSegment& segment,
                                     const ocl::Array<int>& counters, std::uint32_t first_sample) {
    const auto items = static_cast<std::size_t>(std::min(count, pixel_count));
    const auto first = static_cast<std::size_t>(first_pixel);
    if (first < segment.first || first + items > segment.first + segment.size)
        fail("accumulate: pixels {} to {} are not inside the film segment {} to {}", first,
             first + items, segment.first, segment.first + segment.size);
    if (!variance_)
        return kernel_.launch(target_, items, radiance, cl_int(first_pixel), cl_int(count),
                              cl_int(pixel_count), cl_int(segment.first), segment.sum, counters);
    if (segment.sum_sq.size == 0) fail("accumulate: the variance kernel needs a film with a sum of squares");
    if (replicates_ > 1) {
        if (segment.replicate_sum.size != segment.size * std::size_t(replicates_))
            fail("accumulate: the film segment has no sums for {} replicates", replicates_);
        return kernel_.launch(target_, items, radiance, cl_int(first_pixel), cl_int(count),
                              cl_int(pixel_count), cl_int(segment.first), segment.sum, counters,
                              segment.sum_sq, segment.replicate_sum, cl_uint(first_sample),
                              cl_int(replicates_));
    }
    return kernel_.launch(target_, items, radiance, cl_int(first_pixel), cl_int(count),
                          cl_int(pixel_count), cl_int(segment.first), segment.sum, counters,
                          segment.sum_sq);
}

::cl::Event AccumulateStage::enqueue_active(const ocl::Array<float4>& radiance,
                                            const ocl::Array<int>& active, int first, int count,
                                            int active_count, const FilmSegment& segment,
                                            const ocl::Array<int>& counters, std::uint32_t first_sample) {
    if (segment.sum_sq.size == 0) fail("accumulate: adaptive sampling needs a film with a sum of squares");
    const auto items = static_cast<std::size_t>(std::min(count, active_count));
    if (replicates_ > 1) {
        if (segment.replicate_sum.size != segment.size * std::size_t(replicates_))
            fail("accumulate: the film segment has no sums for {} replicates", replicates_);
        return active_.launch(target_, items, radiance, active, cl_int(first), cl_int(count),
                              cl_int(active_count), cl_int(segment.first), segment.sum, counters,
                              segment.sum_sq, segment.replicate_sum, cl_uint(first_sample),
                              cl_int(replicates_));
    }
    return active_.launch(target_, items, radiance, active, cl_int(first), cl_int(count),
                          cl_int(active_count), cl_int(segment.first), segment.sum, counters,
                          segment.sum_sq);
}

}  // namespace wp::render
