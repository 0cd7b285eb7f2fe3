#pragma once
/// @file meshgen.hpp
/// Aircraft meshes from the aircraft file (docs/meshgen.md): the CAD is built with gmsh's
/// OpenCASCADE kernel (lifting surfaces lofted through their sections, the fuselage through its
/// elliptic stations, fused into one closed body), placed in a spherical far field (a half
/// sphere with a symmetry plane for the half model), and filled with tetrahedra whose sizes are
/// refined at the leading and trailing edges, the tips and the control-surface edges. Each
/// control surface is its own wall marker, split from the rest along its hinge and side edges.
/// Beside the mesh a companion file records the marker roles, the hinge lines (in the
/// `control_surfaces:` form that meshmotion reads) and the reference values (docs/formats.md).
///
/// Geometry axes of the aircraft file throughout: x aft, y right, z up, metres.

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "manta/aircraft/aircraft.hpp"
#include "manta/geometry/aircraft_geometry.hpp"
#include "manta/mesh/companion.hpp"

namespace manta::meshgen {

/// Which part of the aircraft is meshed.
enum class Model {
    half,  ///< the right half (y >= 0) with a symmetry plane at y = 0 (longitudinal work)
    full,  ///< the whole aircraft in a full sphere (sideslip, lateral controls)
};
/// Mesh density; the levels are about 2.5x apart in nodes (sizes 2.5^(1/3) apart).
enum class Level { coarse, medium, fine };

[[nodiscard]] std::string_view to_string(Model m);
[[nodiscard]] std::string_view to_string(Level l);
/// "half" / "full"; InputError naming `what` and the value otherwise.
[[nodiscard]] Model parse_model(std::string_view text, std::string_view what = "--model");
/// "coarse" / "medium" / "fine"; InputError naming `what` and the value otherwise.
[[nodiscard]] Level parse_level(std::string_view text, std::string_view what = "--level");

/// How the mesh is made.
struct MeshOptions {
    Model model = Model::half;
    Level level = Level::coarse;
    /// Far-field radius in wing spans (of `reference.span`), sphere centred on the aircraft.
    double farfield_spans = 5.0;
    /// Threads gmsh may use (1 = serial; the meshes are then reproducible).
    int threads = 1;
    /// Multiply every size by this (tests make tiny meshes with it); > 0.
    double size_factor = 1.0;
};

/// The companion file and its parts live in the mesh module (mesh/companion.hpp).
using mesh::Companion;
using mesh::companion_path;
using mesh::CompanionControlSurface;
using mesh::CompanionReference;
using mesh::format_companion;
using mesh::MarkerRole;
using mesh::read_companion;
using mesh::write_companion;

/// The quality report of a generated mesh.
struct QualityReport {
    long long nodes = 0;
    long long cells = 0;           ///< tetrahedra
    long long boundary_faces = 0;  ///< triangles on markers
    double min_dihedral_deg = 0.0;
    double max_dihedral_deg = 0.0;
    /// Largest ratio of the volumes of two cells sharing a face (>= 1).
    double max_volume_ratio = 0.0;
    /// Cells with a dihedral angle below `sliver_min_deg` or above 180 - `sliver_min_deg`
    /// (four nearly coplanar nodes; docs/meshgen.md).
    long long slivers = 0;
    double sliver_min_deg = 5.0;
    /// Every exposed cell face is a marker face, every marker face is exposed, and every edge of
    /// the marker faces is shared by exactly two of them.
    bool surface_closed = false;
    /// Every cell has a positive volume (nodes ordered right-handedly).
    bool volume_positive = false;
    double volume = 0.0;           ///< sum of the cell volumes [m^3]
    double min_cell_volume = 0.0;  ///< [m^3]
    long long open_edges = 0;      ///< marker-face edges not shared by exactly two faces
    long long unmarked_faces = 0;  ///< exposed cell faces on no marker
};

/// One marker's faces in the generated mesh.
struct MarkerSummary {
    std::string name;
    std::string role;
    long long faces = 0;
    long long nodes = 0;
    double area = 0.0;  ///< [m^2]
};

/// What `generate_mesh` made.
struct MeshResult {
    std::filesystem::path mesh_file;
    std::filesystem::path companion_file;
    Companion companion;
    QualityReport quality;
    std::vector<MarkerSummary> markers;
    double wetted_area = 0.0;    ///< all wall markers [m^2] (the half model: the right half)
    double body_volume = 0.0;    ///< CAD volume of the fused body [m^3] (half model: y >= 0)
    double seconds_cad = 0.0;    ///< building and classifying the CAD
    double seconds_mesh = 0.0;   ///< surface and volume meshing
    double seconds_total = 0.0;  ///< everything, writing and the quality report included
    /// Shapes that had to be approximated (e.g. a 6-series section), one line each.
    std::vector<std::string> notes;
};

/// Check that the aircraft's shape can be built; ConfigError naming the aircraft file, the key
/// and its value for sections out of order, a control surface outside its surface, a degenerate
/// or self-intersecting airfoil contour, overlapping twin copies, a fuselage station of zero size
/// between the ends. `generate_mesh` calls it first.
void check_buildable(const aircraft::AircraftDefinition& aircraft);

/// Build the CAD, mesh it and write the mesh (format by the extension of `out`: .su2, .msh,
/// .cgns) and its companion file beside it, both atomically. ConfigError (bad geometry, naming
/// the aircraft file key), InputError (bad options or output name), IoError (cannot write),
/// NumericalError (gmsh failed to mesh, with its message).
[[nodiscard]] MeshResult generate_mesh(const aircraft::AircraftDefinition& aircraft,
                                       const MeshOptions& options,
                                       const std::filesystem::path& out);

/// Quality of a tetrahedral mesh given by node coordinates (x, y, z per node), cells (four
/// 0-based node indices each) and marker faces (three indices each).
[[nodiscard]] QualityReport assess_quality(const std::vector<double>& xyz,
                                           const std::vector<std::array<long long, 4>>& tets,
                                           const std::vector<std::array<long long, 3>>& faces,
                                           double sliver_min_deg = 5.0);

}  // namespace manta::meshgen
