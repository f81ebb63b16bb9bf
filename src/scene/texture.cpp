#include "scene/texture.h"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <exception>
#include <memory>
#include <new>
#include <system_error>

#include <fmt/format.h>

#include "image/codec.h"
#include "image/image.h"
#include "util/error.h"
#include "util/limits.h"
#include "util/strings.h"

namespace wp {

namespace fs = std::filesystem;

namespace {

// A texture that could not be loaded: what() is the full message ("cannot load texture
// 'FILE': REASON"), reason the part after the colon (for add_texture_file's warning).
struct TextureError : Error {
    std::string reason;
    TextureError(const std::string& name, std::string why)
        : Error(fmt::format("cannot load texture '{}': {}", name, why)), reason(std::move(why)) {}
};

[[noreturn]] void refuse(const std::string& name, std::string why) { throw TextureError(name, std::move(why)); }

using codec::Header;
using codec::Storage;

bool is_eight_bit(const Header& spec) { return spec.storage == Storage::UInt8 || spec.storage == Storage::Int8; }

bool is_float_format(const Header& spec) {
    return spec.storage == Storage::Half || spec.storage == Storage::Float || spec.storage == Storage::Double;
}

// The file says its values are linear: oiio:ColorSpace Linear, lin_*, scene_linear, or
// oiio:Gamma 1 (a PNG gAMA of 1.0).
bool tagged_linear(const Header& spec) {
    const std::string cs = ascii_lower(spec.colorspace);
    if (cs == "linear" || cs == "scene_linear" || cs.rfind("lin_", 0) == 0) return true;
    return spec.gamma == 1.0f;
}

// Whether a load for `use` decodes (8-bit: keeps flagged) sRGB: colour data in an integer
// format that the file does not tag as linear. Float and half files are linear as stored.
bool srgb_for(const Header& spec, TextureUse use) {
    return use == TextureUse::Colour && !is_float_format(spec) && !tagged_linear(spec);
}

// Header checks, before any pixel is read.
void check_spec(const Header& spec, const std::string& name) {
    if (spec.deep) refuse(name, "deep images are not supported");
    if (spec.width <= 0 || spec.height <= 0 || spec.channels <= 0)
        refuse(name, fmt::format("it holds no pixels ({}x{}, {} channels)", spec.width, spec.height,
                                 spec.channels));
    if (spec.depth > 1) refuse(name, fmt::format("it is a volume ({} slices), not a 2D image", spec.depth));
    if (spec.width > limits::kMaxTextureSide || spec.height > limits::kMaxTextureSide)
        refuse(name, fmt::format("{}x{} texels; a side may be at most {}", spec.width, spec.height,
                                 limits::kMaxTextureSide));
    std::int64_t pixels = std::int64_t(spec.width) * spec.height;
    if (pixels > limits::kMaxTexturePixels)
        refuse(name, fmt::format("{}x{} is {} texels; at most {} are allowed", spec.width, spec.height,
                                 pixels, limits::kMaxTexturePixels));
}

// Grey (1 channel) and grey + alpha (2) to RGBA; 3 channels get alpha = `one`. The first
// `channels` values of each RGBA texel hold the file's channels.
template <typename T>
void expand_to_rgba(std::vector<T>& rgba, int channels, T one) {
    std::size_t n = rgba.size() / 4;
    for (std::size_t i = 0; i < n; ++i) {
        T* t = &rgba[i * 4];
        if (channels == 1) {
            t[1] = t[2] = t[0];
            t[3] = one;
        } else if (channels == 2) {
            t[3] = t[1];
            t[1] = t[2] = t[0];
        } else if (channels == 3) {
            t[3] = one;
        }
    }
}

// Reads the first subimage of an opened reader into a Texture.
Texture read_texture(codec::Reader& in, const std::string& name, TextureUse use,
                     std::vector<std::string>& warnings) {
    const Header spec = in.header();
    check_spec(spec, name);
    Texture tex;
    tex.source = name;
    tex.width = spec.width;
    tex.height = spec.height;
    tex.srgb = srgb_for(spec, use);
    const int channels = std::min(spec.channels, 4);
    const std::size_t values = std::size_t(spec.width) * std::size_t(spec.height) * 4;
    auto read = [&](codec::Pixel type, void* data, std::size_t value_size) {
        // Each texel's first `channels` values; the rest are filled by expand_to_rgba.
        if (!in.read(channels, type, data, std::ptrdiff_t(4 * value_size))) refuse(name, in.error());
    };

    if (is_eight_bit(spec)) {
        tex.texels8.resize(values);
        read(codec::Pixel::UInt8, tex.texels8.data(), 1);
        expand_to_rgba<std::uint8_t>(tex.texels8, channels, 255);
        return tex;
    }

    tex.texelsf.resize(values);
    if (spec.storage == Storage::UInt16 || spec.storage == Storage::Int16) {
        // 16-bit: codes through a table (exact double-precision decode, no pow per value).
        std::vector<std::uint16_t> codes(values);
        read(codec::Pixel::UInt16, codes.data(), 2);
        expand_to_rgba<std::uint16_t>(codes, channels, 65535);
        std::vector<float> linear(65536), stored(65536);
        for (int c = 0; c < 65536; ++c) {
            stored[c] = static_cast<float>(c / 65535.0);
            linear[c] = tex.srgb ? static_cast<float>(srgb_decode(c / 65535.0)) : stored[c];
        }
        for (std::size_t i = 0; i < values; ++i)
            tex.texelsf[i] = (i % 4 == 3) ? stored[codes[i]] : linear[codes[i]];  // alpha as stored
        return tex;
    }

    read(codec::Pixel::Float, tex.texelsf.data(), 4);
    expand_to_rgba<float>(tex.texelsf, channels, 1.0f);
    if (tex.srgb)  // other integer formats (32-bit): normalised, decoded per value
        for (std::size_t i = 0; i < values; ++i)
            if (i % 4 != 3) tex.texelsf[i] = static_cast<float>(srgb_decode(tex.texelsf[i]));
    std::size_t bad = 0;
    for (float& v : tex.texelsf)
        if (!std::isfinite(v)) {
            v = 0.0f;
            ++bad;
        }
    if (bad > 0)
        warnings.push_back(fmt::format("{}: {} non-finite texel value(s) (NaN or infinity) replaced by 0",
                                       name, bad));
    return tex;
}

void check_file(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) refuse(path.string(), "no such file");
    if (fs::is_directory(path, ec)) refuse(path.string(), "it is a folder");
    // A device or pipe (/dev/zero, a FIFO) would never end or never answer.
    if (!fs::is_regular_file(path, ec)) refuse(path.string(), "not a regular file");
}

// The opened reader of a file (header read, no pixels), colour and alpha as stored: the
// readers otherwise premultiply straight alpha (PNG, TGA, TIFF), which would darken the
// colour of cut-out texels.
std::unique_ptr<codec::Reader> open_file(const fs::path& path) {
    check_file(path);
    std::string why;
    std::unique_ptr<codec::Reader> in = codec::image_codec().open_file(path.string(), true, &why);
    if (!in) refuse(path.string(), why);
    return in;
}

// Placeholder texture of `path` in scene.textures (see add_texture_file).
std::string placeholder_source(const std::string& file) { return file + " (placeholder)"; }

}  // namespace

