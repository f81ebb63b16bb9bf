#include "app/commands.h"

#include <vector>

#include <CL/opencl.hpp>
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "app/subcommands.h"
#include "dist/comm.h"
#include "render/distributed.h"
#include "util/error.h"

namespace wp::app {

int run(int argc, char** argv) {
    CLI::App app{"wavepath: a wavefront Monte Carlo path tracer on OpenCL"};
    app.set_version_flag("--version", std::string("wavepath ") + WP_VERSION);
    app.require_subcommand(1);
    std::vector<Subcommand> subs = {add_render(app), add_compare(app), add_converge(app),
                                   add_bench(app), add_devices(app), add_view(app)};
    // Under mpirun every rank parses the same command line: rank 0 alone prints its errors
    // (render/distributed.h; failures of one rank are worded by rank 0 too).
    const bool speak = dist::Comm::launcher_rank() == 0;
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help / --version print their text and exit 0; every other parse error (a value
        // of the wrong type, an unknown option, a missing argument) is a usage error: one
        // line with wavepath's prefix, exit 2 (commands.h).
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return speak ? app.exit(e) : 0;
        if (speak) fmt::print(stderr, "wavepath: error: {}\nRun with --help for more information.\n",
                   e.what());
        return 2;
    }
    try {
        for (auto& s : subs)
            if (s.app->parsed()) return s.run();
    } catch (const render::RankFailure& e) {
        if (!e.quiet) fmt::print(stderr, "wavepath: error: {}\n", e.what());
        return e.exit_code;
    } catch (const UsageError& e) {
        if (speak) fmt::print(stderr, "wavepath: error: {}\n", e.what());
        return 2;
    } catch (const Error& e) {
        if (speak) fmt::print(stderr, "wavepath: error: {}\n", e.what());
        return 1;
    } catch (const cl::Error& e) {
        if (speak) fmt::print(stderr, "wavepath: OpenCL error {} in {}\n", e.err(), e.what());
        return 1;
    } catch (const std::exception& e) {
        if (speak) fmt::print(stderr, "wavepath: error: {}\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace wp::app
