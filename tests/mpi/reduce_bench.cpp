// reduce_bench.cpp — the cost of one film reduction (render/distributed.h) under mpirun:
// `mpirun -np N mpi_reduce_bench WIDTH HEIGHT [variance] [REPS]` reduces a film of that size
// (the sum, and with `variance` the sum of squares: 24 or 48 bytes a pixel) REPS times along
// the binomial tree and prints, on rank 0, the bytes each sending rank sends and the median
// and best time per reduction (docs/distributed.md). No device is involved.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "dist/comm.h"
#include "render/distributed.h"
#include "util/timer.h"

using namespace wp;

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: mpirun -np N mpi_reduce_bench WIDTH HEIGHT [variance] [REPS]\n");
        return 2;
    }
    dist::Comm& comm = dist::Comm::world();
    const int w = std::atoi(argv[1]), h = std::atoi(argv[2]);
    const bool variance = argc > 3 && std::string(argv[3]) == "variance";
    const int reps = argc > 4 ? std::atoi(argv[4]) : 10;
    render::FilmState st;
    st.width = w;
    st.height = h;
    st.passes = 1;
    st.arrays.push_back({"sum", std::vector<double>(3 * st.pixels(), 1.0 + comm.rank())});
    if (variance) st.arrays.push_back({"sum_sq", std::vector<double>(3 * st.pixels(), 2.0)});
    std::vector<double> ms;
    for (int i = 0; i < reps + 1; ++i) {
        render::FilmState s = st;
        comm.barrier();
        const double t = render::reduce_film_state(comm, s);
        comm.barrier();
        if (i > 0) ms.push_back(t);  // the first warms the transport
        if (comm.rank() == 0 && s.passes != comm.size()) {
            std::fprintf(stderr, "reduction lost passes: %lld\n", static_cast<long long>(s.passes));
            return 1;
        }
    }
    // The per-round status exchange: one 32-byte allgather per rank.
    render::RankStatus mine;
    std::vector<render::RankStatus> all(static_cast<std::size_t>(comm.size()));
    comm.barrier();
    Timer t;
    const int rounds = 1000;
    for (int i = 0; i < rounds; ++i) comm.allgather(&mine, sizeof mine, all.data());
    const double status_us = t.ms() * 1e3 / rounds;
    std::sort(ms.begin(), ms.end());
    if (comm.rank() == 0)
        std::printf("ranks %d film %dx%d%s: %zu bytes sent per rank, reduce median %.2f ms, best %.2f ms "
                    "(%.2f GB/s per link at the median); status allgather %.1f us\n",
                    comm.size(), w, h, variance ? " +variance" : "", st.array_bytes(), ms[ms.size() / 2],
                    ms.front(), double(st.array_bytes()) / (ms[ms.size() / 2] * 1e6), status_us);
    return 0;
}
