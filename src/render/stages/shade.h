// shade.h — the shade stage (kernels/shade.cl): emission, scattering, light samples,
// Russian roulette and the push of the surviving paths.
#pragma once

#include <cstdint>

#include "bvh/device_bvh.h"
#include "render/device_scene.h"
#include "render/frame_state.h"
#include "render/kernel_config.h"

namespace wp::render {

class ShadeStage {
  public:
    ShadeStage() = default;
    // Builds shade.cl with the config's shade slice (materials, estimator, NEE, injection).
    ShadeStage(const ocl::Device& dev, const KernelConfig& config, ocl::Profiler* profiler = nullptr);

    // shade_triangle_frames: fills scene.tri_frames (allocated by DeviceScene::upload, one
    // per triangle) from scene.tris. Once per scene, before the first enqueue.
    void prepare(const ShadingScene& scene);

    // shade_surface: shades the paths of `in` (hit by `hits`) at bounce `bounce`, adds
    // emission to radiance[item], pushes survivors into `out` and, with NEE, light samples
    // into `shadow` (or, where it traces them itself, KernelConfig::shade_traces_shadows,
    // adds their unoccluded contributions through `bvh`, the scene's; only their count goes
    // to shadow.count). `out` and `shadow` must have been emptied (QueueUpkeep::enqueue_reset).
    ::cl::Event enqueue(std::size_t launch, const PathQueue& in, const ocl::Array<Hit>& hits,
                        const ShadingScene& scene, std::uint32_t seed, int bounce, int max_depth,
                        const ocl::Array<float4>& radiance, const ocl::Array<int>& counters,
                        const PathQueue& out, const ShadowQueue& shadow,
                        const bvh::DeviceBvh* bvh = nullptr);
    // shade_final (KernelConfig::shade_final): the last bounce, bounce == max_depth, of the
    // paths of `in` in one launch: traced through `emitters` first and then `bvh` (as
    // IntersectStage::enqueue_final), and the emission of the rays that meet an emitter added
    // to radiance[item]. Nothing is pushed; no hit is written. `bvh` is also the BVH shade
    // traces its shadow rays through where it does (enqueue).
    ::cl::Event enqueue_final(std::size_t launch, const PathQueue& in, const ShadingScene& scene,
                              std::uint32_t seed, int max_depth, const ocl::Array<float4>& radiance,
                              const ocl::Array<int>& counters, const PathQueue& out,
                              const ShadowQueue& shadow, const ocl::Array<Hit>& hits,
                              const bvh::DeviceBvh& bvh, const bvh::DeviceBvh& emitters);
    bool has_final() const { return bool(final_); }
    const ocl::Program& program() const { return program_; }

  private:
    ocl::LaunchTarget target_;
    ocl::Program program_;
    bool lanes_ = false;  // kernel_ is shade_surface8 (KernelConfig::shade_lanes)
    bool traces_ = false;  // it traces its shadow rays (KernelConfig::shade_traces_shadows)
    ocl::Kernel kernel_;
    ocl::Kernel final_;  // shade_final, where the program has it (KernelConfig::shade_final)
    ocl::Kernel frames_;
};

}  // namespace wp::render
