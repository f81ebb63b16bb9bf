// assimp_loader.h — PLY and the long tail of mesh formats (.stl, .off, .3ds, .dae, .fbx)
// through Assimp (Debian libassimp-dev).
//
// Geometry: Assimp reads the file with no post-processing, wavepath checks it (below), then
// only aiProcess_Triangulate runs (polygons → triangle fans/ear clipping). No process that
// drops, merges or reorders anything is used (no FindDegenerates, FindInvalidData,
// JoinIdenticalVertices, SortByPType): every triangle is kept, degenerate ones included,
// and vertices are kept as Assimp reads them (a PLY's vertex i is the scene's vertex i;
// STL has no index, so each triangle has its own three vertices). Faces with 1 or 2
// vertices (points, lines) are skipped with one warning. The node tree is walked (parent ×
// child transforms; a mesh under several nodes is instanced once per node); a node whose
// transform mirrors reverses its triangles' winding, so the front stays the front.
//
// PLY files are checked by wavepath before Assimp sees them, because Assimp 5.2 hangs on a
// truncated header and silently repeats the last face of a truncated ASCII file:
//   - the header must start with "ply", have a known format (ascii, binary_little_endian,
//     binary_big_endian), known property types, and end with "end_header";
//   - the data must hold every element the header declares: binary data is walked (list
//     lengths read, bounds checked), ASCII data is counted token by token and must hold
//     exactly the declared values (a missing value on one line shifts every later one);
//   - vertex x, y, z must be finite (ASCII: file:line:column; binary: vertex and byte offset);
//   - after Assimp: every face index < the vertex count, and the face count read equals the
//     header's;
//   - binary PLY: Assimp's vertices and faces must equal the walker's own decoding; Assimp 5.2
//     skips whitespace bytes after "end_header" and misreads files whose data starts with one,
//     so when they differ the walker's vertices and faces (polygons as fans) are used.
//
// Vertex attributes: per-vertex normals (PLY nx, ny, nz; any format's normals) →
// Scene::normals, transformed by the inverse transpose of the node transform; the first uv
// set (PLY u/v, s/t, texture_u/texture_v, ...) → Scene::uvs as (u, 1 - v) (Assimp's uvs are
// v-up: aiProcess_FlipUVs is not used). The binary PLY walker decodes both too, for the
// files where its decoding replaces Assimp's. Non-finite values become none / (0, 0) (one
// warning). Tangents are not read (the renderer computes them where a normal map needs them).
//
// Materials: PLY, STL and OFF have none: every triangle gets the mid-grey (0.5) diffuse
// material "default", without a warning. Other formats map each used material:
//   diffuse colour  → Diffuse albedo (clamped to [0, 1]; 0.5 grey when absent)
//   first diffuse texture → albedo_map (colour; a file relative to the model's folder, or an
//                     embedded compressed image), with albedo 1 (the texture replaces the
//                     colour, as in Collada and FBX)
//   emissive colour → emission (× emissive intensity when given; negative → 0)
//   Assimp's own "DefaultMaterial" → wavepath's "default"
// with ONE warning per approximation kind per file: specular colour ignored, other textures
// ignored, a diffuse texture on another uv channel (read with the first), uncompressed
// embedded textures ignored, opacity < 1 ignored, albedo clamped. Cameras and lights in the
// file are ignored; the camera frames the geometry as load_obj does (800 x 600, 40 degrees,
// from +z), black background.
//
// Limits against hostile input: files up to 2 GiB, PLY element counts up to 2^28, header up
// to 1 MiB, at most 2^25 triangles and 2^27 vertices after instancing (checked before
// anything is allocated), node tree depth up to 1024.
//
// Errors: wp::Error naming the file, the place (line:column, byte offset, element index, or
// mesh name) and the problem, e.g. "m.ply: truncated: the header declares 12 faces, the data
// ends after 7 (byte 301 of 301)". The result has passed validate_scene.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "scene/scene.h"

namespace wp {

// Reads the file (missing, unreadable, empty → wp::Error) and parses it by its extension.
Scene load_assimp(const std::filesystem::path& path);

// The same from memory: `extension` picks the format (".ply" or "ply", any case); `origin`
// names the file in messages and the scene. Never touches the file system for the input
// itself; returns a Scene or throws wp::Error for any bytes.
Scene parse_assimp(std::string_view bytes, const std::string& extension,
                   const std::filesystem::path& origin);

}  // namespace wp
