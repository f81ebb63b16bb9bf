#include "scene/json_scene.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <system_error>
#include <unordered_set>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "scene/load.h"
#include "scene/metals.h"
#include "scene/normals.h"
#include "scene/procedural.h"
#include "scene/shape_uv.h"
#include "scene/texture.h"
#include "scene/validate.h"
#include "util/error.h"
#include "util/limits.h"
#include "util/read_file.h"

namespace wp {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// Film, spp and depth ranges: util/limits.h, the same as the command line's.
constexpr int kMaxFilmSide = limits::kMaxImageSide;
constexpr long long kMaxFilmPixels = limits::kMaxPixels;
constexpr long long kMaxSpp = limits::kMaxSpp;
constexpr long long kMaxDepth = limits::kMaxDepth;

// ---------------------------------------------------------------------------------------
// JSON paths (RFC 6901 pointers) for messages
// ---------------------------------------------------------------------------------------

struct Seg {
    std::string key;  // object member, when !is_index
    std::size_t index = 0;
    bool is_index = false;
};

struct Path {
    std::vector<Seg> segs;
    Path key(std::string_view k) const {
        Path p = *this;
        p.segs.push_back({std::string(k), 0, false});
        return p;
    }
    Path index(std::size_t i) const {
        Path p = *this;
        p.segs.push_back({{}, i, true});
        return p;
    }
};

// Bytes that would garble a one-line message (control characters, quotes) as escapes;
// long texts are cut.
std::string printable(std::string_view s, std::size_t max = 60) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (out.size() >= max) {
            out += "...";
            break;
        }
        unsigned char c = static_cast<unsigned char>(s[i]);
        if (c < 0x20 || c == 0x7f)
            out += fmt::format("\\x{:02x}", c);
        else
            out.push_back(char(c));
    }
    return out;
}

std::string pointer(const Path& p) {
    if (p.segs.empty()) return "/";
    std::string out;
    for (const Seg& s : p.segs) {
        out.push_back('/');
        if (s.is_index) {
            out += std::to_string(s.index);
            continue;
        }
        for (char c : printable(s.key)) {
            if (c == '~')
                out += "~0";
            else if (c == '/')
                out += "~1";
            else
                out.push_back(c);
        }
    }
    return out;
}

// ---------------------------------------------------------------------------------------
// The raw text: positions of values and keys (nlohmann::json keeps none), duplicate keys.
// Every function here runs on text that nlohmann has accepted as JSON, and loops rather
// than recurses, so nesting depth costs nothing.
// ---------------------------------------------------------------------------------------

class Text {
public:
    explicit Text(std::string_view s) : s_(s) {
        if (s_.substr(0, 3) == "\xEF\xBB\xBF") begin_ = 3;  // UTF-8 byte order mark
    }

    std::size_t size() const { return s_.size(); }
    std::string_view str() const { return s_; }

    // 1-based line and column (in code points) of a byte offset.
    std::pair<std::size_t, std::size_t> line_col(std::size_t off) const {
        off = std::min(off, s_.size());
        std::size_t line = 1, col = 1;
        for (std::size_t i = 0; i < off; ++i) {
            unsigned char c = static_cast<unsigned char>(s_[i]);
            if (c == '\n') {
                ++line;
                col = 1;
            } else if ((c & 0xC0) != 0x80) {
                ++col;
            }
        }
        return {line, col};
    }

    // Offset of the value at p (of its key instead, when at_key and p ends in a key).
    std::optional<std::size_t> locate(const Path& p, bool at_key = false) const {
        std::size_t i = ws(begin_);
        for (std::size_t k = 0; k < p.segs.size(); ++k) {
            const Seg& seg = p.segs[k];
            if (i >= s_.size()) return std::nullopt;
            if (seg.is_index) {
                if (s_[i] != '[') return std::nullopt;
                i = ws(i + 1);
                for (std::size_t j = 0;; ++j) {
                    if (i >= s_.size() || s_[i] == ']') return std::nullopt;
                    if (j == seg.index) break;
                    i = ws(value_end(i));
                    if (i < s_.size() && s_[i] == ',') i = ws(i + 1);
                }
            } else {
                if (s_[i] != '{') return std::nullopt;
                i = ws(i + 1);
                bool found = false;
                while (i < s_.size() && s_[i] == '"') {
                    const std::size_t a = i, b = string_end(i);
                    const bool match = decode(a, b) == seg.key;
                    i = ws(b);
                    if (i < s_.size() && s_[i] == ':') i = ws(i + 1);
                    if (match) {
                        if (at_key && k + 1 == p.segs.size()) return a;
                        found = true;
                        break;
                    }
                    i = ws(value_end(i));
                    if (i < s_.size() && s_[i] == ',') i = ws(i + 1);
                }
                if (!found) return std::nullopt;
            }
        }
        return i;
    }

    // The keys of the object at p, in the order of the text.
    std::vector<std::string> keys(const Path& p) const {
        std::vector<std::string> out;
        auto at = locate(p);
        if (!at || *at >= s_.size() || s_[*at] != '{') return out;
        std::size_t i = ws(*at + 1);
        while (i < s_.size() && s_[i] == '"') {
            const std::size_t b = string_end(i);
            out.push_back(decode(i, b));
            i = ws(b);
            if (i < s_.size() && s_[i] == ':') i = ws(i + 1);
            i = ws(value_end(i));
            if (i < s_.size() && s_[i] == ',') i = ws(i + 1);
        }
        return out;
    }

    // The first key that appears twice in one object: its path and offset.
    std::optional<std::pair<Path, std::size_t>> duplicate_key() const {
        struct Frame {
            bool object;
            std::unordered_set<std::string> keys;
            Seg seg;  // the member or element being read
        };
        std::vector<Frame> st;
        auto path_of = [&](const std::string& key) {
            Path p;
            for (const Frame& f : st) p.segs.push_back(f.seg);
            p.segs.back() = Seg{key, 0, false};
            return p;
        };
        enum class State { Value, Key, After } state = State::Value;
        std::size_t i = ws(begin_);
        while (i < s_.size()) {
            if (state == State::Value) {
                const char c = s_[i];
                if (c == '{' || c == '[') {
                    st.push_back({c == '{', {}, {{}, 0, c == '['}});
                    i = ws(i + 1);
                    if (i < s_.size() && (s_[i] == '}' || s_[i] == ']')) {
                        ++i;
                        st.pop_back();
                        state = State::After;
                    } else {
                        state = c == '{' ? State::Key : State::Value;
                    }
                } else {
                    i = value_end(i);
                    state = State::After;
                }
            } else if (state == State::Key) {
                const std::size_t a = i, b = string_end(i);
                std::string key = decode(a, b);
                if (!st.back().keys.insert(key).second) return std::pair{path_of(key), a};
                st.back().seg = Seg{std::move(key), 0, false};
                i = ws(b);
                if (i < s_.size() && s_[i] == ':') i = ws(i + 1);
                state = State::Value;
            } else {
                if (st.empty()) break;
                i = ws(i);
                if (i >= s_.size()) break;
                if (s_[i] == ',') {
                    i = ws(i + 1);
                    if (st.back().object) {
                        state = State::Key;
                    } else {
                        ++st.back().seg.index;
                        state = State::Value;
                    }
                } else {  // '}' or ']'
                    ++i;
                    st.pop_back();
                }
            }
        }
        return std::nullopt;
    }

private:
    std::size_t ws(std::size_t i) const {
        while (i < s_.size() && (s_[i] == ' ' || s_[i] == '\t' || s_[i] == '\n' || s_[i] == '\r'))
            ++i;
        return i;
    }
    // i at an opening quote; returns the offset past the closing one.
    std::size_t string_end(std::size_t i) const {
        for (++i; i < s_.size(); ++i) {
            if (s_[i] == '\\')
                ++i;
            else if (s_[i] == '"')
                return i + 1;
        }
        return s_.size();
    }
    std::size_t value_end(std::size_t i) const {
        if (i >= s_.size()) return i;
        const char c = s_[i];
        if (c == '"') return string_end(i);
        if (c == '{' || c == '[') {
            std::size_t depth = 0;
            while (i < s_.size()) {
                const char d = s_[i];
                if (d == '"') {
                    i = string_end(i);
                    continue;
                }
                if (d == '{' || d == '[') ++depth;
                if (d == '}' || d == ']') {
                    if (--depth == 0) return i + 1;
                }
                ++i;
            }
            return i;
        }
        while (i < s_.size() && std::string_view(",}] \t\r\n").find(s_[i]) == std::string_view::npos)
            ++i;
        return i;
    }
    // The key of the string token [a, b).
    std::string decode(std::size_t a, std::size_t b) const {
        std::string_view tok = s_.substr(a, b - a);
        if (tok.size() >= 2 && tok.find('\\') == std::string_view::npos)
            return std::string(tok.substr(1, tok.size() - 2));
        try {
            return Json::parse(tok).get<std::string>();
        } catch (const std::exception&) {
            return {};
        }
    }

    std::string_view s_;
    std::size_t begin_ = 0;
};

// ---------------------------------------------------------------------------------------
// "Did you mean": common synonyms, then the closest known key by edit distance
// ---------------------------------------------------------------------------------------

// Optimal string alignment distance (Levenshtein plus adjacent transpositions), case-blind.
std::size_t edit_distance(std::string_view a, std::string_view b) {
    if (a.size() > 64 || b.size() > 64) return 1000;
    auto low = [](char c) { return char(std::tolower(static_cast<unsigned char>(c))); };
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = low(a[i - 1]) == low(b[j - 1]) ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && low(a[i - 1]) == low(b[j - 2]) && low(a[i - 2]) == low(b[j - 1]))
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[a.size()][b.size()];
}

