// test_texture.cpp — image textures (issue 13): loading through OpenImageIO (scene/texture.h),
// the mip chains of upload_textures, and the device lookups of kernels/shared/texture.h
// compiled here as host C++ (and once as OpenCL C, compared with the host).
//
// Independent answers: analytic values (ramps, wrapped texel blends, painted levels, the
// view's level from its transform), box averages in double precision written here, the
// sRGB curve of image.h, and values the test writes into image files itself.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "shared/texture.h"

#include "cl/kernel.h"
#include "cl/program.h"
#include "image/image.h"
#include "scene/texture.h"
#include "util/error.h"
#include "util/limits.h"
#include "support.h"
#include "temp_dir.h"

using namespace wp;
namespace fs = std::filesystem;

namespace {

// Device views of an upload (and of extra views) for host lookups.
struct HostPool {
    TextureUpload up;
    std::vector<TextureView> views;
    TexturePool pool() const {
        TexturePool p;
        p.textures = up.textures.data();
        p.views = views.data();
        p.texels8 = up.texels8.data();
        p.texelsf = up.texelsf.data();
        return p;
    }
};

TextureView view_of(int texture, float a = 1, float b = 0, float c = 0, float d = 0, float e = 1, float f = 0) {
    TextureView v{};
    v.u_row = make_float4(a, b, c, 0.0f);
    v.v_row = make_float4(d, e, f, 0.0f);
    v.texture = texture;
    return v;
}

// A float texture whose texel (x, y) is fn(x, y) (RGBA).
template <typename Fn>
Texture float_texture(int w, int h, Fn fn, const std::string& name = "float") {
    Texture t;
    t.source = name;
    t.width = w;
    t.height = h;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::array<float, 4> v = fn(x, y);
            t.texelsf.insert(t.texelsf.end(), v.begin(), v.end());
        }
    return t;
}

float4 lookup(const HostPool& hp, int t, float u, float v, float level = 0.0f) {
    return wp_texture_lookup(hp.pool(), t, make_float2(u, v), level);
}

// Writes `data` as given: with alpha, straight (not premultiplied, OIIO's default).
void write_oiio(const fs::path& p, OIIO::ImageSpec spec, OIIO::TypeDesc type, const void* data) {
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (spec.nchannels == 4 || spec.nchannels == 2) spec.alpha_channel = spec.nchannels - 1;
    auto out = OIIO::ImageOutput::create(p.string());
    REQUIRE(out);
    REQUIRE(out->open(p.string(), spec));
    REQUIRE(out->write_image(type, data));
    REQUIRE(out->close());
}

