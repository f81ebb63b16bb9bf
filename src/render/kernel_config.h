// kernel_config.h — what the kernels must model for one scene, as compile options.
//
// Derived from the scene (which material kinds exist, whether anything emits) and turned
// into a short -D option string for shade.cl; code for absent material kinds is not
// compiled. The option string is part of the program cache key (cl/program.h).
#pragma once

#include <string>

#include "scene/scene.h"

namespace wp::render {

enum class DiffuseSampling : int {
    Uniform = 0,  // uniform over the hemisphere (the original renderer); WP_SAMPLING_UNIFORM
};

struct KernelConfig {
    bool diffuse = true;   // some material is MaterialKind::Diffuse
    bool mirror = true;    // ... Mirror
    bool glossy = true;    // ... Glossy
    bool emission = true;  // some material emits
    DiffuseSampling diffuse_sampling = DiffuseSampling::Uniform;

    static KernelConfig from_scene(const Scene& scene);
    // "-D WP_HAVE_DIFFUSE=1 -D WP_HAVE_MIRROR=0 ..." (every switch explicit).
    std::string options() const;
};

}  // namespace wp::render
