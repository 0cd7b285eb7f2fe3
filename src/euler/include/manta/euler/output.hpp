#pragma once
/// @file output.hpp
/// Files of a `manta cfd` run (docs/formats.md#cfd-run-folder): the convergence history CSV,
/// the surface solution CSV and the binary restart file. Every file is written atomically.

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "manta/euler/solver.hpp"
#include "manta/mesh/mesh.hpp"
#include "manta/parallel/communicator.hpp"

namespace manta::euler {

/// Header line of history.csv (no newline).
[[nodiscard]] std::string history_header();
/// One history.csv row (no newline).
[[nodiscard]] std::string history_row(const IterationRecord& r);

/// Write surface.csv: one row per node of the wall markers (global node number, marker,
/// x y z [m], rho, u, v, w, p (solver units, gas.hpp), Cp, Mach). `primitive`: 5 values per
/// global node; `cp`, `mach`: one per node; `file_node`, if not empty, the node's number in the
/// mesh file (when the solver renumbered the nodes), written instead of its own.
void write_surface_csv(const std::filesystem::path& file, const mesh::Mesh& mesh,
                       const std::vector<BoundaryKind>& roles, std::span<const double> primitive,
                       std::span<const double> cp, std::span<const double> mach,
                       std::span<const mesh::Index> file_node = {});

/// A restart file's content.
struct RestartData {
    std::string fingerprint;  ///< mesh and case identity (`restart_fingerprint`)
    IterationState state;
    double mach = 0, alpha = 0, beta = 0;  ///< the flow condition it was computed at
    std::vector<double> U;                 ///< 5 conservative values per global node
    /// The back-off state (`SteadySolver::backoff_state`), 5 per global node; empty in files
    /// of format 1 (then the solution is used).
    std::vector<float> U_backoff;
    /// The frozen limiter, 5 per global node; empty when the limiter is not frozen.
    std::vector<double> limiter;
};

/// Identity of a mesh for restart files: the global node count and a checksum of the nodes'
/// numbers and coordinates that is the same however the mesh is partitioned. `global_node`:
/// global number of each local node; nodes [0, n_owned) are owned. A reduction over `comm`.
[[nodiscard]] std::string mesh_fingerprint(const mesh::Mesh& mesh,
                                           std::span<const std::int64_t> global_node,
                                           mesh::Index n_owned, const parallel::Communicator& comm);

/// Write a restart file (format 2: binary, little-endian, atomically; docs/formats.md). IoError
/// if not writable.
void write_restart(const std::filesystem::path& file, const RestartData& data);
/// Read a restart file of format 2 or 1 (format 1 holds only the solution and the first four
/// `IterationState` fields: the rest take their start values, and a frozen limiter, which that
/// format did not keep, is released). IoError if unreadable; InputError naming the file if it is
/// not a MANTA restart file, is truncated, or has `n_nodes` != the expected count (when > 0).
[[nodiscard]] RestartData read_restart(const std::filesystem::path& file, std::int64_t n_nodes = 0);

}  // namespace manta::euler
