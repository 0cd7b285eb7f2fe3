#pragma once
/// @file aircraft.hpp
/// The aircraft definition file (docs/formats.md#aircraft-file): geometry for the flow solvers,
/// mass cases, engine, control limits, aerodynamic model and envelope, read through the validated
/// configuration layer. This module joins `geometry` and `flightdyn`.

#include <array>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "manta/aero/motion.hpp"
#include "manta/flightdyn/model.hpp"
#include "manta/geometry/aircraft_geometry.hpp"

namespace manta::aircraft {

/// Flight envelope as published (used for sanity checks and plots).
struct Envelope {
    double max_mach = 0.0;                  ///< M_MO
    double dive_mach = 0.0;                 ///< M_D
    double ceiling = 0.0;                   ///< [m]
    std::array<double, 2> alpha{0.0, 0.0};  ///< [rad] range of data / validity
    std::array<double, 2> beta{0.0, 0.0};   ///< [rad]
};

/// Everything an aircraft file holds, validated (see `load_aircraft`).
struct AircraftDefinition {
    std::filesystem::path file;  ///< where it was read from (the source label for parse_aircraft)
    std::string name;            ///< `name`
    std::string description;     ///< `description` ("" if absent)
    geometry::AircraftGeometry geometry;     ///< the outer shape (`geometry:`)
    flightdyn::ReferenceGeometry reference;  ///< S, b, c-bar of the coefficients
    /// Moment reference point of the aero model, geometry axes [m].
    Eigen::Vector3d moment_reference_geom = Eigen::Vector3d::Zero();
    std::vector<flightdyn::MassProperties> mass_cases;  ///< loading cases, names unique
    std::string default_mass_case;                      ///< name of one of `mass_cases`
    flightdyn::EngineModel engine;                      ///< thrust model
    /// Engine rotor angular momentum, body axes [kg m^2/s] (zero if not given).
    Eigen::Vector3d engine_angular_momentum = Eigen::Vector3d::Zero();
    flightdyn::ControlLimits limits;     ///< `controls:` (the paper's limits by default)
    flightdyn::Environment environment;  ///< `environment:` (standard gravity by default)
    Envelope envelope;                   ///< `envelope:` (zeros if absent)
    /// The aerodynamic model, shared by every flight model made from this definition.
    std::shared_ptr<const aero::AeroDatabase> aero;
    std::string aero_label;  ///< how the aero model was obtained (e.g. "linear derivatives (typical
                             ///< jet trainer)")

    /// Flight model with the named loading case ("" = default). InputError if unknown, listing
    /// names.
    [[nodiscard]] flightdyn::FlightModel flight_model(std::string_view mass_case = {}) const;
    /// The named loading case ("" = default). InputError if unknown, listing the names.
    [[nodiscard]] const flightdyn::MassProperties& mass_case(std::string_view name = {}) const;
    /// The control limits as limits of a motion file's modes `elevator`, `aileron`, `rudder`
    /// [rad] (the global controls, signs of docs/conventions.md), for aero::check_mode_limits.
    [[nodiscard]] std::vector<aero::ModeLimit> mode_limits() const;
};

/// Read and validate an aircraft file (YAML). ConfigError/IoError with file, line, key on any
/// problem. Format: docs/aircraft-format.md. Relative paths inside (airfoil files, aero database)
/// are resolved against the file's folder.
[[nodiscard]] AircraftDefinition load_aircraft(const std::filesystem::path& file);

/// Same as `load_aircraft` for YAML text held in memory (e.g. an aircraft compiled into the
/// program); `source` names it in messages, relative paths are resolved against `base_dir`.
[[nodiscard]] AircraftDefinition parse_aircraft(std::string_view yaml_text,
                                                const std::string& source,
                                                const std::filesystem::path& base_dir = ".");

}  // namespace manta::aircraft
