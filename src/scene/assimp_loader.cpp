#include "scene/assimp_loader.h"
#include "scene/load.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <vector>

#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "scene/texture.h"
#include "scene/validate.h"
#include "util/error.h"
#include "util/read_file.h"

namespace wp {

namespace {

constexpr std::uint64_t kMaxFileBytes = std::uint64_t(2) << 30;
constexpr std::uint64_t kMaxPlyElements = std::uint64_t(1) << 28;
constexpr std::size_t kMaxPlyHeader = std::size_t(1) << 20;
constexpr std::uint64_t kMaxTriangles = std::uint64_t(1) << 25;
constexpr std::uint64_t kMaxVertices = std::uint64_t(1) << 27;
constexpr int kMaxNodeDepth = 1024;

// ---------------------------------------------------------------------------------------
// PLY pre-check: header, element sizes, finite coordinates (see assimp_loader.h)

enum class PlyFormat { Ascii, BinaryLe, BinaryBe };

struct PlyProperty {
    std::string name;
    int size = 0;          // bytes of a value (the item type for lists)
    bool is_float = false;  // float / double
    bool list = false;
    int count_size = 0;     // bytes of the list length
    bool count_signed = false;
    bool is_signed = false;  // the value (item) type
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> props;
};

struct PlyHeader {
    PlyFormat format = PlyFormat::Ascii;
    std::vector<PlyElement> elements;
    std::size_t data_offset = 0;  // first byte after "end_header\n"
    std::size_t lines = 0;        // header lines (the data starts on line lines + 1)
};

// Size and kind of a PLY scalar type name; size 0 when unknown.
struct PlyType {
    int size = 0;
    bool is_float = false;
    bool is_signed = false;
};
PlyType ply_type(std::string_view t) {
    if (t == "char" || t == "int8") return {1, false, true};
    if (t == "uchar" || t == "uint8") return {1, false, false};
    if (t == "short" || t == "int16") return {2, false, true};
    if (t == "ushort" || t == "uint16") return {2, false, false};
    if (t == "int" || t == "int32") return {4, false, true};
    if (t == "uint" || t == "uint32") return {4, false, false};
    if (t == "float" || t == "float32") return {4, true, true};
    if (t == "double" || t == "float64") return {8, true, true};
    return {};
}

std::vector<std::string_view> split_ws(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        std::size_t j = i;
        while (j < line.size() && !std::isspace(static_cast<unsigned char>(line[j]))) ++j;
        if (j > i) out.push_back(line.substr(i, j - i));
        i = j;
    }
    return out;
}

// Printable form of a token for messages (at most 40 characters, no control bytes).
std::string printable(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 40)) out.push_back(std::isprint(static_cast<unsigned char>(c)) ? c : '?');
    if (s.size() > 40) out += "...";
    return out;
}

