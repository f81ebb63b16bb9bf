// test_adaptive.cpp — adaptive sampling and the error estimate (render/adaptive.h): the
// check schedule, the per-pixel estimate against double precision, the active list and the
// per-pixel counts against a host simulation on the non-adaptive film, unbiasedness by
// z-tests, and --target-error's estimate against the true relMSE.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <limits>
#include <vector>

#include "image/image.h"
#include "image/stats.h"
#include "render/adaptive.h"
#include "render/aov.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "shared/adaptive.h"
#include "shared/film.h"
#include "shared/rng.h"
#include "support.h"
#include "temp_dir.h"
#include "util/limits.h"

using namespace wp;

namespace {

double value(const FilmPixel& p, int c) {
    const float* hi = &p.sum.x;
    const float* lo = &p.comp.x;
    return double(hi[c]) + double(lo[c]);
}

// The per-pixel estimate in double, written out from its definition (adaptive.h).
double pixel_relmse_double(const FilmPixel& s, const FilmPixel& q, int n) {
    if (n < 2) return std::numeric_limits<double>::infinity();
    double e = 0.0;
    for (int c = 0; c < 3; ++c) {
        double m = value(s, c) / n;
        double var = std::max(0.0, (value(q, c) - n * m * m) / (n - 1));
        e += var / n / (m * m + 1e-2);
    }
    return e / 3.0;
}

render::RenderSettings small_settings(int w, int h, std::uint32_t seed) {
    render::RenderSettings s;
    s.width = w;
    s.height = h;
    s.seed = seed;
    return s;
}

// The veach plates with a constant grey background: pixels that see only the background
// have zero variance from the first sample on.
Scene plates_with_background() {
    Scene s = make_veach_plates();
    s.background = glm::vec3(0.3f);
    return s;
}

}  // namespace

TEST_CASE("adaptive: the check schedule is min spp, then every max(4, spp/4) passes",
          "[unit][adaptive]") {
    for (int min_spp : {2, 16, 100}) {
        CHECK(render::next_error_check(0, min_spp) == min_spp);
        CHECK(render::next_error_check(min_spp, min_spp) == min_spp);
        int c = min_spp;
        for (int i = 0; i < 40; ++i) {
            const int next = render::next_error_check(c + 1, min_spp);
            CHECK(next - c == std::max(4, c / 4));
            // Every pass in between maps to that next check.
            CHECK(render::next_error_check(next - 1, min_spp) == next);
            c = next;
        }
    }
}

// RQMC replicates: the checks (and --target-error's estimates) fall on multiples of K, so
// the K replicates of a pixel have equal counts there; the interval is the plain one rounded
// up to a multiple of K.
TEST_CASE("replicates: the check schedule falls on multiples of K", "[unit][adaptive]") {
    for (int k : {2, 4, 8, 64})
        for (int min_spp : {2, 16, 17, 100}) {
            INFO("K " << k << ", min spp " << min_spp);
            int c = render::next_error_check(0, min_spp, k);
            CHECK(c % k == 0);
            CHECK(c >= min_spp);
            CHECK(c < min_spp + k);
            for (int i = 0; i < 30; ++i) {
                const int next = render::next_error_check(c + 1, min_spp, k);
                const int plain = std::max(4, c / 4);
                CHECK(next % k == 0);
                CHECK(next - c >= plain);
                CHECK(next - c < plain + k);
                CHECK(render::next_error_check(next - 1, min_spp, k) == next);
                c = next;
            }
        }
    // K = 1 is the schedule of before (the test above).
    for (int p : {0, 5, 16, 17, 33, 1000}) CHECK(render::next_error_check(p, 16, 1) == render::next_error_check(p, 16));
}

