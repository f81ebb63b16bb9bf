#include "scene/obj_loader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include <tiny_obj_loader.h>

#include "scene/texture.h"
#include "scene/validate.h"
#include "util/error.h"
#include "util/limits.h"
#include "util/read_file.h"

namespace wp {

namespace {

// Larger texts are refused before any parsing (tinyobjloader needs several times the
// text size in memory).
constexpr std::size_t kMaxObjBytes = std::size_t(2) << 30;

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

// Splits a line into whitespace-separated tokens, up to a comment ('#').
std::vector<std::string_view> tokens(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_space(line[i]))
            ++i;
        std::size_t j = i;
        while (j < line.size() && !is_space(line[j]))
            ++j;
        if (j > i && line[i] == '#') break;
        if (j > i) out.push_back(line.substr(i, j - i));
        i = j;
    }
    return out;
}

// Calls fn(line) for every line of text, ending lines where tinyobjloader ends them: at
// "\n", "\r\n" or a lone "\r". Every check made before tinyobjloader reads a text must see
// its lines (a checker that split at "\n" alone read "o a\rvw 1 21e39" as an `o` line, while
// tinyobjloader read a `vw` line; found by fuzz_obj).
template <class Fn>
void for_each_line(std::string_view text, Fn&& fn) {
    std::size_t pos = 0;
    while (pos < text.size()) {
        std::size_t eol = text.find_first_of("\r\n", pos);
        if (eol == std::string_view::npos) eol = text.size();
        fn(text.substr(pos, eol - pos));
        pos = eol + 1;
        if (eol < text.size() && text[eol] == '\r' && pos < text.size() && text[pos] == '\n')
            ++pos;
    }
}

// tinyobjloader's number parser overflows a signed int (undefined behaviour) on an exponent
// of 10 digits, e.g. "1e2147483648" (found by fuzz_obj). Every token of a line that looks
// like a number with an exponent of more than 6 digits is refused before it gets there.
void check_exponents(const std::vector<std::string_view>& tok, const std::string& file,
                     std::size_t line_no) {
    for (auto t : tok) {
        std::size_t e = t.find_first_of("eE");
        if (e == std::string_view::npos || e == 0) continue;
        char before = t[e - 1];
        if (!(std::isdigit(static_cast<unsigned char>(before)) || before == '.')) continue;
        std::size_t k = e + 1;
        if (k < t.size() && (t[k] == '+' || t[k] == '-')) ++k;
        std::size_t digits = 0;
        while (k + digits < t.size() && std::isdigit(static_cast<unsigned char>(t[k + digits])))
            ++digits;
        if (digits > 6)
            fail("{}:{}: number '{}' is out of range (its exponent has {} digits)", file, line_no,
                 std::string(t.substr(0, 40)), digits);
    }
}