PlyHeader parse_ply_header(std::string_view bytes, const std::string& file) {
    if (bytes.size() < 4 || bytes.substr(0, 3) != "ply" || (bytes[3] != '\n' && bytes[3] != '\r'))
        fail("{}:1: not a PLY file (it does not start with the line 'ply')", file);
    PlyHeader h;
    bool have_format = false;
    std::size_t pos = 0, line_no = 0;
    const std::size_t limit = std::min(bytes.size(), kMaxPlyHeader);
    while (true) {
        if (pos >= limit) {
            if (bytes.size() > kMaxPlyHeader)
                fail("{}: PLY header longer than {} bytes (no 'end_header' line)", file,
                     kMaxPlyHeader);
            fail("{}:{}: truncated PLY header: the file ends before the 'end_header' line", file,
                 line_no);
        }
        std::size_t eol = bytes.find('\n', pos);
        if (eol == std::string_view::npos || eol >= limit) {
            if (bytes.size() > kMaxPlyHeader && eol != std::string_view::npos)
                fail("{}: PLY header longer than {} bytes", file, kMaxPlyHeader);
            fail("{}:{}: truncated PLY header: the file ends before the 'end_header' line", file,
                 line_no + 1);
        }
        std::string_view line = bytes.substr(pos, eol - pos);
        pos = eol + 1;
        ++line_no;
        if (line_no == 1) continue;  // "ply"
        auto tok = split_ws(line);
        if (tok.empty()) continue;
        const std::string_view key = tok[0];
        if (key == "comment" || key == "obj_info") continue;
        if (key == "end_header") {
            h.data_offset = pos;
            h.lines = line_no;
            break;
        }
        if (key == "format") {
            if (tok.size() != 3)
                fail("{}:{}: PLY 'format' line needs a format and a version", file, line_no);
            if (tok[1] == "ascii") h.format = PlyFormat::Ascii;
            else if (tok[1] == "binary_little_endian") h.format = PlyFormat::BinaryLe;
            else if (tok[1] == "binary_big_endian") h.format = PlyFormat::BinaryBe;
            else
                fail("{}:{}: unknown PLY format '{}' (ascii, binary_little_endian or "
                     "binary_big_endian)",
                     file, line_no, printable(tok[1]));
            have_format = true;
            continue;
        }
        if (key == "element") {
            if (tok.size() != 3)
                fail("{}:{}: PLY 'element' line needs a name and a count", file, line_no);
            // (Assimp 5.2 reads a name that starts with a digit as a count: a name of twenty
            // 9s made it allocate 100 GB; found by fuzz_assimp)
            if (!(std::isalpha(static_cast<unsigned char>(tok[1][0])) || tok[1][0] == '_'))
                fail("{}:{}: PLY element name '{}' must start with a letter or '_'", file, line_no,
                     printable(tok[1]));
            PlyElement e;
            e.name = std::string(tok[1]);
            auto [end, ec] = std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), e.count);
            if (ec != std::errc() || end != tok[2].data() + tok[2].size())
                fail("{}:{}: element '{}' has an unreadable count '{}'", file, line_no,
                     printable(e.name), printable(tok[2]));
            if (e.count > kMaxPlyElements)
                fail("{}:{}: element '{}' count {} exceeds the limit of {}", file, line_no,
                     printable(e.name), e.count, kMaxPlyElements);
            h.elements.push_back(std::move(e));
            continue;
        }
        if (key == "property") {
            if (h.elements.empty())
                fail("{}:{}: PLY 'property' line before any 'element'", file, line_no);
            PlyProperty p;
            if (tok.size() == 5 && tok[1] == "list") {
                PlyType ct = ply_type(tok[2]), it = ply_type(tok[3]);
                if (ct.size == 0 || ct.is_float)
                    fail("{}:{}: list length type '{}' is not an integer type", file, line_no,
                         printable(tok[2]));
                if (it.size == 0)
                    fail("{}:{}: unknown PLY type '{}'", file, line_no, printable(tok[3]));
                p.list = true;
                p.count_size = ct.size;
                p.count_signed = ct.is_signed;
                p.size = it.size;
                p.is_float = it.is_float;
                p.is_signed = it.is_signed;
                p.name = std::string(tok[4]);
            } else if (tok.size() == 3) {
                PlyType t = ply_type(tok[1]);
                if (t.size == 0)
                    fail("{}:{}: unknown PLY type '{}'", file, line_no, printable(tok[1]));
                p.size = t.size;
                p.is_float = t.is_float;
                p.is_signed = t.is_signed;
                p.name = std::string(tok[2]);
            } else {
                fail("{}:{}: PLY 'property' line must be 'property TYPE NAME' or 'property list "
                     "COUNT_TYPE TYPE NAME'",
                     file, line_no);
            }
            h.elements.back().props.push_back(std::move(p));
            continue;
        }
        fail("{}:{}: unknown PLY header keyword '{}'", file, line_no, printable(key));
    }
    if (!have_format) fail("{}: PLY header has no 'format' line", file);
    if (h.elements.empty()) fail("{}: PLY header declares no elements", file);
    return h;
}

// "faces" for "face", "vertices" for "vertex", else NAME + " elements".
std::string plural(const std::string& name) {
    if (name == "vertex") return "vertices";
    if (name == "face") return "faces";
    return "'" + printable(name) + "' elements";
}

// Index of property x, y, z in a vertex element, or -1.
std::array<int, 3> xyz_index(const PlyElement& e) {
    std::array<int, 3> r{-1, -1, -1};
    if (e.name != "vertex") return r;
    for (std::size_t i = 0; i < e.props.size(); ++i) {
        const auto& n = e.props[i].name;
        int k = n == "x" ? 0 : n == "y" ? 1 : n == "z" ? 2 : -1;
        if (k >= 0 && !e.props[i].list && e.props[i].is_float) r[k] = int(i);
    }
    return r;
}

// Index of the float properties nx, ny, nz and of the texture coordinates (the names Assimp's
// PLY reader takes: u/s/tx/texture_u/texture_s and v/t/ty/texture_v/texture_t) in a vertex
// element, or -1.
struct PlyAttributes {
    std::array<int, 3> normal{-1, -1, -1};
    std::array<int, 2> uv{-1, -1};
    bool has_normal() const { return normal[0] >= 0 && normal[1] >= 0 && normal[2] >= 0; }
    bool has_uv() const { return uv[0] >= 0 && uv[1] >= 0; }
};
PlyAttributes attribute_index(const PlyElement& e) {
    PlyAttributes r;
    if (e.name != "vertex") return r;
    for (std::size_t i = 0; i < e.props.size(); ++i) {
        if (e.props[i].list || !e.props[i].is_float) continue;
        const auto& n = e.props[i].name;
        if (n == "nx") r.normal[0] = int(i);
        if (n == "ny") r.normal[1] = int(i);
        if (n == "nz") r.normal[2] = int(i);
        if (n == "u" || n == "s" || n == "tx" || n == "texture_u" || n == "texture_s") r.uv[0] = int(i);
        if (n == "v" || n == "t" || n == "ty" || n == "texture_v" || n == "texture_t") r.uv[1] = int(i);
    }
    return r;
}

std::uint64_t read_uint(const unsigned char* p, int size, bool big_endian, bool is_signed,
                        bool& negative) {
    std::uint64_t v = 0;
    for (int i = 0; i < size; ++i) {
        int b = big_endian ? i : size - 1 - i;
        v = (v << 8) | p[b];
    }
    negative = is_signed && (v >> (8 * size - 1)) != 0;
    return v;
}