// The sampler with replicates (kernels/shared/rng.h): K = 1 is the Owen-scrambled Sobol
// point `sample` under the pixel's scramble, as before replicates existed (written out
// here from its definition); with K = 4, the samples s = 4q + r of a pixel are point q of
// replicate r's own scramble, so the first 2^m samples of each replicate are a (0,m,2)-net
// in the first two dimensions (every elementary interval of area 2^-m holds one point),
// and the replicates' scrambles differ.
TEST_CASE("replicates: each replicate's samples are a scrambled (0,2)-sequence prefix",
          "[unit][adaptive]") {
    const std::uint32_t seed = 7;
    for (std::uint32_t pixel : {0u, 5u, 123456u})
        for (std::uint32_t bounce : {0u, 2u})
            for (std::uint32_t group : {0u, 1u}) {
                const std::uint32_t base = wp_pcg4d(pixel, bounce * WP_RNG_GROUPS + group, seed, 0x50b01u).x;
                for (std::uint32_t s = 0; s < 64; ++s) {
                    uint4 a = wp_sobol_rng4(seed, pixel, s, bounce, group, 1u);
                    uint4 b = wp_sobol_owen4(s, base);
                    CHECK((a.x == b.x && a.y == b.y && a.z == b.z && a.w == b.w));
                }
                const std::uint32_t k = 4;
                std::uint32_t first_x[4];
                for (std::uint32_t r = 0; r < k; ++r) {
                    for (int m : {4, 6}) {
                        const std::uint32_t n = 1u << m;
                        for (int a = 0; a <= m; ++a) {
                            std::vector<int> cells(n, 0);
                            for (std::uint32_t q = 0; q < n; ++q) {
                                uint4 v = wp_sobol_rng4(seed, pixel, q * k + r, bounce, group, k);
                                const std::uint32_t cx = a == 0 ? 0u : v.x >> (32 - a);
                                const std::uint32_t cy = a == m ? 0u : v.y >> (32 - (m - a));
                                cells[(cx << (m - a)) | cy] += 1;
                            }
                            int empty = 0;
                            for (int c : cells) empty += c != 1;
                            INFO("pixel " << pixel << " replicate " << r << " m " << m << " split " << a);
                            CHECK(empty == 0);
                        }
                    }
                    first_x[r] = wp_sobol_rng4(seed, pixel, r, bounce, group, k).x;
                }
                for (std::uint32_t r = 1; r < k; ++r) CHECK(first_x[r] != first_x[0]);
            }
}

TEST_CASE("adaptive: the per-pixel error kernel agrees with double precision", "[kernel][adaptive]") {
    auto& dev = test::device();
    const std::size_t n = 1000;
    test::Rng rng(5);
    std::vector<FilmPixel> sum(n), sq(n);
    const int samples = 37;
    for (std::size_t p = 0; p < n; ++p) {
        // Sums of `samples` values drawn around a random mean (some constant, some dark).
        float x[3][64];
        for (int c = 0; c < 3; ++c) {
            float mean = p % 7 == 0 ? 0.0f : float(rng.uniform()) * (p % 3 == 0 ? 0.05f : 4.0f);
            float spread = p % 5 == 0 ? 0.0f : float(rng.uniform());
            for (int i = 0; i < samples; ++i) x[c][i] = mean * (1.0f + spread * float(rng.uniform() - 0.5));
        }
        FilmPixel a{}, b{};
        for (int i = 0; i < samples; ++i) {
            float3 v = make_float3(x[0][i], x[1][i], x[2][i]);
            a = wp_film_add(a, v);
            b = wp_film_add_square(b, v);
        }
        sum[p] = a;
        sq[p] = b;
    }
    render::FilmBuffers film(dev, n, true);
    film.segments[0].sum.write(dev, sum);
    film.segments[0].sum_sq.write(dev, sq);
    const int w = 40, h = 25;  // n pixels
    render::ActivePixels active(dev, w, h, nullptr);
    active.refresh(dev, film, samples);
    for (std::size_t p = 0; p < n; ++p) {
        const double want = pixel_relmse_double(sum[p], sq[p], samples);
        INFO("pixel " << p << " want " << want << " got " << active.errors()[p]);
        // Float sums: the cancellation in S2 - S1 m leaves ~1e-7 m^2 / n (adaptive.h).
        CHECK(std::abs(active.errors()[p] - want) <= 1e-4 * want + 1e-6 / samples);
    }
    // Dropping at a threshold keeps exactly the pixels with a neighbour (or themselves)
    // above it, in order.
    const double t = 1e-3;
    active.drop_converged(dev, t, samples);
    std::vector<int> want;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            bool keep = false;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && xx < w && yy >= 0 && yy < h && !(active.errors()[yy * w + xx] <= t))
                        keep = true;
                }
            if (keep) want.push_back(y * w + x);
        }
    CHECK(active.list() == want);
    CHECK(want.size() > 50);
    CHECK(want.size() < n - 20);
    CHECK(active.device_list().read(dev, 0, want.size()) == want);
}

