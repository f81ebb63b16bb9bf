// fuzz_mitsuba.cpp — parse_mitsuba (the Mitsuba 3 scene XML subset).
// Mesh files the scene names resolve inside the empty scratch folder, so they are missing;
// shapes the XML defines itself (rectangle, cube, sphere, ...) are built.
#include "fuzz_common.h"
#include "scene/mitsuba_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace wp::fuzz;
    run_one("parse_mitsuba",
            [&] { return wp::parse_mitsuba(as_text(data, size), scratch_dir() / "fuzz.xml"); });
    return 0;
}
