// cmd_converge.cpp — `wavepath converge [SCENE] --time T`: speed against error.
//
// Renders each named configuration (--config NAME=OPTIONS, OPTIONS being `render` options
// such as "--depth 2 --traversal stack") K times with seeds base, base+1, ..., each for T
// seconds of render time, and records the error against a reference at checkpoints:
// every power of two in spp, and the end. The Wavefront is built once per configuration
// (Wavefront::reset between runs) and one discarded warm-up pass runs first, so program
// builds and kernel JIT are not render time; film reads and metrics at checkpoints are not
// counted either (render/loop.h). Writes a CSV (configuration, run, seed, spp, seconds,
// rmse, relmse, mae, mean_spp) and prints per configuration: relMSE at equal time (mean and
// standard deviation over runs), efficiency 1 / (relMSE · seconds), and the time to reach
// a target relMSE (log-log interpolation between checkpoints, mean over the runs that
// reach it).
//
// The reference is --reference REF.exr, or rendered here at --reference-spp with its own
// seed and variance (saved next to the CSV). Its own estimated error (from REF.var.exr) must
// be at most a tenth of the smallest relMSE reported, else a warning says so.
//
// Strategies side by side: a configuration may use adaptive sampling ("--adaptive
// [--adaptive-threshold X --min-spp N]", render/adaptive.h); its spp column is then the
// most samples any pixel has, and mean_spp the mean over pixels. The time of its checks is
// render time. A configuration with "--denoise" is measured by wavepath's denoised image
// (render/denoise.h) at each checkpoint: the time of that one denoise is added to the
// checkpoint's seconds (the render so far plus one denoise, so equal time stays equal
// time), and its errors are those of a biased image (the table says so).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/render_options.h"
#include "app/subcommands.h"
#include "cl/device.h"
#include "image/image.h"
#include "image/stats.h"
#include "render/denoise.h"
#include "render/loop.h"
#include "render/reference.h"
#include "render/wavefront.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/timer.h"

namespace wp::app {

namespace fs = std::filesystem;

namespace {

struct ConvergeArgs {
    std::string scene;
    std::string reference;
    int reference_spp = 1024;
    std::string reference_options;  // empty: the first configuration's options
    double time_s = 0.0;
    int runs = 4;
    std::vector<std::string> configs;  // NAME=OPTIONS
    std::string csv = "converge.csv";
    double target_relmse = -1.0;  // < 0: the worst configuration's equal-time relMSE
    std::uint32_t seed = 1;
    int max_spp = limits::kMaxSpp;
    bool quiet = false;
};

struct Config {
    std::string name;
    std::string options;
    ConfigArgs args;
    bool denoise = false;  // "--denoise": measured by the denoised image (biased)
};

struct Row {
    std::string config;
    int run = 0;
    std::uint32_t seed = 0;
    int spp = 0;
    double seconds = 0.0;
    ErrorMetrics err;
    double mean_spp = 0.0;  // the mean over pixels (adaptive sampling); else spp
};

// The image a configuration is measured by at a checkpoint: the film's mean, or with
// --denoise its denoised image, whose time is returned in *post_s (0 otherwise).
Image checkpoint_image(render::Wavefront& wf, const Config& config, render::Denoiser* denoiser,
                       double* post_s) {
    *post_s = 0.0;
    if (!config.denoise) return wf.resolve();
    Timer t;
    render::FilmMoments m = wf.moments();
    Image img = denoiser->run(m.mean, m.mean_variance, wf.aovs());
    *post_s = t.ms() / 1000.0;
    return img;
}

// Parses "NAME=OPTIONS" with the render configuration options.
Config parse_config(const std::string& spec) {
    auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0)
        usage_fail("--config '{}': expected NAME=OPTIONS, e.g. \"depth2=--depth 2\"", spec);
    Config c{spec.substr(0, eq), spec.substr(eq + 1), {}};
    if (c.name.find_first_of(",\"\n") != std::string::npos)
        usage_fail("--config '{}': the name must not contain commas or quotes", spec);
    // --denoise is converge's own (render has it as an output option): taken out here.
    std::string options;
    for (std::size_t i = 0; i < c.options.size();) {
        std::size_t j = c.options.find_first_of(" \t", i);
        if (j == std::string::npos) j = c.options.size();
        std::string word = c.options.substr(i, j - i);
        if (word == "--denoise")
            c.denoise = true;
        else if (!word.empty())
            options += (options.empty() ? "" : " ") + word;
        i = j + 1;
    }
    CLI::App parser{"configuration"};
    add_config_options(&parser, c.args);
    try {
        parser.parse(options, false);
    } catch (const CLI::ParseError& e) {
        usage_fail("--config '{}': {} (a configuration takes --depth, --size, --device, --traversal, --sampling, --glossy, --sampler, --rr-depth, --pool, --kernels, --shade-lanes, --adaptive, --adaptive-threshold, --min-spp, --replicates, --denoise)",
             spec, e.what());
    }
    return c;
}

bool power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }

