#pragma once
/// @file dynamic.hpp
/// Dynamic derivatives by forced harmonic oscillation with the unsteady vortex lattice: the
/// source-generic driver `aero::forced_oscillation` (aero/forced_oscillation.hpp) on a
/// `VlmSource` of the model and lattice, the reference lengths those of the model
/// (docs/forced-oscillation.md).

#include "manta/aero/forced_oscillation.hpp"
#include "manta/aero/motion.hpp"
#include "manta/aero/oscillation.hpp"
#include "manta/vlm/lattice.hpp"
#include "manta/vlm/model.hpp"
#include "manta/vlm/unsteady.hpp"

namespace manta::vlm {

struct ForcedOscillationOptions {
    aero::OscillationAxis axis = aero::OscillationAxis::pitch;
    /// Amplitude of the oscillating angle [rad] (1 deg); for plunge, of the angle of attack
    /// (height amplitude A V / omega).
    double amplitude = 0.0174533;
    /// Reduced frequency k = omega l / (2 V), l = c_ref for pitch and plunge, b_ref for roll and
    /// yaw.
    double reduced_frequency = 0.05;
    double alpha0 = 0.0;   ///< mean angle of attack [rad] (a constant pitch attitude)
    double speed = 100.0;  ///< v0 [m/s] (the lattice is scale-free; only k and M matter)
    int n_periods = 3;     ///< simulated; the first is discarded as the start transient
    int steps_per_period = 48;
    UnsteadyOptions solver;  ///< dt and speed are set from the above
};

/// In-phase and out-of-phase derivatives of the six coefficients {CL CD CY Cl Cm Cn}, per radian
/// of the oscillating angle and per non-dimensional rate (see docs/forced-oscillation.md for the
/// combination each axis measures: pitch C_q + C_alphadot, roll C_p + C_betadot sin alpha0, yaw
/// C_r cos alpha0 - C_p sin alpha0 - C_betadot, about the motion's axes).
using ForcedOscillationResult = aero::ForcedOscillationResult;

/// The generic driver's options for `model`: the axis, amplitude, frequency, mean, speed and
/// periods of `o`, the model's reference chord and span, `o.solver.mach` as the Mach number.
[[nodiscard]] aero::ForcedOscillationOptions oscillation_options(const Model& model,
                                                                 const ForcedOscillationOptions& o);

/// Run the oscillation and analyse it: aero::forced_oscillation on VlmSource(model, lattice) with
/// `o.solver` as its unsteady options (speed v0 = o.speed). InputError for options out of range.
[[nodiscard]] ForcedOscillationResult forced_oscillation(
    const Model& model, const Lattice& lattice, const ForcedOscillationOptions& options,
    const aero::ForcedOscillationCallback& progress = {});

}  // namespace manta::vlm
