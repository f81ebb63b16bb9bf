#include "render/distributed.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <new>

#include <CL/opencl.hpp>

#include "util/error.h"
#include "util/host_trace.h"
#include "util/timer.h"

namespace wp::render {

PassRange split_passes(std::int64_t base, int total, int ranks, int rank) {
    if (ranks < 1 || rank < 0 || rank >= ranks || total < 0)
        fail("split_passes: rank {} of {} with {} passes", rank, ranks, total);
    const int q = total / ranks, extra = total % ranks;
    PassRange r;
    r.count = q + (rank < extra ? 1 : 0);
    r.first = base + std::int64_t(rank) * q + std::min(rank, extra);
    return r;
}

std::vector<std::vector<ReduceTransfer>> reduce_order(int ranks) {
    std::vector<std::vector<ReduceTransfer>> steps;
    for (int s = 1; s < ranks; s <<= 1) {
        std::vector<ReduceTransfer> step;
        for (int to = 0; to + s < ranks; to += 2 * s) step.push_back({to + s, to});
        steps.push_back(std::move(step));
    }
    return steps;
}

FilmState reduce_in_tree_order(std::vector<FilmState> states) {
    if (states.empty()) fail("reduce_in_tree_order: no states");
    for (const auto& step : reduce_order(static_cast<int>(states.size())))
        for (const auto& t : step) add_film_state(states[std::size_t(t.to)], states[std::size_t(t.from)]);
    return std::move(states[0]);
}

namespace {

constexpr std::size_t kMessageBytes = 480;  // a failure's text in the second gather
constexpr int kTagHeader = 101, kTagArray = 102;

// The non-array part of a film state on the wire.
struct StateHeader {
    std::int64_t passes = 0;
    std::uint64_t rays = 0, shadow_rays = 0;
    std::int64_t counters[WP_COUNTER_COUNT] = {};
    std::uint64_t values = 0;  // doubles in all arrays (a consistency check)
};

}  // namespace

std::vector<RankStatus> exchange_status(const dist::Comm& comm, RankStatus mine, const std::string& error) {
    if (!error.empty()) mine.state = kRankFailed;
    std::vector<RankStatus> all(static_cast<std::size_t>(comm.size()));
    comm.allgather(&mine, sizeof mine, all.data());
    bool failed = false;
    for (const auto& s : all) failed = failed || s.state != kRankOk;
    if (!failed) return all;
    // Every rank saw the failure in the same exchange: the messages follow in one more.
    char text[kMessageBytes] = {};
    std::strncpy(text, error.c_str(), kMessageBytes - 1);
    std::vector<char> texts(kMessageBytes * all.size());
    comm.allgather(text, kMessageBytes, texts.data());
    int code = 1;
    std::vector<int> ranks;
    std::vector<std::string> msgs;
    for (std::size_t r = 0; r < all.size(); ++r)
        if (all[r].state != kRankOk) {
            ranks.push_back(static_cast<int>(r));
            msgs.emplace_back(texts.data() + r * kMessageBytes,
                              strnlen(texts.data() + r * kMessageBytes, kMessageBytes));
            code = std::max(code, static_cast<int>(all[r].code));
        }
    std::string what;
    const bool alike = ranks.size() == all.size() &&
                       std::all_of(msgs.begin(), msgs.end(), [&](const std::string& m) { return m == msgs[0]; });
    if (alike) {
        what = msgs[0];  // every rank failed alike (e.g. the scene): said once
    } else {
        for (std::size_t i = 0; i < ranks.size(); ++i)
            what += fmt::format("{}rank {} of {} failed: {}", i ? "; " : "", ranks[i], all.size(), msgs[i]);
        what += " (nothing was written)";
    }
    throw RankFailure(what, code, comm.rank() != 0);
}

std::vector<std::string> gather_text(const dist::Comm& comm, const std::string& text) {
    constexpr std::size_t kBytes = 128;
    char mine[kBytes] = {};
    std::strncpy(mine, text.c_str(), kBytes - 1);
    std::vector<char> all(kBytes * std::size_t(comm.size()));
    comm.allgather(mine, kBytes, all.data());
    std::vector<std::string> out;
    for (int r = 0; r < comm.size(); ++r)
        out.emplace_back(all.data() + std::size_t(r) * kBytes, strnlen(all.data() + std::size_t(r) * kBytes, kBytes));
    return out;
}

std::vector<RankStatus> protected_step(const dist::Comm& comm, const std::function<RankStatus()>& step) {
    RankStatus mine;
    std::string error;
    try {
        mine = step();
    } catch (const UsageError& e) {
        error = e.what();
        mine.code = 2;
    } catch (const Error& e) {
        error = e.what();
        mine.code = 1;
    } catch (const ::cl::Error& e) {
        error = fmt::format("OpenCL error {} in {}", e.err(), e.what());
        mine.code = 1;
    } catch (const std::bad_alloc&) {
        error = "out of host memory";
        mine.code = 1;
    } catch (const std::exception& e) {
        error = e.what();
        mine.code = 1;
    }
    if (!error.empty() && error.size() >= kMessageBytes) error = error.substr(0, kMessageBytes - 4) + "...";
    return exchange_status(comm, mine, error);
}

double reduce_film_state(const dist::Comm& comm, FilmState& state) {
    Timer t;
    const int me = comm.rank();
    StateHeader h;
    h.passes = state.passes;
    h.rays = state.rays;
    h.shadow_rays = state.shadow_rays;
    std::copy(state.counters.begin(), state.counters.end(), h.counters);
    for (const auto& a : state.arrays) h.values += a.values.size();
    const std::size_t piece = kReducePieceBytes / sizeof(double);
    std::vector<double> buf;
    for (const auto& step : reduce_order(comm.size()))
        for (const auto& tr : step) {
            if (tr.from == me) {
                comm.send_bytes(tr.to, &h, sizeof h, kTagHeader);
                for (const auto& a : state.arrays)
                    for (std::size_t k = 0; k < a.values.size(); k += piece)
                        comm.send(tr.to, a.values.data() + k, std::min(piece, a.values.size() - k), kTagArray);
                return t.ms();  // this rank's part is done
            }
            if (tr.to == me) {
                StateHeader in;
                comm.recv_bytes(tr.from, &in, sizeof in, kTagHeader);
                if (in.values != h.values)
                    fail("reduce: rank {} sent {} film values, rank {} holds {}", tr.from, in.values, me, h.values);
                buf.resize(std::min<std::size_t>(piece, std::max<std::uint64_t>(h.values, 1)));
                for (auto& a : state.arrays)
                    for (std::size_t k = 0; k < a.values.size(); k += piece) {
                        const std::size_t n = std::min(piece, a.values.size() - k);
                        comm.recv(tr.from, buf.data(), n, kTagArray);
                        double* d = a.values.data() + k;
                        for (std::size_t i = 0; i < n; ++i) d[i] += buf[i];
                    }
                h.passes += in.passes;
                h.rays += in.rays;
                h.shadow_rays += in.shadow_rays;
                for (int c = 0; c < WP_COUNTER_COUNT; ++c) h.counters[c] += in.counters[c];
            }
        }
    state.passes = h.passes;
    state.rays = h.rays;
    state.shadow_rays = h.shadow_rays;
    std::copy(std::begin(h.counters), std::end(h.counters), state.counters.begin());
    return t.ms();
}

int test_fail_round(int rank) {
    const char* v = std::getenv("WP_TEST_FAIL_RANK");
    if (!v || !*v) return -1;
    const std::string s = v;
    const auto at = s.find('@');
    if (std::atoi(s.substr(0, at).c_str()) != rank) return -1;
    return at == std::string::npos ? 0 : std::max(1, std::atoi(s.substr(at + 1).c_str()));
}

namespace {

// A state of the same layout with every sum, count and total zero.
FilmState zero_like(const FilmState& s) {
    FilmState z;
    z.width = s.width;
    z.height = s.height;
    for (const auto& a : s.arrays) z.arrays.push_back({a.name, std::vector<double>(a.values.size(), 0.0)});
    return z;
}

double kernel_ms(const ocl::Profiler& p) {
    double ms = 0.0;
    for (const auto& t : p.totals()) ms += t.total_ms;
    return ms;
}

}  // namespace

DistributedResult render_distributed(const dist::Comm& comm, Wavefront& wf, const LoopOptions& o,
                                     Progress* progress) {
    DistributedResult r;
    LoopResult& res = r.loop;
    const int N = comm.size(), me = comm.rank();
    Timer timer;
    const double kernel_ms_before = kernel_ms(wf.profiler());
    const bool target = o.target_error > 0.0;
    std::int64_t base = 0;          // passes of all ranks so far
    int mine = 0;                   // passes this rank rendered
    // Rays: this rank's in films already reduced, and what its film held when it was
    // (re)loaded (rank 0: the total; others: 0).
    Wavefront::RayTotals done_rays, loaded_rays;
    std::int64_t reduced_at = -1;   // base at the latest reduction (rank 0 holds the total)
    const int replicates = wf.settings().replicates;  // estimates on multiples of it (RQMC)
    std::int64_t next_estimate = next_error_check(1, o.min_spp, replicates);
    std::int64_t estimated_at = -1;
    std::uint64_t total_rays = 0;
    const int fail_round = test_fail_round(me);
    auto own_rays = [&] {
        const auto t = wf.ray_totals();
        return Wavefront::RayTotals{done_rays.closest + t.closest - loaded_rays.closest,
                                    done_rays.shadow + t.shadow - loaded_rays.shadow};
    };
    // The films onto rank 0, which loads the total; the others start again from empty films
    // (not after the last reduction: they are done).
    auto reduce = [&](bool last) {
        FilmState st;
        Timer io;
        protected_step(comm, [&] {
            st = wf.save_film_state();
            const auto t = own_rays();
            done_rays = t;
            return RankStatus{};
        });
        double io_ms = io.ms();
        // A transfer that fails leaves its partner waiting in the tree: no status exchange
        // can follow, so the job ends here, from this rank, naming it.
        try {
            r.reduce.ms += reduce_film_state(comm, st);
        } catch (const std::exception& e) {
            fmt::print(stderr, "wavepath: error: rank {} of {}: the film reduction failed: {} (ending the job)\n",
                       me, N, e.what());
            comm.abort(1);
        }
        r.reduce.count += 1;
        r.reduce.bytes = st.array_bytes() + sizeof(StateHeader);
        io.reset();
        protected_step(comm, [&] {
            if (me == 0) {
                wf.load_film_state(st);
                loaded_rays = {st.rays, st.shadow_rays};
            } else if (!last) {
                wf.load_film_state(zero_like(st));
                loaded_rays = {};
            }
            return RankStatus{};
        });
        r.reduce.film_io_ms += io_ms + io.ms();
        reduced_at = base;
    };

    while (base < o.spp) {
        const std::int64_t per_wave = std::max(1, wf.passes_per_wave());
        std::int64_t T = std::min({std::int64_t(N) * per_wave, std::max<std::int64_t>(N, base),
                                   std::int64_t(o.spp) - base});
        if (target) T = std::max<std::int64_t>(1, std::min(T, next_estimate - base));
        const PassRange pr = split_passes(base, static_cast<int>(T), N, me);
        const double round_start = timer.seconds();
        r.ranks = protected_step(comm, [&] {
            if (fail_round > 0 && r.rounds + 1 == fail_round)
                fail("WP_TEST_FAIL_RANK: rank {} was told to fail in round {}", me, fail_round);
            if (pr.count > 0)
                wf.render_passes_from(pr.first, pr.count, [&](double part) {
                    if (progress && progress->due())
                        progress->update(double(base) + part * double(T) / pr.count, total_rays);
                });
            wf.device().queue.finish();
            wf.profiler().resolve();
            mine += pr.count;
            RankStatus st;
            st.passes = mine;
            st.seconds = timer.seconds();
            const auto t = own_rays();
            st.rays = t.closest + t.shadow;
            if (o.should_stop && o.should_stop()) st.flags |= kStopVote;
            return st;
        });
        base += T;
        r.rounds += 1;
        total_rays = 0;
        bool stop_vote = false;
        for (const auto& s : r.ranks) {
            total_rays += s.rays;
            stop_vote = stop_vote || (s.flags & kStopVote);
        }
        if (res.first_frame_done_ns == 0) {
            res.first_frame_done_ns = steady_ns();
            res.first_frame_ms = timer.ms();
            res.first_frame_kernel_ms = kernel_ms(wf.profiler()) - kernel_ms_before;
        }
        if (progress) {
            progress->step(double(T), timer.seconds() - round_start);
            if (progress->due()) progress->update(double(base), total_rays);
        }
        if (target && base >= next_estimate) {
            reduce(false);
            double estimate = 0.0;
            const auto verdict = protected_step(comm, [&] {
                RankStatus st = r.ranks[std::size_t(me)];
                if (me == 0) {
                    estimate = wf.estimate_error();
                    if (estimate <= o.target_error) st.flags |= kTargetReached;
                }
                return st;
            });
            estimated_at = base;
            next_estimate = next_error_check(base + 1, o.min_spp, replicates);
            if (me == 0) {
                res.estimated_error = estimate;
                if (o.on_estimate) o.on_estimate(estimate);
            }
            if (verdict[0].flags & kTargetReached) {
                res.stopped_by_target = true;
                break;
            }
        }
        if (stop_vote && base < o.spp) {
            res.interrupted = true;
            break;
        }
        if (o.time_limit_s > 0.0 && r.ranks[0].seconds >= o.time_limit_s && base < o.spp) {
            res.stopped_by_time = true;
            break;
        }
    }
    if (reduced_at != base) reduce(true);
    if (me == 0 && target && estimated_at != base && base >= 2) {
        res.estimated_error = wf.estimate_error();
        if (o.on_estimate) o.on_estimate(res.estimated_error);
    }
    wf.device().queue.finish();
    wf.profiler().resolve();
    res.frames = static_cast<int>(base);
    res.render_s = timer.seconds();
    res.wall_s = res.render_s;
    const auto t = wf.ray_totals();
    r.rays = t.closest;
    r.shadow_rays = t.shadow;
    // The last reduction took this rank's rays into done_rays (its film is not reloaded).
    r.own_rays = done_rays.closest;
    r.own_shadow_rays = done_rays.shadow;
    return r;
}

}  // namespace wp::render
