#include "render/startup.h"

#include <fmt/format.h>

namespace wp::render {

nlohmann::json startup_json(const Startup& s) {
    nlohmann::json j;
    j["clock"] = "wall ms, steady clock; to_first_frame_ms from main(), exec_to_main_ms from the "
                 "process start (10 ms resolution)";
    if (s.exec_to_main_ms >= 0.0) j["exec_to_main_ms"] = s.exec_to_main_ms;
    j["load_ms"] = s.load_ms;
    j["device_ms"] = s.device_ms;
    j["device_wait_ms"] = s.device_wait_ms;
    j["scene_ms"] = s.scene_ms;
    j["programs_ms"] = s.programs_ms;
    auto& p = j["programs"] = nlohmann::json::array();
    for (const auto& x : s.programs) p.push_back({{"file", x.file}, {"ms", x.ms}, {"from_cache", x.from_cache}});
    j["first_frame_ms"] = s.first_frame_ms;
    j["first_frame_device_ms"] = s.first_frame_device_ms;
    j["first_launch_ms"] = s.first_launch_ms;
    j["to_first_frame_ms"] = s.to_first_frame_ms;
    if (s.exec_to_main_ms >= 0.0) j["to_first_frame_from_exec_ms"] = s.exec_to_main_ms + s.to_first_frame_ms;
    j["cache_store_ms"] = s.cache_store_ms;
    return j;
}

std::string format_startup(const Startup& s) {
    std::string exec = s.exec_to_main_ms >= 0.0 ? fmt::format(" (+{:.0f} ms exec to main)", s.exec_to_main_ms) : "";
    std::string out = fmt::format(
        "startup: {:.0f} ms from main to the first frame{}: load {:.0f}, device {:.0f} (beside the load; "
        "waited {:.0f}), scene {:.0f}, programs {:.0f}, first frame {:.0f} (device {:.0f}, first launches "
        "{:.0f}) ms\n",
        s.to_first_frame_ms, exec, s.load_ms, s.device_ms, s.device_wait_ms, s.scene_ms, s.programs_ms,
        s.first_frame_ms, s.first_frame_device_ms, s.first_launch_ms);
    std::string progs;
    for (const auto& p : s.programs)
        progs += fmt::format("{}{} {:.0f} ms ({})", progs.empty() ? "" : ", ", p.file, p.ms,
                             p.from_cache ? "cache" : "built");
    if (s.cache_store_ms > 0.0) progs += fmt::format("; after the render, cache stores {:.0f} ms", s.cache_store_ms);
    return out + "programs: " + progs + "\n";
}

}  // namespace wp::render
