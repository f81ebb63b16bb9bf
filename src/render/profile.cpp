#include "render/profile.h"

#include <algorithm>

#include <fmt/format.h>

namespace wp::render {

double median_ms_per_pass(const std::vector<ocl::WaveRecord>& waves, bool thinned) {
    std::vector<double> per_spp;
    double span = 0.0, passes = 0.0;
    for (const auto& w : waves) {
        if (!(w.passes > 0.0)) continue;
        span += w.span_ms;
        passes += w.passes;
        // A group ends at a whole number of passes (the parts of a pass add up to 1 up to
        // rounding: count / pixels per wave).
        if (thinned || passes >= 1.0 - 1e-9) {
            per_spp.push_back(span / passes);
            span = passes = 0.0;
        }
    }
    if (per_spp.empty()) return 0.0;
    std::sort(per_spp.begin(), per_spp.end());
    const std::size_t m = per_spp.size();
    return m % 2 ? per_spp[m / 2] : 0.5 * (per_spp[m / 2 - 1] + per_spp[m / 2]);
}

ProfileSummary summarize_profile(const ocl::Profiler& profiler, std::uint64_t rays,
                                 std::uint64_t shadow_rays) {
    ProfileSummary p;
    p.rays = rays;
    p.shadow_rays = shadow_rays;
    p.spp = profiler.passes();
    p.wave_count = profiler.wave_count();
    p.waves = profiler.waves();
    for (const auto& t : profiler.totals()) {
        StageProfile s;
        s.name = t.name;
        s.launches = t.launches;
        s.total_ms = t.total_ms;
        s.max_ms_per_wave = t.max_ms_per_wave;
        s.ms_per_spp = p.spp > 0.0 ? t.total_ms / p.spp : 0.0;
        p.kernel_ms += t.total_ms;
        p.stages.push_back(s);
    }
    for (auto& s : p.stages) s.percent = p.kernel_ms > 0.0 ? 100.0 * s.total_ms / p.kernel_ms : 0.0;
    p.median_ms_per_spp =
        median_ms_per_pass(p.waves, static_cast<std::size_t>(p.wave_count) > p.waves.size());
    const double span = profiler.span_ms();
    p.mrays_per_s = span > 0.0 ? rays / (span * 1e-3) * 1e-6 : 0.0;
    return p;
}

std::string format_profile_table(const ProfileSummary& p) {
    std::string s = fmt::format("Wavefront kernel profile ({:g} spp in {} waves, device times)\n",
                                p.spp, p.wave_count);
    s += fmt::format("  {:<20} {:>9} {:>11} {:>8} {:>11} {:>12}\n", "stage", "launches",
                     "total ms", "% total", "ms/spp", "max ms/wave");
    for (const auto& st : p.stages)
        s += fmt::format("  {:<20} {:>9} {:>11.2f} {:>7.1f}% {:>11.3f} {:>12.3f}\n", st.name,
                         st.launches, st.total_ms, st.percent, st.ms_per_spp, st.max_ms_per_wave);
    s += fmt::format("  {:<20} {:>9} {:>11.2f} {:>7.1f}%\n", "total", "", p.kernel_ms, 100.0);
    s += fmt::format("  median {:.2f} ms/spp, {:.2f} Mrays/s ({} rays)\n", p.median_ms_per_spp,
                     p.mrays_per_s, p.rays);
    return s;
}

nlohmann::json profile_json(const ProfileSummary& p) {
    nlohmann::json j;
    j["spp"] = p.spp;
    j["waves"] = p.wave_count;
    j["kernel_ms"] = p.kernel_ms;
    j["median_ms_per_spp"] = p.median_ms_per_spp;
    j["rays"] = p.rays;
    j["rays_closest"] = p.rays - p.shadow_rays;  // intersect.closest
    j["rays_shadow"] = p.shadow_rays;            // shadow
    j["rays_per_spp"] = p.spp > 0.0 ? double(p.rays) / p.spp : 0.0;
    j["mrays_per_s"] = p.mrays_per_s;
    auto& w = j["wave_ms"] = nlohmann::json::array();
    for (const auto& r : p.waves)
        w.push_back({{"wave", r.index}, {"passes", r.passes}, {"span_ms", r.span_ms},
                     {"kernel_ms", r.kernel_ms}});
    auto& st = j["stages"] = nlohmann::json::array();
    for (const auto& s : p.stages)
        st.push_back({{"name", s.name},
                      {"launches", s.launches},
                      {"total_ms", s.total_ms},
                      {"percent", s.percent},
                      {"ms_per_spp", s.ms_per_spp},
                      {"max_ms_per_wave", s.max_ms_per_wave}});
    return j;
}

std::int64_t device_clock_offset_ns(ocl::Device& dev) {
    try {
        dev.queue.finish();
        ::cl::Event ev;
        const std::uint64_t h0 = steady_ns();
        dev.queue.enqueueMarkerWithWaitList(nullptr, &ev);
        dev.queue.finish();
        const std::uint64_t h1 = steady_ns();
        const auto d = ev.getProfilingInfo<CL_PROFILING_COMMAND_END>();
        return static_cast<std::int64_t>(d) - static_cast<std::int64_t>(h0 + (h1 - h0) / 2);
    } catch (const ::cl::Error&) {
        return 0;
    }
}

nlohmann::json chrome_trace(const std::vector<ocl::LaunchRecord>& records, std::size_t dropped,
                            const std::vector<HostEvent>& host, std::int64_t host_offset_ns) {
    auto on_device = [&](std::uint64_t host_ns) {
        return static_cast<std::int64_t>(host_ns) + host_offset_ns;
    };
    std::int64_t t0 = INT64_MAX;
    for (const auto& r : records) t0 = std::min(t0, static_cast<std::int64_t>(r.start_ns));
    for (const auto& h : host) t0 = std::min(t0, on_device(h.start_ns));
    if (t0 == INT64_MAX) t0 = 0;
    auto events = nlohmann::json::array();
    events.push_back({{"name", "process_name"}, {"ph", "M"}, {"pid", 1},
                      {"args", {{"name", "wavepath device"}}}});
    events.push_back({{"name", "thread_name"}, {"ph", "M"}, {"pid", 1}, {"tid", 1},
                      {"args", {{"name", "device queue"}}}});
    events.push_back({{"name", "thread_name"}, {"ph", "M"}, {"pid", 1}, {"tid", 2},
                      {"args", {{"name", "host"}}}});
    for (const auto& r : records) {
        events.push_back({{"name", r.name},
                          {"cat", "kernel"},
                          {"ph", "X"},
                          {"pid", 1},
                          {"tid", 1},
                          {"ts", (static_cast<std::int64_t>(r.start_ns) - t0) * 1e-3},
                          {"dur", (r.end_ns - r.start_ns) * 1e-3},
                          {"args", {{"wave", r.wave}}}});
    }
    for (const auto& h : host)
        events.push_back({{"name", h.name},
                          {"cat", "host"},
                          {"ph", "X"},
                          {"pid", 1},
                          {"tid", 2},
                          {"ts", (on_device(h.start_ns) - t0) * 1e-3},
                          {"dur", (h.end_ns - h.start_ns) * 1e-3}});
    return {{"traceEvents", events},
            {"displayTimeUnit", "ms"},
            {"otherData", {{"launches_not_recorded", dropped}}}};
}

std::filesystem::path trace_path_for(const std::filesystem::path& profile_path) {
    std::filesystem::path p = profile_path;
    std::string stem = p.extension() == ".json" ? p.stem().string() : p.filename().string();
    return p.parent_path() / (stem + ".trace.json");
}

}  // namespace wp::render
