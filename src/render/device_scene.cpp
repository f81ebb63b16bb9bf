#include "render/device_scene.h"

#include <algorithm>
#include <optional>

#include "bvh/build.h"
#include "bvh/flatten.h"
#include "scene/upload.h"
#include "util/host_trace.h"
#include "util/timer.h"

namespace wp::render {

DeviceScene DeviceScene::upload(const ocl::Device& dev, const Scene& scene, const KernelConfig& config,
                                int width, int height, bool jitter) {
    DeviceScene d;
    Timer timer;
    std::optional<HostSpan> span(std::in_place, "bvh");
    auto boxes = bvh::triangle_boxes(scene.positions, scene.triangles);
    bvh::Bvh bvh = bvh::build(boxes);
    bvh::FlatBvh flat = bvh::flatten(bvh, scene.positions, scene.triangles);
    span.emplace("upload");  // ends the BVH's span
    SceneUpload up = upload_scene(scene);
    d.camera = upload_camera(scene.camera, width, height, jitter);

    SceneStats& st = d.stats;
    st.triangles = scene.triangle_count();
    st.vertices = scene.positions.size();
    st.materials = scene.materials.size();
    st.emissive_materials = static_cast<std::size_t>(std::count_if(
        scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.emissive(); }));
    st.bvh_nodes = flat.nodes.size();
    st.bvh_depth = flat.depth;
    st.bvh_build_ms = bvh.build_ms;

    d.bvh = bvh::DeviceBvh::upload(dev, flat);
    ShadingScene& s = d.shading;
    s.tris = ocl::Array<Triangle>::upload(dev, up.triangles, "the shading triangles");
    s.material_ids = ocl::Array<int>::upload(dev, up.material_ids, "the material ids");
    s.materials = ocl::Array<MaterialData>::upload(dev, up.materials, "the materials");
    s.background = up.background;
    LightTable lights;
    if (config.nee()) lights = build_light_table(scene);
    st.light_triangles = lights.size();
    s.light_count = static_cast<int>(lights.size());
    if (lights.size() > 0) {
        s.light_cdf = ocl::Array<float>::upload(dev, lights.cdf, "the light CDF");
        s.light_prims = ocl::Array<int>::upload(dev, lights.prims, "the light triangles");
        s.light_pdf_area = ocl::Array<float>::upload(dev, lights.pdf_area, "the light densities");
    } else {
        s.light_cdf = ocl::Array<float>::zeros(dev, 0, "a placeholder");
        s.light_prims = ocl::Array<int>::zeros(dev, 0, "a placeholder");
        s.light_pdf_area = ocl::Array<float>::zeros(dev, 0, "a placeholder");
    }
    st.scene_bytes = d.bvh.bytes + s.tris.bytes() + s.material_ids.bytes() + s.materials.bytes() +
                     s.light_cdf.bytes() + s.light_prims.bytes() + s.light_pdf_area.bytes();
    st.upload_ms = timer.ms();
    return d;
}

}  // namespace wp::render
