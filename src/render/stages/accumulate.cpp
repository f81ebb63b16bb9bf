#include "render/stages/accumulate.h"

#include <algorithm>

#include "util/error.h"

namespace wp::render {

AccumulateStage::AccumulateStage(const ocl::Device& dev, const KernelConfig& config, bool variance,
                                 ocl::Profiler* profiler)
    : target_{&dev.queue, profiler},
      program_(ocl::Program::build(dev, "accumulate.cl", config.accumulate_options())),
      kernel_(program_, variance ? "accumulate_film_variance" : "accumulate_film", "accumulate"),
      variance_(variance) {}

::cl::Event AccumulateStage::enqueue(const ocl::Array<float4>& radiance, int first_pixel, int count,
                                     int pixel_count, const FilmBuffers& film) {
    const auto items = static_cast<std::size_t>(std::min(count, pixel_count));
    if (!variance_)
        return kernel_.launch(target_, items, radiance, cl_int(first_pixel), cl_int(count),
                              cl_int(pixel_count), film.sum, film.counters);
    if (!film.variance) fail("accumulate: the variance kernel needs a film with a sum of squares");
    return kernel_.launch(target_, items, radiance, cl_int(first_pixel), cl_int(count),
                          cl_int(pixel_count), film.sum, film.counters, film.sum_sq);
}

}  // namespace wp::render
