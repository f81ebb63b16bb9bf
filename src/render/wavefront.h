// wavefront.h — the wavefront path tracer: the scene on the device, the path pool, the
// five stages and the loop over waves and bounces.
//
// The samples of a render are the sequence s = sample * pixels + pixel. They run in waves
// of at most the pool's capacity (render/frame_state.h): a wave is k whole passes (every
// pixel k more samples) when the image fits the pool k times, else a part of one pass.
// One wave is, as in pbrt-v4's wavefront integrator (wavefront/integrator.cpp, Render()):
//
//   generate ─► [ intersect ─► queue.reset ─► shade (─► shadow, with NEE and b < depth) ]
//               for bounce b = 0, 1, ... while the queue is not empty and b <= depth
//            ─► accumulate
//
// Bounce b = 0 traces the camera rays; shade at bounce b adds emission (or background)
// and, while b < depth, scatters and pushes survivors into the other queue. So `depth` is
// the number of bounces (scattering events) a path may make: depth 0 shows emitters and
// background only, depth D gathers light that reached the camera after at most D bounces
// (as pbrt's maxdepth). Queues are launched at a bound of their length and read it on the
// device; the host reads each bounce's surviving count back one bounce late (a 4-byte
// read the device does not wait for), to end the wave when the queue is empty and to
// shrink later launches to what is left. Every path of a wave is at the same bounce.
//
// Results are the same bits whatever the pool size: a sample's random numbers depend only
// on (seed, pixel, sample, bounce), its radiance has its own slot, and accumulate adds
// the samples of each pixel in sample order (kernels/accumulate.cl).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <CL/opencl.hpp>

#include "cl/device.h"
#include "cl/profiler.h"
#include "image/image.h"
#include "render/adaptive.h"
#include "render/aov.h"
#include "render/device_scene.h"
#include "render/film.h"
#include "render/frame_state.h"
#include "render/kernel_config.h"
#include "render/memory.h"
#include "render/stages/accumulate.h"
#include "render/stages/generate.h"
#include "render/stages/intersect.h"
#include "render/stages/shade.h"
#include "render/stages/shadow.h"
#include "render/startup.h"
#include "scene/scene.h"
#include "shared/types.h"
#include "util/limits.h"

