#pragma once
/// @file config.hpp
/// The configuration file of `manta cfd` (docs/formats.md#cfd-configuration): flow conditions,
/// marker roles, reference values, numerics, solver and output settings. Every key is optional;
/// unknown keys, wrong types and out-of-range values are one-line errors naming file, line and
/// key.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "manta/euler/solver.hpp"
#include "manta/euler/unsteady.hpp"
#include "manta/mesh/companion.hpp"
#include "manta/mesh/mesh.hpp"
#include "manta/meshmotion/mesh_motion.hpp"

namespace manta::euler {

/// What `manta cfd` writes besides the summary.
struct OutputSettings {
    double checkpoint_interval_s = 60.0;  ///< seconds between restart files (0: only at the end)
    bool volume = true;                   ///< flow.vtu with the volume solution
    bool surface = true;                  ///< surface.vtu and surface.csv
};

/// A parsed configuration file. Flow values the file does not give stay unset (the command line
/// gives them).
struct CfdConfig {
    std::optional<double> mach;
    std::optional<double> alpha;  ///< [rad]
    std::optional<double> beta;   ///< [rad]
    /// Non-dimensional body rates p_hat, q_hat, r_hat (`flow.p_hat` ...; rotating_frame.hpp).
    std::optional<double> p_hat, q_hat, r_hat;
    double gamma = 1.4;
    std::map<std::string, BoundaryKind> markers;  ///< roles given by name
    ReferenceValues reference;
    SpatialOptions spatial;
    SolverSettings solver;
    OutputSettings output;
    /// `mesh.up`: the mesh's up axis, "z" (MANTA's axes) or "y" (a 2-D mesh in the x-y plane,
    /// whose slab is turned by +90 deg about x, (x, y, z) -> (x, -z, y), after reading).
    std::string mesh_up = "z";
    /// `unsteady:` time stepping of `manta cfd --motion` (dt comes from the command line or the
    /// motion file).
    UnsteadySettings unsteady;
    int output_every = 0;  ///< `unsteady.output_every`: steps between VTU outputs (0: none)
    /// `unsteady.mesh_motion`: rigid (the whole mesh moves) | deforming (the walls move, the far
    /// field stays, symmetry planes slide; docs/mesh-motion.md).
    meshmotion::BodyMotion mesh_motion = meshmotion::BodyMotion::rigid;
    /// `unsteady.rigid_radius`, `unsteady.fixed_radius` [m] of the deforming mesh motion (0: the
    /// defaults of meshmotion::DeformationOptions).
    double rigid_radius = 0.0, fixed_radius = 0.0;
    /// `control_surfaces:` (meshmotion::parse_control_surfaces, docs/mesh-motion.md).
    std::vector<meshmotion::ControlSurfaceSpec> control_surfaces;
    std::string source = "<defaults>";    ///< the file, for messages
    bool reference_given = false;         ///< the file has a `reference:` section
    bool control_surfaces_given = false;  ///< the file has a `control_surfaces:` section
    /// The mesh companion file whose values `apply_companion` took (empty: none).
    std::filesystem::path companion;
};

/// Read a configuration file (ConfigError on any bad key or value).
[[nodiscard]] CfdConfig read_cfd_config(const std::filesystem::path& file);
/// Parse configuration text; `source` names it in messages.
[[nodiscard]] CfdConfig parse_cfd_config(std::string_view text, const std::string& source);

/// Take the mesh companion file's values (mesh/companion.hpp, written by `manta mesh`) where the
/// configuration gives none: the role of every marker it does not name, the whole `reference:`
/// section when it has none, the `control_surfaces:` when it has none. What the configuration
/// gives wins. `file` names the companion in messages and in `config.companion`.
void apply_companion(CfdConfig& config, const mesh::Companion& companion,
                     const std::filesystem::path& file);
/// `apply_companion` with the companion beside `mesh_file` when there is one (mesh::
/// companion_path); nothing otherwise. ConfigError naming the companion when it is malformed.
void apply_mesh_companion(CfdConfig& config, const std::filesystem::path& mesh_file);

/// One role per marker of `mesh`: the configured role, else the default from the marker's name
/// (`default_role`). InputError naming the marker and the mesh if a marker has no role, or
/// naming the configuration if it gives a role to a marker the mesh does not have.
[[nodiscard]] std::vector<BoundaryKind> resolve_roles(const mesh::Mesh& mesh,
                                                      const CfdConfig& config);

}  // namespace manta::euler
