// cmd_compare.cpp — `wavepath compare A B`: how far image A is from image B.
//
// Prints RMSE, relMSE (eps 1e-2), MAE and the largest per-pixel difference with where it
// is; with --variance (and/or --ref-variance) also a per-pixel z-test, α = 0.01 Šidák-
// corrected over pixels (image/stats.h), and the fraction of pixels that pass. Writes a
// false-colour error image on request. Exit codes for scripts and tests:
//   0  compared, and every threshold given holds
//   1  compared, and a threshold failed (--max-relmse, --min-pass)
//   2  usage error or unreadable input (nothing compared)
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "app/render_options.h"
#include "app/subcommands.h"
#include "image/image.h"
#include "image/stats.h"
#include "util/error.h"

namespace wp::app {

namespace {

struct CompareArgs {
    std::string a, b;
    std::string variance;      // variance of A's mean
    std::string ref_variance;  // variance of B's mean
    std::string error_image;
    double max_relmse = -1.0;  // < 0: no threshold
    double min_pass = -1.0;    // < 0: no threshold
    double alpha = 0.01;
};

std::optional<Image> read_variance(const std::string& path, const Image& like, const char* what) {
    if (path.empty()) return std::nullopt;
    Image v = read_image(path);
    if (v.width != like.width || v.height != like.height)
        fail("{} '{}' is {}x{}, the images are {}x{}", what, path, v.width, v.height, like.width,
             like.height);
    return v;
}

// Everything up to the threshold decision; wp::Error here is a usage/input error (exit 2).
int run_compare(const CompareArgs& a) {
    if (a.min_pass >= 0.0 && a.variance.empty() && a.ref_variance.empty())
        usage_fail("--min-pass needs --variance or --ref-variance (the z-test needs variances)");
    if (a.min_pass > 1.0) usage_fail("--min-pass {} is a fraction and must be in [0, 1]", a.min_pass);
    if (!(a.alpha > 0.0 && a.alpha < 1.0)) usage_fail("--alpha {} must be in (0, 1)", a.alpha);
    if (!a.error_image.empty()) check_writable(a.error_image, "--error-image", true);

    Image x = read_image(a.a);
    Image r = read_image(a.b);
    if (x.width != r.width || x.height != r.height)
        fail("'{}' is {}x{} but '{}' is {}x{}", a.a, x.width, x.height, a.b, r.width, r.height);
    std::optional<Image> va = read_variance(a.variance, x, "--variance");
    std::optional<Image> vb = read_variance(a.ref_variance, x, "--ref-variance");

    // Metrics.
    ErrorMetrics m = compare_images(x, r);
    fmt::print("{} vs {} ({}x{})\n", a.a, a.b, x.width, x.height);
    fmt::print("  RMSE     {:.6e}\n  relMSE   {:.6e}   (mean of (a-b)^2/(b^2+0.01) over pixels "
               "and channels)\n  MAE      {:.6e}\n",
               m.rmse, m.relmse, m.mae);
    fmt::print("  max |a-b| {:.6e} at pixel ({}, {})\n", m.max_abs, m.max_x, m.max_y);
    std::optional<ZTest> z;
    if (va || vb) {
        z = z_test(x, r, va ? &*va : nullptr, vb ? &*vb : nullptr, a.alpha);
        fmt::print("  z-test   alpha {} Sidak-corrected over {} pixels x 3 channels: per-channel "
                   "alpha {:.3e}, |z| <= {:.3f}\n",
                   a.alpha, z->pixels, z->alpha_channel, z->z_crit);
        fmt::print("           {} of {} pixels pass ({:.4f}%); largest |z| {:.3f} at pixel "
                   "({}, {})\n",
                   z->passed, z->pixels, 100.0 * z->pass_fraction, z->max_abs_z, z->max_x,
                   z->max_y);
    }

    // Error image: |z| up to 2 z_crit with variance, else |a-b| up to its largest value.
    if (!a.error_image.empty()) {
        Image e = z ? false_colour(z->pixel_z, x.width, x.height, 2.0 * z->z_crit)
                    : false_colour(abs_difference(x, r), x.width, x.height,
                                   std::max(m.max_abs, 1e-30));
        write_image(a.error_image, e);
        fmt::print("  error image {} ({})\n", a.error_image,
                   z ? fmt::format("|z| from 0 to {:.2f}; pink: above", 2.0 * z->z_crit)
                     : fmt::format("mean |a-b| over channels, 0 to {:.3e}", m.max_abs));
    }

    // Thresholds.
    bool ok = true;
    if (a.max_relmse >= 0.0 && !(m.relmse <= a.max_relmse)) {
        fmt::print("FAIL: relMSE {:.6e} > --max-relmse {}\n", m.relmse, a.max_relmse);
        ok = false;
    }
    if (a.min_pass >= 0.0 && z && !(z->pass_fraction >= a.min_pass)) {
        fmt::print("FAIL: {:.4f}% of pixels pass the z-test < --min-pass {}%\n",
                   100.0 * z->pass_fraction, 100.0 * a.min_pass);
        ok = false;
    }
    if (ok && (a.max_relmse >= 0.0 || a.min_pass >= 0.0)) fmt::print("PASS\n");
    return ok ? 0 : 1;
}

}  // namespace

Subcommand add_compare(CLI::App& app) {
    auto args = std::make_shared<CompareArgs>();
    Subcommand s;
    s.app = app.add_subcommand(
        "compare",
        "Compare image A with image B (the reference): RMSE, relMSE, MAE, the largest "
        "difference and where; with variances a per-pixel z-test. Exit code 0 when every "
        "threshold given holds, 1 when one fails, 2 on usage errors or unreadable files.");
    auto* c = s.app;
    c->add_option("a", args->a, "Image to test (EXR, PNG, ...)")->required();
    c->add_option("b", args->b, "Reference image, the same size")->required();
    c->add_option("--variance", args->variance,
                  "Variance of A's mean per pixel (VAR.exr, as `render --variance` writes: s^2/n)");
    c->add_option("--ref-variance", args->ref_variance,
                  "Variance of B's mean per pixel; the z-test uses the sum of both variances");
    c->add_option("--error-image", args->error_image,
                  "Write a false-colour error image (PNG or EXR): |z| when variances are given "
                  "(scale 0 to 2 z_crit), else the mean |A-B| over channels");
    c->add_option("--max-relmse", args->max_relmse,
                  "Fail (exit 1) when relMSE = mean over pixels and channels of "
                  "(a-b)^2/(b^2+0.01) exceeds this");
    c->add_option("--min-pass", args->min_pass,
                  "Fail (exit 1) when the fraction of pixels passing the z-test is below this "
                  "(e.g. 0.9975); needs --variance or --ref-variance");
    c->add_option("--alpha", args->alpha,
                  "Family-wise significance level of the z-test, Sidak-corrected over the 3N "
                  "channel tests: alpha_channel = 1-(1-alpha)^(1/(3N)), |z| <= "
                  "Phi^-1(1-alpha_channel/2)")
        ->capture_default_str();
    s.run = [args]() -> int {
        try {
            return run_compare(*args);
        } catch (const Error& e) {
            fmt::print(stderr, "wavepath compare: error: {}\n", e.what());
            return 2;
        }
    };
    return s;
}

}  // namespace wp::app
