#include "render/kernel_config.h"

#include <fmt/format.h>

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

KernelConfig KernelConfig::from_scene(const Scene& scene, const Estimator& estimator) {
    KernelConfig c;
    c.estimator = estimator;
    c.kinds.reset();
    c.emission = false;
    for (const Material& m : scene.materials) {
        if (static_cast<int>(m.kind) < kMaterialKindCount) c.kinds.set(static_cast<std::size_t>(m.kind));
        c.emission |= m.emissive();
    }
    return c;
}

std::string KernelConfig::inject_options() const {
    if (inject_nan == 0) return "";
    return fmt::format(" -D WP_INJECT_NAN={} -D WP_INJECT_PERIOD={}", inject_nan, inject_period);
}

std::string KernelConfig::generate_options() const {
    return fmt::format("-D WP_SAMPLER={}{}", int(estimator.sobol), inject_options());
}

std::string KernelConfig::shade_options() const {
    std::string o;
#define WP_KIND_OPTION_(KIND, Kind, name, specular, alpha, ior) \
    o += fmt::format("-D WP_HAVE_" #KIND "={} ", int(has(MaterialKind::Kind)));
    WP_MATERIAL_KINDS(WP_KIND_OPTION_)
#undef WP_KIND_OPTION_
    return o + fmt::format("-D WP_HAVE_EMISSION={} -D WP_SAMPLING={} -D WP_GLOSSY_MODEL={} "
                           "-D WP_HAVE_NEE={} -D WP_RR_DEPTH={} -D WP_SAMPLER={}{}",
                           int(emission), static_cast<int>(estimator.sampling),
                           static_cast<int>(estimator.glossy), int(nee()), estimator.rr_depth,
                           int(estimator.sobol), inject_options());
}

std::string KernelConfig::accumulate_options() const {
    std::string s = inject_options();
    return s.empty() ? s : s.substr(1);
}

}  // namespace wp::render
