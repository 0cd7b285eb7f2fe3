#pragma once
/// @file trim.hpp
/// Trim (steady flight) and linearisation about a trim point.
///
/// Steady wings-level flight, steady climb or descent at flight-path angle gamma, and the
/// coordinated steady turn at turn rate psi_dot, after Stevens, Lewis & Johnson (2015) sec. 3.6:
/// unknowns throttle, elevator, alpha, aileron, rudder, beta; bank from the turn-coordination
/// constraint (their eq. 3.6-5), pitch from the rate-of-climb constraint (eq. 3.6-3), body rates
/// p = -psi_dot sin(theta), q = psi_dot cos(theta) sin(phi), r = psi_dot cos(theta) cos(phi); residual
/// the six dynamic derivatives (V, alpha, beta, p, q, r), solved by Newton's method with exact
/// (automatic-differentiation) Jacobians and a backtracking line search.

#include <Eigen/Core>
#include <string>

#include "manta/flightdyn/eom.hpp"
#include "manta/flightdyn/model.hpp"

namespace manta::flightdyn {

/// The steady flight asked for.
struct TrimTarget {
    double airspeed = 0.0;     ///< true airspeed V [m/s]
    double altitude = 0.0;     ///< [m]
    double climb_angle = 0.0;  ///< flight-path angle gamma [rad], + climbing
    double turn_rate = 0.0;    ///< psi_dot [rad/s], + turning right
    double heading = 0.0;      ///< psi [rad]
};

struct TrimOptions {
    double tolerance = 1e-10;  ///< on the scaled residual norm
    int max_iterations = 100;
    /// Reject solutions whose controls are outside the model's limits (ConvergenceError naming
    /// the control, its value and the limit). False: report them in TrimResult::violations only.
    bool enforce_limits = true;
};

struct TrimResult {
    EulerState<double> state;  ///< full state at trim (x = y = 0, z = -altitude)
    Controls<double> controls;
    double residual_norm = 0.0;  ///< max |derivative| of (V, alpha, beta, p, q, r) in SI units
    int iterations = 0;
    std::string violations;  ///< limit violations when enforce_limits is false ("" if none)
};

/// Trim the model; ConvergenceError with a clear reason when no trim exists (throttle above 1
/// needed, alpha beyond the tables, Newton failure), InputError for a bad target.
[[nodiscard]] TrimResult trim(const FlightModel& model, const TrimTarget& target, const TrimOptions& options = {});

/// Linear model x_dot = A x + B u about (x0, u0) for the Euler-angle state and controls
/// (elevator, aileron, rudder, throttle), exact first derivatives by automatic differentiation.
struct LinearModel {
    Eigen::Matrix<double, 12, 12> A;
    Eigen::Matrix<double, 12, 4> B;
    EulerState<double> x0;
    Controls<double> u0;
};
[[nodiscard]] LinearModel linearise(const FlightModel& model, const EulerState<double>& x0, const Controls<double>& u0);

}  // namespace manta::flightdyn