// Checks the raw text before tinyobjloader sees it: tinyobjloader reads "nan" or garbage
// as 0, and turns out-of-range face indices into out-of-range shape indices (or silently
// drops the face), without a line number. Here every `v` must have 3 finite coordinates and
// every `f` at least 3 vertices whose position index lies in [1, vertex count]. Returns the
// text for tinyobjloader, with trailing comments removed from geometry lines (tinyobjloader
// rejects "f 1 2 3 # note") and every line ending as "\n"; line numbers are kept.
std::string checked_obj_text(std::string_view input, const std::string& file,
                             std::size_t& face_count) {
    std::string text;
    text.reserve(input.size() + input.size() / 8 + 16);

    struct Forward { // a positive index beyond the vertices read so far, checked at the end
        std::size_t line;
        long index;
    };
    std::vector<Forward> forward;
    std::size_t vertices = 0, line_no = 0;
    face_count = 0;
    for_each_line(input, [&](std::string_view line) {
        ++line_no;
        auto tok = tokens(line);
        check_exponents(tok, file, line_no);
        // Geometry lines without their comment tail; other lines (names may hold '#') as is.
        // `vw` (tinyobjloader's skin-weight extension) is dropped: nothing here renders
        // skinning, and tinyobjloader casts its joint ids to int unchecked (undefined
        // behaviour for "vw 1 21e39", found by fuzz_obj). The line stays, empty, so that
        // later line numbers still match the file.
        static constexpr std::string_view kGeometry[] = {"v", "vt", "vn", "vp", "f", "l", "p"};
        if (!tok.empty() && tok[0] == "vw") {
            // nothing
        } else if (!tok.empty() && std::find(std::begin(kGeometry), std::end(kGeometry),
                                             tok[0]) != std::end(kGeometry)) {
            for (auto t : tok)
                text.append(t).push_back(' ');
        } else {
            text.append(line);
        }
        text.push_back('\n');
        if (tok.empty()) return;

        // Vertex: 3 finite coordinates (a 4th w or RGB colours may follow)
        if (tok[0] == "v") {
            ++vertices;
            if (tok.size() < 4)
                fail("{}:{}: vertex {} has {} coordinates, expected 3", file, line_no, vertices,
                     tok.size() - 1);
            for (std::size_t k = 1; k < 4; ++k) {
                std::string_view t = tok[k];
                if (!t.empty() && t[0] == '+') t.remove_prefix(1);
                double x = 0.0;
                auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
                if (ec == std::errc::result_out_of_range ||
                    (ec == std::errc() && !std::isfinite(x)))
                    fail("{}:{}: vertex {} has a non-finite coordinate '{}'", file, line_no,
                         vertices, tok[k]);
                if (ec != std::errc() || end != t.data() + t.size())
                    fail("{}:{}: vertex {} has an unreadable coordinate '{}'", file, line_no,
                         vertices, tok[k]);
                if (!std::isfinite(static_cast<float>(x)))
                    fail("{}:{}: vertex {} has a coordinate '{}' beyond the float range", file,
                         line_no, vertices, tok[k]);
            }
            return;
        }

        // Face: >= 3 vertices, position indices 1..N or -1..-N (relative to this line)
        if (tok[0] == "f") {
            if (tok.size() < 4)
                fail("{}:{}: face has {} vertices, at least 3 are needed", file, line_no,
                     tok.size() - 1);
            for (std::size_t k = 1; k < tok.size(); ++k) {
                std::string_view t = tok[k].substr(0, tok[k].find('/'));
                long idx = 0;
                auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), idx);
                if (ec != std::errc() || end != t.data() + t.size())
                    fail("{}:{}: face vertex '{}' is not a vertex index", file, line_no, tok[k]);
                if (idx == 0)
                    fail("{}:{}: face vertex index 0 is invalid (OBJ indices start at 1)", file,
                         line_no);
                if (idx < 0 && long(vertices) + idx < 0)
                    fail("{}:{}: face vertex index {} is out of range: only {} vertices precede "
                         "this line",
                         file, line_no, idx, vertices);
                if (idx > long(vertices)) forward.push_back({line_no, idx});
            }
            ++face_count;
        }
    });
    // Positive indices may name vertices defined later in the file, but must exist
    for (const Forward& f : forward)
        if (f.index > long(vertices))
            fail("{}:{}: face vertex index {} is out of range: the file has {} vertices", file,
                 f.line, f.index, vertices);
    return text;
}

// Reads `mtllib` files relative to the .obj's folder (tinyobjloader's own reader splits the
// folder at ':' and would follow any path into a device or a fifo). Only regular files up
// to kMaxMtlBytes are read; anything else is a warning ("not found"), as a missing one is.
constexpr std::uintmax_t kMaxMtlBytes = std::uintmax_t(64) << 20;

MtlSource mtl_files_beside(const std::filesystem::path& origin) {
    namespace fs = std::filesystem;
    const fs::path dir = origin.parent_path().empty() ? fs::path(".") : origin.parent_path();
    return [dir](const std::string& name) -> std::optional<std::string> {
        return try_read_file(dir / name, kMaxMtlBytes);
    };
}

// What tinyobjloader's material_t does not say: the library a material came from (its
// textures are relative to the library's folder) and whether the material has a `Kd` / `Ke`
// line (tinyobjloader fills a missing Kd with 0.6 when map_Kd is given, and a missing Ke
// with 0; wavepath reads a map without its constant as the map alone, see convert_material).
struct MtlInfo {
    std::string library;
    bool has_kd = false, has_ke = false;
};

// The `newmtl` names of an MTL text that have a `Kd` / `Ke` line (first definition wins, as
// in tinyobjloader's name lookup); names are parsed as tinyobjloader does.
struct MtlLines {
    std::map<std::string, std::pair<bool, bool>> kd_ke;
};
MtlLines scan_mtl(std::string_view text) {
    MtlLines out;
    std::string current;
    bool have = false;
    std::pair<bool, bool> flags{false, false};
    auto flush = [&] {
        if (have) out.kd_ke.emplace(current, flags);
    };
    for_each_line(text, [&](std::string_view line) {
        while (!line.empty() && (line.front() == ' ' || line.front() == '\t')) line.remove_prefix(1);
        while (!line.empty() && is_space(line.back())) line.remove_suffix(1);
        auto key = [&](std::string_view k) {
            return line.size() > k.size() && line.substr(0, k.size()) == k &&
                   (line[k.size()] == ' ' || line[k.size()] == '\t');
        };
        if (key("newmtl")) {
            flush();
            current = std::string(line.substr(7));
            have = true;
            flags = {false, false};
        } else if (key("Kd")) {
            flags.first = true;
        } else if (key("Ke")) {
            flags.second = true;
        }
    });
    flush();
    return out;
}