std::string read_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::uint32_t crc32(const unsigned char* data, std::size_t n) {
    std::uint32_t c = 0xffffffffu;
    for (std::size_t i = 0; i < n; ++i) {
        c ^= data[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

void put_be32(std::string& s, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) s[at + i] = static_cast<char>((v >> (24 - 8 * i)) & 0xff);
}

// A valid 1x1 PNG whose IHDR then claims w x h (CRC fixed): OIIO reads the header as that.
std::string png_claiming(const test::TempDir& dir, std::uint32_t w, std::uint32_t h) {
    fs::path p = dir.path / "tiny.png";
    const std::uint8_t rgb[3] = {10, 20, 30};
    write_oiio(p, OIIO::ImageSpec(1, 1, 3, OIIO::TypeDesc::UINT8), OIIO::TypeDesc::UINT8, rgb);
    std::string s = read_bytes(p);
    REQUIRE(s.size() > 33);
    REQUIRE(s.substr(12, 4) == "IHDR");
    put_be32(s, 16, w);
    put_be32(s, 20, h);
    put_be32(s, 29, crc32(reinterpret_cast<const unsigned char*>(s.data()) + 12, 17));
    return s;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace

// ------------------------------------------------------------------ device lookups ----------

TEST_CASE("texture: the sRGB8 decode table is srgb_decode of every code", "[unit][texture]") {
    // Level 0 of a nearest 256 x 1 SRGB8 texture and a LINEAR8 one: texel c has code c in
    // every channel.
    HostPool hp;
    hp.up.textures.push_back(TextureData{0, 256, 1, 1, WP_TEXEL_SRGB8, 1, 0, 0});
    hp.up.textures.push_back(TextureData{256, 256, 1, 1, WP_TEXEL_LINEAR8, 1, 0, 0});
    for (int pass = 0; pass < 2; ++pass)
        for (std::uint32_t c = 0; c < 256; ++c) hp.up.texels8.push_back(c | c << 8 | c << 16 | c << 24);
    for (int c = 0; c < 256; ++c) {
        INFO("code " << c);
        const float expected = static_cast<float>(srgb_decode(c / 255.0));
        CHECK(wp_srgb8_to_linear[c] == expected);
        float4 s = lookup(hp, 0, (c + 0.5f) / 256.0f, 0.5f);
        float4 l = lookup(hp, 1, (c + 0.5f) / 256.0f, 0.5f);
        CHECK(s.x == expected);
        CHECK(s.z == expected);
        CHECK(std::abs(s.w - c / 255.0) <= 3e-8);  // alpha is not sRGB-encoded
        CHECK(std::abs(l.y - c / 255.0) <= 3e-8);
    }
}

TEST_CASE("texture: bilinear filtering reproduces a linear ramp", "[unit][texture]") {
    // R = (i + 0.5) / w and G = (j + 0.5) / h at texel centres: between centres bilinear
    // interpolation is exact, so R = u and G = v.
    const int w = 8, h = 4;
    Texture t = float_texture(w, h, [&](int x, int y) {
        return std::array<float, 4>{(x + 0.5f) / w, (y + 0.5f) / h, 1.0f, 0.5f};
    });
    HostPool hp;
    hp.up = upload_textures({&t});
    test::Rng rng(3);
    for (int i = 0; i < 1000; ++i) {
        float u = rng.uniform(0.5f / w, 1.0f - 0.5f / w);
        float v = rng.uniform(0.5f / h, 1.0f - 0.5f / h);
        float4 r = lookup(hp, 0, u, v);
        INFO("u " << u << " v " << v);
        CHECK(std::abs(r.x - u) <= 1e-6f);
        CHECK(std::abs(r.y - v) <= 1e-6f);
        CHECK(r.z == 1.0f);
        CHECK(r.w == 0.5f);
    }
}

TEST_CASE("texture: uv repeats, also for negative, huge and non-finite coordinates", "[unit][texture]") {
    const int w = 4, h = 4;
    test::Rng rng(5);
    std::vector<float> vals(w * h);
    for (float& v : vals) v = rng.uniform();
    Texture t = float_texture(w, h, [&](int x, int y) {
        float v = vals[y * w + x];
        return std::array<float, 4>{v, 0.0f, 0.0f, 1.0f};
    });
    HostPool hp;
    hp.up = upload_textures({&t});
    auto at = [&](int x, int y) { return vals[((y % h + h) % h) * w + ((x % w + w) % w)]; };
    const int row = 2;
    const float v = (row + 0.5f) / h;  // a texel centre row: no vertical blend
    // u wraps to 0.75: x = 2.5, halfway between texels 2 and 3.
    CHECK(lookup(hp, 0, -0.25f, v).x == Approx(0.5 * (at(2, row) + at(3, row))).epsilon(1e-6));
    // u = 1.25 wraps to 0.25: x = 0.5, texels 0 and 1.
    CHECK(lookup(hp, 0, 1.25f, v).x == Approx(0.5 * (at(0, row) + at(1, row))).epsilon(1e-6));
    // u = 1e6 and -1e6 wrap to 0: x = -0.5, texels 3 (across the border) and 0.
    const double edge = 0.5 * (at(3, row) + at(0, row));
    CHECK(lookup(hp, 0, 1e6f, v).x == Approx(edge).epsilon(1e-6));
    CHECK(lookup(hp, 0, -1e6f, v).x == Approx(edge).epsilon(1e-6));
    CHECK(lookup(hp, 0, 3.0e38f, v).x == Approx(edge).epsilon(1e-6));
    // A tiny negative u wraps to just below 1 (or to 1): also texels 3 and 0.
    CHECK(lookup(hp, 0, -1e-9f, v).x == Approx(edge).epsilon(1e-6));
    // NaN and infinities count as 0.
    CHECK(lookup(hp, 0, NAN, v).x == Approx(edge).epsilon(1e-6));
    CHECK(lookup(hp, 0, INFINITY, v).x == Approx(edge).epsilon(1e-6));
    CHECK(lookup(hp, 0, -INFINITY, v).x == Approx(edge).epsilon(1e-6));
    // v wraps the same way (u at a texel centre column).
    const float u = (1 + 0.5f) / w;
    CHECK(lookup(hp, 0, u, -0.25f).x == Approx(0.5 * (at(1, 2) + at(1, 3))).epsilon(1e-6));
    CHECK(lookup(hp, 0, u, 1.25f).x == Approx(0.5 * (at(1, 0) + at(1, 1))).epsilon(1e-6));
    CHECK(lookup(hp, 0, u, NAN).x == Approx(0.5 * (at(1, 3) + at(1, 0))).epsilon(1e-6));
    // Whole periods change nothing.
    for (int i = 0; i < 200; ++i) {
        float a = rng.uniform(), b = rng.uniform();
        float k = std::floor(rng.uniform(-50.0f, 50.0f));
        float4 p = lookup(hp, 0, a, b), q = lookup(hp, 0, a + k, b - k);
        CHECK(std::abs(p.x - q.x) <= 2e-5f);  // a + k rounds a to ~4e-6 at |k| = 50
    }
}

TEST_CASE("texture: each mip level is the box average of level 0", "[unit][texture]") {
    // 16 x 8: level k texel (x, y) is the mean of level 0 over the 2^k x 2^k block at
    // (x 2^k, y 2^k) clipped to the image (once a side is 1 the block is clipped).
    const int w = 16, h = 8;
    test::Rng rng(7);
    Texture f = float_texture(w, h, [&](int, int) {
        return std::array<float, 4>{rng.uniform(0.0f, 4.0f), rng.uniform(), rng.uniform(-1.0f, 1.0f), rng.uniform()};
    });
    Texture s, l;
    for (Texture* t : {&s, &l}) {
        t->width = w;
        t->height = h;
        for (int i = 0; i < w * h * 4; ++i) t->texels8.push_back(static_cast<std::uint8_t>(rng.next() & 255));
    }
    s.srgb = true;
    s.source = "srgb";
    l.source = "linear";
    TextureUpload up = upload_textures({&f, &s, &l});
    REQUIRE(up.textures.size() == 3);
    CHECK(up.textures[0].levels == 5);
    CHECK(up.textures[0].format == WP_TEXEL_FLOAT);
    CHECK(up.textures[1].format == WP_TEXEL_SRGB8);
    CHECK(up.textures[2].format == WP_TEXEL_LINEAR8);
    CHECK(up.texelsf.size() == std::size_t(16 * 8 + 8 * 4 + 4 * 2 + 2 * 1 + 1 * 1));
    CHECK(up.texels8.size() == 2 * up.texelsf.size());
    CHECK(up.textures[1].offset == 0);
    CHECK(up.textures[2].offset == static_cast<int>(up.texelsf.size()));
    CHECK(up.bytes() == 3 * sizeof(TextureData) + up.texels8.size() * 4 + up.texelsf.size() * 16);

    auto decode = [](const Texture& t, int x, int y, int c) {
        double code = t.texels8[(std::size_t(y) * t.width + x) * 4 + c];
        return (t.srgb && c < 3) ? srgb_decode(code / 255.0) : code / 255.0;
    };
    auto block_mean = [&](const Texture& t, int k, int x, int y, int c) {
        double sum = 0.0;
        int n = 0;
        for (int j = y << k; j < std::min(h, (y + 1) << k); ++j)
            for (int i = x << k; i < std::min(w, (x + 1) << k); ++i, ++n)
                sum += t.is_float() ? t.texelsf[(std::size_t(j) * w + i) * 4 + c] : decode(t, i, j, c);
        return sum / n;
    };
    int first = 0;
    int worst8 = 0;
    for (int k = 0; k < 5; ++k) {
        int lw = std::max(1, w >> k), lh = std::max(1, h >> k);
        for (int y = 0; y < lh; ++y)
            for (int x = 0; x < lw; ++x) {
                INFO("level " << k << " texel " << x << ", " << y);
                const float4 tf = up.texelsf[first + y * lw + x];
                const float got[4] = {tf.x, tf.y, tf.z, tf.w};
                for (int c = 0; c < 4; ++c) CHECK(got[c] == Approx(block_mean(f, k, x, y, c)).margin(4e-6));
                for (int which = 1; which <= 2; ++which) {
                    const Texture& t = which == 1 ? s : l;
                    std::uint32_t packed = up.texels8[up.textures[which].offset + first + y * lw + x];
                    for (int c = 0; c < 4; ++c) {
                        double m = block_mean(t, k, x, y, c);
                        double enc = (t.srgb && c < 3) ? srgb_encode(m) : m;
                        int expected = static_cast<int>(std::floor(enc * 255.0 + 0.5));
                        int code = (packed >> (8 * c)) & 255;
                        if (k == 0) CHECK(code == t.texels8[(std::size_t(y) * w + x) * 4 + c]);
                        worst8 = std::max(worst8, std::abs(code - expected));
                    }
                }
            }
        first += lw * lh;
    }
    CHECK(worst8 <= 1);  // rounding of a float chain vs a double mean, at a code boundary
    // The lookups read those levels: at a level-2 texel centre, level 2 is that texel.
    HostPool hp;
    hp.up = up;
    float4 r = lookup(hp, 0, (1 + 0.5f) / 4, (0 + 0.5f) / 2, 2.0f);
    CHECK(r.x == Approx(block_mean(f, 2, 1, 0, 0)).margin(1e-6));
    CHECK(r.w == Approx(block_mean(f, 2, 1, 0, 3)).margin(1e-6));
    r = lookup(hp, 0, 0.3f, 0.9f, 4.0f);  // the 1 x 1 level: the mean of everything
    CHECK(r.y == Approx(block_mean(f, 4, 0, 0, 1)).margin(1e-6));
    r = lookup(hp, 0, 0.3f, 0.9f, 100.0f);  // clamped to the last level
    CHECK(r.y == Approx(block_mean(f, 4, 0, 0, 1)).margin(1e-6));
}

TEST_CASE("texture: odd sizes give max(1, side >> l) levels with the clamped 2x2 box", "[unit][texture]") {
    // 5 x 3: levels 5x3, 2x1, 1x1. Level 1 texel x averages level-0 columns 2x, 2x + 1 and
    // rows 0, 1 (column 4 and row 2 do not reach it); level 2 averages level 1's two
    // texels with themselves (rows clamped to the single row).
    Texture t = float_texture(5, 3, [](int x, int y) {
        return std::array<float, 4>{float(x + 10 * y), float(x * x), 1.0f, float(y)};
    });
    TextureUpload up = upload_textures({&t});
    REQUIRE(up.textures.size() == 1);
    const TextureData& d = up.textures[0];
    CHECK(d.width == 5);
    CHECK(d.height == 3);
    CHECK(d.levels == 3);
    CHECK(d.nearest == 0);
    REQUIRE(up.texelsf.size() == std::size_t(15 + 2 + 1));
    auto l0 = [&](int x, int y) { return std::array<double, 2>{double(x + 10 * y), double(x * x)}; };
    for (int x = 0; x < 2; ++x) {
        double r = 0, g = 0;
        for (int j = 0; j < 2; ++j)
            for (int i = 2 * x; i < 2 * x + 2; ++i) {
                r += l0(i, j)[0] / 4;
                g += l0(i, j)[1] / 4;
            }
        CHECK(up.texelsf[15 + x].x == Approx(r));
        CHECK(up.texelsf[15 + x].y == Approx(g));
        CHECK(up.texelsf[15 + x].w == Approx(0.5));
    }
    CHECK(up.texelsf[17].x == Approx((up.texelsf[15].x + up.texelsf[16].x) / 2.0));
    CHECK(mip_levels(5, 3) == 3);
    CHECK(mip_levels(1, 1) == 1);
    CHECK(mip_levels(1, 9) == 4);
    CHECK(mip_levels(1024, 2) == 11);
    // A 1 x 9 texture: levels 1x9, 1x4, 1x2, 1x1.
    Texture col = float_texture(1, 9, [](int, int y) { return std::array<float, 4>{float(y), 0, 0, 1}; });
    up = upload_textures({&col});
    CHECK(up.textures[0].levels == 4);
    CHECK(up.texelsf.size() == std::size_t(9 + 4 + 2 + 1));
    // Level 1 (offset 9): rows (2j, 2j + 1), so 0.5, 2.5, 4.5, 6.5 (row 8 does not reach it);
    // level 2 (offset 13): 1.5, 5.5; level 3 (offset 15): 3.5.
    CHECK(up.texelsf[9].x == 0.5f);
    CHECK(up.texelsf[12].x == 6.5f);
    CHECK(up.texelsf[13].x == 1.5f);
    CHECK(up.texelsf[14].x == 5.5f);
    CHECK(up.texelsf[15].x == 3.5f);
}

TEST_CASE("texture: trilinear filtering between levels painted different colours", "[unit][texture]") {
    // An 8 x 8 float texture (4 levels) built by hand: every texel of level l has R = l, so
    // the lookup's R is the level it used, clamp(level, 0, 3), blended linearly.
    HostPool hp;
    hp.up.textures.push_back(TextureData{0, 8, 8, 4, WP_TEXEL_FLOAT, 0, 0, 0});
    for (int l = 0, s = 8; l < 4; ++l, s /= 2)
        for (int i = 0; i < s * s; ++i) hp.up.texelsf.push_back(make_float4(float(l), 1.0f, 0.0f, 1.0f));
    const struct { float level, expected; } cases[] = {
        {0.0f, 0.0f}, {0.25f, 0.25f}, {1.0f, 1.0f}, {1.75f, 1.75f}, {2.5f, 2.5f}, {3.0f, 3.0f},
        {3.5f, 3.0f}, {40.0f, 3.0f}, {-2.0f, 0.0f}, {-FLT_MAX, 0.0f}, {NAN, 0.0f},
        {INFINITY, 3.0f}, {-INFINITY, 0.0f},
    };
    test::Rng rng(9);
    for (const auto& c : cases) {
        INFO("level " << c.level);
        float4 r = lookup(hp, 0, rng.uniform(-2.0f, 2.0f), rng.uniform(-2.0f, 2.0f), c.level);
        CHECK(r.x == Approx(c.expected).margin(1e-6));
        CHECK(r.y == 1.0f);
    }
}

TEST_CASE("texture: the view's uv map and its mip level", "[unit][texture]") {
    // The painted 8 x 8 texture of the trilinear test (R = the level used). A view with
    // u' = a u + b v + c, v' = d u + e v + f reads level lod_uv + 0.5 log2(64 |ae - bd|).
    HostPool hp;
    hp.up.textures.push_back(TextureData{0, 8, 8, 4, WP_TEXEL_FLOAT, 0, 0, 0});
    for (int l = 0, s = 8; l < 4; ++l, s /= 2)
        for (int i = 0; i < s * s; ++i) hp.up.texelsf.push_back(make_float4(float(l), 0.0f, 0.0f, 1.0f));
    hp.views.push_back(view_of(0));                          // identity: det 1
    hp.views.push_back(view_of(0, 2, 0, 0.3f, 0, 4, -1));    // scale 2 x 4: det 8
    const float a = 3.0f * std::cos(0.7f), b = 3.0f * std::sin(0.7f);
    hp.views.push_back(view_of(0, a, -b, 5, b, a, 2));       // rotation x 3: det 9
    hp.views.push_back(view_of(0, 1, 2, 0, 2, 4, 0));        // singular: det 0
    const struct { int view; float lod_uv; double level; } cases[] = {
        {0, -3.0f, 0.0},         // 2^-3 of uv = one texel of 8: level 0
        {0, -2.0f, 1.0},
        {0, -1.5f, 1.5},
        {0, 0.0f, 3.0},          // clamped
        {0, -FLT_MAX, 0.0},
        {1, -4.0f, 0.5},         // -4 + 0.5 log2(64 * 8) = 0.5
        {1, -3.25f, 1.25},
        {2, -4.5f, 0.5 * std::log2(64.0 * 9.0) - 4.5},
        {2, -3.0f, 0.5 * std::log2(64.0 * 9.0) - 3.0},
        {3, 0.0f, 0.0},          // no area: level 0
    };
    TexturePool p = hp.pool();
    for (const auto& c : cases) {
        INFO("view " << c.view << " lod_uv " << c.lod_uv);
        double expected = std::clamp(c.level, 0.0, 3.0);
        float level = wp_texture_view_level(p, c.view, c.lod_uv);
        if (c.level > 0.0) CHECK(level == Approx(c.level).margin(1e-5));
        float4 r = wp_texture_view(p, c.view, make_float2(0.37f, -1.2f), c.lod_uv);
        CHECK(r.x == Approx(expected).margin(1e-5));
    }
    // The map itself: a view of a ramp texture reads the ramp at the mapped uv.
    HostPool ramp;
    Texture t = float_texture(16, 16, [](int x, int y) {
        return std::array<float, 4>{(x + 0.5f) / 16, (y + 0.5f) / 16, 0, 1};
    });
    ramp.up = upload_textures({&t});
    ramp.views.push_back(view_of(0, 0.5f, 0.25f, 0.1f, -0.25f, 0.5f, 0.6f));
    test::Rng rng(13);
    for (int i = 0; i < 200; ++i) {
        float u = rng.uniform(), v = rng.uniform();
        double mu = 0.5 * u + 0.25 * v + 0.1, mv = -0.25 * u + 0.5 * v + 0.6;
        mu -= std::floor(mu);
        mv -= std::floor(mv);
        if (mu < 1.0 / 32 || mu > 31.0 / 32 || mv < 1.0 / 32 || mv > 31.0 / 32) continue;  // border blends
        float4 r = wp_texture_view(ramp.pool(), 0, make_float2(u, v), -FLT_MAX);
        CHECK(r.x == Approx(mu).margin(2e-6));
        CHECK(r.y == Approx(mv).margin(2e-6));
    }
}

TEST_CASE("texture: nearest lookups, Mitsuba's checkerboard and the placeholder", "[unit][texture]") {
    const glm::vec3 c0(0.1f, 0.2f, 0.3f), c1(0.9f, 0.8f, 0.7f);
    Texture cb = checkerboard_texture(c0, c1, "checks");
    Texture ph = placeholder_texture("missing.png (placeholder)");
    CHECK(cb.nearest);
    CHECK(cb.is_float());
    CHECK(cb.source == "checks");
    CHECK(ph.nearest);
    CHECK(ph.width == 8);
    CHECK(ph.height == 8);
    HostPool hp;
    hp.up = upload_textures({&cb, &ph});
    CHECK(hp.up.textures[0].levels == 1);
    CHECK(hp.up.textures[1].levels == 1);
    CHECK(hp.up.textures[1].format == WP_TEXEL_LINEAR8);
    test::Rng rng(17);
    for (int i = 0; i < 2000; ++i) {
        float u = rng.uniform(-3.0f, 3.0f), v = rng.uniform(-3.0f, 3.0f);
        double fu = u - std::floor(double(u)), fv = v - std::floor(double(v));
        if (std::abs(fu - 0.5) < 1e-5 || std::abs(fv - 0.5) < 1e-5 || fu < 1e-5 || fv < 1e-5 ||
            fu > 1 - 1e-5 || fv > 1 - 1e-5)
            continue;
        glm::vec3 expected = ((fu < 0.5) == (fv < 0.5)) ? c0 : c1;  // Mitsuba 3's rule
        for (float level : {0.0f, 5.0f}) {
            float4 r = lookup(hp, 0, u, v, level);
            CHECK(r.x == expected.x);
            CHECK(r.y == expected.y);
            CHECK(r.z == expected.z);
            CHECK(r.w == 1.0f);
        }
        // Placeholder: magenta where (floor(8u) + floor(8v)) is even, else black.
        int xi = static_cast<int>(std::floor(fu * 8)), yi = static_cast<int>(std::floor(fv * 8));
        if (std::abs(fu * 8 - std::round(fu * 8)) < 1e-4 || std::abs(fv * 8 - std::round(fv * 8)) < 1e-4) continue;
        float4 m = lookup(hp, 1, u, v);
        bool magenta = ((xi + yi) & 1) == 0;
        CHECK(m.x == (magenta ? 1.0f : 0.0f));
        CHECK(m.y == 0.0f);
        CHECK(m.z == (magenta ? 1.0f : 0.0f));
        CHECK(m.w == 1.0f);
    }
}

TEST_CASE("texture: upload packs RGBA8 with R in the low byte and refuses bad input", "[unit][texture]") {
    Texture t;
    t.source = "px";
    t.width = t.height = 1;
    t.texels8 = {0x11, 0x22, 0x33, 0x44};
    TextureUpload up = upload_textures({&t});
    REQUIRE(up.texels8.size() == 1);
    CHECK(up.texels8[0] == 0x44332211u);
    CHECK(up.textures[0].levels == 1);

    Texture wrong = t;
    wrong.source = "short.png";
    wrong.texels8.pop_back();
    CHECK_THROWS_WITH(upload_textures({&wrong}), Catch::Contains("short.png") && Catch::Contains("texel values"));
    Texture empty;
    empty.source = "empty.png";
    CHECK_THROWS_WITH(upload_textures({&empty}), Catch::Contains("empty.png"));
    // Two 32768^2 textures (sizes only: the pool check comes before the texels are read):
    // 1.43e9 texels each with their mip levels, so the second passes 2^31 - 1.
    Texture big;
    big.width = big.height = limits::kMaxTextureSide;
    big.source = "big-a.png";
    Texture big2 = big;
    big2.source = "big-b.png";
    CHECK_THROWS_WITH(upload_textures({&big, &big2}), Catch::Contains("big-b.png") && Catch::Contains("2^31"));
    CHECK(upload_textures({}).bytes() == 0);
}

// ------------------------------------------------------------------------- loading ----------

TEST_CASE("texture: 8-bit PNGs load as codes, sRGB for colour, as stored for data", "[parser][texture]") {
    test::TempDir dir;
    const int w = 3, h = 2;
    const std::uint8_t rgb[w * h * 3] = {0, 1, 2, 50, 100, 150, 200, 250, 255, 7, 8, 9, 128, 64, 32, 255, 0, 17};
    fs::path p = dir.path / "rgb.png";
    write_oiio(p, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8), OIIO::TypeDesc::UINT8, rgb);
    std::vector<std::string> warnings;
    Texture c = load_texture(p, TextureUse::Colour, warnings);
    CHECK(warnings.empty());
    CHECK(c.source == p.string());
    CHECK(c.width == w);
    CHECK(c.height == h);
    CHECK(c.srgb);
    CHECK_FALSE(c.nearest);
    CHECK_FALSE(c.is_float());
    REQUIRE(c.texels8.size() == std::size_t(w * h * 4));
    for (int i = 0; i < w * h; ++i) {
        for (int k = 0; k < 3; ++k) CHECK(c.texels8[i * 4 + k] == rgb[i * 3 + k]);
        CHECK(c.texels8[i * 4 + 3] == 255);
    }
    Texture d = load_texture(p, TextureUse::Data, warnings);
    CHECK_FALSE(d.srgb);
    CHECK(d.texels8 == c.texels8);

    // Grey and grey + alpha: grey replicated to RGB.
    const std::uint8_t ga[4] = {10, 200, 30, 40};
    fs::path pg = dir.path / "grey.png", pga = dir.path / "grey_alpha.png";
    write_oiio(pg, OIIO::ImageSpec(2, 1, 1, OIIO::TypeDesc::UINT8), OIIO::TypeDesc::UINT8, ga);
    OIIO::ImageSpec sga(2, 1, 2, OIIO::TypeDesc::UINT8);
    sga.alpha_channel = 1;
    write_oiio(pga, sga, OIIO::TypeDesc::UINT8, ga);
    Texture g = load_texture(pg, TextureUse::Colour, warnings);
    CHECK(g.texels8 == std::vector<std::uint8_t>{10, 10, 10, 255, 200, 200, 200, 255});
    Texture gat = load_texture(pga, TextureUse::Data, warnings);
    CHECK(gat.texels8 == std::vector<std::uint8_t>{10, 10, 10, 200, 30, 30, 30, 40});

    // A PNG that says it is linear (gAMA 1.0) is not sRGB even for colour.
    OIIO::ImageSpec lin(w, h, 3, OIIO::TypeDesc::UINT8);
    lin.attribute("oiio:ColorSpace", "Linear");
    fs::path pl = dir.path / "linear.png";
    write_oiio(pl, lin, OIIO::TypeDesc::UINT8, rgb);
    Texture l = load_texture(pl, TextureUse::Colour, warnings);
    CHECK_FALSE(l.srgb);
    CHECK(l.texels8 == c.texels8);
    CHECK(warnings.empty());
}

TEST_CASE("texture: 16-bit PNGs load as float, colour decoded from sRGB", "[parser][texture]") {
    test::TempDir dir;
    const std::uint16_t codes[8] = {0, 1, 1000, 30000, 65535, 12345, 40000, 500};  // 2 x 1 RGBA
    OIIO::ImageSpec spec(2, 1, 4, OIIO::TypeDesc::UINT16);
    fs::path p = dir.path / "deep16.png";
    write_oiio(p, spec, OIIO::TypeDesc::UINT16, codes);
    std::vector<std::string> warnings;
    Texture c = load_texture(p, TextureUse::Colour, warnings);
    Texture d = load_texture(p, TextureUse::Data, warnings);
    CHECK(warnings.empty());
    REQUIRE(c.is_float());
    REQUIRE(d.is_float());
    CHECK(c.srgb);  // records the decode
    CHECK_FALSE(d.srgb);
    for (int i = 0; i < 8; ++i) {
        INFO("value " << i);
        double stored = codes[i] / 65535.0;
        bool alpha = i % 4 == 3;
        CHECK(c.texelsf[i] == Approx(alpha ? stored : srgb_decode(stored)).epsilon(1e-6).margin(1e-9));
        CHECK(d.texelsf[i] == Approx(stored).epsilon(1e-6).margin(1e-9));
    }
}

TEST_CASE("texture: EXR files load as linear float, NaN and infinity become 0 with a warning",
          "[parser][texture]") {
    test::TempDir dir;
    const float rgba[2 * 2 * 4] = {0.25f, 2.5f, -1.0f, 1.0f, 1000.0f, 0.0f, 1e-3f, 0.5f,
                                   3.0f,  4.0f, 5.0f,  0.0f, 0.125f,  7.0f, 8.0f,  1.0f};
    OIIO::ImageSpec spec(2, 2, 4, OIIO::TypeDesc::FLOAT);
    fs::path p = dir.path / "values.exr";
    write_oiio(p, spec, OIIO::TypeDesc::FLOAT, rgba);
    std::vector<std::string> warnings;
    for (TextureUse use : {TextureUse::Colour, TextureUse::Data}) {
        Texture t = load_texture(p, use, warnings);
        REQUIRE(t.is_float());
        CHECK_FALSE(t.srgb);
        CHECK(t.texelsf == std::vector<float>(rgba, rgba + 16));
    }
    // Half RGB (no alpha): values exact in half, alpha 1.
    const float rgb[2 * 3] = {0.5f, 2.0f, 0.25f, 1024.0f, 0.0f, 3.0f};
    fs::path ph = dir.path / "half.exr";
    write_oiio(ph, OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::HALF), OIIO::TypeDesc::FLOAT, rgb);
    Texture h = load_texture(ph, TextureUse::Colour, warnings);
    CHECK(h.texelsf == std::vector<float>{0.5f, 2.0f, 0.25f, 1.0f, 1024.0f, 0.0f, 3.0f, 1.0f});
    CHECK(warnings.empty());

    const float bad[2 * 2 * 3] = {1.0f, NAN, 2.0f, INFINITY, 3.0f, 4.0f, 5.0f, 6.0f, -INFINITY, 7.0f, 8.0f, 9.0f};
    fs::path pb = dir.path / "nan.exr";
    write_oiio(pb, OIIO::ImageSpec(2, 2, 3, OIIO::TypeDesc::FLOAT), OIIO::TypeDesc::FLOAT, bad);
    Texture b = load_texture(pb, TextureUse::Colour, warnings);
    CHECK(b.texelsf == std::vector<float>{1, 0, 2, 1, 0, 3, 4, 1, 5, 6, 0, 1, 7, 8, 9, 1});
    REQUIRE(warnings.size() == 1);
    CHECK(contains(warnings[0], pb.string()));
    CHECK(contains(warnings[0], " 3 non-finite"));
}

TEST_CASE("texture: of several subimages the first is loaded", "[parser][texture]") {
    test::TempDir dir;
    fs::path p = dir.path / "pages.tif";
    auto out = OIIO::ImageOutput::create(p.string());
    REQUIRE(out);
    REQUIRE(out->supports("multiimage"));
    OIIO::ImageSpec specs[2] = {OIIO::ImageSpec(2, 1, 3, OIIO::TypeDesc::FLOAT),
                                OIIO::ImageSpec(3, 3, 3, OIIO::TypeDesc::FLOAT)};
    const std::vector<float> a(2 * 3, 1.5f), b(9 * 3, 2.5f);
    bool opened = out->open(p.string(), 2, specs);
    INFO(out->geterror());
    REQUIRE(opened);
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, a.data()));
    REQUIRE(out->open(p.string(), specs[1], OIIO::ImageOutput::AppendSubimage));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, b.data()));
    REQUIRE(out->close());
    std::vector<std::string> warnings;
    Texture t = load_texture(p, TextureUse::Colour, warnings);
    CHECK(t.width == 2);
    CHECK(t.height == 1);
    CHECK(t.texelsf == std::vector<float>{1.5f, 1.5f, 1.5f, 1.0f, 1.5f, 1.5f, 1.5f, 1.0f});
}

