#include "render/stages/intersect.h"

namespace wp::render {

const char* traversal_name(Traversal t) {
    return t == Traversal::Stack ? "stack" : "stackless";
}

IntersectStage::IntersectStage(const ocl::Device& dev, Traversal traversal, ocl::Profiler* profiler)
    : target_{&dev.queue, profiler}, program_(ocl::Program::build(dev, "intersect.cl")),
      kernel_(program_, traversal == Traversal::Stack ? "intersect_closest_stack" : "intersect_closest",
              "intersect.closest") {}

::cl::Event IntersectStage::enqueue(std::size_t launch, const PathQueue& queue,
                                    const bvh::DeviceBvh& bvh, const ocl::Array<Hit>& hits) {
    return kernel_.launch(target_, launch, queue.rays, queue.count, bvh.nodes, bvh.links,
                          bvh.triangles, bvh.prim_ids, hits);
}

}  // namespace wp::render
