#include "app/render_options.h"

#include <unistd.h>

#include <array>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <regex>

#include <glm/gtc/matrix_transform.hpp>

#include "image/codec.h"
#include "image/image.h"
#include "scene/builtin.h"
#include "scene/load.h"
#include "scene/normals.h"
#include "scene/texture.h"
#include "scene/validate.h"
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
                  "'platform: name' (default: the first GPU, else the first device; `render` under mpirun: "
                  "each rank the GPU, else the device, numbered by its rank on the node)");
    c->add_option("--traversal", a.traversal,
                  "Closest-hit BVH traversal of the intersect stage: stackless (ordered, "
                  "the default) or stack (the small private-stack traversal, kept as the "
                  "oracle and speed reference)")
        ->capture_default_str();
    c->add_option("--sampling", a.sampling,
                  "Estimator: uniform (the original: uniform hemisphere, no light sampling), "
                  "cosine (BSDF sampling only: cosine diffuse, GGX visible normals), nee "
                  "(cosine + next-event estimation to emissive triangles and the environment map) or mis (NEE and "
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
    c->add_option("--kernels", a.kernels,
                  "Kernel programs: specialised (compiled for what the scene has: its material "
                  "kinds, emission, normals, textures, normal maps, cut-outs, environment, "
                  "anisotropy, thin lens) or generic (every stage with every feature switch on, "
                  "the scene's missing features fed neutral data (a black environment that light "
                  "sampling never picks): the same estimator and image in expectation, for "
                  "measuring what specialisation gains)")
        ->capture_default_str();
    c->add_option("--shade-lanes", a.shade_lanes,
                  "on: on a CPU device, shade eight paths at a time in vector lanes where "
                  "that kernel models the scene (any material kind: diffuse, mirror, glossy and "
                  "rough conductor in lane code, the other kinds' BSDFs one lane at a time; "
                  "shading normals; no "
                  "textures, normal maps, anisotropy or environment); the same image bit for "
                  "bit. off: one path per work-item always")
        ->capture_default_str();
    c->add_option("--shadow-rays", a.shadow_rays,
                  "shade: where shading runs in vector lanes (--shade-lanes) with light sampling "
                  "and no material is cut out, it traces its shadow rays itself; the same image bit for bit, without the "
                  "shadow queue (52 bytes a path in flight) or a shadow stage. stage: shadow "
                  "rays go through a queue to their own stage, which --profile then times apart "
                  "(\"shadow\"; with shade, its time is part of \"shade\")")
        ->capture_default_str();
    c->add_option("--light-pairs", a.light_pairs,
                  "on: light sampling draws the half of a closed emitter (a tessellated sphere "
                  "light, an emitting box) that faces the shading point: a sample on a light "
                  "triangle that faces away moves to its back-to-back partner on the far side "
                  "(docs/design.md, \"Light pairs\"); the same image in expectation, less noise. "
                  "off: every sample stays on the triangle the light table picked")
        ->capture_default_str();
    c->add_option("--light-clearance", a.light_clearance,
                  "on: a shadow ray towards a light triangle ends where its clearance begins "
                  "(the distance from the light to the nearest triangle that reaches in front "
                  "of its plane, found once at load; docs/design.md, \"Light clearance\"), so it "
                  "skips the light's own neighbourhood, where it can meet nothing; the same "
                  "image. off: "
                  "every shadow ray runs up to the light's plane (less its error bound)")
        ->capture_default_str();
    c->add_option("--final-rays", a.final_rays,
                  "emitters: where escaped rays carry no light (black background, no "
                  "environment), without --aov or --denoise, and where emitters hold at most a "
                  "quarter of the surface area, the last bounce's rays are traced through the "
                  "emitting triangles' own BVH first, and through the scene only up to the "
                  "emitter they meet (at the last bounce only an emitter adds light; "
                  "docs/design.md, \"The last bounce's rays\"); the same image bit for bit. "
                  "closest: every bounce traced through the whole scene")
        ->capture_default_str();
    c->add_flag("--adaptive", a.adaptive,
                "Adaptive sampling: after --min-spp samples, a pixel stops receiving samples "
                "when the largest estimated relMSE over its 3x3 neighbourhood (per pixel: 1/3 "
                "sum over channels of (s^2/n) / (mean^2 + 0.01), from its own samples) is <= "
                "--adaptive-threshold; checked at --min-spp, then every max(4, spp/4) passes. "
                "Each pixel stays the mean of its own samples (--spp is then the most samples "
                "a pixel gets); see docs/adaptive.md")
        ->group("Adaptive sampling");
    c->add_option("--adaptive-threshold", a.adaptive_threshold,
                  "The estimated relMSE at which --adaptive stops a pixel (the largest over "
                  "its 3x3 neighbourhood), " +
                      fmt::format("{:g}..{:g}. Default {:g}, or the --target-error when one is given",
                                  limits::kMinErrorThreshold, limits::kMaxErrorThreshold,
                                  limits::kDefaultAdaptiveThreshold))
        ->group("Adaptive sampling")
        ->each([&a](const std::string&) { a.adaptive_threshold_given = true; });
    c->add_option("--min-spp", a.min_spp,
                  fmt::format("Samples every pixel gets before --adaptive may stop it and before "
                              "--target-error trusts its estimate, {}..2^24",
                              limits::kMinMinSpp))
        ->capture_default_str()
        ->group("Adaptive sampling");
    c->add_option("--replicates", a.replicates,
                  fmt::format("RQMC replicates K, a power of two in 1..{}: sample s of a pixel is "
                              "point s/K of replicate s mod K, each replicate an independently "
                              "scrambled Sobol sequence, and --target-error estimates each pixel's "
                              "variance from the spread of its K replicate means (s^2/n overstates "
                              "the error of Sobol points; --adaptive's per-pixel stopping keeps "
                              "s^2/n). Estimates and --adaptive checks then fall on multiples of K samples. Costs part of "
                              "Sobol's advantage at equal samples (docs/adaptive.md). 0 = auto: {} "
                              "with --target-error and --sampler sobol, else 1 (none)",
                              limits::kMaxReplicates, limits::kDefaultReplicates))
        ->capture_default_str()
        ->group("Adaptive sampling");
}

