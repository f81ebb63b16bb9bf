#include "scene/pbrt_loader.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <glm/gtc/matrix_transform.hpp>

#include "scene/load.h"
#include "scene/notes.h"
#include "scene/metals.h"
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

// Tessellation of the disk (and annulus): segments around.
constexpr int kDiskSegments = 128;
// BSDF nesting of the mix material (a mix of mixes ...).
constexpr int kMaxMaterialNesting = 16;

// --- Colour ---------------------------------------------------------------------------------

// CIE 1931 2° colour matching functions: the multi-lobe Gaussian fit of Wyman, Sloan and
// Shirley, "Simple Analytic Approximations to the CIE XYZ Color Matching Functions" (JCGT
// 2(2), 2013), within about 1 % of the tables (the tables are not carried here).
glm::dvec3 cie_xyz(double l) {
    auto g = [l](double mu, double s1, double s2) {
        const double t = (l - mu) / (l < mu ? s1 : s2);
        return std::exp(-0.5 * t * t);
    };
    return {1.056 * g(599.8, 37.9, 31.0) + 0.362 * g(442.0, 16.0, 26.7) -
                0.065 * g(501.1, 20.4, 26.2),
            0.821 * g(568.8, 46.9, 40.5) + 0.286 * g(530.9, 16.3, 31.1),
            1.217 * g(437.0, 11.8, 36.0) + 0.681 * g(459.0, 26.0, 13.8)};
}

// XYZ of a spectrum given as a function of the wavelength in nm, 360..830 nm in 1 nm steps.
glm::dvec3 spectrum_xyz(const std::function<double(double)>& s) {
    glm::dvec3 sum(0.0);
    for (int l = 360; l <= 830; ++l) sum += cie_xyz(double(l)) * s(double(l));
    return sum;
}

// Linear sRGB (D65) from CIE XYZ (IEC 61966-2-1).
glm::dvec3 xyz_to_srgb(glm::dvec3 c) {
    return {3.2404542 * c.x - 1.5371385 * c.y - 0.4985314 * c.z,
            -0.9692660 * c.x + 1.8760108 * c.y + 0.0415560 * c.z,
            0.0556434 * c.x - 0.2040259 * c.y + 1.0572252 * c.z};
}

// The linear sRGB colour of luminance Y = 1 with the chromaticity of `xyz` (pbrt-v4 scales
// every spectral light to 1 nit: DiffuseAreaLight / UniformInfiniteLight::Create divide
// `scale` by SpectrumToPhotometric). Negative channels (outside the sRGB gamut) become 0.
glm::vec3 unit_luminance_rgb(glm::dvec3 xyz) {
    if (!(xyz.y > 0.0)) return glm::vec3(0.0f);
    return glm::vec3(glm::max(xyz_to_srgb(xyz / xyz.y), glm::dvec3(0.0)));
}

glm::vec3 chromaticity_rgb(double x, double y) {
    return unit_luminance_rgb({x / y, 1.0, (1.0 - x - y) / y});
}

// Planck's law (shape only; the caller normalises).
double planck(double lambda_nm, double t) {
    const double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
    const double l = lambda_nm * 1e-9;
    return (2.0 * h * c * c) / (std::pow(l, 5) * (std::exp((h * c) / (l * kb * t)) - 1.0));
}

// pbrt-v4's named illuminants by their CIE 1931 chromaticities (CIE 15:2004; ACES D60 from
// SMPTE ST 2065-1): with the luminance normalised to 1, an illuminant's RGB depends on its
// chromaticity only.
struct NamedIlluminant {
    std::string_view name;
    double x, y;
};
constexpr NamedIlluminant kIlluminants[] = {
    {"stdillum-A", 0.44757, 0.40745},  {"stdillum-D50", 0.34567, 0.35850},
    {"stdillum-F1", 0.31310, 0.33727}, {"stdillum-F2", 0.37208, 0.37529},
    {"stdillum-F3", 0.40910, 0.39430}, {"stdillum-F4", 0.44018, 0.40329},
    {"stdillum-F5", 0.31379, 0.34531}, {"stdillum-F6", 0.37790, 0.38835},
    {"stdillum-F7", 0.31292, 0.32933}, {"stdillum-F8", 0.34588, 0.35875},
    {"stdillum-F9", 0.37417, 0.37281}, {"stdillum-F10", 0.34609, 0.35986},
    {"stdillum-F11", 0.38052, 0.37713}, {"stdillum-F12", 0.43695, 0.40441},
    {"illum-acesD60", 0.32168, 0.33767},
};

// pbrt-v4's named glasses (its "glass-*" spectra are Sellmeier fits of the Schott catalogue
// glasses): the index at the helium d line, 587.6 nm (Schott catalogue n_d).
struct NamedGlass {
    std::string_view name;
    double nd;
};
constexpr NamedGlass kGlasses[] = {
    {"glass-BK7", 1.5168},   {"glass-BAF10", 1.67003}, {"glass-FK51A", 1.48656},
    {"glass-LASF9", 1.85025}, {"glass-F5", 1.67270},   {"glass-F10", 1.72825},
    {"glass-F11", 1.78472},
};

// Channel c of texel i, linear (scene/texture.h).
float texel(const Texture& t, std::size_t i, int c) { return texel_linear(t, i, c); }

// --- pbrt-v4's equal-area octahedral sphere mapping (Clarberg 2008) --------------------------

// pbrt-v4 EqualAreaSphereToSquare (src/pbrt/util/math.cpp), with the exact arctangent where
// pbrt uses a polynomial fit of it (they differ by about 1e-6).
glm::dvec2 equal_area_sphere_to_square(glm::dvec3 d) {
    const double x = std::abs(d.x), y = std::abs(d.y), z = std::abs(d.z);
    const double r = std::sqrt(std::max(0.0, 1.0 - z));
    const double a = std::max(x, y);
    const double b = a == 0.0 ? 0.0 : std::min(x, y) / a;
    double phi = std::atan(b) * 2.0 / kPi;
    if (x < y) phi = 1.0 - phi;
    double v = phi * r, u = r - v;
    if (d.z < 0.0) {
        std::swap(u, v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    u = std::copysign(u, d.x);
    v = std::copysign(v, d.y);
    return {0.5 * (u + 1.0), 0.5 * (v + 1.0)};
}

// An equal-area square map (pbrt-v4's ImageInfiniteLight) resampled to wavepath's
// equirectangular map (kernels/shared/envmap.h: column i at u = (i + 1/2) / W, row j at
// v = j / (H - 1), direction (sin φ sin θ, cos θ, -cos φ sin θ), θ = πv, φ = 2πu), 2N x N
// for an N x N map (N at most limits::kMaxEnvResampleHeight). Each texel is pbrt's bilinear lookup (Image::Bilerp with WrapMode
// OctahedralSphere) at EqualAreaSphereToSquare of the texel's direction, read as a direction
// in the light's own space; the caller sets the environment's rotation to the light's.
Texture equal_area_to_equirect(const Texture& src) {
    const int n = src.width;
    const int h = std::clamp(n, 2, limits::kMaxEnvResampleHeight), w = 2 * h;
    auto fetch = [&](int x, int y, int c) {
        // pbrt-v4 RemapPixelCoords, WrapMode::OctahedralSphere
        if (x < 0) {
            x = -x;
            y = n - 1 - y;
        } else if (x >= n) {
            x = 2 * n - 1 - x;
            y = n - 1 - y;
        }
        if (y < 0) {
            x = n - 1 - x;
            y = -y;
        } else if (y >= n) {
            x = n - 1 - x;
            y = 2 * n - 1 - y;
        }
        x = std::clamp(x, 0, n - 1);
        y = std::clamp(y, 0, n - 1);
        return texel(src, std::size_t(y) * std::size_t(n) + std::size_t(x), c);
    };
    Texture out;
    out.source = src.source + " (equal-area map resampled to equirectangular)";
    out.width = w;
    out.height = h;
    out.texelsf.resize(std::size_t(w) * std::size_t(h) * 4);
    for (int j = 0; j < h; ++j) {
        const double theta = kPi * double(j) / double(h - 1);
        for (int i = 0; i < w; ++i) {
            const double phi = 2.0 * kPi * (double(i) + 0.5) / double(w);
            const glm::dvec3 d(std::sin(phi) * std::sin(theta), std::cos(theta),
                               -std::cos(phi) * std::sin(theta));
            const glm::dvec2 st = equal_area_sphere_to_square(d);
            const double x = st.x * n - 0.5, y = st.y * n - 0.5;
            const double fx = std::floor(x), fy = std::floor(y);
            const int xi = int(fx), yi = int(fy);
            const double dx = x - fx, dy = y - fy;
            float* o = &out.texelsf[(std::size_t(j) * std::size_t(w) + std::size_t(i)) * 4];
            for (int c = 0; c < 3; ++c)
                o[c] = float((1 - dx) * (1 - dy) * fetch(xi, yi, c) +
                             dx * (1 - dy) * fetch(xi + 1, yi, c) +
                             (1 - dx) * dy * fetch(xi, yi + 1, c) + dx * dy * fetch(xi + 1, yi + 1, c));
            o[3] = 1.0f;
        }
    }
    return out;
}

// --- Tokens and parameters ------------------------------------------------------------------

struct Loc {
    int file = -1;
    int line = 0, col = 0;
};

// EndImport: the end of an Imported file, returned once after its last token so that its last
// directive is done before the importing file's graphics state comes back.
enum class TokKind { Word, String, Open, Close, EndImport };

struct Token {
    TokKind kind = TokKind::Word;
    std::string_view text;  // a string's contents without the quotes, escapes decoded
    Loc loc;
};

struct Param {
    std::string type, name;
    Loc loc;
    std::vector<double> nums;
    std::vector<std::string> strs;
    std::vector<char> bools;
    bool used = false;
    std::string decl() const { return type + " " + name; }
};

// A directive with its parameter list: Shape "sphere" "float radius" 2 ...
struct Directive {
    std::string what;  // "Shape"
    std::string type;  // "sphere" (the texture class for Texture)
    Loc loc;
    std::vector<Param> params;
    std::string describe() const {
        return type.empty() ? what : fmt::format("{} \"{}\"", what, type);
    }
};

// A spectrum-valued parameter after reading: an RGB value or a texture's name.
struct SpecVal {
    glm::vec3 rgb{0.0f};
    std::string texture;  // non-empty: "texture NAME"
    Loc loc;
};

enum class SpecUse {
    Reflectance,  // albedo-like: clamped to [0, 1] by the caller
    Unbounded,    // eta, k
    Light,        // L: spectral values normalised to luminance 1 as pbrt-v4 does
};

// A texture after resolution: image × scale, or a constant.
struct TexResult {
    bool image = false;
    TextureRef ref;
    glm::vec3 scale{1.0f};      // multiplies the image (imagemap "scale", scale textures)
    glm::vec3 constant{0.5f};   // when !image
    bool missing = false;       // a file that did not load (placeholder image)
};

struct TexDef {
    Directive d;
    bool is_float = false;
    bool resolving = false, resolved = false;
    TexResult result;
};

struct MatDef {
    std::string name;  // MakeNamedMaterial's name; the type for anonymous ones
    Directive d;
    bool resolving = false, resolved = false;
    Material m;
    bool interface = false;
};

// What a shape's triangles use: a material (by reference) and maybe an area light.
struct MatRef {
    bool named = false;
    std::string name;  // named material
    int anon = 0;      // index into anon_ (when !named)
    Loc loc;           // the Material / NamedMaterial directive
};

struct AreaLight {
    glm::vec3 radiance{0.0f};
    bool twosided = false;
    Loc loc;
};

struct Slot {
    int matref = 0;
    std::optional<AreaLight> light;
};

struct GState {
    glm::dmat4 ctm{1.0};
    bool reverse = false;
    int matref = 0;
    std::optional<AreaLight> area;
    std::map<std::string, std::vector<Param>> attrs;  // Attribute defaults per target
    bool active_start = true, active_end = true;
};

// A shape's geometry in its own space.
struct Geometry {
    std::vector<glm::vec3> positions;
    std::vector<glm::uvec3> triangles;
    std::vector<glm::vec3> normals;  // empty or one per position
    std::vector<glm::vec2> uvs;      // empty or one per position (wavepath's convention)
    bool face_forward = false;       // a mesh with N: each triangle's front faces its normals
    bool analytic = false;           // sphere, disk: ReverseOrientation turns the normals too
};

struct InstanceShape {
    Geometry g;  // in the object's space, winding final
    int slot = 0;
};

struct ObjectDef {
    std::vector<InstanceShape> shapes;
    std::size_t triangles = 0;
    Loc loc;
};

struct InstanceUse {
    std::string name;
    glm::dmat4 ctm;
    Loc loc;
};

struct Source {
    std::string_view text;
    std::size_t pos = 0;
    int line = 1, col = 1;
    int file = 0;
    std::string key;  // canonical path, for cycles
    bool import = false;
    std::size_t saved_depth = 0;  // import: the state stack depth to return to
    GState saved_state;           // import: the importing file's state
    bool saved_object = false;    // import: inside ObjectBegin when it began
    Loc loc;                      // the Include / Import directive
};

bool is_space(char c) { return c == ' ' || c == '\n' || c == '\t' || c == '\r'; }

std::optional<double> parse_number(std::string_view s) {
    if (!s.empty() && s[0] == '+') s.remove_prefix(1);
    if (s.empty()) return std::nullopt;
    double x = 0.0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), x);
    if (ec == std::errc::result_out_of_range) return HUGE_VAL;  // reported as not finite
    if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return x;
}

glm::vec3 clamp01(glm::vec3 v) { return glm::clamp(v, glm::vec3(0.0f), glm::vec3(1.0f)); }

// --- The reader -----------------------------------------------------------------------------

