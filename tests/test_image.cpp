// test_image.cpp — image files (EXR, PNG, JPEG), the sRGB transfer function, atomic writes,
// error metrics and downsampling. Expected values are computed by hand in the comments.
#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "image/image.h"
#include "util/error.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

namespace {

using wp::test::TempDir;

// A fresh folder under the system temporary folder, removed with everything in it.
std::string file_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

// Reads an 8-bit file's codes straight through OpenImageIO, without read_image.
std::vector<std::uint8_t> raw_codes(const fs::path& p, int& channels) {
    auto in = OIIO::ImageInput::open(p.string());
    REQUIRE(in);
    const OIIO::ImageSpec spec = in->spec();
    channels = spec.nchannels;
    std::vector<std::uint8_t> codes(static_cast<std::size_t>(spec.width) * spec.height *
                                    channels);
    REQUIRE(in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, codes.data()));
    in->close();
    return codes;
}

// Writes a float image with any channel count straight through OpenImageIO.
void write_raw_exr(const fs::path& p, int w, int h, int channels, const std::vector<float>& d) {
    auto out = OIIO::ImageOutput::create(p.string());
    REQUIRE(out);
    OIIO::ImageSpec spec(w, h, channels, OIIO::TypeDesc::FLOAT);
    REQUIRE(out->open(p.string(), spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, d.data()));
    REQUIRE(out->close());
}

}  // namespace

TEST_CASE("supported image extensions", "[unit][image-io]") {
    CHECK(wp::is_supported_image_path("a.exr"));
    CHECK(wp::is_supported_image_path("dir/b.png"));
    CHECK(wp::is_supported_image_path("c.jpg"));
    CHECK(wp::is_supported_image_path("d.jpeg"));
    CHECK(wp::is_supported_image_path("E.EXR"));
    CHECK_FALSE(wp::is_supported_image_path("f.tif"));
    CHECK_FALSE(wp::is_supported_image_path("g"));
    CHECK_FALSE(wp::is_supported_image_path("h.exr.txt"));
}

TEST_CASE("EXR round trip is bit-identical", "[unit][image-io]") {
    TempDir dir;
    wp::Image img(3, 2);
    const std::vector<float> values = {
        0.0f, 1.0f, 0.5f,  0.1f, 0.2f, 0.3f,                   // ordinary values
        1e-30f, 1e-40f /* denormal */, 3.0e-8f,                // tiny values
        1.5f, 1000.25f, 65504.0f,                              // above 1, half's maximum
        1e20f, -2.5f, std::numeric_limits<float>::max(),       // beyond half, negative
        0.333333343f, 16777217.0f /* rounds to 2^24 */, 7.0f};
    img.rgb = values;
    fs::path p = dir.path / "round.exr";
    wp::write_image(p, img);
    CHECK(dir.entries() == std::vector<std::string>{"round.exr"});

    wp::Image back = wp::read_image(p);
    REQUIRE(back.width == 3);
    REQUIRE(back.height == 2);
    REQUIRE(back.rgb.size() == values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
        INFO("float " << i << ": wrote " << values[i] << ", read " << back.rgb[i]);
        CHECK(bits(back.rgb[i]) == bits(values[i]));
    }
    // Pixel layout: row-major from the top-left.
    CHECK(back.pixel(2, 1)[1] == 16777216.0f);
    CHECK(back.pixel(1, 0)[0] == 0.1f);

    // The file stores 32-bit float channels, not half.
    auto in = OIIO::ImageInput::open(p.string());
    REQUIRE(in);
    CHECK(in->spec().format == OIIO::TypeDesc::FLOAT);
    CHECK(in->spec().nchannels == 3);
}

