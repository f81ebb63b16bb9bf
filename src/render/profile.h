// profile.h — where the time went: the per-stage table, profile JSON and Chrome trace.
//
// Built from the profiling events of every named launch (cl/profiler.h), after pbrt-v4's
// "Wavefront Kernel Profile". Times are device times (CL_PROFILING_COMMAND_START/END).
// A frame's time is the span from the start of its first launch to the end of its last.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cl/profiler.h"

namespace wp::render {

struct StageProfile {
    std::string name;
    int launches = 0;
    double total_ms = 0.0;
    double percent = 0.0;             // of the sum over all stages
    double mean_ms_per_frame = 0.0;   // over frames
    double max_ms_per_frame = 0.0;
};

struct ProfileSummary {
    std::vector<StageProfile> stages;  // in first-launch order
    std::vector<double> frame_ms;      // per frame, device span
    int frames = 0;
    double kernel_ms = 0.0;            // sum of all launch times
    double median_frame_ms = 0.0;
    std::uint64_t rays = 0;            // rays traced (closest hit), all frames
    double mrays_per_s = 0.0;          // rays / sum of frame spans
};

ProfileSummary summarize_profile(const std::vector<ocl::LaunchRecord>& records, std::uint64_t rays);

// The table, ending in a newline.
std::string format_profile_table(const ProfileSummary& p);

// The summary as JSON (the caller adds device and scene sections).
nlohmann::json profile_json(const ProfileSummary& p);

// Chrome trace-event JSON (Perfetto, chrome://tracing): one complete event ("ph": "X") per
// launch on one track, times in microseconds from the first launch.
nlohmann::json chrome_trace(const std::vector<ocl::LaunchRecord>& records);

// "out/prof.json" -> "out/prof.trace.json"
std::filesystem::path trace_path_for(const std::filesystem::path& profile_path);

}  // namespace wp::render
