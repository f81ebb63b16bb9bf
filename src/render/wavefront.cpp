#include "render/wavefront.h"

#include <algorithm>
#include <cmath>

#include "bvh/build.h"
#include "bvh/flatten.h"
#include "render/film.h"
#include "scene/upload.h"
#include "util/error.h"
#include "util/timer.h"

namespace wp::render {

namespace {

::cl::Buffer make_scratch(const ocl::Device& dev, std::size_t bytes, const char* what) {
    dev.check_alloc(bytes, what);
    return ::cl::Buffer(dev.context, CL_MEM_READ_WRITE, std::max<std::size_t>(bytes, 16));
}

template <typename T>
void fill_zero(const ocl::Device& dev, const ::cl::Buffer& b, std::size_t count) {
    dev.queue.enqueueFillBuffer(b, T{}, 0, count * sizeof(T));
}

}  // namespace

const char* traversal_name(Traversal t) {
    return t == Traversal::Stack ? "stack" : "stackless";
}

Wavefront::Wavefront(ocl::Device& dev, const Scene& scene, const RenderSettings& settings)
    : dev_(dev), settings_(settings) {
    if (settings.width <= 0 || settings.height <= 0)
        fail("image size {}x{} must be positive", settings.width, settings.height);
    if (settings.depth < 0) fail("depth {} must be >= 0", settings.depth);
    if (static_cast<double>(settings.width) * settings.height > 1 << 28)
        fail("image size {}x{} is too large", settings.width, settings.height);

    // Kernel configuration from what the scene uses.
    config_ = KernelConfig::from_scene(scene);
    config_.sampling = settings.sampling;
    config_.glossy_model = settings.glossy;
    config_.rr_depth = settings.rr_depth;
    config_.sobol = settings.sobol;
    options_ = config_.options();

    // BVH and scene upload.
    Timer up_timer;
    auto boxes = bvh::triangle_boxes(scene.positions, scene.triangles);
    bvh::Bvh bvh = bvh::build(boxes);
    bvh::FlatBvh flat = bvh::flatten(bvh, scene.positions, scene.triangles);
    SceneUpload up = upload_scene(scene);
    camera_ = upload_camera(scene.camera, settings.width, settings.height, settings.jitter);
    background_ = up.background;
    stats_.triangles = scene.triangle_count();
    stats_.vertices = scene.positions.size();
    stats_.materials = scene.materials.size();
    stats_.emissive_materials = static_cast<std::size_t>(std::count_if(
        scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.emissive(); }));
    stats_.bvh_nodes = flat.nodes.size();
    stats_.bvh_depth = flat.depth;
    stats_.bvh_build_ms = bvh.build_ms;

    bvh_ = bvh::DeviceBvh::upload(dev, flat);
    tris_ = ocl::upload_buffer(dev, up.triangles, "the shading triangles");
    material_ids_ = ocl::upload_buffer(dev, up.material_ids, "the material ids");
    materials_ = ocl::upload_buffer(dev, up.materials, "the materials");
    LightTable lights;
    if (config_.nee()) lights = build_light_table(scene);
    stats_.light_triangles = lights.size();
    if (lights.size() > 0) {
        light_cdf_ = ocl::upload_buffer(dev, lights.cdf, "the light CDF");
        light_prims_ = ocl::upload_buffer(dev, lights.prims, "the light triangles");
        light_pdf_area_ = ocl::upload_buffer(dev, lights.pdf_area, "the light densities");
    } else {
        light_cdf_ = make_scratch(dev, 16, "a placeholder");
        light_prims_ = make_scratch(dev, 16, "a placeholder");
        light_pdf_area_ = make_scratch(dev, 16, "a placeholder");
    }

