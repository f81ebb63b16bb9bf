// obj_loader.h — Wavefront OBJ/MTL files into a Scene (tinyobjloader, polygons triangulated).
//
// Geometry: every face of n corners becomes n - 2 triangles with the face's winding: a fan
// when the polygon is convex, ear clipping in the polygon's plane when it is not (a
// self-intersecting polygon, or a concave one over 128 corners, is fanned with a warning).
// Negative (relative) indices are supported; lines and points are ignored.
//
// Vertex attributes: `vn` → Scene::normals (shading normals, as written, not normalised),
// `vt` → Scene::uvs stored as (u, 1 - v) (wavepath's uvs have the image's top-left at
// (0, 0); OBJ's v points up). A file whose faces name no vt and no vn keeps the file's
// vertices in file order (vertex i of the scene is `v` line i + 1); otherwise there is one
// vertex per distinct (v, vt, vn) index triple, in order of first use, so every corner keeps
// its exact attributes (corners without vt / vn get (0, 0) / a zero normal, i.e. none).
// A vt / vn index outside the file's lists is ignored for that corner (one warning), a
// non-finite value is replaced by none (one warning). Polygon triangulation keeps each
// corner's vertex, hence its attributes.
//
// Material mapping (MTL → wavepath), first rule that matches wins; "≈ 0" means every channel
// <= 0.001, and Ks "perfect" means every channel >= 0.999:
//   Ke                                                   → emission (any kind; negative → 0)
//   illum 4, 6 or 7                                      → Glass, η = Ni (1.5 with a warning
//                                                          when Ni is missing, 1 or outside
//                                                          [0.01, 100]), albedo = Tf (the
//                                                          transmittance; 1 when Tf ≈ 0);
//                                                          reflection untinted (specular 1)
//   illum 3 or 5, Kd ≈ 0, Ks > 0, and Ns >= 1000 or Ks perfect
//                                                        → Mirror, albedo = Ks
//   illum 2, 3 or 5, Kd ≈ 0, Ks > 0 (Ns finite)          → Glossy, albedo = Ks, α from exponent Ns
//   anything else                                        → Diffuse, albedo = Kd
// Conductors are not recognised as such: MTL has no complex index of refraction, and the
// PBR extension's Pm (metallic) / Pr (roughness) are not read (no exact mapping from an F0
// such as Ks to η, k exists), so a metal written as Kd 0, Ks = F0, Ns, illum 3 is Glossy
// (Schlick with F0 = Ks, GGX α from Ns). Comments are never parsed.
// Albedos are clamped to [0, 1]. A material with both Kd and Ks that asks for reflection
// (illum 3 or 5) becomes Diffuse with a warning (wavepath has no layered material);
// illum 9 (glass without refraction) is rendered as the kind above with a warning.
//
// Texture maps (paths relative to the folder of the MTL file, '\' read as '/'; loaded once
// through scene/texture.h; a missing or undecodable file: a warning naming it and a visible
// placeholder; a folder or device: a warning, map ignored):
//   map_Kd   → albedo_map (colour) of Diffuse; × Kd, or alone (Kd = 1) when the material has
//              no Kd line
//   map_Ks   → albedo_map (colour) of Glossy and Mirror (× Ks); ignored with a warning on
//              Diffuse and Glass (map_Kd too on Glass)
//   map_Ke   → emission_map (colour), × Ke, or alone (Ke = 1) without a Ke line; ignored
//              with a warning when Ke is 0
//   norm     → normal_map (data), normal_scale = -bm
//   map_Bump / bump → the same when `norm` is absent, unless the image is grey (R = G = B
//              everywhere: a height map, which wavepath does not model: warning, ignored)
//   map_d    → alpha_map (data), cut-out at 0.5: coverage = the image's alpha channel, or its
//              first channel (R, copied into A) when the alpha is 1 everywhere (an image
//              without alpha); no alpha map when no texel is below 0.5
//   -o ou ov / -s su sv → uv_transform: MTL looks up (su u + ou, sv v + ov) with v up, which
//              on the stored (u, 1 - v) is [su 0 ou; 0 sv 1 - sv - ov; 0 0 1]
// Not supported (warning): -clamp on (maps repeat), -mm, map_Ka, map_Ns, disp, refl,
// map_Pr, map_Pm, map_Ps. The scalar d / Tr (dissolve) is ignored.
// Triangles without a material (no `usemtl`, an unknown name, a missing .mtl) get the
// mid-grey (0.5) diffuse material "default", with ONE warning for the whole file. Only the
// materials that some triangle uses are kept (and only their textures loaded).
//
// Warnings (those of tinyobjloader and the ones above, each prefixed by the file name) are
// returned in Scene::warnings; nothing is printed.
//
// Camera: 800 x 600, vertical fov 40 degrees, looking from +z at the centre of the bounding
// box, far enough that the bounding sphere fits the vertical fov; up = +y; black
// background. A companion `<file>.camera.json` is not read yet (the scene format of issue 7
// will bring cameras).
//
// Errors throw wp::Error with the file name, the line where known, and what is wrong:
//   "cannot open 'path'", tinyobjloader's own errors, a face index that is 0 or out of
//   range ("path:LINE: face vertex index 9 is out of range: ..."), a face with fewer than 3
//   vertices, a vertex coordinate that is missing, unreadable, NaN or infinite
//   ("path:LINE: vertex 4 has a non-finite coordinate 'nan'"), and a file with no triangles.
// The result has passed validate_scene.
//
// Size limits: OBJ texts over 2 GiB are refused; `mtllib` files are read only when they are
// regular files of at most 64 MiB, relative to the .obj's folder (otherwise: a warning, as
// for a missing one). Everything else the parser allocates grows linearly with the text.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "scene/scene.h"

namespace wp {

Scene load_obj(const std::filesystem::path& path);

// The same from text in memory. `origin` names the file in messages and Scene::name, and its
// folder is where `mtllib` files are looked up (the current folder when it has none). Never
// writes files; any input either gives a validated Scene or throws wp::Error.
Scene parse_obj(std::string_view text, const std::filesystem::path& origin);

// The same with `mtllib` libraries looked up through `mtl_source` (name as written in the
// file -> the library's text, or nullopt when there is none) instead of the file system: for
// tests and the fuzzer. Texture maps are still looked up as files beside `origin` (the
// fuzzer's origin is an empty folder; only regular files are ever opened).
using MtlSource = std::function<std::optional<std::string>(const std::string& name)>;
Scene parse_obj(std::string_view text, const std::filesystem::path& origin,
                const MtlSource& mtl_source);

} // namespace wp
