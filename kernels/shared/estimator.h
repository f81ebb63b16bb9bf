// estimator.h — the estimator's compile switches, their values and their defaults.
//
// The one definition of the shipped configuration: the kernels fall back to these
// defaults when a switch is not given, and the host's render::Estimator (render/
// kernel_config.h) takes its defaults from the same macros, so a program built without
// options and `wavepath render` without estimator options are the same estimator. The host
// passes every switch explicitly anyway (KernelConfig::*_options()). Plain macros only, so
// host code may include it.
#ifndef WP_ESTIMATOR_H
#define WP_ESTIMATOR_H

// Sampling strategies (WP_SAMPLING, --sampling).
#define WP_SAMPLING_UNIFORM 0  // uniform hemisphere for diffuse, no light sampling (original)
#define WP_SAMPLING_COSINE 1   // BSDF sampling only: cosine diffuse, lobe sampling for glossy
#define WP_SAMPLING_NEE 2      // cosine + next-event estimation for diffuse/glossy surfaces
#define WP_SAMPLING_MIS 3      // NEE and BSDF sampling combined by the power heuristic
// Glossy models (WP_GLOSSY_MODEL, --glossy).
#define WP_GLOSSY_PHONG 0  // the original weighted Phong lobe
#define WP_GLOSSY_GGX 1    // GGX microfacet BRDF, visible-normal sampling
// Samplers (WP_SAMPLER, --sampler).
#define WP_SAMPLER_RANDOM 0  // counter-based pcg4d numbers (rng.h)
#define WP_SAMPLER_SOBOL 1   // Owen-scrambled Sobol points (sobol.h)

// The shipped estimator.
#define WP_DEFAULT_SAMPLING WP_SAMPLING_MIS
#define WP_DEFAULT_GLOSSY_MODEL WP_GLOSSY_GGX
#define WP_DEFAULT_SAMPLER WP_SAMPLER_SOBOL
#define WP_DEFAULT_RR_DEPTH 3  // Russian roulette from this bounce on (-1: off)

#endif  // WP_ESTIMATOR_H