TEST_CASE("texture: missing, undecodable and oversized files are refused by name", "[parser][texture]") {
    test::TempDir dir;
    std::vector<std::string> warnings;
    fs::path missing = dir.path / "nope.png";
    CHECK_THROWS_WITH(load_texture(missing, TextureUse::Colour, warnings),
                      Catch::Contains(missing.string()) && Catch::Contains("no such file"));
    CHECK_THROWS_WITH(load_texture(dir.path, TextureUse::Colour, warnings), Catch::Contains("folder"));
    fs::path garbage = dir.write("garbage.png", "this is not a PNG file at all, just words");
    CHECK_THROWS_WITH(load_texture(garbage, TextureUse::Colour, warnings), Catch::Contains(garbage.string()));
    CHECK_THROWS_AS(load_texture(garbage, TextureUse::Colour, warnings), Error);

    // Headers claiming 40000^2 (a side over the limit) and 30000^2 (9e8 texels): refused
    // from the header, at once (decoding would need gigabytes).
    fs::path huge = dir.write("huge.png", png_claiming(dir, 40000, 40000));
    fs::path many = dir.write("many.png", png_claiming(dir, 30000, 30000));
    {
        std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::open(huge.string());
        REQUIRE(in);  // the patched file is a valid header: OIIO reads it as 40000 x 40000
        CHECK(in->spec().width == 40000);
    }
    auto start = std::chrono::steady_clock::now();
    CHECK_THROWS_WITH(load_texture(huge, TextureUse::Colour, warnings),
                      Catch::Contains(huge.string()) && Catch::Contains("40000x40000"));
    CHECK_THROWS_WITH(load_texture(many, TextureUse::Data, warnings),
                      Catch::Contains(many.string()) && Catch::Contains("900000000 texels"));
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    CHECK(seconds < 1.0);
    CHECK(warnings.empty());
}

