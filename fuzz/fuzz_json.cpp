// fuzz_json.cpp — parse_json_scene (wavepath JSON scene files).
// Mesh files the scene names resolve inside the empty scratch folder, so they are missing.
//
// The format lets a few bytes ask for up to 2^24 triangles of built-in geometry (a "stress"
// shape is 250,000 triangles by default; spheres, quads and boxes take large tessellation
// counts). Those inputs are valid and merely slow under the sanitizers, so they would only
// show up as timeouts: inputs whose built-in shapes add up to more than kMaxTriangles (as
// estimated here from the documented formulas, on a plain JSON parse) are skipped. The
// limits themselves (2^24 in all, per-shape ranges) are covered by the unit tests.
#include <cmath>

#include <nlohmann/json.hpp>

#include "fuzz_common.h"
#include "scene/json_scene.h"

namespace {

constexpr double kMaxTriangles = 100000.0;

// A count field: a number, or an array of numbers (their product), else `fallback`.
double count_of(const nlohmann::json& shape, const char* key, double fallback) {
    auto it = shape.find(key);
    if (it == shape.end()) return fallback;
    if (it->is_number()) return std::abs(it->get<double>());
    if (it->is_array()) {
        double p = 1.0;
        for (const auto& v : *it)
            p *= v.is_number() ? std::abs(v.get<double>()) : 1.0;
        return it->size() == 1 ? p * p : p;
    }
    return fallback;
}

// Built-in triangles the scene asks for, by json_scene.h's formulas (an over-estimate is
// fine); 0 when the text is not plain JSON (the parser then refuses it quickly).
double builtin_triangles(std::string_view text) {
    nlohmann::json doc = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (!doc.is_object()) return 0.0;
    auto shapes = doc.find("shapes");
    if (shapes == doc.end() || !shapes->is_array()) return 0.0;
    double total = 0.0;
    for (const auto& s : *shapes) {
        if (!s.is_object()) continue;
        auto type = s.find("type");
        if (type == s.end() || !type->is_string()) continue;
        const std::string t = type->get<std::string>();
        if (t == "stress") total += count_of(s, "triangles", 250000.0);
        else if (t == "sphere")
            total += 2.0 * count_of(s, "segments", 64.0) * count_of(s, "rings", 32.0);
        else if (t == "quad") {
            double n = count_of(s, "subdivisions", 1.0);
            auto sub = s.find("subdivisions");
            if (sub != s.end() && sub->is_number()) n *= n;  // n means n x n
            total += 2.0 * n;
        } else if (t == "box") {
            const double n = count_of(s, "subdivisions", 1.0);
            total += 12.0 * n * n;
        }
    }
    return total;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace wp::fuzz;
    const std::string_view text = as_text(data, size);
    if (!(builtin_triangles(text) <= kMaxTriangles)) return 0;  // valid but slow: skipped
    run_one("parse_json_scene",
            [&] { return wp::parse_json_scene(text, scratch_dir() / "fuzz.json"); });
    return 0;
}