// tinyobjloader's hook for `mtllib`: the library's text from an MtlSource; records an
// MtlInfo per material it adds.
class MtlReader : public tinyobj::MaterialReader {
  public:
    MtlReader(const MtlSource& source, std::vector<MtlInfo>& info) : source_(source), info_(info) {}
    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* names, std::string* warn,
                    std::string* err) override {
        std::optional<std::string> text = source_ ? source_(name) : std::nullopt;
        if (!text) {
            if (warn)
                *warn += fmt::format("material library '{}' not found (or not a regular file "
                                     "of at most {} MiB)\n",
                                     name, kMaxMtlBytes >> 20);
            return false;
        }
        std::size_t line_no = 0;
        for_each_line(*text, [&](std::string_view line) {
            check_exponents(tokens(line), name, ++line_no);
        });
        const MtlLines lines = scan_mtl(*text);
        const std::size_t before = materials->size();
        std::istringstream in(std::move(*text));
        tinyobj::LoadMtl(names, materials, &in, warn, err);
        info_.resize(before);
        for (std::size_t i = before; i < materials->size(); ++i) {
            MtlInfo mi;
            mi.library = name;
            auto it = lines.kd_ke.find((*materials)[i].name);
            if (it != lines.kd_ke.end()) {
                mi.has_kd = it->second.first;
                mi.has_ke = it->second.second;
            }
            info_.push_back(std::move(mi));
        }
        return true;
    }

  private:
    const MtlSource& source_;
    std::vector<MtlInfo>& info_;
};

float max3(const tinyobj::real_t c[3]) {
    return float(std::max({c[0], c[1], c[2]}));
}
float min3(const tinyobj::real_t c[3]) {
    return float(std::min({c[0], c[1], c[2]}));
}
glm::vec3 vec3(const tinyobj::real_t c[3]) {
    return glm::vec3(float(c[0]), float(c[1]), float(c[2]));
}

// The uv transform of the MTL texture options `-s su sv` and `-o ou ov`. MTL looks a map up at
// (su u + ou, sv v + ov) in its own v-up coordinates (as three.js's and Blender's importers
// do); wavepath stores (u, w) with w = 1 - v and looks up its transformed (u', w') top-down,
// so w' = 1 - (sv (1 - w) + ov) = sv w + (1 - sv - ov):
//   uv_transform = [su 0 ou; 0 sv 1 - sv - ov; 0 0 1].
glm::mat3 mtl_uv_transform(const tinyobj::texture_option_t& o) {
    glm::mat3 m(1.0f);
    const float su = float(o.scale[0]), sv = float(o.scale[1]);
    const float ou = float(o.origin_offset[0]), ov = float(o.origin_offset[1]);
    m[0][0] = su;
    m[1][1] = sv;
    m[2][0] = ou;
    m[2][1] = 1.0f - sv - ov;
    return m;
}

