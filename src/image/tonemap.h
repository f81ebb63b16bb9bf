// tonemap.h — display transforms for the viewer (`wavepath view`): exposure, a tone curve and
// the sRGB encoding, from the film's linear RGB to 8-bit RGBA.
//
// Per channel: y = curve(x * 2^exposure), then the 8-bit code of y:
//   clamp     y = clamp(x, 0, 1)
//   reinhard  y = x / (1 + x)                       (Reinhard et al. 2002, per channel)
//   filmic    y = x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1]
//             (Narkowicz 2015's fit of the ACES reference rendering transform)
// With sRGB output the code is exactly write_image's PNG code (image.h): round(255 *
// srgb_encode(clamp(y, 0, 1))), NaN -> 0; found by a binary search over the 255 code
// boundaries, which are computed once from srgb_encode itself. Without sRGB it is
// round(255 clamp(y, 0, 1)). So clamp, exposure 0 and sRGB shows the pixels of `render`'s PNG.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "image/image.h"

namespace wp {

enum class ToneCurve { Clamp, Reinhard, Filmic };

const char* tone_curve_name(ToneCurve c);
std::optional<ToneCurve> parse_tone_curve(std::string_view name);
// The next curve in the order clamp, reinhard, filmic (a key cycles through them).
ToneCurve next_tone_curve(ToneCurve c);

struct ToneMapping {
    double exposure = 0.0;  // stops: values are multiplied by 2^exposure
    ToneCurve curve = ToneCurve::Clamp;
    bool srgb = true;       // sRGB transfer function (else linear codes)
};

// The curve applied to one exposed value (not clamped for clamp: the code step clamps).
float apply_tone_curve(ToneCurve c, float x);

// 8-bit sRGB code of a linear value, equal to round(255 srgb_encode(clamp(x, 0, 1))) for
// every float (NaN -> 0).
std::uint8_t srgb_code8(float linear);

// The image as 8-bit RGBA (alpha 255), row-major from the top-left: 4 w h bytes in `rgba`
// (resized).
void tonemap_rgba8(const Image& image, const ToneMapping& t, std::vector<std::uint8_t>& rgba);

// The image after exposure and curve, still linear (what the viewer saves as PNG).
Image apply_tone_mapping(const Image& image, const ToneMapping& t);

}  // namespace wp
