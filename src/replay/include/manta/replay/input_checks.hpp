#pragma once
/// @file input_checks.hpp
/// Checks of a replay's inputs against each other before any flow solution starts
/// (docs/replay.md, "Bad input"): the aircraft file, the tables, the trajectory and, for the
/// Euler source, the mesh's companion file and the CFD configuration. The steady start of an
/// Euler replay takes minutes and the replay hours: a mesh of another aircraft, a half model
/// for a trajectory that rolls, a Mach number the configuration fixes otherwise, tables of
/// another aircraft or of another Mach range are found here, as one-line InputErrors naming the
/// file, the value and what was expected. What may be meant (tables slightly out of range, a
/// reference the configuration gives explicitly) is a one-line warning instead.
///
/// The facts are plain values: the caller reads the files (mesh::Companion, euler::CfdConfig,
/// aero::AeroDatabase) and this module compares them, so it depends on no solver.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "manta/aero/database.hpp"
#include "manta/replay/trajectory.hpp"

namespace manta::replay {

/// Reference values that make forces and moments coefficients [m^2, m, m, m].
struct ReferenceFacts {
    double area = 0.0;
    double chord = 0.0;
    double span = 0.0;
    std::array<double, 3> moment_point{};  ///< geometry axes (x aft, y right, z up)
};

/// The aircraft file.
struct AircraftFacts {
    std::string file;
    std::string name;
    ReferenceFacts reference;
};

/// A mesh companion file (mesh::Companion, written by `manta mesh`).
struct CompanionFacts {
    std::string file;
    std::string aircraft_name;
    bool half_model = false;   ///< model: half (a symmetry plane y = 0)
    ReferenceFacts reference;  ///< area: the aircraft's (`aircraft_area`), not the half of it
    std::vector<std::string> control_modes;  ///< modes of its control_surfaces
};

/// The Euler source's set-up: the CFD configuration with the mesh companion's defaults applied
/// (euler::apply_mesh_companion), as the source will run it.
struct EulerFacts {
    std::string mesh;    ///< the mesh file
    std::string config;  ///< the configuration file, or "the default CFD configuration"
    std::optional<CompanionFacts> companion;  ///< the mesh's companion file, if any
    std::optional<double> mach;               ///< the configuration's flow.mach
    /// Keys of the configuration's flow: the replay replaces (flow.alpha_deg, ...).
    std::vector<std::string> ignored_flow_keys;
    bool reference_given = false;  ///< the configuration has its own `reference:`
    ReferenceFacts reference;      ///< what the solver divides by (half the area for a half model)
    bool half_model = false;       ///< reference.half_model, or a marker with the symmetry role
    std::vector<std::string> control_modes;  ///< modes of the control surfaces it will move
};

/// The tables the replay compares with.
struct TablesFacts {
    std::string file;  ///< `--tables` (a database or a `manta tables` folder); empty: the
                       ///< aircraft file's own aerodynamic model (no aircraft check)
    const aero::AeroDatabase* database = nullptr;
    /// Companion files of the meshes a `manta tables` folder's Euler campaign made (mesh/ in
    /// the folder, or beside its database.yaml).
    std::vector<CompanionFacts> mesh_companions;
};

/// Largest |value| of a trajectory column and where (the first row reaching it).
struct ColumnPeak {
    double value = 0.0;  ///< signed value at the peak
    double t = 0.0;      ///< [s]
};

/// Entry Mach number of a trajectory as the replay takes it (motion.csv `# mach:`): its mach
/// column's first value, else V / a(-z) of the US 1976 atmosphere at the first row.
[[nodiscard]] double entry_mach(const Trajectory& trajectory);
/// Mach number of every row (the mach column, else V / a(-z)). InputError naming the row for an
/// altitude outside the atmosphere's -5 to 80 km.
[[nodiscard]] std::vector<double> trajectory_mach(const Trajectory& trajectory);

/// Compare the tables with the aircraft and the trajectory (either source). InputError for
/// tables of another aircraft (a `manta tables` folder whose mesh companion names another
/// aircraft or other reference values) and for a trajectory whose Mach number leaves the
/// tables' Mach range by more than `mach_margin_error`; returns warnings (one line each) for a
/// database name that does not name the aircraft, a trajectory slightly beyond the tables'
/// Mach, alpha or beta range, a control the trajectory moves that the tables lack, and a
/// trajectory whose `# aircraft:` is another aircraft's.
[[nodiscard]] std::vector<std::string> check_tables(const TablesFacts& tables,
                                                    const AircraftFacts& aircraft,
                                                    const Trajectory& trajectory);

/// Compare the Euler source's set-up with the aircraft and the trajectory. InputError for a mesh
/// companion of another aircraft (its reference values) or a configuration whose reference
/// differs from the aircraft file's while the companion's agrees, a half model for a
/// trajectory with sideslip, roll or yaw rate, or aileron or rudder deflections, a control the
/// trajectory moves without a control surface, and a flow.mach other than the trajectory's
/// entry Mach number; warnings for a companion that names another aircraft with the same
/// reference values, an explicit configuration reference other than the aircraft's, and flow
/// keys the replay replaces.
[[nodiscard]] std::vector<std::string> check_euler_setup(const EulerFacts& euler,
                                                         const AircraftFacts& aircraft,
                                                         const Trajectory& trajectory);

/// Thresholds of the checks (docs/replay.md, "Bad input").
inline constexpr double mach_margin_error = 0.1;   ///< Mach beyond the tables' range: error
inline constexpr double lateral_angle_tol = 1e-3;  ///< |beta| [rad] a half model refuses
inline constexpr double lateral_rate_tol = 1e-3;   ///< |p|, |r| [rad/s] a half model refuses
inline constexpr double deflection_tol = 1e-9;     ///< a control "moves" above this [rad]
inline constexpr double reference_rel_tol = 1e-6;  ///< relative difference of reference values

}  // namespace manta::replay
