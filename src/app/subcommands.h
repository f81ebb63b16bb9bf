// subcommands.h — each subcommand registers its options on the CLI and returns the action
// that runs it. One file per subcommand (cmd_<name>.cpp).
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace wp::app {

struct Subcommand {
    CLI::App* app = nullptr;
    std::function<int()> run;  // returns the exit code
};

Subcommand add_devices(CLI::App& app);
Subcommand add_render(CLI::App& app);
Subcommand add_bench(CLI::App& app);
Subcommand add_compare(CLI::App& app);
Subcommand add_converge(CLI::App& app);
Subcommand add_view(CLI::App& app);  // cmd_view.cpp (docs/viewer.md)

}  // namespace wp::app
