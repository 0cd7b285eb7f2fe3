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
#include <span>
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
    /// Topology cached for the per-step geometry (`update_dual_metrics`, `swept_volumes`): the
    /// edge number of every face edge of every cell, cells in order, faces in `cell_faces`
    /// order, edges k -> k+1 of each face; and the local number (in its marker's `nodes`) of
    /// every node of every boundary face, faces in order.
    std::vector<Index> cell_face_edges;
    std::vector<Index> boundary_face_slots;  ///< see `cell_face_edges`

    [[nodiscard]] Index n_edges() const noexcept { return static_cast<Index>(edges.size()); }
    /// Bytes held by the arrays, for memory reports.
    [[nodiscard]] std::size_t memory_bytes() const noexcept;
};

/// Compute the median-dual metrics of a finalized mesh (InputError otherwise).
[[nodiscard]] DualMetrics compute_dual_metrics(const Mesh& mesh);

/// Recompute the geometric part of `dual` (edge normals, dual volumes, boundary normals) from the
/// mesh's current coordinates, in place: the edge list, the adjacency and the boundary node lists
/// are kept and nothing is allocated. The arithmetic is that of `compute_dual_metrics`, so the
/// result equals a fresh computation bit for bit. InputError if `dual` does not belong to the
/// mesh (node, edge or marker counts differ).
void update_dual_metrics(const Mesh& mesh, DualMetrics& dual);

/// One value per dual face: per edge, in `DualMetrics::edges` order and with the orientation of
/// its area vector (from node i to node j), and per boundary vertex of each marker, in
/// `BoundaryVertices::nodes` order, outward. Swept volumes (m^3) and grid fluxes (m^3/s).
struct DualFaceValues {
    std::vector<double> edges;
    std::vector<std::vector<double>> boundary;  ///< one per marker

    /// Size the arrays for `dual` (values zero); no allocation when they already fit.
    void resize_for(const DualMetrics& dual);
    /// Whether the sizes are those of `dual`.
    [[nodiscard]] bool fits(const DualMetrics& dual) const noexcept;
};

/// The volume each dual face sweeps when every node moves linearly in time from `x_a` to `x_b`
/// (each 3 per node, x0 y0 z0 x1 ..., m), signed positive along the face's area vector, computed
/// exactly (docs/mesh.md, "Swept volumes"). Every median-dual face is made of triangles whose
/// corners (edge midpoints, face and cell node averages, nodes) move linearly; a triangle with
/// corner displacements d_k and area vectors n_a, n_m, n_b at the start, the middle and the end
/// sweeps S = (d_1 + d_2 + d_3) / 3 . (n_a + 4 n_m + n_b) / 6 (exact: the area vector is
/// quadratic in time, the velocity linear over the triangle and constant in time), as in
/// Mavriplis & Yang, "Construction of the discrete geometric conservation law for high-order
/// time-accurate simulations on dynamic meshes", J. Comput. Phys. 213, 557-573, 2006. Hence for
/// every node, with its metrics at a and b, V_i(b) - V_i(a) = sum over i's edges of +-S (+ where
/// i is the edge's first node) plus its boundary parts, to round-off. `out` is sized by
/// `resize_for` (no allocation after the first call). InputError if the sizes do not match the
/// mesh or `dual` does not belong to it.
void swept_volumes(const Mesh& mesh, const DualMetrics& dual, std::span<const double> x_a,
                   std::span<const double> x_b, DualFaceValues& out);

/// Largest defect of the discrete geometric conservation law over the nodes,
/// max_i |V_i(b) - V_i(a) - (sum of i's swept volumes)|, divided by the largest dual volume at b
/// (dimensionless; round-off size for exact swept volumes). `v_a`, `v_b`: dual volumes at the two
/// levels. InputError if the sizes do not match `dual`.
[[nodiscard]] double max_swept_volume_defect(const DualMetrics& dual, std::span<const double> v_a,
                                             std::span<const double> v_b,
                                             const DualFaceValues& swept);

/// Largest closure defect over all dual cells, |sum_j ±n_ij + n_i(boundary)|, divided by the
/// largest dual-face area magnitude at that node (dimensionless; round-off size for a correct
/// mesh and metrics).
[[nodiscard]] double max_closure_defect(const Mesh& mesh, const DualMetrics& dual);

}  // namespace manta::mesh