Texture load_texture(const fs::path& path, TextureUse use, std::vector<std::string>& warnings) {
    std::unique_ptr<codec::Reader> in = open_file(path);
    return read_texture(*in, path.string(), use, warnings);
}

Texture load_texture_from_memory(const std::string& bytes, const std::string& name, TextureUse use,
                                 std::vector<std::string>& warnings) {
    if (bytes.empty()) refuse(name, "the image holds no bytes");
    // The reader is chosen by the name's extension, else by trying each on the bytes.
    std::string why;
    std::unique_ptr<codec::Reader> in = codec::image_codec().open_memory(name, bytes, true, &why);
    if (!in) refuse(name, why);
    return read_texture(*in, name, use, warnings);
}

int add_texture_file(Scene& scene, const fs::path& path, TextureUse use) {
    const std::string source = path.string();
    auto& textures = scene.textures;
    auto index_of = [&](auto pred) -> int {
        for (std::size_t i = 0; i < textures.size(); ++i)
            if (pred(textures[i])) return static_cast<int>(i);
        return -1;
    };
    // Failed before: its placeholder, without a second warning.
    if (int i = index_of([&](const Texture& t) { return t.source == placeholder_source(source); }); i >= 0)
        return i;
    try {
        // Loaded before for a use that gives the same texels: same srgb flag (read from the
        // header, which costs no pixels).
        if (index_of([&](const Texture& t) { return t.source == source; }) >= 0) {
            bool srgb = srgb_for(open_file(path)->header(), use);
            if (int i = index_of([&](const Texture& t) { return t.source == source && t.srgb == srgb; }); i >= 0)
                return i;
        }
        textures.push_back(load_texture(path, use, scene.warnings));
        return static_cast<int>(textures.size()) - 1;
    } catch (const TextureError& e) {
        scene.warnings.push_back(
            fmt::format("{}: texture not loaded ({}); using a magenta placeholder", source, e.reason));
    } catch (const std::bad_alloc&) {
        scene.warnings.push_back(
            fmt::format("{}: texture not loaded (out of memory); using a magenta placeholder", source));
    } catch (const std::exception& e) {
        scene.warnings.push_back(
            fmt::format("{}: texture not loaded ({}); using a magenta placeholder", source, e.what()));
    }
    textures.push_back(placeholder_texture(placeholder_source(source)));
    return static_cast<int>(textures.size()) - 1;
}

