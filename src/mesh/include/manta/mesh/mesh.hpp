#pragma once
/// @file mesh.hpp
/// Unstructured mixed-element volume meshes (tetrahedra, pyramids, prisms, hexahedra) with
/// boundary faces (triangles, quadrilaterals) grouped by named markers (docs/mesh.md).
///
/// Layout: flat contiguous arrays and CSR connectivity (offsets + node lists), so that a mesh can
/// be partitioned (METIS takes CSR graphs) and sent between processes without conversion. Node
/// numbers are 0-based. Node order within a cell follows VTK (the VTK file-format document,
/// Kitware, "VTK File Formats", cell types 10, 12, 13, 14); the readers convert other orders.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace manta::mesh {

/// Node, cell and face numbers (0-based).
using Index = std::int32_t;

/// Volume cell kinds; the values are VTK cell type ids.
enum class CellType : std::uint8_t {
    tetra = 10,    ///< 4 nodes; (0,1,2) has its right-hand normal toward node 3
    hexa = 12,     ///< 8 nodes; (0,1,2,3) bottom with normal toward the top (4,5,6,7)
    prism = 13,    ///< 6 nodes (VTK wedge); (0,1,2) has its normal away from (3,4,5)
    pyramid = 14,  ///< 5 nodes; base (0,1,2,3) with normal toward the apex 4
};

/// Boundary face kinds; the values are VTK cell type ids.
enum class FaceType : std::uint8_t {
    triangle = 5,  ///< 3 nodes
    quad = 9,      ///< 4 nodes
};

/// Number of nodes of a cell type.
[[nodiscard]] int node_count(CellType t) noexcept;
/// Number of nodes of a face type.
[[nodiscard]] int node_count(FaceType t) noexcept;
/// Lower-case name ("tetra", "hexa", "prism", "pyramid").
[[nodiscard]] const char* name(CellType t) noexcept;

/// The faces of a cell type as local node lists, each ordered so that its right-hand normal
/// points out of the cell; a triangle's fourth entry is -1.
[[nodiscard]] std::span<const std::array<int, 4>> cell_faces(CellType t) noexcept;

/// What `Mesh::finalize` accepts beyond a complete, closed mesh.
struct FinalizeOptions {
    /// Accept cell faces that are exposed (a face of one cell only) but on no marker. A
    /// partition-local mesh (parallel::distribute) has such faces on the partition cut, where
    /// they touch only ghost nodes; a mesh read from a file must not (false, the default).
    bool allow_unmarked_exposed_faces = false;
};

/// A volume mesh. Build with `add_*`, then `finalize` (validation, boundary orientation); every
/// consumer (metrics, writers) expects a finalized mesh.
class Mesh {
public:
    /// An empty mesh; `source` names the data in error messages (usually the file name).
    explicit Mesh(std::string source = "<mesh>");

    /// Append a node (m); returns its number.
    Index add_node(const Eigen::Vector3d& x);
    /// Append a cell with nodes in VTK order; returns its number. Indices are checked by
    /// `finalize`. `where` (> 0) is the cell's line or element number in the source, named in
    /// error messages (see `set_where_label`); InputError if the node count is wrong.
    Index add_cell(CellType t, std::span<const Index> nodes, std::int64_t where = 0);
    /// Add a marker (boundary name) if not present; returns its number.
    int add_marker(const std::string& name);
    /// Append a boundary face on marker `marker` (any node order; `finalize` orients it);
    /// `where` as for `add_cell`.
    Index add_face(FaceType t, std::span<const Index> nodes, int marker, std::int64_t where = 0);
    /// What `where` numbers count in messages: "line" (default) or e.g. "element".
    void set_where_label(std::string label) { where_label_ = std::move(label); }
    /// Reserve storage.
    void reserve(Index n_nodes, Index n_cells, Index n_faces);

    /// Validate and complete the mesh: node indices in range, positive cell volumes, every
    /// boundary face a face of exactly one cell, every exposed cell face on a marker, no cell
    /// face shared by more than two cells, every marker named and used. Boundary faces are
    /// re-ordered to their cell face's order, so their normals point out of the domain; the
    /// source positions (`where`) are then dropped. InputError naming the source, the line or
    /// element, the cell or face and the bad value. `options` may relax the check of exposed
    /// faces for partition-local meshes; every other check stays.
    void finalize(const FinalizeOptions& options = {});

