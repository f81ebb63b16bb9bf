// texture.h — texture images on the host: loading through OpenImageIO, procedural textures,
// and the device layout (mip chains in two texel pools) that kernels/shared/texture.h reads.
//
// Loading turns any image OpenImageIO reads into RGBA (grey replicated to RGB, missing
// alpha = 1), row 0 at the top:
//   * 8-bit files keep their codes (Texture::texels8); for TextureUse::Colour they are
//     sRGB-encoded (Texture::srgb) unless the file says it is linear (oiio:ColorSpace
//     "Linear"/"lin_*"/"scene_linear", or oiio:Gamma 1); for TextureUse::Data (normal,
//     roughness, alpha maps) they are taken as stored (linear). Alpha is always linear.
//   * every other file becomes linear float (Texture::texelsf): float and half files as
//     stored, integer files (16-bit PNG, TIFF) normalised to [0, 1] and, for Colour data
//     not tagged linear, decoded from sRGB in double precision. Such a decoded float texture
//     has srgb = true as a record of where it came from (the device ignores srgb for float
//     textures); add_texture_file uses it to tell a file's Colour and Data loads apart.
// Limits (util/limits.h): each side at most kMaxTextureSide, at most kMaxTexturePixels,
// checked on the header before any pixel is read.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "shared/types.h"

namespace wp {

enum class TextureUse {
    Colour,  // colours (albedo, emission): 8-bit data sRGB-encoded unless the file says linear
    Data,    // normal, roughness, alpha maps: 8-bit data taken as stored (linear)
};

// Loads an image file as a texture (bilinear, mip-mapped). Throws wp::Error naming the file
// when it is missing or does not decode, holds no pixels, is deep or a volume, or is too
// large (checked from the header, before any pixel is read). Of several subimages the
// first is used. Non-finite float texel values are replaced by 0 with one warning naming
// the file and how many, appended to `warnings`.
Texture load_texture(const std::filesystem::path& path, TextureUse use,
                     std::vector<std::string>& warnings);

// The same for an image held in memory (glTF's embedded and data-URI images), read through
// an OpenImageIO IOProxy; `name` names it in messages and Texture::source (its extension
// helps choose the format, but the bytes decide). Formats whose reader has no IOProxy
// support (most besides PNG, JPEG, EXR) are refused with an error naming `name`.
Texture load_texture_from_memory(const std::string& bytes, const std::string& name, TextureUse use,
                                 std::vector<std::string>& warnings);

// The index in scene.textures of the file `path` loaded for `use`, loading it the first
// time: a (path, use) pair is loaded once (the key is Texture::source and Texture::srgb; the
// file's header is read again to know the srgb flag a load would give). Never throws for a
// bad file: on any failure it appends the warning
//   "FILE: texture not loaded (REASON); using a magenta placeholder"
// to scene.warnings and returns the index of the file's placeholder_texture (made once per
// file, so the warning is given once).
int add_texture_file(Scene& scene, const std::filesystem::path& path, TextureUse use);

// An 8 x 8 magenta / black checker (texel (0, 0) magenta), nearest lookups, alpha 1: the
// visible stand-in for a texture that could not be loaded. `source` names it.
Texture placeholder_texture(const std::string& source);

// The index of a texture with the texels of scene.textures[index] and the filter `nearest`
// (a sampler's choice, while add_texture_file shares one image per file): `index` itself
// when its filter matches, else an earlier copy with that filter, else a new copy.
int texture_with_filter(Scene& scene, int index, bool nearest);

// Mitsuba 3's checkerboard texture: c0 where (u mod 1 < 0.5) == (v mod 1 < 0.5), else c1,
// as a 2 x 2 float texture with nearest lookups (texels (0, 0) and (1, 1) are c0).
Texture checkerboard_texture(glm::vec3 c0, glm::vec3 c1, const std::string& name);

// Mip levels of a bilinear w x h texture: floor(log2(max(w, h))) + 1 (down to 1 x 1).
int mip_levels(int width, int height);

// Every texture of a scene in the device layout (kernels/shared/texture.h TexturePool).
struct TextureUpload {
    std::vector<TextureData> textures;   // one per input texture, in order
    std::vector<std::uint32_t> texels8;  // WP_TEXEL_SRGB8 / _LINEAR8: RGBA8, R in the low byte
    std::vector<float4> texelsf;         // WP_TEXEL_FLOAT: linear RGBA
    std::size_t bytes() const;           // of the three arrays, for reports
};

// Builds the mip chains and pools. Formats: float textures WP_TEXEL_FLOAT, 8-bit ones
// WP_TEXEL_SRGB8 when srgb, else WP_TEXEL_LINEAR8. Nearest textures: level 0 only. Else
// mip_levels(w, h) levels, each a 2 x 2 box filter of the previous level in linear space:
// texel (x, y) of level l averages texels (2x + i, 2y + j), i, j in {0, 1}, of level l - 1
// with each index clamped to that level (so a side of 1 averages a texel with itself, and
// an odd side's last row or column does not reach the next level: the simple rule, a small
// shift for odd sizes). 8-bit levels are computed from the previous level in float (not
// from its rounded codes) and rounded to the nearest code, sRGB re-encoded for SRGB8;
// alpha is averaged as stored. Throws wp::Error naming the texture when its texel array
// does not hold width x height x 4 values, and when a pool would exceed 2^31 - 1 texels
// (offsets are int on the device).
TextureUpload upload_textures(const std::vector<const Texture*>& textures);

// Channel c (0..3) of texel i as a linear value: float texels as stored, 8-bit ones / 255
// with the sRGB colour channels decoded (in float). For loaders that derive constants or
// maps from an image (means, luminance, resampling).
float texel_linear(const Texture& t, std::size_t i, int c);

}  // namespace wp
