#include "cl/profiler.h"

#include <algorithm>

namespace wp::ocl {

void Profiler::add(const std::string& name, const ::cl::Event& ev, int frame) {
    pending_.push_back({name, ev, frame});
}

void Profiler::resolve() {
    for (auto& p : pending_) {
        p.event.wait();
        LaunchRecord r;
        r.name = p.name;
        r.frame = p.frame;
        r.queued_ns = p.event.getProfilingInfo<CL_PROFILING_COMMAND_QUEUED>();
        r.start_ns = p.event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
        r.end_ns = p.event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        records_.push_back(std::move(r));
    }
    pending_.clear();
}

std::vector<StageTotals> Profiler::totals() const {
    std::vector<StageTotals> out;
    for (const auto& r : records_) {
        auto it = std::find_if(out.begin(), out.end(), [&](const StageTotals& s) { return s.name == r.name; });
        if (it == out.end()) {
            out.push_back({r.name});
            it = out.end() - 1;
        }
        double ms = (r.end_ns - r.start_ns) * 1e-6;
        it->launches += 1;
        it->total_ms += ms;
        it->max_ms = std::max(it->max_ms, ms);
    }
    return out;
}

void Profiler::clear() {
    pending_.clear();
    records_.clear();
}

::cl::Event launch(const ::cl::CommandQueue& queue, const ::cl::Kernel& kernel, const std::string& name,
                   std::size_t count, Profiler* profiler, int frame) {
    std::size_t global = (count + kLocalSize - 1) / kLocalSize * kLocalSize;
    if (global == 0) global = kLocalSize;
    ::cl::Event ev;
    queue.enqueueNDRangeKernel(kernel, ::cl::NullRange, ::cl::NDRange(global), ::cl::NDRange(kLocalSize),
                               nullptr, &ev);
    if (profiler) profiler->add(name, ev, frame);
    return ev;
}

}  // namespace wp::ocl
