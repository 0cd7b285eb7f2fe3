#pragma once
/// @file source.hpp
/// `AeroSource`: the one interface through which table campaigns, replays and reports reach an
/// aerodynamic solver (vortex lattice, Euler CFD, an analytic test function), so none of them
/// knows which solver it drives.
///
/// A source answers a steady evaluation at a flight state and control setting (an `AeroQuery`;
/// rates are quasi-steady: alpha_dot_hat and beta_dot_hat are ignored by steady solvers), and,
/// when it can, an unsteady evaluation along a prescribed motion (`Motion`).

#include <functional>
#include <string>
#include <vector>

#include "manta/aero/motion.hpp"
#include "manta/aero/types.hpp"

namespace manta::aero {

/// Dimensional conditions a non-dimensional query leaves open.
struct FlowConditions {
    /// Reynolds number per metre, rho V / mu [1/m]; 0: no viscous (profile) drag estimate.
    double reynolds_per_metre = 0.0;
};

/// Coefficients of one steady evaluation.
struct SourceResult {
    BodyCoefficients<double> body;  ///< CX CY CZ body axes; Cl Cm Cn about the reference point
    WindForceCoefficients<double> wind;
    double CD_induced = 0.0;  ///< pressure / induced part of CD
    double CD_profile = 0.0;  ///< viscous (profile) part of CD
};

/// Time history of the coefficients along a motion.
struct CoefficientHistory {
    std::vector<double> t;  ///< [s]
    std::vector<BodyCoefficients<double>> body;
    std::vector<WindForceCoefficients<double>> wind;
};

/// Progress of a long evaluation: fraction done in [0, 1].
using ProgressCallback = std::function<void(double fraction)>;

class AeroSource {
public:
    virtual ~AeroSource() = default;
    /// Short name ("vlm", "euler", ...).
    [[nodiscard]] virtual std::string name() const = 0;
    /// Changes whenever results could change (model, discretisation, options, code version): a
    /// sample store compares it to detect a changed source.
    [[nodiscard]] virtual std::string fingerprint() const = 0;
    /// Steady coefficients at `q`. Thread-safe.
    [[nodiscard]] virtual SourceResult evaluate(const AeroQuery<double>& q,
                                                const FlowConditions& conditions) const = 0;
    /// True if `replay` is implemented.
    [[nodiscard]] virtual bool unsteady() const { return false; }
    /// Coefficients along a motion (time-accurate). The default throws InputError naming the
    /// source: it has no unsteady mode.
    [[nodiscard]] virtual CoefficientHistory replay(const Motion& motion,
                                                    const ProgressCallback& progress) const;
};

}  // namespace manta::aero
