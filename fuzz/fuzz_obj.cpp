// fuzz_obj.cpp — parse_obj (Wavefront OBJ) and the MTL libraries it names.
//
// Input: OBJ text, optionally followed by a line "#--mtl--" and MTL text; every `mtllib`
// name then resolves to that MTL text (in memory: no file is read), so one input exercises
// tinyobjloader's OBJ and MTL parsers and wavepath's material mapping together.
#include "fuzz_common.h"
#include "scene/obj_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace wp::fuzz;
    const std::string_view input = as_text(data, size);
    constexpr std::string_view kSplit = "#--mtl--";
    const std::size_t at = input.find(kSplit);
    const std::string_view obj = input.substr(0, at);
    const bool has_mtl = at != std::string_view::npos;
    const std::string mtl = has_mtl ? std::string(input.substr(at + kSplit.size())) : std::string();
    wp::MtlSource source = [&](const std::string&) -> std::optional<std::string> {
        if (!has_mtl) return std::nullopt;
        return mtl;
    };
    run_one("parse_obj", [&] { return wp::parse_obj(obj, scratch_dir() / "fuzz.obj", source); });
    return 0;
}