// The replicate estimate (kernels/shared/adaptive.h) against its definition in double on
// hand-made pixels: K = 4 replicates, equal counts (36), unequal counts (37) and too few
// samples (7 < 2K: the s^2/n estimate); the stopping estimate stays s^2/n.
TEST_CASE("replicates: the replicate error kernel agrees with double precision", "[kernel][adaptive]") {
    auto& dev = test::device();
    const int k = 4, w = 20, h = 10;
    const std::size_t n = std::size_t(w) * h;
    for (int samples : {36, 37, 7}) {
        INFO(samples << " samples");
        test::Rng rng(11 + samples);
        std::vector<FilmPixel> sum(n), sq(n), rep(n * k);
        std::vector<double> want(n), want_plain(n);
        for (std::size_t p = 0; p < n; ++p) {
            FilmPixel a{}, b{};
            double rs[4][3] = {}, rn[4] = {};
            const float mean = p % 7 == 0 ? 0.0f : float(rng.uniform()) * (p % 3 == 0 ? 0.05f : 4.0f);
            const float spread = p % 5 == 0 ? 0.0f : float(rng.uniform());
            for (int i = 0; i < samples; ++i) {
                float3 v;
                float* c = &v.x;
                for (int ch = 0; ch < 3; ++ch) c[ch] = mean * (1.0f + spread * float(rng.uniform() - 0.5));
                a = wp_film_add(a, v);
                b = wp_film_add_square(b, v);
                FilmPixel& rp = rep[p * k + std::size_t(i % k)];
                rp = wp_film_add(rp, v);
                for (int ch = 0; ch < 3; ++ch) rs[i % k][ch] += c[ch];
                rn[i % k] += 1;
            }
            sum[p] = a;
            sq[p] = b;
            want_plain[p] = pixel_relmse_double(a, b, samples);
            if (samples < 2 * k) {
                want[p] = want_plain[p];
                continue;
            }
            double e = 0.0;
            for (int ch = 0; ch < 3; ++ch) {
                double mr[4], mbar = 0.0;
                for (int r = 0; r < k; ++r) mbar += (mr[r] = rs[r][ch] / rn[r]) / k;
                double v = 0.0;
                for (int r = 0; r < k; ++r) v += (mr[r] - mbar) * (mr[r] - mbar);
                v /= double(k) * (k - 1);
                const double m = value(a, ch) / samples;
                e += v / (m * m + 1e-2);
            }
            want[p] = e / 3.0;
        }
        render::FilmBuffers film(dev, n, true, 0, k);
        REQUIRE(film.segments[0].replicate_sum.size == n * k);
        film.segments[0].sum.write(dev, sum);
        film.segments[0].sum_sq.write(dev, sq);
        film.segments[0].replicate_sum.write(dev, rep);
        render::ActivePixels active(dev, w, h, nullptr, k);
        active.refresh(dev, film, samples);
        double mean = 0.0;
        int nonzero = 0;
        for (std::size_t p = 0; p < n; ++p) {
            INFO("pixel " << p << " want " << want[p] << " got " << active.image_errors()[p]);
            // The s^2/n fallback: the tolerance of the test above (float cancellation).
            const double slack = samples < 2 * k ? 1e-6 / samples : 1e-9;
            CHECK(std::abs(active.image_errors()[p] - want[p]) <= 1e-4 * want[p] + slack);
            CHECK(std::abs(active.errors()[p] - want_plain[p]) <= 1e-4 * want_plain[p] + 1e-6 / samples);
            mean += want[p] / n;
            nonzero += want[p] > 1e-6;
        }
        CHECK(nonzero > 50);
        CHECK(active.mean_error() == Approx(mean).epsilon(1e-4));
    }
}

