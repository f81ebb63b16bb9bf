#include "scene/mitsuba_loader.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>
#include <pugixml.hpp>

#include "scene/load.h"
#include "scene/notes.h"
#include "scene/metals.h"
#include "scene/normals.h"
#include "scene/procedural.h"
#include "scene/shape_uv.h"
#include "scene/tessellate.h"
#include "scene/texture.h"
#include "scene/validate.h"
#include "util/error.h"
#include "util/limits.h"
#include "util/read_file.h"

namespace wp {

namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

// Limits against hostile input (see mitsuba_loader.h).
// Film and spp ranges: util/limits.h, the same as the command line's.
constexpr int kMaxFilmSide = limits::kMaxImageSide;
constexpr long long kMaxFilmPixels = limits::kMaxPixels;
constexpr long long kMaxSpp = limits::kMaxSpp;
constexpr std::size_t kMaxTriangles = std::size_t(1) << 25;
constexpr int kMaxBsdfNesting = 16;
constexpr int kMaxElementNesting = 64;
constexpr std::size_t kMaxExpansion = std::size_t(1) << 16; // bytes of one expanded attribute
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(256) << 20;
// Tessellation of the analytic shapes.
constexpr int kRoundSegments = 128;    // disk and cylinder

// --- Grammar ------------------------------------------------------------------------------

enum class TagKind { Scene, Default, Property, Transform, TransformOp, Object, Ref, Unsupported };

struct TagInfo {
    std::string_view name;
    TagKind kind;
    std::array<std::string_view, 5> attrs; // allowed attributes ("" = unused slot)
};

// Every element of Mitsuba 3's scene format that this reader knows. Elements outside this
// table are errors; "Unsupported" ones are skipped with a warning.
constexpr TagInfo kTags[] = {
    {"scene", TagKind::Scene, {"version"}},
    {"default", TagKind::Default, {"name", "value"}},
    {"integer", TagKind::Property, {"name", "value"}},
    {"float", TagKind::Property, {"name", "value"}},
    {"boolean", TagKind::Property, {"name", "value"}},
    {"string", TagKind::Property, {"name", "value"}},
    {"rgb", TagKind::Property, {"name", "value"}},
    {"spectrum", TagKind::Property, {"name", "value", "filename"}},
    {"point", TagKind::Property, {"name", "value", "x", "y", "z"}},
    {"vector", TagKind::Property, {"name", "value", "x", "y", "z"}},
    {"transform", TagKind::Transform, {"name"}},
    {"translate", TagKind::TransformOp, {"value", "x", "y", "z"}},
    {"rotate", TagKind::TransformOp, {"value", "x", "y", "z", "angle"}},
    {"scale", TagKind::TransformOp, {"value", "x", "y", "z"}},
    {"matrix", TagKind::TransformOp, {"value"}},
    {"lookat", TagKind::TransformOp, {"origin", "target", "up"}},
    {"ref", TagKind::Ref, {"id", "name"}},
    {"bsdf", TagKind::Object, {"type", "id", "name"}},
    {"shape", TagKind::Object, {"type", "id", "name"}},
    {"emitter", TagKind::Object, {"type", "id", "name"}},
    {"sensor", TagKind::Object, {"type", "id", "name"}},
    {"film", TagKind::Object, {"type", "id", "name"}},
    {"sampler", TagKind::Object, {"type", "id", "name"}},
    {"integrator", TagKind::Object, {"type", "id", "name"}},
    {"rfilter", TagKind::Object, {"type", "id", "name"}},
    {"texture", TagKind::Object, {"type", "id", "name"}},
    {"medium", TagKind::Object, {"type", "id", "name"}},
    {"phase", TagKind::Object, {"type", "id", "name"}},
    {"volume", TagKind::Object, {"type", "id", "name"}},
    {"include", TagKind::Unsupported, {"filename"}},
    {"alias", TagKind::Unsupported, {"id", "as"}},
    {"path", TagKind::Unsupported, {"value"}},
};

const TagInfo* tag_info(std::string_view name) {
    for (const TagInfo& t : kTags)
        if (t.name == name) return &t;
    return nullptr;
}

bool is_ident_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

bool is_identifier(std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), is_ident_char);
}

std::string lower(std::string s) {
    for (auto& c : s)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

// --- Tables ---------------------------------------------------------------------------------

// Mitsuba's named indices of refraction (include/mitsuba/render/ior.h).
struct NamedIor {
    std::string_view name;
    double ior;
};
constexpr NamedIor kIors[] = {
    {"vacuum", 1.0},      {"helium", 1.000036},        {"hydrogen", 1.000132},
    {"air", 1.000277},    {"carbon dioxide", 1.00045}, {"water", 1.3330},
    {"acetone", 1.36},    {"ethanol", 1.361},          {"carbon tetrachloride", 1.461},
    {"glycerol", 1.4729}, {"benzene", 1.501},          {"silicone oil", 1.52045},
    {"bromine", 1.661},   {"water ice", 1.31},         {"fused quartz", 1.458},
    {"pyrex", 1.470},     {"acrylic glass", 1.49},     {"polypropylene", 1.49},
    {"bk7", 1.5046},      {"sodium chloride", 1.544},  {"amber", 1.55},
    {"pet", 1.5750},      {"diamond", 2.419},
};

// --- Texels ---------------------------------------------------------------------------------

// Channel c of texel i, linear (scene/texture.h).
float texel(const Texture& t, std::size_t i, int c) { return texel_linear(t, i, c); }

// Mitsuba's luminance of linear RGB: what a colour texture gives where a BSDF asks for one
// number (eval_1: roughness, opacity). The weights sum to 1, so a grey texture gives its grey.
float luminance(glm::vec3 c) { return 0.212671f * c.x + 0.715160f * c.y + 0.072169f * c.z; }

float texel_luminance(const Texture& t, std::size_t i) {
    return luminance({texel(t, i, 0), texel(t, i, 1), texel(t, i, 2)});
}

// Mitsuba's to_uv, a 4x4 transform of which a texture uses the 3x3 affine map of (u, v):
// the x and y rows and columns and the translation (the z row and column are dropped).
glm::mat3 uv_matrix(const glm::dmat4& m) {
    glm::mat3 r(1.0f);  // [column][row]
    r[0][0] = float(m[0][0]);
    r[0][1] = float(m[0][1]);
    r[1][0] = float(m[1][0]);
    r[1][1] = float(m[1][1]);
    r[2][0] = float(m[3][0]);
    r[2][1] = float(m[3][1]);
    return r;
}

// Mitsuba's coordinate_system(n) (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited"): the frame its cylinder is built in, so that u = phi / 2 pi starts where
// Mitsuba's does.
std::pair<glm::dvec3, glm::dvec3> coordinate_system(glm::dvec3 n) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
    return {glm::dvec3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            glm::dvec3(b, sign + n.y * n.y * a, -n.y)};
}

// --- The reader -----------------------------------------------------------------------------

struct Obj {
    struct Item {
        pugi::xml_node node;
        bool used = false;
    };
    pugi::xml_node node;
    std::string tag, type;
    std::vector<std::pair<std::string, Item>> props; // property elements by name
    std::vector<Item> nested;                        // nested objects and refs
};

// A <texture> as wavepath uses it (scene/texture.h): an image in Scene::textures with the uv
// map, or, for the types wavepath does not model, a constant stand-in.
struct TexInfo {
    TextureRef ref;            // !ref.used(): not representable; `mean` stands in
    glm::vec3 mean{0.5f};      // the constant stand-in (checkerboard: the mean of its colours)
    bool missing = false;      // a bitmap whose file did not load (a placeholder image)
    bool checker = false;      // a checkerboard of color0, color1
    glm::vec3 color0{0.4f}, color1{0.2f};
    bool raw = false;          // bitmap raw = true: data, no sRGB decoding
};

// A shape's geometry in its own space, before to_world.
struct ShapeGeometry {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    std::vector<glm::vec3> normals;  // empty, or one shading normal per position
    std::vector<glm::vec2> uvs;      // empty, or one per position (wavepath's convention)
};

class Reader {
  public:
    Reader(std::string_view xml, const fs::path& origin, const MitsubaParams& params)
        : text_(xml), file_(origin.string()), dir_(origin.parent_path()), params_(params) {
        for (const auto& [name, value] : params)
            if (!is_identifier(name))
                fail("{}: parameter name '{}' must consist of letters, digits and '_'", file_,
                     name);
        line_starts_.push_back(0);
        for (std::size_t i = 0; i < text_.size(); ++i)
            if (text_[i] == '\n') line_starts_.push_back(i + 1);
    }

    Scene read();

  private:
    std::string_view text_;
    std::string file_;
    fs::path dir_;
    MitsubaParams params_;
    std::vector<std::size_t> line_starts_;
    Scene scene_;

    // Warnings, aggregated by kind: text, first place, count.
    NoteLog notes_;  // warnings, once per kind

    // Objects with an id (Mitsuba: one namespace), named BSDFs and textures.
    std::map<std::string, pugi::xml_node> ids_;
    struct NamedBsdf {
        Material material;
        std::optional<std::uint32_t> id; // scene material, once a shape uses it
    };
    std::map<std::string, NamedBsdf> bsdfs_;
    std::map<std::string, pugi::xml_node> textures_;
    std::optional<std::uint32_t> default_material_;
    std::map<std::string, Scene> mesh_cache_;
    std::map<std::ptrdiff_t, TexInfo> texture_cache_;  // <texture> elements by offset
    std::set<int> placeholders_;                       // images standing in for bad files
    std::optional<std::string> env_where_;             // the envmap, for a second one's error

    bool have_sensor_ = false;
    std::optional<glm::dmat4> camera_to_world_; // set by the sensor
    int emitter_shapes_ = 0;
    int skipped_shapes_ = 0;

    // Places and messages
    std::pair<int, int> line_col(std::ptrdiff_t offset) const;
    std::string where(pugi::xml_node n) const;
    static std::string describe(pugi::xml_node n);
    template <typename... Args>
    [[noreturn]] void error(pugi::xml_node n, fmt::format_string<Args...> f, Args&&... args) const {
        fail("{}: {}: {}", where(n), describe(n), fmt::format(f, std::forward<Args>(args)...));
    }
    void note(const std::string& key, pugi::xml_node n, std::string text);

    // Structure and attributes
    void check_structure(pugi::xml_node root) const;
    std::string expand(pugi::xml_node n, const char* attr, std::string_view raw) const;
    std::optional<std::string> attr(pugi::xml_node n, const char* name) const;
    std::string required(pugi::xml_node n, const char* name) const;
    double number(pugi::xml_node n, const char* what, std::string_view s) const;
    std::vector<double> numbers(pugi::xml_node n, const char* what, std::string_view s) const;
    glm::dvec3 vec3_attr(pugi::xml_node n, const char* name, std::optional<glm::dvec3> def) const;

