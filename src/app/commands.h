// commands.h — subcommands of the wavepath program.
#pragma once

namespace wp::app {

// Parses the command line and runs the subcommand; returns the process exit code:
// 0 success, 1 a failure (message on stderr), 2 a usage error.
int run(int argc, char** argv);

}  // namespace wp::app