class Reader {
  public:
    Reader(std::string_view text, const fs::path& origin) : dir_(origin.parent_path()) {
        files_.push_back(origin.string());
        Source s;
        s.text = text;
        s.file = 0;
        s.key = key_of(origin);
        if (s.text.size() >= 3 && s.text.substr(0, 3) == "\xEF\xBB\xBF") s.pos = 3;  // UTF-8 BOM
        sources_.push_back(std::move(s));
        stack_.reserve(16);
    }

    Scene read();

  private:
    // Files and places
    fs::path dir_;
    std::vector<std::string> files_;
    std::deque<std::string> texts_;    // included files' contents (stable)
    std::deque<std::string> escaped_;  // strings with escapes, decoded (stable)
    std::vector<Source> sources_;
    std::vector<Source> ended_imports_;  // imported files read to their end, not yet closed
    std::optional<Token> pending_;
    int includes_ = 0;

    // Warnings, aggregated by kind
    NoteLog notes_;  // warnings, once per kind

    // Graphics state
    GState gs_;
    std::vector<GState> stack_;
    std::vector<std::pair<char, Loc>> pushes_;  // 'a' attribute, 't' transform, 'o' object
    std::map<std::string, glm::dmat4> coord_systems_;
    bool in_world_ = false;

    // Rendering options
    std::optional<Directive> camera_, film_, sampler_, integrator_;
    glm::dmat4 camera_ctm_{1.0};

    // Materials and textures
    std::vector<MatDef> anon_;
    std::map<std::string, MatDef> named_;
    std::vector<MatRef> matrefs_;
    std::map<std::string, int> named_refs_;  // NamedMaterial name -> its MatRef
    std::vector<Slot> slots_;
    std::map<std::pair<int, int>, int> plain_slots_;  // (matref, light or -1) → slot
    std::vector<TexDef> texdefs_;
    std::map<std::string, int> spectrum_tex_, float_tex_;

    // Instancing
    std::map<std::string, ObjectDef> objects_;
    std::optional<std::string> current_object_;
    std::vector<InstanceUse> instances_;
    std::size_t object_triangles_ = 0;  // in all object definitions

    std::map<std::string, Scene> mesh_cache_;
    std::optional<std::string> env_where_;
    int skipped_shapes_ = 0;
    Scene scene_;

    // Places and messages
    std::string where(const Loc& l) const {
        if (l.file < 0) return files_[0];
        return fmt::format("{}:{}:{}", files_[std::size_t(l.file)], l.line, l.col);
    }
    template <typename... Args>
    [[noreturn]] void error(const Loc& l, fmt::format_string<Args...> f, Args&&... args) const {
        fail("{}: {}", where(l), fmt::format(f, std::forward<Args>(args)...));
    }
    void note(const std::string& key, const Loc& l, std::string text) {
        notes_.add(key, where(l), std::move(text));
    }
    static std::string key_of(const fs::path& p) {
        std::error_code ec;
        fs::path c = fs::weakly_canonical(p, ec);
        return (ec ? p : c).lexically_normal().string();
    }

    // Tokens
    std::optional<Token> next_token();
    void end_source();
    void end_import(const Token& t);
    Token require_token(const Loc& at, const char* what);
    std::string read_string(const Token& dir);
    double read_number(const Token& dir);
    std::vector<double> read_numbers(const Token& dir, int n, bool brackets);
    std::vector<Param> read_params();
    void add_value(Param& p, const Token& t);
    void check_param(Param& p);
    Directive read_directive(const Token& t, bool typed);

    // Parameters
    Param* param(Directive& d, std::string_view name, std::initializer_list<std::string_view> types);
    double one(const Directive& d, const Param& p) const;
    std::optional<double> get_float(Directive& d, std::string_view name);
    std::optional<int> get_int(Directive& d, std::string_view name);
    std::optional<bool> get_bool(Directive& d, std::string_view name);
    std::optional<std::string> get_string(Directive& d, std::string_view name);
    std::optional<SpecVal> get_spectrum(Directive& d, std::string_view name, SpecUse use,
                                        bool texture_ok);
    void finish(Directive& d);
    void apply_attributes(Directive& d, const char* target);

    // Directives
    void parse();
    void include(const Token& t, bool import);
    void transform_step(const glm::dmat4& m);
    void push(char kind, const Loc& l);
    void pop(char kind, const Token& t);
    void shape(Directive d);
    void light_source(Directive d);
    void area_light(Directive d);
    void texture(const Token& t);
    int current_slot(const Loc& l);

    // Shapes
    Geometry triangle_mesh(Directive& d, bool bilinear);
    const Scene& mesh_file(Directive& d, const std::string& filename);
    void add_geometry(const Loc& l, Geometry g, const glm::dmat4& m, bool reverse, int slot,
                      bool to_object);
    void check_triangles(const Loc& l, std::size_t more) const;

    // Materials and textures (resolved at the end)
    Material& resolve_material(const MatRef& r, int depth, bool* interface);
    Material build_material(MatDef& def, int depth, bool* interface);
    TexResult& resolve_texture(const std::string& name, bool is_float, const Loc& use, int depth);
    TexResult build_texture(TexDef& def, int depth);
    glm::vec3 texture_mean(const TexResult& t);
    glm::vec3 reflectance(Directive& d, std::string_view name, float def, TextureRef* map,
                          int depth);
    float float_param(Directive& d, std::string_view name, float def, int depth);
    void roughness(Directive& d, const std::string& prefix, Material& m, MaterialKind smooth,
                   MaterialKind rough, int depth);
    float ior(Directive& d, std::string_view name, float def);
    void conductor(Directive& d, const std::string& prefix, Material& m, int depth);

    // The end
    void instantiate();
    void resolve_slots();
    void make_camera();
};

// --- Tokens ---------------------------------------------------------------------------------

void Reader::end_source() {
    Source s = std::move(sources_.back());
    sources_.pop_back();
    if (s.import) ended_imports_.push_back(std::move(s));
}

// The end of an imported file: it may not leave blocks open, and its graphics state does not
// leak into the importing file.
void Reader::end_import(const Token& t) {
    Source s = std::move(ended_imports_.back());
    ended_imports_.pop_back();
    if (stack_.size() != s.saved_depth)
        error(pushes_.back().second, "this block is still open at the end of the imported file");
    if (current_object_ && !s.saved_object)
        error(t.loc, "the imported file leaves ObjectBegin \"{}\" open", *current_object_);
    gs_ = std::move(s.saved_state);
}

std::optional<Token> Reader::next_token() {
    if (pending_) return std::exchange(pending_, std::nullopt);
    while (!sources_.empty()) {
        Source& s = sources_.back();
        auto advance = [&s]() {
            const char c = s.text[s.pos++];
            if (c == '\n') {
                ++s.line;
                s.col = 1;
            } else {
                ++s.col;
            }
            return c;
        };
        // Skip space and comments
        while (s.pos < s.text.size()) {
            const char c = s.text[s.pos];
            if (is_space(c)) {
                advance();
            } else if (c == '#') {
                while (s.pos < s.text.size() && s.text[s.pos] != '\n' && s.text[s.pos] != '\r')
                    advance();
            } else {
                break;
            }
        }
        if (s.pos >= s.text.size()) {
            const bool import = s.import;
            Token end;
            end.kind = TokKind::EndImport;
            end.text = "end of the imported file";
            end.loc = Loc{s.file, s.line, s.col};
            end_source();
            if (import) return end;
            continue;
        }
        Token t;
        t.loc = Loc{s.file, s.line, s.col};
        const char c = s.text[s.pos];
        if (c == '[' || c == ']') {
            advance();
            t.kind = c == '[' ? TokKind::Open : TokKind::Close;
            t.text = c == '[' ? "[" : "]";
            return t;
        }
        if (c == '"') {
            advance();
            const std::size_t begin = s.pos;
            bool escaped = false;
            while (true) {
                if (s.pos >= s.text.size()) error(t.loc, "the string never ends (end of file)");
                const char ch = s.text[s.pos];
                if (ch == '\n' || ch == '\r') error(t.loc, "the string does not end on its line");
                if (ch == '"') break;
                if (ch == '\\') {
                    escaped = true;
                    advance();
                    if (s.pos >= s.text.size())
                        error(t.loc, "the string never ends (end of file after '\\')");
                }
                advance();
            }
            std::string_view raw = s.text.substr(begin, s.pos - begin);
            advance();  // the closing quote
            t.kind = TokKind::String;
            if (!escaped) {
                t.text = raw;
                return t;
            }
            std::string out;
            for (std::size_t i = 0; i < raw.size(); ++i) {
                if (raw[i] != '\\') {
                    out.push_back(raw[i]);
                    continue;
                }
                const char e = raw[++i];
                switch (e) {
                case 'b': out.push_back('\b'); break;
                case 'f': out.push_back('\f'); break;
                case 'n': out.push_back('\n'); break;
                case 'r': out.push_back('\r'); break;
                case 't': out.push_back('\t'); break;
                case '\\': out.push_back('\\'); break;
                case '\'': out.push_back('\''); break;
                case '"': out.push_back('"'); break;
                default:
                    error(t.loc, "unknown escape '\\{}' in a string (pbrt knows \\b \\f \\n \\r "
                                 "\\t \\\\ \\' \\\")",
                          e);
                }
            }
            escaped_.push_back(std::move(out));
            t.text = escaped_.back();
            return t;
        }
        // A word: a directive, a number, true/false
        const std::size_t begin = s.pos;
        while (s.pos < s.text.size()) {
            const char ch = s.text[s.pos];
            if (is_space(ch) || ch == '"' || ch == '[' || ch == ']') break;
            advance();
        }
        t.kind = TokKind::Word;
        t.text = s.text.substr(begin, s.pos - begin);
        return t;
    }
    return std::nullopt;
}

std::string token_desc(const Token& t) {
    if (t.kind == TokKind::EndImport) return "the end of the imported file";
    std::string s(t.text.substr(0, 40));
    if (t.text.size() > 40) s += "...";
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 32 || c == 127) c = '?';
    return t.kind == TokKind::String ? "\"" + s + "\"" : "'" + s + "'";
}

Token Reader::require_token(const Loc& at, const char* what) {
    auto t = next_token();
    if (!t) error(at, "{} (the file ends here)", what);
    return *t;
}

std::string Reader::read_string(const Token& dir) {
    Token t = require_token(dir.loc, fmt::format("{}: expected a quoted string", dir.text).c_str());
    if (t.kind != TokKind::String)
        error(t.loc, "{}: expected a quoted string, found {}", dir.text, token_desc(t));
    return std::string(t.text);
}

double Reader::read_number(const Token& dir) {
    Token t = require_token(dir.loc, fmt::format("{}: expected a number", dir.text).c_str());
    if (t.kind != TokKind::Word)
        error(t.loc, "{}: expected a number, found {}", dir.text, token_desc(t));
    auto v = parse_number(t.text);
    if (!v) error(t.loc, "{}: {} is not a number", dir.text, token_desc(t));
    if (!std::isfinite(*v) || !std::isfinite(float(*v)))
        error(t.loc, "{}: {} is not a finite number", dir.text, token_desc(t));
    return *v;
}

// n numbers, inside [ ] when `brackets` (pbrt-v4 requires them for Transform and
// ConcatTransform; a list without them is accepted too).
std::vector<double> Reader::read_numbers(const Token& dir, int n, bool brackets) {
    bool open = false;
    if (brackets) {
        Token t = require_token(dir.loc, fmt::format("{}: expected [ and {} numbers", dir.text, n).c_str());
        if (t.kind == TokKind::Open)
            open = true;
        else
            pending_ = t;
    }
    std::vector<double> v;
    for (int i = 0; i < n; ++i) {
        Token t = require_token(dir.loc, fmt::format("{}: expected {} numbers", dir.text, n).c_str());
        if (t.kind == TokKind::Close)
            error(t.loc, "{}: expected {} numbers, found {}", dir.text, n, i);
        pending_ = t;
        v.push_back(read_number(dir));
    }
    if (open) {
        Token t = require_token(dir.loc, fmt::format("{}: expected ]", dir.text).c_str());
        if (t.kind != TokKind::Close)
            error(t.loc, "{}: expected ] after {} numbers, found {}", dir.text, n, token_desc(t));
    }
    return v;
}

// The types of pbrt-v4's parameter lists; pbrt-v3's names as pbrt-v4 upgrades them.
std::optional<std::string> param_type(std::string_view t) {
    static const std::array<std::string_view, 13> kTypes{
        "integer", "float", "point2", "vector2", "point3", "vector3", "normal3",
        "rgb", "spectrum", "blackbody", "bool", "string", "texture"};
    for (auto k : kTypes)
        if (t == k) return std::string(k);
    if (t == "point") return "point3";
    if (t == "vector") return "vector3";
    if (t == "normal") return "normal3";
    if (t == "color") return "rgb";
    return std::nullopt;
}

void Reader::add_value(Param& p, const Token& t) {
    if (t.kind == TokKind::EndImport)
        error(t.loc, "parameter \"{}\": the imported file ends inside its values", p.decl());
    if (t.kind == TokKind::Open)
        error(t.loc, "parameter \"{}\": '[' inside a value list", p.decl());
    if (t.kind == TokKind::String) {
        p.strs.emplace_back(t.text);
    } else if (t.text == "true" || t.text == "false") {
        p.bools.push_back(t.text == "true");
    } else {
        auto v = parse_number(t.text);
        if (!v) error(t.loc, "parameter \"{}\": {} is not a number", p.decl(), token_desc(t));
        if (!std::isfinite(*v) || !std::isfinite(float(*v)))
            error(t.loc, "parameter \"{}\": {} is not a finite number", p.decl(), token_desc(t));
        p.nums.push_back(*v);
    }
    const int kinds = !p.strs.empty() + !p.bools.empty() + !p.nums.empty();
    if (kinds > 1)
        error(t.loc, "parameter \"{}\": {} mixes numbers, strings and booleans", p.decl(),
              token_desc(t));
}