    // Objects and their properties
    Obj collect(pugi::xml_node n);
    Obj::Item* prop(Obj& o, std::string_view name, std::initializer_list<std::string_view> tags,
                    const char* expected);
    std::optional<double> get_float(Obj& o, std::string_view name);
    std::optional<long long> get_int(Obj& o, std::string_view name);
    std::optional<bool> get_bool(Obj& o, std::string_view name);
    std::optional<std::string> get_string(Obj& o, std::string_view name);
    std::optional<glm::dvec3> get_point(Obj& o, std::string_view name);
    std::optional<glm::dmat4> get_transform(Obj& o, std::string_view name);
    std::optional<glm::vec3> get_color(Obj& o, std::string_view name);
    glm::vec3 reflectance(Obj& o, std::string_view name, float def);
    glm::vec3 color_value(pugi::xml_node p);
    glm::vec3 texture_color(pugi::xml_node t, std::string_view name);
    // Textures where a BSDF or emitter takes them (mitsuba_loader.h)
    TexInfo read_texture(pugi::xml_node t);
    std::optional<std::pair<TexInfo, pugi::xml_node>> nested_texture(Obj& o, std::string_view name);
    glm::vec3 reflectance_map(Obj& o, std::string_view name, float def, TextureRef& map);
    int image_file(const std::string& filename, TextureUse use, bool& missing);
    bool roughness_texture(pugi::xml_node n, const TexInfo& tex, Material& m);
    bool roughness(Obj& o, Material& m, bool anisotropic, bool textured);
    float ior(Obj& o, double int_default, double ext_default);
    double texture_mean(const TexInfo& tex);
    void opacity(Obj& o, Material& m);
    void mark_used(Obj& o, std::initializer_list<std::string_view> names);
    void finish(Obj& o);
    void skip(Obj& o); // marks everything used (for objects skipped as a whole)

    glm::dmat4 transform(pugi::xml_node t) const;
    double positive(pugi::xml_node n, const char* what, double v) const;

    // Scene parts
    void read_default(pugi::xml_node n);
    void register_id(pugi::xml_node n);
    void read_integrator(pugi::xml_node n);
    void read_sensor(pugi::xml_node n);
    Material read_bsdf(pugi::xml_node n, int depth, bool two_sided);
    Material bsdf_ref(pugi::xml_node ref, const std::string& id);
    void read_shape(pugi::xml_node n);
    void read_emitter(pugi::xml_node n);
    void read_envmap(Obj& o);
    const Scene& mesh_file(pugi::xml_node n, const std::string& filename);
    std::uint32_t shape_material(Obj& o, std::optional<glm::vec3> emission,
                                 const TextureRef& emission_map);
    void add_geometry(pugi::xml_node n, ShapeGeometry g, const glm::dmat4& m, bool flip,
                      std::uint32_t material, bool smooth);
};

// Line (1-based) and column (1-based, in bytes) of a byte offset.
std::pair<int, int> Reader::line_col(std::ptrdiff_t offset) const {
    if (offset < 0) return {0, 0};
    auto off = static_cast<std::size_t>(offset);
    auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), off);
    std::size_t line = static_cast<std::size_t>(it - line_starts_.begin()); // >= 1
    return {int(line), int(off - line_starts_[line - 1] + 1)};
}

std::string Reader::where(pugi::xml_node n) const {
    // offset_debug is the element's name; the '<' is one byte before it.
    std::ptrdiff_t off = n ? n.offset_debug() : -1;
    if (off > 0) --off;
    auto [line, col] = line_col(off);
    if (line == 0) return file_;
    return fmt::format("{}:{}:{}", file_, line, col);
}

// "<shape type="obj" id="floor">": the element with the attributes that identify it (raw
// values: a description must not fail on an undefined $parameter).
std::string Reader::describe(pugi::xml_node n) {
    std::string s = fmt::format("<{}", n.name());
    for (const char* a : {"type", "name", "id"}) {
        auto at = n.attribute(a);
        if (!at) continue;
        std::string v = at.value();
        if (v.size() > 60) v = v.substr(0, 57) + "...";
        s += fmt::format(" {}=\"{}\"", a, v);
    }
    return s + ">";
}

void Reader::note(const std::string& key, pugi::xml_node n, std::string text) {
    notes_.add(key, where(n), std::move(text));
}

// One pass over the whole tree before anything is interpreted: every element known, every
// attribute allowed where it is, transform steps only inside <transform>, properties
// without children, nesting bounded. Iterative, so deep input cannot exhaust the stack.
void Reader::check_structure(pugi::xml_node root) const {
    std::vector<std::pair<pugi::xml_node, int>> stack{{root, 1}};
    while (!stack.empty()) {
        auto [n, depth] = stack.back();
        stack.pop_back();
        const TagInfo* info = tag_info(n.name());
        if (!info)
            error(n, "unknown element <{}> (not part of Mitsuba 3's scene format)", n.name());
        if (depth > kMaxElementNesting)
            error(n, "elements are nested more than {} deep", kMaxElementNesting);
        for (pugi::xml_attribute a : n.attributes()) {
            std::string_view an = a.name();
            if (std::find(info->attrs.begin(), info->attrs.end(), an) == info->attrs.end() ||
                an.empty()) {
                std::string allowed;
                for (auto x : info->attrs)
                    if (!x.empty()) allowed += fmt::format("{}{}", allowed.empty() ? "" : ", ", x);
                error(n, "unknown attribute '{}' (<{}> takes: {})", an, n.name(),
                      allowed.empty() ? "none" : allowed);
            }
        }
        pugi::xml_node parent = n.parent();
        const bool in_transform = parent && std::string_view(parent.name()) == "transform";
        if (info->kind == TagKind::Scene && n != root)
            error(n, "<scene> may only be the root element");
        if (info->kind == TagKind::TransformOp && !in_transform)
            error(n, "<{}> belongs inside a <transform>", n.name());
        if (in_transform && info->kind != TagKind::TransformOp)
            error(n, "<transform> may only hold translate, rotate, scale, matrix and lookat");
        if (info->kind == TagKind::Default && parent != root)
            error(n, "<default> must be a child of <scene>");
        const bool leaf = info->kind == TagKind::Property || info->kind == TagKind::TransformOp ||
                          info->kind == TagKind::Default || info->kind == TagKind::Ref;
        for (pugi::xml_node c : n.children()) {
            if (c.type() != pugi::node_element) continue;
            if (leaf) error(c, "<{}> takes no child elements", n.name());
            stack.push_back({c, depth + 1});
        }
    }
}

// Substitutes $parameters in an attribute value: '$' and the longest name after it.
std::string Reader::expand(pugi::xml_node n, const char* attr, std::string_view raw) const {
    std::string out;
    std::size_t i = 0;
    while (i < raw.size()) {
        std::size_t d = raw.find('$', i);
        if (d == std::string_view::npos) {
            out.append(raw.substr(i));
            break;
        }
        out.append(raw.substr(i, d - i));
        std::size_t j = d + 1;
        while (j < raw.size() && is_ident_char(raw[j]))
            ++j;
        std::string name(raw.substr(d + 1, j - d - 1));
        if (name.empty())
            error(n, "attribute {}=\"{}\": '$' must be followed by a parameter name", attr, raw);
        auto it = params_.find(name);
        if (it == params_.end())
            error(n,
                  "attribute {}=\"{}\": undefined parameter ${} (define it with <default "
                  "name=\"{}\" value=\"...\"/> before this element)",
                  attr, raw, name, name);
        out.append(it->second);
        if (out.size() > kMaxExpansion)
            error(n, "attribute {}: expands to more than {} bytes", attr, kMaxExpansion);
        i = j;
    }
    return out;
}

std::optional<std::string> Reader::attr(pugi::xml_node n, const char* name) const {
    pugi::xml_attribute a = n.attribute(name);
    if (!a) return std::nullopt;
    return expand(n, name, a.value());
}

std::string Reader::required(pugi::xml_node n, const char* name) const {
    auto v = attr(n, name);
    if (!v) error(n, "missing attribute '{}'", name);
    return *v;
}

double Reader::number(pugi::xml_node n, const char* what, std::string_view s) const {
    auto v = numbers(n, what, s);
    if (v.size() != 1) error(n, "{} '{}': expected one number", what, s);
    return v[0];
}

// Numbers separated by commas and/or white space; each must be finite.
std::vector<double> Reader::numbers(pugi::xml_node n, const char* what, std::string_view s) const {
    std::vector<double> out;
    std::size_t i = 0;
    auto sep = [](char c) { return c == ',' || c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
    while (i < s.size()) {
        while (i < s.size() && sep(s[i]))
            ++i;
        if (i >= s.size()) break;
        std::size_t j = i;
        while (j < s.size() && !sep(s[j]))
            ++j;
        std::string_view tok = s.substr(i, j - i);
        std::string_view t = tok;
        if (!t.empty() && t[0] == '+') t.remove_prefix(1);
        double x = 0.0;
        auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
        if (ec == std::errc::result_out_of_range)
            error(n, "{} '{}': '{}' is out of the number range", what, s, tok);
        if (ec != std::errc() || end != t.data() + t.size())
            error(n, "{} '{}': '{}' is not a number", what, s, tok);
        if (!std::isfinite(x) || !std::isfinite(static_cast<float>(x)))
            error(n, "{} '{}': '{}' is not a finite float", what, s, tok);
        out.push_back(x);
        if (out.size() > 16) error(n, "{}: more than 16 numbers", what);
        i = j;
    }
    if (out.empty()) error(n, "{}: no number given", what);
    return out;
}

// A 3-vector from value="x, y, z" or the x/y/z attributes (each defaulting to 0), or the
// attribute `name` holding "x, y, z" (lookat).
glm::dvec3 Reader::vec3_attr(pugi::xml_node n, const char* name,
                             std::optional<glm::dvec3> def) const {
    auto v = attr(n, name);
    if (!v) {
        if (!def) error(n, "missing attribute '{}'", name);
        return *def;
    }
    auto xs = numbers(n, name, *v);
    if (xs.size() != 3) error(n, "attribute {}=\"{}\": expected 3 numbers", name, *v);
    return {xs[0], xs[1], xs[2]};
}

Obj Reader::collect(pugi::xml_node n) {
    Obj o;
    o.node = n;
    o.tag = n.name();
    if (auto t = attr(n, "type")) o.type = *t;
    std::set<std::string> names;
    for (pugi::xml_node c : n.children()) {
        if (c.type() != pugi::node_element) continue;
        const TagInfo* info = tag_info(c.name()); // known: check_structure ran
        switch (info->kind) {
        case TagKind::Property:
        case TagKind::Transform: {
            std::string name = required(c, "name");
            if (!names.insert(name).second) error(c, "property '{}' is given twice", name);
            o.props.push_back({name, Obj::Item{c, false}});
            break;
        }
        case TagKind::Object:
        case TagKind::Ref:
            o.nested.push_back({c, false});
            break;
        case TagKind::Unsupported:
            note(fmt::format("unsupported <{}>", c.name()), c,
                 fmt::format("<{}> is not supported; ignored", c.name()));
            break;
        default:
            error(c, "<{}> is not allowed inside <{}>", c.name(), n.name());
        }
    }
    return o;
}

// The property `name` when present: its element must be one of `tags`.
Obj::Item* Reader::prop(Obj& o, std::string_view name, std::initializer_list<std::string_view> tags,
                        const char* expected) {
    for (auto& [pn, item] : o.props) {
        if (pn != name) continue;
        item.used = true;
        std::string_view tag = item.node.name();
        if (std::find(tags.begin(), tags.end(), tag) == tags.end()) {
            std::string list;
            for (auto x : tags)
                list += fmt::format("{}<{}>", list.empty() ? "" : " or ", x);
            error(item.node, "property '{}' must be {} ({})", name, expected, list);
        }
        return &item;
    }
    return nullptr;
}

std::optional<double> Reader::get_float(Obj& o, std::string_view name) {
    auto* p = prop(o, name, {"float", "integer"}, "a number");
    if (!p) return std::nullopt;
    return number(p->node, "value", required(p->node, "value"));
}

std::optional<long long> Reader::get_int(Obj& o, std::string_view name) {
    auto* p = prop(o, name, {"integer"}, "an integer");
    if (!p) return std::nullopt;
    std::string v = required(p->node, "value");
    std::string_view t = v;
    while (!t.empty() && (t.front() == ' ' || t.front() == '\t'))
        t.remove_prefix(1);
    while (!t.empty() && (t.back() == ' ' || t.back() == '\t'))
        t.remove_suffix(1);
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);
    long long x = 0;
    auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
    if (ec == std::errc::result_out_of_range ||
        (ec == std::errc() && (x > INT32_MAX || x < INT32_MIN)))
        error(p->node, "value '{}' is out of the integer range", v);
    if (ec != std::errc() || end != t.data() + t.size() || t.empty())
        error(p->node, "value '{}' is not an integer", v);
    return x;
}

