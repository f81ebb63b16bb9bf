// strings.h — small text helpers shared by the host code.
#pragma once

#include <cctype>
#include <string>

namespace wp {

// `s` with ASCII letters lowered (file extensions, colour-space and keyword names).
inline std::string ascii_lower(std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

}  // namespace wp
