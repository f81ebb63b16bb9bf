// reference.h — a reference image to measure a render's error against, with its variance
// when one lies next to it (REF.var.exr beside REF.exr, as `render --variance` writes).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "image/image.h"

namespace wp::render {

struct Reference {
    std::filesystem::path path;
    Image image;
    std::filesystem::path variance_path;  // empty when no variance file was found
    std::optional<Image> variance;        // variance of the reference's mean, per pixel
    // The relMSE its own noise contributes (image/stats.h reference_relmse); < 0 unknown.
    double own_relmse = -1.0;
};

// Reads `path` and, when it exists, variance_path_for(path). Throws wp::Error naming the
// file when it cannot be read, or when (width, height) > 0 is given and the size differs.
Reference load_reference(const std::filesystem::path& path, int width = 0, int height = 0);

// "RMSE 1.23e-02  relMSE 4.56e-03  MAE 7.89e-03"
std::string format_errors(const ErrorMetrics& m);

// The honesty check of issue 4: a warning text when the reference's own estimated error
// exceeds a tenth of `smallest_relmse`, or when it is unknown (no variance file); empty
// when the reference is good enough.
std::string reference_warning(const Reference& ref, double smallest_relmse);

}  // namespace wp::render