std::optional<bool> Reader::get_bool(Obj& o, std::string_view name) {
    auto* p = prop(o, name, {"boolean"}, "a boolean");
    if (!p) return std::nullopt;
    std::string v = lower(required(p->node, "value"));
    if (v == "true" || v == "1") return true;
    if (v == "false" || v == "0") return false;
    error(p->node, "value '{}' is not a boolean (true or false)", v);
}

std::optional<std::string> Reader::get_string(Obj& o, std::string_view name) {
    auto* p = prop(o, name, {"string"}, "a string");
    if (!p) return std::nullopt;
    return required(p->node, "value");
}

std::optional<glm::dvec3> Reader::get_point(Obj& o, std::string_view name) {
    auto* p = prop(o, name, {"point", "vector"}, "a point");
    if (!p) return std::nullopt;
    if (auto v = attr(p->node, "value")) {
        auto xs = numbers(p->node, "value", *v);
        if (xs.size() == 1) return glm::dvec3(xs[0]);
        if (xs.size() != 3) error(p->node, "value '{}': expected 1 or 3 numbers", *v);
        return glm::dvec3(xs[0], xs[1], xs[2]);
    }
    glm::dvec3 r(0.0);
    const char* axes[] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k)
        if (auto v = attr(p->node, axes[k])) r[k] = number(p->node, axes[k], *v);
    return r;
}

std::optional<glm::dmat4> Reader::get_transform(Obj& o, std::string_view name) {
    auto* p = prop(o, name, {"transform"}, "a transform");
    if (!p) return std::nullopt;
    return transform(p->node);
}

// A colour property: <rgb>, <spectrum>, <float>, or a texture in its place (nested with
// this name, or a <ref name=... id=...> to a texture).
std::optional<glm::vec3> Reader::get_color(Obj& o, std::string_view name) {
    if (auto* p = prop(o, name, {"rgb", "spectrum", "float", "integer"}, "a colour"))
        return color_value(p->node);
    for (auto& item : o.nested) {
        auto nm = item.node.attribute("name");
        if (!nm || expand(item.node, "name", nm.value()) != name) continue;
        item.used = true;
        std::string_view tag = item.node.name();
        if (tag == "texture") return texture_color(item.node, name);
        if (tag == "ref") {
            std::string id = required(item.node, "id");
            auto it = textures_.find(id);
            if (it == textures_.end())
                error(item.node, "no <texture id=\"{}\"> is defined before this point", id);
            return texture_color(it->second, name);
        }
        error(item.node, "property '{}' must be a colour or a texture", name);
    }
    return std::nullopt;
}

// A reflectance: a colour in [0, 1] (default `def` grey).
glm::vec3 Reader::reflectance(Obj& o, std::string_view name, float def) {
    auto c = get_color(o, name);
    if (!c) return glm::vec3(def);
    if (glm::any(glm::lessThan(*c, glm::vec3(0.0f))) ||
        glm::any(glm::greaterThan(*c, glm::vec3(1.0f)))) {
        pugi::xml_node at = o.node;
        for (auto& [pn, item] : o.props)
            if (pn == name) at = item.node;
        error(at, "{} ({}, {}, {}) is outside [0, 1]", name, c->x, c->y, c->z);
    }
    return *c;
}

glm::vec3 Reader::color_value(pugi::xml_node p) {
    std::string_view tag = p.name();
    if (tag == "spectrum" && p.attribute("filename")) {
        note("spectrum file", p, "spectra from files are not supported; 0.5 used instead");
        return glm::vec3(0.5f);
    }
    std::string v = required(p, "value");
    if (tag == "spectrum" && v.find(':') != std::string::npos) {
        // "λ:value, λ:value, ...": wavepath is RGB; the mean value as grey.
        double sum = 0;
        int count = 0;
        std::size_t i = 0;
        while (i < v.size()) {
            std::size_t j = v.find(',', i);
            if (j == std::string::npos) j = v.size();
            std::string pair = v.substr(i, j - i);
            std::size_t colon = pair.find(':');
            if (colon == std::string::npos)
                error(p, "value '{}': expected wavelength:value pairs", v);
            number(p, "wavelength", pair.substr(0, colon));
            sum += number(p, "value", pair.substr(colon + 1));
            ++count;
            if (count > 10000) error(p, "value: more than 10000 wavelength:value pairs");
            i = j + 1;
        }
        note("spectrum pairs", p,
             "sampled spectra (wavelength:value) are reduced to the mean of their values (grey)");
        return glm::vec3(float(sum / count));
    }
    auto xs = numbers(p, "value", v);
    if (xs.size() == 1) return glm::vec3(float(xs[0]));
    if (xs.size() == 3 && tag == "rgb") return glm::vec3(float(xs[0]), float(xs[1]), float(xs[2]));
    error(p, "value '{}': expected {}", v, tag == "rgb" ? "1 or 3 numbers" : "one number");
}

// A texture where wavepath takes only a constant (eta, k, a constant emitter's radiance, ...):
// its mean (a checkerboard's) or 0.5, with a warning.
glm::vec3 Reader::texture_color(pugi::xml_node t, std::string_view name) {
    Obj o = collect(t);
    glm::vec3 c(0.5f);
    if (o.type == "checkerboard") {
        glm::vec3 a = reflectance(o, "color0", 0.4f), b = reflectance(o, "color1", 0.2f);
        c = 0.5f * (a + b);
    }
    note(fmt::format("texture for {}", name), t,
         fmt::format("a texture for '{}' is not supported here (wavepath takes textures for "
                     "reflectances, roughness, opacity, normal maps and area radiance); {} is "
                     "used instead",
                     name, o.type == "checkerboard" ? "the mean of color0 and color1" : "0.5 grey"));
    skip(o);
    return c;
}

// A <texture> that a BSDF or an emitter uses (read once per element: every <ref> to it shares
// the image). bitmap: its file through scene/texture.h (relative to the XML file; raw = true
// reads it as data, else as an sRGB-encoded colour), filter_type, wrap_mode (repeat; mirror and
// clamp warn), to_uv. checkerboard: a 2 x 2 nearest image of color0 (top left, bottom right) and
// color1, which is Mitsuba's pattern on the unit square, and to_uv. Other types: a warning and
// a 0.5 grey stand-in.
TexInfo Reader::read_texture(pugi::xml_node t) {
    const std::ptrdiff_t key = t.offset_debug();
    if (auto it = texture_cache_.find(key); it != texture_cache_.end()) return it->second;
    Obj o = collect(t);
    TexInfo info;
    if (o.type == "bitmap") {
        auto filename = get_string(o, "filename");
        if (!filename) error(t, "missing <string name=\"filename\" value=\"...\"/>");
        if (filename->empty()) error(prop(o, "filename", {"string"}, "")->node, "empty filename");
        info.raw = get_bool(o, "raw").value_or(false);
        const std::string filter = get_string(o, "filter_type").value_or("bilinear");
        if (filter != "bilinear" && filter != "nearest")
            error(prop(o, "filter_type", {"string"}, "")->node,
                  "filter_type '{}' is not bilinear or nearest", filter);
        const std::string wrap = get_string(o, "wrap_mode").value_or("repeat");
        if (wrap != "repeat" && wrap != "mirror" && wrap != "clamp")
            error(prop(o, "wrap_mode", {"string"}, "")->node,
                  "wrap_mode '{}' is not repeat, mirror or clamp", wrap);
        if (wrap != "repeat")
            note("wrap_mode " + wrap, prop(o, "wrap_mode", {"string"}, "")->node,
                 fmt::format("wrap_mode '{}' is rendered as 'repeat' (wavepath's textures repeat)",
                             wrap));
        const glm::dmat4 to_uv = get_transform(o, "to_uv").value_or(glm::dmat4(1.0));
        mark_used(o, {"format", "accel"});
        info.ref.image = image_file(*filename, info.raw ? TextureUse::Data : TextureUse::Colour,
                                    info.missing);
        info.ref.image = texture_with_filter(scene_, info.ref.image, filter == "nearest");
        info.ref.uv_transform = uv_matrix(to_uv);
    } else if (o.type == "checkerboard") {
        info.checker = true;
        info.color0 = get_color(o, "color0").value_or(glm::vec3(0.4f));
        info.color1 = get_color(o, "color1").value_or(glm::vec3(0.2f));
        for (glm::vec3 c : {info.color0, info.color1})
            if (glm::any(glm::lessThan(c, glm::vec3(0.0f))))
                error(t, "checkerboard colour ({}, {}, {}) must be >= 0", c.x, c.y, c.z);
        info.mean = 0.5f * (info.color0 + info.color1);
        const glm::dmat4 to_uv = get_transform(o, "to_uv").value_or(glm::dmat4(1.0));
        scene_.textures.push_back(
            checkerboard_texture(info.color0, info.color1, "checkerboard at " + where(t)));
        info.ref.image = int(scene_.textures.size() - 1);
        info.ref.uv_transform = uv_matrix(to_uv);
    } else {
        note("texture " + o.type, t,
             fmt::format("textures of type '{}' are not supported; 0.5 grey is used instead",
                         o.type));
        skip(o);
    }
    finish(o);
    texture_cache_.emplace(key, info);
    return info;
}

// An image file for a texture or the environment, relative to the XML file's folder. A file
// that is missing or does not decode is a warning and a placeholder image (scene/texture.h):
// `missing` (told by add_texture_file's warning, given once per file).
int Reader::image_file(const std::string& filename, TextureUse use, bool& missing) {
    fs::path p(filename);
    if (p.is_relative()) p = dir_ / p;
    const std::size_t warnings = scene_.warnings.size();
    const int image = add_texture_file(scene_, p, use);
    for (std::size_t i = warnings; i < scene_.warnings.size(); ++i)
        if (scene_.warnings[i].find("texture not loaded") != std::string::npos)
            placeholders_.insert(image);
    missing = placeholders_.count(image) > 0;
    return image;
}

// The texture nested as property `name` (inline, or a <ref name=... id=...> to a top-level
// <texture>), if any.
std::optional<std::pair<TexInfo, pugi::xml_node>> Reader::nested_texture(Obj& o,
                                                                        std::string_view name) {
    for (auto& item : o.nested) {
        auto nm = item.node.attribute("name");
        if (!nm || expand(item.node, "name", nm.value()) != name) continue;
        std::string_view tag = item.node.name();
        pugi::xml_node t = item.node;
        if (tag == "ref") {
            std::string id = required(item.node, "id");
            auto it = textures_.find(id);
            if (it == textures_.end())
                error(item.node, "no <texture id=\"{}\"> is defined before this point", id);
            t = it->second;
        } else if (tag != "texture") {
            error(item.node, "property '{}' must be a colour or a texture", name);
        }
        item.used = true;
        return std::pair{read_texture(t), item.node};
    }
    return std::nullopt;
}

