#include "scene/gltf_loader.h"

#include "util/error.h"

namespace wp {

Scene load_gltf(const std::filesystem::path& path) {
    fail("'{}': this format is not supported yet", path.string());
}

}  // namespace wp