double mean_of(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

double sd_of(const std::vector<double>& v) {
    if (v.size() < 2) return 0.0;
    double m = mean_of(v), s = 0.0;
    for (double x : v) s += (x - m) * (x - m);
    return std::sqrt(s / static_cast<double>(v.size() - 1));
}

// Time at which one run's relMSE first reaches `target`, interpolated log-log between
// checkpoints; nullopt when it never does.
std::optional<double> time_to(const std::vector<Row>& rows, double target) {
    for (std::size_t i = 0; i < rows.size(); ++i) {
        if (rows[i].err.relmse > target) continue;
        if (i == 0) return rows[0].seconds;
        double t0 = std::log(rows[i - 1].seconds), t1 = std::log(rows[i].seconds);
        double e0 = std::log(rows[i - 1].err.relmse), e1 = std::log(rows[i].err.relmse);
        double f = e0 == e1 ? 1.0 : (std::log(target) - e0) / (e1 - e0);
        return std::exp(t0 + f * (t1 - t0));
    }
    return std::nullopt;
}

int run_converge(const ConvergeArgs& a) {
    // 1. Options and outputs, before any work.
    if (!(a.time_s > 0.0) || !std::isfinite(a.time_s))
        usage_fail("--time must be a positive number of seconds (got {})", a.time_s);
    if (a.runs < 1) usage_fail("--runs must be at least 1 (got {})", a.runs);
    if (a.reference_spp < 2 || a.reference_spp > limits::kMaxSpp)
        usage_fail("--reference-spp must be in 2..{} (got {})", limits::kMaxSpp, a.reference_spp);
    if (a.max_spp < limits::kMinSpp || a.max_spp > limits::kMaxSpp)
        usage_fail("--max-spp must be in {}..{} (got {})", limits::kMinSpp, limits::kMaxSpp, a.max_spp);
    std::vector<Config> configs;
    for (const auto& spec : a.configs) configs.push_back(parse_config(spec));
    if (configs.empty()) configs.push_back(parse_config("default="));
    for (std::size_t i = 0; i < configs.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (configs[i].name == configs[j].name)
                usage_fail("--config name '{}' is used twice", configs[i].name);
    check_writable(a.csv, "--csv", false);
    Scene scene = load_scene(a.scene, a.quiet);
    std::vector<render::RenderSettings> settings;
    for (const auto& c : configs) {
        settings.push_back(make_settings(c.args, scene));
        // The denoiser reads the film's variance and every AOV.
        if (c.denoise) settings.back().variance = settings.back().aov = true;
    }

    // 2. The reference: given (size checked now), or rendered here with its own seed.
    render::Reference ref;
    if (!a.reference.empty()) {
        ref = render::load_reference(a.reference);
    } else {
        Config rc = parse_config("reference=" + (a.reference_options.empty()
                                                     ? configs.front().options
                                                     : a.reference_options));
        render::RenderSettings s = make_settings(rc.args, scene);
        s.variance = true;
        s.seed = 0x7e5e0000u + a.seed;  // not one of the runs' seeds
        fs::path out = fs::path(a.csv).replace_extension(".ref.exr");
        check_writable(out, "reference output", true);
        if (!a.quiet)
            fmt::print(stderr, "converge: rendering the reference ({} spp, options '{}') -> {}\n",
                       a.reference_spp, rc.options, out.string());
        ocl::Device dev = ocl::Device::open(rc.args.device);
        render::Wavefront wf(dev, scene, s);
        render::LoopOptions lo;
        lo.spp = a.reference_spp;
        render::render_frames(wf, lo, nullptr);
        render::FilmMoments m = wf.moments();
        write_image(out, m.mean);
        write_image(variance_path_for(out), m.mean_variance);
        ref = render::load_reference(out);
    }
    for (std::size_t i = 0; i < configs.size(); ++i)
        if (settings[i].width != ref.image.width || settings[i].height != ref.image.height)
            usage_fail("--config '{}' renders {}x{} but the reference '{}' is {}x{} (add --size {}x{})",
                 configs[i].name, settings[i].width, settings[i].height, ref.path.string(),
                 ref.image.width, ref.image.height, ref.image.width, ref.image.height);

    // 3. Every configuration's device and Wavefront first, so a bad one fails before any run.
    std::vector<std::unique_ptr<ocl::Device>> devices;
    std::vector<std::unique_ptr<render::Wavefront>> wavefronts;
    std::vector<std::unique_ptr<render::Denoiser>> denoisers;  // with --denoise (program built now)
    for (std::size_t ci = 0; ci < configs.size(); ++ci) {
        devices.push_back(std::make_unique<ocl::Device>(ocl::Device::open(configs[ci].args.device)));
        try {
            wavefronts.push_back(
                std::make_unique<render::Wavefront>(*devices.back(), scene, settings[ci]));
        } catch (const Error& e) {
            fail("--config '{}={}': {}", configs[ci].name, configs[ci].options, e.what());
        }
        wavefronts.back()->render_passes(1);  // warm-up: kernel JIT per local size happens here
        denoisers.push_back(configs[ci].denoise ? std::make_unique<render::Denoiser>(*devices.back())
                                                : nullptr);
    }

    // 4. Runs.
    std::vector<Row> rows;
    std::map<std::string, std::vector<std::vector<Row>>> by_config;  // config -> runs -> rows
    for (std::size_t ci = 0; ci < configs.size(); ++ci) {
        const Config& c = configs[ci];
        render::Wavefront& wf = *wavefronts[ci];
        auto& runs = by_config[c.name];
        for (int run = 0; run < a.runs; ++run) {
            std::uint32_t seed = a.seed + static_cast<std::uint32_t>(run);
            wf.reset(seed);
            std::vector<Row> rr;
            auto record = [&](int frames, double seconds) {
                double post_s = 0.0;  // this checkpoint's denoise (checkpoint_image)
                Image img = checkpoint_image(wf, c, denoisers[ci].get(), &post_s);
                rr.push_back({c.name, run, seed, frames, seconds + post_s,
                              compare_images(img, ref.image), wf.mean_spp()});
            };
            render::LoopOptions lo;
            lo.spp = a.max_spp;
            lo.time_limit_s = a.time_s;
            lo.checkpoint_due = [](int frames, double) { return power_of_two(frames); };
            lo.checkpoint = record;
            render::LoopResult res = render::render_frames(wf, lo, nullptr);
            if (rr.empty() || rr.back().spp != res.frames || rr.back().mean_spp != wf.mean_spp())
                record(res.frames, res.render_s);
            if (!a.quiet)
                fmt::print(stderr, "converge: {} run {} (seed {}): {} spp in {:.2f} s, {}\n",
                           c.name, run, seed, rr.back().spp, rr.back().seconds,
                           render::format_errors(rr.back().err));
            rows.insert(rows.end(), rr.begin(), rr.end());
            runs.push_back(std::move(rr));
        }
    }

    // 5. CSV.
    std::string csv = "configuration,run,seed,spp,seconds,rmse,relmse,mae,mean_spp\n";
    for (const Row& r : rows)
        csv += fmt::format("{},{},{},{},{:.6f},{:.6e},{:.6e},{:.6e},{:.3f}\n", r.config, r.run,
                           r.seed, r.spp, r.seconds, r.err.rmse, r.err.relmse, r.err.mae,
                           r.mean_spp);
    write_text_atomically(a.csv, csv);

    // 6. Summary: equal time, efficiency, time to the target.
    double target = a.target_relmse;
    if (target <= 0.0) {
        for (const auto& c : configs) {
            std::vector<double> last;
            for (const auto& rr : by_config[c.name]) last.push_back(rr.back().err.relmse);
            target = std::max(target, mean_of(last));
        }
    }
    fmt::print("{}: {} configuration(s) x {} run(s) of {} s; reference {} ({}x{}); relMSE eps "
               "1e-2\n",
               scene.name, configs.size(), a.runs, a.time_s, ref.path.string(), ref.image.width,
               ref.image.height);
    fmt::print("| configuration | options | spp at T | relMSE at T (mean ± sd) | efficiency "
               "1/(relMSE·s) | time to relMSE {:.3e} |\n|---|---|---|---|---|---|\n",
               target);
    double smallest = 1e300;
    for (const auto& c : configs) {
        std::vector<double> rel, spp, secs, tt, mspp;
        for (const auto& rr : by_config[c.name]) {
            rel.push_back(rr.back().err.relmse);
            spp.push_back(rr.back().spp);
            mspp.push_back(rr.back().mean_spp);
            secs.push_back(rr.back().seconds);
            for (const Row& r : rr) smallest = std::min(smallest, r.err.relmse);
            if (auto t = time_to(rr, target)) tt.push_back(*t);
        }
        double eff = 1.0 / (mean_of(rel) * mean_of(secs));
        std::string ttext = tt.empty() ? std::string("not reached")
                                       : fmt::format("{:.2f} s ({}/{} runs)", mean_of(tt),
                                                     tt.size(), rel.size());
        std::string spp_text = fmt::format("{:.0f}", mean_of(spp));
        if (c.args.adaptive) spp_text += fmt::format(" (mean {:.1f})", mean_of(mspp));
        fmt::print("| {}{} | {} | {} | {:.3e} ± {:.1e} | {:.3g} | {} |\n", c.name,
                   c.denoise ? " (denoised: biased)" : "",
                   c.options.empty() ? "(defaults)" : c.options, spp_text, mean_of(rel),
                   sd_of(rel), eff, ttext);
    }
    fmt::print("csv: {}\n", a.csv);
    std::string w = render::reference_warning(ref, smallest);
    if (!w.empty())
        fmt::print(stderr, "wavepath: warning: {}\n", w);
    else
        fmt::print("reference check: its own relMSE {:.3e} <= a tenth of the smallest reported "
                   "{:.3e}\n",
                   ref.own_relmse, smallest);
    return 0;
}

}  // namespace

Subcommand add_converge(CLI::App& app) {
    auto args = std::make_shared<ConvergeArgs>();
    Subcommand s;
    s.app = app.add_subcommand(
        "converge",
        "Speed against error: render each --config K times for --time seconds with different "
        "seeds, record RMSE/relMSE/MAE against a reference at every power of two in spp and "
        "at the end (CSV), and print relMSE at equal time, efficiency and time to a target.");
    auto* c = s.app;
    c->add_option("scene", args->scene, kSceneArgHelp);
    c->add_option("--reference", args->reference,
                  "Reference EXR (e.g. from `render --spp 4096 --variance`); REF.var.exr next "
                  "to it is used to check the reference's own error. Default: render one here");
    c->add_option("--reference-spp", args->reference_spp,
                  "Samples per pixel of the reference rendered when --reference is not given")
        ->capture_default_str();
    c->add_option("--reference-options", args->reference_options,
                  "Render options of that reference (default: the first configuration's)");
    c->add_option("--time", args->time_s, "Render time per run, seconds")->required();
    c->add_option("--runs", args->runs, "Runs per configuration (seeds SEED .. SEED+K-1)")
        ->capture_default_str();
    c->add_option("--config", args->configs,
                  "A configuration NAME=OPTIONS, OPTIONS being render options (--depth, --size, "
                  "--device, --traversal, --sampling, --glossy, --sampler, --rr-depth, --pool, "
                  "--kernels, --shade-lanes, --adaptive, --adaptive-threshold, --min-spp, --replicates, --denoise), e.g. \"d2=--depth 2 "
                  "--size 200x150\" or \"adaptive=--adaptive --adaptive-threshold 1e-3\"; repeatable. "
                  "With --adaptive the spp column is the most samples a pixel got and mean_spp the mean; "
                  "with --denoise the error is the denoised image's (biased) and its seconds include "
                  "one denoise")
        ->take_all()
        ->allow_extra_args(false);
    c->add_option("--csv", args->csv, "CSV output")->capture_default_str();
    c->add_option("--target-relmse", args->target_relmse,
                  "relMSE target for the time-to-target column (default: the worst "
                  "configuration's relMSE at equal time)");
    c->add_option("--seed", args->seed, "Seed of run 0")->capture_default_str();
    c->add_option("--max-spp", args->max_spp, "Stop a run at this spp even before --time")
        ->capture_default_str();
    c->add_flag("-q,--quiet", args->quiet, "No per-run lines");
    s.run = [args]() -> int { return run_converge(*args); };
    return s;
}

}  // namespace wp::app
