#include "render/stages/shade.h"

#include "util/error.h"

namespace wp::render {

ShadeStage::ShadeStage(const ocl::Device& dev, const KernelConfig& config, ocl::Profiler* profiler)
    : target_{&dev.queue, profiler},
      program_(ocl::Program::build(dev, "shade.cl", config.shade_options())),
      lanes_(config.shade_lanes()), traces_(config.shade_traces_shadows()),
      kernel_(program_, lanes_ ? "shade_surface8" : "shade_surface", "shade",
              lanes_ ? WP_SHADE_LANE_GROUP : ocl::kLocalSize),
      frames_(program_, "shade_triangle_frames", "shade.frames") {}

void ShadeStage::prepare(const ShadingScene& scene) {
    // Not profiled: it is scene set-up, not a stage of any frame.
    frames_.launch(ocl::LaunchTarget{target_.queue, nullptr}, scene.tris.size, scene.tris,
                   cl_int(scene.tris.size), scene.tri_frames);
}

::cl::Event ShadeStage::enqueue(std::size_t launch, const PathQueue& in, const ocl::Array<Hit>& hits,
                                const ShadingScene& scene, std::uint32_t seed, int bounce,
                                int max_depth, const ocl::Array<float4>& radiance,
                                const ocl::Array<int>& counters, const PathQueue& out,
                                const ShadowQueue& shadow, const bvh::DeviceBvh* bvh) {
    // shade_surface8: one work-item per WP_SHADE_LANE_ENTRIES queue entries.
    const std::size_t items = lanes_ ? (launch + WP_SHADE_LANE_ENTRIES - 1) / WP_SHADE_LANE_ENTRIES : launch;
    // The arguments of WP_SHADE_SURFACE_PARAMS (shade.cl), then the BVH where shade traces
    // its shadow rays (WP_SHADE_BVH_PARAMS).
    auto launch_with = [&](const auto&... bvh_args) {
        return kernel_.launch(target_, items, in.rays, in.paths, in.count, hits, scene.tris,
                              scene.tri_frames, scene.material_ids, scene.materials,
                              scene.material_tables, scene.background, scene.light_cdf,
                              scene.light_guide, cl_int(scene.light_guide_size), scene.light_prims,
                              scene.light_pdf_area, scene.light_pairs, scene.light_clearance,
                              cl_int(scene.light_count), scene.tri_normals, scene.tex.tri_uvs,
                              scene.tri_tangents, scene.tex.material_textures, scene.tex.textures,
                              scene.tex.views, scene.tex.texels8, scene.tex.texelsf, scene.env,
                              scene.env_texels, scene.env_marginal, scene.env_conditional,
                              cl_float(scene.env_distance), cl_float(scene.cone_spread), cl_uint(seed),
                              cl_int(bounce), cl_int(max_depth), radiance, counters, out.rays, out.paths,
                              out.count, shadow.rays, shadow.items, shadow.contrib, shadow.count,
                              bvh_args...);
    };
    if (!traces_) return launch_with();
    if (!bvh) fail("shade: built to trace its shadow rays but launched without the BVH");
    return launch_with(bvh->nodes, bvh->links, bvh->triangles, bvh->prim_ids);
}

}  // namespace wp::render