Texture placeholder_texture(const std::string& source) {
    Texture t;
    t.source = source;
    t.width = t.height = 8;
    t.nearest = true;
    t.texels8.resize(8 * 8 * 4);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            std::uint8_t* p = &t.texels8[std::size_t(y * 8 + x) * 4];
            bool magenta = ((x + y) & 1) == 0;
            p[0] = magenta ? 255 : 0;
            p[1] = 0;
            p[2] = magenta ? 255 : 0;
            p[3] = 255;
        }
    return t;
}

int texture_with_filter(Scene& scene, int index, bool nearest) {
    const Texture& t = scene.textures.at(static_cast<std::size_t>(index));
    if (t.nearest == nearest) return index;
    for (std::size_t i = 0; i < scene.textures.size(); ++i) {
        const Texture& c = scene.textures[i];
        if (c.nearest == nearest && c.source == t.source && c.srgb == t.srgb &&
            c.width == t.width && c.height == t.height && c.texels8 == t.texels8 &&
            c.texelsf == t.texelsf)
            return static_cast<int>(i);
    }
    Texture copy = t;
    copy.nearest = nearest;
    scene.textures.push_back(std::move(copy));
    return static_cast<int>(scene.textures.size() - 1);
}

Texture checkerboard_texture(glm::vec3 c0, glm::vec3 c1, const std::string& name) {
    Texture t;
    t.source = name;
    t.width = t.height = 2;
    t.nearest = true;
    // Row 0 is v in [0, 0.5): texel (0, 0) has u < 0.5 and v < 0.5, both true: c0.
    const glm::vec3 texels[4] = {c0, c1, c1, c0};
    for (const glm::vec3& c : texels) t.texelsf.insert(t.texelsf.end(), {c.x, c.y, c.z, 1.0f});
    return t;
}

int mip_levels(int width, int height) {
    int side = std::max(width, height), levels = 1;
    while (side > 1) {
        side >>= 1;
        ++levels;
    }
    return levels;
}