// A known word close to `word`, or "".
std::string suggest(std::string_view word, std::span<const std::string_view> known) {
    static const std::map<std::string_view, std::string_view> synonyms{
        {"albedo", "reflectance"}, {"color", "reflectance"},  {"colour", "reflectance"},
        {"kd", "reflectance"},     {"diffuse", "reflectance"}, {"radiance", "emission"},
        {"emissive", "emission"},  {"emit", "emission"},       {"le", "emission"},
        {"alpha", "roughness"},    {"eta", "ior"},             {"target", "look_at"},
        {"lookat", "look_at"},     {"look", "look_at"},        {"center", "look_at"},
        {"eye", "position"},       {"origin", "position"},     {"from", "position"},
        {"to", "look_at"},         {"filename", "file"},       {"path", "file"},
        {"samples", "spp"},        {"max_depth", "depth"},     {"bounces", "depth"},
        {"kind", "type"},          {"fovy", "fov"},            {"to_world", "transform"},
        {"shininess", "exponent"}, {"ns", "exponent"},         {"objects", "shapes"},
        {"meshes", "shapes"},      {"lights", "shapes"},       {"integrator", "render"},
        {"translation", "translate"}, {"rotation", "rotate"},  {"angle", "degrees"},
        {"subdivision", "subdivisions"}, {"divisions", "subdivisions"}, {"res", "width"},
        {"env", "environment"},    {"envmap", "environment"},  {"sky", "environment"},
        {"texture", "albedo_texture"}, {"map_kd", "albedo_texture"},
        {"normalmap", "normal_map"},   {"bump", "normal_map"}, {"opacity", "alpha_texture"},
        {"mask", "alpha_texture"},     {"cutoff", "alpha_cutoff"}, {"smoothing", "smooth"},
        {"crease", "smooth"},          {"filter_type", "filter"},
        {"alpha_u", "roughness_u"},    {"alpha_v", "roughness_v"}, {"uroughness", "roughness_u"},
        {"vroughness", "roughness_v"}, {"specular_reflectance", "specular"},
        {"specular_transmittance", "transmittance"}, {"int_ior", "ior"}, {"material", "metal"},
        {"ks", "specular"},            {"distrib", "distribution"}, {"specular", "reflectance"},
    };
    auto is_known = [&](std::string_view k) {
        return std::find(known.begin(), known.end(), k) != known.end();
    };
    std::string lower(word.substr(0, 64));
    for (auto& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (auto it = synonyms.find(lower); it != synonyms.end() && is_known(it->second) &&
                                        lower != it->second)
        return std::string(it->second);
    std::string_view best;
    std::size_t best_d = 1000;
    for (std::string_view k : known) {
        std::size_t d = edit_distance(word, k);
        if (d < best_d) {
            best_d = d;
            best = k;
        }
    }
    const std::size_t allowed = word.size() <= 4 ? 1 : 2;
    if (best_d <= allowed && best_d < word.size()) return std::string(best);
    return {};
}

std::string join(std::span<const std::string_view> words) {
    std::string out;
    for (std::string_view w : words) {
        if (!out.empty()) out += ", ";
        out += w;
    }
    return out;
}

// What a JSON value is, for "expected X, got Y".
std::string describe(const Json& v) {
    switch (v.type()) {
    case Json::value_t::null: return "null";
    case Json::value_t::boolean: return v.get<bool>() ? "true" : "false";
    case Json::value_t::string: return fmt::format("the string \"{}\"", printable(v.get_ref<const std::string&>(), 40));
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return fmt::format("the number {}", printable(v.dump(), 40));
    case Json::value_t::object: return "an object";
    case Json::value_t::array: return fmt::format("an array of {}", v.size());
    default: return "a value of another type";
    }
}

// ---------------------------------------------------------------------------------------
// The reader: typed accessors with path-named errors, then scene assembly
// ---------------------------------------------------------------------------------------

using Keys = std::span<const std::string_view>;

constexpr std::array<std::string_view, 7> kTopKeys{"version", "camera",    "background",
                                                   "render",  "materials", "shapes",
                                                   "environment"};
constexpr std::array<std::string_view, 11> kCameraKeys{
    "position", "look_at", "up",          "matrix",          "fov",           "fov_axis",
    "width",    "height",  "lens_radius", "aperture_radius", "focus_distance"};
constexpr std::array<std::string_view, 3> kRenderKeys{"spp", "depth", "seed"};
// The kinds' names, in the order of kernels/shared/material_kinds.h.
constexpr std::array<std::string_view, kMaterialKindCount> kMaterialTypes{
#define WP_KIND_NAME_(KIND, Kind, name, specular, alpha, ior, etak) #name,
    WP_MATERIAL_KINDS(WP_KIND_NAME_)
#undef WP_KIND_NAME_
};
// Texture references (docs/scene-format.md): a file name or an object of these keys.
constexpr std::array<std::string_view, 6> kTextureKeys{"file",   "checkerboard", "scale",
                                                       "offset", "rotation",     "filter"};
constexpr std::array<std::string_view, 4> kEnvironmentKeys{"file", "scale", "rotation", "rotate_y"};

// The texture slots of a material, by key.
enum class TexSlot { Albedo, Roughness, Emission, Normal, Alpha };
struct TexSlotKey {
    std::string_view key;
    TexSlot slot;
};
constexpr TexSlotKey kTexSlots[] = {{"albedo_texture", TexSlot::Albedo},
                                    {"roughness_texture", TexSlot::Roughness},
                                    {"emission_texture", TexSlot::Emission},
                                    {"normal_map", TexSlot::Normal},
                                    {"alpha_texture", TexSlot::Alpha}};

// A texture reference as read (and checked); it becomes an image of the Scene only when a
// shape uses its material.
struct TexSpec {
    TexSlot slot;
    std::string file;            // relative to the scene file's folder; empty: checkerboard
    glm::vec3 color0{0.0f}, color1{0.0f};  // checkerboard colours
    glm::mat3 uv{1.0f};          // T(offset) · R(rotation) · S(scale), as KHR_texture_transform
    bool nearest = false;
};
constexpr std::array<std::string_view, 5> kShapeTypes{"mesh", "quad", "box", "sphere", "stress"};
constexpr std::array<std::string_view, 4> kTransformKeys{"matrix", "scale", "rotate", "translate"};
constexpr std::array<std::string_view, 2> kRotateKeys{"axis", "degrees"};

// Kinds by what their colours mean (material_kinds.h): plastics (a diffuse base under a
// dielectric coat), dielectrics (the other kinds with an index of refraction).
bool is_plastic(MaterialKind k) { return k == MaterialKind::Plastic || k == MaterialKind::RoughPlastic; }
bool is_dielectric(MaterialKind k) { return uses_ior(k) && !is_plastic(k); }

// The keys a material of kind k takes besides type, reflectance, emission and the texture
// slots (docs/scene-format.md), by the columns of material_kinds.h.
std::vector<std::string_view> material_kind_keys(MaterialKind k) {
    std::vector<std::string_view> keys;
    if (k == MaterialKind::Glossy)
        keys.insert(keys.end(), {"roughness", "exponent", "roughness_texture"});
    else if (uses_alpha(k))
        keys.insert(keys.end(), {"roughness", "roughness_u", "roughness_v", "distribution", "g",
                                 "roughness_texture"});
    if (uses_eta_k(k)) keys.insert(keys.end(), {"eta", "k", "metal"});
    if (is_dielectric(k)) keys.insert(keys.end(), {"ior", "specular", "transmittance"});
    if (is_plastic(k)) keys.insert(keys.end(), {"ior", "specular", "nonlinear"});
    return keys;
}

struct MaterialEntry {
    std::string name;
    Material material;
    std::vector<TexSpec> textures;    // its texture slots, resolved when a shape uses it
    Path path;
    bool used = false;                // some shape names it
    std::optional<std::uint32_t> id;  // scene id, when used
};

constexpr double kNoMax = double(std::numeric_limits<float>::max());

// The decimal number a float limit was written as (1e-4f → 1e-4, not 9.99999974e-05): the
// bound the file's numbers are checked against and the one the message shows; a number that
// passes becomes a float within the limit.
double decimal(float x) {
    const std::string text = fmt::format("{}", x);
    double d = x;
    std::from_chars(text.data(), text.data() + text.size(), d);
    return d;
}

class Reader {
public:
    Reader(std::string_view text, const fs::path& origin)
        : text_(text), file_(origin.empty() ? std::string("(json)") : origin.string()),
          name_(origin.empty() ? std::string("(json)") : origin.filename().string()),
          dir_(origin.parent_path()) {}

    Scene read();

private:
    // --- errors -------------------------------------------------------------------------
    template <typename... Args>
    [[noreturn]] void error(const Path& p, fmt::format_string<Args...> f, Args&&... args) const {
        raise(p, false, fmt::format(f, std::forward<Args>(args)...));
    }
    template <typename... Args>
    [[noreturn]] void error_at_key(const Path& p, fmt::format_string<Args...> f,
                                   Args&&... args) const {
        raise(p, true, fmt::format(f, std::forward<Args>(args)...));
    }
    [[noreturn]] void raise_at(std::size_t off, const Path& p, const std::string& msg) const {
        auto [line, col] = text_.line_col(off);
        throw Error(fmt::format("{}:{}:{}: {}: {}", file_, line, col, pointer(p), msg));
    }
    [[noreturn]] void syntax_error(std::size_t chars_read, const std::string& message,
                                   const std::string& token) const;
    [[noreturn]] void raise(const Path& p, bool at_key, const std::string& msg) const {
        std::optional<std::size_t> off = text_.locate(p, at_key);
        // A key that is missing: point at the object that lacks it
        for (Path q = p; !off && !q.segs.empty();) {
            q.segs.pop_back();
            off = text_.locate(q);
        }
        if (off) raise_at(*off, p, msg);
        throw Error(fmt::format("{}: {}: {}", file_, pointer(p), msg));
    }

    // --- typed accessors ----------------------------------------------------------------
    void expect_object(const Json& v, const Path& p, std::string_view what) const {
        if (!v.is_object()) error(p, "expected {} (a JSON object), got {}", what, describe(v));
    }

    // Every key of v must be in `known`; `what` names the object in the message.
    void check_keys(const Json& v, const Path& p, Keys known, std::string_view what) const {
        for (auto it = v.begin(); it != v.end(); ++it) {
            const std::string& k = it.key();
            if (std::find(known.begin(), known.end(), k) != known.end()) continue;
            std::string hint = suggest(k, known);
            error_at_key(p.key(k), "unknown key '{}' in {}{}; known keys: {}", printable(k), what,
                         hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint),
                         join(known));
        }
    }

    static const Json* find(const Json& obj, std::string_view key) {
        auto it = obj.find(std::string(key));
        return it == obj.end() ? nullptr : &*it;
    }

    double number(const Json& v, const Path& p) const {
        if (!v.is_number()) error(p, "expected a number, got {}", describe(v));
        const double x = v.get<double>();
        if (!std::isfinite(x)) error(p, "the number is not finite");
        return x;
    }

    float real(const Json& v, const Path& p) const {
        const double x = number(v, p);
        if (std::abs(x) > double(std::numeric_limits<float>::max()))
            error(p, "{} is beyond the range of a 32-bit float", x);
        return static_cast<float>(x);
    }

    // A number in [lo, hi] (or (lo, hi] etc. by the flags), in the message as `range`.
    // (hi = kNoMax: no upper bound but the float range.)
    float real_in(const Json& v, const Path& p, double lo, double hi, bool lo_open, bool hi_open,
                  std::string_view unit = "") const {
        const double x = number(v, p);
        const bool ok = (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
        const std::string u = unit.empty() ? "" : fmt::format(" {}", unit);
        if (!ok && hi == kNoMax)
            error(p, "{} is out of range: expected a number {} {}{}", printable(v.dump(), 40),
                  lo_open ? ">" : ">=", lo, u);
        if (!ok)
            error(p, "{} is out of range: expected a number in {}{}, {}{}{}", printable(v.dump(), 40),
                  lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]", u);
        return real(v, p);
    }

    long long integer(const Json& v, const Path& p, long long lo, long long hi) const {
        if (!v.is_number()) error(p, "expected an integer, got {}", describe(v));
        long double x;
        if (v.is_number_unsigned())
            x = static_cast<long double>(v.get<std::uint64_t>());
        else if (v.is_number_integer())
            x = static_cast<long double>(v.get<std::int64_t>());
        else
            x = static_cast<long double>(v.get<double>());
        if (!std::isfinite(double(x)) || x != std::floor(x))
            error(p, "expected an integer, got {}", describe(v));
        if (x < lo || x > hi)
            error(p, "{} is out of range: expected an integer in [{}, {}]", printable(v.dump(), 40),
                  lo, hi);
        return static_cast<long long>(x);
    }

    std::string string(const Json& v, const Path& p) const {
        if (!v.is_string()) error(p, "expected a string, got {}", describe(v));
        return v.get<std::string>();
    }

    glm::vec3 vec3(const Json& v, const Path& p) const {
        if (!v.is_array() || v.size() != 3)
            error(p, "expected an array of 3 numbers [x, y, z], got {}", describe(v));
        return {real(v[0], p.index(0)), real(v[1], p.index(1)), real(v[2], p.index(2))};
    }

    // A number (grey) or [r, g, b], each in [lo, hi].
    glm::vec3 color(const Json& v, const Path& p, float lo, float hi) const {
        auto channel = [&](const Json& c, const Path& cp) {
            const float x = real(c, cp);
            if (x < lo || x > hi) {
                if (double(hi) == kNoMax)
                    error(cp, "{} is out of range: expected a number >= {}", printable(c.dump(), 40), lo);
                error(cp, "{} is out of range: expected a number in [{}, {}]", printable(c.dump(), 40), lo, hi);
            }
            return x;
        };
        if (v.is_number()) return glm::vec3(channel(v, p));
        if (!v.is_array() || v.size() != 3)
            error(p, "expected a number or an array of 3 numbers [r, g, b], got {}", describe(v));
        return {channel(v[0], p.index(0)), channel(v[1], p.index(1)), channel(v[2], p.index(2))};
    }

    // 16 numbers row-major, or 4 rows of 4 numbers; returned as glm (column-major).
    glm::mat4 matrix(const Json& v, const Path& p) const {
        glm::mat4 m(1.0f);
        if (v.is_array() && v.size() == 16) {
            for (int r = 0; r < 4; ++r)
                for (int c = 0; c < 4; ++c) m[c][r] = real(v[4 * r + c], p.index(4 * r + c));
        } else if (v.is_array() && v.size() == 4) {
            for (int r = 0; r < 4; ++r) {
                const Json& row = v[r];
                if (!row.is_array() || row.size() != 4)
                    error(p.index(r), "expected a row of 4 numbers, got {}", describe(row));
                for (int c = 0; c < 4; ++c) m[c][r] = real(row[c], p.index(r).index(c));
            }
        } else {
            error(p, "expected a 4x4 matrix: 16 numbers row-major or 4 rows of 4, got {}",
                  describe(v));
        }
        if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
            error(p, "the last row must be 0 0 0 1 (an affine transform), got {} {} {} {}",
                  m[0][3], m[1][3], m[2][3], m[3][3]);
        return m;
    }

    // --- parts of the scene -------------------------------------------------------------
    void read_render(const Json& v, const Path& p, Scene& s) const;
    void read_materials(const Json& root);
    Material read_material(const Json& v, const Path& p, std::vector<TexSpec>& textures) const;
    TexSpec read_texture(const Json& v, const Path& p, TexSlot slot) const;
    TextureRef use_texture(const TexSpec& t, Scene& s) const;
    void read_environment(const Json& v, const Path& p, Scene& s) const;
    fs::path file_path(const std::string& name) const {
        const fs::path rel(name);
        return rel.is_absolute() ? rel : dir_ / rel;
    }
    glm::mat4 read_transform(const Json& v, const Path& p) const;
    glm::mat4 read_transform_op(const std::string& key, const Json& v, const Path& p) const;
    void read_shape(const Json& v, const Path& p, Scene& s);
    std::uint32_t use_material(const Json& v, const Path& p) const;
    void read_camera(const Json* v, const Path& p, Scene& s) const;
    void reserve_triangles(double n, const Path& p, std::string_view what);
    // Positions from `first` on must be finite (a huge size or transform can overflow).
    void check_finite(const std::vector<glm::vec3>& pos, std::size_t first, const Path& p) const {
        for (std::size_t i = first; i < pos.size(); ++i)
            if (!std::isfinite(pos[i].x) || !std::isfinite(pos[i].y) || !std::isfinite(pos[i].z))
                error(p, "the shape's vertex {} is not finite ({}, {}, {}): its size or transform "
                         "overflows the float range",
                      i - first, pos[i].x, pos[i].y, pos[i].z);
    }

    Text text_;
    std::string file_;  // as given, for messages
    std::string name_;  // file name, for Scene::name
    fs::path dir_;
    std::vector<MaterialEntry> materials_;
    std::size_t triangles_ = 0;  // reserved so far, against kJsonSceneMaxTriangles
};

// The whole scene: top-level keys, materials, shapes, camera, then checks and warnings.
Scene Reader::read() {
    // 1. Parse, with the position of any syntax error (a SAX handler sees it; the DOM
    //    parser would drop it for number overflows).
    Json root;
    struct Sax {
        nlohmann::detail::json_sax_dom_parser<Json> dom;
        std::optional<std::size_t> error_at;  // chars read when the error was found
        std::string message, token;
        explicit Sax(Json& j) : dom(j, false) {}
        bool null() { return dom.null(); }
        bool boolean(bool b) { return dom.boolean(b); }
        bool number_integer(Json::number_integer_t x) { return dom.number_integer(x); }
        bool number_unsigned(Json::number_unsigned_t x) { return dom.number_unsigned(x); }
        bool number_float(Json::number_float_t x, const Json::string_t& s) {
            return dom.number_float(x, s);
        }
        bool string(Json::string_t& s) { return dom.string(s); }
        bool binary(Json::binary_t& b) { return dom.binary(b); }
        bool start_object(std::size_t n) { return dom.start_object(n); }
        bool key(Json::string_t& k) { return dom.key(k); }
        bool end_object() { return dom.end_object(); }
        bool start_array(std::size_t n) { return dom.start_array(n); }
        bool end_array() { return dom.end_array(); }
        bool parse_error(std::size_t pos, const std::string& tok,
                         const nlohmann::detail::exception& e) {
            error_at = pos;
            message = e.what();
            token = tok;
            return false;
        }
    } sax(root);
    const std::string_view raw = text_.str();
    bool parsed = Json::sax_parse(raw.begin(), raw.end(), &sax, Json::input_format_t::json,
                                  /*strict=*/true, /*ignore_comments=*/false);
    if (!parsed || sax.error_at || sax.dom.is_errored())
        syntax_error(sax.error_at.value_or(raw.size()), sax.message, sax.token);
    if (auto dup = text_.duplicate_key())
        raise_at(dup->second, dup->first,
                 fmt::format("the key '{}' appears twice in the same object (each key may appear "
                             "once)",
                             printable(dup->first.segs.back().key)));

    // 2. Top level.
    const Path top;
    expect_object(root, top, "a scene");
    check_keys(root, top, kTopKeys, "the scene");
    if (const Json* v = find(root, "version")) {
        const Path p = top.key("version");
        if (!v->is_number()) error(p, "expected a number, got {}", describe(*v));
        if (v->get<double>() != 1.0)
            error(p, "unsupported version {}: this wavepath reads version 1", printable(v->dump(), 40));
    }
    Scene s;
    s.name = name_;

    // 3. Materials (only the used ones enter the scene, in file order), then shapes.
    read_materials(root);
    const Json* shapes = find(root, "shapes");
    if (!shapes) error(top, "the scene has no triangles: there is no \"shapes\" array");
    const Path sp = top.key("shapes");
    if (!shapes->is_array()) error(sp, "expected an array of shapes, got {}", describe(*shapes));
    if (shapes->empty()) error(sp, "the scene has no triangles: \"shapes\" is empty");
    for (const Json& shape : *shapes)
        if (shape.is_object())
            if (const Json* m = find(shape, "material"); m && m->is_string())
                for (MaterialEntry& e : materials_)
                    if (e.name == m->get_ref<const std::string&>()) e.used = true;
    for (MaterialEntry& e : materials_)
        if (e.used) {
            Material m = e.material;
            m.name = e.name;
            for (const TexSpec& t : e.textures) {
                const TextureRef r = use_texture(t, s);
                switch (t.slot) {
                case TexSlot::Albedo: m.albedo_map = r; break;
                case TexSlot::Roughness: m.roughness_map = r; break;
                case TexSlot::Emission: m.emission_map = r; break;
                case TexSlot::Normal: m.normal_map = r; break;
                case TexSlot::Alpha: m.alpha_map = r; break;
                }
            }
            e.id = s.add_material(m);
        }
    for (std::size_t i = 0; i < shapes->size(); ++i) read_shape((*shapes)[i], sp.index(i), s);

    // 4. Background, render defaults, camera (which may frame the geometry).
    if (const Json* v = find(root, "background"))
        s.background = color(*v, top.key("background"), 0.0f, kNoMax);
    if (const Json* v = find(root, "render")) read_render(*v, top.key("render"), s);
    if (const Json* v = find(root, "environment")) read_environment(*v, top.key("environment"), s);
    read_camera(find(root, "camera"), top.key("camera"), s);

    // 5. Warnings: unused materials (no light at all: the command line's one warning,
    // scene/validate.h has_light, for every format).
    for (const MaterialEntry& e : materials_)
        if (!e.used)
            s.warnings.push_back(fmt::format("{}: material '{}' ({}) is not used by any shape",
                                             file_, printable(e.name), pointer(e.path)));
    validate_scene(s);
    return s;
}

void Reader::syntax_error(std::size_t chars_read, const std::string& message,
                          const std::string& token) const {
    // nlohmann counts the characters it read: the offending one is the last of them
    const std::string_view raw = text_.str();
    std::size_t off = std::min(chars_read > 0 ? chars_read - 1 : 0, raw.size());
    // A number out of range is found at its end: point at its start
    if (message.find("number overflow") != std::string::npos && !token.empty() &&
        off + 1 >= token.size() && raw.substr(off + 1 - token.size(), token.size()) == token)
        off = off + 1 - token.size();
    std::string desc = message;
    if (auto c = desc.find(", column "); c != std::string::npos) {
        if (auto colon = desc.find(": ", c); colon != std::string::npos) desc = desc.substr(colon + 2);
    } else if (auto br = desc.find("] "); br != std::string::npos) {
        desc = desc.substr(br + 2);
    }
    if (desc.empty()) desc = "not a JSON document";
    // NaN and Infinity are not JSON: say so
    auto word_char = [&](std::size_t i) {
        const char ch = raw[i];
        return std::isalnum(static_cast<unsigned char>(ch)) || ch == '+' || ch == '-' || ch == '.';
    };
    std::size_t a = std::min(off, raw.size()), b = a;
    while (a > 0 && a - 1 < raw.size() && word_char(a - 1)) --a;
    while (b < raw.size() && word_char(b)) ++b;
    std::string word(raw.substr(a, b - a));
    for (auto& ch : word) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    while (!word.empty() && (word[0] == '+' || word[0] == '-')) word.erase(0, 1);
    std::string hint;
    if (word.rfind("nan", 0) == 0 || word.rfind("inf", 0) == 0 ||
        desc.find("number overflow") != std::string::npos)
        hint = " (JSON has no NaN or Infinity: every number must be finite)";
    auto [line, col] = text_.line_col(off);
    throw Error(fmt::format("{}:{}:{}: malformed JSON: {}{}", file_, line, col,
                            printable(desc, 200), hint));
}

void Reader::read_render(const Json& v, const Path& p, Scene& s) const {
    expect_object(v, p, "render settings");
    check_keys(v, p, kRenderKeys, "\"render\"");
    if (const Json* x = find(v, "spp")) s.render.spp = int(integer(*x, p.key("spp"), limits::kMinSpp, kMaxSpp));
    if (const Json* x = find(v, "depth"))
        s.render.depth = int(integer(*x, p.key("depth"), limits::kMinDepth, kMaxDepth));
    if (const Json* x = find(v, "seed"))
        s.render.seed = std::uint32_t(integer(*x, p.key("seed"), 0, 0xFFFFFFFFLL));
}

void Reader::read_materials(const Json& root) {
    const Json* mats = find(root, "materials");
    if (!mats) return;
    const Path p = Path{}.key("materials");
    if (!mats->is_object())
        error(p, "expected an object of named materials (\"name\": {{\"type\": ...}}), got {}",
              describe(*mats));
    // File order, from the text (the parsed object is sorted by name)
    std::vector<std::string> order = text_.keys(p);
    bool same = order.size() == mats->size();
    for (const auto& k : order) same = same && mats->contains(k);
    if (!same) {
        order.clear();
        for (auto it = mats->begin(); it != mats->end(); ++it) order.push_back(it.key());
    }
    for (const std::string& name : order) {
        const Path mp = p.key(name);
        if (name.empty()) error_at_key(mp, "a material name must not be empty");
        std::vector<TexSpec> textures;
        Material m = read_material(mats->at(name), mp, textures);
        materials_.push_back({name, m, std::move(textures), mp, false, std::nullopt});
    }
}

Material Reader::read_material(const Json& v, const Path& p, std::vector<TexSpec>& textures) const {
    expect_object(v, p, "a material");
    const Json* t = find(v, "type");
    if (!t) error(p, "a material needs a \"type\": one of {}", join(kMaterialTypes));
    const std::string type = string(*t, p.key("type"));
    if (std::find(kMaterialTypes.begin(), kMaterialTypes.end(), type) == kMaterialTypes.end()) {
        std::string hint = suggest(type, kMaterialTypes);
        error(p.key("type"), "unknown material type '{}'{}; expected one of: {}", printable(type),
              hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint), join(kMaterialTypes));
    }
    Material m;
    m.kind = *material_kind_from_string(type);
    // The keys of the kind (material_kind_keys), then the textures.
    std::vector<std::string_view> allowed{"type", "reflectance", "emission"};
    for (std::string_view k : material_kind_keys(m.kind)) allowed.push_back(k);
    allowed.insert(allowed.end(), {"albedo_texture", "emission_texture", "normal_map",
                                   "normal_scale", "alpha_texture", "alpha_cutoff"});
    for (auto it = v.begin(); it != v.end(); ++it) {
        const std::string& k = it.key();
        if (std::find(allowed.begin(), allowed.end(), k) != allowed.end()) continue;
        std::vector<std::string_view> owners;  // the kinds that take k
        for (int i = 0; i < kMaterialKindCount; ++i)
            for (std::string_view x : material_kind_keys(MaterialKind(i)))
                if (x == k) owners.push_back(kMaterialTypes[i]);
        if (!owners.empty()) {
            std::string hint = suggest(k, allowed);
            error_at_key(p.key(k),
                         "'{}' does not apply to a {} material (it is a key of {} materials){}; "
                         "a {} material takes: {}",
                         k, type, join(owners),
                         hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint), type,
                         join(allowed));
        }
        check_keys(v, p, allowed, fmt::format("a {} material", type));
    }

    // Textures (each multiplies its constant, whose default becomes 1)
    for (const TexSlotKey& slot : kTexSlots)
        if (const Json* x = find(v, slot.key))
            textures.push_back(read_texture(*x, p.key(slot.key), slot.slot));
    auto has = [&](std::string_view k) { return find(v, k) != nullptr; };
    if (has("normal_scale") && !has("normal_map"))
        error_at_key(p.key("normal_scale"), "\"normal_scale\" needs a \"normal_map\"");
    if (has("alpha_cutoff") && !has("alpha_texture"))
        error_at_key(p.key("alpha_cutoff"), "\"alpha_cutoff\" needs an \"alpha_texture\"");
    if (const Json* x = find(v, "normal_scale")) m.normal_scale = real(*x, p.key("normal_scale"));
    if (const Json* x = find(v, "alpha_cutoff"))
        m.alpha_cutoff = real_in(*x, p.key("alpha_cutoff"), 0.0, 1.0, false, false);

    // Colours. "reflectance" is Material::albedo (what albedo_texture multiplies): the
    // diffuse reflectance of diffuse and plastics (0.8), glossy's F0 (0.8), the tint of
    // mirror and conductors (1); on dielectrics the tint of reflection and transmission
    // both (1), which "specular" and "transmittance" give one by one.
    const bool reflects_diffusely = m.kind == MaterialKind::Diffuse ||
                                    m.kind == MaterialKind::Glossy || is_plastic(m.kind);
    m.albedo = glm::vec3(!reflects_diffusely || has("albedo_texture") ? 1.0f : 0.8f);
    if (const Json* x = find(v, "reflectance")) m.albedo = color(*x, p.key("reflectance"), 0.0f, 1.0f);
    if (is_dielectric(m.kind)) {
        if (has("reflectance"))
            for (const char* k : {"specular", "transmittance"})
                if (has(k))
                    error_at_key(p.key(k),
                                 "give either \"reflectance\" (the tint of reflection and "
                                 "transmission) or \"specular\" and \"transmittance\", not both");
        m.specular = m.albedo;
        if (const Json* x = find(v, "transmittance"))
            m.albedo = color(*x, p.key("transmittance"), 0.0f, 1.0f);
    }
    if (const Json* x = find(v, "specular")) m.specular = color(*x, p.key("specular"), 0.0f, 1.0f);
    if (has("emission_texture")) m.emission = glm::vec3(1.0f);
    if (const Json* x = find(v, "emission")) m.emission = color(*x, p.key("emission"), 0.0f, kNoMax);

    // Roughness: glossy (the original lobe) takes α in [1e-4, 1] or a Phong exponent; the
    // rough kinds α in [1e-4, 2], isotropic or per axis, and their microfacet model
    if (m.kind == MaterialKind::Glossy) {
        const Json* r = find(v, "roughness");
        const Json* e = find(v, "exponent");
        if (r && e)
            error_at_key(p.key("exponent"),
                         "give either \"roughness\" (GGX alpha) or \"exponent\", not both");
        if (has("roughness_texture")) m.alpha = 1.0f;  // alpha = G² of the texture
        if (r) m.alpha = real_in(*r, p.key("roughness"), 1e-4, 1.0, false, false);
        if (e) m.alpha = phong_exponent_to_alpha(real_in(*e, p.key("exponent"), 0.0, kNoMax, false, false));
    } else if (uses_alpha(m.kind)) {
        const double lo = decimal(limits::kMinMicrofacetAlpha), hi = decimal(limits::kMaxMicrofacetAlpha);
        const Json* r = find(v, "roughness");
        const Json* ru = find(v, "roughness_u");
        const Json* rv = find(v, "roughness_v");
        if (r && (ru || rv))
            error_at_key(p.key(ru ? "roughness_u" : "roughness_v"),
                         "give either \"roughness\" (isotropic) or \"roughness_u\" and "
                         "\"roughness_v\", not both");
        if (bool(ru) != bool(rv))
            error_at_key(p.key(ru ? "roughness_u" : "roughness_v"),
                         "\"roughness_u\" and \"roughness_v\" go together (give both)");
        if (ru && has("roughness_texture"))
            error_at_key(p.key("roughness_texture"),
                         "\"roughness_texture\" needs an isotropic \"roughness\" (not "
                         "\"roughness_u\"/\"roughness_v\")");
        m.alpha = has("roughness_texture") ? 1.0f : limits::kDefaultMicrofacetAlpha;
        if (r) m.alpha = real_in(*r, p.key("roughness"), lo, hi, false, false);
        if (ru) {
            m.alpha = real_in(*ru, p.key("roughness_u"), lo, hi, false, false);
            m.alpha_v = real_in(*rv, p.key("roughness_v"), lo, hi, false, false);
        }
        if (const Json* x = find(v, "distribution")) {
            constexpr std::array<std::string_view, 2> names{"ggx", "beckmann"};
            const std::string d = string(*x, p.key("distribution"));
            if (d == "ggx")
                m.distribution = MicrofacetModel::GGX;
            else if (d == "beckmann")
                m.distribution = MicrofacetModel::Beckmann;
            else
                error(p.key("distribution"), "unknown distribution '{}'; expected one of: {}",
                      printable(d), join(names));
        }
        if (const Json* x = find(v, "g")) {
            constexpr std::array<std::string_view, 2> names{"height-correlated", "separable"};
            const std::string g = string(*x, p.key("g"));
            if (g != names[0] && g != names[1])
                error(p.key("g"), "unknown masking-shadowing '{}'; expected one of: {}",
                      printable(g), join(names));
            m.separable_g = g == "separable";
        }
    }

    // Conductors: "eta" and "k", or a named "metal"; neither: η 0, k 1 (reflects everything)
    if (uses_eta_k(m.kind)) {
        const Json* eta = find(v, "eta");
        const Json* k = find(v, "k");
        const Json* metal = find(v, "metal");
        if (metal && (eta || k))
            error_at_key(p.key(eta ? "eta" : "k"),
                         "give either \"metal\" or \"eta\" and \"k\", not both");
        if (bool(eta) != bool(k))
            error_at_key(p.key(eta ? "eta" : "k"), "\"eta\" and \"k\" go together (give both)");
        if (eta) {
            m.eta = color(*eta, p.key("eta"), 0.0f, kNoMax);
            m.k = color(*k, p.key("k"), 0.0f, kNoMax);
        }
        if (metal) {
            const std::string name = string(*metal, p.key("metal"));
            std::vector<std::string_view> names{"none"};
            for (const MetalIor& x : metal_table()) names.push_back(x.name);
            if (const MetalIor* x = find_metal(name)) {
                m.eta = x->eta;
                m.k = x->k;
            } else if (name != "none") {
                std::string hint = suggest(name, names);
                error(p.key("metal"), "unknown metal '{}'{}; expected one of: {}", printable(name),
                      hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint), join(names));
            }
        }
    }
    if (uses_ior(m.kind))
        if (const Json* x = find(v, "ior"))
            m.ior = real_in(*x, p.key("ior"), decimal(limits::kMinIor), decimal(limits::kMaxIor),
                            false, false);
    if (const Json* x = find(v, "nonlinear")) {
        if (!x->is_boolean())
            error(p.key("nonlinear"), "expected true or false, got {}", describe(*x));
        m.nonlinear = x->get<bool>();
    }
    return m;
}