// The film's replicate sums (accumulate.cl) against the samples themselves: K = 4, the film
// read after every pass, so sample s's radiance is the difference of two snapshots, and
// replicate r's sum must be the sum of the samples s = r mod 4. The same bits with a pool
// that cuts a pass into chunks and a film in segments; with adaptive sampling, every pixel's
// replicate sums are the plain render's at the pixel's own count (a multiple of 4). K = 1
// compiles and allocates nothing for replicates.
TEST_CASE("replicates: the film's replicate sums hold each replicate's samples",
          "[render][adaptive]") {
    Scene scene = plates_with_background();
    const int w = 16, h = 12, k = 4, max_spp = 32;
    const std::size_t n = std::size_t(w) * h;
    render::RenderSettings s = small_settings(w, h, 5);
    s.replicates = k;
    std::vector<std::vector<FilmPixel>> sums(max_spp + 1), reps(max_spp + 1);
    sums[0].assign(n, FilmPixel{});
    reps[0].assign(n * k, FilmPixel{});
    {
        render::Wavefront wf(test::device(), scene, s);
        CHECK(wf.options().find("-D WP_SOBOL_REPLICATES=4") != std::string::npos);
        // Memory: the sum, the sum of squares (implied) and 4 replicate sums, 32 bytes each,
        // a pixel; the counters and ray totals (test_memory.cpp).
        CHECK(wf.memory().bytes_per_pixel == 32u * (2 + k));
        CHECK(wf.film_bytes() == n * 32u * (2 + k));
        CHECK(wf.memory().group("film") == n * 32u * (2 + k) + 8 * 4 + 2 * 8);
        for (int p = 1; p <= max_spp; ++p) {
            wf.render_passes(1);
            sums[p] = wf.film();
            reps[p] = wf.film_replicates();
        }
    }
    int bad = 0;
    for (std::size_t p = 0; p < n; ++p)
        for (int r = 0; r < k; ++r)
            for (int c = 0; c < 3; ++c) {
                double want = 0.0;
                for (int q = r; q < max_spp; q += k) want += value(sums[q + 1][p], c) - value(sums[q][p], c);
                const double got = value(reps[max_spp][p * k + r], c);
                bad += std::abs(got - want) > 1e-5 * std::abs(value(sums[max_spp][p], c)) + 1e-6;
            }
    CHECK(bad == 0);
    // Pool and film cuts: the same bits.
    {
        render::RenderSettings cut = s;
        cut.pool = 37;
        cut.film_segment = 50;
        render::Wavefront wf(test::device(), scene, cut);
        wf.render_passes(max_spp);
        auto f = wf.film();
        auto rp = wf.film_replicates();
        CHECK(std::memcmp(f.data(), sums[max_spp].data(), n * sizeof(FilmPixel)) == 0);
        CHECK(std::memcmp(rp.data(), reps[max_spp].data(), n * k * sizeof(FilmPixel)) == 0);
    }
    // Adaptive sampling over the active list.
    {
        render::RenderSettings a = s;
        a.adaptive.enabled = true;
        a.adaptive.threshold = 2e-3;
        a.adaptive.min_spp = 6;  // rounded up to 8
        render::Wavefront wf(test::device(), scene, a);
        render::LoopOptions lo;
        lo.spp = max_spp;
        render::render_frames(wf, lo, nullptr);
        std::vector<int> counts = wf.sample_counts();
        auto f = wf.film();
        auto rp = wf.film_replicates();
        int differs = 0, not_multiple = 0, stopped = 0;
        for (std::size_t p = 0; p < n; ++p) {
            const int c = counts[p];
            not_multiple += c % k != 0;
            stopped += c < max_spp;
            differs += std::memcmp(&f[p], &sums[c][p], sizeof(FilmPixel)) != 0;
            differs += std::memcmp(&rp[p * k], &reps[c][p * k], k * sizeof(FilmPixel)) != 0;
        }
        CHECK(not_multiple == 0);
        CHECK(stopped > 20);
        CHECK(differs == 0);
    }
    // K = 1: no replicate define, no replicate buffer.
    render::RenderSettings one = small_settings(w, h, 5);
    one.error_estimate = true;
    render::Wavefront wf(test::device(), scene, one);
    CHECK(wf.options().find("WP_SOBOL_REPLICATES") == std::string::npos);
    CHECK_THROWS(wf.film_replicates());
    for (const auto& b : wf.memory().buffers) CHECK(b.name.find("replicate") == std::string::npos);
}

