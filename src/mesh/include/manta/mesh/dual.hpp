#pragma once
/// @file dual.hpp
/// Median-dual metrics for a vertex-centred, edge-based finite-volume scheme (docs/mesh.md).
///
/// The control volume of node i is bounded, inside each cell around it, by triangles joining
/// the midpoint of an edge (i, j), the node average of a cell face holding that edge and the
/// node average of the cell (Barth, "Aspects of unstructured grids and finite-volume solvers
/// for the Euler and Navier-Stokes equations", AGARD-R-787, 1992; Blazek, *Computational Fluid
/// Dynamics: Principles and Applications*, 3rd ed., 2015, sec. 5.2). The same triangles make
/// the edge normals, the boundary normals and the volumes, so each dual cell is closed exactly:
/// sum_j n_ij + n_i(boundary) = 0 to round-off, and the dual volumes sum to the mesh volume.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "manta/mesh/mesh.hpp"

namespace manta::mesh {

/// The boundary vertices of one marker and their dual-face area vectors.
struct BoundaryVertices {
    int marker = 0;            ///< marker number in the mesh
    std::vector<Index> nodes;  ///< nodes on the marker, ascending
    Eigen::Matrix3Xd normals;  ///< outward area vector of each node's part of the marker (m^2)
};

/// Edge list, dual-face area vectors, dual volumes and boundary normals of a mesh.
struct DualMetrics {
    /// Edges (i, j) with i < j, sorted by i then j.
    std::vector<std::array<Index, 2>> edges;
    /// Area vector of the dual face of each edge, pointing from node i to node j (m^2).
    Eigen::Matrix3Xd edge_normals;
    /// Volume of each node's dual cell (m^3).
    std::vector<double> dual_volumes;
    /// CSR node-to-edge adjacency: the edges of node n are
    /// node_edges[node_edge_offsets[n] .. node_edge_offsets[n+1]).
    std::vector<std::int64_t> node_edge_offsets;
    std::vector<Index> node_edges;  ///< see `node_edge_offsets`
    /// One entry per marker, in the mesh's marker order.
    std::vector<BoundaryVertices> boundary;

    [[nodiscard]] Index n_edges() const noexcept { return static_cast<Index>(edges.size()); }
    /// Bytes held by the arrays, for memory reports.
    [[nodiscard]] std::size_t memory_bytes() const noexcept;
};

/// Compute the median-dual metrics of a finalized mesh (InputError otherwise).
[[nodiscard]] DualMetrics compute_dual_metrics(const Mesh& mesh);

/// Largest closure defect over all dual cells, |sum_j ±n_ij + n_i(boundary)|, divided by the
/// largest dual-face area magnitude at that node (dimensionless; round-off size for a correct
/// mesh and metrics).
[[nodiscard]] double max_closure_defect(const Mesh& mesh, const DualMetrics& dual);

}  // namespace manta::mesh
