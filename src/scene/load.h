// load.h — one entry point for every scene file format, and the load report.
//
// load_scene_file picks the reader by extension (case-insensitive):
//   .json                      wavepath scene file      (scene/json_scene.h)
//   .xml                       Mitsuba 3 scene subset   (scene/mitsuba_loader.h)
//   .pbrt                      pbrt-v4 scene subset     (scene/pbrt_loader.h)
//   .obj                       Wavefront OBJ/MTL        (scene/obj_loader.h)
//   .gltf .glb                 glTF 2.0                 (scene/gltf_loader.h)
//   .ply and other mesh files  through Assimp           (scene/assimp_loader.h)
// Mesh loaders return a Scene too (triangles and materials, a default camera), so scene
// files compose them with Scene::append. Every error is a wp::Error naming the file, the
// place in it where known and the problem; nothing is printed here.
#pragma once

#include <filesystem>
#include <string>

#include "scene/scene.h"

namespace wp {

// The mesh extensions load_mesh_file accepts besides .obj, .gltf, .glb (lower case, with dot).
bool is_assimp_extension(const std::string& ext);

// Any supported file: scene files (.json, .xml, .pbrt) and mesh files. Throws wp::Error for a
// missing file or an unknown extension, naming the supported ones.
Scene load_scene_file(const std::filesystem::path& path);

// A mesh file only (.obj, .gltf, .glb, .ply, ...): what scene files reference.
Scene load_mesh_file(const std::filesystem::path& path);

// Lower-case extension with the dot (".obj"), "" when none.
std::string lower_extension(const std::filesystem::path& path);

// "NAME: 16,020 triangles, materials 5 diffuse + 1 mirror + 1 glossy, 1 emissive material
// (2 triangles), background (0, 0, 0), bounds (-1, 0, -1) to (1, 2, 1), loaded in 3.1 ms"
std::string describe_scene(const Scene& scene, double load_ms);

}  // namespace wp
