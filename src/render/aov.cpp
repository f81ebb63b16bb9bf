#include "render/aov.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/memory.h"
#include "shared/aov.h"
#include "util/error.h"

namespace wp::render {

AovSet parse_aov_list(const std::string& list) {
    AovSet s;
    std::size_t i = 0;
    if (list.empty())
        usage_fail("--aov: empty list (expected a comma list of albedo, normal, depth, or all)");
    while (i <= list.size()) {
        std::size_t j = list.find(',', i);
        if (j == std::string::npos) j = list.size();
        const std::string name = list.substr(i, j - i);
        bool* flag = name == "albedo"   ? &s.albedo
                     : name == "normal" ? &s.normal
                     : name == "depth"  ? &s.depth
                                        : nullptr;
        if (name == "all") {
            s = AovSet::all();
        } else if (!flag) {
            usage_fail(
                "--aov: unknown AOV '{}' (expected a comma list of albedo, normal, depth, or all)",
                name);
        } else {
            if (*flag) usage_fail("--aov: '{}' is listed twice", name);
            *flag = true;
        }
        i = j + 1;
    }
    return s;
}

AovBuffers::AovBuffers(const ocl::Device& dev, std::size_t pool_capacity, const FilmBuffers& film) {
    {
        ocl::MemoryGroup group(dev, kMemoryPool);
        items = ocl::Array<float4>::allocate(dev, 2 * pool_capacity, "the sample AOVs");
    }
    ocl::MemoryGroup group(dev, kMemoryFilm);
    for (const FilmSegment& f : film.segments) {
        AovSegment s;
        s.first = f.first;
        s.size = f.size;
        s.sums = ocl::Array<float4>::allocate(dev, 2 * f.size, "the film's AOVs");
        segments.push_back(std::move(s));
    }
    clear(dev);
}

const AovSegment& AovBuffers::segment_of(std::size_t p) const {
    return segment_holding(segments, p, "AOV film");
}

void AovBuffers::clear(const ocl::Device& dev) const {
    for (const auto& s : segments)
        s.sums.fill_zero(dev);
}

AovStage::AovStage(const ocl::Device& dev, const KernelConfig& config, ocl::Profiler* profiler)
    : target_{&dev.queue, profiler},
      program_(ocl::Program::build(dev, "aov.cl", config.aov_options())),
      record_(program_, "aov_record", "aov.record"),
      accumulate_(program_, "aov_accumulate", "aov.accumulate"),
      accumulate_active_(program_, "aov_accumulate_active", "aov.accumulate"), specular_(config.any_specular()) {}

::cl::Event AovStage::record(std::size_t launch, const PathQueue& in, const ocl::Array<Hit>& hits,
                             const ShadingScene& scene, int bounce, const AovBuffers& aov) {
    return record_.launch(target_, launch, in.rays, in.paths, in.count, hits, scene.tri_frames,
                          scene.material_ids, scene.materials, scene.tri_normals, scene.tex.tri_uvs,
                          scene.tri_tangents, scene.tex.material_textures, scene.tex.textures,
                          scene.tex.views, scene.tex.texels8, scene.tex.texelsf, cl_int(bounce),
                          aov.items);
}

::cl::Event AovStage::accumulate(const AovBuffers& aov, int first_pixel, int count, int pixel_count,
                                 const AovSegment& segment) {
    const auto items = static_cast<std::size_t>(std::min(count, pixel_count));
    const auto first = static_cast<std::size_t>(first_pixel);
    if (first < segment.first || first + items > segment.first + segment.size)
        fail("aov: pixels {} to {} are not inside the film segment {} to {}", first, first + items,
             segment.first, segment.first + segment.size);
    return accumulate_.launch(target_, items, aov.items, cl_int(first_pixel), cl_int(count),
                              cl_int(pixel_count), cl_int(segment.first), segment.sums);
}

::cl::Event AovStage::accumulate_active(const AovBuffers& aov, const ocl::Array<int>& active,
                                        int first, int count, int active_count,
                                        const AovSegment& segment) {
    const auto items = static_cast<std::size_t>(std::min(count, active_count));
    return accumulate_active_.launch(target_, items, aov.items, active, cl_int(first), cl_int(count),
                                     cl_int(active_count), cl_int(segment.first), segment.sums);
}

void resolve_aovs_into(const float4* sums, std::size_t count, std::size_t first, int samples,
                       AovImages& out) {
    const std::vector<int> counts(count, samples);
    resolve_aovs_into(sums, count, first, counts.data(), out);
}

void resolve_aovs_into(const float4* sums, std::size_t count, std::size_t first, const int* counts,
                       AovImages& out) {
    for (std::size_t k = 0; k < count; ++k) {
        const double inv = counts[k] > 0 ? 1.0 / counts[k] : 0.0;
        const float4 a = sums[2 * k], b = sums[2 * k + 1];
        const std::size_t i = first + k;
        const float av[3] = {a.x, a.y, a.z}, nv[3] = {b.x, b.y, b.z};
        for (int c = 0; c < 3; ++c) {
            out.albedo.rgb[3 * i + c] = static_cast<float>(av[c] * inv);
            out.normal.rgb[3 * i + c] = static_cast<float>(nv[c] * inv);
        }
        // b.w: the samples that hit; a.w: the sum of their depths.
        out.depth[i] = b.w > 0.0f ? static_cast<float>(double(a.w) / double(b.w))
                                  : std::numeric_limits<float>::infinity();
    }
}

Image aov_preview_normal(const AovImages& a) {
    Image img(a.normal.width, a.normal.height);
    for (std::size_t i = 0; i < img.rgb.size(); ++i) {
        // The linear value whose sRGB code is (n + 1) / 2.
        double e = std::clamp((double(a.normal.rgb[i]) + 1.0) * 0.5, 0.0, 1.0);
        img.rgb[i] = static_cast<float>(srgb_decode(e));
    }
    return img;
}

Image aov_preview_depth(const AovImages& a) {
    Image img(a.albedo.width, a.albedo.height);
    float dmax = 0.0f;
    for (float d : a.depth)
        if (std::isfinite(d)) dmax = std::max(dmax, d);
    for (std::size_t i = 0; i < a.depth.size(); ++i) {
        const float d = a.depth[i];
        double e = !std::isfinite(d) ? 1.0
                   : dmax > 0.0f     ? std::clamp(double(d) / dmax, 0.0, 1.0)
                                     : 0.0;
        const float v = static_cast<float>(srgb_decode(e));
        img.rgb[3 * i] = img.rgb[3 * i + 1] = img.rgb[3 * i + 2] = v;
    }
    return img;
}

} // namespace wp::render
