#include "scene/gltf_loader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
// tinygltf is compiled here, in its own namespace, rather than called in Debian's
// libtinygltf.so: libdraco.so.7 (linked through Assimp) exports an older tinygltf with a
// different TinyGLTF layout, and the dynamic linker binds the shared library's entry points
// to it (heap corruption). Renaming the namespace makes every symbol ours. Images are
// decoded by scene/texture.h (OpenImageIO), not by tinygltf, so stb_image is left out.
#define tinygltf wp_tinygltf
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include "scene/texture.h"
#include "scene/validate.h"
#include "util/error.h"
#include "util/limits.h"
#include "util/read_file.h"

namespace wp {

namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kMaxFileBytes = std::uint64_t(1) << 30;
constexpr std::uint64_t kMaxTriangles = std::uint64_t(1) << 25;
constexpr std::uint64_t kMaxVertices = std::uint64_t(1) << 27;
constexpr int kMaxNodeDepth = 256;
constexpr std::uint64_t kMaxNodeVisits = std::uint64_t(1) << 20;

std::uint32_t read_u32(std::string_view b, std::size_t at) {
    const auto* p = reinterpret_cast<const unsigned char*>(b.data() + at);
    return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) |
           (std::uint32_t(p[3]) << 24);
}

// GLB container: 12-byte header (magic, version 2, total length), then chunks of
// (length, type, data); the first must be JSON. Checked so a truncated file gets a clear
// message before tinygltf sees it.
void check_glb(std::string_view b, const std::string& file) {
    if (b.size() < 12)
        fail("{}: truncated: a GLB file needs a 12-byte header, the file has {} bytes", file,
             b.size());
    const std::uint32_t version = read_u32(b, 4), length = read_u32(b, 8);
    if (version != 2) fail("{}: GLB version {} is not supported (only 2)", file, version);
    if (length > b.size())
        fail("{}: truncated: the GLB header says {} bytes, the file has {}", file, length, b.size());
    if (length < b.size())
        fail("{}: the GLB header says {} bytes, but the file has {} (extra data at byte {})", file,
             length, b.size(), length);
    std::size_t at = 12;
    int chunk = 0;
    while (at < length) {
        if (length - at < 8)
            fail("{}: truncated: chunk {} header at byte {} needs 8 bytes, {} remain", file, chunk,
                 at, length - at);
        const std::uint32_t clen = read_u32(b, at), type = read_u32(b, at + 4);
        if (chunk == 0 && type != 0x4E4F534Au)
            fail("{}: byte {}: the first GLB chunk is not JSON", file, at + 4);
        if (clen > length - at - 8)
            fail("{}: truncated: chunk {} ({}) at byte {} declares {} bytes, {} remain", file, chunk,
                 type == 0x4E4F534Au ? "JSON" : type == 0x004E4942u ? "BIN" : "unknown", at, clen,
                 length - at - 8);
        at += 8 + std::size_t(clen);
        ++chunk;
    }
    if (chunk == 0) fail("{}: truncated: the GLB file has no JSON chunk", file);
}

// File access for tinygltf: regular files only, size-capped, never written, no expansion.
bool fs_exists(const std::string& name, void*) {
    std::error_code ec;
    return fs::is_regular_file(name, ec);
}
std::string fs_expand(const std::string& name, void*) { return name; }
bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& name, void*) {
    std::optional<std::string> bytes = try_read_file(name, kMaxFileBytes);
    if (!bytes) {
        if (err) *err += "'" + name + "' is not a regular file, unreadable or larger than 1 GiB\n";
        return false;
    }
    out->assign(bytes->begin(), bytes->end());
    return true;
}
bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "wavepath never writes files while loading glTF\n";
    return false;
}
// tinygltf's image hook: images are decoded later, by scene/texture.h. A data: URI arrives
// here decoded from base64: its bytes are kept in Image::image (as_is). An image in a buffer
// view arrives as a pointer that tinygltf has not bounds-checked: it is ignored here and read
// later with the checks of accessor_view.
bool keep_image_bytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
    if (image->bufferView < 0 && bytes && size > 0) {
        image->image.assign(bytes, bytes + size);
        image->as_is = true;
    }
    return true;
}

// tinygltf's messages as lines.
std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::size_t i = 0;
    while (i < text.size()) {
        std::size_t j = text.find('\n', i);
        if (j == std::string::npos) j = text.size();
        std::string l = text.substr(i, j - i);
        while (!l.empty() && std::isspace(static_cast<unsigned char>(l.back()))) l.pop_back();
        if (!l.empty()) out.push_back(l);
        i = j + 1;
    }
    return out;
}

bool finite(const glm::mat4& m) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// A node's local transform: `matrix` (column-major) or T × R × S.
glm::mat4 local_transform(const tinygltf::Node& n, const std::string& file, int index) {
    glm::mat4 m(1.0f);
    if (n.matrix.size() == 16) {
        for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = float(n.matrix[i]);
    } else {
        if (!n.matrix.empty())
            fail("{}: nodes[{}].matrix has {} numbers, expected 16", file, index, n.matrix.size());
        glm::mat4 t(1.0f), r(1.0f), s(1.0f);
        if (n.translation.size() == 3)
            t = glm::translate(glm::mat4(1.0f), glm::vec3(float(n.translation[0]),
                                                          float(n.translation[1]),
                                                          float(n.translation[2])));
        else if (!n.translation.empty())
            fail("{}: nodes[{}].translation has {} numbers, expected 3", file, index,
                 n.translation.size());
        if (n.rotation.size() == 4) {
            // glTF quaternions are (x, y, z, w); glm::quat's constructor takes (w, x, y, z)
            glm::quat q(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]),
                        float(n.rotation[2]));
            const float len = glm::length(q);
            if (!(len > 0.0f) || !std::isfinite(len))
                fail("{}: nodes[{}].rotation is not a usable quaternion", file, index);
            r = glm::mat4_cast(q / len);
        } else if (!n.rotation.empty()) {
            fail("{}: nodes[{}].rotation has {} numbers, expected 4", file, index, n.rotation.size());
        }
        if (n.scale.size() == 3)
            s = glm::scale(glm::mat4(1.0f),
                           glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
        else if (!n.scale.empty())
            fail("{}: nodes[{}].scale has {} numbers, expected 3", file, index, n.scale.size());
        m = t * r * s;
    }
    if (!finite(m)) fail("{}: nodes[{}] has a non-finite transform", file, index);
    return m;
}

