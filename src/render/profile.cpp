#include "render/profile.h"

#include <algorithm>
#include <map>

#include <fmt/format.h>

namespace wp::render {

ProfileSummary summarize_profile(const std::vector<ocl::LaunchRecord>& records, std::uint64_t rays) {
    ProfileSummary p;
    p.rays = rays;
    int max_frame = -1;
    for (const auto& r : records) max_frame = std::max(max_frame, r.frame);
    p.frames = max_frame + 1;

    // Per stage: totals and per-frame sums; per frame: the device span.
    std::vector<std::uint64_t> lo(p.frames, UINT64_MAX), hi(p.frames, 0);
    std::map<std::string, std::vector<double>> per_frame;
    for (const auto& r : records) {
        double ms = (r.end_ns - r.start_ns) * 1e-6;
        auto it = std::find_if(p.stages.begin(), p.stages.end(),
                               [&](const StageProfile& s) { return s.name == r.name; });
        if (it == p.stages.end()) {
            p.stages.push_back({r.name});
            it = p.stages.end() - 1;
        }
        it->launches += 1;
        it->total_ms += ms;
        p.kernel_ms += ms;
        if (r.frame >= 0) {
            auto& v = per_frame[r.name];
            v.resize(p.frames, 0.0);
            v[r.frame] += ms;
            lo[r.frame] = std::min(lo[r.frame], r.start_ns);
            hi[r.frame] = std::max(hi[r.frame], r.end_ns);
        }
    }
    for (auto& s : p.stages) {
        s.percent = p.kernel_ms > 0.0 ? 100.0 * s.total_ms / p.kernel_ms : 0.0;
        auto it = per_frame.find(s.name);
        if (it != per_frame.end() && p.frames > 0) {
            double sum = 0.0;
            for (double v : it->second) {
                sum += v;
                s.max_ms_per_frame = std::max(s.max_ms_per_frame, v);
            }
            s.mean_ms_per_frame = sum / p.frames;
        }
    }
    double span_total = 0.0;
    for (int f = 0; f < p.frames; ++f) {
        double ms = hi[f] > lo[f] ? (hi[f] - lo[f]) * 1e-6 : 0.0;
        p.frame_ms.push_back(ms);
        span_total += ms;
    }
    if (!p.frame_ms.empty()) {
        std::vector<double> sorted = p.frame_ms;
        std::sort(sorted.begin(), sorted.end());
        std::size_t m = sorted.size();
        p.median_frame_ms = m % 2 ? sorted[m / 2] : 0.5 * (sorted[m / 2 - 1] + sorted[m / 2]);
    }
    p.mrays_per_s = span_total > 0.0 ? rays / (span_total * 1e-3) * 1e-6 : 0.0;
    return p;
}

std::string format_profile_table(const ProfileSummary& p) {
    std::string s = fmt::format("Wavefront kernel profile ({} frames, device times)\n", p.frames);
    s += fmt::format("  {:<20} {:>9} {:>11} {:>8} {:>13} {:>12}\n", "stage", "launches",
                     "total ms", "% total", "mean ms/frame", "max ms/frame");
    for (const auto& st : p.stages)
        s += fmt::format("  {:<20} {:>9} {:>11.2f} {:>7.1f}% {:>13.3f} {:>12.3f}\n", st.name,
                         st.launches, st.total_ms, st.percent, st.mean_ms_per_frame,
                         st.max_ms_per_frame);
    s += fmt::format("  {:<20} {:>9} {:>11.2f} {:>7.1f}%\n", "total", "", p.kernel_ms, 100.0);
    s += fmt::format("  median {:.2f} ms/frame, {:.2f} Mrays/s ({} rays)\n", p.median_frame_ms,
                     p.mrays_per_s, p.rays);
    return s;
}

nlohmann::json profile_json(const ProfileSummary& p) {
    nlohmann::json j;
    j["frames"] = p.frames;
    j["kernel_ms"] = p.kernel_ms;
    j["median_frame_ms"] = p.median_frame_ms;
    j["rays"] = p.rays;
    j["mrays_per_s"] = p.mrays_per_s;
    j["frame_ms"] = p.frame_ms;
    auto& st = j["stages"] = nlohmann::json::array();
    for (const auto& s : p.stages)
        st.push_back({{"name", s.name},
                      {"launches", s.launches},
                      {"total_ms", s.total_ms},
                      {"percent", s.percent},
                      {"mean_ms_per_frame", s.mean_ms_per_frame},
                      {"max_ms_per_frame", s.max_ms_per_frame}});
    return j;
}

nlohmann::json chrome_trace(const std::vector<ocl::LaunchRecord>& records) {
    std::uint64_t t0 = UINT64_MAX;
    for (const auto& r : records) t0 = std::min(t0, r.start_ns);
    auto events = nlohmann::json::array();
    events.push_back({{"name", "process_name"}, {"ph", "M"}, {"pid", 1},
                      {"args", {{"name", "wavepath device"}}}});
    events.push_back({{"name", "thread_name"}, {"ph", "M"}, {"pid", 1}, {"tid", 1},
                      {"args", {{"name", "queue"}}}});
    for (const auto& r : records) {
        events.push_back({{"name", r.name},
                          {"cat", "kernel"},
                          {"ph", "X"},
                          {"pid", 1},
                          {"tid", 1},
                          {"ts", (r.start_ns - t0) * 1e-3},
                          {"dur", (r.end_ns - r.start_ns) * 1e-3},
                          {"args", {{"frame", r.frame}}}});
    }
    return {{"traceEvents", events}, {"displayTimeUnit", "ms"}};
}

std::filesystem::path trace_path_for(const std::filesystem::path& profile_path) {
    std::filesystem::path p = profile_path;
    std::string stem = p.extension() == ".json" ? p.stem().string() : p.filename().string();
    return p.parent_path() / (stem + ".trace.json");
}

}  // namespace wp::render