    // Wavefront state, sized for one path per pixel.
    std::size_t n = static_cast<std::size_t>(pixel_count());
    for (int q = 0; q < 2; ++q) {
        rays_[q] = make_scratch(dev, n * sizeof(Ray), "the ray queue");
        paths_[q] = make_scratch(dev, n * sizeof(PathState), "the path queue");
        count_[q] = make_scratch(dev, sizeof(int), "a queue length");
        fill_zero<int>(dev, count_[q], 1);
    }
    hits_ = make_scratch(dev, n * sizeof(Hit), "the hit buffer");
    const std::size_t ns = config_.nee() ? n : 1;
    shadow_rays_ = make_scratch(dev, ns * sizeof(Ray), "the shadow ray queue");
    shadow_pixels_ = make_scratch(dev, ns * sizeof(int), "the shadow ray pixels");
    shadow_contrib_ = make_scratch(dev, ns * sizeof(float4), "the shadow contributions");
    shadow_count_ = make_scratch(dev, sizeof(int), "the shadow queue length");
    fill_zero<int>(dev, shadow_count_, 1);
    radiance_ = make_scratch(dev, n * sizeof(float4), "the frame radiance");
    film_ = make_scratch(dev, n * sizeof(FilmPixel), "the film");
    fill_zero<float>(dev, film_, n * sizeof(FilmPixel) / sizeof(float));
    if (settings.variance) {
        film_sq_ = make_scratch(dev, n * sizeof(FilmPixel), "the film's sum of squares");
        fill_zero<float>(dev, film_sq_, n * sizeof(FilmPixel) / sizeof(float));
    }
    counters_ = make_scratch(dev, WP_COUNTER_COUNT * sizeof(int), "the counters");
    fill_zero<int>(dev, counters_, WP_COUNTER_COUNT);
    ray_total_ = make_scratch(dev, sizeof(cl_ulong), "the ray total");
    fill_zero<cl_ulong>(dev, ray_total_, 1);
    stats_.upload_ms = up_timer.ms();

    // Programs (disk-cached), one per stage file.
    Timer prog_timer;
    std::string inject;
    if (settings.inject_nan != 0)
        inject = fmt::format(" -D WP_INJECT_NAN={} -D WP_INJECT_PERIOD={}", settings.inject_nan,
                             settings.inject_period);
    generate_prog_ = ocl::Program::build(
        dev, "generate.cl", fmt::format("-D WP_SAMPLER={}{}", int(config_.sobol), inject));
    intersect_prog_ = ocl::Program::build(dev, "intersect.cl");
    options_ += inject;
    shade_prog_ = ocl::Program::build(dev, "shade.cl", options_);
    accumulate_prog_ = ocl::Program::build(dev, "accumulate.cl", inject);
    stats_.program_ms = prog_timer.ms();
    generate_ = generate_prog_.kernel("generate_camera");
    intersect_ = intersect_prog_.kernel(settings.traversal == Traversal::Stack ? "intersect_closest_stack"
                                                                                : "intersect_closest");
    reset_ = shade_prog_.kernel("queue_reset");
    shade_ = shade_prog_.kernel("shade_surface");
    if (config_.nee()) {
        shadow_trace_ = intersect_prog_.kernel("intersect_any");
        shadow_resolve_ = shade_prog_.kernel("shadow_resolve");
    }
    accumulate_ = accumulate_prog_.kernel(settings.variance ? "accumulate_film_variance"
                                                            : "accumulate_film");

    // Arguments that never change.
    generate_.setArg(0, camera_);
    generate_.setArg(1, static_cast<cl_uint>(settings_.seed));
    generate_.setArg(3, rays_[0]);
    generate_.setArg(4, paths_[0]);
    generate_.setArg(5, radiance_);
    generate_.setArg(6, count_[0]);
    generate_.setArg(7, counters_);
    bvh_.set_args(intersect_, 2);
    intersect_.setArg(6, hits_);
    reset_.setArg(2, ray_total_);
    reset_.setArg(3, shadow_count_);
    shade_.setArg(2, hits_);
    shade_.setArg(4, tris_);
    shade_.setArg(5, material_ids_);
    shade_.setArg(6, materials_);
    shade_.setArg(7, background_);
    shade_.setArg(8, static_cast<cl_uint>(settings_.seed));
    shade_.setArg(11, static_cast<cl_int>(settings_.depth));
    shade_.setArg(12, radiance_);
    shade_.setArg(16, counters_);
    shade_.setArg(17, light_cdf_);
    shade_.setArg(18, light_prims_);
    shade_.setArg(19, light_pdf_area_);
    shade_.setArg(20, static_cast<cl_int>(lights.size()));
    shade_.setArg(21, shadow_rays_);
    shade_.setArg(22, shadow_pixels_);
    shade_.setArg(23, shadow_count_);
    shade_.setArg(24, shadow_contrib_);
    if (config_.nee()) {
        // intersect_any(rays, queue_count, nodes, links, tris, prim_ids, hits): the shadow
        // hits reuse the hit buffer, which shade has finished reading.
        shadow_trace_.setArg(0, shadow_rays_);
        shadow_trace_.setArg(1, shadow_count_);
        bvh_.set_args(shadow_trace_, 2);
        shadow_trace_.setArg(6, hits_);
        shadow_resolve_.setArg(0, hits_);
        shadow_resolve_.setArg(1, shadow_pixels_);
        shadow_resolve_.setArg(2, shadow_count_);
        shadow_resolve_.setArg(3, shadow_contrib_);
        shadow_resolve_.setArg(4, radiance_);
    }
    accumulate_.setArg(0, radiance_);
    accumulate_.setArg(1, static_cast<cl_int>(n));
    accumulate_.setArg(2, film_);
    accumulate_.setArg(3, counters_);
    if (settings.variance) accumulate_.setArg(4, film_sq_);
    dev.queue.finish();
}