TEST_CASE("sRGB transfer function", "[unit][image-io]") {
    // Hand values: 1.055 * 0.5^(1/2.4) - 0.055 = 0.7353569830...
    CHECK(wp::srgb_encode(0.0) == 0.0);
    CHECK(wp::srgb_encode(1.0) == Approx(1.0).margin(1e-12));
    CHECK(wp::srgb_encode(0.5) == Approx(0.7353569830524495).epsilon(1e-12));
    CHECK(wp::srgb_encode(0.001) == Approx(0.01292).epsilon(1e-12));  // linear segment
    // Both sides of the boundary meet at 0.04045 (to 3e-8).
    CHECK(wp::srgb_encode(0.0031307999) == Approx(0.04045).margin(1e-7));
    CHECK(wp::srgb_encode(0.0031308) == Approx(0.04045).margin(1e-7));
    CHECK(wp::srgb_decode(0.0) == 0.0);
    CHECK(wp::srgb_decode(1.0) == 1.0);
    CHECK(wp::srgb_decode(0.7353569830524495) == Approx(0.5).epsilon(1e-12));
    CHECK(wp::srgb_decode(0.01292) == Approx(0.001).epsilon(1e-12));
    for (double x : {0.0, 1e-4, 0.003, 0.0032, 0.01, 0.18, 0.5, 0.9, 1.0})
        CHECK(wp::srgb_decode(wp::srgb_encode(x)) == Approx(x).epsilon(1e-12).margin(1e-15));
}

TEST_CASE("PNG stores rounded 8-bit sRGB codes", "[unit][image-io]") {
    TempDir dir;
    // Codes by hand: round(255 * encode(x)) with encode(0.5) = 0.735357 → 187.516 → 188,
    // encode(0.18) = 0.461356 → 117.646 → 118, encode(0.0031308) = 0.0404499 → 10.315 → 10,
    // encode(0.001) = 0.01292 → 3.295 → 3. Out of range clamps; NaN gives 0.
    wp::Image img(4, 2);
    img.rgb = {0.0f, 1.0f, 0.5f,                       // (0,0)
               0.0031308f, 0.18f, 0.001f,              // (1,0)
               2.0f, -1.0f, 1e30f,                     // (2,0) clamped
               std::numeric_limits<float>::quiet_NaN(), 0.9999999f, 0.0031307f,  // (3,0)
               0.25f, 0.75f, 1.0f / 3.0f,              // (0,1)
               0.0f, 0.0f, 0.0f,   1.0f, 1.0f, 1.0f,   0.5f, 0.5f, 0.5f};
    // encode(0.25) = 0.537099 → 136.96 → 137; encode(0.75) = 0.880825 → 224.61 → 225;
    // encode(1/3) = 0.612501 → 156.19 → 156.
    const std::vector<int> expected = {0,   255, 188, 10, 118, 3,   255, 0,   255, 0,   255, 10,
                                       137, 225, 156, 0,  0,   0,   255, 255, 255, 188, 188, 188};
    fs::path p = dir.path / "codes.png";
    wp::write_image(p, img);
    CHECK(dir.entries() == std::vector<std::string>{"codes.png"});

    int channels = 0;
    std::vector<std::uint8_t> codes = raw_codes(p, channels);
    REQUIRE(channels == 3);
    REQUIRE(codes.size() == expected.size());
    for (std::size_t i = 0; i < codes.size(); ++i) {
        INFO("channel " << i);
        CHECK(int(codes[i]) == expected[i]);
    }

    // read_image decodes the codes back to linear.
    wp::Image back = wp::read_image(p);
    REQUIRE(back.width == 4);
    REQUIRE(back.height == 2);
    CHECK(back.rgb[0] == 0.0f);
    CHECK(back.rgb[1] == 1.0f);
    // Code 188 is 0.737255 encoded: ((0.737255 + 0.055) / 1.055)^2.4 = 0.502886.
    CHECK(back.rgb[2] == Approx(0.502886).epsilon(1e-5));
    for (std::size_t i = 0; i < codes.size(); ++i)
        CHECK(back.rgb[i] == static_cast<float>(wp::srgb_decode(expected[i] / 255.0)));
}

TEST_CASE("JPEG round trip is close", "[unit][image-io]") {
    TempDir dir;
    wp::Image img(16, 16);
    for (std::size_t i = 0; i < img.rgb.size(); i += 3) {
        img.rgb[i] = 0.5f;
        img.rgb[i + 1] = 0.18f;
        img.rgb[i + 2] = 1.0f;
    }
    for (const char* name : {"flat.jpg", "flat.jpeg"}) {
        wp::write_image(dir.path / name, img);
        wp::Image back = wp::read_image(dir.path / name);
        REQUIRE(back.width == 16);
        REQUIRE(back.height == 16);
        // A flat colour survives JPEG to within a couple of codes (~0.01 linear here).
        CHECK(back.pixel(7, 7)[0] == Approx(0.5).margin(0.01));
        CHECK(back.pixel(7, 7)[1] == Approx(0.18).margin(0.01));
        CHECK(back.pixel(7, 7)[2] == Approx(1.0).margin(0.01));
    }
}

