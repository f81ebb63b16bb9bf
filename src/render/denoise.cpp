#include "render/denoise.h"

#include <bit>
#include <cstdint>
#include <vector>

#include "util/error.h"

namespace wp::render {

Denoiser::Denoiser(ocl::Device& dev, ocl::Profiler* profiler)
    : dev_(&dev), target_{&dev.queue, profiler}, program_(ocl::Program::build(dev, "denoise.cl")),
      prepare_(program_, "denoise_prepare", "denoise.prepare"),
      atrous_(program_, "denoise_atrous", "denoise.atrous"),
      combine_(program_, "denoise_combine", "denoise.combine"),
      finish_(program_, "denoise_finish", "denoise.finish") {}

namespace {

void check_same_size(const Image& a, const Image& b, const char* what) {
    if (a.width != b.width || a.height != b.height)
        fail("denoise: the {} is {}x{}, the colour {}x{}", what, b.width, b.height, a.width,
             a.height);
}

}  // namespace

Image Denoiser::run(const Image& color, const Image& variance, const AovImages& aov,
                    const DenoiseSettings& s) {
    if (!dev_) fail("denoise: the denoiser has no device");
    const int w = color.width, h = color.height;
    if (w <= 0 || h <= 0) fail("denoise: the image {}x{} is empty", w, h);
    check_same_size(color, variance, "variance");
    check_same_size(color, aov.albedo, "albedo AOV");
    check_same_size(color, aov.normal, "normal AOV");
    const std::size_t n = static_cast<std::size_t>(w) * h;
    if (aov.depth.size() != n)
        fail("denoise: the depth AOV holds {} pixels, expected {}", aov.depth.size(), n);
    if (s.iterations < 0 || s.iterations > limits::kMaxDenoiseIterations ||
        s.restore_iterations < 0 || s.restore_iterations > limits::kMaxDenoiseIterations)
        fail("denoise: {} iterations, {} restore iterations: each must be in 0..{}", s.iterations,
             s.restore_iterations, limits::kMaxDenoiseIterations);
    if (s.normal_power < 1 || !std::has_single_bit(static_cast<std::uint32_t>(s.normal_power)))
        fail("denoise: the normal power {} is not a power of two", s.normal_power);
    if (!(s.sigma_luminance > 0.0f) || !(s.sigma_depth > 0.0f) || !(s.sigma_albedo > 0.0f) ||
        !(s.min_albedo >= 0.0f))
        fail("denoise: the sigmas must be > 0 and the minimum albedo >= 0");

    // Pack into float4 rows.
    std::vector<float4> c(n), v(n), ad(n), nm(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float* pc = &color.rgb[3 * i];
        const float* pv = &variance.rgb[3 * i];
        const float* pa = &aov.albedo.rgb[3 * i];
        const float* pn = &aov.normal.rgb[3 * i];
        c[i] = float4{pc[0], pc[1], pc[2], 0.0f};
        v[i] = float4{pv[0], pv[1], pv[2], 0.0f};
        ad[i] = float4{pa[0], pa[1], pa[2], aov.depth[i]};
        nm[i] = float4{pn[0], pn[1], pn[2], 0.0f};
    }
    ocl::MemoryGroup group(*dev_, "denoise");
    auto color_buf = ocl::Array<float4>::upload(*dev_, c, "the denoiser's colour");
    auto var_buf = ocl::Array<float4>::upload(*dev_, v, "the denoiser's variance");
    auto ad_buf = ocl::Array<float4>::upload(*dev_, ad, "the denoiser's albedo and depth");
    auto normal_buf = ocl::Array<float4>::upload(*dev_, nm, "the denoiser's normals");
    auto guide_buf = ocl::Array<float4>::allocate(*dev_, n, "the denoiser's guide");
    // Three images rotate through the passes (no pass writes a buffer it reads).
    ocl::Array<float4> buf[3] = {ocl::Array<float4>::allocate(*dev_, n, "the denoiser's image"),
                                 ocl::Array<float4>::allocate(*dev_, n, "the denoiser's image"),
                                 ocl::Array<float4>::allocate(*dev_, n, "the denoiser's image")};
    // The index of 0, 1, 2 that is neither a nor b (a == b: the next one after a).
    auto other = [](int a, int b) { return a == b ? (a + 1) % 3 : 3 - a - b; };

    const int squarings = std::countr_zero(static_cast<std::uint32_t>(s.normal_power));
    std::vector<::cl::Event> events;
    // `iterations` à-trous passes from buf[src], alternating between the two buffers that
    // are not buf[keep] (keep == src: buf[src] itself stays); returns the result's index.
    auto atrous = [&](int src, int keep, int iterations, float sigma_l) {
        for (int it = 0; it < iterations; ++it) {
            const int dst = other(src, keep);
            events.push_back(atrous_.launch(target_, n, buf[src], ad_buf, guide_buf, cl_int(w),
                                            cl_int(h), cl_int(1 << it), cl_float(sigma_l),
                                            cl_float(s.sigma_depth), cl_float(s.sigma_albedo),
                                            cl_int(squarings), buf[dst]));
            src = dst;
        }
        return src;
    };
    // Demodulated illumination and its variance into buf[0]; the guide.
    events.push_back(prepare_.launch(target_, n, color_buf, var_buf, ad_buf, normal_buf, cl_int(w),
                                     cl_int(h), cl_float(s.min_albedo), buf[0], guide_buf));
    // The filter, keeping its input in buf[0] for the residual.
    int d = atrous(0, 0, s.iterations, s.sigma_luminance);
    if (s.restore_iterations > 0 && d != 0) {
        // Energy restore (denoise.cl): the residual, filtered by the guides alone, added back.
        const int r = other(0, d);
        events.push_back(combine_.launch(target_, n, buf[0], buf[d], cl_int(w), cl_int(h),
                                         cl_float(-1.0f), buf[r]));
        const int rf = atrous(r, d, s.restore_iterations, 0.0f);
        const int sum = other(d, rf);
        events.push_back(combine_.launch(target_, n, buf[d], buf[rf], cl_int(w), cl_int(h),
                                         cl_float(1.0f), buf[sum]));
        d = sum;
    }
    const int fin = other(d, d);
    events.push_back(finish_.launch(target_, n, buf[d], ad_buf, cl_int(w), cl_int(h),
                                    cl_float(s.min_albedo), buf[fin]));
    const std::vector<float4> out = buf[fin].read(*dev_);
    device_ms_ = 0.0;
    for (auto& e : events)
        device_ms_ += double(e.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                             e.getProfilingInfo<CL_PROFILING_COMMAND_START>()) *
                      1e-6;
    Image img(w, h);
    for (std::size_t i = 0; i < n; ++i) {
        img.rgb[3 * i] = out[i].x;
        img.rgb[3 * i + 1] = out[i].y;
        img.rgb[3 * i + 2] = out[i].z;
    }
    return img;
}

}  // namespace wp::render
