#include "render/frame_state.h"

#include <algorithm>

#include "cl/profiler.h"
#include "render/memory.h"
#include "util/error.h"

namespace wp::render {

std::size_t PathPool::bytes_per_path(bool nee) {
    std::size_t b = 2 * (sizeof(Ray) + sizeof(PathState)) + sizeof(Hit) + sizeof(float4);
    if (nee) b += sizeof(Ray) + sizeof(int) + sizeof(float4);
    return b;
}

PathPool::PathPool(const ocl::Device& dev, std::size_t capacity, bool nee) : capacity_(capacity) {
    ocl::MemoryGroup group(dev, kMemoryPool);
    // The whole pool first, so that a pool too large is named as such.
    if (dev.memory) dev.memory->check_room(capacity * bytes_per_path(nee), "the path pool");
    for (auto& q : queue) {
        q.rays = ocl::Array<Ray>::allocate(dev, capacity, "the ray queue");
        q.paths = ocl::Array<PathState>::allocate(dev, capacity, "the path queue");
        q.count = ocl::Array<int>::zeros(dev, 1, "a queue length");
    }
    hits = ocl::Array<Hit>::allocate(dev, capacity, "the hit buffer");
    radiance = ocl::Array<float4>::allocate(dev, capacity, "the sample radiance");
    const std::size_t ns = nee ? capacity : 0;
    shadow.rays = ocl::Array<Ray>::allocate(dev, ns, "the shadow ray queue");
    shadow.items = ocl::Array<int>::allocate(dev, ns, "the shadow ray items");
    shadow.contrib = ocl::Array<float4>::allocate(dev, ns, "the shadow contributions");
    shadow.count = ocl::Array<int>::zeros(dev, 1, "the shadow queue length");
    bytes_ = capacity * bytes_per_path(nee);
}

FilmBuffers::FilmBuffers(const ocl::Device& dev, std::size_t pixels, bool with_variance,
                         std::size_t segment_pixels, int replicates_)
    : variance(with_variance), replicates(std::max(replicates_, 1)) {
    ocl::MemoryGroup group(dev, kMemoryFilm);
    // The whole film first, so that a film too large is named as such.
    if (dev.memory)
        dev.memory->check_room(pixels * bytes_per_pixel(variance, replicates),
                               fmt::format("the film ({} pixels)", pixels));
    // The largest buffer of a segment: its replicate sums with K > 1, else its sum.
    const std::size_t widest = sizeof(FilmPixel) * static_cast<std::size_t>(replicates > 1 ? replicates : 1);
    std::size_t seg = segment_pixels > 0 ? segment_pixels : dev.info.max_alloc / widest;
    seg = std::max<std::size_t>(seg, 1);
    // Each segment must fit one buffer. (The whole film is held to the ledger's capacity,
    // which for a CPU device sharing the host's memory is that memory, not the smaller
    // figure PoCL reports: a 16384^2 film of 8 GiB renders there; cl/memory.h.)
    dev.check_alloc(std::min(seg, pixels) * widest, "a film segment");
    for (std::size_t first = 0; first < pixels; first += seg) {
        FilmSegment s;
        s.first = first;
        s.size = std::min(seg, pixels - first);
        s.sum = ocl::Array<FilmPixel>::allocate(dev, s.size, "the film");
        if (variance) s.sum_sq = ocl::Array<FilmPixel>::allocate(dev, s.size, "the film's sum of squares");
        if (replicates > 1)
            s.replicate_sum = ocl::Array<FilmPixel>::allocate(
                dev, s.size * static_cast<std::size_t>(replicates), "the film's replicate sums");
        segments.push_back(std::move(s));
    }
    counters = ocl::Array<int>::allocate(dev, WP_COUNTER_COUNT, "the counters");
    ray_total = ocl::Array<cl_ulong>::allocate(dev, 1, "the ray total");
    shadow_ray_total = ocl::Array<cl_ulong>::allocate(dev, 1, "the shadow ray total");
    clear(dev);
}

const FilmSegment& FilmBuffers::segment_of(std::size_t p) const {
    return segment_holding(segments, p, "film");
}

void FilmBuffers::clear(const ocl::Device& dev) const {
    for (const auto& s : segments) {
        s.sum.fill_zero(dev);
        if (variance) s.sum_sq.fill_zero(dev);
        if (replicates > 1) s.replicate_sum.fill_zero(dev);
    }
    counters.fill_zero(dev);
    ray_total.fill_zero(dev);
    shadow_ray_total.fill_zero(dev);
}

std::size_t pool_capacity(const ocl::Device& dev, std::size_t pixels, std::size_t requested, bool nee,
                          std::size_t reserve, std::size_t extra_per_path) {
    const std::size_t per_path = PathPool::bytes_per_path(nee) + extra_per_path;
    const std::size_t widest = std::max(sizeof(Ray), sizeof(PathState));  // largest array element
    if (requested > 0) {
        dev.check_alloc(requested * widest, "a path pool array (--pool)");
        if (dev.memory) dev.memory->check_room(requested * per_path, "the path pool (--pool)");
        return requested;
    }
    std::size_t cap = std::min(PathPool::kDefaultCapacity, 16 * std::max<std::size_t>(pixels, 1));
    const auto budget = static_cast<std::size_t>(PathPool::kMemoryShare * double(dev.info.global_mem));
    cap = std::min(cap, budget / per_path);
    cap = std::min<std::size_t>(cap, dev.info.max_alloc / widest);
    // What is left once the scene is on the device and `reserve` bytes are kept back.
    if (dev.memory) {
        const std::uint64_t free = dev.memory->available();
        cap = std::min<std::size_t>(cap, free > reserve ? (free - reserve) / per_path : 0);
    }
    return std::max<std::size_t>(cap, ocl::kLocalSize);
}

}  // namespace wp::render

namespace wp::render {

QueueUpkeep::QueueUpkeep(const ocl::Device& dev, ocl::Profiler* profiler)
    : target_{&dev.queue, profiler}, program_(ocl::Program::build(dev, "queue.cl")),
      reset_(program_, "queue_reset", "queue.reset") {}

::cl::Event QueueUpkeep::enqueue_reset(const ocl::Array<int>& count_in, const ocl::Array<int>& count_out,
                                       const ocl::Array<int>& shadow_count,
                                       const ocl::Array<cl_ulong>& ray_total,
                                       const ocl::Array<cl_ulong>& shadow_ray_total) {
    return reset_.launch(target_, 1, count_in, count_out, shadow_count, ray_total, shadow_ray_total);
}

}  // namespace wp::render