// A reflectance that may be a texture: a constant in [0, 1] (default `def` grey), or 1 with
// `map` set to the texture (which then is the reflectance; a checkerboard's colours must lie
// in [0, 1] too). A texture wavepath does not model gives its constant stand-in.
glm::vec3 Reader::reflectance_map(Obj& o, std::string_view name, float def, TextureRef& map) {
    auto tex = nested_texture(o, name);
    if (!tex) return reflectance(o, name, def);
    const TexInfo& ti = tex->first;
    if (ti.checker)
        for (glm::vec3 c : {ti.color0, ti.color1})
            if (glm::any(glm::greaterThan(c, glm::vec3(1.0f))))
                error(tex->second, "{}: checkerboard colour ({}, {}, {}) is outside [0, 1]", name,
                      c.x, c.y, c.z);
    if (!ti.ref.used()) return ti.mean;
    map = ti.ref;
    return glm::vec3(1.0f);
}

// The mean of a texture's luminance: a checkerboard's colours, a bitmap's texels; the
// stand-in of anything else (and of a missing file).
double Reader::texture_mean(const TexInfo& tex) {
    if (!tex.ref.used() || tex.missing) return luminance(tex.mean);
    if (tex.checker) return luminance(tex.mean);
    const Texture& src = scene_.textures[std::size_t(tex.ref.image)];
    const std::size_t count = std::size_t(src.width) * std::size_t(src.height);
    double sum = 0.0;
    for (std::size_t i = 0; i < count; ++i) sum += texel_luminance(src, i);
    return count ? sum / double(count) : 0.0;
}

// alpha of a rough kind as a texture. wavepath's roughness is alpha × G² of its roughness
// map, so the map is made from the texture's values: G = sqrt(a / a_max) per texel (a: the
// texel's luminance, Mitsuba's eval_1), alpha = a_max. Exact at the texels; filtering
// interpolates G instead of a. Returns false when every texel is below 1e-4 (the caller
// takes the smooth kind).
bool Reader::roughness_texture(pugi::xml_node n, const TexInfo& tex, Material& m) {
    const float lo = limits::kMinMicrofacetAlpha, hi = limits::kMaxMicrofacetAlpha;
    if (!tex.ref.used() || tex.missing) {
        const float a = tex.mean.x;  // the stand-in; a warning was given
        m.alpha = std::clamp(a, lo, hi);
        return a >= lo;
    }
    const Texture& src = scene_.textures[std::size_t(tex.ref.image)];
    const std::size_t count = std::size_t(src.width) * std::size_t(src.height);
    std::vector<float> a(count);
    float amax = 0.0f;
    bool clamped = false;
    for (std::size_t i = 0; i < count; ++i) {
        float v = texel_luminance(src, i);
        if (!(v >= 0.0f)) error(n, "the alpha texture has a negative or non-finite value {}", v);
        if (v > hi) v = hi, clamped = true;
        a[i] = v;
        amax = std::max(amax, v);
    }
    if (clamped) note("alpha > 2", n, fmt::format("alpha above {:g} is clamped to {:g}", hi, hi));
    if (amax < lo) return false;
    Texture r;
    r.source = "alpha of " + src.source;
    r.width = src.width;
    r.height = src.height;
    r.nearest = src.nearest;
    r.texelsf.reserve(count * 4);
    for (float v : a) {
        const float g = std::sqrt(v / amax);
        r.texelsf.insert(r.texelsf.end(), {g, g, g, 1.0f});
    }
    scene_.textures.push_back(std::move(r));
    m.alpha = amax;
    m.roughness_map = TextureRef{int(scene_.textures.size() - 1), tex.ref.uv_transform};
    return true;
}

// The microfacet parameters of roughconductor, roughdielectric and roughplastic into m:
// `distribution` (beckmann, Mitsuba's default, or ggx), Mitsuba's separable G1·G1, and the
// roughness: `alpha` (default 0.1; a texture where `textured`) or, where `anisotropic`,
// `alpha_u` and `alpha_v` (α_u along the shading frame's x). α above 2 is clamped to 2;
// returns false when α is below 1e-4 (the caller takes the smooth kind and notes it).
bool Reader::roughness(Obj& o, Material& m, bool anisotropic, bool textured) {
    const pugi::xml_node n = o.node;
    const std::string& t = o.type;
    const double lo = limits::kMinMicrofacetAlpha, hi = limits::kMaxMicrofacetAlpha;
    std::string dist = lower(get_string(o, "distribution").value_or("beckmann"));
    if (dist == "beckmann")
        m.distribution = MicrofacetModel::Beckmann;
    else if (dist == "ggx")
        m.distribution = MicrofacetModel::GGX;
    else
        error(n, "distribution '{}' is not beckmann or ggx", dist);
    m.separable_g = true;
    mark_used(o, {"sample_visible"});  // sampling only: the image's mean is the same

    auto a = get_float(o, "alpha");
    std::optional<double> au, av;
    std::optional<std::pair<TexInfo, pugi::xml_node>> alpha_tex;
    if (!a) alpha_tex = nested_texture(o, "alpha");
    if (alpha_tex && !textured)
        error(alpha_tex->second, "{} takes alpha as a number only (as Mitsuba 3 does)", t);
    if (anisotropic) {
        au = get_float(o, "alpha_u"), av = get_float(o, "alpha_v");
        // Anisotropic roughness as textures: their mean values, with a warning
        using AlphaSlot = std::pair<const char*, std::optional<double>*>;
        for (auto [an, value] : {AlphaSlot{"alpha_u", &au}, AlphaSlot{"alpha_v", &av}})
            if (auto tex = nested_texture(o, an)) {
                *value = texture_mean(tex->first);
                note("anisotropic texture", tex->second,
                     "alpha_u/alpha_v textures are not supported; their mean values are used");
            }
    } else {
        for (const char* an : {"alpha_u", "alpha_v"})
            for (auto& [pn, item] : o.props)
                if (pn == an)
                    error(item.node,
                          "{} is isotropic (Mitsuba 3 refuses alpha_u/alpha_v here); give alpha", t);
    }
    auto clamp_high = [&](double x) {
        if (x > hi) {
            note("alpha > 2", n, fmt::format("alpha above {:g} is clamped to {:g}", hi, hi));
            return hi;
        }
        return x;
    };
    if (au || av) {
        if (!(au && av)) error(n, "alpha_u and alpha_v must be given together");
        if (a || alpha_tex) error(n, "give either alpha or alpha_u/alpha_v");
        if (!(*au >= 0.0 && *av >= 0.0)) error(n, "alpha_u and alpha_v must be >= 0");
        const double u = clamp_high(*au), v = clamp_high(*av);
        if (std::max(u, v) < lo) return false;
        if (std::min(u, v) < lo)
            note("alpha_u/v small", n,
                 fmt::format("alpha_u or alpha_v below {:g} is raised to {:g}", lo, lo));
        m.alpha = float(std::max(u, lo));
        if (u != v) m.alpha_v = float(std::max(v, lo));
        return true;
    }
    if (alpha_tex) return roughness_texture(alpha_tex->second, alpha_tex->first, m);
    const double alpha = a.value_or(0.1);
    if (!(alpha >= 0.0)) error(n, "alpha {} must be >= 0", alpha);
    if (alpha < lo) return false;
    m.alpha = float(clamp_high(alpha));
    return true;
}

// The relative index of refraction int_ior / ext_ior of the dielectrics and plastics (numbers
// or Mitsuba's names; defaults as given), or `eta` (relative to vacuum).
float Reader::ior(Obj& o, double int_default, double ext_default) {
    auto ior_of = [&](const char* name, double def) {
        auto* p = prop(o, name, {"float", "integer", "string"}, "a number or a material name");
        if (!p) return def;
        std::string v = required(p->node, "value");
        if (std::string_view(p->node.name()) == "string") {
            std::string lv = lower(v);
            for (const NamedIor& x : kIors)
                if (x.name == lv) return x.ior;
            error(p->node,
                  "unknown index of refraction '{}' (known: vacuum, air, water, "
                  "bk7, diamond, ... see mitsuba_loader.h)",
                  v);
        }
        double x = number(p->node, "value", v);
        if (!(x > 0.0)) error(p->node, "{} {} must be > 0", name, x);
        return x;
    };
    double int_ior = ior_of("int_ior", int_default), ext_ior = ior_of("ext_ior", ext_default);
    if (auto eta = get_float(o, "eta")) int_ior = positive(o.node, "eta", *eta), ext_ior = 1.0;
    const double r = int_ior / ext_ior;
    if (!(r >= 0.01 && r <= 100.0))
        error(o.node, "int_ior / ext_ior = {} is out of range [0.01, 100]", r);
    return float(r);
}

// The mask BSDF's opacity (default 0.5) as wavepath's alpha cut-out with cutoff 0.5: the
// opacity (the texture's luminance) is the coverage, the A channel of an alpha map made from
// it. Mitsuba's mask is stochastic (the surface is there with probability = opacity), so this
// is exact only where the opacity is 0 or 1; anything else warns once.
void Reader::opacity(Obj& o, Material& m) {
    auto tex = nested_texture(o, "opacity");
    std::optional<float> constant;
    if (!tex) {
        constant = luminance(get_color(o, "opacity").value_or(glm::vec3(0.5f)));
    } else if (!tex->first.ref.used() || tex->first.missing) {
        constant = luminance(tex->first.mean);
        if (tex->first.missing) constant = 1.0f;  // a missing mask leaves the surface there
    }
    const pugi::xml_node at = tex ? tex->second : o.node;
    auto approximate = [&] {
        note("mask opacity", at,
             "mask opacity between 0 and 1 (stochastic in Mitsuba) is rendered as a cut-out: "
             "opacity < 0.5 is not there, >= 0.5 is opaque");
    };
    Texture a;
    if (constant) {
        const float c = *constant;
        if (!(c >= 0.0f && c <= 1.0f)) error(at, "opacity {} is outside [0, 1]", c);
        if (c != 0.0f && c != 1.0f) approximate();
        if (c >= m.alpha_cutoff) return;  // opaque: no cut-out at all
        a.source = "opacity at " + where(at);
        a.width = a.height = 1;
        a.nearest = true;
        a.texelsf = {c, c, c, c};
    } else {
        const Texture& src = scene_.textures[std::size_t(tex->first.ref.image)];
        const std::size_t count = std::size_t(src.width) * std::size_t(src.height);
        a.source = "opacity of " + src.source;
        a.width = src.width;
        a.height = src.height;
        a.nearest = src.nearest;
        a.texelsf.reserve(count * 4);
        bool binary = true;
        for (std::size_t i = 0; i < count; ++i) {
            const float r = texel(src, i, 0), g = texel(src, i, 1), b = texel(src, i, 2);
            // 0/1 texels are exactly 0/1 (the luminance weights sum to 1 only approximately)
            const bool zero = r == 0.0f && g == 0.0f && b == 0.0f;
            const bool one = r == 1.0f && g == 1.0f && b == 1.0f;
            binary = binary && (zero || one);
            const float v = zero ? 0.0f : one ? 1.0f : std::clamp(luminance({r, g, b}), 0.0f, 1.0f);
            a.texelsf.insert(a.texelsf.end(), {v, v, v, v});
        }
        if (!binary) approximate();
    }
    scene_.textures.push_back(std::move(a));
    m.alpha_map = TextureRef{int(scene_.textures.size() - 1),
                             tex ? tex->first.ref.uv_transform : glm::mat3(1.0f)};
    m.alpha_factor = 1.0f;
    m.alpha_cutoff = 0.5f;
}

void Reader::mark_used(Obj& o, std::initializer_list<std::string_view> names) {
    for (auto& [pn, item] : o.props)
        if (std::find(names.begin(), names.end(), pn) != names.end()) item.used = true;
}

void Reader::skip(Obj& o) {
    for (auto& [pn, item] : o.props)
        item.used = true;
    for (auto& item : o.nested)
        item.used = true;
}

