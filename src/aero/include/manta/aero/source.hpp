#pragma once
/// @file source.hpp
/// `AeroSource`: the one interface through which table campaigns, replays and reports reach an
/// aerodynamic solver (vortex lattice, Euler CFD, an analytic test function), so none of them
/// knows which solver it drives.
///
/// A source answers a steady evaluation at a flight state and control setting (an `AeroQuery`;
/// rates are quasi-steady: alpha_dot_hat and beta_dot_hat are ignored by steady solvers), and,
/// when it can, an unsteady evaluation along a prescribed motion (`Motion`).

#include <filesystem>
#include <functional>
#include <memory>
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

/// Loads and state of one instant of an unsteady run.
struct UnsteadySample {
    int index = 0;                       ///< step number, 0 the start
    double t = 0.0;                      ///< time [s] (the motion's clock)
    BodyCoefficients<double> body;       ///< CX CY CZ body axes; Cl Cm Cn about the reference point
    WindForceCoefficients<double> wind;  ///< CL CD CY at the instantaneous alpha and beta
    double alpha = 0.0;                  ///< of the reference point's air-relative velocity [rad]
    double beta = 0.0;                   ///< [rad]
    double airspeed = 0.0;  ///< of the reference point [m/s]; coefficients on rho airspeed^2 / 2
    /// Iterations an iterative source spent on this sample (the inner iterations of a step; for
    /// the start, those of its steady solution), and whether they met the source's stopping
    /// rule. 0 and true for a source solved directly (the vortex lattice).
    int iterations = 0;
    bool converged = true;
};

/// Settings of an unsteady run that the motion does not carry.
struct UnsteadySettings {
    /// Time step [s]; 0: the source's own default.
    double dt = 0.0;
    /// Viscous drag conditions (a source adds its profile-drag estimate as in `evaluate`).
    FlowConditions conditions;
};

/// A time-accurate run in progress, advanced one step at a time. Its whole state can be written
/// to a file and read back (`save`, `restore`): a run restored from a file and stepped on gives,
/// bit for bit, what the uninterrupted run gives.
class UnsteadyRun {
public:
    virtual ~UnsteadyRun() = default;
    /// The current instant (the start after construction, then the last step).
    [[nodiscard]] virtual const UnsteadySample& current() const = 0;
    /// Advance one time step. InputError past the motion's end.
    virtual const UnsteadySample& step() = 0;
    /// True when no whole time step is left before the motion's end.
    [[nodiscard]] virtual bool finished() const = 0;
    /// Number of steps from the motion's start to its end.
    [[nodiscard]] virtual int n_steps() const = 0;
    /// Time step [s].
    [[nodiscard]] virtual double dt() const = 0;
    /// Write the run's state to `file` (binary, atomically). IoError if it cannot be written.
    virtual void save(const std::filesystem::path& file) const = 0;
    /// Replace the run's state by the one saved in `file` by a run of the same source, motion and
    /// settings. IoError if unreadable; InputError if the file does not fit this run.
    virtual void restore(const std::filesystem::path& file) = 0;
};

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
    /// True if `start_unsteady` (and so `replay`) is implemented.
    [[nodiscard]] virtual bool unsteady() const { return false; }
    /// A time-accurate run along `motion`, started at its first instant. The default throws
    /// InputError naming the source: it has no unsteady mode (cannot move).
    [[nodiscard]] virtual std::unique_ptr<UnsteadyRun> start_unsteady(
        const Motion& motion, const UnsteadySettings& settings) const;
    /// Coefficients along a motion (time-accurate), by `start_unsteady` with default settings
    /// stepped to the end. InputError as `start_unsteady` for a source that cannot move.
    [[nodiscard]] virtual CoefficientHistory replay(const Motion& motion,
                                                    const ProgressCallback& progress) const;
};

}  // namespace manta::aero
