// json_scene.h — wavepath JSON scene files (docs/scene-format.md).
//
// A scene file is one JSON object. Every key is checked: an unknown key anywhere is an error
// that names its JSON path and suggests a close known key ("materail" → "material"); so is a
// key given twice in one object. Keys (defaults in brackets):
//
//   "version"     1 (optional; the only version so far)
//   "camera"      optional object; without it (or without a position) the camera frames the
//                 scene's bounding box from +z
//     "position", "look_at"   [x, y, z]; both or neither
//     "up"                    [x, y, z]                         [[0, 1, 0]]
//     "matrix"                instead of position/look_at/up: camera-to-world, 16 numbers
//                             row-major (or 4 rows of 4); column 1 = up, column 2 = viewing
//                             direction, column 3 = position (Scene camera_from_matrix)
//     "fov"                   field of view in degrees, in (0, 180)   [40]
//     "fov_axis"              "y" (vertical) or "x" (horizontal)      ["y"]
//     "width", "height"       film in pixels, 1..16384 each, at most 2^28 pixels  [800, 600]
//                             (util/limits.h, as the command line)
//   "background"  radiance of rays that leave the scene: a number (grey) or [r, g, b], >= 0  [0]
//   "environment" optional: {"file": an equirectangular image relative to the scene file,
//                 "scale": >= 0 [1], "rotation": [rx, ry, rz] degrees (x first, then y, then
//                 z) or "rotate_y": degrees} → Scene::environment
//   "render"      optional defaults that --spp, --depth and --seed on the command line beat:
//     "spp" 1..2^24, "depth" (bounces, as --depth) 0..2^20, "seed" 0..2^32-1 (util/limits.h)
//   "materials"   object: name → material
//     "type"          a kind of kernels/shared/material_kinds.h (required): "diffuse" |
//                     "mirror" | "glossy" | "glass" | "conductor" | "roughconductor" |
//                     "roughdielectric" | "thindielectric" | "plastic" | "roughplastic"
//     "reflectance"   Material::albedo, number or [r, g, b] in [0, 1]: diffuse reflectance
//                     (diffuse, plastics), F0 (glossy), tint (mirror, conductors); on the
//                     dielectrics (glass, roughdielectric, thindielectric) the tint of both
//                     reflection and transmission (sets albedo and specular)
//                     [0.8 diffuse, glossy, plastics; 1 the others]
//     "emission"      emitted radiance, front (counter-clockwise) side only: number or
//                     [r, g, b] >= 0; any type  [0]
//     glossy:  "roughness" GGX alpha in [0.0001, 1], stored as given, or "exponent": a Phong
//              exponent e >= 0, alpha = sqrt(2 / (e + 2))  [100, alpha ≈ 0.14]
//     roughconductor, roughdielectric, roughplastic:
//              "roughness" α in [0.0001, 2] [0.1], or "roughness_u" and "roughness_v"
//              (anisotropic α_u along the shading frame's x, α_v); "distribution" "ggx" |
//              "beckmann" ["ggx"]; "g" (masking-shadowing) "height-correlated" | "separable"
//              ["height-correlated"]
//     conductor, roughconductor: "eta" and "k" (number or [r, g, b] >= 0, both), or "metal":
//              a name of scene/metals.h ("Au", "Cu", ...; "none": η 0, k 1)  [η 0, k 1]
//     dielectrics: "ior" inside / outside in [0.01, 100] [1.5]; "specular" (reflection tint)
//              and "transmittance" (Material::albedo), each in [0, 1] [1], instead of
//              "reflectance"
//     plastics: "ior" [1.5], "specular" (the coat's reflection tint) [1], "nonlinear"
//              true | false [false] (Mitsuba's)
//     "albedo_texture", "roughness_texture" (kinds with roughness; the rough kinds: with an
//                     isotropic "roughness" only), "emission_texture",
//     "normal_map", "alpha_texture": a texture, each multiplying its constant (reflectance,
//                     roughness: alpha × G², emission; whose default becomes 1 with a
//                     texture): a file name relative to the scene file, or {"file": ...,
//                     "scale": s or [su, sv], "offset": [ou, ov], "rotation": degrees,
//                     "filter": "bilinear" | "nearest"}, or {"checkerboard": [c0, c1], and the
//                     same transform keys} (a 2 x 2 nearest image; for alpha, the colours'
//                     first component is the coverage). uv' = T(offset) R(rotation) S(scale) uv
//                     (KHR_texture_transform). Albedo and emission files are colour (sRGB for
//                     8-bit), the others data; a missing file warns (placeholder image)
//     "normal_scale"  with normal_map: the map's xy scale   [1]
//     "alpha_cutoff"  with alpha_texture: coverage below it is not there, [0, 1]   [0.5]
//   "shapes"      array (required, non-empty); each an object with
//     "type"          "mesh" | "quad" | "box" | "sphere" | "stress"
//     "material"      a name from "materials"; required except for "mesh", whose default is
//                     the file's own materials
//     "transform"     optional, below
//   and by type:
//     mesh:   "file"  .obj/.gltf/.glb/.ply/... (scene/load.h: load_mesh_file), relative to
//                     the scene file's folder; "smooth": crease angle in [0, 180] degrees:
//                     computed smooth normals (scene/normals.h) for its triangles without any
//     quad:   "corner", "edge_u", "edge_v" ([x, y, z] each; normal cross(edge_u, edge_v)),
//             or "size" (number or [w, h]: the quad [-w/2, w/2] x [-h/2, h/2] at z = 0,
//             facing +z); "subdivisions" n or [nu, nv], 1..4096  [1]
//     box:    "min" and "max" ([x, y, z], min < max), or "size" (number or [x, y, z] > 0)
//             with "center" ([0, 0, 0]); "subdivisions" per face edge 1..1024  [1]
//     sphere: "center" [[0, 0, 0]], "radius" > 0 [1], "rings" 2..4096 [32],
//             "segments" 3..8192 [64]  (UV sphere, 2 segments (rings - 1) triangles), smooth
//             normals (p - c) / r
//   Shapes whose material has a texture get uvs (others none): quad (s, 1 - t) at corner +
//   s edge_u + t edge_v (upright when edge_v points up); box: each face the whole image
//   along make_box's face axes; sphere: (phi / 2 pi, theta / pi), phi about +y from +z
//   towards +x, theta from +y. A mesh with a named, untextured material drops its uvs.
//     stress: "triangles" 48..2^24 [250000]: make_stress_mesh, the BVH benchmark's torus knot
//   transform: an object {"matrix": M} or {"scale", "rotate", "translate"} (any subset,
//     applied scale first, then rotate, then translate), or an array of one-key objects
//     [{"translate": ...}, {"rotate": ...}, {"scale": ...}, {"matrix": ...}] applied in the
//     order listed (the first entry acts on the shape first):
//       "translate" [x, y, z]; "scale" s or [sx, sy, sz] (no zero; negative mirrors);
//       "rotate" {"axis": [x, y, z], "degrees": d} (right-handed, counter-clockwise looking
//       down the axis); "matrix" 16 numbers row-major or 4 rows of 4, affine (last row
//       0 0 0 1), not singular.
//
// Only materials that some shape uses are kept (in file order); unused ones give a warning.
// A scene in which no triangle emits and whose background is black gives the warning "no
// light" and still loads. Warnings go to Scene::warnings, prefixed with the file name.
//
// Errors throw wp::Error with one message: "FILE:LINE:COLUMN: /json/path: problem", e.g.
// "scene.json:7:9: /materials/white/materail: unknown key 'materail' ...". Malformed JSON
// gives the line and column of the syntax error. Limits against hostile input: 2^24
// triangles in the whole scene, the per-shape counts above, files up to 64 MiB.
// The result has passed validate_scene.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string_view>

#include "scene/scene.h"

namespace wp {

// Most triangles a JSON scene may hold (built-in shapes and mesh files together).
inline constexpr std::size_t kJsonSceneMaxTriangles = std::size_t(1) << 24;
// Largest scene file load_json_scene reads.
inline constexpr std::size_t kJsonSceneMaxBytes = std::size_t(64) << 20;

// Reads and parses a scene file; mesh paths are relative to its folder.
Scene load_json_scene(const std::filesystem::path& path);

// Parses scene text in memory. `origin` names the file in messages, and its parent folder
// resolves relative mesh paths. Returns a Scene or throws wp::Error, whatever the bytes; it
// only ever reads files (the meshes the text names), never writes any.
Scene parse_json_scene(std::string_view text, const std::filesystem::path& origin);

}  // namespace wp