// A texture reference: "file.png", {"file": ..., "scale", "offset", "rotation", "filter"} or
// {"checkerboard": [c0, c1], "scale", "offset", "rotation"}. Checked here; the image is read
// only when a shape uses the material (use_texture).
TexSpec Reader::read_texture(const Json& v, const Path& p, TexSlot slot) const {
    TexSpec t;
    t.slot = slot;
    auto file_name = [&](const Json& f, const Path& fp) {
        std::string name = string(f, fp);
        if (name.empty() || name.find('\0') != std::string::npos)
            error(fp, "expected a file name, got \"{}\"", printable(name));
        return name;
    };
    if (v.is_string()) {
        t.file = file_name(v, p);
        return t;
    }
    if (!v.is_object())
        error(p, "expected a texture: a file name, {{\"file\": ...}} or {{\"checkerboard\": "
                 "[c0, c1]}}, got {}",
              describe(v));
    check_keys(v, p, kTextureKeys, "a texture");
    const Json* f = find(v, "file");
    const Json* c = find(v, "checkerboard");
    if (f && c) error_at_key(p.key("checkerboard"), "give either \"file\" or \"checkerboard\", not both");
    if (!f && !c) error(p, "a texture needs \"file\" (an image) or \"checkerboard\" ([c0, c1])");
    if (f) {
        t.file = file_name(*f, p.key("file"));
    } else {
        const Path cp = p.key("checkerboard");
        if (!c->is_array() || c->size() != 2)
            error(cp, "expected two colours [c0, c1] (each a number or [r, g, b]), got {}",
                  describe(*c));
        // Emission takes any radiance >= 0; the other slots values in [0, 1]
        const float hi = slot == TexSlot::Emission ? float(kNoMax) : 1.0f;
        t.color0 = color((*c)[0], cp.index(0), 0.0f, hi);
        t.color1 = color((*c)[1], cp.index(1), 0.0f, hi);
        t.nearest = true;
    }
    if (const Json* x = find(v, "filter")) {
        const Path fp = p.key("filter");
        if (c) error_at_key(fp, "a checkerboard is always nearest; \"filter\" applies to an image \"file\"");
        const std::string filter = string(*x, fp);
        if (filter != "bilinear" && filter != "nearest")
            error(fp, "expected \"bilinear\" or \"nearest\", got \"{}\"", printable(filter));
        t.nearest = filter == "nearest";
    }
    // uv' = T(offset) · R(rotation) · S(scale) · uv (KHR_texture_transform's order and
    // rotation: counter-clockwise in uv space, u' = cos u + sin v, v' = -sin u + cos v)
    glm::vec2 scale(1.0f), offset(0.0f);
    float degrees = 0.0f;
    if (const Json* x = find(v, "scale")) {
        const Path sp = p.key("scale");
        if (x->is_number()) {
            scale = glm::vec2(real(*x, sp));
        } else {
            if (!x->is_array() || x->size() != 2)
                error(sp, "expected a number or [su, sv], got {}", describe(*x));
            scale = {real((*x)[0], sp.index(0)), real((*x)[1], sp.index(1))};
        }
        if (scale.x == 0.0f || scale.y == 0.0f) error(sp, "a texture scale must not be 0");
    }
    if (const Json* x = find(v, "offset")) {
        const Path op = p.key("offset");
        if (!x->is_array() || x->size() != 2) error(op, "expected [ou, ov], got {}", describe(*x));
        offset = {real((*x)[0], op.index(0)), real((*x)[1], op.index(1))};
    }
    if (const Json* x = find(v, "rotation")) degrees = real(*x, p.key("rotation"));
    const double r = double(degrees) * 3.14159265358979323846 / 180.0;
    const float cs = float(std::cos(r)), sn = float(std::sin(r));
    glm::mat3 m(1.0f);  // [column][row]
    m[0][0] = cs * scale.x;
    m[0][1] = -sn * scale.x;
    m[1][0] = sn * scale.y;
    m[1][1] = cs * scale.y;
    m[2][0] = offset.x;
    m[2][1] = offset.y;
    t.uv = m;
    return t;
}

