// cmd_render.cpp — `wavepath render [SCENE]`: the wavefront path tracer on the command line.
//
// Loads the scene (the built-in Cornell box, or an OBJ/MTL file), checks every output path
// before any work, renders progressively (one sample per pixel per frame) until --spp or
// --time, writes the image(s) atomically and prints the per-stage kernel profile.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/subcommands.h"
#include "cl/device.h"
#include "image/image.h"
#include "render/loop.h"
#include "render/profile.h"
#include "render/progress.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "scene/obj_loader.h"
#include "util/atomic_file.h"
#include "util/error.h"

namespace wp::app {

namespace fs = std::filesystem;

namespace {

struct RenderArgs {
    std::string scene;     // empty: the built-in Cornell box
    int spp = 64;
    double time_s = 0.0;   // 0: no time limit
    int depth = 3;
    std::string size;      // "WxH"; empty: the scene camera's size
    std::uint32_t seed = 0;
    std::string device;
    std::string output;    // empty: render.exr + render.png in the current folder
    std::string profile;   // profile JSON path; the trace goes next to it
    bool quiet = false;
    bool verbose = false;
};

// Fails unless `path` can be created: a supported extension (when an image), an existing,
// writable folder, and not itself a folder.
void check_writable(const fs::path& path, const char* what, bool image) {
    if (image && !is_supported_image_path(path))
        fail("{} '{}': unknown image extension '{}' (supported: .exr, .png, .jpg, .jpeg)", what,
             path.string(), path.extension().string());
    fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        fail("{} '{}': folder '{}' does not exist", what, path.string(), dir.string());
    if (access(dir.c_str(), W_OK) != 0)
        fail("{} '{}': folder '{}' is not writable", what, path.string(), dir.string());
    if (fs::is_directory(path, ec)) fail("{} '{}' is a folder", what, path.string());
}

Scene load_scene(const std::string& arg) {
    if (arg.empty()) return make_cornell_box();
    fs::path p(arg);
    std::error_code ec;
    if (!fs::exists(p, ec)) fail("scene file '{}' not found", arg);
    std::string ext = p.extension().string();
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".obj") return load_obj(p);
    fail("scene file '{}': unsupported format '{}' (supported: .obj)", arg, ext);
}

int run_render(const RenderArgs& a) {
    // 1. Options.
    if (a.spp < 1) fail("--spp must be at least 1 (got {})", a.spp);
    if (a.depth < 0) fail("--depth must be at least 0 (got {})", a.depth);
    if (!(a.time_s >= 0.0) || !std::isfinite(a.time_s))
        fail("--time must be a number of seconds >= 0 (got {})", a.time_s);
    std::optional<std::pair<int, int>> size;
    if (!a.size.empty()) {
        static const std::regex re(R"((\d{1,6})[xX](\d{1,6}))");
        std::smatch m;
        if (!std::regex_match(a.size, m, re))
            fail("--size '{}': expected WIDTHxHEIGHT, e.g. 800x600", a.size);
        int w = std::stoi(m[1]), h = std::stoi(m[2]);
        if (w <= 0 || h <= 0) fail("--size '{}': width and height must be positive", a.size);
        if (static_cast<long long>(w) * h > (1LL << 26))
            fail("--size '{}': more than 2^26 pixels", a.size);
        size = {w, h};
    }

    // 2. Outputs: checked before any work, so a bad path fails in milliseconds.
    std::vector<fs::path> outputs;
    if (a.output.empty())
        outputs = {"render.exr", "render.png"};
    else
        outputs = {a.output};
    for (const auto& o : outputs) check_writable(o, "output", true);
    fs::path trace_path;
    if (!a.profile.empty()) {
        check_writable(a.profile, "--profile", false);
        trace_path = render::trace_path_for(a.profile);
    }

    // 3. Scene and device.
    Scene scene = load_scene(a.scene);
    if (!a.quiet)
        for (const auto& w : scene.warnings) fmt::print(stderr, "wavepath: warning: {}\n", w);
    ocl::Device dev = ocl::Device::open(a.device);

    render::RenderSettings s;
    s.width = size ? size->first : scene.camera.width;
    s.height = size ? size->second : scene.camera.height;
    s.depth = a.depth;
    s.seed = a.seed;
    render::Wavefront wf(dev, scene, s);
    if (a.verbose) {
        fmt::print(stderr, "device: {}: {} ({})\n", dev.info.platform, dev.info.name, dev.info.driver);
        fmt::print(stderr, "scene: {} ({} triangles, {} materials, BVH {} nodes, depth {}, {:.1f} ms)\n",
                   scene.name, wf.stats().triangles, wf.stats().materials, wf.stats().bvh_nodes,
                   wf.stats().bvh_depth, wf.stats().bvh_build_ms);
        fmt::print(stderr, "kernel options: {}\n", wf.options());
    }

    // 4. Render.
    render::Progress progress(a.spp, a.time_s, !a.quiet);
    render::LoopOptions lo;
    lo.spp = a.spp;
    lo.time_limit_s = a.time_s;
    render::LoopResult res = render::render_frames(wf, lo, &progress);
    std::uint64_t rays = wf.rays_traced();
    progress.finish(res.frames, rays);

    // 5. Images (atomic writes).
    Image img = wf.resolve();
    for (const auto& o : outputs) write_image(o, img);

    // 6. Report.
    auto counters = wf.counters();
    int nonfinite = counters[WP_COUNTER_GENERATE_NONFINITE] + counters[WP_COUNTER_SHADE_NONFINITE] +
                    counters[WP_COUNTER_ACCUMULATE_NONFINITE];
    if (nonfinite > 0)
        fmt::print(stderr,
                   "wavepath: warning: {} NaN/Inf values caught and dropped (generate {}, shade {}, "
                   "accumulate {})\n",
                   nonfinite, counters[WP_COUNTER_GENERATE_NONFINITE],
                   counters[WP_COUNTER_SHADE_NONFINITE], counters[WP_COUNTER_ACCUMULATE_NONFINITE]);
    render::ProfileSummary prof = render::summarize_profile(wf.profiler().records(), rays);
    if (!a.quiet) {
        std::string names;
        for (const auto& o : outputs) names += (names.empty() ? "" : ", ") + o.string();
        fmt::print("{}: {}x{}, {} spp, depth {}, {:.2f} s{}; wrote {}\n", scene.name, s.width,
                   s.height, res.frames, s.depth, res.wall_s,
                   res.stopped_by_time ? " (time limit)" : "", names);
        fmt::print("kernel options: {}\n", wf.options());
        fmt::print("{}", render::format_profile_table(prof));
    }
    if (!a.profile.empty()) {
        nlohmann::json j = render::profile_json(prof);
        j["device"] = {{"platform", dev.info.platform}, {"name", dev.info.name},
                       {"version", dev.info.version}, {"driver", dev.info.driver},
                       {"type", dev.info.type}, {"compute_units", dev.info.compute_units}};
        const auto& st = wf.stats();
        j["scene"] = {{"name", scene.name}, {"triangles", st.triangles}, {"vertices", st.vertices},
                      {"materials", st.materials}, {"emissive_materials", st.emissive_materials},
                      {"bvh_nodes", st.bvh_nodes}, {"bvh_depth", st.bvh_depth},
                      {"bvh_build_ms", st.bvh_build_ms}, {"upload_ms", st.upload_ms},
                      {"program_ms", st.program_ms}};
        j["settings"] = {{"width", s.width}, {"height", s.height}, {"spp_requested", a.spp},
                         {"spp", res.frames}, {"depth", s.depth}, {"seed", s.seed},
                         {"time_limit_s", a.time_s}, {"wall_s", res.wall_s}};
        j["kernel_options"] = wf.options();
        j["nonfinite"] = {{"generate", counters[WP_COUNTER_GENERATE_NONFINITE]},
                          {"shade", counters[WP_COUNTER_SHADE_NONFINITE]},
                          {"accumulate", counters[WP_COUNTER_ACCUMULATE_NONFINITE]}};
        j["trace"] = trace_path.string();
        write_text_atomically(a.profile, j.dump(2) + "\n");
        write_text_atomically(trace_path, render::chrome_trace(wf.profiler().records()).dump() + "\n");
        if (!a.quiet) fmt::print("profile: {} (trace: {})\n", a.profile, trace_path.string());
    }
    return 0;
}

}  // namespace

