// frame_state.h — the buffers a render works in: the path pool (queues, hits, per-sample
// radiance, the shadow queue), the film and the counters.
//
// The pool holds a fixed number of paths in flight (`capacity`), whatever the image size:
// the renderer runs the samples of a render in waves of at most `capacity` samples
// (render/wavefront.h), so memory is film + pool + scene, and an 8192² or 16384² image
// needs no more pool than a small one. Every array of the pool is indexed by queue slot or
// by the sample's item in its wave, both below `capacity`.
//
// Bytes per pooled path (PathPool::bytes_per_path): two ray queues and two path queues
// (ping-pong between bounces, 2 x (32 + 32)), the hit of each ray (16), the sample's
// radiance (16) and, with next-event estimation, one shadow ray with its item and
// contribution (32 + 4 + 16): 212 bytes with NEE, 160 without. Bytes per film pixel: 32
// (the double-float sum), 64 with --variance (the sum of squares too), and 32 more per RQMC
// replicate with K > 1 replicates (one double-float sum per replicate; docs/adaptive.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "cl/kernel.h"
#include "shared/types.h"
#include "util/error.h"

namespace wp::render {

// A queue of paths: rays[i] and paths[i] for i < count[0] (the length lives on the device).
struct PathQueue {
    ocl::Array<Ray> rays;
    ocl::Array<PathState> paths;
    ocl::Array<int> count;  // one element
};

// The shadow rays shade pushes with next-event estimation (kernels/shadow.cl).
struct ShadowQueue {
    ocl::Array<Ray> rays;        // segments to the light points, hits need 0 < t < dir.w
    ocl::Array<int> items;       // the sample each ray belongs to
    ocl::Array<float4> contrib;  // its unoccluded contribution
    ocl::Array<int> count;       // one element
};

class PathPool {
  public:
    // Largest pool chosen automatically: 2^20 paths (212 MiB with NEE).
    static constexpr std::size_t kDefaultCapacity = std::size_t(1) << 20;
    // The pool takes at most this share of the device's memory when sized automatically.
    static constexpr double kMemoryShare = 0.25;

    static std::size_t bytes_per_path(bool nee);

    PathPool() = default;
    // capacity paths; the shadow queue only with nee (else placeholders).
    PathPool(const ocl::Device& dev, std::size_t capacity, bool nee);

    std::size_t capacity() const { return capacity_; }
    std::size_t bytes() const { return bytes_; }

    PathQueue queue[2];          // bounce b reads queue[b & 1] and pushes into the other
    ocl::Array<Hit> hits;        // closest hit of each queued ray (slot order)
    ocl::Array<float4> radiance; // per item of the wave: the sample's radiance so far
    ShadowQueue shadow;

  private:
    std::size_t capacity_ = 0;
    std::size_t bytes_ = 0;
};

// Pixels [first, first + size) of the film in one buffer (and its sum of squares).
// The segment of `segments` (each with `first` and `size`, in pixel order) that holds
// pixel p; throws wp::Error naming `what` when none does. The film's and the AOVs'.
template <typename Segment>
const Segment& segment_holding(const std::vector<Segment>& segments, std::size_t p, const char* what) {
    for (const auto& s : segments)
        if (p < s.first + s.size) return s;
    fail("pixel {} is outside the {}", p, what);
}

struct FilmSegment {
    std::size_t first = 0, size = 0;
    ocl::Array<FilmPixel> sum;
    ocl::Array<FilmPixel> sum_sq;  // allocated only with variance
    // RQMC replicates (K > 1 only, else empty): size * K sums, pixel f's replicate r at
    // [f * K + r], the samples s with s mod K == r (kernels/accumulate.cl).
    ocl::Array<FilmPixel> replicate_sum;
};

// The film: running sums per pixel (and of squares with variance), the NaN/Inf counters
// per stage and the totals of rays traced (closest hit and shadow). A device caps one buffer (PoCL: 2 GiB, 67M
// pixels), so the film is cut into segments of at most that; a wave never straddles two
// (Wavefront::render_passes), and one segment holds any image that fits the pool.
struct FilmBuffers {
    std::vector<FilmSegment> segments;
    ocl::Array<int> counters;        // WP_COUNTER_COUNT
    ocl::Array<cl_ulong> ray_total;         // one element: closest-hit rays (queue_reset)
    ocl::Array<cl_ulong> shadow_ray_total;  // one element: shadow rays (queue_reset)
    bool variance = false;
    int replicates = 1;  // RQMC replicates K (a power of two); > 1: replicate_sum per segment

    FilmBuffers() = default;
    // segment_pixels: pixels per segment; 0 = the most one buffer of the device holds (the
    // replicate sums, K times larger, included).
    FilmBuffers(const ocl::Device& dev, std::size_t pixels, bool variance,
                std::size_t segment_pixels = 0, int replicates = 1);
    static std::size_t bytes_per_pixel(bool variance, int replicates = 1) {
        return sizeof(FilmPixel) * ((variance ? 2 : 1) + (replicates > 1 ? replicates : 0));
    }
    // The segment that holds pixel p.
    const FilmSegment& segment_of(std::size_t p) const;
    // Zeroes the sums, counters and ray total (enqueued).
    void clear(const ocl::Device& dev) const;
};

// The pool capacity for a render of `pixels` pixels: `requested` when > 0, else the smallest
// of kDefaultCapacity, 16 passes of the image, what the device's memory share holds and what
// its free memory holds after keeping `reserve` bytes back (the film, allocated after the
// pool); at least one work-group. `extra_per_path`: bytes per path of other arrays sized by
// the pool (the AOV items, AovBuffers::kBytesPerPath), counted with the pool's own. Throws
// wp::Error when a requested pool does not fit.
std::size_t pool_capacity(const ocl::Device& dev, std::size_t pixels, std::size_t requested, bool nee,
                          std::size_t reserve = 0, std::size_t extra_per_path = 0);

}  // namespace wp::render

namespace wp::render {

// Queue upkeep between intersect and shade (kernels/queue.cl), owned with the queues.
class QueueUpkeep {
  public:
    QueueUpkeep() = default;
    QueueUpkeep(const ocl::Device& dev, ocl::Profiler* profiler);
    // queue_reset: ray_total += count_in; shadow_ray_total += shadow_count (the previous
    // bounce's shadow rays); count_out = 0; shadow_count = 0 (one work-item).
    ::cl::Event enqueue_reset(const ocl::Array<int>& count_in, const ocl::Array<int>& count_out,
                              const ocl::Array<int>& shadow_count, const ocl::Array<cl_ulong>& ray_total,
                              const ocl::Array<cl_ulong>& shadow_ray_total);
    const ocl::Program& program() const { return program_; }

  private:
    ocl::LaunchTarget target_;
    ocl::Program program_;
    ocl::Kernel reset_;
};

}  // namespace wp::render
