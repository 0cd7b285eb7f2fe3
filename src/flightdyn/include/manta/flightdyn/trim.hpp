#pragma once
/// @file trim.hpp
/// Trim (steady flight) and linearisation about a trim point.
///
/// Steady wings-level flight, steady climb or descent at flight-path angle gamma, and the
/// coordinated steady turn at turn rate psi_dot, after Stevens, Lewis & Johnson (2015) sec. 3.6:
/// unknowns throttle, elevator, alpha, aileron, rudder, beta; bank from the turn-coordination
/// constraint (their eq. 3.6-5), pitch from the rate-of-climb constraint (eq. 3.6-3), body rates
/// p = -psi_dot sin(theta), q = psi_dot cos(theta) sin(phi), r = psi_dot cos(theta) cos(phi);
/// residual the six dynamic derivatives (V, alpha, beta, p, q, r), solved by Newton's method with
/// exact (automatic-differentiation) Jacobians and a backtracking line search.

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

/// Settings of the Newton iteration and of the checks on its solution.
struct TrimOptions {
    /// Convergence test on the weighted residual, each row an acceleration in units of g:
    /// max(|dV/dt|, |dalpha/dt| V, |dbeta/dt| V, |dp/dt| b/2, |dq/dt| c/2, |dr/dt| b/2) / g.
    /// Up to three further Newton steps then polish the solution while they reduce the residual.
    double tolerance = 1e-10;
    int max_iterations = 100;  ///< Newton steps before a ConvergenceError
    /// Reject solutions whose controls are outside the model's limits (ConvergenceError naming
    /// the control, its value and the limit). False: report them in TrimResult::violations only.
    bool enforce_limits = true;
};

/// A trimmed flight condition.
struct TrimResult {
    EulerState<double> state;  ///< full state at trim (x = y = 0, z = -altitude)
    /// Deflections [rad] in MANTA's signs and throttle (outside [0, 1] only if limits are not
    /// enforced).
    Controls<double> controls;
    double residual_norm = 0.0;  ///< max |derivative| of (V, alpha, beta, p, q, r) in SI units
    int iterations = 0;      ///< Newton steps to reach the tolerance (polishing steps not counted)
    std::string violations;  ///< limit violations when enforce_limits is false ("" if none)
};

/// Trim the model; ConvergenceError with a clear reason when no trim exists (throttle above 1
/// needed, alpha beyond the tables, Newton failure), InputError for a bad target.
/// The converged solution is checked against the model's control limits and against the ranges
/// of the aero tables (alpha, beta, Mach, and each control's axis): with `enforce_limits` a
/// violation is a ConvergenceError "no trim at V = .., h = ..: <every violation>", without it the
/// violations are listed in TrimResult::violations. Starts from alpha for the lift needed
/// (scanning the tables), elevator for zero pitching moment and throttle for zero acceleration.
[[nodiscard]] TrimResult trim(const FlightModel& model, const TrimTarget& target,
                              const TrimOptions& options = {});

/// Linear model x_dot = A x + B u about (x0, u0) for the Euler-angle state and controls
/// (elevator, aileron, rudder, throttle), exact first derivatives by automatic differentiation.
struct LinearModel {
    Eigen::Matrix<double, 12, 12>
        A;  ///< d(x_dot)/dx, Euler-angle state order of eom.hpp (euler::Index)
    Eigen::Matrix<double, 12, 4>
        B;                  ///< d(x_dot)/du, columns elevator, aileron, rudder [1/rad], throttle
    EulerState<double> x0;  ///< the point of linearisation
    Controls<double> u0;
};
/// A model whose tables carry alpha-dot/beta-dot columns is linearised with those terms whether or
/// not `finalize` was called on it (a finalized copy is used). NumericalError on non-finite
/// derivatives.
[[nodiscard]] LinearModel linearise(const FlightModel& model, const EulerState<double>& x0,
                                    const Controls<double>& u0);

}  // namespace manta::flightdyn
