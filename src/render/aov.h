// aov.h — feature buffers (AOVs) of a render: albedo, shading normal and depth at the
// first non-specular hit of each path (docs/denoise.md).
//
// Which ones a render writes (AovSet, `render --aov albedo,normal,depth`), the device
// buffers (two float4 rows per pooled path and per film pixel: kernels/shared/aov.h), the
// aov stage (kernels/aov.cl: aov_record after intersect, aov_accumulate after accumulate)
// and the resolved images. Nothing of this exists in a render that asks for no AOVs:
// RenderSettings::aov false allocates no buffer and builds no program.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "image/image.h"
#include "render/device_scene.h"
#include "render/frame_state.h"
#include "render/kernel_config.h"

namespace wp::render {

// The AOVs a render writes into its EXR output (and as PNG previews).
struct AovSet {
    bool albedo = false;
    bool normal = false;
    bool depth = false;
    bool any() const { return albedo || normal || depth; }
    static AovSet all() { return {true, true, true}; }
};

// Parses a comma list of albedo, normal, depth (each at most once; "all" for every one).
// Throws wp::UsageError naming the unknown or repeated name and the accepted ones.
AovSet parse_aov_list(const std::string& list);

// The resolved AOVs of a w x h film, row-major from the top-left (render/aov.cpp):
//   albedo: mean over the pixel's samples of the albedo at the first non-specular hit
//           (0 for samples that miss), linear RGB;
//   normal: mean of the unit shading normals there, turned towards the viewer (0 for
//           misses; not renormalised: shorter than 1 where the samples disagree);
//   depth:  mean over the samples that hit of the path length from the camera to that
//           hit (world units, through specular bounces); +inf where no sample hit.
struct AovImages {
    Image albedo;
    Image normal;
    std::vector<float> depth; // one per pixel
};

// The device side: per pooled path two float4 (the sample's AOVs), per film pixel two
// float4 (their sums), cut into the same segments as the film.
struct AovSegment {
    std::size_t first = 0, size = 0;
    ocl::Array<float4> sums; // 2 per pixel
};

struct AovBuffers {
    static constexpr std::size_t kBytesPerPath = 2 * sizeof(float4);
    static constexpr std::size_t kBytesPerPixel = 2 * sizeof(float4);

    ocl::Array<float4> items; // 2 per pooled path
    std::vector<AovSegment> segments;

    AovBuffers() = default;
    // In the pool's and film's memory groups; `film` gives the segments.
    AovBuffers(const ocl::Device& dev, std::size_t pool_capacity, const FilmBuffers& film);
    const AovSegment& segment_of(std::size_t p) const;
    void clear(const ocl::Device& dev) const; // zeroes the sums (enqueued)
};

// The aov stage (kernels/aov.cl) with the config's aov slice.
class AovStage {
  public:
    AovStage() = default;
    AovStage(const ocl::Device& dev, const KernelConfig& config, ocl::Profiler* profiler = nullptr);

    // True when bounce b needs an aov_record launch: bounce 0, and later bounces only when
    // the scene has a specular kind (a path may still be looking through one).
    bool record_at(int bounce) const { return bounce == 0 || specular_; }
    // aov_record over the queue `in` at `bounce` (launch: a bound of its length).
    ::cl::Event record(std::size_t launch, const PathQueue& in, const ocl::Array<Hit>& hits,
                       const ShadingScene& scene, int bounce, const AovBuffers& aov);
    // aov_accumulate: the wave's samples [0, count) from pixel first_pixel into the segment.
    ::cl::Event accumulate(const AovBuffers& aov, int first_pixel, int count, int pixel_count,
                           const AovSegment& segment);
    // aov_accumulate_active (adaptive sampling): the same for a wave over the active list
    // (list entries first.., active_count listed pixels); the wave's pixels lie in `segment`.
    ::cl::Event accumulate_active(const AovBuffers& aov, const ocl::Array<int>& active, int first,
                                  int count, int active_count, const AovSegment& segment);
    const ocl::Program& program() const { return program_; }

  private:
    ocl::LaunchTarget target_;
    ocl::Program program_;
    ocl::Kernel record_, accumulate_, accumulate_active_;
    bool specular_ = false;
};

// Resolves `count` film pixels (2 float4 each) starting at pixel `first` of `out` (sized
// already) from `samples` samples per pixel.
void resolve_aovs_into(const float4* sums, std::size_t count, std::size_t first, int samples,
                       AovImages& out);
// The same with a sample count per pixel (adaptive sampling): counts[k] for pixel first + k.
void resolve_aovs_into(const float4* sums, std::size_t count, std::size_t first, const int* counts,
                       AovImages& out);

// The AOV images prepared for viewing (PNG previews; render --aov-png), as linear values
// that write_image's sRGB encoding turns into the codes named here:
//   albedo as is (a colour);
//   normal: codes round(255 (n + 1) / 2) per axis (the usual normal-map colours);
//   depth:  grey codes round(255 d / d_max) (d_max: the largest finite depth), white
//           where no sample hit.
Image aov_preview_normal(const AovImages& a);
Image aov_preview_depth(const AovImages& a);

} // namespace wp::render
