// cmd_bench.cpp — `wavepath bench ...` (placeholder).
#include "app/subcommands.h"
#include "util/error.h"

namespace wp::app {

Subcommand add_bench(CLI::App& app) {
    Subcommand s;
    s.app = app.add_subcommand("bench", "Benchmarks");
    s.run = []() -> int { fail("bench is not implemented yet"); };
    return s;
}

}  // namespace wp::app
