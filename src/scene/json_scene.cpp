#include "scene/json_scene.h"

#include "util/error.h"

namespace wp {

Scene load_json_scene(const std::filesystem::path& path) {
    fail("'{}': this format is not supported yet", path.string());
}

}  // namespace wp