// The image of a texture reference, added to the scene: a file (colours are sRGB-encoded
// unless the file is float; roughness, normal and alpha maps are data), or a 2 x 2 nearest
// checkerboard (for an alpha texture its coverage is the colours' first component). A
// missing file is a warning and a placeholder (scene/texture.h).
TextureRef Reader::use_texture(const TexSpec& t, Scene& s) const {
    int image;
    if (t.file.empty()) {
        Texture c = checkerboard_texture(t.color0, t.color1, fmt::format("checkerboard in {}", file_));
        if (t.slot == TexSlot::Alpha) {
            for (std::size_t i = 0; i < std::size_t(c.width) * std::size_t(c.height); ++i) {
                if (c.is_float())
                    c.texelsf[i * 4 + 3] = c.texelsf[i * 4];
                else
                    c.texels8[i * 4 + 3] = c.texels8[i * 4];
            }
        }
        s.textures.push_back(std::move(c));
        image = int(s.textures.size() - 1);
    } else {
        const bool colour = t.slot == TexSlot::Albedo || t.slot == TexSlot::Emission;
        image = add_texture_file(s, file_path(t.file), colour ? TextureUse::Colour : TextureUse::Data);
        image = texture_with_filter(s, image, t.nearest);
    }
    return TextureRef{image, t.uv};
}

