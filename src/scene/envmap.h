// envmap.h — PROVISIONAL until the envmap branch lands with the same signatures.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"
#include "shared/types.h"

namespace wp {

struct EnvUpload {
    EnvData data{};
    std::vector<float4> texels;
    std::vector<float> marginal;
    std::vector<float> conditional;
    double mean_luminance = 0.0;
};

EnvUpload upload_environment(const Environment& env, const Texture& image,
                             std::vector<std::string>& warnings);

}  // namespace wp
