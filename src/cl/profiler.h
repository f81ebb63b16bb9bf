// profiler.h — named, timed launches, summarised as they finish.
//
// Every kernel launch goes through launch(), which pads the global size to a multiple of
// the fixed local size (NOTES-pocl.md, trap 4: one work-group function per local size)
// and records the launch's profiling event under its name ("intersect.closest", ...).
// resolve() waits for the recorded events and folds them into a summary whose size does
// not grow with the number of launches: per name the launch count, total and longest
// launch; per wave (a batch of samples the renderer launches together, begin_wave()) the
// device span and per-name time, kept for at most kMaxWaves waves (every other one is
// dropped when full, so the median stays representative); and the first kMaxTrace launches
// as records for the Chrome trace (later ones are counted, not kept).
#pragma once

#include <CL/opencl.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "shared/types.h"

namespace wp::ocl {

constexpr std::size_t kLocalSize = WP_GROUP_SIZE;  // kernels/shared/types.h

struct LaunchRecord {
    std::string name;
    std::uint64_t queued_ns = 0, start_ns = 0, end_ns = 0;  // device clock
    int wave = -1;                                         // wave index, -1 outside waves
};

struct StageTotals {
    std::string name;
    int launches = 0;
    double total_ms = 0.0;
    double max_ms = 0.0;           // longest single launch
    double max_ms_per_wave = 0.0;  // largest sum over one wave
};

// One wave: `passes` samples per pixel (1 = every pixel once; 0.25 = a quarter of the
// pixels once; 4 = every pixel four times), its device span and total launch time.
struct WaveRecord {
    int index = 0;
    double passes = 0.0;
    double span_ms = 0.0;    // first launch start to last launch end
    double kernel_ms = 0.0;  // sum of its launch times
};

class Profiler {
  public:
    static constexpr std::size_t kMaxTrace = 100000;
    static constexpr std::size_t kMaxWaves = 1 << 16;

    // Launches added from now on belong to a new wave of `passes` samples per pixel.
    void begin_wave(double passes);
    void add(const std::string& name, const ::cl::Event& ev);
    // Waits for all recorded events and folds them into the summary. Cheap when empty.
    void resolve();
    void clear();

    // Totals per name in first-launch order (the open wave included).
    std::vector<StageTotals> totals() const;
    // Finished waves (the open one included), at most kMaxWaves of them (see above).
    std::vector<WaveRecord> waves() const;
    double passes() const { return passes_total_; }  // samples per pixel of all waves begun
    int wave_count() const { return wave_count_; }
    double span_ms() const;  // sum of the device spans of all waves
    const std::vector<LaunchRecord>& trace() const { return trace_; }
    std::size_t trace_dropped() const { return trace_dropped_; }

  private:
    // A launch, or (wave >= 0 and no event) the start of wave `wave` of `passes`.
    struct Pending {
        std::string name;
        ::cl::Event event;
        int wave = -1;
        double passes = 0.0;
        bool wave_start = false;
    };
    struct OpenWave {
        WaveRecord rec;
        std::uint64_t lo = UINT64_MAX, hi = 0;
        std::vector<double> per_stage;  // ms per stage index
        bool any = false;
    };
    std::size_t stage_index(const std::string& name);
    void close_wave();
    WaveRecord finished(const OpenWave& w) const;

    std::vector<Pending> pending_;
    std::vector<StageTotals> stages_;
    std::vector<WaveRecord> waves_;
    std::size_t wave_stride_ = 1;  // keep every wave_stride_-th finished wave
    OpenWave open_;
    int wave_count_ = 0;   // waves begun
    double span_ms_closed_ = 0.0;
    double passes_total_ = 0.0;
    std::vector<LaunchRecord> trace_;
    std::size_t trace_dropped_ = 0;
};

// Enqueues `kernel` over `count` work-items (padded to the local size `local`, kLocalSize
// unless the kernel asks for another: Kernel) and records it.
::cl::Event launch(const ::cl::CommandQueue& queue, const ::cl::Kernel& kernel, const std::string& name,
                   std::size_t count, Profiler* profiler = nullptr, std::size_t local = kLocalSize);

}  // namespace wp::ocl
