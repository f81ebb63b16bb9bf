#include "image/codec.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <system_error>

#include "util/error.h"

// Set by the build (CMakeLists.txt): the module's path in the build tree.
#ifndef WP_IMAGE_MODULE_BUILT
#define WP_IMAGE_MODULE_BUILT ""
#endif

// Programs that link the codec's objects (the fuzzers) reference it strongly; everywhere
// else the reference is weak, so a program without it gets a null address and loads the
// module.
#if !defined(WP_IMAGE_CODEC_LINKED)
extern "C" const wp::codec::Codec* wp_image_codec_v1() __attribute__((weak));
#endif

namespace wp::codec {

#if !defined(WP_IMAGE_CODEC_LINKED)
namespace {

constexpr const char* kModuleName = "libwavepath_oiio.so";

// Where the module may be: $WP_IMAGE_MODULE alone when set, else next to the executable,
// then where the build put it.
std::vector<std::string> candidates() {
    namespace fs = std::filesystem;
    if (const char* env = std::getenv("WP_IMAGE_MODULE"); env && *env) return {env};
    std::vector<std::string> c;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) c.push_back((exe.parent_path() / kModuleName).string());
    if (*WP_IMAGE_MODULE_BUILT) c.emplace_back(WP_IMAGE_MODULE_BUILT);
    return c;
}

[[noreturn]] void not_loaded(const std::string& tried) {
    fail("cannot load the image module {} (OpenImageIO), which reads and writes image files; tried:{}{}",
         kModuleName, tried.empty() ? "\n  (no candidate path)" : tried,
         std::getenv("WP_IMAGE_MODULE") ? "" : "\n  (set WP_IMAGE_MODULE to its path)");
}

const Codec* load_module() {
    std::string tried;
    for (const std::string& path : candidates()) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
            tried += "\n  " + path + ": no such file";
            continue;
        }
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* why = dlerror();
            tried += "\n  " + path + ": " + (why ? why : "dlopen failed");
            continue;
        }
        using Entry = const Codec* (*)();
        auto entry = reinterpret_cast<Entry>(dlsym(handle, "wp_image_codec_v1"));
        if (!entry) {
            tried += "\n  " + path + ": no wp_image_codec_v1 in it";
            continue;
        }
        return entry();  // the handle stays open for the life of the process
    }
    not_loaded(tried);
}

}  // namespace
#endif

void check_available() {
#if !defined(WP_IMAGE_CODEC_LINKED)
    if (wp_image_codec_v1) return;
    std::string tried;
    for (const std::string& path : candidates()) {
        std::error_code ec;
        if (std::filesystem::exists(path, ec)) return;
        tried += "\n  " + path + ": no such file";
    }
    not_loaded(tried);
#endif
}

const Codec& image_codec() {
#if defined(WP_IMAGE_CODEC_LINKED)
    return *wp_image_codec_v1();
#else
    if (wp_image_codec_v1) return *wp_image_codec_v1();
    static std::once_flag once;
    static const Codec* codec = nullptr;
    static std::string failure;
    std::call_once(once, [] {
        try {
            codec = load_module();
        } catch (const Error& e) {
            failure = e.what();
        }
    });
    if (!codec) throw Error(failure);
    return *codec;
#endif
}

}  // namespace wp::codec
