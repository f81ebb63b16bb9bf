// kernel_config.h — what the kernels must model for one scene, as compile options.
//
// Derived from the scene (which material kinds exist, whether anything emits) and the
// render settings (estimator, debug injection), and turned into short -D option strings,
// one slice per stage (generate_options(), shade_options(), ...): code for absent material
// kinds, and light sampling for scenes without emitters or strategies without it, is not
// compiled, and a stage is not rebuilt for switches it does not read. The option strings
// are part of the program cache key (cl/program.h).
#pragma once

#include <bitset>
#include <string>

#include "scene/scene.h"
#include "util/limits.h"

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

// The estimator (--sampling, --glossy, --sampler, --rr-depth). The defaults here are the
// shipped configuration, the one definition that the CLI and the renderer use.
struct Estimator {
    Sampling sampling = Sampling::Mis;
    GlossyModel glossy = GlossyModel::Ggx;
    bool sobol = true;   // Owen-scrambled Sobol points (WP_SAMPLER=1), else pcg4d numbers
    int rr_depth = limits::kDefaultRrDepth;  // Russian roulette from this bounce on; < 0 off

    // The original program's estimator: uniform hemisphere, weighted Phong lobe, random
    // numbers, no roulette.
    static Estimator original() { return {Sampling::Uniform, GlossyModel::Phong, false, -1}; }
};

struct KernelConfig {
    // The material kinds some material uses (bit i: MaterialKind i), WP_HAVE_<KIND>.
    std::bitset<kMaterialKindCount> kinds = std::bitset<kMaterialKindCount>().set();
    bool emission = true;  // some material emits
    Estimator estimator;
    // Debug (render --debug-nan): WP_INJECT_* stage bits (kernels/shared/types.h) whose
    // guards get a NaN for every pixel p with p % inject_period == 0; 0 compiles nothing.
    int inject_nan = 0;
    int inject_period = 97;

    bool has(MaterialKind k) const { return kinds.test(static_cast<std::size_t>(k)); }
    // Light sampling is compiled only when something emits and the strategy uses it.
    bool nee() const {
        return emission && (estimator.sampling == Sampling::Nee || estimator.sampling == Sampling::Mis);
    }

    // Every material kind and emission on (the generic program); the given estimator.
    static KernelConfig from_scene(const Scene& scene, const Estimator& estimator = {});

    // Option slices, every switch a stage reads explicit:
    std::string generate_options() const;    // sampler, injection
    std::string shade_options() const;       // materials, estimator, NEE, injection
    std::string accumulate_options() const;  // injection
    // What the renderer prints with -v: the shade slice, the largest.
    std::string options() const { return shade_options(); }

  private:
    std::string inject_options() const;
};

}  // namespace wp::render