bool finite_matrix(const glm::mat3& m) {
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// True when every texel of the texture has R = G = B: a grey image, which under map_Bump or
// bump is a height map (a tangent-space normal map has B near 1 and R, G varying).
bool grey_image(const Texture& t) {
    if (t.width <= 0 || t.height <= 0) return false;
    const std::size_t n = std::size_t(t.width) * std::size_t(t.height);
    if (t.is_float()) {
        if (t.texelsf.size() < 4 * n) return false;
        for (std::size_t i = 0; i < n; ++i)
            if (t.texelsf[4 * i] != t.texelsf[4 * i + 1] || t.texelsf[4 * i] != t.texelsf[4 * i + 2])
                return false;
        return true;
    }
    if (t.texels8.size() < 4 * n) return false;
    for (std::size_t i = 0; i < n; ++i)
        if (t.texels8[4 * i] != t.texels8[4 * i + 1] || t.texels8[4 * i] != t.texels8[4 * i + 2])
            return false;
    return true;
}

// Coverage (A, or channel `c`) below `cutoff` somewhere in the image.
bool cuts_out(const Texture& t, int c, float cutoff) {
    const std::size_t n = std::size_t(std::max(t.width, 0)) * std::size_t(std::max(t.height, 0));
    if (t.is_float()) {
        for (std::size_t i = 0; i < n && 4 * i + 3 < t.texelsf.size(); ++i)
            if (!(t.texelsf[4 * i + c] >= cutoff)) return true;
        return false;
    }
    for (std::size_t i = 0; i < n && 4 * i + 3 < t.texels8.size(); ++i)
        if (!(float(t.texels8[4 * i + c]) / 255.0f >= cutoff)) return true;
    return false;
}

// An alpha channel that is 1 everywhere (an image without one reads as opaque).
bool opaque_alpha(const Texture& t) { return !cuts_out(t, 3, 1.0f); }

// Loads the texture maps an MTL material names (see obj_loader.h): paths relative to the
// folder of the MTL library the material comes from.
struct MtlTextures {
    Scene& scene;
    std::filesystem::path obj_dir;
    std::string file;

    // The texture `name` of material `mat` for `slot` ("map_Kd", ...), its uv transform from
    // the options; nullopt (with a warning) when the path is something other than a file.
    std::optional<TextureRef> load(const tinyobj::material_t& mat, const MtlInfo& info,
                                   std::string name, const tinyobj::texture_option_t& opt,
                                   TextureUse use, const char* slot) {
        namespace fs = std::filesystem;
        while (!name.empty() && is_space(name.back())) name.pop_back();
        while (!name.empty() && is_space(name.front())) name.erase(name.begin());
        if (name.empty()) return std::nullopt;
        std::replace(name.begin(), name.end(), '\\', '/');  // paths written on Windows
        const fs::path path = obj_dir / fs::path(info.library).parent_path() / fs::path(name);
        std::error_code ec;
        const fs::file_status st = fs::status(path, ec);
        if (fs::exists(st) && !fs::is_regular_file(st)) {
            scene.warnings.push_back(fmt::format(
                "{}: material '{}': {} '{}' is not a regular file; ignored", file, mat.name, slot,
                path.string()));
            return std::nullopt;
        }
        TextureRef r;
        r.image = add_texture_file(scene, path, use);
        r.uv_transform = mtl_uv_transform(opt);
        if (!finite_matrix(r.uv_transform)) {
            scene.warnings.push_back(fmt::format(
                "{}: material '{}': {} has a non-finite -o or -s option; ignored", file, mat.name,
                slot));
            r.uv_transform = glm::mat3(1.0f);
        }
        if (opt.clamp)
            scene.warnings.push_back(fmt::format(
                "{}: material '{}': {} -clamp on is not supported; the map repeats", file,
                mat.name, slot));
        if (opt.brightness != 0.0f || opt.contrast != 1.0f)
            scene.warnings.push_back(fmt::format(
                "{}: material '{}': {} -mm (base, gain) is not supported; ignored", file,
                mat.name, slot));
        return r;
    }

    // map_d's coverage in A: the image's alpha channel, or its first channel (R) when the
    // alpha is 1 everywhere (a grey or RGB image): then R is copied into A in place (no
    // other OBJ slot reads A, so a texture shared with map_Kd is unchanged for it).
    void coverage_in_alpha(int image) {
        Texture& t = scene.textures[std::size_t(image)];
        if (!opaque_alpha(t)) return;
        const std::size_t n = std::size_t(t.width) * std::size_t(t.height);
        for (std::size_t i = 0; i < n && 4 * i + 3 < t.texels8.size(); ++i)
            t.texels8[4 * i + 3] = t.texels8[4 * i];
        for (std::size_t i = 0; i < n && 4 * i + 3 < t.texelsf.size(); ++i)
            t.texelsf[4 * i + 3] = t.texelsf[4 * i];
    }

    // Forgets a texture that the last load() added but no slot uses after all.
    void drop_if_added(const TextureRef& r, std::size_t count_before) {
        if (scene.textures.size() == count_before + 1 && r.image == int(count_before))
            scene.textures.pop_back();
    }
};

// One MTL material to a wavepath material, by the table in obj_loader.h.
Material convert_material(const tinyobj::material_t& mt, const MtlInfo& info, MtlTextures& tex,
                          const std::string& file, std::vector<std::string>& warnings) {
    Material m;
    m.name = mt.name;
    // A map without its constant (map_Kd without Kd, map_Ke without Ke) is the map alone
    tinyobj::real_t diffuse[3] = {mt.diffuse[0], mt.diffuse[1], mt.diffuse[2]};
    tinyobj::real_t emission[3] = {mt.emission[0], mt.emission[1], mt.emission[2]};
    if (!mt.diffuse_texname.empty() && !info.has_kd) diffuse[0] = diffuse[1] = diffuse[2] = 1;
    if (!mt.emissive_texname.empty() && !info.has_ke) emission[0] = emission[1] = emission[2] = 1;
    const bool kd_zero = max3(diffuse) <= 0.001f;
    const bool ks_some = max3(mt.specular) > 0.0f;
    const bool ks_perfect = min3(mt.specular) >= 0.999f;
    const bool reflect = mt.illum == 3 || mt.illum == 5;
    const float ns = float(mt.shininess);
    auto clamped = [&](const char* what, glm::vec3 c) {
        glm::vec3 r = glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f));
        if (r != c)
            warnings.push_back(fmt::format("{}: material '{}': {} ({}, {}, {}) clamped to [0, 1]",
                                           file, mt.name, what, c.x, c.y, c.z));
        return r;
    };
    auto ignored = [&](const std::string& texname, const char* slot, const char* why) {
        if (!texname.empty())
            warnings.push_back(fmt::format("{}: material '{}': {} '{}' ignored ({})", file,
                                           mt.name, slot, texname, why));
    };

    // Kind and albedo: glass, mirror, glossy, else diffuse
    const bool glass = mt.illum == 4 || mt.illum == 6 || mt.illum == 7;
    if (glass) {
        m.kind = MaterialKind::Glass;
        glm::vec3 tf = vec3(mt.transmittance);
        m.albedo = max3(mt.transmittance) > 0.0f ? clamped("Tf", tf) : glm::vec3(1.0f);
        const float ior = float(mt.ior);
        const bool usable = ior >= limits::kMinIor && ior <= limits::kMaxIor &&
                            ior != 1.0f;  // (NaN: false)
        m.ior = usable ? ior : 1.5f;
        if (!usable)
            warnings.push_back(fmt::format("{}: material '{}': glass without a usable Ni ({}); "
                                           "using 1.5", file, mt.name, ior));
        ignored(mt.diffuse_texname, "map_Kd", "glass has no diffuse colour");
        ignored(mt.specular_texname, "map_Ks", "glass is tinted by Tf only");
    } else if (reflect && kd_zero && ks_some && (ns >= 1000.0f || ks_perfect)) {
        m.kind = MaterialKind::Mirror;
        m.albedo = clamped("Ks", vec3(mt.specular));
    } else if ((mt.illum == 2 || reflect) && kd_zero && ks_some && std::isfinite(ns)) {
        m.kind = MaterialKind::Glossy;
        m.albedo = clamped("Ks", vec3(mt.specular));
        m.alpha = phong_exponent_to_alpha(std::max(0.0f, ns));
    } else {
        m.kind = MaterialKind::Diffuse;
        m.albedo = clamped("Kd", vec3(diffuse));
        if (reflect && ks_some && !kd_zero)
            warnings.push_back(fmt::format(
                "{}: material '{}': has both Kd and Ks with illum {}; wavepath has no layered "
                "material, so it is diffuse (Ks ignored)",
                file, mt.name, mt.illum));
        ignored(mt.specular_texname, "map_Ks", "the material is diffuse");
    }

    // Emission: Ke, one-sided radiance
    glm::vec3 e = vec3(emission);
    m.emission = glm::max(e, glm::vec3(0.0f));
    if (m.emission != e)
        warnings.push_back(fmt::format("{}: material '{}': negative Ke ({}, {}, {}) set to 0", file,
                                       mt.name, e.x, e.y, e.z));

    // Texture maps (paths relative to the MTL file)
    if (m.kind == MaterialKind::Diffuse) {
        if (auto r = tex.load(mt, info, mt.diffuse_texname, mt.diffuse_texopt, TextureUse::Colour,
                              "map_Kd"))
            m.albedo_map = *r;
    } else if (m.kind == MaterialKind::Glossy || m.kind == MaterialKind::Mirror) {
        if (auto r = tex.load(mt, info, mt.specular_texname, mt.specular_texopt,
                              TextureUse::Colour, "map_Ks"))
            m.albedo_map = *r;
    }
    if (!mt.emissive_texname.empty() && !m.emissive())
        ignored(mt.emissive_texname, "map_Ke", "Ke is 0");
    else if (auto r = tex.load(mt, info, mt.emissive_texname, mt.emissive_texopt,
                               TextureUse::Colour, "map_Ke"))
        m.emission_map = *r;
    // Normal map: `norm`, else map_Bump / bump unless the image is grey (a height map)
    const bool norm = !mt.normal_texname.empty();
    const tinyobj::texture_option_t& nopt = norm ? mt.normal_texopt : mt.bump_texopt;
    std::size_t before = tex.scene.textures.size();
    if (auto r = tex.load(mt, info, norm ? mt.normal_texname : mt.bump_texname, nopt,
                          TextureUse::Data, norm ? "norm" : "map_Bump")) {
        if (!norm && grey_image(tex.scene.textures[std::size_t(r->image)])) {
            warnings.push_back(fmt::format(
                "{}: material '{}': map_Bump '{}' is a grey image, a height (bump) map; only "
                "normal maps are supported, so it is ignored",
                file, mt.name, mt.bump_texname));
            tex.drop_if_added(*r, before);
        } else {
            m.normal_map = *r;
            const float bm = float(nopt.bump_multiplier);
            m.normal_scale = std::isfinite(bm) ? bm : 1.0f;
        }
    }
    if (norm) ignored(mt.bump_texname, "map_Bump", "norm is given");
    // Cut-out: map_d's coverage (A, or the first channel without alpha) below 0.5
    before = tex.scene.textures.size();
    if (auto r = tex.load(mt, info, mt.alpha_texname, mt.alpha_texopt, TextureUse::Data, "map_d")) {
        tex.coverage_in_alpha(r->image);
        if (cuts_out(tex.scene.textures[std::size_t(r->image)], 3, m.alpha_cutoff))
            m.alpha_map = *r;
        else
            tex.drop_if_added(*r, before);  // nothing is cut out: no alpha test needed
    }

    // What is not modelled
    if (mt.illum == 9)
        warnings.push_back(fmt::format(
            "{}: material '{}': illum {} (transparency/refraction) is not supported; rendered as "
            "{}",
            file, mt.name, mt.illum, to_string(m.kind)));
    ignored(mt.ambient_texname, "map_Ka", "not supported");
    ignored(mt.specular_highlight_texname, "map_Ns", "not supported");
    ignored(mt.displacement_texname, "disp", "not supported");
    ignored(mt.reflection_texname, "refl", "not supported");
    ignored(mt.roughness_texname, "map_Pr", "not supported");
    ignored(mt.metallic_texname, "map_Pm", "not supported");
    ignored(mt.sheen_texname, "map_Ps", "not supported");
    return m;
}