    [[nodiscard]] const std::string& source() const noexcept { return source_; }
    [[nodiscard]] Index n_nodes() const noexcept { return static_cast<Index>(x_.size() / 3); }
    [[nodiscard]] Index n_cells() const noexcept { return static_cast<Index>(cell_types_.size()); }
    [[nodiscard]] Index n_faces() const noexcept { return static_cast<Index>(face_types_.size()); }
    [[nodiscard]] int n_markers() const noexcept { return static_cast<int>(markers_.size()); }
    [[nodiscard]] bool is_finalized() const noexcept { return finalized_; }

    /// Position of node `i` (m).
    [[nodiscard]] Eigen::Vector3d node(Index i) const {
        return {x_[3 * i], x_[3 * i + 1], x_[3 * i + 2]};
    }
    /// All coordinates, x0 y0 z0 x1 ... (m).
    [[nodiscard]] std::span<const double> coordinates() const noexcept { return x_; }
    /// Move node `i` to `x` (m); the topology and the finalized state are kept, so a moving or
    /// deforming mesh keeps its cells, faces and markers (docs/mesh.md, "Moving geometry").
    /// Nothing is checked here (a cell may invert): the caller checks volumes when it must.
    /// InputError if `i` is not a node or `x` is not finite.
    void set_node(Index i, const Eigen::Vector3d& x);
    /// Replace all coordinates (x0 y0 z0 x1 ..., 3 per node, m; an Eigen::Matrix3Xd's data in
    /// this order), topology kept; no allocation. InputError if the size is not 3 n_nodes or a
    /// value is not finite (the mesh is then unchanged).
    void set_coordinates(std::span<const double> x);

    [[nodiscard]] CellType cell_type(Index c) const { return cell_types_[c]; }
    /// Nodes of cell `c` in VTK order.
    [[nodiscard]] std::span<const Index> cell(Index c) const {
        return {cell_nodes_.data() + cell_offsets_[c],
                static_cast<std::size_t>(cell_offsets_[c + 1] - cell_offsets_[c])};
    }
    /// CSR offsets of the cell connectivity (n_cells + 1 entries).
    [[nodiscard]] std::span<const std::int64_t> cell_offsets() const noexcept {
        return cell_offsets_;
    }
    /// CSR node lists of the cells.
    [[nodiscard]] std::span<const Index> cell_nodes() const noexcept { return cell_nodes_; }

    [[nodiscard]] FaceType face_type(Index f) const { return face_types_[f]; }
    /// Nodes of boundary face `f`; after `finalize`, its normal points out of the domain.
    [[nodiscard]] std::span<const Index> face(Index f) const {
        return {face_nodes_.data() + face_offsets_[f],
                static_cast<std::size_t>(face_offsets_[f + 1] - face_offsets_[f])};
    }
    /// Marker number of boundary face `f`.
    [[nodiscard]] int face_marker(Index f) const { return face_markers_[f]; }
    /// Marker names.
    [[nodiscard]] const std::vector<std::string>& markers() const noexcept { return markers_; }
    /// Number of a marker, or -1.
    [[nodiscard]] int find_marker(const std::string& name) const;

    /// Volume of cell `c` (m^3): faces split into triangles about their node average, cones
    /// from the node average of the cell (exact for planar faces).
    [[nodiscard]] double cell_volume(Index c) const;
    /// Sum of the cell volumes (m^3).
    [[nodiscard]] double volume() const;

    /// Bytes held by the arrays (capacity), for memory reports.
    [[nodiscard]] std::size_t memory_bytes() const noexcept;

private:
    [[nodiscard]] std::string cell_at(Index c) const;
    [[nodiscard]] std::string face_at(Index f) const;

    std::string source_;
    std::string where_label_ = "line";
    std::vector<std::int64_t> cell_where_;
    std::vector<std::int64_t> face_where_;
    std::vector<double> x_;
    std::vector<CellType> cell_types_;
    std::vector<std::int64_t> cell_offsets_{0};
    std::vector<Index> cell_nodes_;
    std::vector<FaceType> face_types_;
    std::vector<std::int64_t> face_offsets_{0};
    std::vector<Index> face_nodes_;
    std::vector<int> face_markers_;
    std::vector<std::string> markers_;
    bool finalized_ = false;
};

}  // namespace manta::mesh
