// fuzz_pbrt.cpp — parse_pbrt (the pbrt-v4 scene subset).
// Files the scene names (Include, Import, plymesh, textures, environment maps) resolve inside
// the empty scratch folder, so they are missing; shapes the file defines itself
// (trianglemesh, bilinearmesh, sphere, disk, ...) are built.
#include "fuzz_common.h"
#include "scene/pbrt_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace wp::fuzz;
    run_one("parse_pbrt",
            [&] { return wp::parse_pbrt(as_text(data, size), scratch_dir() / "fuzz.pbrt"); });
    return 0;
}
