// PROVISIONAL minimal version so the loaders can build; replaced by the texture branch.
#include "scene/texture.h"

#include <OpenImageIO/imageio.h>

#include "util/error.h"

namespace wp {

namespace {
Texture placeholder(const std::string& name) {
    Texture t;
    t.source = name;
    t.width = t.height = 8;
    t.nearest = true;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            bool m = ((x ^ y) & 1) == 0;
            t.texels8.insert(t.texels8.end(), {std::uint8_t(m ? 255 : 0), 0, std::uint8_t(m ? 255 : 0), 255});
        }
    return t;
}
}  // namespace

Texture load_texture(const std::filesystem::path& path, TextureUse use, std::vector<std::string>&) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) fail("{}: cannot read the texture", path.string());
    const OIIO::ImageSpec& spec = in->spec();
    Texture t;
    t.source = path.string();
    t.width = spec.width;
    t.height = spec.height;
    std::vector<float> px(std::size_t(spec.width) * spec.height * spec.nchannels);
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data());
    t.texelsf.resize(std::size_t(spec.width) * spec.height * 4, 1.0f);
    for (std::size_t i = 0; i < std::size_t(spec.width) * spec.height; ++i)
        for (int c = 0; c < 4; ++c)
            t.texelsf[i * 4 + c] = c < spec.nchannels ? px[i * spec.nchannels + c]
                                   : c < 3           ? px[i * spec.nchannels]
                                                     : 1.0f;
    (void)use;
    return t;
}

Texture load_texture_from_memory(const std::string&, const std::string& name, TextureUse,
                                 std::vector<std::string>&) {
    return placeholder(name);
}

int add_texture_file(Scene& scene, const std::filesystem::path& path, TextureUse use) {
    for (std::size_t i = 0; i < scene.textures.size(); ++i)
        if (scene.textures[i].source == path.string()) return int(i);
    try {
        scene.textures.push_back(load_texture(path, use, scene.warnings));
    } catch (const Error& e) {
        scene.warnings.push_back(fmt::format("{}: texture not loaded ({}); using a magenta placeholder",
                                             path.string(), e.what()));
        scene.textures.push_back(placeholder(path.string()));
    }
    return int(scene.textures.size() - 1);
}

Texture checkerboard_texture(glm::vec3 c0, glm::vec3 c1, const std::string& name) {
    Texture t;
    t.source = name;
    t.width = t.height = 2;
    t.nearest = true;
    for (glm::vec3 c : {c0, c1, c1, c0}) t.texelsf.insert(t.texelsf.end(), {c.x, c.y, c.z, 1.0f});
    return t;
}

std::size_t TextureUpload::bytes() const {
    return textures.size() * sizeof(TextureData) + texels8.size() * 4 + texelsf.size() * sizeof(float4);
}

TextureUpload upload_textures(const std::vector<const Texture*>&) { return {}; }

}  // namespace wp