// "environment": {"file", "scale", "rotation": [rx, ry, rz] degrees (x first, then y, then z)
// or "rotate_y": degrees}: the equirectangular map (scene/scene.h Environment).
void Reader::read_environment(const Json& v, const Path& p, Scene& s) const {
    expect_object(v, p, "an environment {\"file\": ..., \"scale\": ..., \"rotate_y\": ...}");
    check_keys(v, p, kEnvironmentKeys, "the environment");
    const Json* f = find(v, "file");
    if (!f) error(p, "an environment needs a \"file\" (an equirectangular image, e.g. .exr or .hdr)");
    const std::string name = string(*f, p.key("file"));
    if (name.empty() || name.find('\0') != std::string::npos)
        error(p.key("file"), "expected a file name, got \"{}\"", printable(name));
    Environment env;
    if (const Json* x = find(v, "scale")) env.scale = real_in(*x, p.key("scale"), 0.0, kNoMax, false, false);
    const Json* rot = find(v, "rotation");
    const Json* ry = find(v, "rotate_y");
    if (rot && ry) error_at_key(p.key("rotate_y"), "give either \"rotation\" or \"rotate_y\", not both");
    glm::mat4 r(1.0f);
    if (rot) {
        const glm::vec3 d = vec3(*rot, p.key("rotation"));
        r = glm::rotate(glm::mat4(1.0f), glm::radians(d.z), glm::vec3(0, 0, 1)) *
            glm::rotate(glm::mat4(1.0f), glm::radians(d.y), glm::vec3(0, 1, 0)) *
            glm::rotate(glm::mat4(1.0f), glm::radians(d.x), glm::vec3(1, 0, 0));
    } else if (ry) {
        r = glm::rotate(glm::mat4(1.0f), glm::radians(real(*ry, p.key("rotate_y"))), glm::vec3(0, 1, 0));
    }
    env.to_world = glm::mat3(r);
    env.image = add_texture_file(s, file_path(name), TextureUse::Colour);
    s.environment = env;
}