// One accessor's elements, bounds-checked: `at(i)` is the byte address of element i.
struct View {
    const unsigned char* base = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
    const unsigned char* at(std::size_t i) const { return base + i * stride; }
};

int component_size(int type) {
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return 8;
    }
    return 0;
}

View accessor_view(const tinygltf::Model& model, int index, std::size_t elem_size,
                   const std::string& file, const std::string& where) {
    if (index < 0 || std::size_t(index) >= model.accessors.size())
        fail("{}: {} refers to accessors[{}], but there are {} accessors", file, where, index,
             model.accessors.size());
    const tinygltf::Accessor& a = model.accessors[index];
    if (a.bufferView < 0 || std::size_t(a.bufferView) >= model.bufferViews.size())
        fail("{}: accessors[{}] refers to bufferViews[{}], but there are {}", file, index,
             a.bufferView, model.bufferViews.size());
    const tinygltf::BufferView& bv = model.bufferViews[a.bufferView];
    if (bv.buffer < 0 || std::size_t(bv.buffer) >= model.buffers.size())
        fail("{}: bufferViews[{}] refers to buffers[{}], but there are {}", file, a.bufferView,
             bv.buffer, model.buffers.size());
    const std::vector<unsigned char>& data = model.buffers[bv.buffer].data;
    const std::uint64_t bv_off = bv.byteOffset, bv_len = bv.byteLength;
    if (bv_off > data.size() || bv_len > data.size() - bv_off)
        fail("{}: bufferViews[{}] (bytes {} to {}) lies outside buffers[{}] of {} bytes", file,
             a.bufferView, bv_off, bv_off + bv_len, bv.buffer, data.size());
    const std::uint64_t stride = bv.byteStride > 0 ? std::uint64_t(bv.byteStride) : elem_size;
    if (bv.byteStride > 0 && stride < elem_size)
        fail("{}: bufferViews[{}] byteStride {} is smaller than an element of accessors[{}] ({} "
             "bytes)",
             file, a.bufferView, stride, index, elem_size);
    const std::uint64_t count = a.count, off = a.byteOffset;
    if (count > kMaxVertices * 3)
        fail("{}: accessors[{}] count {} exceeds the limit of {}", file, index, count,
             kMaxVertices * 3);
    if (count > 0 && (off > bv_len || (count - 1) * stride > bv_len - off ||
                      elem_size > bv_len - off - (count - 1) * stride))
        fail("{}: accessors[{}] ({} elements of {} bytes, stride {}, offset {}) reads past the "
             "end of bufferViews[{}] ({} bytes)",
             file, index, count, elem_size, stride, off, a.bufferView, bv_len);
    return {data.data() + bv_off + off, std::size_t(stride), std::size_t(count)};
}

// Approximations met while mapping materials: one warning each per file.
struct Notes {
    int partial_metal = 0, rough_glass = 0, clamped = 0, specular_ext = 0;
    int modes = 0, sparse = 0, quantized = 0, ortho = 0;
    int metallic_map = 0, occlusion = 0, blend = 0, cut_out = 0, wrap = 0, texcoord = 0;
    int no_source = 0, attributes = 0, non_finite = 0, bad_transform = 0;
};

// Percent-decoding of a relative URI ("my%20tex.png" -> "my tex.png").
std::string decode_uri(const std::string& uri) {
    std::string out;
    auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return -1;
    };
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out.push_back(char(hex(uri[i + 1]) * 16 + hex(uri[i + 2])));
            i += 2;
        } else {
            out.push_back(uri[i]);
        }
    }
    return out;
}

// Coverage A × factor below cutoff at some texel (bilinear and mip-mapped lookups are
// weighted means of texels, so no lookup goes below the smallest texel).
bool cuts_out(const Texture& t, float factor, float cutoff) {
    const std::size_t n = std::size_t(std::max(t.width, 0)) * std::size_t(std::max(t.height, 0));
    if (t.is_float()) {
        for (std::size_t i = 0; i < n && 4 * i + 3 < t.texelsf.size(); ++i)
            if (!(t.texelsf[4 * i + 3] * factor >= cutoff)) return true;
        return false;
    }
    for (std::size_t i = 0; i < n && 4 * i + 3 < t.texels8.size(); ++i)
        if (!(float(t.texels8[4 * i + 3]) / 255.0f * factor >= cutoff)) return true;
    return false;
}

