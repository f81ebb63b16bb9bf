// test_cl.cpp — the device layer: device selection errors, build errors that point at
// kernels/<file>:<line>, and the program cache.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "cl/device.h"
#include "cl/program.h"
#include "support.h"
#include "util/error.h"

using namespace wp;
namespace fs = std::filesystem;

namespace {

// Sets an environment variable for the lifetime of the object.
struct ScopedEnv {
    std::string name;
    std::string old;
    bool had;
    ScopedEnv(const char* n, const std::string& value) : name(n) {
        const char* o = std::getenv(n);
        had = o != nullptr;
        if (had) old = o;
        setenv(n, value.c_str(), 1);
    }
    ~ScopedEnv() {
        if (had)
            setenv(name.c_str(), old.c_str(), 1);
        else
            unsetenv(name.c_str());
    }
};

fs::path temp_dir(const char* tag) {
    fs::path d = fs::temp_directory_path() / fmt::format("wp-{}-{:08x}", tag, std::random_device{}());
    fs::create_directories(d / "shared");
    return d;
}

}  // namespace

TEST_CASE("device selection: an unknown selector lists the devices", "[kernel][cl]") {
    auto devices = ocl::list_devices();
    REQUIRE(!devices.empty());
    try {
        ocl::select_device("no-such-device-zzz");
        FAIL("no error");
    } catch (const Error& e) {
        std::string msg = e.what();
        CHECK(msg.find("no-such-device-zzz") != std::string::npos);
        CHECK(msg.find(devices[0].name) != std::string::npos);
    }
    CHECK_THROWS_AS(ocl::select_device("999"), Error);
    CHECK(ocl::select_device("0").name == devices[0].name);
    // A substring of the name, in another case, finds the same device.
    std::string part = devices[0].name.substr(0, 4);
    for (auto& c : part) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    CHECK(ocl::select_device(part).name == devices[0].name);
}

TEST_CASE("a kernel that fails to build names kernels/<file>:<line>", "[kernel][cl]") {
    // An included header followed by an error on line 4 of the .cl file: the #line markers
    // must map the compiler's message back to the real file and line.
    fs::path dir = temp_dir("broken");
    fs::copy_file(fs::path(WP_SOURCE_DIR) / "kernels/shared/compat.h", dir / "shared/compat.h");
    std::ofstream(dir / "broken.cl") << "#include \"shared/compat.h\"\n"
                                        "__kernel void broken(__global int* x) {\n"
                                        "    int ok = 1;\n"
                                        "    x[0] = ok + not_declared_anywhere;\n"
                                        "}\n";
    ScopedEnv env("WP_KERNEL_DIR", dir.string());
    ScopedEnv cache("WP_CACHE_DIR", "off");
    try {
        ocl::Program::build(test::device(), "broken.cl");
        FAIL("the broken kernel built");
    } catch (const Error& e) {
        std::string msg = e.what();
        INFO(msg);
        CHECK(msg.find("kernels/broken.cl:4") != std::string::npos);
        CHECK(msg.find("not_declared_anywhere") != std::string::npos);
    }
    fs::remove_all(dir);
}

TEST_CASE("programs come from the disk cache the second time", "[kernel][cl]") {
    fs::path dir = temp_dir("cache");
    ScopedEnv cache("WP_CACHE_DIR", (dir / "cache").string());
    auto a = ocl::Program::build(test::device(), "utility.cl", "-D WP_TEST_CACHE_KEY=1");
    auto b = ocl::Program::build(test::device(), "utility.cl", "-D WP_TEST_CACHE_KEY=1");
    auto c = ocl::Program::build(test::device(), "utility.cl", "-D WP_TEST_CACHE_KEY=2");
    CHECK_FALSE(a.from_cache);
    CHECK(b.from_cache);
    CHECK_FALSE(c.from_cache);  // other options: another key
    b.kernel("probe_layout");   // the cached binary is a usable program
    CHECK_THROWS_AS(b.kernel("no_such_kernel"), Error);
    fs::remove_all(dir);
}

// A deferred store (render defers them past its first frame) writes nothing until
// store_deferred_programs(), and the next build then loads the stored binary.
TEST_CASE("program cache: deferred stores are written by store_deferred_programs", "[kernel][cl]") {
    fs::path dir = temp_dir("deferred");
    ScopedEnv cache("WP_CACHE_DIR", (dir / "cache").string());
    auto files = [&] {
        std::size_t n = 0;
        if (fs::exists(dir / "cache"))
            for (const auto& e : fs::directory_iterator(dir / "cache")) n += e.path().extension() == ".bin";
        return n;
    };
    ocl::defer_cache_stores(true);
    auto a = ocl::Program::build(test::device(), "utility.cl", "-D WP_TEST_CACHE_KEY=3");
    ocl::defer_cache_stores(false);
    CHECK_FALSE(a.from_cache);
    CHECK(files() == 0);
    CHECK(ocl::store_deferred_programs() > 0.0);
    CHECK(files() == 1);
    CHECK(ocl::store_deferred_programs() == 0.0);  // nothing left
    auto b = ocl::Program::build(test::device(), "utility.cl", "-D WP_TEST_CACHE_KEY=3");
    CHECK(b.from_cache);
    fs::remove_all(dir);
}
