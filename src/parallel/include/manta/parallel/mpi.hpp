#pragma once
/// @file mpi.hpp
/// The MPI runtime of a process (docs/parallel.md). MPI is started only when the process was
/// launched by an MPI launcher (mpirun, mpiexec, srun with PMI), so that a plain `manta cfd`
/// never touches MPI and runs without an MPI runtime. The MPI headers stay in the module's .cpp
/// files: code that uses this header needs no MPI include path.

#include <memory>

#include "manta/parallel/communicator.hpp"

namespace manta::parallel {

/// True when the environment says an MPI launcher started this process (Open MPI's
/// OMPI_COMM_WORLD_SIZE, MPICH/Hydra's PMI_SIZE, or PMIx's PMIX_RANK is set).
[[nodiscard]] bool launched_by_mpi() noexcept;

/// Global reductions over MPI_COMM_WORLD with MPI_Allreduce. Constructed by `MpiEnvironment`;
/// valid while it lives. MPI failures throw NumericalError naming the call and MPI's message.
class MpiCommunicator final : public Communicator {
public:
    /// Wrap MPI_COMM_WORLD (MPI must be initialised) and make its errors return codes.
    MpiCommunicator();
    ~MpiCommunicator() override;
    MpiCommunicator(const MpiCommunicator&) = delete;
    MpiCommunicator& operator=(const MpiCommunicator&) = delete;

    [[nodiscard]] int rank() const override;
    [[nodiscard]] int size() const override;
    [[nodiscard]] double sum(double value) const override;
    [[nodiscard]] double max(double value) const override;
    [[nodiscard]] double min(double value) const override;
    void sum(std::span<double> values) const override;
    void barrier() const override;

private:
    int rank_ = 0;
    int size_ = 1;
};

/// Owns the MPI runtime of the process (RAII): the constructor calls MPI_Init_thread
/// (MPI_THREAD_FUNNELED: the process may use threads, but only the thread that made the
/// environment calls MPI) when
/// `launched_by_mpi()` and MPI is not yet initialised, the destructor MPI_Finalize if this
/// object initialised it. Make one, in `main`, before any parallel work, and keep it for the
/// life of the computation; everything holding its communicator must be gone before it is.
class MpiEnvironment {
public:
    /// Start MPI if launched by an MPI launcher (NumericalError if MPI_Init_thread fails).
    MpiEnvironment();
    ~MpiEnvironment();
    MpiEnvironment(const MpiEnvironment&) = delete;
    MpiEnvironment& operator=(const MpiEnvironment&) = delete;

    /// True when MPI is in use (launched by an MPI launcher), even with one process.
    [[nodiscard]] bool active() const noexcept { return active_; }
    /// The world communicator: an `MpiCommunicator` when active, else a `SerialCommunicator`.
    [[nodiscard]] const Communicator& communicator() const noexcept { return *communicator_; }

private:
    bool active_ = false;
    bool initialised_here_ = false;
    std::unique_ptr<Communicator> communicator_;
};

}  // namespace manta::parallel