// KHR_texture_transform's matrix T × R × S on uv (column-major, as the extension writes it):
// T = [1 0 ox; 0 1 oy; 0 0 1], R = [cos r  sin r  0; -sin r  cos r  0; 0 0 1] (columns
// (cos, sin), (-sin, cos)), S = diag(sx, sy, 1).
glm::mat3 texture_transform(glm::vec2 offset, float rotation, glm::vec2 scale) {
    glm::mat3 t(1.0f), r(1.0f), s(1.0f);
    t[2][0] = offset.x;
    t[2][1] = offset.y;
    const float c = std::cos(rotation), sn = std::sin(rotation);
    r[0][0] = c;
    r[0][1] = sn;
    r[1][0] = -sn;
    r[1][1] = c;
    s[0][0] = scale.x;
    s[1][1] = scale.y;
    return t * r * s;
}

// Textures of glTF materials into the scene: images decoded once per (image, use), samplers
// read (NEAREST magnification; wrap modes other than REPEAT noted), uv transforms.
struct GltfTextures {
    const tinygltf::Model& model;
    Scene& scene;
    fs::path base_dir;
    std::string file;
    Notes& notes;
    std::map<std::pair<int, int>, int> loaded;     // (image, use) -> scene texture

    // The scene texture of image `ii` for `use`, or -1 (with a warning) when it has no data.
    int image(int ii, TextureUse use, const std::string& where) {
        if (ii < 0 || std::size_t(ii) >= model.images.size())
            fail("{}: {} refers to images[{}], but there are {}", file, where, ii,
                 model.images.size());
        auto key = std::make_pair(ii, int(use));
        if (auto it = loaded.find(key); it != loaded.end()) return it->second;
        const tinygltf::Image& img = model.images[std::size_t(ii)];
        const std::string name = fmt::format("{}: images[{}]{}", file, ii,
                                             img.name.empty() ? "" : " ('" + img.name + "')");
        int index = -1;
        if (img.bufferView >= 0) {  // GLB or a buffer: bounds-checked here
            if (std::size_t(img.bufferView) >= model.bufferViews.size())
                fail("{}: images[{}] refers to bufferViews[{}], but there are {}", file, ii,
                     img.bufferView, model.bufferViews.size());
            const tinygltf::BufferView& bv = model.bufferViews[std::size_t(img.bufferView)];
            if (bv.buffer < 0 || std::size_t(bv.buffer) >= model.buffers.size())
                fail("{}: bufferViews[{}] refers to buffers[{}], but there are {}", file,
                     img.bufferView, bv.buffer, model.buffers.size());
            const auto& data = model.buffers[std::size_t(bv.buffer)].data;
            if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
                fail("{}: images[{}]: bufferViews[{}] (bytes {} to {}) lies outside buffers[{}] "
                     "of {} bytes",
                     file, ii, img.bufferView, bv.byteOffset, bv.byteOffset + bv.byteLength,
                     bv.buffer, data.size());
            const std::string bytes(reinterpret_cast<const char*>(data.data()) + bv.byteOffset,
                                    bv.byteLength);
            scene.textures.push_back(load_texture_from_memory(bytes, name, use, scene.warnings));
            index = int(scene.textures.size() - 1);
        } else if (img.as_is && !img.image.empty()) {  // a data: URI
            const std::string bytes(img.image.begin(), img.image.end());
            scene.textures.push_back(load_texture_from_memory(bytes, name, use, scene.warnings));
            index = int(scene.textures.size() - 1);
        } else if (!img.uri.empty()) {  // a file beside the .gltf
            const fs::path path = base_dir / fs::path(decode_uri(img.uri));
            std::error_code ec;
            const fs::file_status st = fs::status(path, ec);
            if (fs::exists(st) && !fs::is_regular_file(st))
                scene.warnings.push_back(fmt::format(
                    "{}: images[{}] '{}' is not a regular file; its textures are ignored", file,
                    ii, path.string()));
            else
                index = add_texture_file(scene, path, use);
        } else {
            scene.warnings.push_back(fmt::format(
                "{}: images[{}] has no data (an empty data: URI?); its textures are ignored",
                file, ii));
        }
        loaded[key] = index;
        return index;
    }

    // The slot of a textureInfo (index, texCoord, extensions), or nullopt.
    std::optional<TextureRef> ref(int index, int tex_coord,
                                  const tinygltf::ExtensionMap& extensions, TextureUse use,
                                  const std::string& where) {
        if (index < 0) return std::nullopt;
        if (std::size_t(index) >= model.textures.size())
            fail("{}: {} refers to textures[{}], but there are {}", file, where, index,
                 model.textures.size());
        const tinygltf::Texture& tex = model.textures[std::size_t(index)];
        if (tex.source < 0) {  // only an extension's image (KTX2, WebP, ...)
            ++notes.no_source;
            return std::nullopt;
        }
        bool nearest = false;
        if (tex.sampler >= 0) {
            if (std::size_t(tex.sampler) >= model.samplers.size())
                fail("{}: textures[{}] refers to samplers[{}], but there are {}", file, index,
                     tex.sampler, model.samplers.size());
            const tinygltf::Sampler& smp = model.samplers[std::size_t(tex.sampler)];
            if (smp.wrapS != TINYGLTF_TEXTURE_WRAP_REPEAT ||
                smp.wrapT != TINYGLTF_TEXTURE_WRAP_REPEAT)
                ++notes.wrap;
            nearest = smp.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
        }
        int image_index = image(tex.source, use, fmt::format("textures[{}]", index));
        if (image_index < 0) return std::nullopt;
        TextureRef r;
        // The sampler's filter is this use's (an image loaded before with the other filter
        // is copied; the copy nobody uses is pruned at the end).
        r.image = texture_with_filter(scene, image_index, nearest);

        // KHR_texture_transform: offset, rotation, scale; texCoord overrides
        auto it = extensions.find("KHR_texture_transform");
        if (it != extensions.end() && it->second.IsObject()) {
            const tinygltf::Value& v = it->second;
            bool ok = true;
            auto number = [&](const tinygltf::Value& n, float fallback) {
                if (!n.IsNumber()) {
                    ok = false;
                    return fallback;
                }
                const double d = n.GetNumberAsDouble();
                if (!std::isfinite(d)) ok = false;
                return std::isfinite(d) ? float(d) : fallback;
            };
            auto pair = [&](const char* key, glm::vec2 fallback) {
                if (!v.Has(key)) return fallback;
                const tinygltf::Value& a = v.Get(key);
                if (!a.IsArray() || a.ArrayLen() != 2) {
                    ok = false;
                    return fallback;
                }
                return glm::vec2(number(a.Get(0), fallback.x), number(a.Get(1), fallback.y));
            };
            const glm::vec2 offset = pair("offset", glm::vec2(0.0f));
            const glm::vec2 scale = pair("scale", glm::vec2(1.0f));
            const float rotation = v.Has("rotation") ? number(v.Get("rotation"), 0.0f) : 0.0f;
            if (v.Has("texCoord")) {
                const tinygltf::Value& tc = v.Get("texCoord");
                tex_coord = tc.IsNumber() ? tc.GetNumberAsInt() : tex_coord;
            }
            if (ok)
                r.uv_transform = texture_transform(offset, rotation, scale);
            else
                ++notes.bad_transform;
        }
        if (tex_coord != 0) ++notes.texcoord;
        return r;
    }
};

