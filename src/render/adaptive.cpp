#include "render/adaptive.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "render/memory.h"
#include "shared/adaptive.h"
#include "util/error.h"

namespace wp::render {

AdaptiveStage::AdaptiveStage(const ocl::Device& dev, ocl::Profiler* profiler)
    : target_{&dev.queue, profiler},
      program_(ocl::Program::build(dev, "adaptive.cl")),
      kernel_(program_, "adaptive_error", "adaptive.error"),
      replicates_(program_, "adaptive_error_replicates", "adaptive.error") {}

::cl::Event AdaptiveStage::enqueue(const ocl::Array<int>& active, int first, int count,
                                   const FilmSegment& segment, int samples, float eps,
                                   const ocl::Array<float>& error) {
    if (segment.sum_sq.size == 0) fail("adaptive: the error estimate needs a film with a sum of squares");
    return kernel_.launch(target_, static_cast<std::size_t>(count), active, cl_int(first),
                          cl_int(count), cl_int(segment.first), segment.sum, segment.sum_sq,
                          cl_int(samples), eps, error);
}

::cl::Event AdaptiveStage::enqueue_replicates(const ocl::Array<int>& active, int first, int count,
                                              const FilmSegment& segment, int replicates,
                                              int samples, float eps, const ocl::Array<float>& error,
                                              const ocl::Array<float>& image_error) {
    if (segment.sum_sq.size == 0) fail("adaptive: the error estimate needs a film with a sum of squares");
    if (segment.replicate_sum.size != segment.size * std::size_t(replicates))
        fail("adaptive: the film segment has no sums for {} replicates", replicates);
    return replicates_.launch(target_, static_cast<std::size_t>(count), active, cl_int(first),
                              cl_int(count), cl_int(segment.first), segment.sum, segment.sum_sq,
                              segment.replicate_sum, cl_int(replicates), cl_int(samples), eps,
                              error, image_error);
}

ActivePixels::ActivePixels(const ocl::Device& dev, int width, int height, ocl::Profiler* profiler,
                           int replicates)
    : stage_(dev, profiler), width_(width), height_(height), replicates_(std::max(replicates, 1)) {
    const auto pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    ocl::MemoryGroup group(dev, kMemoryFilm);
    device_list_ = ocl::Array<int>::allocate(dev, pixels, "the active-pixel list");
    device_error_ = ocl::Array<float>::allocate(dev, pixels, "the per-pixel error estimates");
    if (replicates_ > 1)
        device_image_error_ =
            ocl::Array<float>::allocate(dev, pixels, "the per-pixel replicate error estimates");
    stopped_at_.assign(pixels, 0);
    reset(dev);
}

void ActivePixels::reset(const ocl::Device& dev) {
    const std::size_t n = stopped_at_.size();
    list_.resize(n);
    std::iota(list_.begin(), list_.end(), 0);
    std::fill(stopped_at_.begin(), stopped_at_.end(), 0);
    error_.assign(n, std::numeric_limits<float>::infinity());
    if (replicates_ > 1) image_error_.assign(n, std::numeric_limits<float>::infinity());
    device_list_.write(dev, list_);
}

std::pair<std::size_t, std::size_t> ActivePixels::range(const FilmSegment& seg) const {
    auto lo = std::lower_bound(list_.begin(), list_.end(), static_cast<long long>(seg.first),
                               [](int a, long long b) { return a < b; });
    auto hi = std::lower_bound(lo, list_.end(), static_cast<long long>(seg.first + seg.size),
                               [](int a, long long b) { return a < b; });
    return {static_cast<std::size_t>(lo - list_.begin()), static_cast<std::size_t>(hi - list_.begin())};
}

std::vector<int> ActivePixels::sample_counts(int passes) const {
    std::vector<int> c(stopped_at_.size());
    for (std::size_t p = 0; p < c.size(); ++p) c[p] = samples(p, passes);
    return c;
}

void ActivePixels::refresh(const ocl::Device& dev, const FilmBuffers& film, int passes) {
    if (list_.empty()) return;
    for (const FilmSegment& seg : film.segments) {
        auto [b, e] = range(seg);
        if (b >= e) continue;
        if (replicates_ > 1)
            stage_.enqueue_replicates(device_list_, static_cast<int>(b), static_cast<int>(e - b), seg,
                                      replicates_, passes, WP_RELMSE_EPS, device_error_,
                                      device_image_error_);
        else
            stage_.enqueue(device_list_, static_cast<int>(b), static_cast<int>(e - b), seg, passes,
                           WP_RELMSE_EPS, device_error_);
    }
    std::vector<float> err = device_error_.read(dev, 0, list_.size());
    for (std::size_t k = 0; k < list_.size(); ++k) error_[static_cast<std::size_t>(list_[k])] = err[k];
    if (replicates_ > 1) {
        std::vector<float> ie = device_image_error_.read(dev, 0, list_.size());
        for (std::size_t k = 0; k < list_.size(); ++k)
            image_error_[static_cast<std::size_t>(list_[k])] = ie[k];
    }
}

std::size_t ActivePixels::drop_converged(const ocl::Device& dev, double threshold, int passes) {
    const std::size_t before = list_.size();
    std::size_t kept = 0;
    // The largest error over the 3x3 neighbourhood of pixel p (clipped at the borders).
    auto neighbourhood = [&](int p) {
        const int y = p / width_, x = p - y * width_;
        float e = 0.0f;
        for (int yy = std::max(0, y - 1); yy <= std::min(height_ - 1, y + 1); ++yy)
            for (int xx = std::max(0, x - 1); xx <= std::min(width_ - 1, x + 1); ++xx)
                e = std::max(e, error_[static_cast<std::size_t>(yy) * width_ + xx]);
        return e;
    };
    // Decide on the errors as refreshed (the list is compacted in place, so decide first).
    std::vector<char> stop(list_.size());
    for (std::size_t k = 0; k < list_.size(); ++k) stop[k] = neighbourhood(list_[k]) <= threshold;
    for (std::size_t k = 0; k < stop.size(); ++k) {
        const int p = list_[k];
        if (stop[k])
            stopped_at_[static_cast<std::size_t>(p)] = passes;
        else
            list_[kept++] = p;
    }
    list_.resize(kept);
    if (kept < before && kept > 0)
        dev.queue.enqueueWriteBuffer(device_list_.buffer, CL_TRUE, 0, kept * sizeof(int), list_.data());
    return before - kept;
}

double ActivePixels::mean_error() const {
    const std::vector<float>& errors = image_errors();
    double s = 0.0;
    for (float e : errors) s += e;
    return errors.empty() ? 0.0 : s / static_cast<double>(errors.size());
}

}  // namespace wp::render
