// image.h — images on the host: OpenImageIO files and error metrics.
//
// Image holds linear RGB float pixels, row-major from the top-left, 3 floats per pixel.
// Files: .exr is written as linear float RGB; .png (and .jpg) as 8-bit sRGB after clamping
// to [0, 1] (no tone curve besides the sRGB transfer function). Writing is atomic: a
// failed write leaves no file behind and an existing file untouched. Reading returns linear
// values: 8-bit sRGB files (PNG, JPEG) are decoded with the exact sRGB transfer function.
// Also here: the sRGB transfer function itself and a box filter for downsampling renders.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace wp {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // width * height * 3, linear

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0.0f) {}
    float* pixel(int x, int y) { return &rgb[(static_cast<std::size_t>(y) * width + x) * 3]; }
    const float* pixel(int x, int y) const {
        return &rgb[(static_cast<std::size_t>(y) * width + x) * 3];
    }
};

// Metadata stored in the file's header (EXR attributes; PNG/JPEG text where the format
// keeps it): name and value, an integer when `integer` is set (e.g. "wavepath:spp").
struct ImageAttribute {
    std::string name;
    std::string value;
    bool integer = false;
};

// Throws wp::Error naming the path when the extension is unknown, the folder is missing
// or not writable, or the writer fails.
void write_image(const std::filesystem::path& path, const Image& image,
                 const std::vector<ImageAttribute>& attributes = {});

// The header attribute `name` of an image file as text, or nothing when the file has none.
// Throws wp::Error naming a missing or unreadable file.
std::optional<std::string> read_image_attribute(const std::filesystem::path& path,
                                                const std::string& name);

// True when write_image supports the extension of `path` (.exr, .png, .jpg, .jpeg).
bool is_supported_image_path(const std::filesystem::path& path);

// Reads any format OpenImageIO reads; returns the first three channels (grey is
// replicated, alpha dropped) as linear float: EXR values as stored, files OpenImageIO tags
// as sRGB (PNG, JPEG) decoded with srgb_decode. Throws wp::Error naming a missing or
// unreadable file.
Image read_image(const std::filesystem::path& path);

struct ErrorMetrics {
    double rmse = 0.0;    // sqrt(mean over pixels and channels of (x - r)^2)
    double relmse = 0.0;  // mean over pixels and channels of (x - r)^2 / (r^2 + eps), eps = 1e-2
    double mae = 0.0;     // mean over pixels and channels of |x - r|
    double max_abs = 0.0; // largest |x - r| over pixels and channels
    int max_x = 0, max_y = 0;  // where max_abs is
};

// Compares image x with reference r; throws wp::Error when sizes differ.
ErrorMetrics compare_images(const Image& x, const Image& r, double relmse_eps = 1e-2);

// Writes a multi-layer linear float EXR, atomically. Each entry is a layer name and
// w * h * 3 floats (row-major RGB); its channels are "<name>.R", "<name>.G", "<name>.B",
// or plain "R", "G", "B" for an empty name. Throws wp::Error like write_image; the path
// must end in .exr.
void write_exr_layers(const std::filesystem::path& path, int w, int h,
                      const std::vector<std::pair<std::string, const float*>>& rgb_layers);

// One named channel of a w x h image for write_exr_channels: channel value of pixel p is
// data[p * stride + offset].
struct ImageChannel {
    std::string name;
    const float* data = nullptr;
    std::size_t stride = 1;
    std::size_t offset = 0;
};

// Writes a linear float EXR with the given named channels (e.g. "R", "G", "B",
// "albedo.R", "normal.X", "depth.Z"), atomically, with `attributes` in its header. Throws
// wp::Error like write_image; the path must end in .exr and the names must be distinct.
void write_exr_channels(const std::filesystem::path& path, int w, int h,
                        const std::vector<ImageChannel>& channels,
                        const std::vector<ImageAttribute>& attributes = {});

// Every channel of an image file as float, by name (as OpenImageIO names them), w x h.
struct ChannelImage {
    int width = 0, height = 0;
    std::vector<std::string> names;
    std::vector<float> data;  // interleaved: pixel p, channel c at p * names.size() + c
    // Channel `name`'s values (w * h); throws wp::Error naming the file's channels when absent.
    std::vector<float> channel(const std::string& name) const;
    bool has(const std::string& name) const;
};
// Throws wp::Error naming a missing or unreadable file.
ChannelImage read_image_channels(const std::filesystem::path& path);

// The sRGB transfer function (IEC 61966-2-1): linear in [0, 1] to encoded in [0, 1],
// 12.92 x below 0.0031308, else 1.055 x^(1/2.4) - 0.055. No clamping.
double srgb_encode(double linear);
// Its inverse: e / 12.92 up to 12.92 * 0.0031308, else ((e + 0.055) / 1.055)^2.4.
double srgb_decode(double encoded);

// Mean of factor x factor blocks; throws wp::Error unless factor >= 1 divides both sides.
Image downsample_box(const Image& image, int factor);

}  // namespace wp