double read_float(const unsigned char* p, int size, bool big_endian) {
    unsigned char b[8] = {};
    for (int i = 0; i < size; ++i) b[i] = p[big_endian ? size - 1 - i : i];
    if (size == 4) {
        float f;
        std::memcpy(&f, b, 4);
        return f;
    }
    double d;
    std::memcpy(&d, b, 8);
    return d;
}

// What the binary walker decodes on the way: vertex positions and the face index lists, to
// check Assimp's result against (see parse_assimp).
struct PlyGeometry {
    bool complete = false;  // x, y, z all found and a face list found
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;  // nx, ny, nz when all three are float properties
    std::vector<glm::vec2> uvs;      // (u, v) as in the file when both are float properties
    std::vector<std::uint32_t> face_sizes;
    std::vector<std::uint32_t> indices;
};

// Walks binary data: every declared element must be there; vertex x, y, z finite.
void check_ply_binary(std::string_view bytes, const PlyHeader& h, const std::string& file,
                      PlyGeometry& geo) {
    const bool be = h.format == PlyFormat::BinaryBe;
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const std::uint64_t size = bytes.size();
    std::uint64_t pos = h.data_offset;
    auto truncated = [&](const PlyElement& e, std::uint64_t done) {
        fail("{}: truncated: the header declares {} {}, the data ends after {} (byte {} of {})",
             file, e.count, plural(e.name), done, std::min(pos, size), size);
    };
    std::uint64_t want_vertices = 0, want_faces = 0;
    for (const PlyElement& e : h.elements) {
        if (e.name == "vertex") want_vertices = e.count;
        if (e.name == "face") want_faces = e.count;
    }
    for (const PlyElement& e : h.elements) {
        if (e.props.empty() || e.count == 0) continue;
        const bool fixed = std::none_of(e.props.begin(), e.props.end(),
                                        [](const PlyProperty& p) { return p.list; });
        const auto xyz = xyz_index(e);
        const bool check_xyz = xyz[0] >= 0 || xyz[1] >= 0 || xyz[2] >= 0;
        const bool all_xyz = xyz[0] >= 0 && xyz[1] >= 0 && xyz[2] >= 0;
        int face_list = -1;  // the index list of a face element
        if (e.name == "face")
            for (std::size_t k = 0; k < e.props.size() && face_list < 0; ++k)
                if (e.props[k].list && !e.props[k].is_float &&
                    (e.props[k].name == "vertex_indices" || e.props[k].name == "vertex_index"))
                    face_list = int(k);
        const PlyAttributes attr = attribute_index(e);
        const bool with_normal = all_xyz && attr.has_normal(), with_uv = all_xyz && attr.has_uv();
        if (all_xyz) geo.positions.reserve(e.count);
        if (with_normal) geo.normals.reserve(e.count);
        if (with_uv) geo.uvs.reserve(e.count);
        if (face_list >= 0) geo.face_sizes.reserve(e.count);
        if (fixed && !check_xyz) {
            std::uint64_t row = 0;
            for (const auto& p : e.props) row += std::uint64_t(p.size);
            if (size - pos < row * e.count) truncated(e, (size - pos) / row);
            pos += row * e.count;
            continue;
        }
        for (std::uint64_t i = 0; i < e.count; ++i) {
            if (all_xyz) geo.positions.emplace_back(0.0f);
            if (with_normal) geo.normals.emplace_back(0.0f);
            if (with_uv) geo.uvs.emplace_back(0.0f);
            for (std::size_t k = 0; k < e.props.size(); ++k) {
                const PlyProperty& p = e.props[k];
                if (p.list) {
                    if (size - pos < std::uint64_t(p.count_size)) truncated(e, i);
                    bool negative = false;
                    std::uint64_t n = read_uint(data + pos, p.count_size, be, p.count_signed, negative);
                    if (negative)
                        fail("{}: {} {} (byte {}): negative list length", file, e.name, i, pos);
                    pos += std::uint64_t(p.count_size);
                    if ((size - pos) / std::uint64_t(p.size) < n) truncated(e, i);
                    if (int(k) == face_list) {
                        geo.face_sizes.push_back(std::uint32_t(n));
                        for (std::uint64_t j = 0; j < n; ++j) {
                            bool neg = false;
                            std::uint64_t v = read_uint(data + pos + j * p.size, p.size, be,
                                                        p.is_signed, neg);
                            if (neg || v > 0xffffffffu)
                                fail("{}: face {} (byte {}): vertex index out of range", file, i,
                                     pos + j * p.size);
                            geo.indices.push_back(std::uint32_t(v));
                        }
                    }
                    pos += n * std::uint64_t(p.size);
                } else {
                    if (size - pos < std::uint64_t(p.size)) truncated(e, i);
                    if (check_xyz && (int(k) == xyz[0] || int(k) == xyz[1] || int(k) == xyz[2])) {
                        double v = read_float(data + pos, p.size, be);
                        if (!std::isfinite(v) || !std::isfinite(float(v)))
                            fail("{}: vertex {} (byte {}) has a non-finite coordinate {} = {}",
                                 file, i, pos, p.name, v);
                        if (all_xyz)
                            geo.positions.back()[int(k) == xyz[0] ? 0 : int(k) == xyz[1] ? 1 : 2] =
                                float(v);
                    } else if (with_normal && (int(k) == attr.normal[0] ||
                                               int(k) == attr.normal[1] || int(k) == attr.normal[2])) {
                        geo.normals.back()[int(k) == attr.normal[0] ? 0
                                           : int(k) == attr.normal[1] ? 1
                                                                       : 2] =
                            float(read_float(data + pos, p.size, be));
                    } else if (with_uv && (int(k) == attr.uv[0] || int(k) == attr.uv[1])) {
                        geo.uvs.back()[int(k) == attr.uv[0] ? 0 : 1] =
                            float(read_float(data + pos, p.size, be));
                    }
                    pos += std::uint64_t(p.size);
                }
            }
        }
    }
    geo.complete = want_vertices > 0 && want_faces > 0 && geo.positions.size() == want_vertices &&
                   geo.face_sizes.size() == want_faces;
}