namespace wp::render {

// Adaptive sampling (render/adaptive.h): after min_spp samples, pixels whose estimated relMSE
// is <= threshold stop receiving samples.
struct AdaptiveSettings {
    bool enabled = false;
    double threshold = limits::kDefaultAdaptiveThreshold;  // per-pixel estimated relMSE
    int min_spp = limits::kDefaultMinSpp;
};

struct RenderSettings {
    int width = limits::kDefaultWidth;  // pixels
    int height = limits::kDefaultHeight;
    int depth = limits::kDefaultDepth;  // maximum number of bounces (see above)
    std::uint32_t seed = 0;   // random stream; the same seed gives the same image
    bool jitter = true;       // random position inside each pixel (false: pixel centres)
    bool variance = false;    // also keep the per-pixel sum of squares (moments())
    // Also record the feature buffers (albedo, normal, depth: aovs(); render/aov.h). Off:
    // no AOV buffer is allocated and the aov program is not built.
    bool aov = false;
    Traversal traversal = Traversal::Stackless;
    Estimator estimator;      // --sampling, --glossy, --sampler, --rr-depth
    // --kernels: the scene-specialised programs (the default) or the generic build with
    // every feature switch on (KernelConfig::with_every_feature()).
    KernelSet kernels = KernelSet::Specialised;
    // Shade eight paths at a time (kernels/shade.cl shade_surface8) on CPU devices where
    // that kernel models the scene (KernelConfig::shade_lanes); off: shade_surface always.
    bool shade_lanes = true;
    // Where the lane kernel shades with light sampling, it traces its shadow rays itself
    // (KernelConfig::shade_traces_shadows): the same image bit for bit, without the shadow
    // queue (52 bytes a path) or the shadow stage. Off: shadow rays go through the queue to
    // the shadow stage, which the profile then times on its own.
    bool shadows_in_shade = true;
    // Light sampling draws the half of a closed emitter that faces the receiver, through
    // back-to-back pairs of light triangles (scene/light_pairs.h): the same image in
    // expectation, less noise from sphere lights. Off: every light sample stays on the
    // triangle the table picked (the estimator before pairs).
    bool light_pairs = true;
    // Shadow segments towards a light triangle end where its clearance begins, the distance
    // to the nearest triangle in front of its plane (scene/light_clearance.h): the same
    // occlusion, fewer triangle tests next to the light. Off: they run up to the light's
    // plane (less the error bound), as before.
    bool light_clearance = true;
    // The last bounce's rays are traced through the emitting triangles' BVH first where that
    // gives the same image bit for bit and pays (final_rays_through_emitters in
    // render/device_scene.h; not with aov, and only with the stackless traversal: the stack
    // traversal, the oracle, traces every bounce itself). Off: every bounce through
    // intersect_closest.
    bool final_rays = true;
    // Debug (render --debug-nan): see KernelConfig::inject_nan.
    int inject_nan = 0;
    int inject_period = 97;
    // Paths in flight (the pool's capacity); 0 = automatic (pool_capacity()).
    std::size_t pool = 0;
    // Pixels per film buffer; 0 = the most one device buffer holds (tests set small values
    // to exercise a film in several segments).
    std::size_t film_segment = 0;
    // Adaptive sampling (implies variance and error_estimate).
    AdaptiveSettings adaptive;
    // Keep the per-pixel error estimates (estimate_error(); --target-error); implies variance.
    bool error_estimate = false;
    // RQMC replicates K (render --replicates; a power of two, 1..limits::kMaxReplicates):
    // sample s of a pixel is point s / K of replicate s mod K's own scramble (Sobol sampler,
    // kernels/shared/rng.h), the film keeps a sum per replicate (FilmSegment::replicate_sum)
    // and the image's error estimate comes from the replicate means (render/adaptive.h).
    // K > 1 implies variance. 1: none (nothing allocated or launched for them).
    int replicates = 1;
};

// The passes at which adaptive sampling checks its list (and --target-error its estimate):
// min_spp, then every max(kAdaptiveMinInterval, c / kAdaptiveIntervalDivisor) passes after
// the check c; with K > 1 replicates each of these rounded up to a multiple of K (so the
// replicates have equal counts at every check). Returns the first such pass >= passes.
int next_error_check(int passes, int min_spp, int replicates = 1);

// Throws wp::Error naming the setting when a value is outside limits.h.
void validate(const RenderSettings& s);

// The most last-level cache one compute unit (core) of a CPU device is counted on: 12 MiB,
// the largest share per core of x86 parts (96 MiB over the 8 cores of a stacked-cache die).
// A virtual machine reports its host's whole last-level cache (480 MiB on the 2-core Xeon
// VMs of 2026-11), which its cores share with every other guest of the host.
inline constexpr std::uint64_t kCachePerComputeUnit = std::uint64_t(12) << 20;
// The cache a device's queues may stay in: the cache it reports, at most kCachePerComputeUnit
// per compute unit (the report alone where the unit count is unknown).
std::uint64_t usable_cache_bytes(const ocl::DeviceInfo& device);
// Whether shade pushes its queues with non-temporal stores (KernelConfig::stream_stores): on
// a CPU device, where the pool's queue_bytes exceed usable_cache_bytes (the next stage reads
// them from memory anyway). A GPU, or a device that reports no cache, never streams.
bool stream_queues(const ocl::DeviceInfo& device, std::uint64_t queue_bytes);

class Wavefront {
  public:
    Wavefront(ocl::Device& dev, const Scene& scene, const RenderSettings& settings);

    // Enqueues `passes` more samples of every pixel, in waves; returns once the last wave is
    // enqueued (it may still run; the queue is in order, so a later read sees it).
    // `on_wave`, when given, is called after each wave is enqueued with the passes of this
    // call enqueued so far (fractional when one pass takes several waves, e.g. 0.25), so a
    // caller can report progress within a pass of an image larger than the pool.
    void render_passes(int passes, const std::function<void(double passes_done)>& on_wave = {});
    // The same with the samples' indices starting at `first_pass` instead of frames(): the
    // passes first_pass .. first_pass + passes - 1 of every pixel (a distributed render's
    // share, render/distributed.h). frames() still grows by `passes`: it counts the samples
    // in this film. Not with adaptive sampling (throws wp::Error unless first_pass ==
    // frames()).
    void render_passes_from(std::int64_t first_pass, int passes,
                            const std::function<void(double passes_done)>& on_wave = {});
    // Whole passes one wave holds (0 when one pass takes several waves); with adaptive
    // sampling, passes of the active pixels.
    int passes_per_wave() const;

