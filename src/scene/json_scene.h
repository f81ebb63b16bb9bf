// json_scene.h — wavepath JSON scene files (see README, 'Scene files').
// (Interface stub: the full contract is written with the implementation.)
#pragma once

#include <filesystem>
#include <string_view>

#include "scene/scene.h"

namespace wp {

Scene load_json_scene(const std::filesystem::path& path);

}  // namespace wp