// The values a type takes, and their number.
void Reader::check_param(Param& p) {
    const std::string& t = p.type;
    auto want = [&](const char* what) {
        error(p.loc, "parameter \"{}\" takes {}", p.decl(), what);
    };
    if (t == "bool") {
        // pbrt-v3 wrote "true" in quotes
        for (const auto& s : p.strs) {
            if (s != "true" && s != "false") want("true or false");
            p.bools.push_back(s == "true");
        }
        p.strs.clear();
        if (!p.nums.empty()) want("true or false");
        return;
    }
    if (t == "string" || t == "texture") {
        if (!p.nums.empty() || !p.bools.empty()) want("quoted strings");
        return;
    }
    if (t == "spectrum") {
        if (!p.bools.empty()) want("wavelength-value pairs or the name of a spectrum");
        if (!p.strs.empty() && p.strs.size() != 1) want("one name");
        if (p.nums.size() > 1 && p.nums.size() % 2 != 0)
            want("wavelength-value pairs (an even count of numbers)");
        for (std::size_t i = 2; i + 1 < p.nums.size(); i += 2)
            if (!(p.nums[i] > p.nums[i - 2]))
                error(p.loc, "parameter \"{}\": the wavelengths must increase ({} after {})",
                      p.decl(), p.nums[i], p.nums[i - 2]);
        return;
    }
    if (!p.strs.empty() || !p.bools.empty()) want("numbers");
    const std::size_t n = p.nums.size();
    if (t == "integer") {
        for (double v : p.nums)
            if (v != std::floor(v) || v < -2147483648.0 || v > 2147483647.0)
                error(p.loc, "parameter \"{}\": {} is not a 32-bit integer", p.decl(), v);
    } else if ((t == "point2" || t == "vector2") && n % 2 != 0) {
        want("pairs of numbers");
    } else if ((t == "point3" || t == "vector3" || t == "normal3") && n % 3 != 0) {
        want("triples of numbers");
    } else if (t == "rgb" && n != 3) {
        want("3 numbers");
    } else if (t == "blackbody" && (n < 1 || n > 2)) {
        want("a temperature in kelvin");
    }
}

std::vector<Param> Reader::read_params() {
    std::vector<Param> ps;
    while (true) {
        auto t = next_token();
        if (!t) break;
        if (t->kind != TokKind::String) {
            pending_ = t;
            break;
        }
        // "TYPE NAME"
        std::vector<std::string_view> words;
        std::string_view s = t->text;
        std::size_t i = 0;
        while (i < s.size()) {
            while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
            std::size_t j = i;
            while (j < s.size() && s[j] != ' ' && s[j] != '\t') ++j;
            if (j > i) words.push_back(s.substr(i, j - i));
            i = j;
        }
        if (words.size() != 2)
            error(t->loc, "expected a parameter \"TYPE NAME\", found {}", token_desc(*t));
        Param p;
        auto type = param_type(words[0]);
        if (!type)
            error(t->loc, "unknown parameter type '{}' in {} (pbrt-v4's types: integer, float, "
                          "point2, vector2, point3, vector3, normal3, rgb, spectrum, blackbody, "
                          "bool, string, texture)",
                  words[0], token_desc(*t));
        p.type = *type;
        p.name = std::string(words[1]);
        p.loc = t->loc;
        Token v = require_token(t->loc, fmt::format("parameter \"{}\" has no value", p.decl()).c_str());
        if (v.kind == TokKind::Open) {
            while (true) {
                Token x = require_token(v.loc, "'[' is never closed");
                if (x.kind == TokKind::Close) break;
                add_value(p, x);
            }
        } else if (v.kind == TokKind::Close) {
            error(v.loc, "parameter \"{}\": unexpected ']'", p.decl());
        } else {
            add_value(p, v);
        }
        check_param(p);
        for (const Param& q : ps)
            if (q.name == p.name)
                error(p.loc, "parameter '{}' is given twice (first at {})", p.name, where(q.loc));
        ps.push_back(std::move(p));
    }
    return ps;
}

Directive Reader::read_directive(const Token& t, bool typed) {
    Directive d;
    d.what = std::string(t.text);
    d.loc = t.loc;
    if (typed) d.type = read_string(t);
    d.params = read_params();
    return d;
}

// --- Parameters -----------------------------------------------------------------------------

Param* Reader::param(Directive& d, std::string_view name,
                     std::initializer_list<std::string_view> types) {
    for (Param& p : d.params) {
        if (p.name != name) continue;
        p.used = true;
        if (std::find(types.begin(), types.end(), p.type) == types.end()) {
            std::string list;
            for (auto x : types) list += fmt::format("{}\"{} {}\"", list.empty() ? "" : " or ", x, name);
            error(p.loc, "{}: parameter \"{}\" must be {}", d.describe(), p.decl(), list);
        }
        return &p;
    }
    return nullptr;
}

double Reader::one(const Directive& d, const Param& p) const {
    if (p.nums.size() != 1)
        error(p.loc, "{}: parameter \"{}\" takes one value, found {}", d.describe(), p.decl(),
              p.nums.size());
    return p.nums[0];
}

std::optional<double> Reader::get_float(Directive& d, std::string_view name) {
    Param* p = param(d, name, {"float", "integer"});
    if (!p) return std::nullopt;
    return one(d, *p);
}

std::optional<int> Reader::get_int(Directive& d, std::string_view name) {
    Param* p = param(d, name, {"integer"});
    if (!p) return std::nullopt;
    return int(one(d, *p));
}

std::optional<bool> Reader::get_bool(Directive& d, std::string_view name) {
    Param* p = param(d, name, {"bool"});
    if (!p) return std::nullopt;
    if (p->bools.size() != 1)
        error(p->loc, "{}: parameter \"{}\" takes one value", d.describe(), p->decl());
    return p->bools[0] != 0;
}

std::optional<std::string> Reader::get_string(Directive& d, std::string_view name) {
    Param* p = param(d, name, {"string"});
    if (!p) return std::nullopt;
    if (p->strs.size() != 1)
        error(p->loc, "{}: parameter \"{}\" takes one string", d.describe(), p->decl());
    return p->strs[0];
}

// A spectrum: rgb, a float (grey), blackbody, spectrum (named or wavelength-value pairs) or,
// where allowed, "texture NAME".
std::optional<SpecVal> Reader::get_spectrum(Directive& d, std::string_view name, SpecUse use,
                                            bool texture_ok) {
    Param* p = texture_ok
                   ? param(d, name, {"rgb", "spectrum", "blackbody", "float", "texture"})
                   : param(d, name, {"rgb", "spectrum", "blackbody", "float"});
    if (!p) return std::nullopt;
    SpecVal v;
    v.loc = p->loc;
    const std::string what = fmt::format("{} \"{}\"", d.describe(), p->decl());
    if (p->type == "texture") {
        if (p->strs.size() != 1)
            error(p->loc, "{}: parameter \"{}\" takes one texture name", d.describe(), p->decl());
        v.texture = p->strs[0];
        return v;
    }
    if (p->type == "rgb") {
        v.rgb = glm::vec3(float(p->nums[0]), float(p->nums[1]), float(p->nums[2]));
    } else if (p->type == "float") {
        v.rgb = glm::vec3(float(one(d, *p)));
    } else if (p->type == "blackbody") {
        const double t = p->nums[0];
        if (!(t > 0.0)) error(p->loc, "{}: temperature {} K must be > 0", what, t);
        v.rgb = unit_luminance_rgb(spectrum_xyz([t](double l) { return planck(l, t); }));
        if (p->nums.size() == 2) v.rgb *= float(p->nums[1]);  // pbrt-v3's scale
        if (use == SpecUse::Light)
            note("blackbody", p->loc,
                 "blackbody spectra are converted to linear sRGB of luminance 1 (pbrt-v4's "
                 "normalisation) through a fit of the CIE 1931 matching functions (~1 %)");
        else
            note("blackbody reflectance", p->loc,
                 "a blackbody spectrum where a reflectance is expected: its colour at "
                 "luminance 1 is used");
    } else {  // spectrum
        if (!p->strs.empty()) {
            const std::string& s = p->strs[0];
            if (use == SpecUse::Unbounded) {
                if (auto m = pbrt_metal_spectrum(s)) {
                    v.rgb = *m;
                    return v;
                }
                for (const NamedGlass& g : kGlasses)
                    if (g.name == s) {
                        v.rgb = glm::vec3(float(g.nd));
                        note("glass spectrum", p->loc,
                             "named glass spectra become their index at 587.6 nm (Schott n_d); "
                             "pbrt-v4 disperses them");
                        return v;
                    }
            }
            if (use == SpecUse::Light) {
                if (s == "stdillum-D65") {
                    v.rgb = glm::vec3(1.0f);  // sRGB's white
                    return v;
                }
                for (const NamedIlluminant& il : kIlluminants)
                    if (il.name == s) {
                        v.rgb = chromaticity_rgb(il.x, il.y);
                        return v;
                    }
            }
            if (use == SpecUse::Unbounded && s.rfind("metal-", 0) == 0) {
                // brass (CuZn) and other metals outside the table: copper's values
                const bool eta = s.size() > 4 && s.substr(s.size() - 4) == "-eta";
                v.rgb = *pbrt_metal_spectrum(eta ? "metal-Cu-eta" : "metal-Cu-k");
                note("metal " + s, p->loc,
                     fmt::format("spectrum \"{}\" is not in wavepath's table of metals "
                                 "(scene/metals.h); copper's is used",
                                 s));
            } else {
                v.rgb = glm::vec3(0.5f);
                note("spectrum " + s, p->loc,
                     fmt::format("spectrum \"{}\" is not a named spectrum wavepath knows for "
                                 "this parameter (spectrum files are not read); 0.5 is used",
                                 s));
            }
            return v;
        }
        // (Odd counts are refused where the parameter is read; an empty list is refused here.)
        if (p->nums.empty())
            error(p->loc, "{}: parameter \"{}\" takes one value or (wavelength, value) pairs; got none",
                  d.describe(), p->decl());
        if (p->nums.size() == 1) {
            v.rgb = glm::vec3(float(p->nums[0]));
        } else if (use == SpecUse::Light) {
            const std::vector<double>& n = p->nums;
            auto at = [&n](double l) {
                if (l < n.front() || l > n[n.size() - 2]) return 0.0;
                for (std::size_t i = 2; i < n.size(); i += 2)
                    if (l <= n[i]) {
                        const double f = (l - n[i - 2]) / (n[i] - n[i - 2]);
                        return n[i - 1] + f * (n[i + 1] - n[i - 1]);
                    }
                return n.back();
            };
            v.rgb = unit_luminance_rgb(spectrum_xyz(at));
            note("light spectrum", p->loc,
                 "sampled light spectra become linear sRGB of luminance 1 (pbrt-v4's "
                 "normalisation) through a fit of the CIE 1931 matching functions (~1 %)");
        } else {
            double sum = 0.0;
            for (std::size_t i = 1; i < p->nums.size(); i += 2) sum += p->nums[i];
            v.rgb = glm::vec3(float(sum / double(p->nums.size() / 2)));
            note("spectrum pairs", p->loc,
                 "sampled spectra (wavelength-value pairs) are reduced to the mean of their "
                 "values (grey)");
        }
    }
    return v;
}

// Whatever a directive had that nothing read: one warning per kind.
void Reader::finish(Directive& d) {
    for (Param& p : d.params)
        if (!p.used)
            note(fmt::format("unused {} {}", d.describe(), p.name), p.loc,
                 fmt::format("parameter \"{}\" of {} is not supported; ignored", p.decl(),
                             d.describe()));
}

// Attribute "target" defaults: parameters the directive does not give itself.
void Reader::apply_attributes(Directive& d, const char* target) {
    auto it = gs_.attrs.find(target);
    if (it == gs_.attrs.end()) return;
    for (const Param& a : it->second) {
        bool have = false;
        for (const Param& p : d.params) have = have || p.name == a.name;
        if (!have) d.params.push_back(a);
    }
}

// --- Directives -----------------------------------------------------------------------------

void Reader::transform_step(const glm::dmat4& m) {
    if (!gs_.active_start) return;  // only the end time's transform changes: ignored
    gs_.ctm = gs_.ctm * m;
}

void Reader::push(char kind, const Loc& l) {
    if (int(stack_.size()) >= limits::kMaxAttributeDepth)
        error(l, "blocks nested more than {} deep", limits::kMaxAttributeDepth);
    stack_.push_back(gs_);
    pushes_.emplace_back(kind, l);
}

void Reader::pop(char kind, const Token& t) {
    static const char* const kNames[] = {"AttributeBegin", "TransformBegin", "ObjectBegin"};
    auto name = [](char k) { return k == 'a' ? kNames[0] : k == 't' ? kNames[1] : kNames[2]; };
    if (pushes_.empty()) error(t.loc, "{} without {}", t.text, name(kind));
    if (!sources_.empty() && sources_.back().import && stack_.size() <= sources_.back().saved_depth)
        error(t.loc, "{} closes a block opened before Import", t.text);
    if (pushes_.back().first != kind)
        error(t.loc, "{} closes the {} at {}", t.text, name(pushes_.back().first),
              where(pushes_.back().second));
    if (kind == 't') {
        const glm::dmat4 ctm = stack_.back().ctm;
        stack_.pop_back();
        gs_.ctm = ctm;  // TransformBegin/End keep and restore only the transform
    } else {
        gs_ = std::move(stack_.back());
        stack_.pop_back();
    }
    pushes_.pop_back();
}