    // Starts over with another seed: clears the film, counters, ray total and profile,
    // keeping programs and scene buffers (for repeated runs of one configuration).
    void reset(std::uint32_t seed);
    // Moves the camera (the viewer): the generate stage's CameraData is made from `camera` by
    // upload_camera (the one camera definition) at this render's size, and the film starts
    // over as reset(seed) does. The lens must stay what the programs were built for (a
    // pinhole stays a pinhole), and the field of view the scene's (ray cones); throws
    // wp::Error otherwise, and for a degenerate camera.
    void set_camera(const Camera& camera);

    // Samples per pixel so far (with adaptive sampling: of the pixels still active, the most
    // any pixel has).
    int frames() const { return passes_; }
    int pixel_count() const { return settings_.width * settings_.height; }
    const RenderSettings& settings() const { return settings_; }
    const KernelConfig& config() const { return config_; }
    const std::string& options() const { return options_; }
    const SceneStats& stats() const { return scene_.stats; }
    // The last bounce's rays go through the emitters' BVH first (RenderSettings::final_rays).
    bool final_rays_through_emitters() const { return final_emitters_; }
    // Where the shadow rays are traced: "shade" (KernelConfig::shade_traces_shadows),
    // "stage" (the shadow stage) or "none" (no light sampling).
    const char* shadow_rays() const {
        return config_.shade_traces_shadows() ? "shade" : config_.shadow_queue() ? "stage" : "none";
    }
    // Warnings of the scene's upload (e.g. an environment map that is not 2:1).
    const std::vector<std::string>& scene_warnings() const { return scene_.warnings; }
    // Each stage's program (build or cache load time), in build order: queue, generate,
    // intersect, shade, shadow (with NEE), accumulate.
    std::vector<StartupProgram> program_builds() const;
    ocl::Profiler& profiler() { return profiler_; }
    ocl::Device& device() { return dev_; }
    std::size_t pool_capacity() const { return pool_.capacity(); }
    std::size_t pool_bytes() const { return pool_.bytes(); }
    std::size_t film_bytes() const;
    // Every device buffer this render allocated, by group (render/memory.h).
    const MemoryReport& memory() const { return memory_; }

    // The film's per-pixel arrays as (name, member of FilmSegment, film pixels per image
    // pixel): "sum", "sum_sq" with variance, "replicate_sum" (K a pixel) with K > 1
    // replicates. FilmState, its save, load and reduction
    // follow this list, so one more film array is one more entry here (an array of K sums a
    // pixel, pixel f's k-th at f * K + k, is {name, member, K}).
    struct FilmArrayRef {
        const char* name;
        ocl::Array<FilmPixel> FilmSegment::*member;
        int per_pixel = 1;
    };
    std::vector<FilmArrayRef> film_arrays() const;
    // The whole film on the host (blocking; render/film.h): every film array, frames(),
    // the counters and the ray totals.
    FilmState save_film_state();
    // Replaces the film by `state` (same size and arrays as save_film_state gives, else
    // wp::Error): frames() becomes state.passes, and resolve(), moments() and
    // estimate_error() then read it. Not with adaptive sampling (wp::Error).
    void load_film_state(const FilmState& state);

