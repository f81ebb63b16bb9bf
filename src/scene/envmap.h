// envmap.h — the environment light's device data: its map as linear float4 texels and the
// tables of its importance sampling (kernels/shared/envmap.h: the Mitsuba 3 mapping, the
// cells of the distribution and their weights are described there).
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"
#include "shared/types.h"

namespace wp {

struct EnvUpload {
    EnvData data{};                  // rotation world -> map frame, scale, width, height
    std::vector<float4> texels;      // width * height, row 0 = top (+y), xyz linear RGB, w 0
    std::vector<float> marginal;     // max(height - 1, 1) entries (the cell rows)
    std::vector<float> conditional;  // max(height - 1, 1) * width entries
    // The mean over the sphere of the luminance (Rec. 709) of the radiance the device
    // returns, scale included: (1 / 4π) ∫ Y(L(ω)) dω, integrated exactly over the bilinear
    // grid in double. 0 for a black map.
    double mean_luminance = 0.0;
};

// The device data of `env`, whose map is `image` (Scene::textures[env.image]). 8-bit texels
// are decoded (sRGB when image.srgb, else code / 255), float ones kept; alpha is dropped;
// negative values are clamped to 0 (one warning). A map that is not 2:1 is used as it is
// with one warning naming the file and its size; a black map gives all-zero tables.
// Throws wp::Error naming the file for a map without pixels, a texel count that does not
// match its size, more than INT_MAX texels, a non-finite texel, a negative or non-finite
// scale, or a to_world that is not a rotation (orthogonal within 1e-3; a reflection is
// fine); a rotation within that tolerance is re-orthonormalised.
EnvUpload upload_environment(const Environment& env, const Texture& image,
                             std::vector<std::string>& warnings);

}  // namespace wp
