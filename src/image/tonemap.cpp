#include "image/tonemap.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <vector>

namespace wp {

namespace {

// The reference code (image.cpp's PNG encoding), in double.
int reference_code(float linear) {
    double x = std::isnan(linear) ? 0.0 : std::clamp(static_cast<double>(linear), 0.0, 1.0);
    return static_cast<int>(std::floor(srgb_encode(x) * 255.0 + 0.5));
}

// bounds[k - 1]: the smallest float in [0, 1] whose code is >= k (codes grow with x; positive
// floats are ordered as their bit patterns, so a binary search over the bits finds it).
std::array<float, 255> make_bounds() {
    std::array<float, 255> b{};
    for (int k = 1; k <= 255; ++k) {
        std::uint32_t lo = 0, hi = std::bit_cast<std::uint32_t>(1.0f);  // code(lo) < k <= code(hi)
        while (hi - lo > 1) {
            std::uint32_t mid = lo + (hi - lo) / 2;
            if (reference_code(std::bit_cast<float>(mid)) >= k) hi = mid;
            else lo = mid;
        }
        b[k - 1] = std::bit_cast<float>(hi);
    }
    return b;
}

const std::array<float, 255>& bounds() {
    static const std::array<float, 255> b = make_bounds();
    return b;
}

// A faster lookup with the same answers: the floats in (0, 1) fall into 16256 buckets by
// their top 16 bits (exponent and 7 mantissa bits, a width of at most 1/128 of the value);
// per bucket, the code at its start and the next boundary when one lies inside it. Code
// steps are wider than the buckets (the linear part's 1/(255 12.92); above it the step is
// ~0.0089 x^0.58 >= x / 128 for x <= 1), so a bucket holds at most one boundary; a bucket that
// held more would fall back to the binary search (`many`).
constexpr std::uint32_t kBuckets = 0x3F80;  // bits(1.0f) >> 16
struct Bucket {
    float next;  // the boundary inside the bucket, else +inf
    std::uint8_t base;
    bool many;
};

std::vector<Bucket> make_buckets() {
    const auto& b = bounds();
    std::vector<Bucket> out(kBuckets);
    for (std::uint32_t i = 0; i < kBuckets; ++i) {
        const float lo = std::bit_cast<float>(i << 16), hi = std::bit_cast<float>((i + 1) << 16);
        const auto first = std::upper_bound(b.begin(), b.end(), lo);  // first boundary > lo
        const auto last = std::lower_bound(b.begin(), b.end(), hi);    // first boundary >= hi
        out[i].base = static_cast<std::uint8_t>(first - b.begin());
        out[i].next = first != last ? *first : std::numeric_limits<float>::infinity();
        out[i].many = last - first > 1;
    }
    return out;
}

const std::vector<Bucket>& buckets() {
    static const std::vector<Bucket> b = make_buckets();
    return b;
}

std::uint8_t linear_code8(float y) {
    if (!(y > 0.0f)) return 0;
    if (y >= 1.0f) return 255;
    return static_cast<std::uint8_t>(std::floor(static_cast<double>(y) * 255.0 + 0.5));
}

}  // namespace

const char* tone_curve_name(ToneCurve c) {
    switch (c) {
        case ToneCurve::Clamp: return "clamp";
        case ToneCurve::Reinhard: return "reinhard";
        case ToneCurve::Filmic: return "filmic";
    }
    return "?";
}

std::optional<ToneCurve> parse_tone_curve(std::string_view name) {
    if (name == "clamp") return ToneCurve::Clamp;
    if (name == "reinhard") return ToneCurve::Reinhard;
    if (name == "filmic") return ToneCurve::Filmic;
    return std::nullopt;
}

ToneCurve next_tone_curve(ToneCurve c) {
    return c == ToneCurve::Clamp ? ToneCurve::Reinhard
           : c == ToneCurve::Reinhard ? ToneCurve::Filmic
                                      : ToneCurve::Clamp;
}

float apply_tone_curve(ToneCurve c, float x) {
    switch (c) {
        case ToneCurve::Clamp: return x;
        case ToneCurve::Reinhard: return x > 0.0f ? x / (1.0f + x) : 0.0f;
        case ToneCurve::Filmic: {
            if (!(x > 0.0f)) return 0.0f;
            if (x > 1e6f) return 1.0f;  // the rational tends to 2.51 / 2.43 > 1: clamped anyway
            float y = x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f);
            return std::min(y, 1.0f);
        }
    }
    return x;
}

std::uint8_t srgb_code8(float linear) {
    if (!(linear > 0.0f)) return 0;  // NaN and <= 0
    if (linear >= 1.0f) return 255;
    const Bucket& k = buckets()[std::bit_cast<std::uint32_t>(linear) >> 16];
    if (!k.many) return static_cast<std::uint8_t>(k.base + (linear >= k.next));
    const auto& b = bounds();
    return static_cast<std::uint8_t>(std::upper_bound(b.begin(), b.end(), linear) - b.begin());
}

void tonemap_rgba8(const Image& image, const ToneMapping& t, std::vector<std::uint8_t>& rgba) {
    const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
    rgba.resize(n * 4);
    const float scale = static_cast<float>(std::exp2(t.exposure));
    const float* in = image.rgb.data();
    std::uint8_t* out = rgba.data();
    buckets();  // built before the loop
    for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            float y = apply_tone_curve(t.curve, in[i * 3 + c] * scale);
            out[i * 4 + c] = t.srgb ? srgb_code8(y) : linear_code8(y);
        }
        out[i * 4 + 3] = 255;
    }
}

Image apply_tone_mapping(const Image& image, const ToneMapping& t) {
    Image out = image;
    const float scale = static_cast<float>(std::exp2(t.exposure));
    for (float& v : out.rgb) v = apply_tone_curve(t.curve, v * scale);
    return out;
}

}  // namespace wp
