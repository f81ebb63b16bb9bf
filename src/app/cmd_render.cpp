// cmd_render.cpp — `wavepath render` (placeholder until the wavefront renderer lands).
#include "app/subcommands.h"
#include "util/error.h"

namespace wp::app {

Subcommand add_render(CLI::App& app) {
    Subcommand s;
    s.app = app.add_subcommand("render", "Render a scene (not implemented yet)");
    s.run = []() -> int { fail("render is not implemented yet"); };
    return s;
}

}  // namespace wp::app