TEST_CASE("texture: a bad file becomes a magenta placeholder with one warning", "[parser][texture]") {
    test::TempDir dir;
    Scene scene;
    fs::path missing = dir.path / "gone.png";
    int a = add_texture_file(scene, missing, TextureUse::Colour);
    REQUIRE(a >= 0);
    REQUIRE(scene.textures.size() == 1);
    REQUIRE(scene.warnings.size() == 1);
    CHECK(scene.warnings[0] == missing.string() + ": texture not loaded (no such file); using a magenta placeholder");
    const Texture& ph = scene.textures[a];
    CHECK(ph.nearest);
    CHECK(ph.width == 8);
    CHECK(ph.texels8[0] == 255);  // texel (0, 0) magenta
    CHECK(ph.texels8[1] == 0);
    CHECK(ph.texels8[2] == 255);
    CHECK(ph.texels8[4] == 0);    // texel (1, 0) black
    // Asked again (for any use): the same placeholder, no second warning.
    CHECK(add_texture_file(scene, missing, TextureUse::Data) == a);
    CHECK(scene.warnings.size() == 1);

    fs::path garbage = dir.write("junk.png", std::string(100, '\x42'));
    int b = add_texture_file(scene, garbage, TextureUse::Colour);
    CHECK(b != a);
    REQUIRE(scene.warnings.size() == 2);
    CHECK(contains(scene.warnings[1], garbage.string() + ": texture not loaded ("));
    CHECK(contains(scene.warnings[1], "); using a magenta placeholder"));
    CHECK(scene.textures[b].nearest);

    fs::path huge = dir.write("huge.png", png_claiming(dir, 40000, 40000));
    int c = add_texture_file(scene, huge, TextureUse::Colour);
    REQUIRE(scene.warnings.size() == 3);
    CHECK(contains(scene.warnings[2], "40000x40000"));
    CHECK(scene.textures[c].width == 8);
}