glm::mat4 Reader::read_transform_op(const std::string& key, const Json& v, const Path& p) const {
    if (key == "translate") return glm::translate(glm::mat4(1.0f), vec3(v, p));
    if (key == "scale") {
        glm::vec3 k = v.is_number() ? glm::vec3(real(v, p)) : vec3(v, p);
        if (k.x == 0.0f || k.y == 0.0f || k.z == 0.0f)
            error(p, "a scale of 0 flattens the shape (negative values mirror it)");
        return glm::scale(glm::mat4(1.0f), k);
    }
    if (key == "rotate") {
        expect_object(v, p, "a rotation {\"axis\": [x, y, z], \"degrees\": d}");
        check_keys(v, p, kRotateKeys, "a rotation");
        const Json* axis = find(v, "axis");
        const Json* deg = find(v, "degrees");
        if (!axis || !deg)
            error(p, "a rotation needs \"axis\" and \"degrees\": {{\"axis\": [x, y, z], "
                     "\"degrees\": d}}");
        const glm::vec3 a = vec3(*axis, p.key("axis"));
        if (a == glm::vec3(0.0f)) error(p.key("axis"), "the rotation axis must not be zero");
        return glm::rotate(glm::mat4(1.0f), glm::radians(real(*deg, p.key("degrees"))), a);
    }
    return matrix(v, p);  // "matrix"
}

glm::mat4 Reader::read_transform(const Json& v, const Path& p) const {
    std::optional<glm::mat4> m;  // no identity factor: the composition is exactly the ops'
    auto then = [&](const glm::mat4& op) { m = m ? op * *m : op; };
    if (v.is_object()) {
        check_keys(v, p, kTransformKeys, "a transform");
        if (v.contains("matrix") && v.size() > 1)
            for (auto it = v.begin(); it != v.end(); ++it)
                if (it.key() != "matrix")
                    error_at_key(p.key(it.key()),
                                 "a transform with \"matrix\" takes no other key; to combine "
                                 "them, use a list: [{{\"matrix\": ...}}, {{\"{}\": ...}}]",
                                 it.key());
        // Scale first, then rotate, then translate
        for (const char* k : {"matrix", "scale", "rotate", "translate"})
            if (const Json* x = find(v, k)) then(read_transform_op(k, *x, p.key(k)));
    } else if (v.is_array()) {
        // In the order listed: the first step acts on the shape first
        for (std::size_t i = 0; i < v.size(); ++i) {
            const Json& step = v[i];
            const Path sp = p.index(i);
            expect_object(step, sp, "a transform step ({\"translate\": ...}, ...)");
            check_keys(step, sp, kTransformKeys, "a transform step");
            if (step.size() != 1)
                error(sp, "each step of a transform list has exactly one key (translate, rotate, "
                          "scale or matrix), this one has {}",
                      step.size());
            then(read_transform_op(step.begin().key(), step.begin().value(),
                                   sp.key(step.begin().key())));
        }
    } else {
        error(p, "expected a transform: an object ({{\"translate\", \"rotate\", \"scale\"}} or "
                 "{{\"matrix\"}}) or a list of steps, got {}",
              describe(v));
    }
    const glm::mat4 r = m.value_or(glm::mat4(1.0f));
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k)
            if (!std::isfinite(r[c][k])) error(p, "the transform is not finite (overflow)");
    const float det = glm::determinant(glm::mat3(r));
    if (!(std::abs(det) > 0.0f) || !std::isfinite(det))
        error(p, "the transform is singular (determinant {}): it would flatten the shape", det);
    return r;
}

std::uint32_t Reader::use_material(const Json& v, const Path& p) const {
    const std::string name = string(v, p);
    for (const MaterialEntry& e : materials_)
        if (e.name == name && e.id) return *e.id;
    std::vector<std::string_view> names;
    for (const MaterialEntry& e : materials_) names.push_back(e.name);
    if (names.empty())
        error(p, "no material named '{}': the scene defines no materials (add a \"materials\" "
                 "object)",
              printable(name));
    std::string hint = suggest(name, names);
    error(p, "no material named '{}'{}; \"materials\" defines: {}", printable(name),
          hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint), printable(join(names), 200));
}

void Reader::reserve_triangles(double n, const Path& p, std::string_view what) {
    const double left = double(kJsonSceneMaxTriangles - triangles_);
    if (n > left)
        error(p, "this {} has {:.0f} triangles, which would bring the scene past the limit of {} "
                 "triangles",
              what, n, kJsonSceneMaxTriangles);
    triangles_ += std::size_t(n);
}

