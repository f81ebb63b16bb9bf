// splitmix.h — splitmix64 (Steele, Lea & Flood, "Fast Splittable Pseudorandom Number
// Generators", OOPSLA 2014): a tiny, fully specified generator for the host, so a seed gives
// the same meshes, ray sets and test data on every platform (std distributions do not).
#pragma once

#include <cstdint>

namespace wp {

struct SplitMix64 {
    std::uint64_t state = 0;

    explicit SplitMix64(std::uint64_t seed = 0) : state(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1): the top 24 bits, exactly representable as a float.
    float uniform() { return static_cast<float>(next() >> 40) * 0x1p-24f; }
    float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
};

}  // namespace wp