// Vertex attribute `name` of a primitive as `comps` floats per vertex (`count` vertices, as
// POSITION): FLOAT, or with `normalized_ok` normalized unsigned byte / short (TEXCOORD_n).
// False when the primitive has none, or (noted) an accessor wavepath does not read
// (sparse, another type, quantized); a wrong count or bounds fail.
bool read_attribute(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                    const char* name, int type, int comps, bool normalized_ok, std::size_t count,
                    const std::string& file, const std::string& where, Notes& notes,
                    std::vector<float>& out) {
    auto it = prim.attributes.find(name);
    if (it == prim.attributes.end()) return false;
    const int ai = it->second;
    if (ai < 0 || std::size_t(ai) >= model.accessors.size())
        fail("{}: {} {} refers to accessors[{}], but there are {}", file, where, name, ai,
             model.accessors.size());
    const tinygltf::Accessor& a = model.accessors[std::size_t(ai)];
    int csize = 0;
    if (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) csize = 4;
    else if (normalized_ok && a.normalized &&
             a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) csize = 1;
    else if (normalized_ok && a.normalized &&
             a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) csize = 2;
    if (a.sparse.isSparse || a.type != type || csize == 0) {
        ++notes.attributes;
        return false;
    }
    if (a.count != count)
        fail("{}: {} {} (accessors[{}]) has {} elements, but POSITION has {}", file, where, name,
             ai, a.count, count);
    const View v = accessor_view(model, ai, std::size_t(comps * csize), file, where + " " + name);
    out.resize(count * std::size_t(comps));
    for (std::size_t i = 0; i < count; ++i) {
        const unsigned char* q = v.at(i);
        for (int k = 0; k < comps; ++k) {
            float f;
            if (csize == 4) {
                std::memcpy(&f, q + 4 * k, 4);
            } else if (csize == 1) {
                f = float(q[k]) / 255.0f;
            } else {
                std::uint16_t u;
                std::memcpy(&u, q + 2 * k, 2);
                f = float(u) / 65535.0f;
            }
            out[i * std::size_t(comps) + std::size_t(k)] = f;
        }
    }
    return true;
}

