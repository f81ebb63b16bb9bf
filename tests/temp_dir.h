// temp_dir.h — test scaffolding for files on disk: a temporary folder that removes itself,
// and `wavepath render` run as a user runs it (the binary at WP_CLI_PATH, in a folder,
// stderr captured). Header-only, so that any test file can use it (the ASan parser-test
// build picks test files by their [parser] tag, not by what they include).
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace wp::test {

class TempDir {
  public:
    std::filesystem::path path;

    // A new, empty folder under the system's temporary folder, unique in this process.
    TempDir() {
        static std::atomic<int> counter{0};
        path = std::filesystem::temp_directory_path() /
               ("wp-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        std::filesystem::remove_all(path);
        std::filesystem::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    // Writes `bytes` to path / name (creating folders on the way) and returns that path.
    std::filesystem::path write(const std::string& name, const std::string& bytes) const {
        std::filesystem::path p = path / name;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << bytes;
        return p;
    }

    // Every entry in the folder (hidden temporaries included).
    std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& e : std::filesystem::directory_iterator(path))
            names.push_back(e.path().filename().string());
        return names;
    }

    // No .exr, .png or .jpg in the folder.
    bool empty_of_images() const {
        for (const auto& e : std::filesystem::directory_iterator(path)) {
            auto ext = e.path().extension();
            if (ext == ".exr" || ext == ".png" || ext == ".jpg") return false;
        }
        return true;
    }
};

#ifdef WP_CLI_PATH
struct CliRun {
    int status = -1;   // exit status (-1: did not exit normally)
    std::string err;   // what it wrote to stderr
};

// `wavepath render ARGS` run in the folder `cwd` (stdout discarded).
inline CliRun run_render(const std::filesystem::path& cwd, const std::string& args) {
    static std::atomic<int> counter{0};
    std::filesystem::path err = std::filesystem::temp_directory_path() /
                                ("wp-test-stderr-" + std::to_string(::getpid()) + "-" +
                                 std::to_string(counter++) + ".txt");
    std::string cmd = "cd '" + cwd.string() + "' && '" WP_CLI_PATH "' render " + args +
                      " > /dev/null 2> '" + err.string() + "'";
    int rc = std::system(cmd.c_str());
    CliRun r;
    r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
    std::ifstream in(err);
    std::stringstream ss;
    ss << in.rdbuf();
    r.err = ss.str();
    std::error_code ec;
    std::filesystem::remove(err, ec);
    return r;
}
#endif

}  // namespace wp::test
