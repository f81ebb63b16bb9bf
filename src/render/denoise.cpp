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
      finish_(program_, "denoise_finish", "denoise.finish") {}

namespace {

void check_same_size(const Image& a, const Image& b, const char* what) {
    if (a.width != b.width || a.height != b.height)
        fail("denoise: the {} is {}x{}, the colour {}x{}", what, b.width, b.height, a.width,
             a.height);
}

} // namespace

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
    if (s.iterations < 0 || s.iterations > limits::kMaxDenoiseIterations)
        fail("denoise: {} iterations is outside 0..{}", s.iterations,
             limits::kMaxDenoiseIterations);
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
    auto ping = ocl::Array<float4>::allocate(*dev_, n, "the denoiser's image");
    auto pong = ocl::Array<float4>::allocate(*dev_, n, "the denoiser's image");

    const int squarings = std::countr_zero(static_cast<std::uint32_t>(s.normal_power));
    // The guide: unit normal and depth gradient.
    std::vector<::cl::Event> events;
    events.push_back(prepare_.launch(target_, n, color_buf, var_buf, ad_buf, normal_buf, cl_int(w),
                                     cl_int(h), cl_float(s.min_albedo), ping, guide_buf));
    for (int it = 0; it < s.iterations; ++it) {
        events.push_back(atrous_.launch(target_, n, ping, ad_buf, guide_buf, cl_int(w), cl_int(h),
                                        cl_int(1 << it), cl_float(s.sigma_luminance),
                                        cl_float(s.sigma_depth), cl_float(s.sigma_albedo),
                                        cl_int(squarings), pong));
        std::swap(ping, pong);
    }
    events.push_back(finish_.launch(target_, n, ping, ad_buf, cl_int(w), cl_int(h),
                                    cl_float(s.min_albedo), pong));
    const std::vector<float4> out = pong.read(*dev_);
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

} // namespace wp::render
