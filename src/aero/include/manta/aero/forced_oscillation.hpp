#pragma once
/// @file forced_oscillation.hpp
/// Dynamic derivatives by forced harmonic oscillation on any aerodynamic source that can move
/// (`AeroSource::start_unsteady`: the unsteady vortex lattice, the Euler CFD): the harmonic
/// motion about the reference point (`harmonic_motion`), the time-accurate run from the source's
/// start at the motion's first instant, with a progress callback and atomic checkpoints that a
/// later call resumes, and the six coefficients reduced by `analyse_oscillation` over all periods
/// but the first (theory and the combination of derivatives each axis measures:
/// docs/forced-oscillation.md).

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "manta/aero/motion.hpp"
#include "manta/aero/oscillation.hpp"
#include "manta/aero/source.hpp"

namespace manta::aero {

struct ForcedOscillationOptions {
    OscillationAxis axis = OscillationAxis::pitch;
    /// Amplitude of the oscillating angle [rad] (1 deg); for plunge, of the angle of attack
    /// (height amplitude A V / omega).
    double amplitude = 0.0174533;
    /// Reduced frequency k = omega l / (2 V), l = `chord` for pitch and plunge, `span` for roll
    /// and yaw.
    double reduced_frequency = 0.05;
    /// Mean angle of attack [rad]: a constant pitch attitude theta = alpha0 (the mean of the
    /// pitch oscillation).
    double alpha0 = 0.0;
    /// Entry free-stream speed v0 [m/s], the motion's `v0` (the results depend on k and the
    /// Mach number only).
    double speed = 100.0;
    /// The motion's `mach` metadata; unset: the source's own Mach number.
    std::optional<double> mach;
    int n_periods = 3;          ///< simulated, >= 2; the first is discarded as the start transient
    int steps_per_period = 48;  ///< time steps (and motion samples) per period, >= 8
    double chord = 0.0;         ///< reference chord c [m] of the source's coefficients, > 0
    double span = 0.0;          ///< reference span b [m], > 0
    /// Viscous drag conditions passed to the source (UnsteadySettings::conditions).
    FlowConditions conditions;
    /// Checkpoint file (empty: none): the history so far and the run's state
    /// (UnsteadyRun::save), written atomically after the start, every `checkpoint_seconds` and
    /// at the end. A call that finds it resumes from it (InputError when it belongs to another
    /// source or other options, or is not a checkpoint).
    std::filesystem::path checkpoint;
    double checkpoint_seconds = 60.0;  ///< wall time between checkpoints [s]; 0: every step
};

/// One step's progress.
struct ForcedOscillationProgress {
    int step = 0;                            ///< steps done (the current sample's index)
    int n_steps = 0;                         ///< steps of the whole motion
    double t = 0.0;                          ///< time of the current sample [s]
    double end_time = 0.0;                   ///< the motion's end [s]
    const UnsteadySample* sample = nullptr;  ///< the current sample
    int resumed_from = -1;  ///< the step this call resumed from a checkpoint (-1: none)
    double wall_s = 0.0;    ///< wall time of this call so far [s]
    /// From the mean wall time per step of this call (none before its first step).
    std::optional<double> seconds_left;
    bool checkpoint_written = false;  ///< a checkpoint was written after this step
};
using ForcedOscillationCallback = std::function<void(const ForcedOscillationProgress&)>;

/// In-phase and out-of-phase derivatives of the six coefficients, per radian of the
/// oscillating angle and per non-dimensional rate (docs/forced-oscillation.md).
struct ForcedOscillationResult {
    ForcedOscillationOptions options;
    double omega = 0.0;  ///< [rad/s]
    /// {CL CD CY} (wind axes) and {Cl Cm Cn} (body axes, about the reference point).
    std::array<OscillationResult, 6> coefficients;
    std::vector<UnsteadySample> history;  ///< the start and every step
    int resumed_from = -1;                ///< step resumed from a checkpoint (-1: none)
    int steps_computed = 0;               ///< steps run by this call
    double wall_s = 0.0;                  ///< wall time of this call [s]
};

/// Names of the six coefficients in ForcedOscillationResult::coefficients order.
inline constexpr std::array<const char*, 6> oscillation_coefficient_names = {"CL", "CD", "CY",
                                                                             "Cl", "Cm", "Cn"};

/// InputError (one line, naming the option, its value and what was expected) unless amplitude,
/// reduced frequency and speed are finite and > 0, n_periods >= 2, steps_per_period >= 8, the
/// reference length of the axis (chord: pitch, plunge; span: roll, yaw) is > 0, alpha0 is
/// finite, a given Mach number is finite and >= 0, and checkpoint_seconds >= 0.
void check_options(const ForcedOscillationOptions& options);

/// Angular frequency omega = 2 V k / l [rad/s] (options checked first).
[[nodiscard]] double oscillation_omega(const ForcedOscillationOptions& options);

/// The motion `forced_oscillation` runs: `harmonic_motion` on the axis, mean alpha0 for pitch,
/// alpha0 as a constant pitch attitude for the other axes; for plunge a height amplitude
/// A V / omega (the angle of attack then leads the height by a quarter period); metadata v0 =
/// speed and the given Mach number.
[[nodiscard]] Motion oscillation_motion(const ForcedOscillationOptions& options);

/// The analysis of a history (samples at the motion's times) over its last n_periods - 1
/// periods: pitch x0 = alpha0, phase 0; roll and yaw x0 = 0; plunge x0 = alpha0, phase pi/2.
/// InputError as analyse_oscillation.
[[nodiscard]] std::array<OscillationResult, 6> analyse_forced_oscillation(
    const std::vector<UnsteadySample>& history, const ForcedOscillationOptions& options);

/// Run the oscillation on `source` to the end of the motion and analyse it. InputError for bad
/// options, a source that cannot move, or a checkpoint that does not fit; IoError when the
/// checkpoint cannot be written; the source's errors as they come.
[[nodiscard]] ForcedOscillationResult forced_oscillation(
    const AeroSource& source, const ForcedOscillationOptions& options,
    const ForcedOscillationCallback& progress = {});

}  // namespace manta::aero
