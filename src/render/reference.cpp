#include "render/reference.h"

#include <fmt/format.h>

#include "image/stats.h"
#include "util/error.h"

namespace wp::render {

namespace fs = std::filesystem;

Reference load_reference(const fs::path& path, int width, int height) {
    Reference r;
    r.path = path;
    r.image = read_image(path);
    if (width > 0 && height > 0 && (r.image.width != width || r.image.height != height))
        fail("reference '{}' is {}x{} but the render is {}x{} (use --size {}x{})", path.string(),
             r.image.width, r.image.height, width, height, r.image.width, r.image.height);
    fs::path vp = variance_path_for(path);
    std::error_code ec;
    if (vp != path && fs::exists(vp, ec)) {
        Image v = read_image(vp);
        if (v.width != r.image.width || v.height != r.image.height)
            fail("variance file '{}' is {}x{} but its reference '{}' is {}x{}", vp.string(),
                 v.width, v.height, path.string(), r.image.width, r.image.height);
        r.own_relmse = reference_relmse(r.image, v);
        r.variance = std::move(v);
        r.variance_path = vp;
    }
    return r;
}

std::string format_errors(const ErrorMetrics& m) {
    return fmt::format("RMSE {:.3e}  relMSE {:.3e}  MAE {:.3e}", m.rmse, m.relmse, m.mae);
}

std::string reference_warning(const Reference& ref, double smallest_relmse) {
    if (ref.own_relmse < 0.0)
        return fmt::format("reference '{}' has no variance file '{}': its own error is unknown, "
                           "so errors near it may be the reference's",
                           ref.path.string(), variance_path_for(ref.path).string());
    if (ref.own_relmse > 0.1 * smallest_relmse)
        return fmt::format("reference '{}' is too noisy: its own relMSE {:.3e} (from '{}') is "
                           "more than a tenth of the smallest error reported ({:.3e}); render "
                           "it with more samples",
                           ref.path.string(), ref.own_relmse, ref.variance_path.string(),
                           smallest_relmse);
    return {};
}

}  // namespace wp::render