// The adaptive render's film, counts and list against a host simulation of the stopping
// rule (in double, with the 3x3 neighbourhood's largest error) on the non-adaptive render's film pass by pass: each pixel's film must
// be, bit for bit, the non-adaptive film at the pixel's own count (same samples); some pixels
// stop at min spp (the constant background), some later, some never.
TEST_CASE("adaptive: counts, active list and film match a brute-force simulation",
          "[render][adaptive]") {
    Scene scene = plates_with_background();
    const int w = 32, h = 24, max_spp = 48, min_spp = 8;
    const double threshold = 2.1e-3;
    render::RenderSettings s = small_settings(w, h, 3);
    s.variance = true;
    // Non-adaptive, film snapshots after every pass.
    std::vector<std::vector<FilmPixel>> sums(max_spp + 1), sqs(max_spp + 1);
    {
        render::Wavefront wf(test::device(), scene, s);
        for (int p = 1; p <= max_spp; ++p) {
            wf.render_passes(1);
            sums[p] = wf.film();
            sqs[p] = wf.film_squares();
        }
    }
    // The stopping rule simulated on the host.
    const std::size_t n = std::size_t(w) * h;
    std::vector<int> stop(n, 0);
    std::vector<int> active;
    for (std::size_t p = 0; p < n; ++p) active.push_back(int(p));
    int ambiguous = 0;
    std::vector<std::vector<int>> lists;  // the list after each check
    std::vector<double> err(n, std::numeric_limits<double>::infinity());
    for (int pass = 1; pass <= max_spp; ++pass) {
        if (render::next_error_check(pass, min_spp) != pass) continue;
        for (int p : active) err[p] = pixel_relmse_double(sums[pass][p], sqs[pass][p], pass);
        std::vector<int> kept;
        for (int p : active) {
            // The largest error over the 3x3 neighbourhood (stopped pixels: at their stop).
            const int y = p / w, x = p % w;
            double e = 0.0;
            for (int yy = y - 1; yy <= y + 1; ++yy)
                for (int xx = x - 1; xx <= x + 1; ++xx)
                    if (xx >= 0 && xx < w && yy >= 0 && yy < h) e = std::max(e, err[yy * w + xx]);
            if (std::abs(e - threshold) < 1e-4 * threshold) ++ambiguous;
            if (e <= threshold)
                stop[p] = pass;
            else
                kept.push_back(p);
        }
        active = kept;
        lists.push_back(active);
    }
    REQUIRE(ambiguous == 0);

    // The adaptive render, with the pool's default, a pool that cuts a pass into chunks and
    // a film in segments.
    struct Cut {
        std::size_t pool, segment;
    };
    for (Cut cut : {Cut{0, 0}, Cut{37, 0}, Cut{101, 200}}) {
        INFO("pool " << cut.pool << ", film segment " << cut.segment);
        render::RenderSettings a = small_settings(w, h, 3);
        a.adaptive.enabled = true;
        a.adaptive.threshold = threshold;
        a.adaptive.min_spp = min_spp;
        a.pool = cut.pool;
        a.film_segment = cut.segment;
        render::Wavefront wf(test::device(), scene, a);
        // The list after each check, one pass at a time.
        std::size_t check = 0;
        for (int pass = 1; pass <= max_spp; ++pass) {
            wf.render_passes(1);
            if (render::next_error_check(pass, min_spp) == pass) {
                REQUIRE(check < lists.size());
                CHECK(wf.active_list() == lists[check]);
                ++check;
            }
        }
        CHECK(wf.frames() == max_spp);
        std::vector<int> counts = wf.sample_counts();
        std::vector<FilmPixel> film = wf.film();
        int mismatched = 0, film_differs = 0, at_min = 0, at_max = 0, between = 0;
        for (std::size_t p = 0; p < n; ++p) {
            const int want = stop[p] ? stop[p] : max_spp;
            mismatched += counts[p] != want;
            film_differs += std::memcmp(&film[p], &sums[want][p], sizeof(FilmPixel)) != 0;
            at_min += want == min_spp;
            at_max += want == max_spp;
            between += want > min_spp && want < max_spp;
        }
        CHECK(mismatched == 0);
        CHECK(film_differs == 0);
        // Some pixels stop at once (background), some in between, some never.
        CHECK(at_min > 50);
        CHECK(between > 20);
        CHECK(at_max > 20);
        // The resolved image divides by each pixel's own count.
        Image img = wf.resolve();
        render::FilmMoments m = wf.moments();
        int wrong = 0;
        for (std::size_t p = 0; p < n; ++p)
            for (int c = 0; c < 3; ++c) {
                const double mean = value(film[p], c) / counts[p];
                wrong += img.rgb[3 * p + c] != float(mean);
                wrong += m.mean.rgb[3 * p + c] != float(mean);
            }
        CHECK(wrong == 0);
        // The mean spp is the mean of the counts.
        double total = 0;
        for (int c : counts) total += c;
        CHECK(wf.mean_spp() == Approx(total / n));
    }
}

// Adaptive sampling with the feature buffers (render --adaptive --aov/--denoise): the AOVs
// run over the active list (aov_accumulate_active) and each pixel's are the plain render's
// after the pixel's own count, bit for bit (same samples, same order, same division), with
// the default pool and with a pool that cuts a pass into chunks and a film in segments.
TEST_CASE("adaptive: the AOVs are the plain render's at each pixel's own count",
          "[render][adaptive][aov]") {
    Scene scene = plates_with_background();
    const int w = 16, h = 12, max_spp = 24;
    const std::size_t n = std::size_t(w) * h;
    render::RenderSettings s = small_settings(w, h, 9);
    s.aov = true;
    std::vector<render::AovImages> plain(max_spp + 1);
    {
        render::Wavefront wf(test::device(), scene, s);
        for (int p = 1; p <= max_spp; ++p) {
            wf.render_passes(1);
            plain[p] = wf.aovs();
        }
    }
    struct Cut {
        std::size_t pool, segment;
    };
    for (Cut cut : {Cut{0, 0}, Cut{37, 50}}) {
        INFO("pool " << cut.pool << ", film segment " << cut.segment);
        render::RenderSettings a = s;
        a.adaptive.enabled = true;
        a.adaptive.threshold = 2e-3;
        a.adaptive.min_spp = 4;
        a.pool = cut.pool;
        a.film_segment = cut.segment;
        render::Wavefront wf(test::device(), scene, a);
        render::LoopOptions lo;
        lo.spp = max_spp;
        render::render_frames(wf, lo, nullptr);
        const std::vector<int> counts = wf.sample_counts();
        const render::AovImages got = wf.aovs();
        int differs = 0, stopped = 0, hit = 0;
        for (std::size_t p = 0; p < n; ++p) {
            const render::AovImages& want = plain[counts[p]];
            stopped += counts[p] < max_spp;
            hit += std::isfinite(want.depth[p]);
            for (int c = 0; c < 3; ++c) {
                differs += got.albedo.rgb[3 * p + c] != want.albedo.rgb[3 * p + c];
                differs += got.normal.rgb[3 * p + c] != want.normal.rgb[3 * p + c];
            }
            differs += std::memcmp(&got.depth[p], &want.depth[p], sizeof(float)) != 0;
        }
        CHECK(stopped > 20);
        CHECK(stopped < int(n));
        CHECK(hit > 20);
        CHECK(differs == 0);
    }
}