TEST_CASE("failed writes leave nothing behind", "[unit][image-io]") {
    TempDir dir;
    wp::Image img(2, 2);

    SECTION("unknown extension") {
        fs::path p = dir.path / "out.tif";
        REQUIRE_THROWS_AS(wp::write_image(p, img), wp::Error);
        REQUIRE_THROWS_WITH(wp::write_image(p, img),
                            Contains("out.tif") && Contains(".exr") && Contains(".png") &&
                                Contains(".jpg"));
        CHECK(dir.entries().empty());
    }
    SECTION("missing folder") {
        fs::path p = dir.path / "missing" / "out.png";
        REQUIRE_THROWS_AS(wp::write_image(p, img), wp::Error);
        REQUIRE_THROWS_WITH(wp::write_image(p, img), Contains("out.png") && Contains("missing"));
        CHECK(dir.entries().empty());
    }
    SECTION("pixel buffer does not match the size") {
        img.rgb.resize(5);
        fs::path p = dir.path / "out.exr";
        REQUIRE_THROWS_AS(wp::write_image(p, img), wp::Error);
        REQUIRE_THROWS_WITH(wp::write_image(p, img), Contains("out.exr"));
        CHECK(dir.entries().empty());
    }
    SECTION("the destination is a folder: the finished temporary is removed") {
        fs::create_directory(dir.path / "taken.png");
        REQUIRE_THROWS_AS(wp::write_image(dir.path / "taken.png", img), wp::Error);
        CHECK(dir.entries() == std::vector<std::string>{"taken.png"});
        CHECK(fs::is_directory(dir.path / "taken.png"));
    }
}

TEST_CASE("a failing write keeps the existing file intact", "[unit][image-io]") {
    TempDir dir;
    wp::Image old_img(2, 1);
    old_img.rgb = {0.25f, 0.5f, 0.75f, 1.0f, 0.0f, 0.125f};

    SECTION("the writer fails (PNG wider than libpng allows)") {
        fs::path p = dir.path / "keep.png";
        wp::write_image(p, old_img);
        const std::string before = file_bytes(p);
        REQUIRE_FALSE(before.empty());
        // libpng refuses widths over 1,000,000 once the temporary file exists.
        wp::Image wide(1000001, 1);
        REQUIRE_THROWS_AS(wp::write_image(p, wide), wp::Error);
        REQUIRE_THROWS_WITH(wp::write_image(p, wide), Contains("keep.png"));
        CHECK(file_bytes(p) == before);
        CHECK(dir.entries() == std::vector<std::string>{"keep.png"});
    }
    SECTION("JPEG larger than libjpeg allows is an error, not an exit") {
        fs::path p = dir.path / "keep.jpg";
        wp::write_image(p, old_img);
        const std::string before = file_bytes(p);
        wp::Image tall(1, 65501);
        REQUIRE_THROWS_AS(wp::write_image(p, tall), wp::Error);
        REQUIRE_THROWS_WITH(wp::write_image(p, tall), Contains("keep.jpg") && Contains("65500"));
        CHECK(file_bytes(p) == before);
        CHECK(dir.entries() == std::vector<std::string>{"keep.jpg"});
    }
    SECTION("the image is invalid") {
        fs::path p = dir.path / "keep.exr";
        wp::write_image(p, old_img);
        const std::string before = file_bytes(p);
        wp::Image bad(2, 2);
        bad.rgb.resize(3);
        REQUIRE_THROWS_AS(wp::write_image(p, bad), wp::Error);
        CHECK(file_bytes(p) == before);
        CHECK(dir.entries() == std::vector<std::string>{"keep.exr"});
        wp::Image back = wp::read_image(p);
        CHECK(back.rgb == old_img.rgb);
    }
    SECTION("a successful write replaces the file") {
        fs::path p = dir.path / "replace.exr";
        wp::write_image(p, old_img);
        wp::Image new_img(1, 1);
        new_img.rgb = {3.0f, 2.0f, 1.0f};
        wp::write_image(p, new_img);
        CHECK(dir.entries() == std::vector<std::string>{"replace.exr"});
        CHECK(wp::read_image(p).rgb == new_img.rgb);
    }
}

