// cmd_render.cpp — `wavepath render [SCENE]`: the wavefront path tracer on the command line.
//
// Loads the scene (the built-in Cornell box, or a scene or mesh file), checks every output path
// before any work, renders progressively (1, 2, 4, ... samples per pixel per step, in waves of the path
// pool) until --spp or
// --time, writes the image(s) atomically (the samples so far on a first Ctrl-C) and, with
// --stats, prints the per-stage kernel profile.
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <future>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/interrupt.h"
#include "app/render_options.h"
#include "app/subcommands.h"
#include "cl/device.h"
#include "cl/program.h"
#include "dist/comm.h"
#include "image/image.h"
#include "image/stats.h"
#include "render/aov.h"
#include "render/denoise.h"
#include "render/distributed.h"
#include "render/loop.h"
#include "render/profile.h"
#include "render/progress.h"
#include "render/reference.h"
#include "render/startup.h"
#include "render/wavefront.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/host_trace.h"
#include "util/process_clock.h"
#include "util/timer.h"

namespace wp::app {

namespace fs = std::filesystem;

namespace {

struct RenderArgs {
    std::string scene;     // empty: the built-in Cornell box
    int spp = limits::kDefaultSpp;
    double time_s = 0.0;   // 0: no time limit
    double target_error = 0.0;  // --target-error: estimated relMSE to stop at; 0: none
    ConfigArgs config;     // depth, size, device, traversal, sampling, glossy, rr-depth (app/render_options.h)
    SceneEdits edits;      // --env, --env-scale, --env-rotate, --smooth (app/render_options.h)
    long long seed = 0;    // 0..limits::kMaxSeed, checked in run_render
    std::string output;    // empty: render.exr + render.png in the current folder
    std::string profile;   // profile JSON path; the trace goes next to it
    bool variance = false; // also write the variance of the mean (X.var.exr)
    std::string aov;       // --aov: comma list of albedo, normal, depth (render/aov.h)
    bool aov_png = false;  // --aov-png: PNG previews of the AOVs next to the output
    bool denoise = false;  // --denoise: OUT denoised, OUT.noisy.EXT the render itself
    std::string reference; // reference EXR to measure the error against
    bool quiet = false;
    bool verbose = false;
    bool stats = false;    // print the per-stage kernel table
    std::string debug_nan;     // comma list of stages to inject NaN into (debugging)
    int debug_nan_period = 97;
    bool spp_given = false;   // --spp / --seed on the command line beat the scene file's
    bool seed_given = false;
};

// OUT with ".noisy" before its extension: render.exr -> render.noisy.exr (--denoise).
fs::path noisy_path_for(const fs::path& out) {
    return out.parent_path() / (out.stem().string() + ".noisy" + out.extension().string());
}

// The PNG preview of AOV `name` next to `base`: render.exr -> render.albedo.png.
fs::path aov_preview_path_for(const fs::path& base, const char* name) {
    return base.parent_path() / (base.stem().string() + "." + name + ".png");
}

// Writes `img` to `path`: an EXR with the requested AOVs as extra channels (albedo.R/G/B,
// normal.X/Y/Z, depth.Z) when there are any, else as write_image does.
void write_output(const fs::path& path, const Image& img, const render::AovSet& set,
                  const render::AovImages* aov, const std::vector<ImageAttribute>& attrs) {
    std::string ext = path.extension().string();
    for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (!aov || !set.any() || ext != ".exr") {
        write_image(path, img, attrs);
        return;
    }
    std::vector<ImageChannel> ch = {{"R", img.rgb.data(), 3, 0}, {"G", img.rgb.data(), 3, 1},
                                    {"B", img.rgb.data(), 3, 2}};
    if (set.albedo)
        for (int c = 0; c < 3; ++c)
            ch.push_back({std::string("albedo.") + "RGB"[c], aov->albedo.rgb.data(), 3, std::size_t(c)});
    if (set.normal)
        for (int c = 0; c < 3; ++c)
            ch.push_back({std::string("normal.") + "XYZ"[c], aov->normal.rgb.data(), 3, std::size_t(c)});
    if (set.depth) ch.push_back({"depth.Z", aov->depth.data(), 1, 0});
    write_exr_channels(path, img.width, img.height, ch, attrs);
}

// How often the progress line's error against the reference is refreshed (film read-back).
constexpr double kReferenceInterval_s = 3.0;

// "generate,shade,accumulate" -> WP_INJECT_* bits; "" -> 0.
int parse_debug_nan(const std::string& list) {
    int mask = 0;
    std::size_t i = 0;
    while (i < list.size()) {
        std::size_t j = list.find(',', i);
        if (j == std::string::npos) j = list.size();
        std::string stage = list.substr(i, j - i);
        if (stage == "generate") mask |= WP_INJECT_GENERATE;
        else if (stage == "shade") mask |= WP_INJECT_SHADE;
        else if (stage == "accumulate") mask |= WP_INJECT_ACCUMULATE;
        else usage_fail("--debug-nan: unknown stage '{}' (expected generate, shade, accumulate)", stage);
        i = j + 1;
    }
    return mask;
}

// The device of a rank when --device is not given: the local_rank-th GPU of this node
// (modulo their number), else the local_rank-th device; "" when there is none (the
// single-process default then says so).
std::string device_for_rank(int local_rank) {
    const auto devices = ocl::list_devices();
    std::vector<int> gpus, all;
    for (const auto& d : devices) {
        all.push_back(d.index);
        if (d.is_gpu) gpus.push_back(d.index);
    }
    const auto& pick = gpus.empty() ? all : gpus;
    if (pick.empty()) return "";
    return std::to_string(pick[std::size_t(local_rank) % pick.size()]);
}

int run_render(RenderArgs a) {
    // 0. Distributed (mpirun -np N; render/distributed.h): rank 0 alone talks and writes.
    dist::Comm& comm = dist::Comm::world();
    const bool distributed = comm.size() > 1;
    const bool root = comm.rank() == 0;
    if (!dist::Comm::built_with_mpi() && dist::Comm::launched_by_mpi()) {
        const char* n = std::getenv("OMPI_COMM_WORLD_SIZE");
        if (n && std::atoi(n) > 1)
            fail("this wavepath was built without MPI (WP_WITH_MPI off or MPI not found), so {} "
                 "processes would each render and write the whole image; run one", n);
    }
    if (!root) {
        a.quiet = true;
        a.verbose = false;
        a.stats = false;
    }

    // 1. Options.
    if (a.spp < limits::kMinSpp || a.spp > limits::kMaxSpp)
        usage_fail("--spp must be in {}..{} (got {})", limits::kMinSpp, limits::kMaxSpp, a.spp);
    if (a.config.depth < limits::kMinDepth || a.config.depth > limits::kMaxDepth)
        usage_fail("--depth must be in {}..{} (got {})", limits::kMinDepth, limits::kMaxDepth,
             a.config.depth);
    if (!(a.time_s >= 0.0) || !std::isfinite(a.time_s))
        usage_fail("--time must be a finite number of seconds >= 0 (0: no limit; got {})",
                   a.time_s);
    if (a.seed < 0 || a.seed > limits::kMaxSeed)
        usage_fail("--seed must be in 0..{} (got {})", limits::kMaxSeed, a.seed);
    if (a.debug_nan_period < 1)
        usage_fail("--debug-nan-period must be in 1..{} (got {})",
                   std::numeric_limits<int>::max(), a.debug_nan_period);
    if (!(a.target_error == 0.0 || (a.target_error >= limits::kMinErrorThreshold &&
                                    a.target_error <= limits::kMaxErrorThreshold)))
        usage_fail("--target-error must be 0 (none) or in {:g}..{:g} (got {})",
                   limits::kMinErrorThreshold, limits::kMaxErrorThreshold, a.target_error);
    parse_debug_nan(a.debug_nan);  // checked before any work
    const render::AovSet aov_set = a.aov.empty() ? render::AovSet{} : render::parse_aov_list(a.aov);
    if (a.aov_png && !aov_set.any()) usage_fail("--aov-png needs --aov (which AOVs to preview)");
    check_scene_edits(a.edits);
    if (distributed && a.config.adaptive)
        usage_fail("--adaptive cannot be used with several MPI ranks: each pixel's sample count "
                   "would differ from rank to rank, and the ranks' films could not be added "
                   "(--target-error alone can; docs/distributed.md)");
    if (distributed && (aov_set.any() || a.denoise))
        usage_fail("--aov and --denoise cannot be used with several MPI ranks yet (the feature "
                   "buffers are not reduced; docs/distributed.md)");

    // 2. Outputs: checked before any work, so a bad path fails in milliseconds.
    std::vector<fs::path> outputs;
    if (a.output.empty())
        outputs = {"render.exr", "render.png"};
    else
        outputs = {a.output};
    for (const auto& o : outputs) check_writable(o, "output", true);
    // The AOVs go into the EXR outputs' channels (and the PNG previews).
    const fs::path* exr_output = nullptr;
    for (const auto& o : outputs) {
        std::string ext = o.extension().string();
        for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
        if (ext == ".exr" && !exr_output) exr_output = &o;
    }
    if (aov_set.any() && !exr_output && !a.aov_png)
        usage_fail("--aov: the AOVs are written as channels of an EXR output, and '{}' is not one "
                   "(write an .exr, or add --aov-png for PNG previews)", outputs.front().string());
    std::vector<fs::path> noisy_outputs;
    if (a.denoise)
        for (const auto& o : outputs) {
            noisy_outputs.push_back(noisy_path_for(o));
            check_writable(noisy_outputs.back(), "--denoise's noisy output", true);
        }
    std::vector<std::pair<fs::path, const char*>> previews;  // (path, AOV name)
    if (a.aov_png) {
        const fs::path base = exr_output ? *exr_output : outputs.front();
        for (const char* name : {"albedo", "normal", "depth"}) {
            const bool on = std::string(name) == "albedo"   ? aov_set.albedo
                            : std::string(name) == "normal" ? aov_set.normal
                                                            : aov_set.depth;
            if (!on) continue;
            previews.push_back({aov_preview_path_for(base, name), name});
            check_writable(previews.back().first, "--aov-png preview", true);
        }
    }
    fs::path trace_path;
    if (!a.profile.empty()) {
        check_writable(a.profile, "--profile", false);
        trace_path = render::trace_path_for(a.profile);
    }
    // The variance goes next to the EXR output (else next to the first output).
    fs::path variance_path;
    if (a.variance) {
        fs::path base = outputs.front();
        for (const auto& o : outputs)
            if (o.extension() == ".exr") {
                base = o;
                break;
            }
        variance_path = variance_path_for(base);
        check_writable(variance_path, "--variance output", true);
    }

    // 3. Scene and device. The device opens (PoCL's start-up: platform, device, context,
    // queue; tens of ms) on another thread while the scene loads. New programs' cache stores
    // wait until after the render (cl/program.h): a cold start reaches its first frame
    // without them.
    render::Startup startup;  // the cold-start split (render/startup.h)
    ocl::defer_cache_stores(true);
    Scene scene;
    render::RenderSettings s;
    int spp = 0;
    const bool target = a.target_error > 0.0;
    std::optional<render::Reference> ref;
    std::optional<ocl::Device> dev_holder;
    std::unique_ptr<render::Wavefront> wf_holder;
    auto setup = [&] {
        // With several ranks each picks its device by its rank on the node unless --device says.
        const std::string device_selector =
            distributed && a.config.device.empty() ? device_for_rank(comm.local_rank()) : a.config.device;
        std::future<ocl::Device> opening = std::async(std::launch::async, [&] {
            HostSpan span("device");
            Timer t;
            ocl::Device d = ocl::Device::open(device_selector);
            startup.device_ms = t.ms();
            return d;
        });
        // (std::async's future waits in its destructor: the opening ends before a failure
        // leaves this scope.)
        Timer step;
        scene = [&] {
            HostSpan span("load");
            return load_scene(a.scene, a.quiet, &a.edits);
        }();
        startup.load_ms = step.ms();
        s = make_settings(a.config, scene);
        // The scene file's spp and seed, unless given on the command line. With --target-error
        // only --spp limits the samples (the scene file's spp does not).
        spp = a.spp_given ? a.spp
              : target    ? limits::kMaxSpp
              : scene.render.spp ? *scene.render.spp
                                 : a.spp;
        s.seed = a.seed_given || !scene.render.seed ? static_cast<std::uint32_t>(a.seed)
                                                     : *scene.render.seed;
        s.inject_nan = parse_debug_nan(a.debug_nan);
        s.inject_period = a.debug_nan_period;
        if (spp < 1) fail("spp must be at least 1 (got {} from the scene file)", spp);
        // The denoiser reads the film's variance and every AOV.
        s.variance = a.variance || a.denoise;
        s.aov = aov_set.any() || a.denoise;
        // --target-error: the per-pixel error estimates (render/adaptive.h); with --adaptive and
        // no --adaptive-threshold, pixels stop at the target itself.
        s.error_estimate = target;
        // --replicates 0 (auto): RQMC replicates for the estimate of Sobol points (s^2/n
        // overstates their error), none otherwise.
        if (a.config.replicates == 0)
            s.replicates = target && s.estimator.sobol ? limits::kDefaultReplicates : 1;
        if (target && s.adaptive.enabled && !a.config.adaptive_threshold_given)
            s.adaptive.threshold = a.target_error;
        // A reference of the wrong size is an error before any rendering.
        if (!a.reference.empty() && root) ref = render::load_reference(a.reference, s.width, s.height);
        step.reset();
        dev_holder.emplace(opening.get());
        startup.device_wait_ms = step.ms();
        // Test aid for the distributed fault path (tests/mpi/mpi_test.cpp): this rank fails
        // its set-up as a device would.
        if (distributed && render::test_fail_round(comm.rank()) == 0)
            fail("WP_TEST_FAIL_RANK: rank {} was told to fail its set-up", comm.rank());
        wf_holder = std::make_unique<render::Wavefront>(*dev_holder, scene, s);
    };
    if (distributed)
        render::protected_step(comm, [&] {
            setup();
            return render::RankStatus{};
        });
    else
        setup();
    ocl::Device& dev = *dev_holder;
    render::Wavefront& wf = *wf_holder;
    // Each rank's host and device, for the profile's per-rank split.
    std::vector<std::string> rank_devices;
    if (distributed) {
        char host[64] = {};
        gethostname(host, sizeof host - 1);
        rank_devices = render::gather_text(
            comm, fmt::format("{}|{}|{}: {}", host, comm.local_rank(), dev.info.index, dev.info.name));
    }
    startup.scene_ms = wf.stats().upload_ms;
    startup.programs_ms = wf.stats().program_ms;
    startup.programs = wf.program_builds();
    if (!a.quiet) {
        for (const auto& w : wf.scene_warnings()) fmt::print(stderr, "wavepath: warning: {}\n", w);
        std::string app = render::describe_appearance(wf.stats());
        if (!app.empty()) fmt::print(stderr, "wavepath: device memory for appearance: {}\n", app);
    }
    // Host spans go onto the device's clock in the trace (measured once, before the render).
    const std::int64_t host_offset_ns = a.profile.empty() ? 0 : render::device_clock_offset_ns(dev);
    if (a.verbose) {
        fmt::print(stderr, "device: {}: {} ({})\n", dev.info.platform, dev.info.name, dev.info.driver);
        fmt::print(stderr,
                   "scene: {} ({} triangles, {} materials, BVH {} nodes, depth {}, built in {:.1f} ms, "
                   "flattened in {:.1f} ms)\n",
                   scene.name, wf.stats().triangles, wf.stats().materials, wf.stats().bvh_nodes,
                   wf.stats().bvh_depth, wf.stats().bvh_build_ms, wf.stats().bvh_flatten_ms);
        fmt::print(stderr, "{}", render::format_memory(wf.memory()));
        fmt::print(stderr, "kernel options: {}\n", wf.options());
    }

    // 4. Render. From here the first Ctrl-C / SIGTERM stops after the step in flight and the
    // samples so far are written (app/interrupt.h); a second one ends the process at once.
    install_interrupt_handler();
    render::Progress progress(spp, a.time_s, !a.quiet);
    if (target && !a.spp_given) progress.set_open_ended();
    render::LoopOptions lo;
    lo.spp = spp;
    if (target) {
        lo.target_error = a.target_error;
        lo.min_spp = s.adaptive.min_spp;
        lo.on_estimate = [&](double e) {
            std::string note = fmt::format("est. relMSE {:.3e} (target {:.3g})", e, a.target_error);
            if (wf.adaptive())
                note += fmt::format("  active {:.1f}%", 100.0 * double(wf.active_pixels()) / wf.pixel_count());
            progress.set_note(note);
        };
    } else if (s.adaptive.enabled) {
        // The share of pixels still sampled, after each step (no film read).
        lo.after_step = [&] {
            progress.set_note(fmt::format("active {:.1f}%", 100.0 * double(wf.active_pixels()) / wf.pixel_count()));
        };
    }
    lo.time_limit_s = a.time_s;
    lo.should_stop = [] { return interrupt_signal() != 0; };
    if (ref && !a.quiet && !distributed) {
        // The error in the progress line, from a film read every few seconds only.
        auto last = std::make_shared<Timer>();
        lo.checkpoint_due = [last](int, double) {
            return last->seconds() >= kReferenceInterval_s;
        };
        lo.checkpoint = [&, last](int, double) {
            ErrorMetrics m = compare_images(wf.resolve(), ref->image);
            progress.set_note(fmt::format("relMSE {:.3e}", m.relmse));
            last->reset();
        };
    }
    // Distributed: rounds over the ranks; on return rank 0's film is the total and the
    // other ranks are done (rank 0 writes).
    std::optional<render::DistributedResult> dres;
    if (distributed) {
        dres = render::render_distributed(comm, wf, lo, root ? &progress : nullptr);
        if (!root) {
            if (!dres->loop.interrupted && interrupt_signal() == 0) ocl::store_deferred_programs();
            if (int sig = interrupt_signal()) return 128 + sig;
            return 0;
        }
    }
    render::LoopResult res = distributed ? dres->loop : render::render_frames(wf, lo, &progress);
    startup.first_frame_ms = res.first_frame_ms;
    startup.first_frame_device_ms = res.first_frame_kernel_ms;
    startup.first_launch_ms = res.first_frame_ms - res.first_frame_kernel_ms;
    startup.to_first_frame_ms = double(res.first_frame_done_ns - main_start_ns()) * 1e-6;
    startup.exec_to_main_ms = exec_to_main_ms();
    const render::Wavefront::RayTotals ray_totals = wf.ray_totals();
    const std::uint64_t rays = ray_totals.closest + ray_totals.shadow;
    progress.finish(res.frames, rays, res.interrupted);

    // 5. Images (atomic writes).
    // The header records the samples per pixel and whether Ctrl-C cut the render short.
    std::vector<ImageAttribute> attrs = {
        {"wavepath:spp", std::to_string(res.frames), true},
        {"wavepath:interrupted", res.interrupted ? "1" : "0", true}};
    if (distributed) attrs.push_back({"wavepath:ranks", std::to_string(comm.size()), false});
    // Adaptive sampling: spp is the most any pixel got; the mean and the threshold too.
    if (s.adaptive.enabled) {
        attrs.push_back({"wavepath:adaptive_threshold", fmt::format("{:g}", s.adaptive.threshold), false});
        attrs.push_back({"wavepath:mean_spp", fmt::format("{:.3f}", wf.mean_spp()), false});
    }
    if (res.estimated_error >= 0.0)
        attrs.push_back({"wavepath:estimated_relmse", fmt::format("{:.6e}", res.estimated_error), false});
    // RQMC replicates (the estimate's kind; with Sobol points also the sampler's layout).
    if (res.estimated_error >= 0.0 || s.replicates > 1)
        attrs.push_back({"wavepath:replicates", std::to_string(s.replicates), true});
    Image img, variance;
    render::AovImages aov;
    {
        HostSpan span("resolve");
        if (s.aov) aov = wf.aovs();
        if (s.variance) {
            render::FilmMoments mom = wf.moments();
            img = std::move(mom.mean);
            variance = std::move(mom.mean_variance);
        } else {
            img = wf.resolve();
        }
    }
    // Denoise (biased: docs/denoise.md): OUT gets the denoised image, OUT.noisy.EXT the
    // render itself. Its time is reported apart from the render's (not a per-spp stage).
    Image denoised;
    double denoise_ms = 0.0, denoise_device_ms = 0.0, denoise_program_ms = 0.0;
    if (a.denoise) {
        HostSpan span("denoise");
        Timer t;
        render::Denoiser dn(dev);
        denoise_program_ms = t.ms();
        t.reset();
        denoised = dn.run(img, variance, aov);
        denoise_ms = t.ms();
        denoise_device_ms = dn.last_device_ms();
    }
    const Image& final_img = a.denoise ? denoised : img;
    const std::vector<ImageAttribute> out_attrs = [&] {
        std::vector<ImageAttribute> v = attrs;
        if (a.denoise) v.push_back({"wavepath:denoised", "1", true});
        return v;
    }();
    {
        HostSpan span("write");
        if (a.variance) write_image(variance_path, variance, attrs);
        for (const auto& o : noisy_outputs) write_output(o, img, aov_set, &aov, attrs);
        for (const auto& o : outputs) write_output(o, final_img, aov_set, &aov, out_attrs);
        for (const auto& [path, name] : previews) {
            const std::string n = name;
            write_image(path, n == "albedo" ? aov.albedo
                              : n == "normal" ? render::aov_preview_normal(aov)
                                              : render::aov_preview_depth(aov));
        }
    }
    std::optional<ErrorMetrics> err, err_noisy;
    if (ref) err = compare_images(final_img, ref->image);
    if (ref && a.denoise) err_noisy = compare_images(img, ref->image);

    // The deferred program cache stores (a cold start only; up to 2 s on PoCL), skipped
    // after a Ctrl-C, which asked to finish soon (PoCL's own cache keeps the builds).
    if (!res.interrupted && interrupt_signal() == 0) startup.cache_store_ms = ocl::store_deferred_programs();

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
    // The per-stage profile is rank 0's own (its launches, its rays); the ranks' split is in
    // the profile JSON's "distributed".
    render::ProfileSummary prof =
        distributed ? render::summarize_profile(wf.profiler(), dres->own_rays + dres->own_shadow_rays,
                                                dres->own_shadow_rays)
                    : render::summarize_profile(wf.profiler(), rays, ray_totals.shadow);
    if (!a.quiet) {
        std::string names;
        for (const auto& o : outputs) names += (names.empty() ? "" : ", ") + o.string();
        if (a.variance) names += ", " + variance_path.string() + " (variance of the mean)";
        for (const auto& o : noisy_outputs) names += ", " + o.string() + " (noisy)";
        for (const auto& pv : previews) names += ", " + pv.first.string();
        std::string why = res.stopped_by_target  ? fmt::format(" (target error reached)")
                          : res.stopped_by_time  ? std::string(" (time limit)")
                          : res.interrupted      ? fmt::format(" (interrupted at {} spp)", res.frames)
                          : res.converged        ? std::string(" (adaptive: every pixel converged)")
                          : target               ? std::string(" (spp limit)")
                                                 : std::string();
        std::string spp_text = s.adaptive.enabled
                                   ? fmt::format("{} spp at most, {:.1f} mean (adaptive, threshold {:g})",
                                                 res.frames, wf.mean_spp(), s.adaptive.threshold)
                                   : fmt::format("{} spp", res.frames);
        if (distributed) spp_text += fmt::format(" over {} ranks", comm.size());
        fmt::print("{}: {}x{}, {}, depth {}, {:.2f} s{}; wrote {}\n", scene.name, s.width,
                   s.height, spp_text, s.depth, res.render_s, why, names);
        if (res.estimated_error >= 0.0)
            fmt::print("estimated relMSE {:.3e} (from the image's own variance{}, eps 1e-2){}\n",
                       res.estimated_error,
                       s.replicates > 1 ? fmt::format(": {} RQMC replicates", s.replicates) : std::string(),
                       target ? fmt::format("; target {:g} {}", a.target_error,
                                            res.estimated_error <= a.target_error ? "reached" : "not reached")
                              : std::string());
        if (s.adaptive.enabled && a.verbose) {
            auto st = wf.adaptive_stats();
            fmt::print(stderr, "adaptive: {} checks, {:.1f} ms in all ({:.2f} ms each); {} of {} pixels still active\n",
                       st.checks, st.check_ms, st.checks ? st.check_ms / st.checks : 0.0,
                       wf.active_pixels(), wf.pixel_count());
        }
        fmt::print("kernel options: {}\n", wf.options());
        if (a.denoise)
            fmt::print("denoised in {:.1f} ms ({:.1f} ms on the device, {} + {} a-trous "
                       "iterations; program {:.1f} ms); the denoised image is biased\n",
                       denoise_ms, denoise_device_ms, render::DenoiseSettings{}.iterations,
                       render::DenoiseSettings{}.restore_iterations, denoise_program_ms);
        if (err)
            fmt::print("error against {}{}: {} (relMSE eps 1e-2); largest |difference| {:.3e} at "
                       "pixel ({}, {})\n",
                       a.reference, a.denoise ? " (denoised)" : "", render::format_errors(*err),
                       err->max_abs, err->max_x, err->max_y);
        if (err_noisy)
            fmt::print("error against {} (noisy): {}\n", a.reference, render::format_errors(*err_noisy));
        if (a.stats) fmt::print("{}", render::format_profile_table(prof));
    }
    if (a.verbose) fmt::print(stderr, "{}", render::format_startup(startup));
    if (err) {
        std::string w = render::reference_warning(*ref, err->relmse);
        if (!w.empty() && !a.quiet) fmt::print(stderr, "wavepath: warning: {}\n", w);
    }
    if (!a.profile.empty()) {
        nlohmann::json j = render::profile_json(prof);
        j["device"] = {{"platform", dev.info.platform}, {"name", dev.info.name},
                       {"version", dev.info.version}, {"driver", dev.info.driver},
                       {"type", dev.info.type}, {"compute_units", dev.info.compute_units}};
        const auto& st = wf.stats();
        j["scene"] = {{"name", scene.name}, {"triangles", st.triangles}, {"vertices", st.vertices},
                      {"materials", st.materials}, {"emissive_materials", st.emissive_materials},
                      {"light_triangles", st.light_triangles}, {"cleared_lights", st.cleared_lights},
                      {"clearance_ms", st.clearance_ms},
                      {"bvh_nodes", st.bvh_nodes}, {"bvh_depth", st.bvh_depth},
                      {"bvh_build_ms", st.bvh_build_ms}, {"bvh_flatten_ms", st.bvh_flatten_ms},
                      {"upload_ms", st.upload_ms},
                      {"program_ms", st.program_ms}};
        j["settings"] = {{"width", s.width}, {"height", s.height}, {"spp_requested", spp},
                         {"spp", res.frames}, {"depth", s.depth}, {"seed", s.seed},
                         {"traversal", render::traversal_name(s.traversal)},
                         {"kernels", render::kernel_set_name(s.kernels)},
                         {"shade_lanes", s.shade_lanes},
                         {"light_pairs", s.light_pairs},
                         {"light_clearance", s.light_clearance},
                         {"shadow_rays", wf.shadow_rays()},
                         {"final_rays", wf.final_rays_through_emitters() ? "emitters" : "closest"},
                         {"sampling", render::sampling_name(s.estimator.sampling)},
                         {"glossy", render::glossy_name(s.estimator.glossy)},
                         {"rr_depth", s.estimator.rr_depth},
                         {"sampler", s.estimator.sobol ? "sobol" : "random"},
                         {"replicates", s.replicates},
                         {"pool_paths", wf.pool_capacity()},
                         {"pool_bytes", wf.pool_bytes()},
                         {"film_bytes", wf.film_bytes()},
                         {"huge_pages", dev.huge_pages},
                         {"time_limit_s", a.time_s}, {"wall_s", res.wall_s},
                         {"render_s", res.render_s},
                         {"adaptive", s.adaptive.enabled},
                         {"target_error", a.target_error}};
        if (s.adaptive.enabled) {
            auto st = wf.adaptive_stats();
            j["adaptive"] = {{"threshold", s.adaptive.threshold}, {"min_spp", s.adaptive.min_spp},
                             {"mean_spp", wf.mean_spp()}, {"active_pixels", wf.active_pixels()},
                             {"checks", st.checks}, {"check_ms", st.check_ms}};
        }
        if (res.estimated_error >= 0.0)
            j["estimated_relmse"] = {{"value", res.estimated_error}, {"eps", 1e-2},
                                     {"stopped_by_target", res.stopped_by_target}};
        if (err)
            j["error"] = {{"reference", a.reference}, {"rmse", err->rmse},
                          {"relmse", err->relmse}, {"relmse_eps", 1e-2}, {"mae", err->mae},
                          {"max_abs", err->max_abs}, {"max_x", err->max_x},
                          {"max_y", err->max_y}, {"reference_own_relmse", ref->own_relmse}};
        if (a.denoise) {
            nlohmann::json noisy = nlohmann::json::array();
            for (const auto& o : noisy_outputs) noisy.push_back(o.string());
            j["denoise"] = {{"ms", denoise_ms}, {"device_ms", denoise_device_ms},
                            {"program_ms", denoise_program_ms},
                            {"iterations", render::DenoiseSettings{}.iterations},
                            {"restore_iterations", render::DenoiseSettings{}.restore_iterations},
                            {"noisy_outputs", noisy}, {"biased", true}};
            if (err_noisy) j["denoise"]["relmse_noisy"] = err_noisy->relmse;
        }
        j["memory"] = render::memory_json(wf.memory());
        if (distributed) {
            nlohmann::json ranks = nlohmann::json::array();
            for (std::size_t r = 0; r < dres->ranks.size(); ++r) {
                // "host|local rank|index: device name"
                const std::string& t = rank_devices[r];
                const auto bar1 = t.find('|'), bar2 = t.find('|', bar1 + 1);
                ranks.push_back({{"rank", r}, {"passes", dres->ranks[r].passes},
                                 {"seconds", dres->ranks[r].seconds}, {"rays", dres->ranks[r].rays},
                                 {"host", t.substr(0, bar1)},
                                 {"local_rank", std::atoi(t.substr(bar1 + 1, bar2 - bar1 - 1).c_str())},
                                 {"device", t.substr(bar2 + 1)}});
            }
            j["distributed"] = {{"ranks", comm.size()}, {"rounds", dres->rounds},
                                {"stages_from", "rank 0 (its own launches and rays)"},
                                {"reductions", dres->reduce.count},
                                {"reduce_bytes_per_rank", dres->reduce.bytes},
                                {"reduce_ms", dres->reduce.ms},
                                {"film_io_ms", dres->reduce.film_io_ms},
                                {"rays", rays},
                                {"per_rank", ranks}};
        }
        j["kernel_options"] = wf.options();
        j["startup"] = render::startup_json(startup);
        j["nonfinite"] = {{"generate", counters[WP_COUNTER_GENERATE_NONFINITE]},
                          {"shade", counters[WP_COUNTER_SHADE_NONFINITE]},
                          {"accumulate", counters[WP_COUNTER_ACCUMULATE_NONFINITE]}};
        j["trace"] = trace_path.string();
        write_text_atomically(a.profile, j.dump(2) + "\n");
        write_text_atomically(trace_path, render::chrome_trace(wf.profiler().trace(), wf.profiler().trace_dropped(),
                                                   host_trace().events(), host_offset_ns)
                                      .dump() + "\n");
        if (!a.quiet) fmt::print("profile: {} (trace: {})\n", a.profile, trace_path.string());
    }
    // Interrupted (or a signal during the writes): 128 + the signal, as a shell reports it.
    if (int sig = interrupt_signal()) return 128 + sig;
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
        "the current folder. Under `mpirun -np N` (when built with MPI) the N ranks share "
        "every pixel's samples, rank 0 writes the outputs, and the image is within 1 ulp of "
        "one process's (not with --adaptive, --aov or --denoise; docs/distributed.md).");
    auto* c = s.app;
    c->add_option("scene", args->scene, kSceneArgHelp);
    c->add_option("--spp", args->spp,
                  "Samples per pixel, 1..2^24 (beats the scene file's spp); with --adaptive the "
                  "most a pixel gets, with --target-error a limit")
        ->capture_default_str()
        ->each([a = args.get()](const std::string&) { a->spp_given = true; });
    c->add_option("--time", args->time_s,
                  "Stop after this many seconds even if --spp is not reached (the samples in "
                  "flight complete); 0 = no limit")
        ->capture_default_str();
    c->add_option("--target-error", args->target_error,
                  "Render until the image's estimated relMSE falls to this (e.g. 1e-3): the mean "
                  "over pixels of (1/3) sum over channels of v / (mean^2 + 0.01), v the variance "
                  "of the pixel's mean from the image itself (no reference): with Sobol points "
                  "from --replicates (4 by default), else s^2/n; estimated at --min-spp and "
                  "then every max(4, spp/4) passes (multiples of --replicates) and shown in the "
                  "progress line. --time and "
                  "--spp stay limits (whichever comes first; the summary says which stopped "
                  "it); without --spp only they limit it (not the scene file's spp). With "
                  "--adaptive, pixels stop at this error unless --adaptive-threshold is given. "
                  "0 = none")
        ->capture_default_str();
    add_config_options(c, args->config);
    add_scene_edit_options(c, args->edits);
    c->add_option("--seed", args->seed,
                  "Random seed: the same seed on the same device gives a bit-identical image "
                  "(beats the scene file's seed)")
        ->capture_default_str()
        ->each([a = args.get()](const std::string&) { a->seed_given = true; });
    c->add_option("-o,--output", args->output,
                  "Write only this image; format from the extension: .exr (linear float), "
                  ".png/.jpg (8-bit sRGB). Default: render.exr and render.png");
    c->add_option("--profile", args->profile,
                  "Write the kernel profile (device, scene statistics, per-stage, per-spp and per-wave "
                  "times, the start-up split as in -v) as JSON to this file, and a Chrome trace-event file (Perfetto) next to "
                  "it: FILE.json -> FILE.trace.json");
    c->add_flag("--variance", args->variance,
                "Also keep the per-pixel sum of squares and write the variance of the mean, "
                "s^2/n per channel (s^2: the unbiased sample variance of the n samples; "
                "multiply by n = spp to get s^2), as linear float RGB to OUT.var.exr next "
                "to the EXR output (render.var.exr by default): the input of `compare "
                "--variance` and of the reference checks of `converge`");
    c->add_option("--aov", args->aov,
                  "Also record feature buffers at each path's first non-specular hit and write "
                  "them as channels of the EXR output: comma list of albedo (albedo.R/G/B), "
                  "normal (normal.X/Y/Z, shading normal facing the camera), depth (depth.Z: "
                  "path length from the camera, +inf where nothing was hit), or all. Averaged "
                  "over each pixel's samples. Needs an .exr output or --aov-png");
    c->add_flag("--aov-png", args->aov_png,
                "Also write PNG previews of the --aov buffers next to the output: "
                "OUT.albedo.png, OUT.normal.png ((n+1)/2), OUT.depth.png (grey, depth / "
                "largest depth; white: no hit)");
    c->add_flag("--denoise", args->denoise,
                "Denoise: OUT gets the image filtered by wavepath's edge-avoiding a-trous "
                "denoiser (guided by albedo, normal, depth and the per-pixel variance, which "
                "it records), and the render itself is kept as OUT.noisy.EXT (render.exr -> "
                "render.noisy.exr, x.png -> x.noisy.png). Denoised images are biased: use the "
                "noisy one for z-tests (docs/denoise.md)");
    c->add_option("--reference", args->reference,
                  "Reference image (EXR of the same size) to measure the error against: "
                  "RMSE, relMSE = mean over pixels and channels of (x-r)^2/(r^2+0.01), MAE at "
                  "the end, and relMSE in the progress line every few seconds. A REF.var.exr "
                  "next to it is used to check that the reference's own error is small");
    c->add_option("--debug-nan", args->debug_nan,
                  "Debugging the NaN/Inf guards: inject NaN into these stages (comma list of "
                  "generate, shade, accumulate) for every pixel p with p % PERIOD == 0 in every "
                  "sample; each stage's guard must catch and count every one (reported at the "
                  "end), and the image stays finite")
        ->group("Debugging");
    c->add_option("--debug-nan-period", args->debug_nan_period,
                  "PERIOD of --debug-nan: every PERIOD-th pixel gets a NaN")
        ->capture_default_str()
        ->group("Debugging");
    c->add_flag("-q,--quiet", args->quiet,
                "No progress line or summary (errors and NaN warnings only)");
    c->add_flag("--stats", args->stats,
                "Print the per-stage kernel profile table (device times per stage, ms/spp, "
                "Mrays/s) after the summary");
    c->add_flag("-v,--verbose", args->verbose,
                "Print the device, scene statistics and kernel options before rendering, and "
                "after it the start-up split: ms from main() to the first frame (one sample "
                "per pixel done) and its steps (load, device, scene, programs, first frame "
                "and the first launches' compile wait), plus exec to main");
    s.run = [args]() -> int { return run_render(*args); };  // a copy: rank 0 alone talks
    return s;
}

}  // namespace wp::app
