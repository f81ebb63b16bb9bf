// mitsuba_loader.h — Mitsuba 3 scene XML, the subset the classic research scenes use (pugixml).
// (Interface stub: the full contract is written with the implementation.)
#pragma once

#include <filesystem>
#include <string_view>

#include "scene/scene.h"

namespace wp {

Scene load_mitsuba(const std::filesystem::path& path);

}  // namespace wp
