#pragma once
/// @file communicator.hpp
/// The parallel context of a distributed computation: global reductions across processes and
/// the halo exchange of node data between neighbouring partitions (docs/parallel.md).
///
/// A partition-local mesh numbers its nodes so that the nodes this process owns come first,
/// [0, n_owned), and the ghost copies of nodes owned by other processes follow,
/// [n_owned, n_local). A halo exchange copies every owned value to the ghost copies of it held
/// by other processes. The serial implementations do nothing, so a solver written against these
/// interfaces runs unchanged with one process and without MPI.

#include <memory>
#include <span>

namespace manta::parallel {

/// Global reductions over the processes of a computation.
class Communicator {
public:
    virtual ~Communicator() = default;
    /// This process's number in [0, size()).
    [[nodiscard]] virtual int rank() const = 0;
    /// Number of processes.
    [[nodiscard]] virtual int size() const = 0;
    /// Sum of `value` over all processes (every process gets the result).
    [[nodiscard]] virtual double sum(double value) const = 0;
    /// Largest `value` over all processes.
    [[nodiscard]] virtual double max(double value) const = 0;
    /// Smallest `value` over all processes.
    [[nodiscard]] virtual double min(double value) const = 0;
    /// Element-wise sum of `values` over all processes, in place.
    virtual void sum(std::span<double> values) const = 0;
    /// Wait for every process.
    virtual void barrier() const = 0;
};

/// One process: every reduction returns its argument.
class SerialCommunicator final : public Communicator {
public:
    [[nodiscard]] int rank() const override { return 0; }
    [[nodiscard]] int size() const override { return 1; }
    [[nodiscard]] double sum(double value) const override { return value; }
    [[nodiscard]] double max(double value) const override { return value; }
    [[nodiscard]] double min(double value) const override { return value; }
    void sum(std::span<double> /*values*/) const override {}
    void barrier() const override {}
};

/// Halo exchange of node data of a partition-local mesh.
class Halo {
public:
    virtual ~Halo() = default;
    /// Copy the values of owned nodes to their ghost copies on the other processes. `data` holds
    /// `components` contiguous values per local node (node-major: node n's values are
    /// data[n * components .. n * components + components)), for all n_local nodes.
    virtual void exchange(std::span<double> data, int components) const = 0;
};

/// No ghosts: nothing to exchange.
class SerialHalo final : public Halo {
public:
    void exchange(std::span<double> /*data*/, int /*components*/) const override {}
};

}  // namespace manta::parallel