// Counts ASCII tokens: every declared element must be there; vertex x, y, z finite.
void check_ply_ascii(std::string_view bytes, const PlyHeader& h, const std::string& file) {
    std::size_t pos = h.data_offset, line = h.lines + 1, line_start = h.data_offset;
    std::size_t tok_line = line, tok_col = 1;
    // Next whitespace-separated token, or an empty view at the end
    auto next = [&]() -> std::string_view {
        while (pos < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[pos]))) {
            if (bytes[pos] == '\n') {
                ++line;
                line_start = pos + 1;
            }
            ++pos;
        }
        std::size_t start = pos;
        while (pos < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[pos]))) ++pos;
        tok_line = line;
        tok_col = start - line_start + 1;
        return bytes.substr(start, pos - start);
    };
    for (const PlyElement& e : h.elements) {
        if (e.props.empty()) continue;
        const auto xyz = xyz_index(e);
        for (std::uint64_t i = 0; i < e.count; ++i) {
            for (std::size_t k = 0; k < e.props.size(); ++k) {
                const PlyProperty& p = e.props[k];
                std::string_view t = next();
                if (t.empty())
                    fail("{}:{}: truncated: the header declares {} {}, the data ends after {}",
                         file, line, e.count, plural(e.name), i);
                if (p.list) {
                    std::uint64_t n = 0;
                    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), n);
                    if (ec != std::errc() || end != t.data() + t.size())
                        fail("{}:{}:{}: {} {}: list length '{}' is not a non-negative integer",
                             file, tok_line, tok_col, e.name, i, printable(t));
                    for (std::uint64_t j = 0; j < n; ++j)
                        if (next().empty())
                            fail("{}:{}: truncated: the header declares {} {}, the data ends "
                                 "after {}",
                                 file, line, e.count, plural(e.name), i);
                } else if (int(k) == xyz[0] || int(k) == xyz[1] || int(k) == xyz[2]) {
                    std::string_view s = t;
                    if (!s.empty() && s[0] == '+') s.remove_prefix(1);
                    double v = 0.0;
                    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
                    if (ec == std::errc::result_out_of_range ||
                        (ec == std::errc() && (!std::isfinite(v) || !std::isfinite(float(v)))))
                        fail("{}:{}:{}: vertex {} has a non-finite coordinate {} = '{}'", file,
                             tok_line, tok_col, i, p.name, printable(t));
                    if (ec != std::errc() || end != s.data() + s.size())
                        fail("{}:{}:{}: vertex {} has an unreadable coordinate {} = '{}'", file,
                             tok_line, tok_col, i, p.name, printable(t));
                }
            }
        }
    }
    // Values left over: a line with a missing value shifts the rest, or the counts are wrong
    if (!next().empty())
        fail("{}:{}:{}: more values than the header declares (a line with a missing or extra "
             "value, or wrong element counts)",
             file, tok_line, tok_col);
}

// ---------------------------------------------------------------------------------------
// Scene building

Material default_material() {
    Material d;
    d.name = "default";
    d.kind = MaterialKind::Diffuse;
    d.albedo = glm::vec3(0.5f);
    return d;
}

glm::mat4 to_glm(const aiMatrix4x4& m) {
    // Assimp is row-major (a1..a4 = first row); GLM is column-major
    return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4,
                     m.b4, m.c4, m.d4);
}

// Approximations met while mapping materials, one warning each per file.
struct MaterialNotes {
    int specular = 0, textures = 0, opacity = 0, clamped = 0, uv_channel = 0, raw_embedded = 0;
};

