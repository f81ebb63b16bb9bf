// test_distributed.cpp — the parts of a distributed render that need no MPI
// (render/distributed.h): the pass split, the reduction order, the film state's round trip,
// and that films of disjoint pass ranges, added, give the one-process image within 1 ulp.
// The multi-process runs are CTest's mpi_render_np2/np3 and mpi_faults (tests/mpi/).
#include <catch2/catch.hpp>

#include <cmath>
#include <set>

#include "dist/comm.h"
#include "render/distributed.h"
#include "render/loop.h"
#include "render/wavefront.h"
#include "scene/builtin.h"
#include "support.h"

using namespace wp;

TEST_CASE("distributed: the pass split covers each round exactly once, in contiguous blocks", "[distributed]") {
    for (int ranks = 1; ranks <= 6; ++ranks)
        for (int total = 0; total <= 20; ++total) {
            const std::int64_t base = 1000;
            std::set<std::int64_t> seen;
            std::int64_t next = base;
            for (int r = 0; r < ranks; ++r) {
                const render::PassRange p = render::split_passes(base, total, ranks, r);
                CHECK(p.first == next);  // rank order, no gap
                CHECK(p.count >= total / ranks);
                CHECK(p.count <= total / ranks + 1);
                for (int k = 0; k < p.count; ++k) CHECK(seen.insert(p.first + k).second);
                next = p.first + p.count;
            }
            CHECK(seen.size() == std::size_t(total));
            CHECK(next == base + total);
        }
    CHECK_THROWS(render::split_passes(0, 4, 2, 2));
}

TEST_CASE("distributed: the binomial reduction tree", "[distributed]") {
    using Steps = std::vector<std::vector<std::pair<int, int>>>;
    auto pairs = [](int n) {
        Steps out;
        for (const auto& step : render::reduce_order(n)) {
            out.emplace_back();
            for (const auto& t : step) out.back().push_back({t.from, t.to});
        }
        return out;
    };
    CHECK(pairs(1).empty());
    CHECK(pairs(2) == Steps{{{1, 0}}});
    CHECK(pairs(3) == Steps{{{1, 0}}, {{2, 0}}});
    CHECK(pairs(4) == Steps{{{1, 0}, {3, 2}}, {{2, 0}}});
    CHECK(pairs(6) == Steps{{{1, 0}, {3, 2}, {5, 4}}, {{2, 0}}, {{4, 0}}});
    // Every rank but 0 sends once, after everything it receives.
    for (int n = 1; n <= 17; ++n) {
        std::vector<int> sent_at(std::size_t(n), -1), last_recv(std::size_t(n), -1);
        const auto steps = render::reduce_order(n);
        for (std::size_t s = 0; s < steps.size(); ++s)
            for (const auto& t : steps[s]) {
                CHECK(sent_at[std::size_t(t.from)] == -1);
                CHECK(sent_at[std::size_t(t.to)] == -1);
                sent_at[std::size_t(t.from)] = int(s);
                last_recv[std::size_t(t.to)] = int(s);
            }
        CHECK(sent_at[0] == -1);
        for (int r = 1; r < n; ++r) {
            CHECK(sent_at[std::size_t(r)] >= 0);
            CHECK(last_recv[std::size_t(r)] < sent_at[std::size_t(r)]);
        }
    }
}

namespace {

render::FilmState one_value_state(double v, std::int64_t passes) {
    render::FilmState s;
    s.width = 1;
    s.height = 1;
    s.passes = passes;
    s.rays = 10 * passes;
    s.shadow_rays = passes;
    s.counters[0] = passes;
    s.arrays.push_back({"sum", {v, 2 * v, 0.5}});
    s.arrays.push_back({"sum_sq", {v * v, 1.0, 0.25}});
    return s;
}

}  // namespace

TEST_CASE("distributed: the tree adds in its fixed order ((r0 + r1) + (r2 + r3))", "[distributed]") {
    // Values whose sum depends on the order: the tree's order is checked, not just a sum.
    const double a = 1.0, b = 1e16, c = -1e16, d = 1.0;
    volatile double ab = a + b, cd = c + d;
    const double tree = ab + cd;
    volatile double seq1 = a + b;
    volatile double seq2 = seq1 + c;
    const double sequential = seq2 + d;
    REQUIRE(tree != sequential);  // else this test would not see the order
    const render::FilmState r = render::reduce_in_tree_order(
        {one_value_state(a, 1), one_value_state(b, 2), one_value_state(c, 3), one_value_state(d, 4)});
    CHECK(r.arrays[0].values[0] == tree);
    CHECK(r.passes == 10);
    CHECK(r.rays == 100);
    CHECK(r.shadow_rays == 10);
    CHECK(r.counters[0] == 10);
    CHECK(r.arrays[0].values[2] == 2.0);
    CHECK(r.arrays[1].values[2] == 1.0);
    // Mismatched layouts are refused.
    render::FilmState bad = one_value_state(1.0, 1);
    bad.arrays.pop_back();
    CHECK_THROWS_AS(render::reduce_in_tree_order({one_value_state(1.0, 1), bad}), Error);
}

