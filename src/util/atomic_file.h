// atomic_file.h — write a file completely or not at all.
//
// The content goes to a temporary file next to the destination, which is renamed over it
// only after a successful write; a failure removes the temporary and leaves the
// destination as it was.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace wp {

// Calls write(temp_path) and renames temp_path to path if it returns without throwing.
// Throws wp::Error naming `path` when the folder is missing or not writable.
void write_atomically(const std::filesystem::path& path,
                      const std::function<void(const std::filesystem::path&)>& write);

// Writes text atomically.
void write_text_atomically(const std::filesystem::path& path, const std::string& text);

}  // namespace wp