void Reader::include(const Token& t, bool import) {
    const std::string name = read_string(t);
    if (import && !in_world_) error(t.loc, "Import is only allowed after WorldBegin");
    if (name.empty()) error(t.loc, "{}: empty file name", t.text);
    if (int(sources_.size()) >= limits::kMaxIncludeDepth)
        error(t.loc, "{}: files included more than {} deep", t.text, limits::kMaxIncludeDepth);
    if (++includes_ > limits::kMaxIncludes)
        error(t.loc, "{}: more than {} files included in all", t.text, limits::kMaxIncludes);
    fs::path p(name);
    if (p.is_relative()) p = dir_ / p;
    const std::string key = key_of(p);
    for (const Source& s : sources_)
        if (s.key == key)
            error(t.loc, "{} \"{}\": the file includes itself (an include cycle through {})",
                  t.text, name, files_[std::size_t(s.file)]);
    std::string text;
    try {
        text = read_file(p, std::uintmax_t(limits::kMaxSceneFileBytes));
    } catch (const Error& e) {
        error(t.loc, "{} \"{}\": {}", t.text, name, e.what());
    }
    texts_.push_back(std::move(text));
    files_.push_back(p.string());
    Source s;
    s.text = texts_.back();
    s.file = int(files_.size() - 1);
    s.key = key;
    s.loc = t.loc;
    if (s.text.size() >= 3 && s.text.substr(0, 3) == "\xEF\xBB\xBF") s.pos = 3;
    if (import) {
        s.import = true;
        s.saved_depth = stack_.size();
        s.saved_state = gs_;
        s.saved_object = current_object_.has_value();
    }
    sources_.push_back(std::move(s));
}

int Reader::current_slot(const Loc& l) {
    int light = -1;
    std::optional<AreaLight> area = gs_.area;
    if (area && current_object_) {
        note("instance light", l,
             "area lights inside ObjectBegin are not supported (pbrt-v4 ignores them too); "
             "the shapes do not emit");
        area.reset();
    }
    if (!area) {
        auto [it, fresh] = plain_slots_.try_emplace({gs_.matref, light}, int(slots_.size()));
        if (!fresh) return it->second;
    }
    Slot s;
    s.matref = gs_.matref;
    s.light = area;
    slots_.push_back(s);
    Material placeholder;
    placeholder.name = "slot";
    scene_.add_material(placeholder);
    return int(slots_.size() - 1);
}

void Reader::parse() {
    while (auto tok = next_token()) {
        const Token t = *tok;
        if (t.kind == TokKind::EndImport) {
            end_import(t);
            continue;
        }
        if (t.kind != TokKind::Word)
            error(t.loc, "expected a directive, found {}", token_desc(t));
        const std::string_view w = t.text;
        auto world_only = [&] {
            if (!in_world_) error(t.loc, "{} is only allowed after WorldBegin", w);
        };
        auto options_only = [&] {
            if (in_world_) error(t.loc, "{} is only allowed before WorldBegin", w);
        };
        if (w == "AttributeBegin") {
            push('a', t.loc);
        } else if (w == "AttributeEnd") {
            pop('a', t);
        } else if (w == "TransformBegin") {
            note("TransformBegin", t.loc,
                 "TransformBegin/TransformEnd are pbrt-v3's (pbrt-v4 deprecates them); read as "
                 "a push and pop of the transform only");
            push('t', t.loc);
        } else if (w == "TransformEnd") {
            pop('t', t);
        } else if (w == "Attribute") {
            Directive d = read_directive(t, true);
            static const std::set<std::string> kTargets{"shape", "light", "material", "medium",
                                                        "texture"};
            if (!kTargets.count(d.type))
                error(t.loc, "Attribute \"{}\": the target must be shape, light, material, "
                             "medium or texture",
                      d.type);
            auto& list = gs_.attrs[d.type];
            for (Param& p : d.params) {
                std::erase_if(list, [&](const Param& q) { return q.name == p.name; });
                list.push_back(p);
            }
        } else if (w == "ActiveTransform") {
            Token a = require_token(t.loc, "ActiveTransform: expected All, StartTime or EndTime");
            if (a.kind == TokKind::Word && a.text == "All") {
                gs_.active_start = gs_.active_end = true;
            } else if (a.kind == TokKind::Word && a.text == "StartTime") {
                gs_.active_start = true;
                gs_.active_end = false;
            } else if (a.kind == TokKind::Word && a.text == "EndTime") {
                gs_.active_start = false;
                gs_.active_end = true;
                note("motion", a.loc,
                     "motion blur is not supported: transforms for the end time are ignored");
            } else {
                error(a.loc, "ActiveTransform: expected All, StartTime or EndTime, found {}",
                      token_desc(a));
            }
        } else if (w == "TransformTimes") {
            read_number(t);
            read_number(t);
            note("TransformTimes", t.loc, "TransformTimes (motion blur) is ignored");
        } else if (w == "Identity") {
            if (gs_.active_start) gs_.ctm = glm::dmat4(1.0);
        } else if (w == "Translate") {
            auto v = read_numbers(t, 3, false);
            transform_step(glm::translate(glm::dmat4(1.0), glm::dvec3(v[0], v[1], v[2])));
        } else if (w == "Scale") {
            auto v = read_numbers(t, 3, false);
            transform_step(glm::scale(glm::dmat4(1.0), glm::dvec3(v[0], v[1], v[2])));
        } else if (w == "Rotate") {
            auto v = read_numbers(t, 4, false);
            const glm::dvec3 axis(v[1], v[2], v[3]);
            if (!(glm::length(axis) > 0.0)) error(t.loc, "Rotate: the axis is zero");
            transform_step(glm::rotate(glm::dmat4(1.0), v[0] * kPi / 180.0, glm::normalize(axis)));
        } else if (w == "LookAt") {
            auto v = read_numbers(t, 9, false);
            const glm::dvec3 pos(v[0], v[1], v[2]), look(v[3], v[4], v[5]), up(v[6], v[7], v[8]);
            // pbrt-v4 LookAt: camera axes right = up × dir, up' = dir × right, dir
            if (!(glm::length(look - pos) > 0.0))
                error(t.loc, "LookAt: the eye and the point looked at coincide");
            const glm::dvec3 dir = glm::normalize(look - pos);
            if (!(glm::length(up) > 0.0)) error(t.loc, "LookAt: the up vector is zero");
            const glm::dvec3 c = glm::cross(glm::normalize(up), dir);
            if (!(glm::length(c) > 1e-12))
                error(t.loc, "LookAt: the up vector is parallel to the viewing direction");
            const glm::dvec3 right = glm::normalize(c);
            const glm::dvec3 new_up = glm::cross(dir, right);
            const glm::dmat4 world_from_camera(glm::dvec4(right, 0), glm::dvec4(new_up, 0),
                                               glm::dvec4(dir, 0), glm::dvec4(pos, 1));
            transform_step(glm::inverse(world_from_camera));
        } else if (w == "Transform" || w == "ConcatTransform") {
            auto v = read_numbers(t, 16, true);
            glm::dmat4 m;
            for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = v[std::size_t(i)];  // column by column
            if (w == "Transform") {
                if (gs_.active_start) gs_.ctm = m;
            } else {
                transform_step(m);
            }
        } else if (w == "CoordinateSystem") {
            coord_systems_[read_string(t)] = gs_.ctm;
        } else if (w == "CoordSysTransform") {
            const std::string n = read_string(t);
            auto it = coord_systems_.find(n);
            if (it == coord_systems_.end())
                note("coordsys " + n, t.loc,
                     fmt::format("CoordSysTransform \"{}\": no such coordinate system; ignored", n));
            else if (gs_.active_start)
                gs_.ctm = it->second;
        } else if (w == "ReverseOrientation") {
            gs_.reverse = !gs_.reverse;
        } else if (w == "Camera") {
            options_only();
            Directive d = read_directive(t, true);
            if (camera_) error(t.loc, "a second Camera (the first is at {})", where(camera_->loc));
            camera_ = std::move(d);
            camera_ctm_ = gs_.ctm;
            coord_systems_["camera"] = glm::inverse(gs_.ctm);
        } else if (w == "Film" || w == "Sampler" || w == "Integrator") {
            options_only();
            Directive d = read_directive(t, true);
            auto& slot = w == "Film" ? film_ : w == "Sampler" ? sampler_ : integrator_;
            if (slot) note("second " + d.what, t.loc, fmt::format("a second {}: the last one is used", w));
            slot = std::move(d);
        } else if (w == "PixelFilter") {
            options_only();
            Directive d = read_directive(t, true);
            if (d.type != "box")
                note("filter", t.loc,
                     fmt::format("PixelFilter \"{}\" is ignored: wavepath box-filters each pixel",
                                 d.type));
            for (Param& p : d.params) p.used = true;
        } else if (w == "Accelerator") {
            options_only();
            Directive d = read_directive(t, true);
            for (Param& p : d.params) p.used = true;  // wavepath builds its own BVH
        } else if (w == "ColorSpace") {
            const std::string n = read_string(t);
            if (n != "srgb")
                note("colorspace", t.loc,
                     fmt::format("ColorSpace \"{}\": wavepath renders in linear sRGB; values are "
                                 "taken as sRGB",
                                 n));
        } else if (w == "Option") {
            Directive d;
            d.what = "Option";
            d.loc = t.loc;
            d.params = read_params();
            if (d.params.size() != 1) error(t.loc, "Option takes one \"TYPE NAME\" VALUE");
            note("option " + d.params[0].name, t.loc,
                 fmt::format("Option \"{}\" is ignored", d.params[0].decl()));
        } else if (w == "WorldBegin") {
            if (in_world_) error(t.loc, "a second WorldBegin");
            in_world_ = true;
            gs_.ctm = glm::dmat4(1.0);
            coord_systems_["world"] = gs_.ctm;
        } else if (w == "WorldEnd") {
            note("WorldEnd", t.loc, "WorldEnd is pbrt-v3's; ignored");
        } else if (w == "Include" || w == "Import") {
            include(t, w == "Import");
        } else if (w == "Shape") {
            world_only();
            shape(read_directive(t, true));
        } else if (w == "LightSource") {
            world_only();
            light_source(read_directive(t, true));
        } else if (w == "AreaLightSource") {
            world_only();
            area_light(read_directive(t, true));
        } else if (w == "Material") {
            world_only();
            Directive d = read_directive(t, true);
            apply_attributes(d, "material");
            MatDef def;
            def.d = std::move(d);
            anon_.push_back(std::move(def));
            MatRef r;
            r.anon = int(anon_.size() - 1);
            r.loc = t.loc;
            matrefs_.push_back(r);
            gs_.matref = int(matrefs_.size() - 1);
        } else if (w == "MakeNamedMaterial") {
            world_only();
            Directive d = read_directive(t, true);
            apply_attributes(d, "material");
            const std::string name = d.type;
            auto type = get_string(d, "type");
            if (!type) error(t.loc, "MakeNamedMaterial \"{}\": missing \"string type\"", name);
            if (named_.count(name))
                error(t.loc, "MakeNamedMaterial \"{}\": redefined (first at {})", name,
                      where(named_.at(name).d.loc));
            d.what = "MakeNamedMaterial \"" + name + "\"";
            d.type = *type;
            MatDef def;
            def.name = name;
            def.d = std::move(d);
            named_.emplace(name, std::move(def));
        } else if (w == "NamedMaterial") {
            world_only();
            const std::string name = read_string(t);
            // One reference per name (its first use is where an undefined name is reported),
            // so that every shape using the name shares one material
            auto [it, fresh] = named_refs_.try_emplace(name, int(matrefs_.size()));
            if (fresh) {
                MatRef r;
                r.named = true;
                r.name = name;
                r.loc = t.loc;
                matrefs_.push_back(r);
            }
            gs_.matref = it->second;
        } else if (w == "Texture") {
            world_only();
            texture(t);
        } else if (w == "ObjectBegin") {
            world_only();
            const std::string name = read_string(t);
            if (current_object_)
                error(t.loc, "ObjectBegin \"{}\" inside ObjectBegin \"{}\"", name, *current_object_);
            if (objects_.count(name))
                error(t.loc, "ObjectBegin \"{}\": redefined (first at {})", name,
                      where(objects_.at(name).loc));
            push('o', t.loc);
            ObjectDef def;
            def.loc = t.loc;
            objects_.emplace(name, std::move(def));
            current_object_ = name;
        } else if (w == "ObjectEnd") {
            world_only();
            if (!current_object_) error(t.loc, "ObjectEnd without ObjectBegin");
            pop('o', t);
            current_object_.reset();
        } else if (w == "ObjectInstance") {
            world_only();
            const std::string name = read_string(t);
            if (current_object_)
                error(t.loc, "ObjectInstance \"{}\" inside ObjectBegin \"{}\"", name,
                      *current_object_);
            instances_.push_back({name, gs_.ctm, t.loc});
        } else if (w == "MakeNamedMedium") {
            Directive d = read_directive(t, true);
            note("medium", t.loc, "participating media are not supported; MakeNamedMedium ignored");
            for (Param& p : d.params) p.used = true;
        } else if (w == "MediumInterface") {
            read_string(t);
            auto second = next_token();
            if (second && second->kind != TokKind::String) pending_ = second;
            note("medium", t.loc,
                 "participating media are not supported; MediumInterface ignored");
        } else {
            error(t.loc, "unknown directive {} (not part of pbrt-v4's scene format)", token_desc(t));
        }
    }
    if (!pushes_.empty()) {
        const char k = pushes_.back().first;
        error(pushes_.back().second, "{} is never closed",
              k == 'a' ? "AttributeBegin" : k == 't' ? "TransformBegin" : "ObjectBegin");
    }
}

// --- Lights ---------------------------------------------------------------------------------

void Reader::area_light(Directive d) {
    apply_attributes(d, "light");
    if (d.type != "diffuse") {
        note("area " + d.type, d.loc,
             fmt::format("AreaLightSource \"{}\" is not supported (pbrt-v4 has \"diffuse\"); "
                         "the shapes do not emit",
                         d.type));
        for (Param& p : d.params) p.used = true;
        gs_.area.reset();
        return;
    }
    AreaLight a;
    a.loc = d.loc;
    glm::vec3 l(1.0f);
    if (auto s = get_spectrum(d, "L", SpecUse::Light, false)) l = s->rgb;
    const double scale = get_float(d, "scale").value_or(1.0);
    if (auto f = get_string(d, "filename")) {
        note("area image", d.loc,
             "AreaLightSource \"diffuse\" \"filename\" (an emission image) is not supported; "
             "L = 1 is used");
    }
    if (auto pw = get_float(d, "power"))
        note("area power", d.loc, "AreaLightSource \"power\" is not supported; ignored");
    a.twosided = get_bool(d, "twosided").value_or(false);
    if (a.twosided)
        note("twosided", d.loc,
             "two-sided area lights emit from the front only in wavepath (the side of the "
             "shape's normals, or its winding); pbrt-v4 emits from both sides");
    a.radiance = l * float(scale);
    if (!std::isfinite(a.radiance.x) || !std::isfinite(a.radiance.y) ||
        !std::isfinite(a.radiance.z) || glm::any(glm::lessThan(a.radiance, glm::vec3(0.0f))))
        error(d.loc, "AreaLightSource: radiance ({}, {}, {}) must be finite and >= 0",
              a.radiance.x, a.radiance.y, a.radiance.z);
    finish(d);
    gs_.area = a;
}