TEST_CASE("distributed: double-float pixels to doubles and back", "[distributed]") {
    // hi + lo with lo below hi's ulp: the double holds both words; back, the pair is the
    // double rounded (hi) and its remainder (lo), whose value is the double again.
    FilmPixel p{};
    p.sum = float4{1.0f, 3.0e6f, 0.0f, 0.0f};
    p.comp = float4{std::ldexp(1.0f, -30), -0.125f, 0.0f, 0.0f};
    double d[3];
    render::film_pixels_to_doubles(&p, 1, d);
    CHECK(d[0] == 1.0 + std::ldexp(1.0, -30));
    CHECK(d[1] == 3.0e6 - 0.125);
    CHECK(d[2] == 0.0);
    FilmPixel q{};
    render::doubles_to_film_pixels(d, 1, &q);
    double e[3];
    render::film_pixels_to_doubles(&q, 1, e);
    for (int c = 0; c < 3; ++c) CHECK(e[c] == d[c]);
    CHECK(q.sum.w == 0.0f);
    CHECK(q.comp.w == 0.0f);
}

namespace {

render::RenderSettings small_settings(bool variance) {
    render::RenderSettings s;
    s.width = 24;
    s.height = 18;
    s.depth = 3;
    s.seed = 5;
    s.variance = variance;
    return s;
}

float ulp_of(float x) {
    x = std::fabs(x);
    return std::nextafter(x, INFINITY) - x;
}

}  // namespace

TEST_CASE("distributed: a film state saved and loaded gives the same image", "[distributed]") {
    const Scene scene = make_cornell_box(200);
    render::Wavefront a(test::device(), scene, small_settings(true));
    a.render_passes(6);
    const render::FilmState st = a.save_film_state();
    CHECK(st.passes == 6);
    REQUIRE(st.arrays.size() == 2);
    CHECK(st.arrays[0].name == "sum");
    CHECK(st.arrays[1].name == "sum_sq");
    CHECK(st.rays == a.ray_totals().closest);
    render::Wavefront b(test::device(), scene, small_settings(true));
    b.load_film_state(st);
    CHECK(b.frames() == 6);
    const Image ia = a.resolve(), ib = b.resolve();
    CHECK(ia.rgb == ib.rgb);
    const render::FilmMoments ma = a.moments(), mb = b.moments();
    CHECK(ma.mean_variance.rgb == mb.mean_variance.rgb);
    // A film without variance does not take a state with it.
    render::Wavefront c(test::device(), scene, small_settings(false));
    CHECK_THROWS_AS(c.load_film_state(st), Error);
}

TEST_CASE("distributed: disjoint pass ranges, added in tree order, give one process's image within 1 ulp",
          "[distributed]") {
    const Scene scene = make_cornell_box(200);
    const int total = 11;
    render::Wavefront one(test::device(), scene, small_settings(true));
    one.render_passes(total);
    const Image ref = one.resolve();
    for (int ranks : {2, 3, 4}) {
        std::vector<render::FilmState> states;
        for (int r = 0; r < ranks; ++r) {
            render::Wavefront w(test::device(), scene, small_settings(true));
            // Two rounds, as render_distributed takes them: 5 passes, then 6.
            for (auto [base, count] : {std::pair{0, 5}, std::pair{5, 6}}) {
                const render::PassRange p = render::split_passes(base, count, ranks, r);
                if (p.count > 0) w.render_passes_from(p.first, p.count);
            }
            states.push_back(w.save_film_state());
        }
        render::Wavefront sum(test::device(), scene, small_settings(true));
        sum.load_film_state(render::reduce_in_tree_order(states));
        REQUIRE(sum.frames() == total);
        CHECK(sum.ray_totals().closest == one.ray_totals().closest);  // the same samples
        const Image img = sum.resolve();
        long differ = 0;
        double worst = 0.0;
        for (std::size_t i = 0; i < img.rgb.size(); ++i) {
            differ += img.rgb[i] != ref.rgb[i];
            worst = std::max(worst, std::fabs(double(img.rgb[i]) - ref.rgb[i]) /
                                        std::max(ulp_of(img.rgb[i]), ulp_of(ref.rgb[i])));
        }
        INFO(ranks << " ranks: " << differ << " values differ, largest " << worst << " ulp");
        CHECK(worst <= 1.0);
    }
}

TEST_CASE("distributed: without a launcher the world is one process", "[distributed]") {
    dist::Comm& c = dist::Comm::world();
    if (dist::Comm::launched_by_mpi()) {
        WARN("SKIP: run under an MPI launcher");
        return;
    }
    CHECK(c.size() == 1);
    CHECK(c.rank() == 0);
    CHECK(c.local_rank() == 0);
    CHECK_FALSE(c.mpi());
    int mine = 7, all = 0;
    c.allgather(&mine, sizeof mine, &all);
    CHECK(all == 7);
}
