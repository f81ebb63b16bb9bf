// image.h — images on the host: OpenImageIO files and error metrics.
//
// Image holds linear RGB float pixels, row-major from the top-left, 3 floats per pixel.
// Files: .exr is written as linear float RGB; .png (and .jpg) as 8-bit sRGB after clamping
// to [0, 1] (no tone curve besides the sRGB transfer function). Writing is atomic: a
// failed write leaves no file behind and an existing file untouched.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace wp {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // width * height * 3, linear

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(static_cast<std::size_t>(w) * h * 3, 0.0f) {}
    float* pixel(int x, int y) { return &rgb[(static_cast<std::size_t>(y) * width + x) * 3]; }
    const float* pixel(int x, int y) const { return &rgb[(static_cast<std::size_t>(y) * width + x) * 3]; }
};

// Throws wp::Error naming the path when the extension is unknown, the folder is missing
// or not writable, or the writer fails.
void write_image(const std::filesystem::path& path, const Image& image);

// True when write_image supports the extension of `path` (.exr, .png, .jpg, .jpeg).
bool is_supported_image_path(const std::filesystem::path& path);

// Reads any format OpenImageIO reads; returns the first three channels (grey is
// replicated), converted to linear float as stored in the file (EXR: as is).
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

}  // namespace wp
