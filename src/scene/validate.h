// validate.h — checks that a Scene is safe to build a BVH over and upload.
//
// Loaders call validate_scene before returning; code that builds scenes by hand should
// too. It throws wp::Error naming the scene and the first problem found: a vertex index
// out of range, a non-finite position, a material id out of range or a missing one, no
// triangles at all, an invalid material (albedo outside [0, 1], negative or non-finite
// emission, a parameter its kind reads out of range: validate_material_parameters) or an
// unusable camera. Degenerate (zero-area) triangles are allowed: real scenes have them and
// the traversal must cope.
#pragma once

#include <string>

#include "scene/scene.h"

namespace wp {

void validate_scene(const Scene& scene);

// The parameters that m's kind reads (material_kinds.h columns), each with its range
// (util/limits.h): roughness α in (0, 1] for glossy, α and α_v in [kMinMicrofacetAlpha,
// kMaxMicrofacetAlpha] for the rough kinds; the index of refraction in [kMinIor, kMaxIor] and the
// specular tint in [0, 1] (kinds with IOR); a conductor's η and k finite and >= 0. Throws
// wp::Error "WHAT has ...", `what` naming the material. Parameters the kind does not read
// are not checked (upload sends them as 0).
void validate_material_parameters(const Material& m, const std::string& what);

// True when anything can light the image: a triangle whose material emits, or a background
// brighter than black. Every loader's scene and the built-ins are checked by the command
// line (app/render_options.cpp: load_scene), which warns once when this is false.
bool has_light(const Scene& scene);

// The one warning for a scene without light, naming `source` (the file or built-in).
std::string no_light_warning(const std::string& source);

} // namespace wp
