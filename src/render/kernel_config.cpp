#include "render/kernel_config.h"

#include <fmt/format.h>

#include <algorithm>
#include <vector>

#include "scene/light_pairs.h"
#include "util/error.h"

namespace wp::render {

const char* sampling_name(Sampling s) {
    switch (s) {
        case Sampling::Uniform: return "uniform";
        case Sampling::Cosine: return "cosine";
        case Sampling::Nee: return "nee";
        case Sampling::Mis: return "mis";
    }
    return "?";
}

const char* glossy_name(GlossyModel g) { return g == GlossyModel::Phong ? "phong" : "ggx"; }

Sampling parse_sampling(const std::string& s) {
    if (s == "uniform") return Sampling::Uniform;
    if (s == "cosine") return Sampling::Cosine;
    if (s == "nee") return Sampling::Nee;
    if (s == "mis") return Sampling::Mis;
    fail("--sampling '{}': expected uniform, cosine, nee or mis", s);
}

GlossyModel parse_glossy(const std::string& s) {
    if (s == "phong") return GlossyModel::Phong;
    if (s == "ggx") return GlossyModel::Ggx;
    fail("--glossy '{}': expected phong or ggx", s);
}

const char* kernel_set_name(KernelSet k) {
    return k == KernelSet::Generic ? "generic" : "specialised";
}

KernelSet parse_kernel_set(const std::string& s) {
    if (s == "specialised") return KernelSet::Specialised;
    if (s == "generic") return KernelSet::Generic;
    fail("--kernels '{}': expected specialised or generic", s);
}

KernelConfig KernelConfig::with_every_feature() const {
    KernelConfig c = *this;
    c.kinds.set();
    c.emission = true;
    c.normals = c.textures = c.normal_maps = c.alpha_mask = c.env = c.lens = c.anisotropic = true;
    c.light_pairs = true;
    c.light_clearance = true;
    return c;
}

KernelConfig KernelConfig::from_scene(const Scene& scene, const Estimator& estimator, bool light_pairs) {
    KernelConfig c;
    c.estimator = estimator;
    c.kinds.reset();
    c.emission = false;
    // Only materials some triangle uses count for the appearance features.
    std::vector<char> used(scene.materials.size(), 0);
    for (std::uint32_t id : scene.material_ids)
        if (id < used.size()) used[id] = 1;
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        if (static_cast<int>(m.kind) < kMaterialKindCount) c.kinds.set(static_cast<std::size_t>(m.kind));
        c.emission |= m.emissive();
        if (!used[i]) continue;
        c.textures |= m.textured();  // a scene without uvs reads texel (0, 0)
        c.normal_maps |= m.normal_map.used();
        c.alpha_mask |= m.alpha_masked();
        c.anisotropic |= m.anisotropic();
    }
    for (const glm::vec3& n : scene.normals)
        if (n != glm::vec3(0.0f)) {
            c.normals = true;
            break;
        }
    // A normal map needs a shading frame: the geometric normal serves where there are no
    // vertex normals.
    c.normals |= c.normal_maps;
    c.env = scene.environment.has_value() && scene.environment->image >= 0;
    // Pairs matter to light sampling only (the search costs ~1 µs a light triangle).
    if (c.nee() && light_pairs) {
        auto partner = std::make_shared<const std::vector<int>>(find_light_partners(scene));
        c.light_pairs = std::any_of(partner->begin(), partner->end(), [](int p) { return p >= 0; });
        if (c.light_pairs) c.light_partners = std::move(partner);
    }
    c.lens = scene.camera.lens_radius > 0.0f;
    return c;
}

std::string KernelConfig::inject_options() const {
    if (inject_nan == 0) return "";
    return fmt::format(" -D WP_INJECT_NAN={} -D WP_INJECT_PERIOD={}", inject_nan, inject_period);
}

std::string KernelConfig::replicate_options() const {
    if (!estimator.sobol || replicates <= 1) return "";
    return fmt::format(" -D WP_SOBOL_REPLICATES={}", replicates);
}