TEST_CASE("texture: add_texture_file loads each file once per use", "[parser][texture]") {
    test::TempDir dir;
    const std::uint8_t rgb[3] = {100, 150, 200};
    fs::path png = dir.path / "c.png", exr = dir.path / "c.exr", png16 = dir.path / "c16.png";
    write_oiio(png, OIIO::ImageSpec(1, 1, 3, OIIO::TypeDesc::UINT8), OIIO::TypeDesc::UINT8, rgb);
    const float f[3] = {0.5f, 1.5f, 2.5f};
    write_oiio(exr, OIIO::ImageSpec(1, 1, 3, OIIO::TypeDesc::FLOAT), OIIO::TypeDesc::FLOAT, f);
    const std::uint16_t c16[3] = {1000, 20000, 60000};
    write_oiio(png16, OIIO::ImageSpec(1, 1, 3, OIIO::TypeDesc::UINT16), OIIO::TypeDesc::UINT16, c16);
    Scene scene;
    int pc = add_texture_file(scene, png, TextureUse::Colour);
    CHECK(add_texture_file(scene, png, TextureUse::Colour) == pc);
    int pd = add_texture_file(scene, png, TextureUse::Data);
    CHECK(pd != pc);
    CHECK(add_texture_file(scene, png, TextureUse::Data) == pd);
    CHECK(scene.textures[pc].srgb);
    CHECK_FALSE(scene.textures[pd].srgb);
    // Float files are the same for both uses.
    int ec = add_texture_file(scene, exr, TextureUse::Colour);
    CHECK(add_texture_file(scene, exr, TextureUse::Data) == ec);
    // 16-bit: colour is decoded, data is not.
    int hc = add_texture_file(scene, png16, TextureUse::Colour);
    int hd = add_texture_file(scene, png16, TextureUse::Data);
    CHECK(hc != hd);
    CHECK(add_texture_file(scene, png16, TextureUse::Colour) == hc);
    CHECK(add_texture_file(scene, png16, TextureUse::Data) == hd);
    CHECK(scene.textures[hd].texelsf[0] == Approx(1000 / 65535.0));
    CHECK(scene.textures[hc].texelsf[0] == Approx(srgb_decode(1000 / 65535.0)));
    CHECK(scene.textures.size() == 5);
    CHECK(scene.warnings.empty());
}