// A box of make_box with a texture on each face: every face gets its own vertices (the
// texture is cut at the edges) with uv (s, 1 - t) along the face's grid axes (make_box's u, v:
// cross(u, v) outward), the whole image on each face.
void box_uvs(Mesh& mesh, glm::vec3 lo, glm::vec3 hi, int n, std::vector<glm::vec2>& uvs) {
    const std::size_t per_face = 2 * std::size_t(n) * std::size_t(n);
    std::vector<glm::vec3> pos;
    std::map<std::pair<std::size_t, std::uint32_t>, std::uint32_t> index;  // (face, vertex)
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const std::size_t face = i / per_face;
        const int a = int(face / 2), side = int(face % 2);
        int u = (a + 1) % 3, v = (a + 2) % 3;
        if (side == 0) std::swap(u, v);
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t old = mesh.triangles[i][k];
            auto [it, fresh] = index.try_emplace({face, old}, std::uint32_t(pos.size()));
            if (fresh) {
                const glm::vec3 q = mesh.positions[old];
                pos.push_back(q);
                uvs.emplace_back((q[u] - lo[u]) / (hi[u] - lo[u]),
                                 1.0f - (q[v] - lo[v]) / (hi[v] - lo[v]));
            }
            mesh.triangles[i][k] = it->second;
        }
    }
    mesh.positions = std::move(pos);
}

void Reader::read_shape(const Json& v, const Path& p, Scene& s) {
    expect_object(v, p, "a shape");
    const Json* t = find(v, "type");
    if (!t) error(p, "a shape needs a \"type\": one of {}", join(kShapeTypes));
    const std::string type = string(*t, p.key("type"));
    static const std::map<std::string, std::vector<std::string_view>> kKeys{
        {"mesh", {"file", "smooth"}},
        {"quad", {"corner", "edge_u", "edge_v", "size", "subdivisions"}},
        {"box", {"min", "max", "center", "size", "subdivisions"}},
        {"sphere", {"center", "radius", "rings", "segments"}},
        {"stress", {"triangles"}},
    };
    auto it = kKeys.find(type);
    if (it == kKeys.end()) {
        std::string hint = suggest(type, kShapeTypes);
        error(p.key("type"), "unknown shape type '{}'{}; expected one of: {}", printable(type),
              hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint), join(kShapeTypes));
    }
    std::vector<std::string_view> allowed{"type", "material", "transform"};
    allowed.insert(allowed.end(), it->second.begin(), it->second.end());
    for (auto k = v.begin(); k != v.end(); ++k) {
        if (std::find(allowed.begin(), allowed.end(), k.key()) != allowed.end()) continue;
        for (const auto& [other, keys] : kKeys)
            if (std::find(keys.begin(), keys.end(), k.key()) != keys.end())
                error_at_key(p.key(k.key()),
                             "'{}' does not apply to a {} shape (it is a key of {} shapes); a {} "
                             "takes: {}",
                             k.key(), type, other, type, join(allowed));
        check_keys(v, p, allowed, fmt::format("a {} shape", type));
    }
    auto get = [&](std::string_view k) { return find(v, k); };
    std::optional<glm::mat4> to_world;
    if (const Json* x = get("transform")) to_world = read_transform(*x, p.key("transform"));

    // Mesh files: their own materials unless one is named
    if (type == "mesh") {
        const Json* f = get("file");
        if (!f) error(p, "a mesh needs a \"file\" (a path relative to the scene file)");
        const Path fp = p.key("file");
        const std::string name = string(*f, fp);
        if (name.empty() || name.find('\0') != std::string::npos)
            error(fp, "expected a file name, got \"{}\"", printable(name));
        std::optional<float> crease;  // "smooth": computed normals, this crease angle
        if (const Json* x = get("smooth"))
            crease = real_in(*x, p.key("smooth"), 0.0, limits::kMaxCreaseDeg, false, false,
                             "degrees");
        const fs::path rel(name);
        const fs::path full = rel.is_absolute() ? rel : dir_ / rel;
        std::error_code ec;
        if (!fs::exists(full, ec))
            error(fp, "mesh file '{}' not found (looked for '{}')", printable(name, 200),
                  printable(full.string(), 200));
        if (!fs::is_regular_file(full, ec))
            error(fp, "mesh file '{}' is not a regular file", printable(full.string(), 200));
        Scene mesh;
        try {
            mesh = load_mesh_file(full);
        } catch (const Error& e) {
            error(fp, "{}", e.what());
        } catch (const std::exception& e) {
            error(fp, "cannot load mesh file '{}': {}", printable(full.string(), 200), e.what());
        }
        reserve_triangles(double(mesh.triangles.size()), fp, "mesh file");
        std::optional<std::uint32_t> id;
        if (const Json* m = get("material")) id = use_material(*m, p.key("material"));
        // A named material without textures or anisotropy needs no texture coordinates
        if (id && !s.materials[*id].textured() && !s.materials[*id].anisotropic()) {
            mesh.uvs.clear();
            mesh.tangents.clear();
        }
        const std::size_t first = s.positions.size(), first_triangle = s.triangles.size();
        s.append(mesh, to_world.value_or(glm::mat4(1.0f)), id);
        check_finite(s.positions, first, p);
        if (crease) smooth_normals(s, *crease, first_triangle);
        return;
    }

    // Built-in shapes: a material is required
    const Json* mat = get("material");
    if (!mat) error(p, "a {} needs a \"material\" (a name from \"materials\")", type);
    const std::uint32_t id = use_material(*mat, p.key("material"));
    const bool textured = s.materials[id].textured();
    std::vector<glm::vec3> normals;  // the sphere's (analytic); flat shapes have none
    std::vector<glm::vec2> uvs;      // only for a textured material
    auto count = [&](std::string_view k, long long lo, long long hi, long long dflt) {
        const Json* x = get(k);
        return x ? int(integer(*x, p.key(k), lo, hi)) : int(dflt);
    };
    Mesh mesh;
    if (type == "quad") {
        const Json *c = get("corner"), *u = get("edge_u"), *w = get("edge_v"), *sz = get("size");
        glm::vec3 corner, eu, ev;
        if (sz && (c || u || w))
            error_at_key(p.key("size"),
                         "give either \"size\" or \"corner\", \"edge_u\" and \"edge_v\", not both");
        if (sz) {
            const Path zp = p.key("size");
            glm::vec2 wh;
            if (sz->is_number()) {
                wh = glm::vec2(real_in(*sz, zp, 0.0, kNoMax, true, false));
            } else {
                if (!sz->is_array() || sz->size() != 2)
                    error(zp, "expected a number or an array of 2 numbers [width, height], got {}",
                          describe(*sz));
                wh = {real_in((*sz)[0], zp.index(0), 0.0, kNoMax, true, false),
                      real_in((*sz)[1], zp.index(1), 0.0, kNoMax, true, false)};
            }
            corner = glm::vec3(-0.5f * wh.x, -0.5f * wh.y, 0.0f);
            eu = glm::vec3(wh.x, 0.0f, 0.0f);
            ev = glm::vec3(0.0f, wh.y, 0.0f);
        } else if (c || u || w) {
            if (!c || !u || !w)
                error(p, "a quad with corner and edges needs all three: \"corner\", \"edge_u\" "
                         "and \"edge_v\"");
            corner = vec3(*c, p.key("corner"));
            eu = vec3(*u, p.key("edge_u"));
            ev = vec3(*w, p.key("edge_v"));
        } else {
            error(p, "a quad needs \"size\", or \"corner\", \"edge_u\" and \"edge_v\"");
        }
        const glm::vec3 n = glm::cross(eu, ev);
        const float n2 = glm::dot(n, n);
        if (!(n2 > 0.0f) || !std::isfinite(n2))
            error(p.key(sz ? "size" : "edge_v"),
                  "edge_u and edge_v are zero, parallel or too long: the quad has no usable area");
        int nu = 1, nv = 1;
        if (const Json* x = get("subdivisions")) {
            const Path dp = p.key("subdivisions");
            if (x->is_array()) {
                if (x->size() != 2)
                    error(dp, "expected a number or an array of 2 integers [nu, nv], got {}",
                          describe(*x));
                nu = int(integer((*x)[0], dp.index(0), 1, 4096));
                nv = int(integer((*x)[1], dp.index(1), 1, 4096));
            } else {
                nu = nv = int(integer(*x, dp, 1, 4096));
            }
        }
        reserve_triangles(2.0 * nu * nv, p, "quad");
        mesh = make_quad(corner, eu, ev, nu, nv);
        // uv (s, 1 - t) at corner + s edge_u + t edge_v: upright when edge_v points up
        if (textured)
            for (int j = 0; j <= nv; ++j)
                for (int i = 0; i <= nu; ++i)
                    uvs.emplace_back(float(i) / float(nu), 1.0f - float(j) / float(nv));
    } else if (type == "box") {
        const Json *lo = get("min"), *hi = get("max"), *sz = get("size"), *c = get("center");
        glm::vec3 a, b;
        if ((lo || hi) && (sz || c))
            error_at_key(p.key(sz ? "size" : "center"),
                         "give either \"min\" and \"max\", or \"size\" (and \"center\"), not both");
        if (lo || hi) {
            if (!lo || !hi) error(p, "a box needs both \"min\" and \"max\"");
            a = vec3(*lo, p.key("min"));
            b = vec3(*hi, p.key("max"));
            if (!glm::all(glm::lessThan(a, b)))
                error(p.key("max"), "max ({}, {}, {}) must exceed min ({}, {}, {}) on every axis",
                      b.x, b.y, b.z, a.x, a.y, a.z);
        } else if (sz) {
            const Path zp = p.key("size");
            glm::vec3 size;
            if (sz->is_number()) {
                size = glm::vec3(real_in(*sz, zp, 0.0, kNoMax, true, false));
            } else {
                size = vec3(*sz, zp);
                for (int k = 0; k < 3; ++k)
                    if (!(size[k] > 0.0f)) error(zp.index(k), "a box size must be > 0, got {}", size[k]);
            }
            const glm::vec3 center = c ? vec3(*c, p.key("center")) : glm::vec3(0.0f);
            a = center - 0.5f * size;
            b = center + 0.5f * size;
            if (!glm::all(glm::lessThan(a, b)) || !std::isfinite(a.x + a.y + a.z + b.x + b.y + b.z))
                error(zp, "the box is too small or too large for its center to be represented");
        } else {
            error(p, "a box needs \"min\" and \"max\", or \"size\"");
        }
        const int n = count("subdivisions", 1, 1024, 1);
        reserve_triangles(12.0 * n * n, p, "box");
        mesh = make_box(a, b, n);
        if (textured) box_uvs(mesh, a, b, n, uvs);
    } else if (type == "sphere") {
        const glm::vec3 c = get("center") ? vec3(*get("center"), p.key("center")) : glm::vec3(0.0f);
        const float r = get("radius") ? real_in(*get("radius"), p.key("radius"), 0.0, kNoMax, true, false)
                                      : 1.0f;
        const int rings = count("rings", 2, 4096, 32);
        const int segments = count("segments", 3, 8192, 64);
        reserve_triangles(2.0 * segments * (rings - 1), p, "sphere");
        mesh = make_uv_sphere(c, r, rings, segments);
        // Smooth: the normal is the direction from the centre. uv = (phi / 2 pi, theta / pi):
        // phi around +y from +z towards +x, theta from the +y pole (v = 0 at the top).
        normals = sphere_normals(mesh.positions, c);  // as the built-in box's sphere
        if (textured)
            wrap_uvs(
                mesh.positions, mesh.triangles, normals, uvs,
                [c](glm::vec3 q) {
                    const glm::dvec3 d = glm::dvec3(q) - glm::dvec3(c);
                    double phi = std::atan2(d.x, d.z);
                    if (phi < 0.0) phi += 2.0 * 3.14159265358979323846;
                    const double theta = std::acos(std::clamp(d.y / glm::length(d), -1.0, 1.0));
                    return glm::vec2(float(phi / (2.0 * 3.14159265358979323846)),
                                     float(theta / 3.14159265358979323846));
                },
                [c](glm::vec3 q) { return q.x - c.x == 0.0f && q.z - c.z == 0.0f; });
    } else {  // stress
        const int target =
            count("triangles", 48, static_cast<long long>(kJsonSceneMaxTriangles), 250000);
        reserve_triangles(double(target), p, "stress mesh");
        mesh = make_stress_mesh(std::size_t(target));
        if (mesh.triangles.size() > std::size_t(target))
            reserve_triangles(double(mesh.triangles.size() - std::size_t(target)), p, "stress mesh");
    }
    if (to_world) {
        mesh = transform(mesh, *to_world);
        const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(*to_world)));
        for (auto& n : normals) n = glm::normalize(nm * n);
    }
    check_finite(mesh.positions, 0, p);
    s.add_mesh(mesh.positions, mesh.triangles, id, normals, uvs);
}

