// error.h — the one exception type of wavepath, and small helpers around it.
//
// Every failure the user can cause or meet (bad input, a missing device, a kernel that does
// not build) is a wp::Error whose message names what failed and where; main() prints it
// once and exits non-zero.
#pragma once

#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace wp {

struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A usage error: an option or argument out of its range or malformed (the command line's
// fault, not the input files' or the machine's). The command line exits 2 for it, 1 for
// every other wp::Error.
struct UsageError : Error {
    using Error::Error;
};

template <typename... Args>
[[noreturn]] void fail(fmt::format_string<Args...> f, Args&&... args) {
    throw Error(fmt::format(f, std::forward<Args>(args)...));
}

template <typename... Args>
[[noreturn]] void usage_fail(fmt::format_string<Args...> f, Args&&... args) {
    throw UsageError(fmt::format(f, std::forward<Args>(args)...));
}

}  // namespace wp