void Wavefront::reset(std::uint32_t seed) {
    dev_.queue.finish();
    profiler_.resolve();
    profiler_.clear();
    std::size_t n = static_cast<std::size_t>(pixel_count());
    fill_zero<float>(dev_, film_, n * sizeof(FilmPixel) / sizeof(float));
    if (settings_.variance) fill_zero<float>(dev_, film_sq_, n * sizeof(FilmPixel) / sizeof(float));
    fill_zero<int>(dev_, counters_, WP_COUNTER_COUNT);
    fill_zero<cl_ulong>(dev_, ray_total_, 1);
    fill_zero<int>(dev_, shadow_count_, 1);
    settings_.seed = seed;
    generate_.setArg(1, static_cast<cl_uint>(seed));
    shade_.setArg(8, static_cast<cl_uint>(seed));
    frames_ = 0;
    dev_.queue.finish();
}

::cl::Event Wavefront::enqueue_frame() {
    const int frame = frames_;
    const auto sample = static_cast<cl_uint>(frame);
    const std::size_t n = static_cast<std::size_t>(pixel_count());
    const auto& q = dev_.queue;

    // Camera rays and fresh paths into queue 0.
    generate_.setArg(2, sample);
    ocl::launch(q, generate_, "generate", n, &profiler_, frame);

    shade_.setArg(9, sample);
    for (int b = 0; b <= settings_.depth; ++b) {
        int in = b & 1, out = in ^ 1;
        // Closest hits of the queued rays (at capacity; the length is read on the device).
        intersect_.setArg(0, rays_[in]);
        intersect_.setArg(1, count_[in]);
        ocl::launch(q, intersect_, "intersect.closest", n, &profiler_, frame);
        // Empty the next queue (and count this bounce's rays).
        reset_.setArg(0, count_[in]);
        reset_.setArg(1, count_[out]);
        ocl::launch(q, reset_, "queue.reset", 1, &profiler_, frame);
        // Emission, scattering, push of the survivors.
        shade_.setArg(0, rays_[in]);
        shade_.setArg(1, paths_[in]);
        shade_.setArg(3, count_[in]);
        shade_.setArg(10, static_cast<cl_int>(b));
        shade_.setArg(13, rays_[out]);
        shade_.setArg(14, paths_[out]);
        shade_.setArg(15, count_[out]);
        ocl::launch(q, shade_, "shade", n, &profiler_, frame);
        // Shadow rays of this bounce's light samples (none at the last bounce).
        if (config_.nee() && b < settings_.depth) {
            ocl::launch(q, shadow_trace_, "intersect.shadow", n, &profiler_, frame);
            ocl::launch(q, shadow_resolve_, "shadow.resolve", n, &profiler_, frame);
        }
    }

    // The frame's radiance into the film.
    ::cl::Event last = ocl::launch(q, accumulate_, "accumulate", n, &profiler_, frame);
    ++frames_;
    return last;
}

std::vector<FilmPixel> Wavefront::film() {
    std::vector<FilmPixel> f(static_cast<std::size_t>(pixel_count()));
    dev_.queue.enqueueReadBuffer(film_, CL_TRUE, 0, f.size() * sizeof(FilmPixel), f.data());
    return f;
}

FilmMoments Wavefront::moments() {
    if (!settings_.variance) fail("the film keeps no variance (render settings without variance)");
    std::vector<FilmPixel> sq(static_cast<std::size_t>(pixel_count()));
    std::vector<FilmPixel> f = film();
    dev_.queue.enqueueReadBuffer(film_sq_, CL_TRUE, 0, sq.size() * sizeof(FilmPixel), sq.data());
    return resolve_moments(f, sq, settings_.width, settings_.height, frames_);
}

Image Wavefront::resolve() {
    return resolve_film(film(), settings_.width, settings_.height, frames_);
}

std::array<int, WP_COUNTER_COUNT> Wavefront::counters() {
    std::array<int, WP_COUNTER_COUNT> c{};
    dev_.queue.enqueueReadBuffer(counters_, CL_TRUE, 0, sizeof(c), c.data());
    return c;
}

std::uint64_t Wavefront::rays_traced() {
    cl_ulong total = 0;
    dev_.queue.enqueueReadBuffer(ray_total_, CL_TRUE, 0, sizeof(total), &total);
    return total;
}

}  // namespace wp::render
