// profile.h — where the time went: the per-stage table, profile JSON and Chrome trace.
//
// Built from the profiler's summary of every named launch (cl/profiler.h), after
// pbrt-v4's "Wavefront Kernel Profile". Times are device times
// (CL_PROFILING_COMMAND_START/END). Work is reported per sample per pixel (spp): a wave of
// the path pool may hold several passes of the image or part of one, so "ms/spp" is a
// wave's device span divided by the passes it held.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/device.h"
#include "cl/profiler.h"
#include "util/host_trace.h"

namespace wp::render {

struct StageProfile {
    std::string name;
    int launches = 0;
    double total_ms = 0.0;
    double percent = 0.0;          // of the sum over all stages
    double ms_per_spp = 0.0;       // total over the samples per pixel rendered
    double max_ms_per_wave = 0.0;  // largest time of this stage in one wave
};

struct ProfileSummary {
    std::vector<StageProfile> stages;     // in first-launch order
    std::vector<ocl::WaveRecord> waves;   // per wave (at most Profiler::kMaxWaves kept)
    int wave_count = 0;
    double spp = 0.0;                     // samples per pixel rendered
    double kernel_ms = 0.0;               // sum of all launch times
    double median_ms_per_spp = 0.0;       // median over passes (median_ms_per_pass)
    std::uint64_t rays = 0;               // rays traced (closest hit and shadow)
    std::uint64_t shadow_rays = 0;        // of them, shadow rays (shadow_trace)
    double mrays_per_s = 0.0;             // rays / sum of wave spans
};

// The median time of one sample per pixel: waves are taken together into whole passes (a
// pass of an image larger than the pool runs as several waves over different parts of the
// image, whose costs differ with what those parts show), and the median is over the groups
// of span / passes (a wave of k >= 1 passes is its own group). When the profiler thinned its
// wave records (`thinned`), the waves no longer join into passes, and each kept wave counts
// alone.
double median_ms_per_pass(const std::vector<ocl::WaveRecord>& waves, bool thinned);

// rays: all rays traced; shadow_rays: how many of them were shadow rays.
ProfileSummary summarize_profile(const ocl::Profiler& profiler, std::uint64_t rays,
                                 std::uint64_t shadow_rays = 0);

// The table, ending in a newline.
std::string format_profile_table(const ProfileSummary& p);

// The summary as JSON (the caller adds device and scene sections).
nlohmann::json profile_json(const ProfileSummary& p);

// Chrome trace-event JSON (Perfetto, chrome://tracing): one complete event ("ph": "X") per
// recorded launch on track (tid) 1 "device queue" (cat "kernel"), and one per host span
// (util/host_trace.h: load, device, bvh, upload, programs, resolve, write) on track 2 "host" (cat
// "host"), shifted onto the device clock by `host_offset_ns` (device_clock_offset_ns());
// times in microseconds from the earliest event; `dropped` launches past the profiler's
// record limit are noted in the metadata.
nlohmann::json chrome_trace(const std::vector<ocl::LaunchRecord>& records, std::size_t dropped = 0,
                            const std::vector<HostEvent>& host = {}, std::int64_t host_offset_ns = 0);

// Device profiling clock minus the host's steady clock, in nanoseconds, measured once with a
// marker: its end time against the host time halfway between enqueue and finish (0 when the
// device does not time markers).
std::int64_t device_clock_offset_ns(ocl::Device& dev);

// "out/prof.json" -> "out/prof.trace.json"
std::filesystem::path trace_path_for(const std::filesystem::path& profile_path);

}  // namespace wp::render