// Pixels of zero variance (background, black plates at depth 0) with neighbours of zero
// variance stop at min spp exactly,
// noisy ones (edges, jittered) keep going; and a loop asked for 2^20 spp ends as soon as
// every pixel has stopped.
TEST_CASE("adaptive: zero-variance pixels stop at min spp; the loop ends when all stopped",
          "[render][adaptive]") {
    Scene scene = plates_with_background();
    render::RenderSettings a = small_settings(16, 12, 1);
    a.adaptive.enabled = true;
    a.adaptive.threshold = 1e-5;
    a.adaptive.min_spp = 4;
    a.depth = 0;  // emitters and background only
    {
        render::Wavefront wf(test::device(), scene, a);
        render::LoopOptions lo;
        lo.spp = 64;
        render::LoopResult res = render::render_frames(wf, lo, nullptr);
        CHECK(res.frames == 64);
        std::vector<int> counts = wf.sample_counts();
        const auto& errs = wf.pixel_errors();
        int zero = 0, noisy_longer = 0;
        const int w = a.width, h = a.height;
        for (int p = 0; p < w * h; ++p) {
            bool quiet = true;  // zero variance over the 3x3 neighbourhood
            for (int yy = p / w - 1; yy <= p / w + 1; ++yy)
                for (int xx = p % w - 1; xx <= p % w + 1; ++xx)
                    if (xx >= 0 && xx < w && yy >= 0 && yy < h && errs[yy * w + xx] != 0.0f) quiet = false;
            if (quiet) {
                CHECK(counts[p] == 4);
                ++zero;
            } else {
                noisy_longer += counts[p] > 4;
            }
        }
        CHECK(zero > 50);
        CHECK(noisy_longer > 0);
    }
    a.adaptive.threshold = 1e3;  // every pixel stops at the first check
    render::Wavefront wf(test::device(), scene, a);
    render::LoopOptions lo;
    lo.spp = 1 << 20;
    render::LoopResult res = render::render_frames(wf, lo, nullptr);
    CHECK(res.converged);
    CHECK(res.frames == 4);
    CHECK(wf.active_pixels() == 0);
    CHECK(wf.mean_spp() == 4.0);
}

// Unbiased per pixel: the adaptive image z-tests against a non-adaptive render with 4x the
// most samples (variances of the means from each film: per-pixel counts for the adaptive
// one), on the built-in Cornell box and the veach plates.
TEST_CASE("adaptive: the image z-tests against a non-adaptive high-spp render",
          "[render][adaptive][stat]") {
    for (int which = 0; which < 2; ++which) {
        Scene scene = which == 0 ? make_cornell_box(2000) : make_veach_plates();
        INFO(scene.name);
        const int w = 32, h = 24;
        render::RenderSettings ref_s = small_settings(w, h, 101);
        ref_s.variance = true;
        render::Wavefront ref(test::device(), scene, ref_s);
        ref.render_passes(512);
        render::FilmMoments r = ref.moments();

        render::RenderSettings a = small_settings(w, h, 7);
        a.adaptive.enabled = true;
        a.adaptive.threshold = 3e-3;
        a.adaptive.min_spp = 16;
        render::Wavefront wf(test::device(), scene, a);
        render::LoopOptions lo;
        lo.spp = 128;
        render::render_frames(wf, lo, nullptr);
        render::FilmMoments m = wf.moments();
        CHECK(wf.mean_spp() < 0.9 * 128);  // it did adapt
        // The variance of each adaptive mean: the larger of its own estimate and the
        // reference's sample variance over the pixel's own count. (Not its own estimate
        // alone: a pixel stops because that estimate is small, so it is biased low at the
        // stop and would inflate z; not the reference's alone: a pixel that caught a rare
        // bright path the reference missed has a far larger variance than it says.)
        std::vector<int> counts = wf.sample_counts();
        Image var_a(w, h);
        for (std::size_t p = 0; p < counts.size(); ++p)
            for (int c = 0; c < 3; ++c)
                var_a.rgb[3 * p + c] = r.sample_variance.rgb[3 * p + c] / float(counts[p]);
        ZTest own = z_test(m.mean, r.mean, &m.mean_variance, &r.mean_variance, 0.01);
        UNSCOPED_INFO("with the pixels' own variances: pass fraction " << own.pass_fraction
                                                                      << ", max |z| " << own.max_abs_z);
        for (std::size_t i = 0; i < var_a.rgb.size(); ++i)
            var_a.rgb[i] = std::max(var_a.rgb[i], m.mean_variance.rgb[i]);
        ZTest z = z_test(m.mean, r.mean, &var_a, &r.mean_variance, 0.01);
        INFO("pass fraction " << z.pass_fraction << ", max |z| " << z.max_abs_z << " at ("
                              << z.max_x << ", " << z.max_y << ")");
        CHECK(z.pass_fraction >= 0.9975);
    }
}

