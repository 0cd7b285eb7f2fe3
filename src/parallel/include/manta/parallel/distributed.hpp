#pragma once
/// @file distributed.hpp
/// A mesh read once and distributed over the processes (docs/parallel.md).
///
/// Rank 0 reads the global mesh, partitions its nodes (partition.hpp) and sends each process its
/// partition-local mesh: every cell that touches a node the process owns, the nodes of those
/// cells and the boundary faces of those cells. Local numbering: the owned nodes first, in
/// ascending global number, then the ghosts, in ascending global number. Because every cell
/// around an owned node is present, the median-dual metrics (mesh/dual.hpp) of owned nodes and
/// of edges with at least one owned node are the global mesh's; ghost volumes, ghost boundary
/// normals and edges between two ghosts are incomplete and must be ignored. The halo exchange
/// copies owned values onto the ghost copies.

#include <cstdint>
#include <exception>
#include <memory>
#include <span>
#include <vector>

#include "manta/mesh/mesh.hpp"
#include "manta/parallel/communicator.hpp"

namespace manta::parallel {

/// One process's part of a distributed mesh.
struct LocalMesh {
    /// The local mesh (finalized with `allow_unmarked_exposed_faces`: the cut faces lie on no
    /// marker). It has every marker of the global mesh, with the same numbers, even those
    /// without a face here.
    mesh::Mesh mesh;
    /// Nodes [0, n_owned) are owned, [n_owned, mesh.n_nodes()) are ghosts.
    mesh::Index n_owned = 0;
    /// Global number of each local node (ascending among the owned, and among the ghosts).
    std::vector<std::int64_t> global_node;
    /// Number of nodes of the global mesh.
    std::int64_t n_global_nodes = 0;
    /// Exchange of owned values onto ghosts (a SerialHalo with one process).
    std::unique_ptr<Halo> halo;

    /// Nodes held by this process, owned and ghosts.
    [[nodiscard]] mesh::Index n_local() const noexcept { return mesh.n_nodes(); }
    /// Ghost nodes.
    [[nodiscard]] mesh::Index n_ghosts() const noexcept { return mesh.n_nodes() - n_owned; }
};

/// Distribute a mesh over the processes of `comm` (collective: every process calls it).
/// `global` is the finalized global mesh on rank 0 and is ignored elsewhere (pass nullptr).
/// With one process the result is a copy of the global mesh, all nodes owned, a SerialHalo.
/// An error on rank 0 (no mesh, partitioning failed) is thrown on every process with the same
/// kind and message.
[[nodiscard]] LocalMesh distribute(const mesh::Mesh* global, const Communicator& comm);

/// After a step that only rank 0 did (reading the mesh, say), make its failure every process's
/// failure (collective): rank 0 passes the exception it caught, or nullptr, the others nullptr;
/// if rank 0 had one, every process throws an error of the same kind (InputError, IoError,
/// NumericalError; ConfigError arrives as InputError) with rank 0's message, rank 0 its own
/// exception. With one process it just rethrows a non-null `root_error`. Without it, the other
/// processes would wait for rank 0 in their next collective call forever.
void rethrow_root_error(std::exception_ptr root_error, const Communicator& comm);

/// The one-process local mesh of `global` (moved in): all nodes owned, identity numbering,
/// a SerialHalo. InputError if `global` is not finalized.
[[nodiscard]] LocalMesh serial_local_mesh(mesh::Mesh global);

/// The owned values of all processes in global node order (collective). `local` holds
/// `components` values per node, node-major, for the owned nodes or for all local nodes (the
/// ghosts' are not used). Rank 0 gets n_global_nodes x components values; the other ranks an
/// empty vector.
[[nodiscard]] std::vector<double> gather_owned(const LocalMesh& local_mesh,
                                               std::span<const double> local, int components,
                                               const Communicator& comm);

/// Sum over the owned nodes of all processes of each of the `components` values per node
/// (collective; every process gets the `components` sums). `local` as for `gather_owned`.
[[nodiscard]] std::vector<double> sum_owned(const LocalMesh& local_mesh,
                                            std::span<const double> local, int components,
                                            const Communicator& comm);

/// The halo of a partition-local mesh on several MPI processes: for each neighbouring process,
/// the owned local nodes whose values it receives (`send`) and the ghost local nodes whose values
/// come from it (`recv`), matched entry by entry across the pair. `exchange` posts one
/// MPI_Irecv and one MPI_Isend of packed values per neighbour and waits for all; the packing
/// buffers are kept between calls (so one MpiHalo must not exchange from two threads at once).
class MpiHalo final : public Halo {
public:
    /// The lists exchanged with one neighbouring process.
    struct Neighbour {
        int rank = 0;                   ///< the neighbour's rank in MPI_COMM_WORLD
        std::vector<mesh::Index> send;  ///< owned local nodes it holds as ghosts
        std::vector<mesh::Index> recv;  ///< ghost local nodes it owns
    };

    /// Build the lists (collective over MPI_COMM_WORLD, which must be initialised: an active
    /// MpiEnvironment): each process asks each ghost's owner for it by global number.
    /// `ghost_owner[g]` is the rank owning ghost n_owned + g. NumericalError if an owner does not
    /// own a requested node.
    MpiHalo(std::span<const std::int64_t> global_node, mesh::Index n_owned,
            std::span<const int> ghost_owner);

    void exchange(std::span<double> data, int components) const override;

    /// The neighbours, by ascending rank.
    [[nodiscard]] const std::vector<Neighbour>& neighbours() const noexcept { return neighbours_; }

private:
    std::vector<Neighbour> neighbours_;
    std::size_t n_local_ = 0;
    std::size_t n_send_ = 0;
    std::size_t n_recv_ = 0;
    mutable std::vector<double> send_buffer_;
    mutable std::vector<double> recv_buffer_;
};

}  // namespace manta::parallel
