// kernel_config.h — what the kernels must model for one scene, as compile options.
//
// Derived from the scene (which material kinds exist, whether anything emits) and the
// render settings (estimator, debug injection), and turned into short -D option strings,
// one slice per stage (generate_options(), shade_options(), ...): code for absent material
// kinds, and light sampling for scenes without emitters or strategies without it, is not
// compiled, and a stage is not rebuilt for switches it does not read. The option strings
// are part of the program cache key (cl/program.h).
//
// `render --kernels generic` builds every stage with every feature switch on instead
// (KernelConfig::with_every_feature()): one program set that models everything, the
// baseline against which the specialised kernels are measured (docs/performance.md, "Model
// only what the scene needs"). The scene then uploads neutral data for the features it
// lacks (render/device_scene.h).
#pragma once

#include <bitset>
#include <memory>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "shared/estimator.h"

namespace wp::render {

// --sampling (kernels/shared/estimator.h WP_SAMPLING_*).
enum class Sampling : int {
    Uniform = WP_SAMPLING_UNIFORM,  // uniform hemisphere for diffuse, no light sampling (the original)
    Cosine = WP_SAMPLING_COSINE,    // BSDF sampling only: cosine diffuse, lobe/VNDF sampling for glossy
    Nee = WP_SAMPLING_NEE,          // cosine + next-event estimation (emission after specular bounces only)
    Mis = WP_SAMPLING_MIS,          // NEE and BSDF sampling, power heuristic (Veach & Guibas 1995)
};
// --glossy (WP_GLOSSY_*).
enum class GlossyModel : int {
    Phong = WP_GLOSSY_PHONG,  // the original weighted Phong lobe
    Ggx = WP_GLOSSY_GGX,      // GGX microfacet BRDF, visible-normal sampling
};

const char* sampling_name(Sampling s);
const char* glossy_name(GlossyModel g);
// Parse "uniform|cosine|nee|mis" / "phong|ggx"; throw wp::Error naming the option.
Sampling parse_sampling(const std::string& s);
GlossyModel parse_glossy(const std::string& s);

// The estimator (--sampling, --glossy, --sampler, --rr-depth). Its defaults are the shipped
// configuration of kernels/shared/estimator.h, the one definition that the kernels, the
// CLI and the renderer use.
struct Estimator {
    Sampling sampling = static_cast<Sampling>(WP_DEFAULT_SAMPLING);
    GlossyModel glossy = static_cast<GlossyModel>(WP_DEFAULT_GLOSSY_MODEL);
    bool sobol = WP_DEFAULT_SAMPLER == WP_SAMPLER_SOBOL;  // else the pcg4d numbers
    int rr_depth = WP_DEFAULT_RR_DEPTH;  // Russian roulette from this bounce on; < 0 off

    // The original program's estimator: uniform hemisphere, weighted Phong lobe, random
    // numbers, no roulette.
    static Estimator original() { return {Sampling::Uniform, GlossyModel::Phong, false, -1}; }
};

// --kernels: what the programs model.
enum class KernelSet : int {
    Specialised,  // only what the scene needs (KernelConfig::from_scene): the default
    Generic,      // every feature switch on (KernelConfig::with_every_feature())
};
const char* kernel_set_name(KernelSet k);  // "specialised" / "generic"
// Parse "specialised|generic"; throws wp::Error naming --kernels.
KernelSet parse_kernel_set(const std::string& s);

struct KernelConfig {
    // The material kinds some material uses (bit i: MaterialKind i), WP_HAVE_<KIND>.
    std::bitset<kMaterialKindCount> kinds = std::bitset<kMaterialKindCount>().set();
    bool emission = true;  // some material emits
    // Appearance features (issue 13), each compiled only when the scene has it:
    bool normals = false;      // some vertex has a shading normal (WP_HAVE_NORMALS)
    bool textures = false;     // some material has a texture (WP_HAVE_TEXTURES; uvs too)
    bool normal_maps = false;  // some material has a normal map (WP_HAVE_NORMAL_MAPS)
    bool alpha_mask = false;   // some material is cut out (WP_HAVE_ALPHA_MASK: intersect, shadow)
    bool env = false;          // the scene has an environment map (WP_HAVE_ENV)
    bool lens = false;         // the camera has a thin lens (WP_HAVE_LENS; generate only)
    bool anisotropic = false;  // some rough material has α_v != α (WP_HAVE_ANISOTROPY; uvs too)
    Estimator estimator;
    // RQMC replicates of the Sobol sampler (RenderSettings::replicates, kernels/shared/rng.h):
    // -D WP_SOBOL_REPLICATES=K in generate and shade only when K > 1 and the sampler is Sobol.
    int replicates = 1;
    // Debug (render --debug-nan): WP_INJECT_* stage bits (kernels/shared/types.h) whose
    // guards get a NaN for every pixel p with p % inject_period == 0; 0 compiles nothing.
    int inject_nan = 0;
    int inject_period = 97;
    // Lanes allowed (RenderSettings::shade_lanes on a CPU device): see shade_lanes().
    bool lanes = false;
    // Generate eight items per work-item, their jitter in vector lanes (a CPU device;
    // kernels/generate.cl WP_GENERATE_LANES): the same rays bit for bit.
    bool generate_lanes = false;
    // The lane kernel may trace its own shadow rays (RenderSettings::shadows_in_shade): see
    // shade_traces_shadows().
    bool shadows_in_shade = false;
    // Some light triangle has a back-to-back partner (scene/light_pairs.h), and the render
    // uses them (RenderSettings::light_pairs): see sample_pairs(). from_scene keeps the
    // partners it found for the light table (DeviceScene), so they are searched once.
    bool light_pairs = false;
    std::shared_ptr<const std::vector<int>> light_partners;  // find_light_partners; null: none
    // Shadow segments end where the light triangle's clearance begins (RenderSettings::
    // light_clearance; scene/light_clearance.h): see clear_shadow_ends(). Wavefront turns
    // it off again where no light triangle has a clearance (DeviceScene's cleared_lights)
    // and the kernels are specialised; with_every_feature() turns it on.
    bool light_clearance = false;
    // Generate and shade fill their queues with non-temporal stores (WP_STREAM_STORES,
    // kernels/shared/queue_store.h): Wavefront sets it on CPU devices where the pool's queues
    // exceed the cache their cores count on (render::stream_queues), where it was measured
    // faster (performance.md, "Eleventh round", "Twentieth round"); the same bits.
    bool stream_stores = false;
    // The renderer traces the last bounce's rays through the emitters' BVH (Wavefront::
    // final_rays_through_emitters: escaped rays carry no light): see shade_final().
    bool final_rays = false;