// --target-error: the loop stops once the image's estimated relMSE (from its own variance)
// is <= the target; the true relMSE at that point, against an independent reference of many
// more samples less the reference's own noise (image/stats.h reference_relmse), is within a
// factor 1.5 of the estimate both ways, on the built-in box and the veach plates, over
// several seeds, with and without adaptive sampling, for independent samples (the random
// sampler: s^2/n) and for the default Owen-scrambled Sobol points with their default
// kDefaultReplicates RQMC replicates (the estimate from the replicate means; s^2/n
// overstates the error of stratified points, up to 2.7x here before replicates existed).
TEST_CASE("target error: the true relMSE at the stop is within 1.5x of the estimate",
          "[render][adaptive][stat]") {
    const int w = 64, h = 48;
    for (int which = 0; which < 2; ++which) {
        Scene scene = which == 0 ? make_cornell_box(2000) : make_veach_plates();
        // Targets that need more than a hundred samples (docs/adaptive.md: below, a light's
        // edge pixel that few samples have hit makes the estimate optimistic): the plates'
        // light pairs reach 4e-3 at 72 to 90 spp, 2.5e-3 at 140.
        const double target = which == 0 ? 3e-3 : 2.5e-3;
        render::RenderSettings ref_s = small_settings(w, h, 1001);
        ref_s.variance = true;
        render::Wavefront ref(test::device(), scene, ref_s);
        ref.render_passes(4096);
        render::FilmMoments r = ref.moments();
        const double ref_own = reference_relmse(r.mean, r.mean_variance);
        for (bool adaptive : {false, true})
          for (bool sobol : {false, true})
            for (std::uint32_t seed : {1u, 2u, 3u}) {
                render::RenderSettings s = small_settings(w, h, seed);
                s.estimator.sobol = sobol;
                s.replicates = sobol ? limits::kDefaultReplicates : 1;  // render's auto
                s.error_estimate = true;
                s.adaptive.enabled = adaptive;
                s.adaptive.threshold = target;
                render::Wavefront wf(test::device(), scene, s);
                render::LoopOptions lo;
                lo.spp = 4096;
                lo.target_error = target;
                render::LoopResult res = render::render_frames(wf, lo, nullptr);
                const double truth = compare_images(wf.resolve(), r.mean).relmse - ref_own;
                INFO(scene.name << (adaptive ? " adaptive" : "") << (sobol ? " sobol" : " random") << " seed " << seed << ": stopped at "
                                << res.frames << " spp, estimate " << res.estimated_error
                                << ", true " << truth << " (reference's own " << ref_own << ")");
                // WP_TEST_RATIOS=1 prints the measured ratios (docs/adaptive.md's table).
                if (std::getenv("WP_TEST_RATIOS"))
                    std::fprintf(stderr, "%s%s %s seed %u: %d spp, estimate %.3e, true %.3e, true/estimate %.2f\n",
                                 scene.name.c_str(), adaptive ? " adaptive" : "", sobol ? "sobol" : "random",
                                 seed, res.frames, res.estimated_error, truth, truth / res.estimated_error);
                CHECK(res.stopped_by_target);
                CHECK(res.estimated_error <= target);
                CHECK(res.frames >= 16);
                CHECK(res.frames % s.replicates == 0);
                CHECK(truth <= 1.5 * res.estimated_error);
                CHECK(truth >= res.estimated_error / 1.5);
                // The reference is good enough to tell.
                CHECK(ref_own < 0.2 * res.estimated_error);
            }
    }
}