void Reader::read_camera(const Json* v, const Path& p, Scene& s) const {
    Camera c;  // 800 x 600, 40 degrees
    auto get = [&](std::string_view k) { return v ? find(*v, k) : nullptr; };
    if (v) {
        expect_object(*v, p, "a camera");
        check_keys(*v, p, kCameraKeys, "the camera");
    }
    // Film and field of view
    if (const Json* x = get("width")) c.width = int(integer(*x, p.key("width"), 1, kMaxFilmSide));
    if (const Json* x = get("height")) c.height = int(integer(*x, p.key("height"), 1, kMaxFilmSide));
    if (static_cast<long long>(c.width) * c.height > kMaxFilmPixels)
        error(p.key("height"), "the film {} x {} has more than {} pixels", c.width, c.height,
              kMaxFilmPixels);
    float fov = 40.0f;
    if (const Json* x = get("fov")) fov = real_in(*x, p.key("fov"), 0.0, 180.0, true, true, "degrees");
    bool horizontal = false;
    if (const Json* x = get("fov_axis")) {
        const std::string axis = string(*x, p.key("fov_axis"));
        if (axis != "x" && axis != "y")
            error(p.key("fov_axis"), "expected \"x\" (horizontal) or \"y\" (vertical), got \"{}\"",
                  printable(axis));
        horizontal = axis == "x";
    }
    c.vfov_deg = horizontal ? vfov_from_hfov(fov, c.width, c.height) : fov;
    if (!(c.vfov_deg > 0.0f && c.vfov_deg < 180.0f))
        error(p.key("fov"), "the vertical field of view {} degrees is not in (0, 180)", c.vfov_deg);

    // Placement: a matrix, position/look_at/up, or framing the scene
    const Json *m = get("matrix"), *pos = get("position"), *at = get("look_at"), *up = get("up");
    if (m && (pos || at || up))
        error_at_key(p.key(pos ? "position" : at ? "look_at" : "up"),
                     "give either \"matrix\" or \"position\"/\"look_at\"/\"up\", not both");
    if (m) {
        const Path mp = p.key("matrix");
        const glm::mat4 to_world = matrix(*m, mp);
        const glm::vec3 dir(to_world[2]), upv(to_world[1]);
        if (glm::dot(dir, dir) == 0.0f)
            error(mp, "column 2 (the viewing direction) is zero");
        const glm::vec3 side = glm::cross(dir, upv);
        if (!(glm::dot(side, side) > 0.0f))
            error(mp, "column 1 (up) is zero or parallel to column 2 (the viewing direction)");
        try {
            Camera k = camera_from_matrix(to_world, c.vfov_deg, c.width, c.height);
            c = k;
        } catch (const Error& e) {
            error(mp, "{}", e.what());
        }
    } else if (pos || at) {
        if (!pos || !at)
            error(p, "\"position\" and \"look_at\" go together: give both (or neither, to frame "
                     "the whole scene)");
        c.position = vec3(*pos, p.key("position"));
        c.target = vec3(*at, p.key("look_at"));
        if (up) c.up = vec3(*up, p.key("up"));
        const glm::vec3 dir = c.target - c.position;
        if (!(glm::dot(dir, dir) > 0.0f))
            error(p.key("look_at"), "look_at equals position: the camera has no viewing direction");
        const glm::vec3 side = glm::cross(dir, c.up);
        if (!(glm::dot(side, side) > 0.0f))
            error(up ? p.key("up") : p.key("look_at"),
                  "up ({}, {}, {}) is zero or parallel to the viewing direction", c.up.x, c.up.y,
                  c.up.z);
    } else {
        if (up) error_at_key(p.key("up"), "\"up\" needs \"position\" and \"look_at\"");
        // From +z, far enough for the bounding sphere to fit the smaller field of view
        const Aabb b = s.bounds();
        const float radius = std::max(0.5f * glm::length(b.extent()), 1e-3f);
        const float vhalf = glm::radians(0.5f * c.vfov_deg);
        const float hhalf = std::atan(std::tan(vhalf) * float(c.width) / float(c.height));
        const float distance = radius / std::sin(std::min(vhalf, hhalf));
        c.target = b.center();
        c.position = c.target + glm::vec3(0.0f, 0.0f, distance);
        c.up = glm::vec3(0.0f, 1.0f, 0.0f);
        if (!std::isfinite(distance) || !std::isfinite(c.position.z))
            error(p, "cannot frame the scene automatically (its bounds are too large); give "
                     "\"position\" and \"look_at\"");
    }

    // Thin lens: the radius (lens_radius, or Mitsuba's name aperture_radius) and the distance
    // in focus, by default that of look_at (or the framed scene's centre; 1 with a matrix)
    const Json *lr = get("lens_radius"), *ar = get("aperture_radius"), *fd = get("focus_distance");
    if (lr && ar)
        error_at_key(p.key("aperture_radius"),
                     "give either \"lens_radius\" or \"aperture_radius\" (the same), not both");
    if (lr || ar) {
        const char* k = lr ? "lens_radius" : "aperture_radius";
        c.lens_radius =
            real_in(lr ? *lr : *ar, p.key(k), 0.0, kNoMax, false, false, "(world units)");
    }
    if (fd) {
        c.focus_distance =
            real_in(*fd, p.key("focus_distance"), 0.0, kNoMax, true, false, "(world units)");
    } else if (c.lens_radius > 0.0f) {
        c.focus_distance = glm::length(c.target - c.position);
        if (!(std::isfinite(c.focus_distance) && c.focus_distance > 0.0f))
            error(p, "the distance from position to look_at ({}) cannot be the focus distance: "
                     "give \"focus_distance\"", c.focus_distance);
    }
    s.camera = c;
}

}  // namespace

Scene parse_json_scene(std::string_view text, const fs::path& origin) {
    const std::string file = origin.empty() ? std::string("(json)") : origin.string();
    if (text.size() > kJsonSceneMaxBytes)
        fail("{}: {} bytes, more than the limit of {} bytes for a scene file", file, text.size(),
             kJsonSceneMaxBytes);
    try {
        Reader r(text, origin);
        return r.read();
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        fail("{}: out of memory while reading the scene", file);
    } catch (const std::exception& e) {
        fail("{}: {}", file, e.what());
    }
}

Scene load_json_scene(const fs::path& path) {
    std::string text = read_file(path, kJsonSceneMaxBytes);
    return parse_json_scene(text, path);
}

}  // namespace wp
