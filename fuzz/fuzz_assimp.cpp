// fuzz_assimp.cpp — parse_assimp (mesh formats read through Assimp).
//
// Input: one byte choosing the extension (its value mod 2: '0' .ply, '1' .stl), then the
// file's bytes. (.off was fuzzed too until it found Assimp 5.2's OFF importer reading out of
// bounds — regressions/assimp/off-face-corner-count-oob — and wavepath stopped reading .off.)
// then the file's bytes. Only these formats are fuzzed: Assimp's other importers (.3ds,
// .dae, .fbx) are large, uninstrumented here and known upstream to crash on hostile input;
// wavepath reads them as Assimp does.
#include <array>

#include "fuzz_common.h"
#include "scene/assimp_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace wp::fuzz;
    if (size < 1) return 0;
    static const std::array<const char*, 2> kExt{".ply", ".stl"};
    const std::string ext = kExt[data[0] % kExt.size()];
    run_one("parse_assimp", [&] {
        return wp::parse_assimp(as_text(data + 1, size - 1), ext, scratch_dir() / ("fuzz" + ext));
    });
    return 0;
}