TEST_CASE("read_image errors name the file", "[unit][image-io]") {
    TempDir dir;
    fs::path missing = dir.path / "nothing-here.exr";
    REQUIRE_THROWS_AS(wp::read_image(missing), wp::Error);
    REQUIRE_THROWS_WITH(wp::read_image(missing), Contains("nothing-here.exr"));

    fs::path junk = dir.path / "junk.png";
    std::ofstream(junk) << "this is not a PNG file";
    REQUIRE_THROWS_AS(wp::read_image(junk), wp::Error);
    REQUIRE_THROWS_WITH(wp::read_image(junk), Contains("junk.png"));

    REQUIRE_THROWS_AS(wp::read_image(dir.path), wp::Error);
}

TEST_CASE("read_image replicates grey and drops alpha", "[unit][image-io]") {
    TempDir dir;
    SECTION("one channel") {
        fs::path p = dir.path / "grey.exr";
        write_raw_exr(p, 2, 1, 1, {0.25f, 4.0f});
        wp::Image img = wp::read_image(p);
        REQUIRE(img.width == 2);
        CHECK(img.rgb == std::vector<float>{0.25f, 0.25f, 0.25f, 4.0f, 4.0f, 4.0f});
    }
    SECTION("grey and alpha") {
        fs::path p = dir.path / "greya.exr";
        write_raw_exr(p, 1, 1, 2, {0.5f, 0.125f});
        CHECK(wp::read_image(p).rgb == std::vector<float>{0.5f, 0.5f, 0.5f});
    }
    SECTION("RGBA") {
        fs::path p = dir.path / "rgba.exr";
        write_raw_exr(p, 2, 1, 4, {1.0f, 2.0f, 3.0f, 0.5f, 4.0f, 5.0f, 6.0f, 0.25f});
        CHECK(wp::read_image(p).rgb == std::vector<float>{1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f});
    }
}

TEST_CASE("write_exr_layers stores named RGB layers", "[unit][image-io]") {
    TempDir dir;
    const std::vector<float> beauty = {1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f};
    const std::vector<float> albedo = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};
    fs::path p = dir.path / "layers.exr";
    wp::write_exr_layers(p, 2, 1, {{"", beauty.data()}, {"albedo", albedo.data()}});
    CHECK(dir.entries() == std::vector<std::string>{"layers.exr"});

    auto in = OIIO::ImageInput::open(p.string());
    REQUIRE(in);
    const OIIO::ImageSpec spec = in->spec();
    REQUIRE(spec.nchannels == 6);
    std::vector<float> data(12);
    REQUIRE(in->read_image(0, 0, 0, 6, OIIO::TypeDesc::FLOAT, data.data()));
    // Look each channel up by name: the reader may order them its own way.
    auto value = [&](const std::string& name, int pixel) {
        int c = spec.channelindex(name);
        REQUIRE(c >= 0);
        return data[static_cast<std::size_t>(pixel) * 6 + c];
    };
    CHECK(value("R", 0) == 1.0f);
    CHECK(value("B", 1) == 6.0f);
    CHECK(value("albedo.R", 0) == 0.1f);
    CHECK(value("albedo.G", 1) == 0.5f);
    CHECK(value("albedo.B", 1) == 0.6f);

    // The unnamed layer is what read_image returns.
    CHECK(wp::read_image(p).rgb == beauty);

    REQUIRE_THROWS_AS(wp::write_exr_layers(dir.path / "layers.png", 2, 1,
                                           {{"", beauty.data()}}),
                      wp::Error);
    CHECK(dir.entries() == std::vector<std::string>{"layers.exr"});
}

