#pragma once
/// @file aircraft.hpp
/// The aircraft definition file (docs/formats.md#aircraft-file): geometry for the flow solvers,
/// mass cases, engine, control limits, aerodynamic model and envelope, read through the validated
/// configuration layer. This module joins `geometry` and `flightdyn`.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "manta/flightdyn/model.hpp"
#include "manta/geometry/aircraft_geometry.hpp"

namespace manta::aircraft {

/// Flight envelope as published (used for sanity checks and plots).
struct Envelope {
    double max_mach = 0.0;          ///< M_MO
    double dive_mach = 0.0;         ///< M_D
    double ceiling = 0.0;           ///< [m]
    std::array<double, 2> alpha{0.0, 0.0};  ///< [rad] range of data / validity
    std::array<double, 2> beta{0.0, 0.0};   ///< [rad]
};

struct AircraftDefinition {
    std::filesystem::path file;  ///< where it was read from
    std::string name;
    std::string description;
    geometry::AircraftGeometry geometry;
    flightdyn::ReferenceGeometry reference;
    Eigen::Vector3d moment_reference_geom = Eigen::Vector3d::Zero();
    std::vector<flightdyn::MassProperties> mass_cases;
    std::string default_mass_case;
    flightdyn::EngineModel engine;
    Eigen::Vector3d engine_angular_momentum = Eigen::Vector3d::Zero();
    flightdyn::ControlLimits limits;
    flightdyn::Environment environment;
    Envelope envelope;
    std::shared_ptr<const aero::AeroDatabase> aero;
    std::string aero_label;  ///< how the aero model was obtained (e.g. "linear derivatives (typical jet trainer)")

    /// Flight model with the named loading case ("" = default). InputError if unknown, listing names.
    [[nodiscard]] flightdyn::FlightModel flight_model(std::string_view mass_case = {}) const;
};

/// Read and validate an aircraft file (YAML). ConfigError/IoError with file, line, key on any problem.
[[nodiscard]] AircraftDefinition load_aircraft(const std::filesystem::path& file);

}  // namespace manta::aircraft