TEST_CASE("texture: images in memory load like files, whatever their name", "[parser][texture]") {
    test::TempDir dir;
    const std::uint8_t rgba[2 * 2 * 4] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
    OIIO::ImageSpec spec(2, 2, 4, OIIO::TypeDesc::UINT8);
    spec.alpha_channel = 3;
    fs::path p = dir.path / "a.png";
    write_oiio(p, spec, OIIO::TypeDesc::UINT8, rgba);
    const std::string bytes = read_bytes(p);
    std::vector<std::string> warnings;
    Texture file = load_texture(p, TextureUse::Colour, warnings);
    for (const char* name : {"scene.gltf#image0.png", "image0", "mislabelled.jpg"}) {
        INFO(name);
        Texture t = load_texture_from_memory(bytes, name, TextureUse::Colour, warnings);
        CHECK(t.source == name);
        CHECK(t.width == 2);
        CHECK(t.srgb);
        CHECK(t.texels8 == file.texels8);
        CHECK(t.texels8 == std::vector<std::uint8_t>(rgba, rgba + 16));
    }
    const float f[3] = {0.5f, 1.5f, 2.5f};
    fs::path exr = dir.path / "m.exr";
    write_oiio(exr, OIIO::ImageSpec(1, 1, 3, OIIO::TypeDesc::FLOAT), OIIO::TypeDesc::FLOAT, f);
    Texture e = load_texture_from_memory(read_bytes(exr), "embedded.exr", TextureUse::Data, warnings);
    CHECK(e.texelsf == std::vector<float>{0.5f, 1.5f, 2.5f, 1.0f});
    CHECK(warnings.empty());
    CHECK_THROWS_WITH(load_texture_from_memory("not an image", "bad.png", TextureUse::Colour, warnings),
                      Catch::Contains("bad.png"));
    CHECK_THROWS_WITH(load_texture_from_memory("", "empty.png", TextureUse::Colour, warnings),
                      Catch::Contains("empty.png"));
    CHECK_THROWS_WITH(load_texture_from_memory(png_claiming(dir, 40000, 40000), "huge.png", TextureUse::Colour, warnings),
                      Catch::Contains("huge.png") && Catch::Contains("40000x40000"));
}