    // Blocking reads (call between render_passes, not inside the hot path). resolve() and
    // moments() read the film in chunks, so a 16384² film is not copied whole.
    Image resolve();                                    // film sum / spp, linear RGB
    std::array<int, WP_COUNTER_COUNT> counters();       // non-finite values per stage
    std::uint64_t rays_traced();                        // all rays traced so far
    struct RayTotals {
        std::uint64_t closest = 0, shadow = 0;
    };
    RayTotals ray_totals();                             // the same, per kind of ray
    std::vector<FilmPixel> film();                      // the raw film
    // The raw film as it will be once the work enqueued so far is done, read without
    // blocking (the viewer's double buffering): enqueues reads of every segment into `dst`
    // (resized to pixel_count()) and returns the last one's event (the queue is in order);
    // `dst` must stay alive and untouched until it completes. Its sample count is frames()
    // at the call. With `rays`, the ray totals are read along (into rays[0] closest hit,
    // rays[1] shadow), so live numbers need no blocking read either.
    ::cl::Event enqueue_film_read(std::vector<FilmPixel>& dst, cl_ulong* rays = nullptr);
    std::vector<FilmPixel> film_squares();              // its sum of squares (with variance)
    // The replicate sums (settings.replicates > 1, else throws): pixel p's replicate r at
    // [p * K + r] (FilmSegment::replicate_sum).
    std::vector<FilmPixel> film_replicates();
    // Mean, sample variance and variance of the mean (render/film.h); needs
    // settings.variance, else throws wp::Error.
    FilmMoments moments();
    // The feature buffers (render/aov.h); needs settings.aov, else throws wp::Error.
    AovImages aovs();

    // Adaptive sampling and the error estimate (render/adaptive.h).
    bool adaptive() const { return settings_.adaptive.enabled; }
    // Pixels still sampled: all of them without adaptive sampling.
    std::size_t active_pixels() const;
    // Adaptive sampling has stopped every pixel: render_passes does nothing more.
    bool converged() const { return adaptive() && active_pixels() == 0; }
    // The active list (ascending pixel ids) and every pixel's sample count (frames() for all
    // without adaptive sampling) and their mean.
    std::vector<int> active_list() const;
    std::vector<int> sample_counts() const;
    double mean_spp() const;
    // The image's estimated relMSE (mean of the per-pixel estimates) after refreshing the
    // estimates of the active pixels (a kernel and a read of 4 bytes per active pixel);
    // +inf before 2 samples. Needs settings.error_estimate or adaptive, else throws.
    double estimate_error();
    // Per pixel: the latest estimate (stopped pixels: the one they stopped with).
    const std::vector<float>& pixel_errors() const;
    // Checks of the active list so far and their time (kernel, read, compaction, upload;
    // after the queue has drained).
    struct AdaptiveStats {
        int checks = 0;
        double check_ms = 0.0;
    };
    AdaptiveStats adaptive_stats() const { return adaptive_stats_; }

  private:
    // One wave of `count` samples from (first_pixel, first_sample) (generate.cl). With
    // active_count > 0 the wave runs over the active list (adaptive sampling) and
    // first_pixel is its first list entry (generate_camera_active).
    void run_wave(int first_pixel, std::uint32_t first_sample, int count, int active_count = 0);
    // render_passes with adaptive sampling: waves over the active list, checks between them.
    void render_active(int passes, const std::function<void(double passes_done)>& on_wave);
    // One film array of every segment, concatenated (film(), film_squares(), ...).
    std::vector<FilmPixel> read_segments(ocl::Array<FilmPixel> FilmSegment::*member);
    // The adaptive check at pass `passes` if one is due there (next_error_check).
    void check_active(int passes);

    ocl::Device& dev_;
    RenderSettings settings_;
    KernelConfig config_;
    std::string options_;
    ocl::Profiler profiler_;
    int passes_ = 0;

    std::uint64_t memory_from_ = 0;  // the ledger's first buffer id of this render
    // The last bounce's rays go through the emitters' BVH first (RenderSettings::final_rays,
    // final_rays_through_emitters, no feature buffers).
    bool final_emitters_ = false;
    DeviceScene scene_;
    PathPool pool_;
    FilmBuffers film_;
    QueueUpkeep queues_;
    GenerateStage generate_;
    IntersectStage intersect_;
    ShadeStage shade_;
    ShadowStage shadow_;  // built only with NEE
    AccumulateStage accumulate_;
    AovBuffers aov_;      // only with settings.aov
    AovStage aov_stage_;  // only with settings.aov
    MemoryReport memory_;
    std::unique_ptr<ActivePixels> active_;  // with adaptive sampling or the error estimate
    int checked_at_ = -1;                   // passes of the latest adaptive check
    AdaptiveStats adaptive_stats_;
    // Surviving counts read back per bounce (non-blocking; see above).
    std::array<int, 2> count_read_{};
    std::array<::cl::Event, 2> count_event_;
};

}  // namespace wp::render
