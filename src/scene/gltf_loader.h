// gltf_loader.h — glTF 2.0 files (.gltf, .glb) through tinygltf.
// (Interface stub: the full contract is written with the implementation.)
#pragma once

#include <filesystem>
#include <string_view>

#include "scene/scene.h"

namespace wp {

Scene load_gltf(const std::filesystem::path& path);

}  // namespace wp
