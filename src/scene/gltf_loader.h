// gltf_loader.h — glTF 2.0 files (.gltf JSON with external or data-URI buffers, .glb) through
// tinygltf (Debian libtinygltf-dev).
//
// Geometry: the default scene (else scene 0, else every root node) is walked depth first;
// each node's local transform is its `matrix` or T × R × S, composed parent × child. Every
// primitive of mode TRIANGLES (4, the default) is added, indexed (u8, u16, u32 indices) or
// not, positions transformed to world space; a mirroring world transform reverses the
// winding so the front stays the front. Other modes (points, lines, strips, fans) and sparse
// or non-float POSITION accessors are skipped with ONE warning per kind per file. Every
// accessor is bounds-checked against its buffer view and buffer (tinygltf does not always).
// Degenerate triangles are kept.
//
// Vertex attributes: NORMAL (VEC3 float) → Scene::normals, transformed by the inverse
// transpose of the node's world matrix; TEXCOORD_0 (VEC2 float, or normalized unsigned
// byte / short) → Scene::uvs as they are (glTF's origin is the image's top-left, as
// wavepath's); TANGENT (VEC4 float) → Scene::tangents, xyz transformed as a vector, w (the
// bitangent sign) negated under a mirroring transform so that w · cross(n, t) stays the
// transformed bitangent (TANGENT without NORMAL is dropped). Primitives without an attribute
// get zeros (none) where others have it (Scene::add_mesh). An attribute accessor of another
// type, sparse or quantized is skipped (noted once); one with another count than POSITION
// fails; non-finite values become none / (0, 0) (noted once).
//
// Materials (metallic-roughness → wavepath), first rule that matches wins:
//   KHR_materials_transmission, transmissionFactor >= 0.5 → RoughDielectric with GGX α =
//                                                          roughness² (height-correlated G, as
//                                                          the spec's V_GGX), or Glass when
//                                                          α < 1e-4 (noted once when rough);
//                                                          ior = KHR_materials_ior (1.5 when
//                                                          absent, 1 or outside [0.01, 100]);
//                                                          albedo (transmittance) = base,
//                                                          reflection untinted (specular 1)
//   metallicFactor >= 0.5, GGX alpha = roughness² < 0.001  → Mirror, albedo = base colour
//   metallicFactor >= 0.5                                   → Glossy, albedo = base colour,
//                                                            roughness alpha (at most 1)
//   otherwise                                               → Diffuse, albedo = base colour
// base colour = baseColorFactor rgb, clamped to [0, 1]; emission = emissiveFactor ×
// KHR_materials_emissive_strength (any kind).
// Textures (through scene/texture.h; images are files relative to the .gltf, percent-decoded,
// data: URIs or buffer views, each decoded once per use; a missing or undecodable image is a
// warning and a visible placeholder):
//   baseColorTexture (colour)         → albedo_map, × the base colour factor
//   metallicRoughnessTexture (data)   → roughness_map of Glossy and RoughDielectric
//                                       (α = (roughnessFactor · G)²:
//                                       alpha stays roughnessFactor², the device multiplies
//                                       G²); its metallic (B) is not modelled (noted once)
//   emissiveTexture (colour)          → emission_map, × emission (only when that is > 0)
//   normalTexture (data)              → normal_map, normal_scale = scale
//   occlusionTexture                  → ignored (noted once)
// KHR_texture_transform on any of them → uv_transform = T × R × S as the extension defines it
// (a texCoord other than 0, here or on the textureInfo, is noted: only TEXCOORD_0 is read).
// Samplers: magFilter NEAREST → Texture::nearest; wrapS / wrapT other than REPEAT noted once
// (only repeat is supported). A texture without `source` (an extension's image) is noted.
// Alpha: alphaMode MASK → alpha_factor = baseColorFactor[3], alpha_cutoff = alphaCutoff (0.5),
// alpha_map = the base colour texture (its A) when it has a texel below the cutoff; without a
// texture, a factor below the cutoff leaves nothing: the primitive is not added (noted once).
// BLEND is approximated as MASK with cutoff 0.5 (noted once). OPAQUE ignores alpha (spec).
// ONE warning per file for each other approximation: metallic between 0 and 1 rounded, rough
// glass below α 1e-4 rendered smooth, KHR_materials_specular on transmission (not modelled:
// its factors change glTF's Schlick Fresnel, which no tint of wavepath's exact Fresnel
// reproduces), base colour clamped. The metallic-roughness metal stays the glossy kind (its
// metal is Schlick with F0 = base colour, which is what glossy models; no η, k).
// Specular/dielectric reflection of non-metals (glTF's F0 = 0.04 layer) is not modelled.
// A primitive without a material gets the mid-grey
// (0.5) diffuse "default", without a warning (glTF allows it).
//
// Camera: the first node in the walk that has a camera. Perspective: vertical fov = yfov;
// film 800 × round(800 / aspectRatio) (800 × 600 without aspectRatio); the camera looks down
// its node's −Z with +Y up. Orthographic cameras are ignored with a warning. Without a
// camera: the framing of load_obj (800 x 600, 40 degrees, from +z). Black background.
//
// Hostile input: GLB header and chunk lengths checked before tinygltf sees them; external
// files are read only as regular files up to 1 GiB (never written, no path expansion);
// image files only as regular files, image buffer views bounds-checked; at most 2^25 triangles and 2^27 vertices after instancing, node
// depth 256 (a cycle fails there), 2^20 node visits.
//
// Errors: wp::Error naming the file, the JSON place (meshes[i].primitives[j],
// accessors[k], nodes[n]) or the byte offset, and the problem, e.g.
// "box.glb: truncated: the GLB header says 2048 bytes, the file has 1000". The result has
// passed validate_scene.
#pragma once

#include <filesystem>
#include <string_view>

#include "scene/scene.h"

namespace wp {

// Reads the file (missing, unreadable, empty → wp::Error) and parses it.
Scene load_gltf(const std::filesystem::path& path);

// The same from memory: a .glb when the bytes start with "glTF", else JSON text; external
// buffers are resolved relative to origin's folder; origin names the file in messages.
Scene parse_gltf(std::string_view bytes, const std::filesystem::path& origin);

}  // namespace wp