render::RenderSettings make_settings(const ConfigArgs& a, const Scene& scene) {
    if (a.depth < limits::kMinDepth || a.depth > limits::kMaxDepth)
        usage_fail("--depth must be in {}..{} (got {})", limits::kMinDepth, limits::kMaxDepth, a.depth);
    render::RenderSettings s;
    s.width = scene.camera.width;
    s.height = scene.camera.height;
    if (!a.size.empty()) {
        static const std::regex re(R"((\d{1,6})[xX](\d{1,6}))");
        std::smatch m;
        if (!std::regex_match(a.size, m, re))
            usage_fail("--size '{}': expected WIDTHxHEIGHT, e.g. 800x600", a.size);
        int w = std::stoi(m[1]), h = std::stoi(m[2]);
        if (w <= 0 || h <= 0) usage_fail("--size '{}': width and height must be in 1..{}", a.size,
                                          limits::kMaxImageSide);
        if (w > limits::kMaxImageSide || h > limits::kMaxImageSide)
            usage_fail("--size '{}': each side must be in 1..{} pixels", a.size, limits::kMaxImageSide);
        if (static_cast<std::int64_t>(w) * h > limits::kMaxPixels)
            usage_fail("--size '{}': more than {} pixels in all (at most {})", a.size,
                       limits::kMaxPixels, limits::kMaxPixels);
        s.width = w;
        s.height = h;
    }
    if (a.traversal == "stackless")
        s.traversal = render::Traversal::Stackless;
    else if (a.traversal == "stack")
        s.traversal = render::Traversal::Stack;
    else
        usage_fail("--traversal '{}': expected stackless or stack", a.traversal);
    s.depth = a.depth_given || !scene.render.depth ? a.depth : *scene.render.depth;
    s.estimator.sampling = render::parse_sampling(a.sampling);
    s.estimator.glossy = render::parse_glossy(a.glossy);
    if (a.rr_depth < -1 || a.rr_depth > limits::kMaxDepth)
        usage_fail("--rr-depth must be -1 (off) or in 0..{} (got {})", limits::kMaxDepth,
                   a.rr_depth);
    s.estimator.rr_depth = a.rr_depth;
    if (a.sampler != "random" && a.sampler != "sobol")
        usage_fail("--sampler '{}': expected random or sobol", a.sampler);
    s.estimator.sobol = a.sampler == "sobol";
    if (a.pool < 0 || a.pool > limits::kMaxPool)
        usage_fail("--pool must be in 0..{} paths (0: automatic; got {})", limits::kMaxPool, a.pool);
    s.pool = static_cast<std::size_t>(a.pool);
    if (a.kernels != "specialised" && a.kernels != "generic")
        usage_fail("--kernels '{}': expected specialised or generic", a.kernels);
    s.kernels = render::parse_kernel_set(a.kernels);
    if (a.shade_lanes != "on" && a.shade_lanes != "off")
        usage_fail("--shade-lanes '{}': expected on or off", a.shade_lanes);
    s.shade_lanes = a.shade_lanes == "on";
    if (a.light_pairs != "on" && a.light_pairs != "off")
        usage_fail("--light-pairs '{}': expected on or off", a.light_pairs);
    s.light_pairs = a.light_pairs == "on";
    if (a.shadow_rays != "shade" && a.shadow_rays != "stage")
        usage_fail("--shadow-rays '{}': expected shade or stage", a.shadow_rays);
    s.shadows_in_shade = a.shadow_rays == "shade";
    if (a.light_clearance != "on" && a.light_clearance != "off")
        usage_fail("--light-clearance '{}': expected on or off", a.light_clearance);
    s.light_clearance = a.light_clearance == "on";
    if (a.final_rays != "emitters" && a.final_rays != "closest")
        usage_fail("--final-rays '{}': expected emitters or closest", a.final_rays);
    s.final_rays = a.final_rays == "emitters";
    if (!(a.adaptive_threshold >= limits::kMinErrorThreshold &&
          a.adaptive_threshold <= limits::kMaxErrorThreshold))
        usage_fail("--adaptive-threshold must be in {:g}..{:g} (got {})", limits::kMinErrorThreshold,
                   limits::kMaxErrorThreshold, a.adaptive_threshold);
    if (a.min_spp < limits::kMinMinSpp || a.min_spp > limits::kMaxSpp)
        usage_fail("--min-spp must be in {}..{} (got {})", limits::kMinMinSpp, limits::kMaxSpp,
                   a.min_spp);
    if (a.adaptive_threshold_given && !a.adaptive)
        usage_fail("--adaptive-threshold needs --adaptive");
    s.adaptive.enabled = a.adaptive;
    s.adaptive.threshold = a.adaptive_threshold;
    s.adaptive.min_spp = a.min_spp;
    if (a.replicates < 0 || a.replicates > limits::kMaxReplicates ||
        (a.replicates & (a.replicates - 1)) != 0)
        usage_fail("--replicates must be 0 (auto) or a power of two in 1..{} (got {})",
                   limits::kMaxReplicates, a.replicates);
    s.replicates = a.replicates == 0 ? 1 : static_cast<int>(a.replicates);
    return s;
}