// Whatever an object had that nothing read: one warning per kind of property.
void Reader::finish(Obj& o) {
    for (auto& [pn, item] : o.props)
        if (!item.used)
            note(fmt::format("unused {} {} {}", o.tag, o.type, pn), item.node,
                 fmt::format("property '{}' of <{} type=\"{}\"> is not supported; ignored", pn,
                             o.tag, o.type));
    for (auto& item : o.nested)
        if (!item.used)
            note(fmt::format("unused nested {} {} {}", o.tag, o.type, item.node.name()), item.node,
                 fmt::format("<{}> inside <{} type=\"{}\"> is not supported; ignored",
                             item.node.name(), o.tag, o.type));
}

// The steps of a <transform>, in document order, each applied after the previous ones.
glm::dmat4 Reader::transform(pugi::xml_node t) const {
    glm::dmat4 m(1.0);
    for (pugi::xml_node c : t.children()) {
        if (c.type() != pugi::node_element) continue;
        std::string_view tag = c.name();
        glm::dmat4 step(1.0);
        if (tag == "translate") {
            glm::dvec3 v = vec3_attr(c, "value", glm::dvec3(0.0));
            if (!c.attribute("value")) {
                const char* axes[] = {"x", "y", "z"};
                for (int k = 0; k < 3; ++k)
                    if (auto s = attr(c, axes[k])) v[k] = number(c, axes[k], *s);
            }
            step = glm::translate(glm::dmat4(1.0), v);
        } else if (tag == "scale") {
            glm::dvec3 v(1.0);
            if (auto s = attr(c, "value")) {
                auto xs = numbers(c, "value", *s);
                if (xs.size() == 1)
                    v = glm::dvec3(xs[0]);
                else if (xs.size() == 3)
                    v = glm::dvec3(xs[0], xs[1], xs[2]);
                else
                    error(c, "value '{}': expected 1 or 3 numbers", *s);
            } else {
                const char* axes[] = {"x", "y", "z"};
                for (int k = 0; k < 3; ++k)
                    if (auto s = attr(c, axes[k])) v[k] = number(c, axes[k], *s);
            }
            step = glm::scale(glm::dmat4(1.0), v);
        } else if (tag == "rotate") {
            glm::dvec3 axis(0.0);
            if (c.attribute("value")) {
                axis = vec3_attr(c, "value", std::nullopt);
            } else {
                const char* axes[] = {"x", "y", "z"};
                for (int k = 0; k < 3; ++k)
                    if (auto s = attr(c, axes[k])) axis[k] = number(c, axes[k], *s);
            }
            double angle = number(c, "angle", required(c, "angle"));
            if (glm::length(axis) == 0.0) error(c, "the rotation axis is zero");
            step = glm::rotate(glm::dmat4(1.0), angle * kPi / 180.0, glm::normalize(axis));
        } else if (tag == "matrix") {
            std::string v = required(c, "value");
            auto xs = numbers(c, "value", v);
            if (xs.size() == 16) {
                for (int r = 0; r < 4; ++r)
                    for (int col = 0; col < 4; ++col)
                        step[col][r] = xs[4 * r + col];
            } else if (xs.size() == 9) {
                for (int r = 0; r < 3; ++r)
                    for (int col = 0; col < 3; ++col)
                        step[col][r] = xs[3 * r + col];
            } else {
                error(c, "value: expected 16 (4 x 4) or 9 (3 x 3) numbers, row by row; got {}",
                      xs.size());
            }
        } else if (tag == "lookat") {
            glm::dvec3 origin = vec3_attr(c, "origin", std::nullopt);
            glm::dvec3 target = vec3_attr(c, "target", std::nullopt);
            glm::dvec3 dir = target - origin;
            if (glm::length(dir) == 0.0) error(c, "origin and target coincide");
            dir = glm::normalize(dir);
            glm::dvec3 up;
            if (c.attribute("up")) {
                up = vec3_attr(c, "up", std::nullopt);
            } else { // any up that is not parallel to dir
                up = std::abs(dir.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
            }
            glm::dvec3 left = glm::cross(up, dir);
            if (glm::length(left) < 1e-12 * std::max(1.0, glm::length(up)))
                error(c, "'up' is zero or parallel to the viewing direction");
            left = glm::normalize(left);
            glm::dvec3 new_up = glm::cross(dir, left);
            step = glm::dmat4(glm::dvec4(left, 0), glm::dvec4(new_up, 0), glm::dvec4(dir, 0),
                              glm::dvec4(origin, 1));
        }
        m = step * m;
    }
    return m;
}

double Reader::positive(pugi::xml_node n, const char* what, double v) const {
    if (!(v > 0.0)) error(n, "{} {} must be > 0", what, v);
    return v;
}

// --- Scene parts ------------------------------------------------------------------------------

void Reader::read_default(pugi::xml_node n) {
    std::string name = required(n, "name");
    if (!is_identifier(name))
        error(n, "parameter name '{}' must consist of letters, digits and '_'", name);
    std::string value = required(n, "value");
    params_.try_emplace(name, value); // an override (or an earlier default) wins
}

void Reader::register_id(pugi::xml_node n) {
    auto id = attr(n, "id");
    if (!id) return;
    if (id->empty()) error(n, "empty id");
    auto [it, fresh] = ids_.try_emplace(*id, n);
    if (!fresh) error(n, "id '{}' is already used at {}", *id, where(it->second));
}

void Reader::read_integrator(pugi::xml_node n) {
    Obj o = collect(n);
    const std::string& t = o.type;
    if (t != "path" && t != "volpath" && t != "volpathmis")
        note("integrator " + t, n,
             fmt::format("integrator '{}' is not supported; wavepath's path tracer renders the "
                         "scene with its max_depth",
                         t));
    long long md = get_int(o, "max_depth").value_or(-1);
    int depth;
    if (md < -1) {
        error(n, "max_depth {} is out of range (-1 = unbounded, or >= 0)", md);
    } else if (md == -1) {
        depth = limits::kMaxDepth;  // unbounded: Russian roulette ends the paths
    } else if (md == 0) {
        note("max_depth 0", n,
             "max_depth 0 renders nothing in Mitsuba; wavepath shows the emitters (depth 0)");
        depth = 0;
    } else if (md - 1 > limits::kMaxDepth) {
        note("max_depth cap", n,
             fmt::format("max_depth {} capped at {} bounces", md, limits::kMaxDepth));
        depth = limits::kMaxDepth;
    } else {
        depth = int(md - 1);
    }
    scene_.render.depth = depth;
    if (auto h = get_bool(o, "hide_emitters"); h && *h)
        note("hide_emitters", n, "hide_emitters is not supported; emitters stay visible");
    mark_used(o, {"rr_depth", "samples_per_pass", "timeout"});
    finish(o);
}

void Reader::read_sensor(pugi::xml_node n) {
    Obj o = collect(n);
    const bool thinlens = o.type == "thinlens";
    if (!thinlens && o.type != "perspective")
        note("sensor " + o.type, n,
             fmt::format("sensor '{}' is not supported; rendered as a perspective camera", o.type));
    glm::dmat4 m = get_transform(o, "to_world").value_or(glm::dmat4(1.0));

    // Film and sampler (nested objects)
    long long width = 768, height = 576;
    for (auto& item : o.nested) {
        std::string_view tag = item.node.name();
        if (tag == "film") {
            item.used = true;
            Obj f = collect(item.node);
            if (f.type != "hdrfilm" && f.type != "specfilm")
                note("film " + f.type, item.node,
                     fmt::format("film '{}' is read as an hdrfilm (width, height)", f.type));
            if (auto w = get_int(f, "width")) width = *w;
            if (auto h = get_int(f, "height")) height = *h;
            auto* wprop = prop(f, "width", {"integer"}, "an integer");
            if (width < 1 || width > kMaxFilmSide || height < 1 || height > kMaxFilmSide ||
                width * height > kMaxFilmPixels)
                error(wprop ? wprop->node : item.node,
                      "film size {} x {} is out of range (each side 1..{}, at most {} pixels)",
                      width, height, kMaxFilmSide, kMaxFilmPixels);
            mark_used(f, {"file_format", "pixel_format", "component_format", "banner",
                          "sample_border", "compensate", "high_quality_edges"});
            for (auto& fi : f.nested) {
                if (std::string_view(fi.node.name()) != "rfilter") continue;
                fi.used = true;
                Obj r = collect(fi.node);
                if (r.type != "box")
                    note("rfilter", fi.node,
                         fmt::format("reconstruction filter '{}' ignored: wavepath box-filters "
                                     "each pixel",
                                     r.type));
                skip(r);
            }
            finish(f);
        } else if (tag == "sampler") {
            item.used = true;
            Obj s = collect(item.node);
            if (auto c = get_int(s, "sample_count")) {
                if (*c < limits::kMinSpp || *c > kMaxSpp)
                    error(prop(s, "sample_count", {"integer"}, "")->node,
                          "sample_count {} is out of range ({}..{})", *c, limits::kMinSpp, kMaxSpp);
                scene_.render.spp = int(*c);
            }
            if (auto seed = get_int(s, "seed")) {
                if (*seed < 0) error(prop(s, "seed", {"integer"}, "")->node, "seed must be >= 0");
                scene_.render.seed = std::uint32_t(*seed);
            }
            skip(s); // sampler types and their options do not change the expectation
        }
    }

    // Field of view → vertical fov
    const double aspect = double(width) / double(height);
    auto fov = get_float(o, "fov");
    auto focal = get_string(o, "focal_length");
    if (fov && focal) error(n, "give either fov or focal_length, not both");
    std::string axis = lower(get_string(o, "fov_axis").value_or("x"));
    double f;
    if (fov) {
        f = *fov;
    } else {
        std::string s = focal.value_or("50mm");
        if (s.size() > 2 && s.substr(s.size() - 2) == "mm") s.resize(s.size() - 2);
        double mm = positive(n, "focal_length", number(n, "focal_length", s));
        f = 2.0 * std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2.0 * mm)) * 180.0 / kPi;
        axis = "diagonal";
    }
    if (!(f > 0.0 && f < 180.0)) error(n, "fov {} is out of range (0, 180) degrees", f);
    if (axis == "smaller") axis = aspect > 1.0 ? "y" : "x";
    if (axis == "larger") axis = aspect > 1.0 ? "x" : "y";
    const double t = std::tan(0.5 * f * kPi / 180.0);
    double tv; // tan(vfov / 2)
    if (axis == "x")
        tv = t / aspect;
    else if (axis == "y")
        tv = t;
    else if (axis == "diagonal")
        tv = t / std::sqrt(1.0 + aspect * aspect);
    else
        error(n, "fov_axis '{}' is not one of x, y, smaller, larger, diagonal", axis);
    const float vfov = float(2.0 * std::atan(tv) * 180.0 / kPi);
    if (!(vfov > 0.0f && vfov < 180.0f)) error(n, "vertical fov {} is out of range", vfov);

    for (const char* pp : {"principal_point_offset_x", "principal_point_offset_y"})
        if (auto v = get_float(o, pp); v && *v != 0.0)
            note("principal point", n, "principal_point_offset is not supported; ignored");
    // Thin lens (thinlens): aperture_radius (required, as in Mitsuba 3; 0 is a pinhole) and
    // focus_distance (Mitsuba's default: far_clip, 1e4), both in world units. A perspective
    // sensor reads neither.
    float lens_radius = 0.0f, focus_distance = 1.0f;
    if (thinlens) {
        auto* ap = prop(o, "aperture_radius", {"float", "integer"}, "a number");
        if (!ap)
            error(n, "sensor 'thinlens' needs aperture_radius (the lens radius in world units)");
        const double a = number(ap->node, "value", required(ap->node, "value"));
        if (!(a >= 0.0 && a <= double(std::numeric_limits<float>::max())))
            error(ap->node, "aperture_radius {} must be >= 0 (0: a pinhole)", a);
        const double far = get_float(o, "far_clip").value_or(1e4);
        auto* fp = prop(o, "focus_distance", {"float", "integer"}, "a number");
        const double fd = fp ? number(fp->node, "value", required(fp->node, "value")) : far;
        if (!(fd > 0.0 && fd <= double(std::numeric_limits<float>::max())))
            error(fp ? fp->node : n, "focus_distance {} must be > 0", fd);
        lens_radius = float(a);
        focus_distance = float(fd);
        // Mitsuba 3 refuses a scaled to_world for thinlens; here the lens stays in world units.
        for (int k = 0; k < 3; ++k)
            if (std::abs(glm::length(glm::dvec3(m[k])) - 1.0) > 1e-3) {
                note("thinlens scale", n,
                     "the thinlens sensor's to_world scales (Mitsuba 3 rejects that); "
                     "aperture_radius and focus_distance are taken in world units");
                break;
            }
    }
    mark_used(o, {"near_clip", "far_clip", "focus_distance", "aperture_radius", "srf",
                  "shutter_open", "shutter_close"});

    // Camera from the matrix: column 2 forward, column 1 up, column 0 left
    glm::dvec3 dir(m[2]), up(m[1]), left(m[0]);
    if (!(glm::length(dir) > 0.0)) error(n, "to_world has no viewing direction (column 2 is 0)");
    if (!(glm::length(glm::cross(dir, up)) > 1e-12 * glm::length(dir) * glm::length(up)))
        error(n, "to_world's up (column 1) is zero or parallel to the viewing direction");
    if (glm::dot(left, glm::cross(up, dir)) < 0.0)
        note(
            "mirrored sensor", n,
            "the sensor's to_world mirrors the image (column 0 points right); rendered unmirrored");
    scene_.camera = camera_from_matrix(glm::mat4(m), vfov, int(width), int(height));
    scene_.camera.lens_radius = lens_radius;
    scene_.camera.focus_distance = focus_distance;
    camera_to_world_ = m;
    finish(o);
}