void Reader::light_source(Directive d) {
    apply_attributes(d, "light");
    if (d.type != "infinite") {
        note("light " + d.type, d.loc,
             fmt::format("LightSource \"{}\" is not supported (wavepath has area lights, a "
                         "constant background and an environment map); skipped",
                         d.type));
        for (Param& p : d.params) p.used = true;
        return;
    }
    const double scale = get_float(d, "scale").value_or(1.0);
    if (!(scale >= 0.0)) error(d.loc, "LightSource \"infinite\": scale {} must be >= 0", scale);
    auto l = get_spectrum(d, "L", SpecUse::Light, false);
    auto file = get_string(d, "filename");
    if (l && file)
        error(d.loc, "LightSource \"infinite\": give either \"L\" or \"filename\", not both");
    if (get_float(d, "illuminance"))
        note("illuminance", d.loc, "LightSource \"infinite\" \"illuminance\" is not supported; ignored");
    if (param(d, "portal", {"point3"}))
        note("portal", d.loc, "infinite light portals are not supported; the whole map lights the scene");
    finish(d);
    if (!file) {
        const glm::vec3 c = l ? l->rgb : glm::vec3(1.0f);
        if (glm::any(glm::lessThan(c, glm::vec3(0.0f))))
            error(d.loc, "LightSource \"infinite\": L ({}, {}, {}) must be >= 0", c.x, c.y, c.z);
        scene_.background += c * float(scale);
        return;
    }
    if (env_where_)
        error(d.loc, "a second infinite light with a map: wavepath takes one (the first is at {})",
              *env_where_);
    if (file->empty()) error(d.loc, "LightSource \"infinite\": empty filename");
    fs::path p(*file);
    if (p.is_relative()) p = dir_ / p;
    const std::size_t warnings = scene_.warnings.size();
    int image = add_texture_file(scene_, p, TextureUse::Colour);
    bool missing = false;
    for (std::size_t i = warnings; i < scene_.warnings.size(); ++i)
        missing = missing || scene_.warnings[i].find("texture not loaded") != std::string::npos;
    if (!missing) {
        const Texture& src = scene_.textures[std::size_t(image)];
        if (src.width != src.height)
            error(d.loc,
                  "LightSource \"infinite\": '{}' is {} x {}; pbrt-v4's environment maps are "
                  "square equal-area (octahedral) images, not equirectangular ones",
                  p.string(), src.width, src.height);
        scene_.textures.push_back(equal_area_to_equirect(src));
        image = int(scene_.textures.size() - 1);
    }
    // The rotation of the light's transform (pbrt: directions in the light's space)
    glm::dmat3 r(gs_.ctm);
    const double det = glm::determinant(r);
    if (!(std::abs(det) > 1e-12) || !std::isfinite(det))
        error(d.loc, "LightSource \"infinite\": its transform is singular");
    const glm::dvec3 x = glm::normalize(r[0]);
    const glm::dvec3 y = glm::normalize(r[1] - glm::dot(r[1], x) * x);
    const glm::dmat3 q(x, y, det > 0.0 ? glm::cross(x, y) : -glm::cross(x, y));
    double off = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) off = std::max(off, std::abs(q[i][j] - r[i][j]));
    if (off > 1e-5)
        note("env transform", d.loc,
             "the infinite light's transform is not a rotation; only its rotation is used");
    Environment env;
    env.image = image;
    env.scale = float(scale);
    env.to_world = glm::mat3(q);
    scene_.environment = env;
    env_where_ = where(d.loc);
}

// --- Textures -------------------------------------------------------------------------------

void Reader::texture(const Token& t) {
    const std::string name = read_string(t);
    std::string kind = read_string(t);
    TexDef def;
    def.d.what = fmt::format("Texture \"{}\"", name);
    def.d.loc = t.loc;
    def.d.type = read_string(t);
    def.d.params = read_params();
    apply_attributes(def.d, "texture");
    if (kind == "color") kind = "spectrum";  // pbrt-v3
    if (kind != "spectrum" && kind != "float")
        error(t.loc, "Texture \"{}\": the type must be \"spectrum\" or \"float\", not \"{}\"", name,
              kind);
    def.is_float = kind == "float";
    auto& names = def.is_float ? float_tex_ : spectrum_tex_;
    if (names.count(name))
        error(t.loc, "Texture \"{}\" ({}): redefined (first at {})", name, kind,
              where(texdefs_[std::size_t(names.at(name))].d.loc));
    names[name] = int(texdefs_.size());
    texdefs_.push_back(std::move(def));
}

TexResult& Reader::resolve_texture(const std::string& name, bool is_float, const Loc& use,
                                   int depth) {
    auto& names = is_float ? float_tex_ : spectrum_tex_;
    auto it = names.find(name);
    if (it == names.end())
        error(use, "no {} texture \"{}\" is defined (Texture \"{}\" \"{}\" ...)",
              is_float ? "float" : "spectrum", name, name, is_float ? "float" : "spectrum");
    TexDef& def = texdefs_[std::size_t(it->second)];
    if (def.resolved) return def.result;
    if (def.resolving || depth > kMaxMaterialNesting)
        error(def.d.loc, "{} refers to itself (or textures are nested more than {} deep)",
              def.d.what, kMaxMaterialNesting);
    def.resolving = true;
    TexResult r = build_texture(def, depth + 1);
    def.resolving = false;
    def.resolved = true;
    def.result = r;
    return def.result;
}

glm::vec3 Reader::texture_mean(const TexResult& t) {
    if (!t.image) return t.constant;
    if (t.missing) return glm::vec3(0.5f) * t.scale;
    const Texture& src = scene_.textures[std::size_t(t.ref.image)];
    const std::size_t n = std::size_t(src.width) * std::size_t(src.height);
    glm::dvec3 sum(0.0);
    for (std::size_t i = 0; i < n; ++i)
        sum += glm::dvec3(texel(src, i, 0), texel(src, i, 1), texel(src, i, 2));
    return n ? glm::vec3(sum / double(n)) * t.scale : glm::vec3(0.0f);
}

TexResult Reader::build_texture(TexDef& def, int depth) {
    Directive& d = def.d;
    const std::string& cls = d.type;
    TexResult r;
    // A texture-valued parameter of this texture: a constant or another texture
    auto value = [&](std::string_view name, float dflt) -> TexResult {
        TexResult v;
        v.constant = glm::vec3(dflt);
        if (def.is_float) {
            Param* p = param(d, name, {"float", "texture"});
            if (!p) return v;
            if (p->type == "texture") {
                if (p->strs.size() != 1) error(p->loc, "{}: one texture name expected", d.what);
                return resolve_texture(p->strs[0], true, p->loc, depth);
            }
            v.constant = glm::vec3(float(one(d, *p)));
            return v;
        }
        auto s = get_spectrum(d, name, SpecUse::Unbounded, true);
        if (!s) return v;
        if (!s->texture.empty()) return resolve_texture(s->texture, false, s->loc, depth);
        v.constant = s->rgb;
        return v;
    };
    // pbrt's uv mapping (s, t) = (su u + du, sv v + dv), v up
    auto mapping = [&](glm::vec2& su_sv, glm::vec2& du_dv) {
        auto m = get_string(d, "mapping").value_or("uv");
        if (m != "uv")
            note("mapping " + m, d.loc,
                 fmt::format("texture mapping \"{}\" is not supported; the uv mapping is used", m));
        su_sv = glm::vec2(float(get_float(d, "uscale").value_or(1.0)),
                          float(get_float(d, "vscale").value_or(1.0)));
        du_dv = glm::vec2(float(get_float(d, "udelta").value_or(0.0)),
                          float(get_float(d, "vdelta").value_or(0.0)));
        for (const char* n : {"v1", "v2"}) param(d, n, {"vector3"});
    };
    if (cls == "imagemap") {
        glm::vec2 s, o;
        mapping(s, o);
        auto file = get_string(d, "filename");
        if (!file || file->empty()) error(d.loc, "{}: imagemap needs \"string filename\"", d.what);
        const std::string enc = get_string(d, "encoding").value_or("sRGB");
        std::optional<double> gamma;
        TextureUse use = TextureUse::Colour;
        if (enc == "linear") {
            use = TextureUse::Data;
        } else if (enc.rfind("gamma ", 0) == 0) {
            auto g = parse_number(std::string_view(enc).substr(6));
            if (!g || !(*g > 0.0) || !std::isfinite(*g))
                error(d.loc, "{}: encoding \"{}\": expected \"gamma VALUE\"", d.what, enc);
            gamma = *g;
            use = TextureUse::Data;
        } else if (enc != "sRGB") {
            error(d.loc, "{}: encoding \"{}\" is not sRGB, linear or \"gamma VALUE\"", d.what, enc);
        }
        const std::string filter = get_string(d, "filter").value_or("bilinear");
        static const std::set<std::string> kFilters{"point", "bilinear", "trilinear", "ewa", "EWA"};
        if (!kFilters.count(filter))
            error(d.loc, "{}: filter \"{}\" is not point, bilinear, trilinear or ewa", d.what, filter);
        const std::string wrap = get_string(d, "wrap").value_or("repeat");
        if (wrap != "repeat" && wrap != "black" && wrap != "clamp" && wrap != "octahedralsphere")
            error(d.loc, "{}: wrap \"{}\" is not repeat, black, clamp or octahedralsphere", d.what,
                  wrap);
        if (wrap != "repeat")
            note("wrap " + wrap, d.loc,
                 fmt::format("texture wrap \"{}\" is rendered as \"repeat\"", wrap));
        get_float(d, "maxanisotropy");
        const double scale = get_float(d, "scale").value_or(1.0);
        const bool invert = get_bool(d, "invert").value_or(false);
        fs::path p(*file);
        if (p.is_relative()) p = dir_ / p;
        const std::size_t warnings = scene_.warnings.size();
        int image = add_texture_file(scene_, p, use);
        for (std::size_t i = warnings; i < scene_.warnings.size(); ++i)
            r.missing = r.missing ||
                        scene_.warnings[i].find("texture not loaded") != std::string::npos;
        if (!r.missing && (gamma || invert)) {
            // Bake the decoding and the inversion: max(0, 1 - scale v) (pbrt-v4)
            const Texture& src = scene_.textures[std::size_t(image)];
            Texture t;
            t.source = src.source + (invert ? " (inverted)" : " (gamma)");
            t.width = src.width;
            t.height = src.height;
            const std::size_t n = std::size_t(src.width) * std::size_t(src.height);
            t.texelsf.resize(n * 4);
            for (std::size_t i = 0; i < n; ++i)
                for (int c = 0; c < 4; ++c) {
                    float v = texel(src, i, c);
                    if (c < 3 && gamma && !src.is_float()) v = std::pow(v, float(*gamma));
                    if (c < 3 && invert) v = std::max(0.0f, 1.0f - float(scale) * v);
                    t.texelsf[i * 4 + std::size_t(c)] = v;
                }
            scene_.textures.push_back(std::move(t));
            image = int(scene_.textures.size() - 1);
        }
        if (filter == "point") image = texture_with_filter(scene_, image, true);
        r.image = true;
        r.ref.image = image;
        r.scale = glm::vec3(invert ? 1.0f : float(scale));
        // pbrt looks up (s, 1 - t); wavepath's stored v is 1 - v_pbrt:
        // u' = su u + du, v' = 1 - (sv (1 - v) + dv) = sv v + 1 - sv - dv
        glm::mat3 m(1.0f);
        m[0][0] = s.x;
        m[1][1] = s.y;
        m[2][0] = o.x;
        m[2][1] = 1.0f - s.y - o.y;
        r.ref.uv_transform = m;
    } else if (cls == "checkerboard") {
        const int dim = get_int(d, "dimension").value_or(2);
        if (dim != 2 && dim != 3) error(d.loc, "{}: dimension {} is not 2 or 3", d.what, dim);
        TexResult a = value("tex1", 1.0f), b = value("tex2", 0.0f);
        glm::vec2 s, o;
        mapping(s, o);
        const glm::vec3 ca = texture_mean(a), cb = texture_mean(b);
        if (a.image || b.image)
            note("checker textures", d.loc,
                 "a checkerboard of textures: the textures' mean colours are used");
        if (dim == 3) {
            note("checker 3d", d.loc,
                 "3D checkerboards are not supported; their mean colour is used");
            r.constant = 0.5f * (ca + cb);
            return r;
        }
        scene_.textures.push_back(checkerboard_texture(ca, cb, d.what + " at " + where(d.loc)));
        r.image = true;
        r.ref.image = int(scene_.textures.size() - 1);
        // pbrt: tex1 where floor(s) + floor(t) is even, cells of size 1; wavepath's 2 x 2
        // checker has cells of 1/2: (s / 2, t / 2) with t = sv (1 - v) + dv
        glm::mat3 m(1.0f);
        m[0][0] = 0.5f * s.x;
        m[1][1] = -0.5f * s.y;
        m[2][0] = 0.5f * o.x;
        m[2][1] = 0.5f * (s.y + o.y);
        r.ref.uv_transform = m;
    } else if (cls == "constant") {
        r.constant = value("value", 1.0f).constant;
    } else if (cls == "scale") {
        TexResult a = value("tex", 1.0f), b = value("scale", 1.0f);
        if (!a.image && !b.image) {
            r.constant = a.constant * b.constant;
        } else if (a.image != b.image) {
            r = a.image ? a : b;
            r.scale *= a.image ? b.constant : a.constant;
        } else {
            note("scale of textures", d.loc,
                 "a scale texture of two textures: the first times the mean of the second");
            r = a;
            r.scale *= texture_mean(b);
        }
    } else if (cls == "mix") {
        TexResult a = value("tex1", 0.0f), b = value("tex2", 1.0f);
        Param* ap = param(d, "amount", {"float", "texture"});
        float amount = 0.5f;
        bool amount_tex = false;
        if (ap && ap->type == "texture") {
            if (ap->strs.size() != 1) error(ap->loc, "{}: one texture name expected", d.what);
            TexResult t = resolve_texture(ap->strs[0], true, ap->loc, depth);
            amount = texture_mean(t).x;
            amount_tex = t.image;
        } else if (ap) {
            amount = float(one(d, *ap));
        }
        if (!a.image && !b.image && !amount_tex) {
            r.constant = (1.0f - amount) * a.constant + amount * b.constant;
        } else {
            note("mix", d.loc,
                 "a mix texture of textures (or with a textured amount): the one with the "
                 "larger weight is used");
            r = amount <= 0.5f ? a : b;
        }
    } else {
        note("texture " + cls, d.loc,
             fmt::format("textures of class \"{}\" are not supported; 0.5 is used instead", cls));
        for (Param& p : d.params) p.used = true;
        r.constant = glm::vec3(0.5f);
    }
    finish(d);
    return r;
}

