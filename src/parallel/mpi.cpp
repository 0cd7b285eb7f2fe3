/// @file mpi.cpp
/// MpiEnvironment and MpiCommunicator (mpi.hpp): the only place MPI is started and stopped.

#include "manta/parallel/mpi.hpp"

#include <fmt/format.h>
#include <mpi.h>

#include <climits>
#include <cstdlib>
#include <string>

#include "detail/mpi_check.hpp"
#include "manta/core/error.hpp"

namespace manta::parallel {

namespace detail {

void mpi_check(int rc, const char* call) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING] = {};
    int len = 0;
    if (MPI_Error_string(rc, text, &len) != MPI_SUCCESS) len = 0;
    throw NumericalError(fmt::format("MPI: {} failed with error {}: {}", call, rc,
                                     len > 0 ? std::string(text, len) : "(no message)"));
}

bool is_mpi(const Communicator& comm) noexcept {
    return dynamic_cast<const MpiCommunicator*>(&comm) != nullptr;
}

int mpi_count(std::size_t n, const char* what) {
    if (n > static_cast<std::size_t>(INT_MAX))
        throw NumericalError(fmt::format(
            "MPI: {} needs {} elements in one message; expected at most {} (use more processes)",
            what, n, INT_MAX));
    return static_cast<int>(n);
}

}  // namespace detail

bool launched_by_mpi() noexcept {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (std::getenv(v) != nullptr) return true;
    return false;
}

MpiCommunicator::MpiCommunicator() {
    // Errors come back as codes (then NumericalError) instead of aborting every process.
    detail::mpi_check(MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN),
                      "MPI_Comm_set_errhandler");
    detail::mpi_check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
    detail::mpi_check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
}

MpiCommunicator::~MpiCommunicator() = default;

int MpiCommunicator::rank() const {
    return rank_;
}

int MpiCommunicator::size() const {
    return size_;
}

namespace {

double all_reduce(double value, MPI_Op op, const char* what) {
    double out = 0.0;
    detail::mpi_check(MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, op, MPI_COMM_WORLD), what);
    return out;
}

}  // namespace

double MpiCommunicator::sum(double value) const {
    return all_reduce(value, MPI_SUM, "MPI_Allreduce (sum)");
}

double MpiCommunicator::max(double value) const {
    return all_reduce(value, MPI_MAX, "MPI_Allreduce (max)");
}

double MpiCommunicator::min(double value) const {
    return all_reduce(value, MPI_MIN, "MPI_Allreduce (min)");
}

void MpiCommunicator::sum(std::span<double> values) const {
    if (values.empty()) return;
    detail::mpi_check(
        MPI_Allreduce(MPI_IN_PLACE, values.data(), detail::mpi_count(values.size(), "a vector sum"),
                      MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD),
        "MPI_Allreduce (vector sum)");
}

void MpiCommunicator::barrier() const {
    detail::mpi_check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
}

MpiEnvironment::MpiEnvironment() {
    if (launched_by_mpi()) {
        int done = 0;
        detail::mpi_check(MPI_Initialized(&done), "MPI_Initialized");
        if (!done) {
            // Funneled: threads may run between MPI calls, which the creating thread makes.
            int provided = 0;
            detail::mpi_check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided),
                              "MPI_Init_thread");
            initialised_here_ = true;
        }
        active_ = true;
        try {
            communicator_ = std::make_unique<MpiCommunicator>();
        } catch (...) {
            if (initialised_here_) MPI_Finalize();
            throw;
        }
    } else {
        communicator_ = std::make_unique<SerialCommunicator>();
    }
}

MpiEnvironment::~MpiEnvironment() {
    communicator_.reset();
    if (initialised_here_) {
        int finalized = 0;
        MPI_Finalized(&finalized);
        if (!finalized) MPI_Finalize();
    }
}

}  // namespace manta::parallel
