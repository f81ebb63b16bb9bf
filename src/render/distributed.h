// distributed.h — one render over several processes (MPI ranks): `mpirun -np N wavepath
// render ...` (docs/distributed.md).
//
// Samples. A render's samples are passes 0, 1, 2, ... of every pixel, and a sample's
// random numbers depend only on (seed, pixel, pass, bounce) (render/wavefront.h), so any
// process can take any pass. The loop runs in rounds: each round takes T more passes, cut
// into N contiguous blocks, rank r rendering the passes [base + first_r, base + first_r +
// count_r) into its own film (Wavefront::render_passes_from). The union over ranks and
// rounds is exactly passes 0 .. total - 1: the samples one process would take.
//
// Status. After each round every rank gives a 32-byte RankStatus in one MPI_Allgather (ok
// or failed and why, passes and rays so far, seconds, a stop vote). Every rank then takes
// the same decision from the same gathered bytes, rank 0's clock deciding --time: so the
// ranks stop together after the same round, and a rank that failed (bad device, out of
// memory, an exception in a stage) is seen by all at the same point. Its message then
// travels in a second gather, rank 0 prints it naming the rank, and every rank exits
// non-zero without writing anything. (A rank killed outright is mpirun's to report: it ends
// the job; rank 0 has written nothing by then, as it writes only after the last reduction.)
//
// Reduction. The films go to rank 0 along a fixed binomial tree (reduce_order): at step s =
// 1, 2, 4, ... rank r with r mod 2s == s sends to r - s, which adds what it receives to its
// own film. The adds are in double, element by element, in pieces of kReducePieceBytes, and
// their order depends only on N, so a run is repeatable to the bit. Against one process,
// which adds every sample into a double-float pair (~48 bits), the reduced sums differ by a
// few units of 2^-48 relative; the float image rounds those away except where a value lies
// that close to a rounding boundary: within 1 ulp of the one-process image (measured and
// tested: docs/distributed.md).
//
// --target-error: the estimate is of the reduced film: at each check the films are
// reduced, rank 0 loads the total and estimates (render/adaptive.h), the other ranks start
// from empty films, and rank 0's verdict goes out in one more status exchange.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dist/comm.h"
#include "render/film.h"
#include "render/loop.h"
#include "render/progress.h"
#include "render/wavefront.h"

namespace wp::render {

// Passes [first, first + count) of the round's `total` passes from `base` that rank `rank`
// of `ranks` renders: contiguous blocks in rank order, the first total % ranks ranks one
// more.
struct PassRange {
    std::int64_t first = 0;
    int count = 0;
};
PassRange split_passes(std::int64_t base, int total, int ranks, int rank);

// The binomial reduction tree: its steps in order, each a list of (from -> to) transfers.
struct ReduceTransfer {
    int from = 0, to = 0;
};
std::vector<std::vector<ReduceTransfer>> reduce_order(int ranks);

// What the tree gives rank 0, computed in one process over states[r] = rank r's film: the
// same adds in the same order as reduce_film_state (tests; docs/distributed.md).
FilmState reduce_in_tree_order(std::vector<FilmState> states);

// The status a rank gives after each round (32 bytes; all ranks get all).
struct RankStatus {
    std::int32_t state = 0;   // kRankOk, kRankFailed
    std::int32_t code = 0;    // exit code the failure asks for (1 error, 2 usage)
    std::int32_t passes = 0;  // passes this rank has rendered in all
    std::int32_t flags = 0;   // kStopVote, kTargetReached
    double seconds = 0.0;     // render time so far
    std::uint64_t rays = 0;   // rays this rank has traced in all
};
static_assert(sizeof(RankStatus) == 32);
inline constexpr std::int32_t kRankOk = 0, kRankFailed = 1;
inline constexpr std::int32_t kStopVote = 1, kTargetReached = 2;

// A failure of one or more ranks, as rank 0 words it. quiet on the other ranks (rank 0
// prints it).
struct RankFailure : Error {
    RankFailure(const std::string& what, int exit_code, bool quiet)
        : Error(what), exit_code(exit_code), quiet(quiet) {}
    int exit_code;
    bool quiet;
};

// The exchange after a protected step: every rank calls it with its own outcome (empty
// `error`: ok). When any rank failed, the messages are gathered and every rank throws
// RankFailure: rank 0's names the failed ranks and their causes (one message when all
// failed alike, e.g. a scene file that does not load), the others' is quiet. Else returns
// every rank's status.
std::vector<RankStatus> exchange_status(const dist::Comm& comm, RankStatus mine,
                                        const std::string& error);

// Every rank's `text` (cut to 127 bytes), in rank order, on every rank (a collective): the
// ranks' hosts and devices for the profile.
std::vector<std::string> gather_text(const dist::Comm& comm, const std::string& text);

// Runs `step` (which gives this rank's status) and reports its outcome through
// exchange_status: a wp::UsageError asks for exit code 2, every other exception 1
// (std::bad_alloc is named as running out of host memory, an OpenCL error by its code).
std::vector<RankStatus> protected_step(const dist::Comm& comm, const std::function<RankStatus()>& step);

// Test aid for the fault path (tests/mpi/mpi_test.cpp): WP_TEST_FAIL_RANK=R makes rank R fail
// its set-up, R@K its round K (1, 2, ...), as a device that fails would. Returns the round at
// which `rank` is to fail (0: the set-up), -1 for none.
int test_fail_round(int rank);

// The cost of the reductions of one render.
struct ReduceStats {
    int count = 0;
    std::uint64_t bytes = 0;   // film bytes each sending rank sent, per reduction
    double ms = 0.0;           // all reductions' tree time (transfers and adds), on rank 0
    double film_io_ms = 0.0;   // reading the film from the device and loading the total
};

// Reduces `state` onto rank 0 along reduce_order (a collective: every rank calls it); on
// rank 0 `state` becomes the total, on the others it is left as sent. Pieces of
// kReducePieceBytes. Returns the tree time in ms.
inline constexpr std::size_t kReducePieceBytes = std::size_t(16) << 20;
double reduce_film_state(const dist::Comm& comm, FilmState& state);

struct DistributedResult {
    LoopResult loop;                  // frames: the total passes of all ranks
    std::vector<RankStatus> ranks;    // the last status of every rank
    ReduceStats reduce;
    std::uint64_t rays = 0, shadow_rays = 0;  // all ranks' (rank 0: from the reduced film)
    std::uint64_t own_rays = 0, own_shadow_rays = 0;  // this rank's own
    int rounds = 0;
};

// The render loop of a distributed render (a collective): rounds as above until
// options.spp passes in all, rank 0's time reaching options.time_limit_s, the reduced
// estimate reaching options.target_error, or a stop vote (Ctrl-C). Checkpoints and
// after_step are not supported (the caller refuses what needs them). `progress` is rank
// 0's (null elsewhere). On return rank 0's Wavefront holds the reduced film (frames() =
// all passes), the others' their share. Throws RankFailure when a rank failed.
DistributedResult render_distributed(const dist::Comm& comm, Wavefront& wf, const LoopOptions& options,
                                     Progress* progress);

}  // namespace wp::render
