// metals.h — RGB complex indices of refraction (η + i k per channel) of named metals, for the
// loaders that accept a metal by name (Mitsuba's conductor `material`, pbrt-v4's named
// spectra "metal-Cu-eta" / "metal-Cu-k").
//
// The values are the RGB fits in Tungsten's src/core/bsdfs/ComplexIorData.hpp (Benedikt
// Bitterli; fits of the measured spectra that Mitsuba's conductor also uses), the same numbers
// Bitterli's scene exports write as "rgb eta" / "rgb k". Names are Mitsuba's (Ag, Al, Au, Cu,
// ...); pbrt-v4's metal names map onto them (pbrt_metal below).
#pragma once

#include <optional>
#include <span>
#include <string_view>

#include <glm/glm.hpp>

namespace wp {

struct MetalIor {
    std::string_view name;  // Mitsuba's name: "Cu", "Au", "Na_palik", ...
    glm::vec3 eta, k;
};

// Every metal of the table, in alphabetical order.
std::span<const MetalIor> metal_table();

// The metal named `name` (Mitsuba's names, exact match), if any.
const MetalIor* find_metal(std::string_view name);

// pbrt-v4's named conductor spectra: "metal-X-eta" / "metal-X-k" with X one of Ag, Al, Au,
// Cu, MgO, TiO2 (pbrt-v4 src/pbrt/util/spectrum.cpp, namedSpectra). Returns the channel
// values (η for "-eta", k for "-k"), or nullopt for another name. "metal-CuZn-eta/-k"
// (brass) is not in the table: nullopt (the caller warns).
std::optional<glm::vec3> pbrt_metal_spectrum(std::string_view name);

}  // namespace wp
