#pragma once
/// @file model.hpp
/// Everything the 6-DoF equations need about an aircraft: reference geometry, mass properties
/// of one loading case, engine, aerodynamic database, control limits and environment.
/// Built by the aircraft loader (module `aircraft`) from the aircraft YAML file.

#include <Eigen/Core>
#include <array>
#include <limits>
#include <memory>
#include <string>

#include "manta/aero/database.hpp"
#include "manta/core/units.hpp"
#include "manta/flightdyn/engine.hpp"

namespace manta::flightdyn {

/// Reference values that make coefficients dimensional.
struct ReferenceGeometry {
    double area = 0.0;   ///< S [m^2]
    double span = 0.0;   ///< b [m]
    double chord = 0.0;  ///< mean aerodynamic chord c [m]
};

/// Mass properties of one loading case.
struct MassProperties {
    std::string name;
    double mass = 0.0;  ///< [kg]
    /// Centre of gravity, geometry axes (x aft, y right, z up) [m].
    Eigen::Vector3d cg_geom = Eigen::Vector3d::Zero();
    /// Inertia tensor about the CG in body axes (x fwd, y right, z down) [kg m^2]; Ixz as the
    /// product of inertia with the sign convention I =
    /// [[Ixx,-Ixy,-Ixz],[-Ixy,Iyy,-Iyz],[-Ixz,-Iyz,Izz]].
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();
};

/// Deflection and throttle limits (radians; throttle 0..1).
struct ControlLimits {
    std::array<double, 2> elevator{-core::deg(25.0), core::deg(15.0)};
    std::array<double, 2> aileron{-core::deg(25.0), core::deg(15.0)};
    std::array<double, 2> rudder{-core::deg(17.5), core::deg(17.5)};
    std::array<double, 2> throttle{0.0, 1.0};
};

/// Physical environment of a flight.
struct Environment {
    double gravity = core::standard_gravity;  ///< [m/s^2], uniform, along earth z (down)
};

/// The flying aircraft.
struct FlightModel {
    std::string name;
    ReferenceGeometry reference;
    /// Moment reference point of the aero database, geometry axes [m].
    Eigen::Vector3d moment_reference_geom = Eigen::Vector3d::Zero();
    MassProperties mass;
    EngineModel engine;
    /// Engine rotor angular momentum, body axes [kg m^2/s] (gyroscopic term; zero in the paper).
    Eigen::Vector3d engine_angular_momentum = Eigen::Vector3d::Zero();
    std::shared_ptr<const aero::AeroDatabase> aero;
    ControlLimits limits;
    Environment environment;
    /// Interpolation used for the aero tables in the equations of motion.
    aero::Interpolation interpolation = aero::Interpolation::multilinear;
    /// True when the aero tables carry alpha-dot or beta-dot columns (set by flightdyn::finalize);
    /// the equations of motion then solve the implicit angle-rate dependence exactly.
    bool angle_rate_terms = false;
    bool alpha_dot_terms = false;  ///< tables have alpha-dot columns (set by finalize)
    bool beta_dot_terms = false;   ///< tables have beta-dot columns (set by finalize)
    /// Inverse of mass.inertia (set by finalize) and the inertia tensor it is the inverse of. The
    /// equations of motion use it only while `inertia_inverse_of` equals mass.inertia (compared
    /// on every use), so an inertia changed after finalize is never paired with a stale inverse;
    /// NaN until finalize, so an unfinalized model inverts on every use.
    Eigen::Matrix3d inertia_inverse = Eigen::Matrix3d::Identity();
    Eigen::Matrix3d inertia_inverse_of =
        Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

}  // namespace manta::flightdyn
