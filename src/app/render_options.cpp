#include "app/render_options.h"

#include <unistd.h>

#include <cctype>
#include <regex>

#include "image/image.h"
#include "scene/builtin.h"
#include "scene/load.h"
#include "util/error.h"
#include "util/timer.h"

namespace wp::app {

namespace fs = std::filesystem;

void add_config_options(CLI::App* c, ConfigArgs& a) {
    c->add_option("--depth", a.depth,
                  "Maximum number of bounces (scattering events) per path, 0..2^20: 0 shows only "
                  "emitters and the background, D gathers light that bounced at most D times "
                  "(beats the scene file's depth). Default: the scene file's depth, else " +
                      std::to_string(limits::kDefaultSceneDepth) + " for a scene file and " +
                      std::to_string(limits::kDefaultDepth) + " for the built-in scenes")
        ->each([&a](const std::string&) { a.depth_given = true; });
    c->add_option("--size", a.size,
                  "Image size WIDTHxHEIGHT in pixels (default: the scene's, 800x600)");
    c->add_option("--device", a.device,
                  "OpenCL device: an index from `wavepath devices`, or text matched against "
                  "'platform: name' (default: the first GPU, else the first device)");
    c->add_option("--traversal", a.traversal,
                  "Closest-hit BVH traversal of the intersect stage: stackless (ordered, "
                  "the default) or stack (the small private-stack traversal, kept as the "
                  "oracle and speed reference)")
        ->capture_default_str();
    c->add_option("--sampling", a.sampling,
                  "Estimator: uniform (the original: uniform hemisphere, no light sampling), "
                  "cosine (BSDF sampling only: cosine diffuse, GGX visible normals), nee "
                  "(cosine + next-event estimation to emissive triangles) or mis (NEE and "
                  "BSDF sampling combined by the power heuristic; the default)")
        ->capture_default_str();
    c->add_option("--glossy", a.glossy,
                  "Glossy BRDF: ggx (microfacet with the material's roughness alpha; a Phong "
                  "exponent e in a scene is alpha = sqrt(2 / (e + 2)); the default) or phong "
                  "(the original weighted Phong lobe, exponent 2 / alpha^2 - 2)")
        ->capture_default_str();
    c->add_option("--sampler", a.sampler,
                  "Sample numbers: sobol (Owen-scrambled Sobol points, Burley 2020, per pixel "
                  "and dimension group; the default) or random (the counter-based pcg4d "
                  "numbers of the original)")
        ->capture_default_str();
    c->add_option("--rr-depth", a.rr_depth,
                  "Russian roulette from this bounce on (survival min(1, max throughput "
                  "component), unbiased); -1 disables it. Paths still end at --depth")
        ->capture_default_str();
    c->add_option("--pool", a.pool,
                  "Paths in flight: the samples run in waves of this many (several passes of a "
                  "small image, or parts of one pass of a large one); the image is the same "
                  "bit for bit whatever the size. 0 (the default): min(2^20, 16 passes of the "
                  "image), at most a quarter of the device's memory (212 bytes a path with "
                  "light sampling, 160 without)")
        ->capture_default_str();
}

render::RenderSettings make_settings(const ConfigArgs& a, const Scene& scene) {
    if (a.depth < limits::kMinDepth || a.depth > limits::kMaxDepth)
        fail("--depth must be in {}..{} (got {})", limits::kMinDepth, limits::kMaxDepth, a.depth);
    render::RenderSettings s;
    s.width = scene.camera.width;
    s.height = scene.camera.height;
    if (!a.size.empty()) {
        static const std::regex re(R"((\d{1,6})[xX](\d{1,6}))");
        std::smatch m;
        if (!std::regex_match(a.size, m, re))
            fail("--size '{}': expected WIDTHxHEIGHT, e.g. 800x600", a.size);
        int w = std::stoi(m[1]), h = std::stoi(m[2]);
        if (w <= 0 || h <= 0) fail("--size '{}': width and height must be positive", a.size);
        if (w > limits::kMaxImageSide || h > limits::kMaxImageSide)
            fail("--size '{}': each side must be at most {} pixels", a.size, limits::kMaxImageSide);
        if (static_cast<std::int64_t>(w) * h > limits::kMaxPixels)
            fail("--size '{}': more than {} pixels", a.size, limits::kMaxPixels);
        s.width = w;
        s.height = h;
    }
    if (a.traversal == "stackless")
        s.traversal = render::Traversal::Stackless;
    else if (a.traversal == "stack")
        s.traversal = render::Traversal::Stack;
    else
        fail("--traversal '{}': expected stackless or stack", a.traversal);
    s.depth = a.depth_given || !scene.render.depth ? a.depth : *scene.render.depth;
    s.estimator.sampling = render::parse_sampling(a.sampling);
    s.estimator.glossy = render::parse_glossy(a.glossy);
    if (a.rr_depth < -1) fail("--rr-depth must be -1 (off) or >= 0 (got {})", a.rr_depth);
    s.estimator.rr_depth = a.rr_depth;
    if (a.sampler != "random" && a.sampler != "sobol")
        fail("--sampler '{}': expected random or sobol", a.sampler);
    s.estimator.sobol = a.sampler == "sobol";
    s.pool = a.pool;
    return s;
}

const char* const kSceneArgHelp =
    "Scene: a wavepath scene file (.json), a Mitsuba 3 scene (.xml), a mesh file (.obj with its "
    ".mtl, .gltf, .glb, .ply, .stl, .3ds, .dae, .fbx), or builtin:cornell-box (the "
    "default), builtin:closed-box-furnace, builtin:veach-plates";

namespace {

Scene load_any(const std::string& arg, bool quiet) {
    if (arg.empty() || arg == "builtin:cornell-box") return make_cornell_box();
    // The analytic furnace of the render tests: emission 0.5, albedo 0.6.
    if (arg == "builtin:closed-box-furnace") return make_closed_box_furnace(0.5f, 0.6f);
    if (arg == "builtin:veach-plates") return make_veach_plates();
    if (arg.rfind("builtin:", 0) == 0)
        fail("scene '{}': unknown built-in scene (builtin:cornell-box, "
             "builtin:closed-box-furnace, builtin:veach-plates)", arg);
    Timer t;
    Scene scene = load_scene_file(arg);
    if (!quiet) fmt::print(stderr, "wavepath: {}\n", describe_scene(scene, t.ms()));
    // A scene file without a depth of its own gets the physically sensible default; the
    // built-in scenes keep the original program's 3 (the benchmarks' workload).
    if (!scene.render.depth) scene.render.depth = limits::kDefaultSceneDepth;
    return scene;
}

}  // namespace

Scene load_scene(const std::string& arg, bool quiet) {
    Scene scene = load_any(arg, quiet);
    if (!quiet)
        for (const auto& w : scene.warnings) fmt::print(stderr, "wavepath: warning: {}\n", w);
    return scene;
}

void check_writable(const fs::path& path, const char* what, bool image) {
    if (image && !is_supported_image_path(path))
        fail("{} '{}': unknown image extension '{}' (supported: .exr, .png, .jpg, .jpeg)", what,
             path.string(), path.extension().string());
    fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        fail("{} '{}': folder '{}' does not exist", what, path.string(), dir.string());
    if (access(dir.c_str(), W_OK) != 0)
        fail("{} '{}': folder '{}' is not writable", what, path.string(), dir.string());
    if (fs::is_directory(path, ec)) fail("{} '{}' is a folder", what, path.string());
}

}  // namespace wp::app
