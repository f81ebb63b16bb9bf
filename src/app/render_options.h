// render_options.h — the options that say how to render, shared by `render`, `converge`
// (its --config option sets) and anything else that renders.
//
// add_config_options registers the options that change *how* the image is made (depth,
// size, device, traversal): everything a converge configuration may set. Options of one
// render run (samples, time, seed, outputs) belong to each subcommand.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>

#include "render/wavefront.h"
#include "scene/scene.h"
#include "util/limits.h"

namespace wp::app {

struct ConfigArgs {
    int depth = limits::kDefaultDepth;
    std::string size;                    // "WxH"; empty: the scene camera's size
    std::string device;
    std::string traversal = "stackless";  // stackless | stack
    // The estimator's defaults are render::Estimator's (the one definition).
    std::string sampling = render::sampling_name(render::Estimator{}.sampling);  // uniform | cosine | nee | mis
    std::string glossy = render::glossy_name(render::Estimator{}.glossy);        // phong | ggx
    std::string sampler = render::Estimator{}.sobol ? "sobol" : "random";       // sobol | random
    int rr_depth = render::Estimator{}.rr_depth;  // Russian roulette from this bounce on; -1 off
    long long pool = 0;                   // paths in flight, 0..limits::kMaxPool; 0: automatic
    std::string kernels = "specialised";  // specialised | generic (render::KernelSet)
    std::string shade_lanes = "on";       // on | off (render::RenderSettings::shade_lanes)
    std::string light_pairs = "on";       // on | off (render::RenderSettings::light_pairs)
    std::string light_clearance = "on";   // on | off (render::RenderSettings::light_clearance)
    std::string shadow_rays = "shade";    // shade | stage (render::RenderSettings::shadows_in_shade)
    std::string final_rays = "emitters";  // emitters | closest (render::RenderSettings::final_rays)
    bool depth_given = false;             // --depth was on the command line (beats the scene's)
    // Adaptive sampling (render/adaptive.h): --adaptive, --adaptive-threshold, --min-spp.
    bool adaptive = false;
    double adaptive_threshold = limits::kDefaultAdaptiveThreshold;
    int min_spp = limits::kDefaultMinSpp;
    bool adaptive_threshold_given = false;
    // --replicates: RQMC replicates, a power of two in 1..limits::kMaxReplicates; 0 = auto
    // (make_settings gives 1; render gives kDefaultReplicates with --target-error and Sobol).
    long long replicates = 0;
};

// Registers --depth, --size, --device, --traversal, --sampling, --glossy, --sampler,
// --rr-depth, --pool, --kernels, --adaptive, --adaptive-threshold, --min-spp and
// --replicates on `c`.
void add_config_options(CLI::App* c, ConfigArgs& a);

// Validates the options and fills the settings (size from the scene when not given).
// Throws wp::Error naming the option.
render::RenderSettings make_settings(const ConfigArgs& a, const Scene& scene);

// The options of `render` that change the scene after loading (applied before rendering):
// --env FILE (an equirectangular map replacing the scene's environment), --env-scale S,
// --env-rotate DEG (about +y), --smooth DEG (computed smooth normals, crease angle DEG, for
// every triangle without normals). Ranges: util/limits.h.
struct SceneEdits {
    std::string env;          // empty: the scene's own environment (if any)
    double env_scale = 1.0;   // 0..limits::kMaxEnvScale
    double env_rotate = 0.0;  // degrees, -kMaxEnvRotateDeg..kMaxEnvRotateDeg
    double smooth = 0.0;      // crease angle in degrees, 0..kMaxCreaseDeg
    bool env_scale_given = false, env_rotate_given = false, smooth_given = false;
};

// Registers --env, --env-scale, --env-rotate and --smooth on `c`.
void add_scene_edit_options(CLI::App* c, SceneEdits& e);

// Checks the ranges (wp::UsageError naming the option and the allowed range) and that the
// --env file exists (wp::Error); before any work.
void check_scene_edits(const SceneEdits& e);

// Applies the edits to a loaded scene. With --env: its map (scene/texture.h, read as colour)
// with scale S and rotation DEG about +y replaces the scene's environment. Without --env,
// --env-scale multiplies and --env-rotate turns (after its own rotation) the scene's
// environment; a scene without one is a usage error. --smooth: scene/normals.h
// smooth_normals(scene, DEG) for every triangle without normals.
void apply_scene_edits(const SceneEdits& e, Scene& scene);

// The built-in Cornell box for an empty argument or "builtin:cornell-box", the furnace box
// of the render tests (emission 0.5, albedo 0.6) for "builtin:closed-box-furnace", the
// MIS test scene for "builtin:veach-plates", else the scene file (scene/load.h). Prints
// the load report (scene/load.h: describe_scene) and the warnings to stderr unless quiet.
// A scene file without a depth of its own gets render.depth = limits::kDefaultSceneDepth;
// the built-in scenes leave it unset (--depth's default, limits::kDefaultDepth, applies).
// `edits` (when given) are applied before the warnings are printed.
Scene load_scene(const std::string& arg, bool quiet = false, const SceneEdits* edits = nullptr);

// The one-line list of what `load_scene` accepts, for --help texts.
extern const char* const kSceneArgHelp;

// Fails unless `path` can be created: a supported extension (when an image; else a
// wp::UsageError), an existing folder in which a probe file (.wavepath-probe-XXXXXX) can be
// created, written (4 KiB) and removed, and not itself a folder. Milliseconds, before any
// work: a read-only or pseudo file system or a full disk fails here, not after the render.
void check_writable(const std::filesystem::path& path, const char* what, bool image);

}  // namespace wp::app