// A reflectance (albedo) parameter: the constant, or 1 (the image's scale) with `map` set.
// pbrt-v4 clamps reflectances to [0, 1]; so does this (a note where it changes a value).
glm::vec3 Reader::reflectance(Directive& d, std::string_view name, float def, TextureRef* map,
                              int depth) {
    auto s = get_spectrum(d, name, SpecUse::Reflectance, true);
    glm::vec3 v(def);
    if (s && s->texture.empty()) {
        v = s->rgb;
    } else if (s) {
        TexResult& t = resolve_texture(s->texture, false, s->loc, depth);
        if (t.image && map) {
            *map = t.ref;
            v = t.scale;
        } else {
            v = texture_mean(t);
            if (t.image)
                note("texture mean " + std::string(name), s->loc,
                     fmt::format("a texture for \"{}\" of {} is not supported there; its mean "
                                 "is used",
                                 name, d.describe()));
        }
    }
    const glm::vec3 c = clamp01(v);
    if (c != v)
        note("clamp " + std::string(name), s ? s->loc : d.loc,
             fmt::format("{} ({}, {}, {}) is clamped to [0, 1] (as pbrt-v4 does)", name, v.x, v.y,
                         v.z));
    return c;
}

// A float parameter that may be a float texture (its mean: wavepath takes a constant there).
float Reader::float_param(Directive& d, std::string_view name, float def, int depth) {
    Param* p = param(d, name, {"float", "integer", "texture"});
    if (!p) return def;
    if (p->type != "texture") return float(one(d, *p));
    if (p->strs.size() != 1) error(p->loc, "{}: one texture name expected", d.describe());
    TexResult& t = resolve_texture(p->strs[0], true, p->loc, depth);
    if (t.image)
        note("float texture " + std::string(name), p->loc,
             fmt::format("a texture for \"{}\" of {} is not supported; its mean is used", name,
                         d.describe()));
    return texture_mean(t).x;
}

// pbrt-v4's microfacet roughness: uroughness / vroughness (default roughness, default 0),
// remapped (α = sqrt(r), TrowbridgeReitzDistribution::RoughnessToAlpha) unless
// remaproughness is false; below α = 1e-3 on both axes pbrt-v4 treats it as smooth
// (EffectivelySmooth), and so does this. GGX with the height-correlated masking.
void Reader::roughness(Directive& d, const std::string& prefix, Material& m,
                       MaterialKind smooth, MaterialKind rough, int depth) {
    const float r = float_param(d, prefix + "roughness", 0.0f, depth);
    float u = float_param(d, prefix + "uroughness", r, depth);
    float v = float_param(d, prefix + "vroughness", r, depth);
    if (!(u >= 0.0f) || !(v >= 0.0f))
        error(d.loc, "{}: roughness ({}, {}) must be >= 0", d.describe(), u, v);
    if (get_bool(d, "remaproughness").value_or(true)) {
        u = std::sqrt(u);
        v = std::sqrt(v);
    }
    m.distribution = MicrofacetModel::GGX;
    m.separable_g = false;
    if (std::max(u, v) < 1e-3f) {
        m.kind = smooth;
        return;
    }
    m.kind = rough;
    auto clamp_alpha = [&](float a) {
        const float c = std::clamp(a, limits::kMinMicrofacetAlpha, limits::kMaxMicrofacetAlpha);
        if (c != a)
            note("alpha clamp", d.loc,
                 fmt::format("microfacet alpha {} is clamped to [{}, {}]", a,
                             limits::kMinMicrofacetAlpha, limits::kMaxMicrofacetAlpha));
        return c;
    };
    m.alpha = clamp_alpha(u);
    if (v != u) m.alpha_v = clamp_alpha(v);  // α_u along dp/du, as pbrt-v4 (microfacet.h)
}

// A dielectric's index of refraction: a float, or a spectrum (a named glass's n_d, else the
// mean with a note). pbrt-v4: 0 means 1.
float Reader::ior(Directive& d, std::string_view name, float def) {
    Param* p = param(d, name, {"float", "integer", "spectrum", "rgb"});
    if (!p) return def;
    p->used = false;
    double eta;
    if (p->type == "float" || p->type == "integer") {
        p->used = true;
        eta = one(d, *p);
    } else {
        auto s = get_spectrum(d, name, SpecUse::Unbounded, false);
        eta = (s->rgb.x + s->rgb.y + s->rgb.z) / 3.0;
        if (p->type == "rgb" || (p->strs.empty() && p->nums.size() > 1))
            note("ior spectrum", p->loc,
                 "a spectrally varying index of refraction becomes its mean (no dispersion)");
    }
    if (eta == 0.0) eta = 1.0;
    if (!(eta >= 0.01 && eta <= 100.0))
        error(p->loc, "{}: index of refraction {} is out of range [0.01, 100]", d.describe(), eta);
    return float(eta);
}

// pbrt-v4's conductor: eta / k (spectra, default copper) or reflectance (its "artist" mode:
// η = 1, k = 2 sqrt(r) / sqrt(1 - r), so that the normal-incidence reflectance is r).
void Reader::conductor(Directive& d, const std::string& prefix, Material& m, int depth) {
    auto eta = get_spectrum(d, prefix + "eta", SpecUse::Unbounded, true);
    auto k = get_spectrum(d, prefix + "k", SpecUse::Unbounded, true);
    const bool has_refl = param(d, "reflectance", {"rgb", "spectrum", "blackbody", "float",
                                                   "texture"}) != nullptr;
    auto value_of = [&](std::optional<SpecVal>& s, const char* def) {
        if (!s) return *pbrt_metal_spectrum(def);
        if (s->texture.empty()) return s->rgb;
        TexResult& t = resolve_texture(s->texture, false, s->loc, depth);
        if (t.image)
            note("conductor texture", s->loc,
                 "textured eta / k are not supported; their means are used");
        return texture_mean(t);
    };
    if (has_refl) {
        if (eta || k)
            error(d.loc, "{}: give either \"reflectance\" or \"eta\" and \"k\", not both",
                  d.describe());
        for (Param& p : d.params) if (p.name == "reflectance") p.used = false;
        auto s = get_spectrum(d, "reflectance", SpecUse::Reflectance, true);
        glm::vec3 r = s->rgb;
        if (!s->texture.empty()) {
            TexResult& t = resolve_texture(s->texture, false, s->loc, depth);
            if (t.image)
                note("conductor reflectance texture", s->loc,
                     "a textured conductor reflectance is not supported; its mean is used");
            r = texture_mean(t);
        }
        r = glm::clamp(r, glm::vec3(0.0f), glm::vec3(0.9999f));
        m.eta = glm::vec3(1.0f);
        m.k = 2.0f * glm::sqrt(r) / glm::sqrt(glm::vec3(1.0f) - r);
    } else {
        m.eta = value_of(eta, "metal-Cu-eta");
        m.k = value_of(k, "metal-Cu-k");
    }
    if (glm::any(glm::lessThan(m.eta, glm::vec3(0.0f))) ||
        glm::any(glm::lessThan(m.k, glm::vec3(0.0f))))
        error(d.loc, "{}: eta ({}, {}, {}) and k ({}, {}, {}) must be >= 0", d.describe(),
              m.eta.x, m.eta.y, m.eta.z, m.k.x, m.k.y, m.k.z);
    m.albedo = glm::vec3(1.0f);
    roughness(d, prefix, m, MaterialKind::Conductor, MaterialKind::RoughConductor, depth);
}

Material Reader::build_material(MatDef& def, int depth, bool* interface) {
    Directive& d = def.d;
    const std::string& t = d.type;
    Material m;
    m.name = def.name.empty() ? t : def.name;
    m.kind = MaterialKind::Diffuse;
    if (Param* p = param(d, "displacement", {"float", "texture"}))
        note("displacement " + t, p->loc, "\"displacement\" is not supported; ignored");
    // pbrt-v4's normal map: an image read as linear data, (2 rgb - 1) in the frame x = dp/du,
    // z = n, y = n × x, looked up at (u, 1 - v): wavepath's stored uvs and its tangent frame
    // (the image's up = +y, scene/normals.h), which is pbrt's wherever the uvs are not mirrored
    std::optional<TextureRef> normal_map;
    if (auto nm = get_string(d, "normalmap")) {
        if (nm->empty()) error(d.loc, "{}: empty \"normalmap\"", d.describe());
        fs::path p(*nm);
        if (p.is_relative()) p = dir_ / p;
        const std::size_t warnings = scene_.warnings.size();
        const int image = add_texture_file(scene_, p, TextureUse::Data);
        bool missing = false;
        for (std::size_t i = warnings; i < scene_.warnings.size(); ++i)
            missing = missing || scene_.warnings[i].find("texture not loaded") != std::string::npos;
        if (!missing) normal_map = TextureRef{image, glm::mat3(1.0f)};
        note("normalmap", d.loc,
             "normal maps use wavepath's tangent frame, which is pbrt's (x along dp/du, y = n x "
             "x) except where the uvs are mirrored");
    }
    if (t == "diffuse") {
        m.albedo = reflectance(d, "reflectance", 0.5f, &m.albedo_map, depth);
    } else if (t == "conductor") {
        conductor(d, "", m, depth);
    } else if (t == "coatedconductor") {
        conductor(d, "conductor.", m, depth);
        note("coatedconductor", d.loc,
             "coatedconductor is rendered as its conductor (the dielectric coat is dropped)");
        for (Param& p : d.params)
            if (p.name.rfind("interface.", 0) == 0 || p.name == "thickness" || p.name == "albedo" ||
                p.name == "g" || p.name == "maxdepth" || p.name == "nsamples")
                p.used = true;
    } else if (t == "dielectric") {
        m.ior = ior(d, "eta", 1.5f);
        m.albedo = glm::vec3(1.0f);
        m.specular = glm::vec3(1.0f);
        roughness(d, "", m, MaterialKind::Glass, MaterialKind::RoughDielectric, depth);
    } else if (t == "thindielectric") {
        m.ior = ior(d, "eta", 1.5f);
        m.albedo = glm::vec3(1.0f);
        m.specular = glm::vec3(1.0f);
        m.kind = MaterialKind::ThinDielectric;
    } else if (t == "coateddiffuse") {
        m.albedo = reflectance(d, "reflectance", 0.5f, &m.albedo_map, depth);
        m.ior = ior(d, "eta", 1.5f);
        m.specular = glm::vec3(1.0f);
        m.nonlinear = true;
        roughness(d, "", m, MaterialKind::Plastic, MaterialKind::RoughPlastic, depth);
        note("coateddiffuse", d.loc,
             "coateddiffuse is approximated by Mitsuba's plastic / roughplastic with the same "
             "eta, roughness and reflectance (internal reflections tint the base, as in pbrt's "
             "layered model); pbrt-v4's stochastic layered evaluation differs slightly");
        const glm::vec3 a = reflectance(d, "albedo", 0.0f, nullptr, depth);
        if (a != glm::vec3(0.0f))
            note("coat albedo", d.loc,
                 "coateddiffuse with a scattering layer (albedo > 0) is not supported; the "
                 "layer is left out");
        for (const char* n : {"thickness", "g"}) float_param(d, n, 0.0f, depth);
        get_int(d, "maxdepth");
        get_int(d, "nsamples");
    } else if (t == "diffusetransmission") {
        m.albedo = reflectance(d, "reflectance", 0.25f, &m.albedo_map, depth);
        note("diffusetransmission", d.loc,
             "diffusetransmission is rendered as diffuse with its reflectance (no transmission)");
        for (Param& p : d.params) p.used = true;
    } else if (t == "mix") {
        Param* p = param(d, "materials", {"string"});
        if (!p || p->strs.size() != 2)
            error(d.loc, "{}: needs \"string materials\" [ \"A\" \"B\" ]", d.describe());
        float amount = float_param(d, "amount", 0.5f, depth);
        if (amount != 0.0f && amount != 1.0f)
            note("mix material", d.loc,
                 "mix materials are rendered as the one with the larger weight (pbrt-v4 picks "
                 "one at random per hit)");
        const std::string pick = p->strs[amount <= 0.5f ? 0 : 1];
        MatRef r;
        r.named = true;
        r.name = pick;
        r.loc = p->loc;
        m = resolve_material(r, depth + 1, interface);
    } else if (t == "interface" || t == "none" || t.empty()) {
        *interface = true;
        note("interface", d.loc,
             "shapes with the \"interface\" material only bound participating media (not "
             "supported); they are left out");
        for (Param& p : d.params) p.used = true;
    } else {
        glm::vec3 c(0.5f);
        if (t == "subsurface" || t == "measured" || t == "hair") {
            if (param(d, "reflectance", {"rgb", "spectrum", "float", "texture", "blackbody"})) {
                for (Param& q : d.params) if (q.name == "reflectance") q.used = false;
                c = reflectance(d, "reflectance", 0.5f, &m.albedo_map, depth);
            }
        }
        note("material " + t, d.loc,
             fmt::format("material \"{}\" is not supported; rendered as diffuse {}", t,
                         c == glm::vec3(0.5f) ? "0.5" : "with its reflectance"));
        m.albedo = c;
        for (Param& q : d.params) q.used = true;
    }
    if (normal_map) {
        m.normal_map = *normal_map;
        m.normal_scale = 1.0f;
    }
    finish(d);
    return m;
}