// A glTF material as wavepath's, with `cut_out` set when alphaMode MASK/BLEND without a
// texture leaves nothing of the surface (factor below the cutoff).
Material convert_material(const tinygltf::Material& gm, int index, GltfTextures& tex,
                          Notes& notes, bool& cut_out) {
    Material m;
    m.name = gm.name.empty() ? std::string("unnamed") : gm.name;
    const std::string where = fmt::format("materials[{}]", index);
    const auto& pbr = gm.pbrMetallicRoughness;
    glm::vec3 base(1.0f);
    float alpha = 1.0f;
    if (pbr.baseColorFactor.size() == 4) {
        base = glm::vec3(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                         float(pbr.baseColorFactor[2]));
        alpha = float(pbr.baseColorFactor[3]);
    }
    if (!std::isfinite(alpha)) alpha = 1.0f;
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(base[k])) base[k] = 0.5f;
    const glm::vec3 clamped = glm::clamp(base, glm::vec3(0.0f), glm::vec3(1.0f));
    if (clamped != base) ++notes.clamped;
    base = clamped;
    const float metallic = std::isfinite(pbr.metallicFactor) ? float(pbr.metallicFactor) : 1.0f;
    float roughness = std::isfinite(pbr.roughnessFactor) ? float(pbr.roughnessFactor) : 1.0f;
    roughness = std::clamp(roughness, 0.0f, 1.0f);

    auto ext_number = [&](const char* ext, const char* key, double fallback) {
        auto it = gm.extensions.find(ext);
        if (it == gm.extensions.end() || !it->second.IsObject() || !it->second.Has(key))
            return fallback;
        const auto& v = it->second.Get(key);
        if (!v.IsNumber()) return fallback;
        double d = v.GetNumberAsDouble();
        return std::isfinite(d) ? d : fallback;
    };
    const bool has_transmission = gm.extensions.count("KHR_materials_transmission") > 0;
    const double transmission = ext_number("KHR_materials_transmission", "transmissionFactor", 0.0);

    if (has_transmission && transmission >= 0.5) {
        // A dielectric: the base colour tints the transmission only (the spec's
        // dielectric_brdf reflects untinted), GGX with height-correlated masking as the
        // spec's V_GGX; smooth below the rough kinds' least α
        m.albedo = base;
        const double ior = ext_number("KHR_materials_ior", "ior", 1.5);
        m.ior = ior >= limits::kMinIor && ior <= limits::kMaxIor && ior != 1.0 ? float(ior) : 1.5f;
        const float a = roughness * roughness;
        if (a >= limits::kMinMicrofacetAlpha) {
            m.kind = MaterialKind::RoughDielectric;
            m.alpha = a;
        } else {
            m.kind = MaterialKind::Glass;
            if (roughness > 0.0f) ++notes.rough_glass;
        }
        if (gm.extensions.count("KHR_materials_specular") > 0) ++notes.specular_ext;
    } else if (metallic >= 0.5f) {
        const float a = roughness * roughness;
        m.albedo = base;
        if (a < 0.001f) {
            m.kind = MaterialKind::Mirror;
        } else {
            m.kind = MaterialKind::Glossy;
            m.alpha = std::min(a, 1.0f);
        }
    } else {
        m.kind = MaterialKind::Diffuse;
        m.albedo = base;
    }
    if (metallic > 0.0f && metallic < 1.0f) ++notes.partial_metal;

    // Emission: emissiveFactor × KHR_materials_emissive_strength
    if (gm.emissiveFactor.size() == 3) {
        const float strength =
            float(ext_number("KHR_materials_emissive_strength", "emissiveStrength", 1.0));
        glm::vec3 e(float(gm.emissiveFactor[0]), float(gm.emissiveFactor[1]),
                    float(gm.emissiveFactor[2]));
        e *= strength;
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(e[k]) || e[k] < 0.0f) e[k] = 0.0f;
        m.emission = e;
    }

    // Textures: base colour (× the factor), roughness (G; glossy only), emission (× the
    // factor; only where it is > 0), normal map; occlusion and metallic are not modelled
    const auto& bct = pbr.baseColorTexture;
    std::optional<TextureRef> base_map =
        tex.ref(bct.index, bct.texCoord, bct.extensions, TextureUse::Colour,
                where + ".pbrMetallicRoughness.baseColorTexture");
    if (base_map) m.albedo_map = *base_map;
    const auto& mrt = pbr.metallicRoughnessTexture;
    if (mrt.index >= 0) {
        ++notes.metallic_map;
        if (m.kind == MaterialKind::Glossy || m.kind == MaterialKind::RoughDielectric)
            if (auto r = tex.ref(mrt.index, mrt.texCoord, mrt.extensions, TextureUse::Data,
                                 where + ".pbrMetallicRoughness.metallicRoughnessTexture"))
                m.roughness_map = *r;
    }
    if (m.emissive())
        if (auto r = tex.ref(gm.emissiveTexture.index, gm.emissiveTexture.texCoord,
                             gm.emissiveTexture.extensions, TextureUse::Colour,
                             where + ".emissiveTexture"))
            m.emission_map = *r;
    if (auto r = tex.ref(gm.normalTexture.index, gm.normalTexture.texCoord,
                         gm.normalTexture.extensions, TextureUse::Data, where + ".normalTexture")) {
        m.normal_map = *r;
        m.normal_scale = std::isfinite(gm.normalTexture.scale) ? float(gm.normalTexture.scale) : 1.0f;
    }
    if (gm.occlusionTexture.index >= 0) ++notes.occlusion;

    // Alpha: MASK (BLEND approximated as MASK at 0.5); coverage = base colour A × factor
    cut_out = false;
    if (gm.alphaMode == "MASK" || gm.alphaMode == "BLEND") {
        const bool blend = gm.alphaMode == "BLEND";
        if (blend) ++notes.blend;
        m.alpha_factor = std::clamp(alpha, 0.0f, 1.0f);
        m.alpha_cutoff = !blend && std::isfinite(gm.alphaCutoff) ? float(gm.alphaCutoff) : 0.5f;
        if (base_map) {
            if (cuts_out(tex.scene.textures[std::size_t(base_map->image)], m.alpha_factor,
                         m.alpha_cutoff))
                m.alpha_map = *base_map;  // (else every texel is kept: no test needed)
        } else if (m.alpha_factor < m.alpha_cutoff) {
            cut_out = true;
        }
    }
    return m;
}

}  // namespace

