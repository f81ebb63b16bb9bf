// upload.h — the host Scene turned into the plain-data layouts of kernels/shared/types.h.
//
// With bvh/flatten this is the only place where host types (GLM, Scene) become device
// types. Everything is returned as host vectors of device structs; render/ creates the
// OpenCL buffers, so scene/ stays free of OpenCL.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "scene/envmap.h"
#include "scene/scene.h"
#include "scene/texture.h"
#include "shared/types.h"

namespace wp {

struct SceneUpload {
    std::vector<Triangle> triangles;       // original triangle order (shade reads them by prim)
    std::vector<int> material_ids;         // one per triangle
    std::vector<MaterialData> materials;
    // The tables some kinds read at MaterialData.table (scene/material_tables.h); empty when
    // no material has any.
    std::vector<float> material_tables;
    float4 background{0.0f, 0.0f, 0.0f, 0.0f};  // xyz: radiance of escaped rays
};

// The light table of next-event estimation (kernels/shared/lights.h): every emissive
// triangle with positive area, chosen with probability proportional to its emitted power
// area × luminance(Le) (Rec. 709 luminance; one-sided emitters, so the factor π cancels).
struct LightTable {
    std::vector<float> cdf;       // inclusive cumulative probabilities, last exactly 1
    std::vector<int> guide;       // build_cdf_guide(cdf) from WP_LIGHT_GUIDE_MIN lights on, else empty
    std::vector<int> prims;       // triangle (scene order) of each light
    std::vector<float> pdf_area;  // per scene triangle: P(choose it) / its area; 0 if no light
    // Per scene triangle, when asked for and some light triangle has a partner
    // (scene/light_pairs.h): its partner and P(choose partner) / its area; else empty.
    std::vector<LightPair> pairs;
    double total_power = 0.0;     // sum of area × luminance, for reports
    std::size_t size() const { return prims.size(); }
};

// Which appearance data the kernels read (render/kernel_config decides from the scene).
struct AppearanceNeeds {
    bool normals = false;   // TriNormals
    bool uvs = false;       // TriUVs, MaterialTextures, views and textures (textures, alpha)
    bool tangents = false;  // TriTangents (normal maps)
    bool env = false;       // the environment map
};

// The appearance data of a scene in device layouts; each part empty when not needed.
struct AppearanceUpload {
    std::vector<TriNormals> normals;    // per triangle, scene order
    std::vector<TriUVs> uvs;            // per triangle, scene order ((0, 0) without uvs)
    std::vector<TriTangents> tangents;  // per triangle, scene order
    std::vector<MaterialTextures> material_textures;  // per material
    std::vector<TextureView> views;     // the texture slots of all materials
    TextureUpload textures;             // the images materials use, mip-mapped
    std::optional<EnvUpload> env;
    std::vector<std::string> warnings;  // from the environment's upload
};

// Throws wp::Error for an environment or texture index out of range.
AppearanceUpload upload_appearance(const Scene& scene, const AppearanceNeeds& needs);

// The guide table of wp_cdf_pick_guided (kernels/shared/sampling.h) for a non-decreasing
// cdf of n >= 1 entries: m + 1 entries for m = the least power of two >= n (at most 2^24),
// guide[j] = the first k with cdf[k] > j / m (n − 1 if none) and guide[0] = 0; its size()
// − 1 is m. Empty for an empty cdf.
std::vector<int> build_cdf_guide(const std::vector<float>& cdf);

// Empty (no lights) when nothing emits. The probability of light k is taken as the float
// difference cdf[k] - cdf[k - 1], which is exactly what the device's binary search draws.
// With `pairs`, also the back-to-back pairs (LightTable::pairs) of find_light_partners, or of
// `partners` when given (its result for this scene, found earlier).
LightTable build_light_table(const Scene& scene, bool pairs = false, const std::vector<int>* partners = nullptr);

// Throws wp::Error when a triangle's material id or vertex index is out of range.
SceneUpload upload_scene(const Scene& scene);

// Mitsuba's specular sampling weight of a plastic (MaterialData.specular.w): the mean of its
// specular tint over the means of both reflectances (each the mean of its RGB, the albedo's
// times the mean of its texture's linear texels), mean specular / (mean diffuse + mean
// specular); 0.5 when both are black.
float plastic_specular_weight(const Material& m, const std::vector<Texture>& textures);

// The camera for a width x height image (throws wp::Error for a degenerate camera:
// position == target, up parallel to the view direction, a field of view outside
// (0, 180) degrees, a lens radius < 0 or not finite, or with a lens a focus distance <= 0
// or not finite). lens = (lens_radius, focus_distance, 0, 0).
CameraData upload_camera(const Camera& camera, int width, int height, bool jitter);

}  // namespace wp