// tinyobjloader's multi-line messages as prefixed warning lines.
void add_lines(std::vector<std::string>& out, const std::string& file, const std::string& text) {
    std::size_t i = 0;
    while (i < text.size()) {
        std::size_t j = text.find('\n', i);
        if (j == std::string::npos) j = text.size();
        std::string_view l(text.data() + i, j - i);
        while (!l.empty() && is_space(l.back()))
            l.remove_suffix(1);
        if (!l.empty()) out.push_back(fmt::format("{}: {}", file, l));
        i = j + 1;
    }
}

// Polygons with more corners than this that are not convex are split as fans (ear clipping
// costs up to n^3 here; real files rarely have large concave faces).
constexpr std::size_t kMaxEarClipCorners = 128;

// Splits one polygon (vertex indices in file order) into triangles that keep its winding.
// Convex polygons become fans; others are ear-clipped (Meisters 1975) in the projection
// onto the plane of their Newell normal's largest axis, with an ear's triangle checked to
// hold no other corner. Returns false when it had to fall back to a fan that is not exact
// (a self-intersecting polygon, or one over kMaxEarClipCorners corners).
// tinyobjloader's own triangulation is not used: it splits concave quads along the
// shorter diagonal and its ear clipping depends on the starting corner, both of which
// give flipped triangles outside the polygon.
bool triangulate_polygon(const std::vector<glm::vec3>& pos, const std::vector<std::uint32_t>& poly,
                         std::vector<glm::uvec3>& out) {
    const std::size_t n = poly.size();
    auto fan = [&](const std::vector<std::uint32_t>& p) {
        for (std::size_t k = 1; k + 1 < p.size(); ++k)
            out.emplace_back(p[0], p[k], p[k + 1]);
    };
    if (n == 3) {
        out.emplace_back(poly[0], poly[1], poly[2]);
        return true;
    }

    // Newell normal (double: products of float coordinates cannot overflow)
    glm::dvec3 normal(0.0);
    for (std::size_t k = 0; k < n; ++k) {
        const glm::dvec3 a(pos[poly[k]]), b(pos[poly[(k + 1) % n]]);
        normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x),
                             (a.x - b.x) * (a.y + b.y));
    }
    const glm::dvec3 mag = glm::abs(normal);
    if (!(mag.x + mag.y + mag.z > 0.0) || !std::isfinite(mag.x + mag.y + mag.z)) {
        fan(poly); // no area: any split is as good
        return true;
    }

    // 2D coordinates with the polygon counter-clockwise (positive area)
    const int axis = mag.x >= mag.y && mag.x >= mag.z ? 0 : (mag.y >= mag.z ? 1 : 2);
    const int iu = (axis + 1) % 3, iv = (axis + 2) % 3;
    const double flip = normal[axis] < 0.0 ? -1.0 : 1.0;
    std::vector<glm::dvec2> p2(n);
    for (std::size_t k = 0; k < n; ++k)
        p2[k] = glm::dvec2(flip * double(pos[poly[k]][iu]), double(pos[poly[k]][iv]));
    auto cross = [&](std::size_t a, std::size_t b, std::size_t c) {
        const glm::dvec2 e0 = p2[b] - p2[a], e1 = p2[c] - p2[b];
        return e0.x * e1.y - e0.y * e1.x;
    };

    // Convex (no corner turns clockwise): a fan is exact
    bool convex = true;
    for (std::size_t k = 0; k < n && convex; ++k)
        convex = cross(k, (k + 1) % n, (k + 2) % n) >= 0.0;
    if (convex) {
        fan(poly);
        return true;
    }
    if (n > kMaxEarClipCorners) {
        fan(poly);
        return false;
    }

    // Ear clipping over the remaining corners (local indices into poly / p2)
    std::vector<std::uint32_t> rem(n);
    for (std::size_t k = 0; k < n; ++k)
        rem[k] = std::uint32_t(k);
    auto inside = [&](std::size_t q, std::size_t a, std::size_t b, std::size_t c) {
        if (p2[q] == p2[a] || p2[q] == p2[b] || p2[q] == p2[c]) return false;
        return cross(a, b, q) >= 0.0 && cross(b, c, q) >= 0.0 && cross(c, a, q) >= 0.0;
    };
    std::size_t i = 0, stalled = 0;
    while (rem.size() > 3) {
        const std::size_t r = rem.size();
        const std::size_t a = rem[(i + r - 1) % r], b = rem[i], c = rem[(i + 1) % r];
        bool ear = cross(a, b, c) > 0.0;
        for (std::size_t k = 0; ear && k < r; ++k)
            if (rem[k] != a && rem[k] != b && rem[k] != c && inside(rem[k], a, b, c)) ear = false;
        if (ear) {
            out.emplace_back(poly[a], poly[b], poly[c]);
            rem.erase(rem.begin() + std::ptrdiff_t(i));
            if (i >= rem.size()) i = 0;
            stalled = 0;
        } else if (++stalled > r) {
            // No ear left: self-intersecting (or numerically degenerate); fan the rest
            std::vector<std::uint32_t> rest;
            for (auto k : rem)
                rest.push_back(poly[k]);
            bool exact = true; // a fan of collinear leftovers is still right
            for (std::size_t k = 1; k + 1 < rem.size(); ++k)
                exact = exact && cross(rem[0], rem[k], rem[k + 1]) >= 0.0 &&
                        cross(rem[k], rem[k + 1], rem[0]) >= 0.0;
            fan(rest);
            return exact;
        } else {
            i = (i + 1) % r;
        }
    }
    out.emplace_back(poly[rem[0]], poly[rem[1]], poly[rem[2]]);
    return true;
}

} // namespace

