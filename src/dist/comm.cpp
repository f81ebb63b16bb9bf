#include "dist/comm.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "util/error.h"

#ifdef WP_HAVE_MPI
// The C API only (the C++ bindings are deprecated and warn).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace wp::dist {

namespace {

const char* env(const char* name) {
    const char* v = std::getenv(name);
    return v && *v ? v : nullptr;
}

#ifdef WP_HAVE_MPI
// MPI counts are int: transfers of more are cut into pieces of at most this many elements.
constexpr std::size_t kMaxCount = std::size_t(std::numeric_limits<int>::max()) / 16;

void check(int rc, const char* what) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int len = 0;
    MPI_Error_string(rc, text, &len);
    fail("MPI {} failed: {}", what, std::string(text, static_cast<std::size_t>(len)));
}
#endif

}  // namespace

bool Comm::built_with_mpi() {
#ifdef WP_HAVE_MPI
    return true;
#else
    return false;
#endif
}

bool Comm::launched_by_mpi() {
    return env("OMPI_COMM_WORLD_SIZE") || env("PMI_SIZE") || env("PMIX_RANK") || env("PMI_RANK");
}

int Comm::launcher_rank() {
    for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
        if (const char* v = env(name)) return std::atoi(v);
    return 0;
}

Comm& Comm::world() {
    static Comm* w = [] {
        auto* c = new Comm();
#ifdef WP_HAVE_MPI
        if (launched_by_mpi()) {
            int provided = 0;
            check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init");
            // Errors come back as codes (check() turns them into wp::Error) rather than
            // aborting inside the library.
            MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
            c->mpi_ = true;
            MPI_Comm_rank(MPI_COMM_WORLD, &c->rank_);
            MPI_Comm_size(MPI_COMM_WORLD, &c->size_);
            MPI_Comm node;
            check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, c->rank_, MPI_INFO_NULL, &node),
                  "MPI_Comm_split_type");
            MPI_Comm_rank(node, &c->local_rank_);
            MPI_Comm_size(node, &c->local_size_);
            MPI_Comm_free(&node);
            std::atexit([] { Comm::world().finalize(); });
        }
#endif
        return c;
    }();
    return *w;
}

void Comm::allgather(const void* mine, std::size_t bytes, void* all) const {
#ifdef WP_HAVE_MPI
    if (mpi_) {
        check(MPI_Allgather(mine, static_cast<int>(bytes), MPI_BYTE, all, static_cast<int>(bytes), MPI_BYTE,
                            MPI_COMM_WORLD),
              "MPI_Allgather");
        return;
    }
#endif
    std::memcpy(all, mine, bytes);
}

void Comm::send(int to, const double* data, std::size_t count, int tag) const {
#ifdef WP_HAVE_MPI
    for (std::size_t k = 0; k < count; k += kMaxCount) {
        const int n = static_cast<int>(std::min(kMaxCount, count - k));
        check(MPI_Send(data + k, n, MPI_DOUBLE, to, tag, MPI_COMM_WORLD), "MPI_Send");
    }
#else
    (void)to, (void)data, (void)count, (void)tag;
    fail("send: this build has no MPI");
#endif
}

void Comm::recv(int from, double* data, std::size_t count, int tag) const {
#ifdef WP_HAVE_MPI
    for (std::size_t k = 0; k < count; k += kMaxCount) {
        const int n = static_cast<int>(std::min(kMaxCount, count - k));
        check(MPI_Recv(data + k, n, MPI_DOUBLE, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE), "MPI_Recv");
    }
#else
    (void)from, (void)data, (void)count, (void)tag;
    fail("recv: this build has no MPI");
#endif
}

void Comm::send_bytes(int to, const void* data, std::size_t bytes, int tag) const {
#ifdef WP_HAVE_MPI
    check(MPI_Send(data, static_cast<int>(bytes), MPI_BYTE, to, tag, MPI_COMM_WORLD), "MPI_Send");
#else
    (void)to, (void)data, (void)bytes, (void)tag;
    fail("send: this build has no MPI");
#endif
}

void Comm::recv_bytes(int from, void* data, std::size_t bytes, int tag) const {
#ifdef WP_HAVE_MPI
    check(MPI_Recv(data, static_cast<int>(bytes), MPI_BYTE, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
          "MPI_Recv");
#else
    (void)from, (void)data, (void)bytes, (void)tag;
    fail("recv: this build has no MPI");
#endif
}

void Comm::barrier() const {
#ifdef WP_HAVE_MPI
    if (mpi_) check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
#endif
}

void Comm::abort(int code) const {
#ifdef WP_HAVE_MPI
    if (mpi_) MPI_Abort(MPI_COMM_WORLD, code);
#endif
    std::_Exit(code);
}

void Comm::finalize() {
#ifdef WP_HAVE_MPI
    if (mpi_ && !finalized_) {
        finalized_ = true;
        int done = 0;
        MPI_Finalized(&done);
        if (!done) MPI_Finalize();
    }
#endif
}

}  // namespace wp::dist
