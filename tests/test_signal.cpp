// test_signal.cpp — Ctrl-C keeps the work (issue 12, item 3), with real signals.
//
// Starts `wavepath render` (WP_CLI_PATH) with fork/exec on a render far too long to finish,
// waits until it has printed progress, and signals it: the first SIGINT/SIGTERM writes the
// samples so far (readable, finite, with "wavepath:interrupted" = 1 and "wavepath:spp" >= 1
// in its header) and exits 130/143; a second SIGINT ends it at once, killed by the signal,
// with no image left behind.
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "image/image.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

using wp::test::TempDir;

pid_t start_render(const fs::path& dir, const std::vector<std::string>& args) {
    std::vector<std::string> all = {WP_CLI_PATH, "render"};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    const std::string err = (dir / "stderr.txt").string();
    const std::string cwd = dir.string();
    pid_t pid = ::fork();
    if (pid == 0) {
        if (::chdir(cwd.c_str()) != 0) ::_exit(126);
        int fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        int out = ::open("stdout.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0 || out < 0) ::_exit(126);
        ::dup2(fd, 2);
        ::dup2(out, 1);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    return pid;
}

std::string read_text(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Waits (at most a minute) until the render has printed a progress line; false if it ended.
bool wait_for_progress(pid_t pid, const fs::path& dir) {
    for (auto t0 = std::chrono::steady_clock::now(); std::chrono::steady_clock::now() - t0 < 60s;) {
        if (read_text(dir / "stderr.txt").find("render: ") != std::string::npos) return true;
        int status = 0;
        if (::waitpid(pid, &status, WNOHANG) == pid) return false;
        std::this_thread::sleep_for(50ms);
    }
    return true;  // no progress yet: signal it anyway
}

// The wait status of pid, killing it after two minutes.
int wait_exit(pid_t pid) {
    int status = 0;
    for (auto t0 = std::chrono::steady_clock::now(); std::chrono::steady_clock::now() - t0 < 120s;) {
        if (::waitpid(pid, &status, WNOHANG) == pid) return status;
        std::this_thread::sleep_for(20ms);
    }
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    FAIL("the render did not end within two minutes of the signal");
    return status;
}

const std::vector<std::string> kLongRender = {"--size", "64x48", "--spp", "1000000", "-o", "out.exr"};

void check_interrupted(int sig, int expected_exit) {
    TempDir d;
    pid_t pid = start_render(d.path, kLongRender);
    REQUIRE(pid > 0);
    REQUIRE(wait_for_progress(pid, d.path));
    REQUIRE(::kill(pid, sig) == 0);
    int status = wait_exit(pid);
    std::string err = read_text(d.path / "stderr.txt");
    INFO(err);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == expected_exit);
    CHECK(err.find("interrupted at ") != std::string::npos);
    REQUIRE(fs::exists(d.path / "out.exr"));
    wp::Image img = wp::read_image(d.path / "out.exr");
    CHECK(img.width == 64);
    CHECK(img.height == 48);
    bool finite = true;
    double sum = 0.0;
    for (float v : img.rgb) {
        finite &= std::isfinite(v);
        sum += v;
    }
    CHECK(finite);
    CHECK(sum > 0.0);
    auto interrupted = wp::read_image_attribute(d.path / "out.exr", "wavepath:interrupted");
    auto spp = wp::read_image_attribute(d.path / "out.exr", "wavepath:spp");
    REQUIRE(interrupted);
    REQUIRE(spp);
    CHECK(*interrupted == "1");
    CHECK(std::stoi(*spp) >= 1);
    CHECK(std::stoi(*spp) < 1000000);
    // Nothing else left behind (no temporary of the atomic write).
    for (const auto& name : d.entries()) CHECK((name == "out.exr" || name == "stderr.txt" || name == "stdout.txt"));
}

}  // namespace

TEST_CASE("render: the first SIGINT writes the samples so far and exits 130", "[cli]") {
    check_interrupted(SIGINT, 130);
}

TEST_CASE("render: the first SIGTERM writes the samples so far and exits 143", "[cli]") {
    check_interrupted(SIGTERM, 143);
}

TEST_CASE("render: a second SIGINT ends the render at once, writing nothing", "[cli]") {
    TempDir d;
    // Steps of one pass of a 1024x768 image at depth 8 (the pool holds one pass) take far
    // longer than the 20 ms between the two signals, so the second always arrives while the
    // first one's step is still in flight, before any image is written.
    pid_t pid = start_render(d.path, {"--size", "1024x768", "--depth", "8", "--spp", "1000000",
                                      "-o", "out.exr"});
    REQUIRE(pid > 0);
    REQUIRE(wait_for_progress(pid, d.path));
    REQUIRE(::kill(pid, SIGINT) == 0);
    std::this_thread::sleep_for(20ms);  // two signals at once may merge into one
    REQUIRE(::kill(pid, SIGINT) == 0);
    int status = wait_exit(pid);
    INFO(read_text(d.path / "stderr.txt"));
    REQUIRE(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == SIGINT);
    CHECK_FALSE(fs::exists(d.path / "out.exr"));
}

// Progress within a pass (issue 12, item 5): a pass of three waves of a small pool reports
// fractional samples per pixel (the first line is printed after the first wave); the
// per-stage table is printed only with --stats.
TEST_CASE("render: progress within a pass, and the kernel table only with --stats", "[cli]") {
    for (bool stats : {false, true}) {
        TempDir d;
        std::vector<std::string> args = {"--size", "64x48", "--pool", "1024", "--spp", "2",
                                         "-o", "out.exr"};
        if (stats) args.push_back("--stats");
        pid_t pid = start_render(d.path, args);
        REQUIRE(pid > 0);
        int status = wait_exit(pid);
        std::string err = read_text(d.path / "stderr.txt");
        std::string out = read_text(d.path / "stdout.txt");
        INFO(err << out);
        REQUIRE(WIFEXITED(status));
        CHECK(WEXITSTATUS(status) == 0);
        CHECK(err.find("render: 0.33/2 spp") != std::string::npos);
        CHECK(err.find("render: 2/2 spp") != std::string::npos);
        CHECK(out.find("2 spp") != std::string::npos);  // the one-line summary
        CHECK((out.find("Wavefront kernel profile") != std::string::npos) == stats);
        CHECK(wp::read_image_attribute(d.path / "out.exr", "wavepath:interrupted") == "0");
        CHECK(wp::read_image_attribute(d.path / "out.exr", "wavepath:spp") == "2");
    }
}
