#include "util/atomic_file.h"

#include <fstream>
#include <random>
#include <system_error>

#include "util/error.h"

namespace wp {

namespace fs = std::filesystem;

void write_atomically(const fs::path& path, const std::function<void(const fs::path&)>& write) {
    fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) fail("cannot write '{}': folder '{}' does not exist", path.string(), dir.string());
    // The temporary keeps the destination's extension: writers pick the format from it.
    std::random_device rd;
    fs::path tmp = dir / fmt::format(".{}.tmp{:08x}{}", path.stem().string(), rd(), path.extension().string());
    try {
        write(tmp);
    } catch (...) {
        fs::remove(tmp, ec);
        throw;
    }
    fs::rename(tmp, path, ec);
    if (ec) {
        fs::remove(tmp, ec);
        fail("cannot write '{}': {}", path.string(), ec.message());
    }
}

void write_text_atomically(const fs::path& path, const std::string& text) {
    write_atomically(path, [&](const fs::path& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        if (!out) fail("cannot write '{}': cannot create a file in its folder", path.string());
        out << text;
        out.close();
        if (!out) fail("cannot write '{}': write failed", path.string());
    });
}

}  // namespace wp
