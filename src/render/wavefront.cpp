#include "render/wavefront.h"

#include <algorithm>
#include <limits>

#include "scene/upload.h"
#include "util/error.h"
#include "util/host_trace.h"
#include "util/timer.h"

namespace wp::render {

void validate(const RenderSettings& s) {
    if (s.width < 1 || s.height < 1 || s.width > limits::kMaxImageSide || s.height > limits::kMaxImageSide)
        fail("image size {}x{}: each side must be 1 to {} pixels", s.width, s.height,
             limits::kMaxImageSide);
    if (std::int64_t(s.width) * s.height > limits::kMaxPixels)
        fail("image size {}x{}: more than {} pixels", s.width, s.height, limits::kMaxPixels);
    if (s.depth < limits::kMinDepth || s.depth > limits::kMaxDepth)
        fail("depth {} is outside {} to {}", s.depth, limits::kMinDepth, limits::kMaxDepth);
    if (s.estimator.rr_depth < -1 || s.estimator.rr_depth > limits::kMaxDepth)
        fail("rr-depth {} must be -1 (off) or in 0..{}", s.estimator.rr_depth, limits::kMaxDepth);
    if (!(s.adaptive.threshold >= limits::kMinErrorThreshold &&
          s.adaptive.threshold <= limits::kMaxErrorThreshold))
        fail("adaptive threshold {} is outside {} to {}", s.adaptive.threshold,
             limits::kMinErrorThreshold, limits::kMaxErrorThreshold);
    if (s.adaptive.min_spp < limits::kMinMinSpp || s.adaptive.min_spp > limits::kMaxSpp)
        fail("adaptive min spp {} is outside {} to {}", s.adaptive.min_spp, limits::kMinMinSpp,
             limits::kMaxSpp);
    if (s.replicates < 1 || s.replicates > limits::kMaxReplicates || (s.replicates & (s.replicates - 1)) != 0)
        fail("replicates {} must be a power of two in 1..{}", s.replicates, limits::kMaxReplicates);
}

std::uint64_t usable_cache_bytes(const ocl::DeviceInfo& device) {
    if (device.compute_units == 0) return device.cache_bytes;
    return std::min<std::uint64_t>(device.cache_bytes, std::uint64_t(device.compute_units) * kCachePerComputeUnit);
}

bool stream_queues(const ocl::DeviceInfo& device, std::uint64_t queue_bytes) {
    return device.type == "CPU" && device.cache_bytes > 0 && queue_bytes > usable_cache_bytes(device);
}

int next_error_check(int passes, int min_spp, int replicates) {
    const long long k = std::max(replicates, 1);
    auto round_up = [k](long long v) { return (v + k - 1) / k * k; };
    long long c = round_up(min_spp);
    while (c < passes)
        c += round_up(std::max<long long>(limits::kAdaptiveMinInterval, c / limits::kAdaptiveIntervalDivisor));
    return static_cast<int>(std::min<long long>(c, std::numeric_limits<int>::max()));
}

namespace {

// Room an automatic pool leaves, beyond the film, for the counters, ray totals and queue
// lengths (a few dozen bytes) and the shadow queue's placeholders.
constexpr std::size_t kSmallBuffersBytes = std::size_t(64) << 10;

// Adaptive sampling needs the error estimate, which needs the film's sum of squares.
RenderSettings with_implied(RenderSettings s) {
    if (s.adaptive.enabled) s.error_estimate = true;
    if (s.error_estimate || s.replicates > 1) s.variance = true;
    return s;
}

KernelConfig make_config(const ocl::Device& dev, const Scene& scene, const RenderSettings& s) {
    KernelConfig c = KernelConfig::from_scene(scene, s.estimator, s.light_pairs);
    if (s.kernels == KernelSet::Generic) c = c.with_every_feature();
    // Eight paths per work-item suit a CPU's vector units; a GPU wants one per thread.
    c.lanes = s.shade_lanes && dev.info.type == "CPU";
    c.generate_lanes = dev.info.type == "CPU";
    c.shadows_in_shade = s.shadows_in_shade;
    c.light_pairs = c.light_pairs && s.light_pairs;
    c.light_clearance = s.light_clearance;
    c.replicates = s.replicates;
    c.inject_nan = s.inject_nan;
    c.inject_period = s.inject_period;
    return c;
}

}  // namespace

Wavefront::Wavefront(ocl::Device& dev, const Scene& scene, const RenderSettings& settings)
    : dev_(dev), settings_((validate(settings), with_implied(settings))), config_(make_config(dev, scene, settings)),
      options_(config_.options()), memory_from_(dev.memory ? dev.memory->next_id() : 0),
      final_emitters_(settings.final_rays && !settings.aov && settings.traversal == Traversal::Stackless &&
                      render::final_rays_through_emitters(scene)),
      scene_(DeviceScene::upload(dev, scene, config_, settings.width, settings.height, settings.jitter,
                                 final_emitters_)) {
    // Scene, pool, film: each buffer is checked against the device before it is created
    // (cl/memory.h), so a render that does not fit fails here, before any kernel runs.
    const auto pixels = static_cast<std::size_t>(pixel_count());
    // An automatic pool leaves room for the film and the few small buffers after it.
    const std::size_t reserve = film_bytes() + kSmallBuffersBytes;
    // The AOV items (2 float4 a path) are sized by the pool too.
    const std::size_t aov_per_path = settings_.aov ? AovBuffers::kBytesPerPath : 0;
    const bool shadow_queue = config_.shadow_queue();
    pool_ = PathPool(dev, render::pool_capacity(dev, pixels, settings.pool, shadow_queue, reserve, aov_per_path),
                     shadow_queue);
    film_ = FilmBuffers(dev, pixels, settings_.variance, settings.film_segment, settings_.replicates);
    if (settings_.aov) aov_ = AovBuffers(dev, pool_.capacity(), film_);
    memory_.capacity = dev.memory ? dev.memory->capacity() : dev.info.global_mem;
    memory_.max_alloc = dev.info.max_alloc;
    memory_.triangles = scene_.stats.triangles;
    memory_.pool_paths = pool_.capacity();
    memory_.bytes_per_path =
        PathPool::bytes_per_path(shadow_queue) + (settings.aov ? AovBuffers::kBytesPerPath : 0);
    memory_.pixels = pixels;
    memory_.bytes_per_pixel = film_bytes() / pixels;  // film, AOVs, active list and errors

    // Where no light triangle has a clearance (concave emitters only), shade is compiled
    // without the code that applies it (its array is then a placeholder).
    if (config_.clear_shadow_ends() && scene_.stats.cleared_lights == 0 &&
        settings.kernels == KernelSet::Specialised) {
        config_.light_clearance = false;
        scene_.stats.scene_bytes -= scene_.shading.light_clearance.bytes();
        scene_.shading.light_clearance = ocl::Array<float>::zeros(dev, 0, "a placeholder");
        scene_.stats.scene_bytes += scene_.shading.light_clearance.bytes();
    }
    config_.stream_stores = stream_queues(dev.info, std::uint64_t(memory_.pool_paths) * memory_.bytes_per_path);
    config_.final_rays = final_emitters_;
    options_ = config_.options();

    // Programs (disk-cached), one per stage, each with its slice of the configuration.
    Timer prog_timer;
    HostSpan span("programs");
    queues_ = QueueUpkeep(dev, &profiler_);
    generate_ = GenerateStage(dev, config_, &profiler_);
    intersect_ = IntersectStage(dev, settings.traversal, config_, &profiler_);
    shade_ = ShadeStage(dev, config_, &profiler_);
    shade_.prepare(scene_.shading);
    if (config_.shadow_queue()) shadow_ = ShadowStage(dev, config_, &profiler_);
    accumulate_ = AccumulateStage(dev, config_, settings_.variance, &profiler_, settings_.replicates);
    // The active list and the per-pixel errors (8 bytes a pixel, 12 with replicates) join
    // the film's group.
    if (settings_.error_estimate)
        active_ = std::make_unique<ActivePixels>(dev, settings_.width, settings_.height, &profiler_,
                                                 settings_.replicates);
    if (settings_.aov) aov_stage_ = AovStage(dev, config_, &profiler_);
    scene_.stats.program_ms = prog_timer.ms();
    // Every device buffer this renderer made (the memory report).
    if (dev.memory)
        for (auto& b : dev.memory->live())
            if (b.id >= memory_from_) memory_.buffers.push_back(std::move(b));
    dev.queue.finish();
}

std::vector<StartupProgram> Wavefront::program_builds() const {
    std::vector<StartupProgram> v;
    for (const ocl::Program* p : {&queues_.program(), &generate_.program(), &intersect_.program(),
                                  &shade_.program(), &shadow_.program(), &accumulate_.program(),
                                  &aov_stage_.program()})
        if (!p->file.empty()) v.push_back({p->file, p->build_ms, p->from_cache});
    if (active_) {
        const ocl::Program& p = active_->program();
        v.push_back({p.file, p.build_ms, p.from_cache});
    }
    return v;
}

std::size_t Wavefront::film_bytes() const {
    return static_cast<std::size_t>(pixel_count()) *
           (FilmBuffers::bytes_per_pixel(settings_.variance, settings_.replicates) +
            (settings_.error_estimate ? ActivePixels::bytes_per_pixel(settings_.replicates) : 0) +
            (settings_.aov ? AovBuffers::kBytesPerPixel : 0));
}

int Wavefront::passes_per_wave() const {
    // A film in several segments (only images larger than the pool) runs in chunks.
    if (film_.segments.size() > 1) return 0;
    const std::size_t n = adaptive() ? std::max<std::size_t>(active_->count(), 1)
                                     : static_cast<std::size_t>(pixel_count());
    return static_cast<int>(std::min<std::size_t>(pool_.capacity() / n, std::numeric_limits<int>::max()));
}

void Wavefront::reset(std::uint32_t seed) {
    dev_.queue.finish();
    profiler_.resolve();
    profiler_.clear();
    film_.clear(dev_);
    if (settings_.aov) aov_.clear(dev_);
    settings_.seed = seed;
    passes_ = 0;
    if (active_) active_->reset(dev_);
    checked_at_ = -1;
    adaptive_stats_ = {};
    dev_.queue.finish();
}

void Wavefront::set_camera(const Camera& camera) {
    const CameraData next = upload_camera(camera, settings_.width, settings_.height, settings_.jitter);
    if ((next.lens.x > 0.0f) != (scene_.camera.lens.x > 0.0f))
        fail("set_camera: the camera's lens (radius {}) does not match the programs' ({})",
             next.lens.x, scene_.camera.lens.x);
    reset(settings_.seed);
    scene_.camera = next;
}

void Wavefront::render_passes(int passes, const std::function<void(double)>& on_wave) {
    if (adaptive()) return render_active(passes, on_wave);
    render_passes_from(passes_, passes, on_wave);
}

void Wavefront::render_passes_from(std::int64_t first_pass, int passes,
                                   const std::function<void(double)>& on_wave) {
    if (adaptive()) {
        if (first_pass != passes_)
            fail("adaptive sampling renders its pixels' passes in order (first pass {}, film at {})",
                 first_pass, passes_);
        return render_active(passes, on_wave);
    }
    if (first_pass < 0 || first_pass + passes > std::int64_t(std::numeric_limits<std::uint32_t>::max()))
        fail("passes {} .. {} are outside the sample index range", first_pass, first_pass + passes);
    const int n = pixel_count();
    const int per_wave = passes_per_wave();
    int done = 0;
    while (done < passes) {
        const auto sample = static_cast<std::uint32_t>(first_pass + done);
        if (per_wave >= 1) {
            // k whole passes in one wave.
            int k = std::min(per_wave, passes - done);
            run_wave(0, sample, k * n);
            done += k;
            if (on_wave) on_wave(done);
        } else {
            // One pass in chunks of the pool's capacity, none straddling two film segments.
            const auto chunk = pool_.capacity();
            for (const FilmSegment& seg : film_.segments)
                for (std::size_t first = seg.first; first < seg.first + seg.size; first += chunk) {
                    const auto count = std::min(chunk, seg.first + seg.size - first);
                    run_wave(static_cast<int>(first), sample, static_cast<int>(count));
                    if (on_wave) on_wave(done + double(first + count) / double(n));
                }
            done += 1;
        }
    }
    passes_ += passes;
}

std::size_t Wavefront::active_pixels() const {
    return adaptive() ? active_->count() : static_cast<std::size_t>(pixel_count());
}

std::vector<int> Wavefront::active_list() const {
    if (adaptive()) return active_->list();
    std::vector<int> v(static_cast<std::size_t>(pixel_count()));
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<int>(i);
    return v;
}

std::vector<int> Wavefront::sample_counts() const {
    if (adaptive()) return active_->sample_counts(passes_);
    return std::vector<int>(static_cast<std::size_t>(pixel_count()), passes_);
}

double Wavefront::mean_spp() const {
    if (!adaptive()) return passes_;
    double s = 0.0;
    for (int c : active_->sample_counts(passes_)) s += c;
    return s / pixel_count();
}

double Wavefront::estimate_error() {
    if (!active_) fail("the film keeps no error estimate (render settings without error_estimate)");
    if (passes_ < 2) return std::numeric_limits<double>::infinity();
    // An adaptive check at this pass has just refreshed every listed pixel.
    if (!(adaptive() && checked_at_ == passes_)) active_->refresh(dev_, film_, passes_);
    return active_->mean_error();
}

const std::vector<float>& Wavefront::pixel_errors() const {
    if (!active_) fail("the film keeps no error estimate (render settings without error_estimate)");
    return active_->errors();
}

void Wavefront::check_active(int passes) {
    if (passes == checked_at_ ||
        next_error_check(passes, settings_.adaptive.min_spp, settings_.replicates) != passes)
        return;
    // The check reads the film, so it waits for the waves before it; that wait is not its
    // cost (the device is busy with them), so the clock starts after it.
    dev_.queue.finish();
    Timer t;
    active_->refresh(dev_, film_, passes);
    active_->drop_converged(dev_, settings_.adaptive.threshold, passes);
    checked_at_ = passes;
    adaptive_stats_.checks += 1;
    adaptive_stats_.check_ms += t.ms();
}

void Wavefront::render_active(int passes, const std::function<void(double)>& on_wave) {
    int done = 0;
    for (;;) {
        const int now = passes_ + done;
        check_active(now);
        const auto active = active_->count();
        if (done >= passes || active == 0) break;
        // Waves never run past the next check.
        const int until = next_error_check(now + 1, settings_.adaptive.min_spp, settings_.replicates) - now;
        const auto sample = static_cast<std::uint32_t>(now);
        const int a = static_cast<int>(active);
        const int per_wave = passes_per_wave();
        if (per_wave >= 1) {
            // k whole passes of the active pixels in one wave.
            const int k = std::min({per_wave, passes - done, until});
            run_wave(0, sample, k * a, a);
            done += k;
            if (on_wave) on_wave(done);
        } else {
            // One pass of the active pixels in chunks of the pool, none straddling two film
            // segments (the list is sorted, so a segment's pixels are one range of it).
            const auto chunk = pool_.capacity();
            for (const FilmSegment& seg : film_.segments) {
                auto [b, e] = active_->range(seg);
                for (std::size_t first = b; first < e; first += chunk) {
                    const auto count = std::min(chunk, e - first);
                    run_wave(static_cast<int>(first), sample, static_cast<int>(count), a);
                    if (on_wave) on_wave(done + double(first + count) / double(a));
                }
            }
            done += 1;
        }
    }
    passes_ += done;
}

void Wavefront::run_wave(int first_pixel, std::uint32_t first_sample, int count, int active_count) {
    const int n = pixel_count();
    const int depth = settings_.depth;
    const bool shadow_stage = config_.shadow_queue();
    profiler_.begin_wave(double(count) / double(n));

    // Camera rays and fresh paths into queue 0.
    if (active_count > 0)
        generate_.enqueue_active(scene_.camera, settings_.seed, active_->device_list(), first_pixel,
                                 active_count, first_sample, count, pool_.queue[0], pool_.radiance,
                                 film_.counters);
    else
        generate_.enqueue(scene_.camera, settings_.seed, first_pixel, first_sample, count,
                          pool_.queue[0], pool_.radiance, film_.counters);
    // `live` bounds the length of the queue the next bounce reads: the last count read back
    // (lengths only shrink within a wave).
    auto live = static_cast<std::size_t>(count);
    for (int b = 0; b <= depth; ++b) {
        const PathQueue& in = pool_.queue[b & 1];
        const PathQueue& out = pool_.queue[(b & 1) ^ 1];
        if (b == depth && final_emitters_ && shade_.has_final()) {
            // The last bounce in one launch: traced as below, and shaded only where a ray
            // meets an emitter (shade_final; the same image).
            queues_.enqueue_reset(in.count, out.count, pool_.shadow.count, film_.ray_total,
                                  film_.shadow_ray_total);
            shade_.enqueue_final(live, in, scene_.shading, settings_.seed, depth, pool_.radiance,
                                 film_.counters, out, pool_.shadow, pool_.hits, scene_.bvh,
                                 scene_.emitter_bvh);
            break;
        }
        // Closest hits of the queued rays; at the last bounce, where only emitters can add
        // light, through the emitters' BVH first (the same hits wherever shade adds).
        if (b == depth && final_emitters_)
            intersect_.enqueue_final(live, in, scene_.bvh, scene_.emitter_bvh, pool_.hits, &scene_.shading.tex);
        else
            intersect_.enqueue(live, in, scene_.bvh, pool_.hits, &scene_.shading.tex);
        // Feature buffers at the first non-specular hit (render --aov, --denoise).
        if (settings_.aov && aov_stage_.record_at(b))
            aov_stage_.record(live, in, pool_.hits, scene_.shading, b, aov_);
        // Empty the queues shade fills (and count this bounce's rays and the last bounce's
        // shadow rays).
        queues_.enqueue_reset(in.count, out.count, pool_.shadow.count, film_.ray_total,
                              film_.shadow_ray_total);
        // Emission, scattering, light samples, push of the survivors.
        shade_.enqueue(live, in, pool_.hits, scene_.shading, settings_.seed, b, depth, pool_.radiance,
                       film_.counters, out, pool_.shadow, &scene_.bvh);
        // Shadow rays of this bounce's light samples (none at the last bounce), unless shade
        // traced them itself.
        if (shadow_stage && b < depth)
            shadow_.enqueue(live, pool_.shadow, scene_.bvh, pool_.radiance, &scene_.shading.tex);
        if (b == depth) break;
        // Read this bounce's survivors without waiting; wait for the previous bounce's.
        dev_.queue.enqueueReadBuffer(out.count.buffer, CL_FALSE, 0, sizeof(int), &count_read_[b & 1],
                                     nullptr, &count_event_[b & 1]);
        if (b > 0) {
            count_event_[(b - 1) & 1].wait();
            const int left = count_read_[(b - 1) & 1];  // the queue bounce b read
            if (left == 0) break;                       // bounce b had nothing: done
            live = static_cast<std::size_t>(left);
        }
    }
    // The wave's radiance into the film, pixel by pixel in sample order.
    if (active_count > 0) {
        const auto p = static_cast<std::size_t>(active_->list()[static_cast<std::size_t>(first_pixel)]);
        accumulate_.enqueue_active(pool_.radiance, active_->device_list(), first_pixel, count,
                                   active_count, film_.segment_of(p), film_.counters, first_sample);
        // The feature buffers over the same list (the AOV segments are the film's).
        if (settings_.aov)
            aov_stage_.accumulate_active(aov_, active_->device_list(), first_pixel, count,
                                         active_count, aov_.segment_of(p));
    } else {
        accumulate_.enqueue(pool_.radiance, first_pixel, count, n,
                            film_.segment_of(static_cast<std::size_t>(first_pixel)), film_.counters,
                            first_sample);
        if (settings_.aov)
            aov_stage_.accumulate(aov_, first_pixel, count, n,
                                  aov_.segment_of(static_cast<std::size_t>(first_pixel)));
    }
}

std::vector<FilmPixel> Wavefront::read_segments(ocl::Array<FilmPixel> FilmSegment::*member) {
    std::vector<FilmPixel> f;
    for (const auto& seg : film_.segments) {
        auto v = (seg.*member).read(dev_);
        f.insert(f.end(), v.begin(), v.end());
    }
    return f;
}

std::vector<FilmPixel> Wavefront::film() { return read_segments(&FilmSegment::sum); }

std::vector<FilmPixel> Wavefront::film_squares() {
    if (!settings_.variance) fail("the film keeps no variance (render settings without variance)");
    return read_segments(&FilmSegment::sum_sq);
}

std::vector<FilmPixel> Wavefront::film_replicates() {
    if (settings_.replicates <= 1) fail("the film keeps no replicate sums (render settings without replicates)");
    return read_segments(&FilmSegment::replicate_sum);
}

namespace {
constexpr std::size_t kResolveChunk = std::size_t(1) << 22;  // pixels per film read
}

FilmMoments Wavefront::moments() {
    if (!settings_.variance) fail("the film keeps no variance (render settings without variance)");
    const int w = settings_.width, h = settings_.height;
    FilmMoments m{Image(w, h), Image(w, h), Image(w, h)};
    const std::vector<int> counts = adaptive() ? sample_counts() : std::vector<int>{};
    for (const auto& seg : film_.segments)
        for (std::size_t k = 0; k < seg.size; k += kResolveChunk) {
            std::size_t c = std::min(kResolveChunk, seg.size - k);
            auto s = seg.sum.read(dev_, k, c);
            auto sq = seg.sum_sq.read(dev_, k, c);
            if (adaptive())
                resolve_moments_into(s.data(), sq.data(), c, seg.first + k,
                                     counts.data() + seg.first + k, m);
            else
                resolve_moments_into(s.data(), sq.data(), c, seg.first + k, passes_, m);
        }
    return m;
}

AovImages Wavefront::aovs() {
    if (!settings_.aov) fail("the render keeps no AOVs (render settings without aov)");
    const int w = settings_.width, h = settings_.height;
    AovImages a{Image(w, h), Image(w, h), std::vector<float>(static_cast<std::size_t>(w) * h)};
    const std::vector<int> counts = adaptive() ? sample_counts() : std::vector<int>{};
    for (const auto& seg : aov_.segments)
        for (std::size_t k = 0; k < seg.size; k += kResolveChunk) {
            std::size_t c = std::min(kResolveChunk, seg.size - k);
            auto s = seg.sums.read(dev_, 2 * k, 2 * c);
            if (adaptive())
                resolve_aovs_into(s.data(), c, seg.first + k, counts.data() + seg.first + k, a);
            else
                resolve_aovs_into(s.data(), c, seg.first + k, passes_, a);
        }
    return a;
}

Image Wavefront::resolve() {
    Image img(settings_.width, settings_.height);
    const std::vector<int> counts = adaptive() ? sample_counts() : std::vector<int>{};
    for (const auto& seg : film_.segments)
        for (std::size_t k = 0; k < seg.size; k += kResolveChunk) {
            std::size_t c = std::min(kResolveChunk, seg.size - k);
            auto s = seg.sum.read(dev_, k, c);
            if (adaptive())
                resolve_film_into(s.data(), c, seg.first + k, counts.data() + seg.first + k, img);
            else
                resolve_film_into(s.data(), c, seg.first + k, passes_, img);
        }
    return img;
}

::cl::Event Wavefront::enqueue_film_read(std::vector<FilmPixel>& dst, cl_ulong* rays) {
    dst.resize(static_cast<std::size_t>(pixel_count()));
    ::cl::Event last;
    if (rays) {
        dev_.queue.enqueueReadBuffer(film_.ray_total.buffer, CL_FALSE, 0, sizeof(cl_ulong), &rays[0]);
        dev_.queue.enqueueReadBuffer(film_.shadow_ray_total.buffer, CL_FALSE, 0, sizeof(cl_ulong), &rays[1]);
    }
    for (const auto& seg : film_.segments)
        if (seg.size > 0)
            dev_.queue.enqueueReadBuffer(seg.sum.buffer, CL_FALSE, 0, seg.size * sizeof(FilmPixel),
                                         dst.data() + seg.first, nullptr, &last);
    return last;
}

std::vector<Wavefront::FilmArrayRef> Wavefront::film_arrays() const {
    std::vector<FilmArrayRef> v = {{"sum", &FilmSegment::sum}};
    if (settings_.variance) v.push_back({"sum_sq", &FilmSegment::sum_sq});
    if (film_.replicates > 1)
        v.push_back({"replicate_sum", &FilmSegment::replicate_sum, film_.replicates});
    return v;
}

FilmState Wavefront::save_film_state() {
    FilmState st;
    st.width = settings_.width;
    st.height = settings_.height;
    st.passes = passes_;
    const RayTotals t = ray_totals();
    st.rays = t.closest;
    st.shadow_rays = t.shadow;
    const auto c = counters();
    std::copy(c.begin(), c.end(), st.counters.begin());
    for (const FilmArrayRef& ref : film_arrays()) {
        const std::size_t m = static_cast<std::size_t>(ref.per_pixel);
        FilmArray a{ref.name, std::vector<double>(3 * m * st.pixels())};
        for (const auto& seg : film_.segments)
            for (std::size_t k = 0; k < seg.size * m; k += kResolveChunk) {
                const std::size_t n = std::min(kResolveChunk, seg.size * m - k);
                const auto px = (seg.*ref.member).read(dev_, k, n);
                film_pixels_to_doubles(px.data(), n, a.values.data() + 3 * (seg.first * m + k));
            }
        st.arrays.push_back(std::move(a));
    }
    return st;
}

void Wavefront::load_film_state(const FilmState& st) {
    if (adaptive()) fail("load_film_state: adaptive sampling keeps per-pixel sample counts a film state does not hold");
    const auto refs = film_arrays();
    if (st.width != settings_.width || st.height != settings_.height || st.arrays.size() != refs.size())
        fail("load_film_state: a {}x{} film with {} arrays does not fit this {}x{} render with {}",
             st.width, st.height, st.arrays.size(), settings_.width, settings_.height, refs.size());
    if (st.passes < 0 || st.passes > std::numeric_limits<int>::max())
        fail("load_film_state: {} passes is out of range", st.passes);
    dev_.queue.finish();
    for (std::size_t i = 0; i < refs.size(); ++i) {
        const FilmArray& a = st.arrays[i];
        const std::size_t m = static_cast<std::size_t>(refs[i].per_pixel);
        if (a.name != refs[i].name || a.values.size() != 3 * m * st.pixels())
            fail("load_film_state: array {} is '{}' with {} values, expected '{}' with {}", i, a.name,
                 a.values.size(), refs[i].name, 3 * m * st.pixels());
        for (const auto& seg : film_.segments)
            for (std::size_t k = 0; k < seg.size * m; k += kResolveChunk) {
                const std::size_t n = std::min(kResolveChunk, seg.size * m - k);
                std::vector<FilmPixel> px(n);
                doubles_to_film_pixels(a.values.data() + 3 * (seg.first * m + k), n, px.data());
                dev_.queue.enqueueWriteBuffer((seg.*refs[i].member).buffer, CL_TRUE, k * sizeof(FilmPixel),
                                              n * sizeof(FilmPixel), px.data());
            }
    }
    std::vector<int> c(WP_COUNTER_COUNT);
    for (std::size_t i = 0; i < c.size(); ++i)
        c[i] = static_cast<int>(std::min<std::int64_t>(st.counters[i], std::numeric_limits<int>::max()));
    film_.counters.write(dev_, c);
    film_.ray_total.write(dev_, std::vector<cl_ulong>{st.rays});
    film_.shadow_ray_total.write(dev_, std::vector<cl_ulong>{st.shadow_rays});
    passes_ = static_cast<int>(st.passes);
}

std::array<int, WP_COUNTER_COUNT> Wavefront::counters() {
    std::array<int, WP_COUNTER_COUNT> c{};
    auto v = film_.counters.read(dev_);
    std::copy(v.begin(), v.end(), c.begin());
    return c;
}

Wavefront::RayTotals Wavefront::ray_totals() {
    return {film_.ray_total.read(dev_)[0], film_.shadow_ray_total.read(dev_)[0]};
}

std::uint64_t Wavefront::rays_traced() {
    const RayTotals t = ray_totals();
    return t.closest + t.shadow;
}

}  // namespace wp::render
