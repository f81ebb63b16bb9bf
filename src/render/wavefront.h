// wavefront.h — the wavefront path tracer: device buffers, programs and the frame loop.
//
// One frame is one sample per pixel (DESIGN.md):
//   generate ─► [ intersect.closest ─► queue.reset ─► shade
//                 (─► intersect.shadow ─► shadow.resolve, with NEE and b < depth) ]
//               × (depth + 1) ─► accumulate
// Bounce b = 0 traces the camera rays; shade at bounce b adds emission (or background)
// and, while b < depth, scatters and pushes survivors into the other queue. So `depth` is
// the number of bounces (scattering events) a path may make: depth 0 shows emitters and
// background only, depth D gathers light that reached the camera after at most D bounces
// (as pbrt's maxdepth). Queues are launched at capacity and read their length on the
// device; the host never reads counts back inside a frame. With NEE (--sampling nee|mis and
// an emitter in the scene) shade pushes one shadow ray per light sample into the shadow
// queue; intersect_any traces them and shadow_resolve adds the stored unoccluded
// contribution to the pixel's radiance. Russian roulette (rr_depth) may end a path before
// `depth`; with the default rr_depth 3 and depth 3 it never triggers.
//
// Programs and buffers are created once in the constructor; enqueue_frame() only sets
// arguments and enqueues. Every launch is named and profiled (cl/profiler.h).
// With settings.variance the accumulate stage also sums squares into a second film
// (accumulate_film_variance); otherwise that buffer is never allocated.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include <CL/opencl.hpp>

#include "bvh/device_bvh.h"
#include "cl/device.h"
#include "cl/profiler.h"
#include "cl/program.h"
#include "image/image.h"
#include "render/film.h"
#include "render/kernel_config.h"
#include "scene/scene.h"
#include "shared/types.h"

namespace wp::render {

// Closest-hit traversal for the intersect stage (kernels/intersect.cl entry points).
enum class Traversal {
    Stackless,  // intersect_closest: the ordered stackless traversal (the default)
    Stack,      // intersect_closest_stack: the small-stack traversal (speed reference)
};

// "stackless" / "stack".
const char* traversal_name(Traversal t);

struct RenderSettings {
    int width = 800;           // pixels
    int height = 600;
    int depth = 3;             // maximum number of bounces (see above)
    std::uint32_t seed = 0;    // random stream; the same seed gives the same image
    bool jitter = true;        // random position inside each pixel (false: pixel centres)
    bool variance = false;     // also keep the per-pixel sum of squares (moments())
    Traversal traversal = Traversal::Stackless;
    // Estimator (--sampling, --glossy, --rr-depth): defaults are the best strategy.
    Sampling sampling = Sampling::Mis;
    GlossyModel glossy = GlossyModel::Ggx;
    bool sobol = true;   // --sampler sobol (the default), else the counter-based random numbers
    int rr_depth = 3;  // Russian roulette from this bounce on (< 0: off); see kernels/shade.cl
    // Debug (render --debug-nan): WP_INJECT_* stage bits (kernels/shared/types.h) whose
    // guards get a NaN for every pixel p with p % inject_period == 0; 0 compiles nothing.
    int inject_nan = 0;
    int inject_period = 97;
};

struct SceneStats {
    std::size_t triangles = 0;
    std::size_t vertices = 0;
    std::size_t materials = 0;
    std::size_t emissive_materials = 0;
    std::size_t light_triangles = 0;  // entries of the NEE light table (0 without NEE)
    std::size_t bvh_nodes = 0;  // interior nodes of the flattened BVH
    int bvh_depth = 0;
    double bvh_build_ms = 0.0;
    double upload_ms = 0.0;     // flatten + upload + buffer creation
    double program_ms = 0.0;    // all program builds (or cache loads)
};

class Wavefront {
  public:
    Wavefront(ocl::Device& dev, const Scene& scene, const RenderSettings& settings);

    // Enqueues one frame (one sample per pixel) and returns the event of its last launch.
    ::cl::Event enqueue_frame();

    // Starts over with another seed: clears the film(s), counters, ray total and profile,
    // keeping programs and scene buffers (for repeated runs of one configuration).
    void reset(std::uint32_t seed);

    int frames() const { return frames_; }
    int pixel_count() const { return settings_.width * settings_.height; }
    const RenderSettings& settings() const { return settings_; }
    const KernelConfig& config() const { return config_; }
    const std::string& options() const { return options_; }
    const SceneStats& stats() const { return stats_; }
    ocl::Profiler& profiler() { return profiler_; }
    ocl::Device& device() { return dev_; }

    // Blocking reads (call between frames, not inside the loop's hot path).
    Image resolve();                                    // film sum / frames, linear RGB
    std::array<int, WP_COUNTER_COUNT> counters();       // non-finite values per stage
    std::uint64_t rays_traced();                        // all rays traced so far
    std::vector<FilmPixel> film();                      // the raw film
    // Mean, sample variance and variance of the mean (render/film.h); needs
    // settings.variance, else throws wp::Error.
    FilmMoments moments();

  private:
    ocl::Device& dev_;
    RenderSettings settings_;
    KernelConfig config_;
    std::string options_;
    SceneStats stats_;
    ocl::Profiler profiler_;
    int frames_ = 0;

    CameraData camera_{};
    float4 background_{};
    ocl::Program generate_prog_, intersect_prog_, shade_prog_, accumulate_prog_;
    ::cl::Kernel generate_, intersect_, reset_, shade_, accumulate_;
    ::cl::Kernel shadow_trace_, shadow_resolve_;  // only with config_.nee()
    // Scene.
    bvh::DeviceBvh bvh_;
    ::cl::Buffer tris_, material_ids_, materials_;
    // NEE light table (scene/upload.h LightTable); 16-byte placeholders without NEE.
    ::cl::Buffer light_cdf_, light_prims_, light_pdf_area_;
    // Wavefront state: two ray/path queues with their lengths, hits, per-pixel radiance.
    ::cl::Buffer rays_[2], paths_[2], count_[2], hits_, radiance_;
    // Shadow queue (rays, their pixels, length) and per-pixel unoccluded contributions;
    // sized for one path per pixel with NEE, placeholders otherwise.
    ::cl::Buffer shadow_rays_, shadow_pixels_, shadow_count_, shadow_contrib_;
    ::cl::Buffer film_, counters_, ray_total_;
    ::cl::Buffer film_sq_;  // sum of squares; allocated only with settings.variance
};

}  // namespace wp::render
