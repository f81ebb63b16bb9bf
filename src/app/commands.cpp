#include "app/commands.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "cl/device.h"
#include "util/error.h"

namespace wp::app {

namespace {

int cmd_devices() {
    auto devices = ocl::list_devices();
    if (devices.empty()) {
        fmt::print("no OpenCL devices found (is an OpenCL driver such as pocl-opencl-icd installed?)\n");
        return 1;
    }
    for (const auto& d : devices) {
        fmt::print("[{}] {}: {}\n    type {}, {} compute units, {} memory ({} per buffer)\n    {}, driver {}\n",
                   d.index, d.platform, d.name, d.type, d.compute_units, ocl::format_bytes(d.global_mem),
                   ocl::format_bytes(d.max_alloc), d.version, d.driver);
    }
    return 0;
}

}  // namespace

int run(int argc, char** argv) {
    CLI::App app{"wavepath: a wavefront Monte Carlo path tracer on OpenCL"};
    app.set_version_flag("--version", std::string("wavepath ") + WP_VERSION);
    app.require_subcommand(1);
    auto* devices = app.add_subcommand("devices", "List every OpenCL platform and device");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        if (devices->parsed()) return cmd_devices();
    } catch (const Error& e) {
        fmt::print(stderr, "wavepath: error: {}\n", e.what());
        return 1;
    } catch (const cl::Error& e) {
        fmt::print(stderr, "wavepath: OpenCL error {} in {}\n", e.err(), e.what());
        return 1;
    } catch (const std::exception& e) {
        fmt::print(stderr, "wavepath: error: {}\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace wp::app