Material& Reader::resolve_material(const MatRef& r, int depth, bool* interface) {
    if (depth > kMaxMaterialNesting)
        error(r.loc, "materials nested more than {} deep (a mix material that contains itself?)",
              kMaxMaterialNesting);
    MatDef* def = nullptr;
    if (r.named) {
        auto it = named_.find(r.name);
        if (it == named_.end())
            error(r.loc, "no MakeNamedMaterial \"{}\" in the scene", r.name);
        def = &it->second;
    } else {
        def = &anon_[std::size_t(r.anon)];
    }
    if (!def->resolved) {
        if (def->resolving)
            error(def->d.loc, "{} contains itself (through mix)", def->d.describe());
        def->resolving = true;
        bool iface = false;
        def->m = build_material(*def, depth, &iface);
        def->interface = iface;
        def->resolving = false;
        def->resolved = true;
    }
    if (def->interface) *interface = true;
    return def->m;
}

// --- Shapes ---------------------------------------------------------------------------------

void Reader::check_triangles(const Loc& l, std::size_t more) const {
    const std::size_t have = scene_.triangles.size() + object_triangles_;
    if (have + more > std::size_t(limits::kMaxSceneTriangles))
        error(l, "the scene would have more than {} triangles (util/limits.h)",
              limits::kMaxSceneTriangles);
}

// trianglemesh, bilinearmesh, loopsubdiv: P, indices, N, uv.
Geometry Reader::triangle_mesh(Directive& d, bool bilinear) {
    Geometry g;
    Param* p = param(d, "P", {"point3"});
    if (!p) error(d.loc, "{}: missing \"point3 P\"", d.describe());
    const std::size_t n = p->nums.size() / 3;
    if (n == 0) error(p->loc, "{}: \"point3 P\" is empty", d.describe());
    for (std::size_t i = 0; i < n; ++i)
        g.positions.emplace_back(float(p->nums[3 * i]), float(p->nums[3 * i + 1]),
                                 float(p->nums[3 * i + 2]));
    for (const glm::vec3& x : g.positions)
        if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z))
            error(p->loc, "{}: a position is out of the float range", d.describe());
    std::vector<std::uint32_t> idx;
    const std::size_t corners = bilinear ? 4 : 3;
    if (Param* ip = param(d, "indices", {"integer"})) {
        for (double v : ip->nums) {
            if (v < 0.0 || v >= double(n))
                error(ip->loc, "{}: index {} is out of range (there are {} vertices)", d.describe(),
                      v, n);
            idx.push_back(std::uint32_t(v));
        }
        if (idx.size() % corners != 0)
            error(ip->loc, "{}: {} indices is not a multiple of {}", d.describe(), idx.size(),
                  corners);
    } else if (n == corners) {
        for (std::uint32_t i = 0; i < corners; ++i) idx.push_back(i);
    } else {
        error(d.loc, "{}: missing \"integer indices\"", d.describe());
    }
    if (Param* np = param(d, "N", {"normal3"})) {
        if (np->nums.size() / 3 != n)
            error(np->loc, "{}: {} normals for {} positions", d.describe(), np->nums.size() / 3, n);
        for (std::size_t i = 0; i < n; ++i)
            g.normals.emplace_back(float(np->nums[3 * i]), float(np->nums[3 * i + 1]),
                                   float(np->nums[3 * i + 2]));
        g.face_forward = true;
    }
    Param* up = param(d, "uv", {"point2", "float"});
    if (!up) up = param(d, "st", {"point2", "float"});
    if (up) {
        if (up->nums.size() != 2 * n)
            error(up->loc, "{}: {} uvs for {} positions", d.describe(), up->nums.size() / 2, n);
        for (std::size_t i = 0; i < n; ++i)
            g.uvs.emplace_back(float(up->nums[2 * i]), 1.0f - float(up->nums[2 * i + 1]));
    }
    if (param(d, "S", {"vector3"}))
        note("tangents S", d.loc, "per-vertex tangents \"S\" are ignored");
    if (param(d, "faceIndices", {"integer"})) {
        // only Ptex textures read them
    }
    if (!bilinear) {
        for (std::size_t i = 0; i < idx.size(); i += 3)
            g.triangles.emplace_back(idx[i], idx[i + 1], idx[i + 2]);
        return g;
    }
    // Bilinear patches (pbrt's vertex order p00 p10 p01 p11): two triangles each,
    // (p00, p10, p11) and (p00, p11, p01), front = dp/du × dp/dv as pbrt's
    const bool own_uvs = g.uvs.empty();
    Geometry out;
    out.face_forward = g.face_forward;
    bool nonplanar = false;
    for (std::size_t i = 0; i < idx.size(); i += 4) {
        const std::uint32_t v[4] = {idx[i], idx[i + 1], idx[i + 2], idx[i + 3]};
        const glm::dvec3 p00(g.positions[v[0]]), p10(g.positions[v[1]]), p01(g.positions[v[2]]),
            p11(g.positions[v[3]]);
        const glm::dvec3 nrm = glm::cross(p10 - p00, p01 - p00);
        const double size = std::max({glm::length(p10 - p00), glm::length(p01 - p00), 1e-30});
        if (glm::length(nrm) > 0.0 &&
            std::abs(glm::dot(glm::normalize(nrm), p11 - p00)) > 1e-4 * size)
            nonplanar = true;
        const auto base = std::uint32_t(out.positions.size());
        static const glm::vec2 kCorner[4] = {{0, 1}, {1, 1}, {0, 0}, {1, 0}};  // (u, 1 - v)
        for (int c = 0; c < 4; ++c) {
            out.positions.push_back(g.positions[v[c]]);
            if (!g.normals.empty()) out.normals.push_back(g.normals[v[c]]);
            out.uvs.push_back(own_uvs ? kCorner[c] : g.uvs[v[c]]);
        }
        out.triangles.emplace_back(base, base + 1, base + 3);
        out.triangles.emplace_back(base, base + 3, base + 2);
    }
    if (nonplanar)
        note("bilinear", d.loc,
             "non-planar bilinear patches are rendered as two triangles each");
    return out;
}

const Scene& Reader::mesh_file(Directive& d, const std::string& filename) {
    fs::path p(filename);
    if (p.is_relative()) p = dir_ / p;
    const std::string key = p.lexically_normal().string();
    if (auto it = mesh_cache_.find(key); it != mesh_cache_.end()) return it->second;
    std::error_code ec;
    if (!fs::exists(p, ec)) error(d.loc, "{}: mesh file '{}' not found", d.describe(), p.string());
    if (!fs::is_regular_file(p, ec))
        error(d.loc, "{}: mesh file '{}' is not a regular file", d.describe(), p.string());
    Scene s;
    try {
        s = load_mesh_file(p);
    } catch (const Error& e) {
        error(d.loc, "{}: {}", d.describe(), e.what());
    }
    for (auto& w : s.warnings)
        if (w.find("have no material") == std::string::npos) scene_.warnings.push_back(w);
    Scene m;
    m.positions = std::move(s.positions);
    m.triangles = std::move(s.triangles);
    m.normals = std::move(s.normals);
    m.uvs = std::move(s.uvs);
    return mesh_cache_.emplace(key, std::move(m)).first->second;
}

// disk (pbrt-v4): the annulus innerradius <= r <= radius at z = height, front +z, uv
// (φ / φmax, (radius - r) / (radius - innerradius)) with v up. kDiskSegments segments; both
// radii scaled so that the polygon's area is the disk's.
Geometry disk_geometry(double radius, double inner, double height) {
    const int n = kDiskSegments;
    const double k = std::sqrt(kPi / (0.5 * n * std::sin(2.0 * kPi / n)));
    Geometry g;
    for (int ring = 0; ring < 2; ++ring) {
        const double r = (ring == 0 ? radius : inner) * k;
        const float v = ring == 0 ? 1.0f : 0.0f;  // wavepath's 1 - v: outer rim v_pbrt = 0
        for (int i = 0; i <= n; ++i) {
            const double a = 2.0 * kPi * (i % n) / n;
            g.positions.emplace_back(float(r * std::cos(a)), float(r * std::sin(a)), float(height));
            g.uvs.emplace_back(float(i) / float(n), v);
        }
    }
    const auto row = std::uint32_t(n + 1);
    for (std::uint32_t i = 0; i < std::uint32_t(n); ++i) {
        const std::uint32_t o0 = i, o1 = i + 1, i0 = row + i, i1 = row + i + 1;
        g.triangles.push_back({o0, o1, i1});
        if (inner > 0.0) g.triangles.push_back({o0, i1, i0});
    }
    return g;
}

// Adds a shape's triangles: positions by `m`, normals by its inverse transpose. The front
// (wavepath's counter-clockwise winding, the emitting side) is pbrt-v4's: for a mesh with N
// each triangle faces its normals (pbrt's FaceForward); otherwise the object's winding,
// which a mirroring transform (pbrt's transformSwapsHandedness) and ReverseOrientation
// reverse (for spheres and disks ReverseOrientation turns the normals too).
void Reader::add_geometry(const Loc& l, Geometry g, const glm::dmat4& m, bool reverse, int slot,
                          bool to_object) {
    check_triangles(l, g.triangles.size());
    const glm::dmat3 linear(m);
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
    const double det = glm::determinant(linear);
    for (auto& p : g.positions) {
        p = glm::vec3(m * glm::dvec4(glm::dvec3(p), 1.0));
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            error(l, "the transform maps a vertex to a non-finite position");
    }
    for (auto& v : g.normals) {
        const glm::dvec3 w = normal_matrix * glm::dvec3(v);
        const double len = glm::length(w);
        v = len > 0.0 && std::isfinite(len) ? glm::vec3(w / len) : glm::vec3(0.0f);
        if (reverse && g.analytic) v = -v;
    }
    if (g.face_forward && !g.normals.empty()) {
        for (auto& t : g.triangles) {
            const glm::dvec3 a(g.positions[t.x]), b(g.positions[t.y]), c(g.positions[t.z]);
            const glm::dvec3 ns = glm::dvec3(g.normals[t.x]) + glm::dvec3(g.normals[t.y]) +
                                  glm::dvec3(g.normals[t.z]);
            if (glm::dot(glm::cross(b - a, c - a), ns) < 0.0) std::swap(t.y, t.z);
        }
    } else if ((det < 0.0) != reverse) {
        for (auto& t : g.triangles) std::swap(t.y, t.z);
    }
    g.face_forward = false;  // winding final
    if (to_object) {
        ObjectDef& obj = objects_.at(*current_object_);
        obj.triangles += g.triangles.size();
        object_triangles_ += g.triangles.size();
        obj.shapes.push_back({std::move(g), slot});
        return;
    }
    scene_.add_mesh(g.positions, g.triangles, std::uint32_t(slot), g.normals, g.uvs);
}

void Reader::shape(Directive d) {
    apply_attributes(d, "shape");
    const std::string& t = d.type;
    Geometry g;
    if (t == "trianglemesh") {
        g = triangle_mesh(d, false);
    } else if (t == "bilinearmesh") {
        g = triangle_mesh(d, true);
    } else if (t == "loopsubdiv") {
        get_int(d, "levels");
        g = triangle_mesh(d, false);
        note("loopsubdiv", d.loc, "loopsubdiv is rendered as its control mesh (not subdivided)");
    } else if (t == "plymesh") {
        auto file = get_string(d, "filename");
        if (!file || file->empty()) error(d.loc, "{}: missing \"string filename\"", d.describe());
        const Scene& s = mesh_file(d, *file);
        g.positions = s.positions;
        g.triangles = s.triangles;
        g.uvs = s.uvs;  // PLY's v up: the loader stored 1 - v, as wavepath's convention wants
        bool any = false;
        for (const auto& v : s.normals) any = any || v != glm::vec3(0.0f);
        if (any) {
            g.normals = s.normals;
            g.face_forward = true;
        }
        if (param(d, "displacement", {"float", "texture"}) || param(d, "edgelength", {"float"}))
            note("displacement", d.loc, "plymesh displacement is not supported; ignored");
    } else if (t == "sphere") {
        const double r = get_float(d, "radius").value_or(1.0);
        if (!(r > 0.0)) error(d.loc, "{}: radius {} must be > 0", d.describe(), r);
        const double zmin = get_float(d, "zmin").value_or(-r), zmax = get_float(d, "zmax").value_or(r);
        const double phimax = get_float(d, "phimax").value_or(360.0);
        if (zmin > -r || zmax < r || phimax < 360.0)
            note("partial sphere", d.loc,
                 "partial spheres (zmin, zmax, phimax) are rendered as the whole sphere");
        TessellatedShape s = tessellated_sphere(true);
        g.positions = std::move(s.positions);
        g.triangles = std::move(s.triangles);
        g.normals = std::move(s.normals);
        g.uvs = std::move(s.uvs);
        for (auto& p : g.positions) p *= float(r);
        g.analytic = true;
    } else if (t == "disk") {
        const double r = get_float(d, "radius").value_or(1.0);
        const double ri = get_float(d, "innerradius").value_or(0.0);
        const double h = get_float(d, "height").value_or(0.0);
        if (!(r > 0.0) || !(ri >= 0.0) || !(ri < r))
            error(d.loc, "{}: needs 0 <= innerradius ({}) < radius ({})", d.describe(), ri, r);
        if (get_float(d, "phimax").value_or(360.0) < 360.0)
            note("partial disk", d.loc, "partial disks (phimax) are rendered whole");
        g = disk_geometry(r, ri, h);
        g.analytic = true;
    } else {
        note("shape " + t, d.loc,
             fmt::format("Shape \"{}\" is not supported; skipped", t));
        ++skipped_shapes_;
        for (Param& p : d.params) p.used = true;
        return;
    }
    if (Param* a = param(d, "alpha", {"float", "texture"}))
        note("shape alpha", a->loc, "shape \"alpha\" (cut-outs) is not supported; ignored");
    for (const char* e : {"emission", "emissionfilename"}) param(d, e, {"string", "rgb"});
    finish(d);
    if (g.triangles.empty()) return;
    const int slot = current_slot(d.loc);
    add_geometry(d.loc, std::move(g), gs_.ctm, gs_.reverse, slot, current_object_.has_value());
}

