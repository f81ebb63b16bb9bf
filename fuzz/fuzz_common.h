// fuzz_common.h — what every fuzz target shares: an empty scratch folder for `origin`, and
// the rule "wp::Error is an answer, anything else is a bug".
//
// Each target calls one parser on the fuzzer's bytes with an origin inside a folder that
// is created empty once per process. Relative references in the input (meshes, .mtl, .bin
// buffers, textures) therefore find nothing. After every call the folder must still be
// empty: a parser that writes a file aborts the run. wp::Error is expected and swallowed;
// any other exception escapes and terminates (a crash the fuzzer reports), as do
// sanitizer findings, hangs (-timeout) and huge allocations (-rss_limit_mb/-malloc_limit_mb).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "util/error.h"

namespace wp::fuzz {

// The process's empty scratch folder (made on first use under $TMPDIR, removed at exit).
inline const std::filesystem::path& scratch_dir() {
    static const std::filesystem::path dir = [] {
        std::string tmpl = (std::filesystem::temp_directory_path() / "wp-fuzz-XXXXXX").string();
        if (!mkdtemp(tmpl.data())) {
            std::perror("wp-fuzz: mkdtemp");
            std::abort();
        }
        static std::filesystem::path keep;
        keep = tmpl;
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(keep, ec);
        });
        return std::filesystem::path(tmpl);
    }();
    return dir;
}

// Aborts when a parser left anything in the scratch folder.
inline void check_scratch_empty(const char* parser) {
    std::error_code ec;
    if (!std::filesystem::is_empty(scratch_dir(), ec) || ec) {
        std::fprintf(stderr, "wp-fuzz: %s wrote into the scratch folder %s\n", parser,
                     scratch_dir().c_str());
        std::abort();
    }
}

// Runs `parse` (a callable returning a Scene); wp::Error is an expected outcome.
template <typename Parse>
void run_one(const char* parser, Parse&& parse) {
    try {
        auto scene = parse();
        // A returned scene is validated by every loader; touch it so nothing is optimised away
        if (scene.triangles.empty()) {
            std::fprintf(stderr, "wp-fuzz: %s returned a scene without triangles\n", parser);
            std::abort();
        }
    } catch (const wp::Error&) {
    }
    check_scratch_empty(parser);
}

inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

}  // namespace wp::fuzz