// The command line: --target-error stops at its estimate (shown in the progress line and
// stored in the EXR header) without an spp total; --adaptive records its mean spp; bad
// values are usage errors that write nothing.
TEST_CASE("render CLI: --target-error and --adaptive", "[render][cli][adaptive]") {
    test::TempDir d;
    test::CliRun r = test::run_render(d.path, "--size 32x24 --target-error 1e-2 -o t.exr");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.find("est. relMSE") != std::string::npos);
    auto est = read_image_attribute(d.path / "t.exr", "wavepath:estimated_relmse");
    auto spp = read_image_attribute(d.path / "t.exr", "wavepath:spp");
    REQUIRE(est);
    REQUIRE(spp);
    CHECK(std::stod(*est) <= 1e-2);
    CHECK(std::stoi(*spp) >= limits::kDefaultMinSpp);
    CHECK(std::stoi(*spp) < 4096);
    // --target-error with the default (Sobol) sampler: 4 replicates, in the header, and the
    // estimates (so the stop) on multiples of 4.
    auto k = read_image_attribute(d.path / "t.exr", "wavepath:replicates");
    REQUIRE(k);
    CHECK(*k == std::to_string(limits::kDefaultReplicates));
    CHECK(std::stoi(*spp) % limits::kDefaultReplicates == 0);
    r = test::run_render(d.path, "--size 16x12 --target-error 1e-2 --sampler random -o rand.exr");
    REQUIRE(r.status == 0);
    CHECK(read_image_attribute(d.path / "rand.exr", "wavepath:replicates") == std::optional<std::string>("1"));
    // --replicates 0 is auto, explicitly.
    r = test::run_render(d.path, "--size 16x12 --target-error 1e-2 --replicates 0 -o auto.exr");
    REQUIRE(r.status == 0);
    CHECK(read_image_attribute(d.path / "auto.exr", "wavepath:replicates") == std::optional<std::string>("4"));
    r = test::run_render(d.path, "--size 16x12 --target-error 1e-2 --replicates 8 --profile p.json -o r8.exr");
    REQUIRE(r.status == 0);
    CHECK(read_image_attribute(d.path / "r8.exr", "wavepath:replicates") == std::optional<std::string>("8"));
    {
        std::ifstream pj(d.path / "p.json");
        std::stringstream ps;
        ps << pj.rdbuf();
        CHECK(ps.str().find("\"replicates\": 8") != std::string::npos);
    }
    // A plain render records none.
    r = test::run_render(d.path, "--size 16x12 --spp 2 -o plain.exr");
    REQUIRE(r.status == 0);
    CHECK(!read_image_attribute(d.path / "plain.exr", "wavepath:replicates"));

    // --adaptive with the feature buffers and the denoiser (the AOVs follow the active list).
    r = test::run_render(d.path, "--size 16x12 --adaptive --min-spp 4 --spp 16 --aov albedo --denoise -o ad.exr");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(std::filesystem::exists(d.path / "ad.exr"));
    CHECK(std::filesystem::exists(d.path / "ad.noisy.exr"));

    r = test::run_render(d.path, "--size 32x24 --adaptive --spp 64 -o a.exr");
    REQUIRE(r.status == 0);
    auto mean = read_image_attribute(d.path / "a.exr", "wavepath:mean_spp");
    REQUIRE(mean);
    CHECK(std::stod(*mean) < 64.0);
    CHECK(std::stod(*mean) >= limits::kDefaultMinSpp);

    for (const char* bad : {"--adaptive-threshold 1e-3", "--adaptive --adaptive-threshold 0",
                            "--adaptive --min-spp 1", "--target-error -1", "--target-error nan",
                            "--target-error 1e-2 --replicates 3", "--replicates -1",
                            "--replicates 128", "--target-error 1e-2 --replicates 65",
                            "--replicates x", "--replicates 4.5"}) {
        test::TempDir e;
        test::CliRun b = test::run_render(e.path, std::string("--size 8x6 --spp 4 ") + bad);
        INFO(bad << ": " << b.err);
        CHECK(b.status == 2);
        CHECK(e.empty_of_images());
    }
}

// converge takes adaptive configurations: the CSV's mean_spp column is the mean over pixels
// (below the most samples a pixel got, the spp column) for them, and equal to spp otherwise.
TEST_CASE("converge CLI: adaptive configurations side by side", "[cli][adaptive]") {
    test::TempDir d;
    const std::string cmd = "cd '" + d.path.string() + "' && '" WP_CLI_PATH
                            "' converge --time 0.3 --runs 1 --reference-spp 16 --csv c.csv -q "
                            "--config 'plain=--size 16x12' "
                            "--config 'adaptive=--size 16x12 --adaptive --min-spp 4 "
                            "--adaptive-threshold 1e-2' > out.txt 2> err.txt";
    REQUIRE(std::system(cmd.c_str()) == 0);
    std::ifstream in(d.path / "c.csv");
    std::string line;
    std::getline(in, line);
    CHECK(line == "configuration,run,seed,spp,seconds,rmse,relmse,mae,mean_spp");
    int plain = 0, adaptive = 0, adapted = 0;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
        REQUIRE(f.size() == 9);
        const double spp = std::stod(f[3]), mean = std::stod(f[8]);
        if (f[0] == "plain") {
            ++plain;
            CHECK(mean == spp);
        } else {
            ++adaptive;
            CHECK(mean <= spp);
            adapted += mean < spp;
        }
    }
    CHECK(plain > 0);
    CHECK(adaptive > 0);
    CHECK(adapted > 0);
    std::ifstream out(d.path / "out.txt");
    std::stringstream table;
    table << out.rdbuf();
    CHECK(table.str().find("(mean ") != std::string::npos);  // the adaptive row's mean spp
}
