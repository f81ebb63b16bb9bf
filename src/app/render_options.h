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
    std::string sampling = "mis";         // uniform | cosine | nee | mis
    std::string glossy = "ggx";           // phong | ggx
    std::string sampler = "sobol";        // sobol | random
    int rr_depth = limits::kDefaultRrDepth;  // Russian roulette from this bounce on; -1 off
    bool depth_given = false;             // --depth was on the command line (beats the scene's)
};

// Registers --depth, --size, --device, --traversal, --sampling, --glossy, --rr-depth on `c`.
void add_config_options(CLI::App* c, ConfigArgs& a);

// Validates the options and fills the settings (size from the scene when not given).
// Throws wp::Error naming the option.
render::RenderSettings make_settings(const ConfigArgs& a, const Scene& scene);

// The built-in Cornell box for an empty argument or "builtin:cornell-box", the furnace box
// of the render tests (emission 0.5, albedo 0.6) for "builtin:closed-box-furnace", the
// MIS test scene for "builtin:veach-plates", else the scene file (scene/load.h). Prints
// the load report (scene/load.h: describe_scene) and the warnings to stderr unless quiet.
Scene load_scene(const std::string& arg, bool quiet = false);

// The one-line list of what `load_scene` accepts, for --help texts.
extern const char* const kSceneArgHelp;

// Fails unless `path` can be created: a supported extension (when an image), an existing,
// writable folder, and not itself a folder.
void check_writable(const std::filesystem::path& path, const char* what, bool image);

}  // namespace wp::app
