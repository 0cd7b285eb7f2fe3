#pragma once
/// @file readers.hpp
/// Mesh readers: SU2 native (.su2, gzip-compressed .su2.gz; several zones joined), gmsh MSH 2.2
/// and 4.1 (ASCII and binary) and CGNS (unstructured zones, and structured zones turned into
/// hexahedra). Two-dimensional meshes
/// are extruded into a slab one cell thick between two symmetry markers. Every reader returns a
/// finalized `Mesh`; errors name the file and line (CGNS: zone, section and element) and what was
/// expected (docs/mesh.md).

#include <filesystem>
#include <string>
#include <string_view>

#include "manta/mesh/mesh.hpp"

namespace manta::mesh {

/// How two-dimensional meshes become volume meshes.
struct ReadOptions {
    /// Thickness of the slab a 2-D mesh (in the x-y plane) is extruded into, along +z (m).
    double slab_thickness = 1.0;
    /// Marker of the slab face at the 2-D mesh's plane (its normal is -z).
    std::string slab_marker_back = "symmetry_back";
    /// Marker of the slab face at z + slab_thickness (its normal is +z).
    std::string slab_marker_front = "symmetry_front";

    /// ConfigError if the thickness is not positive and finite or a marker name is empty or
    /// both names are equal.
    void validate() const;
};

/// File formats `read_mesh` knows.
enum class MeshFormat {
    su2,   ///< SU2 native, plain or gzip-compressed
    gmsh,  ///< gmsh MSH 2.2 or 4.1, ASCII or binary
    cgns,  ///< CGNS (HDF5 or ADF), structured and unstructured zones
};

/// The format from the file name: .su2 and .su2.gz, .msh, .cgns and .cgn. InputError naming
/// the file and the extensions known otherwise.
[[nodiscard]] MeshFormat detect_format(const std::filesystem::path& file);

/// Read a mesh in the format its name says (see `detect_format`).
[[nodiscard]] Mesh read_mesh(const std::filesystem::path& file, const ReadOptions& options = {});

/// Read an SU2 native mesh (gzip detected from the content). IoError if unreadable.
[[nodiscard]] Mesh read_su2(const std::filesystem::path& file, const ReadOptions& options = {});
/// Parse SU2 native text; `source` names it in messages.
[[nodiscard]] Mesh parse_su2(std::string_view text, const std::string& source,
                             const ReadOptions& options = {});

/// Read a gmsh MSH 2.2 or 4.1 mesh, ASCII or binary (either byte order; gzip also accepted).
/// Errors name the line, or in a binary file the byte offset.
[[nodiscard]] Mesh read_gmsh(const std::filesystem::path& file, const ReadOptions& options = {});
/// Parse gmsh MSH file contents (text or binary); `source` names it in messages.
[[nodiscard]] Mesh parse_gmsh(std::string_view text, const std::string& source,
                              const ReadOptions& options = {});

/// Read every zone of the first base of a CGNS file. Unstructured zones: element sections,
/// MIXED included; boundary conditions given as element ranges or lists, or as vertex lists;
/// face sections without a boundary condition become markers of their section name.
/// Structured zones become hexahedra (quadrilaterals in 2-D), with boundary conditions as point
/// ranges or point lists (Vertex, or I/J/KFaceCenter). With several zones, or structured ones,
/// nodes on exposed faces that coincide (within 1e-10 of the bounding-box diagonal) are merged
/// and boundary faces that thereby become interior (zone interfaces) are dropped; a lone
/// unstructured zone is read as it is. A boundary condition's FamilyName, if any, is its
/// marker, else its own name; equal names in several zones make one marker.
/// IoError if the file cannot be opened; InputError naming the file, zone, section, element.
[[nodiscard]] Mesh read_cgns(const std::filesystem::path& file, const ReadOptions& options = {});

/// Read a whole file, gunzipping it if it is gzip-compressed. IoError if unreadable.
[[nodiscard]] std::string read_maybe_gzipped(const std::filesystem::path& file);

}  // namespace manta::mesh
