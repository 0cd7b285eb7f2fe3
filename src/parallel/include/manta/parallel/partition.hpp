#pragma once
/// @file partition.hpp
/// Node partitioning of a mesh for the vertex-centred scheme (docs/parallel.md): METIS's
/// multilevel k-way partitioning (Karypis & Kumar, "A fast and high quality multilevel scheme
/// for partitioning irregular graphs", SIAM J. Sci. Comput. 20(1), 1998) of the node graph whose
/// edges are the cell edges, i.e. the edges of the dual metrics. The edge cut is then the number
/// of flux edges that join two processes.

#include <cstdint>
#include <span>
#include <vector>

#include "manta/mesh/mesh.hpp"

namespace manta::parallel {

/// The node graph of a mesh in CSR form (METIS's xadj/adjncy): the neighbours of node n are
/// adjacency[offsets[n] .. offsets[n+1]), ascending; no self-loops.
struct NodeGraph {
    std::vector<std::int32_t> offsets;    ///< n_nodes + 1 entries
    std::vector<std::int32_t> adjacency;  ///< 2 x number of edges entries
};

/// The node graph of the cell edges of `mesh` (every edge of every cell face).
[[nodiscard]] NodeGraph node_graph(const mesh::Mesh& mesh);

/// Part (in [0, n_parts)) of every node of `mesh`, by METIS_PartGraphKway on `node_graph(mesh)`
/// with unit node weights, a fixed seed (the same mesh gives the same parts) and METIS's default
/// imbalance tolerance (3 %). n_parts == 1 gives all zeros without calling METIS. InputError if
/// n_parts < 1 or exceeds the node count, NumericalError if METIS fails.
[[nodiscard]] std::vector<int> partition_nodes(const mesh::Mesh& mesh, int n_parts);

/// How good a partition is for the edge-based scheme.
struct PartitionQuality {
    int n_parts = 1;                   ///< number of parts
    std::int64_t n_edges = 0;          ///< edges of the node graph
    std::int64_t edge_cut = 0;         ///< edges whose nodes lie in different parts
    std::vector<std::int64_t> sizes;   ///< nodes per part
    std::vector<std::int64_t> ghosts;  ///< ghost nodes per part (nodes of other parts that
                                       ///< share a cell with a node of the part)
    double imbalance = 1.0;            ///< largest part size / mean part size (1 = perfect)
    /// edge_cut / n_edges (0 for a graph without edges).
    [[nodiscard]] double cut_fraction() const noexcept {
        return n_edges > 0 ? static_cast<double>(edge_cut) / static_cast<double>(n_edges) : 0.0;
    }
};

/// Measure `part` (one entry per node of `mesh`, each in [0, n_parts)); InputError otherwise.
[[nodiscard]] PartitionQuality partition_quality(const mesh::Mesh& mesh, std::span<const int> part,
                                                 int n_parts);

}  // namespace manta::parallel
