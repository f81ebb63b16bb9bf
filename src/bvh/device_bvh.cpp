#include "bvh/device_bvh.h"

#include "util/error.h"

namespace wp::bvh {

DeviceBvh DeviceBvh::upload(const ocl::Device& dev, const FlatBvh& flat, std::string_view whose) {
    auto name = [&](const char* what) { return fmt::format("{} {}", whose, what); };
    DeviceBvh d;
    d.nodes = ocl::Array<BvhNode>::upload(dev, flat.nodes, name("BVH nodes").c_str());
    d.links = ocl::Array<BvhLinks>::upload(dev, flat.links, name("BVH links").c_str());
    d.triangles = ocl::Array<TriBlock>::upload(dev, flat.triangles, name("triangles").c_str());
    d.prim_ids = ocl::Array<int>::upload(dev, flat.prim_ids, name("triangle ids").c_str());
    d.node_count = static_cast<int>(flat.nodes.size());
    d.triangle_count = static_cast<int>(flat.triangle_count);
    d.bytes = flat.nodes.size() * sizeof(BvhNode) + flat.links.size() * sizeof(BvhLinks) +
              flat.triangles.size() * sizeof(TriBlock) + flat.prim_ids.size() * sizeof(int);
    return d;
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
    closest_ = ocl::Kernel(program_, "intersect_closest_batch", "intersect.closest");
    stack_ = ocl::Kernel(program_, "intersect_closest_stack_batch", "intersect.closest_stack");
    any_ = ocl::Kernel(program_, "intersect_any_batch", "intersect.any");
    final_ = ocl::Kernel(program_, "intersect_final", "intersect.final");
    dummy_stats_ = ocl::Array<TraceStats>::allocate(dev, 1, "a placeholder");
}

::cl::Event BatchTracer::enqueue(const DeviceBvh& bvh, const ::cl::Buffer& rays, int count, const ::cl::Buffer& hits,
                                 TraceVariant v, const ::cl::Buffer* stats, ocl::Profiler* profiler) {
    ocl::Kernel& k = v == TraceVariant::Stackless ? closest_ : v == TraceVariant::Stack ? stack_ : any_;
    if (stats && !stats_) fail("BatchTracer: statistics requested from a tracer built without them");
    // A WP_STATS kernel writes stats[i] for every ray: never into the one-element placeholder.
    if (stats_ && !stats) fail("BatchTracer: a tracer built with statistics needs a statistics buffer");
    // *_batch(rays, count, nodes, links, tris, prim_ids, hits, stats)
    return k.launch({&dev_.queue, profiler}, static_cast<std::size_t>(count), rays, count,
                    bvh.nodes, bvh.links, bvh.triangles, bvh.prim_ids, hits,
                    stats ? *stats : dummy_stats_.buffer);
}

std::vector<Hit> BatchTracer::trace_final(const DeviceBvh& bvh, const DeviceBvh& emitters,
                                          const std::vector<Ray>& rays) {
    std::vector<Hit> hits(rays.size());
    if (rays.empty()) return hits;
    const std::size_t n = rays.size();
    ::cl::Buffer rb = dev_.create_buffer(CL_MEM_READ_ONLY, n * sizeof(Ray), "the ray batch");
    ::cl::Buffer hb = dev_.create_buffer(CL_MEM_WRITE_ONLY, n * sizeof(Hit), "the hit batch");
    ::cl::Buffer cb = dev_.create_buffer(CL_MEM_READ_ONLY, sizeof(int), "the ray count");
    const int count = static_cast<int>(n);
    dev_.queue.enqueueWriteBuffer(rb, CL_FALSE, 0, n * sizeof(Ray), rays.data());
    dev_.queue.enqueueWriteBuffer(cb, CL_FALSE, 0, sizeof(int), &count);
    // intersect_final(rays, queue_count, nodes, links, tris, prim_ids, e_nodes, e_links, e_tris,
    // e_prim_ids, hits)
    final_.launch({&dev_.queue, nullptr}, n, rb, cb, bvh.nodes, bvh.links, bvh.triangles, bvh.prim_ids,
                  emitters.nodes, emitters.links, emitters.triangles, emitters.prim_ids, hb);
    dev_.queue.enqueueReadBuffer(hb, CL_TRUE, 0, n * sizeof(Hit), hits.data());
    return hits;
}

std::vector<Hit> BatchTracer::trace(const DeviceBvh& bvh, const std::vector<Ray>& rays, TraceVariant v,
                                    std::vector<TraceStats>* stats) {
    std::vector<Hit> hits(rays.size());
    if (rays.empty()) return hits;
    std::size_t n = rays.size();
    ::cl::Buffer rb = dev_.create_buffer(CL_MEM_READ_ONLY, n * sizeof(Ray), "the ray batch");
    ::cl::Buffer hb = dev_.create_buffer(CL_MEM_WRITE_ONLY, n * sizeof(Hit), "the hit batch");
    dev_.queue.enqueueWriteBuffer(rb, CL_FALSE, 0, n * sizeof(Ray), rays.data());
    ::cl::Buffer sb;
    if (stats_) sb = dev_.create_buffer(CL_MEM_WRITE_ONLY, n * sizeof(TraceStats), "the trace statistics");
    enqueue(bvh, rb, static_cast<int>(n), hb, v, stats_ ? &sb : nullptr);
    dev_.queue.enqueueReadBuffer(hb, CL_TRUE, 0, n * sizeof(Hit), hits.data());
    if (stats) {
        stats->resize(n);
        dev_.queue.enqueueReadBuffer(sb, CL_TRUE, 0, n * sizeof(TraceStats), stats->data());
    }
    return hits;
}

}  // namespace wp::bvh