// Assimp's own "DefaultMaterial" (a format without materials) is not converted: nullopt.
std::optional<Material> convert_material(const aiMaterial& am, MaterialNotes& notes) {
    aiString name;
    if (am.Get(AI_MATKEY_NAME, name) == AI_SUCCESS && std::string(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME)
        return std::nullopt;
    Material m;
    m.name = name.length > 0 ? std::string(name.C_Str()) : std::string("unnamed");
    m.kind = MaterialKind::Diffuse;
    aiColor3D kd(0.5f, 0.5f, 0.5f), ke(0.0f, 0.0f, 0.0f), ks(0.0f, 0.0f, 0.0f);
    am.Get(AI_MATKEY_COLOR_DIFFUSE, kd);
    glm::vec3 a(kd.r, kd.g, kd.b);
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(a[k])) a[k] = 0.5f;
    glm::vec3 c = glm::clamp(a, glm::vec3(0.0f), glm::vec3(1.0f));
    if (c != a) ++notes.clamped;
    m.albedo = c;
    if (am.Get(AI_MATKEY_COLOR_EMISSIVE, ke) == AI_SUCCESS) {
        float scale = 1.0f;
        if (am.Get(AI_MATKEY_EMISSIVE_INTENSITY, scale) != AI_SUCCESS || !std::isfinite(scale))
            scale = 1.0f;
        glm::vec3 e = glm::vec3(ke.r, ke.g, ke.b) * scale;
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(e[k]) || e[k] < 0.0f) e[k] = 0.0f;
        m.emission = e;
    }
    if (am.Get(AI_MATKEY_COLOR_SPECULAR, ks) == AI_SUCCESS && (ks.r > 0.0f || ks.g > 0.0f || ks.b > 0.0f))
        ++notes.specular;
    float opacity = 1.0f;
    if (am.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && opacity < 1.0f) ++notes.opacity;
    for (int t = aiTextureType_DIFFUSE; t <= AI_TEXTURE_TYPE_MAX; ++t)
        if (am.GetTextureCount(aiTextureType(t)) > (t == aiTextureType_DIFFUSE ? 1u : 0u)) {
            ++notes.textures;  // (the first diffuse texture is read: diffuse_texture)
            break;
        }
    return m;
}

// The first diffuse texture of a material: a file relative to the model's folder, or an
// embedded compressed image ("*N" or its name); nullopt when there is none or it cannot be
// used (a folder or device, an uncompressed embedded texel array: noted).
std::optional<TextureRef> diffuse_texture(const aiScene& as, const aiMaterial& am, Scene& scene,
                                          const std::filesystem::path& dir,
                                          const std::string& file, MaterialNotes& notes,
                                          std::map<std::string, int>& embedded) {
    namespace fs = std::filesystem;
    aiString path;
    unsigned uv_index = 0;
    if (am.GetTextureCount(aiTextureType_DIFFUSE) == 0 ||
        am.GetTexture(aiTextureType_DIFFUSE, 0, &path, nullptr, &uv_index) != AI_SUCCESS)
        return std::nullopt;
    std::string name = path.C_Str();
    if (name.empty()) return std::nullopt;
    if (uv_index != 0) ++notes.uv_channel;
    TextureRef r;
    if (const aiTexture* t = as.GetEmbeddedTexture(name.c_str())) {
        if (t->mHeight != 0 || !t->pcData || t->mWidth == 0) {
            ++notes.raw_embedded;
            return std::nullopt;
        }
        auto it = embedded.find(name);
        if (it == embedded.end()) {
            const std::string bytes(reinterpret_cast<const char*>(t->pcData), t->mWidth);
            scene.textures.push_back(load_texture_from_memory(
                bytes, fmt::format("{}: embedded texture '{}'", file, printable(name)),
                TextureUse::Colour, scene.warnings));
            it = embedded.emplace(name, int(scene.textures.size() - 1)).first;
        }
        r.image = it->second;
        return r;
    }
    std::replace(name.begin(), name.end(), '\\', '/');  // paths written on Windows
    const fs::path p = dir / fs::path(name);
    std::error_code ec;
    const fs::file_status st = fs::status(p, ec);
    if (fs::exists(st) && !fs::is_regular_file(st)) {
        scene.warnings.push_back(fmt::format("{}: texture '{}' is not a regular file; ignored",
                                             file, p.string()));
        return std::nullopt;
    }
    r.image = add_texture_file(scene, p, TextureUse::Colour);
    return r;
}

// True when Assimp read exactly what the binary walker decoded.
bool assimp_matches(const aiScene* as, const PlyGeometry& geo) {
    if (!as || as->mNumMeshes != 1 || !as->mMeshes || !as->mMeshes[0]) return false;
    const aiMesh* m = as->mMeshes[0];
    if (m->mNumVertices != geo.positions.size() || m->mNumFaces != geo.face_sizes.size())
        return false;
    for (unsigned v = 0; v < m->mNumVertices; ++v) {
        const aiVector3D& p = m->mVertices[v];
        if (glm::vec3(p.x, p.y, p.z) != geo.positions[v]) return false;
    }
    std::size_t at = 0;
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
        const aiFace& face = m->mFaces[f];
        if (face.mNumIndices != geo.face_sizes[f]) return false;
        for (unsigned k = 0; k < face.mNumIndices; ++k)
            if (face.mIndices[k] != geo.indices[at + k]) return false;
        at += face.mNumIndices;
    }
    return true;
}

std::string lower(std::string s) {
    for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

}  // namespace

