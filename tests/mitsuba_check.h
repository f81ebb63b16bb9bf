// mitsuba_check.h — renders a Mitsuba 3 XML scene with wavepath and compares it with Mitsuba 3's
// reference of the same file (tests/test_appearance_reference.cpp, test_material_reference.cpp).
//
// A reference set is a folder of scenes (<name>.xml, read by wavepath's own loader) and a
// folder of references made by a script with Mitsuba 3: <name>.exr (mean), <name>.var.exr
// (variance of that mean, from independent seeds) and mitsuba.json (each scene's spp).
// Criteria, per scene:
//  * z-test (image/stats.h, α = 0.01 with Šidák over pixels and channels): at least
//    `min_pass` of the pixels pass, with the variances of both means; the render's variance
//    is max(its own estimate, the reference's per-sample variance scaled to the render's
//    spp), as in test_image_regression.cpp (a few hundred samples of a heavy-tailed pixel
//    underestimate their own variance), plus the case's `tolerance` (below).
//  * relMSE (compare_images, ε = 1e-2) at most 1.25 × the relMSE that the two images' noise
//    alone gives in expectation (noise = mean of (var_render + var_ref) / (ref² + ε)) plus
//    `allowance`, the bias the scene's deliberate model differences may add.
// A missing scene or reference file is a skip (WARN + return), never a failure: the
// references are made only by their script. No counter of the render may be non-zero. On a
// failure the render, the reference and a false-colour z image go to `<set.out>/` under the
// working folder.
#pragma once

#include <filesystem>
#include <functional>

#include "scene/scene.h"

namespace wp::test {

struct MitsubaSet {
    std::filesystem::path scenes;  // <name>.xml
    std::filesystem::path refs;    // <name>.exr, <name>.var.exr, mitsuba.json
    const char* script;            // what makes them (for the skip message)
    const char* out;               // folder for the images of a failure
};

struct MitsubaCase {
    const char* name;   // the scene's name in the set
    int spp;            // wavepath's samples per pixel
    double min_pass;    // z-test pass fraction
    double allowance;   // relMSE a deliberate model difference may add
    // Relative difference per pixel that a deterministic model difference may cause (0: none):
    // (tolerance × max(|render|, |reference|))² joins the render's variance in the z-test.
    // Pixels of a Dirac reflection of a constant environment have almost no variance, so
    // that differences of 1e-4 in the Fresnel term would otherwise fail them.
    double tolerance = 0.0;
};

// Renders the scene file and compares it with its Mitsuba reference (CHECKs). `features`
// checks that the loader read what the scene is about, so that a loader that ignores it
// fails with a message naming what is missing rather than with an image difference.
void check_against_mitsuba(const MitsubaSet& set, const MitsubaCase& c,
                           const std::function<void(const Scene&)>& features);

}  // namespace wp::test
