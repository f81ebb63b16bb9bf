#include "util/read_file.h"

#include <fstream>
#include <system_error>

#include "util/error.h"

namespace wp {

namespace fs = std::filesystem;

namespace {

// Reads at most max_bytes + 1 bytes (a file may grow after its size was asked).
bool read_bounded(const fs::path& path, std::uintmax_t max_bytes, std::string& out) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    char buf[1 << 16];
    while (in && out.size() <= max_bytes) {
        in.read(buf, sizeof buf);
        out.append(buf, static_cast<std::size_t>(in.gcount()));
    }
    return !in.bad();
}

}  // namespace

std::string read_file(const fs::path& path, std::uintmax_t max_bytes) {
    const std::string file = path.string();
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) fail("cannot open '{}': no such file", file);
    if (!fs::is_regular_file(st)) fail("cannot open '{}': not a regular file", file);
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec) fail("cannot read '{}': {}", file, ec.message());
    if (size > max_bytes)
        fail("'{}': the file is {} bytes, more than the limit of {}", file, size, max_bytes);
    std::string bytes;
    bytes.reserve(static_cast<std::size_t>(size));
    if (!read_bounded(path, max_bytes, bytes)) fail("cannot read '{}'", file);
    if (bytes.size() > max_bytes)
        fail("'{}': the file is more than the limit of {} bytes", file, max_bytes);
    return bytes;
}

std::optional<std::string> try_read_file(const fs::path& path, std::uintmax_t max_bytes) {
    std::error_code ec;
    if (!fs::is_regular_file(fs::status(path, ec)) || ec) return std::nullopt;
    const std::uintmax_t size = fs::file_size(path, ec);
    if (ec || size > max_bytes) return std::nullopt;
    std::string bytes;
    if (!read_bounded(path, max_bytes, bytes) || bytes.size() > max_bytes) return std::nullopt;
    return bytes;
}

}  // namespace wp
