// profiler.h — named, timed launches.
//
// Every kernel launch goes through launch(), which pads the global size to a multiple of
// the fixed local size (NOTES-pocl.md, trap 4: one work-group function per local size)
// and records the launch's profiling event under its name ("intersect.closest", ...).
// resolve() turns events into per-name totals once the queue has finished.
#pragma once

#include <CL/opencl.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace wp::ocl {

constexpr std::size_t kLocalSize = 64;

struct LaunchRecord {
    std::string name;
    std::uint64_t queued_ns = 0, start_ns = 0, end_ns = 0;  // device clock
    int frame = -1;                                        // caller's frame index, if any
};

struct StageTotals {
    std::string name;
    int launches = 0;
    double total_ms = 0.0;
    double max_ms = 0.0;
};

class Profiler {
  public:
    void add(const std::string& name, const ::cl::Event& ev, int frame = -1);
    // Waits for all recorded events and moves them into records(). Cheap when empty.
    void resolve();
    const std::vector<LaunchRecord>& records() const { return records_; }
    // Totals per name in first-launch order.
    std::vector<StageTotals> totals() const;
    void clear();

  private:
    struct Pending {
        std::string name;
        ::cl::Event event;
        int frame;
    };
    std::vector<Pending> pending_;
    std::vector<LaunchRecord> records_;
};

// Enqueues `kernel` over `count` work-items (padded to kLocalSize) and records it.
::cl::Event launch(const ::cl::CommandQueue& queue, const ::cl::Kernel& kernel, const std::string& name,
                   std::size_t count, Profiler* profiler = nullptr, int frame = -1);

}  // namespace wp::ocl
