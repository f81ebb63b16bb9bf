#include "scene/metals.h"

#include <algorithm>
#include <array>
#include <string>

namespace wp {

namespace {

// Tungsten's ComplexIorData.hpp (https://github.com/tunabrain/tungsten, src/core/bsdfs/),
// to 7 digits. MgO and TiO2 are dielectrics (k ~ 0): TiO2's fitted k has a tiny negative
// green channel there (-9e-5), stored here as 0.
constexpr std::array<MetalIor, 20> kMetals{{
    {"Ag", {0.1552646f, 0.1167233f, 0.1383807f}, {4.8283433f, 3.1222459f, 2.1469504f}},
    {"Al", {1.6574600f, 0.8803690f, 0.5212287f}, {9.2238692f, 6.2695232f, 4.8370012f}},
    {"Au", {0.1431190f, 0.3749570f, 1.4424786f}, {3.9831604f, 2.3857207f, 1.6032153f}},
    {"Be", {4.1850593f, 3.1850604f, 2.7840913f}, {3.8354398f, 3.0101260f, 2.8690089f}},
    {"Cr", {4.3696829f, 2.9167025f, 1.6547005f}, {5.2064338f, 4.2313645f, 3.7549468f}},
    {"Cu", {0.2004377f, 0.9240334f, 1.1022120f}, {3.9129485f, 2.4528477f, 2.1421880f}},
    {"Hg", {2.3989315f, 1.4400255f, 0.9095512f}, {6.3276269f, 4.3719414f, 3.4217899f}},
    {"Ir", {3.0864098f, 2.0821938f, 1.6178867f}, {5.5921510f, 4.0671757f, 3.2672611f}},
    {"K", {0.0640493f, 0.0464101f, 0.0381842f}, {2.1042156f, 1.3489364f, 0.9132114f}},
    {"Li", {0.2657872f, 0.1956102f, 0.2209199f}, {3.5401743f, 2.3111307f, 1.6685930f}},
    {"MgO", {2.0895886f, 1.6507225f, 1.5948760f}, {0.0f, 0.0f, 0.0f}},
    {"Mo", {4.4837010f, 3.5254578f, 2.7760769f}, {4.1111308f, 3.4208716f, 3.1506031f}},
    {"Na_palik", {0.0602665f, 0.0561412f, 0.0619909f}, {3.1792906f, 2.1124801f, 1.5790940f}},
    {"Ni_palik", {2.3672754f, 1.6633583f, 1.4670554f}, {4.4988330f, 3.0501644f, 2.3454274f}},
    {"Rh", {2.5857955f, 1.8601866f, 1.5544280f}, {6.7822927f, 4.7029501f, 3.9760892f}},
    {"Ta", {2.0625847f, 2.3930916f, 2.6280685f}, {2.4080468f, 1.7413706f, 1.9470377f}},
    {"TiN", {1.6484692f, 1.1504483f, 1.3797795f}, {3.3684596f, 1.9434889f, 1.1020123f}},
    {"TiO2", {3.4566203f, 2.8017077f, 2.9051485f}, {0.0001027f, 0.0f, 0.0006357f}},
    {"VN", {2.8656012f, 2.1191818f, 1.9400767f}, {3.0323265f, 2.0561076f, 1.6162931f}},
    {"W", {4.3707030f, 3.3002972f, 2.9982667f}, {3.5006779f, 2.6048653f, 2.2731931f}},
}};

}  // namespace

std::span<const MetalIor> metal_table() { return kMetals; }

const MetalIor* find_metal(std::string_view name) {
    auto it = std::find_if(kMetals.begin(), kMetals.end(),
                           [&](const MetalIor& m) { return m.name == name; });
    return it == kMetals.end() ? nullptr : &*it;
}

std::optional<glm::vec3> pbrt_metal_spectrum(std::string_view name) {
    constexpr std::string_view prefix = "metal-";
    if (name.substr(0, prefix.size()) != prefix) return std::nullopt;
    name.remove_prefix(prefix.size());
    const bool eta = name.size() > 4 && name.substr(name.size() - 4) == "-eta";
    const bool k = !eta && name.size() > 2 && name.substr(name.size() - 2) == "-k";
    if (!eta && !k) return std::nullopt;
    const std::string_view metal = name.substr(0, name.size() - (eta ? 4 : 2));
    for (std::string_view m : {"Ag", "Al", "Au", "Cu", "MgO", "TiO2"})
        if (metal == m) {
            const MetalIor* x = find_metal(m);
            return eta ? x->eta : x->k;
        }
    return std::nullopt;
}

}  // namespace wp
