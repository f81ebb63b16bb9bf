// mitsuba_check.cpp — see mitsuba_check.h.
#include "mitsuba_check.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "image/stats.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/load.h"
#include "support.h"

namespace fs = std::filesystem;

namespace wp::test {

namespace {

// The reference's spp as the script recorded it (<refs>/mitsuba.json); 0 when the file or the
// entry is missing.
int reference_spp(const fs::path& refs, const std::string& name) {
    std::ifstream in(refs / "mitsuba.json");
    if (!in) return 0;
    nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded() || !j.contains("scenes") || !j["scenes"].contains(name)) return 0;
    return j["scenes"][name].value("spp", 0);
}

}  // namespace

void check_against_mitsuba(const MitsubaSet& set, const MitsubaCase& c,
                           const std::function<void(const Scene&)>& features) {
    const fs::path xml = set.scenes / (std::string(c.name) + ".xml");
    const fs::path ref_path = set.refs / (std::string(c.name) + ".exr");
    const fs::path var_path = variance_path_for(ref_path);
    for (const fs::path& p : {xml, ref_path, var_path})
        if (!fs::exists(p)) {
            WARN("SKIP: " << p << " does not exist; run " << set.script
                          << " (Mitsuba 3) to make the scenes and references");
            return;
        }
    const int ref_spp = reference_spp(set.refs, c.name);
    if (ref_spp <= 0) {
        WARN("SKIP: " << (set.refs / "mitsuba.json") << " has no spp for " << c.name << "; rerun "
                      << set.script);
        return;
    }

    Scene scene = load_scene_file(xml);
    std::string warnings;
    for (const auto& w : scene.warnings) warnings += "\n  " + w;
    INFO("loader warnings:" << (warnings.empty() ? std::string(" none") : warnings));
    features(scene);
    REQUIRE(scene.render.depth.has_value());

    Image ref = read_image(ref_path), ref_var = read_image(var_path);
    render::RenderSettings rs;
    rs.width = scene.camera.width;
    rs.height = scene.camera.height;
    REQUIRE(ref.width == rs.width);
    REQUIRE(ref.height == rs.height);
    rs.depth = *scene.render.depth;
    rs.seed = 7;
    rs.variance = true;
    render::Wavefront wf(device(), scene, rs);
    render::LoopOptions lo;
    lo.spp = c.spp;
    const auto t0 = std::chrono::steady_clock::now();
    render::render_frames(wf, lo, nullptr);
    render::FilmMoments m = wf.moments();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    auto counters = wf.counters();
    for (int k = 0; k < WP_COUNTER_COUNT; ++k) {
        INFO("counter " << k);
        CHECK(counters[k] == 0);
    }

    // The render's variance of the mean: its own, or the reference's per-sample variance
    // scaled to c.spp, whichever is larger (see the header).
    Image var_a = ref_var;
    const float scale = static_cast<float>(ref_spp) / static_cast<float>(c.spp);
    for (std::size_t i = 0; i < var_a.rgb.size(); ++i)
        var_a.rgb[i] = std::max(ref_var.rgb[i] * scale, m.mean_variance.rgb[i]);
    Image var_z = var_a;  // with the model tolerance, for the z-test only
    for (std::size_t i = 0; i < var_z.rgb.size(); ++i) {
        const double t = c.tolerance * std::max(std::abs(m.mean.rgb[i]), std::abs(ref.rgb[i]));
        var_z.rgb[i] += static_cast<float>(t * t);
    }
    const ZTest z = z_test(m.mean, ref, &var_z, &ref_var);
    const double relmse = compare_images(m.mean, ref).relmse;
    const double noise = reference_relmse(ref, var_a) + reference_relmse(ref, ref_var);
    const double bound = 1.25 * noise + c.allowance;
    WARN(c.name << " (" << rs.width << "x" << rs.height << ", " << c.spp << " spp, depth "
                << rs.depth << ", " << seconds << " s): z-test " << z.passed << "/" << z.pixels
                << " pass (" << z.pass_fraction << ", need " << c.min_pass << "; tolerance " << c.tolerance << ", |z| <= "
                << z.z_crit << ", largest " << z.max_abs_z << " at (" << z.max_x << ", "
                << z.max_y << ")); relMSE " << relmse << " (bound " << bound << " = 1.25 x noise "
                << noise << " + " << c.allowance << ")");
    const bool ok = z.pass_fraction >= c.min_pass && relmse <= bound;
    if (!ok) {
        fs::path out = fs::current_path() / set.out;
        fs::create_directories(out);
        write_image(out / (std::string(c.name) + ".exr"), m.mean);
        write_image(out / (std::string(c.name) + ".ref.exr"), ref);
        write_image(out / (std::string(c.name) + ".z.png"),
                    false_colour(z.pixel_z, rs.width, rs.height, 2.0 * z.z_crit));
        WARN("wrote " << (out / c.name).string() << ".{exr,ref.exr,z.png}");
    }
    CHECK(z.pass_fraction >= c.min_pass);
    CHECK(relmse <= bound);
}

}  // namespace wp::test
