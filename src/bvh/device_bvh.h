// device_bvh.h — a flattened BVH in device buffers, and batch tracing through it.
//
// DeviceBvh owns the four buffers the intersect kernels read (nodes, links, leaf-ordered
// triangles, prim_ids). BatchTracer builds kernels/intersect.cl and traces host ray
// arrays (tests, oracles) or device ray buffers (the benchmark) with one of the traversal
// variants.
#pragma once

#include <CL/opencl.hpp>

#include <string>
#include <string_view>
#include <vector>

#include "bvh/flatten.h"
#include "cl/device.h"
#include "cl/kernel.h"
#include "cl/profiler.h"
#include "cl/program.h"

namespace wp::bvh {

// The four arrays every traversal reads, in the order the kernels take them.
struct DeviceBvh {
    ocl::Array<BvhNode> nodes;
    ocl::Array<BvhLinks> links;
    ocl::Array<TriBlock> triangles;  // the leaves' triangles in blocks (FlatBvh::triangles)
    ocl::Array<int> prim_ids;        // block lane -> original triangle index; -1: padding
    int node_count = 0;
    int triangle_count = 0;
    std::size_t bytes = 0;

    // whose: how the memory report and allocation errors name the four buffers ("the BVH
    // nodes", ...); "the emitters'" for the BVH of the emitting triangles alone
    // (render::DeviceScene::emitter_bvh).
    static DeviceBvh upload(const ocl::Device& dev, const FlatBvh& flat, std::string_view whose = "the");
};

enum class TraceVariant { Stackless, Stack, Any };
const char* to_string(TraceVariant v);

class BatchTracer {
  public:
    // stats: compile with -D WP_STATS (per-ray box/triangle test counts; slower).
    BatchTracer(const ocl::Device& dev, bool stats = false, const std::string& extra_options = "");

    // Traces host rays; returns one Hit per ray. With stats, fills per-ray counts.
    std::vector<Hit> trace(const DeviceBvh& bvh, const std::vector<Ray>& rays, TraceVariant v,
                           std::vector<TraceStats>* stats = nullptr);

    // Traces host rays as the last bounce's (kernels/intersect.cl intersect_final, the
    // wavefront entry, with a count buffer): through `emitters` (flatten_subset of the
    // emitting triangles) first, then through `bvh` up to the emitter met.
    std::vector<Hit> trace_final(const DeviceBvh& bvh, const DeviceBvh& emitters, const std::vector<Ray>& rays);

    // Enqueues a trace of `count` rays already on the device; returns its event.
    ::cl::Event enqueue(const DeviceBvh& bvh, const ::cl::Buffer& rays, int count, const ::cl::Buffer& hits,
                        TraceVariant v, const ::cl::Buffer* stats = nullptr, ocl::Profiler* profiler = nullptr);

    const ocl::Program& program() const { return program_; }

  private:
    const ocl::Device& dev_;
    bool stats_;
    ocl::Program program_;
    ocl::Kernel closest_, stack_, any_, final_;
    ocl::Array<TraceStats> dummy_stats_;
};

}  // namespace wp::bvh