// A BSDF element to the nearest wavepath material (table in mitsuba_loader.h).
Material Reader::read_bsdf(pugi::xml_node n, int depth, bool two_sided) {
    if (depth > kMaxBsdfNesting) error(n, "BSDFs are nested more than {} deep", kMaxBsdfNesting);
    Obj o = collect(n);
    const std::string& t = o.type;
    Material m;
    m.name = attr(n, "id").value_or(t);
    auto one_sided = [&] {
        if (!two_sided)
            note("one-sided", n,
                 "a reflecting BSDF outside <bsdf type=\"twosided\"> is one-sided in Mitsuba "
                 "(black from behind); wavepath treats it as two-sided");
    };
    // The nested BSDFs (inline or by reference), in order
    auto nested_bsdfs = [&](std::size_t need) {
        std::vector<Material> out;
        for (auto& item : o.nested) {
            std::string_view tag = item.node.name();
            if (tag == "bsdf") {
                item.used = true;
                out.push_back(read_bsdf(item.node, depth + 1, two_sided || t == "twosided"));
            } else if (tag == "ref") {
                std::string id = required(item.node, "id");
                if (!bsdfs_.count(id) && !ids_.count(id))
                    error(item.node, "no <bsdf id=\"{}\"> is defined before this point", id);
                if (bsdfs_.count(id)) {
                    item.used = true;
                    out.push_back(bsdf_ref(item.node, id));
                }
            }
        }
        if (out.size() < need)
            error(n, "needs {} nested <bsdf> (inline or <ref>), found {}", need, out.size());
        return out;
    };

    if (t == "twosided") {
        auto inner = nested_bsdfs(1);
        if (inner.size() > 1)
            note("twosided back", n,
                 "twosided with a different back-side BSDF: both sides use the first one");
        m = inner[0];
    } else if (t == "diffuse") {
        m.kind = MaterialKind::Diffuse;
        m.albedo = reflectance_map(o, "reflectance", 0.5f, m.albedo_map);
        one_sided();
    } else if (t == "conductor" || t == "roughconductor") {
        // η + i k per channel: eta/k (defaults 0 and 1: F = 1), or `material` from the table
        auto eta = get_color(o, "eta");
        auto k = get_color(o, "k");
        auto material = get_string(o, "material");
        if (eta || k) {
            if (material) error(n, "give either eta/k or material, not both");
            m.eta = eta.value_or(glm::vec3(0.0f));
            m.k = k.value_or(glm::vec3(1.0f));
            if (glm::any(glm::lessThan(m.eta, glm::vec3(0.0f))) ||
                glm::any(glm::lessThan(m.k, glm::vec3(0.0f))))
                error(n, "eta and k must be >= 0");
        } else if (material && *material != "none") {
            if (const MetalIor* metal = find_metal(*material)) {
                m.eta = metal->eta;
                m.k = metal->k;
            } else {
                note("metal " + *material, n,
                     fmt::format("conductor material '{}' is not in wavepath's table of metals; "
                                 "material \"none\" (reflectance 1) is used",
                                 *material));
            }
        }
        m.albedo = reflectance_map(o, "specular_reflectance", 1.0f, m.albedo_map);
        m.kind = MaterialKind::Conductor;
        if (t == "roughconductor") {
            if (roughness(o, m, true, true))
                m.kind = MaterialKind::RoughConductor;
            else
                note("alpha 0", n, "roughconductor with alpha < 1e-4 is rendered as a smooth conductor");
        }
        one_sided();
    } else if (t == "dielectric" || t == "thindielectric" || t == "roughdielectric") {
        // Two-sided in Mitsuba too. bk7 in air by default.
        m.ior = ior(o, 1.5046, 1.000277);
        m.albedo = reflectance_map(o, "specular_transmittance", 1.0f, m.albedo_map);
        m.specular = reflectance(o, "specular_reflectance", 1.0f);
        m.kind = t == "thindielectric" ? MaterialKind::ThinDielectric : MaterialKind::Glass;
        if (t == "roughdielectric") {
            if (roughness(o, m, true, true))
                m.kind = MaterialKind::RoughDielectric;
            else
                note("alpha 0 dielectric", n,
                     "roughdielectric with alpha < 1e-4 is rendered as a smooth dielectric");
        }
    } else if (t == "plastic" || t == "roughplastic") {
        // Polypropylene in air by default.
        m.albedo = reflectance_map(o, "diffuse_reflectance", 0.5f, m.albedo_map);
        m.specular = reflectance(o, "specular_reflectance", 1.0f);
        m.ior = ior(o, 1.49, 1.000277);
        m.nonlinear = get_bool(o, "nonlinear").value_or(false);
        m.kind = MaterialKind::Plastic;
        if (t == "roughplastic") {
            if (roughness(o, m, false, false))
                m.kind = MaterialKind::RoughPlastic;
            else
                note("alpha 0 plastic", n,
                     "roughplastic with alpha < 1e-4 is rendered as a smooth plastic");
        }
        one_sided();
    } else if (t == "principled" || t == "principledthin") {
        m.kind = MaterialKind::Diffuse;
        m.albedo = reflectance_map(o, "base_color", 0.5f, m.albedo_map);
        note("bsdf " + t, n,
             fmt::format("bsdf '{}' is rendered as diffuse with its base_color", t));
        skip(o);
    } else if (t == "normalmap") {
        // Its nested BSDF with the texture as the tangent-space normal map (Mitsuba: the map's
        // x along dp/du, y = n × x; raw = true for linear maps, as Mitsuba's documentation asks)
        m = nested_bsdfs(1)[0];
        auto tex = nested_texture(o, "normalmap");
        if (!tex) {
            if (prop(o, "normalmap", {"rgb", "spectrum", "float", "integer"}, "a texture"))
                note("constant normalmap", n,
                     "a constant normalmap is not supported; the nested BSDF is used unchanged");
            else
                error(n, "needs <texture name=\"normalmap\" type=\"bitmap\"> (the normal map)");
        } else if (tex->first.ref.used() && !tex->first.missing) {
            if (m.normal_map.used())
                note("nested normalmap", n,
                     "normalmap inside normalmap: only the outer normal map is used");
            m.normal_map = tex->first.ref;
            m.normal_scale = 1.0f;
        }
    } else if (t == "mask") {
        // Its nested BSDF with an alpha cut-out from the opacity (see opacity())
        m = nested_bsdfs(1)[0];
        if (m.alpha_map.used())
            note("nested mask", n, "mask inside mask: only the outer opacity is used");
        m.alpha_map = TextureRef{};
        opacity(o, m);
    } else if (t == "blendbsdf" || t == "bumpmap") {
        auto inner = nested_bsdfs(1);
        m = inner[0];
        note("bsdf " + t, n,
             fmt::format("bsdf '{}' is not supported; its first nested BSDF is used", t));
        skip(o);
    } else if (t == "null") {
        m.kind = MaterialKind::Diffuse;
        m.albedo = glm::vec3(0.0f);
        note("bsdf null", n, "bsdf 'null' (invisible surface) is rendered as black diffuse");
    } else {
        m.kind = MaterialKind::Diffuse;
        m.albedo = glm::vec3(0.5f);
        note("bsdf " + t, n, fmt::format("bsdf '{}' is not supported; rendered as diffuse 0.5", t));
        skip(o);
    }
    m.emission = glm::vec3(0.0f);
    finish(o);
    return m;
}

Material Reader::bsdf_ref(pugi::xml_node ref, const std::string& id) {
    auto it = bsdfs_.find(id);
    if (it == bsdfs_.end()) error(ref, "no <bsdf id=\"{}\"> is defined before this point", id);
    return it->second.material;
}

const Scene& Reader::mesh_file(pugi::xml_node n, const std::string& filename) {
    fs::path p(filename);
    if (p.is_relative()) p = dir_ / p;
    std::string key = p.lexically_normal().string();
    if (auto it = mesh_cache_.find(key); it != mesh_cache_.end()) return it->second;
    std::error_code ec;
    if (!fs::exists(p, ec)) error(n, "mesh file '{}' not found", p.string());
    if (!fs::is_regular_file(p, ec)) error(n, "mesh file '{}' is not a regular file", p.string());
    Scene s;
    try {
        s = load_mesh_file(p);
    } catch (const Error& e) {
        error(n, "{}", e.what());
    }
    // The mesh file's own materials are not used (Mitsuba ignores them too), so its note
    // about triangles without a material does not apply.
    for (auto& w : s.warnings)
        if (w.find("have no material") == std::string::npos) scene_.warnings.push_back(w);
    Scene m;  // the geometry and its attributes only
    m.positions = std::move(s.positions);
    m.triangles = std::move(s.triangles);
    m.normals = std::move(s.normals);
    m.uvs = std::move(s.uvs);
    return mesh_cache_.emplace(key, std::move(m)).first->second;
}