// ------------------------------------------------------------------------ OpenCL C ----------

TEST_CASE("texture: the OpenCL lookups agree with the host's", "[kernel][texture]") {
    // The shared header built as OpenCL C with a probe kernel, against the same header as
    // host C++: bit for bit for wp_texture_lookup; wp_texture_view within float rounding
    // (log2 may differ by an ulp between libraries).
    test::Rng rng(23);
    Texture f = float_texture(13, 6, [&](int, int) {
        return std::array<float, 4>{rng.uniform(0.0f, 3.0f), rng.uniform(), rng.uniform(), rng.uniform()};
    });
    Texture s, l;
    for (Texture* t : {&s, &l}) {
        t->width = 9;
        t->height = 16;
        for (int i = 0; i < 9 * 16 * 4; ++i) t->texels8.push_back(static_cast<std::uint8_t>(rng.next() & 255));
    }
    s.srgb = true;
    Texture cb = checkerboard_texture(glm::vec3(0.1f), glm::vec3(0.7f, 0.2f, 0.4f), "cb");
    HostPool hp;
    hp.up = upload_textures({&f, &s, &l, &cb});
    for (int t = 0; t < 4; ++t) hp.views.push_back(view_of(t, 1.5f, 0.5f * t, 0.1f, -0.3f, 2.0f, 0.7f));
    const int n = 4096;
    std::vector<float4> queries(n);
    std::vector<int> which(n);
    for (int i = 0; i < n; ++i) {
        queries[i] = make_float4(rng.uniform(-3.0f, 3.0f), rng.uniform(-3.0f, 3.0f), rng.uniform(-1.0f, 6.0f),
                                 rng.uniform(-8.0f, 1.0f));
        which[i] = i % 4;
    }
    queries[0].x = NAN;
    queries[1].y = INFINITY;
    queries[2].z = NAN;
    queries[3].w = -FLT_MAX;

    auto& dev = test::device();
    const std::string probe = R"(
__kernel void probe_texture(__global const TextureData* textures, __global const TextureView* views,
                            __global const uint* texels8, __global const float4* texelsf,
                            __global const float4* queries, __global const int* which, int n,
                            __global float4* out) {
    int i = get_global_id(0);
    if (i >= n) return;
    TexturePool p;
    p.textures = textures;
    p.views = views;
    p.texels8 = texels8;
    p.texelsf = texelsf;
    float4 q = queries[i];
    out[2 * i] = wp_texture_lookup(p, which[i], (float2)(q.x, q.y), q.z);
    out[2 * i + 1] = wp_texture_view(p, which[i], (float2)(q.x, q.y), q.w);
}
)";
    ocl::Program prog;
    prog.file = "test_texture (inline)";
    prog.program = ::cl::Program(dev.context, ocl::assemble_source("shared/texture.h") + probe);
    try {
        prog.program.build({dev.info.device}, "-cl-std=CL1.2");
    } catch (const ::cl::Error&) {
        FAIL(prog.program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(dev.info.device));
    }
    auto buf = [&](const auto& v) { return ocl::upload_buffer(dev, v, "texture test"); };
    ::cl::Buffer bt = buf(hp.up.textures), bv = buf(hp.views), b8 = buf(hp.up.texels8), bf = buf(hp.up.texelsf),
                 bq = buf(queries), bw = buf(which);
    ::cl::Buffer bo(dev.context, CL_MEM_WRITE_ONLY, sizeof(float4) * 2 * n);
    ocl::Kernel(prog, "probe_texture").launch({&dev.queue}, n, bt, bv, b8, bf, bq, bw, n, bo);
    std::vector<float4> out(2 * n);
    dev.queue.enqueueReadBuffer(bo, CL_TRUE, 0, sizeof(float4) * out.size(), out.data());

    int mismatches = 0;
    for (int i = 0; i < n; ++i) {
        const float4 q = queries[i];
        float4 h = wp_texture_lookup(hp.pool(), which[i], make_float2(q.x, q.y), q.z);
        float4 hv = wp_texture_view(hp.pool(), which[i], make_float2(q.x, q.y), q.w);
        const float4 d = out[2 * i], dv = out[2 * i + 1];
        const float hl[4] = {h.x, h.y, h.z, h.w}, dl[4] = {d.x, d.y, d.z, d.w};
        const float hvl[4] = {hv.x, hv.y, hv.z, hv.w}, dvl[4] = {dv.x, dv.y, dv.z, dv.w};
        for (int c = 0; c < 4; ++c) {
            if (std::memcmp(&hl[c], &dl[c], 4) != 0 && mismatches++ < 10)
                FAIL_CHECK("lookup " << i << " lane " << c << ": device " << dl[c] << ", host " << hl[c]);
            if (!(std::abs(hvl[c] - dvl[c]) <= 1e-5f * std::max(1.0f, std::abs(hvl[c]))) && mismatches++ < 10)
                FAIL_CHECK("view " << i << " lane " << c << ": device " << dvl[c] << ", host " << hvl[c]);
        }
    }
    CHECK(mismatches == 0);
}
