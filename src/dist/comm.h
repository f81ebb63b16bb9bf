// comm.h — the process group of a distributed render (MPI), and nothing else of MPI.
//
// comm.cpp is the only file that includes mpi.h. Built with WP_WITH_MPI (CMake finds MPI),
// Comm::world() is the MPI_COMM_WORLD of a job that mpirun (or srun, any PMI launcher)
// started; a process started without a launcher does not initialise MPI at all and is a
// group of one, so a plain `wavepath render` is exactly the single-process program. Built
// without MPI, every Comm is a group of one and the collectives are copies.
//
// Every collective here is blocking and must be called by every rank in the same order
// (render/distributed.h keeps that order: each rank catches its own failures and reports
// them in the next status exchange instead of leaving a collective).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace wp::dist {

class Comm {
  public:
    // The world group: initialises MPI on the first call when the process was started by
    // an MPI launcher (launched_by_mpi()); else a group of one. Not thread-safe; call it
    // from the main thread.
    static Comm& world();
    // True when the environment shows an MPI launcher (OMPI_COMM_WORLD_SIZE, PMI_SIZE,
    // PMIX_RANK) — read before MPI is initialised, e.g. to print a parse error once.
    static bool launched_by_mpi();
    // This process's rank from the launcher's environment (0 when none): for messages
    // printed before MPI is initialised.
    static int launcher_rank();
    // True when this build has MPI (WP_WITH_MPI).
    static bool built_with_mpi();

    int rank() const { return rank_; }
    int size() const { return size_; }
    // The rank among the processes of this node (MPI_Comm_split_type SHARED) and their
    // number: picks the OpenCL device on a node with several.
    int local_rank() const { return local_rank_; }
    int local_size() const { return local_size_; }
    // True when MPI was initialised (also for mpirun -np 1).
    bool mpi() const { return mpi_; }

    // Every rank gives `bytes` bytes; `all` receives size() * bytes, rank r's at r * bytes.
    void allgather(const void* mine, std::size_t bytes, void* all) const;
    // Point-to-point transfers of doubles and of bytes (the film reduction's tree).
    void send(int to, const double* data, std::size_t count, int tag) const;
    void recv(int from, double* data, std::size_t count, int tag) const;
    void send_bytes(int to, const void* data, std::size_t bytes, int tag) const;
    void recv_bytes(int from, void* data, std::size_t bytes, int tag) const;
    void barrier() const;
    // Ends every rank of the job (MPI_Abort); exits the process when there is no MPI.
    [[noreturn]] void abort(int code) const;
    // MPI_Finalize when MPI was initialised (idempotent). Called by the render command
    // before it returns, and at exit otherwise.
    void finalize();

  private:
    Comm() = default;
    int rank_ = 0, size_ = 1, local_rank_ = 0, local_size_ = 1;
    bool mpi_ = false, finalized_ = false;
};

}  // namespace wp::dist