std::size_t TextureUpload::bytes() const {
    return textures.size() * sizeof(TextureData) + texels8.size() * sizeof(std::uint32_t) +
           texelsf.size() * sizeof(float4);
}

namespace {

// Linear RGBA of one level, in float, and its size.
struct Level {
    int w = 0, h = 0;
    std::vector<float> rgba;
};

// The level after the aw x ah linear RGBA texels `a`: 2 x 2 boxes, indices clamped to the
// level (upload_textures).
Level box_down(int aw, int ah, const float* a) {
    Level b;
    b.w = std::max(1, aw >> 1);
    b.h = std::max(1, ah >> 1);
    b.rgba.resize(std::size_t(b.w) * b.h * 4);
    for (int y = 0; y < b.h; ++y) {
        int y0 = std::min(2 * y, ah - 1), y1 = std::min(2 * y + 1, ah - 1);
        for (int x = 0; x < b.w; ++x) {
            int x0 = std::min(2 * x, aw - 1), x1 = std::min(2 * x + 1, aw - 1);
            const float* t00 = &a[(std::size_t(y0) * aw + x0) * 4];
            const float* t10 = &a[(std::size_t(y0) * aw + x1) * 4];
            const float* t01 = &a[(std::size_t(y1) * aw + x0) * 4];
            const float* t11 = &a[(std::size_t(y1) * aw + x1) * 4];
            float* o = &b.rgba[(std::size_t(y) * b.w + x) * 4];
            for (int c = 0; c < 4; ++c) o[c] = ((t00[c] + t10[c]) + (t01[c] + t11[c])) * 0.25f;
        }
    }
    return b;
}

// Linear [0, 1] to the nearest 8-bit code, linearly or sRGB-encoded: the code whose
// interval (between the decoded midpoints of neighbouring codes) holds x.
class Quantizer {
  public:
    explicit Quantizer(bool srgb) {
        for (int c = 0; c < 255; ++c) {
            double mid = (c + 0.5) / 255.0;
            bounds_[c] = static_cast<float>(srgb ? srgb_decode(mid) : mid);
        }
    }
    std::uint8_t operator()(float x) const {
        if (!(x > 0.0f)) return 0;
        return static_cast<std::uint8_t>(std::upper_bound(bounds_.begin(), bounds_.end(), x) - bounds_.begin());
    }

  private:
    std::array<float, 255> bounds_{};
};

std::uint32_t pack(std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a) {
    return std::uint32_t(r) | std::uint32_t(g) << 8 | std::uint32_t(b) << 16 | std::uint32_t(a) << 24;
}

}  // namespace

