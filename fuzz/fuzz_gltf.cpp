// fuzz_gltf.cpp — parse_gltf (glTF 2.0). Inputs starting with the binary magic "glTF" are
// passed as fuzz.glb, others as fuzz.gltf; external buffers (`uri` to a file) are missing
// from the empty scratch folder, embedded data: URIs and GLB chunks are read.
#include "fuzz_common.h"
#include "scene/gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace wp::fuzz;
    const std::string_view bytes = as_text(data, size);
    const bool glb = bytes.substr(0, 4) == "glTF";
    run_one("parse_gltf", [&] {
        return wp::parse_gltf(bytes, scratch_dir() / (glb ? "fuzz.glb" : "fuzz.gltf"));
    });
    return 0;
}