Scene load_obj(const std::filesystem::path& path) {
    return parse_obj(read_file(path, kMaxObjBytes), path);
}

Scene parse_obj(std::string_view input, const std::filesystem::path& origin) {
    return parse_obj(input, origin, mtl_files_beside(origin));
}

Scene parse_obj(std::string_view input, const std::filesystem::path& origin,
                const MtlSource& mtl_source) {
    const std::string file = origin.string();
    if (input.size() > kMaxObjBytes)
        fail("{}: the text is {} bytes; OBJ files over {} GiB are refused", file, input.size(),
             kMaxObjBytes >> 30);

    // Raw-text checks that tinyobjloader does not make (indices, NaN, line numbers)
    std::size_t faces = 0;
    std::istringstream text(checked_obj_text(input, file, faces));
    if (faces == 0) fail("{}: no triangles (the file has no faces)", file);

    // Parse (polygons are triangulated below); .mtl libraries come from mtl_source
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> mtls;
    std::string warn, err;
    std::vector<MtlInfo> mtl_info;
    MtlReader mtl_reader(mtl_source, mtl_info);
    if (!tinyobj::LoadObj(&attrib, &shapes, &mtls, &warn, &err, &text, &mtl_reader,
                          /*triangulate=*/false, /*default_vcols_fallback=*/false)) {
        while (!err.empty() && (is_space(err.back()) || err.back() == '\n'))
            err.pop_back();
        fail("{}: {}", file, err.empty() ? "tinyobjloader could not parse the file" : err);
    }
    Scene scene;
    scene.name = origin.filename().string();
    add_lines(scene.warnings, file, warn);
    add_lines(scene.warnings, file, err); // non-fatal messages (e.g. from the .mtl)

    // Attributes: `vt` (stored as (u, 1 - v)) and `vn`; a corner's index outside the file's
    // vt / vn lines is ignored (that corner has none), with one warning.
    const std::size_t nv = attrib.vertices.size() / 3;
    const std::size_t nvt = attrib.texcoords.size() / 2, nvn = attrib.normals.size() / 3;
    std::size_t bad_refs = 0;
    bool has_uv = false, has_normal = false;
    for (auto& shape : shapes)
        for (auto& idx : shape.mesh.indices) {
            if (idx.texcoord_index != -1 &&
                (idx.texcoord_index < 0 || std::size_t(idx.texcoord_index) >= nvt)) {
                idx.texcoord_index = -1;
                ++bad_refs;
            }
            if (idx.normal_index != -1 &&
                (idx.normal_index < 0 || std::size_t(idx.normal_index) >= nvn)) {
                idx.normal_index = -1;
                ++bad_refs;
            }
            has_uv = has_uv || idx.texcoord_index >= 0;
            has_normal = has_normal || idx.normal_index >= 0;
        }
    if (bad_refs > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} face corner(s) name a texture coordinate or normal that the file does not "
            "have; those corners have none",
            file, bad_refs));
    std::size_t non_finite = 0;
    auto uv_of = [&](int i) {
        glm::vec2 t(float(attrib.texcoords[2 * std::size_t(i)]),
                    1.0f - float(attrib.texcoords[2 * std::size_t(i) + 1]));
        if (std::isfinite(t.x) && std::isfinite(t.y)) return t;
        ++non_finite;
        return glm::vec2(0.0f);
    };
    auto normal_of = [&](int i) {
        const tinyobj::real_t* c = &attrib.normals[3 * std::size_t(i)];
        const glm::vec3 v{float(c[0]), float(c[1]), float(c[2])};
        if (std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) return v;
        ++non_finite;
        return glm::vec3(0.0f);
    };
    auto position_of = [&](std::size_t i) {
        return glm::vec3(float(attrib.vertices[3 * i]), float(attrib.vertices[3 * i + 1]),
                         float(attrib.vertices[3 * i + 2]));
    };

    // Vertices: without attributes, the file's in file order (vertex i = `v` line i + 1);
    // with them, one per distinct (v, vt, vn) triple, in order of first use, so every corner
    // keeps its exact uv and normal.
    const bool attributes = has_uv || has_normal;
    struct TripleHash {
        std::size_t operator()(const glm::ivec3& k) const {
            std::uint64_t h = std::uint32_t(k.x);
            h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(k.y);
            h = h * 0x9E3779B97F4A7C15ull ^ std::uint32_t(k.z);
            return std::size_t(h ^ (h >> 29));
        }
    };
    std::unordered_map<glm::ivec3, std::uint32_t, TripleHash> vertex_of_triple;
    if (!attributes) {
        scene.positions.reserve(nv);
        for (std::size_t i = 0; i < nv; ++i) scene.positions.push_back(position_of(i));
    }
    auto vertex = [&](const tinyobj::index_t& idx) -> std::uint32_t {
        if (!attributes) return std::uint32_t(idx.vertex_index);
        const glm::ivec3 key(idx.vertex_index, idx.texcoord_index, idx.normal_index);
        auto [it, added] =
            vertex_of_triple.emplace(key, std::uint32_t(scene.positions.size()));
        if (added) {
            scene.positions.push_back(position_of(std::size_t(idx.vertex_index)));
            if (has_uv)
                scene.uvs.push_back(idx.texcoord_index >= 0 ? uv_of(idx.texcoord_index)
                                                            : glm::vec2(0.0f));
            if (has_normal)
                scene.normals.push_back(idx.normal_index >= 0 ? normal_of(idx.normal_index)
                                                              : glm::vec3(0.0f));
        }
        return it->second;
    };

    // Triangles, with materials converted on first use
    MtlTextures textures{scene, origin.parent_path(), file};
    std::vector<std::uint32_t> used(mtls.size(), ~0u);
    std::uint32_t default_id = ~0u;
    std::size_t without_material = 0;
    std::size_t inexact = 0;
    std::vector<std::uint32_t> poly;
    for (const auto& shape : shapes) {
        const auto& mesh = shape.mesh;
        std::size_t offset = 0;
        for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
            const std::size_t n = mesh.num_face_vertices[f];
            if (n < 3 || offset + n > mesh.indices.size())
                fail("{}: shape '{}': face {} has {} vertices", file, shape.name, f, n);
            poly.clear();
            for (std::size_t k = 0; k < n; ++k) {
                int vi = mesh.indices[offset + k].vertex_index;
                if (vi < 0 || std::size_t(vi) >= nv)
                    fail("{}: shape '{}': face {} uses vertex index {} of {}", file, shape.name, f,
                         vi + 1, nv);
                poly.push_back(vertex(mesh.indices[offset + k]));
            }
            offset += n;

            // Material: the file's, or the default one
            int mi = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
            std::uint32_t id;
            if (mi >= 0 && std::size_t(mi) < mtls.size()) {
                if (used[mi] == ~0u) {
                    const MtlInfo info =
                        std::size_t(mi) < mtl_info.size() ? mtl_info[mi] : MtlInfo{};
                    used[mi] = scene.add_material(
                        convert_material(mtls[mi], info, textures, file, scene.warnings));
                }
                id = used[mi];
            } else {
                if (default_id == ~0u) {
                    Material d;
                    d.name = "default";
                    d.kind = MaterialKind::Diffuse;
                    d.albedo = glm::vec3(0.5f);
                    default_id = scene.add_material(d);
                }
                id = default_id;
                without_material += n - 2;
            }
            if (!triangulate_polygon(scene.positions, poly, scene.triangles)) ++inexact;
            scene.material_ids.resize(scene.triangles.size(), id);
        }
    }
    if (non_finite > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} texture coordinate(s) or normal(s) are not finite; replaced by (0, 0) / no "
            "normal",
            file, non_finite));
    if (inexact > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} polygon(s) are self-intersecting or have more than {} corners without being "
            "convex; they were split as fans, which may cover more than the polygon",
            file, inexact, kMaxEarClipCorners));
    if (scene.triangles.empty()) fail("{}: no triangles (every face was dropped)", file);
    if (without_material > 0)
        scene.warnings.push_back(fmt::format(
            "{}: {} of {} triangles have no material; they use the mid-grey diffuse 'default'",
            file, without_material, scene.triangles.size()));

    // Camera framing the geometry; black background
    scene.camera = frame_bounds(scene.bounds(), file);
    scene.background = glm::vec3(0.0f);
    validate_scene(scene);
    return scene;
}

} // namespace wp
