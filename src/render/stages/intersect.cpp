#include "render/stages/intersect.h"

#include "util/error.h"

namespace wp::render {

const char* traversal_name(Traversal t) {
    return t == Traversal::Stack ? "stack" : "stackless";
}

IntersectStage::IntersectStage(const ocl::Device& dev, Traversal traversal, const KernelConfig& config,
                               ocl::Profiler* profiler)
    : target_{&dev.queue, profiler},
      program_(ocl::Program::build(dev, "intersect.cl", config.trace_options())),
      kernel_(program_, traversal == Traversal::Stack ? "intersect_closest_stack" : "intersect_closest",
              "intersect.closest"),
      final_(program_, "intersect_final", "intersect.final"),
      alpha_(config.alpha_mask) {}

::cl::Event IntersectStage::enqueue(std::size_t launch, const PathQueue& queue,
                                    const bvh::DeviceBvh& bvh, const ocl::Array<Hit>& hits,
                                    const TextureArrays* alpha) {
    if (alpha_) {
        if (!alpha) fail("intersect: built with alpha cut-outs but launched without their textures");
        return kernel_.launch(target_, launch, queue.rays, queue.count, bvh.nodes, bvh.links,
                              bvh.triangles, bvh.prim_ids, hits, alpha->material_ids,
                              alpha->material_textures, alpha->tri_uvs, alpha->textures,
                              alpha->views, alpha->texels8, alpha->texelsf);
    }
    return kernel_.launch(target_, launch, queue.rays, queue.count, bvh.nodes, bvh.links,
                          bvh.triangles, bvh.prim_ids, hits);
}

::cl::Event IntersectStage::enqueue_final(std::size_t launch, const PathQueue& queue,
                                          const bvh::DeviceBvh& bvh, const bvh::DeviceBvh& emitters,
                                          const ocl::Array<Hit>& hits, const TextureArrays* alpha) {
    if (emitters.node_count == 0) fail("intersect: the last bounce's rays need the emitters' BVH");
    if (alpha_) {
        if (!alpha) fail("intersect: built with alpha cut-outs but launched without their textures");
        return final_.launch(target_, launch, queue.rays, queue.count, bvh.nodes, bvh.links,
                             bvh.triangles, bvh.prim_ids, emitters.nodes, emitters.links,
                             emitters.triangles, emitters.prim_ids, hits, alpha->material_ids,
                             alpha->material_textures, alpha->tri_uvs, alpha->textures,
                             alpha->views, alpha->texels8, alpha->texelsf);
    }
    return final_.launch(target_, launch, queue.rays, queue.count, bvh.nodes, bvh.links,
                         bvh.triangles, bvh.prim_ids, emitters.nodes, emitters.links,
                         emitters.triangles, emitters.prim_ids, hits);
}

}  // namespace wp::render