Scene parse_gltf(std::string_view bytes, const fs::path& origin) {
    const std::string file = origin.string();
    if (bytes.empty()) fail("{}: the file is empty", file);
    if (bytes.size() > kMaxFileBytes)
        fail("{}: the file is {} bytes, more than the limit of {}", file, bytes.size(), kMaxFileBytes);
    const bool glb = bytes.size() >= 4 && bytes.substr(0, 4) == "glTF";
    if (glb) check_glb(bytes, file);

    // Parse with tinygltf: our file access, no image decoding
    tinygltf::TinyGLTF loader;
    tinygltf::FsCallbacks cb{&fs_exists, &fs_expand, &fs_read, &fs_write, nullptr};
    loader.SetFsCallbacks(cb);
    loader.SetImageLoader(&keep_image_bytes, nullptr);
    tinygltf::Model model;
    std::string err, warn;
    std::string base_dir = origin.parent_path().string();
    if (base_dir.empty()) base_dir = ".";
    bool ok = false;
    try {
        ok = glb ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                               reinterpret_cast<const unsigned char*>(bytes.data()),
                                               unsigned(bytes.size()), base_dir)
                 : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                              unsigned(bytes.size()), base_dir);
    } catch (const std::exception& e) {
        fail("{}: glTF: {}", file, e.what());
    }
    if (!ok) {
        auto l = lines_of(err);
        std::string msg;
        for (std::size_t i = 0; i < l.size() && i < 3; ++i) msg += (i ? "; " : "") + l[i];
        if (msg.empty()) msg = "tinygltf could not parse the file";
        // The library's wording, inside wavepath's: a text that is no glTF 2.0 JSON at all
        // (not JSON, too short, no "asset") says so first.
        const bool not_gltf = !glb && (msg.find("JSON") != std::string::npos ||
                                       msg.find("json") != std::string::npos ||
                                       msg.find("asset") != std::string::npos);
        if (not_gltf) fail("{}: not a glTF 2.0 file: {}", file, msg);
        fail("{}: glTF: {}", file, msg);
    }

    Scene scene;
    scene.name = origin.filename().string();
    if (scene.name.empty()) scene.name = file;
    for (const auto& l : lines_of(warn)) scene.warnings.push_back(file + ": " + l);
    for (const auto& l : lines_of(err)) scene.warnings.push_back(file + ": " + l);

    // Root nodes: the default scene, else scene 0, else every node nobody lists as a child
    std::vector<int> roots;
    if (!model.scenes.empty()) {
        int si = model.defaultScene;
        if (si < 0 || std::size_t(si) >= model.scenes.size()) si = 0;
        roots = model.scenes[si].nodes;
    } else {
        std::vector<char> is_child(model.nodes.size(), 0);
        for (const auto& n : model.nodes)
            for (int c : n.children)
                if (c >= 0 && std::size_t(c) < model.nodes.size()) is_child[c] = 1;
        for (std::size_t i = 0; i < model.nodes.size(); ++i)
            if (!is_child[i]) roots.push_back(int(i));
    }

    Notes notes;
    GltfTextures textures{model, scene, fs::path(base_dir), file, notes, {}};
    constexpr std::uint32_t kUnset = ~0u, kCutOut = ~0u - 1;  // (ids past any real one)
    std::vector<std::uint32_t> mat_ids(model.materials.size(), kUnset);
    std::uint32_t default_id = kUnset;
    // The scene material of a primitive's material index; kCutOut when nothing of it is left
    auto material_for = [&](int index) -> std::uint32_t {
        if (index >= 0 && std::size_t(index) < model.materials.size()) {
            if (mat_ids[index] == kUnset) {
                bool cut_out = false;
                Material m = convert_material(model.materials[index], index, textures, notes,
                                              cut_out);
                mat_ids[index] = cut_out ? kCutOut : scene.add_material(m);
            }
            return mat_ids[index];
        }
        if (index >= 0)
            fail("{}: a primitive refers to materials[{}], but there are {}", file, index,
                 model.materials.size());
        if (default_id == kUnset) {
            Material d;
            d.name = "default";
            d.albedo = glm::vec3(0.5f);
            default_id = scene.add_material(d);
        }
        return default_id;
    };

    std::optional<Camera> camera;
    std::uint64_t visits = 0;
    struct Item {
        int node;
        glm::mat4 parent;
        int depth;
    };
    std::vector<Item> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, glm::mat4(1.0f), 0});
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        if (item.node < 0 || std::size_t(item.node) >= model.nodes.size())
            fail("{}: a scene or node refers to nodes[{}], but there are {} nodes", file, item.node,
                 model.nodes.size());
        if (item.depth > kMaxNodeDepth)
            fail("{}: nodes[{}]: the node hierarchy is deeper than {} levels (a cycle?)", file,
                 item.node, kMaxNodeDepth);
        if (++visits > kMaxNodeVisits)
            fail("{}: more than {} node visits (nodes shared too often)", file, kMaxNodeVisits);
        const tinygltf::Node& node = model.nodes[item.node];
        const glm::mat4 world = item.parent * local_transform(node, file, item.node);

        // The first camera met
        if (node.camera >= 0 && !camera) {
            if (std::size_t(node.camera) >= model.cameras.size())
                fail("{}: nodes[{}] refers to cameras[{}], but there are {}", file, item.node,
                     node.camera, model.cameras.size());
            const tinygltf::Camera& gc = model.cameras[node.camera];
            if (gc.type == "perspective") {
                Camera c;
                const double yfov = gc.perspective.yfov * 180.0 / M_PI;
                if (!(yfov > 0.0 && yfov < 180.0))
                    fail("{}: cameras[{}].perspective.yfov {} is not in (0, pi)", file, node.camera,
                         gc.perspective.yfov);
                c.vfov_deg = float(yfov);
                c.width = limits::kDefaultWidth;
                c.height = limits::kDefaultHeight;
                const double aspect = gc.perspective.aspectRatio;
                if (aspect > 0.0 && std::isfinite(aspect)) {
                    const double h = std::round(c.width / aspect);
                    if (!(h >= 1.0 && h <= limits::kMaxImageSide))
                        fail("{}: cameras[{}].perspective.aspectRatio {} gives a film of {} x {}",
                             file, node.camera, aspect, c.width, h);
                    c.height = int(h);
                }
                c.position = glm::vec3(world[3]);
                const glm::vec3 fwd = -glm::vec3(world[2]);
                const float len = glm::length(fwd);
                if (!(len > 0.0f) || !std::isfinite(len))
                    fail("{}: nodes[{}]: the camera's transform has no viewing direction", file,
                         item.node);
                c.target = c.position + fwd / len;
                c.up = glm::vec3(world[1]);
                camera = c;
            } else {
                ++notes.ortho;
            }
        }

        // Mesh primitives
        if (node.mesh >= 0) {
            if (std::size_t(node.mesh) >= model.meshes.size())
                fail("{}: nodes[{}] refers to meshes[{}], but there are {}", file, item.node,
                     node.mesh, model.meshes.size());
            const tinygltf::Mesh& mesh = model.meshes[node.mesh];
            const bool mirror = glm::determinant(glm::mat3(world)) < 0.0f;
            for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
                const tinygltf::Primitive& prim = mesh.primitives[pi];
                const std::string where = fmt::format("meshes[{}].primitives[{}]", node.mesh, pi);
                if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES) {
                    ++notes.modes;
                    continue;
                }
                auto pos_it = prim.attributes.find("POSITION");
                if (pos_it == prim.attributes.end())
                    fail("{}: {} has no POSITION attribute", file, where);
                const int pa = pos_it->second;
                if (pa < 0 || std::size_t(pa) >= model.accessors.size())
                    fail("{}: {} POSITION refers to accessors[{}], but there are {}", file, where,
                         pa, model.accessors.size());
                const tinygltf::Accessor& pacc = model.accessors[pa];
                if (pacc.sparse.isSparse) {
                    ++notes.sparse;
                    continue;
                }
                if (pacc.type != TINYGLTF_TYPE_VEC3)
                    fail("{}: {} POSITION (accessors[{}]) is not VEC3", file, where, pa);
                if (pacc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
                    ++notes.quantized;
                    continue;
                }
                const View pv = accessor_view(model, pa, 12, file, where + " POSITION");

                // Triangles: indices or consecutive vertices
                std::size_t ntri = 0;
                View iv;
                int isize = 0;
                if (prim.indices >= 0) {
                    if (std::size_t(prim.indices) >= model.accessors.size())
                        fail("{}: {} indices refer to accessors[{}], but there are {}", file, where,
                             prim.indices, model.accessors.size());
                    const tinygltf::Accessor& ia = model.accessors[prim.indices];
                    if (ia.sparse.isSparse) {
                        ++notes.sparse;
                        continue;
                    }
                    if (ia.type != TINYGLTF_TYPE_SCALAR ||
                        (ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                         ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                         ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
                        fail("{}: {} indices (accessors[{}]) must be SCALAR unsigned byte, short "
                             "or int",
                             file, where, prim.indices);
                    isize = component_size(ia.componentType);
                    iv = accessor_view(model, prim.indices, std::size_t(isize), file,
                                       where + " indices");
                    if (iv.count % 3 != 0)
                        fail("{}: {} has {} indices, not a multiple of 3", file, where, iv.count);
                    ntri = iv.count / 3;
                } else {
                    if (pv.count % 3 != 0)
                        fail("{}: {} has {} vertices and no indices, not a multiple of 3", file,
                             where, pv.count);
                    ntri = pv.count / 3;
                }
                if (scene.triangles.size() + ntri > kMaxTriangles ||
                    scene.positions.size() + pv.count > kMaxVertices)
                    fail("{}: {}: more than {} triangles or {} vertices in all (the limit)", file,
                         where, kMaxTriangles, kMaxVertices);

                const std::uint32_t mat = material_for(prim.material);
                if (mat == kCutOut) {  // alpha MASK/BLEND, no texture, factor < cutoff
                    ++notes.cut_out;
                    continue;
                }

                // Positions to world space, checked
                std::vector<glm::vec3> pos;
                pos.reserve(pv.count);
                for (std::size_t i = 0; i < pv.count; ++i) {
                    float p[3];
                    std::memcpy(p, pv.at(i), 12);
                    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
                        fail("{}: {} POSITION (accessors[{}]) element {} is not finite ({}, {}, "
                             "{})",
                             file, where, pa, i, p[0], p[1], p[2]);
                    const glm::vec3 w = glm::vec3(world * glm::vec4(p[0], p[1], p[2], 1.0f));
                    if (!std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z))
                        fail("{}: {} vertex {} is not finite after the node transform", file, where,
                             i);
                    pos.push_back(w);
                }

                // Attributes: normals by the inverse transpose, tangents as vectors (their
                // bitangent sign flips with a mirroring transform: b = w cross(n, t) must
                // stay the transformed bitangent), uvs as they are (top-left origin already)
                std::vector<float> nf, uf, tf;
                const bool has_n = read_attribute(model, prim, "NORMAL", TINYGLTF_TYPE_VEC3, 3,
                                                  false, pv.count, file, where, notes, nf);
                const bool has_uv = read_attribute(model, prim, "TEXCOORD_0", TINYGLTF_TYPE_VEC2,
                                                   2, true, pv.count, file, where, notes, uf);
                bool has_t = read_attribute(model, prim, "TANGENT", TINYGLTF_TYPE_VEC4, 4, false,
                                            pv.count, file, where, notes, tf);
                if (has_t && !has_n) {  // a tangent frame needs the normal
                    ++notes.attributes;
                    has_t = false;
                }
                const glm::mat3 linear(world);
                const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
                auto finite3 = [](glm::vec3 v) {
                    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
                };
                std::vector<glm::vec3> nrm;
                std::vector<glm::vec2> uv;
                std::vector<glm::vec4> tan;
                if (has_n) {
                    nrm.resize(pv.count);
                    for (std::size_t i = 0; i < pv.count; ++i) {
                        const glm::vec3 n(nf[3 * i], nf[3 * i + 1], nf[3 * i + 2]);
                        const glm::vec3 w = normal_matrix * n;
                        if (finite3(n) && finite3(w)) nrm[i] = w;
                        else ++notes.non_finite;  // (zero: this vertex has no normal)
                    }
                }
                if (has_uv) {
                    uv.resize(pv.count);
                    for (std::size_t i = 0; i < pv.count; ++i) {
                        const glm::vec2 t(uf[2 * i], uf[2 * i + 1]);
                        if (std::isfinite(t.x) && std::isfinite(t.y)) uv[i] = t;
                        else ++notes.non_finite;
                    }
                }
                if (has_t) {
                    tan.resize(pv.count);
                    for (std::size_t i = 0; i < pv.count; ++i) {
                        const glm::vec3 t(tf[4 * i], tf[4 * i + 1], tf[4 * i + 2]);
                        const float sign = tf[4 * i + 3] < 0.0f ? -1.0f : 1.0f;
                        const glm::vec3 w = linear * t;
                        if (finite3(t) && finite3(w) && std::isfinite(tf[4 * i + 3]))
                            tan[i] = glm::vec4(w, mirror ? -sign : sign);
                        else ++notes.non_finite;
                    }
                }

                // Triangles (local indices; a mirroring transform reverses the winding)
                std::vector<glm::uvec3> tris;
                tris.reserve(ntri);
                for (std::size_t t = 0; t < ntri; ++t) {
                    glm::uvec3 tri;
                    for (int k = 0; k < 3; ++k) {
                        std::uint32_t v = std::uint32_t(3 * t + k);
                        if (isize > 0) {
                            const unsigned char* q = iv.at(3 * t + k);
                            if (isize == 1) v = q[0];
                            else if (isize == 2) {
                                std::uint16_t s;
                                std::memcpy(&s, q, 2);
                                v = s;
                            } else {
                                std::memcpy(&v, q, 4);
                            }
                            if (v >= pv.count)
                                fail("{}: {} index {} is {}, but POSITION has {} vertices", file,
                                     where, 3 * t + k, v, pv.count);
                        }
                        tri[k] = v;
                    }
                    if (mirror) std::swap(tri.y, tri.z);
                    tris.push_back(tri);
                }
                scene.add_mesh(pos, tris, mat, nrm, uv, tan);
            }
        }
        for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
            stack.push_back({*c, world, item.depth + 1});
    }
    if (scene.triangles.empty()) fail("{}: no triangles (no TRIANGLES primitive in the scene)", file);

    // One warning per approximation kind
    auto note = [&](int n, const std::string& text) {
        if (n > 0) scene.warnings.push_back(fmt::format("{}: {}", file, fmt::format(fmt::runtime(text), n)));
    };
    note(notes.partial_metal, "{} material(s) have metallicFactor between 0 and 1; rounded to 0 or 1");
    note(notes.metallic_map, "{} material(s) have a metallicRoughnessTexture; its roughness (G) is "
                             "read for glossy metals and rough transmission, its metallic (B) is "
                             "not modelled "
                             "(metallicFactor decides)");
    note(notes.occlusion, "{} material(s) have an occlusionTexture; ignored (a path tracer "
                          "computes occlusion)");
    note(notes.blend, "{} material(s) use alphaMode BLEND; approximated as MASK with cutoff 0.5");
    note(notes.cut_out, "{} primitive(s) have alphaMode MASK/BLEND with base colour alpha below "
                        "the cutoff and no texture; nothing of them is rendered");
    note(notes.wrap, "{} texture use(s) have a sampler wrap mode other than REPEAT; only repeat "
                     "is supported");
    note(notes.texcoord, "{} texture use(s) ask for a texCoord set other than 0; only "
                         "TEXCOORD_0 is read, so they use it");
    note(notes.no_source, "{} texture use(s) have no `source` image (only an extension's "
                          "image format); ignored");
    note(notes.bad_transform, "{} KHR_texture_transform(s) have non-numeric or non-finite "
                              "values; ignored");
    note(notes.attributes, "{} NORMAL, TEXCOORD_0 or TANGENT accessor(s) are sparse, of another "
                           "type or quantized (or a TANGENT without NORMAL); ignored");
    note(notes.non_finite, "{} normal, uv or tangent value(s) are not finite; replaced by none "
                           "(zero) or (0, 0)");
    note(notes.rough_glass, "{} transmissive material(s) have a roughness below 0.01 (alpha = "
                            "roughness^2 below 1e-4); rendered as smooth glass");
    note(notes.specular_ext, "{} transmissive material(s) have KHR_materials_specular; not "
                             "modelled (wavepath's dielectrics reflect with the exact Fresnel "
                             "term of their ior)");
    note(notes.clamped, "{} material(s) have baseColorFactor outside [0, 1]; clamped");
    note(notes.modes, "{} primitive(s) are not TRIANGLES (points, lines, strips, fans); skipped");
    note(notes.sparse, "{} primitive(s) use sparse accessors; skipped");
    note(notes.quantized, "{} primitive(s) have non-float POSITION (quantized); skipped");
    note(notes.ortho, "{} orthographic camera(s) ignored");

    scene.prune_textures();  // images whose only use asked for the other filter
    scene.camera = camera ? *camera : frame_bounds(scene.bounds(), file);
    scene.background = glm::vec3(0.0f);
    validate_scene(scene);
    return scene;
}

Scene load_gltf(const fs::path& path) {
    return parse_gltf(read_file(path, kMaxFileBytes), path);
}

}  // namespace wp
