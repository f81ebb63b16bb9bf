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

    // Wavefront state, sized for one path per pixel.
    std::size_t n = static_cast<std::size_t>(pixel_count());
    for (int q = 0; q < 2; ++q) {
        rays_[q] = make_scratch(dev, n * sizeof(Ray), "the ray queue");
        paths_[q] = make_scratch(dev, n * sizeof(PathState), "the path queue");
        count_[q] = make_scratch(dev, sizeof(int), "a queue length");
        fill_zero<int>(dev, count_[q], 1);
    }
    hits_ = make_scratch(dev, n * sizeof(Hit), "the hit buffer");
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
    generate_prog_ = ocl::Program::build(dev, "generate.cl");
    intersect_prog_ = ocl::Program::build(dev, "intersect.cl");
    shade_prog_ = ocl::Program::build(dev, "shade.cl", options_);
    accumulate_prog_ = ocl::Program::build(dev, "accumulate.cl");
    stats_.program_ms = prog_timer.ms();
    generate_ = generate_prog_.kernel("generate_camera");
    intersect_ = intersect_prog_.kernel(settings.traversal == Traversal::Stack ? "intersect_closest_stack"
                                                                                : "intersect_closest");
    reset_ = shade_prog_.kernel("queue_reset");
    shade_ = shade_prog_.kernel("shade_surface");
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
    shade_.setArg(2, hits_);
    shade_.setArg(4, tris_);
    shade_.setArg(5, material_ids_);
    shade_.setArg(6, materials_);
    shade_.setArg(7, background_);
    shade_.setArg(8, static_cast<cl_uint>(settings_.seed));
    shade_.setArg(11, static_cast<cl_int>(settings_.depth));
    shade_.setArg(12, radiance_);
    shade_.setArg(16, counters_);
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
