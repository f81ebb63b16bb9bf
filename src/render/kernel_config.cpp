#include "render/kernel_config.h"

#include <fmt/format.h>

namespace wp::render {

KernelConfig KernelConfig::from_scene(const Scene& scene) {
    KernelConfig c;
    c.diffuse = c.mirror = c.glossy = c.emission = false;
    for (const Material& m : scene.materials) {
        c.diffuse |= m.kind == MaterialKind::Diffuse;
        c.mirror |= m.kind == MaterialKind::Mirror;
        c.glossy |= m.kind == MaterialKind::Glossy;
        c.emission |= m.emissive();
    }
    return c;
}

std::string KernelConfig::options() const {
    return fmt::format("-D WP_HAVE_DIFFUSE={} -D WP_HAVE_MIRROR={} -D WP_HAVE_GLOSSY={} "
                       "-D WP_HAVE_EMISSION={} -D WP_DIFFUSE_SAMPLING={}",
                       int(diffuse), int(mirror), int(glossy), int(emission),
                       static_cast<int>(diffuse_sampling));
}

}  // namespace wp::render