    bool has(MaterialKind k) const { return kinds.test(static_cast<std::size_t>(k)); }
    // Light sampling is compiled only when something emits (a triangle or the environment)
    // and the strategy uses it.
    bool nee() const {
        return (emission || env) &&
               (estimator.sampling == Sampling::Nee || estimator.sampling == Sampling::Mis);
    }

    // The material kinds, emission and appearance features the scene has; the given
    // estimator. light_pairs: search the light triangles' back-to-back partners where light
    // sampling is compiled (false: light_pairs stays off and nothing is searched).
    static KernelConfig from_scene(const Scene& scene, const Estimator& estimator = {}, bool light_pairs = true);
    // This configuration with every feature switch on (the generic build): all material
    // kinds, emission, shading normals, textures, normal maps, alpha cut-outs, the
    // environment, anisotropy, the thin lens and light pairs. The estimator and the debug switches stay;
    // light sampling follows the estimator alone (env = true makes nee() true for nee and
    // mis). The scene must then supply neutral data for what it lacks (DeviceScene::upload).
    KernelConfig with_every_feature() const;

    // Option slices, every switch a stage reads explicit:
    std::string generate_options() const;    // sampler, thin lens, lanes, streams, injection
    std::string shade_options() const;       // materials, estimator, NEE, injection
    std::string accumulate_options() const;  // injection
    std::string trace_options() const;       // intersect and shadow: alpha cut-outs
    std::string aov_options() const;         // aov (render/aov.h): normals, textures, normal maps
    // Shade runs shade_surface8, eight paths at a time in vector lanes (kernels/shared/
    // lanes.h): lanes are allowed and the lane kernel models the configuration — every kind (lane
    // code for diffuse, mirror and glossy; the others' scalar BSDF lane by lane), shading
    // normals, no other appearance feature, no NaN injection. Adds -D WP_SHADE_LANES=1 to
    // shade_options().
    bool shade_lanes() const;
    // The lane kernel traces its own shadow rays (-D WP_SHADE_TRACES_SHADOWS=1): where it
    // runs with light sampling, no material is cut out (its traversal has no alpha test)
    // and shadows_in_shade allows it. Its light samples then never enter a queue: no
    // shadow queue in the pool, no shadow stage (kernels/shade.cl says why).
    bool shade_traces_shadows() const;
    // Shade also builds shade_final (-D WP_SHADE_FINAL=1), the last bounce's tracing and
    // emission in one launch (kernels/shade.cl): where final_rays, no material is cut out
    // (its traversal has no alpha test) and no NaN is injected (its entry guard would not see
    // the misses).
    bool shade_final() const { return final_rays && !alpha_mask && inject_nan == 0; }
    // The pool holds a shadow queue and the shadow stage runs: light sampling without the
    // lane kernel.
    bool shadow_queue() const;
    // Light sampling moves samples from light triangles that face away to their partners
    // (WP_HAVE_LIGHT_PAIRS in shade_options()): light_pairs where light sampling is compiled.
    bool sample_pairs() const { return light_pairs && nee(); }
    // Shadow segments towards light triangles end at their clearance (WP_HAVE_LIGHT_CLEARANCE
    // in shade_options(); DeviceScene uploads the clearances): light_clearance with light
    // sampling.
    bool clear_shadow_ends() const { return light_clearance && nee(); }
    // Some material kind the scene has is specular in every event (material_kinds.h).
    bool any_specular() const;
    // What the renderer prints with -v: the shade slice, the largest.
    std::string options() const { return shade_options(); }

  private:
    std::string inject_options() const;
    std::string replicate_options() const;
};

}  // namespace wp::render