std::string KernelConfig::generate_options() const {
    // The lens switch only when on: a pinhole camera keeps its program and cache key.
    return fmt::format("-D WP_SAMPLER={}{}{}{}{}{}", int(estimator.sobol),
                       lens ? " -D WP_HAVE_LENS=1" : "", generate_lanes ? " -D WP_GENERATE_LANES=1" : "",
                       stream_stores ? " -D WP_STREAM_STORES=1" : "", replicate_options(), inject_options());
}

std::string KernelConfig::shade_options() const {
    std::string o;
#define WP_KIND_OPTION_(KIND, Kind, name, specular, alpha, ior, etak) \
    o += fmt::format("-D WP_HAVE_" #KIND "={} ", int(has(MaterialKind::Kind)));
    WP_MATERIAL_KINDS(WP_KIND_OPTION_)
#undef WP_KIND_OPTION_
    o += fmt::format("-D WP_HAVE_EMISSION={} -D WP_SAMPLING={} -D WP_GLOSSY_MODEL={} "
                     "-D WP_HAVE_NEE={} -D WP_RR_DEPTH={} -D WP_SAMPLER={}",
                     int(emission), static_cast<int>(estimator.sampling),
                     static_cast<int>(estimator.glossy), int(nee()), estimator.rr_depth,
                     int(estimator.sobol));
    // The appearance switches only when on, so a scene without them keeps the program
    // (and the cache key) it had before they existed.
    if (normals) o += " -D WP_HAVE_NORMALS=1";
    if (textures) o += " -D WP_HAVE_TEXTURES=1";
    if (normal_maps) o += " -D WP_HAVE_NORMAL_MAPS=1";
    if (env) o += " -D WP_HAVE_ENV=1";
    if (anisotropic) o += " -D WP_HAVE_ANISOTROPY=1";
    if (sample_pairs()) o += " -D WP_HAVE_LIGHT_PAIRS=1";
    if (clear_shadow_ends()) o += " -D WP_HAVE_LIGHT_CLEARANCE=1";
    if (stream_stores) o += " -D WP_STREAM_STORES=1";
    if (shade_lanes()) o += " -D WP_SHADE_LANES=1";
    if (shade_traces_shadows()) o += " -D WP_SHADE_TRACES_SHADOWS=1";
    if (shade_final()) o += " -D WP_SHADE_FINAL=1";
    return o + replicate_options() + inject_options();
}

bool KernelConfig::shade_lanes() const {
    // Keep in step with the #error list of shade_surface8 (kernels/shade.cl). Every material
    // kind: the kinds without lane code take their scalar BSDF lane by lane there.
    return lanes && !textures && !normal_maps && !env && !anisotropic && inject_nan == 0;
}

bool KernelConfig::shade_traces_shadows() const {
    // The lane kernel's any hit takes none of the alpha test's arguments, so a scene with
    // cut-outs (textured, or a constant alpha below its cutoff, which needs no texture)
    // keeps the shadow stage, whose traversal skips them.
    return shadows_in_shade && shade_lanes() && nee() && !alpha_mask;
}

bool KernelConfig::shadow_queue() const { return nee() && !shade_traces_shadows(); }

std::string KernelConfig::trace_options() const {
    return alpha_mask ? "-D WP_HAVE_ALPHA_MASK=1" : "";
}

std::string KernelConfig::aov_options() const {
    std::string o;
    if (normals) o += " -D WP_HAVE_NORMALS=1";
    if (textures) o += " -D WP_HAVE_TEXTURES=1";
    if (normal_maps) o += " -D WP_HAVE_NORMAL_MAPS=1";
    return o.empty() ? o : o.substr(1);
}

bool KernelConfig::any_specular() const {
    bool any = false;
#define WP_KIND_SPECULAR_(KIND, Kind, name, specular, alpha, ior, etak) \
    any |= (specular) && has(MaterialKind::Kind);
    WP_MATERIAL_KINDS(WP_KIND_SPECULAR_)
#undef WP_KIND_SPECULAR_
    return any;
}

std::string KernelConfig::accumulate_options() const {
    std::string s = inject_options();
    return s.empty() ? s : s.substr(1);
}

}  // namespace wp::render