void add_scene_edit_options(CLI::App* c, SceneEdits& e) {
    c->add_option("--env", e.env,
                  "Environment light: an equirectangular (latitude-longitude, 2:1) image (.exr, "
                  ".hdr or any format the textures read) that replaces the scene's environment "
                  "map")
        ->type_name("FILE")
        ->group("Scene");
    c->add_option("--env-scale", e.env_scale,
                  "Radiance scale S of the environment map, 0..1e6 (with --env: its scale; "
                  "without: multiplies the scene file's). Default 1")
        ->type_name("S")
        ->group("Scene")
        ->each([&e](const std::string&) { e.env_scale_given = true; });
    c->add_option("--env-rotate", e.env_rotate,
                  "Turn the environment map by DEG degrees about +y (right-handed), -360..360 "
                  "(with --env: its rotation; without: after the scene file's own). Default 0")
        ->type_name("DEG")
        ->group("Scene")
        ->each([&e](const std::string&) { e.env_rotate_given = true; });
    c->add_option("--smooth", e.smooth,
                  "Smooth shading for every triangle that has no normals (any scene): "
                  "angle-weighted vertex normals, split where faces meet at more than DEG "
                  "degrees, 0..180 (180: no creases)")
        ->type_name("DEG")
        ->group("Scene")
        ->each([&e](const std::string&) { e.smooth_given = true; });
}

void check_scene_edits(const SceneEdits& e) {
    if (!(e.env_scale >= 0.0 && e.env_scale <= limits::kMaxEnvScale))
        usage_fail("--env-scale must be in 0..{} (got {})", limits::kMaxEnvScale, e.env_scale);
    if (!(e.env_rotate >= -limits::kMaxEnvRotateDeg && e.env_rotate <= limits::kMaxEnvRotateDeg))
        usage_fail("--env-rotate must be in -{}..{} degrees (got {})", limits::kMaxEnvRotateDeg,
                   limits::kMaxEnvRotateDeg, e.env_rotate);
    if (e.smooth_given && !(e.smooth >= 0.0 && e.smooth <= limits::kMaxCreaseDeg))
        usage_fail("--smooth must be in 0..{} degrees (got {})", limits::kMaxCreaseDeg, e.smooth);
    if (!e.env.empty()) {
        std::error_code ec;
        if (!fs::is_regular_file(e.env, ec))
            fail("--env '{}': {}", e.env,
                 fs::exists(e.env, ec) ? "not a regular file" : "file not found");
    }
}