// The material of a shape: its BSDF (nested or <ref>), else Mitsuba's default diffuse 0.5;
// with an area emitter, a copy of it that emits.
std::uint32_t Reader::shape_material(Obj& o, std::optional<glm::vec3> emission,
                                     const TextureRef& emission_map) {
    std::optional<Material> mat;
    std::string named; // id of a referenced BSDF
    for (auto& item : o.nested) {
        std::string_view tag = item.node.name();
        if (tag != "bsdf" && tag != "ref") continue;
        std::string id;
        if (tag == "ref") {
            id = required(item.node, "id");
            if (!bsdfs_.count(id)) {
                if (ids_.count(id)) continue; // a reference to something else: reported later
                error(item.node, "no <bsdf id=\"{}\"> is defined before this point", id);
            }
        }
        item.used = true;
        if (mat) {
            note("two bsdfs", item.node, "a shape with more than one BSDF uses the first");
            continue;
        }
        if (tag == "ref") {
            mat = bsdf_ref(item.node, id);
            named = id;
        } else {
            mat = read_bsdf(item.node, 1, false);
        }
    }
    if (emission) {
        Material m = mat.value_or(Material{});
        if (!mat) {
            m.kind = MaterialKind::Diffuse;
            m.albedo = glm::vec3(0.5f);
        }
        m.emission = *emission;
        m.emission_map = emission_map;
        m.name = attr(o.node, "id").value_or(fmt::format("emitter {}", emitter_shapes_));
        ++emitter_shapes_;
        return scene_.add_material(m);
    }
    if (!named.empty()) {
        NamedBsdf& b = bsdfs_.at(named);
        if (!b.id) b.id = scene_.add_material(b.material);
        return *b.id;
    }
    if (mat) return scene_.add_material(*mat);
    if (!default_material_) {
        Material d;
        d.name = "default (diffuse 0.5)";
        d.kind = MaterialKind::Diffuse;
        d.albedo = glm::vec3(0.5f);
        default_material_ = scene_.add_material(d);
    }
    return *default_material_;
}

// Per-vertex tangents for Mitsuba's normal-map frame: the normalised sum of the unit dp/du
// of the vertex's faces, w = +1 (so the bitangent is n × t, Mitsuba's y axis); zero where
// no face has usable uvs (the upload computes one there).
std::vector<glm::vec4> dpdu_tangents(const std::vector<glm::vec3>& p,
                                     const std::vector<glm::uvec3>& tris,
                                     const std::vector<glm::vec2>& uv) {
    std::vector<glm::dvec3> sum(p.size(), glm::dvec3(0.0));
    for (const auto& t : tris) {
        const glm::dvec3 e1 = glm::dvec3(p[t.y]) - glm::dvec3(p[t.x]);
        const glm::dvec3 e2 = glm::dvec3(p[t.z]) - glm::dvec3(p[t.x]);
        const glm::dvec2 d1 = glm::dvec2(uv[t.y]) - glm::dvec2(uv[t.x]);
        const glm::dvec2 d2 = glm::dvec2(uv[t.z]) - glm::dvec2(uv[t.x]);
        const double det = d1.x * d2.y - d2.x * d1.y;
        if (!(std::abs(det) > 0.0)) continue;
        const glm::dvec3 dpdu = (e1 * d2.y - e2 * d1.y) / det;
        const double len = glm::length(dpdu);
        if (!(len > 0.0) || !std::isfinite(len)) continue;
        for (int k = 0; k < 3; ++k) sum[t[k]] += dpdu / len;
    }
    std::vector<glm::vec4> out(p.size(), glm::vec4(0.0f));
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double len = glm::length(sum[i]);
        if (len > 1e-12) out[i] = glm::vec4(glm::vec3(sum[i] / len), 1.0f);
    }
    return out;
}

// Adds a shape: positions by `m`, shading normals by its inverse transpose (negated with
// flip_normals), uvs only when the material uses a texture (a scene without textures carries
// none). A mirroring `m` or flip_normals reverses the winding, so the front stays the side the
// normals point to. smooth: the shape is a mesh without normals, which Mitsuba shades with
// smooth vertex normals (scene/normals.h, no crease).
void Reader::add_geometry(pugi::xml_node n, ShapeGeometry g, const glm::dmat4& m, bool flip,
                          std::uint32_t material, bool smooth) {
    if (scene_.triangles.size() + g.triangles.size() > kMaxTriangles)
        error(n, "the scene would have more than {} triangles", kMaxTriangles);
    const glm::dmat3 linear(m);
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
    for (auto& p : g.positions) {
        p = glm::vec3(m * glm::dvec4(glm::dvec3(p), 1.0));
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            error(n, "to_world maps a vertex to a non-finite position");
    }
    for (auto& v : g.normals) {
        const glm::dvec3 w = normal_matrix * glm::dvec3(v);
        const double len = glm::length(w);
        v = len > 0.0 && std::isfinite(len) ? glm::vec3((flip ? -w : w) / len) : glm::vec3(0.0f);
    }
    if ((glm::determinant(linear) < 0.0) != flip)
        for (auto& t : g.triangles) std::swap(t.y, t.z);
    if (!scene_.materials[material].textured() && !scene_.materials[material].anisotropic()) g.uvs.clear();
    // Normal maps in Mitsuba's frame: x along dp/du, y = n × x whatever the uvs' handedness
    // (wavepath's default follows the uvs, MikkTSpace-like): tangents dp/du with w = +1
    std::vector<glm::vec4> tangents;
    if (scene_.materials[material].normal_map.used() && !g.uvs.empty())
        tangents = dpdu_tangents(g.positions, g.triangles, g.uvs);
    const std::size_t first =
        scene_.add_mesh(g.positions, g.triangles, material, g.normals, g.uvs, tangents);
    if (smooth) smooth_normals(scene_, 180.0f, first);
}

// The analytic shapes as Mitsuba 3 defines them (src/shapes/*.cpp), in their own space, with
// Mitsuba's uvs and, for the curved ones, analytic normals.

// rectangle: [-1, 1]² at z = 0, normal +z, uv = ((x + 1) / 2, (y + 1) / 2): uv (0, 0), the
// image's top-left corner, is at (-1, -1). Flat: no normals.
ShapeGeometry rectangle_geometry() {
    ShapeGeometry g;
    Mesh q = make_quad(glm::vec3(-1, -1, 0), glm::vec3(2, 0, 0), glm::vec3(0, 2, 0));
    g.positions = std::move(q.positions);
    g.triangles = std::move(q.triangles);
    for (const auto& p : g.positions) g.uvs.push_back(0.5f * (glm::vec2(p) + 1.0f));
    return g;
}

