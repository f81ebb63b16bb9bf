// read_file.h — a whole file into memory, with a size limit: what every scene and mesh
// reader does before it parses (the parsers work on bytes in memory, see the fuzz targets).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace wp {

// The file's bytes. Throws wp::Error naming the file when it does not exist ("cannot open
// 'F': no such file"), is not a regular file (a folder, a device), is larger than max_bytes,
// or cannot be read.
std::string read_file(const std::filesystem::path& path, std::uintmax_t max_bytes);

// The same without exceptions: nullopt in each of those cases (for library callbacks that
// report a missing file their own way, such as `mtllib` and glTF buffers).
std::optional<std::string> try_read_file(const std::filesystem::path& path, std::uintmax_t max_bytes);

}  // namespace wp
