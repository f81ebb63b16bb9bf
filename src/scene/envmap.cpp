// PROVISIONAL until the envmap branch lands with the same signatures.
#include "scene/envmap.h"

#include "image/image.h"

namespace wp {

EnvUpload upload_environment(const Environment& env, const Texture& image, std::vector<std::string>&) {
    EnvUpload u;
    glm::mat3 inv = glm::transpose(env.to_world);
    u.data.to_local0 = {inv[0][0], inv[1][0], inv[2][0], 0.0f};
    u.data.to_local1 = {inv[0][1], inv[1][1], inv[2][1], 0.0f};
    u.data.to_local2 = {inv[0][2], inv[1][2], inv[2][2], 0.0f};
    u.data.scale = {env.scale, env.scale, env.scale, 0.0f};
    u.data.width = image.width;
    u.data.height = image.height;
    std::size_t n = std::size_t(image.width) * image.height;
    for (std::size_t i = 0; i < n; ++i) {
        if (image.is_float())
            u.texels.push_back({image.texelsf[4 * i], image.texelsf[4 * i + 1], image.texelsf[4 * i + 2], 0.0f});
        else {
            auto dec = [&](int c) {
                float v = image.texels8[4 * i + c] / 255.0f;
                return image.srgb ? float(srgb_decode(v)) : v;
            };
            u.texels.push_back({dec(0), dec(1), dec(2), 0.0f});
        }
    }
    return u;
}

}  // namespace wp