namespace {

glm::mat3 rotate_y(double degrees) {
    return glm::mat3(glm::rotate(glm::mat4(1.0f), glm::radians(float(degrees)), glm::vec3(0, 1, 0)));
}

}  // namespace

void apply_scene_edits(const SceneEdits& e, Scene& scene) {
    if (!e.env.empty()) {
        if (scene.environment) {
            scene.environment.reset();
            scene.prune_textures();  // the replaced map, unless a material uses it too
        }
        Environment env;
        // Asked for by name: a file that does not decode is an error (exit 1), not the
        // placeholder a texture named inside a scene file gets.
        scene.textures.push_back(load_texture(e.env, TextureUse::Colour, scene.warnings));
        env.image = static_cast<int>(scene.textures.size() - 1);
        env.scale = float(e.env_scale);
        env.to_world = rotate_y(e.env_rotate);
        scene.environment = env;
    } else if (e.env_scale_given || e.env_rotate_given) {
        if (!scene.environment)
            usage_fail("{}: the scene has no environment map; give one with --env FILE",
                       e.env_scale_given ? "--env-scale" : "--env-rotate");
        scene.environment->scale *= float(e.env_scale);
        scene.environment->to_world = rotate_y(e.env_rotate) * scene.environment->to_world;
    }
    if (e.smooth_given) smooth_normals(scene, float(e.smooth), 0);
}

const char* const kSceneArgHelp =
    "Scene: a wavepath scene file (.json), a Mitsuba 3 scene (.xml), a pbrt-v4 scene (.pbrt), a mesh file (.obj with its "
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

Scene load_scene(const std::string& arg, bool quiet, const SceneEdits* edits) {
    Scene scene = load_any(arg, quiet);
    if (edits) apply_scene_edits(*edits, scene);
    // The one no-light warning, whatever the format (OBJ, PLY, glTF, XML, JSON, built-ins),
    // after the edits (--env lights a scene too).
    if (!has_light(scene))
        scene.warnings.push_back(no_light_warning(arg.empty() ? "builtin:cornell-box" : arg));
    if (!quiet)
        for (const auto& w : scene.warnings) fmt::print(stderr, "wavepath: warning: {}\n", w);
    return scene;
}

void check_writable(const fs::path& path, const char* what, bool image) {
    if (image && !is_supported_image_path(path))
        usage_fail("{} '{}': unknown image extension '{}' (supported: .exr, .png, .jpg, .jpeg)",
                   what, path.string(), path.extension().string());
    if (image) codec::check_available();
    fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        fail("{} '{}': folder '{}' does not exist", what, path.string(), dir.string());
    if (fs::is_directory(path, ec)) fail("{} '{}' is a folder", what, path.string());
    // Create, write and remove a probe file where the output's temporary will go
    // (util/atomic_file.h): permissions alone miss a read-only or pseudo file system
    // (/proc), root's bypass of them and a full disk, each of which would otherwise be found
    // only after the whole render.
    std::string probe = (dir / ".wavepath-probe-XXXXXX").string();
    int fd = ::mkstemp(probe.data());
    if (fd < 0) {
        const int e = errno;
        fail("{} '{}': cannot create a file in folder '{}': {}", what, path.string(),
             dir.string(), std::strerror(e));
    }
    // A block's worth of bytes, so that a full disk fails here too (file systems with delayed
    // allocation still reserve the space at write time).
    const std::string block(4096, '\0');
    const ssize_t n = ::write(fd, block.data(), block.size());
    const int write_errno = errno;
    const bool closed = ::close(fd) == 0;
    const int close_errno = errno;
    ::unlink(probe.c_str());
    if (n != static_cast<ssize_t>(block.size()) || !closed)
        fail("{} '{}': cannot write in folder '{}': {}", what, path.string(), dir.string(),
             std::strerror(n < 0 ? write_errno : !closed ? close_errno : ENOSPC));
}

}  // namespace wp::app