// --- The end --------------------------------------------------------------------------------

void Reader::instantiate() {
    // Count first, so that a scene over the cap fails before anything is allocated
    std::size_t total = scene_.triangles.size();
    for (const InstanceUse& use : instances_) {
        auto it = objects_.find(use.name);
        if (it == objects_.end())
            error(use.loc, "ObjectInstance \"{}\": no ObjectBegin \"{}\" in the scene", use.name,
                  use.name);
        total += it->second.triangles;
        if (total > std::size_t(limits::kMaxSceneTriangles))
            error(use.loc,
                  "ObjectInstance \"{}\": the flattened scene would have more than {} "
                  "triangles (util/limits.h)",
                  use.name, limits::kMaxSceneTriangles);
    }
    for (const InstanceUse& use : instances_) {
        const ObjectDef& obj = objects_.at(use.name);
        const glm::dmat3 linear(use.ctm);
        const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
        const bool mirror = glm::determinant(linear) < 0.0;
        for (const InstanceShape& s : obj.shapes) {
            std::vector<glm::vec3> pos, nrm;
            pos.reserve(s.g.positions.size());
            for (const auto& p : s.g.positions) {
                const glm::vec3 q(use.ctm * glm::dvec4(glm::dvec3(p), 1.0));
                if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
                    error(use.loc, "the transform maps a vertex to a non-finite position");
                pos.push_back(q);
            }
            for (const auto& v : s.g.normals) {
                const glm::dvec3 w = normal_matrix * glm::dvec3(v);
                const double len = glm::length(w);
                nrm.push_back(len > 0.0 && std::isfinite(len) ? glm::vec3(w / len) : glm::vec3(0.0f));
            }
            std::vector<glm::uvec3> tris = s.g.triangles;
            if (mirror)
                for (auto& t : tris) std::swap(t.y, t.z);
            scene_.add_mesh(pos, tris, std::uint32_t(s.slot), nrm, s.g.uvs);
        }
    }
}

void Reader::resolve_slots() {
    std::vector<char> drop(slots_.size(), 0);
    for (std::size_t i = 0; i < slots_.size(); ++i) {
        const Slot& s = slots_[i];
        bool interface = false;
        Material m = resolve_material(matrefs_[std::size_t(s.matref)], 0, &interface);
        if (s.light) {
            m.emission = s.light->radiance;
            if (interface) {
                note("interface light", s.light->loc,
                     "an area light on an \"interface\" shape: rendered as a black emitter");
                m = Material{};
                m.name = "interface";
                m.kind = MaterialKind::Diffuse;
                m.albedo = glm::vec3(0.0f);
                m.emission = s.light->radiance;
            }
            m.name += " (emitter)";
        } else if (interface) {
            drop[i] = 1;
        }
        scene_.materials[i] = m;
    }
    // Leave out the triangles of interface shapes
    bool any = false;
    for (char c : drop) any = any || c;
    if (!any) return;
    std::size_t out = 0;
    for (std::size_t t = 0; t < scene_.triangles.size(); ++t) {
        if (drop[scene_.material_ids[t]]) continue;
        scene_.triangles[out] = scene_.triangles[t];
        scene_.material_ids[out] = scene_.material_ids[t];
        ++out;
    }
    scene_.triangles.resize(out);
    scene_.material_ids.resize(out);
}

void Reader::make_camera() {
    // Film
    long long width = 1280, height = 720;
    if (film_) {
        Directive& f = *film_;
        if (f.type != "rgb" && f.type != "gbuffer" && f.type != "spectral")
            note("film " + f.type, f.loc,
                 fmt::format("Film \"{}\" is read as \"rgb\" (xresolution, yresolution)", f.type));
        if (auto x = get_int(f, "xresolution")) width = *x;
        if (auto y = get_int(f, "yresolution")) height = *y;
        if (width < 1 || width > limits::kMaxImageSide || height < 1 ||
            height > limits::kMaxImageSide || width * height > limits::kMaxPixels)
            error(f.loc, "Film: size {} x {} is out of range (each side 1..{}, at most {} pixels)",
                  width, height, limits::kMaxImageSide, limits::kMaxPixels);
        if (get_string(f, "filename"))
            note("film filename", f.loc,
                 "Film \"filename\" is ignored: wavepath writes the file named by --output");
        for (const char* n : {"cropwindow", "pixelbounds"})
            if (param(f, n, {"float", "integer"}))
                note(std::string("film ") + n, f.loc,
                     fmt::format("Film \"{}\" is not supported; the whole image is rendered", n));
        for (const char* n : {"diagonal", "savefp16", "maxcomponentvalue", "sensor"})
            for (Param& p : f.params)
                if (p.name == n) p.used = true;  // do not change the expected value
        finish(f);
    }
    // Sampler (pbrt-v4's default: zsobol, 16 samples per pixel)
    int spp = 16;
    if (sampler_) {
        Directive& s = *sampler_;
        if (auto n = get_int(s, "pixelsamples")) {
            if (*n < limits::kMinSpp || *n > limits::kMaxSpp)
                error(s.loc, "Sampler: pixelsamples {} is out of range ({}..{})", *n,
                      limits::kMinSpp, limits::kMaxSpp);
            spp = *n;
        }
        if (auto seed = get_int(s, "seed")) {
            if (*seed < 0) error(s.loc, "Sampler: seed {} must be >= 0", *seed);
            scene_.render.seed = std::uint32_t(*seed);
        }
        for (Param& p : s.params) p.used = true;  // sampler options do not change the expectation
    }
    scene_.render.spp = spp;
    // Integrator (pbrt-v4's default: volpath, maxdepth 5); maxdepth counts bounces as --depth
    int depth = 5;
    if (integrator_) {
        Directive& in = *integrator_;
        static const std::set<std::string> kPath{"path", "volpath"};
        if (!kPath.count(in.type))
            note("integrator " + in.type, in.loc,
                 fmt::format("Integrator \"{}\" is not supported; wavepath's path tracer renders "
                             "the scene with its maxdepth",
                             in.type));
        if (auto md = get_int(in, "maxdepth")) {
            if (*md < 0) error(in.loc, "Integrator: maxdepth {} must be >= 0", *md);
            depth = std::min(*md, limits::kMaxDepth);
        }
        for (Param& p : in.params)
            if (p.name == "lightsampler" || p.name == "regularize") p.used = true;
        for (Param& p : in.params)
            if (!p.used && in.type != "path" && in.type != "volpath") p.used = true;
        finish(in);
    }
    scene_.render.depth = depth;

    Camera cam;
    cam.width = int(width);
    cam.height = int(height);
    if (!camera_) {
        cam = frame_bounds(scene_.bounds(), files_[0]);
        cam.width = int(width);
        cam.height = int(height);
        note("no camera", Loc{}, "no Camera: the camera frames the scene from +z (40 degrees)");
        scene_.camera = cam;
        return;
    }
    Directive& c = *camera_;
    if (c.type != "perspective")
        note("camera " + c.type, c.loc,
             fmt::format("Camera \"{}\" is rendered as a perspective camera", c.type));
    const double fov = get_float(c, "fov").value_or(90.0);
    if (!(fov > 0.0 && fov < 180.0)) error(c.loc, "Camera: fov {} is out of range (0, 180)", fov);
    const double frame = get_float(c, "frameaspectratio").value_or(double(width) / double(height));
    if (!(frame > 0.0)) error(c.loc, "Camera: frameaspectratio {} must be > 0", frame);
    // pbrt-v4 PerspectiveCamera: the screen window spans [-1, 1] on the shorter axis, where
    // the fov applies (screen y in [-1/frame, 1/frame] for portrait frames)
    double sy = frame > 1.0 ? 1.0 : 1.0 / frame;
    if (Param* sw = param(c, "screenwindow", {"float"})) {
        if (sw->nums.size() != 4) error(sw->loc, "Camera: \"screenwindow\" takes 4 numbers");
        const double x0 = sw->nums[0], x1 = sw->nums[1], y0 = sw->nums[2], y1 = sw->nums[3];
        if (!(x1 > x0) || !(y1 > y0)) error(sw->loc, "Camera: \"screenwindow\" is empty");
        if (std::abs(x0 + x1) > 1e-6 * (x1 - x0) || std::abs(y0 + y1) > 1e-6 * (y1 - y0))
            note("screenwindow", sw->loc,
                 "an off-centre \"screenwindow\" is rendered centred (the same size)");
        const double w = 0.5 * (x1 - x0), h = 0.5 * (y1 - y0);
        if (std::abs(w / h - double(width) / double(height)) > 1e-3 * w / h)
            note("screenwindow aspect", sw->loc,
                 "a \"screenwindow\" whose aspect differs from the film's stretches the image in "
                 "pbrt; wavepath keeps square pixels (the vertical extent is kept)");
        sy = h;
    }
    const double tv = std::tan(0.5 * fov * kPi / 180.0) * sy;
    const float vfov = float(2.0 * std::atan(tv) * 180.0 / kPi);
    if (!(vfov > 0.0f && vfov < 180.0f)) error(c.loc, "Camera: vertical fov {} is out of range", vfov);
    const double lens = get_float(c, "lensradius").value_or(0.0);
    const double focus = get_float(c, "focaldistance").value_or(1e6);
    if (!(lens >= 0.0)) error(c.loc, "Camera: lensradius {} must be >= 0", lens);
    if (!(focus > 0.0)) error(c.loc, "Camera: focaldistance {} must be > 0", focus);
    if (!std::isfinite(float(focus))) error(c.loc, "Camera: focaldistance {} is out of range", focus);
    for (const char* n : {"shutteropen", "shutterclose"}) get_float(c, n);
    finish(c);

    // The camera's frame: world from camera = inverse of the transform at Camera. pbrt's
    // camera looks along +z, +y up, +x to the image's right.
    const double det = glm::determinant(camera_ctm_);
    if (!(std::abs(det) > 0.0) || !std::isfinite(det))
        error(c.loc, "Camera: the transform at Camera is singular");
    const glm::dmat4 w = glm::inverse(camera_ctm_);
    const glm::dvec3 pos(w[3]), right(w[0]), up(w[1]), dir(w[2]);
    if (!(glm::length(dir) > 0.0) || !(glm::length(glm::cross(dir, up)) > 0.0))
        error(c.loc, "Camera: the transform at Camera has no usable viewing direction and up");
    if (glm::dot(right, glm::cross(dir, up)) < 0.0)
        note("mirrored camera", c.loc,
             "pbrt renders this camera's image mirrored (its +x, the image's right, is the "
             "left of a right-handed frame, as after a plain LookAt); wavepath renders it "
             "unmirrored (add Scale -1 1 1 before LookAt for pbrt to agree)");
    const glm::dvec3 fwd = glm::normalize(dir);
    cam.position = glm::vec3(pos);
    cam.target = glm::vec3(pos + fwd);
    cam.up = glm::vec3(glm::normalize(up - glm::dot(up, fwd) * fwd));
    cam.vfov_deg = vfov;
    // Thin lens: pbrt-v4's plane in focus is at camera-space z = focaldistance, the distance
    // along the viewing direction, as Camera::focus_distance
    cam.lens_radius = float(lens);
    cam.focus_distance = float(focus);
    scene_.camera = cam;
}

Scene Reader::read() {
    scene_.name = fs::path(files_[0]).filename().string();
    if (scene_.name.empty()) scene_.name = files_[0];
    MatDef def;  // pbrt's default material: diffuse 0.5
    def.d.what = "Material";
    def.d.type = "diffuse";
    anon_.push_back(std::move(def));
    matrefs_.push_back(MatRef{});
    if (sources_[0].text.size() >= 2 &&
        ((sources_[0].text[0] == '\xFE' && sources_[0].text[1] == '\xFF') ||
         (sources_[0].text[0] == '\xFF' && sources_[0].text[1] == '\xFE')))
        fail("{}: the file is UTF-16; pbrt scene files are UTF-8 or ASCII", files_[0]);
    parse();
    if (!in_world_) fail("{}: no WorldBegin (nothing to render)", files_[0]);
    instantiate();
    resolve_slots();
    if (scene_.triangles.empty())
        fail("{}: no shape that wavepath can render ({} skipped)", files_[0], skipped_shapes_);
    make_camera();
    // uvs only where a material reads them: a texture, or anisotropic roughness (dp/du)
    bool textured = false;
    for (const Material& m : scene_.materials) textured = textured || m.textured() || m.anisotropic();
    if (!textured) scene_.uvs.clear();
    scene_.prune_textures();
    notes_.append_to(scene_.warnings);
    validate_scene(scene_);
    return std::move(scene_);
}

}  // namespace

Scene parse_pbrt(std::string_view text, const fs::path& origin) {
    Reader r(text, origin);
    return r.read();
}

Scene load_pbrt(const fs::path& path) {
    return parse_pbrt(read_file(path, std::uintmax_t(limits::kMaxSceneFileBytes)), path);
}

}  // namespace wp
