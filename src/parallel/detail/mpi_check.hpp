#pragma once
/// @file mpi_check.hpp
/// Private to the parallel module: turning MPI return codes into MANTA errors, and telling
/// whether a communicator is the MPI one. Includes <mpi.h>; never include from a public header.

#include <mpi.h>

#include "manta/parallel/communicator.hpp"

namespace manta::parallel::detail {

/// Throw NumericalError "MPI: <call> failed: <MPI's message>" unless rc is MPI_SUCCESS.
void mpi_check(int rc, const char* call);

/// True when `comm` is an MpiCommunicator (reductions and messages go through MPI_COMM_WORLD).
[[nodiscard]] bool is_mpi(const Communicator& comm) noexcept;

/// Largest element count one MPI call takes (its count argument is an int); NumericalError naming
/// `what` if `n` exceeds it.
[[nodiscard]] int mpi_count(std::size_t n, const char* what);

}  // namespace manta::parallel::detail
