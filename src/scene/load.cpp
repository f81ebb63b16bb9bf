#include "scene/load.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <system_error>

#include <fmt/format.h>

#include "scene/assimp_loader.h"
#include "scene/gltf_loader.h"
#include "scene/json_scene.h"
#include "scene/mitsuba_loader.h"
#include "scene/obj_loader.h"
#include "scene/pbrt_loader.h"
#include "util/error.h"

namespace wp {

namespace fs = std::filesystem;

std::string lower_extension(const fs::path& path) {
    std::string ext = path.extension().string();
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

bool is_assimp_extension(const std::string& ext) {
    // Not .off: Assimp 5.2's OFF importer reads out of bounds when a face lists more corners
    // than the file has (found by fuzz_assimp; a crash inside the library, not fixable here).
    static const std::array<const char*, 5> k{".ply", ".stl", ".3ds", ".dae", ".fbx"};
    return std::any_of(k.begin(), k.end(), [&](const char* e) { return ext == e; });
}

namespace {

void check_exists(const fs::path& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) fail("scene file '{}' not found", path.string());
    if (fs::is_directory(path, ec)) fail("scene file '{}' is a folder", path.string());
}

constexpr const char* kMeshFormats = ".obj, .gltf, .glb, .ply, .stl, .3ds, .dae, .fbx";

}  // namespace

Scene load_mesh_file(const fs::path& path) {
    check_exists(path);
    std::string ext = lower_extension(path);
    if (ext == ".obj") return load_obj(path);
    if (ext == ".gltf" || ext == ".glb") return load_gltf(path);
    if (is_assimp_extension(ext)) return load_assimp(path);
    fail("mesh file '{}': unsupported format '{}' (supported: {})", path.string(), ext,
         kMeshFormats);
}

Scene load_scene_file(const fs::path& path) {
    check_exists(path);
    std::string ext = lower_extension(path);
    if (ext == ".json") return load_json_scene(path);
    if (ext == ".xml") return load_mitsuba(path);
    if (ext == ".pbrt") return load_pbrt(path);
    if (ext == ".obj" || ext == ".gltf" || ext == ".glb" || is_assimp_extension(ext))
        return load_mesh_file(path);
    fail("scene file '{}': unsupported format '{}' (supported: .json, .xml (Mitsuba 3), .pbrt (pbrt-v4), {})",
         path.string(), ext, kMeshFormats);
}

std::string describe_scene(const Scene& scene, double load_ms) {
    std::map<MaterialKind, int> kinds;
    std::vector<std::size_t> used(scene.materials.size(), 0);
    for (auto id : scene.material_ids)
        if (id < used.size()) ++used[id];
    int emissive = 0;
    std::size_t emissive_tris = 0;
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        ++kinds[scene.materials[i].kind];
        if (scene.materials[i].emissive()) {
            ++emissive;
            emissive_tris += used[i];
        }
    }
    std::string mats;
    for (const auto& [k, n] : kinds)
        mats += fmt::format("{}{} {}", mats.empty() ? "" : " + ", n, to_string(k));
    if (mats.empty()) mats = "none";
    Aabb b = scene.bounds();
    const glm::vec3& bg = scene.background;
    return fmt::format(
        "{}: {} triangles, materials {}, {} emissive material{} ({} triangles), background "
        "({:g}, {:g}, {:g}), bounds ({:g}, {:g}, {:g}) to ({:g}, {:g}, {:g}), loaded in {:.1f} ms",
        scene.name, scene.triangle_count(), mats, emissive, emissive == 1 ? "" : "s", emissive_tris,
        bg.x, bg.y, bg.z, b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z, load_ms);
}

}  // namespace wp