Subcommand add_render(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    Subcommand s;
    s.app = app.add_subcommand(
        "render",
        "Render a scene with the wavefront path tracer. Without SCENE, renders the built-in "
        "Cornell box at 800x600 and writes render.exr (linear float) and render.png (sRGB) in "
        "the current folder.");
    auto* c = s.app;
    c->add_option("scene", args->scene,
                  "Scene file: a Wavefront .obj (with its .mtl). Default: the built-in Cornell box");
    c->add_option("--spp", args->spp, "Samples per pixel (one per frame), >= 1")
        ->capture_default_str();
    c->add_option("--time", args->time_s,
                  "Stop after this many seconds even if --spp is not reached (the frame in "
                  "flight completes); 0 = no limit")
        ->capture_default_str();
    c->add_option("--depth", args->depth,
                  "Maximum number of bounces (scattering events) per path, >= 0: 0 shows only "
                  "emitters and the background, D gathers light that bounced at most D times")
        ->capture_default_str();
    c->add_option("--size", args->size,
                  "Image size WIDTHxHEIGHT in pixels (default: the scene's, 800x600)");
    c->add_option("--seed", args->seed,
                  "Random seed: the same seed on the same device gives a bit-identical image")
        ->capture_default_str();
    c->add_option("--device", args->device,
                  "OpenCL device: an index from `wavepath devices`, or text matched against "
                  "'platform: name' (default: the first GPU, else the first device)");
    c->add_option("-o,--output", args->output,
                  "Write only this image; format from the extension: .exr (linear float), "
                  ".png/.jpg (8-bit sRGB). Default: render.exr and render.png");
    c->add_option("--profile", args->profile,
                  "Write the kernel profile (device, scene statistics, per-stage and per-frame "
                  "times) as JSON to this file, and a Chrome trace-event file (Perfetto) next to "
                  "it: FILE.json -> FILE.trace.json");
    c->add_flag("-q,--quiet", args->quiet,
                "No progress line, summary or profile table (errors and NaN warnings only)");
    c->add_flag("-v,--verbose", args->verbose,
                "Print the device, scene statistics and kernel options before rendering");
    s.run = [args]() -> int { return run_render(*args); };
    return s;
}

}  // namespace wp::app
