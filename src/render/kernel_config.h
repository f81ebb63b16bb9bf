// kernel_config.h — what the kernels must model for one scene, as compile options.
//
// Derived from the scene (which material kinds exist, whether anything emits) and the
// render settings (sampling strategy, glossy model, Russian roulette), and turned into a
// short -D option string for shade.cl; code for absent material kinds, and light sampling
// for scenes without emitters or strategies without it, is not compiled. The option string
// is part of the program cache key (cl/program.h).
#pragma once

#include <bitset>
#include <string>

#include "scene/scene.h"

namespace wp::render {

// --sampling (kernels/shared/bsdf.h WP_SAMPLING_*).
enum class Sampling : int {
    Uniform = 0,  // uniform hemisphere for diffuse, no light sampling (the original renderer)
    Cosine = 1,   // BSDF sampling only: cosine-weighted diffuse, lobe/VNDF sampling for glossy
    Nee = 2,      // cosine + next-event estimation (emission after specular bounces only)
    Mis = 3,      // NEE and BSDF sampling, power heuristic (Veach & Guibas 1995)
};
// --glossy (WP_GLOSSY_*).
enum class GlossyModel : int {
    Phong = 0,  // the original weighted Phong lobe
    Ggx = 1,    // GGX microfacet BRDF, visible-normal sampling
};

const char* sampling_name(Sampling s);
const char* glossy_name(GlossyModel g);
// Parse "uniform|cosine|nee|mis" / "phong|ggx"; throw wp::Error naming the option.
Sampling parse_sampling(const std::string& s);
GlossyModel parse_glossy(const std::string& s);

struct KernelConfig {
    // The material kinds some material uses (bit i: MaterialKind i), WP_HAVE_<KIND>.
    std::bitset<kMaterialKindCount> kinds = std::bitset<kMaterialKindCount>().set();
    bool emission = true;  // some material emits
    Sampling sampling = Sampling::Uniform;
    GlossyModel glossy_model = GlossyModel::Phong;
    bool sobol = false;    // --sampler sobol: Owen-scrambled Sobol points (WP_SAMPLER=1)
    int rr_depth = -1;     // first bounce at which Russian roulette may end a path; < 0 off

    // Light sampling is compiled only when something emits and the strategy uses it.
    bool has(MaterialKind k) const { return kinds.test(static_cast<std::size_t>(k)); }
    bool nee() const { return emission && (sampling == Sampling::Nee || sampling == Sampling::Mis); }

    static KernelConfig from_scene(const Scene& scene);
    // "-D WP_HAVE_DIFFUSE=1 -D WP_HAVE_MIRROR=0 ..." (every switch explicit).
    std::string options() const;
};

}  // namespace wp::render
