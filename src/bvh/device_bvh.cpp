#include "bvh/device_bvh.h"

#include "util/error.h"

namespace wp::bvh {

DeviceBvh DeviceBvh::upload(const ocl::Device& dev, const FlatBvh& flat) {
    DeviceBvh d;
    d.nodes = ocl::upload_buffer(dev, flat.nodes, "the BVH nodes");
    d.links = ocl::upload_buffer(dev, flat.links, "the BVH links");
    d.triangles = ocl::upload_buffer(dev, flat.triangles, "the triangles");
    d.prim_ids = ocl::upload_buffer(dev, flat.prim_ids, "the triangle ids");
    d.node_count = static_cast<int>(flat.nodes.size());
    d.triangle_count = static_cast<int>(flat.triangles.size());
    d.bytes = flat.nodes.size() * sizeof(BvhNode) + flat.links.size() * sizeof(BvhLinks) +
              flat.triangles.size() * sizeof(Triangle) + flat.prim_ids.size() * sizeof(int);
    return d;
}

void DeviceBvh::set_args(::cl::Kernel& k, int first_arg) const {
    k.setArg(first_arg + 0, nodes);
    k.setArg(first_arg + 1, links);
    k.setArg(first_arg + 2, triangles);
    k.setArg(first_arg + 3, prim_ids);
}

const char* to_string(TraceVariant v) {
    switch (v) {
    case TraceVariant::Stackless: return "stackless";
    case TraceVariant::Stack: return "stack";
    case TraceVariant::Any: return "any";
    }
    return "?";
}

BatchTracer::BatchTracer(const ocl::Device& dev, bool stats, const std::string& extra_options)
    : dev_(dev), stats_(stats),
      program_(ocl::Program::build(dev, "intersect.cl", (stats ? "-D WP_STATS " : "") + extra_options)) {
    closest_ = program_.kernel("intersect_closest_batch");
    stack_ = program_.kernel("intersect_closest_stack_batch");
    any_ = program_.kernel("intersect_any_batch");
    dummy_stats_ = ::cl::Buffer(dev.context, CL_MEM_READ_WRITE, sizeof(TraceStats));
}

::cl::Event BatchTracer::enqueue(const DeviceBvh& bvh, const ::cl::Buffer& rays, int count, const ::cl::Buffer& hits,
                                 TraceVariant v, const ::cl::Buffer* stats, ocl::Profiler* profiler) {
    ::cl::Kernel& k = v == TraceVariant::Stackless ? closest_ : v == TraceVariant::Stack ? stack_ : any_;
    if (stats && !stats_) fail("BatchTracer: statistics requested from a tracer built without them");
    k.setArg(0, rays);
    k.setArg(1, count);
    bvh.set_args(k, 2);
    k.setArg(6, hits);
    k.setArg(7, stats ? *stats : dummy_stats_);
    const char* name = v == TraceVariant::Any ? "intersect.any" : v == TraceVariant::Stack ? "intersect.closest_stack"
                                                                                           : "intersect.closest";
    return ocl::launch(dev_.queue, k, name, static_cast<std::size_t>(count), profiler);
}

std::vector<Hit> BatchTracer::trace(const DeviceBvh& bvh, const std::vector<Ray>& rays, TraceVariant v,
                                    std::vector<TraceStats>* stats) {
    std::vector<Hit> hits(rays.size());
    if (rays.empty()) return hits;
    std::size_t n = rays.size();
    dev_.check_alloc(n * sizeof(Ray), "the ray batch");
    ::cl::Buffer rb(dev_.context, CL_MEM_READ_ONLY, n * sizeof(Ray));
    ::cl::Buffer hb(dev_.context, CL_MEM_WRITE_ONLY, n * sizeof(Hit));
    dev_.queue.enqueueWriteBuffer(rb, CL_FALSE, 0, n * sizeof(Ray), rays.data());
    ::cl::Buffer sb;
    if (stats) sb = ::cl::Buffer(dev_.context, CL_MEM_WRITE_ONLY, n * sizeof(TraceStats));
    enqueue(bvh, rb, static_cast<int>(n), hb, v, stats ? &sb : nullptr);
    dev_.queue.enqueueReadBuffer(hb, CL_TRUE, 0, n * sizeof(Hit), hits.data());
    if (stats) {
        stats->resize(n);
        dev_.queue.enqueueReadBuffer(sb, CL_TRUE, 0, n * sizeof(TraceStats), stats->data());
    }
    return hits;
}

}  // namespace wp::bvh
