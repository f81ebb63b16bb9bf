// texture.h — texture images: loading (OpenImageIO) and the device upload (mip chains).
// PROVISIONAL minimal version so the loaders can build; replaced by the texture branch.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "shared/types.h"

namespace wp {

enum class TextureUse { Colour, Data };

Texture load_texture(const std::filesystem::path& path, TextureUse use,
                     std::vector<std::string>& warnings);
Texture load_texture_from_memory(const std::string& bytes, const std::string& name, TextureUse use,
                                 std::vector<std::string>& warnings);
int add_texture_file(Scene& scene, const std::filesystem::path& path, TextureUse use);
Texture checkerboard_texture(glm::vec3 c0, glm::vec3 c1, const std::string& name);

struct TextureUpload {
    std::vector<TextureData> textures;
    std::vector<std::uint32_t> texels8;
    std::vector<float4> texelsf;
    std::size_t bytes() const;
};
TextureUpload upload_textures(const std::vector<const Texture*>& textures);

}  // namespace wp
