#include "render/stages/shade.h"

#include "util/error.h"

namespace wp::render {

ShadeStage::ShadeStage(const ocl::Device& dev, const KernelConfig& config, ocl::Profiler* profiler)
    : target_{&dev.queue, profiler},
      program_(ocl::Program::build(dev, "shade.cl", config.shade_options())),
      lanes_(config.shade_lanes()), traces_(config.shade_traces_shadows()),
      kernel_(program_, lanes_ ? "shade_surface8" : "shade_surface", "shade",
              lanes_ ? WP_SHADE_LANE_GROUP : ocl::kLocalSize),
      frames_(program_, "shade_triangle_frames", "shade.frames") {
    // Profiled as the last bounce's tracing ("intersect.final"), which is most of its time.
    if (config.shade_final()) final_ = ocl::Kernel(program_, "shade_final", "intersect.final");
}

void ShadeStage::prepare(const ShadingScene& scene) {
    // Not profiled: it is scene set-up, not a stage of any frame.
    frames_.launch(ocl::LaunchTarget{target_.queue, nullptr}, scene.tris.size, scene.tris,
                   cl_int(scene.tris.size), scene.tri_frames);
}

namespace {

// Launches a shade kernel over `items` work-items with the arguments of
// WP_SHADE_SURFACE_PARAMS (shade.cl), then `more` (the BVHs).
template <typename... More>
::cl::Event launch_shade(ocl::Kernel& kernel, const ocl::LaunchTarget& target, std::size_t items,
                         const PathQueue& in, const ocl::Array<Hit>& hits, const ShadingScene& scene,
                         std::uint32_t seed, int bounce, int max_depth, const ocl::Array<float4>& radiance,
                         const ocl::Array<int>& counters, const PathQueue& out, const ShadowQueue& shadow,
                         const More&... more) {
    return kernel.launch(target, items, in.rays, in.paths, in.count, hits, scene.tris, scene.tri_frames,
                         scene.material_ids, scene.materials, scene.material_tables, scene.background,
                         scene.light_cdf, scene.light_guide, cl_int(scene.light_guide_size),
                         scene.light_prims, scene.light_pdf_area, scene.light_pairs, scene.light_clearance,
                         cl_int(scene.light_count), scene.tri_normals, scene.tex.tri_uvs, scene.tri_tangents,
                         scene.tex.material_textures, scene.tex.textures, scene.tex.views, scene.tex.texels8,
                         scene.tex.texelsf, scene.env, scene.env_texels, scene.env_marginal,
                         scene.env_conditional, cl_float(scene.env_distance), cl_float(scene.cone_spread),
                         cl_uint(seed), cl_int(bounce), cl_int(max_depth), radiance, counters, out.rays,
                         out.paths, out.count, shadow.rays, shadow.items, shadow.contrib, shadow.count,
                         more...);
}

}  // namespace

::cl::Event ShadeStage::enqueue(std::size_t launch, const PathQueue& in, const ocl::Array<Hit>& hits,
                                const ShadingScene& scene, std::uint32_t seed, int bounce,
                                int max_depth, const ocl::Array<float4>& radiance,
                                const ocl::Array<int>& counters, const PathQueue& out,
                                const ShadowQueue& shadow, const bvh::DeviceBvh* bvh) {
    // shade_surface8: one work-item per WP_SHADE_LANE_ENTRIES queue entries.
    const std::size_t items = lanes_ ? (launch + WP_SHADE_LANE_ENTRIES - 1) / WP_SHADE_LANE_ENTRIES : launch;
    // Then the BVH where shade traces its shadow rays (WP_SHADE_BVH_PARAMS).
    if (!traces_)
        return launch_shade(kernel_, target_, items, in, hits, scene, seed, bounce, max_depth, radiance,
                            counters, out, shadow);
    if (!bvh) fail("shade: built to trace its shadow rays but launched without the BVH");
    return launch_shade(kernel_, target_, items, in, hits, scene, seed, bounce, max_depth, radiance, counters,
                        out, shadow, bvh->nodes, bvh->links, bvh->triangles, bvh->prim_ids);
}

::cl::Event ShadeStage::enqueue_final(std::size_t launch, const PathQueue& in, const ShadingScene& scene,
                                      std::uint32_t seed, int max_depth, const ocl::Array<float4>& radiance,
                                      const ocl::Array<int>& counters, const PathQueue& out,
                                      const ShadowQueue& shadow, const ocl::Array<Hit>& hits,
                                      const bvh::DeviceBvh& bvh, const bvh::DeviceBvh& emitters) {
    if (!final_) fail("shade: shade_final launched but not built (KernelConfig::shade_final)");
    if (emitters.node_count == 0) fail("shade: the last bounce's rays need the emitters' BVH");
    // One work-item per queue entry; after shade_surface's arguments (with its shadow BVH
    // where it traces) the scene's BVH and the emitters'.
    auto launch_with = [&](const auto&... shadow_bvh) {
        return launch_shade(final_, target_, launch, in, hits, scene, seed, max_depth, max_depth, radiance,
                            counters, out, shadow, shadow_bvh..., bvh.nodes, bvh.links, bvh.triangles,
                            bvh.prim_ids, emitters.nodes, emitters.links, emitters.triangles, emitters.prim_ids);
    };
    if (!traces_) return launch_with();
    return launch_with(bvh.nodes, bvh.links, bvh.triangles, bvh.prim_ids);
}

}  // namespace wp::render