// cube: [-1, 1]³ as Mitsuba's 24-vertex mesh, each face with its own four corners and the
// whole texture: corners (counter-clockwise seen from outside) at uv (0, 1), (1, 1), (1, 0),
// (0, 0), triangles (0, 1, 2) and (3, 0, 2) of them. Flat faces: no normals.
ShapeGeometry cube_geometry() {
    // Per face its four corners, in the order of Mitsuba's vertex table
    static const float kFaces[6][4][3] = {
        {{1, -1, -1}, {1, -1, 1}, {-1, -1, 1}, {-1, -1, -1}},  // -y
        {{1, 1, -1}, {-1, 1, -1}, {-1, 1, 1}, {1, 1, 1}},      // +y
        {{1, -1, -1}, {1, 1, -1}, {1, 1, 1}, {1, -1, 1}},      // +x
        {{1, -1, 1}, {1, 1, 1}, {-1, 1, 1}, {-1, -1, 1}},      // +z
        {{-1, -1, 1}, {-1, 1, 1}, {-1, 1, -1}, {-1, -1, -1}},  // -x
        {{1, 1, -1}, {1, -1, -1}, {-1, -1, -1}, {-1, 1, -1}},  // -z
    };
    static const glm::vec2 kUv[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    ShapeGeometry g;
    for (std::uint32_t f = 0; f < 6; ++f) {
        for (int k = 0; k < 4; ++k) {
            g.positions.emplace_back(kFaces[f][k][0], kFaces[f][k][1], kFaces[f][k][2]);
            g.uvs.push_back(kUv[k]);
        }
        const std::uint32_t b = 4 * f;
        g.triangles.emplace_back(b, b + 1, b + 2);
        g.triangles.emplace_back(b + 3, b, b + 2);
    }
    return g;
}

// sphere: the unit sphere of scene/tessellate.h (area 4 pi, normals p / |p|); uvs (only
// when textured: they split vertices at the seam and the poles) Mitsuba's.
ShapeGeometry sphere_geometry(bool with_uvs) {
    TessellatedShape t = tessellated_sphere(with_uvs);
    ShapeGeometry g;
    g.positions = std::move(t.positions);
    g.triangles = std::move(t.triangles);
    g.normals = std::move(t.normals);
    g.uvs = std::move(t.uvs);
    return g;
}

// disk: radius 1 at z = 0, normal +z, a fan of kRoundSegments triangles of area pi;
// uv = (r, phi / 2 pi) (Mitsuba's): the rim at u = 1 with the seam's vertex twice (v = 0 and
// v = 1), the centre once per triangle (at the triangle's mean angle). Flat: no normals.
ShapeGeometry disk_geometry() {
    const int n = kRoundSegments;
    // The regular n-gon of area pi: (n/2) r² sin(2 pi/n) = pi
    const double r = std::sqrt(kPi / (0.5 * n * std::sin(2.0 * kPi / n)));
    ShapeGeometry g;
    for (int i = 0; i <= n; ++i) {  // rim; vertex n is vertex 0 again
        const double a = 2.0 * kPi * (i % n) / n;
        g.positions.emplace_back(float(r * std::cos(a)), float(r * std::sin(a)), 0.0f);
        g.uvs.emplace_back(1.0f, float(i) / float(n));
    }
    for (int i = 0; i < n; ++i) {  // centre, one per triangle, counter-clockwise from +z
        g.positions.emplace_back(0.0f);
        g.uvs.emplace_back(0.0f, (float(i) + 0.5f) / float(n));
        g.triangles.emplace_back(std::uint32_t(n + 1 + i), std::uint32_t(i), std::uint32_t(i + 1));
    }
    return g;
}

// cylinder: the open tube of radius 1 (area-preserving: perimeter 2 pi) from z = 0 to 1,
// normals (x, y, 0) outward, uv = (phi / 2 pi, z) (Mitsuba's), the seam's vertices twice
// (u = 0 and u = 1).
ShapeGeometry tube_geometry() {
    const int n = kRoundSegments;
    const double r = kPi / (n * std::sin(kPi / n));
    ShapeGeometry g;
    for (int z = 0; z < 2; ++z)
        for (int i = 0; i <= n; ++i) {
            const double a = 2.0 * kPi * (i % n) / n;
            const glm::vec3 d(float(std::cos(a)), float(std::sin(a)), 0.0f);
            g.positions.emplace_back(float(r * std::cos(a)), float(r * std::sin(a)), float(z));
            g.normals.push_back(d);
            g.uvs.emplace_back(float(i) / float(n), float(z));
        }
    const auto row = std::uint32_t(n + 1);
    for (std::uint32_t i = 0; i < std::uint32_t(n); ++i) {
        const std::uint32_t bi = i, bj = i + 1, ti = i + row, tj = i + 1 + row;
        g.triangles.push_back({bi, bj, tj});
        g.triangles.push_back({bi, tj, ti});
    }
    return g;
}

void Reader::read_shape(pugi::xml_node n) {
    Obj o = collect(n);
    const std::string& t = o.type;
    static const char* const kShapes[] = {"obj",    "ply",  "rectangle", "cube",
                                          "sphere", "disk", "cylinder"};
    if (std::find(std::begin(kShapes), std::end(kShapes), t) == std::end(kShapes)) {
        note("shape " + t, n, fmt::format("shape '{}' is not supported; skipped", t));
        ++skipped_shapes_;
        skip(o);
        return;
    }
    glm::dmat4 m = get_transform(o, "to_world").value_or(glm::dmat4(1.0));
    const bool flip = get_bool(o, "flip_normals").value_or(false);
    const bool mesh = t == "obj" || t == "ply";
    // Meshes: Mitsuba's own options (face_normals: flat shading; flip_tex_coords, default
    // true: v -> 1 - v, which wavepath's mesh loaders already apply)
    const bool face_normals = mesh && get_bool(o, "face_normals").value_or(false);
    const bool flip_tex = !mesh || get_bool(o, "flip_tex_coords").value_or(true);
    mark_used(o, {"face_normals", "flip_tex_coords"});

    // The parameters of the shape's geometry, and its matrix to the world
    const Scene* file = nullptr;
    if (mesh) {
        auto filename = get_string(o, "filename");
        if (!filename) error(n, "missing <string name=\"filename\" value=\"...\"/>");
        file = &mesh_file(n, *filename);
    } else if (t == "sphere") {
        glm::dvec3 c = get_point(o, "center").value_or(glm::dvec3(0.0));
        double r = get_float(o, "radius").value_or(1.0);
        if (!(r > 0.0)) error(n, "radius {} must be > 0", r);
        m = m * glm::translate(glm::dmat4(1.0), c) * glm::scale(glm::dmat4(1.0), glm::dvec3(r));
    } else if (t == "cylinder") {
        glm::dvec3 p0 = get_point(o, "p0").value_or(glm::dvec3(0.0));
        glm::dvec3 p1 = get_point(o, "p1").value_or(glm::dvec3(0, 0, 1));
        double r = get_float(o, "radius").value_or(1.0);
        if (!(r > 0.0)) error(n, "radius {} must be > 0", r);
        glm::dvec3 d = p1 - p0;
        if (!(glm::length(d) > 0.0)) error(n, "p0 and p1 coincide");
        // Mitsuba: to_world · translate(p0) · to_frame(Frame(d / |d|)) · scale(r, r, |d|)
        auto [u, v] = coordinate_system(glm::normalize(d));
        glm::dmat4 frame(glm::dvec4(u * r, 0), glm::dvec4(v * r, 0), glm::dvec4(d, 0),
                         glm::dvec4(p0, 1));
        m = m * frame;
    }

    // Emitter (area lights) and material
    std::optional<glm::vec3> emission;
    TextureRef emission_map;
    for (auto& item : o.nested) {
        if (std::string_view(item.node.name()) != "emitter") continue;
        item.used = true;
        Obj e = collect(item.node);
        if (e.type != "area") {
            note("shape emitter " + e.type, item.node,
                 fmt::format("emitter '{}' inside a shape is not supported; ignored", e.type));
            skip(e);
            continue;
        }
        if (emission) {
            note("two emitters", item.node, "a shape with more than one emitter uses the first");
            skip(e);
            continue;
        }
        glm::vec3 l(1.0f);
        if (auto tex = nested_texture(e, "radiance")) {
            // A textured radiance: the texture is the emitted radiance (emission 1 × map)
            l = tex->first.mean;
            if (tex->first.ref.used() && !tex->first.missing) {
                l = glm::vec3(1.0f);
                emission_map = tex->first.ref;
            }
        } else {
            l = get_color(e, "radiance").value_or(glm::vec3(1.0f));
        }
        if (glm::any(glm::lessThan(l, glm::vec3(0.0f))))
            error(item.node, "radiance ({}, {}, {}) must be >= 0", l.x, l.y, l.z);
        emission = l;
        finish(e);
    }
    const std::uint32_t material = shape_material(o, emission, emission_map);
    // uvs are kept where a texture or anisotropic roughness (axes along dp/du) reads them
    const bool textured = scene_.materials[material].textured() || scene_.materials[material].anisotropic();

    // The geometry in the shape's own space
    ShapeGeometry g;
    bool smooth = false;
    if (mesh) {
        g.positions = file->positions;
        g.triangles = file->triangles;
        if (!face_normals) g.normals = file->normals;
        if (textured) {
            g.uvs = file->uvs;
            if (!flip_tex)
                for (auto& uv : g.uvs) uv.y = 1.0f - uv.y;  // undo the loaders' 1 - v
        }
        bool any_normal = false;
        for (const auto& v : g.normals) any_normal = any_normal || v != glm::vec3(0.0f);
        if (!any_normal) g.normals.clear();
        smooth = !face_normals;  // triangles without normals get smooth ones, as in Mitsuba
    } else if (t == "rectangle") {
        g = rectangle_geometry();
    } else if (t == "cube") {
        g = cube_geometry();
    } else if (t == "sphere") {
        g = sphere_geometry(textured);
    } else if (t == "disk") {
        g = disk_geometry();
    } else if (t == "cylinder") {
        g = tube_geometry();
    }
    add_geometry(n, std::move(g), m, flip, material, smooth);
    finish(o);
}

// An environment map (Mitsuba's envmap): the equirectangular image, scale and to_world.
void Reader::read_envmap(Obj& o) {
    const pugi::xml_node n = o.node;
    if (env_where_)
        error(n, "a second environment map: wavepath takes one (the first is at {})", *env_where_);
    auto filename = get_string(o, "filename");
    if (!filename) error(n, "missing <string name=\"filename\" value=\"...\"/> (the map)");
    if (filename->empty()) error(prop(o, "filename", {"string"}, "")->node, "empty filename");
    const double scale = get_float(o, "scale").value_or(1.0);
    if (!(scale >= 0.0))
        error(prop(o, "scale", {"float", "integer"}, "")->node, "scale {} must be >= 0", scale);
    const glm::dmat4 to_world = get_transform(o, "to_world").value_or(glm::dmat4(1.0));
    mark_used(o, {"filter_type", "mis_compensation"});
    // The rotation of to_world (Mitsuba's envmap turns directions by it); anything else (a
    // scale, a shear) is dropped with a warning: the columns are made orthonormal.
    glm::dmat3 r(to_world);
    const double det = glm::determinant(r);
    if (!(std::abs(det) > 1e-12) || !std::isfinite(det))
        error(prop(o, "to_world", {"transform"}, "")->node, "to_world is singular");
    const glm::dmat3 rtr = glm::transpose(r) * r;
    double off = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) off = std::max(off, std::abs(rtr[i][j] - (i == j ? 1.0 : 0.0)));
    if (off > 1e-5) {
        note("envmap to_world", prop(o, "to_world", {"transform"}, "")->node,
             "the envmap's to_world is not a rotation; only its rotation is used");
        const glm::dvec3 x = glm::normalize(r[0]);
        const glm::dvec3 y = glm::normalize(r[1] - glm::dot(r[1], x) * x);
        r = glm::dmat3(x, y, det > 0.0 ? glm::cross(x, y) : -glm::cross(x, y));
    }
    Environment env;
    bool missing = false;
    env.image = image_file(*filename, TextureUse::Colour, missing);
    env.scale = float(scale);
    env.to_world = glm::mat3(r);
    scene_.environment = env;
    env_where_ = where(n);
    finish(o);
}

void Reader::read_emitter(pugi::xml_node n) {
    Obj o = collect(n);
    if (o.type == "envmap") {
        read_envmap(o);
        return;
    }
    if (o.type == "constant") {
        glm::vec3 l = get_color(o, "radiance").value_or(glm::vec3(1.0f));
        if (glm::any(glm::lessThan(l, glm::vec3(0.0f))))
            error(n, "radiance ({}, {}, {}) must be >= 0", l.x, l.y, l.z);
        scene_.background += l;
        finish(o);
        return;
    }
    if (o.type == "area")
        note("area outside shape", n,
             "an area emitter outside a <shape> has nothing to emit from; ignored");
    else
        note("emitter " + o.type, n,
             fmt::format("emitter '{}' is not supported; skipped (wavepath has area lights, "
                         "a constant background and an environment map)",
                         o.type));
    skip(o);
}

Scene Reader::read() {
    // Parse: pugixml copies the buffer; offsets stay those of the text (no conversion).
    pugi::xml_document doc;
    pugi::xml_parse_result res =
        doc.load_buffer(text_.data(), text_.size(), pugi::parse_default, pugi::encoding_utf8);
    if (!res) {
        auto [line, col] = line_col(res.offset);
        fail("{}:{}:{}: malformed XML: {}", file_, line, col, res.description());
    }
    pugi::xml_node root = doc.document_element();
    if (!root) fail("{}: no root element (expected <scene version=\"3.0.0\">)", file_);
    if (std::string_view(root.name()) != "scene")
        fail("{}: {}: the root element must be <scene>", where(root), describe(root));
    check_structure(root);
    scene_.name = fs::path(file_).filename().string();
    if (scene_.name.empty()) scene_.name = file_;

    // Version: Mitsuba 3 requires it; older files used other parameter names
    std::string version = required(root, "version");
    {
        int major = 0;
        auto [end, ec] = std::from_chars(version.data(), version.data() + version.size(), major);
        if (ec != std::errc()) error(root, "version '{}' is not a version number", version);
        if (major < 2)
            note("version", root,
                 fmt::format("version {} predates Mitsuba 2; its parameters are read with "
                             "Mitsuba 3's names",
                             version));
    }
    scene_.render.depth = limits::kMaxDepth; // Mitsuba's default integrator: path, max_depth -1

    // Top-level elements in document order
    for (pugi::xml_node c : root.children()) {
        if (c.type() != pugi::node_element) continue;
        std::string_view tag = c.name();
        const TagInfo* info = tag_info(tag);
        if (info->kind == TagKind::Default) {
            read_default(c);
            continue;
        }
        if (info->kind == TagKind::Object) register_id(c);
        if (tag == "integrator") {
            read_integrator(c);
        } else if (tag == "sensor") {
            if (have_sensor_) {
                note("second sensor", c, "more than one sensor: the first is used");
                continue;
            }
            have_sensor_ = true;
            read_sensor(c);
        } else if (tag == "bsdf") {
            Material m = read_bsdf(c, 1, false);
            if (auto id = attr(c, "id"))
                bsdfs_[*id] = NamedBsdf{m, std::nullopt};
            else
                note("anonymous bsdf", c, "a top-level <bsdf> without an id is never used");
        } else if (tag == "texture") {
            if (auto id = attr(c, "id")) textures_[*id] = c;
        } else if (tag == "shape") {
            read_shape(c);
        } else if (tag == "emitter") {
            read_emitter(c);
        } else if (info->kind == TagKind::Unsupported) {
            note(fmt::format("unsupported <{}>", tag), c,
                 fmt::format("<{}> is not supported; ignored", tag));
        } else {
            note(fmt::format("top-level <{}>", tag), c,
                 fmt::format("<{}> at the top level is not supported; ignored", tag));
        }
    }

    if (scene_.triangles.empty())
        fail("{}: no shape that wavepath can render ({} skipped)", file_, skipped_shapes_);
    if (!have_sensor_) {
        scene_.camera = frame_bounds(scene_.bounds(), file_);
        note("no sensor", root,
             "no <sensor>: the camera frames the scene from +z (800 x 600, 40 degrees)");
    }
    scene_.prune_textures();  // the sources of derived roughness and opacity maps, textures of
                              // BSDFs no shape uses
    notes_.append_to(scene_.warnings);
    validate_scene(scene_);
    return std::move(scene_);
}

} // namespace

Scene parse_mitsuba(std::string_view xml, const fs::path& origin, const MitsubaParams& params) {
    Reader r(xml, origin, params);
    return r.read();
}

Scene parse_mitsuba(std::string_view xml, const fs::path& origin) {
    return parse_mitsuba(xml, origin, {});
}

Scene load_mitsuba(const fs::path& path, const MitsubaParams& params) {
    return parse_mitsuba(read_file(path, kMaxFileBytes), path, params);
}

Scene load_mitsuba(const fs::path& path) {
    return load_mitsuba(path, {});
}

} // namespace wp
