#pragma once
/// @file companion.hpp
/// The mesh companion file (docs/formats.md#mesh-companion-file): beside a mesh `X.su2` (or
/// `.msh`, `.cgns`) the file `X.mesh.yaml` records the marker roles, the reference values that
/// make the forces coefficients of the whole aircraft, and the hinge lines of the control
/// surfaces in the `control_surfaces:` form meshmotion reads. `manta mesh` writes it; `manta cfd`
/// and the Euler source read it as defaults of the CFD configuration (docs/euler.md).
///
/// Geometry axes of the aircraft file throughout: x aft, y right, z up, metres.

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace manta::mesh {

/// One wall marker of a control surface and its hinge, as `meshmotion::parse_control_surfaces`
/// reads it: positive local deflection rotates the surface right-handedly about
/// hinge[1] - hinge[0] (trailing edge down on horizontal surfaces, toward -y on fins).
struct CompanionControlSurface {
    std::string mode;                        ///< the driving control: elevator, aileron, rudder
    std::string marker;                      ///< wall marker of the moving surface
    std::array<Eigen::Vector3d, 2> hinge{};  ///< inboard, outboard point [m] (ordered as above)
    double gain = 1.0;                       ///< local deflection = gain * control
    std::string control_surface;             ///< name in the aircraft file
    std::string side;  ///< "right" (defined copy), "left" (mirror) or "" (one copy)
};

/// A mesh marker and its boundary role (euler::BoundaryKind names: wall, farfield, symmetry).
struct MarkerRole {
    std::string name;
    std::string role;
};

/// The reference values that make the flow solution's forces coefficients of the whole aircraft.
struct CompanionReference {
    /// Area the solver divides by [m^2]: the aircraft's reference area for the full model, half
    /// of it for the half model (a half model's forces over q * S/2 are the whole aircraft's
    /// coefficients CL, CD, Cm; forces are not doubled).
    double area = 0.0;
    double aircraft_area = 0.0;  ///< the aircraft file's reference.area [m^2]
    double chord = 0.0;          ///< reference.chord [m]
    double span = 0.0;           ///< reference.span [m] (whole aircraft, both models)
    /// Moment point [m]: the aircraft file's moment reference point (that of its aerodynamic
    /// model and of the vortex lattice), geometry axes.
    Eigen::Vector3d moment_point = Eigen::Vector3d::Zero();
    std::string cg_case;                           ///< default mass case
    Eigen::Vector3d cg = Eigen::Vector3d::Zero();  ///< its CG, geometry axes [m]
};

/// The companion file of a mesh (docs/formats.md#mesh-companion-file).
struct Companion {
    std::string mesh;      ///< mesh file name (as written beside the companion)
    std::string aircraft;  ///< aircraft file it was made from
    std::string aircraft_name;
    std::string model = "half";    ///< half (y >= 0 with a symmetry plane) or full
    std::string level = "coarse";  ///< coarse, medium or fine
    std::vector<MarkerRole> markers;
    CompanionReference reference;
    std::vector<CompanionControlSurface> control_surfaces;
};

/// The companion file's path for a mesh file: the extension (.su2, .msh, .cgns, also after .gz)
/// replaced by `.mesh.yaml` (ranger.su2 -> ranger.mesh.yaml).
[[nodiscard]] std::filesystem::path companion_path(const std::filesystem::path& mesh_file);

/// Companion file text (YAML) and writer (atomic).
[[nodiscard]] std::string format_companion(const Companion& c);
void write_companion(const std::filesystem::path& file, const Companion& c);
/// Read a companion file: ConfigError naming file, line, key for anything malformed or unknown.
/// Its `control_surfaces:` list can also be handed to meshmotion::parse_control_surfaces as is.
[[nodiscard]] Companion read_companion(const std::filesystem::path& file);
/// The companion beside `mesh_file` (`companion_path`), read, or none when there is no such file.
/// ConfigError as `read_companion` when it exists but is malformed.
[[nodiscard]] std::optional<Companion> find_companion(const std::filesystem::path& mesh_file);

}  // namespace manta::mesh