Scene parse_assimp(std::string_view bytes, const std::string& extension,
                   const std::filesystem::path& origin) {
    const std::string file = origin.string();
    std::string ext = lower(extension);
    if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
    if (ext.empty() || ext.size() > 8 ||
        !std::all_of(ext.begin(), ext.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)); }))
        fail("{}: unsupported mesh file extension '{}'", file, printable(extension));
    if (!is_assimp_extension("." + ext))
        fail("{}: format '.{}' is not read through Assimp (supported: .ply, .stl, .3ds, .dae, "
             ".fbx; .off is refused: Assimp 5.2's OFF importer reads out of bounds on a face "
             "with more corners than the file has)",
             file, ext);
    if (bytes.empty()) fail("{}: the file is empty", file);
    if (bytes.size() > kMaxFileBytes)
        fail("{}: the file is {} bytes, more than the limit of {}", file, bytes.size(), kMaxFileBytes);

    Scene scene;
    scene.name = origin.filename().string();
    if (scene.name.empty()) scene.name = file;

    // PLY: header and data checked here (Assimp hangs or repeats faces on truncated files)
    std::optional<PlyHeader> ply;
    PlyGeometry ply_geo;
    if (ext == "ply") {
        ply = parse_ply_header(bytes, file);
        if (ply->format == PlyFormat::Ascii) check_ply_ascii(bytes, *ply, file);
        else check_ply_binary(bytes, *ply, file, ply_geo);
    }

    // Read without post-processing, check, then triangulate
    Assimp::Importer importer;
    const aiScene* as = nullptr;
    try {
        as = importer.ReadFileFromMemory(bytes.data(), bytes.size(), 0, ext.c_str());
    } catch (const std::exception& e) {
        fail("{}: Assimp could not read the file: {}", file, e.what());
    }
    // Assimp 5.2 skips whitespace bytes after "end_header", so a binary PLY whose data starts
    // with 0x09-0x0d or 0x20 is read shifted (garbage vertices, empty faces). When its result
    // differs from what the walker decoded, the walker's vertices and faces are used.
    if (ply && ply->format != PlyFormat::Ascii && ply_geo.complete && !assimp_matches(as, ply_geo)) {
        std::uint64_t skipped = 0, at = 0;
        scene.positions = ply_geo.positions;
        scene.normals = ply_geo.normals;
        for (glm::vec3& n : scene.normals)
            if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) n = glm::vec3(0.0f);
        scene.uvs.reserve(ply_geo.uvs.size());
        for (const glm::vec2& t : ply_geo.uvs)  // v up in the file: stored 1 - v
            scene.uvs.push_back(std::isfinite(t.x) && std::isfinite(t.y) ? glm::vec2(t.x, 1.0f - t.y)
                                                                        : glm::vec2(0.0f));
        for (std::size_t f = 0; f < ply_geo.face_sizes.size(); ++f) {
            const std::uint32_t n = ply_geo.face_sizes[f];
            for (std::uint32_t k = 0; k < n; ++k)
                if (ply_geo.indices[at + k] >= scene.positions.size())
                    fail("{}: face {} uses vertex {}, but the file has {} vertices", file, f,
                         ply_geo.indices[at + k], scene.positions.size());
            if (n < 3) ++skipped;
            for (std::uint32_t k = 1; k + 1 < n; ++k)  // fan
                scene.triangles.emplace_back(ply_geo.indices[at], ply_geo.indices[at + k],
                                             ply_geo.indices[at + k + 1]);
            at += n;
            if (scene.triangles.size() > kMaxTriangles)
                fail("{}: more than {} triangles (the limit)", file, kMaxTriangles);
        }
        if (scene.triangles.empty()) fail("{}: no triangles (no face has 3 or more vertices)", file);
        if (skipped > 0)
            scene.warnings.push_back(fmt::format(
                "{}: {} faces with fewer than 3 vertices (points, lines) skipped", file, skipped));
        scene.material_ids.assign(scene.triangles.size(), scene.add_material(default_material()));
        scene.camera = frame_bounds(scene.bounds(), file);
        validate_scene(scene);
        return scene;
    }
    if (!as) {
        std::string why = importer.GetErrorString();
        while (!why.empty() && std::isspace(static_cast<unsigned char>(why.back()))) why.pop_back();
        fail("{}: Assimp could not read the file as .{}: {}", file, ext,
             why.empty() ? std::string("unknown error") : why);
    }
    if (!as->mRootNode || as->mNumMeshes == 0 || !as->mMeshes)
        fail("{}: no triangles (the file has no meshes)", file);

    // Every face index in range, before any post-processing touches them
    std::uint64_t faces_read = 0;
    for (unsigned mi = 0; mi < as->mNumMeshes; ++mi) {
        const aiMesh* m = as->mMeshes[mi];
        if (!m) fail("{}: mesh {} is missing", file, mi);
        if (m->mNumVertices > 0 && !m->mVertices) fail("{}: mesh {} has no positions", file, mi);
        faces_read += m->mNumFaces;
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            const aiFace& face = m->mFaces[f];
            // (a face with no indices makes Assimp 5.2's Triangulate abort the process:
            // found by fuzz_assimp, e.g. a PLY face list of length 0 or a truncated OFF)
            if (face.mNumIndices == 0 || !face.mIndices)
                fail("{}: face {} has no vertex indices", file, f);
            for (unsigned k = 0; k < face.mNumIndices; ++k)
                if (face.mIndices[k] >= m->mNumVertices) {
                    if (as->mNumMeshes == 1)
                        fail("{}: face {} uses vertex {}, but the file has {} vertices", file, f,
                             face.mIndices[k], m->mNumVertices);
                    fail("{}: mesh {} ('{}'): face {} uses vertex {}, but the mesh has {} "
                         "vertices",
                         file, mi, printable(m->mName.C_Str()), f, face.mIndices[k], m->mNumVertices);
                }
        }
    }
    if (ply) {
        for (const PlyElement& e : ply->elements)
            if (e.name == "face" && faces_read != e.count)
                fail("{}: the header declares {} faces, but {} were read", file, e.count,
                     faces_read);
    }
    // Non-finite positions (PLY was checked already, with line or byte offset)
    for (unsigned mi = 0; mi < as->mNumMeshes; ++mi) {
        const aiMesh* m = as->mMeshes[mi];
        for (unsigned v = 0; v < m->mNumVertices; ++v) {
            const aiVector3D& p = m->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                fail("{}: mesh {} ('{}'): vertex {} has a non-finite position ({}, {}, {})", file,
                     mi, printable(m->mName.C_Str()), v, p.x, p.y, p.z);
        }
    }
    // Triangulate polygons, only when there are some: Assimp 5.2's Triangulate aborts the
    // process (ai_assert) when a mesh's primitive-type flags claim polygons it does not have,
    // so the flags are recomputed from the faces first.
    bool polygons = false;
    for (unsigned mi = 0; mi < as->mNumMeshes; ++mi) {
        aiMesh* m = const_cast<aiMesh*>(as->mMeshes[mi]);
        unsigned types = 0;
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            const unsigned n = m->mFaces[f].mNumIndices;
            types |= n == 1   ? unsigned(aiPrimitiveType_POINT)
                     : n == 2 ? unsigned(aiPrimitiveType_LINE)
                     : n == 3 ? unsigned(aiPrimitiveType_TRIANGLE)
                              : unsigned(aiPrimitiveType_POLYGON);  // n >= 1 (checked above)
        }
        m->mPrimitiveTypes = types;
        polygons = polygons || (types & aiPrimitiveType_POLYGON) != 0;
    }
    if (polygons) {
        as = importer.ApplyPostProcessing(aiProcess_Triangulate);
        if (!as)
            fail("{}: Assimp could not triangulate the file: {}", file, importer.GetErrorString());
    }

    // Node instances (iterative walk, parent × child), and the size they add up to
    struct Instance {
        unsigned mesh;
        glm::mat4 to_world;
    };
    std::vector<Instance> instances;
    std::uint64_t total_tris = 0, total_verts = 0;
    {
        struct Item {
            const aiNode* node;
            glm::mat4 parent;
            int depth;
        };
        std::vector<Item> stack{{as->mRootNode, glm::mat4(1.0f), 0}};
        while (!stack.empty()) {
            Item it = stack.back();
            stack.pop_back();
            if (!it.node) continue;
            if (it.depth > kMaxNodeDepth)
                fail("{}: node tree deeper than {} levels", file, kMaxNodeDepth);
            const glm::mat4 world = it.parent * to_glm(it.node->mTransformation);
            for (unsigned k = 0; k < it.node->mNumMeshes; ++k) {
                unsigned mi = it.node->mMeshes[k];
                if (mi >= as->mNumMeshes)
                    fail("{}: node '{}' refers to mesh {} of {}", file,
                         printable(it.node->mName.C_Str()), mi, as->mNumMeshes);
                total_tris += as->mMeshes[mi]->mNumFaces;
                total_verts += as->mMeshes[mi]->mNumVertices;
                if (total_tris > kMaxTriangles || total_verts > kMaxVertices)
                    fail("{}: more than {} triangles or {} vertices after instancing (the limit)",
                         file, kMaxTriangles, kMaxVertices);
                instances.push_back({mi, world});
            }
            for (unsigned c = it.node->mNumChildren; c-- > 0;)
                stack.push_back({it.node->mChildren[c], world, it.depth + 1});
        }
    }

    // Materials: none for PLY/STL/OFF (default grey), else mapped on first use
    const bool has_materials = !(ext == "ply" || ext == "stl" || ext == "off");
    std::vector<std::uint32_t> used(as->mNumMaterials, ~0u);
    std::uint32_t default_id = ~0u;
    MaterialNotes notes;
    std::map<std::string, int> embedded;  // embedded texture name -> scene texture
    auto material_for = [&](unsigned index) -> std::uint32_t {
        if (has_materials && index < as->mNumMaterials && as->mMaterials && as->mMaterials[index]) {
            if (used[index] == ~0u) {
                if (auto m = convert_material(*as->mMaterials[index], notes)) {
                    // A diffuse texture replaces the diffuse colour (Collada, FBX)
                    if (auto t = diffuse_texture(*as, *as->mMaterials[index], scene,
                                                 origin.parent_path(), file, notes, embedded)) {
                        m->albedo_map = *t;
                        m->albedo = glm::vec3(1.0f);
                    }
                    used[index] = scene.add_material(*m);
                }
            }
            if (used[index] != ~0u) return used[index];
        }
        if (default_id == ~0u) default_id = scene.add_material(default_material());
        return default_id;
    };

    // Geometry: positions transformed, normals by the inverse transpose, the first uv set as
    // (u, 1 - v) (Assimp's uvs are v-up without aiProcess_FlipUVs); triangles kept
    // (mirroring transforms flip winding)
    scene.positions.reserve(total_verts);
    scene.triangles.reserve(total_tris);
    scene.material_ids.reserve(total_tris);
    std::uint64_t skipped = 0, non_finite = 0;
    std::vector<glm::vec3> pos, nrm;
    std::vector<glm::vec2> uv;
    std::vector<glm::uvec3> tris;
    for (const Instance& inst : instances) {
        const aiMesh* m = as->mMeshes[inst.mesh];
        const glm::mat3 linear(inst.to_world);
        const glm::mat3 normal_matrix = glm::transpose(glm::inverse(linear));
        pos.clear();
        nrm.clear();
        uv.clear();
        tris.clear();
        for (unsigned v = 0; v < m->mNumVertices; ++v) {
            const aiVector3D& p = m->mVertices[v];
            glm::vec3 w = glm::vec3(inst.to_world * glm::vec4(p.x, p.y, p.z, 1.0f));
            if (!std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z))
                fail("{}: mesh {} ('{}'): vertex {} is not finite after its node transform ({}, "
                     "{}, {})",
                     file, inst.mesh, printable(m->mName.C_Str()), v, w.x, w.y, w.z);
            pos.push_back(w);
        }
        if (m->mNormals) {
            nrm.resize(m->mNumVertices, glm::vec3(0.0f));
            for (unsigned v = 0; v < m->mNumVertices; ++v) {
                const aiVector3D& n = m->mNormals[v];
                const glm::vec3 w = normal_matrix * glm::vec3(n.x, n.y, n.z);
                if (std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)) nrm[v] = w;
                else ++non_finite;  // (zero: no normal at this vertex)
            }
        }
        if (m->mTextureCoords[0] && m->mNumUVComponents[0] >= 2) {
            uv.resize(m->mNumVertices, glm::vec2(0.0f));
            for (unsigned v = 0; v < m->mNumVertices; ++v) {
                const aiVector3D& t = m->mTextureCoords[0][v];
                if (std::isfinite(t.x) && std::isfinite(t.y)) uv[v] = glm::vec2(t.x, 1.0f - t.y);
                else ++non_finite;
            }
        }
        const bool mirror = glm::determinant(linear) < 0.0f;
        const std::uint32_t mat = material_for(m->mMaterialIndex);
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            const aiFace& face = m->mFaces[f];
            if (face.mNumIndices != 3) {
                ++skipped;
                continue;
            }
            glm::uvec3 t(face.mIndices[0], face.mIndices[1], face.mIndices[2]);
            for (int k = 0; k < 3; ++k)
                if (t[k] >= m->mNumVertices)
                    fail("{}: mesh {}: triangle {} uses vertex {} of {}", file, inst.mesh, f, t[k],
                         m->mNumVertices);
            if (mirror) std::swap(t.y, t.z);
            tris.push_back(t);
        }
        scene.add_mesh(pos, tris, mat, nrm, uv);
    }
    if (non_finite > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} normal(s) or texture coordinate(s) are not finite; replaced by none / (0, 0)",
            file, non_finite));
    if (scene.triangles.empty()) fail("{}: no triangles (the file has no faces with 3 or more vertices)", file);
    if (skipped > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} faces with fewer than 3 vertices (points, lines) skipped", file, skipped));
    if (notes.specular > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} material(s) have a specular colour; wavepath maps them to diffuse (specular "
            "ignored)",
            file, notes.specular));
    if (notes.textures > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} material(s) have textures other than their first diffuse one; those are "
            "ignored",
            file, notes.textures));
    if (notes.uv_channel > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} diffuse texture(s) ask for a uv channel other than the first; only the first "
            "is read, so they use it",
            file, notes.uv_channel));
    if (notes.raw_embedded > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} embedded texture(s) are uncompressed texel arrays; not supported, ignored",
            file, notes.raw_embedded));
    if (notes.opacity > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} material(s) have opacity < 1; transparency is ignored (opaque)", file,
            notes.opacity));
    if (notes.clamped > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} material(s) have a diffuse colour outside [0, 1]; clamped", file, notes.clamped));

    scene.camera = frame_bounds(scene.bounds(), file);
    scene.background = glm::vec3(0.0f);
    validate_scene(scene);
    return scene;
}

Scene load_assimp(const std::filesystem::path& path) {
    return parse_assimp(read_file(path, kMaxFileBytes), path.extension().string(), path);
}

}  // namespace wp
