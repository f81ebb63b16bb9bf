// replay_main.cpp — runs a fuzz target's LLVMFuzzerTestOneInput on files, without libFuzzer.
//
// Built by the main CMake project (any compiler) as fuzz_replay_<target>: every argument is
// a file or a folder (its files, sorted; a missing folder is skipped); each file is read and
// passed once. No input at all is a failure. Used to keep
// the seed corpora and the regression inputs (fuzz/regressions/<target>) passing in the
// ordinary and the ASan+UBSan builds, where clang's libFuzzer is not available.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    std::vector<fs::path> files;
    for (int i = 1; i < argc; ++i) {
        std::error_code ec;
        if (fs::is_directory(argv[i], ec)) {
            for (const auto& e : fs::directory_iterator(argv[i]))
                if (e.is_regular_file()) files.push_back(e.path());
        } else if (fs::is_regular_file(argv[i], ec)) {
            files.emplace_back(argv[i]);
        } else if (!fs::exists(argv[i], ec)) {
            // fuzz/regressions/<target> exists only once a target has a regression input
            std::fprintf(stderr, "replay: '%s' does not exist; skipped\n", argv[i]);
        } else {
            std::fprintf(stderr, "replay: '%s' is neither a file nor a folder\n", argv[i]);
            return 2;
        }
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) {
        std::fprintf(stderr, "replay: no input files\n");
        return 2;
    }
    for (const fs::path& f : files) {
        std::ifstream in(f, std::ios::binary);
        std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::fprintf(stderr, "replay: %s (%zu bytes)\n", f.c_str(), bytes.size());
        LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    }
    std::printf("replay: %zu inputs, no crash\n", files.size());
    return 0;
}
