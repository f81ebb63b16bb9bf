// assimp_loader.h — PLY and other mesh formats through Assimp.
// (Interface stub: the full contract is written with the implementation.)
#pragma once

#include <filesystem>
#include <string_view>

#include "scene/scene.h"

namespace wp {

Scene load_assimp(const std::filesystem::path& path);

}  // namespace wp