TEST_CASE("compare_images on hand-made 2x2 images", "[unit][image-io]") {
    wp::Image r(2, 2), x(2, 2);
    // Reference pixels (row-major): (0,0) black, (1,0) white, (0,1) grey 0.5, (1,1) black.
    r.rgb = {0, 0, 0, 1, 1, 1, 0.5f, 0.5f, 0.5f, 0, 0, 0};
    x.rgb = r.rgb;

    SECTION("identical images") {
        wp::ErrorMetrics m = wp::compare_images(x, r);
        CHECK(m.rmse == 0.0);
        CHECK(m.relmse == 0.0);
        CHECK(m.mae == 0.0);
        CHECK(m.max_abs == 0.0);
    }
    SECTION("three differing channels") {
        x.pixel(1, 0)[1] = 1.5f;    // d = 0.5 where r = 1
        x.pixel(0, 1)[2] = 0.25f;   // d = -0.25 where r = 0.5
        x.pixel(1, 1)[0] = 0.125f;  // d = 0.125 where r = 0
        // 12 values. Squared: 0.25 + 0.0625 + 0.015625 = 0.328125.
        // relMSE terms: 0.25 / 1.01 + 0.0625 / 0.26 + 0.015625 / 0.01.
        wp::ErrorMetrics m = wp::compare_images(x, r);
        CHECK(m.rmse == Approx(std::sqrt(0.328125 / 12.0)).epsilon(1e-12));
        CHECK(m.rmse == Approx(0.1653594569).epsilon(1e-9));
        CHECK(m.relmse == Approx((0.25 / 1.01 + 0.0625 / 0.26 + 1.5625) / 12.0).epsilon(1e-12));
        CHECK(m.relmse == Approx(0.1708674473).epsilon(1e-9));
        CHECK(m.mae == Approx(0.875 / 12.0).epsilon(1e-12));
        CHECK(m.max_abs == 0.5);
        CHECK(m.max_x == 1);
        CHECK(m.max_y == 0);

        // Another eps: 0.25 / 2 + 0.0625 / 1.25 + 0.015625 / 1.
        wp::ErrorMetrics m1 = wp::compare_images(x, r, 1.0);
        CHECK(m1.relmse == Approx((0.125 + 0.05 + 0.015625) / 12.0).epsilon(1e-12));
    }
    SECTION("the largest difference in the bottom row") {
        x.pixel(0, 1)[0] = -1.5f;  // d = -2 at (0, 1)
        x.pixel(1, 0)[2] = 2.0f;   // d = 1 at (1, 0)
        wp::ErrorMetrics m = wp::compare_images(x, r);
        CHECK(m.max_abs == 2.0);
        CHECK(m.max_x == 0);
        CHECK(m.max_y == 1);
        CHECK(m.mae == Approx(3.0 / 12.0).epsilon(1e-12));
        CHECK(m.rmse == Approx(std::sqrt(5.0 / 12.0)).epsilon(1e-12));
    }
}

TEST_CASE("compare_images rejects different sizes", "[unit][image-io]") {
    wp::Image a(2, 2), b(3, 2);
    REQUIRE_THROWS_AS(wp::compare_images(a, b), wp::Error);
    REQUIRE_THROWS_WITH(wp::compare_images(a, b), Contains("2x2") && Contains("3x2"));
    REQUIRE_THROWS_AS(wp::compare_images(wp::Image(2, 3), a), wp::Error);
}

TEST_CASE("downsample_box averages blocks", "[unit][image-io]") {
    wp::Image img(4, 2);
    // Red channel 0..7 row-major, green = 10 * red, blue = 1.
    for (int i = 0; i < 8; ++i) {
        img.rgb[i * 3] = float(i);
        img.rgb[i * 3 + 1] = 10.0f * float(i);
        img.rgb[i * 3 + 2] = 1.0f;
    }
    wp::Image half = wp::downsample_box(img, 2);
    REQUIRE(half.width == 2);
    REQUIRE(half.height == 1);
    // Left block: red 0, 1, 4, 5 → 2.5; right block: 2, 3, 6, 7 → 4.5.
    CHECK(half.rgb == std::vector<float>{2.5f, 25.0f, 1.0f, 4.5f, 45.0f, 1.0f});

    CHECK(wp::downsample_box(img, 1).rgb == img.rgb);
    REQUIRE_THROWS_AS(wp::downsample_box(img, 3), wp::Error);
    REQUIRE_THROWS_WITH(wp::downsample_box(img, 3), Contains("4x2"));
    REQUIRE_THROWS_AS(wp::downsample_box(img, 0), wp::Error);

    wp::Image big(256, 256);
    for (float& v : big.rgb) v = 0.75f;
    wp::Image small = wp::downsample_box(big, 2);
    CHECK(small.width == 128);
    CHECK(small.height == 128);
    CHECK(small.pixel(127, 127)[2] == 0.75f);
}