TextureUpload upload_textures(const std::vector<const Texture*>& textures) {
    TextureUpload up;
    // 1. Layout from the sizes: formats, levels, offsets, pool sizes.
    std::int64_t pool8 = 0, poolf = 0;
    for (std::size_t i = 0; i < textures.size(); ++i) {
        const Texture* t = textures[i];
        if (!t) fail("cannot upload texture {}: it is missing (null)", i);
        if (t->width <= 0 || t->height <= 0 || t->width > limits::kMaxTextureSide ||
            t->height > limits::kMaxTextureSide)
            fail("cannot upload texture '{}': size {}x{} is empty or larger than {} a side", t->source,
                 t->width, t->height, limits::kMaxTextureSide);
        TextureData d{};
        d.width = t->width;
        d.height = t->height;
        d.levels = t->nearest ? 1 : mip_levels(t->width, t->height);
        d.format = t->is_float() ? WP_TEXEL_FLOAT : (t->srgb ? WP_TEXEL_SRGB8 : WP_TEXEL_LINEAR8);
        d.nearest = t->nearest ? 1 : 0;
        std::int64_t texels = 0;
        for (int l = 0, w = d.width, h = d.height; l < d.levels; ++l, w = std::max(1, w >> 1), h = std::max(1, h >> 1))
            texels += std::int64_t(w) * h;
        std::int64_t& pool = d.format == WP_TEXEL_FLOAT ? poolf : pool8;
        if (pool + texels > INT_MAX)
            fail("cannot upload texture '{}': its {} texels (with mip levels) would grow the {} texel pool "
                 "past 2^31 - 1 texels",
                 t->source, texels, d.format == WP_TEXEL_FLOAT ? "float" : "8-bit");
        d.offset = static_cast<int>(pool);
        pool += texels;
        up.textures.push_back(d);
    }
    for (std::size_t i = 0; i < textures.size(); ++i) {
        const Texture& t = *textures[i];
        std::size_t values = std::size_t(t.width) * t.height * 4;
        std::size_t held = t.is_float() ? t.texelsf.size() : t.texels8.size();
        if (held != values || (t.is_float() && !t.texels8.empty()))
            fail("cannot upload texture '{}': {}x{} needs {} texel values, it holds {}", t.source, t.width,
                 t.height, values, held + (t.is_float() ? t.texels8.size() : 0));
    }
    up.texels8.reserve(static_cast<std::size_t>(pool8));
    up.texelsf.reserve(static_cast<std::size_t>(poolf));

    // 2. Level 0 as given, then each level from the previous one in linear float.
    for (std::size_t i = 0; i < textures.size(); ++i) {
        const Texture& t = *textures[i];
        const TextureData& d = up.textures[i];
        const std::size_t n = std::size_t(t.width) * t.height;
        if (d.format == WP_TEXEL_FLOAT) {
            for (std::size_t k = 0; k < n; ++k)
                up.texelsf.push_back(make_float4(t.texelsf[k * 4], t.texelsf[k * 4 + 1], t.texelsf[k * 4 + 2],
                                                 t.texelsf[k * 4 + 3]));
            if (d.levels == 1) continue;
            Level level = box_down(t.width, t.height, t.texelsf.data());
            for (int l = 1; l < d.levels; ++l) {
                if (l > 1) level = box_down(level.w, level.h, level.rgba.data());
                for (std::size_t k = 0; k < level.rgba.size(); k += 4)
                    up.texelsf.push_back(
                        make_float4(level.rgba[k], level.rgba[k + 1], level.rgba[k + 2], level.rgba[k + 3]));
            }
            continue;
        }
        const std::uint8_t* c = t.texels8.data();
        for (std::size_t k = 0; k < n; ++k) up.texels8.push_back(pack(c[k * 4], c[k * 4 + 1], c[k * 4 + 2], c[k * 4 + 3]));
        if (d.levels == 1) continue;
        const bool srgb = d.format == WP_TEXEL_SRGB8;
        float to_linear[256], stored[256];
        for (int code = 0; code < 256; ++code) {
            stored[code] = static_cast<float>(code / 255.0);
            to_linear[code] = srgb ? static_cast<float>(srgb_decode(code / 255.0)) : stored[code];
        }
        Level level{t.width, t.height, std::vector<float>(n * 4)};
        for (std::size_t k = 0; k < n * 4; ++k) level.rgba[k] = (k % 4 == 3) ? stored[c[k]] : to_linear[c[k]];
        const Quantizer colour(srgb), alpha(false);
        for (int l = 1; l < d.levels; ++l) {
            level = box_down(level.w, level.h, level.rgba.data());
            const float* v = level.rgba.data();
            for (std::size_t k = 0; k < level.rgba.size(); k += 4)
                up.texels8.push_back(pack(colour(v[k]), colour(v[k + 1]), colour(v[k + 2]), alpha(v[k + 3])));
        }
    }
    return up;
}

float texel_linear(const Texture& t, std::size_t i, int c) {
    if (t.is_float()) return t.texelsf[i * 4 + std::size_t(c)];
    const float v = float(t.texels8[i * 4 + std::size_t(c)]) / 255.0f;
    if (!t.srgb || c == 3) return v;
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

}  // namespace wp
